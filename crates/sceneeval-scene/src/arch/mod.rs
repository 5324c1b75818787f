//! Architecture: rooms with a floor polygon, walls with door and window openings, ceilings.
//!
//! # Wall geometry
//! A wall is given by a segment on the floor plan (`start` to `end`), a base height, a height
//! and a thickness. **The segment is the wall's inner face**, the side toward its room; the
//! thickness extends away from the room. (The reference builds 1 mm walls centred on the
//! segment, so its inner face is 0.5 mm from ours.)
//!
//! Each wall is oriented against **its own room's floor polygon**: its inward normal points
//! into that room, for walls at any angle and in scenes with several rooms. The reference tests
//! every wall against the last floor it read and only handles axis-aligned walls
//! (reference notes Q8, Q9).
//!
//! The wall frame puts local -y into the room (a wall's front faces its room, as an object's
//! front is local -y), z up, and x completing a right-handed frame.
//!
//! Openings are rectangles in wall coordinates: `along` is measured from the wall's start
//! point toward its end, `height` above the wall's base.
//!
//! Rooms are built in code with [`RoomBuilder`], or from a room described as plain data
//! ([`RoomSpec`]: an outline, heights, thickness, doors and windows by wall index; the room of
//! `sceneeval relate`'s JSON lines and of the Python package's dicts).

mod builder;
mod kind;
mod opening;
mod room;
mod spec;
mod wall;

