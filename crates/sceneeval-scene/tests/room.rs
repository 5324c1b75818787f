//! Rooms prepared once: the walls' solid boxes, the floor and ceiling triangulations, the
//! openings' boxes and the floor's enclosing rectangle; and the architecture a scene file may
//! get wrong (an opening covering its whole wall, a ceiling below its floor, repeated opening
//! ids).

#![allow(clippy::unwrap_used)]

use sceneeval_geom::{Point2, Point3, Polygon2, Real, Vector2};
use sceneeval_scene::{Ceiling, Element, Floor, OpeningKind, Room, RoomBuilder, SceneError, WallSpec};
use sceneeval_test_support::bedroom;

/// The bedroom with a window on wall 2 (y = 5) spanning x in [1.0, 2.5], 0.9 to 2.0 m up.
fn room() -> Room {
    bedroom("r").window(2, [1.0, 2.5], [0.9, 2.0]).build().unwrap()
}

#[test]
fn cells_cover_the_wall_minus_openings() {
    let room = room();
    // Wall 0 (4 m x 2.8 m) minus the 0.9 x 2.1 door: 11.2 - 1.89 = 9.31 m^2 of face.
    let w0 = &room.walls()[0];
    let area: Real = w0
        .solid_boxes()
        .iter()
        .map(|c| 4.0 * c.half_extents.x * c.half_extents.z)
        .sum();
    assert!((area - 9.31).abs() < 1e-12, "{area}");
    // Wall 2 with a window: columns left, middle (below + above the window), right = 4 cells.
    assert_eq!(room.walls()[2].solid_boxes().len(), 4);
    // Every cell's inner face lies on the wall's inner face (y = 0 for wall 0) and the slab
    // extends outward (y < 0).
    for c in w0.solid_boxes() {
        assert!((c.center.y + 0.05).abs() < 1e-12);
        assert!((c.half_extents.y - 0.05).abs() < 1e-12);
    }
    assert_eq!(room.walls()[1].solid_boxes().len(), 1);
    let all: usize = room.walls().iter().map(|w| w.solid_boxes().len()).sum();
    assert_eq!(all, 3 + 1 + 4 + 1);
}

#[test]
fn floor_ceiling_and_openings() {
    let room = room();
    let tri_area: Real = room
        .floor_triangles()
        .iter()
        .map(|[a, b, c]| 0.5 * (b - a).perp(&(c - a)))
        .sum();
    assert!((tri_area - 20.0).abs() < 1e-12);
    assert_eq!(room.ceiling_z(), Some(2.8));
    assert!(
        room.ceiling_triangles()
            .iter()
            .all(|t| t.iter().all(|p| p.z == 2.8))
    );
    assert_eq!(room.floor_centroid(), Point2::new(2.0, 2.5));
    let door = &room.openings()[0];
    assert_eq!(door.kind, OpeningKind::Door);
    assert!((door.obb.center - Point3::new(1.45, -0.05, 1.05)).norm() < 1e-12);
    assert_eq!(room.floor_id(), "floor_r");
    assert_eq!(
        room.floor_rectangle(),
        (Point2::new(2.0, 2.5), Vector2::new(4.0, 5.0))
    );
}

#[test]
fn minimum_rectangle_of_turned_and_l_shaped_floors() {
    // A 4 x 5 rectangle turned by 0.5 rad: the rectangle is the room itself.
    let (c, s) = (0.5f64.cos(), 0.5f64.sin());
    let turned: Vec<Point2> = [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]]
        .iter()
        .map(|p| Point2::new(c * p[0] - s * p[1] + 1.0, s * p[0] + c * p[1] - 2.0))
        .collect();
    let (centre, dims) = RoomBuilder::polygon("t", turned)
        .build()
        .unwrap()
        .floor_rectangle();
    let mut d = [dims.x, dims.y];
    d.sort_by(|a, b| a.total_cmp(b));
    assert!((d[0] - 4.0).abs() < 1e-12 && (d[1] - 5.0).abs() < 1e-12, "{dims}");
    let expected = Point2::new(c * 2.0 - s * 2.5 + 1.0, s * 2.0 + c * 2.5 - 2.0);
    assert!((centre - expected).norm() < 1e-12);
    // An L inside the 4 x 4 square keeps the square.
    let l = [
        [0.0, 0.0],
        [4.0, 0.0],
        [4.0, 2.0],
        [2.0, 2.0],
        [2.0, 4.0],
        [0.0, 4.0],
    ]
    .map(|p| Point2::new(p[0], p[1]));
    assert_eq!(
        RoomBuilder::polygon("l", l.to_vec())
            .build()
            .unwrap()
            .floor_rectangle(),
        (Point2::new(2.0, 2.0), Vector2::new(4.0, 4.0))
    );
}

