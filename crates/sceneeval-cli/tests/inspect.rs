//! `sceneeval inspect` on a generated scene, with and without `--json`, and on bad files.

// Set-up helpers outside `#[test]` functions may stop the test on failure.
#![allow(clippy::unwrap_used)]

use std::path::Path;

use assert_cmd::Command;
use predicates::prelude::*;
use sceneeval::geom::conventions::pose_from_yaw;
use sceneeval::geom::{Isometry3, Point2, Point3, Side, Vector3};
use sceneeval::io::assets::PlainFolderSource;
use sceneeval::io::{AssetLibrary, GlbMesh, write_glb, write_scene_state};
use sceneeval::scene::{Category, RoomBuilder, Scene, SupportType};

/// A 1 x 0.5 x 0.8 m (width x depth x height) block asset, y up, front +z, origin at the
/// bottom centre, with a sidecar category.
fn write_asset(dir: &Path) {
    let (mut positions, mut indices) = (Vec::new(), Vec::new());
    sceneeval_test_support::push_cuboid(&mut positions, &mut indices, [-0.5, 0.0, -0.25], [0.5, 0.8, 0.25]);
    write_glb(
        &dir.join("dresser.glb"),
        &[GlbMesh::new("dresser", positions, indices)],
    )
    .unwrap();
    std::fs::write(
        dir.join("dresser.json"),
        r#"{"category": "dresser", "description": "a dresser"}"#,
    )
    .unwrap();
}

/// Writes `scene_0.json` (a 4 x 3 m room with a door and a window, a dresser asset turned
/// 90 degrees and a box table) and returns the asset folder spec.
fn write_scene(dir: &Path) -> String {
    let assets = dir.join("assets");
    std::fs::create_dir_all(&assets).unwrap();
    write_asset(&assets);
    let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(&assets));
    let pose = Isometry3::new(
        Vector3::new(0.25, 1.5, 0.0),
        Vector3::z() * std::f64::consts::FRAC_PI_2,
    );
    let dresser = library
        .object(
            "idx0_fixture.dresser",
            "fixture.dresser",
            pose,
            Vector3::repeat(1.0),
        )
        .unwrap()
        .with_index(0)
        .with_support_type(SupportType::Ground)
        .with_functional_sides([Side::Front]);
    let scene = Scene::builder()
        .room_builder(
            RoomBuilder::rectangle("bedroom", Point2::new(0.0, 0.0), Point2::new(4.0, 3.0))
                .kind("bedroom")
                .door(0, [1.0, 1.9], [0.0, 2.1])
                .window(2, [1.0, 2.5], [0.9, 2.0]),
        )
        .object(dresser)
        .add_box(
            "table",
            Category::new("table"),
            Vector3::new(0.6, 0.4, 0.375),
            pose_from_yaw(Point3::new(2.0, 1.5, 0.375), 0.0),
        )
        .build()
        .unwrap();
    write_scene_state(&scene, &dir.join("scene_0.json")).unwrap();
    format!("fixture={}", assets.display())
}

fn sceneeval() -> Command {
    Command::cargo_bin("sceneeval").unwrap()
}

#[test]
fn prints_tables_for_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write_scene(dir.path());
    sceneeval()
        .arg("inspect")
        .arg(dir.path().join("scene_0.json"))
        .args(["--assets", &spec])
        .assert()
        .success()
        .stdout(predicate::str::contains("scene scene_0"))
        .stdout(predicate::str::contains("2 objects, 1 room, 4 walls, 2 openings"))
        .stdout(predicate::str::contains("idx0_fixture.dresser"))
        .stdout(predicate::str::contains("dresser"))
        .stdout(predicate::str::contains("(box)"))
        .stdout(predicate::str::contains("1.000 x 0.500 x 0.800"))
        .stdout(predicate::str::contains("90.0"))
        .stdout(predicate::str::contains("bedroom_wall_0_door_0"))
        .stdout(predicate::str::contains("window"));
}

