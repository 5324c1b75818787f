//! A SceneEval evaluation run: a folder of scene files evaluated under one plan into an output
//! folder, with each default written once.
//!
//! - [`EvaluationRequest`]: everything a run is asked to do (scenes, assets, output folder,
//!   annotations, plan, VLM, threads, shard), the one request both front ends build
//!   (`sceneeval evaluate`'s flags, Python's `sceneeval.evaluate`'s keyword arguments);
//!   [`EvaluationRequest::prepare`] checks it before any work and [`PreparedRun::run`] runs it
//!   (or [`PreparedRun::dry_run`] counts what it would ask the VLM).
//! - [`find_scenes`]: a folder's `scene_<ID>.json` files, each scene's identity made once
//!   ([`SceneFile`]).
//! - [`run_batch`]: files, fingerprints, reuse and parallelism: one `eval.json` per scene,
//!   written as it finishes, reused only while its [`Fingerprint`](sceneeval_results::Fingerprint)
//!   matches ([`Fingerprints`]); with a VLM more scenes in flight than CPU workers, each lending
//!   its slot while it waits for the model.
//! - the output folder: checked for writing before any work ([`check_output_dir`]) and held by
//!   one run at a time ([`OutputLock`]); then the paper's tables
//!   (`sceneeval_results::Summary`).
//!
//! - [`ensemble`]: runs made with different judges on the same scenes combined into one run
//!   folder, each text-fidelity verdict the majority of the runs' (`sceneeval ensemble`).
//!
//! What happens to one scene is `sceneeval_eval::Evaluator::evaluate_scene`. The data flow:
//! `docs/architecture.md`.
//!
//! # Features
//! `render`, `openai` and `physics` turn on the evaluator's (`sceneeval-eval`): the renderer
//! of the VLM's views, the OpenAI-compatible HTTP client, the stability metric's simulation.

mod batch;
mod dry_run;
mod ensemble;
mod error;
mod files;
mod fingerprint;
mod request;
mod scene_file;

pub use batch::{BatchOptions, BatchOutcome, Reason, RunEvent, SceneStatus, run_batch};
pub use dry_run::{DryRun, TaskCost};
pub use ensemble::{EnsembleError, EnsembleOptions, EnsembleOutcome, ensemble};
pub use error::RunError;
pub use files::{LOCK_FILE, OutputLock, check_output_dir};
pub use fingerprint::{Fingerprints, annotation_digest, matching_file_digest};
pub use request::{EvaluationRequest, PreparedRun, RunOutcome, Shard};
pub use scene_file::{SceneFile, SceneSet, SkippedFile, find_scenes};
