//! Bounded cost: deadlines stop an evaluation between and inside metrics, parameters are
//! checked before anything runs, and support's ray origins never materialise more points than
//! its budget, even on a mesh of many coincident faces.

#![allow(clippy::unwrap_used)]

mod common;

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use common::scene;
use sceneeval_geom::Side;
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Isometry3, Mesh, Point3, Vector3};
use sceneeval_plausibility::*;
use sceneeval_scene::{Category, ObjectId, Scene, SceneObject};

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

/// Sources whose support types cancel `deadline` when the 5th object is asked.
fn cancelling_at_fifth(deadline: &Deadline) -> Sources {
    let source = CancelAfter {
        calls: AtomicUsize::new(0),
        after: 5,
        deadline: deadline.clone(),
    };
    Sources::new(source, FunctionalSidePriors::default())
}

#[test]
fn a_cancelled_deadline_stops_a_metric_inside_its_loop() {
    // 36 objects; the deadline is cancelled while the support metric handles the 5th.
    let s = row_of_boxes(36);
    let deadline = Deadline::none();
    let sources = cancelling_at_fifth(&deadline);
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
    params.collision.contact_tolerance_m = -0.1;
    assert!(matches!(
        params.validate(),
        Err(PlausibilityError::InvalidParameter {
            metric: "collision",
            name: "contact_tolerance_m",
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
        ("opening_clearance", "pixels_per_m", |p| {
            p.opening_clearance.pixels_per_m = 1e5
        }),
        ("opening_clearance", "pixels_per_m", |p| {
            p.opening_clearance.pixels_per_m = 1e6
        }),
        ("opening_clearance", "pixels_per_m", |p| {
            p.opening_clearance.pixels_per_m = 2f64.powi(31)
        }),
        ("opening_clearance", "pixels_per_m", |p| {
            p.opening_clearance.pixels_per_m = 1000.5
        }),
        ("opening_clearance", "pixels_per_m", |p| {
            p.opening_clearance.pixels_per_m = 0.0
        }),
        ("opening_clearance", "pixels_per_m", |p| {
            p.opening_clearance.pixels_per_m = f64::NAN
        }),
        ("opening_clearance", "door_depth_m", |p| {
            p.opening_clearance.door_depth_m = f64::INFINITY
        }),
        ("opening_clearance", "window_depth_m", |p| {
            p.opening_clearance.window_depth_m = -1.0
        }),
        ("opening_clearance", "probe_offset_m", |p| {
            p.opening_clearance.probe_offset_m = f64::NAN
        }),
        ("opening_clearance", "touch_tolerance_m", |p| {
            p.opening_clearance.touch_tolerance_m = -1e-3
        }),
        ("opening_clearance", "walkable_height_m", |p| {
            p.opening_clearance.walkable_height_m = -0.1
        }),
        ("collision", "contact_tolerance_m", |p| {
            p.collision.contact_tolerance_m = f64::NAN
        }),
        ("collision", "depth_sample_spacing_m", |p| {
            p.collision.depth_sample_spacing_m = 0.0
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
        ("support", "lift_m", |p| p.support.lift_m = -1.0),
        ("support", "contact_distance_m", |p| {
            p.support.contact_distance_m = 0.0
        }),
        ("support", "extreme_band_m", |p| {
            p.support.extreme_band_m = f64::INFINITY
        }),
        ("support", "normal_facing_threshold", |p| {
            p.support.normal_facing_threshold = 1.5
        }),
        ("support", "samples_per_m2", |p| {
            p.support.samples_per_m2 = f64::NAN
        }),
        ("support", "max_face_samples", |p| {
            p.support.max_face_samples = SupportParams::MAX_FACE_SAMPLES + 1
        }),
        ("support", "max_face_samples", |p| {
            p.support.max_face_samples = usize::MAX
        }),
        ("navigability", "margin_m", |p| p.navigability.margin_m = -0.1),
        ("navigability", "robot_width_m", |p| {
            p.navigability.robot_width_m = f64::INFINITY
        }),
        ("navigability", "height_cutoff_m", |p| {
            p.navigability.height_cutoff_m = f64::NAN
        }),
        ("navigability", "walkable_height_m", |p| {
            p.navigability.walkable_height_m = -1.0
        }),
        ("navigability", "door_max_sill_m", |p| {
            p.navigability.door_max_sill_m = -1.0
        }),
        ("navigability", "door_strip_depth_m", |p| {
            p.navigability.door_strip_depth_m = 0.0
        }),
        ("navigability", "resolution", |p| {
            p.navigability.resolution = Resolution::Pixels(0)
        }),
        ("navigability", "resolution", |p| {
            p.navigability.resolution = Resolution::MetresPerPixel(-0.01)
        }),
        ("accessibility", "strip_offset_m", |p| {
            p.accessibility.strip_offset_m = -0.1
        }),
        ("accessibility", "strip_width_m", |p| {
            p.accessibility.strip_width_m = 0.0
        }),
        ("accessibility", "height_cutoff_m", |p| {
            p.accessibility.height_cutoff_m = f64::NAN
        }),
        ("accessibility", "walkable_height_m", |p| {
            p.accessibility.walkable_height_m = -0.1
        }),
        ("out_of_bounds", "threshold", |p| p.out_of_bounds.threshold = 1.01),
        ("out_of_bounds", "below_floor_tolerance_m", |p| {
            p.out_of_bounds.below_floor_tolerance_m = -1.0
        }),
        ("out_of_bounds", "boundary_tolerance_m", |p| {
            p.out_of_bounds.boundary_tolerance_m = f64::NAN
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
    params.opening_clearance.pixels_per_m = OpeningClearanceParams::MAX_PIXELS_PER_METRE;
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
    params.navigability.margin_m = 40.0;
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
    params.opening_clearance.pixels_per_m = 1000.0;
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

/// The bed of issue 34 (a 1.6 x 2.1 m bed against the far wall of the 4 x 5 m room, front,
/// left and right functional sides) and `n` copies of a round plant (a 32-segment sphere of
/// radius 0.25 m, turned 0.3 rad) at one pose, over the bed's left access strip.
fn bed_with_plants(n: usize) -> Scene {
    let plant = common::sphere(0.25, 16);
    let mut b = scene().add_box(
        "bed",
        Category::new("bed"),
        Vector3::new(0.8, 1.05, 0.3),
        pose_from_yaw(Point3::new(2.0, 3.95, 0.3), 0.0),
    );
    for k in 0..n {
        b = b.object(
            SceneObject::from_mesh(
                format!("plant{k}"),
                Arc::clone(&plant),
                common::at(1.0, 3.95, 0.25, 0.3),
            )
            .unwrap()
            .with_category("plant"),
        );
    }
    b.build().unwrap()
}

#[test]
fn coincident_round_objects_keep_accessibility_polynomial() {
    // Issue 34, item 7: a bed plus 45 plants at one pose took 4 s and 437 MB, plus 50 took
    // 19 s and 2.16 GB: every copy split each piece of the strip's free part again into
    // slivers of rounding-error width. Now the copies after the first split nothing: the
    // pieces per strip stay those of one plant, the total work grows linearly, and the scores
    // are those of one plant.
    let sides = FunctionalSidePriors::default();
    let (one, one_work) =
        accessibility_with_work(&bed_with_plants(1), &AccessibilityParams::default(), &sides).unwrap();
    for n in [16, 50] {
        let (r, work) =
            accessibility_with_work(&bed_with_plants(n), &AccessibilityParams::default(), &sides).unwrap();
        assert_eq!(work.most_pieces, one_work.most_pieces, "{n}: {work:?}");
        assert_eq!(
            work.subtractions,
            n as u64 * one_work.subtractions,
            "{n}: {work:?}"
        );
        assert_eq!(work.pieces, n as u64 * one_work.pieces, "{n}: {work:?}");
        let (bed, bed_one) = (&r.objects[0], &one.objects[0]);
        assert_eq!(bed.sides, bed_one.sides, "{n}: only the first plant blocks");
        assert_eq!(bed.score, bed_one.score);
    }
    // The plant covers part of the left strip (x in [0.95, 1.15], y in [2.9, 5]); the front and
    // right strips are free, so the bed's best side scores 1.
    let left = &one.objects[0].sides[1];
    assert_eq!(left.side, Side::Left);
    assert_eq!(left.blocked_by, vec![ObjectId::new("plant0")]);
    assert!(left.score > 0.5 && left.score < 0.95, "{}", left.score);
    assert_eq!(one.objects[0].score, Some(1.0));
}

/// A box object: category, half extents, centre, yaw and functional sides.
type Furniture = (&'static str, Vector3, (f64, f64, f64), f64, &'static [Side]);

/// A Holodeck-like bedroom (issue 34: six objects x 200 duplicates was OOM-killed at 24 GB):
/// a bed, two nightstands, a desk, a round lamp and a wardrobe, each placed `copies` times at
/// one pose, with their functional sides stated.
fn duplicated_bedroom(copies: usize) -> Scene {
    let lamp = common::sphere(0.2, 8);
    let mut b = scene();
    let boxes: [Furniture; 5] = [
        (
            "bed",
            Vector3::new(0.8, 1.05, 0.3),
            (2.0, 3.9, 0.3),
            0.0,
            &[Side::Front, Side::Left, Side::Right],
        ),
        (
            "nightstand",
            Vector3::new(0.22, 0.2, 0.28),
            (0.9, 4.7, 0.28),
            0.0,
            &[Side::Front],
        ),
        (
            "nightstand",
            Vector3::new(0.22, 0.2, 0.28),
            (3.1, 4.7, 0.28),
            0.1,
            &[Side::Front],
        ),
        (
            "desk",
            Vector3::new(0.6, 0.3, 0.38),
            (3.6, 1.5, 0.38),
            1.2,
            &[Side::Front],
        ),
        (
            "wardrobe",
            Vector3::new(0.5, 0.3, 1.0),
            (0.35, 1.6, 1.0),
            -std::f64::consts::FRAC_PI_2,
            &[Side::Front],
        ),
    ];
    for k in 0..copies {
        for (i, (cat, half, (x, y, z), yaw, sides)) in boxes.iter().enumerate() {
            b = b.object(
                SceneObject::new_box(
                    format!("{cat}{i}_{k}"),
                    *half,
                    pose_from_yaw(Point3::new(*x, *y, *z), *yaw),
                )
                .unwrap()
                .with_category(*cat)
                .with_functional_sides(sides.iter().copied()),
            );
        }
        b = b.object(
            SceneObject::from_mesh(
                format!("lamp_{k}"),
                Arc::clone(&lamp),
                common::at(1.05, 3.0, 0.2, 0.4),
            )
            .unwrap()
            .with_category("floor lamp")
            .with_functional_sides([Side::Front]),
        );
    }
    b.build().unwrap()
}

#[test]
fn duplicated_objects_cost_polynomially_in_every_metric() {
    // The house of issue 34 scaled down to 40 copies of each object. Accessibility's pieces
    // stay those of one copy; every metric finishes and every first copy scores as alone.
    let params = PlausibilityParams::default();
    let sides = Stated;
    let single = duplicated_bedroom(1);
    let (one, one_work) = accessibility_with_work(&single, &params.accessibility, &sides).unwrap();
    let copies = 40;
    let s = duplicated_bedroom(copies);
    let (acc, work) = accessibility_with_work(&s, &params.accessibility, &sides).unwrap();
    // Every copy's strip meets every copy of what one strip met (its own object's copies
    // included): subtractions grow with the square of the copies, and each leaves no more
    // pieces than one copy's strips hold.
    assert_eq!(work.most_pieces, one_work.most_pieces, "{work:?} {one_work:?}");
    let strips: usize = one.objects.iter().map(|o| o.sides.len()).sum();
    let squared = (copies * copies) as u64;
    assert!(
        work.subtractions <= squared * (one_work.subtractions + strips as u64),
        "{work:?}"
    );
    assert!(
        work.pieces <= work.subtractions * one_work.most_pieces,
        "{work:?}"
    );
    for (k, o) in one.objects.iter().enumerate() {
        // The first copy of object k is object k of the duplicated scene.
        assert_eq!(acc.objects[k].score, o.score, "{}", o.id);
    }
    let report = evaluate(&s, &params, &Sources::default()).unwrap();
    common::check_invariants(&report);
    // Collision's narrow phase sees every pair of copies (6 groups of C(40, 2) = 780) plus the
    // pairs of different objects whose boxes meet (the lamp and the bed's foot, 40 x 40).
    let (_, cw) = collision_with_work(&s, &params.collision).unwrap();
    assert!(cw.candidate_pairs >= 6 * 780, "{cw:?}");
    assert!(cw.candidate_pairs <= 6 * 780 + 3 * copies * copies, "{cw:?}");
}

/// Answers "no sides" for every object but `last`, whose sides are asked last on one thread;
/// asked for `last`, it cancels `deadline` and answers its front.
struct CancelAtLast {
    last: &'static str,
    deadline: Deadline,
}

impl Source<FunctionalSidesOf> for CancelAtLast {
    fn answer(&self, _: &Scene, o: &SceneObject) -> Option<Answer<Vec<Side>>> {
        let value = if o.id().as_str() == self.last {
            self.deadline.cancel();
            vec![Side::Front]
        } else {
            Vec::new()
        };
        Some(Answer {
            value,
            source: "test".into(),
        })
    }
}

#[test]
fn a_deadline_stops_accessibility_inside_one_strip() {
    // The deadline passes while the last object's strip is computed: the footprints over it
    // are subtracted one at a time, checking the deadline before each, so the metric stops
    // (it used to check only before each object, and finished a strip however long it took).
    let mut b = scene();
    for k in 0..8 {
        b = b.add_box(
            format!("post{k}"),
            Category::new("post"),
            Vector3::new(0.03, 0.03, 1.0),
            pose_from_yaw(Point3::new(1.3 + 0.2 * f64::from(k), 2.6, 1.0), 0.7),
        );
    }
    let s = b
        .add_box(
            "cabinet",
            Category::new("cabinet"),
            Vector3::new(1.0, 0.3, 0.5),
            pose_from_yaw(Point3::new(2.0, 3.0, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let deadline = Deadline::none();
    let sources = Sources::new(
        SupportTypePriors::default(),
        CancelAtLast {
            last: "cabinet",
            deadline: deadline.clone(),
        },
    );
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let run = |deadline: &Deadline| {
        pool.install(|| {
            evaluate_metrics(
                &s,
                &PlausibilityParams::default(),
                &sources,
                &[Metric::Accessibility],
                deadline,
                &mut Vec::new(),
            )
        })
    };
    let err = run(&deadline).unwrap_err();
    assert!(
        matches!(
            err,
            PlausibilityError::DeadlineExceeded {
                stage: "accessibility",
                budget_seconds: None
            }
        ),
        "{err}"
    );
    // Without a deadline to cancel, the strip is blocked by the eight posts.
    let r = run(&Deadline::none()).unwrap();
    assert_eq!(r.accessibility.unwrap().objects[8].sides[0].blocked_by.len(), 8);
}

#[test]
fn metrics_finished_before_the_deadline_are_kept() {
    // The deadline is cancelled while support handles its 5th object: collision is kept,
    // support and every later metric fail at once, each naming itself.
    let s = row_of_boxes(36);
    let deadline = Deadline::none();
    let sources = cancelling_at_fifth(&deadline);
    let mut timings = Vec::new();
    let (report, failed) = evaluate_metrics_each(
        &s,
        &PlausibilityParams::default(),
        &sources,
        &Metric::ALL,
        &deadline,
        &mut timings,
    )
    .unwrap();
    let alone = collision(&s, &CollisionParams::default()).unwrap();
    assert_eq!(report.collision, Some(alone));
    assert!(report.support.is_none() && report.opening_clearance.is_none());
    assert_eq!(
        timings.iter().map(|t| t.metric).collect::<Vec<_>>(),
        [Metric::Collision]
    );
    let stopped: Vec<(Metric, &str)> = failed
        .iter()
        .map(|(m, e)| match e {
            PlausibilityError::DeadlineExceeded { stage, .. } => (*m, *stage),
            e => panic!("{m}: {e}"),
        })
        .collect();
    let names: Vec<(Metric, &str)> = Metric::ALL[1..].iter().map(|m| (*m, m.name())).collect();
    assert_eq!(stopped, names);
    assert_eq!(report.summary.col_sc, Some(false));
    assert_eq!(report.summary.sup, None);
}
