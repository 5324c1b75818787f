//! Scenes for the stability tests: the standard 4 x 5 m bedroom (floor at z = 0, walls 2.8 m
//! high) with box objects placed by hand.

#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)]

use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Point3, Vector3};
use sceneeval_physics::{DecompositionCache, Stability, StabilityParams, StabilityReport, WeldMode};
use sceneeval_scene::{Scene, SceneObject, SupportType};
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
    let mut b = Scene::builder().id("test").room_builder(bedroom("r"));
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
        .evaluate(scene, &support, &DecompositionCache::in_memory(), &|| false)
        .unwrap()
}

/// The centre of an object's final pose.
pub fn final_position(report: &StabilityReport, i: usize) -> Point3 {
    let p = report.objects[i].final_pose.position;
    Point3::new(p[0], p[1], p[2])
}
