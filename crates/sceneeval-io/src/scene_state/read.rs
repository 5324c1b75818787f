//! Reading sceneState JSON into a [`Scene`].

use std::collections::HashMap;
use std::path::Path;

use sceneeval_geom::na::{Quaternion, Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Point2, Polygon2, Real, Side, Vector3};
use sceneeval_scene::{
    ArchElement, Ceiling, Element, Floor, Opening, Room, Scene, SceneError, SceneObject, SupportType,
    WallSpec,
};
use serde_json::{Map, Value};

use super::json_in::{Doc, optional, parse, ptr_index, ptr_key};
use super::keys::{OBJECT_KEYS, similar};
use super::{ARCH_VERSION, FORMAT, SCENE_VERSION, derived_object_id};
use crate::frames::{FrameError, ObjectFront, PlacedObject, TransformFrame};
use crate::{AssetLibrary, IoError, MissingAsset};

/// What to do about architecture when reading a sceneState file.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ArchitectureMode {
    /// Use `scene.arch`; when the file has no `arch` at all, build the reference's simple
    /// architecture around the objects (see [`ReadOptions`]). The reference's default.
    #[default]
    FileOrSimple,
    /// Use `scene.arch`; when the file has none, the scene has no rooms.
    FileOnly,
    /// Ignore `scene.arch` and always build the simple architecture (the reference's
    /// `method_use_simple_architecture`).
    AlwaysSimple,
}

/// Where the simple architecture's floor goes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SimpleFloorHeight {
    /// At the lowest point of any object, as the reference does (so the lowest object always
    /// stands on the floor).
    #[default]
    LowestObject,
    /// At world `z = 0`.
    Zero,
}

/// Options for [`read_scene_state`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ReadOptions {
    /// What to do about architecture.
    pub architecture: ArchitectureMode,
    /// Height of the simple architecture's walls (the reference's 3 m).
    pub simple_wall_height_m: Real,
    /// Where the simple architecture's floor goes.
    pub simple_floor: SimpleFloorHeight,
    /// Refuse a file with keys the sceneState format does not have
    /// ([`IoError::UnknownKeys`]) instead of warning about each (default `false`). Whether a
    /// scene is read strictly does not change what is read, so it is not part of a plan file
    /// or of a result's fingerprint: it is set by the caller (`--strict`, `strict=True`).
    #[serde(skip)]
    pub strict: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            architecture: ArchitectureMode::default(),
            simple_wall_height_m: 3.0,
            simple_floor: SimpleFloorHeight::default(),
            strict: false,
        }
    }
}

impl ReadOptions {
    /// These options, reading strictly or not (see [`ReadOptions::strict`]).
    pub fn with_strict(mut self, strict: bool) -> Self {
        self.strict = strict;
        self
    }
}

/// Reads the sceneState file at `path`, loading asset meshes through `assets`. The scene is
/// named after the file's stem (`scene_12.json` -> `scene_12`).
///
/// Keys the format does not have ([`super::unknown_keys`]: a misspelt `"transfrom"`, say) are
/// each logged as one warning naming the file, the key's first JSON pointer, how often it
/// occurs and the known key it resembles; with [`ReadOptions::strict`] they are an error
/// listing them all.
///
/// # Errors
/// Every problem is an [`IoError`] naming the file and the JSON pointer of the offending value
/// (see the crate docs for the list); nothing panics. A file larger than the library's
/// [`crate::Limits::max_file_bytes`] is [`IoError::TooLarge`]; one that is not UTF-8 is
/// [`IoError::InvalidUtf8`] with the byte offset, line and column of the first bad byte.
pub fn read_scene_state(path: &Path, assets: &AssetLibrary, options: &ReadOptions) -> Result<Scene, IoError> {
    let bytes = crate::uri::read_file_limited(path, assets.limits().max_file_bytes)?;
    let text = IoError::utf8(path, &bytes)?;
    read_scene_state_str(text, path, assets, options)
}

