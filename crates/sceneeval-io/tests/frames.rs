//! The asset-to-object frame conversion, checked with an asset whose front (+z in the file)
//! carries a bump, against hand-computed OBBs.

// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use sceneeval_geom::{Point3, Side, Vector3};
use sceneeval_io::{ReadOptions, read_scene_state_str};

fn scene_json(model: &str, data: &[f64; 16]) -> String {
    format!(
        r#"{{"format": "sceneState", "scene": {{"arch": {{"elements": []}},
           "object": [{{"index": 0, "modelId": "{model}", "transform": {{"data": {data:?}}}}}]}}}}"#
    )
}

fn load(data: &[f64; 16]) -> sceneeval_scene::SceneObject {
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    let library = common::fixture_library(dir.path());
    let text = scene_json("fixture.bump", data);
    let scene = read_scene_state_str(
        &text,
        &dir.path().join("s.json"),
        &library,
        &ReadOptions::default(),
    )
    .unwrap();
    scene.objects()[0].clone()
}

#[test]
fn front_plus_z_in_the_file_is_minus_y_in_the_scene() {
    // T = Rx(+90 deg): the standard y-up -> z-up transform, no yaw. Column-major columns:
    // asset x -> (1, 0, 0), asset y (up) -> (0, 0, 1), asset z (front) -> (0, -1, 0).
    let data = [
        1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let obj = load(&data);
    let obb = obj.obb();
    assert!((obb.side_direction(Side::Front) - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-12);
    assert!((obb.side_direction(Side::Top) - Vector3::z()).norm() < 1e-12);
    // Object-frame bounds (x, -z, y of the asset): x [-0.5, 0.5], y [-0.3, 0.2], z [0, 0.5].
    // Centre (0, -0.05, 0.25), half extents (0.5, 0.25, 0.25).
    assert!(
        (obb.center - Point3::new(0.0, -0.05, 0.25)).norm() < 1e-7,
        "{}",
        obb.center
    );
    assert!((obb.half_extents - Vector3::new(0.5, 0.25, 0.25)).norm() < 1e-7);
    // The bump is on the front face: the mesh's lowest y is the bump's -0.3.
    assert!((obj.mesh().aabb().min.y + 0.3).abs() < 1e-7);
    assert!((obj.yaw()).abs() < 1e-12);
}

#[test]
fn turned_and_scaled_asset_has_the_hand_computed_obb() {
    // T = Rz(90) * Rx(90) * diag(2, 1.5, 1) + (3, 4, 0.1). Columns, by hand:
    // Rx(90) sends x, y, z to (1,0,0), (0,0,1), (0,-1,0); Rz(90) sends (a, b, c) to (-b, a, c):
    // (0,1,0), (0,0,1), (1,0,0); scaled: (0,2,0), (0,0,1.5), (1,0,0).
    let data = [
        0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.5, 0.0, 1.0, 0.0, 0.0, 0.0, 3.0, 4.0, 0.1, 1.0,
    ];
    let obj = load(&data);
    // Asset front +z -> column 2 = world +x: the object faces +x, yaw +90 degrees.
    let obb = obj.obb();
    assert!((obb.side_direction(Side::Front) - Vector3::x()).norm() < 1e-12);
    assert!((obb.side_direction(Side::Top) - Vector3::z()).norm() < 1e-12);
    assert!((obj.yaw() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    // Object-frame scale (sx, sz, sy) = (2, 1, 1.5).
    assert_eq!(obj.scale(), Vector3::new(2.0, 1.0, 1.5));
    // Scaled local bounds: x [-1, 1], y [-0.3, 0.2], z [0, 0.75]: half extents (1, 0.25,
    // 0.375), local centre (0, -0.05, 0.375). Rz(90) sends it to (0.05, 0, 0.375); plus the
    // translation: (3.05, 4, 0.475).
    assert!((obb.half_extents - Vector3::new(1.0, 0.25, 0.375)).norm() < 1e-7);
    assert!(
        (obb.center - Point3::new(3.05, 4.0, 0.475)).norm() < 1e-7,
        "{}",
        obb.center
    );
    // World bounds: x = 3 - y_local in [2.8, 3.3], y = 4 + x_local in [3, 5], z in [0.1, 0.85].
    let w = obj.world_aabb();
    assert!((w.min - Point3::new(2.8, 3.0, 0.1)).norm() < 1e-7, "{w:?}");
    assert!((w.max - Point3::new(3.3, 5.0, 0.85)).norm() < 1e-7, "{w:?}");
}

#[test]
fn mirrored_transform_is_a_negative_x_scale() {
    // T = Rx(90) * diag(-1, 1, 1): determinant -1, folded into the x scale; the bump stays in
    // front (-y), the body's x range is mirrored onto itself.
    let data = [
        -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let obj = load(&data);
    assert_eq!(obj.scale(), Vector3::new(-1.0, 1.0, 1.0));
    assert!((obj.obb().side_direction(Side::Front) + Vector3::y()).norm() < 1e-12);
    assert!((obj.obb().center - Point3::new(0.0, -0.05, 0.25)).norm() < 1e-7);
    assert!(obj.mesh().is_closed());
    assert!((obj.mesh().volume().unwrap() - (1.0 * 0.5 * 0.4 + 0.2 * 0.2 * 0.1)).abs() < 1e-6);
}

#[test]
fn box_objects_use_the_object_frame_directly() {
    // A box's transform has no y-up conversion: yaw 90 about z, size (2, 1, 0.5), scale 2 in z.
    let text = r#"{"format": "sceneState", "scene": {"arch": {"elements": []}, "object": [
        {"index": 3, "box": {"size": [2.0, 1.0, 0.5]}, "category": "bed",
         "transform": {"data": [0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 2, 0, 1, 2, 0.5, 1]}}]}}"#;
    let library = sceneeval_io::AssetLibrary::new();
    let scene = read_scene_state_str(
        text,
        std::path::Path::new("b.json"),
        &library,
        &ReadOptions::default(),
    )
    .unwrap();
    let obj = &scene.objects()[0];
    assert_eq!(obj.id().as_str(), "idx3_box");
    assert_eq!(obj.category(), Some("bed"));
    // Half extents = size / 2 * scale = (1, 0.5, 0.5).
    assert_eq!(obj.box_half_extents(), Some(Vector3::new(1.0, 0.5, 0.5)));
    assert_eq!(obj.scale(), Vector3::new(1.0, 1.0, 2.0));
    // Column 0 = (0, 1, 0): local x points to world +y, so the front (-y local) points to +x.
    assert!((obj.obb().side_direction(Side::Front) - Vector3::x()).norm() < 1e-12);
    assert!((obj.obb().center - Point3::new(1.0, 2.0, 0.5)).norm() < 1e-12);
}
