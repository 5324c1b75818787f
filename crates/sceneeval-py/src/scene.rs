//! Scenes from Python: built from numpy arrays of boxes and a room, or loaded from sceneState
//! files with asset folders; inspected as plain values; scored by the plausibility metrics and
//! the predicates.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{PoisonError, RwLock};

use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyInt, PyList, PyTuple};
use sceneeval::geom::conventions::pose_from_yaw;
use sceneeval::geom::{Point3, Vector3};
use sceneeval::inspect::{ObjectInfo, RoomInfo, SceneInfo};
use sceneeval::io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval::physics::WeldMode;
use sceneeval::relations::{Query, Relation, SceneRelations};
use sceneeval::scene::{Category, Room, Scene, SceneObject};
use sceneeval::{EvaluationPlan, Evaluator, ObjectPlacement, PlanRequest, SceneInputs, SettleRequest};

use crate::convert::{rows, to_json, to_python};
use crate::errors::{
    chain, deprecation_warning, detached, eval_error, relation_error, scene_error, value_error,
};
use crate::relations::{BOX_COLUMNS, obbs_from_rows, relation_params, room_from_json, room_spec};
use crate::run::{asset_specs, metrics_of, plan_and_preset, request_error, vlm_options};

/// A scene: objects (boxes or meshes) and rooms with walls, doors and windows.
///
/// Build one from boxes with Scene.from_boxes or load a sceneState file with load_scene.
/// Objects can be moved (set_pose, set_boxes), for example in an optimisation loop; a scene
/// may be shared between threads (a move waits for the computations under way).
#[pyclass(module = "sceneeval", name = "Scene", frozen)]
pub struct PyScene {
    /// The scene. Locked only by Rust code that calls no Python (so a thread waiting for the
    /// lock never holds it while waiting for the GIL, and one holding the GIL while waiting
    /// for the lock waits only for such code): read for inspection and computations (with the
    /// GIL released), written by the moves.
    scene: RwLock<Scene>,
}

impl PyScene {
    /// A Python scene wrapping `scene`.
    pub fn new(scene: Scene) -> Self {
        PyScene {
            scene: RwLock::new(scene),
        }
    }

    /// What `stability` and `settle` share: the settled scene and the report (with
    /// `placement` when the VLM was asked), from the one request `sceneeval settle` makes too
    /// ([`SettleRequest`]).
    fn settled<'py>(
        &self,
        py: Python<'py>,
        plan: Option<PathBuf>,
        preset: Option<&str>,
        weld: Option<&str>,
        vlm: Option<&Bound<'py, PyDict>>,
        assets: Option<BTreeMap<String, PathBuf>>,
    ) -> PyResult<(PyScene, Bound<'py, PyAny>)> {
        let plan = plan.map(|p| p.to_string_lossy().into_owned());
        let (plan, preset) = plan_and_preset(py, plan.as_deref(), preset)?;
        let weld = weld
            .map(|w| {
                w.parse::<WeldMode>()
                    .map_err(|e| value_error(format!("weld: {e}")))
            })
            .transpose()?;
        let request = SettleRequest {
            assets: asset_specs(assets),
            plan: PlanRequest {
                plan,
                preset,
                ..PlanRequest::default()
            },
            weld,
            vlm: vlm.map(vlm_options).transpose()?,
            // The scene is read already: `strict` applies to reading a file.
            ..SettleRequest::default()
        };
        let prepared = detached(py, || request.prepare().map_err(|e| request_error(&e)))?;
        let settled = detached(py, || {
            self.with_scene(|scene| prepared.settle(scene))
                .map_err(|e| eval_error(&e))
        })?;
        let report = to_python(
            py,
            &StabilityWithPlacement {
                report: settled.report,
                placement: settled.placement,
            },
        )?;
        Ok((PyScene::new(settled.scene), report))
    }

    /// `f` applied to the scene, read-locked (`f` must not call Python).
    pub fn with_scene<T>(&self, f: impl FnOnce(&Scene) -> T) -> T {
        f(&self.scene.read().unwrap_or_else(PoisonError::into_inner))
    }

    /// `f` applied to the scene, write-locked: at once when no computation holds the scene,
    /// else with the GIL released while waiting.
    fn with_scene_mut<T: Send>(&self, py: Python<'_>, f: impl FnOnce(&mut Scene) -> T + Send) -> PyResult<T> {
        if let Ok(mut scene) = self.scene.try_write() {
            return Ok(f(&mut scene));
        }
        detached(py, || {
            Ok(f(&mut self.scene.write().unwrap_or_else(PoisonError::into_inner)))
        })
    }

    /// The JSON text `f` writes of the scene (under the read lock) as plain Python values
    /// (converted after the lock is released).
    fn to_python_with<'py>(
        &self,
        py: Python<'py>,
        f: impl FnOnce(&Scene) -> serde_json::Result<String>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let text = self
            .with_scene(f)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("serialising a result: {e}")))?;
        py.import("json")?.call_method1("loads", (text,))
    }
}

