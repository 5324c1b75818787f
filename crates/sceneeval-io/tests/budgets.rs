//! Resource budgets and the files an asset is built from: oversized meshes fail their scene
//! with a clear error before anything big is allocated, and every file read is reported.

#![allow(clippy::unwrap_used)]

mod common;

use std::path::Path;

use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::mesh_load::read_mesh_file_with;
use sceneeval_io::{AssetLibrary, GlbMesh, IoError, Limits, ReadOptions, read_scene_state, write_glb};

/// `n` coincident copies of one triangle over 3 vertices: the shape of the 4.7 MB GLB that
/// asked for gigabytes.
fn coincident(n: usize) -> GlbMesh {
    let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    let indices = (0..n).flat_map(|_| [0u32, 1, 2]).collect();
    GlbMesh::new("coincident", positions, indices)
}

/// A scene with one object showing `fixture.<id>` inside a 4 x 4 m room.
fn scene_with(dir: &Path, id: &str) -> std::path::PathBuf {
    let text = format!(
        r#"{{"format":"sceneState","scene":{{"arch":{{"elements":[
        {{"id":"f","roomId":"r","type":"Floor","points":[[0,0,0],[4,0,0],[4,4,0],[0,4,0]]}}]}},
        "object":[{{"index":0,"modelId":"fixture.{id}",
        "transform":{{"data":[1,0,0,0,0,1,0,0,0,0,1,0,2,2,0,1]}}}}]}}}}"#
    );
    let path = dir.join("scene_0.json");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_mesh_over_the_triangle_budget_fails_its_scene_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    write_glb(&dir.path().join("many.glb"), &[coincident(20_000)]).unwrap();
    let scene = scene_with(dir.path(), "many");
    let limits = Limits {
        max_triangles: 10_000,
        ..Limits::default()
    };
    let library = AssetLibrary::new()
        .with_source("fixture", PlainFolderSource::new(dir.path()))
        .with_limits(limits);
    let err = read_scene_state(&scene, &library, &ReadOptions::default()).unwrap_err();
    // The scene error names the scene file and the object; its cause names the asset and the
    // budget.
    let IoError::ObjectAsset { source, .. } = &err else {
        panic!("{err}")
    };
    assert!(
        matches!(
            **source,
            IoError::TooManyTriangles {
                triangles: 20_000,
                limit: 10_000,
                ..
            }
        ),
        "{source}"
    );
    let text = source.to_string();
    assert!(
        text.contains("many.glb") && text.contains("20000 triangles") && text.contains("10000"),
        "{text}"
    );
    assert_eq!(library.files_read(), 0, "nothing was decoded");

    // The same asset within the default budget loads.
    let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(dir.path()));
    assert!(read_scene_state(&scene, &library, &ReadOptions::default()).is_ok());
}

#[test]
fn the_memory_budget_uses_the_declared_sizes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("many.glb");
    write_glb(&path, &[coincident(1000)]).unwrap();
    // 1000 triangles x 350 + 3 vertices x 100 = 350,300 bytes.
    let tight = Limits {
        max_asset_memory_bytes: 350_299,
        ..Limits::default()
    };
    let err = read_mesh_file_with(&path, &tight).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::OverMemoryBudget {
                estimate: 350_300,
                limit: 350_299,
                ..
            }
        ),
        "{err}"
    );
    let enough = Limits {
        max_asset_memory_bytes: 350_300,
        ..Limits::default()
    };
    assert_eq!(read_mesh_file_with(&path, &enough).unwrap().triangles.len(), 1000);
}

/// The 36 bytes of one triangle's positions.
fn triangle_bytes() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// A `.gltf` with one triangle mesh in a `data:` buffer, placed by `nodes` nodes.
fn instanced_gltf(nodes: usize) -> String {
    use base64::Engine;
    let data = base64::engine::general_purpose::STANDARD.encode(triangle_bytes());
    gltf_text(nodes, &format!("data:application/octet-stream;base64,{data}"))
}

/// A `.gltf` with one triangle mesh whose buffer is `uri`, placed by `nodes` nodes.
fn gltf_text(nodes: usize, uri: &str) -> String {
    let node_list: Vec<String> = (0..nodes).map(|_| r#"{"mesh":0}"#.to_owned()).collect();
    let roots: Vec<String> = (0..nodes).map(|i| i.to_string()).collect();
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{{"byteLength":36,"uri":"{uri}"}}]}}"#,
        roots.join(","),
        node_list.join(",")
    )
}

#[test]
fn every_instance_of_a_mesh_counts_against_the_budget() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("inst.gltf");
    std::fs::write(&path, instanced_gltf(5000)).unwrap();
    let limits = Limits {
        max_triangles: 1000,
        ..Limits::default()
    };
    let err = read_mesh_file_with(&path, &limits).unwrap_err();
    // Reported at the first instance over the budget: the 1001st.
    assert!(
        matches!(
            err,
            IoError::TooManyTriangles {
                triangles: 1001,
                limit: 1000,
                ..
            }
        ),
        "{err}"
    );
    assert_eq!(
        read_mesh_file_with(&path, &Limits::default())
            .unwrap()
            .triangles
            .len(),
        5000
    );
}

