//! Writing a scene and reading it back gives an equal scene, and writing that again gives the
//! same bytes.

// Helpers outside `#[test]` functions may stop the test on a set-up failure.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::f64::consts::FRAC_PI_2;
use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Point2, Point3, Side, Vector3};
use sceneeval_io::{
    AssetLibrary, ReadOptions, read_scene_state, read_scene_state_str, scene_state_to_string,
    write_scene_state,
};
use sceneeval_scene::Category;
use sceneeval_scene::{RoomBuilder, Scene, SceneObject, SupportType};

fn pose(x: f64, y: f64, z: f64, yaw: f64) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
    )
}

/// Two rooms (one L-shaped, one with an explicit ceiling), doors and windows, box objects and
/// asset objects with scale, a mirror, categories and descriptions.
fn rich_scene(library: &AssetLibrary) -> Scene {
    let l_shape = vec![
        Point2::new(4.0, 0.0),
        Point2::new(8.0, 0.0),
        Point2::new(8.0, 2.0),
        Point2::new(6.0, 2.0),
        Point2::new(6.0, 4.0),
        Point2::new(4.0, 4.0),
    ];
    Scene::builder()
        .name("scene_7")
        .room_builder(
            RoomBuilder::rectangle("bedroom", Point2::new(0.0, 0.0), Point2::new(4.0, 4.0))
                .kind("bedroom")
                .wall_height(2.6)
                .wall_thickness(0.12)
                .with_ceiling()
                .door(1, [1.0, 1.9], [0.0, 2.05])
                .window(2, [0.7, 1.9], [0.9, 2.1])
                .window(2, [2.3, 3.3], [0.9, 2.1]),
        )
        .room_builder(
            RoomBuilder::polygon("hall", l_shape)
                .floor_z(0.05)
                .wall_height(2.75)
                .wall_thickness(0.0)
                .door(5, [0.5, 1.4], [0.0, 2.0]),
        )
        .add_box(
            "bed",
            Category::new("bed"),
            Vector3::new(0.8, 1.0, 0.25),
            pose_from_yaw(Point3::new(2.0, 3.0, 0.25), std::f64::consts::PI),
        )
        .object(
            SceneObject::new_box(
                "idx5_generator.desk",
                Vector3::new(0.6, 0.3, 0.4),
                pose_from_yaw(Point3::new(1.0, 0.5, 0.4), 0.3),
            )
            .unwrap()
            .with_index(5)
            .with_model_id("generator.desk")
            .with_category("desk")
            .with_description("a wooden desk \"with\" drawers")
            .with_support_type(SupportType::Ground)
            .with_functional_sides([Side::Front]),
        )
        .object(
            library
                .object(
                    "idx1_fixture.bump",
                    "fixture.bump",
                    pose(5.0, 1.0, 0.05, FRAC_PI_2),
                    Vector3::repeat(1.0),
                )
                .unwrap()
                .with_index(1),
        )
        .object(
            library
                .object(
                    "lamp",
                    "fixture.bump",
                    pose(7.0, 1.0, 0.05, -0.7),
                    Vector3::new(1.2, 0.8, 1.5),
                )
                .unwrap()
                .with_category("lamp")
                .with_support_type(SupportType::Ceiling)
                .with_functional_sides([]),
        )
        .object(
            library
                .object(
                    "mirrored",
                    "fixture.bump",
                    pose(5.0, 3.0, 0.05, 2.5),
                    Vector3::new(-1.0, 1.0, 1.0),
                )
                .unwrap(),
        )
        .build()
        .unwrap()
}

fn assert_objects_match(a: &Scene, b: &Scene) {
    assert_eq!(a.objects().len(), b.objects().len());
    for (x, y) in a.objects().iter().zip(b.objects()) {
        assert_eq!(x.id(), y.id());
        assert_eq!(x.model_id(), y.model_id(), "{}", x.id());
        assert_eq!(x.category(), y.category(), "{}", x.id());
        assert_eq!(x.description(), y.description(), "{}", x.id());
        assert_eq!(x.support_type(), y.support_type(), "{}", x.id());
        assert_eq!(x.functional_sides(), y.functional_sides(), "{}", x.id());
        assert_eq!(x.box_half_extents(), y.box_half_extents(), "{}", x.id());
        assert_eq!(x.scale(), y.scale(), "{}", x.id());
        assert_eq!(x.mesh(), y.mesh(), "{}", x.id());
        let (p, q) = (x.pose(), y.pose());
        assert!(
            (p.translation.vector - q.translation.vector).norm() < 1e-12,
            "{}",
            x.id()
        );
        assert!(p.rotation.angle_to(&q.rotation) < 1e-12, "{}", x.id());
        assert!((x.obb().center - y.obb().center).norm() < 1e-12, "{}", x.id());
        assert!(
            (x.obb().half_extents - y.obb().half_extents).norm() < 1e-12,
            "{}",
            x.id()
        );
    }
}