/// The plan for `Scene.plausibility`: as for `evaluate` (see [`PlanRequest::resolve`]),
/// geometry metrics only.
fn plausibility_plan(
    py: Python<'_>,
    plan: Option<&str>,
    preset: Option<&str>,
    metrics: Option<Vec<String>>,
) -> PyResult<EvaluationPlan> {
    let (plan, preset) = plan_and_preset(py, plan, preset)?;
    let request = PlanRequest {
        plan: plan.clone(),
        preset,
        metrics: metrics_of(metrics)?,
        ..PlanRequest::default()
    };
    // Annotations are checked below with a message for this method.
    let chosen = request.resolve(false, true).map_err(|e| request_error(&e))?;
    if chosen.plan.has_fidelity() {
        return Err(value_error(format!(
            "plan {:?} runs text-fidelity metrics (cnt, atr, oor, oar): Scene.plausibility runs the \
             geometry metrics only (evaluate a folder with sceneeval.evaluate(..., annotations=...) for those)",
            plan.unwrap_or_default()
        )));
    }
    Ok(chosen.plan)
}

/// What `Scene.stability` returns: the stability report, and with a VLM where each object's
/// support type came from.
#[derive(Debug, serde::Serialize)]
struct StabilityWithPlacement {
    #[serde(flatten)]
    report: sceneeval::physics::StabilityReport,
    #[serde(skip_serializing_if = "Option::is_none")]
    placement: Option<Vec<ObjectPlacement>>,
}

/// An asset library from `{prefix: folder}` (a folder may be written `LAYOUT:folder`).
fn asset_library(assets: Option<BTreeMap<String, PathBuf>>) -> PyResult<AssetLibrary> {
    AssetLibrary::from_specs(&asset_specs(assets)).map_err(|e| value_error(format!("assets: {}", chain(&e))))
}

/// A room of `Scene.from_boxes`: a dict with `relate`'s room keys and optionally `id` (the
/// room's id, default `default_id`). `what` names it in errors.
fn scene_room(obj: &Bound<'_, PyAny>, what: &str, default_id: &str) -> PyResult<Room> {
    let mut id = default_id.to_owned();
    let spec = if let Ok(dict) = obj.cast::<PyDict>()
        && dict.contains("id")?
    {
        let mut value = to_json(obj, what)?;
        if let Some(map) = value.as_object_mut()
            && let Some(given) = map.remove("id")
        {
            id = given
                .as_str()
                .ok_or_else(|| value_error(format!("{what}.id must be a string, got {given}")))?
                .to_owned();
        }
        room_from_json(value, what)?
    } else {
        room_spec(obj, what)?
    };
    spec.build_with_id(&id).map_err(|e| {
        if what == "room" {
            value_error(chain(&e))
        } else {
            value_error(format!("{what}: {}", chain(&e)))
        }
    })
}

