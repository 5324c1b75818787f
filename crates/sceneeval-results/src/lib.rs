//! The result files of SceneEval runs, as types: what `eval.json`, `timing.json` and the
//! summary tables hold, read and written without evaluating anything.
//!
//! - [`SceneReport`]: everything measured on one scene (the geometry metrics' report with the
//!   scene-level [`SceneSummary`], text fidelity, stability, where placement values came from,
//!   the metrics that could not be computed), built once by [`SceneReport::new`].
//! - [`SceneRecord`]: one scene's `eval.json` (its [`SceneName`], [`Fingerprint`] and
//!   [`Outcome`]: the report, or why it failed), read with [`SceneRecord::read`] (which checks
//!   the schema) and written atomically.
//! - [`Metric`]: every metric a run can evaluate under one name, with the summary's columns
//!   and which way each improves ([`Better`]); [`Preset`]: the named parameter presets.
//! - [`Summary`]: the paper's tables (overall and by difficulty) and the per-scene table, from
//!   records; `summary.csv`, `summary.md`, `summary_scenes.csv`.
//! - [`EnsembleVotes`]: an ensemble's votes per spec and the geometry its runs differ in
//!   (the `ensemble` section of a scene report).
//! - [`RunPlan`]: the plan a run folder's results were made with (`plan.json`), with its VLM
//!   and, for an ensemble, the runs it combines.
//! - [`SceneTiming`]: a scene's wall times, `timing.json` (never in `eval.json`, which is the
//!   same from run to run).
//!
//! No field depends on a cargo feature: the stability section is read and written without the
//! rigid-body simulation (`sceneeval-physics` without its `simulate` feature), so that every
//! reader of runs (`sceneeval-report`, `summarize`, `compare`) reads every section.
//! Formats: `docs/formats.md`.
//!
//! ```
//! use sceneeval_results::{Preset, SceneName, SceneRecord, SceneReport, Summary};
//! use sceneeval_plausibility::{Metric, PlausibilityReport, PlausibilitySummary};
//!
//! let geometry = PlausibilityReport::of_summary(
//!     None,
//!     vec![Metric::OutOfBounds],
//!     PlausibilitySummary { oob: Some(0.25), ..PlausibilitySummary::default() },
//! );
//! let report = SceneReport::new(Some("scene_7".into()), geometry, None);
//! let record = SceneRecord::ok(SceneName::new("scene_7"), report);
//! let summary = Summary::from_records([&record], None).with_plan(Preset::Default, "0123456789abcdef");
//! assert_eq!(summary.groups[0].oob, Some(25.0));
//! assert!(summary.to_markdown().contains("Preset: `default`"));
//! ```

mod ensemble;
mod error;
mod fingerprint;
mod metric;
mod name;
mod preset;
mod record;
mod report;
mod run_plan;
mod summary;
mod timing;

pub use ensemble::{EnsembleVotes, GeometryDifference};
pub use error::ResultsError;
pub use fingerprint::{AssetDigest, FileDigest, Fingerprint, TOOL_VERSION};
pub use metric::{Better, Metric, UnknownMetric};
pub use name::SceneName;
pub use preset::{Preset, UnknownPreset};
pub use record::{
    Outcome, READABLE_RECORD_SCHEMAS, RECORD_FILE, RECORD_SCHEMA, SceneRecord, Stage, TIMING_FILE,
};
pub use report::{
    IncompleteMetric, ObjectPlacement, PlacementSource, Provenance, SCENE_REPORT_SCHEMA, SceneReport,
    SceneSummary,
};
pub use run_plan::{JudgeModel, RUN_PLAN_FILE, RUN_PLAN_SCHEMA, RunPlan, SourceRun};
pub use summary::{
    ALL_SCENES, GroupSummary, LEGEND, SUMMARY_CSV, SUMMARY_MD, SUMMARY_SCENES_CSV, SceneRow, Summary,
    UNANNOTATED, difficulty_groups,
};
pub use timing::{SceneTiming, TIMING_SCHEMA};
