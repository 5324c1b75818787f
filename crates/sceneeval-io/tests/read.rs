//! Reader behaviour on valid files: architecture rules, the simple architecture, ids.

// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use sceneeval_geom::{Point2, Vector2};
use sceneeval_io::{ArchitectureMode, AssetLibrary, ReadOptions, SimpleFloorHeight, read_scene_state_str};
use sceneeval_scene::{OpeningKind, Scene};

fn read(text: &str, options: &ReadOptions) -> Scene {
    read_scene_state_str(text, Path::new("dir/scene_4.json"), &AssetLibrary::new(), options).unwrap()
}

/// Shaped like the sstk files other tools write: walls before the floor, integer element ids,
/// extra fields the reader ignores (`materials`, `regions`, `defaults`, nulls).
const STYLE: &str = r#"{
  "format": "sceneState",
  "scene": {
    "version": "scene@1.0.2", "up": [0, 0, 1], "front": [0, 1, 0], "unit": 1.0, "assetSource": ["x"],
    "arch": {
      "version": "arch@1.0.2", "coords2d": [0, 1], "defaults": {"Wall": {"depth": 0.1}},
      "regions": [{"id": "0", "type": "Other", "walls": [1, 2]}],
      "elements": [
        {"id": 1, "roomId": "0", "type": "Wall", "height": 3.0, "depth": 0.025, "materials": [],
         "points": [[0, 0, 0], [6, 0, 0]],
         "holes": [{"type": "door", "box": {"min": [1, 0], "max": [2, 2.1]}},
                   {"type": "Opening", "box": {"min": [3, 0], "max": [4, 2.1]}},
                   {"id": "win", "type": "WINDOW", "box": {"min": [4.5, 1], "max": [5.5, 2]}}]},
        {"id": 2, "roomId": 0, "type": "Wall", "height": 3.0, "points": [[6, 0, 0], [6, 6, 0]], "holes": null},
        {"id": 3, "type": "Wall", "height": 2.5, "points": [[10, 0, 0.5], [10, 4, 0.5]]},
        {"id": 0, "roomId": "0", "type": "Floor", "materials": [],
         "points": [[0, 0, 0], [6, 0, 0], [6, 6, 0], [0, 6, 0]]},
        {"id": "f2", "roomId": "annex", "type": "floor", "points": [[7, 0, 0.5], [9, 0, 0.5], [9, 4, 0.5], [7, 4, 0.5]]},
        {"roomId": "annex", "type": "Ceiling", "points": [[7, 0, 2.9], [9, 0, 2.9], [9, 4, 2.9], [7, 4, 2.9]]}
      ]
    },
    "object": [
      {"id": "1", "index": 0, "box": {"size": [1, 1, 1]}, "parentId": "", "parentIndex": 0,
       "transform": {"rows": 4, "cols": 4, "data": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 3, 3, 0.5, 1],
                     "rotation": [0, 0, 0, 1], "scale": [1, 1, 1], "translation": [3, 3, 0.5]}},
      {"index": 1, "box": {"size": [2, 1, 1]}, "modelId": "gen.sofa", "objectId": "sofa",
       "transform": {"data": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}}
    ]
  },
  "selected": []
}"#;

#[test]
fn sstk_style_file_is_read() {
    let scene = read(STYLE, &ReadOptions::default());
    assert_eq!(scene.name(), Some("scene_4"));
    assert_eq!(scene.rooms().len(), 2);
    let main = &scene.rooms()[0];
    assert_eq!(main.id().as_str(), "0");
    assert_eq!(main.floor_id(), "0");
    assert_eq!(main.walls().len(), 2, "roomId 0 as a number matches \"0\"");
    let w1 = &main.walls()[0];
    assert_eq!(w1.id(), "1");
    assert_eq!(w1.thickness(), 0.025);
    assert_eq!(w1.inward_normal(), Vector2::new(0.0, 1.0));
    // Door and window (any case) are kept; the "Opening" hole is skipped.
    let kinds: Vec<_> = w1.openings().iter().map(|o| (o.id.as_str(), o.kind)).collect();
    assert_eq!(
        kinds,
        [("1_door_0", OpeningKind::Door), ("win", OpeningKind::Window)]
    );
    assert_eq!(main.walls()[1].thickness(), 0.0, "no depth: zero thickness");
    assert!(main.explicit_ceiling().is_none());

    // The wall without roomId is attached to the nearest floor (the annex, 1 m away), and
    // its base is at its points' z.
    let annex = scene.room("annex").unwrap();
    assert_eq!(annex.floor_id(), "f2");
    assert_eq!(annex.floor_z(), 0.5);
    assert_eq!(annex.walls()[0].id(), "3");
    assert_eq!(annex.walls()[0].base_z(), 0.5);
    let ceiling = annex.explicit_ceiling().unwrap();
    assert_eq!((ceiling.id.as_str(), ceiling.z), ("ceiling_annex", 2.9));
    assert_eq!(annex.ceiling_z(), Some(2.9));

    // Objects: sstk "id" is ignored (reference naming), "objectId" is ours.
    let ids: Vec<_> = scene.objects().iter().map(|o| o.id().as_str()).collect();
    assert_eq!(ids, ["idx0_box", "sofa"]);
    assert_eq!(
        scene.objects()[1].model_id(),
        Some("gen.sofa"),
        "kept, never resolved"
    );
    // A missing transform is the identity.
    assert_eq!(scene.objects()[1].obb().center, sceneeval_geom::Point3::origin());
}

