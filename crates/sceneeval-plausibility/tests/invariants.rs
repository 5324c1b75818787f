//! Property tests: laws that hold for any placement.

// Test helpers outside #[test] functions may unwrap too.
#![allow(clippy::unwrap_used)]

mod common;

use common::scene;
use proptest::prelude::*;
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Point3, Vector3};
use sceneeval_plausibility::*;
use sceneeval_scene::Category;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A box entirely inside the room is fully in bounds, and any box's ratio is in [0, 1]
    /// and falls as the box leaves the floor.
    #[test]
    fn oob_ratio_bounds(x in 0.5..3.5f64, y in 0.5..4.5f64, w in 0.1..0.7f64, yaw in 0.0..6.3f64, dx in 0.0..3.0f64) {
        let s = scene()
            .add_box("in", Category::new("box"), Vector3::new(w, w, 1.0) * 0.5, pose_from_yaw(Point3::new(x, y, 0.5), yaw))
            .add_box("moved", Category::new("box"), Vector3::new(w, w, 1.0) * 0.5, pose_from_yaw(Point3::new(x + dx, y, 0.5), yaw))
            .build()
            .unwrap();
        let r = out_of_bounds(&s, &OutOfBoundsParams::default()).unwrap();
        // Half diagonal at most 0.7 / sqrt(2) < 0.495, and the centre is at least 0.5 from every
        // wall: inside at any yaw.
        prop_assert!((r.objects[0].ratio_in_bounds - 1.0).abs() < 1e-9);
        let moved = r.objects[1].ratio_in_bounds;
        prop_assert!((0.0..=1.0).contains(&moved));
        prop_assert!(moved <= 1.0 + 1e-12);
    }

    /// Collision does not depend on the order of objects, and nothing collides with itself.
    #[test]
    fn collision_is_order_independent(
        ax in 1.0..3.0f64, ay in 1.0..4.0f64, bx in 1.0..3.0f64, by in 1.0..4.0f64,
        az in 0.0..0.5f64, yaw in 0.0..3.2f64,
    ) {
        let mk = |first: bool| {
            let mut b = scene();
            let boxes = [
                ("a", Point3::new(ax, ay, 0.3 + az), 0.0),
                ("b", Point3::new(bx, by, 0.3), yaw),
            ];
            let order: Vec<usize> = if first { vec![0, 1] } else { vec![1, 0] };
            for i in order {
                let (id, c, yw) = boxes[i];
                b = b.add_box(id, Category::new("box"), Vector3::new(0.4, 0.3, 0.3), pose_from_yaw(c, yw));
            }
            b.build().unwrap()
        };
        let r1 = collision(&mk(true), &CollisionParams::default()).unwrap();
        let r2 = collision(&mk(false), &CollisionParams::default()).unwrap();
        prop_assert_eq!(r1.col_sc, r2.col_sc);
        prop_assert_eq!(r1.num_in_collision, r2.num_in_collision);
        // The first bound found above the tolerance depends on which object is searched
        // first; the largest one does not.
        let deepest = CollisionParams { depth_search: sceneeval_geom::DepthSearch::All, ..CollisionParams::default() };
        let d1 = collision(&mk(true), &deepest).unwrap();
        let d2 = collision(&mk(false), &deepest).unwrap();
        if let (Some(c1), Some(c2)) = (d1.contacts.first(), d2.contacts.first()) {
            prop_assert!((c1.depth - c2.depth).abs() < 1e-9, "{:?} {:?}", c1, c2);
        }
        // Boxes whose centres are farther apart than their half diagonals never touch.
        let d = ((ax - bx).powi(2) + (ay - by).powi(2)).sqrt();
        if d > 1.0 + 1e-9 {
            prop_assert!(r1.contacts.is_empty());
        }
    }

    /// Navigability and accessibility scores stay in [0, 1] and NAV is 1 with one object.
    #[test]
    fn scores_are_shares(x in 0.6..3.4f64, y in 0.6..4.4f64, yaw in 0.0..6.3f64) {
        let s = scene()
            .add_box("bed", Category::new("bed"), Vector3::new(0.4, 0.45, 0.3), pose_from_yaw(Point3::new(x, y, 0.3), yaw))
            .build()
            .unwrap();
        let nav = navigability(&s, &NavigabilityParams { resolution: Resolution::Pixels(64), ..NavigabilityParams::default() }).unwrap();
        prop_assert!((0.0..=1.0).contains(&nav.nav));
        let acc = accessibility(&s, &AccessibilityParams::default(), &FunctionalSidePriors::default()).unwrap();
        let score = acc.objects[0].score.unwrap();
        prop_assert!((0.0..=1.0).contains(&score));
        // Each strip is 0.2 m wide and as long as its side.
        for side in &acc.objects[0].sides {
            let len = if matches!(side.side, sceneeval_geom::Side::Front | sceneeval_geom::Side::Back) { 0.8 } else { 0.9 };
            prop_assert!((side.strip_area - 0.2 * len).abs() < 1e-9);
        }
    }
}
