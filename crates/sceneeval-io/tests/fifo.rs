//! Only regular files are opened: a named pipe (FIFO) where a scene, a mesh, a sidecar, a
//! metadata file, a glTF buffer or a material library is expected is refused with an error (or,
//! for appearance files, a warning) that names it and says what it is, and never blocks the
//! reader (opening a FIFO for reading waits for a writer forever). Unix only: the pipes are
//! made with `mkfifo`.

#![cfg(unix)]
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::error::Error;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use sceneeval_io::assets::HssdSource;
use sceneeval_io::{AssetLibrary, IoError, ReadOptions, read_scene_state};
use serde_json::json;

fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo").arg(path).status().unwrap();
    assert!(status.success(), "mkfifo {}", path.display());
}

/// Runs `f` on another thread and fails the test if it has not returned after 20 s.
fn within_20s<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(20))
        .expect("blocked: a named pipe was opened for reading")
}

/// The error and its causes, one per line.
fn chain(err: &dyn Error) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(s) = source {
        text.push('\n');
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}

/// A scene file in `dir` with one object of asset `model_id`.
fn scene_with(dir: &Path, model_id: &str) -> PathBuf {
    let path = dir.join("scene_1.json");
    let scene = json!({"format": "sceneState", "scene": {"object": [
        {"index": 0, "modelId": model_id,
         "transform": {"data": [1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 1, 1, 0, 1]}}]}});
    std::fs::write(&path, scene.to_string()).unwrap();
    path
}

/// Reads `scene` with `library` on another thread; the error's text with its causes.
fn read_error(scene: PathBuf, library: AssetLibrary) -> String {
    within_20s(move || {
        let err = read_scene_state(&scene, &library, &ReadOptions::default()).unwrap_err();
        chain(&err)
    })
}

#[test]
fn a_sidecar_that_is_a_pipe_fails_the_scene_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "chair");
    let sidecar = dir.path().join("chair.json");
    mkfifo(&sidecar);
    let text = read_error(
        scene_with(dir.path(), "fixture.chair"),
        common::fixture_library(dir.path()),
    );
    assert!(text.contains("cannot load asset \"fixture.chair\""), "{text}");
    assert!(
        text.contains(&format!(
            "{}: file: is a named pipe (FIFO), not a regular file",
            sidecar.display()
        )),
        "{text}"
    );
}

#[test]
fn a_mesh_file_that_is_a_pipe_is_not_reported_missing() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("table.glb");
    mkfifo(&mesh);
    let text = read_error(
        scene_with(dir.path(), "fixture.table"),
        common::fixture_library(dir.path()),
    );
    assert!(
        text.contains(&format!(
            "{}: is a named pipe (FIFO), not a regular file",
            mesh.display()
        )),
        "{text}"
    );
    assert!(!text.contains("not found"), "{text}");
}

#[test]
fn a_scene_file_that_is_a_pipe_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene_7.json");
    mkfifo(&scene);
    let text = read_error(scene.clone(), AssetLibrary::new());
    assert_eq!(
        text,
        format!(
            "{}: is a named pipe (FIFO), not a regular file\nis a named pipe (FIFO), not a regular file",
            scene.display()
        )
    );
}

#[test]
fn a_gltf_buffer_that_is_a_pipe_fails_the_asset() {
    let dir = tempfile::tempdir().unwrap();
    // A glTF whose external buffer is a pipe.
    let gltf = json!({"asset": {"version": "2.0"}, "buffers": [{"uri": "tri.bin", "byteLength": 42}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0});
    std::fs::write(dir.path().join("tri.gltf"), gltf.to_string()).unwrap();
    let buffer = dir.path().join("tri.bin");
    mkfifo(&buffer);
    let text = read_error(
        scene_with(dir.path(), "fixture.tri"),
        common::fixture_library(dir.path()),
    );
    assert!(
        text.contains("is a named pipe (FIFO), not a regular file"),
        "{text}"
    );
    assert!(text.contains("tri.bin"), "{text}");
}

#[test]
fn hssd_metadata_that_is_a_pipe_fails_the_asset() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("glb/a")).unwrap();
    common::write_bump_asset(&dir.path().join("glb/a"), "abc");
    let csv = dir.path().join("fpmodels.csv");
    mkfifo(&csv);
    let library = AssetLibrary::new().with_source("fpModel", HssdSource::new(dir.path()));
    let text = read_error(scene_with(dir.path(), "fpModel.abc"), library);
    assert!(
        text.contains(&format!(
            "{}: file: is a named pipe (FIFO), not a regular file",
            csv.display()
        )),
        "{text}"
    );
}

#[test]
fn a_material_library_that_is_a_pipe_leaves_the_default_material() {
    // The renderer's appearance of an OBJ whose `mtllib` names a pipe: the library is refused
    // without being opened (logged as a warning naming it), so the faces keep the default
    // grey, as for any material library that cannot be read.
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("lamp.obj"),
        "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shade\nf 1 2 3\n",
    )
    .unwrap();
    mkfifo(&dir.path().join("lamp.mtl"));
    let library = common::fixture_library(dir.path());
    let appearance = within_20s(move || library.appearance("fixture.lamp").map(|a| a.materials.len()));
    assert_eq!(appearance.unwrap(), 1, "one default material");
    // The geometry never reads material libraries.
    let library = common::fixture_library(dir.path());
    within_20s(move || library.asset("fixture.lamp").map(|_| ())).unwrap();
}

#[test]
fn io_errors_of_pipes_are_file_errors_with_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("x.glb");
    mkfifo(&fifo);
    let f = fifo.clone();
    let err = within_20s(move || sceneeval_io::uri::read_file_limited(&f, 1 << 20).unwrap_err());
    match &err {
        IoError::File { path, source } => {
            assert_eq!(path, &fifo);
            assert_eq!(source.kind(), std::io::ErrorKind::InvalidInput);
        }
        other => panic!("{other:?}"),
    }
}
