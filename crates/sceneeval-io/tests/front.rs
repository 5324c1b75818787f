//! The two sceneState fields of the generators that do not follow the model's conventions:
//! `objectFrontVector` (an object's front in its own z-up frame) turns each object so that
//! local -y is its front, and `isArchitecture: true` entries are left out before any asset
//! lookup. Both round-trip through the writer. Also: the z-up transform convention of the
//! `idesign` / `scene-agent` / `scenesmith` prefixes.

// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::Path;

use sceneeval_geom::{Point3, Side, Vector3};
use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, IoError, ReadOptions, read_scene_state_str, scene_state_to_string};
use sceneeval_scene::Scene;
use serde_json::{Value, json};

/// The upright transform Rx(+90) (asset y-up to world z-up) at `(x, y, z)`, column-major.
fn upright(x: f64, y: f64, z: f64) -> Vec<f64> {
    vec![
        1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, x, y, z, 1.0,
    ]
}

fn read(doc: &Value, library: &AssetLibrary) -> Result<Scene, IoError> {
    read_scene_state_str(
        &doc.to_string(),
        Path::new("scene_1.json"),
        library,
        &ReadOptions::default(),
    )
}

fn state(objects: Value) -> Value {
    json!({"format": "sceneState", "scene": {"arch": {"elements": []}, "object": objects}})
}

/// A library with the "front bump" asset `bump` (bump at asset +z, i.e. object -y) and the
/// same asset turned by pi about its up axis, `bump_turned` (bump at asset -z).
fn library(dir: &Path) -> AssetLibrary {
    common::write_bump_asset(dir, "bump");
    let body = common::box_mesh("body", [-0.5, 0.0, -0.2], [0.5, 0.5, 0.2]);
    let bump = common::box_mesh("bump", [-0.1, 0.1, -0.3], [0.1, 0.3, -0.2]);
    sceneeval_io::write_glb(&dir.join("bump_turned.glb"), &[body, bump]).unwrap();
    common::fixture_library(dir).with_source("idesign", PlainFolderSource::new(dir))
}

#[test]
fn a_plus_y_front_is_the_same_object_turned_by_pi() {
    let dir = tempfile::tempdir().unwrap();
    let lib = library(dir.path());
    // (a) the bump asset declared to face +y (its bump is then at its back), upright;
    // (b) the asset turned by pi about its up axis (bump at asset -z), with the default
    // front, upright and turned by pi about world z: T = Rz(pi) * Rx(+90), columns
    // (-1, 0, 0), (0, 0, 1), (0, 1, 0). The same geometry and the same front in the world.
    let turned_by_pi = [
        -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 1.0, 0.0, 1.0,
    ];
    let a = read(
        &state(json!([{"modelId": "fixture.bump", "objectFrontVector": [0, 1, 0],
                        "transform": {"data": upright(2.0, 1.0, 0.0)}}])),
        &lib,
    )
    .unwrap();
    let b = read(
        &state(json!([{"modelId": "fixture.bump_turned", "transform": {"data": turned_by_pi}}])),
        &lib,
    )
    .unwrap();
    let (a, b) = (&a.objects()[0], &b.objects()[0]);
    // The file pose is the identity rotation at (2, 1, 0); the model turns it by pi about z,
    // so the world front is +y (object -y turned by pi), the side away from the bump (world
    // -y: asset +z -> world -y under Rx(+90)).
    assert!((a.obb().side_direction(Side::Front) - Vector3::y()).norm() < 1e-15);
    assert!((b.obb().side_direction(Side::Front) - Vector3::y()).norm() < 1e-15);
    // Object frame of (a): body y in [-0.2, 0.2], bump y in [0.2, 0.3] after the turn; the OBB
    // centre (0, 0.05, 0.25) placed by Rz(pi) at (2, 1, 0) is (2, 0.95, 0.25), as for (b)
    // (to the f32 rounding of the GLB's vertices).
    for o in [a, b] {
        assert!(
            (o.obb().center - Point3::new(2.0, 0.95, 0.25)).norm() < 1e-7,
            "{}",
            o.obb().center
        );
        assert!((o.obb().half_extents - Vector3::new(0.5, 0.25, 0.25)).norm() < 1e-7);
        assert!((o.yaw().abs() - std::f64::consts::PI).abs() < 1e-15);
    }
    assert!((a.world_aabb().min - b.world_aabb().min).norm() < 1e-7);
    assert!((a.world_aabb().max - b.world_aabb().max).norm() < 1e-7);
    assert_eq!(a.asset_front(), Some(Vector3::y()));
    assert_eq!(b.asset_front(), None);
    // The scene-level field applies to every object that does not state its own.
    let c = read(
        &json!({"format": "sceneState", "scene": {"objectFrontVector": [0, 1, 0], "arch": {"elements": []},
            "object": [{"modelId": "fixture.bump", "transform": {"data": upright(2.0, 1.0, 0.0)}},
                       {"modelId": "fixture.bump", "objectFrontVector": [0, -1, 0],
                        "transform": {"data": upright(0.0, 0.0, 0.0)}}]}}),
        &lib,
    )
    .unwrap();
    assert!((c.objects()[0].obb().side_direction(Side::Front) - Vector3::y()).norm() < 1e-15);
    assert!((c.objects()[1].obb().side_direction(Side::Front) + Vector3::y()).norm() < 1e-15);
    assert_eq!(c.objects()[1].asset_front(), None);
}

