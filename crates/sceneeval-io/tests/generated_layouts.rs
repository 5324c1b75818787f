//! The `idesign` and `scene-agent` layouts: assets named `scene_<ID>__<object id>` kept next to
//! the converted scene files, as the SceneSmith fork lays them out.

// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::Path;

use sceneeval_io::assets::{AssetSpec, Layout};
use sceneeval_io::{AssetLibrary, IoError};
use serde_json::json;

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

fn sdf(uri: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<sdf version=\"1.7\">\n  <model name=\"desk\">\n    <link name=\"base\">\n\
         <!-- the collision mesh comes first and is not what is shown -->\n\
         <collision name=\"c\"><geometry><mesh><uri>desk_collision_0.obj</uri></mesh></geometry></collision>\n\
         <visual name=\"v\"><geometry><mesh><uri> {uri} </uri></mesh></geometry></visual>\n\
         </link>\n  </model>\n</sdf>\n"
    )
}

/// A converted folder: IDesign scene 3 with `bed_1`, SceneAgent scene 5 with `desk_0`.
fn converted(dir: &Path) {
    std::fs::create_dir_all(dir.join("scene_3/assets")).unwrap();
    std::fs::write(
        dir.join("scene_3/assets/bed_1.glb"),
        std::fs::read(write_box(dir, "tmp_bed", [-1.0, 0.0, -0.8], [1.0, 0.5, 0.8])).unwrap(),
    )
    .unwrap();
    write(
        &dir.join("scene_3.json"),
        &json!({"format": "sceneState", "scene": {"object": [
            {"id": "bed_1", "modelId": "idesign.scene_3__bed_1", "description": "Modern Wood twin bed"}
        ]}})
        .to_string(),
    );
    let sdf_dir = dir.join("scene_5/assets/furniture/sdf/desk_0_1700");
    std::fs::create_dir_all(&sdf_dir).unwrap();
    std::fs::rename(
        write_box(dir, "tmp_desk", [-0.6, 0.0, -0.3], [0.6, 0.75, 0.3]),
        sdf_dir.join("desk.glb"),
    )
    .unwrap();
    write(&sdf_dir.join("desk.sdf"), &sdf("desk.glb"));
    write(
        &dir.join("scene_5.json"),
        &json!({"format": "sceneState", "scene": {"object": [
            {"id": "desk_0", "modelId": "scene-agent.scene_5__desk_0", "sdfPath": "furniture/sdf/desk_0_1700/desk.sdf"},
            {"id": "lamp_0", "modelId": "scene-agent.scene_5__lamp_0"},
            {"id": "cup_0", "modelId": "scene-agent.scene_5__cup_0", "sdfPath": "furniture/sdf/cup/cup.sdf"}
        ]}})
        .to_string(),
    );
}

fn write_box(dir: &Path, name: &str, min: [f32; 3], max: [f32; 3]) -> std::path::PathBuf {
    let path = dir.join(format!("{name}.glb"));
    sceneeval_io::write_glb(&path, &[common::box_mesh(name, min, max)]).unwrap();
    path
}

fn library(dir: &Path) -> AssetLibrary {
    let specs = [
        format!("idesign={}", dir.display()),
        format!("scene-agent={}", dir.display()),
        format!("scenesmith={}", dir.display()),
    ];
    AssetLibrary::from_specs(&specs).unwrap()
}

#[test]
fn prefixes_choose_the_layouts_as_the_fork_does() {
    for (prefix, layout) in [
        ("idesign", Layout::IDesign),
        ("scene-agent", Layout::SceneAgent),
        ("scenesmith", Layout::SceneAgent),
    ] {
        assert_eq!(AssetSpec::parse(&format!("{prefix}=/d")).unwrap().layout, layout);
        assert_eq!(layout.name().parse::<Layout>().unwrap(), layout);
    }
}