/// An object of the scene as given from Python: its id or its position in `Scene.objects`.
enum ObjectRef {
    Index(i64),
    Id(String),
}

impl ObjectRef {
    /// Read from an id (a str) or a position (an int).
    fn extract(object: &Bound<'_, PyAny>) -> PyResult<Self> {
        if object.is_instance_of::<PyInt>() {
            return object
                .extract::<i64>()
                .map(ObjectRef::Index)
                .map_err(|_| value_error(format!("no object at index {object}")));
        }
        object.extract::<String>().map(ObjectRef::Id).map_err(|_| {
            value_error(format!(
                "object must be an id (str) or an index (int), got {object}"
            ))
        })
    }

    /// The object's position in the scene.
    fn position(&self, scene: &Scene) -> PyResult<usize> {
        match self {
            ObjectRef::Index(i) => {
                let count = scene.objects().len();
                usize::try_from(*i)
                    .ok()
                    .filter(|&i| i < count)
                    .ok_or_else(|| value_error(format!("no object at index {i}: the scene has {count}")))
            }
            ObjectRef::Id(id) => scene
                .object_index(id)
                .ok_or_else(|| value_error(format!("no object with id {id:?} in the scene"))),
        }
    }
}

/// Three numbers from a sequence (a tuple, list or numpy array). `what` names it in errors.
fn point(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 3]> {
    let numbers: Vec<f64> = obj
        .extract()
        .map_err(|_| value_error(format!("{what} must be a sequence of 3 numbers (x, y, z)")))?;
    numbers
        .try_into()
        .map_err(|_| value_error(format!("{what} must be a sequence of 3 numbers (x, y, z)")))
}

/// The pose that puts the box of `object` at `center`, turned by `yaw` about +z: for a box
/// object the box's centre is the pose's origin; a mesh object's box centre is offset from
/// its origin by the centre of its mesh bounds (object frame).
fn pose_for_box(object: &SceneObject, center: [f64; 3], yaw: f64) -> sceneeval::geom::Isometry3 {
    let c = Point3::from(center);
    if object.box_half_extents().is_some() {
        return pose_from_yaw(c, yaw);
    }
    let turned = pose_from_yaw(Point3::origin(), yaw);
    let offset = turned * object.mesh().aabb().center();
    pose_from_yaw(c - offset.coords, yaw)
}

/// `Ok` when every number is finite; `what` is the prefix of the names in errors
/// (`boxes[2].`).
fn finite_pose(center: &[f64; 3], yaw: f64, what: &str) -> PyResult<()> {
    if !center.iter().all(|v| v.is_finite()) {
        return Err(value_error(format!("{what}center is not finite")));
    }
    if !yaw.is_finite() {
        return Err(value_error(format!("{what}yaw is not finite")));
    }
    Ok(())
}

