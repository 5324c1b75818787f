//! The per-object checks for optimisers give the metrics' numbers, bit for bit.

#![allow(clippy::unwrap_used)]

mod common;

use sceneeval_geom::Vector3;
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_plausibility::{LayoutChecks, LayoutScratch, OutOfBoundsParams, out_of_bounds};
use sceneeval_scene::Category;

#[test]
fn in_bounds_ratios_equal_the_metric() {
    // Boxes inside, straddling walls and corners, turned, sunk below the floor, and a ball.
    let mut b = common::scene();
    for k in 0..24 {
        let t = f64::from(k);
        let (x, y) = (-0.4 + 0.2 * t, 5.3 - 0.23 * t);
        b = b.add_box(
            format!("box{k}"),
            Category::new("box"),
            Vector3::new(0.3, 0.2, 0.25),
            pose_from_yaw(sceneeval_geom::Point3::new(x, y, 0.25 - 0.02 * t), 0.4 * t),
        );
    }
    let scene = b
        .add_mesh(
            "ball",
            Category::new("ball"),
            common::sphere(0.3, 10),
            common::at(3.9, 0.2, 0.3, 0.0),
        )
        .build()
        .unwrap();
    let params = OutOfBoundsParams::default();
    let report = out_of_bounds(&scene, &params).unwrap();
    let checks = LayoutChecks::new(scene.rooms(), &params).unwrap();
    let mut scratch = LayoutScratch::default();
    let mut partial = 0;
    for (o, r) in scene.objects().iter().zip(&report.objects) {
        let ratio = checks.in_bounds_ratio(o, &mut scratch);
        assert_eq!(ratio.to_bits(), r.ratio_in_bounds.to_bits(), "{}", o.id());
        assert_eq!(checks.is_out_of_bounds(o, &mut scratch), r.out_of_bounds);
        partial += usize::from(ratio > 0.0 && ratio < 1.0);
    }
    assert!(partial >= 4, "only {partial} objects straddle the outline");
}
