//! Asset sources for the five folder layouts, glTF hierarchy flattening, and the per-run
//! cache.

// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::Path;
use std::sync::Arc;

use sceneeval_geom::{Point3, Side, Vector3};
use sceneeval_io::assets::{HssdSource, Layout, PlainFolderSource};
use sceneeval_io::{AssetLibrary, IoError, ReadOptions, read_scene_state_str, write_glb};

/// A unit cube (asset coordinates y in [0, 1]) with a bump toward +z, as an OBJ with two
/// groups.
const BUMP_OBJ: &str = "\
o body
v -0.5 0 -0.5
v 0.5 0 -0.5
v 0.5 1 -0.5
v -0.5 1 -0.5
v -0.5 0 0.5
v 0.5 0 0.5
v 0.5 1 0.5
v -0.5 1 0.5
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
g bump
v -0.1 0.4 0.5
v 0.1 0.4 0.5
v 0 0.6 0.8
f 9 10 11
";

fn mkdir(p: std::path::PathBuf) -> std::path::PathBuf {
    std::fs::create_dir_all(&p).unwrap();
    p
}

#[test]
fn three_d_future_layout() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(mkdir(dir.path().join("abc-1")).join("raw_model.obj"), BUMP_OBJ).unwrap();
    std::fs::write(
        dir.path().join("model_info.json"),
        r#"[{"model_id": "abc-1", "category": "Nightstand", "super-category": "Cabinet/Shelf/Desk",
             "style": "Modern", "theme": null, "material": "Wood"},
            {"model_id": "other", "category": "Bed"}]"#,
    )
    .unwrap();
    let lib = AssetLibrary::from_specs(&[format!("3dfModel={}", dir.path().display())]).unwrap();
    assert_eq!(lib.source("3dfModel").unwrap().layout(), Layout::ThreeDFuture);
    let asset = lib.asset("3dfModel.abc-1").unwrap();
    assert_eq!(asset.info.category.as_deref(), Some("Nightstand"));
    assert_eq!(
        asset.info.description.as_deref(),
        Some("Nightstand - Cabinet/Shelf/Desk, Modern, Wood")
    );
    // Both OBJ groups are loaded: 6 quads (12 triangles) and the bump triangle.
    assert_eq!(asset.mesh.triangles().len(), 13);
    // Asset +z (the bump at z = 0.8) is object -y; asset y (up) is object z.
    let aabb = asset.mesh.aabb();
    assert!(
        (aabb.min - Point3::new(-0.5, -0.8, 0.0)).norm() < 1e-6,
        "{aabb:?}"
    );
    assert!((aabb.max - Point3::new(0.5, 0.5, 1.0)).norm() < 1e-6, "{aabb:?}");
}

