//! Scene files with typos (issue 34, item 4): an object without `transform` is an error naming
//! the file and the object, keys the format does not have are one warning per key and file (an
//! error when reading strictly), and a key given twice in one object is an error.

// The sstk-shaped document of `the_keys_of_sstk_files_and_generators_exports_are_known` is one
// large `json!`.
#![recursion_limit = "256"]
// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use sceneeval_io::scene_state::UnknownKey;
use sceneeval_io::{AssetLibrary, IoError, ReadOptions, read_scene_state_str};
use sceneeval_scene::Scene;
use sceneeval_test_support::logs::SharedBuffer;
use serde_json::{Value, json};

/// Runs `f` with the warnings it logs captured (this thread only), one per line.
fn warnings<T>(f: impl FnOnce() -> T) -> (T, Vec<String>) {
    let buffer = SharedBuffer::default();
    let writer = buffer.clone();
    let subscriber = tracing_subscriber::fmt()
        .with_max_level(tracing::Level::WARN)
        .with_writer(move || writer.clone())
        .with_ansi(false)
        .finish();
    let out = tracing::subscriber::with_default(subscriber, f);
    (out, buffer.text().lines().map(str::to_owned).collect())
}

fn read(doc: &Value, file: &str, options: &ReadOptions) -> Result<Scene, IoError> {
    read_scene_state_str(&doc.to_string(), Path::new(file), &AssetLibrary::new(), options)
}

fn translation(x: f64, y: f64, z: f64) -> Value {
    json!({"data": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, y, z, 1]})
}

/// A 4 x 3 m room with a bed against the far wall and a lamp in the near right corner.
fn room(lamp: Value) -> Value {
    json!({
        "format": "sceneState",
        "scene": {
            "arch": {"elements": [
                {"id": "floor", "roomId": "r0", "type": "Floor",
                 "points": [[0, 0, 0], [4, 0, 0], [4, 3, 0], [0, 3, 0]]}
            ]},
            "object": [
                {"index": 0, "objectId": "bed", "box": {"size": [1.6, 2.0, 0.5]},
                 "transform": translation(2.0, 1.9, 0.25)},
                lamp
            ]
        }
    })
}

#[test]
fn a_misspelt_transform_is_an_error_naming_the_object_not_an_object_at_the_origin() {
    // The reproduction: with the key misspelt, the lamp used to stand at the origin,
    // half outside the room and inside nothing, and the scores changed without a word.
    let doc = room(
        json!({"index": 1, "objectId": "lamp", "box": {"size": [0.3, 0.3, 1.5]},
                          "transfrom": translation(3.6, 0.4, 0.75)}),
    );
    let (result, logged) = warnings(|| read(&doc, "scenes/scene_7.json", &ReadOptions::default()));
    match result {
        Err(IoError::MissingTransform {
            path,
            pointer,
            index,
            id,
            similar,
        }) => {
            assert_eq!(path, Path::new("scenes/scene_7.json"));
            assert_eq!(
                (pointer.as_str(), index, id.as_str()),
                ("/scene/object/1", 1, "lamp")
            );
            assert_eq!(similar, "transfrom");
        }
        other => panic!("{other:?}"),
    }
    let err = read(&doc, "scenes/scene_7.json", &ReadOptions::default()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "scenes/scene_7.json: /scene/object/1: object \"lamp\" (index 1) has no \"transform\" \
         (it has the unknown key \"transfrom\")"
    );
    // The unknown key was reported before, with the key it resembles.
    assert_eq!(logged.len(), 1, "{logged:?}");
    assert!(
        logged[0].contains("scenes/scene_7.json")
            && logged[0].contains("/scene/object/1: unknown key \"transfrom\"; did you mean \"transform\"?"),
        "{}",
        logged[0]
    );
    // A box without any transform is refused just the same (the identity is never meant).
    let doc = room(json!({"index": 1, "box": {"size": [0.3, 0.3, 1.5]}}));
    match read(&doc, "s.json", &ReadOptions::default()) {
        Err(IoError::MissingTransform { id, similar, .. }) => {
            assert_eq!((id.as_str(), similar.as_str()), ("idx1_box", ""));
        }
        other => panic!("{other:?}"),
    }
}