#[test]
fn quarter_turns_swap_box_sizes_and_scales() {
    let dir = tempfile::tempdir().unwrap();
    let lib = library(dir.path());
    // A 1 x 0.4 x 0.5 box (file frame) whose front is +x, at the identity: the model turns
    // it by +90 deg (Rz(-90) sends +x to -y, the pose is turned back by its inverse), so its
    // world front is +x, its width (model x) is 0.4 and its depth 1.
    let identity = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 3.0, 2.0, 0.25, 1.0,
    ];
    let s = read(
        &state(json!([{"box": {"size": [1.0, 0.4, 0.5]}, "objectFrontVector": [1, 0, 0],
                        "transform": {"data": identity}},
                       {"modelId": "fixture.bump", "objectFrontVector": [-1, 0, 0],
                        "transform": {"data": [2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]}}])),
        &lib,
    )
    .unwrap();
    let o = &s.objects()[0];
    assert!((o.obb().side_direction(Side::Front) - Vector3::x()).norm() < 1e-15);
    assert_eq!(o.box_half_extents(), Some(Vector3::new(0.2, 0.5, 0.25)));
    assert!((o.obb().center - Point3::new(3.0, 2.0, 0.25)).norm() < 1e-15);
    // The bump stretched 2x along asset x = object x; declared front -x, so after the turn
    // the stretch is along model y and the recorded scale is (1, 2, 1).
    let m = &s.objects()[1];
    assert!((m.obb().side_direction(Side::Front) + Vector3::x()).norm() < 1e-15);
    assert_eq!(m.scale(), Vector3::new(1.0, 2.0, 1.0));
    assert!((m.obb().half_extents - Vector3::new(0.25, 1.0, 0.25)).norm() < 1e-7);
}

#[test]
fn fronts_round_trip_through_the_writer() {
    let dir = tempfile::tempdir().unwrap();
    let lib = library(dir.path());
    let shared = read(
        &json!({"format": "sceneState", "scene": {"objectFrontVector": [0, 1, 0], "arch": {"elements": []},
            "object": [{"modelId": "fixture.bump", "transform": {"data": upright(2.0, 1.0, 0.0)}},
                       {"box": {"size": [1.0, 0.4, 0.5]}, "transform": {"data": upright(0.0, 0.0, 0.25)}}]}}),
        &lib,
    )
    .unwrap();
    let mixed = read(
        &state(
            json!([{"modelId": "fixture.bump", "transform": {"data": upright(2.0, 1.0, 0.0)}},
                       {"modelId": "fixture.bump", "objectFrontVector": [1, 0, 0],
                        "transform": {"data": upright(1.0, 1.0, 0.0)}}]),
        ),
        &lib,
    )
    .unwrap();
    for (scene, scene_level) in [(&shared, true), (&mixed, false)] {
        let text = scene_state_to_string(scene).unwrap();
        let v: Value = serde_json::from_str(&text).unwrap();
        // One front for every object is written once, as the SceneSmith fork writes it;
        // otherwise on each object that does not face -y.
        assert_eq!(
            v["scene"].get("objectFrontVector").is_some(),
            scene_level,
            "{text}"
        );
        if !scene_level {
            assert!(v["scene"]["object"][0].get("objectFrontVector").is_none());
            assert_eq!(
                v["scene"]["object"][1]["objectFrontVector"],
                json!([1.0, 0.0, 0.0])
            );
        }
        // The transform is the file's own: the upright transform, not the turned pose.
        let data: Vec<f64> =
            serde_json::from_value(v["scene"]["object"][0]["transform"]["data"].clone()).unwrap();
        assert!(
            data.iter()
                .zip(upright(2.0, 1.0, 0.0))
                .all(|(a, b)| (a - b).abs() < 1e-15),
            "{data:?}"
        );
        let back =
            read_scene_state_str(&text, Path::new("scene_1.json"), &lib, &ReadOptions::default()).unwrap();
        assert_eq!(&back, scene);
        assert_eq!(scene_state_to_string(&back).unwrap(), text);
    }
}

