//! Holodeck: an AI2-THOR house JSON per scene folder, in Unity's frame (y up, left-handed,
//! metres, Euler angles in degrees).
//!
//! - Rooms: `rooms[].floorPolygon` (`{x, y, z}` points; Unity `(x, z)` is the floor plan,
//!   `y` the height), `id`, `roomType`.
//! - Walls: `walls[]` with `id`, `roomId`, `segment` (`[[x, z], [x, z]]`), `height`, `width`;
//!   written 0.025 m thick. A wall `<id>|exterior` is the outside face of wall `<id>` (its
//!   segment reversed): it is not written, its openings go to its twin.
//! - Doors and windows: `doors[]` / `windows[]` with `wall0`, `wall1` and `holePolygon` (two
//!   `{x, y}` corners: x along `wall0` from its first point, y above the floor). Each is placed
//!   where it is in the world and projected onto every wall that shows it (`wall0`, and
//!   `wall1`, where the projection is the fork's mirror `width - x`).
//! - Objects: `objects[]` with `assetId`, `position` (the object's box centre) and `rotation`
//!   (Unity Euler angles). Model id `objaverse.<assetId>`; an asset id that is not an Objaverse
//!   uid (32 hex digits: AI2-THOR's own assets) is skipped with a warning. Objects listed in
//!   `floor_objects` stand on their room's floor; all others have their box centre at
//!   `position` (which is where AI2-THOR puts it: it spawns house objects by their bounding-box
//!   centre).

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use sceneeval_geom::{Point2, Point3, Polygon2, Real, Rotation3, Vector2, Vector3};
use sceneeval_io::frames::ObjectFront;
use sceneeval_io::scene_state::derived_object_id;
use sceneeval_io::scene_state::json_in::{Doc, optional, ptr_index, ptr_key};
use sceneeval_io::{AssetLibrary, IoError};
use sceneeval_scene::{Floor, Opening, OpeningKind, Room, SceneObject, WallSpec};
use serde_json::{Map, Value};

use crate::format::Converter;
use crate::native::{Ids, read_json, subfolders, text, xyz};
use crate::output::Output;
use crate::place::{Target, place};
use crate::{ConvertError, NativeScene, SkippedObject, Written};

/// Wall thickness written for Holodeck walls (the fork's 0.025 m).
pub const WALL_DEPTH: Real = 0.025;
/// The suffix of Holodeck's exterior wall faces.
const EXTERIOR: &str = "|exterior";

/// The rotation Unity's `Quaternion.Euler(x, y, z)` makes (angles in degrees), as a matrix
/// acting on column vectors in Unity's coordinates: `Ry(y) * Rx(x) * Rz(z)`.
///
/// Unity's scripting reference for `Quaternion.Euler` (versions 5.6 to 2021 alike): "Returns a
/// rotation that rotates z degrees around the z axis, x degrees around the x axis, and y
/// degrees around the y axis; applied in that order", i.e. about the fixed axes z first, then
/// x, then y. Unity's quaternion algebra is the usual one on coordinates (its left-handedness
/// only changes how a positive angle looks on screen), so the matrices are the usual
/// right-handed ones: `Quaternion.Euler(0, 90, 0) * (0, 0, 1) = (1, 0, 0)`. The SceneSmith
/// fork's headless converter composes `Rz * Rx * Ry` instead (scipy's intrinsic `"ZXY"`),
/// which differs for every object tilted about x or z.
///
/// ```
/// use sceneeval_convert::unity_euler;
/// use sceneeval_geom::Vector3;
/// // z first (x -> y), then y by 90 leaves y alone: (1, 0, 0) -> (0, 1, 0).
/// let v = unity_euler(0.0, 90.0, 90.0) * Vector3::x();
/// assert!((v - Vector3::y()).norm() < 1e-15);
/// ```
pub fn unity_euler(x: Real, y: Real, z: Real) -> Rotation3 {
    let about = |axis: Vector3, deg: Real| {
        Rotation3::from_axis_angle(&sceneeval_geom::na::Unit::new_normalize(axis), deg.to_radians())
    };
    about(Vector3::y(), y) * about(Vector3::x(), x) * about(Vector3::z(), z)
}