#[pymethods]
impl PyScene {
    /// A scene of box objects in one room or several.
    ///
    /// boxes: a float64 array of shape (N, 7), one object per row (cx, cy, cz, hx, hy, hz,
    /// yaw): centre, half extents (metres) and yaw (radians, yaw 0: front faces -y).
    /// room: a dict as for relation(): the floor polygon, wall height and thickness, doors
    /// and windows (openings); its id is "room". rooms: several such dicts instead (ids
    /// "room_0", "room_1", ...); a room dict may also carry its id (the key id), used by
    /// Scene.relation's floors= and in the plausibility report. categories: one per object
    /// (used by the support and accessibility tables); ids: one per object (default `box_0`,
    /// `box_1`, ...); name: the scene's name (id=, its old spelling, warns).
    ///
    /// Raises ValueError for a bad array, a bad room or a bad box.
    #[staticmethod]
    #[pyo3(signature = (boxes, room=None, *, rooms=None, categories=None, ids=None, name=None, id=None))]
    #[allow(clippy::too_many_arguments)] // The keyword arguments of `Scene.from_boxes`.
    fn from_boxes(
        py: Python<'_>,
        boxes: &Bound<'_, PyAny>,
        room: Option<&Bound<'_, PyAny>>,
        rooms: Option<&Bound<'_, PyAny>>,
        categories: Option<Vec<String>>,
        ids: Option<Vec<String>>,
        name: Option<String>,
        id: Option<String>,
    ) -> PyResult<Self> {
        if id.is_some() {
            if name.is_some() {
                return Err(value_error(
                    "give the scene's name once, as name= (id= is its old spelling)",
                ));
            }
            deprecation_warning(
                py,
                "Scene.from_boxes(id=...) is deprecated: pass name= (scene_id means the benchmark id)",
                1,
            )?;
        }
        let name = name.or(id);
        let box_rows = rows::<BOX_COLUMNS>(boxes, "boxes")?;
        let n = box_rows.len();
        for (what, list) in [("categories", &categories), ("ids", &ids)] {
            if let Some(list) = list
                && list.len() != n
            {
                return Err(value_error(format!(
                    "{what} has {} entries, boxes has {n} rows",
                    list.len()
                )));
            }
        }
        // Checks every number (NaN, negative half extents) with the messages of `relate`.
        obbs_from_rows(&box_rows, "boxes").map_err(|e| relation_error(&e))?;
        let mut builder = Scene::builder();
        if let Some(name) = name {
            builder = builder.name(name);
        }
        match (room, rooms) {
            (Some(_), Some(_)) => {
                return Err(value_error(
                    "give room (one room) or rooms (a list of rooms), not both",
                ));
            }
            (Some(room), None) => builder = builder.room(scene_room(room, "room", "room")?),
            (None, Some(rooms)) => {
                if !(rooms.is_instance_of::<PyList>() || rooms.is_instance_of::<PyTuple>()) {
                    return Err(value_error("rooms must be a list of room dicts"));
                }
                for (i, room) in rooms.try_iter()?.enumerate() {
                    builder = builder.room(scene_room(&room?, &format!("rooms[{i}]"), &format!("room_{i}"))?);
                }
            }
            (None, None) => {}
        }
        for (i, row) in box_rows.iter().enumerate() {
            let object_id = ids
                .as_ref()
                .map_or_else(|| format!("box_{i}"), |ids| ids[i].clone());
            let half = Vector3::new(row[3], row[4], row[5]);
            let pose = pose_from_yaw(Point3::new(row[0], row[1], row[2]), row[6]);
            let mut object = SceneObject::new_box(object_id, half, pose)
                .map_err(|e| value_error(format!("boxes[{i}]: {}", chain(&e))))?
                .with_index(i as i64);
            if let Some(categories) = &categories {
                object = object.with_category(Category::new(categories[i].as_str()));
            }
            builder = builder.object(object);
        }
        let scene = builder.build().map_err(|e| value_error(chain(&e)))?;
        Ok(PyScene::new(scene))
    }

    /// The scene's name (for a file, its stem: `scene_12`), if it has one.
    #[getter]
    fn name(&self) -> Option<String> {
        self.with_scene(|scene| scene.name().map(str::to_owned))
    }

    /// The scene's name: Scene.name, with a DeprecationWarning (scene_id means the benchmark
    /// id, `12`; the name is the file stem).
    #[getter]
    fn id(&self, py: Python<'_>) -> PyResult<Option<String>> {
        deprecation_warning(
            py,
            "Scene.id is deprecated: use Scene.name (scene_id means the benchmark id)",
            1,
        )?;
        Ok(self.name())
    }

