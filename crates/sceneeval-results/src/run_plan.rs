//! [`RunPlan`]: the plan a run folder's results were made with (`plan.json`), so that readers
//! of a run (the ensemble, above all) can say which parameter two runs differ in, not only
//! that their digests differ.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::ResultsError;

/// The name of a run's plan file, in the run folder beside the scene folders.
pub const RUN_PLAN_FILE: &str = "plan.json";

/// The schema name and version of [`RUN_PLAN_FILE`].
pub const RUN_PLAN_SCHEMA: &str = "sceneeval.run-plan/1";

/// The plan of a run folder, as `plan.json` holds it: written by every run (evaluate, and the
/// ensemble) before its first scene, so that an interrupted run has it too.
///
/// Runs written before this file existed have none: [`RunPlan::read`] gives `None`, and a
/// reader knows only each record's plan digest ([`crate::Fingerprint::plan`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunPlan {
    /// Always [`RUN_PLAN_SCHEMA`].
    pub schema: String,
    /// The digest the run's records carry in their fingerprints (`fingerprint.plan`): the
    /// plan's and the VLM's. A record whose digest differs was made by an earlier run with
    /// another plan or VLM in the same folder.
    pub digest: String,
    /// The resolved plan, as a plan file writes it (`preset`, `metrics`, `params`, `read`,
    /// `limits`, `time_budget_s`; `sceneeval_eval::EvaluationPlan` reads it back). Kept
    /// as JSON here, so that reading results does not need the evaluator.
    pub plan: serde_json::Value,
    /// The VLM that answered the run's questions, when one was used.
    pub vlm: Option<JudgeModel>,
    /// For an ensemble (`sceneeval ensemble`): the runs it combines, in vote order. Empty
    /// (absent) for a run of `sceneeval evaluate`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sources: Vec<SourceRun>,
}

/// A VLM as a run used it: its model name and sampling settings (never a key or an address).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct JudgeModel {
    /// The model name sent with each request.
    pub model: String,
    /// The sampling settings as canonical text (`detail=low;seed=42`), empty without any.
    #[serde(default)]
    pub settings: String,
}

/// One of the runs an ensemble combines.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SourceRun {
    /// The run's name (its folder's name; the name its votes are listed under).
    pub name: String,
    /// The run folder as it was given.
    pub path: String,
    /// The run's plan digest ([`RunPlan::digest`]).
    pub digest: String,
    /// The run's plan ([`RunPlan::plan`]): its judge settings (`params.fidelity.matching`,
    /// `params.fidelity.relation_mapping`) may differ from the ensemble's `plan` (the first
    /// run's).
    pub plan: serde_json::Value,
    /// The run's VLM, if any.
    pub vlm: Option<JudgeModel>,
}

impl RunPlan {
    /// The plan file of the run `digest` made with `plan` and `vlm`.
    pub fn new(digest: impl Into<String>, plan: serde_json::Value, vlm: Option<JudgeModel>) -> Self {
        RunPlan {
            schema: RUN_PLAN_SCHEMA.to_owned(),
            digest: digest.into(),
            plan,
            vlm,
            sources: Vec::new(),
        }
    }

    /// Reads `<dir>/plan.json`: `None` when the run has none (a run written before the file
    /// existed).
    ///
    /// # Errors
    /// [`ResultsError::File`] when it exists but cannot be read; [`ResultsError::BadRecord`]
    /// when it is not a plan file of [`RUN_PLAN_SCHEMA`].
    pub fn read(dir: &Path) -> Result<Option<Self>, ResultsError> {
        let path = dir.join(RUN_PLAN_FILE);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => return Err(ResultsError::File { path, source }),
        };
        let plan: RunPlan = serde_json::from_str(&text).map_err(|e| ResultsError::BadRecord {
            path: path.clone(),
            message: e.to_string(),
        })?;
        if plan.schema != RUN_PLAN_SCHEMA {
            return Err(ResultsError::BadRecord {
                path,
                message: format!("schema {:?}, expected {RUN_PLAN_SCHEMA:?}", plan.schema),
            });
        }
        Ok(Some(plan))
    }

    /// Writes `<dir>/plan.json` as pretty JSON, atomically.
    ///
    /// # Errors
    /// [`ResultsError::File`] when it cannot be written.
    pub fn write(&self, dir: &Path) -> Result<(), ResultsError> {
        let path = dir.join(RUN_PLAN_FILE);
        let mut text = serde_json::to_string_pretty(self).map_err(|e| ResultsError::BadRecord {
            path: path.clone(),
            message: e.to_string(),
        })?;
        text.push('\n');
        crate::error::write_atomic(&path, text.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plan_file_round_trips_and_old_runs_have_none() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(RunPlan::read(dir.path()).unwrap(), None);
        let plan = RunPlan::new(
            "abc",
            serde_json::json!({"preset": "default", "metrics": ["cnt"]}),
            Some(JudgeModel {
                model: "m".into(),
                settings: "detail=low".into(),
            }),
        );
        plan.write(dir.path()).unwrap();
        assert_eq!(RunPlan::read(dir.path()).unwrap(), Some(plan.clone()));
        let text = std::fs::read_to_string(dir.path().join(RUN_PLAN_FILE)).unwrap();
        assert!(text.contains("\"schema\": \"sceneeval.run-plan/1\""), "{text}");
        assert!(!text.contains("sources"), "{text}");
        std::fs::write(
            dir.path().join(RUN_PLAN_FILE),
            text.replace(RUN_PLAN_SCHEMA, "x/2"),
        )
        .unwrap();
        let err = RunPlan::read(dir.path()).unwrap_err();
        assert!(
            err.to_string().contains("plan.json") && err.to_string().contains("x/2"),
            "{err}"
        );
    }
}
