//! Scenes from Python: built from numpy arrays of boxes and a room, or loaded from sceneState
//! files with asset folders; inspected as plain values; scored by the plausibility metrics and
//! the predicates; and whole folders evaluated as `sceneeval evaluate` does.

use std::collections::BTreeMap;
use std::path::PathBuf;

use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sceneeval::geom::conventions::pose_from_yaw;
use sceneeval::geom::{Point3, Vector3};
use sceneeval::inspect::{ObjectInfo, RoomInfo, SceneInfo};
use sceneeval::io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval::relations::spec::relation_from_spec;
use sceneeval::relations::{Query, SceneRelations};
use sceneeval::scene::{Category, Scene, SceneObject};
use sceneeval::{EvaluationPlan, Evaluator, FolderRun, Metric, find_scenes};
use serde::Serialize;

use crate::convert::{rows, to_python};
use crate::errors::{detached, eval_error, relation_error, scene_error, value_error};
use crate::relations::{BOX_COLUMNS, obbs_from_rows, relation_params, room_spec};

/// A scene: objects (boxes or meshes) and rooms with walls, doors and windows.
///
/// Build one from boxes with Scene.from_boxes or load a sceneState file with load_scene.
#[pyclass(module = "sceneeval", name = "Scene", frozen)]
pub struct PyScene {
    scene: Scene,
}

impl PyScene {
    /// The wrapped scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }
}

/// The plan named by `plan` (a preset name or a plan file; default: every geometry metric
/// with the default preset), restricted to `metrics` when given.
fn plan_of(plan: Option<&str>, metrics: Option<Vec<String>>) -> PyResult<EvaluationPlan> {
    let mut plan = match plan {
        Some(spec) => EvaluationPlan::from_preset_or_file(spec).map_err(|e| eval_error(&e))?,
        None => EvaluationPlan::geometry_only(),
    };
    if let Some(names) = metrics {
        plan.metrics = names
            .iter()
            .map(|n| n.parse::<Metric>().map_err(|e| value_error(e.to_string())))
            .collect::<PyResult<_>>()?;
    }
    Ok(plan)
}

/// An asset library from `{prefix: folder}` (a folder may be written `LAYOUT:folder`).
fn asset_library(assets: Option<BTreeMap<String, PathBuf>>) -> PyResult<AssetLibrary> {
    let specs: Vec<String> = assets
        .unwrap_or_default()
        .into_iter()
        .map(|(prefix, dir)| format!("{prefix}={}", dir.display()))
        .collect();
    AssetLibrary::from_specs(&specs).map_err(|e| value_error(format!("assets: {}", crate::errors::chain(&e))))
}

#[pymethods]
impl PyScene {
    /// A scene of box objects in one room.
    ///
    /// boxes: a float64 array of shape (N, 7), one object per row (cx, cy, cz, hx, hy, hz,
    /// yaw): centre, half extents (metres) and yaw (radians, yaw 0: front faces -y).
    /// room: a dict as for relation(): the floor polygon, wall height and thickness, doors
    /// and windows (openings). categories: one per object (used by the support and
    /// accessibility tables); ids: one per object (default `box_0`, `box_1`, ...); id: the
    /// scene's name.
    ///
    /// Raises ValueError for a bad array, a bad room or a bad box.
    #[staticmethod]
    #[pyo3(signature = (boxes, room=None, *, categories=None, ids=None, id=None))]
    fn from_boxes(
        boxes: &Bound<'_, PyAny>,
        room: Option<&Bound<'_, PyAny>>,
        categories: Option<Vec<String>>,
        ids: Option<Vec<String>>,
        id: Option<String>,
    ) -> PyResult<Self> {
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
        if let Some(id) = id {
            builder = builder.id(id);
        }
        if let Some(room) = room {
            let room = room_spec(room)?.build().map_err(|e| relation_error(&e))?;
            builder = builder.room(room);
        }
        for (i, row) in box_rows.iter().enumerate() {
            let object_id = ids
                .as_ref()
                .map_or_else(|| format!("box_{i}"), |ids| ids[i].clone());
            let half = Vector3::new(row[3], row[4], row[5]);
            let pose = pose_from_yaw(Point3::new(row[0], row[1], row[2]), row[6]);
            let mut object = SceneObject::new_box(object_id, half, pose)
                .map_err(|e| value_error(format!("boxes[{i}]: {}", crate::errors::chain(&e))))?
                .with_index(i as i64);
            if let Some(categories) = &categories {
                object = object.with_category(Category::new(categories[i].as_str()));
            }
            builder = builder.object(object);
        }
        let scene = builder
            .build()
            .map_err(|e| value_error(crate::errors::chain(&e)))?;
        Ok(PyScene { scene })
    }

