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
//!
//! On top of them: an [`EvaluationPlan`] names the metrics to run and their parameters, an
//! [`Evaluator`] runs a plan on a [`scene::Scene`] and returns a [`SceneReport`], [`run_batch`]
//! evaluates a folder of `scene_<ID>.json` files in parallel writing one [`SceneRecord`]
//! (`eval.json`) per scene as it finishes, and [`Summary`] turns records into the paper's tables,
//! overall and by difficulty. File formats: `docs/formats.md`.
//!
//! # Example
//! ```
//! use sceneeval::{Evaluator, EvaluationPlan, Summary, SceneRecord};
//! use sceneeval::scene::{RoomBuilder, Scene};
//! use sceneeval::geom::{Point2, Point3, Vector3};
//!
//! let scene = Scene::builder()
//!     .id("scene_0")
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!         .door(0, [1.0, 1.9], [0.0, 2.1]))
//!     .add_box("bed", "bed", Point3::new(2.0, 3.9, 0.25), Vector3::new(1.6, 2.0, 0.5), 0.0)
//!     .build()
//!     .unwrap();
//! let evaluator = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
//! let report = evaluator.evaluate(&scene).unwrap();
//! assert_eq!(report.summary.col_sc, Some(false));
//! assert_eq!(report.summary.oob, Some(0.0));
//!
//! let summary = Summary::from_records(&[SceneRecord::ok("scene_0", report)], |_| None);
//! assert_eq!(summary.groups[0].col_ob, Some(0.0));
//! assert!(summary.to_markdown().starts_with("| group | scenes |"));
//! ```

pub use sceneeval_annotation as annotation;
pub use sceneeval_geom as geom;
pub use sceneeval_io as io;
pub use sceneeval_plausibility as plausibility;
pub use sceneeval_relations as relations;
#[cfg(feature = "render")]
pub use sceneeval_render as render;
pub use sceneeval_scene as scene;

mod batch;
mod error;
mod evaluator;
mod plan;
mod record;
mod summary;

pub use batch::{BatchOptions, BatchOutcome, RECORD_FILE, SceneFile, SceneStatus, find_scenes, run_batch};
pub use error::EvalError;
pub use evaluator::{Evaluator, SCENE_REPORT_SCHEMA, SceneReport, SceneSummary};
pub use plan::{EvaluationPlan, Metric};
pub use record::{Outcome, RECORD_SCHEMA, SceneRecord, Stage, benchmark_id};
pub use summary::{ALL_SCENES, GroupSummary, Summary, UNANNOTATED};