#[test]
fn idesign_assets_come_from_the_scene_folder() {
    let dir = tempfile::tempdir().unwrap();
    converted(dir.path());
    let lib = library(dir.path());
    let bed = lib.asset("idesign.scene_3__bed_1").unwrap();
    assert_eq!(bed.path, dir.path().join("scene_3/assets/bed_1.glb"));
    assert_eq!(bed.info.category.as_deref(), Some("bed"));
    // The description is the scene file's, as the fork reads it.
    assert_eq!(bed.info.description.as_deref(), Some("Modern Wood twin bed"));
    // The asset's mesh is the file turned y-up to z-up: 2 x 1.6 x 0.5 m.
    let e = bed.mesh.aabb().extents();
    assert!(
        (e - sceneeval_geom::Vector3::new(2.0, 1.6, 0.5)).norm() < 1e-6,
        "{e}"
    );
    match lib.asset("idesign.scene_3__sofa_2") {
        Err(IoError::AssetNotFound { tried, .. }) => {
            assert_eq!(tried, vec![dir.path().join("scene_3/assets/sofa_2.glb")]);
        }
        other => panic!("{other:?}"),
    }
    match lib.asset("idesign.bed_1") {
        Err(IoError::BadAssetId { model_id, expected }) => {
            assert_eq!(model_id, "idesign.bed_1");
            assert!(expected.contains("scene_<ID>__<object id>"));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn scene_agent_meshes_come_from_the_sdf_visual() {
    let dir = tempfile::tempdir().unwrap();
    converted(dir.path());
    let lib = library(dir.path());
    let sdf_dir = dir.path().join("scene_5/assets/furniture/sdf/desk_0_1700");
    for model_id in ["scene-agent.scene_5__desk_0", "scenesmith.scene_5__desk_0"] {
        let desk = lib.asset(model_id).unwrap();
        // The visual's mesh, not the collision mesh listed before it.
        assert_eq!(desk.path, sdf_dir.join("desk.glb"));
        assert_eq!(desk.info.category.as_deref(), Some("desk"));
        assert_eq!(desk.info.description.as_deref(), Some("desk"));
        assert!(desk.files.contains(&sdf_dir.join("desk.sdf")));
        assert!(desk.files.contains(&dir.path().join("scene_5.json")));
    }
    // Errors name the scene file and the object entry, or the file that is missing.
    match lib.asset("scene-agent.scene_5__lamp_0") {
        Err(IoError::BadMetadata { path, location, .. }) => {
            assert_eq!(path, dir.path().join("scene_5.json"));
            assert_eq!(location, "/scene/object/1/sdfPath");
        }
        other => panic!("{other:?}"),
    }
    match lib.asset("scene-agent.scene_5__chair_9") {
        Err(IoError::BadMetadata { message, .. }) => assert!(message.contains("chair_9"), "{message}"),
        other => panic!("{other:?}"),
    }
    match lib.asset("scene-agent.scene_5__cup_0") {
        Err(IoError::AssetNotFound { tried, .. }) => {
            assert_eq!(
                tried,
                vec![dir.path().join("scene_5/assets/furniture/sdf/cup/cup.sdf")]
            );
        }
        other => panic!("{other:?}"),
    }
    match lib.asset("scene-agent.scene_6__desk_0") {
        Err(IoError::AssetNotFound { tried, .. }) => assert_eq!(tried, vec![dir.path().join("scene_6.json")]),
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_sdf_files_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    converted(dir.path());
    let sdf_path = dir
        .path()
        .join("scene_5/assets/furniture/sdf/desk_0_1700/desk.sdf");
    for (text, expect) in [
        ("<sdf><model><link>".to_owned(), "malformed XML"),
        (
            "<sdf><model><link><visual/></link></model></sdf>".to_owned(),
            "no visual mesh",
        ),
        (
            sdf("../../../../../../scene_3/assets/bed_1.glb"),
            "leaves the asset's folder",
        ),
        (sdf("package://scenesmith/desk.glb"), "only relative paths"),
    ] {
        std::fs::write(&sdf_path, &text).unwrap();
        // A fresh library: failed loads are not cached, but be explicit.
        let lib = library(dir.path());
        let err = lib.asset("scene-agent.scene_5__desk_0").unwrap_err();
        let message = err.to_string();
        assert!(message.contains("desk.sdf"), "{message}");
        assert!(message.contains(expect), "{expect}: {message}");
    }
}

#[test]
fn a_duplicated_object_id_is_an_error_naming_both_entries() {
    // The reproduction: two entries share the id `desk_0` but name different SDF
    // files; the fork's lookup (and this crate's, before) gave the second the first's mesh.
    let dir = tempfile::tempdir().unwrap();
    converted(dir.path());
    let scene_6 = dir.path().join("scene_6.json");
    write(
        &scene_6,
        &json!({"format": "sceneState", "scene": {"object": [
            {"id": "desk_0", "modelId": "scene-agent.scene_6__desk_0", "sdfPath": "furniture/sdf/desk_0_1700/desk.sdf"},
            {"id": "desk_0", "modelId": "scene-agent.scene_6__desk_0", "sdfPath": "furniture/sdf/bed_0/bed.sdf"}
        ]}})
        .to_string(),
    );
    match library(dir.path()).asset("scene-agent.scene_6__desk_0") {
        Err(IoError::BadMetadata {
            path,
            location,
            message,
        }) => {
            assert_eq!(path, scene_6);
            assert_eq!(location, "/scene/object/1");
            assert!(
                message.contains("\"desk_0\"") && message.contains("/scene/object/0"),
                "{message}"
            );
            assert!(message.contains("sdfPath"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // Entries of one asset (the same SDF and description: SceneSmith's stacks) are one asset.
    let scene_7 = dir.path().join("scene_7.json");
    let sdf_dir = dir.path().join("scene_7/assets/furniture/sdf/desk_0_1700");
    std::fs::create_dir_all(&sdf_dir).unwrap();
    for f in ["desk.sdf", "desk.glb"] {
        std::fs::copy(
            dir.path()
                .join("scene_5/assets/furniture/sdf/desk_0_1700")
                .join(f),
            sdf_dir.join(f),
        )
        .unwrap();
    }
    let entry = json!({"id": "desk_0", "modelId": "scene-agent.scene_7__desk_0", "sdfPath": "furniture/sdf/desk_0_1700/desk.sdf"});
    write(
        &scene_7,
        &json!({"format": "sceneState", "scene": {"object": [entry, entry]}}).to_string(),
    );
    let desk = library(dir.path()).asset("scene-agent.scene_7__desk_0").unwrap();
    assert_eq!(desk.path, sdf_dir.join("desk.glb"));
}