/// Reads sceneState JSON `text` (asset files are still read through `assets`); `path` only
/// names the text in errors and gives the scene's name (its stem).
///
/// # Errors
/// As [`read_scene_state`].
pub fn read_scene_state_str(
    text: &str,
    path: &Path,
    assets: &AssetLibrary,
    options: &ReadOptions,
) -> Result<Scene, IoError> {
    let doc = Doc { path };
    let root = parse(text, path)?;
    report_unknown_keys(&doc, &root, options.strict)?;
    let root = doc.object(&root, "")?;
    let format = doc.required(root, "", "format")?;
    if doc.string(format, "/format")? != FORMAT {
        return Err(doc.invalid("/format", format!("expected \"{FORMAT}\", found {format}")));
    }
    let scene = doc.object(doc.required(root, "", "scene")?, "/scene")?;
    check_version(&doc, scene, "/scene", SCENE_VERSION);

    let scene_front = read_front(&doc, scene, "/scene")?.unwrap_or_default();
    let objects = read_objects(&doc, scene, assets, scene_front)?;
    let arch = optional(scene, "arch");
    let rooms = match (options.architecture, arch) {
        (ArchitectureMode::AlwaysSimple, _) | (ArchitectureMode::FileOrSimple, None) => {
            simple_architecture(&doc, &objects, options)?
        }
        (ArchitectureMode::FileOnly, None) => Vec::new(),
        (_, Some(arch)) => read_arch(&doc, arch)?,
    };
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    Scene::new(name, objects, rooms).map_err(|source| IoError::Scene {
        path: doc.path_buf(),
        pointer: "/scene".into(),
        source,
    })
}

/// Warns about each key the format does not have (once per key and place of the format), or
/// with `strict` refuses the file.
fn report_unknown_keys(doc: &Doc<'_>, root: &Value, strict: bool) -> Result<(), IoError> {
    let keys = super::unknown_keys(root);
    if keys.is_empty() {
        return Ok(());
    }
    if strict {
        return Err(IoError::UnknownKeys {
            path: doc.path_buf(),
            keys,
        });
    }
    for k in &keys {
        tracing::warn!(
            file = %doc.path.display(),
            pointer = %k.pointer,
            key = %k.key,
            occurrences = k.occurrences,
            "{k}: not a sceneState key here, ignored (a misspelt key is read as absent)"
        );
    }
    Ok(())
}

fn check_version(doc: &Doc<'_>, o: &Map<String, Value>, ptr: &str, expected: &str) {
    match optional(o, "version").and_then(Value::as_str) {
        Some(v) if v != expected => tracing::warn!(
            file = %doc.path.display(),
            pointer = %ptr_key(ptr, "version"),
            "version {v:?}, this reader follows {expected:?}"
        ),
        Some(_) => {}
        None => tracing::debug!(file = %doc.path.display(), pointer = ptr, "no version"),
    }
}

// ------------------------------------------------------------------------------------------
// Objects

/// The `objectFrontVector` of the JSON object at `ptr`, if it has one.
fn read_front(doc: &Doc<'_>, o: &Map<String, Value>, ptr: &str) -> Result<Option<ObjectFront>, IoError> {
    let Some(v) = optional(o, "objectFrontVector") else {
        return Ok(None);
    };
    let p = ptr_key(ptr, "objectFrontVector");
    let v = doc.numbers::<3>(v, &p, "an array of 3 numbers")?;
    ObjectFront::from_vector(v)
        .map(Some)
        .map_err(|reason| doc.invalid(&p, format!("objectFrontVector {reason}")))
}

/// Whether the object entry at `ptr` is marked `isArchitecture: true` (part of the building,
/// which the reader leaves out before looking up any asset).
fn is_architecture(doc: &Doc<'_>, o: &Map<String, Value>, ptr: &str) -> Result<bool, IoError> {
    match optional(o, "isArchitecture") {
        None => Ok(false),
        Some(Value::Bool(b)) => Ok(*b),
        Some(v) => Err(doc.wrong(&ptr_key(ptr, "isArchitecture"), "a boolean", v)),
    }
}

fn read_objects(
    doc: &Doc<'_>,
    scene: &Map<String, Value>,
    assets: &AssetLibrary,
    scene_front: ObjectFront,
) -> Result<Vec<SceneObject>, IoError> {
    let Some(list) = optional(scene, "object") else {
        return Ok(Vec::new());
    };
    let list = doc.array(list, "/scene/object")?;
    let mut seen: HashMap<String, String> = HashMap::with_capacity(list.len());
    let mut objects = Vec::with_capacity(list.len());
    let mut architecture = 0usize;
    let mut missing = Vec::new();
    for (i, entry) in list.iter().enumerate() {
        let ptr = ptr_index("/scene/object", i);
        if is_architecture(doc, doc.object(entry, &ptr)?, &ptr)? {
            architecture += 1;
            continue;
        }
        let object = match read_object(doc, entry, &ptr, i, assets, scene_front) {
            Ok(object) => object,
            // Every missing asset is listed, not only the first: read on.
            Err(e) => {
                missing_asset(e, &mut missing)?;
                continue;
            }
        };
        if let Some(first) = seen.insert(object.id().to_string(), ptr.clone()) {
            return Err(IoError::DuplicateObjectId {
                path: doc.path_buf(),
                id: object.id().to_string(),
                first,
                second: ptr,
            });
        }
        objects.push(object);
    }
    if architecture > 0 {
        tracing::warn!(
            file = %doc.path.display(),
            left_out = architecture,
            kept = objects.len(),
            "object entries marked isArchitecture left out: {architecture} (part of the building, not furniture)"
        );
    }
    if !missing.is_empty() {
        return Err(IoError::MissingAssets {
            path: doc.path_buf(),
            missing,
        });
    }
    Ok(objects)
}