fn read(path: &Path, library: &AssetLibrary) -> Scene {
    read_scene_state(path, library, &ReadOptions::default()).unwrap()
}

#[test]
fn write_read_write_is_byte_identical_and_lossless() {
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    std::fs::write(
        dir.path().join("bump.json"),
        r#"{"category": "cabinet", "description": "a bump"}"#,
    )
    .unwrap();
    let library = common::fixture_library(dir.path());
    let a = rich_scene(&library);

    let path = dir.path().join("scene_7.json");
    write_scene_state(&a, &path).unwrap();
    let first = std::fs::read_to_string(&path).unwrap();
    let b = read(&path, &library);
    let second = scene_state_to_string(&b).unwrap();
    assert_eq!(first, second, "write -> read -> write changed the file");

    // The first read is lossless up to the pose quaternion's last bits.
    assert_eq!(b.name(), Some("scene_7"));
    assert_eq!(a.rooms(), b.rooms(), "architecture must survive exactly");
    assert_objects_match(&a, &b);
    // Reading the second file gives exactly the same scene.
    let c = read_scene_state_str(&second, &path, &library, &ReadOptions::default()).unwrap();
    assert_eq!(b, c);

    // Spot checks of the fields that must survive.
    let hall = b.room("hall").unwrap();
    assert_eq!(hall.floor_z(), 0.05);
    assert_eq!(hall.walls()[5].openings()[0].id, "hall_wall_5_door_0");
    let bedroom = b.room("bedroom").unwrap();
    assert_eq!(bedroom.kind(), Some("bedroom"));
    assert_eq!(bedroom.explicit_ceiling().unwrap().z, 2.6);
    assert_eq!(bedroom.walls()[0].thickness(), 0.12);
    assert_eq!(
        b.object("lamp").unwrap().category(),
        Some("lamp"),
        "file category overrides the asset's"
    );
    assert_eq!(b.object("mirrored").unwrap().category(), Some("cabinet"));
    assert_eq!(b.object("idx5_generator.desk").unwrap().index(), Some(5));
    assert_eq!(b.object("lamp").unwrap().scale(), Vector3::new(1.2, 0.8, 1.5));
    // Objects of one asset at one scale share one mesh; the asset file was read once.
    assert!(std::sync::Arc::ptr_eq(
        a.object("idx1_fixture.bump").unwrap().mesh(),
        b.object("idx1_fixture.bump").unwrap().mesh()
    ));
    assert_eq!(library.files_read(), 1);
}

#[test]
fn scaled_asset_has_the_scaled_obb() {
    // The bump asset's object-frame bounds are x [-0.5, 0.5], y [-0.3, 0.2], z [0, 0.5]; the
    // lamp is scaled by (1.2, 0.8, 1.5) in the object frame, so its OBB half extents are
    // (0.6, 0.2, 0.375) and its local centre (0, -0.04, 0.375).
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    let library = common::fixture_library(dir.path());
    let s = rich_scene(&library);
    let path = dir.path().join("s.json");
    write_scene_state(&s, &path).unwrap();
    let lamp = read(&path, &library).object("lamp").unwrap().clone();
    assert!((lamp.obb().half_extents - Vector3::new(0.6, 0.2, 0.375)).norm() < 1e-7);
    let local_centre = lamp.pose().inverse_transform_point(&lamp.obb().center);
    assert!((local_centre - Point3::new(0.0, -0.04, 0.375)).norm() < 1e-7);
    assert!((lamp.yaw() + 0.7).abs() < 1e-12);
}

#[test]
fn random_poses_and_scales_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    let library = common::fixture_library(dir.path());
    let path = dir.path().join("p.json");
    let angle = -3.2..3.2f64;
    let coord = -50.0..50.0f64;
    let scale = 0.05..20.0f64;
    let strategy = (
        (angle.clone(), angle.clone(), angle),
        (coord.clone(), coord.clone(), coord),
        (scale.clone(), scale.clone(), scale),
        any::<bool>(),
        (0.01..5.0f64, 0.01..5.0f64, 0.01..5.0f64),
    );
    let mut runner = TestRunner::new(Config::with_cases(512));
    runner
        .run(&strategy, |(euler, t, s, mirror, size)| {
            let rotation = UnitQuaternion::from_euler_angles(euler.0, euler.1, euler.2);
            let pose = Isometry3::from_parts(Translation3::new(t.0, t.1, t.2), rotation);
            let scale = Vector3::new(if mirror { -s.0 } else { s.0 }, s.1, s.2);
            let a = Scene::builder()
                .object(library.object("asset", "fixture.bump", pose, scale).unwrap())
                .object(SceneObject::new_box("box", Vector3::new(size.0, size.1, size.2), pose).unwrap())
                .build()
                .unwrap();
            let first = scene_state_to_string(&a).unwrap();
            let b = read_scene_state_str(&first, &path, &library, &ReadOptions::default()).unwrap();
            let second = scene_state_to_string(&b).unwrap();
            prop_assert_eq!(&first, &second);
            assert_objects_match(&a, &b);
            Ok(())
        })
        .unwrap();
}

