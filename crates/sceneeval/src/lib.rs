//! SceneEval facade: one dependency that re-exports the member crates as modules and runs
//! evaluation plans on scenes.
//!
//! | module | crate | what |
//! |---|---|---|
//! | [`geom`] | `sceneeval-geom` | boxes, meshes, polygons, conventions |
//! | [`scene`] | `sceneeval-scene` | the scene model |
//! | [`relations`] | `sceneeval-relations` | the 23 spatial predicates |
//! | [`io`] | `sceneeval-io` | sceneState files and assets |
//! | [`annotation`] | `sceneeval-annotation` | the SceneEval-500 annotation schema |
//! | [`plausibility`] | `sceneeval-plausibility` | collision, support, navigability, ... |
//! | `render` (feature `render`) | `sceneeval-render` | offscreen wgpu renders of scenes |
//! | [`vlm`] | `sceneeval-vlm` | VLM tasks, sessions, the response cache |
//! | [`fidelity`] | `sceneeval-fidelity` | object matching, CNT, ATR, OOR, OAR |
//! | `vlm_openai` (feature `openai`) | `sceneeval-vlm-openai` | the OpenAI-compatible HTTP client |
//! | `physics` (feature `physics`) | `sceneeval-physics` | physical stability (the `stability` metric) |
//!
//! On top of them:
//! - an [`EvaluationPlan`] names the [`Metric`]s to run and their parameters (starting from a
//!   [`Preset`]: this implementation's defaults or every reference-parity switch);
//! - an [`Evaluator`] runs a plan: [`Evaluator::evaluate_scene`] is the per-scene pipeline
//!   (the VLM's object views, support types and functional sides when one is configured, the
//!   geometry metrics, then CNT, ATR, OOR, OAR against the scene's annotation row) and returns
//!   the [`SceneReport`], built once;
//! - an [`EvaluationRequest`] is a whole run (scenes, assets, annotations, output folder, plan,
//!   VLM, threads, shard), each default written once, that `sceneeval evaluate` and the Python
//!   package's `sceneeval.evaluate` both build; [`EvaluationRequest::prepare`] checks it before
//!   any work and [`PreparedRun::run`] runs it: [`run_batch`] (files, fingerprints, reuse,
//!   parallelism: one [`SceneRecord`] per scene in `eval.json`, written as it finishes, reused
//!   only while its [`Fingerprint`] matches), then the paper's tables ([`Summary`], overall and
//!   by difficulty);
//! - a scene's identity, [`SceneName`] (its name and benchmark id, which finds its annotation
//!   row), is made once where scene files are found ([`find_scenes`]);
//! - [`annotate`] makes annotation rows with a model, the paper's semi-automatic process
//!   (`sceneeval annotations annotate` and `generate`);
//! - [`ErrorChain`] prints an error and its causes as every front end shows them, and
//!   [`inspect`] gives a scene's objects, rooms, walls and openings as plain values.
//!
//! Every result file is written atomically ([`write_atomic`]). File formats and the guarantees
//! a user may rely on: `docs/formats.md`; the data flow: `docs/architecture.md`.
//!
//! # Example
//! ```
//! use sceneeval::{Evaluator, EvaluationPlan, SceneName, SceneRecord, Summary};
//! use sceneeval::scene::{Category, RoomBuilder, Scene};
//! use sceneeval::geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//!
//! let scene = Scene::builder()
//!     .id("scene_0")
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!         .door(0, [1.0, 1.9], [0.0, 2.1]))
//!     // A 1.6 x 2.0 x 0.5 m bed (half extents 0.8, 1.0, 0.25).
//!     .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.25),
//!              pose_from_yaw(Point3::new(2.0, 3.9, 0.25), 0.0))
//!     .build()
//!     .unwrap();
//! let plan = EvaluationPlan::geometry_only();
//! let evaluator = Evaluator::new(plan.clone()).unwrap();
//! let report = evaluator.evaluate(&scene).unwrap();
//! assert_eq!(report.summary.geometry.col_sc, Some(false));
//! assert_eq!(report.summary.geometry.oob, Some(0.0));
//!
//! let summary = Summary::from_records(&[SceneRecord::ok(SceneName::new("scene_0"), report)], None)
//!     .with_plan(&plan);
//! assert_eq!(summary.groups[0].col_ob, Some(0.0));
//! let md = summary.to_markdown();
//! assert!(md.starts_with("| group | scenes |"));
//! assert!(md.contains("Preset: `default`"));
//! ```

pub use sceneeval_annotation as annotation;
pub use sceneeval_fidelity as fidelity;
pub use sceneeval_geom as geom;
pub use sceneeval_io as io;
#[cfg(feature = "physics")]
pub use sceneeval_physics as physics;
pub use sceneeval_plausibility as plausibility;
pub use sceneeval_relations as relations;
#[cfg(feature = "render")]
pub use sceneeval_render as render;
pub use sceneeval_scene as scene;
pub use sceneeval_vlm as vlm;
#[cfg(feature = "openai")]
pub use sceneeval_vlm_openai as vlm_openai;

pub mod annotate;
mod batch;
mod chain;
mod dry_run;
mod dyn_vlm;
mod error;
mod evaluator;
mod files;
mod fingerprint;
pub mod inspect;
mod metric;
mod plan;
mod record;
pub mod relate;
mod report;
mod request;
mod scene_file;
mod schedule;
mod summary;

pub use batch::{
    BatchOptions, BatchOutcome, Reason, RunEvent, SceneStatus, SceneTiming, TIMING_SCHEMA, run_batch,
};
pub use chain::{ErrorChain, causes};
pub use dry_run::{DryRun, TaskCost};
pub use dyn_vlm::SharedVlm;
pub use error::EvalError;
pub use evaluator::{Evaluator, SceneEvaluation, SceneInputs};
pub use files::{LOCK_FILE, OutputLock, check_output_dir, write_atomic, write_atomic_with};
pub use fingerprint::{
    AssetDigest, FileDigest, Fingerprint, Fingerprints, TOOL_VERSION, annotation_digest, matching_file_digest,
};
pub use metric::{Better, Metric, UnknownMetric};
pub use plan::{DEFAULT_TIME_BUDGET_SECONDS, EvaluationPlan, Preset};
pub use plausibility::{Deadline, MetricTiming};
pub use record::{Outcome, RECORD_SCHEMA, SceneRecord, Stage};
pub use report::{
    IncompleteMetric, ObjectPlacement, PlacementSource, Provenance, SCENE_REPORT_SCHEMA, SceneReport,
    SceneSummary,
};
pub use request::{
    ChosenPlan, DEFAULT_PHYSICS_CACHE_DIR, DEFAULT_RENDER_SIZE, DEFAULT_VLM_CACHE_DIR,
    DEFAULT_VLM_CONCURRENCY, DEFAULT_VLM_TIMEOUT_SECONDS, EvaluationRequest, MAX_VLM_TIMEOUT_SECONDS,
    NoVlmFallback, PlanRequest, PlanSpec, PreparedRun, RENDER_SIZE_RANGE, RequestField, RunOutcome, Shard,
    VlmOptions,
};
pub use scene_file::{RECORD_FILE, SceneFile, SceneName, SceneSet, SkippedFile, TIMING_FILE, find_scenes};
pub use schedule::BudgetSpent;
pub use summary::{
    ALL_SCENES, GroupSummary, LEGEND, SUMMARY_CSV, SUMMARY_MD, SUMMARY_SCENES_CSV, SceneRow, Summary,
    UNANNOTATED,
};
