//! Footprints (convex hull or the reference's bounding rectangle), floor coverings walked over
//! (or not), and the spatial index's work growing as `n log n`.

// Test helpers outside #[test] functions may unwrap too.
#![allow(clippy::unwrap_used)]

mod common;

use std::sync::Arc;

use common::{at, scene};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Mesh, Point2, Point3, Side, Vector3};
use sceneeval_plausibility::*;
use sceneeval_scene::{Category, RoomBuilder, Scene, SceneObject};

/// A round bath: a closed cylinder of radius `r` and height `h` (64 sides), origin at the
/// centre of its bottom.
fn round_bath(r: f64, h: f64) -> Arc<Mesh> {
    let n = 64u32;
    let mut v = vec![Point3::new(0.0, 0.0, 0.0), Point3::new(0.0, 0.0, h)];
    for k in 0..n {
        let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
        v.push(Point3::new(r * a.cos(), r * a.sin(), 0.0));
        v.push(Point3::new(r * a.cos(), r * a.sin(), h));
    }
    let mut t = Vec::new();
    for k in 0..n {
        let (b0, t0) = (2 + 2 * k, 3 + 2 * k);
        let (b1, t1) = (2 + 2 * ((k + 1) % n), 3 + 2 * ((k + 1) % n));
        t.push([0, b1, b0]);
        t.push([1, t0, t1]);
        t.push([b0, b1, t1]);
        t.push([b0, t1, t0]);
    }
    Arc::new(Mesh::new(v, t).unwrap())
}

/// The 4 x 5 m room split by two shelves along y in [2.3, 2.7] (x <= 1 and x >= 3), and a round
/// bath of radius 1 centred at (2, 3.7) above the 2 m gap between them. Its bounding square
/// spans x in [1, 3], y in [2.7, 4.7]: its corners meet the shelves' corners and close the gap.
/// The circle stays sqrt(2) - 1 = 0.414 m from each shelf corner, leaving a diagonal passage
/// wider than the 0.2 m robot on each side.
fn bath_room() -> Scene {
    scene()
        .add_box(
            "shelf_w",
            Category::new("shelf"),
            Vector3::new(1.0, 0.4, 1.0) * 0.5,
            pose_from_yaw(Point3::new(0.5, 2.5, 0.5), 0.0),
        )
        .add_box(
            "shelf_e",
            Category::new("shelf"),
            Vector3::new(1.0, 0.4, 1.0) * 0.5,
            pose_from_yaw(Point3::new(3.5, 2.5, 0.5), 0.0),
        )
        .add_mesh(
            "bath",
            Category::new("bathtub"),
            round_bath(1.0, 0.5),
            at(2.0, 3.7, 0.0, 0.0),
        )
        .build()
        .unwrap()
}

#[test]
fn a_round_bath_leaves_passages_its_rectangle_closes() {
    let s = bath_room();
    let hull = NavigabilityParams {
        resolution: Resolution::MetresPerPixel(0.02),
        ..NavigabilityParams::default()
    };
    let r = navigability(&s, &hull).unwrap();
    assert_eq!(r.num_components, 1, "{r:?}");
    assert_eq!(r.nav, 1.0);
    let rect = NavigabilityParams {
        footprint: Footprint::BoundingBox,
        ..hull
    };
    let r = navigability(&s, &rect).unwrap();
    // South of the shelves, and the two strips west and east of the bath north of them
    // (joined north of the bath: y from 4.8 to 4.9 stays free).
    assert_eq!(r.num_components, 2, "{r:?}");
    assert!(r.nav < 0.8, "{}", r.nav);
}

