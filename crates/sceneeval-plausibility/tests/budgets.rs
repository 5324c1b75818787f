//! Bounded cost: deadlines stop an evaluation between and inside metrics, parameters are
//! checked before anything runs, and support's ray origins never materialise more points than
//! its budget, even on a mesh of many coincident faces.

#![allow(clippy::unwrap_used)]

mod common;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use common::scene;
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Isometry3, Mesh, Point3, Vector3};
use sceneeval_plausibility::*;
use sceneeval_scene::{Category, Scene, SceneObject};

/// `n` boxes in a row, 0.4 m apart, all on the floor.
fn row_of_boxes(n: usize) -> Scene {
    let mut b = scene();
    for k in 0..n {
        b = b.add_box(
            format!("box_{k}"),
            Category::new("cabinet"),
            Vector3::new(0.15, 0.15, 0.15),
            pose_from_yaw(
                Point3::new(0.3 + 0.4 * (k % 9) as f64, 0.3 + 0.5 * (k / 9) as f64, 0.15),
                0.0,
            ),
        );
    }
    b.build().unwrap()
}

#[test]
fn an_expired_deadline_stops_before_the_first_metric() {
    let s = row_of_boxes(4);
    let mut timings = Vec::new();
    let err = evaluate_metrics(
        &s,
        &PlausibilityParams::default(),
        &Sources::default(),
        &[Metric::Support, Metric::Navigability],
        &Deadline::after(Duration::ZERO),
        &mut timings,
    )
    .unwrap_err();
    assert!(
        matches!(err, PlausibilityError::DeadlineExceeded { stage: "support", budget_seconds: Some(b) } if b == 0.0),
        "{err}"
    );
    assert!(err.to_string().contains("time budget of 0 s"), "{err}");
    assert!(timings.is_empty(), "no metric ran");
}

/// Answers `ground` and cancels `deadline` on its `after`-th call.
struct CancelAfter {
    calls: AtomicUsize,
    after: usize,
    deadline: Deadline,
}

impl Source<SupportTypeOf> for CancelAfter {
    fn answer(&self, _: &Scene, _: &SceneObject) -> Option<Answer<SupportType>> {
        if self.calls.fetch_add(1, Ordering::SeqCst) + 1 == self.after {
            self.deadline.cancel();
        }
        Some(Answer {
            value: SupportType::Ground,
            source: "test".into(),
        })
    }
}