    /// Every object as a dict: id, index, model_id, category, description, is_box, center, size
    /// (full width, depth, height), yaw, front (world direction of its front), asset_front (the
    /// front its file declared, or None), scale, support_type, functional_sides.
    #[getter]
    fn objects<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.to_python_with(py, |scene| {
            serde_json::to_string(&scene.objects().iter().map(ObjectInfo::new).collect::<Vec<_>>())
        })
    }

    /// Every room as a dict (id, kind, floor_id, floor_z, ceiling_z, floor_area, floor, walls),
    /// each wall with its openings.
    #[getter]
    fn rooms<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.to_python_with(py, |scene| {
            serde_json::to_string(&scene.rooms().iter().map(RoomInfo::new).collect::<Vec<_>>())
        })
    }

    /// The scene as one dict with scene, objects and rooms: what `sceneeval inspect --json` prints,
    /// without the file.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.to_python_with(py, |scene| serde_json::to_string(&SceneInfo::new(scene)))
    }

    /// The objects' boxes as a float64 array of shape (N, 7): centre, half extents, yaw.
    fn boxes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self.with_scene(|scene| {
            scene
                .objects()
                .iter()
                .map(|o| {
                    let obb = o.obb();
                    let (c, h) = (obb.center, obb.half_extents);
                    vec![c.x, c.y, c.z, h.x, h.y, h.z, o.yaw()]
                })
                .collect()
        });
        if rows.is_empty() {
            return Ok(PyArray2::zeros(py, [0, BOX_COLUMNS], false));
        }
        PyArray2::from_vec2(py, &rows).map_err(|e| value_error(e.to_string()))
    }

    /// Moves one object: its box's centre to center (x, y, z) and its yaw to yaw (radians
    /// about +z; the object is then upright), as boxes() reports them. object: the object's
    /// id (str) or its position in objects (int). For a box object the centre is the box's;
    /// for a mesh object, the centre of its mesh bounds. Everything computed afterwards
    /// (relations, plausibility, objects, boxes) sees the object where it now is.
    ///
    /// Raises ValueError for an unknown id, an index out of range, or a NaN or infinite
    /// number (the object then stays where it was).
    fn set_pose(
        &self,
        py: Python<'_>,
        object: &Bound<'_, PyAny>,
        center: &Bound<'_, PyAny>,
        yaw: f64,
    ) -> PyResult<()> {
        let object = ObjectRef::extract(object)?;
        let center = point(center, "center")?;
        finite_pose(&center, yaw, "")?;
        self.with_scene_mut(py, |scene| {
            let index = object.position(scene)?;
            let pose = scene
                .object_at(index)
                .map(|o| pose_for_box(o, center, yaw))
                .ok_or_else(|| value_error(format!("no object at index {index}")))?;
            scene.set_pose(index, pose).map_err(|e| value_error(chain(&e)))
        })?
    }

    /// Moves every object at once: boxes is a float64 array of shape (N, 7) as boxes()
    /// returns it, one row per object in order; each object's box centre and yaw are set
    /// from its row as set_pose does. The half extents of a row must be the object's (an
    /// object cannot be resized): `b = scene.boxes(); b[:, 0] += 0.1; scene.set_boxes(b)`
    /// moves everything 10 cm along x.
    ///
    /// Raises ValueError for an array of the wrong shape or dtype, a NaN or infinite number,
    /// or half extents that differ from the object's; then no object is moved.
    fn set_boxes(&self, py: Python<'_>, boxes: &Bound<'_, PyAny>) -> PyResult<()> {
        let box_rows = rows::<BOX_COLUMNS>(boxes, "boxes")?;
        self.with_scene(|scene| -> PyResult<()> {
            let objects = scene.objects();
            if box_rows.len() != objects.len() {
                return Err(value_error(format!(
                    "boxes has {} rows, the scene has {} objects",
                    box_rows.len(),
                    objects.len()
                )));
            }
            for (i, (row, object)) in box_rows.iter().zip(objects).enumerate() {
                finite_pose(&[row[0], row[1], row[2]], row[6], &format!("boxes[{i}]."))?;
                let h = object.obb().half_extents;
                let given = [row[3], row[4], row[5]];
                let same = given
                    .iter()
                    .zip(h.iter())
                    .all(|(g, h)| (g - h).abs() <= 1e-9 * (1.0 + h.abs()));
                if !same {
                    return Err(value_error(format!(
                        "boxes[{i}]: half extents {given:?} differ from object {:?}'s {:?}: objects cannot be resized",
                        object.id().as_str(),
                        [h.x, h.y, h.z]
                    )));
                }
            }
            Ok(())
        })?;
        self.with_scene_mut(py, |scene| -> PyResult<()> {
            for (i, row) in box_rows.iter().enumerate() {
                let pose = scene
                    .object_at(i)
                    .map(|o| pose_for_box(o, [row[0], row[1], row[2]], row[6]))
                    .ok_or_else(|| value_error(format!("no object at index {i}")))?;
                scene.set_pose(i, pose).map_err(|e| value_error(chain(&e)))?;
            }
            Ok(())
        })?
    }

    fn __len__(&self) -> usize {
        self.with_scene(|scene| scene.objects().len())
    }

    fn __repr__(&self) -> String {
        self.with_scene(|scene| {
            format!(
                "Scene(name={}, objects={}, rooms={})",
                scene
                    .name()
                    .map_or_else(|| "None".to_owned(), |name| format!("{name:?}")),
                scene.objects().len(),
                scene.rooms().len()
            )
        })
    }

    /// Runs the geometry-only plausibility metrics and returns the report as in eval.json.
    ///
    /// plan: as for evaluate() ("geometry", the default: every geometry metric; a
    /// comma-separated metric list; or the path of a plan file), without text-fidelity
    /// metrics. preset: "default" or "reference" (every reference-parity switch), replacing
    /// a plan file's. metrics: run only these (collision, support, navigability,
    /// accessibility, out_of_bounds, opening_clearance).
    /// The report holds the scene-level summary and each metric's per-object evidence.
    /// Computed with the GIL released.
    #[pyo3(signature = (*, plan=None, preset=None, metrics=None))]
    fn plausibility<'py>(
        &self,
        py: Python<'py>,
        plan: Option<&str>,
        preset: Option<&str>,
        metrics: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let evaluator =
            Evaluator::new(plausibility_plan(py, plan, preset, metrics)?).map_err(|e| eval_error(&e))?;
        let report = detached(py, || {
            self.with_scene(|scene| evaluator.evaluate_scene(scene, &SceneInputs::default()))
                .map(|done| done.report)
                .map_err(|e| eval_error(&e))
        })?;
        to_python(py, &report)
    }

    /// Simulates the scene under gravity (the stability metric) and returns its report as
    /// eval.json's report.stability: per object id, stable, displacement_m, rotation_rad,
    /// welded, weld_reason, final_pose, ...; and frac_unstable (unstable over the objects free
    /// to move; None when none was, with frac_unstable_missing saying why).
    ///
    /// plan: as for evaluate() ("geometry", the default: the built-in parameters; "full"; a
    /// metric list; or a plan file, JSON or TOML) and preset ("default" or "reference"): the
    /// plan's stability section, reading options, limits and time budget apply, as
    /// `sceneeval settle --plan` takes it; weld: "architectural" (default: objects on walls and
    /// ceilings are fixed in place),
    /// "penetration", "combined" or "none", replacing the plan's. Support types come from
    /// what the objects state, then (with vlm) the VLM's answer for each object that states
    /// none, then the category tables, as evaluate() gets them. vlm: the OpenAI-compatible
    /// endpoint asked, the same dict as evaluate()'s vlm (base_url, model, api_key_env,
    /// cache, render_size, ...); its answers are kept in vlm["cache"] when given (else for
    /// this call only, as `sceneeval settle` keeps them), and the report then has placement: for
    /// each object, where
    /// its support type came from and why (eval.json's report.placement). assets: as for
    /// load_scene, the library the VLM's object views are drawn from (their materials;
    /// default: plain colours). The scene is not moved. Computed with the GIL released.
    ///
    /// Raises ValueError for a bad plan, weld mode, vlm dict or assets mapping (the message
    /// starts with the keyword at fault, `vlm["model"]: ...`), SceneEvalError when the
    /// scene cannot be simulated (no room, hence no floor; the time budget ran out).
    #[pyo3(signature = (*, plan=None, preset=None, weld=None, vlm=None, assets=None))]
    fn stability<'py>(
        &self,
        py: Python<'py>,
        plan: Option<PathBuf>,
        preset: Option<&str>,
        weld: Option<&str>,
        vlm: Option<Bound<'py, PyDict>>,
        assets: Option<BTreeMap<String, PathBuf>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (_settled, report) = self.settled(py, plan, preset, weld, vlm.as_ref(), assets)?;
        Ok(report)
    }

    /// Simulates the scene as stability() does and returns (settled, report): a new Scene
    /// with every object at its pose after the simulation (fixed objects where they were),
    /// and the report. This scene is not moved. Arguments and errors as stability().
    #[pyo3(signature = (*, plan=None, preset=None, weld=None, vlm=None, assets=None))]
    fn settle<'py>(
        &self,
        py: Python<'py>,
        plan: Option<PathBuf>,
        preset: Option<&str>,
        weld: Option<&str>,
        vlm: Option<Bound<'py, PyDict>>,
        assets: Option<BTreeMap<String, PathBuf>>,
    ) -> PyResult<(PyScene, Bound<'py, PyAny>)> {
        self.settled(py, plan, preset, weld, vlm.as_ref(), assets)
    }

    /// The score of a relation between objects of this scene, by object id.
    ///
    /// As relation(), but the objects' meshes are used where the predicate uses geometry, and
    /// the architecture is the scene's rooms (floors= restricts the floor-based relations to
    /// some floors or rooms). surround takes targets=[id, ...] with target None.
    #[pyo3(signature = (name, target, anchor=None, *, side=None, arch=None, targets=None, floors=None, reference=false, **params))]
    #[allow(clippy::too_many_arguments)] // Mirrors `sceneeval.relation`'s keyword arguments.
    fn relation(
        &self,
        py: Python<'_>,
        name: &str,
        target: Option<String>,
        anchor: Option<String>,
        side: Option<&str>,
        arch: Option<&str>,
        targets: Option<Vec<String>>,
        floors: Option<Vec<String>>,
        reference: bool,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<f64> {
        let relation = Relation::from_fields(name, side, arch).map_err(|e| relation_error(&e))?;
        let relations =
            SceneRelations::new(relation_params(reference, params)?).map_err(|e| relation_error(&e))?;
        let mut query = Query::new(relation);
        query.targets = target.into_iter().chain(targets.unwrap_or_default()).collect();
        query.anchor = anchor;
        query.floors = floors.unwrap_or_default();
        detached(py, || {
            self.with_scene(|scene| relations.evaluate(scene, &query))
                .map(|e| e.score)
                .map_err(|e| relation_error(&e))
        })
    }
}

/// Loads a sceneState file (`scene_<ID>.json`).
///
/// assets maps a model id prefix to its folder, {"objaverse": "/data/objathor-assets"}; the
/// folder layout is chosen from the prefix as by `sceneeval evaluate --assets`, or given as
/// "LAYOUT:folder" (3d-future, objathor, hssd, layoutvlm, plain). Read with the GIL released.
/// Keys the sceneState format does not have (a misspelt key is read as absent) are each logged
/// as a warning; strict=True raises SceneEvalError listing them instead.
///
/// Raises SceneEvalError naming the file, the JSON pointer and the asset when the scene
/// cannot be read, and ValueError for a bad assets mapping.
#[pyfunction]
#[pyo3(signature = (path, assets=None, *, strict=false))]
pub fn load_scene(
    py: Python<'_>,
    path: PathBuf,
    assets: Option<BTreeMap<String, PathBuf>>,
    strict: bool,
) -> PyResult<PyScene> {
    let library = asset_library(assets)?;
    let options = ReadOptions::default().with_strict(strict);
    let scene = detached(py, || {
        read_scene_state(&path, &library, &options).map_err(|e| scene_error(&e))
    })?;
    Ok(PyScene::new(scene))
}