/// Records `e` in `missing` when it is an object's asset that was not found; returns any other
/// error.
fn missing_asset(e: IoError, missing: &mut Vec<MissingAsset>) -> Result<(), IoError> {
    let IoError::ObjectAsset {
        path,
        pointer,
        model_id,
        source,
    } = e
    else {
        return Err(e);
    };
    let tried = match *source {
        IoError::AssetNotFound { tried, .. } => tried,
        other => {
            return Err(IoError::ObjectAsset {
                path,
                pointer,
                model_id,
                source: Box::new(other),
            });
        }
    };
    match missing.iter_mut().find(|m| m.model_id == model_id) {
        Some(m) => m.objects.push(pointer),
        None => missing.push(MissingAsset {
            model_id,
            objects: vec![pointer],
            tried,
        }),
    }
    Ok(())
}

fn bad_transform(doc: &Doc<'_>, data_ptr: &str, e: &FrameError) -> IoError {
    let pointer = match e {
        FrameError::NonFinite { index, .. } => ptr_index(data_ptr, *index),
        _ => data_ptr.to_owned(),
    };
    IoError::BadTransform {
        path: doc.path_buf(),
        pointer,
        reason: e.to_string(),
    }
}

fn read_object(
    doc: &Doc<'_>,
    entry: &Value,
    ptr: &str,
    position: usize,
    assets: &AssetLibrary,
    scene_front: ObjectFront,
) -> Result<SceneObject, IoError> {
    let o = doc.object(entry, ptr)?;
    let front = read_front(doc, o, ptr)?.unwrap_or(scene_front);
    let field = |key: &str| optional(o, key).map(|v| (v, ptr_key(ptr, key)));
    let index = match field("index") {
        Some((v, p)) => doc.integer(v, &p)?,
        None => position as i64,
    };
    let model_id = field("modelId").map(|(v, p)| doc.string(v, &p)).transpose()?;
    let text_field = |key: &str| {
        field(key)
            .map(|(v, p)| doc.string(v, &p).map(str::to_owned))
            .transpose()
    };
    let category = text_field("category")?;
    let description = text_field("description")?;
    let support_type = field("supportType")
        .map(|(v, p)| {
            doc.string(v, &p)?
                .parse::<SupportType>()
                .map_err(|e| doc.invalid(&p, e.to_string()))
        })
        .transpose()?;
    let functional_sides = field("functionalSides")
        .map(|(v, p)| functional_sides(doc, v, &p))
        .transpose()?;
    let id = text_field("objectId")?.unwrap_or_else(|| derived_object_id(index, model_id));

    let box_size = match field("box") {
        Some((v, p)) => {
            let b = doc.object(v, &p)?;
            let size_ptr = ptr_key(&p, "size");
            let size = doc.numbers::<3>(doc.required(b, &p, "size")?, &size_ptr, "an array of 3 numbers")?;
            if let Some(k) = size.iter().position(|&s| s < 0.0) {
                return Err(doc.invalid(
                    &ptr_index(&size_ptr, k),
                    format!("box size {} is negative", size[k]),
                ));
            }
            Some(Vector3::from(size))
        }
        None => None,
    };
    if box_size.is_none() && model_id.is_none() {
        return Err(IoError::MissingField {
            path: doc.path_buf(),
            pointer: ptr.to_owned(),
            field: "modelId",
        });
    }

    let data_ptr = ptr_key(&ptr_key(ptr, "transform"), "data");
    let data = match field("transform") {
        None => {
            let misspelt = o
                .keys()
                .filter(|k| !OBJECT_KEYS.contains(&k.as_str()))
                .find(|k| similar(k, &["transform"]).is_some());
            return Err(IoError::MissingTransform {
                path: doc.path_buf(),
                pointer: ptr.to_owned(),
                index,
                id,
                similar: misspelt.cloned().unwrap_or_default(),
            });
        }
        Some((v, p)) => {
            let t = doc.object(v, &p)?;
            doc.numbers::<16>(doc.required(t, &p, "data")?, &data_ptr, "an array of 16 numbers")?
        }
    };
    let is_box = box_size.is_some();
    // Boxes, and assets of the z-up generators, have transforms in the object frame.
    let frame = match model_id {
        Some(m) if !is_box => TransformFrame::for_model_id(m),
        _ => TransformFrame::Object,
    };
    let placed = frame
        .placed(&data)
        .map_err(|e| bad_transform(doc, &data_ptr, &e))?;
    // The model's pose (turned so that local -y is the declared front), and the scale applied
    // to the geometry and the scale recorded on the object, both in the file's object frame
    // (before the turn). A box written by this crate has its scale already in its size and a
    // rigid transform; its `objectPose.scale` only records the scale that was baked in.
    let unturned = (front.model_pose(&placed.pose), placed.scale, placed.scale);
    let (pose, applied_scale, recorded_scale) = match field("objectPose") {
        Some((v, p)) => match exact_pose(doc, v, &p, &data, frame, is_box, front)? {
            Some(exact) if is_box => (exact.pose, Vector3::repeat(1.0), exact.scale),
            Some(exact) => (exact.pose, exact.scale, exact.scale),
            None => unturned,
        },
        None => unturned,
    };
    let recorded_scale = front.turn_scale(&recorded_scale);

    let scene_err = |source: SceneError| IoError::Scene {
        path: doc.path_buf(),
        pointer: ptr.to_owned(),
        source,
    };
    let unit = Vector3::repeat(1.0);
    let mut object = match box_size {
        Some(size) => {
            let half = front.turn_scale(&(size * 0.5).component_mul(&applied_scale.abs()));
            let obj = SceneObject::new_box(id, half, pose).map_err(scene_err)?;
            if let Some(m) = model_id {
                obj.with_model_id(m)
            } else {
                obj
            }
        }
        None => {
            // `model_id` is present: checked above.
            let model_id = model_id.unwrap_or_default();
            let wrap = |source: IoError| IoError::ObjectAsset {
                path: doc.path_buf(),
                pointer: ptr.to_owned(),
                model_id: model_id.to_owned(),
                source: Box::new(source),
            };
            let asset = assets.asset(model_id).map_err(wrap)?;
            let mesh = assets
                .mesh_facing(model_id, &applied_scale, front)
                .map_err(wrap)?;
            let obj = SceneObject::from_mesh(id, mesh, pose)
                .map_err(scene_err)?
                .with_model_id(model_id);
            let obj = match (&category, &asset.info.category) {
                (None, Some(c)) => obj.with_category(c.clone()),
                _ => obj,
            };
            match (&description, &asset.info.description) {
                (None, Some(d)) => obj.with_description(d.clone()),
                _ => obj,
            }
        }
    };
    object = object.with_index(index);
    if recorded_scale != unit {
        object = object.with_scale(recorded_scale);
    }
    if front != ObjectFront::MinusY {
        object = object.with_asset_front(front.vector());
    }
    if let Some(c) = category {
        object = object.with_category(c);
    }
    if let Some(d) = description {
        object = object.with_description(d);
    }
    if let Some(t) = support_type {
        object = object.with_support_type(t);
    }
    if let Some(sides) = functional_sides {
        object = object.with_functional_sides(sides);
    }
    Ok(object)
}