/// The sceneState rotation of a Holodeck object with Unity Euler angles `(x, y, z)`: the
/// reference's Unity bridge `Quaternion.Euler(90, 0, 0) * Quaternion.Euler(x, -(y - 180), -z)`
/// (Unity's y-up left-handed frame to z-up right-handed, and the 180-degree turn of the
/// Objathor assets as SceneEval prepares them), mapping the asset's file coordinates.
pub(crate) fn sstk_rotation(x: Real, y: Real, z: Real) -> Rotation3 {
    unity_euler(90.0, 0.0, 0.0) * unity_euler(x, 180.0 - y, -z)
}

/// Whether an asset id is an Objaverse uid (32 hexadecimal digits).
pub(crate) fn is_objaverse(asset_id: &str) -> bool {
    asset_id.len() == 32 && asset_id.bytes().all(|b| b.is_ascii_hexdigit())
}

/// The house JSON of a scene folder: `<name>/<name>.json`, else the folder's only `.json`
/// file; `None` when it has none.
fn house_file(name: &str, dir: &Path) -> Result<Option<PathBuf>, ConvertError> {
    let own = dir.join(format!("{name}.json"));
    if own.is_file() {
        return Ok(Some(own));
    }
    let entries = std::fs::read_dir(dir)
        .map_err(|e| ConvertError::input(dir, format!("cannot list the folder: {e}")))?;
    let mut jsons: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "json"))
        .collect();
    jsons.sort();
    match jsons.len() {
        0 => Ok(None),
        1 => Ok(jsons.pop()),
        _ => Err(ConvertError::input(
            dir,
            format!(
                "{} JSON files and none named {name}.json: cannot tell which is the house",
                jsons.len()
            ),
        )),
    }
}

/// The Holodeck conversion.
pub(crate) struct Holodeck;

impl Converter for Holodeck {
    /// Every sub-folder holding a house JSON, keyed by its position in name order (as the fork
    /// numbers them).
    fn scenes(&self, input: &Path) -> Result<Vec<NativeScene>, ConvertError> {
        let mut out = Vec::new();
        for (name, dir) in subfolders(input)? {
            match house_file(&name, &dir)? {
                Some(_) => out.push(NativeScene {
                    key: out.len() as u64,
                    dir,
                }),
                None => tracing::debug!(folder = %dir.display(), "no house JSON; not a Holodeck scene"),
            }
        }
        Ok(out)
    }

    fn expected_scenes(&self) -> &'static str {
        "a folder per scene holding its house JSON"
    }

    /// Converts one Holodeck scene into `scene_<id>.json` of `out`.
    fn convert(
        &self,
        scene: &NativeScene,
        id: u64,
        out: Output<'_>,
        library: &AssetLibrary,
    ) -> Result<Written, ConvertError> {
        let name = scene
            .dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let file =
            house_file(&name, &scene.dir)?.ok_or_else(|| ConvertError::input(&scene.dir, "no house JSON"))?;
        let root = read_json(&file, library)?;
        let doc = Doc { path: &file };
        let house = doc.object(&root, "")?;

        let mut rooms = read_rooms(&doc, house)?;
        let mut walls = read_walls(&doc, house)?;
        for (key, kind) in [("doors", OpeningKind::Door), ("windows", OpeningKind::Window)] {
            add_openings(&doc, house, key, kind, &mut walls)?;
        }
        let mut built = Vec::with_capacity(rooms.len());
        for (room_ptr, id, kind, floor) in rooms.drain(..) {
            let specs = walls
                .iter()
                .filter(|w| w.twin.is_none() && w.room == id)
                .map(|w| WallSpec {
                    openings: w.openings.clone(),
                    ..WallSpec::new(w.id.clone(), w.start, w.end, floor.z, w.height, WALL_DEPTH)
                })
                .collect();
            let room = Room::new(id.clone(), floor, specs, None)
                .map_err(|e| ConvertError::scene(&file, &room_ptr, e))?;
            built.push(match kind {
                Some(k) => room.with_kind(k),
                None => room,
            });
        }
        if let Some(w) = walls
            .iter()
            .find(|w| w.twin.is_none() && !built.iter().any(|r| r.id().as_str() == w.room))
        {
            return Err(doc
                .invalid(
                    &ptr_key(&w.ptr, "roomId"),
                    format!("no room {:?} in /rooms", w.room),
                )
                .into());
        }

        let (objects, skipped_objects) = read_objects(&doc, house, &built, library)?;
        out.write_scene(objects, built, &file, id)?;
        Ok(Written {
            files: Vec::new(),
            skipped_objects,
        })
    }
}