const NO_ARCH: &str = r#"{"format": "sceneState", "scene": {"object": [
    {"index": 0, "box": {"size": [2, 1, 1]}, "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 1,1,0.7,1]}},
    {"index": 1, "box": {"size": [1, 1, 1]}, "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 4,3,0.5,1]}}]}}"#;

#[test]
fn missing_arch_builds_the_simple_architecture() {
    // Objects span x in [0, 4.5], y in [0.5, 3.5], z from 0 (the second box's bottom).
    let scene = read(NO_ARCH, &ReadOptions::default());
    let room = &scene.rooms()[0];
    assert_eq!(room.id().as_str(), "room");
    assert_eq!(room.floor_id(), "floor");
    assert_eq!(room.floor_z(), 0.0);
    let (min, max) = room.floor().bounds();
    assert_eq!((min, max), (Point2::new(0.0, 0.5), Point2::new(4.5, 3.5)));
    let ids: Vec<_> = room.walls().iter().map(|w| w.id()).collect();
    assert_eq!(ids, ["wall_0", "wall_1", "wall_2", "wall_3"]);
    // wall_0 at max y facing -y; wall_1 at min x facing +x; all 3 m high.
    assert_eq!(room.walls()[0].start().y, 3.5);
    assert_eq!(room.walls()[0].inward_normal(), Vector2::new(0.0, -1.0));
    assert_eq!(room.walls()[1].inward_normal(), Vector2::new(1.0, 0.0));
    assert!(
        room.walls()
            .iter()
            .all(|w| w.height() == 3.0 && w.thickness() == 0.0)
    );

    // The floor at the lowest object (0.2 here, the first box's bottom) or at zero.
    let lifted = NO_ARCH.replace("4,3,0.5,1", "4,3,0.9,1");
    let lowest = read(&lifted, &ReadOptions::default());
    assert!((lowest.rooms()[0].floor_z() - 0.2).abs() < 1e-12);
    let zero = read(
        &lifted,
        &ReadOptions {
            simple_floor: SimpleFloorHeight::Zero,
            ..ReadOptions::default()
        },
    );
    assert_eq!(zero.rooms()[0].floor_z(), 0.0);

    let none = read(
        NO_ARCH,
        &ReadOptions {
            architecture: ArchitectureMode::FileOnly,
            ..ReadOptions::default()
        },
    );
    assert!(none.rooms().is_empty());
}

#[test]
fn always_simple_ignores_the_file_arch() {
    let scene = read(
        STYLE,
        &ReadOptions {
            architecture: ArchitectureMode::AlwaysSimple,
            simple_wall_height_m: 2.5,
            ..ReadOptions::default()
        },
    );
    assert_eq!(scene.rooms().len(), 1);
    assert_eq!(scene.rooms()[0].walls()[0].height(), 2.5);
    // An empty arch means no rooms; no objects means no simple architecture either.
    let empty = read(
        r#"{"format": "sceneState", "scene": {"arch": {}}}"#,
        &ReadOptions::default(),
    );
    assert!(empty.rooms().is_empty() && empty.objects().is_empty());
    let bare = read(
        r#"{"format": "sceneState", "scene": {}}"#,
        &ReadOptions::default(),
    );
    assert!(bare.rooms().is_empty());
}