/// The `functionalSides` of an object: an array of horizontal side names (possibly empty).
fn functional_sides(doc: &Doc<'_>, v: &Value, ptr: &str) -> Result<Vec<Side>, IoError> {
    doc.array(v, ptr)?
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let p = ptr_index(ptr, i);
            let side = doc
                .string(s, &p)?
                .parse::<Side>()
                .map_err(|e| doc.invalid(&p, e.to_string()))?;
            if Side::HORIZONTAL.contains(&side) {
                Ok(side)
            } else {
                Err(doc.invalid(
                    &p,
                    format!(
                        "functional side {side:?} is not horizontal: expected left, right, front or back"
                    ),
                ))
            }
        })
        .collect()
}

/// The exact pose from `objectPose` (written by this crate), if it reproduces
/// `transform.data` exactly; `None` (with a debug message) when it does not, e.g. because the
/// matrix was edited by hand. `objectPose` holds the model's pose and scale (after the turn
/// to the declared `front`); the result has the model's pose and the scale in the file's
/// object frame.
fn exact_pose(
    doc: &Doc<'_>,
    v: &Value,
    ptr: &str,
    data: &[Real; 16],
    frame: TransformFrame,
    is_box: bool,
    front: ObjectFront,
) -> Result<Option<PlacedObject>, IoError> {
    let o = doc.object(v, ptr)?;
    let rotation_ptr = ptr_key(ptr, "rotation");
    let q = doc.numbers::<4>(
        doc.required(o, ptr, "rotation")?,
        &rotation_ptr,
        "an array of 4 numbers",
    )?;
    let scale = match optional(o, "scale") {
        Some(s) => Vector3::from(doc.numbers::<3>(s, &ptr_key(ptr, "scale"), "an array of 3 numbers")?),
        None => Vector3::repeat(1.0),
    };
    let quaternion = Quaternion::new(q[3], q[0], q[1], q[2]);
    if (quaternion.norm() - 1.0).abs() > 1e-9 {
        tracing::debug!(file = %doc.path.display(), pointer = ptr, "objectPose rotation is not a unit quaternion; ignored");
        return Ok(None);
    }
    let pose = Isometry3::from_parts(
        Translation3::new(data[12], data[13], data[14]),
        UnitQuaternion::new_unchecked(quaternion),
    );
    let scale = front.turn_scale(&scale);
    let applied = if is_box { Vector3::repeat(1.0) } else { scale };
    let recomposed = frame.sstk(&front.file_pose(&pose), &applied);
    if recomposed == *data {
        Ok(Some(PlacedObject { pose, scale }))
    } else {
        tracing::debug!(file = %doc.path.display(), pointer = ptr, "objectPose does not match transform.data; using the matrix");
        Ok(None)
    }
}