#[test]
fn a_node_with_two_parents_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dag.gltf");
    // Nodes 0 and 1 both list node 2 as a child.
    let text = instanced_gltf(1).replace(
        r#""nodes":[{"mesh":0}]"#,
        r#""nodes":[{"children":[2]},{"children":[2]},{"mesh":0}]"#,
    );
    let text = text.replace(r#""scenes":[{"nodes":[0]}]"#, r#""scenes":[{"nodes":[0,1]}]"#);
    std::fs::write(&path, text).unwrap();
    let err = read_mesh_file_with(&path, &Limits::default()).unwrap_err();
    assert!(
        err.to_string()
            .contains("node 2 is a child of both node 0 and node 1"),
        "{err}"
    );
}

#[test]
fn obj_lines_and_points_are_not_faces() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lines.obj");
    // A polyline through three points would become a triangle if read as a face.
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\nl 1 2\np 1 2 3\n").unwrap();
    let err = read_mesh_file_with(&path, &Limits::default()).unwrap_err();
    assert!(matches!(err, IoError::EmptyMesh { .. }), "{err}");
    assert!(err.to_string().contains("holds no triangles"), "{err}");

    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nl 1 2 3\nf 1 2 4 3\n").unwrap();
    let m = read_mesh_file_with(&path, &Limits::default()).unwrap();
    assert_eq!(m.triangles.len(), 2, "the quad only");

    // A pentagon counts 3 triangles against the budget.
    std::fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 2 0\nv 0 1 0\nf 1 2 3 4 5\n",
    )
    .unwrap();
    let limits = Limits {
        max_triangles: 2,
        ..Limits::default()
    };
    let err = read_mesh_file_with(&path, &limits).unwrap_err();
    assert!(
        matches!(err, IoError::TooManyTriangles { triangles: 3, .. }),
        "{err}"
    );
}

#[test]
fn oversized_files_are_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.glb");
    write_glb(&path, &[coincident(100)]).unwrap();
    let size = std::fs::metadata(&path).unwrap().len();
    let limits = Limits {
        max_file_bytes: size - 1,
        ..Limits::default()
    };
    let err = read_mesh_file_with(&path, &limits).unwrap_err();
    assert!(matches!(err, IoError::TooLarge { .. }), "{err}");

    let scene = scene_with(dir.path(), "big");
    let scene_size = std::fs::metadata(&scene).unwrap().len();
    let library = AssetLibrary::new().with_limits(Limits {
        max_file_bytes: scene_size - 1,
        ..Limits::default()
    });
    let err = read_scene_state(&scene, &library, &ReadOptions::default()).unwrap_err();
    assert!(
        matches!(err, IoError::TooLarge { .. }) && err.to_string().contains("scene_0.json"),
        "{err}"
    );
}

#[test]
fn invalid_utf8_in_a_scene_names_offset_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene_1.json");
    // `{\n` is 2 bytes, `  "format": "x",\n` 17, then `  "sc` 5: offset 24, line 3, column 6.
    let mut bytes = b"{\n  \"format\": \"x\",\n  \"sc".to_vec();
    bytes.extend([0xff, 0xfe]);
    bytes.extend(b"ene\": {}\n}\n");
    std::fs::write(&path, &bytes).unwrap();
    let err = read_scene_state(&path, &AssetLibrary::new(), &ReadOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::InvalidUtf8 {
                offset: 24,
                line: 3,
                column: 6,
                ..
            }
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.contains("scene_1.json:3:6") && text.contains("byte offset 24"),
        "{text}"
    );
}

#[test]
fn assets_list_every_file_they_were_built_from() {
    let dir = tempfile::tempdir().unwrap();
    // A .gltf with an external buffer, and a sidecar.
    std::fs::write(dir.path().join("tri.bin"), triangle_bytes()).unwrap();
    std::fs::write(dir.path().join("tri.gltf"), gltf_text(1, "tri.bin")).unwrap();
    std::fs::write(dir.path().join("tri.json"), r#"{"category": "thing"}"#).unwrap();
    let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(dir.path()));
    let location = library.locate("fixture.tri").unwrap();
    assert_eq!(location.path, dir.path().join("tri.gltf"));
    assert_eq!(location.metadata, vec![dir.path().join("tri.json")]);
    assert!(library.loaded("fixture.tri").is_none(), "locate loads nothing");
    let asset = library.asset("fixture.tri").unwrap();
    assert_eq!(
        asset.files,
        vec![
            dir.path().join("tri.gltf"),
            dir.path().join("tri.bin"),
            dir.path().join("tri.json")
        ]
    );
    assert!(library.loaded("fixture.tri").is_some());
    assert_eq!(asset.info.category.as_deref(), Some("thing"));
}