pub use builder::RoomBuilder;
pub use kind::ArchElement;
pub use opening::{Opening, OpeningKind, PlacedOpening};
pub use room::{Ceiling, Floor, Room};
pub use spec::{OpeningSpec, RoomSpec, RoomSpecError};
pub use wall::{InwardEvidence, Wall, WallSpec};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SceneError;
    use sceneeval_geom::{Isometry3, Point2, Point3, Polygon2, Real, Vector2, Vector3};

    fn p(x: Real, y: Real) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn rectangle_walls_face_inward_either_winding() {
        for outline in [
            vec![p(0.0, 0.0), p(4.0, 0.0), p(4.0, 5.0), p(0.0, 5.0)],
            vec![p(0.0, 0.0), p(0.0, 5.0), p(4.0, 5.0), p(4.0, 0.0)],
        ] {
            let room = RoomBuilder::polygon("r", outline).build().unwrap();
            let centre = room.floor().centroid();
            for w in room.walls() {
                let mid = w.start() + w.direction() * (w.length() * 0.5);
                assert!(w.inward_normal().dot(&(centre - mid)) > 0.0, "{}", w.id());
                assert_eq!(w.inward_evidence(), InwardEvidence::Floor);
                // Frame: local -y is the inward normal, z up, right-handed.
                let r = w.rotation();
                assert!((r * -Vector3::y() - w.inward_normal_3d()).norm() < 1e-12);
                assert!((r.matrix().determinant() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn diagonal_wall_faces_inward() {
        // A right triangle: the hypotenuse from (4, 0) to (0, 4) is diagonal.
        let room = RoomBuilder::polygon("tri", vec![p(0.0, 0.0), p(4.0, 0.0), p(0.0, 4.0)])
            .build()
            .unwrap();
        let hyp = &room.walls()[1];
        let expected = Vector2::new(-1.0, -1.0) / 2f64.sqrt();
        assert!((hyp.inward_normal() - expected).norm() < 1e-12);
        // The wall box's inner face passes through the segment; the box lies outside the room.
        let obb = hyp.obb();
        let inner_face = obb.face_center(sceneeval_geom::Side::Front);
        assert!((inner_face - Point3::new(2.0, 2.0, 1.4)).norm() < 1e-12);
        assert!(
            !room
                .floor()
                .contains_point(&Point2::new(obb.center.x, obb.center.y))
        );
    }

    #[test]
    fn l_shaped_room_reflex_walls_face_inward() {
        let room = RoomBuilder::polygon(
            "l",
            vec![
                p(0.0, 0.0),
                p(4.0, 0.0),
                p(4.0, 2.0),
                p(2.0, 2.0),
                p(2.0, 4.0),
                p(0.0, 4.0),
            ],
        )
        .build()
        .unwrap();
        // Wall 2 runs (4,2) -> (2,2): the room is below it (-y). Wall 3 runs (2,2) -> (2,4): room at -x.
        assert_eq!(room.walls()[2].inward_normal(), Vector2::new(0.0, -1.0));
        assert_eq!(room.walls()[3].inward_normal(), Vector2::new(-1.0, 0.0));
    }

    #[test]
    fn wall_mesh_with_door_is_closed_and_has_a_hole() {
        let room = RoomBuilder::rectangle("r", p(0.0, 0.0), p(4.0, 5.0))
            .wall_thickness(0.1)
            .door(0, [1.0, 2.0], [0.0, 2.0])
            .build()
            .unwrap();
        let wall = &room.walls()[0];
        let mesh = wall.mesh().unwrap();
        assert!(mesh.is_closed());
        // Volume: 4 x 2.8 x 0.1 minus the 1 x 2 x 0.1 door.
        assert!((mesh.volume().unwrap() - (4.0 * 2.8 - 2.0) * 0.1).abs() < 1e-9);
        let id = Isometry3::identity();
        // A ray through the door from inside the room passes; one beside it hits the wall.
        let through = sceneeval_geom::Ray::new(Point3::new(1.5, 1.0, 1.0), -Vector3::y());
        assert!(mesh.cast_ray(&id, &through, 5.0).is_none());
        let beside = sceneeval_geom::Ray::new(Point3::new(3.0, 1.0, 1.0), -Vector3::y());
        let hit = mesh.cast_ray(&id, &beside, 5.0).unwrap();
        assert!((hit.toi - 1.0).abs() < 1e-12, "hits the inner face at y = 0");
        let door = &wall.openings()[0];
        assert_eq!(door.id, "r_wall_0_door_0");
        let obb = wall.opening_obb(door);
        assert!((obb.center - Point3::new(1.5, -0.05, 1.0)).norm() < 1e-12);
        assert!((obb.half_extents - Vector3::new(0.5, 0.05, 1.0)).norm() < 1e-12);
    }

    #[test]
    fn zero_thickness_wall_is_a_sheet() {
        let room = RoomBuilder::rectangle("r", p(0.0, 0.0), p(2.0, 2.0))
            .wall_thickness(0.0)
            .window(1, [0.5, 1.5], [1.0, 2.0])
            .build()
            .unwrap();
        let w = &room.walls()[1];
        assert!((w.mesh().unwrap().surface_area() - (2.0 * 2.8 - 1.0)).abs() < 1e-9);
        assert_eq!(w.obb().half_extents.y, 0.0);
    }

    #[test]
    fn bad_walls_and_openings_are_rejected() {
        let floor = Polygon2::rectangle(p(0.0, 0.0), p(2.0, 2.0)).unwrap();
        let mk = |spec: WallSpec| {
            let floor = Floor {
                id: "floor_r".into(),
                polygon: floor.clone(),
                z: 0.0,
            };
            Room::new("r", floor, vec![spec], None)
        };
        assert!(matches!(
            mk(WallSpec::new("w", p(1.0, 1.0), p(1.0, 1.0), 0.0, 2.0, 0.1)),
            Err(SceneError::ZeroLengthWall { .. })
        ));
        assert!(matches!(
            mk(WallSpec::new("w", p(0.0, 0.0), p(2.0, 0.0), 0.0, 0.0, 0.1)),
            Err(SceneError::BadWallHeight { .. })
        ));
        assert!(matches!(
            mk(WallSpec::new("w", p(0.0, 0.0), p(2.0, 0.0), 0.0, 2.0, -0.1)),
            Err(SceneError::BadWallThickness { .. })
        ));
        let mut spec = WallSpec::new("w", p(0.0, 0.0), p(2.0, 0.0), 0.0, 2.0, 0.1);
        spec.openings
            .push(Opening::new("d", OpeningKind::Door, [3.0, 4.0], [0.0, 2.0]));
        assert!(matches!(mk(spec.clone()), Err(SceneError::BadOpening { .. })));
        spec.openings[0].along = [1.5, 2.5];
        let room = mk(spec).unwrap();
        assert_eq!(
            room.walls()[0].openings()[0].along,
            [1.5, 2.0],
            "clipped to the wall"
        );
        assert!(matches!(
            RoomBuilder::rectangle("r", p(0.0, 0.0), p(1.0, 1.0))
                .door(7, [0.0, 0.5], [0.0, 1.0])
                .build(),
            Err(SceneError::NoSuchWall {
                index: 7,
                count: 4,
                ..
            })
        ));
        assert!(matches!(
            RoomBuilder::polygon("r", vec![p(0.0, 0.0), p(1.0, 0.0)]).build(),
            Err(SceneError::Geometry { .. })
        ));
    }

    #[test]
    fn floor_and_ceiling_meshes() {
        let room = RoomBuilder::rectangle("r", p(0.0, 0.0), p(4.0, 5.0))
            .floor_z(0.5)
            .build()
            .unwrap();
        assert!((room.floor_mesh().surface_area() - 20.0).abs() < 1e-12);
        assert_eq!(room.ceiling_z(), Some(3.3));
        let id = Isometry3::identity();
        let up = sceneeval_geom::Ray::new(Point3::new(1.0, 1.0, 1.0), Vector3::z());
        let hit = room.ceiling_mesh().unwrap().cast_ray(&id, &up, 10.0).unwrap();
        assert!((hit.toi - 2.3).abs() < 1e-12);
    }
}