#[test]
fn accessibility_uses_the_chosen_footprint() {
    // A 0.3 m cabinet at (2.85, 2.5) turned to face +y: its front face is at y = 2.65, its
    // front strip x in [2.7, 3.0], y in [2.7, 2.9], inside the bath's bounding square (x <= 3,
    // y >= 2.7) but outside the circle (its farthest corner (2.7, 2.9) lies
    // sqrt(0.7^2 + 0.8^2) = 1.063 > 1 from the centre).
    let s = Scene::builder()
        .room_builder(RoomBuilder::rectangle(
            "r0",
            Point2::new(0.0, 0.0),
            Point2::new(6.0, 6.0),
        ))
        .add_mesh(
            "bath",
            Category::new("bathtub"),
            round_bath(1.0, 0.5),
            at(2.0, 3.7, 0.0, 0.0),
        )
        .object(
            SceneObject::new_box(
                "cabinet",
                Vector3::new(0.3, 0.3, 0.8) * 0.5,
                pose_from_yaw(Point3::new(2.85, 2.5, 0.4), std::f64::consts::PI),
            )
            .unwrap()
            .with_category("cabinet")
            .with_functional_sides([Side::Front]),
        )
        .build()
        .unwrap();
    let score = |footprint| {
        let p = AccessibilityParams {
            footprint,
            ..AccessibilityParams::default()
        };
        let r = accessibility(&s, &p, &Stated).unwrap();
        r.objects[1].score.unwrap()
    };
    assert!((score(Footprint::ConvexHull) - 1.0).abs() < 1e-12);
    assert!(score(Footprint::BoundingBox).abs() < 1e-12);
}

#[test]
fn floor_coverings_obstruct_unless_walked_over() {
    // A 1 cm rug across the whole room at y in [2, 3], a doormat in front of the door
    // (x in [1.0, 1.9] on y = 0), and a bed whose front faces the rug. With walkable height 0
    // (the reference) they obstruct; with 2 cm, or the 5 cm default, they are walked over.
    let s = scene()
        .add_box(
            "rug",
            Category::new("rug"),
            Vector3::new(2.0, 0.5, 0.005),
            pose_from_yaw(Point3::new(2.0, 2.5, 0.005), 0.0),
        )
        .add_box(
            "mat",
            Category::new("doormat"),
            Vector3::new(0.4, 0.25, 0.005),
            pose_from_yaw(Point3::new(1.45, 0.3, 0.005), 0.0),
        )
        .build()
        .unwrap();
    let walked = NavigabilityParams {
        resolution: Resolution::MetresPerPixel(0.05),
        walkable_height_m: 0.02,
        ..NavigabilityParams::default()
    };
    let r = navigability(&s, &walked).unwrap();
    assert_eq!(r.num_components, 1);
    assert_eq!(
        r.ignored.iter().map(|i| i.as_str()).collect::<Vec<_>>(),
        ["rug", "mat"]
    );
    let reference = NavigabilityParams {
        walkable_height_m: 0.0,
        ..walked
    };
    // The rug then cuts the room in two (the reference draws it).
    assert_eq!(navigability(&s, &reference).unwrap().num_components, 2);

    assert_eq!(
        navigability(&s, &NavigabilityParams::default())
            .unwrap()
            .num_components,
        1
    );
    let reference = OpeningClearanceParams {
        walkable_height_m: 0.0,
        ..OpeningClearanceParams::default()
    };
    assert_eq!(opening_clearance(&s, &reference).unwrap().doors_blocked, 1);
    assert_eq!(
        opening_clearance(&s, &OpeningClearanceParams::default())
            .unwrap()
            .doors_blocked,
        0
    );
    let walked = OpeningClearanceParams {
        walkable_height_m: 0.02,
        ..OpeningClearanceParams::default()
    };
    assert_eq!(opening_clearance(&s, &walked).unwrap().doors_blocked, 0);

    // The bed's front face is at y = 4.0 - 0.7 = 3.3, its front strip y in [3.05, 3.25]: over
    // a rug spanning y in [2.5, 3.5].
    let s = scene()
        .add_box(
            "rug",
            Category::new("rug"),
            Vector3::new(2.0, 0.5, 0.005),
            pose_from_yaw(Point3::new(2.0, 3.0, 0.005), 0.0),
        )
        .object(
            SceneObject::new_box(
                "bed",
                Vector3::new(0.8, 0.7, 0.3),
                pose_from_yaw(Point3::new(1.0, 4.0, 0.3), 0.0),
            )
            .unwrap()
            .with_category("bed")
            .with_functional_sides([Side::Front]),
        )
        .build()
        .unwrap();
    let reference = AccessibilityParams {
        walkable_height_m: 0.0,
        ..AccessibilityParams::default()
    };
    let a = accessibility(&s, &reference, &Stated).unwrap();
    assert_eq!(a.objects[1].score, Some(0.0));
    assert_eq!(
        accessibility(&s, &AccessibilityParams::default(), &Stated)
            .unwrap()
            .objects[1]
            .score,
        Some(1.0)
    );
    let walked = AccessibilityParams {
        walkable_height_m: 0.02,
        ..AccessibilityParams::default()
    };
    assert_eq!(
        accessibility(&s, &walked, &Stated).unwrap().objects[1].score,
        Some(1.0)
    );
}