    /// The scene's name, if it has one.
    #[getter]
    fn id(&self) -> Option<&str> {
        self.scene.id()
    }

    /// Every object as a dict: id, index, model_id, category, description, is_box, center, size
    /// (full width, depth, height), yaw, scale, support_type, functional_sides.
    #[getter]
    fn objects<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let objects: Vec<ObjectInfo<'_>> = self.scene.objects().iter().map(ObjectInfo::new).collect();
        to_python(py, &objects)
    }

    /// Every room as a dict (id, kind, floor_id, floor_z, ceiling_z, floor_area, floor, walls),
    /// each wall with its openings.
    #[getter]
    fn rooms<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let rooms: Vec<RoomInfo<'_>> = self.scene.rooms().iter().map(RoomInfo::new).collect();
        to_python(py, &rooms)
    }

    /// The scene as one dict with scene, objects and rooms: what `sceneeval inspect --json` prints,
    /// without the file.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &SceneInfo::new(&self.scene))
    }

    /// The objects' boxes as a float64 array of shape (N, 7): centre, half extents, yaw.
    fn boxes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self
            .scene
            .objects()
            .iter()
            .map(|o| {
                let obb = o.obb();
                let (c, h) = (obb.center, obb.half_extents);
                vec![c.x, c.y, c.z, h.x, h.y, h.z, o.yaw()]
            })
            .collect();
        if rows.is_empty() {
            return Ok(PyArray2::zeros(py, [0, BOX_COLUMNS], false));
        }
        PyArray2::from_vec2(py, &rows).map_err(|e| value_error(e.to_string()))
    }

    fn __len__(&self) -> usize {
        self.scene.objects().len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(id={}, objects={}, rooms={})",
            self.scene
                .id()
                .map_or_else(|| "None".to_owned(), |id| format!("{id:?}")),
            self.scene.objects().len(),
            self.scene.rooms().len()
        )
    }

    /// Runs the geometry-only plausibility metrics and returns the report as in eval.json.
    ///
    /// plan: a preset name (default, reference) or the path of a plan file; default: every
    /// metric with the default preset. metrics: run only these (collision, support,
    /// navigability, accessibility, out_of_bounds, opening_clearance).
    /// The report holds the scene-level summary and each metric's per-object evidence.
    /// Computed with the GIL released.
    #[pyo3(signature = (*, plan=None, metrics=None))]
    fn plausibility<'py>(
        &self,
        py: Python<'py>,
        plan: Option<&str>,
        metrics: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let evaluator = Evaluator::new(plan_of(plan, metrics)?).map_err(|e| eval_error(&e))?;
        let report = detached(py, || evaluator.evaluate(&self.scene).map_err(|e| eval_error(&e)))?;
        to_python(py, &report)
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
        let relation = relation_from_spec(name, side, arch).map_err(|e| relation_error(&e))?;
        let relations =
            SceneRelations::new(relation_params(reference, params)?).map_err(|e| relation_error(&e))?;
        let mut query = Query::new(relation);
        query.targets = target.into_iter().chain(targets.unwrap_or_default()).collect();
        query.anchor = anchor;
        query.floors = floors.unwrap_or_default();
        detached(py, || {
            relations
                .evaluate(&self.scene, &query)
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
///
/// Raises SceneEvalError naming the file, the JSON pointer and the asset when the scene
/// cannot be read, and ValueError for a bad assets mapping.
#[pyfunction]
#[pyo3(signature = (path, assets=None))]
pub fn load_scene(
    py: Python<'_>,
    path: PathBuf,
    assets: Option<BTreeMap<String, PathBuf>>,
) -> PyResult<PyScene> {
    let library = asset_library(assets)?;
    let scene = detached(py, || {
        read_scene_state(&path, &library, &ReadOptions::default()).map_err(|e| scene_error(&e))
    })?;
    Ok(PyScene { scene })
}

/// What `evaluate` returns: the summary and what happened to each scene.
#[derive(Debug, Serialize)]
struct RunReport {
    out: PathBuf,
    scenes: usize,
    evaluated: usize,
    reused: usize,
    failed: usize,
    skipped: Vec<Skipped>,
    failures: Vec<Failure>,
    summary: sceneeval::Summary,
}

#[derive(Debug, Serialize)]
struct Skipped {
    path: PathBuf,
    reason: String,
}

#[derive(Debug, Serialize)]
struct Failure {
    scene: String,
    error: String,
    causes: Vec<String>,
}

/// Evaluates every `scene_<ID>.json` of scenes_dir as `sceneeval evaluate` does, writing the same
/// files into out: `<scene>/eval.json` and `<scene>/timing.json` as each scene finishes, then
/// summary.csv and summary.md.
///
/// assets: as for load_scene. annotations: a SceneEval-500 annotation CSV (or JSON) adding
/// rows per difficulty to the summary. plan: a preset name (default, reference) or the path
/// of a plan file. A re-run into the same out reuses a scene's result while nothing it
/// depends on changed (force=True evaluates every scene again). threads: worker threads
/// (default one per core). Runs with the GIL released.
///
/// Returns the run: out, scenes, evaluated, reused, failed, skipped (files that look like
/// scenes but are not `scene_<ID>.json`), failures (scene, error, causes) and summary (the
/// table of summary.csv as a dict). A scene that fails is recorded, not raised.
/// Raises SceneEvalError when the folder, the annotations or the output cannot be used, and
/// ValueError for a bad plan or assets mapping.
#[pyfunction]
#[pyo3(signature = (scenes_dir, *, assets, out, annotations=None, plan=None, force=false, threads=None))]
#[allow(clippy::too_many_arguments)] // The Python signature is fixed by issue 15.
pub fn evaluate<'py>(
    py: Python<'py>,
    scenes_dir: PathBuf,
    assets: Option<BTreeMap<String, PathBuf>>,
    out: PathBuf,
    annotations: Option<PathBuf>,
    plan: Option<&str>,
    force: bool,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let set = find_scenes(&scenes_dir).map_err(|e| eval_error(&e))?;
    if set.scenes.is_empty() {
        return Err(crate::errors::SceneEvalError::new_err(format!(
            "no scene_<ID>.json files in {}",
            scenes_dir.display()
        )));
    }
    let evaluator = Evaluator::new(plan_of(plan, None)?).map_err(|e| eval_error(&e))?;
    let library = asset_library(assets)?.with_limits(evaluator.plan().limits);
    let annotations = annotations
        .map(|p| sceneeval::annotation::Annotations::read(&p).map_err(|e| scene_error(&e)))
        .transpose()?;
    sceneeval::check_output_dir(&out).map_err(|e| eval_error(&e))?;
    let run = FolderRun {
        out_dir: out.clone(),
        force,
        diagnostics: false,
        annotations: annotations.as_ref(),
    };
    let scenes = &set.scenes;
    let outcome = detached(py, || {
        let mut pool = rayon_pool_builder();
        if let Some(n) = threads {
            pool = pool.num_threads(n.max(1));
        }
        let pool = pool
            .build()
            .map_err(|e| crate::errors::SceneEvalError::new_err(format!("starting worker threads: {e}")))?;
        pool.install(|| run.run(scenes, &evaluator, &library, &|_, _, _| {}))
            .map_err(|e| eval_error(&e))
    })?;
    let failures = outcome
        .batch
        .records
        .iter()
        .filter_map(|r| match &r.outcome {
            sceneeval::Outcome::Failed { error, causes, .. } => Some(Failure {
                scene: r.scene.clone(),
                error: error.clone(),
                causes: causes.clone(),
            }),
            _ => None,
        })
        .collect();
    let report = RunReport {
        out,
        scenes: scenes.len(),
        evaluated: outcome.batch.evaluated,
        reused: outcome.batch.reused,
        failed: outcome.batch.failed,
        skipped: set
            .skipped
            .into_iter()
            .map(|s| Skipped {
                path: s.path,
                reason: s.reason,
            })
            .collect(),
        failures,
        summary: outcome.summary,
    };
    to_python(py, &report)
}

fn rayon_pool_builder() -> rayon::ThreadPoolBuilder {
    rayon::ThreadPoolBuilder::new()
}