#[test]
fn a_cancelled_deadline_stops_a_metric_inside_its_loop() {
    // 36 objects; the deadline is cancelled while the support metric handles the 5th.
    let s = row_of_boxes(36);
    let deadline = Deadline::none();
    let source = CancelAfter {
        calls: AtomicUsize::new(0),
        after: 5,
        deadline: deadline.clone(),
    };
    let sources = Sources::new(source, FunctionalSidePriors::default());
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut timings = Vec::new();
    let err = pool
        .install(|| {
            evaluate_metrics(
                &s,
                &PlausibilityParams::default(),
                &sources,
                &[Metric::Collision, Metric::Support, Metric::OutOfBounds],
                &deadline,
                &mut timings,
            )
        })
        .unwrap_err();
    assert!(
        matches!(
            err,
            PlausibilityError::DeadlineExceeded {
                stage: "support",
                budget_seconds: None
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("cancelled"), "{err}");
    // Collision finished and was timed; support stopped; out-of-bounds never started.
    assert_eq!(timings.len(), 1);
    assert_eq!(timings[0].metric, Metric::Collision);
}

#[test]
fn work_after_cancellation_is_bounded() {
    // Each worker thread finishes at most the object it is on when the deadline is cancelled,
    // so with 2 threads at most 5 + 1 of the 36 objects are looked at.
    let s = row_of_boxes(36);
    let deadline = Deadline::none();
    let calls = Arc::new(AtomicUsize::new(0));
    struct Counting {
        calls: Arc<AtomicUsize>,
        deadline: Deadline,
    }
    impl Source<SupportTypeOf> for Counting {
        fn answer(&self, _: &Scene, _: &SceneObject) -> Option<Answer<SupportType>> {
            if self.calls.fetch_add(1, Ordering::SeqCst) + 1 == 5 {
                self.deadline.cancel();
            }
            None
        }
    }
    let sources = Sources::new(
        Counting {
            calls: Arc::clone(&calls),
            deadline: deadline.clone(),
        },
        FunctionalSidePriors::default(),
    );
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let r = pool.install(|| {
        evaluate_metrics(
            &s,
            &PlausibilityParams::default(),
            &sources,
            &[Metric::Support],
            &deadline,
            &mut Vec::new(),
        )
    });
    assert!(r.is_err());
    let n = calls.load(Ordering::SeqCst);
    assert!(
        (5..=6).contains(&n),
        "{n} objects looked at after cancelling at the 5th of 36"
    );
}

#[test]
fn parameters_are_checked_before_any_metric_runs() {
    let s = row_of_boxes(2);
    let mut params = PlausibilityParams::default();
    params.navigability.resolution = Resolution::Pixels(100_000);
    let err = params.validate().unwrap_err();
    assert!(
        matches!(err, PlausibilityError::RasterTooLarge { width: 100_000, .. }),
        "{err}"
    );
    // Even when navigability is not selected, a bad plan is a bad plan.
    let mut timings = Vec::new();
    let r = evaluate_metrics(
        &s,
        &params,
        &Sources::default(),
        &[Metric::Collision],
        &Deadline::none(),
        &mut timings,
    );
    assert!(r.is_err() && timings.is_empty());

    let mut params = PlausibilityParams::default();
    params.collision.contact_tolerance = -0.1;
    assert!(matches!(
        params.validate(),
        Err(PlausibilityError::InvalidParameter {
            metric: "collision",
            name: "contact_tolerance",
            ..
        })
    ));
    let mut params = PlausibilityParams::default();
    params.out_of_bounds.threshold = 2.0;
    assert!(params.validate().is_err());
    assert!(PlausibilityParams::default().validate().is_ok());
}

#[test]
fn one_dispatch_gives_the_per_metric_results() {
    let s = row_of_boxes(5);
    let all = evaluate(&s, &PlausibilityParams::default(), &Sources::default()).unwrap();
    for m in Metric::ALL {
        let one = evaluate_metrics(
            &s,
            &PlausibilityParams::default(),
            &Sources::default(),
            &[m],
            &Deadline::none(),
            &mut Vec::new(),
        )
        .unwrap();
        assert_eq!(one.metrics, vec![m]);
        match m {
            Metric::Collision => assert_eq!(one.collision, all.collision),
            Metric::Support => assert_eq!(one.support, all.support),
            Metric::Navigability => assert_eq!(one.navigability, all.navigability),
            Metric::Accessibility => assert_eq!(one.accessibility, all.accessibility),
            Metric::OutOfBounds => assert_eq!(one.out_of_bounds, all.out_of_bounds),
            Metric::OpeningClearance => assert_eq!(one.opening_clearance, all.opening_clearance),
        }
        assert_eq!(m.name().parse::<Metric>().unwrap(), m);
    }
    assert!(matches!(
        "physics".parse::<Metric>(),
        Err(PlausibilityError::UnknownMetric { .. })
    ));
}

#[test]
fn support_lattice_stays_within_its_budget_on_coincident_faces() {
    // 50,000 copies of one horizontal 1 m x 1 m right triangle (area 0.5 m^2) at z = 0.3 over
    // 3 vertices. At 256 points per square metre each face would get a 12 x 12 lattice
    // (ceil(sqrt(128)) = 12): 7.2 million points, 173 MB, if materialised before the budget
    // is applied. The density is lowered first: 4096 / 7.2e6 of it gives each face 0.073
    // expected points, emitted by the running sum about 3,640 times in all.
    let n = 50_000;
    let vertices = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
    ];
    let mesh = Arc::new(Mesh::new(vertices, vec![[0, 1, 2]; n]).unwrap());
    let object = SceneObject::from_mesh("sheet", mesh, Isometry3::translation(1.0, 1.0, 0.3))
        .unwrap()
        .with_category("table");
    let s = scene().object(object).build().unwrap();
    let params = SupportParams::default();
    let r = support(&s, &params, &SupportTypePriors::default()).unwrap();
    let o = &r.objects[0];
    // 3 extreme vertices plus at most the budget of lattice points.
    assert!(
        o.num_ray_origins >= 3 && o.num_ray_origins <= 3 + params.max_face_samples,
        "{}",
        o.num_ray_origins
    );
    assert!(!o.supported, "a sheet 30 cm above the floor rests on nothing");
}

/// `params` with one parameter changed, and that parameter's (metric, name).
type Mutation = (&'static str, &'static str, fn(&mut PlausibilityParams));

#[test]
fn every_numeric_parameter_is_checked_against_its_range() {
    // The values of issue 29 (1e5 ran for minutes, 1e6 aborted on a 1.8 TB allocation, 2^31
    // panicked with "capacity overflow") and one value beyond each documented range.
    let cases: &[Mutation] = &[
        ("opening_clearance", "pixels_per_metre", |p| {
            p.opening_clearance.pixels_per_metre = 1e5
        }),
        ("opening_clearance", "pixels_per_metre", |p| {
            p.opening_clearance.pixels_per_metre = 1e6
        }),
        ("opening_clearance", "pixels_per_metre", |p| {
            p.opening_clearance.pixels_per_metre = 2f64.powi(31)
        }),
        ("opening_clearance", "pixels_per_metre", |p| {
            p.opening_clearance.pixels_per_metre = 1000.5
        }),
        ("opening_clearance", "pixels_per_metre", |p| {
            p.opening_clearance.pixels_per_metre = 0.0
        }),
        ("opening_clearance", "pixels_per_metre", |p| {
            p.opening_clearance.pixels_per_metre = f64::NAN
        }),
        ("opening_clearance", "door_depth", |p| {
            p.opening_clearance.door_depth = f64::INFINITY
        }),
        ("opening_clearance", "window_depth", |p| {
            p.opening_clearance.window_depth = -1.0
        }),
        ("opening_clearance", "probe_offset", |p| {
            p.opening_clearance.probe_offset = f64::NAN
        }),
        ("opening_clearance", "touch_tolerance", |p| {
            p.opening_clearance.touch_tolerance = -1e-3
        }),
        ("opening_clearance", "walkable_height", |p| {
            p.opening_clearance.walkable_height = -0.1
        }),
        ("collision", "contact_tolerance", |p| {
            p.collision.contact_tolerance = f64::NAN
        }),
        ("collision", "depth_sample_spacing", |p| {
            p.collision.depth_sample_spacing = 0.0
        }),
        ("collision", "depth_sample_budget", |p| {
            p.collision.depth_sample_budget = 0
        }),
        ("collision", "depth_sample_budget", |p| {
            p.collision.depth_sample_budget = CollisionParams::MAX_DEPTH_SAMPLE_BUDGET + 1
        }),
        ("collision", "depth_sample_budget", |p| {
            p.collision.depth_sample_budget = usize::MAX
        }),
        ("support", "lift", |p| p.support.lift = -1.0),
        ("support", "contact_distance", |p| {
            p.support.contact_distance = 0.0
        }),
        ("support", "extreme_band", |p| {
            p.support.extreme_band = f64::INFINITY
        }),
        ("support", "normal_facing_threshold", |p| {
            p.support.normal_facing_threshold = 1.5
        }),
        ("support", "samples_per_square_metre", |p| {
            p.support.samples_per_square_metre = f64::NAN
        }),
        ("support", "max_face_samples", |p| {
            p.support.max_face_samples = SupportParams::MAX_FACE_SAMPLES + 1
        }),
        ("support", "max_face_samples", |p| {
            p.support.max_face_samples = usize::MAX
        }),
        ("navigability", "margin", |p| p.navigability.margin = -0.1),
        ("navigability", "robot_width", |p| {
            p.navigability.robot_width = f64::INFINITY
        }),
        ("navigability", "height_cutoff", |p| {
            p.navigability.height_cutoff = f64::NAN
        }),
        ("navigability", "walkable_height", |p| {
            p.navigability.walkable_height = -1.0
        }),
        ("navigability", "door_max_sill", |p| {
            p.navigability.door_max_sill = -1.0
        }),
        ("navigability", "door_strip_depth", |p| {
            p.navigability.door_strip_depth = 0.0
        }),
        ("navigability", "resolution", |p| {
            p.navigability.resolution = Resolution::Pixels(0)
        }),
        ("navigability", "resolution", |p| {
            p.navigability.resolution = Resolution::MetresPerPixel(-0.01)
        }),
        ("accessibility", "strip_offset", |p| {
            p.accessibility.strip_offset = -0.1
        }),
        ("accessibility", "strip_width", |p| {
            p.accessibility.strip_width = 0.0
        }),
        ("accessibility", "height_cutoff", |p| {
            p.accessibility.height_cutoff = f64::NAN
        }),
        ("accessibility", "walkable_height", |p| {
            p.accessibility.walkable_height = -0.1
        }),
        ("out_of_bounds", "threshold", |p| p.out_of_bounds.threshold = 1.01),
        ("out_of_bounds", "below_floor_tolerance", |p| {
            p.out_of_bounds.below_floor_tolerance = -1.0
        }),
        ("out_of_bounds", "boundary_tolerance", |p| {
            p.out_of_bounds.boundary_tolerance = f64::NAN
        }),
    ];
    for (metric, name, mutate) in cases {
        let mut params = PlausibilityParams::default();
        mutate(&mut params);
        match params.validate() {
            Err(PlausibilityError::InvalidParameter {
                metric: m, name: n, ..
            }) => {
                assert_eq!((m, n), (*metric, *name), "{params:?}");
            }
            other => panic!("{metric}.{name}: expected an invalid parameter, got {other:?}"),
        }
    }
    // The ends of the ranges are accepted.
    let mut params = PlausibilityParams::default();
    params.opening_clearance.pixels_per_metre = OpeningClearanceParams::MAX_PIXELS_PER_METRE;
    params.collision.depth_sample_budget = CollisionParams::MAX_DEPTH_SAMPLE_BUDGET;
    params.support.max_face_samples = SupportParams::MAX_FACE_SAMPLES;
    params.support.normal_facing_threshold = 1.0;
    params.navigability.resolution = Resolution::Pixels(65_536);
    assert!(params.validate().is_ok());
    params.support.max_face_samples = 0;
    params.out_of_bounds.threshold = 0.0;
    assert!(params.validate().is_ok());
    // Margins that alone span more than 65,536 pixels are refused without a scene:
    // 2 x 40 m / 1 mm = 80,000 pixels.
    params.navigability.margin = 40.0;
    params.navigability.resolution = Resolution::MetresPerPixel(1e-3);
    assert!(matches!(
        params.validate(),
        Err(PlausibilityError::RasterTooLarge {
            metric: "navigability",
            width: 80_000,
            ..
        })
    ));
}

/// A 12 x 5 m room whose south wall holds a 10 m x 2.5 m window.
fn glass_wall() -> Scene {
    let room = sceneeval_scene::RoomBuilder::rectangle(
        "r0",
        sceneeval_geom::Point2::new(0.0, 0.0),
        sceneeval_geom::Point2::new(12.0, 5.0),
    )
    .window(0, [1.0, 11.0], [0.2, 2.7]);
    Scene::builder()
        .room_builder(room)
        .add_box(
            "sill_plant",
            Category::new("plant"),
            Vector3::new(0.2, 0.2, 0.5),
            pose_from_yaw(Point3::new(6.0, 0.3, 0.5), 0.0),
        )
        .build()
        .unwrap()
}

#[test]
fn an_occlusion_map_over_the_raster_budget_fails_its_scene_before_it_is_allocated() {
    // At 1000 pixels per metre (the largest allowed) the window's map has 10,000 x 2,500 =
    // 25 million pixels, over the dense raster budget of 2^24 = 16,777,216.
    let s = glass_wall();
    let mut params = PlausibilityParams::default();
    params.opening_clearance.pixels_per_metre = 1000.0;
    params.validate().unwrap();
    let err = opening_clearance(&s, &params.opening_clearance).unwrap_err();
    assert!(
        matches!(
            err,
            PlausibilityError::RasterTooLarge {
                metric: "opening_clearance",
                width: 10_000,
                height: 2_500,
                max_pixels: Some(16_777_216),
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("16777216 pixels in all"), "{err}");
    // At the default 100 pixels per metre the same window is 1,000 x 250 pixels: the plant
    // in front of it (0.4 m of the 10 m width; from the sill at 0.2 m to its top at 1.0 m,
    // 0.8 m of the 2.5 m height) covers the 40 x 80 pixels whose centres it spans: 3,200 of
    // 250,000, 1.28 %.
    let r = opening_clearance(&s, &OpeningClearanceParams::default()).unwrap();
    let side = &r.openings[0].sides[0];
    assert!(side.blocked);
    assert_eq!(side.occluded_fraction, 3_200.0 / 250_000.0);
}

#[test]
fn the_deadline_stops_the_navigability_raster_inside_its_rows() {
    // 65,536 x 65,536 pixels (the largest raster) take far longer than the budget of 1 ms:
    // the raster's row loop polls the deadline and stops.
    let s = row_of_boxes(4);
    let mut params = PlausibilityParams::default();
    params.navigability.resolution = Resolution::Pixels(65_536);
    let err = evaluate_metrics(
        &s,
        &params,
        &Sources::default(),
        &[Metric::Navigability],
        &Deadline::after(Duration::from_millis(1)),
        &mut Vec::new(),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            PlausibilityError::DeadlineExceeded {
                stage: "navigability",
                ..
            }
        ),
        "{err}"
    );
}
