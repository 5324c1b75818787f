//! Scenes for the stability tests: the standard 4 x 5 m bedroom (floor at z = 0, walls 2.8 m
//! high) with box objects placed by hand.

#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Point3, Vector3};
use sceneeval_physics::{DecompositionCache, Stability, StabilityParams, StabilityReport, WeldMode};
use sceneeval_scene::{Deadline, Scene, SceneObject, SupportType};
use sceneeval_test_support::bedroom;

/// A box object: half extents `h`, centre `c`, no rotation.
pub fn cuboid(id: &str, h: [f64; 3], c: [f64; 3]) -> SceneObject {
    SceneObject::new_box(id, Vector3::from(h), Isometry3::translation(c[0], c[1], c[2])).unwrap()
}

/// A box object turned by `angle` radians about the world x axis through its centre `c`.
pub fn tilted_cuboid(id: &str, h: [f64; 3], c: [f64; 3], angle: f64) -> SceneObject {
    let pose = Isometry3::from_parts(
        Translation3::new(c[0], c[1], c[2]),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), angle),
    );
    SceneObject::new_box(id, Vector3::from(h), pose).unwrap()
}

/// The bedroom with these objects.
pub fn room(objects: Vec<SceneObject>) -> Scene {
    let mut b = Scene::builder().name("test").room_builder(bedroom("r"));
    for o in objects {
        b = b.object(o);
    }
    b.build().unwrap()
}

/// Evaluates `scene` under `weld` (other parameters default) with the given support types
/// (`None` for every object when empty).
pub fn evaluate(scene: &Scene, weld: WeldMode, support: &[Option<SupportType>]) -> StabilityReport {
    evaluate_with(
        scene,
        StabilityParams {
            weld,
            ..StabilityParams::default()
        },
        support,
    )
}

/// Evaluates `scene` with `params`.
pub fn evaluate_with(
    scene: &Scene,
    params: StabilityParams,
    support: &[Option<SupportType>],
) -> StabilityReport {
    let support = if support.is_empty() {
        vec![None; scene.objects().len()]
    } else {
        support.to_vec()
    };
    Stability::new(params)
        .unwrap()
        .evaluate(
            scene,
            &support,
            &DecompositionCache::in_memory(),
            &Deadline::none(),
        )
        .unwrap()
}

/// The centre of an object's final pose.
pub fn final_position(report: &StabilityReport, i: usize) -> Point3 {
    let p = report.objects[i].final_pose.position;
    Point3::new(p[0], p[1], p[2])
}

/// A scene read from sceneState JSON (`arch` elements and `object` entries as given) as a run
/// reads it, with the repository's fixture furniture as the asset source `fixture`.
pub fn read_scene(arch: serde_json::Value, objects: serde_json::Value) -> Scene {
    use sceneeval_io::assets::PlainFolderSource;
    use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
    let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures"));
    let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(root.join("assets")));
    let json = serde_json::json!({"format": "sceneState", "scene": {
        "version": "scene@1.0.2", "up": [0.0, 0.0, 1.0], "unit": 1.0,
        "arch": {"version": "arch@1.0.2", "elements": arch},
        "object": objects}});
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.json");
    std::fs::write(&path, json.to_string()).unwrap();
    read_scene_state(&path, &library, &ReadOptions::default()).unwrap()
}

/// The `arch` element of a floor without walls, outline `points` (x, y) at z = 0.
pub fn floor(room: &str, points: &[[f64; 2]]) -> serde_json::Value {
    let points: Vec<[f64; 3]> = points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    serde_json::json!({"id": format!("floor_{room}"), "roomId": room, "type": "Floor", "points": points})
}

/// A fixture asset (`fixture.plant`, ...) standing on the floor at (x, y) turned by `yaw`
/// about z: the assets are y up, so the transform also turns y into z.
pub fn fixture_object(index: usize, model: &str, x: f64, y: f64, yaw: f64) -> serde_json::Value {
    let (s, c) = yaw.sin_cos();
    serde_json::json!({"index": index, "modelId": model,
        "transform": {"data": [c, s, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, s, -c, 0.0, 0.0, x, y, 0.0, 1.0]}})
}
