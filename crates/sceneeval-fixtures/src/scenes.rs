//! The fixture scenes as data (see [`crate::spec`] for the placement conventions).
//!
//! Coordinates are chosen so that every fact in `expected.json` can be checked by hand; the
//! arithmetic is written next to each placement. Furniture stands flush against walls (gap 0)
//! or leaves at least a 0.3 m passage, so a 0.2 m wide robot never meets a pocket it cannot
//! leave; neighbours that are not meant to touch keep at least 5 cm apart.
//!
//! Object-frame half sizes used below (width x, depth y, height z; front = -y):
//! bed 0.8 x 1.05 x 1.1 (headboard at +y), nightstand 0.225 x 0.21 x 0.55 (its carcass spans
//! y in [-0.19, 0.21], the handle the rest), desk 0.7 x 0.35 x 0.75, chair 0.22 x 0.22 x 0.9,
//! dining table 0.8 x 0.45 x 0.76, sofa 1.0 x 0.45 x 0.85, coffee table 0.55 x 0.3 x 0.45,
//! wardrobe 0.5 x 0.3 x 2.0 (carcass y in [-0.28, 0.30]), bookshelf 0.4 x 0.15 x 1.8,
//! table lamp 0.12 x 0.12 x 0.45, floor lamp 0.22 x 0.22 x 1.7, rug 1.0 x 0.7 x 0.01,
//! painting 0.4 x 0.02 x 0.6, ceiling lamp 0.25 x 0.25 x 0.73, tv 0.6 x 0.03 x 0.7,
//! plant 0.25 x 0.25 x 0.75, tv stand 0.7 x 0.2 x 0.5, storage box 0.15 x 0.125 x 0.2.
//!
//! Yaw turns the object-frame offset `(x, y)` into the world offset: 0 -> `(x, y)`,
//! 90 -> `(-y, x)`, 180 -> `(-x, -y)`, -90 -> `(y, -x)`. So an object's back (+y) faces world
//! +y, -x, -y and +x respectively.

use std::f64::consts::FRAC_1_SQRT_2;

use sceneeval_geom::Point2;
use sceneeval_scene::{RoomBuilder, SupportType};

use crate::spec::{Flaw, Placement, SceneSpec};

/// Standard wall height (m).
const WALL_H: f64 = 2.8;
/// Bottom of a ceiling lamp: 2.8 - 0.73, so its top touches a 2.8 m ceiling.
const LAMP_Z: f64 = 2.07;
/// A door: 2.1 m high from the floor.
const DOOR_H: [f64; 2] = [0.0, 2.1];
/// A window: from 0.9 m to 2.1 m.
const WINDOW_H: [f64; 2] = [0.9, 2.1];

fn rect(id: &str, kind: &str, min: (f64, f64), max: (f64, f64)) -> RoomBuilder {
    RoomBuilder::rectangle(id, Point2::new(min.0, min.1), Point2::new(max.0, max.1))
        .kind(kind)
        .wall_height(WALL_H)
}

fn a(key: &str, asset: &'static str, x: f64, y: f64, z: f64, yaw: f64) -> Placement {
    Placement::asset(key, asset, [x, y, z], yaw)
}

fn ceiling_lamp(key: &str, x: f64, y: f64) -> Placement {
    a(key, "ceiling_lamp", x, y, LAMP_Z, 0.0).from_ceiling()
}