#[test]
fn json_output_has_objects_rooms_walls_and_openings() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write_scene(dir.path());
    let out = sceneeval()
        .args(["inspect", "--json", "--assets", &spec])
        .arg(dir.path().join("scene_0.json"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // `--json` is the old spelling of `--format json`: the same document.
    let format = sceneeval()
        .args(["inspect", "--format", "json", "--assets", &spec])
        .arg(dir.path().join("scene_0.json"))
        .output()
        .unwrap();
    assert_eq!(format.stdout, out.stdout);
    sceneeval()
        .args(["inspect", "--format", "text", "--json", "--assets", &spec])
        .arg(dir.path().join("scene_0.json"))
        .assert()
        .failure()
        .stderr(predicate::str::contains("--format"));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["scene"], "scene_0");
    let dresser = &v["objects"][0];
    assert_eq!(dresser["id"], "idx0_fixture.dresser");
    assert_eq!(dresser["model_id"], "fixture.dresser");
    assert_eq!(dresser["category"], "dresser");
    assert_eq!(dresser["is_box"], false);
    // Asset bounds in the object frame: x [-0.5, 0.5], y [-0.25, 0.25], z [0, 0.8]; turned
    // 90 degrees about z at (0.25, 1.5, 0): centre (0.25, 1.5, 0.4), front facing +x.
    let f = |x: &serde_json::Value| x.as_f64().unwrap();
    let c: Vec<f64> = dresser["center"].as_array().unwrap().iter().map(f).collect();
    assert!(
        (c[0] - 0.25).abs() < 1e-6 && (c[1] - 1.5).abs() < 1e-6 && (c[2] - 0.4).abs() < 1e-6,
        "{c:?}"
    );
    let s: Vec<f64> = dresser["size"].as_array().unwrap().iter().map(f).collect();
    assert!(
        (s[0] - 1.0).abs() < 1e-6 && (s[1] - 0.5).abs() < 1e-6 && (s[2] - 0.8).abs() < 1e-6,
        "{s:?}"
    );
    assert!((f(&dresser["yaw"]) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert_eq!(dresser["support_type"], "ground");
    assert_eq!(dresser["functional_sides"], serde_json::json!(["front"]));
    let table = &v["objects"][1];
    assert_eq!(
        (table["id"].as_str(), table["is_box"].as_bool()),
        (Some("table"), Some(true))
    );
    assert!(table["support_type"].is_null() && table["functional_sides"].is_null());

    let room = &v["rooms"][0];
    assert_eq!(room["id"], "bedroom");
    assert_eq!(room["kind"], "bedroom");
    assert_eq!(f(&room["floor_area"]), 12.0);
    assert_eq!(room["walls"].as_array().unwrap().len(), 4);
    let door = &room["walls"][0]["openings"][0];
    assert_eq!(door["kind"], "door");
    assert_eq!(door["along"], serde_json::json!([1.0, 1.9]));
    assert_eq!(room["walls"][0]["inward_normal"], serde_json::json!([0.0, 1.0]));
    assert_eq!(room["walls"][2]["openings"][0]["kind"], "window");
}

#[test]
fn a_scene_that_fails_to_load_prints_the_error_chain() {
    let dir = tempfile::tempdir().unwrap();
    write_scene(dir.path());
    // No --assets: the dresser's prefix is unknown.
    sceneeval()
        .arg("inspect")
        .arg(dir.path().join("scene_0.json"))
        .assert()
        .failure()
        .stderr(predicate::str::contains("error: cannot load scene"))
        .stderr(predicate::str::contains("caused by:"))
        .stderr(predicate::str::contains(
            "/scene/object/0: cannot load asset \"fixture.dresser\"",
        ))
        .stderr(predicate::str::contains("no asset source for prefix \"fixture\""))
        .stderr(predicate::str::contains(
            "hint: the scene names assets with the prefix \"fixture\": pass --assets fixture=DIR",
        ));
    // A missing asset file names the paths tried.
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    sceneeval()
        .arg("inspect")
        .arg(dir.path().join("scene_0.json"))
        .args(["--assets", &format!("fixture={}", empty.display())])
        .assert()
        .failure()
        .stderr(predicate::str::contains("dresser.glb"));
    // Malformed JSON gives the line and column.
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, "{\n  \"format\": \"sceneState\",\n  \"scene\": {,}\n}\n").unwrap();
    sceneeval()
        .arg("inspect")
        .arg(&bad)
        .assert()
        .failure()
        .stderr(predicate::str::contains("bad.json:3:13: malformed JSON"));
    // A bad --assets specification.
    sceneeval()
        .arg("inspect")
        .arg(&bad)
        .args(["--assets", "nonsense"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("PREFIX=DIR"));
}
