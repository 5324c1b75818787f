//! Every kind of bad input gives a clear error naming the file and the JSON pointer (or the
//! asset), and nothing panics.

// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use sceneeval_io::{AssetLibrary, IoError, ReadOptions, read_scene_state, read_scene_state_str};
use sceneeval_scene::SceneError;
use serde_json::{Value, json};

struct Fixture {
    dir: tempfile::TempDir,
    library: AssetLibrary,
}

impl Fixture {
    fn new() -> Self {
        let dir = tempfile::tempdir().unwrap();
        common::write_bump_asset(dir.path(), "bump");
        let library = common::fixture_library(dir.path());
        Fixture { dir, library }
    }

    fn path(&self) -> PathBuf {
        self.dir.path().join("scene_1.json")
    }

    fn read_text(&self, text: &str) -> Result<sceneeval_scene::Scene, IoError> {
        std::fs::write(self.path(), text).unwrap();
        read_scene_state(&self.path(), &self.library, &ReadOptions::default())
    }

    fn read(&self, v: &Value) -> Result<sceneeval_scene::Scene, IoError> {
        self.read_text(&serde_json::to_string_pretty(v).unwrap())
    }

    /// Reads `v` and returns the error, checking that it names this fixture's file.
    fn error(&self, v: &Value) -> IoError {
        let err = self.read(v).expect_err("expected an error");
        assert_eq!(err.path(), Some(self.path().as_path()), "{err}");
        assert!(err.to_string().contains("scene_1.json"), "{err}");
        err
    }
}

/// A valid scene: one room with a door, an asset object and a box object.
fn valid() -> Value {
    json!({
        "format": "sceneState",
        "scene": {
            "version": "scene@1.0.2",
            "arch": {"version": "arch@1.0.2", "elements": [
                {"id": "f", "roomId": "r", "type": "Floor",
                 "points": [[0, 0, 0], [4, 0, 0], [4, 3, 0], [0, 3, 0]]},
                {"id": "w0", "roomId": "r", "type": "Wall", "height": 2.8,
                 "points": [[0, 0, 0], [4, 0, 0]],
                 "holes": [{"type": "Door", "box": {"min": [1, 0], "max": [2, 2]}}]},
                {"id": "w1", "roomId": "r", "type": "Wall", "height": 2.8,
                 "points": [[4, 0, 0], [4, 3, 0]]}
            ]},
            "object": [
                {"index": 0, "modelId": "fixture.bump",
                 "transform": {"data": [1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 1, 1, 0, 1]}},
                {"index": 1, "box": {"size": [1, 1, 1]},
                 "transform": {"data": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 2, 0.5, 1]}}
            ]
        }
    })
}

fn with(mut v: Value, pointer: &str, new: Value) -> Value {
    *v.pointer_mut(pointer).unwrap_or_else(|| panic!("no {pointer}")) = new;
    v
}

fn without(mut v: Value, pointer: &str, key: &str) -> Value {
    v.pointer_mut(pointer)
        .unwrap()
        .as_object_mut()
        .unwrap()
        .remove(key);
    v
}

#[test]
fn the_valid_scene_loads() {
    let f = Fixture::new();
    let scene = f.read(&valid()).unwrap();
    assert_eq!(scene.objects().len(), 2);
    assert_eq!(scene.rooms()[0].walls().len(), 2);
}

#[test]
fn malformed_json_reports_line_and_column() {
    let f = Fixture::new();
    let text = "{\n  \"format\": \"sceneState\",\n  \"scene\": {\n    \"object\": [,]\n  }\n}";
    match f.read_text(text) {
        Err(IoError::MalformedJson {
            path, line, column, ..
        }) => {
            assert_eq!(path, f.path());
            assert_eq!(line, 4);
            assert_eq!(column, 16);
        }
        other => panic!("{other:?}"),
    }
    let err = f.read_text(text).unwrap_err().to_string();
    assert!(err.contains("scene_1.json:4:16: malformed JSON"), "{err}");
}