#[test]
fn objathor_and_layoutvlm_layouts() {
    let dir = tempfile::tempdir().unwrap();
    let objathor = mkdir(dir.path().join("objathor"));
    common::write_bump_asset(&mkdir(objathor.join("a1")), "a1");
    std::fs::write(
        objathor.join("annotations.json"),
        r#"{"a1": {"category": "sofa", "ref_category": "Sofa", "description": "", "description_auto": "a grey sofa"}}"#,
    )
    .unwrap();
    let vlm = mkdir(dir.path().join("vlm"));
    let item = mkdir(vlm.join("b2"));
    common::write_bump_asset(&item, "b2");
    std::fs::write(
        item.join("data.json"),
        r#"{"annotations": {"category": "chair", "description": "an office chair", "materials": "mesh, steel"}}"#,
    )
    .unwrap();
    let lib = AssetLibrary::from_specs(&[
        format!("objaverse={}", objathor.display()),
        format!("layoutvlm-objaverse={}", vlm.display()),
    ])
    .unwrap();
    let a = lib.asset("objaverse.a1").unwrap();
    assert_eq!(a.info.category.as_deref(), Some("sofa"));
    assert_eq!(a.info.description.as_deref(), Some("sofa - Sofa, a grey sofa"));
    let b = lib.asset("layoutvlm-objaverse.b2").unwrap();
    assert_eq!(b.info.category.as_deref(), Some("chair"));
    assert_eq!(
        b.info.description.as_deref(),
        Some("chair, an office chair, mesh, steel")
    );
    assert_eq!(b.path, item.join("b2.glb"));
    // A malformed data.json is an error naming the file.
    std::fs::write(item.join("data.json"), "{\"annotations\": 3}").unwrap();
    let fresh = AssetLibrary::from_specs(&[format!("layoutvlm-objaverse={}", vlm.display())]).unwrap();
    match fresh.asset("layoutvlm-objaverse.b2") {
        Err(IoError::BadMetadata { path, .. }) => assert_eq!(path, item.join("data.json")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn hssd_layout_aligns_declared_axes() {
    let dir = tempfile::tempdir().unwrap();
    // Stored z-up with its front toward -y (the bump at y in [-0.3, -0.2]): the metadata says
    // so, and after alignment the object frame sees the bump in front (-y) and z up.
    let body = common::box_mesh("body", [-0.5, -0.2, 0.0], [0.5, 0.2, 0.5]);
    let bump = common::box_mesh("bump", [-0.1, -0.3, 0.1], [0.1, -0.2, 0.3]);
    write_glb(
        &mkdir(dir.path().join("glb/f")).join("f00d.glb"),
        &[body.clone(), bump.clone()],
    )
    .unwrap();
    write_glb(
        &mkdir(dir.path().join("decomposed/f00d")).join("f00d_part_1.glb"),
        &[body],
    )
    .unwrap();
    std::fs::write(
        dir.path().join("fpmodels.csv"),
        "id,name,up,front,wnsynsetkey\n\
         f00d,Tall dresser,\"0,0,1\",\"0,-1,0\",dresser.n.01\n\
         f00d_part_1,,,,\n\
         bad,x,\"0,0\",\"1,0,0\",\n",
    )
    .unwrap();
    std::fs::create_dir_all(dir.path().join("glb/b")).unwrap();
    std::fs::copy(
        dir.path().join("glb/f/f00d.glb"),
        dir.path().join("glb/b/bad.glb"),
    )
    .unwrap();
    let lib = AssetLibrary::new().with_source("fpModel", HssdSource::new(dir.path()));
    let a = lib.asset("fpModel.f00d").unwrap();
    assert_eq!(a.info.category.as_deref(), Some("dresser.n.01"));
    assert_eq!(a.info.description.as_deref(), Some("dresser.n.01 - Tall dresser"));
    let aabb = a.mesh.aabb();
    assert!(
        (aabb.min - Point3::new(-0.5, -0.3, 0.0)).norm() < 1e-6,
        "{aabb:?}"
    );
    assert!((aabb.max - Point3::new(0.5, 0.2, 0.5)).norm() < 1e-6, "{aabb:?}");
    let part = lib.asset("fpModel.f00d_part_1").unwrap();
    assert_eq!(part.path, dir.path().join("decomposed/f00d/f00d_part_1.glb"));
    assert_eq!(part.info.description.as_deref(), Some("generic object category"));
    match lib.asset("fpModel.bad") {
        Err(IoError::BadMetadata { location, .. }) => assert_eq!(location, "row 4, column 3"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn plain_folder_reads_gltf_hierarchy_and_sidecars() {
    let dir = tempfile::tempdir().unwrap();
    // Three vertices (0,0,0), (1,0,0), (0,1,0) in an external buffer.
    let bytes: Vec<u8> = [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(dir.path().join("tri.bin"), bytes).unwrap();
    let gltf = r#"{
      "asset": {"version": "2.0"},
      "buffers": [{"uri": "tri.bin", "byteLength": 36}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "meshes": [
        {"primitives": [{"attributes": {"POSITION": 0}}]},
        {"primitives": [{"attributes": {"POSITION": 0}, "mode": 5}]},
        {"primitives": [{"attributes": {"POSITION": 0}, "mode": 1}]}
      ],
      "nodes": [
        {"mesh": 0, "translation": [1, 0, 0], "children": [1]},
        {"mesh": 0, "translation": [0, 0, 3], "scale": [2, 2, 2]},
        {"mesh": 1, "rotation": [0, 0.7071067811865476, 0, 0.7071067811865476]},
        {"mesh": 0, "translation": [100, 0, 0]},
        {"mesh": 2}
      ],
      "scenes": [{"nodes": [0, 2, 4]}, {"nodes": [3]}],
      "scene": 0
    }"#;
    std::fs::write(dir.path().join("h.gltf"), gltf).unwrap();
    let raw = sceneeval_io::mesh_load::read_mesh_file(&dir.path().join("h.gltf")).unwrap();
    // Node 0: p + (1,0,0). Node 1 (child): 2p + (1,0,3). Node 2: Ry(90) p = (z, y, -x), a
    // strip of three vertices = one triangle. Node 3 is in another scene; node 4 is lines.
    let expected = [
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 3.0],
        [3.0, 0.0, 3.0],
        [1.0, 2.0, 3.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
        [0.0, 1.0, 0.0],
    ];
    assert_eq!(raw.positions.len(), 9);
    for (p, e) in raw.positions.iter().zip(expected) {
        assert!((p - Point3::from(e)).norm() < 1e-6, "{p} vs {e:?}");
    }
    assert_eq!(raw.triangles, vec![[0, 1, 2], [3, 4, 5], [6, 7, 8]]);

    // Through the plain-folder source: .gltf found after .glb, sidecar read.
    std::fs::write(dir.path().join("h.json"), r#"{"category": "thing"}"#).unwrap();
    let lib = AssetLibrary::new().with_source("p", PlainFolderSource::new(dir.path()));
    let a = lib.asset("p.h").unwrap();
    assert_eq!(a.info.category.as_deref(), Some("thing"));
    assert_eq!(a.info.description, None);
    assert_eq!(a.mesh.triangles().len(), 3);
}

#[test]
fn specs_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().display();
    assert!(matches!(
        AssetLibrary::from_specs(&[format!("x={d}/missing")]),
        Err(IoError::BadAssetSpec { .. })
    ));
    match AssetLibrary::from_specs(&[format!("x={d}"), format!("x=hssd:{d}")]) {
        Err(IoError::BadAssetSpec { reason, .. }) => {
            assert!(reason.contains("already registered"), "{reason}")
        }
        other => panic!("{other:?}"),
    }
    let lib = AssetLibrary::from_specs(&[format!("x=hssd:{d}"), format!("y={d}")]).unwrap();
    assert_eq!(lib.prefixes().collect::<Vec<_>>(), ["x", "y"]);
    assert_eq!(lib.source("x").unwrap().layout(), Layout::Hssd);
    assert_eq!(lib.source("y").unwrap().layout(), Layout::Plain);
}

#[test]
fn assets_load_once_and_are_shared_across_threads() {
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    common::write_box_asset(
        dir.path(),
        "cube",
        [-0.5, 0.0, -0.5],
        [0.5, 1.0, 0.5],
        "box",
        "a cube",
    );
    let library = common::fixture_library(dir.path());
    let text = r#"{"format": "sceneState", "scene": {"arch": {"elements": []}, "object": [
        {"index": 0, "modelId": "fixture.bump", "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}},
        {"index": 1, "modelId": "fixture.bump", "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 5,0,0,1]}},
        {"index": 2, "modelId": "fixture.bump", "transform": {"data": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,5,0,1]}},
        {"index": 3, "modelId": "fixture.bump", "transform": {"data": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,9,0,1]}},
        {"index": 4, "modelId": "fixture.cube", "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}}]}}"#;
    let scenes: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|i| {
                let library = &library;
                s.spawn(move || {
                    let path = format!("scene_{i}.json");
                    read_scene_state_str(text, Path::new(&path), library, &ReadOptions::default()).unwrap()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    // Two distinct assets, each read once for all four scenes.
    assert_eq!(library.files_read(), 2);
    let objs = scenes[0].objects();
    assert!(
        Arc::ptr_eq(objs[0].mesh(), objs[1].mesh()),
        "same asset, same scale"
    );
    assert!(
        Arc::ptr_eq(objs[2].mesh(), objs[3].mesh()),
        "same asset, same scale 2"
    );
    assert!(!Arc::ptr_eq(objs[0].mesh(), objs[2].mesh()), "different scales");
    assert!(
        Arc::ptr_eq(objs[2].mesh(), scenes[3].objects()[2].mesh()),
        "shared across scenes"
    );
    assert_eq!(objs[4].category(), Some("box"));
    assert_eq!(objs[4].description(), Some("a cube"));
    // Scale 2 doubles the object-frame extents: (1, 0.5, 0.5) -> (2, 1, 1) half extents.
    assert!((objs[2].obb().half_extents - objs[0].obb().half_extents * 2.0).norm() < 1e-12);
    // T = identity leaves the asset y-up: its front (+z) points to world +z.
    assert!((objs[0].obb().side_direction(Side::Front) - Vector3::z()).norm() < 1e-12);
}

#[test]
fn objects_built_in_code_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    let library = common::fixture_library(dir.path());
    let mut bad = sceneeval_geom::Isometry3::identity();
    bad.translation.vector.x = f64::NAN;
    match library.object("x", "fixture.bump", bad, Vector3::repeat(1.0)) {
        Err(IoError::BadObject { object, .. }) => assert_eq!(object, "x"),
        other => panic!("{other:?}"),
    }
    // Zero or non-finite scales are refused before any mesh is made.
    for s in [Vector3::new(1.0, 0.0, 1.0), Vector3::new(1.0, f64::INFINITY, 1.0)] {
        match library.mesh("fixture.bump", &s) {
            Err(IoError::BadScale { model_id, .. }) => assert_eq!(model_id, "fixture.bump"),
            other => panic!("{other:?}"),
        }
    }
}