// ------------------------------------------------------------------------------------------
// Architecture

struct FloorElement {
    ptr: String,
    id: Option<String>,
    room: String,
    kind: Option<String>,
    polygon: Polygon2,
    z: Real,
}

struct CeilingElement {
    ptr: String,
    id: Option<String>,
    room: Option<String>,
    polygon: Polygon2,
    z: Real,
}

struct WallElement {
    ptr: String,
    room: Option<String>,
    spec: WallSpec,
    hole_ptrs: Vec<String>,
}

fn read_arch(doc: &Doc<'_>, arch: &Value) -> Result<Vec<Room>, IoError> {
    let arch = doc.object(arch, "/scene/arch")?;
    check_version(doc, arch, "/scene/arch", ARCH_VERSION);
    let Some(elements) = optional(arch, "elements") else {
        return Ok(Vec::new());
    };
    let elements = doc.array(elements, "/scene/arch/elements")?;
    let mut floors: Vec<FloorElement> = Vec::new();
    let mut ceilings: Vec<CeilingElement> = Vec::new();
    let mut walls: Vec<WallElement> = Vec::new();
    for (k, e) in elements.iter().enumerate() {
        let ptr = ptr_index("/scene/arch/elements", k);
        let o = doc.object(e, &ptr)?;
        let type_ptr = ptr_key(&ptr, "type");
        let kind = doc.string(doc.required(o, &ptr, "type")?, &type_ptr)?;
        // sceneState's elements are floors, ceilings and walls (doors and windows are holes).
        let kind = match ArchElement::from_name(&kind.to_ascii_lowercase()) {
            Some(k @ (ArchElement::Floor | ArchElement::Ceiling | ArchElement::Wall)) => k,
            _ => {
                return Err(doc.invalid(
                    &type_ptr,
                    format!("unknown element type {kind:?} (expected Floor, Ceiling or Wall)"),
                ));
            }
        };
        let id = optional(o, "id")
            .map(|v| doc.id(v, &ptr_key(&ptr, "id")))
            .transpose()?;
        let room = optional(o, "roomId")
            .map(|v| doc.id(v, &ptr_key(&ptr, "roomId")))
            .transpose()?;
        match kind {
            ArchElement::Floor => {
                let Some(room) = room else {
                    return Err(IoError::MissingField {
                        path: doc.path_buf(),
                        pointer: ptr,
                        field: "roomId",
                    });
                };
                if let Some(first) = floors.iter().find(|f| f.room == room) {
                    return Err(IoError::DuplicateElement {
                        path: doc.path_buf(),
                        pointer: ptr,
                        first: first.ptr.clone(),
                        what: format!("second Floor for room {room:?}"),
                    });
                }
                let kind = optional(o, "roomType")
                    .map(|v| doc.string(v, &ptr_key(&ptr, "roomType")).map(str::to_owned))
                    .transpose()?;
                let (polygon, z) = read_polygon(doc, o, &ptr, "floor")?;
                floors.push(FloorElement {
                    ptr,
                    id,
                    room,
                    kind,
                    polygon,
                    z,
                });
            }
            ArchElement::Ceiling => {
                let (polygon, z) = read_polygon(doc, o, &ptr, "ceiling")?;
                ceilings.push(CeilingElement {
                    ptr,
                    id,
                    room,
                    polygon,
                    z,
                });
            }
            // A wall, the only other kind let through above.
            _ => {
                let id = id.unwrap_or_else(|| format!("wall_{k}"));
                if let Some(first) = walls.iter().find(|w| w.spec.id == id) {
                    return Err(IoError::DuplicateElement {
                        path: doc.path_buf(),
                        pointer: ptr,
                        first: first.ptr.clone(),
                        what: format!("wall id {id:?} is used twice"),
                    });
                }
                walls.push(read_wall(doc, o, ptr, id, room)?);
            }
        }
    }
    assemble_rooms(doc, floors, ceilings, walls)
}

