//! The per-object checks for optimisers give the metrics' numbers, bit for bit.

#![allow(clippy::unwrap_used)]

mod common;

use sceneeval_geom::Vector3;
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_plausibility::{
    CollisionParams, LayoutChecks, LayoutScratch, OpeningClearanceParams, OutOfBoundsParams, collision,
    opening_clearance, out_of_bounds,
};
use sceneeval_scene::{Category, Scene};

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

/// Boxes and balls scattered over the room and around its door (x in [1.0, 1.9] on y = 0), a
/// rug among them (below the walkable height).
fn scattered() -> Scene {
    let mut b = common::scene();
    for k in 0..30 {
        let t = f64::from(k);
        let (x, y) = (0.6 + 0.11 * t, 0.05 + 0.17 * (t * 1.7).sin().abs() * t.sqrt());
        if k % 4 == 3 {
            b = b.add_mesh(
                format!("ball{k}"),
                Category::new("ball"),
                common::sphere(0.15 + 0.01 * t, 6),
                common::at(x, y, 0.3, 0.2 * t),
            );
        } else {
            b = b.add_box(
                format!("box{k}"),
                Category::new("box"),
                Vector3::new(0.2 + 0.01 * t, 0.15, 0.2 + 0.005 * t),
                pose_from_yaw(sceneeval_geom::Point3::new(x, y, 0.25), 0.37 * t),
            );
        }
    }
    b.add_box(
        "rug",
        Category::new("rug"),
        Vector3::new(0.6, 0.4, 0.005),
        pose_from_yaw(sceneeval_geom::Point3::new(1.45, 0.5, 0.005), 0.0),
    )
    .build()
    .unwrap()
}

#[test]
fn door_blocking_agrees_with_the_opening_clearance_metric() {
    let scene = scattered();
    let params = OpeningClearanceParams::default();
    let report = opening_clearance(&scene, &params).unwrap();
    let checks = LayoutChecks::new(scene.rooms(), &OutOfBoundsParams::default())
        .unwrap()
        .with_clearance(scene.rooms(), &params)
        .unwrap();
    let blocking: Vec<&str> = report
        .openings
        .iter()
        .filter(|o| o.kind == sceneeval_scene::OpeningKind::Door)
        .flat_map(|o| {
            o.sides
                .iter()
                .flat_map(|s| s.blocking.iter().map(|b| b.id.as_str()))
        })
        .collect();
    let mut count = 0;
    for o in scene.objects() {
        let blocks = checks.blocks_door(o);
        assert_eq!(blocks, blocking.contains(&o.id().as_str()), "{}", o.id());
        count += usize::from(blocks);
    }
    assert!(
        count >= 3 && count < scene.objects().len() / 2,
        "{count} objects block the door"
    );
    // The rug is below the walkable height: it never blocks.
    assert!(!checks.blocks_door(scene.object("rug").unwrap()));
}

#[test]
fn contacts_agree_with_the_collision_metric() {
    let scene = scattered();
    let params = CollisionParams::default();
    let report = collision(&scene, &params).unwrap();
    let checks = LayoutChecks::new(scene.rooms(), &OutOfBoundsParams::default())
        .unwrap()
        .with_collision(&params)
        .unwrap();
    let objects = scene.objects();
    let (mut colliding, mut with_mesh) = (0, 0);
    for i in 0..objects.len() {
        for j in i + 1..objects.len() {
            let (a, b) = (&objects[i], &objects[j]);
            if b.id().as_str() == "rug" {
                // A floor covering: the metric leaves it out (exclude_floor_coverings); which
                // pairs to check is the caller's choice here.
                continue;
            }
            let c = checks.contact(a, b);
            let metric = report.contacts.iter().find(|p| &p.a == a.id() && &p.b == b.id());
            let boxes = a.box_half_extents().is_some() && b.box_half_extents().is_some();
            if boxes {
                let depth = c.depth.unwrap();
                // The metric certifies a lower bound on the same depth; away from the
                // tolerance by more than its sample spacing the verdicts agree.
                if (depth - params.contact_tolerance_m).abs() > 2.0 * params.depth_sample_spacing_m {
                    assert_eq!(
                        c.colliding,
                        metric.is_some_and(|m| m.colliding),
                        "{} / {}",
                        a.id(),
                        b.id()
                    );
                }
                if let Some(m) = metric {
                    assert!(
                        m.depth <= depth + 1e-9,
                        "{}: certified {} > exact {depth}",
                        a.id(),
                        m.depth
                    );
                }
                assert!(depth == 0.0 || c.gradient.is_some());
            } else {
                // Meshes: the solids meet exactly when the metric found a contact.
                assert_eq!(c.colliding, metric.is_some(), "{} / {}", a.id(), b.id());
                with_mesh += usize::from(c.colliding);
            }
            colliding += usize::from(c.colliding);
        }
    }
    assert!(
        colliding >= 5 && with_mesh >= 1,
        "{colliding} colliding pairs, {with_mesh} with a mesh"
    );
}
