//! The rooms as fixed colliders: each floor a thick slab, each wall's solid boxes grown away
//! from the room, doors and windows left open.
//!
//! - **Floor**: a convex slab [`FLOOR_THICKNESS`] deep whose top is the floor's height as the
//!   scene gives it, spanning the convex hull of the floor's outline grown by
//!   [`FLOOR_MARGIN`] on every side (so under the walls). An object sunk into it is pushed
//!   straight up (the top is the nearest way out for anything sunk less than the margin).
//!   An L-shaped room's slab also covers its notch, which lies behind the walls.
//! - **Walls**: each box of [`sceneeval_scene::Wall::solid_boxes`] (the wall with its doors
//!   and windows cut out) as oriented cuboids whose inner face stays where the scene puts it
//!   and whose thickness grows away from the room to at least [`WALL_THICKNESS`], but never
//!   into a room: a wall collider lies outside every room it bounds. Behind a wall between
//!   two rooms lies the neighbour's floor, which the scene's own thickness would reach into
//!   (a flush object there would start "interpenetrating" the wall and be pushed away from
//!   it); so every floor at the wall's level (its outline triangulated) is clipped against the
//!   wall's grown footprint, and along each stretch of the wall the collider reaches only to
//!   the nearest floor behind it: a wall between two rooms that touch becomes a sheet of zero
//!   thickness on the shared line, a wall with a gap behind it fills the gap. For a floor
//!   that is not convex the stretch's depth is that of the nearest point of each of its
//!   triangles behind the stretch: possibly thinner than the gap, never inside the floor.
//! - Rooms at different floor heights: a slab's margin reaches under the neighbouring room's
//!   floor, lifting what stands within 0.5 m of the shared wall onto the higher floor; scenes
//!   of one level (all SceneEval rooms) are not affected.
//! - **Ceilings** are not simulated: gravity pulls away from them, and what hangs from them is
//!   welded under the architectural weld modes.

use rapier3d_f64::prelude::*;
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::parry_adapter::{point_to_parry, to_parry_pose};
use sceneeval_geom::planar::{area, bounds, clip_convex, convex_hull};
use sceneeval_geom::{Isometry3, Point2, Point3, Real, Vector3};
use sceneeval_scene::Scene;

/// Depth of the floor slab below the floor's surface, metres.
pub const FLOOR_THICKNESS: Real = 1.0;
/// How far the floor slab reaches beyond the floor's outline, metres.
pub const FLOOR_MARGIN: Real = 0.5;
/// Smallest thickness of a simulated wall, metres (grown away from the room).
pub const WALL_THICKNESS: Real = 0.5;
/// Overlaps of a wall's footprint with a floor of at most this area (m²) are touches, not
/// overlaps: a wall's own floor meets its inner face along a line.
const TOUCH_AREA: Real = 1e-9;

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
    for room in scene.rooms() {
        if let Some(slab) = floor_slab(room.floor().points(), room.floor_z()) {
            add(world, room.floor_id().to_owned(), slab);
        } else {
            tracing::warn!(room = %room.id(), "floor outline gives no slab; the room has no floor");
        }
        for wall in room.walls() {
            for b in wall.solid_boxes() {
                for collider in wall_colliders(scene, b) {
                    add(world, wall.id().to_owned(), collider);
                }
            }
        }
    }
    names
}