struct HoloWall {
    ptr: String,
    id: String,
    room: String,
    start: Point2,
    end: Point2,
    height: Real,
    /// The interior wall this one is the outside face of.
    twin: Option<usize>,
    openings: Vec<Opening>,
}

impl HoloWall {
    fn length(&self) -> Real {
        (self.end - self.start).norm()
    }
}

/// A room of the house: its pointer, id, room type and floor.
type HoloRoom = (String, String, Option<String>, Floor);

/// The rooms.
fn read_rooms(doc: &Doc<'_>, house: &Map<String, Value>) -> Result<Vec<HoloRoom>, ConvertError> {
    let list = doc.array(doc.required(house, "", "rooms")?, "/rooms")?;
    let mut out = Vec::with_capacity(list.len());
    for (i, r) in list.iter().enumerate() {
        let ptr = ptr_index("/rooms", i);
        let o = doc.object(r, &ptr)?;
        let id = doc.id(doc.required(o, &ptr, "id")?, &ptr_key(&ptr, "id"))?;
        let kind = text(doc, o, &ptr, "roomType")?.map(str::to_owned);
        let poly_ptr = ptr_key(&ptr, "floorPolygon");
        let points = doc
            .array(doc.required(o, &ptr, "floorPolygon")?, &poly_ptr)?
            .iter()
            .enumerate()
            .map(|(k, p)| xyz(doc, p, &ptr_index(&poly_ptr, k), Some([0.0; 3])))
            .collect::<Result<Vec<_>, _>>()?;
        if points.len() < 3 {
            return Err(doc
                .invalid(
                    &poly_ptr,
                    format!("a floor needs at least 3 points, got {}", points.len()),
                )
                .into());
        }
        // Unity (x, y, z) -> (x, z, y): the floor plan is Unity's x-z plane, its height y.
        let z = points.iter().map(|p| p[1]).sum::<Real>() / points.len() as Real;
        let polygon = Polygon2::new(points.iter().map(|p| Point2::new(p[0], p[2])).collect())
            .map_err(|e| doc.invalid(&poly_ptr, format!("floor polygon: {e}")))?;
        let floor = Floor {
            id: format!("floor|{id}"),
            polygon,
            z,
        };
        out.push((ptr, id, kind, floor));
    }
    Ok(out)
}

fn read_walls(doc: &Doc<'_>, house: &Map<String, Value>) -> Result<Vec<HoloWall>, ConvertError> {
    let Some(list) = optional(house, "walls") else {
        return Ok(Vec::new());
    };
    let list = doc.array(list, "/walls")?;
    let mut walls = Vec::with_capacity(list.len());
    for (i, w) in list.iter().enumerate() {
        let ptr = ptr_index("/walls", i);
        let o = doc.object(w, &ptr)?;
        let id = doc.id(doc.required(o, &ptr, "id")?, &ptr_key(&ptr, "id"))?;
        let room = doc.id(doc.required(o, &ptr, "roomId")?, &ptr_key(&ptr, "roomId"))?;
        let height = doc.number(doc.required(o, &ptr, "height")?, &ptr_key(&ptr, "height"))?;
        let seg_ptr = ptr_key(&ptr, "segment");
        let seg = doc.array(doc.required(o, &ptr, "segment")?, &seg_ptr)?;
        if seg.len() != 2 {
            return Err(doc
                .wrong(&seg_ptr, "two [x, z] points", &Value::Array(seg.clone()))
                .into());
        }
        let a = doc.numbers::<2>(&seg[0], &ptr_index(&seg_ptr, 0), "an [x, z] array of 2 numbers")?;
        let b = doc.numbers::<2>(&seg[1], &ptr_index(&seg_ptr, 1), "an [x, z] array of 2 numbers")?;
        walls.push(HoloWall {
            ptr,
            id,
            room,
            start: Point2::new(a[0], a[1]),
            end: Point2::new(b[0], b[1]),
            height,
            twin: None,
            openings: Vec::new(),
        });
    }
    let mut seen = HashSet::new();
    for w in &walls {
        if !seen.insert(w.id.as_str()) {
            return Err(doc
                .invalid(
                    &ptr_key(&w.ptr, "id"),
                    format!("wall id {:?} is used twice", w.id),
                )
                .into());
        }
    }
    for k in 0..walls.len() {
        if let Some(inner) = walls[k].id.strip_suffix(EXTERIOR) {
            walls[k].twin = walls.iter().position(|w| w.id == inner);
            if walls[k].twin.is_none() {
                tracing::warn!(file = %doc.path.display(), wall = %walls[k].id, "exterior wall without its interior twin; kept as a wall");
            }
        }
    }
    Ok(walls)
}