#[test]
fn architecture_entries_are_left_out_before_any_asset_lookup() {
    let dir = tempfile::tempdir().unwrap();
    let lib = library(dir.path());
    // `sw.wall_0` has no registered prefix: reading it would fail, but it is architecture.
    let s = read(
        &state(json!([{"modelId": "sw.wall_0", "isArchitecture": true},
                       {"modelId": "fixture.bump", "isArchitecture": false, "transform": {"data": upright(1.0, 1.0, 0.0)}},
                       {"modelId": "sw.floor", "isArchitecture": true, "transform": {"data": "not even a matrix"}}])),
        &lib,
    )
    .unwrap();
    assert_eq!(s.objects().len(), 1);
    // The kept object's index is its position in the file's list.
    assert_eq!(s.objects()[0].id().as_str(), "idx1_fixture.bump");
    // Written back, the scene has no architecture entries and reads back the same.
    let text = scene_state_to_string(&s).unwrap();
    assert!(!text.contains("isArchitecture"));
    let back = read_scene_state_str(&text, Path::new("scene_1.json"), &lib, &ReadOptions::default()).unwrap();
    assert_eq!(back, s);
    match read(
        &state(json!([{"modelId": "fixture.bump", "isArchitecture": "yes"}])),
        &lib,
    ) {
        Err(IoError::WrongType {
            pointer, expected, ..
        }) => {
            assert_eq!(
                (pointer.as_str(), expected),
                ("/scene/object/0/isArchitecture", "a boolean")
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_fronts_name_their_pointer() {
    let dir = tempfile::tempdir().unwrap();
    let lib = library(dir.path());
    for (doc, pointer) in [
        (
            json!({"format": "sceneState", "scene": {"objectFrontVector": [0, 0, 1], "object": []}}),
            "/scene/objectFrontVector",
        ),
        (
            state(json!([{"modelId": "fixture.bump", "objectFrontVector": [0.6, 0.8, 0]}])),
            "/scene/object/0/objectFrontVector",
        ),
    ] {
        match read(&doc, &lib) {
            Err(IoError::InvalidValue {
                pointer: p, reason, ..
            }) => {
                assert_eq!(p, pointer);
                assert!(reason.contains("horizontal axis direction"), "{reason}");
            }
            other => panic!("{other:?}"),
        }
    }
    match read(
        &state(json!([{"modelId": "fixture.bump", "objectFrontVector": [0, 1]}])),
        &lib,
    ) {
        Err(IoError::WrongType { pointer, .. }) => assert_eq!(pointer, "/scene/object/0/objectFrontVector"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn z_up_prefixes_place_the_object_frame_directly() {
    let dir = tempfile::tempdir().unwrap();
    let lib = library(dir.path());
    // The identity transform on an `idesign.` asset leaves it upright (its mesh is the file
    // turned y-up to z-up), where a `fixture.` asset would lie on its back.
    let identity = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 2.0, 0.0, 1.0,
    ];
    let s = read(
        &state(
            json!([{"modelId": "idesign.bump", "transform": {"data": identity}},
                       {"modelId": "fixture.bump", "transform": {"data": identity}}]),
        ),
        &lib,
    )
    .unwrap();
    let (z_up, y_up) = (&s.objects()[0], &s.objects()[1]);
    assert!((z_up.obb().side_direction(Side::Top) - Vector3::z()).norm() < 1e-15);
    assert!((z_up.obb().side_direction(Side::Front) + Vector3::y()).norm() < 1e-15);
    assert!((y_up.obb().side_direction(Side::Top) - Vector3::y()).norm() < 1e-15);
    // Written back, the `idesign.` transform is still the identity (its own convention).
    let text = scene_state_to_string(&s).unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    let data: Vec<f64> =
        serde_json::from_value(v["scene"]["object"][0]["transform"]["data"].clone()).unwrap();
    assert_eq!(data, identity.to_vec());
}
