//! The SceneEval evaluator: what to evaluate ([`EvaluationPlan`]), on what (the support-type
//! and functional-side sources, a VLM, a renderer of the views it is shown) and the per-scene
//! pipeline, one call for every plan ([`Evaluator::evaluate_scene`]: the geometry metrics,
//! stability, then CNT, ATR, OOR, OAR against the scene's annotation row), which returns the
//! scene's report (`sceneeval_results::SceneReport`), built once. Settling a scene under gravity
//! is `Evaluator::settle_scene` (feature `physics`).
//!
//! What a front end asks is written in request types, each default once: the plan
//! ([`PlanRequest`]), the VLM ([`VlmOptions`], the OpenAI-compatible client and the renderer it
//! needs, attached with [`VlmOptions::attach`]) and a scene to settle ([`SettleRequest`]).
//! A whole run (scenes, files, reuse, parallelism) is `sceneeval-run`'s.
//!
//! The VLM is any `sceneeval_vlm::Vlm` behind one shareable type, [`SharedVlm`], whose waits
//! follow the scene schedule of a batch ([`schedule`]: a scene waiting for the model lends its
//! CPU slot, and the wait ends when its time budget runs out).
//!
//! # Features
//! - `render`: object views rendered for the VLM (`sceneeval-render`, wgpu).
//! - `openai`: the OpenAI-compatible HTTP client (`sceneeval-vlm-openai`, tokio and reqwest).
//! - `physics`: the stability metric's simulation (`sceneeval-physics/simulate`, rapier). A plan
//!   is read and checked in every build, its stability parameters included; one that runs the
//!   metric needs the feature.
//!
//! # Example
//! ```
//! use sceneeval_eval::{Evaluator, EvaluationPlan, SceneInputs};
//! use sceneeval_scene::{Category, RoomBuilder, Scene};
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
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
//! let evaluator = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
//! let report = evaluator.evaluate_scene(&scene, &SceneInputs::default()).unwrap().report;
//! assert_eq!(report.summary.geometry.col_sc, Some(false));
//! assert_eq!(report.summary.geometry.oob, Some(0.0));
//! ```

mod dyn_vlm;
mod error;
mod evaluator;
mod plan;
mod request;
pub mod schedule;

pub use dyn_vlm::SharedVlm;
pub use error::EvalError;
#[cfg(feature = "physics")]
pub use evaluator::Settled;
pub use evaluator::{Evaluator, SceneEvaluation, SceneInputs};
pub use plan::{DEFAULT_TIME_BUDGET_SECONDS, EvaluationPlan, RENAMED_KEYS, read_renamed_keys};
pub use request::{
    ChosenPlan, DEFAULT_PHYSICS_CACHE_DIR, DEFAULT_RENDER_SIZE, DEFAULT_VLM_CACHE_DIR,
    DEFAULT_VLM_CONCURRENCY, DEFAULT_VLM_MAX_RETRIES, DEFAULT_VLM_TIMEOUT_SECONDS, MAX_VLM_TIMEOUT_SECONDS,
    NoVlmFallback, PlanRequest, PlanSpec, PreparedSettle, RENDER_SIZE_RANGE, RequestField, SettleRequest,
    VlmOptions,
};
/// The metrics and presets a plan names (defined with the results they produce).
pub use sceneeval_results::{Metric, Preset};
pub use schedule::BudgetSpent;
