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
//!
//! On top of them: an [`EvaluationPlan`] names the metrics to run and their parameters
//! (starting from a [`Preset`]: this implementation's defaults or every reference-parity
//! switch), an [`Evaluator`] runs a plan on a [`scene::Scene`] and returns a [`SceneReport`],
//! [`run_batch`] evaluates a folder of `scene_<ID>.json` files in parallel writing one
//! [`SceneRecord`] (`eval.json`, with the [`Fingerprint`] of everything it depends on) per
//! scene as it finishes, reusing an earlier record only when its fingerprint still matches,
//! and [`Summary`] turns records into the paper's tables, overall and by difficulty. Every
//! result file is written atomically ([`write_atomic`]). File formats and the guarantees a
//! user may rely on: `docs/formats.md`.
//!
//! [`FolderRun`] is the whole run of `sceneeval evaluate` (the batch, then `summary.csv` and
//! `summary.md`) and [`PlanChoice`] reads what it evaluates (`--plan geometry|full|LIST|FILE`,
//! the preset, the fidelity choices and the downgrade without a VLM), both shared by the CLI
//! and the Python package; [`inspect`] gives a scene's objects,
//! rooms, walls and openings as plain serializable values.
//!
//! # Example
//! ```
//! use sceneeval::{Evaluator, EvaluationPlan, Summary, SceneRecord};
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
//! assert_eq!(report.plausibility.summary.col_sc, Some(false));
//! assert_eq!(report.plausibility.summary.oob, Some(0.0));
//!
//! let summary = Summary::from_records(&[SceneRecord::ok("scene_0", report)], |_| None)
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
pub use sceneeval_plausibility as plausibility;
pub use sceneeval_relations as relations;
#[cfg(feature = "render")]
pub use sceneeval_render as render;
pub use sceneeval_scene as scene;
pub use sceneeval_vlm as vlm;
#[cfg(feature = "openai")]
pub use sceneeval_vlm_openai as vlm_openai;

mod batch;
mod dyn_vlm;
mod error;
mod evaluator;
mod files;
mod fingerprint;
mod folder;
pub mod inspect;
mod plan;
mod plan_choice;
mod record;
pub mod relate;
mod summary;

pub use batch::{
    BatchOptions, BatchOutcome, RECORD_FILE, Reason, SceneFile, SceneSet, SceneStatus, SceneTiming,
    SkippedFile, TIMING_FILE, TIMING_SCHEMA, find_scenes, run_batch,
};
pub use dyn_vlm::SharedVlm;
pub use error::EvalError;
pub use evaluator::{Evaluator, SCENE_REPORT_SCHEMA, SceneReport};
pub use files::{check_output_dir, write_atomic, write_atomic_with};
pub use fingerprint::{
    AssetDigest, FileDigest, Fingerprint, Fingerprints, TOOL_VERSION, annotation_digest, matching_file_digest,
};
pub use folder::{FolderOutcome, FolderRun, scene_annotation_row};
pub use plan::{DEFAULT_TIME_BUDGET_SECONDS, EvaluationPlan, Preset};
pub use plan_choice::{ChosenPlan, NoVlmFallback, OptionNames, PlanChoice, PlanSpec};
pub use plausibility::{Deadline, Metric, MetricTiming, PlausibilitySummary};
pub use record::{Outcome, RECORD_SCHEMA, SceneRecord, Stage, benchmark_id};
pub use summary::{ALL_SCENES, GroupSummary, LEGEND, SUMMARY_CSV, SUMMARY_MD, Summary, UNANNOTATED};
