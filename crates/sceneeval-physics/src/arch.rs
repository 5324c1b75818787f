//! The rooms as fixed colliders: each floor a thick slab, each wall's solid boxes grown away
//! from the room, doors and windows left open.
//!
//! - **Floor**: a convex slab [`FLOOR_THICKNESS`] deep whose top is the floor's height as the
//!   scene gives it, spanning the convex hull of the floor's outline grown by
//!   [`FLOOR_MARGIN`] on every side (so under the walls). An object sunk into it is pushed
//!   straight up (the top is the nearest way out for anything sunk less than the margin).
//!   An L-shaped room's slab also covers its notch, which lies behind the walls.
//! - **Walls**: each box of [`sceneeval_scene::Wall::solid_boxes`] (the wall with its doors
//!   and windows cut out) as an oriented cuboid whose inner face stays where the scene puts it
//!   and whose thickness grows away from the room to at least [`WALL_THICKNESS`], unless
//!   another room's floor lies behind it (probed at the box's middle and ends): a wall between
//!   two rooms keeps its own thickness (at least [`MIN_SHARED_WALL_THICKNESS`]) so that it
//!   does not reach into the neighbour.
//! - Rooms at different floor heights: a slab's margin reaches under the neighbouring room's
//!   floor, lifting what stands within 0.5 m of the shared wall onto the higher floor; scenes
//!   of one level (all SceneEval rooms) are not affected.
//! - **Ceilings** are not simulated: gravity pulls away from them, and what hangs from them is
//!   welded under the architectural weld modes.

use rapier3d_f64::prelude::*;
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::parry_adapter::{point_to_parry, to_parry_pose};
use sceneeval_geom::planar::convex_hull;
use sceneeval_geom::{Isometry3, Point2, Point3, Real};
use sceneeval_scene::Scene;

/// Depth of the floor slab below the floor's surface, metres.
pub const FLOOR_THICKNESS: Real = 1.0;
/// How far the floor slab reaches beyond the floor's outline, metres.
pub const FLOOR_MARGIN: Real = 0.5;
/// Smallest thickness of a simulated wall, metres (grown away from the room).
pub const WALL_THICKNESS: Real = 0.5;
/// Smallest thickness of a wall with another room behind it, metres: it keeps its own
/// thickness (a zero-thickness wall between two rooms becomes a 1 mm sheet).
pub const MIN_SHARED_WALL_THICKNESS: Real = 0.001;

/// Tags of colliders: an object's index, or an architecture element (offset by this).
pub(crate) const ARCH_TAG: u128 = 1 << 64;

/// Adds every room's floor and walls to `world` as colliders of one fixed body; returns the
/// names of the architecture elements, indexed by `tag - ARCH_TAG`.
pub(crate) fn add_architecture(world: &mut PhysicsWorld, scene: &Scene, friction: Real) -> Vec<String> {
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let mut names = Vec::new();
    let mut add = |world: &mut PhysicsWorld, name: String, collider: ColliderBuilder| {
        let tag = ARCH_TAG + names.len() as u128;
        names.push(name);
        world.insert_collider(
            collider.friction(friction).restitution(0.0).user_data(tag),
            Some(ground),
        );
    };
    for (r, room) in scene.rooms().iter().enumerate() {
        if let Some(slab) = floor_slab(room.floor().points(), room.floor_z()) {
            add(world, room.floor_id().to_owned(), slab);
        } else {
            tracing::warn!(room = %room.id(), "floor outline gives no slab; the room has no floor");
        }
        // Is the plan point over another room's floor?
        let other_room = |x: Real, y: Real| {
            let p = Point2::new(x, y);
            scene
                .rooms()
                .iter()
                .enumerate()
                .any(|(k, o)| k != r && o.floor().contains_point(&p))
        };
        for wall in room.walls() {
            let inward = wall.inward_normal_3d();
            for b in wall.solid_boxes() {
                let h = b.half_extents;
                if !(h.x > 0.0 && h.z > 0.0) {
                    continue;
                }
                let thickness = 2.0 * h.y;
                // Grow away from the room unless another room lies behind the wall: probe its
                // middle and both ends (1 cm in) just behind the wall and at the grown depth.
                let along = b.rotation * sceneeval_geom::Vector3::x();
                let neighbour = [-1.0, 0.0, 1.0].into_iter().any(|s| {
                    let u = s * (h.x - 0.01).max(0.0);
                    [thickness + 0.01, WALL_THICKNESS - 0.01].into_iter().any(|d| {
                        let p = b.center + along * u - inward * (d - 0.5 * thickness);
                        other_room(p.x, p.y)
                    })
                });
                let grown = if neighbour {
                    thickness.max(MIN_SHARED_WALL_THICKNESS)
                } else {
                    thickness.max(WALL_THICKNESS)
                };
                // Keep the inner face: move the centre away from the room by half the growth.
                let center = b.center - inward * (0.5 * (grown - thickness));
                let pose = Isometry3::from_parts(
                    Translation3::from(center.coords),
                    UnitQuaternion::from_rotation_matrix(&b.rotation),
                );
                let collider = ColliderBuilder::cuboid(h.x, 0.5 * grown, h.z).position(to_parry_pose(&pose));
                add(world, wall.id().to_owned(), collider);
            }
        }
    }
    names
}

