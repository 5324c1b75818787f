//! Bad native input (missing files, malformed JSON, NaN, unknown assets, conflicting room
//! assets) is an error naming the file and the JSON pointer, and a failed conversion leaves
//! nothing behind: no output folder, no temporary folder.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};

use common::{native, specs};
use sceneeval_convert::{ConvertError, ConvertOptions, Format, convert};
use sceneeval_io::IoError;

/// Copies the folder `from` into `to`.
fn copy_tree(from: &Path, to: &Path) {
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            std::fs::create_dir_all(&target).unwrap();
            copy_tree(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

/// A writable copy of `fixtures/native/<sub>` in a temporary folder, and an output path in
/// another one.
fn copy(sub: &str) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("input");
    std::fs::create_dir_all(&input).unwrap();
    copy_tree(&native(sub), &input);
    std::fs::create_dir_all(tmp.path().join("results")).unwrap();
    let out = tmp.path().join("results/out");
    (tmp, input, out)
}

/// Converts and expects a failure that leaves the output's parent folder empty.
fn fails(
    format: Format,
    input: &Path,
    out: &Path,
    assets: Vec<sceneeval_io::assets::AssetSpec>,
) -> ConvertError {
    let options = ConvertOptions::default().with_assets(assets);
    let err = convert(format, input, out, &options).unwrap_err();
    let left: Vec<_> = std::fs::read_dir(out.parent().unwrap()).unwrap().collect();
    assert!(left.is_empty(), "left behind: {left:?}");
    err
}

fn layoutvlm_assets() -> Vec<sceneeval_io::assets::AssetSpec> {
    specs(&[("layoutvlm-objaverse", native("layoutvlm/assets"))])
}

#[test]
fn a_missing_file_is_named() {
    let (_tmp, input, out) = copy("layoutvlm/scenes");
    let layout = input.join("scene_001/layout.json");
    std::fs::remove_file(&layout).unwrap();
    let err = fails(Format::LayoutVlm, &input, &out, layoutvlm_assets());
    match &err {
        ConvertError::Native(e) => match &**e {
            IoError::File { path, .. } => assert_eq!(path, &layout),
            other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    }
    // scene_000 converted fine before scene_001 failed: still nothing is left.
    assert!(err.to_string().contains("layout.json"), "{err}");
}

#[test]
fn malformed_json_and_nan_give_file_line_and_column() {
    let (_tmp, input, out) = copy("layoutvlm/scenes");
    let layout = input.join("scene_000/layout.json");
    std::fs::write(&layout, "{\n  \"bed-0\": {\"position\": [NaN, 1, 0]}\n}\n").unwrap();
    let err = fails(Format::LayoutVlm, &input, &out, layoutvlm_assets());
    let message = err.to_string();
    assert!(
        message.starts_with(&format!("{}:2:", layout.display())),
        "{message}"
    );
    assert!(
        message.contains("NaN and Infinity are not valid JSON numbers"),
        "{message}"
    );
    std::fs::write(&layout, "{\"bed-0\": {\"position\": [1, 2").unwrap();
    let message = fails(Format::LayoutVlm, &input, &out, layoutvlm_assets()).to_string();
    assert!(message.contains("malformed JSON"), "{message}");
    // A value of the wrong type: the pointer names it.
    std::fs::write(&layout, r#"{"bed-0": {"position": [1, "2", 0]}}"#).unwrap();
    let message = fails(Format::LayoutVlm, &input, &out, layoutvlm_assets()).to_string();
    assert!(
        message.contains("/bed-0/position/1: expected a number"),
        "{message}"
    );
}

#[test]
fn unknown_assets_are_errors() {
    // A placement of an asset scene.json does not have.
    let (_tmp, input, out) = copy("layoutvlm/scenes");
    let layout = input.join("scene_000/layout.json");
    std::fs::write(
        &layout,
        r#"{"ghost-0": {"position": [1, 1, 0.5], "rotation": [0, 0, 0]}}"#,
    )
    .unwrap();
    let message = fails(Format::LayoutVlm, &input, &out, layoutvlm_assets()).to_string();
    assert!(message.contains("/ghost-0: no asset \"ghost-0\""), "{message}");

    // A Holodeck object whose Objaverse asset is not in the Objathor folder.
    let (_tmp, input, out) = copy("holodeck/scenes");
    let house = input.join("two_rooms/two_rooms.json");
    let text = std::fs::read_to_string(&house).unwrap().replace(
        &sceneeval_fixtures::native::uid("sofa"),
        "00000000000000000000000000000000",
    );
    std::fs::write(&house, text).unwrap();
    let err = fails(
        Format::Holodeck,
        &input,
        &out,
        specs(&[("objaverse", native("holodeck/objathor"))]),
    );
    match &err {
        ConvertError::Asset {
            path,
            pointer,
            model_id,
            ..
        } => {
            assert_eq!((path, pointer.as_str()), (&house, "/objects/1"));
            assert_eq!(model_id, "objaverse.00000000000000000000000000000000");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn holodeck_and_layoutvlm_need_their_asset_folders() {
    for (format, sub, prefix) in [
        (Format::Holodeck, "holodeck/scenes", "objaverse"),
        (Format::LayoutVlm, "layoutvlm/scenes", "layoutvlm-objaverse"),
    ] {
        let (_tmp, input, out) = copy(sub);
        let err = fails(format, &input, &out, vec![]);
        match &err {
            ConvertError::AssetsNeeded { format: f, prefix: p } => assert_eq!((*f, *p), (format, prefix)),
            other => panic!("{other:?}"),
        }
        // The library says what is missing; the command line adds its flag.
        let message = err.to_string();
        assert!(message.contains(&format!("prefix {prefix:?}")), "{message}");
        assert!(!message.contains("--"), "{message}");
    }
}

/// Sets the value at `pointer` of the JSON file `path` to `value`.
fn edit(path: &Path, pointer: &str, value: &str) {
    let mut doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    *doc.pointer_mut(pointer).unwrap() = value.into();
    std::fs::write(path, doc.to_string()).unwrap();
}

#[track_caller]
fn assert_duplicate(err: &ConvertError, file: &Path, id: &str, first: &str, second: &str) {
    match err {
        ConvertError::Native(e) => match &**e {
            IoError::DuplicateObjectId {
                path,
                id: i,
                first: f,
                second: s,
            } => {
                assert_eq!(
                    (path.as_path(), i.as_str(), f.as_str(), s.as_str()),
                    (file, id, first, second)
                );
            }
            other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    }
    assert_eq!(
        err.to_string(),
        format!(
            "{}: object id {id:?} is used by both {first} and {second}",
            file.display()
        )
    );
}

#[test]
fn a_duplicated_scene_agent_object_id_is_an_error_not_a_desk_turned_bed() {
    // The issue's reproduction: the desk's entry carries the bed's id (and so its model id):
    // it converted silently, and the desk was shown with the bed's mesh.
    let (_tmp, input, out) = copy("scene-agent/scenes");
    let state = input.join("scene_000/combined_house/sceneeval_state.json");
    edit(&state, "/scene/object/1/id", "bed_0");
    edit(&state, "/scene/object/1/modelId", "scene-agent.bed_0");
    let err = fails(Format::SceneAgent, &input, &out, vec![]);
    assert_duplicate(&err, &state, "bed_0", "/scene/object/0", "/scene/object/1");

    // Two entries of one asset (the same SDF: SceneSmith lists each member of a stack under
    // its asset's id) are one asset, shown twice.
    edit(
        &state,
        "/scene/object/1/sdfPath",
        "generated_assets/furniture/sdf/bed_1717171717/bed.sdf",
    );
    let report = convert(Format::SceneAgent, &input, &out, &ConvertOptions::default()).unwrap();
    assert_eq!(report.scenes[0].objects, 3);
}

#[test]
fn duplicated_object_ids_are_errors_in_every_format() {
    // Holodeck: `floor_objects` names objects by id.
    let (_tmp, input, out) = copy("holodeck/scenes");
    let house = input.join("two_rooms/two_rooms.json");
    edit(&house, "/objects/1/id", "dining table (kitchen)");
    let err = fails(
        Format::Holodeck,
        &input,
        &out,
        specs(&[("objaverse", native("holodeck/objathor"))]),
    );
    assert_duplicate(&err, &house, "dining table (kitchen)", "/objects/0", "/objects/1");

    // IDesign: an id names the object's GLB and model id.
    let (_tmp, input, out) = copy("idesign/scenes");
    let graph = input.join("scene_000/scene_graph.json");
    edit(&graph, "/7/new_object_id", "bed_1");
    let err = fails(Format::IDesign, &input, &out, vec![]);
    assert_duplicate(&err, &graph, "bed_1", "/6", "/7");

    // LayoutVLM: objects are keyed by their ids, and a key given twice in one JSON object is
    // an error (a JSON reader would keep one of the two silently).
    let (_tmp, input, out) = copy("layoutvlm/scenes");
    let layout = input.join("scene_000/layout.json");
    let text = std::fs::read_to_string(&layout).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let (key, value) = doc.as_object().unwrap().iter().next().unwrap();
    let twice = format!("{{\"{key}\": {value},\n\"{key}\": {value}}}");
    std::fs::write(&layout, twice).unwrap();
    match fails(Format::LayoutVlm, &input, &out, layoutvlm_assets()) {
        ConvertError::Native(e) => match &*e {
            IoError::DuplicateKey {
                path,
                pointer,
                key: k,
                line,
                ..
            } => assert_eq!((path, pointer.as_str(), k, *line), (&layout, "", key, 2)),
            other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    }
}

#[test]
fn an_idesign_object_without_its_glb_is_named() {
    let (_tmp, input, out) = copy("idesign/scenes");
    std::fs::remove_file(input.join("scene_000/Assets/wardrobe_1.glb")).unwrap();
    let message = fails(Format::IDesign, &input, &out, vec![]).to_string();
    assert!(
        message.contains("wardrobe_1.glb") && message.contains("/8"),
        "{message}"
    );
}

#[test]
fn rooms_with_different_files_at_one_path_are_a_conflict() {
    let (_tmp, input, out) = copy("scene-agent/scenes");
    // The office also has a bed folder of that name, with another SDF: which one the state
    // means cannot be told (the fork would silently keep one).
    let scene = input.join("scene_000");
    let bed = "generated_assets/furniture/sdf/bed_1717171717";
    std::fs::create_dir_all(scene.join("room_office").join(bed)).unwrap();
    copy_tree(
        &scene.join("room_bedroom").join(bed),
        &scene.join("room_office").join(bed),
    );
    std::fs::write(scene.join("room_office").join(bed).join("bed.sdf"), "<sdf/>").unwrap();
    match fails(Format::SceneAgent, &input, &out, vec![]) {
        ConvertError::Conflict { target, .. } => {
            assert_eq!(target, Path::new("furniture/sdf/bed_1717171717/bed.sdf"));
        }
        other => panic!("{other:?}"),
    }
    // The same files in both rooms are no conflict.
    std::fs::copy(
        scene.join("room_bedroom").join(bed).join("bed.sdf"),
        scene.join("room_office").join(bed).join("bed.sdf"),
    )
    .unwrap();
    let report = convert(Format::SceneAgent, &input, &out, &ConvertOptions::default()).unwrap();
    assert_eq!(report.scenes[0].objects, 3);
}

#[test]
fn an_existing_output_folder_is_left_alone() {
    let (_tmp, input, out) = copy("idesign/scenes");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("scene_0.json"), "mine").unwrap();
    let err = convert(Format::IDesign, &input, &out, &ConvertOptions::default()).unwrap_err();
    assert!(matches!(err, ConvertError::OutputExists { .. }), "{err:?}");
    assert_eq!(std::fs::read_to_string(out.join("scene_0.json")).unwrap(), "mine");
    assert_eq!(std::fs::read_dir(out.parent().unwrap()).unwrap().count(), 1);
}

#[test]
fn id_maps_skip_scenes_and_report_unused_keys() {
    let (_tmp, input, out) = copy("layoutvlm/scenes");
    let options = ConvertOptions::default()
        .with_assets(layoutvlm_assets())
        .with_id_map(sceneeval_convert::IdMap::parse(r#"{"1": 56, "9": 7}"#).unwrap());
    let report = convert(Format::LayoutVlm, &input, &out, &options).unwrap();
    assert_eq!(
        report.scenes.iter().map(|s| (s.key, s.id)).collect::<Vec<_>>(),
        [(1, 56)]
    );
    assert_eq!(report.skipped.len(), 1);
    assert_eq!(
        (report.skipped[0].key, report.skipped[0].reason.as_str()),
        (0, "not in the id map")
    );
    assert_eq!(report.unused_id_map_keys, [9]);
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["scene_56.json"]);
}

#[test]
fn an_interrupted_conversion_leaves_nothing() {
    let (_tmp, input, out) = copy("idesign/scenes");
    let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    let options = ConvertOptions::default().with_interrupt(flag);
    let err = convert(Format::IDesign, &input, &out, &options).unwrap_err();
    assert!(matches!(err, ConvertError::Interrupted), "{err:?}");
    assert_eq!(std::fs::read_dir(out.parent().unwrap()).unwrap().count(), 0);
}