#[test]
fn matrix_only_files_stabilise_after_one_write() {
    // A transform without `objectPose` (as other writers produce, here with float32 noise) is
    // decomposed; the written file then carries the exact pose and is stable.
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    let library = common::fixture_library(dir.path());
    let text = r#"{"format": "sceneState", "scene": {"arch": {"elements": []}, "object": [
        {"index": 0, "modelId": "fixture.bump", "transform": {"data": [
            -0.006283166352659464, 0.9999802708625793, 0.0, 0.0,
            -7.549640912429822e-08, -4.743658799100103e-10, 1.0, 0.0,
            0.9999802708625793, 0.006283166352659464, 7.549790126404332e-08, 0.0,
            0.5678388476371765, 2.4387855529785156, 1.0016639232635498, 1.0]}}]}}"#;
    let path = dir.path().join("scene_3.json");
    let a = read_scene_state_str(text, &path, &library, &ReadOptions::default()).unwrap();
    let first = scene_state_to_string(&a).unwrap();
    let b = read_scene_state_str(&first, &path, &library, &ReadOptions::default()).unwrap();
    assert_eq!(a, b);
    assert_eq!(first, scene_state_to_string(&b).unwrap());
    // The matrix maps the asset front (+z, column 2) to (0.99998, 0.00628, 0): the object's
    // front points there, and its yaw is atan2(0.99998, ...) ~ 90.36 degrees.
    // Its column lengths are 1 to float32 precision: no scale, and the asset's own mesh.
    assert_eq!(a.objects()[0].scale(), Vector3::repeat(1.0));
    assert!(std::sync::Arc::ptr_eq(
        a.objects()[0].mesh(),
        &library.asset("fixture.bump").unwrap().mesh
    ));
    let front = a.objects()[0].obb().side_direction(sceneeval_geom::Side::Front);
    assert!((front - Vector3::new(0.9999802708625793, 0.006283166352659464, 0.0)).norm() < 1e-6);
}

#[test]
fn float32_matrices_from_other_writers_round_trip_exactly_after_the_first_read() {
    // Transforms written in float32 precision (as Blender- or Unity-based exporters do) are
    // orthogonal only to ~1e-7; reading one, writing it and reading that gives the same scene
    // bit for bit.
    let dir = tempfile::tempdir().unwrap();
    common::write_bump_asset(dir.path(), "bump");
    let library = common::fixture_library(dir.path());
    let path = dir.path().join("f.json");
    let angle = -3.2..3.2f64;
    let strategy = (
        (angle.clone(), angle.clone(), angle),
        (0.2..5.0f64, 0.2..5.0f64, 0.2..5.0f64),
        any::<bool>(),
    );
    let mut runner = TestRunner::new(Config::with_cases(256));
    runner
        .run(&strategy, |(e, s, is_box)| {
            let r = sceneeval_geom::Rotation3::from_euler_angles(e.0, e.1, e.2);
            let data = sceneeval_io::frames::compose_sstk(&r, &Vector3::new(s.0, s.1, s.2), &Vector3::new(1.0, 2.0, 0.5))
                .map(|v| f64::from(v as f32));
            let entry = if is_box {
                serde_json::json!({"index": 0, "box": {"size": [0.5, 0.5, 0.5]}, "transform": {"data": data}})
            } else {
                serde_json::json!({"index": 0, "modelId": "fixture.bump", "transform": {"data": data}})
            };
            let text = serde_json::json!({"format": "sceneState", "scene": {"arch": {"elements": []}, "object": [entry]}})
                .to_string();
            let a = read_scene_state_str(&text, &path, &library, &ReadOptions::default()).unwrap();
            let first = scene_state_to_string(&a).unwrap();
            let b = read_scene_state_str(&first, &path, &library, &ReadOptions::default()).unwrap();
            prop_assert_eq!(&a, &b);
            prop_assert_eq!(&first, &scene_state_to_string(&b).unwrap());
            Ok(())
        })
        .unwrap();
}