#[test]
fn bad_rooms_are_reported() {
    let square = || RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(1.0, 1.0));
    assert!(matches!(
        square().door(9, [0.1, 0.5], [0.0, 2.0]).build(),
        Err(SceneError::NoSuchWall { .. })
    ));
    assert!(square().wall_height(-1.0).build().is_err());
    assert!(
        RoomBuilder::polygon("r", vec![Point2::new(0.0, 0.0), Point2::new(1.0, 0.0)])
            .build()
            .is_err()
    );
}

fn floor() -> Floor {
    Floor {
        id: "floor_r".into(),
        polygon: Polygon2::rectangle(Point2::new(0.0, 0.0), Point2::new(4.0, 3.0)).unwrap(),
        z: 0.0,
    }
}

#[test]
fn an_opening_covering_its_whole_wall_is_clipped_and_leaves_no_solid() {
    // A 4 m wall, 2.5 m high, with a "door" from -1 to 5 m along it and 0 to 3 m up: clipped to
    // the wall (0 to 4, 0 to 2.5). Nothing of the wall is left: no solid boxes, no mesh; the
    // room is still built, and the opening still exists for the door relations.
    let mut wall = WallSpec::new("w", Point2::new(0.0, 0.0), Point2::new(4.0, 0.0), 0.0, 2.5, 0.1);
    wall.openings.push(sceneeval_scene::Opening::new(
        "gap",
        OpeningKind::Door,
        [-1.0, 5.0],
        [0.0, 3.0],
    ));
    let room = Room::new("r", floor(), vec![wall], None).unwrap();
    let w = &room.walls()[0];
    assert!(w.solid_boxes().is_empty());
    assert!(w.mesh().is_none());
    assert_eq!(w.openings()[0].along, [0.0, 4.0]);
    assert_eq!(w.openings()[0].height, [0.0, 2.5]);
    assert_eq!(room.openings().len(), 1);
    // 4 m wide, 2.5 m high, 0.1 m deep box whose inner face is the wall line y = 0.
    let b = room.openings()[0].obb;
    assert!((b.center - Point3::new(2.0, -0.05, 1.25)).norm() < 1e-12);
}

#[test]
fn a_ceiling_at_or_below_the_floor_is_an_error() {
    for z in [0.0, -1.0] {
        let ceiling = Ceiling {
            id: "c".into(),
            polygon: floor().polygon,
            z,
        };
        let err = Room::new("r", floor(), Vec::new(), Some(ceiling)).unwrap_err();
        assert_eq!(
            err,
            SceneError::CeilingBelowFloor {
                room: "r".into(),
                floor_z: 0.0,
                ceiling_z: z,
            }
        );
        assert_eq!(err.element(), Some(Element::Ceiling { room: "r".into() }));
        assert!(err.to_string().contains("is not above the floor"), "{err}");
    }
}

#[test]
fn repeated_opening_ids_in_one_wall_are_an_error() {
    let mut wall = WallSpec::new("w", Point2::new(0.0, 0.0), Point2::new(4.0, 0.0), 0.0, 2.5, 0.1);
    wall.openings.push(sceneeval_scene::Opening::new(
        "d",
        OpeningKind::Door,
        [0.5, 1.4],
        [0.0, 2.0],
    ));
    wall.openings.push(sceneeval_scene::Opening::new(
        "d",
        OpeningKind::Window,
        [2.0, 3.0],
        [1.0, 2.0],
    ));
    let err = Room::new("r", floor(), vec![wall], None).unwrap_err();
    let SceneError::DuplicateOpeningId { id, first, second } = &err else {
        panic!("{err:?}");
    };
    assert_eq!(id, "d");
    let at = |k: usize| Element::Opening {
        room: "r".into(),
        wall: 0,
        wall_id: "w".into(),
        opening: k,
        id: "d".into(),
    };
    assert_eq!((&**first, &**second), (&at(0), &at(1)));
    assert_eq!(err.element(), Some(at(1)));
}

#[test]
fn wall_errors_name_the_wall_structurally() {
    let walls = vec![
        WallSpec::new("ok", Point2::new(0.0, 0.0), Point2::new(4.0, 0.0), 0.0, 2.5, 0.1),
        WallSpec::new(
            "flat",
            Point2::new(4.0, 0.0),
            Point2::new(4.0, 3.0),
            0.0,
            0.0,
            0.1,
        ),
    ];
    let err = Room::new("r", floor(), walls, None).unwrap_err();
    assert_eq!(
        err.element(),
        Some(Element::Wall {
            room: "r".into(),
            wall: 1,
            id: "flat".into(),
        })
    );
    assert_eq!(
        err.to_string(),
        r#"wall "flat" (1) of room "r": height must be positive and finite, got 0"#
    );
}
