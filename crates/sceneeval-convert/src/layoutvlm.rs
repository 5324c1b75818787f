//! LayoutVLM: `scene_NNN/scene.json` (the room's `boundary` and the `assets`, each with its
//! Objaverse `uid`) and `scene_NNN/layout.json` (each placed asset's `position`, its box
//! centre, and `rotation`, Euler angles in degrees), both keyed by the same asset keys.
//!
//! - Room `0`: the floor polygon `boundary.floor_vertices`, one wall per floor edge,
//!   `boundary.wall_height` high (3 m when absent, as the fork), 0.025 m thick.
//! - Objects: model id `layoutvlm-objaverse.<uid>`, transform `R * Rx(+90 deg)` with
//!   `R = Rz(rz) * Ry(ry) * Rx(rx)` (the fork's quaternion formula), the box centre at
//!   `position`. A `layout.json` entry and a `scene.json` asset are **paired by their key**;
//!   the fork pairs them by position, so one asset LayoutVLM failed to place shifts every later
//!   one onto the wrong model. Assets without a placement are skipped (and listed); a
//!   placement of an asset `scene.json` does not have is an error.

use sceneeval_geom::{Point2, Point3, Polygon2, Real, Rotation3, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_io::frames::ObjectFront;
use sceneeval_io::scene_state::derived_object_id;
use sceneeval_io::scene_state::json_in::{Doc, optional, ptr_index, ptr_key};
use sceneeval_scene::{Floor, Room, WallSpec};
use serde_json::Value;

use crate::format::Converter;
use crate::holodeck::{WALL_DEPTH, is_objaverse};
use crate::native::{read_json, text};
use crate::output::Output;
use crate::place::{Target, place};
use crate::{ConvertError, NativeScene, SkippedObject, Written};

/// Wall height when `boundary.wall_height` is absent (the fork's default).
const DEFAULT_WALL_HEIGHT: Real = 3.0;

/// LayoutVLM's Euler angles (degrees) as a rotation: `Rz(z) * Ry(y) * Rx(x)`.
pub(crate) fn euler_zyx(x: Real, y: Real, z: Real) -> Rotation3 {
    let about = |axis, deg: Real| Rotation3::from_axis_angle(&axis, deg.to_radians());
    about(Vector3::z_axis(), z) * about(Vector3::y_axis(), y) * about(Vector3::x_axis(), x)
}

/// The LayoutVLM conversion. Its objects' ids are the keys of `scene.json`'s `assets`,
/// unique since a key given twice in one JSON object is an error.
pub(crate) struct LayoutVlm;

impl Converter for LayoutVlm {
    /// Converts one LayoutVLM scene into `scene_<id>.json` of `out`.
    fn convert(
        &self,
        scene: &NativeScene,
        id: u64,
        out: Output<'_>,
        library: &AssetLibrary,
    ) -> Result<Written, ConvertError> {
        let scene_file = scene.dir.join("scene.json");
        let layout_file = scene.dir.join("layout.json");
        let scene_root = read_json(&scene_file, library)?;
        let layout_root = read_json(&layout_file, library)?;
        let sdoc = Doc { path: &scene_file };
        let ldoc = Doc { path: &layout_file };
        let task = sdoc.object(&scene_root, "")?;
        let layout = ldoc.object(&layout_root, "")?;

        let room = read_room(&sdoc, task)?;
        let assets = sdoc.object(sdoc.required(task, "", "assets")?, "/assets")?;
        if let Some(key) = layout.keys().find(|k| !assets.contains_key(*k)) {
            return Err(ldoc
                .invalid(
                    &ptr_key("", key),
                    format!("no asset {key:?} in {}'s /assets", scene_file.display()),
                )
                .into());
        }
        let mut objects = Vec::new();
        let mut skipped = Vec::new();
        for (key, asset) in assets {
            let aptr = ptr_key("/assets", key);
            let uid = match optional(sdoc.object(asset, &aptr)?, "uid") {
                Some(v) => sdoc.string(v, &ptr_key(&aptr, "uid"))?.to_owned(),
                // Older task files key assets as `<uid>-<n>` without a `uid` field.
                None => match key.rsplit_once('-') {
                    Some((uid, _)) if is_objaverse(uid) => uid.to_owned(),
                    _ => {
                        return Err(sceneeval_io::IoError::MissingField {
                            path: scene_file.clone(),
                            pointer: aptr,
                            field: "uid",
                        }
                        .into());
                    }
                },
            };
            let Some(placement) = layout.get(key) else {
                tracing::info!(file = %layout_file.display(), asset = %key, "not placed by LayoutVLM; skipped");
                skipped.push(SkippedObject {
                    file: scene_file.clone(),
                    pointer: aptr,
                    name: key.clone(),
                    reason: "not placed: layout.json has no entry for it".into(),
                });
                continue;
            };
            let lptr = ptr_key("", key);
            let p = ldoc.object(placement, &lptr)?;
            let position = ldoc.numbers::<3>(
                ldoc.required(p, &lptr, "position")?,
                &ptr_key(&lptr, "position"),
                "an array of 3 numbers",
            )?;
            let rotation = match optional(p, "rotation") {
                Some(v) => ldoc.numbers::<3>(v, &ptr_key(&lptr, "rotation"), "an array of 3 numbers")?,
                None => [0.0; 3],
            };
            let model_id = format!("layoutvlm-objaverse.{uid}");
            let object_id = derived_object_id(objects.len() as i64, Some(&model_id));
            let sstk = euler_zyx(rotation[0], rotation[1], rotation[2])
                * Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
            let object = place(
                library,
                &object_id,
                &model_id,
                &sstk,
                &Vector3::repeat(1.0),
                ObjectFront::MinusY,
                Target::Centre(Point3::from(position)),
                (&layout_file, &lptr),
            )?
            .with_index(objects.len() as i64);
            objects.push(object);
        }
        out.write_scene(objects, vec![room], &scene_file, id)?;
        Ok(Written {
            files: Vec::new(),
            skipped_objects: skipped,
        })
    }
}

fn read_room(doc: &Doc<'_>, task: &serde_json::Map<String, Value>) -> Result<Room, ConvertError> {
    let boundary = doc.object(doc.required(task, "", "boundary")?, "/boundary")?;
    let vptr = "/boundary/floor_vertices";
    let vertices = doc
        .array(doc.required(boundary, "/boundary", "floor_vertices")?, vptr)?
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let p = ptr_index(vptr, i);
            match v.as_array().map(Vec::len) {
                Some(2) => doc
                    .numbers::<2>(v, &p, "an [x, y] or [x, y, z] array")
                    .map(|[x, y]| [x, y, 0.0]),
                _ => doc.numbers::<3>(v, &p, "an [x, y] or [x, y, z] array"),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    if vertices.len() < 3 {
        return Err(doc
            .invalid(
                vptr,
                format!("a floor needs at least 3 points, got {}", vertices.len()),
            )
            .into());
    }
    let height = match optional(boundary, "wall_height") {
        Some(v) => doc.number(v, "/boundary/wall_height")?,
        None => DEFAULT_WALL_HEIGHT,
    };
    let z = vertices.iter().map(|v| v[2]).sum::<Real>() / vertices.len() as Real;
    let points: Vec<Point2> = vertices.iter().map(|v| Point2::new(v[0], v[1])).collect();
    let polygon =
        Polygon2::new(points.clone()).map_err(|e| doc.invalid(vptr, format!("floor polygon: {e}")))?;
    let walls = (0..points.len())
        .map(|i| {
            WallSpec::new(
                format!("wall_{i}"),
                points[i],
                points[(i + 1) % points.len()],
                z,
                height,
                WALL_DEPTH,
            )
        })
        .collect();
    let kind = text(doc, task, "", "room_type")?;
    let floor = Floor {
        id: "floor_0".into(),
        polygon,
        z,
    };
    let room =
        Room::new("0", floor, walls, None).map_err(|e| ConvertError::scene(doc.path, "/boundary", e))?;
    Ok(match kind {
        Some(k) => room.with_kind(k),
        None => room,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_compose_as_the_fork_s_quaternion() {
        // The fork's formula with (rx, ry, rz) = (0, 0, 90): q = (0, 0, sin 45, cos 45), a
        // quarter turn about z: x -> y.
        assert!((euler_zyx(0.0, 0.0, 90.0) * Vector3::x() - Vector3::y()).norm() < 1e-15);
        // Rz * Ry * Rx: x first. (30, 0, 90): x-axis stays under Rx, then z turns it to y.
        assert!((euler_zyx(30.0, 0.0, 90.0) * Vector3::x() - Vector3::y()).norm() < 1e-15);
        // Its quaternion, from the fork's formula (cx cy cz + sx sy sz, ...), for (10, 20, 30).
        let (rx, ry, rz) = (
            10f64.to_radians() / 2.0,
            20f64.to_radians() / 2.0,
            30f64.to_radians() / 2.0,
        );
        let (cx, sx, cy, sy, cz, sz) = (rx.cos(), rx.sin(), ry.cos(), ry.sin(), rz.cos(), rz.sin());
        let q = sceneeval_geom::na::UnitQuaternion::from_quaternion(sceneeval_geom::na::Quaternion::new(
            cx * cy * cz + sx * sy * sz,
            sx * cy * cz - cx * sy * sz,
            cx * sy * cz + sx * cy * sz,
            cx * cy * sz - sx * sy * cz,
        ));
        assert!((q.to_rotation_matrix().matrix() - euler_zyx(10.0, 20.0, 30.0).matrix()).norm() < 1e-15);
    }
}