/// The floor slab of an outline at height `z`: the hull of the outline grown by the margin,
/// from `z - FLOOR_THICKNESS` to `z`.
fn floor_slab(outline: &[Point2], z: Real) -> Option<ColliderBuilder> {
    let m = FLOOR_MARGIN;
    let grown: Vec<Point2> = convex_hull(outline)
        .iter()
        .flat_map(|p| {
            [(-m, -m), (m, -m), (m, m), (-m, m)]
                .into_iter()
                .map(move |(dx, dy)| Point2::new(p.x + dx, p.y + dy))
        })
        .collect();
    let points: Vec<_> = convex_hull(&grown)
        .iter()
        .flat_map(|p| {
            [
                Point3::new(p.x, p.y, z),
                Point3::new(p.x, p.y, z - FLOOR_THICKNESS),
            ]
        })
        .map(|p| point_to_parry(&p))
        .collect();
    ColliderBuilder::convex_hull(&points)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_scene::RoomBuilder;

    #[test]
    fn floors_and_walls_become_fixed_colliders_outside_the_room() {
        // A 4 x 5 m room at floor height 0.2 with a door in wall 0 (y = 0, from x = 1 to 1.9).
        let scene = Scene::builder()
            .room_builder(
                RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
                    .floor_z(0.2)
                    .door(0, [1.0, 1.9], [0.0, 2.1]),
            )
            .build()
            .unwrap();
        let mut world = PhysicsWorld::default();
        let names = add_architecture(&mut world, &scene, 0.5);
        // One floor, four walls, wall 0 cut into three boxes (left, above the door, right).
        assert_eq!(names.len(), 1 + 3 + 3);
        let floor = world
            .colliders
            .iter()
            .find(|(_, c)| c.user_data == ARCH_TAG)
            .unwrap()
            .1;
        let aabb = floor.compute_aabb();
        // The slab: the room grown by 0.5 m, 1 m deep below z = 0.2.
        assert!((aabb.maxs.z - 0.2).abs() < 1e-12 && (aabb.mins.z + 0.8).abs() < 1e-12);
        assert!((aabb.mins.x + 0.5).abs() < 1e-12 && (aabb.maxs.y - 5.5).abs() < 1e-12);
        // Every wall box lies outside the room (inner faces on its outline) and is 0.5 m thick.
        for (_, c) in world.colliders.iter().filter(|(_, c)| c.user_data > ARCH_TAG) {
            let a = c.compute_aabb();
            let outside =
                a.maxs.y <= 1e-9 || a.mins.y >= 5.0 - 1e-9 || a.maxs.x <= 1e-9 || a.mins.x >= 4.0 - 1e-9;
            assert!(outside, "{a:?}");
            let thick = (a.maxs.x - a.mins.x).min(a.maxs.y - a.mins.y);
            assert!((thick - 0.5).abs() < 1e-9, "{a:?}");
        }
    }
}