/// The room with a misspelt key on three objects and on a wall.
fn with_unknown_keys() -> Value {
    let mut doc = room(
        json!({"index": 1, "objectId": "lamp", "box": {"size": [0.3, 0.3, 1.5]},
                              "transform": translation(3.6, 0.4, 0.75), "colour": "red"}),
    );
    let objects = doc["scene"]["object"].as_array_mut().unwrap();
    objects[0]["colour"] = json!("white");
    objects.push(
        json!({"index": 2, "objectId": "rug", "box": {"size": [1, 1, 0.01]},
                        "transform": translation(2.0, 0.8, 0.005), "colour": "grey"}),
    );
    doc["scene"]["arch"]["elements"].as_array_mut().unwrap().push(
        json!({"id": "w0", "roomId": "r0", "type": "Wall", "height": 2.8, "hieght": 3.0,
                     "points": [[0, 0, 0], [4, 0, 0]]}),
    );
    doc
}

#[test]
fn unknown_keys_are_one_warning_per_key_and_file() {
    let doc = with_unknown_keys();
    let (scene, logged) = warnings(|| read(&doc, "a/scene_1.json", &ReadOptions::default()).unwrap());
    assert_eq!(scene.objects().len(), 3, "the scene is read");
    assert_eq!(logged.len(), 2, "{logged:#?}");
    assert!(logged[0].contains("a/scene_1.json"), "{}", logged[0]);
    assert!(
        logged[0].contains("/scene/arch/elements/1: unknown key \"hieght\"; did you mean \"height\"?"),
        "{}",
        logged[0]
    );
    assert!(
        logged[1].contains("/scene/object/0: unknown key \"colour\" (and in 2 more like it)")
            && logged[1].contains("occurrences=3"),
        "{}",
        logged[1]
    );
    // Another file: its own warnings, naming it.
    let (_, logged) = warnings(|| read(&doc, "b/scene_2.json", &ReadOptions::default()).unwrap());
    assert_eq!(logged.len(), 2);
    assert!(logged.iter().all(|l| l.contains("b/scene_2.json")), "{logged:?}");
}

#[test]
fn strict_reading_refuses_unknown_keys_listing_them_all() {
    let doc = with_unknown_keys();
    let strict = ReadOptions::default().with_strict(true);
    let (result, logged) = warnings(|| read(&doc, "a/scene_1.json", &strict));
    assert!(logged.is_empty(), "an error, not warnings: {logged:?}");
    match result {
        Err(e @ IoError::UnknownKeys { .. }) => {
            assert_eq!(e.pointer(), Some("/scene/arch/elements/1"));
            assert_eq!(
                e.to_string(),
                "a/scene_1.json: 2 unknown keys the sceneState format does not have (strict reading):\n  \
                 /scene/arch/elements/1: unknown key \"hieght\"; did you mean \"height\"?\n  \
                 /scene/object/0: unknown key \"colour\" (and in 2 more like it)"
            );
            let IoError::UnknownKeys { keys, .. } = e else {
                unreachable!()
            };
            let colour: &UnknownKey = &keys[1];
            assert_eq!(
                (colour.place, colour.occurrences, colour.similar),
                ("/scene/object/*", 3, None)
            );
        }
        other => panic!("{other:?}"),
    }
    // A file with only known keys reads strictly.
    let clean = room(
        json!({"index": 1, "objectId": "lamp", "box": {"size": [0.3, 0.3, 1.5]},
                            "transform": translation(3.6, 0.4, 0.75)}),
    );
    assert_eq!(read(&clean, "c.json", &strict).unwrap().objects().len(), 2);
}