/// The colliders of one solid box of a wall (wall frame: x along the wall, y away from the
/// room, z up; the box's inner face at `-y`): the box grown away from the room to
/// [`WALL_THICKNESS`], cut along the wall into stretches that each reach only to the nearest
/// floor behind them (zero thickness where a floor starts at the inner face).
fn wall_colliders(scene: &Scene, b: &sceneeval_geom::Obb) -> Vec<ColliderBuilder> {
    let h = b.half_extents;
    if !(h.x > 0.0 && h.z > 0.0) {
        return Vec::new();
    }
    let along = b.rotation * Vector3::x();
    let away = b.rotation * Vector3::y();
    let inner = b.center - away * h.y;
    let depth = (2.0 * h.y).max(WALL_THICKNESS);
    // The footprint in the wall's plan coordinates (u along, d away), counter-clockwise.
    let footprint = [
        Point2::new(-h.x, 0.0),
        Point2::new(h.x, 0.0),
        Point2::new(h.x, depth),
        Point2::new(-h.x, depth),
    ];
    let to_strip = |p: &Point2| {
        let q = Vector3::new(p.x - inner.x, p.y - inner.y, 0.0);
        Point2::new(q.dot(&along), q.dot(&away))
    };
    // The floors behind: per triangle overlapping the footprint, its stretch and nearest depth.
    let top = b.center.z + h.z;
    let mut behind: Vec<(Real, Real, Real)> = Vec::new();
    for room in scene.rooms().iter().filter(|r| r.floor_z() < top) {
        let outline = room.floor().points();
        for t in room.floor().triangulate() {
            let tri = t.map(|i| to_strip(&outline[i]));
            let piece = clip_convex(&tri, &footprint);
            if area(&piece) > TOUCH_AREA {
                let (lo, hi) = bounds(&piece);
                behind.push((lo.x, hi.x, lo.y.max(0.0)));
            }
        }
    }
    let mut cuts: Vec<Real> = behind
        .iter()
        .flat_map(|&(u0, u1, _)| [u0, u1])
        .chain([-h.x, h.x])
        .map(|u| u.clamp(-h.x, h.x))
        .collect();
    cuts.sort_by(Real::total_cmp);
    cuts.dedup();
    // Stretches of equal depth, merged.
    let mut stretches: Vec<(Real, Real, Real)> = Vec::new();
    for w in cuts.windows(2) {
        let (u0, u1) = (w[0], w[1]);
        let d = behind
            .iter()
            .filter(|&&(a, b, _)| a < u1 && b > u0)
            .fold(depth, |d, &(_, _, near)| d.min(near));
        match stretches.last_mut() {
            Some(last) if last.2 == d => last.1 = u1,
            _ => stretches.push((u0, u1, d)),
        }
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&b.rotation);
    stretches
        .into_iter()
        .filter(|&(u0, u1, _)| u1 > u0)
        .map(|(u0, u1, d)| {
            let center = inner + along * (0.5 * (u0 + u1)) + away * (0.5 * d);
            let pose = Isometry3::from_parts(Translation3::from(center.coords), rotation);
            ColliderBuilder::cuboid(0.5 * (u1 - u0), 0.5 * d, h.z).position(to_parry_pose(&pose))
        })
        .collect()
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

    /// Every wall collider of `scene`: its wall's name, its plan corners and its thickness.
    fn wall_footprints(scene: &Scene) -> Vec<(String, Vec<Point2>, Real)> {
        let mut world = PhysicsWorld::default();
        let names = add_architecture(&mut world, scene, 0.5);
        let mut out: Vec<_> = world
            .colliders
            .iter()
            .filter_map(|(_, c)| {
                let name = names[usize::try_from(c.user_data - ARCH_TAG).ok()?].clone();
                let h = c.shape().as_cuboid()?.half_extents;
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(sx, sy)| {
                        let p = c.position() * rapier3d_f64::math::Vector::new(sx * h.x, sy * h.y, 0.0);
                        Point2::new(p.x, p.y)
                    })
                    .to_vec();
                Some((name, corners, 2.0 * h.y))
            })
            .collect();
        out.sort_by(|a, b| a.0.cmp(&b.0));
        out
    }

    /// The area of `footprint` inside any room's floor.
    fn inside_rooms(scene: &Scene, footprint: &[Point2]) -> Real {
        scene
            .rooms()
            .iter()
            .map(|r| r.floor().intersection_area_with_convex(footprint))
            .sum()
    }

    #[test]
    fn walls_shared_by_two_rooms_reach_into_neither() {
        // Two rooms side by side sharing the line x = 4 (each lists its own wall there, its
        // thickness away from its room, so into the other): zero-thickness walls, Holodeck's
        // 0.025 m and 0.1 m. The shared walls become sheets on x = 4; the others keep 0.5 m.
        for t in [0.0, 0.025, 0.1] {
            let scene = Scene::builder()
                .room_builder(
                    RoomBuilder::rectangle("a", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
                        .wall_thickness(t),
                )
                .room_builder(
                    RoomBuilder::rectangle("b", Point2::new(4.0, 0.0), Point2::new(9.0, 5.0))
                        .wall_thickness(t),
                )
                .build()
                .unwrap();
            let walls = wall_footprints(&scene);
            assert_eq!(walls.len(), 8, "{walls:?}");
            for (name, corners, thickness) in &walls {
                assert!(inside_rooms(&scene, corners) <= 1e-9, "{t}: {name} {corners:?}");
                let shared = corners.iter().all(|p| (p.x - 4.0).abs() < 1e-12);
                assert_eq!(shared, *thickness == 0.0, "{t}: {name} {corners:?} {thickness}");
                if !shared {
                    assert!((thickness - 0.5).abs() < 1e-12, "{t}: {name} {thickness}");
                }
            }
            assert_eq!(walls.iter().filter(|w| w.2 == 0.0).count(), 2);
        }
    }

    #[test]
    fn a_wall_reaches_only_to_the_nearest_floor_behind_each_stretch() {
        // Room a (0..4 x 0..5) and room b (4.2..8 x 1..3): behind a's wall x = 4, from y = 1
        // to 3, lies b's floor 0.2 m away; elsewhere nothing. a's wall there is 0.2 m thick
        // from y = 1 to 3 and 0.5 m elsewhere; b's wall x = 4.2 is 0.2 m thick (reaching a's
        // floor).
        let scene = Scene::builder()
            .room_builder(RoomBuilder::rectangle(
                "a",
                Point2::new(0.0, 0.0),
                Point2::new(4.0, 5.0),
            ))
            .room_builder(RoomBuilder::rectangle(
                "b",
                Point2::new(4.2, 1.0),
                Point2::new(8.0, 3.0),
            ))
            .build()
            .unwrap();
        let walls = wall_footprints(&scene);
        let at_x4: Vec<_> = walls
            .iter()
            .filter(|(n, c, _)| n.starts_with("a") && c.iter().all(|p| p.x >= 4.0 - 1e-12))
            .map(|(_, c, t)| {
                let (lo, hi) = sceneeval_geom::planar::bounds(c);
                (lo.y, hi.y, *t)
            })
            .collect();
        let mut at_x4 = at_x4;
        at_x4.sort_by(|a, b| a.0.total_cmp(&b.0));
        let expected = [(0.0, 1.0, 0.5), (1.0, 3.0, 0.2), (3.0, 5.0, 0.5)];
        assert_eq!(at_x4.len(), 3, "{at_x4:?}");
        for (got, want) in at_x4.iter().zip(expected) {
            assert!(
                (got.0 - want.0).abs() < 1e-9
                    && (got.1 - want.1).abs() < 1e-9
                    && (got.2 - want.2).abs() < 1e-9,
                "{got:?} vs {want:?}"
            );
        }
        for (name, corners, _) in &walls {
            assert!(inside_rooms(&scene, corners) <= 1e-9, "{name} {corners:?}");
        }
        // A room with a narrow notch (0.6 m wide at x = 4): the notch's walls, grown away
        // from the room, stop at the room's floor across the notch.
        let notched = RoomBuilder::polygon(
            "n",
            vec![
                Point2::new(0.0, 0.0),
                Point2::new(4.0, 0.0),
                Point2::new(4.0, 1.0),
                Point2::new(1.0, 1.3),
                Point2::new(4.0, 1.6),
                Point2::new(4.0, 3.0),
                Point2::new(0.0, 3.0),
            ],
        );
        let scene = Scene::builder().room_builder(notched).build().unwrap();
        for (name, corners, _) in wall_footprints(&scene) {
            assert!(inside_rooms(&scene, &corners) <= 1e-9, "{name} {corners:?}");
        }
    }
}