/// Reads the `points` of a Floor or Ceiling: at least 3 `[x, y, z]`, a simple polygon, one z.
fn read_polygon(
    doc: &Doc<'_>,
    o: &Map<String, Value>,
    ptr: &str,
    what: &str,
) -> Result<(Polygon2, Real), IoError> {
    let points_ptr = ptr_key(ptr, "points");
    let points = read_points(doc, doc.required(o, ptr, "points")?, &points_ptr)?;
    if points.len() < 3 {
        return Err(doc.invalid(
            &points_ptr,
            format!("a {what} polygon needs at least 3 points, got {}", points.len()),
        ));
    }
    let z = common_z(doc, &points, &points_ptr);
    let polygon = Polygon2::new(points.iter().map(|p| Point2::new(p[0], p[1])).collect())
        .map_err(|e| doc.invalid(&points_ptr, format!("{what} polygon: {e}")))?;
    Ok((polygon, z))
}

fn read_points(doc: &Doc<'_>, v: &Value, ptr: &str) -> Result<Vec<[Real; 3]>, IoError> {
    doc.array(v, ptr)?
        .iter()
        .enumerate()
        .map(|(i, p)| doc.numbers::<3>(p, &ptr_index(ptr, i), "an [x, y, z] array of 3 numbers"))
        .collect()
}

/// The z shared by `points`; if they differ, their mean (with a warning): floors, ceilings
/// and wall bases are horizontal in the scene model.
fn common_z(doc: &Doc<'_>, points: &[[Real; 3]], ptr: &str) -> Real {
    let z0 = points.first().map_or(0.0, |p| p[2]);
    if points.iter().all(|p| p[2] == z0) {
        return z0;
    }
    let mean = points.iter().map(|p| p[2]).sum::<Real>() / points.len() as Real;
    tracing::warn!(file = %doc.path.display(), pointer = ptr, mean, "points have different z; using their mean");
    mean
}