#[test]
fn the_keys_of_sstk_files_and_generators_exports_are_known() {
    // What the reference's template and examples, the fork's converters and SceneSmith's
    // exporter write, none of which the reader uses: no warning, and strict reading accepts it.
    let doc = json!({
        "format": "sceneState",
        "selected": [],
        "scene": {
            "version": "scene@1.0.2", "id": "converted-scene", "up": [0, 0, 1], "front": [0, 1, 0],
            "unit": 1.0, "assetSource": ["objaverse"], "modifications": [],
            "objectFrontVector": [0, -1, 0],
            "arch": {
                "version": "arch@1.0.2", "id": "arch", "up": [0, 0, 1], "front": [0, 1, 0],
                "coords2d": [0, 1], "scaleToMeters": 1, "holes": [], "images": [], "materials": [],
                "textures": [], "open_room_pairs": [["a", "b"]],
                "defaults": {"Wall": {"depth": 0.1, "extraHeight": 0.035}, "textureSource": "smtTexture"},
                "regions": [{"id": "r0", "type": "Other", "walls": [1]}],
                "elements": [
                    {"id": 0, "roomId": "r0", "type": "Floor", "depth": 0.05, "roomType": "bedroom",
                     "materials": [{"diffuse": "#888899", "name": "surface", "texture": "wood"}],
                     "points": [[0, 0, 0], [4, 0, 0], [4, 3, 0], [0, 3, 0]]},
                    {"id": 1, "roomId": "r0", "type": "Wall", "height": 2.8, "depth": 0.025, "materials": [],
                     "points": [[0, 0, 0], [4, 0, 0]],
                     "holes": [{"id": "d0", "type": "Door", "box": {"min": [1, 0], "max": [1.9, 2.1]}}]}
                ]
            },
            "object": [
                {"id": "1", "index": 0, "parentId": "", "parentIndex": -1, "objectId": "bed",
                 "box": {"size": [1.6, 2.0, 0.5]}, "category": "bed", "description": "a bed",
                 "supportType": "ground", "functionalSides": ["left", "right"],
                 "transform": {"rows": 4, "cols": 4, "data": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 1.9, 0.25, 1],
                               "rotation": [0, 0, 0, 1], "scale": [1, 1, 1], "translation": [2, 1.9, 0.25]},
                 "objectPose": {"rotation": [0, 0, 0, 1]}},
                {"id": "floor_0", "modelId": "scenesmith.floor_0", "isArchitecture": true,
                 "sdfPath": "floor.sdf", "transform": translation(0.0, 0.0, 0.0)}
            ]
        }
    });
    assert!(sceneeval_io::scene_state::unknown_keys(&doc).is_empty());
    let strict = ReadOptions::default().with_strict(true);
    let (scene, logged) = warnings(|| read(&doc, "s.json", &strict).unwrap());
    assert_eq!(scene.objects().len(), 1);
    assert!(logged.iter().all(|l| !l.contains("unknown key")), "{logged:?}");
}

#[test]
fn a_key_given_twice_in_one_object_is_an_error() {
    let text = "{\"format\": \"sceneState\", \"scene\": {\"object\": [\n  {\"index\": 0, \"box\": {\"size\": [1, 1, 1]},\n   \"transform\": {\"data\": [1,0,0,0,0,1,0,0,0,0,1,0,0,0,0.5,1]},\n   \"transform\": {\"data\": [1,0,0,0,0,1,0,0,0,0,1,0,3,3,0.5,1]}}\n]}}";
    let err = read_scene_state_str(
        text,
        Path::new("d.json"),
        &AssetLibrary::new(),
        &ReadOptions::default(),
    )
    .unwrap_err();
    match &err {
        IoError::DuplicateKey {
            pointer, key, line, ..
        } => {
            assert_eq!(
                (pointer.as_str(), key.as_str(), *line),
                ("/scene/object/0", "transform", 4)
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(err.to_string().starts_with("d.json:4:"), "{err}");
    assert!(
        err.to_string()
            .ends_with(": /scene/object/0: key \"transform\" appears twice in one object"),
        "{err}"
    );
}
