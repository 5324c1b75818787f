//! Helpers shared by the conversion tests: the generated native fixtures, converting them into
//! a temporary folder, reading the result back, and comparing boxes and metric numbers.

#![allow(dead_code, clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use sceneeval_convert::{ConvertOptions, Format, IdMap, Report, convert};
use sceneeval_geom::{Point3, Side, Vector3};
use sceneeval_io::assets::AssetSpec;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_plausibility::{PlausibilityParams, Sources, evaluate};
use sceneeval_scene::{Scene, SceneObject};
use serde_json::Value;

/// `fixtures/native/<sub>` of the workspace.
pub fn native(sub: &str) -> PathBuf {
    sceneeval_fixtures::default_output_dir().join("native").join(sub)
}

/// Each format with its fixture batch folder (under `fixtures/native`) and the asset folders
/// it converts with.
pub fn fixture_batches() -> Vec<(Format, &'static str, Vec<AssetSpec>)> {
    vec![
        (
            Format::Holodeck,
            "holodeck/scenes",
            specs(&[("objaverse", native("holodeck/objathor"))]),
        ),
        (
            Format::LayoutVlm,
            "layoutvlm/scenes",
            specs(&[("layoutvlm-objaverse", native("layoutvlm/assets"))]),
        ),
        (Format::IDesign, "idesign/scenes", vec![]),
        (Format::SceneAgent, "scene-agent/scenes", vec![]),
    ]
}

/// `--assets` specifications.
pub fn specs(specs: &[(&str, PathBuf)]) -> Vec<AssetSpec> {
    specs
        .iter()
        .map(|(p, d)| AssetSpec::parse(&format!("{p}={}", d.display())).unwrap())
        .collect()
}

/// Converts `input` into a fresh temporary folder (`<tmp>/out`).
pub fn convert_into(
    format: Format,
    input: &Path,
    assets: Vec<AssetSpec>,
    id_map: Option<&str>,
) -> (tempfile::TempDir, Report) {
    let tmp = tempfile::tempdir().unwrap();
    let mut options = ConvertOptions::default().with_assets(assets);
    if let Some(m) = id_map {
        options = options.with_id_map(IdMap::parse(m).unwrap());
    }
    let report = convert(format, input, &tmp.path().join("out"), &options).unwrap();
    (tmp, report)
}

/// Reads a converted scene with these asset folders.
pub fn read(path: &Path, assets: &[AssetSpec]) -> Scene {
    let strings: Vec<String> = assets
        .iter()
        .map(|a| format!("{}={}:{}", a.prefix, a.layout.name(), a.dir.display()))
        .collect();
    let library = AssetLibrary::from_specs(&strings).unwrap();
    read_scene_state(path, &library, &ReadOptions::default()).unwrap()
}

/// Asserts an object's OBB centre, size (width x depth x height) and world front direction.
#[track_caller]
pub fn assert_box(o: &SceneObject, centre: [f64; 3], size: [f64; 3], front: [f64; 3]) {
    let obb = o.obb();
    let tol = 1e-6;
    assert!(
        (obb.center - Point3::from(centre)).norm() < tol,
        "{}: centre {} != {centre:?}",
        o.id(),
        obb.center
    );
    assert!(
        (obb.extents() - Vector3::from(size)).norm() < tol,
        "{}: size {} != {size:?}",
        o.id(),
        obb.extents()
    );
    let f = obb.side_direction(Side::Front);
    assert!(
        (f - Vector3::from(front)).norm() < tol,
        "{}: front {f} != {front:?}",
        o.id()
    );
}

/// The plausibility summary of a scene as JSON (with stated support types and sides).
pub fn plausibility(scene: &Scene) -> Value {
    let report = evaluate(scene, &PlausibilityParams::default(), &Sources::default()).unwrap();
    serde_json::to_value(&report.summary).unwrap()
}

/// Asserts two JSON values are equal, numbers to `tol`.
#[track_caller]
pub fn assert_close(a: &Value, b: &Value, tol: f64) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!((x - y).abs() <= tol, "{x} != {y}");
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{a} vs {b}");
            for (p, q) in x.iter().zip(y) {
                assert_close(p, q, tol);
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(
                x.keys().collect::<Vec<_>>(),
                y.keys().collect::<Vec<_>>(),
                "{a} vs {b}"
            );
            for (k, p) in x {
                assert_close(p, &y[k], tol);
            }
        }
        _ => assert_eq!(a, b),
    }
}

/// A pose from a yaw (degrees) and a translation.
pub fn yawed(yaw_deg: f64, t: [f64; 3]) -> sceneeval_geom::Isometry3 {
    sceneeval_geom::Isometry3::from_parts(
        sceneeval_geom::na::Translation3::new(t[0], t[1], t[2]),
        sceneeval_geom::na::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw_deg.to_radians()),
    )
}

/// A scene built directly from rooms and `(model id, pose, object-frame scale)` placements,
/// written as sceneState and read back: the "native" route a converted scene must match.
pub fn written_directly(
    dir: &Path,
    library: &AssetLibrary,
    rooms: Vec<sceneeval_scene::Room>,
    placements: &[(String, sceneeval_geom::Isometry3, Vector3)],
) -> Scene {
    let objects = placements
        .iter()
        .enumerate()
        .map(|(i, (model_id, pose, scale))| {
            library
                .object(
                    sceneeval_io::scene_state::derived_object_id(i as i64, Some(model_id)),
                    model_id,
                    *pose,
                    *scale,
                )
                .unwrap()
                .with_index(i as i64)
        })
        .collect();
    let scene = Scene::new(None, objects, rooms).unwrap();
    let path = dir.join("direct.json");
    sceneeval_io::write_scene_state(&scene, &path).unwrap();
    read_scene_state(&path, library, &ReadOptions::default()).unwrap()
}

/// A rectangular room `[0, w] x [0, d]` with walls along its edges (counter-clockwise from
/// (0, 0)), ids `ids`, as the converters write them.
pub fn rectangle_room(
    id: &str,
    floor_id: &str,
    w: f64,
    d: f64,
    height: f64,
    thickness: f64,
    ids: [&str; 4],
) -> sceneeval_scene::Room {
    use sceneeval_geom::{Point2, Polygon2};
    let c = [
        Point2::new(0.0, 0.0),
        Point2::new(w, 0.0),
        Point2::new(w, d),
        Point2::new(0.0, d),
    ];
    let walls = (0..4)
        .map(|i| sceneeval_scene::WallSpec::new(ids[i], c[i], c[(i + 1) % 4], 0.0, height, thickness))
        .collect();
    let floor = sceneeval_scene::Floor {
        id: floor_id.into(),
        polygon: Polygon2::new(c.to_vec()).unwrap(),
        z: 0.0,
    };
    sceneeval_scene::Room::new(id, floor, walls, None).unwrap()
}