/// Scene 0: a tidy bedroom in a rectangular 4 m x 5 m room with an explicit ceiling.
fn tidy_bedroom() -> SceneSpec {
    let room = rect("bedroom", "bedroom", (0.0, 0.0), (4.0, 5.0))
        .with_ceiling()
        .door(0, [0.4, 1.3], DOOR_H)
        .window(1, [1.5, 3.0], WINDOW_H);
    SceneSpec {
        number: 0,
        title: "tidy bedroom",
        description: "A tidy bedroom with a double bed between two nightstands with lamps, a wardrobe, a rug, a painting above the bed and a ceiling lamp.",
        rooms: vec![room],
        objects: vec![
            // Headboard (+y) against the north wall: 3.95 + 1.05 = 5.0.
            a("bed", "bed", 2.0, 3.95, 0.0, 0.0),
            // 2.0 - 0.8 - 0.05 - 0.225 = 0.925; back 4.79 + 0.21 = 5.0.
            a("nightstand_left", "nightstand", 0.925, 4.79, 0.0, 0.0),
            a("nightstand_right", "nightstand", 3.075, 4.79, 0.0, 0.0),
            // On the carcass centre (y 4.79 + 0.01) and top (z 0.55).
            a("table_lamp_left", "table_lamp", 0.925, 4.8, 0.55, 0.0).on("nightstand_left"),
            a("table_lamp_right", "table_lamp", 3.075, 4.8, 0.55, 30.0).on("nightstand_right"),
            // Yaw 90: back toward -x, 0.30 - 0.30 = 0 (west wall); spans y 1.6..2.6.
            a("wardrobe", "wardrobe", 0.3, 2.1, 0.0, 90.0),
            // x 1.4..3.4, y 0.9..2.3: 0.1 m clear of the door's 0.9 m deep clearance box.
            a("rug", "rug", 2.4, 1.6, 0.0, 0.0),
            // Back on the north wall: 4.98 + 0.02 = 5.0; z 1.3..1.9 above the 1.1 m headboard.
            a("painting", "painting", 2.0, 4.98, 1.3, 0.0).on_wall("bedroom_wall_2"),
            ceiling_lamp("ceiling_lamp", 2.0, 2.5),
        ],
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Scene 1: a living room facing a wall-mounted TV.
fn living_room() -> SceneSpec {
    let room = rect("living_room", "living_room", (0.0, 0.0), (5.0, 4.5))
        // Wall 2 runs from (5, 4.5) to (0, 4.5): along 3.6..4.5 is x 1.4..0.5.
        .door(2, [3.6, 4.5], DOOR_H)
        .window(0, [2.0, 3.5], [0.8, 2.2]);
    SceneSpec {
        number: 1,
        title: "living room",
        description: "A living room where a sofa faces a wall-mounted TV above a TV stand, with a coffee table on a rug, a reading chair, a floor lamp, a plant and a painting.",
        rooms: vec![room],
        objects: vec![
            // Yaw 90: faces +x, back at x = 0.45 - 0.45 = 0; spans y 1.25..3.25.
            a("sofa", "sofa", 0.45, 2.25, 0.0, 90.0),
            // Yaw 90: x 1.5..2.9, y 1.25..3.25.
            a("rug", "rug", 2.2, 2.25, 0.0, 90.0),
            // Resting on the 1 cm rug: x 1.9..2.5, y 1.7..2.8.
            a("coffee_table", "coffee_table", 2.2, 2.25, 0.01, 90.0).on("rug"),
            // Yaw -90: faces -x, back at x = 4.8 + 0.2 = 5.0.
            a("tv_stand", "tv_stand", 4.8, 2.25, 0.0, -90.0),
            // Back at x = 4.97 + 0.03 = 5.0, 0.4 m above the stand.
            a("tv", "tv", 4.97, 2.25, 0.9, -90.0).on_wall("living_room_wall_1"),
            a("floor_lamp", "floor_lamp", 0.22, 0.22, 0.0, 0.0),
            a("plant", "plant", 4.75, 4.25, 0.0, 0.0),
            a("painting", "painting", 3.2, 4.48, 1.2, 0.0).on_wall("living_room_wall_2"),
            // An armchair-like reading chair turned 135 degrees: its corners reach 0.311 m from
            // the centre, so it spans x 3.39..4.01 and y 0.69..1.31.
            a("chair", "chair", 3.7, 1.0, 0.0, 135.0),
            ceiling_lamp("ceiling_lamp", 2.5, 2.25),
        ],
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Scene 2: a dining room in an L-shaped room.
fn dining_room() -> SceneSpec {
    let outline = [
        (0.0, 0.0),
        (6.0, 0.0),
        (6.0, 3.0),
        (3.0, 3.0),
        (3.0, 6.0),
        (0.0, 6.0),
    ];
    let room = RoomBuilder::polygon(
        "dining_room",
        outline.iter().map(|&(x, y)| Point2::new(x, y)).collect(),
    )
    .kind("dining_room")
    .wall_height(WALL_H)
    .door(0, [4.5, 5.4], DOOR_H)
    .window(1, [0.8, 2.2], WINDOW_H)
    .window(4, [0.8, 2.2], WINDOW_H);
    SceneSpec {
        number: 2,
        title: "dining room (L-shaped)",
        description: "A dining room in an L-shaped room with a dining table surrounded by six chairs, a bookshelf, a plant, a floor lamp, a painting and a ceiling lamp.",
        rooms: vec![room],
        objects: vec![
            // Yaw 90: the 1.6 m side along y: x 1.05..1.95, y 3.2..4.8.
            a("dining_table", "dining_table", 1.5, 4.0, 0.0, 90.0),
            // West chairs face +x: x = 1.05 - 0.05 - 0.22 = 0.78.
            a("chair_west_0", "chair", 0.78, 3.6, 0.0, 90.0),
            a("chair_west_1", "chair", 0.78, 4.4, 0.0, 90.0),
            // East chairs face -x: x = 1.95 + 0.05 + 0.22 = 2.22.
            a("chair_east_0", "chair", 2.22, 3.6, 0.0, -90.0),
            a("chair_east_1", "chair", 2.22, 4.4, 0.0, -90.0),
            // Head chairs: y = 3.2 - 0.27 = 2.93 facing +y, and 4.8 + 0.27 = 5.07 facing -y.
            a("chair_south", "chair", 1.5, 2.93, 0.0, 180.0),
            a("chair_north", "chair", 1.5, 5.07, 0.0, 0.0),
            ceiling_lamp("ceiling_lamp", 1.5, 4.0),
            // Against wall 2 (y = 3, room below): back at 2.85 + 0.15 = 3.0.
            a("bookshelf", "bookshelf", 4.5, 2.85, 0.0, 0.0),
            a("plant", "plant", 5.75, 2.75, 0.0, 0.0),
            a("floor_lamp", "floor_lamp", 0.22, 0.22, 0.0, 0.0),
            // On wall 3 (x = 3, room to the west), facing -x: back at 2.98 + 0.02 = 3.0.
            a("painting", "painting", 2.98, 4.5, 1.3, -90.0).on_wall("dining_room_wall_3"),
        ],
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Scene 3: a home office in a room with a diagonal wall.
fn office() -> SceneSpec {
    let outline = [(0.0, 0.0), (5.0, 0.0), (5.0, 2.0), (2.0, 5.0), (0.0, 5.0)];
    let room = RoomBuilder::polygon(
        "office",
        outline.iter().map(|&(x, y)| Point2::new(x, y)).collect(),
    )
    .kind("office")
    .wall_height(WALL_H)
    // Wall 4 runs from (0, 5) to (0, 0): along 0.5..1.4 is y 4.5..3.6.
    .door(4, [0.5, 1.4], DOOR_H)
    // The diagonal wall 2 from (5, 2) to (2, 5), 3 sqrt(2) = 4.243 m long.
    .window(2, [0.6, 1.6], [0.9, 2.0]);
    // The bookshelf's back on the diagonal wall's midpoint (3.5, 3.5); its centre 0.15 m inward
    // along the inward normal (-1, -1)/sqrt(2); yaw -45 turns its front to that normal.
    let shelf = 3.5 - 0.15 * FRAC_1_SQRT_2;
    SceneSpec {
        number: 3,
        title: "home office (diagonal wall)",
        description: "A home office in a room with a diagonal wall: a desk with a lamp against the wall, a turned desk chair, a bookshelf on the diagonal wall, a rug, a floor lamp, a plant, a painting and a ceiling lamp.",
        rooms: vec![room],
        objects: vec![
            // Yaw 180: faces +y, back at y = 0.35 - 0.35 = 0.
            a("desk", "desk", 2.5, 0.35, 0.0, 180.0),
            // Turned 20 degrees: its lowest corner is at y = 1.0 - 0.22 (cos 20 + sin 20) = 0.718,
            // clear of the desk's front edge at y = 0.7.
            a("chair", "chair", 2.5, 1.0, 0.0, 20.0),
            a("table_lamp", "table_lamp", 2.0, 0.3, 0.75, 0.0).on("desk"),
            a("bookshelf", "bookshelf", shelf, shelf, 0.0, -45.0),
            a("floor_lamp", "floor_lamp", 0.22, 0.22, 0.0, 0.0),
            a("plant", "plant", 4.75, 0.25, 0.0, 0.0),
            // Turned 30 degrees: x 0.78..3.22, y 1.49..3.71, x + y <= 6.22 (wall at 7).
            a("rug", "rug", 2.0, 2.6, 0.0, 30.0),
            ceiling_lamp("ceiling_lamp", 2.2, 2.2),
            a("painting", "painting", 1.0, 4.98, 1.3, 0.0).on_wall("office_wall_3"),
        ],
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Scene 4: a two-room apartment (bedroom and living room joined by a door). Walls have zero
/// thickness so the two floors meet under the connecting door.
fn apartment() -> SceneSpec {
    let bedroom = rect("bedroom", "bedroom", (0.0, 0.0), (4.0, 5.0))
        .wall_thickness(0.0)
        .with_ceiling()
        // Wall 1 (x = 4) from (4, 0) to (4, 5): along 3.6..4.5 is y 3.6..4.5.
        .door(1, [3.6, 4.5], DOOR_H)
        // Wall 3 (x = 0) from (0, 5) to (0, 0): along 1.5..3.0 is y 3.5..2.0.
        .window(3, [1.5, 3.0], WINDOW_H);
    let living = rect("living_room", "living_room", (4.0, 0.0), (9.0, 5.0))
        .wall_thickness(0.0)
        // Wall 3 (x = 4) from (4, 5) to (4, 0): along 0.5..1.4 is y 4.5..3.6, the same door.
        .door(3, [0.5, 1.4], DOOR_H)
        // The entrance: wall 0 from (4, 0) to (9, 0), along 3.5..4.4 is x 7.5..8.4.
        .door(0, [3.5, 4.4], DOOR_H)
        .window(2, [1.0, 2.5], WINDOW_H);
    SceneSpec {
        number: 4,
        title: "two-room apartment",
        description: "A two-room apartment: a bedroom with a bed, two nightstands, a lamp and a wide wardrobe, connected by a door to a living room with a sofa, a coffee table, a TV on a TV stand, a floor lamp and a small plant.",
        rooms: vec![bedroom, living],
        objects: vec![
            // Yaw 180: headboard (+y) toward -y, at y = 1.05 - 1.05 = 0.
            a("bed", "bed", 2.0, 1.05, 0.0, 180.0),
            a("nightstand_left", "nightstand", 0.925, 0.21, 0.0, 180.0),
            a("nightstand_right", "nightstand", 3.075, 0.21, 0.0, 180.0),
            // Carcass centre: y = 0.21 - 0.01 (turned 180 degrees).
            a("table_lamp", "table_lamp", 0.925, 0.2, 0.55, 0.0).on("nightstand_left"),
            // Scaled 1.2 in width: x 0.4..1.6; back at 4.7 + 0.3 = 5.0.
            a("wardrobe", "wardrobe", 1.0, 4.7, 0.0, 0.0).scaled([1.2, 1.0, 1.0]),
            ceiling_lamp("bedroom_lamp", 2.0, 2.5),
            // Yaw -90: back at x = 8.55 + 0.45 = 9.0; y 1.5..3.5.
            a("sofa", "sofa", 8.55, 2.5, 0.0, -90.0),
            a("coffee_table", "coffee_table", 7.0, 2.5, 0.0, 90.0),
            // Yaw 90: back at x = 4.2 - 0.2 = 4.0; y 1.5..2.9, clear of the door at y 3.6.
            a("tv_stand", "tv_stand", 4.2, 2.2, 0.0, 90.0),
            // Standing on the stand's top (z 0.5), screen facing +x toward the sofa.
            a("tv", "tv", 4.2, 2.2, 0.5, 90.0).on("tv_stand"),
            a("floor_lamp", "floor_lamp", 8.78, 4.78, 0.0, 0.0),
            // Scaled 0.8: 0.4 m wide, in the corner x 4.0..4.4, y 0.0..0.4.
            a("plant", "plant", 4.2, 0.2, 0.0, 0.0).scaled([0.8, 0.8, 0.8]),
            ceiling_lamp("living_lamp", 6.5, 2.5),
        ],
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Scene 5 (flawed): a nightstand pushed 0.10 m into the side of a wardrobe.
fn collision() -> SceneSpec {
    let room = rect("bedroom", "bedroom", (0.0, 0.0), (4.0, 4.0))
        .door(0, [2.5, 3.4], DOOR_H)
        // Wall 3 (x = 0) from (0, 4) to (0, 0): along 1.0..2.0 is y 3.0..2.0.
        .window(3, [1.0, 2.0], WINDOW_H);
    SceneSpec {
        number: 5,
        title: "collision",
        description: "A bedroom where a nightstand with a lamp is pushed into the side of a wardrobe, next to a bed and a chair.",
        rooms: vec![room],
        objects: vec![
            // x 0.5..1.5; carcass y 3.40..3.98 (2 cm off the wall), handles down to 3.38.
            a("wardrobe", "wardrobe", 1.0, 3.68, 0.0, 0.0),
            // x 1.4..1.85: its left side is 1.5 - 1.4 = 0.10 m inside the wardrobe; its carcass
            // y 3.55..3.95 lies within the wardrobe's, and its top (0.55) below the wardrobe's (2.0).
            a("nightstand", "nightstand", 1.625, 3.74, 0.0, 0.0),
            a("table_lamp", "table_lamp", 1.625, 3.75, 0.55, 0.0).on("nightstand"),
            // Yaw -90: headboard at x = 2.95 + 1.05 = 4.0; x 1.9..4.0, y 1.2..2.8.
            a("bed", "bed", 2.95, 2.0, 0.0, -90.0),
            a("chair", "chair", 0.8, 1.0, 0.0, 45.0),
        ],
        flaws: vec![Flaw::Collision {
            a: "wardrobe".into(),
            b: "nightstand".into(),
        }],
        navigable: None,
    }
}

/// Scene 6 (flawed): a chair hovering 0.25 m above the floor at a desk.
fn floating() -> SceneSpec {
    let room = rect("study", "office", (0.0, 0.0), (4.0, 4.0))
        .door(0, [0.5, 1.4], DOOR_H)
        .window(1, [1.0, 2.5], WINDOW_H);
    SceneSpec {
        number: 6,
        title: "floating object",
        description: "A study with a desk and a lamp against the wall, where the desk chair floats in the air, plus a bookshelf, a plant and a floor lamp.",
        rooms: vec![room],
        objects: vec![
            // Back at y = 3.65 + 0.35 = 4.0; x 1.3..2.7, front edge at y = 3.3.
            a("desk", "desk", 2.0, 3.65, 0.0, 0.0),
            // Faces +y toward the desk, y 2.81..3.25; its feet 0.25 m above the floor.
            a("chair", "chair", 2.0, 3.03, 0.25, 180.0).unsupported(SupportType::Ground),
            a("table_lamp", "table_lamp", 2.4, 3.7, 0.75, 0.0).on("desk"),
            // Yaw 90: back at x = 0.15 - 0.15 = 0; y 1.6..2.4.
            a("bookshelf", "bookshelf", 0.15, 2.0, 0.0, 90.0),
            a("plant", "plant", 3.75, 0.25, 0.0, 0.0),
            a("floor_lamp", "floor_lamp", 0.22, 3.78, 0.0, 0.0),
        ],
        flaws: vec![Flaw::Floating {
            object: "chair".into(),
        }],
        navigable: None,
    }
}

/// Scene 7 (flawed): a sofa half outside the room, through the east wall.
fn out_of_bounds() -> SceneSpec {
    let room = rect("living_room", "living_room", (0.0, 0.0), (4.0, 4.0))
        // Wall 3 (x = 0) from (0, 4) to (0, 0): along 0.5..1.4 is y 3.5..2.6.
        .door(3, [0.5, 1.4], DOOR_H)
        .window(2, [1.0, 2.5], WINDOW_H);
    SceneSpec {
        number: 7,
        title: "object outside the walls",
        description: "A living room whose sofa sticks halfway out through the wall, with a coffee table, a floor lamp, a plant and a painting.",
        rooms: vec![room],
        objects: vec![
            // Centred on the east wall's inner face x = 4: x 3.0..5.0. The sofa is its own
            // mirror image in x, so exactly half its surface lies beyond the wall. Only its two
            // west legs (x 3.05..3.10) stand on the floor, its centre of mass (x = 4.0) is
            // beyond them: it touches the floor but is not held by it.
            a("sofa", "sofa", 4.0, 2.0, 0.0, 0.0).tipping(),
            a("coffee_table", "coffee_table", 2.0, 1.2, 0.0, 0.0),
            a("floor_lamp", "floor_lamp", 0.22, 0.22, 0.0, 0.0),
            a("plant", "plant", 3.75, 3.75, 0.0, 0.0),
            // Yaw 180: faces +y, back at y = 0.02 - 0.02 = 0 on the south wall.
            a("painting", "painting", 3.0, 0.02, 1.3, 180.0).on_wall("living_room_wall_0"),
        ],
        flaws: vec![Flaw::OutOfBounds {
            object: "sofa".into(),
            wall: "living_room_wall_1".into(),
        }],
        navigable: None,
    }
}

/// Scene 8 (flawed): the room's only door is blocked by a wardrobe.
fn blocked_door() -> SceneSpec {
    let room = rect("bedroom", "bedroom", (0.0, 0.0), (3.5, 4.0))
        .door(0, [1.0, 1.9], DOOR_H)
        // Wall 2 from (3.5, 4) to (0, 4): along 1.0..2.5 is x 2.5..1.0.
        .window(2, [1.0, 2.5], WINDOW_H);
    SceneSpec {
        number: 8,
        title: "blocked door",
        description: "A small bedroom whose only door is blocked by a wardrobe standing right in front of it, with a bed, a nightstand and a ceiling lamp.",
        rooms: vec![room],
        objects: vec![
            // Yaw 180: back toward the door wall at y = 0.32 - 0.30 = 0.02; x 0.95..1.95 covers
            // the door's 1.0..1.9, height 2.0 of the door's 2.1.
            a("wardrobe", "wardrobe", 1.45, 0.32, 0.0, 180.0),
            // Yaw -90: headboard at x = 2.45 + 1.05 = 3.5; x 1.4..3.5, y 1.8..3.4.
            a("bed", "bed", 2.45, 2.6, 0.0, -90.0),
            // Back at y = 3.79 + 0.21 = 4.0; x 3.05..3.5.
            a("nightstand", "nightstand", 3.275, 3.79, 0.0, 0.0),
            ceiling_lamp("ceiling_lamp", 1.75, 2.0),
        ],
        flaws: vec![Flaw::BlockedDoor {
            door: "bedroom_wall_0_door_0".into(),
            by: "wardrobe".into(),
        }],
        navigable: Some(false),
    }
}

/// Scene 9 (flawed): a storage box entirely inside a wardrobe's solid volume.
fn inside() -> SceneSpec {
    let room = rect("bedroom", "bedroom", (0.0, 0.0), (3.0, 3.0))
        .door(0, [1.8, 2.7], DOOR_H)
        // Wall 3 (x = 0) from (0, 3) to (0, 0): along 1.0..2.0 is y 2.0..1.0.
        .window(3, [1.0, 2.0], WINDOW_H);
    SceneSpec {
        number: 9,
        title: "object inside another",
        description: "A small room with a wardrobe that has a storage box stuck inside its closed body, a bookshelf and a chair.",
        rooms: vec![room],
        objects: vec![
            // x 0.3..1.3, carcass y 2.42..3.0 (back on the north wall), z 0..2.
            a("wardrobe", "wardrobe", 0.8, 2.7, 0.0, 0.0),
            // Centred in the carcass (y 2.7 + 0.01): x 0.65..0.95, y 2.585..2.835, z 0.9..1.1.
            // Clearances to the carcass: x 0.35, y 0.165, z 0.9.
            a("storage_box", "storage_box", 0.8, 2.71, 0.9, 0.0).unsupported(SupportType::Object),
            // Yaw -90: back at x = 2.85 + 0.15 = 3.0; y 1.1..1.9.
            a("bookshelf", "bookshelf", 2.85, 1.5, 0.0, -90.0),
            // Turned 200 degrees: corners within 0.282 m, x 1.018..1.582, clear of the door's
            // clearance box x 1.8..2.7, y 0..0.9.
            a("chair", "chair", 1.3, 1.3, 0.0, 200.0),
        ],
        flaws: vec![Flaw::Inside {
            inner: "storage_box".into(),
            outer: "wardrobe".into(),
        }],
        navigable: None,
    }
}

/// Scene 10: a fully navigable, nearly empty room.
fn navigable_room() -> SceneSpec {
    let room = rect("living_room", "living_room", (0.0, 0.0), (5.0, 4.0))
        .door(0, [2.0, 2.9], DOOR_H)
        .window(2, [1.5, 3.0], WINDOW_H);
    SceneSpec {
        number: 10,
        title: "navigable room",
        description: "A nearly empty living room with a rug in the middle, a plant and a floor lamp in the corners, a painting and a ceiling lamp.",
        rooms: vec![room],
        objects: vec![
            a("rug", "rug", 2.5, 2.0, 0.0, 0.0),
            a("plant", "plant", 0.25, 3.75, 0.0, 0.0),
            a("floor_lamp", "floor_lamp", 4.78, 3.78, 0.0, 0.0),
            // Yaw 90: faces +x, back at x = 0.02 - 0.02 = 0 on the west wall.
            a("painting", "painting", 0.02, 2.0, 1.3, 90.0).on_wall("living_room_wall_3"),
            ceiling_lamp("ceiling_lamp", 2.5, 2.0),
        ],
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Scene 11: a bedroom made only of box objects, like a layout generator's output.
fn box_bedroom() -> SceneSpec {
    let room = rect("bedroom", "bedroom", (0.0, 0.0), (4.0, 4.5))
        .door(0, [2.8, 3.7], DOOR_H)
        .window(2, [1.5, 3.0], WINDOW_H);
    let bx = Placement::boxed;
    SceneSpec {
        number: 11,
        title: "box-only bedroom",
        description: "A bedroom laid out with plain boxes: a bed between two nightstands, a lamp, a wardrobe, a desk and a chair.",
        rooms: vec![room],
        objects: vec![
            // Yaw 90: head (+y) toward -x, at x = 1.0 - 1.0 = 0; y 1.7..3.3.
            bx(
                "bed",
                "bed",
                "A double bed.",
                [1.6, 2.0, 0.5],
                [1.0, 2.5, 0.0],
                90.0,
            ),
            // y = 1.7 - 0.05 - 0.225 = 1.425 and 3.3 + 0.05 + 0.225 = 3.575.
            bx(
                "nightstand_0",
                "nightstand",
                "A nightstand.",
                [0.45, 0.4, 0.55],
                [0.2, 1.425, 0.0],
                90.0,
            ),
            bx(
                "nightstand_1",
                "nightstand",
                "A nightstand.",
                [0.45, 0.4, 0.55],
                [0.2, 3.575, 0.0],
                90.0,
            ),
            bx(
                "lamp",
                "table lamp",
                "A small table lamp.",
                [0.2, 0.2, 0.4],
                [0.2, 3.575, 0.55],
                0.0,
            )
            .on("nightstand_1"),
            // Back on the north wall: 4.2 + 0.3 = 4.5; x 2.7..3.7.
            bx(
                "wardrobe",
                "wardrobe",
                "A tall wardrobe.",
                [1.0, 0.6, 2.0],
                [3.2, 4.2, 0.0],
                0.0,
            ),
            // Yaw -90: back at x = 3.7 + 0.3 = 4.0; y 1.4..2.6.
            bx(
                "desk",
                "desk",
                "A writing desk.",
                [1.2, 0.6, 0.75],
                [3.7, 2.0, 0.0],
                -90.0,
            ),
            // Turned 80 degrees (front toward +x): corners reach 0.225 (cos 10 + sin 10) = 0.261,
            // so x 2.814..3.336, 0.064 m from the desk.
            bx(
                "chair",
                "chair",
                "A desk chair.",
                [0.45, 0.45, 0.9],
                [3.075, 2.0, 0.0],
                80.0,
            ),
        ],
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Scene 12: a large open-plan office and a meeting lounge, 108 objects, for benchmarks.
fn large_office() -> SceneSpec {
    let office = rect("office", "office", (0.0, 0.0), (12.0, 8.0))
        .wall_thickness(0.0)
        .door(0, [5.0, 5.9], DOOR_H)
        // Wall 1 (x = 12) from (12, 0) to (12, 8): y 3.5..4.4.
        .door(1, [3.5, 4.4], DOOR_H)
        // Wall 2 runs from (12, 8) to (0, 8): the windows sit over the gaps between desk columns,
        // x 8.8..9.4 and 6.6..7.2.
        .window(2, [2.6, 3.2], WINDOW_H)
        .window(2, [4.8, 5.4], WINDOW_H);
    let lounge = rect("lounge", "living_room", (12.0, 0.0), (20.0, 8.0))
        .wall_thickness(0.0)
        // Wall 3 (x = 12) from (12, 8) to (12, 0): along 3.6..4.5 is y 4.4..3.5.
        .door(3, [3.6, 4.5], DOOR_H)
        // Wall 1 (x = 20): y 5.0..6.0, between the two sofas.
        .window(1, [5.0, 6.0], WINDOW_H);
    let mut objects = Vec::new();
    // 4 rows x 5 columns of desks (yaw 0, backs toward +y), each with a chair in front
    // (yaw 180, y = desk - 0.35 - 0.05 - 0.22) and a lamp turned by 15 degrees per desk.
    for (r, y) in [1.9, 3.8, 5.7, 7.6].into_iter().enumerate() {
        for (c, x) in [1.4, 3.6, 5.8, 8.0, 10.2].into_iter().enumerate() {
            let k = r * 5 + c;
            objects.push(a(&format!("desk_{k}"), "desk", x, y, 0.0, 0.0));
            objects.push(a(&format!("chair_{k}"), "chair", x, y - 0.62, 0.0, 180.0));
            objects.push(
                a(
                    &format!("lamp_{k}"),
                    "table_lamp",
                    x + 0.5,
                    y + 0.1,
                    0.75,
                    15.0 * k as f64,
                )
                .on(&format!("desk_{k}")),
            );
        }
    }
    // Bookshelves along the west wall, facing +x (back at x = 0.15 - 0.15 = 0).
    for (i, y) in [1.0, 2.2, 3.4, 4.6, 5.8, 7.0].into_iter().enumerate() {
        objects.push(a(&format!("bookshelf_{i}"), "bookshelf", 0.15, y, 0.0, 90.0));
    }
    for (i, (x, y)) in [(0.25, 0.25), (0.25, 7.75), (11.75, 0.25), (11.75, 7.75)]
        .into_iter()
        .enumerate()
    {
        objects.push(a(&format!("office_plant_{i}"), "plant", x, y, 0.0, 0.0));
    }
    for (i, (x, y)) in [2.0, 6.0, 10.0]
        .into_iter()
        .flat_map(|x| [(x, 2.8), (x, 5.6)])
        .enumerate()
    {
        objects.push(ceiling_lamp(&format!("office_lamp_{i}"), x, y));
    }
    // Two meeting tables, each with six chairs 5 cm from its edges.
    for (t, ty) in [2.0, 6.0].into_iter().enumerate() {
        objects.push(a(
            &format!("meeting_table_{t}"),
            "dining_table",
            14.5,
            ty,
            0.0,
            0.0,
        ));
        let seats = [
            (14.1, ty - 0.72, 180.0),
            (14.9, ty - 0.72, 180.0),
            (14.1, ty + 0.72, 0.0),
            (14.9, ty + 0.72, 0.0),
            (13.43, ty, 90.0),
            (15.57, ty, -90.0),
        ];
        for (s, (x, y, yaw)) in seats.into_iter().enumerate() {
            objects.push(a(&format!("meeting_chair_{t}_{s}"), "chair", x, y, 0.0, yaw));
        }
    }
    objects.extend([
        a("sofa_0", "sofa", 18.0, 7.55, 0.0, 0.0),
        // y 5.4..6.8, 0.3 m from the sofa's front at 7.1.
        a("rug_0", "rug", 18.0, 6.1, 0.0, 0.0),
        a("coffee_table_0", "coffee_table", 18.0, 6.1, 0.01, 0.0).on("rug_0"),
        a("sofa_1", "sofa", 19.55, 3.5, 0.0, -90.0),
        a("rug_1", "rug", 18.3, 3.5, 0.0, 90.0),
        a("coffee_table_1", "coffee_table", 18.3, 3.5, 0.01, 90.0).on("rug_1"),
        a("tv_stand", "tv_stand", 18.0, 0.2, 0.0, 180.0),
        a("tv", "tv", 18.0, 0.2, 0.5, 180.0).on("tv_stand"),
        a("floor_lamp_0", "floor_lamp", 19.78, 7.78, 0.0, 0.0),
        a("floor_lamp_1", "floor_lamp", 19.78, 0.22, 0.0, 0.0),
        a("painting_0", "painting", 12.02, 1.5, 1.3, 90.0).on_wall("lounge_wall_3"),
        a("painting_1", "painting", 12.02, 6.5, 1.3, 90.0).on_wall("lounge_wall_3"),
        // Not in the corner: the office's plant stands just behind the (zero-thickness) wall.
        a("lounge_plant_0", "plant", 13.2, 7.75, 0.0, 0.0),
        a("lounge_plant_1", "plant", 16.0, 0.25, 0.0, 0.0),
    ]);
    for (i, (x, y)) in [(14.5, 2.0), (14.5, 6.0), (18.0, 2.0), (18.0, 6.0)]
        .into_iter()
        .enumerate()
    {
        objects.push(ceiling_lamp(&format!("lounge_lamp_{i}"), x, y));
    }
    SceneSpec {
        number: 12,
        title: "large office (benchmark)",
        description: "A large open-plan office with twenty desks, chairs and lamps, bookshelves and plants, connected by a door to a lounge with two meeting tables and twelve chairs, two sofas with coffee tables on rugs, a TV and paintings.",
        rooms: vec![office, lounge],
        objects,
        flaws: vec![],
        navigable: Some(true),
    }
}

/// Every fixture scene, in number order.
pub fn all() -> Vec<SceneSpec> {
    vec![
        tidy_bedroom(),
        living_room(),
        dining_room(),
        office(),
        apartment(),
        collision(),
        floating(),
        out_of_bounds(),
        blocked_door(),
        inside(),
        navigable_room(),
        box_bedroom(),
        large_office(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn scenes_are_numbered_in_order_with_unique_keys() {
        let scenes = all();
        assert!(scenes.len() >= 12);
        for (i, s) in scenes.iter().enumerate() {
            assert_eq!(s.number as usize, i);
            let keys: BTreeSet<_> = s.objects.iter().map(|p| p.key.as_str()).collect();
            assert_eq!(keys.len(), s.objects.len(), "{}: duplicate keys", s.name());
            for p in &s.objects {
                if let crate::spec::Support::On(k) = &p.support {
                    assert!(
                        keys.contains(k.as_str()),
                        "{}: {} on unknown {k}",
                        s.name(),
                        p.key
                    );
                }
            }
            for r in &s.rooms {
                r.clone().build().unwrap();
            }
        }
    }

    #[test]
    fn the_large_scene_has_over_100_objects_in_two_rooms() {
        let large = large_office();
        // 20 x (desk, chair, lamp) + 6 shelves + 4 plants + 6 lamps = 76 in the office;
        // 2 x (table + 6 chairs) + 14 lounge pieces + 4 lamps = 32 in the lounge.
        assert_eq!(large.objects.len(), 108);
        assert_eq!(large.rooms.len(), 2);
    }

    #[test]
    fn flaw_kinds_are_all_present() {
        let flaws: Vec<Flaw> = all().into_iter().flat_map(|s| s.flaws).collect();
        assert!(flaws.iter().any(|f| matches!(f, Flaw::Collision { .. })));
        assert!(flaws.iter().any(|f| matches!(f, Flaw::Floating { .. })));
        assert!(flaws.iter().any(|f| matches!(f, Flaw::OutOfBounds { .. })));
        assert!(flaws.iter().any(|f| matches!(f, Flaw::BlockedDoor { .. })));
        assert!(flaws.iter().any(|f| matches!(f, Flaw::Inside { .. })));
    }
}
