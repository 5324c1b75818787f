//! Invariants of the scene model: walls face into their room whatever the room's shape,
//! winding and orientation; object boxes follow their poses.

#![allow(clippy::expect_used)]

use proptest::prelude::*;
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Point2, Point3, Side, Vector2, Vector3};
use sceneeval_scene::{InwardEvidence, RoomBuilder, SceneObject};

/// A simple star-shaped outline (random radii at increasing angles), possibly clockwise.
fn outline() -> impl Strategy<Value = Vec<Point2>> {
    (
        prop::collection::vec(1.0..4.0f64, 3..9),
        -2.0..2.0f64,
        -2.0..2.0f64,
        -3.2..3.2f64,
        any::<bool>(),
    )
        .prop_map(|(radii, cx, cy, phase, clockwise)| {
            let n = radii.len();
            let mut pts: Vec<Point2> = radii
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let a = phase + std::f64::consts::TAU * i as f64 / n as f64;
                    Point2::new(cx + r * a.cos(), cy + r * a.sin())
                })
                .collect();
            if clockwise {
                pts.reverse();
            }
            pts
        })
}

fn rotate(p: &Point2, angle: f64) -> Point2 {
    let (s, c) = angle.sin_cos();
    Point2::new(c * p.x - s * p.y, s * p.x + c * p.y)
}

proptest! {
    /// Every wall of a room built on a simple outline faces into the floor: a point a little way
    /// along the inward normal from the wall's middle is on the floor, its mirror is not.
    #[test]
    fn walls_face_into_their_room(pts in outline()) {
        let room = RoomBuilder::polygon("r", pts).build().expect("valid outline");
        for w in room.walls() {
            prop_assert_eq!(w.inward_evidence(), InwardEvidence::Floor);
            let mid = w.start() + w.direction() * (w.length() * 0.5);
            let n = w.inward_normal();
            prop_assert!((n.norm() - 1.0).abs() < 1e-12);
            prop_assert!(n.dot(&w.direction()).abs() < 1e-12);
            prop_assert!(room.floor().contains_point(&(mid + n * 1e-3)));
            prop_assert!(!room.floor().contains_point(&(mid - n * 1e-3)));
            // The wall's box lies on the far side of its inner face.
            let plane = w.inner_plane();
            for c in w.obb().corners() {
                prop_assert!(plane.signed_distance(&c) <= 1e-9);
            }
        }
    }

    /// Rotating the whole room about z rotates every inward normal by the same angle.
    #[test]
    fn inward_normals_rotate_with_the_room(pts in outline(), angle in -3.2..3.2f64) {
        let a = RoomBuilder::polygon("a", pts.clone()).build().expect("valid outline");
        let b = RoomBuilder::polygon("b", pts.iter().map(|p| rotate(p, angle)).collect()).build().expect("valid outline");
        for (wa, wb) in a.walls().iter().zip(b.walls()) {
            let expected = rotate(&Point2::from(wa.inward_normal()), angle).coords;
            prop_assert!((wb.inward_normal() - expected).norm() < 1e-9);
        }
    }

    /// A box object's OBB is centred on its centre, and its front is its yaw applied to -y.
    #[test]
    fn box_objects_follow_their_pose(
        x in -5.0..5.0f64, y in -5.0..5.0f64, z in 0.0..2.0f64,
        sx in 0.1..2.0f64, sy in 0.1..2.0f64, sz in 0.1..2.0f64, yaw in -3.1..3.1f64,
    ) {
        let o = SceneObject::new_box("o", Vector3::new(sx, sy, sz) * 0.5, pose_from_yaw(Point3::new(x, y, z), yaw)).expect("valid box");
        prop_assert!((o.obb().center - Point3::new(x, y, z)).norm() < 1e-12);
        let front = o.obb().side_direction(Side::Front);
        let expected = Vector2::new(yaw.sin(), -yaw.cos());
        prop_assert!((front.xy() - expected).norm() < 1e-12 && front.z.abs() < 1e-12);
        prop_assert!((o.yaw() - yaw).abs() < 1e-9);
        prop_assert!((o.world_aabb().volume() - o.obb().aabb().volume()).abs() < 1e-9);
    }
}
