//! Hand-computed answers on small box scenes, one per metric.

// Test helpers outside #[test] functions may unwrap too.
#![allow(clippy::unwrap_used)]

mod common;

use approx::assert_abs_diff_eq;
use common::{check_invariants, scene};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Point2, Point3, Side, Vector3};
use sceneeval_plausibility::*;
use sceneeval_scene::Category;
use sceneeval_scene::{RoomBuilder, Scene};

fn b(x: f64, y: f64, z: f64) -> Point3 {
    Point3::new(x, y, z)
}

fn size(x: f64, y: f64, z: f64) -> Vector3 {
    Vector3::new(x, y, z)
}

fn col(scene: &Scene) -> CollisionReport {
    collision(scene, &CollisionParams::default()).unwrap()
}

#[test]
fn boxes_overlapping_by_one_centimetre_collide_with_depth_one_centimetre() {
    // A: x in [0.5, 1.5]. B (0.6 m cube): x in [1.49, 2.09], y and z strictly inside A's.
    // B's -x face lies 1 cm inside A, everything else of the overlap is farther from A's
    // other faces: depth = 1.5 - 1.49 = 0.01.
    let s = scene()
        .add_box(
            "a",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(1.0, 1.0, 0.5), 0.0),
        )
        .add_box(
            "b",
            Category::new("cabinet"),
            size(0.3, 0.3, 0.3),
            pose_from_yaw(b(1.79, 1.0, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert_eq!(r.contacts.len(), 1);
    let c = &r.contacts[0];
    assert_eq!(c.kind, ContactKind::Surface);
    assert_abs_diff_eq!(c.depth, 0.01, epsilon = 1e-9);
    assert!(c.colliding);
    assert_eq!(r.col_ob, Some(1.0));
    assert!(r.col_sc);
    assert_eq!(r.objects[0].colliding_with[0].as_str(), "b");
    assert_abs_diff_eq!(r.objects[1].max_depth, 0.01, epsilon = 1e-9);
}

#[test]
fn flush_boxes_overlapping_by_one_centimetre_collide() {
    // Same size, aligned faces: every corner lies on the other box's boundary, only face
    // points reveal the 1 cm overlap (x in [1.49, 1.5]).
    let s = scene()
        .add_box(
            "a",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(1.0, 1.0, 0.5), 0.0),
        )
        .add_box(
            "b",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(1.99, 1.0, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert_abs_diff_eq!(r.contacts[0].depth, 0.01, epsilon = 1e-9);
    assert!(r.col_sc);
}

#[test]
fn touching_boxes_do_not_collide() {
    // B: x in [1.5, 2.1], touching A's +x face.
    let s = scene()
        .add_box(
            "a",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(1.0, 1.0, 0.5), 0.0),
        )
        .add_box(
            "b",
            Category::new("cabinet"),
            size(0.3, 0.3, 0.3),
            pose_from_yaw(b(1.8, 1.0, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert!(!r.col_sc);
    assert_eq!(r.col_ob, Some(0.0));
    assert!(r.contacts.iter().all(|c| c.depth < 1e-9));
}

#[test]
fn resting_three_millimetres_deep_is_contact_not_collision() {
    // Table top at z = 0.75; lamp bottom at 0.75 + 0.2 - 0.2 - 0.003 = 0.747: depth 0.003,
    // under the 5 mm tolerance.
    let s = scene()
        .add_box(
            "table",
            Category::new("table"),
            size(0.5, 0.5, 0.375),
            pose_from_yaw(b(1.0, 1.0, 0.375), 0.0),
        )
        .add_box(
            "lamp",
            Category::new("table_lamp"),
            size(0.1, 0.1, 0.2),
            pose_from_yaw(b(1.0, 1.0, 0.947), 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert_eq!(r.contacts.len(), 1);
    assert!(!r.contacts[0].colliding);
    assert!(!r.col_sc);
    // The verdict needs no depth below the tolerance (the overlap lies within 5 mm of the
    // table's top face); measured, it is the 3 mm.
    let measured = CollisionParams {
        depth_search: sceneeval_geom::DepthSearch::All,
        ..CollisionParams::default()
    };
    let r = collision(&s, &measured).unwrap();
    assert_abs_diff_eq!(r.contacts[0].depth, 0.003, epsilon = 1e-9);
    assert!(!r.contacts[0].colliding);
    // With a 2 mm tolerance the same pair collides.
    let strict = CollisionParams {
        contact_tolerance_m: 0.002,
        ..CollisionParams::default()
    };
    assert!(collision(&s, &strict).unwrap().col_sc);
}

#[test]
fn object_inside_another_collides() {
    // A 0.2 m cube centred in a 1 m cube: surfaces never meet. Every point of the small cube's
    // surface is 0.5 - 0.1 = 0.4 from the big cube's nearest face.
    let s = scene()
        .add_box(
            "big",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(2.0, 2.0, 0.5), 0.0),
        )
        .add_box(
            "small",
            Category::new("box"),
            size(0.1, 0.1, 0.1),
            pose_from_yaw(b(2.0, 2.0, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert_eq!(r.contacts.len(), 1);
    assert_eq!(
        r.contacts[0].kind,
        ContactKind::Nested {
            inner: "small".into()
        }
    );
    assert!(r.contacts[0].colliding);
    assert_abs_diff_eq!(r.contacts[0].depth, 0.4, epsilon = 1e-9);
    assert_eq!(r.num_in_collision, 2);
    // Turned and off-centre, still nested; order in the scene does not matter.
    let s = scene()
        .add_box(
            "small",
            Category::new("box"),
            size(0.1, 0.15, 0.1),
            pose_from_yaw(b(2.2, 1.9, 0.4), 0.7),
        )
        .add_box(
            "big",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(2.0, 2.0, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert!(r.col_sc);
    assert_eq!(r.contacts[0].a.as_str(), "small");
    assert!(matches!(&r.contacts[0].kind, ContactKind::Nested { inner } if inner.as_str() == "small"));
}

#[test]
fn floor_coverings_can_be_excluded() {
    let s = scene()
        .add_box(
            "rug",
            Category::new("Persian Rug"),
            size(1.0, 1.5, 0.005),
            pose_from_yaw(b(2.0, 2.5, 0.005), 0.0),
        )
        .add_box(
            "bed",
            Category::new("bed"),
            size(0.8, 1.0, 0.3),
            pose_from_yaw(b(2.0, 2.5, 0.3), 0.0),
        )
        .build()
        .unwrap();
    let reference = CollisionParams {
        exclude_floor_coverings: false,
        ..CollisionParams::default()
    };
    assert!(
        collision(&s, &reference).unwrap().col_sc,
        "as the reference: the bed sinks 1 cm into the rug"
    );
    // By default floor coverings are left out.
    let r = col(&s);
    assert!(!r.col_sc);
    assert!(r.objects[0].excluded);
    assert_eq!(r.num_tested, 1);
    assert_eq!(r.col_ob, Some(0.0));
}

fn sup(scene: &Scene) -> SupportReport {
    support(scene, &SupportParams::default(), &SupportTypePriors::default()).unwrap()
}

#[test]
fn support_cases() {
    let s = scene()
        // Resting on the floor.
        .add_box(
            "table",
            Category::new("table"),
            size(0.5, 0.5, 0.375),
            pose_from_yaw(b(1.0, 1.0, 0.375), 0.0),
        )
        // Floating 10 cm above the floor.
        .add_box(
            "cabinet",
            Category::new("cabinet"),
            size(0.4, 0.25, 0.5),
            pose_from_yaw(b(3.0, 1.0, 0.6), 0.0),
        )
        // On the table.
        .add_box(
            "lamp",
            Category::new("table_lamp"),
            size(0.1, 0.1, 0.2),
            pose_from_yaw(b(1.0, 1.0, 0.95), 0.0),
        )
        // On the far wall (y = 5), facing into the room (back = +y toward the wall), beside
        // the window (x in [1.5, 3.0]).
        .add_box(
            "painting",
            Category::new("painting"),
            size(0.4, 0.02, 0.3),
            pose_from_yaw(b(0.8, 4.98, 1.5), 0.0),
        )
        // Over the window hole: nothing behind it.
        .add_box(
            "picture",
            Category::new("picture"),
            size(0.2, 0.02, 0.2),
            pose_from_yaw(b(2.2, 4.98, 1.5), 0.0),
        )
        // 5 cm off the far wall.
        .add_box(
            "poster",
            Category::new("poster"),
            size(0.25, 0.02, 0.35),
            pose_from_yaw(b(3.3, 4.93, 1.5), 0.0),
        )
        // Touching the ceiling at z = 2.8.
        .add_box(
            "chandelier",
            Category::new("chandelier"),
            size(0.15, 0.15, 0.1),
            pose_from_yaw(b(2.0, 2.5, 2.7), 0.0),
        )
        // Overhanging the table edge (x = 1.5) with its centre at 1.6: tips over.
        .add_box(
            "book",
            Category::new("book"),
            size(0.2, 0.15, 0.025),
            pose_from_yaw(b(1.6, 0.8, 0.775), 0.0),
        )
        .build()
        .unwrap();
    let r = sup(&s);
    let get = |id: &str| r.objects.iter().find(|o| o.id.as_str() == id).unwrap();
    assert!(get("table").supported);
    assert_eq!(get("table").supporters, vec![Supporter::Floor("r0".into())]);
    assert_abs_diff_eq!(get("table").contact_hull_area, 1.0, epsilon = 1e-9);
    assert!(!get("cabinet").supported);
    assert_eq!(get("cabinet").num_contacts, 0);
    let lamp = get("lamp");
    assert_eq!(lamp.support_type, SupportType::Object);
    assert!(lamp.supported);
    assert!(lamp.supporters.contains(&Supporter::Object("table".into())));
    assert_abs_diff_eq!(lamp.min_gap.unwrap(), 0.0, epsilon = 1e-9);
    let painting = get("painting");
    assert_eq!(painting.support_type, SupportType::Wall);
    assert!((painting.gravity - Vector3::y()).norm() < 1e-12);
    assert!(painting.supported);
    assert_eq!(painting.supporters, vec![Supporter::Wall("r0_wall_2".into())]);
    assert!(!get("poster").supported);
    let ch = get("chandelier");
    assert_eq!(ch.support_type, SupportType::Ceiling);
    assert!(ch.supported);
    assert_eq!(ch.supporters, vec![Supporter::Ceiling("r0".into())]);
    assert!(!get("book").supported, "centre of mass beyond the contacts");
    assert!(get("book").num_contacts > 0);
    assert!(!get("picture").supported, "hangs over the window");
    // 4 supported of 8 (table, lamp, painting, chandelier).
    assert_eq!(r.num_supported, 4);
    assert_abs_diff_eq!(r.sup.unwrap(), 0.5, epsilon = 1e-12);
    assert_eq!(r.num_unknown_type, 0);
}

#[test]
fn unknown_support_type_is_checked_as_ground_and_given_types_win() {
    let s = scene()
        .add_box(
            "thing",
            Category::new("zorblax"),
            size(0.25, 0.25, 0.25),
            pose_from_yaw(b(2.0, 2.0, 0.25), 0.0),
        )
        .build()
        .unwrap();
    let r = sup(&s);
    assert_eq!(r.objects[0].type_source, None);
    assert_eq!(r.objects[0].support_type, SupportType::Ground);
    assert!(r.objects[0].supported);
    assert_eq!(r.num_unknown_type, 1);
    let mut given = GivenSupportTypes::default();
    given.insert("thing", SupportType::Ceiling);
    let chained = Chain::new(given, SupportTypePriors::default());
    let r = support(&s, &SupportParams::default(), &chained).unwrap();
    assert_eq!(r.objects[0].type_source.as_deref(), Some("given"));
    assert!(!r.objects[0].supported, "nothing above it within 1 cm");
}

#[test]
fn out_of_bounds_half_outside() {
    // A 1 m cube centred on the wall line x = 4. Surface over the floor (x <= 4): top and
    // bottom 0.5 each, the two faces along x 0.5 each, the -x face (x = 3.5) 1, the +x face
    // (x = 4.5) 0: 3 of 6 square metres.
    let s = scene()
        .add_box(
            "half",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(4.0, 2.5, 0.5), 0.0),
        )
        .add_box(
            "inside",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(2.0, 2.5, 0.5), 0.7),
        )
        // Sunk 0.1 m: below z = -0.005 lie the bottom (1) and four side strips 0.095 high:
        // out area 1 + 4 * 0.095 = 1.38, ratio (6 - 1.38) / 6 = 0.77.
        .add_box(
            "sunk",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(2.0, 1.0, 0.4), 0.0),
        )
        .build()
        .unwrap();
    let exact = OutOfBoundsParams {
        boundary_tolerance_m: 0.0,
        ..OutOfBoundsParams::default()
    };
    let r = out_of_bounds(&s, &exact).unwrap();
    assert_abs_diff_eq!(r.objects[0].ratio_in_bounds, 0.5, epsilon = 1e-12);
    assert_abs_diff_eq!(r.objects[0].area_over_floor, 3.0, epsilon = 1e-12);
    // The default 1 mm boundary tolerance adds a 1 mm strip of the top, bottom and both faces
    // along x: (3 + 4 * 0.001) / 6.
    let r = out_of_bounds(&s, &OutOfBoundsParams::default()).unwrap();
    assert_abs_diff_eq!(r.objects[0].ratio_in_bounds, 3.004 / 6.0, epsilon = 1e-12);
    assert!(r.objects[0].out_of_bounds);
    assert_abs_diff_eq!(r.objects[1].ratio_in_bounds, 1.0, epsilon = 1e-12);
    assert!(!r.objects[1].out_of_bounds);
    assert_abs_diff_eq!(r.objects[2].ratio_in_bounds, 0.77, epsilon = 1e-12);
    assert_eq!(r.num_out, 2);
    assert_abs_diff_eq!(r.oob.unwrap(), 2.0 / 3.0, epsilon = 1e-12);
}

#[test]
fn out_of_bounds_on_a_concave_floor() {
    // L-shaped floor: [0,4]x[0,2] plus [0,2]x[2,4]. A 1 m cube centred at (2.5, 2.5) sits in the
    // missing quadrant except for its [2.0, 3.0] x [2.0, 3.0] footprint corner... entirely
    // outside the L (x > 2 and y > 2): ratio 0. One centred at (2, 2) has a quarter of its
    // footprint outside: top/bottom 0.75 each, the -x and -y faces (x = 1.5, y = 1.5) 1 each,
    // the +x face (x = 2.5, y in [1.5, 2.5]) 0.5, the +y face 0.5: 4.5 of 6 = 0.75.
    let l = RoomBuilder::polygon(
        "l",
        vec![
            Point2::new(0.0, 0.0),
            Point2::new(4.0, 0.0),
            Point2::new(4.0, 2.0),
            Point2::new(2.0, 2.0),
            Point2::new(2.0, 4.0),
            Point2::new(0.0, 4.0),
        ],
    );
    let s = Scene::builder()
        .room_builder(l)
        .add_box(
            "out",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(2.6, 2.6, 0.5), 0.0),
        )
        .add_box(
            "corner",
            Category::new("cabinet"),
            size(0.5, 0.5, 0.5),
            pose_from_yaw(b(2.0, 2.0, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let exact = OutOfBoundsParams {
        boundary_tolerance_m: 0.0,
        ..OutOfBoundsParams::default()
    };
    let r = out_of_bounds(&s, &exact).unwrap();
    assert_abs_diff_eq!(r.objects[0].ratio_in_bounds, 0.0, epsilon = 1e-12);
    assert_abs_diff_eq!(r.objects[1].ratio_in_bounds, 0.75, epsilon = 1e-12);
    // With the default 1 mm tolerance the two reflex edges move out by 1 mm: the outside
    // quadrant [2, 2.5]^2 of the top and bottom gains an L-shaped strip of
    // 2 * 0.5 * 0.001 - 0.001^2 = 0.000999 each, and the +x and +y faces 0.001 each:
    // (4.5 + 0.003998) / 6. The cube in the missing quadrant starts 0.1 m beyond both edges.
    let r = out_of_bounds(&s, &OutOfBoundsParams::default()).unwrap();
    assert_abs_diff_eq!(r.objects[0].ratio_in_bounds, 0.0, epsilon = 1e-12);
    assert_abs_diff_eq!(r.objects[1].ratio_in_bounds, 4.503998 / 6.0, epsilon = 1e-12);
}

#[test]
fn wardrobe_blocks_the_door() {
    // Door: x in [1.0, 1.9] on y = 0, height [0, 2.1]; clearance depth = width = 0.9 m.
    // Wardrobe 1.0 x 0.6 x 2.0 centred at (1.45, 0.31): y in [0.01, 0.61], x in [0.95, 1.95].
    // It covers the door's whole width and 2.0 of its 2.1 m: on the 100 px/m raster (90 x 210
    // pixels, centres at 0.005 + 0.01 k) rows with centre below 2.0 -> 200 of 210.
    let s = scene()
        .add_box(
            "wardrobe",
            Category::new("wardrobe"),
            size(0.5, 0.3, 1.0),
            pose_from_yaw(b(1.45, 0.31, 1.0), 0.0),
        )
        // A chair beside the door (x in [2.2, 2.7]): outside the box.
        .add_box(
            "chair",
            Category::new("chair"),
            size(0.25, 0.25, 0.45),
            pose_from_yaw(b(2.45, 0.4, 0.45), 0.0),
        )
        .build()
        .unwrap();
    let r = opening_clearance(&s, &OpeningClearanceParams::default()).unwrap();
    assert_eq!((r.num_doors, r.doors_blocked), (1, 1));
    assert_eq!((r.num_windows, r.windows_blocked), (1, 0));
    let door = &r.openings[0];
    assert_eq!(door.kind, sceneeval_scene::OpeningKind::Door);
    assert_eq!(door.sides.len(), 1, "nothing but outside beyond the wall");
    let side = &door.sides[0];
    assert_eq!(side.side, OpeningSide::Room);
    assert_abs_diff_eq!(side.depth, 0.9, epsilon = 1e-12);
    assert_eq!(side.blocking.len(), 1);
    assert_eq!(side.blocking[0].id.as_str(), "wardrobe");
    assert_abs_diff_eq!(side.blocking[0].occluded_fraction, 200.0 / 210.0, epsilon = 1e-12);
    assert_abs_diff_eq!(side.occluded_fraction, 200.0 / 210.0, epsilon = 1e-12);
    // Moved 1 m into the room (y from 1.01), it leaves the 0.9 m box.
    let clear = scene()
        .add_box(
            "wardrobe",
            Category::new("wardrobe"),
            size(0.5, 0.3, 1.0),
            pose_from_yaw(b(1.45, 1.31, 1.0), 0.0),
        )
        .build()
        .unwrap();
    assert_eq!(
        opening_clearance(&clear, &OpeningClearanceParams::default())
            .unwrap()
            .doors_blocked,
        0
    );
}

fn nav_params() -> NavigabilityParams {
    NavigabilityParams {
        resolution: Resolution::MetresPerPixel(0.05),
        ..NavigabilityParams::default()
    }
}

#[test]
fn empty_room_is_fully_navigable() {
    let s = scene().build().unwrap();
    for params in [nav_params(), NavigabilityParams::default()] {
        let r = navigability(&s, &params).unwrap();
        assert_eq!(r.num_components, 1);
        assert_eq!(r.nav, 1.0);
        assert_eq!(r.rooms[0].reachable, Some(true));
        assert_eq!(r.rooms[0].reachable_fraction, Some(1.0));
        assert_eq!(r.all_rooms_reachable, Some(true));
    }
    // 0.05 m pixels from (-0.2, -0.2): centres at 0.025 + 0.05 k off the walls. Free centres
    // are those at least 0.1 m inside: x in [0.125, 3.875] (76), y in [0.125, 4.875] (96).
    let r = navigability(&s, &nav_params()).unwrap();
    assert_eq!(r.free_pixels, 76 * 96);
    assert_eq!((r.grid.width, r.grid.height), (88, 108));
}

#[test]
fn shelf_splits_the_room() {
    // A shelf across the room, y in [2.0, 2.4]. Free rows: below, y in [0.125, 1.875] (36);
    // above, y in [2.525, 4.875] (48); 76 columns each. NAV = 48 / 84 = 4/7. The door (y = 0)
    // opens into the lower part: 36 / 84 of the room's free space is reachable from it.
    let s = scene()
        .add_box(
            "shelf",
            Category::new("shelf"),
            size(2.0, 0.2, 0.5),
            pose_from_yaw(b(2.0, 2.2, 0.5), 0.0),
        )
        .build()
        .unwrap();
    let r = navigability(&s, &nav_params()).unwrap();
    assert_eq!(r.num_components, 2);
    assert_eq!(r.free_pixels, 84 * 76);
    assert_eq!(r.largest_component_pixels, 48 * 76);
    assert_abs_diff_eq!(r.nav, 4.0 / 7.0, epsilon = 1e-12);
    assert_eq!(r.rooms[0].reachable, Some(true));
    assert_abs_diff_eq!(r.rooms[0].reachable_fraction.unwrap(), 3.0 / 7.0, epsilon = 1e-12);
    // A shelf higher than 2 m above the floor is ignored.
    let high = scene()
        .add_box(
            "shelf",
            Category::new("shelf"),
            size(2.0, 0.2, 0.2),
            pose_from_yaw(b(2.0, 2.2, 2.3), 0.0),
        )
        .build()
        .unwrap();
    let r = navigability(&high, &nav_params()).unwrap();
    assert_eq!(r.nav, 1.0);
    assert_eq!(r.ignored.len(), 1);
}

#[test]
fn wardrobe_in_front_of_the_door_makes_the_room_unreachable() {
    let s = scene()
        .add_box(
            "wardrobe",
            Category::new("wardrobe"),
            size(0.8, 0.3, 1.0),
            pose_from_yaw(b(1.45, 0.31, 1.0), 0.0),
        )
        .build()
        .unwrap();
    let r = navigability(&s, &nav_params()).unwrap();
    // Wardrobe x in [0.65, 2.25], y up to 0.61: every strip pixel (y <= 0.5) is within 0.1 of it.
    assert_eq!(r.rooms[0].reachable, Some(false));
    assert_eq!(r.all_rooms_reachable, Some(false));
}

#[test]
fn rooms_connect_through_doors() {
    // Rooms a = [0,4]x[0,4] and b = [4,7]x[0,4]. A door in a's east wall (wall 1, from (4,0)
    // to (4,4)) at y in [1.5, 2.5] also cuts b's coincident west wall.
    let two = |door: bool| {
        let mut a = RoomBuilder::rectangle("a", Point2::new(0.0, 0.0), Point2::new(4.0, 4.0));
        if door {
            a = a.door(1, [1.5, 2.5], [0.0, 2.1]);
        }
        let b = RoomBuilder::rectangle("b", Point2::new(4.0, 0.0), Point2::new(7.0, 4.0));
        Scene::builder().room_builder(a).room_builder(b).build().unwrap()
    };
    let r = navigability(&two(true), &nav_params()).unwrap();
    assert_eq!(r.num_components, 1);
    assert_eq!(r.nav, 1.0);
    assert_eq!(r.rooms[0].reachable_fraction, Some(1.0));
    assert_eq!(r.rooms[1].reachable, None, "b has no door of its own");
    // Without the door: two components. Each room's 0.1 m wall at x = 4 extends into the other
    // room (a wall's thickness points away from its own room), so free x: a [0.125, 3.775]
    // (74), b [4.225, 6.875] (54); y [0.125, 3.875] (76) each. NAV = 74 / 128.
    let r = navigability(&two(false), &nav_params()).unwrap();
    assert_eq!(r.num_components, 2);
    assert_abs_diff_eq!(r.nav, 74.0 / 128.0, epsilon = 1e-12);
    assert_eq!(r.all_rooms_reachable, None);
}

#[test]
fn accessibility_of_a_bed_in_a_corner() {
    // Bed 1.6 x 2.0 in the north-east corner: x in [2.4, 4.0], y in [3.0, 5.0], front -y.
    // Strips (offset 0.05, width 0.2):
    //   front y in [2.75, 2.95] x [2.4, 4.0] (0.32 m2): the wardrobe (x in [2.0, 4.0], y in
    //     [2.0, 2.9]) covers y in [2.75, 2.9]: 1.6 * 0.15 = 0.24 -> 0.25.
    //   left x in [2.15, 2.35] x [3, 5] (0.4 m2): the nightstand (x in [1.8, 2.3], y in
    //     [4.5, 4.9]) covers 0.15 * 0.4 = 0.06 -> 0.85.
    //   right x in [4.05, 4.25]: off the floor -> 0.
    // Best: left, 0.85. Nightstand (front) and wardrobe (front) are free: 1.0 each.
    // ACC = (0.85 + 1 + 1) / 3 = 0.95.
    let s = scene()
        .add_box(
            "bed",
            Category::new("bed"),
            size(0.8, 1.0, 0.3),
            pose_from_yaw(b(3.2, 4.0, 0.3), 0.0),
        )
        .add_box(
            "nightstand",
            Category::new("nightstand"),
            size(0.25, 0.2, 0.3),
            pose_from_yaw(b(2.05, 4.7, 0.3), 0.0),
        )
        .add_box(
            "wardrobe",
            Category::new("wardrobe"),
            size(1.0, 0.45, 1.0),
            pose_from_yaw(b(3.0, 2.45, 1.0), 0.0),
        )
        .build()
        .unwrap();
    let r = accessibility(
        &s,
        &AccessibilityParams::default(),
        &FunctionalSidePriors::default(),
    )
    .unwrap();
    let bed = &r.objects[0];
    let score = |side: Side| bed.sides.iter().find(|s| s.side == side).unwrap().score;
    assert_abs_diff_eq!(score(Side::Front), 0.25, epsilon = 1e-9);
    assert_abs_diff_eq!(score(Side::Left), 0.85, epsilon = 1e-9);
    assert_abs_diff_eq!(score(Side::Right), 0.0, epsilon = 1e-9);
    assert_eq!(bed.best_side, Some(Side::Left));
    assert_eq!(bed.sides[0].blocked_by[0].as_str(), "wardrobe");
    assert_abs_diff_eq!(r.objects[1].score.unwrap(), 1.0, epsilon = 1e-9);
    assert_abs_diff_eq!(r.acc.unwrap(), 0.95, epsilon = 1e-9);
    assert_eq!(r.num_scored, 3);
    // Given sides override the table; an unknown category is skipped.
    let mut given = GivenFunctionalSides::default();
    given.insert("bed", vec![Side::Right]);
    let r = accessibility(
        &s,
        &AccessibilityParams::default(),
        &Chain::new(given, FunctionalSidePriors::default()),
    )
    .unwrap();
    assert_eq!(r.objects[0].score, Some(0.0));
}

#[test]
fn evaluate_runs_everything_and_serialises() {
    let s = scene()
        .name("demo")
        .add_box(
            "bed",
            Category::new("bed"),
            size(0.8, 1.0, 0.3),
            pose_from_yaw(b(3.2, 4.0, 0.3), 0.0),
        )
        .add_box(
            "nightstand",
            Category::new("nightstand"),
            size(0.25, 0.2, 0.3),
            pose_from_yaw(b(2.05, 4.7, 0.3), 0.0),
        )
        .add_box(
            "wardrobe",
            Category::new("wardrobe"),
            size(0.5, 0.3, 1.0),
            pose_from_yaw(b(1.45, 0.31, 1.0), 0.0),
        )
        .add_box(
            "lamp",
            Category::new("table_lamp"),
            size(0.1, 0.1, 0.2),
            pose_from_yaw(b(2.05, 4.7, 0.8), 0.0),
        )
        .add_mesh(
            "ball",
            Category::new("zorblax"),
            common::sphere(0.3, 12),
            common::at(1.0, 2.5, 1.0, 0.0),
        )
        .build()
        .unwrap();
    let r = evaluate(&s, &PlausibilityParams::default(), &Sources::default()).unwrap();
    check_invariants(&r);
    assert_eq!(r.scene.as_deref(), Some("demo"));
    assert_eq!(r.summary.doors_blocked, Some(1));
    let support = r.support.as_ref().unwrap();
    assert_eq!(support.objects[4].type_source, None);
    assert!(!support.objects[4].supported, "the ball floats");
    let json = serde_json::to_string(&r).unwrap();
    let back: PlausibilityReport = serde_json::from_str(&json).unwrap();
    // serde_json parses floats to within one ulp, so compare structure and counts exactly.
    assert_eq!(back.summary.doors_blocked, r.summary.doors_blocked);
    assert_eq!(back.support.unwrap().objects.len(), 5);
    assert_eq!(back.collision.unwrap().contacts, r.collision.unwrap().contacts);
    assert_abs_diff_eq!(back.summary.acc.unwrap(), r.summary.acc.unwrap(), epsilon = 1e-12);
    let params_json = serde_json::to_string(&PlausibilityParams::default()).unwrap();
    let params: PlausibilityParams = serde_json::from_str(&params_json).unwrap();
    assert_eq!(params, PlausibilityParams::default());
    let partial: PlausibilityParams =
        serde_json::from_str(r#"{"navigability": {"resolution": {"m_per_pixel": 0.02}}}"#).unwrap();
    assert_eq!(partial.navigability.resolution, Resolution::MetresPerPixel(0.02));
    assert_eq!(partial.navigability.robot_width_m, 0.2);
}

#[test]
fn bad_parameters_are_rejected() {
    let s = scene().build().unwrap();
    let p = CollisionParams {
        contact_tolerance_m: -1.0,
        ..CollisionParams::default()
    };
    assert!(matches!(
        collision(&s, &p),
        Err(PlausibilityError::InvalidParameter {
            metric: "collision",
            name: "contact_tolerance_m",
            ..
        })
    ));
    let p = NavigabilityParams {
        resolution: Resolution::MetresPerPixel(1e-5),
        ..NavigabilityParams::default()
    };
    assert!(matches!(
        navigability(&s, &p),
        Err(PlausibilityError::RasterTooLarge { .. })
    ));
    let p = OutOfBoundsParams {
        threshold: 1.5,
        ..OutOfBoundsParams::default()
    };
    assert!(out_of_bounds(&s, &p).is_err());
}

#[test]
fn empty_scenes_give_undefined_shares_not_errors() {
    let empty = Scene::builder().build().unwrap();
    let r = evaluate(&empty, &PlausibilityParams::default(), &Sources::default()).unwrap();
    check_invariants(&r);
    let s = &r.summary;
    assert_eq!((s.col_ob, s.sup, s.acc, s.oob), (None, None, None, None));
    assert_eq!(s.col_sc, Some(false));
    assert_eq!(
        s.nav,
        Some(0.0),
        "no floor, no free space (the reference's convention)"
    );
    assert_eq!(s.all_rooms_reachable, None);
    // Objects without any room: nothing supports them, nothing is floor.
    let no_rooms = Scene::builder()
        .add_box(
            "table",
            Category::new("table"),
            size(0.5, 0.5, 0.375),
            pose_from_yaw(b(0.0, 0.0, 0.375), 0.0),
        )
        .build()
        .unwrap();
    let r = evaluate(&no_rooms, &PlausibilityParams::default(), &Sources::default()).unwrap();
    check_invariants(&r);
    assert_eq!(r.summary.sup, Some(0.0));
    assert_eq!(r.summary.oob, Some(1.0));
    assert_eq!(
        r.summary.acc,
        Some(0.0),
        "access strips off any floor are blocked"
    );
}

#[test]
fn tilted_objects_use_their_projected_hull() {
    // A 2 x 0.4 x 0.4 plank turned 90 degrees about x stands up: its footprint is 2 x 0.4
    // either way, but the tilted path projects every vertex.
    let pose = sceneeval_geom::Isometry3::new(
        Vector3::new(2.0, 2.5, 0.2),
        Vector3::x() * std::f64::consts::FRAC_PI_2,
    );
    let s = scene()
        .object(
            sceneeval_scene::SceneObject::new_box("plank", Vector3::new(1.0, 0.2, 0.2), pose)
                .unwrap()
                .with_category("bench"),
        )
        .build()
        .unwrap();
    let r = evaluate(&s, &PlausibilityParams::default(), &Sources::default()).unwrap();
    check_invariants(&r);
    assert!(r.support.as_ref().unwrap().objects[0].supported);
    // The bench's front (-y local) now points down (-z): its strip projects onto the footprint
    // line, a degenerate strip with zero area scores 0; its back points up likewise.
    assert_eq!(r.accessibility.as_ref().unwrap().objects[0].score, Some(0.0));
    assert_eq!(r.out_of_bounds.as_ref().unwrap().objects[0].ratio_in_bounds, 1.0);
}

#[test]
fn open_meshes_use_the_winding_number() {
    // A 1 m box without its bottom (open), and a 0.6 m closed box entering its +x face by
    // 2 cm: depth 0.02 from both sides. A 0.2 m box inside the open one is nested.
    let cube = sceneeval_geom::Mesh::cuboid(&Vector3::repeat(0.5)).unwrap();
    let open = sceneeval_geom::Mesh::new(cube.vertices().to_vec(), cube.triangles()[2..].to_vec()).unwrap();
    assert!(!open.is_closed());
    let open = std::sync::Arc::new(open);
    let s = scene()
        .add_mesh(
            "shell",
            Category::new("cabinet"),
            open.clone(),
            common::at(1.0, 1.0, 0.5, 0.0),
        )
        .add_box(
            "b",
            Category::new("cabinet"),
            size(0.3, 0.3, 0.3),
            pose_from_yaw(b(1.78, 1.0, 0.5), 0.0),
        )
        .add_mesh(
            "shell2",
            Category::new("cabinet"),
            open,
            common::at(3.0, 3.0, 0.5, 0.0),
        )
        .add_box(
            "inner",
            Category::new("box"),
            size(0.1, 0.1, 0.1),
            pose_from_yaw(b(3.0, 3.0, 0.6), 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    let pair = |a: &str| r.contacts.iter().find(|c| c.a.as_str() == a).unwrap();
    assert_abs_diff_eq!(pair("shell").depth, 0.02, epsilon = 1e-9);
    assert!(pair("shell").colliding);
    assert!(matches!(&pair("shell2").kind, ContactKind::Nested { inner } if inner.as_str() == "inner"));
}