/// A square room holding an `n`-object grid of boxes 1.5 m apart, each with a front side.
fn grid(n: usize) -> Scene {
    let cols = (n as f64).sqrt().ceil() as usize;
    let side = cols as f64 * 1.5 + 1.0;
    let mut b = Scene::builder().room_builder(RoomBuilder::rectangle(
        "r0",
        Point2::new(0.0, 0.0),
        Point2::new(side, side),
    ));
    for k in 0..n {
        let (x, y) = (1.0 + (k % cols) as f64 * 1.5, 1.0 + (k / cols) as f64 * 1.5);
        b = b.object(
            SceneObject::new_box(
                format!("o{k}"),
                Vector3::new(0.6, 0.5, 0.8) * 0.5,
                pose_from_yaw(Point3::new(x, y, 0.4), 0.3),
            )
            .unwrap()
            .with_category("cabinet")
            .with_functional_sides([Side::Front]),
        );
    }
    b.build().unwrap()
}

#[test]
fn support_and_accessibility_index_work_grows_as_n_log_n() {
    let mut per_object = Vec::new();
    for n in [256usize, 1024, 4096] {
        let s = grid(n);
        let (sup, sw) =
            support_with_work(&s, &SupportParams::default(), &SupportTypePriors::default()).unwrap();
        assert_eq!(sup.num_supported, n);
        let (acc, aw) = accessibility_with_work(&s, &AccessibilityParams::default(), &Stated).unwrap();
        assert_eq!(acc.num_scored, n);
        per_object.push((
            sw.box_tests as f64 / n as f64,
            aw.index.box_tests as f64 / n as f64,
        ));
    }
    // Sixteen times the objects: a scan of every box would test sixteen times as many per
    // object; the index's tests grow with log n (log2 4096 / log2 256 = 1.5).
    for k in [0, 1] {
        let (first, last) = (
            if k == 0 { per_object[0].0 } else { per_object[0].1 },
            if k == 0 { per_object[2].0 } else { per_object[2].1 },
        );
        assert!(last <= 2.0 * first, "{per_object:?}");
    }
}

#[test]
fn a_two_centimetre_grid_over_a_large_scene_is_stored_as_runs() {
    // A 150 x 150 m hall with 2,500 boxes: 7,520 x 7,520 = 56.6 million pixels at 2 cm (the
    // old per-pixel masks needed about 7 bytes each). The runs need a few per row.
    let n = 2500;
    let cols = 50;
    let side = 150.0;
    let mut b = Scene::builder().room_builder(RoomBuilder::rectangle(
        "hall",
        Point2::new(0.0, 0.0),
        Point2::new(side, side),
    ));
    for k in 0..n {
        let (x, y) = (1.5 + (k % cols) as f64 * 3.0, 1.5 + (k / cols) as f64 * 3.0);
        b = b.add_box(
            format!("o{k}"),
            Category::new("cabinet"),
            Vector3::new(1.2, 0.6, 0.8) * 0.5,
            pose_from_yaw(Point3::new(x, y, 0.4), 0.4),
        );
    }
    let s = b.build().unwrap();
    let p = NavigabilityParams {
        resolution: Resolution::MetresPerPixel(0.02),
        ..NavigabilityParams::default()
    };
    let map = occupancy_map(&s, &p).unwrap();
    let pixels = map.grid.width * map.grid.height;
    assert!(pixels > 50_000_000, "{pixels}");
    // At most one run more than the boxes a row crosses (50), and far fewer than pixels.
    assert!(
        map.free.runs().len() <= map.grid.height * 51,
        "{}",
        map.free.runs().len()
    );
    let r = navigability(&s, &p).unwrap();
    assert_eq!(r.num_components, 1);
    assert_eq!(r.nav, 1.0);
    assert_eq!(r.obstacles.len(), n);
}