#[test]
fn nan_and_infinite_numbers_are_reported() {
    let f = Fixture::new();
    // Python's json module writes NaN; JSON has no such number.
    let text = serde_json::to_string_pretty(&valid())
        .unwrap()
        .replacen("0.5", "NaN", 1);
    match f.read_text(&text) {
        Err(IoError::MalformedJson { message, .. }) => assert!(message.contains("NaN"), "{message}"),
        other => panic!("{other:?}"),
    }
    let text = serde_json::to_string_pretty(&valid())
        .unwrap()
        .replacen("0.5", "1e999", 1);
    assert!(matches!(f.read_text(&text), Err(IoError::MalformedJson { .. })));
    // Finite numbers whose squares overflow: the transform is not usable.
    let big = with(valid(), "/scene/object/1/transform/data/0", json!(1e300));
    let big = with(big, "/scene/object/1/transform/data/1", json!(1e300));
    match f.error(&big) {
        IoError::BadTransform { pointer, reason, .. } => {
            assert_eq!(pointer, "/scene/object/1/transform/data");
            assert!(reason.contains("singular"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn wrong_format_and_missing_scene() {
    let f = Fixture::new();
    match f.error(&with(valid(), "/format", json!("other"))) {
        IoError::InvalidValue { pointer, .. } => assert_eq!(pointer, "/format"),
        other => panic!("{other:?}"),
    }
    match f.error(&without(valid(), "", "format")) {
        IoError::MissingField { pointer, field, .. } => assert_eq!((pointer.as_str(), field), ("", "format")),
        other => panic!("{other:?}"),
    }
    match f.error(&without(valid(), "", "scene")) {
        IoError::MissingField { field: "scene", .. } => {}
        other => panic!("{other:?}"),
    }
    match f.error(&json!([1, 2])) {
        IoError::WrongType {
            pointer, expected, ..
        } => assert_eq!((pointer.as_str(), expected), ("", "an object")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn missing_and_mistyped_object_fields() {
    let f = Fixture::new();
    match f.error(&without(valid(), "/scene/object/0", "modelId")) {
        IoError::MissingField { pointer, field, .. } => {
            assert_eq!((pointer.as_str(), field), ("/scene/object/0", "modelId"))
        }
        other => panic!("{other:?}"),
    }
    match f.error(&with(valid(), "/scene/object/0/index", json!("0"))) {
        IoError::WrongType {
            pointer,
            expected,
            found,
            ..
        } => {
            assert_eq!(pointer, "/scene/object/0/index");
            assert_eq!(expected, "an integer");
            assert_eq!(found, "the string \"0\"");
        }
        other => panic!("{other:?}"),
    }
    match f.error(&with(valid(), "/scene/object/0/transform/data", json!([1, 2, 3]))) {
        IoError::WrongType { pointer, found, .. } => {
            assert_eq!(pointer, "/scene/object/0/transform/data");
            assert_eq!(found, "an array of 3 elements");
        }
        other => panic!("{other:?}"),
    }
    match f.error(&with(valid(), "/scene/object/0/transform/data/12", json!("1"))) {
        IoError::WrongType { pointer, .. } => assert_eq!(pointer, "/scene/object/0/transform/data/12"),
        other => panic!("{other:?}"),
    }
    match f.error(&without(valid(), "/scene/object/0/transform", "data")) {
        IoError::MissingField {
            pointer,
            field: "data",
            ..
        } => assert_eq!(pointer, "/scene/object/0/transform"),
        other => panic!("{other:?}"),
    }
    match f.error(&with(valid(), "/scene/object/1/box/size/1", json!(-1.0))) {
        IoError::InvalidValue { pointer, .. } => assert_eq!(pointer, "/scene/object/1/box/size/1"),
        other => panic!("{other:?}"),
    }
    match f.error(&with(valid(), "/scene/object", json!({"a": 1}))) {
        IoError::WrongType { pointer, .. } => assert_eq!(pointer, "/scene/object"),
        other => panic!("{other:?}"),
    }
}

/// `v` with field `key` of the object at `pointer` set to `new` (added if missing).
fn with_field(mut v: Value, pointer: &str, key: &str, new: Value) -> Value {
    v.pointer_mut(pointer)
        .and_then(Value::as_object_mut)
        .unwrap_or_else(|| panic!("no object at {pointer}"))
        .insert(key.to_owned(), new);
    v
}

#[test]
fn stated_support_types_and_functional_sides_are_checked() {
    let f = Fixture::new();
    // `with` for a field the valid scene lacks.
    let set = |v: Value, pointer: &str, new: Value| {
        let (object, key) = pointer.rsplit_once('/').unwrap();
        with_field(v, object, key, new)
    };
    let ok = set(valid(), "/scene/object/1/supportType", json!("Wall"));
    let ok = set(ok, "/scene/object/1/functionalSides", json!(["front", "left"]));
    let scene = f.read(&ok).unwrap();
    let stated = &scene.objects()[1];
    assert_eq!(stated.support_type(), Some(sceneeval_scene::SupportType::Wall));
    assert_eq!(
        stated.functional_sides(),
        Some(&[sceneeval_geom::Side::Left, sceneeval_geom::Side::Front][..])
    );
    assert_eq!(scene.objects()[0].support_type(), None);
    match f.error(&set(valid(), "/scene/object/1/supportType", json!("shelf"))) {
        IoError::InvalidValue { pointer, reason, .. } => {
            assert_eq!(pointer, "/scene/object/1/supportType");
            assert!(
                reason.contains("expected one of ground, object, wall, ceiling"),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
    match f.error(&set(valid(), "/scene/object/1/supportType", json!(2))) {
        IoError::WrongType { pointer, .. } => assert_eq!(pointer, "/scene/object/1/supportType"),
        other => panic!("{other:?}"),
    }
    match f.error(&set(valid(), "/scene/object/1/functionalSides", json!("front"))) {
        IoError::WrongType { pointer, .. } => assert_eq!(pointer, "/scene/object/1/functionalSides"),
        other => panic!("{other:?}"),
    }
    match f.error(&set(
        valid(),
        "/scene/object/1/functionalSides",
        json!(["front", "top"]),
    )) {
        IoError::InvalidValue { pointer, reason, .. } => {
            assert_eq!(pointer, "/scene/object/1/functionalSides/1");
            assert!(reason.contains("not horizontal"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    match f.error(&set(
        valid(),
        "/scene/object/1/functionalSides",
        json!(["sideways"]),
    )) {
        IoError::InvalidValue { pointer, .. } => assert_eq!(pointer, "/scene/object/1/functionalSides/0"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn singular_sheared_and_projective_transforms() {
    let f = Fixture::new();
    let cases = [
        (
            json!([0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]),
            "singular",
        ),
        (
            json!([1, 0, 0, 0, 0.5, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
            "shear is not supported",
        ),
        (
            json!([1, 0, 0, 0.2, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
            "bottom row",
        ),
        (
            json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2]),
            "bottom row",
        ),
    ];
    for (data, expected) in cases {
        match f.error(&with(valid(), "/scene/object/0/transform/data", data)) {
            IoError::BadTransform { pointer, reason, .. } => {
                assert_eq!(pointer, "/scene/object/0/transform/data");
                assert!(reason.contains(expected), "{reason}");
            }
            other => panic!("{other:?}"),
        }
    }
}

/// The asset error wrapped for object 0, with its source.
fn asset_error(f: &Fixture, model_id: &str) -> IoError {
    match f.error(&with(valid(), "/scene/object/0/modelId", json!(model_id))) {
        IoError::ObjectAsset {
            pointer,
            model_id: m,
            source,
            ..
        } => {
            assert_eq!(pointer, "/scene/object/0");
            assert_eq!(m, model_id);
            *source
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn asset_problems_name_the_object_and_the_asset() {
    let f = Fixture::new();
    match asset_error(&f, "nosuch.bump") {
        IoError::UnknownPrefix {
            prefix, registered, ..
        } => {
            assert_eq!(prefix, "nosuch");
            assert_eq!(registered, ["fixture"]);
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(asset_error(&f, "nodot"), IoError::BadModelId { .. }));
    match f.error(&with(
        valid(),
        "/scene/object/0/modelId",
        json!("fixture.missing"),
    )) {
        IoError::MissingAssets { missing, .. } => {
            assert_eq!(missing.len(), 1);
            assert_eq!(missing[0].model_id, "fixture.missing");
            assert_eq!(missing[0].objects, ["/scene/object/0"]);
            assert_eq!(missing[0].tried[0], f.dir.path().join("missing.glb"));
            assert_eq!(missing[0].tried.len(), 3);
        }
        other => panic!("{other:?}"),
    }
    std::fs::write(f.dir.path().join("corrupt.glb"), b"glTF not really").unwrap();
    match asset_error(&f, "fixture.corrupt") {
        IoError::BadAssetFile { path, .. } => assert_eq!(path, f.dir.path().join("corrupt.glb")),
        other => panic!("{other:?}"),
    }
    std::fs::write(f.dir.path().join("empty.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    match asset_error(&f, "fixture.empty") {
        IoError::EmptyMesh { path } => assert_eq!(path, f.dir.path().join("empty.obj")),
        other => panic!("{other:?}"),
    }
    // Triangles that all have zero area.
    std::fs::write(
        f.dir.path().join("flat.obj"),
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n",
    )
    .unwrap();
    assert!(matches!(
        asset_error(&f, "fixture.flat"),
        IoError::AssetGeometry { .. }
    ));
    std::fs::write(
        f.dir.path().join("badmeta.glb"),
        std::fs::read(f.dir.path().join("bump.glb")).unwrap(),
    )
    .unwrap();
    std::fs::write(f.dir.path().join("badmeta.json"), "{\"category\": 3}").unwrap();
    match asset_error(&f, "fixture.badmeta") {
        IoError::BadMetadata { location, .. } => assert_eq!(location, "/category"),
        other => panic!("{other:?}"),
    }
    // The CLI prints the chain: the scene-level message, then the asset's.
    let err = f
        .read(&with(
            valid(),
            "/scene/object/0/modelId",
            json!("fixture.corrupt"),
        ))
        .unwrap_err();
    let source = std::error::Error::source(&err).unwrap().to_string();
    assert!(
        err.to_string().contains("/scene/object/0: cannot load asset"),
        "{err}"
    );
    assert!(source.contains("corrupt.glb"), "{source}");
}

#[test]
fn every_missing_asset_of_a_scene_is_listed_with_its_objects_and_files() {
    // 27 objects: the present bump, then 25 missing assets (the first used twice), then a box.
    let f = Fixture::new();
    let object = |model: &str, x: f64| json!({"modelId": model, "transform": {"data": [1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, x, 1, 0, 1]}});
    let mut objects = vec![object("fixture.bump", 1.0)];
    for k in 0..25 {
        objects.push(object(&format!("fixture.gone{k}"), 1.0 + 0.1 * f64::from(k)));
    }
    objects.push(object("fixture.gone0", 3.0));
    let v = with(valid(), "/scene/object", Value::Array(objects));
    let err = f.error(&v);
    let IoError::MissingAssets { missing, .. } = &err else {
        panic!("{err:?}")
    };
    assert_eq!(missing.len(), 25, "each missing asset once");
    assert_eq!(missing[0].objects, ["/scene/object/1", "/scene/object/26"]);
    assert_eq!(missing[24].model_id, "fixture.gone24");
    assert_eq!(missing[24].objects, ["/scene/object/25"]);
    let text = err.to_string();
    let lines: Vec<&str> = text.lines().collect();
    // A heading, the first 20 assets, and the count of the rest.
    assert_eq!(lines.len(), 22, "{text}");
    assert!(
        lines[0].ends_with(
            "scene_1.json: 25 assets not found, used by 26 objects (every missing asset of the scene is listed):"
        ),
        "{text}"
    );
    let dir = f.dir.path().display();
    assert_eq!(
        lines[1],
        format!(
            "  \"fixture.gone0\" for /scene/object/1 and 1 more object: looked for {dir}/gone0.glb, \
             {dir}/gone0.gltf, {dir}/gone0.obj"
        )
    );
    assert!(
        lines[20].starts_with("  \"fixture.gone19\" for /scene/object/20: looked for"),
        "{text}"
    );
    assert_eq!(lines[21], "  and 5 more assets");
    // Other errors still stop the reading at once.
    let mut objects = vec![object("fixture.gone0", 1.0), object("fixture.corrupt", 1.0)];
    std::fs::write(f.dir.path().join("corrupt.glb"), b"glTF not really").unwrap();
    objects.push(object("fixture.gone1", 1.0));
    let err = f.error(&with(valid(), "/scene/object", Value::Array(objects)));
    assert!(matches!(err, IoError::ObjectAsset { .. }), "{err:?}");
}

#[test]
fn architecture_problems_name_the_element() {
    let f = Fixture::new();
    // Zero-length wall.
    let v = with(
        valid(),
        "/scene/arch/elements/2/points",
        json!([[4, 0, 0], [4, 0, 0]]),
    );
    match f.error(&v) {
        IoError::Scene { pointer, source, .. } => {
            assert_eq!(pointer, "/scene/arch/elements/2");
            assert!(matches!(source, SceneError::ZeroLengthWall { .. }));
        }
        other => panic!("{other:?}"),
    }
    // Floor with fewer than 3 points.
    let v = with(
        valid(),
        "/scene/arch/elements/0/points",
        json!([[0, 0, 0], [4, 0, 0]]),
    );
    match f.error(&v) {
        IoError::InvalidValue { pointer, reason, .. } => {
            assert_eq!(pointer, "/scene/arch/elements/0/points");
            assert!(reason.contains("at least 3 points, got 2"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    // Self-intersecting floor.
    let v = with(
        valid(),
        "/scene/arch/elements/0/points",
        json!([[0, 0, 0], [4, 3, 0], [4, 0, 0], [0, 3, 0]]),
    );
    assert!(
        matches!(f.error(&v), IoError::InvalidValue { pointer, .. } if pointer == "/scene/arch/elements/0/points")
    );
    // Zero-height wall.
    let v = with(valid(), "/scene/arch/elements/1/height", json!(0));
    match f.error(&v) {
        IoError::Scene { pointer, source, .. } => {
            assert_eq!(pointer, "/scene/arch/elements/1");
            assert!(matches!(source, SceneError::BadWallHeight { .. }));
        }
        other => panic!("{other:?}"),
    }
    // A door entirely beyond the wall's end.
    let v = with(valid(), "/scene/arch/elements/1/holes/0/box/min", json!([5, 0]));
    let v = with(v, "/scene/arch/elements/1/holes/0/box/max", json!([6, 2]));
    match f.error(&v) {
        IoError::Scene { pointer, source, .. } => {
            assert_eq!(pointer, "/scene/arch/elements/1/holes/0");
            assert!(matches!(source, SceneError::BadOpening { .. }));
        }
        other => panic!("{other:?}"),
    }
    // A wall with three points, a wall without height, a hole without a box.
    let v = with(
        valid(),
        "/scene/arch/elements/2/points",
        json!([[4, 0, 0], [4, 3, 0], [0, 3, 0]]),
    );
    assert!(
        matches!(f.error(&v), IoError::InvalidValue { pointer, .. } if pointer == "/scene/arch/elements/2/points")
    );
    let v = without(valid(), "/scene/arch/elements/2", "height");
    assert!(matches!(
        f.error(&v),
        IoError::MissingField { field: "height", .. }
    ));
    let v = without(valid(), "/scene/arch/elements/1/holes/0", "box");
    assert!(
        matches!(f.error(&v), IoError::MissingField { pointer, field: "box", .. } if pointer == "/scene/arch/elements/1/holes/0")
    );
    // A point with two coordinates.
    let v = with(valid(), "/scene/arch/elements/0/points/2", json!([4, 3]));
    assert!(
        matches!(f.error(&v), IoError::WrongType { pointer, .. } if pointer == "/scene/arch/elements/0/points/2")
    );
    // An unknown element type.
    let v = with(valid(), "/scene/arch/elements/2/type", json!("Column"));
    assert!(
        matches!(f.error(&v), IoError::InvalidValue { pointer, .. } if pointer == "/scene/arch/elements/2/type")
    );
    // A floor without roomId.
    let v = without(valid(), "/scene/arch/elements/0", "roomId");
    assert!(matches!(
        f.error(&v),
        IoError::MissingField { field: "roomId", .. }
    ));
    // Walls but no floor at all.
    let mut v = valid();
    v.pointer_mut("/scene/arch/elements")
        .unwrap()
        .as_array_mut()
        .unwrap()
        .remove(0);
    assert!(
        matches!(f.error(&v), IoError::InvalidValue { pointer, .. } if pointer == "/scene/arch/elements/0")
    );
}

#[test]
fn duplicates_name_both_places() {
    let f = Fixture::new();
    let mut v = valid();
    let copy = v["scene"]["object"][0].clone();
    v["scene"]["object"].as_array_mut().unwrap().push(copy);
    match f.error(&v) {
        IoError::DuplicateObjectId {
            id, first, second, ..
        } => {
            assert_eq!(id, "idx0_fixture.bump");
            assert_eq!(first, "/scene/object/0");
            assert_eq!(second, "/scene/object/2");
        }
        other => panic!("{other:?}"),
    }
    let mut v = valid();
    let floor = v["scene"]["arch"]["elements"][0].clone();
    v["scene"]["arch"]["elements"].as_array_mut().unwrap().push(floor);
    match f.error(&v) {
        IoError::DuplicateElement {
            pointer, first, what, ..
        } => {
            assert_eq!(pointer, "/scene/arch/elements/3");
            assert_eq!(first, "/scene/arch/elements/0");
            assert!(what.contains("second Floor"), "{what}");
        }
        other => panic!("{other:?}"),
    }
    let v = with(valid(), "/scene/arch/elements/2/id", json!("w0"));
    assert!(
        matches!(f.error(&v), IoError::DuplicateElement { first, .. } if first == "/scene/arch/elements/1")
    );
}

#[test]
fn missing_scene_file_is_a_file_error() {
    let f = Fixture::new();
    let missing = f.dir.path().join("nope.json");
    match read_scene_state(&missing, &f.library, &ReadOptions::default()) {
        Err(IoError::File { path, .. }) => assert_eq!(path, missing),
        other => panic!("{other:?}"),
    }
}

/// Every value a mutation can put somewhere in the document.
fn replacement() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        Just(json!("x")),
        Just(json!(-1)),
        Just(json!(0)),
        Just(json!(1e308)),
        Just(json!(-1e-300)),
        Just(json!([])),
        Just(json!({})),
        Just(json!([1, 2])),
        Just(json!([[0, 0, 0], [0, 0, 0], [0, 0, 0]])),
        Just(json!(true)),
    ]
}

/// Every pointer into `v`.
fn pointers(v: &Value, base: String, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => {
            for (k, c) in m {
                let p = format!("{base}/{k}");
                out.push(p.clone());
                pointers(c, p, out);
            }
        }
        Value::Array(a) => {
            for (i, c) in a.iter().enumerate() {
                let p = format!("{base}/{i}");
                out.push(p.clone());
                pointers(c, p, out);
            }
        }
        _ => {}
    }
}

#[test]
fn no_mutation_of_a_valid_scene_panics() {
    let f = Fixture::new();
    let base = valid();
    let mut all = Vec::new();
    pointers(&base, String::new(), &mut all);
    let n = all.len();
    let mut runner = TestRunner::new(Config::with_cases(400));
    runner
        .run(&(0..n, replacement(), 0..n, replacement()), |(i, a, j, b)| {
            let mut v = base.clone();
            if let Some(slot) = v.pointer_mut(&all[i]) {
                *slot = a;
            }
            if let Some(slot) = v.pointer_mut(&all[j]) {
                *slot = b;
            }
            let text = serde_json::to_string(&v).unwrap();
            // Ok or Err, but never a panic.
            let _ = read_scene_state_str(&text, Path::new("fuzz.json"), &f.library, &ReadOptions::default());
            Ok(())
        })
        .unwrap();
}

#[test]
fn no_corruption_of_a_glb_panics() {
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    let good = std::fs::read(dir.path().join("bump.glb")).unwrap();
    let path = dir.path().join("c.glb");
    let mut runner = TestRunner::new(Config::with_cases(300));
    runner
        .run(
            &(
                proptest::collection::vec((0..good.len(), any::<u8>()), 1..6),
                0..good.len() + 1,
            ),
            |(flips, cut)| {
                let mut bytes = good.clone();
                for (i, b) in flips {
                    bytes[i] = b;
                }
                bytes.truncate(cut.max(1));
                std::fs::write(&path, &bytes).unwrap();
                let _ = sceneeval_io::mesh_load::read_mesh_file(&path);
                Ok(())
            },
        )
        .unwrap();
}

#[test]
fn repeated_openings_whole_wall_doors_and_low_ceilings() {
    let f = Fixture::new();
    // Two holes with one id in one wall: an error naming both.
    let mut v = valid();
    v.pointer_mut("/scene/arch/elements/1/holes")
        .unwrap()
        .as_array_mut()
        .unwrap()
        .extend([
            json!({"id": "d", "type": "Window", "box": {"min": [2.5, 1], "max": [3.5, 2]}}),
            json!({"id": "d", "type": "Door", "box": {"min": [0.1, 0], "max": [0.8, 2]}}),
        ]);
    match f.error(&v) {
        IoError::DuplicateElement {
            pointer, first, what, ..
        } => {
            assert_eq!(pointer, "/scene/arch/elements/1/holes/2");
            assert_eq!(first, "/scene/arch/elements/1/holes/1");
            assert!(what.contains("opening id \"d\""), "{what}");
        }
        other => panic!("{other:?}"),
    }
    // A door wider and taller than its wall: clipped to the wall, which has no solid left.
    let mut v = valid();
    v.pointer_mut("/scene/arch/elements/2")
        .unwrap()
        .as_object_mut()
        .unwrap()
        .insert(
            "holes".into(),
            json!([{"type": "Door", "box": {"min": [-1, -1], "max": [9, 9]}}]),
        );
    let scene = f.read(&v).unwrap();
    let wall = &scene.rooms()[0].walls()[1];
    assert!(wall.mesh().is_none() && wall.solid_boxes().is_empty());
    assert_eq!(wall.openings()[0].along, [0.0, 3.0]);
    assert_eq!(wall.openings()[0].height, [0.0, 2.8]);
    // A Ceiling at or below its Floor is ignored (as the reference ignores Ceilings): the
    // ceiling comes from the walls' tops.
    let mut v = valid();
    v.pointer_mut("/scene/arch/elements")
        .unwrap()
        .as_array_mut()
        .unwrap()
        .push(json!({"id": "c", "roomId": "r", "type": "Ceiling",
                     "points": [[0, 0, -0.5], [4, 0, -0.5], [4, 3, -0.5], [0, 3, -0.5]]}));
    let scene = f.read(&v).unwrap();
    let room = &scene.rooms()[0];
    assert!(room.explicit_ceiling().is_none());
    assert_eq!(room.ceiling_z(), Some(2.8));
}