/// Adds the doors or windows of `/key` to the walls that show them.
fn add_openings(
    doc: &Doc<'_>,
    house: &Map<String, Value>,
    key: &str,
    kind: OpeningKind,
    walls: &mut [HoloWall],
) -> Result<(), ConvertError> {
    let Some(list) = optional(house, key) else {
        return Ok(());
    };
    let base = format!("/{key}");
    for (i, item) in doc.array(list, &base)?.iter().enumerate() {
        let ptr = ptr_index(&base, i);
        let o = doc.object(item, &ptr)?;
        let id = doc.id(doc.required(o, &ptr, "id")?, &ptr_key(&ptr, "id"))?;
        let wall_ref = |field: &'static str| -> Result<Option<usize>, ConvertError> {
            let Some(v) = optional(o, field) else {
                return Ok(None);
            };
            let p = ptr_key(&ptr, field);
            let name = doc.id(v, &p)?;
            walls
                .iter()
                .position(|w| w.id == name)
                .map(Some)
                .ok_or_else(|| doc.invalid(&p, format!("no wall {name:?} in /walls")).into())
        };
        let Some(wall0) = wall_ref("wall0")? else {
            return Err(IoError::MissingField {
                path: doc.path_buf(),
                pointer: ptr,
                field: "wall0",
            }
            .into());
        };
        let wall1 = wall_ref("wall1")?;
        let hole_ptr = ptr_key(&ptr, "holePolygon");
        let corners = doc
            .array(doc.required(o, &ptr, "holePolygon")?, &hole_ptr)?
            .iter()
            .enumerate()
            .map(|(k, p)| xyz(doc, p, &ptr_index(&hole_ptr, k), Some([0.0; 3])))
            .collect::<Result<Vec<_>, _>>()?;
        if corners.len() < 2 {
            return Err(doc.invalid(&hole_ptr, "a hole needs two corners").into());
        }
        let (x0, x1) = min_max(corners.iter().map(|c| c[0]));
        let (y0, y1) = min_max(corners.iter().map(|c| c[1]));
        // The hole's ends in the world: along wall0 from its first point.
        let w0 = &walls[wall0];
        let dir0 = (w0.end - w0.start) / w0.length();
        let ends = [w0.start + dir0 * x0, w0.start + dir0 * x1];
        let mut targets: Vec<usize> = Vec::new();
        for w in std::iter::once(wall0).chain(wall1) {
            let t = walls[w].twin.unwrap_or(w);
            if !targets.contains(&t) {
                targets.push(t);
            }
        }
        for t in targets {
            let wall = &mut walls[t];
            let (len, dir) = (wall.length(), (wall.end - wall.start) / wall.length());
            let normal = Vector2::new(-dir.y, dir.x);
            let along = ends.map(|p| (p - wall.start).dot(&dir));
            let off = ends
                .iter()
                .map(|p| (p - wall.start).dot(&normal).abs())
                .fold(0.0, Real::max);
            let (a, b) = min_max(along.into_iter());
            if off > 0.5 || b <= 0.0 || a >= len {
                tracing::warn!(file = %doc.path.display(), opening = %id, wall = %wall.id, "the opening is not on this wall; not added to it");
                continue;
            }
            wall.openings
                .push(Opening::new(id.clone(), kind, [a, b], [y0, y1]));
        }
    }
    Ok(())
}