fn read_wall(
    doc: &Doc<'_>,
    o: &Map<String, Value>,
    ptr: String,
    id: String,
    room: Option<String>,
) -> Result<WallElement, IoError> {
    let points_ptr = ptr_key(&ptr, "points");
    let points = read_points(doc, doc.required(o, &ptr, "points")?, &points_ptr)?;
    if points.len() != 2 {
        return Err(doc.invalid(
            &points_ptr,
            format!("a wall needs exactly 2 points, got {}", points.len()),
        ));
    }
    let base_z = common_z(doc, &points, &points_ptr);
    let height = doc.number(doc.required(o, &ptr, "height")?, &ptr_key(&ptr, "height"))?;
    let thickness = optional(o, "depth")
        .map(|v| doc.number(v, &ptr_key(&ptr, "depth")))
        .transpose()?
        .unwrap_or(0.0);
    let mut spec = WallSpec::new(
        id.clone(),
        Point2::new(points[0][0], points[0][1]),
        Point2::new(points[1][0], points[1][1]),
        base_z,
        height,
        thickness,
    );
    let mut hole_ptrs: Vec<String> = Vec::new();
    if let Some(holes) = optional(o, "holes") {
        let holes_ptr = ptr_key(&ptr, "holes");
        for (h, hole) in doc.array(holes, &holes_ptr)?.iter().enumerate() {
            let hptr = ptr_index(&holes_ptr, h);
            let ho = doc.object(hole, &hptr)?;
            let type_ptr = ptr_key(&hptr, "type");
            let kind = doc.string(doc.required(ho, &hptr, "type")?, &type_ptr)?;
            let kind = match ArchElement::from_name(&kind.to_ascii_lowercase()).and_then(ArchElement::opening)
            {
                Some(kind) => kind,
                None => {
                    tracing::warn!(file = %doc.path.display(), pointer = %type_ptr, "skipping a hole of type {kind:?} (not Door or Window)");
                    continue;
                }
            };
            let box_ptr = ptr_key(&hptr, "box");
            let b = doc.object(doc.required(ho, &hptr, "box")?, &box_ptr)?;
            let min = doc.numbers::<2>(
                doc.required(b, &box_ptr, "min")?,
                &ptr_key(&box_ptr, "min"),
                "an array of 2 numbers",
            )?;
            let max = doc.numbers::<2>(
                doc.required(b, &box_ptr, "max")?,
                &ptr_key(&box_ptr, "max"),
                "an array of 2 numbers",
            )?;
            let opening_id = match optional(ho, "id") {
                Some(v) => doc.id(v, &ptr_key(&hptr, "id"))?,
                None => {
                    let k = spec.openings.iter().filter(|o| o.kind == kind).count();
                    format!("{id}_{}_{k}", kind.name())
                }
            };
            if let Some(first) = spec.openings.iter().position(|o| o.id == opening_id) {
                return Err(IoError::DuplicateElement {
                    path: doc.path_buf(),
                    pointer: hptr,
                    first: hole_ptrs[first].clone(),
                    what: format!("opening id {opening_id:?} is used twice in wall {id:?}"),
                });
            }
            spec.openings
                .push(Opening::new(opening_id, kind, [min[0], max[0]], [min[1], max[1]]));
            hole_ptrs.push(hptr);
        }
    }
    Ok(WallElement {
        ptr,
        room,
        spec,
        hole_ptrs,
    })
}

/// The index of the floor that `room` names, or else of the floor nearest to `p` (with a
/// warning naming the element at `ptr`); `None` when there are no floors.
fn room_for(
    doc: &Doc<'_>,
    floors: &[FloorElement],
    room: Option<&str>,
    p: Point2,
    ptr: &str,
) -> Option<usize> {
    if let Some(i) = room.and_then(|r| floors.iter().position(|f| f.room == r)) {
        return Some(i);
    }
    let distance = |f: &FloorElement| {
        if f.polygon.contains_point(&p) {
            0.0
        } else {
            f.polygon.distance_to_boundary(&p)
        }
    };
    let nearest = (0..floors.len()).min_by(|&a, &b| distance(&floors[a]).total_cmp(&distance(&floors[b])))?;
    tracing::warn!(
        file = %doc.path.display(),
        pointer = ptr,
        room = ?room,
        attached_to = %floors[nearest].room,
        "no Floor for this element's roomId; attached to the room whose floor is nearest"
    );
    Some(nearest)
}

