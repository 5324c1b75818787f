//! SceneEval facade: one dependency that re-exports the member crates as modules, and their
//! most used types at the top, as bevy's facade does. It holds no code of its own
//! (`.ci/check-layering` checks that it stays re-exports only).
//!
//! | module | crate | what |
//! |---|---|---|
//! | [`files`] | `sceneeval-files` | how files are read and written; [`ErrorChain`] |
//! | [`geom`] | `sceneeval-geom` | boxes, meshes, polygons, conventions |
//! | [`scene`] | `sceneeval-scene` | the scene model; [`inspect`] |
//! | [`relations`] | `sceneeval-relations` | the 23 spatial predicates |
//! | [`io`] | `sceneeval-io` | sceneState files and assets |
//! | [`annotation`] | `sceneeval-annotation` | the SceneEval-500 annotation schema |
//! | [`vlm`] | `sceneeval-vlm` | VLM tasks, sessions, the response cache |
//! | [`plausibility`] | `sceneeval-plausibility` | collision, support, navigability, ... |
//! | [`physics`] | `sceneeval-physics` | physical stability (the simulation with the feature `physics`) |
//! | `render` (feature `render`) | `sceneeval-render` | offscreen wgpu renders of scenes |
//! | `vlm_openai` (feature `openai`) | `sceneeval-vlm-openai` | the OpenAI-compatible HTTP client |
//! | [`convert`] | `sceneeval-convert` | generators' native outputs to sceneState files |
//! | [`relate`] | `sceneeval-relate` | relation queries as plain data, the relate line format |
//! | [`annotate`] | `sceneeval-annotate` | annotation rows made with a model, the review store |
//! | [`fidelity`] | `sceneeval-fidelity` | object matching, CNT, ATR, OOR, OAR |
//! | [`stats`] | `sceneeval-stats` | kappas, the seeded bootstrap, Wilcoxon, Holm, McNemar |
//! | [`results`] | `sceneeval-results` | `eval.json`, timings and summary tables as types |
//! | [`eval`] | `sceneeval-eval` | plans, the evaluator (one call per scene), VLM options |
//! | [`run`] | `sceneeval-run` | a run: request, batch, fingerprints, dry run |
//! | `report` (feature `report`) | `sceneeval-report` | comparisons of runs, the static report |
//!
//! At the top: an [`EvaluationPlan`] names the [`Metric`]s to run and their parameters (from
//! a [`Preset`]); an [`Evaluator`] runs it on one scene ([`Evaluator::evaluate_scene`], the
//! one per-scene call, which returns the scene's [`SceneReport`]); an [`EvaluationRequest`] is
//! a whole run (scenes, assets, annotations, output folder, plan, VLM, threads, shard), which
//! [`EvaluationRequest::prepare`] checks and [`PreparedRun::run`] runs, writing one
//! [`SceneRecord`] per scene and the paper's tables ([`Summary`]).
//!
//! File formats and the guarantees a user may rely on: `docs/formats.md`; the crates and the
//! data flow: `docs/architecture.md`.
//!
//! # Features
//! `render`, `openai` and `physics` choose the heavy parts (wgpu; tokio and reqwest; rapier),
//! `report` the comparison tables and the static report; none is on by default, so the
//! default facade is CPU-only and offline.
//!
//! # Example
//! ```
//! use sceneeval::{Evaluator, EvaluationPlan, SceneInputs, SceneName, SceneRecord, Summary};
//! use sceneeval::scene::{Category, RoomBuilder, Scene};
//! use sceneeval::geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//!
//! let scene = Scene::builder()
//!     .name("scene_0")
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!         .door(0, [1.0, 1.9], [0.0, 2.1]))
//!     // A 1.6 x 2.0 x 0.5 m bed (half extents 0.8, 1.0, 0.25).
//!     .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.25),
//!              pose_from_yaw(Point3::new(2.0, 3.9, 0.25), 0.0))
//!     .build()
//!     .unwrap();
//! let plan = EvaluationPlan::geometry_only();
//! let evaluator = Evaluator::new(plan.clone()).unwrap();
//! let report = evaluator.evaluate_scene(&scene, &SceneInputs::default()).unwrap().report;
//! assert_eq!(report.summary.geometry.col_sc, Some(false));
//! assert_eq!(report.summary.geometry.oob, Some(0.0));
//!
//! let summary = Summary::from_records(&[SceneRecord::ok(SceneName::new("scene_0"), report)], None)
//!     .with_plan(plan.preset, plan.result_digest());
//! assert_eq!(summary.groups[0].col_ob, Some(0.0));
//! let md = summary.to_markdown();
//! assert!(md.starts_with("| group | scenes |"));
//! assert!(md.contains("Preset: `default`"));
//! ```