fn min_max(values: impl Iterator<Item = Real>) -> (Real, Real) {
    values.fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

fn read_objects(
    doc: &Doc<'_>,
    house: &Map<String, Value>,
    rooms: &[Room],
    library: &AssetLibrary,
) -> Result<(Vec<SceneObject>, Vec<SkippedObject>), ConvertError> {
    let mut floor_ids = HashSet::new();
    if let Some(list) = optional(house, "floor_objects") {
        for (i, item) in doc.array(list, "/floor_objects")?.iter().enumerate() {
            let ptr = ptr_index("/floor_objects", i);
            let o = doc.object(item, &ptr)?;
            floor_ids.insert(doc.id(doc.required(o, &ptr, "id")?, &ptr_key(&ptr, "id"))?);
        }
    }
    let mut objects = Vec::new();
    let mut skipped = Vec::new();
    let Some(list) = optional(house, "objects") else {
        return Ok((objects, skipped));
    };
    // `floor_objects` names objects by id: two objects with one id could not be told apart.
    let mut ids = Ids::new(doc);
    for (i, item) in doc.array(list, "/objects")?.iter().enumerate() {
        let ptr = ptr_index("/objects", i);
        let o = doc.object(item, &ptr)?;
        let name = doc.id(doc.required(o, &ptr, "id")?, &ptr_key(&ptr, "id"))?;
        ids.add(&name, &ptr)?;
        let asset = doc.string(doc.required(o, &ptr, "assetId")?, &ptr_key(&ptr, "assetId"))?;
        if !is_objaverse(asset) {
            tracing::info!(file = %doc.path.display(), object = %name, asset, "AI2-THOR asset skipped: SceneEval has no AI2-THOR assets");
            skipped.push(SkippedObject {
                file: doc.path_buf(),
                pointer: ptr,
                name,
                reason: format!("asset {asset:?} is an AI2-THOR asset, not an Objaverse uid (32 hex digits)"),
            });
            continue;
        }
        let p = xyz(
            doc,
            doc.required(o, &ptr, "position")?,
            &ptr_key(&ptr, "position"),
            None,
        )?;
        let r = match optional(o, "rotation") {
            Some(v) => xyz(doc, v, &ptr_key(&ptr, "rotation"), Some([0.0; 3]))?,
            None => [0.0; 3],
        };
        // Unity (x, y, z) -> (x, z, y).
        let centre = Point3::new(p[0], p[2], p[1]);
        let target = if floor_ids.contains(&name) {
            let room = text(doc, o, &ptr, "roomId")?;
            let floor_z = rooms
                .iter()
                .find(|r| Some(r.id().as_str()) == room)
                .or_else(|| {
                    rooms
                        .iter()
                        .find(|r| r.floor().contains_point(&Point2::new(centre.x, centre.y)))
                })
                .map_or(0.0, Room::floor_z);
            Target::OnFloor {
                x: centre.x,
                y: centre.y,
                floor_z,
            }
        } else {
            Target::Centre(centre)
        };
        let model_id = format!("objaverse.{asset}");
        let id = derived_object_id(objects.len() as i64, Some(&model_id));
        let object = place(
            library,
            &id,
            &model_id,
            &sstk_rotation(r[0], r[1], r[2]),
            &Vector3::repeat(1.0),
            ObjectFront::MinusY,
            target,
            (doc.path, &ptr),
        )?
        .with_index(objects.len() as i64);
        objects.push(object);
    }
    Ok((objects, skipped))
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::conventions::{OBJECT_FRONT, object_from_asset};

    #[test]
    fn unity_applies_z_then_x_then_y() {
        // Hand-computed on the unit vectors: Rz(90): x -> y; Rx(90): y -> z, z -> -y;
        // Ry(90): z -> x, x -> -z.
        let v = unity_euler(90.0, 90.0, 0.0) * Vector3::z();
        // z -> Rx(90) -> -y -> Ry(90) -> -y.
        assert!((v + Vector3::y()).norm() < 1e-15, "{v}");
        // The fork's order Rz * Rx * Ry: z -> Ry(90) -> x -> Rx(90) -> x.
        let fork = Rotation3::from_axis_angle(&Vector3::x_axis(), 90f64.to_radians())
            * Rotation3::from_axis_angle(&Vector3::y_axis(), 90f64.to_radians());
        assert!((fork * Vector3::z() - Vector3::x()).norm() < 1e-15);
        // Quaternion.Euler(0, 90, 0) * forward = right.
        assert!((unity_euler(0.0, 90.0, 0.0) * Vector3::z() - Vector3::x()).norm() < 1e-15);
        // A 10-degree tilt about x and a 90-degree turn about y. The top (0, 2, 0) of a 2 m
        // tall object: Rx(10) gives (0, 2 cos 10, 2 sin 10), then Ry(90) (z -> x) gives
        // (2 sin 10, 2 cos 10, 0) in Unity's order; the fork's Rx(10) * Ry(90) leaves it at
        // (0, 2 cos 10, 2 sin 10). They are 2 sqrt(2) sin 10 deg = 0.49 m apart.
        let unity = unity_euler(10.0, 90.0, 0.0);
        let fork = Rotation3::from_axis_angle(&Vector3::x_axis(), 10f64.to_radians())
            * Rotation3::from_axis_angle(&Vector3::y_axis(), 90f64.to_radians());
        let top = Vector3::new(0.0, 2.0, 0.0);
        let s = 10f64.to_radians().sin();
        let c = 10f64.to_radians().cos();
        assert!((unity * top - Vector3::new(2.0 * s, 2.0 * c, 0.0)).norm() < 1e-15);
        assert!((fork * top - Vector3::new(0.0, 2.0 * c, 2.0 * s)).norm() < 1e-15);
        let moved = (unity * top - fork * top).norm();
        assert!((moved - 2.0 * 2f64.sqrt() * s).abs() < 1e-15, "{moved}");
    }

    #[test]
    fn upright_objects_turn_by_180_minus_their_unity_yaw() {
        // Rotation (0, y, 0): the object pose (T * Rx(-90)) is Rz(180 - y) about world z,
        // so yaw 0 in Unity faces the object's front (-y) to world +y.
        for y in [0.0, 90.0, 180.0, 270.0, 33.0] {
            let pose = sstk_rotation(0.0, y, 0.0) * object_from_asset().inverse();
            let expected = Rotation3::from_axis_angle(&Vector3::z_axis(), (180.0 - y).to_radians());
            assert!((pose.matrix() - expected.matrix()).norm() < 1e-14, "{y}");
        }
        let front = sstk_rotation(0.0, 0.0, 0.0) * object_from_asset().inverse() * OBJECT_FRONT;
        assert!((front - Vector3::y()).norm() < 1e-15);
        // A tilt about Unity's x is a tilt about the pose's own x: Rz(180) * Rx(x) * Ry(z)
        // (conjugating Unity's axes by Rx(90): y -> z, x -> x, z -> -y).
        let pose = sstk_rotation(20.0, 0.0, 30.0) * object_from_asset().inverse();
        let about = |a: Vector3, d: Real| {
            Rotation3::from_axis_angle(&sceneeval_geom::na::Unit::new_normalize(a), d.to_radians())
        };
        let expected = about(Vector3::z(), 180.0) * about(Vector3::x(), 20.0) * about(Vector3::y(), 30.0);
        assert!((pose.matrix() - expected.matrix()).norm() < 1e-14);
        assert!((pose.matrix().determinant() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn objaverse_ids_are_32_hex_digits() {
        assert!(is_objaverse("0123456789abcdef0123456789ABCDEF"));
        assert!(!is_objaverse("Bed_12"));
        assert!(!is_objaverse("0123456789abcdef0123456789abcdeg"));
    }
}