fn assemble_rooms(
    doc: &Doc<'_>,
    floors: Vec<FloorElement>,
    ceilings: Vec<CeilingElement>,
    walls: Vec<WallElement>,
) -> Result<Vec<Room>, IoError> {
    let mut room_walls: Vec<Vec<WallElement>> = floors.iter().map(|_| Vec::new()).collect();
    for w in walls {
        let mid = Point2::from((w.spec.start.coords + w.spec.end.coords) * 0.5);
        let Some(i) = room_for(doc, &floors, w.room.as_deref(), mid, &w.ptr) else {
            return Err(doc.invalid(&w.ptr, "the file has no Floor element to attach this wall to"));
        };
        room_walls[i].push(w);
    }
    let mut room_ceilings: Vec<Option<CeilingElement>> = floors.iter().map(|_| None).collect();
    for c in ceilings {
        let Some(i) = room_for(doc, &floors, c.room.as_deref(), c.polygon.centroid(), &c.ptr) else {
            return Err(doc.invalid(&c.ptr, "the file has no Floor element to attach this ceiling to"));
        };
        if let Some(first) = &room_ceilings[i] {
            return Err(IoError::DuplicateElement {
                path: doc.path_buf(),
                pointer: c.ptr,
                first: first.ptr.clone(),
                what: format!("second Ceiling for room {:?}", floors[i].room),
            });
        }
        room_ceilings[i] = Some(c);
    }
    let mut rooms = Vec::with_capacity(floors.len());
    for ((floor, walls), ceiling) in floors.into_iter().zip(room_walls).zip(room_ceilings) {
        // The reference ignores Ceiling elements; one at or below its floor is dropped with a
        // warning (the room's ceiling then comes from its walls) rather than failing the scene.
        let ceiling = ceiling.filter(|c| {
            let above = c.z > floor.z;
            if !above {
                tracing::warn!(
                    file = %doc.path.display(),
                    pointer = %c.ptr,
                    ceiling_z = c.z,
                    floor_z = floor.z,
                    room = %floor.room,
                    "the Ceiling is not above its room's Floor; ignored (the ceiling comes from the walls)"
                );
            }
            above
        });
        let ceiling_ptr = ceiling.as_ref().map(|c| c.ptr.clone());
        let ceiling = ceiling.map(|c| Ceiling {
            id: c.id.unwrap_or_else(|| format!("ceiling_{}", floor.room)),
            polygon: c.polygon,
            z: c.z,
        });
        let specs = walls.iter().map(|w| w.spec.clone()).collect();
        let room_floor = Floor {
            id: floor
                .id
                .clone()
                .unwrap_or_else(|| format!("floor_{}", floor.room)),
            polygon: floor.polygon,
            z: floor.z,
        };
        let room = Room::new(floor.room.clone(), room_floor, specs, ceiling).map_err(|source| {
            // The element at fault, by its position in this room's lists, to its pointer.
            let pointer = match source.element() {
                Some(Element::Wall { wall, .. }) => walls.get(wall).map(|w| w.ptr.clone()),
                Some(Element::Opening { wall, opening, .. }) => walls
                    .get(wall)
                    .and_then(|w| w.hole_ptrs.get(opening).or(Some(&w.ptr)))
                    .cloned(),
                Some(Element::Ceiling { .. }) => ceiling_ptr.clone(),
                _ => None,
            }
            .unwrap_or_else(|| floor.ptr.clone());
            IoError::Scene {
                path: doc.path_buf(),
                pointer,
                source,
            }
        })?;
        rooms.push(match floor.kind {
            Some(k) => room.with_kind(k),
            None => room,
        });
    }
    Ok(rooms)
}

/// The reference's simple architecture: a floor over the objects' plan bounds and four walls
/// along its edges (`wall_0` at max y, `wall_1` at min x, `wall_2` at min y, `wall_3` at max
/// x), `simple_wall_height_m` high, in a room `room` with floor id `floor`.
fn simple_architecture(
    doc: &Doc<'_>,
    objects: &[SceneObject],
    options: &ReadOptions,
) -> Result<Vec<Room>, IoError> {
    let Some(bounds) = objects.iter().map(|o| *o.world_aabb()).reduce(|a, b| a.union(&b)) else {
        tracing::warn!("no objects to build the simple architecture around; the scene has no rooms");
        return Ok(Vec::new());
    };
    let (min, max) = (bounds.min, bounds.max);
    if !(max.x > min.x && max.y > min.y) {
        tracing::warn!("the objects' plan bounds have no area; the scene has no rooms");
        return Ok(Vec::new());
    }
    let z = match options.simple_floor {
        SimpleFloorHeight::LowestObject => min.z,
        SimpleFloorHeight::Zero => 0.0,
    };
    let corner = |x: Real, y: Real| Point2::new(x, y);
    let floor = [
        corner(min.x, min.y),
        corner(max.x, min.y),
        corner(max.x, max.y),
        corner(min.x, max.y),
    ];
    let edges = [(2, 3), (3, 0), (0, 1), (1, 2)];
    let walls = edges
        .iter()
        .enumerate()
        .map(|(i, &(a, b))| {
            WallSpec::new(
                format!("wall_{i}"),
                floor[a],
                floor[b],
                z,
                options.simple_wall_height_m,
                0.0,
            )
        })
        .collect();
    let scene_error = |source: SceneError| IoError::Scene {
        path: doc.path_buf(),
        pointer: "/scene".into(),
        source,
    };
    let polygon = Polygon2::new(floor.to_vec()).map_err(|source| {
        scene_error(SceneError::Geometry {
            element: Box::new(Element::Floor { room: "room".into() }),
            source,
        })
    })?;
    let floor = Floor {
        id: "floor".into(),
        polygon,
        z,
    };
    let room = Room::new("room", floor, walls, None).map_err(scene_error)?;
    Ok(vec![room])
}