pub use sceneeval_annotate as annotate;
pub use sceneeval_annotation as annotation;
pub use sceneeval_convert as convert;
pub use sceneeval_eval as eval;
pub use sceneeval_fidelity as fidelity;
pub use sceneeval_files as files;
pub use sceneeval_geom as geom;
pub use sceneeval_io as io;
pub use sceneeval_physics as physics;
pub use sceneeval_plausibility as plausibility;
pub use sceneeval_relate as relate;
pub use sceneeval_relations as relations;
#[cfg(feature = "render")]
pub use sceneeval_render as render;
#[cfg(feature = "report")]
pub use sceneeval_report as report;
pub use sceneeval_results as results;
pub use sceneeval_run as run;
pub use sceneeval_scene as scene;
/// What a scene contains, as plain values (`sceneeval_scene::inspect`).
pub use sceneeval_scene::inspect;
pub use sceneeval_stats as stats;
pub use sceneeval_vlm as vlm;
#[cfg(feature = "openai")]
pub use sceneeval_vlm_openai as vlm_openai;

#[cfg(feature = "physics")]
pub use sceneeval_eval::Settled;
pub use sceneeval_eval::{
    BudgetSpent, ChosenPlan, DEFAULT_PHYSICS_CACHE_DIR, DEFAULT_RENDER_SIZE, DEFAULT_TIME_BUDGET_SECONDS,
    DEFAULT_VLM_CACHE_DIR, DEFAULT_VLM_CONCURRENCY, DEFAULT_VLM_MAX_RETRIES, DEFAULT_VLM_TIMEOUT_SECONDS,
    EvalError, EvaluationPlan, Evaluator, MAX_VLM_TIMEOUT_SECONDS, NoVlmFallback, PlanRequest, PlanSpec,
    PreparedSettle, RENDER_SIZE_RANGE, RequestField, SceneEvaluation, SceneInputs, SettleRequest, SharedVlm,
    VlmOptions,
};
pub use sceneeval_files::{ErrorChain, causes};
pub use sceneeval_plausibility::MetricTiming;
pub use sceneeval_results::{
    ALL_SCENES, AssetDigest, Better, FileDigest, Fingerprint, GroupSummary, IncompleteMetric, LEGEND, Metric,
    ObjectPlacement, Outcome, PlacementSource, Preset, Provenance, READABLE_RECORD_SCHEMAS, RECORD_FILE,
    RECORD_SCHEMA, ResultsError, SCENE_REPORT_SCHEMA, SUMMARY_CSV, SUMMARY_MD, SUMMARY_SCENES_CSV, SceneName,
    SceneRecord, SceneReport, SceneRow, SceneSummary, SceneTiming, Stage, Summary, TIMING_FILE,
    TIMING_SCHEMA, TOOL_VERSION, UNANNOTATED, UnknownMetric, UnknownPreset,
};
pub use sceneeval_run::{
    BatchOptions, BatchOutcome, DryRun, EvaluationRequest, Fingerprints, LOCK_FILE, OutputLock, PreparedRun,
    Reason, RunError, RunEvent, RunOutcome, SceneFile, SceneSet, SceneStatus, Shard, SkippedFile, TaskCost,
    annotation_digest, check_output_dir, find_scenes, matching_file_digest, run_batch,
};
pub use sceneeval_scene::Deadline;
