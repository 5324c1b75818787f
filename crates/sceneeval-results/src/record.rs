//! [`SceneRecord`]: one scene's `eval.json`.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::{Fingerprint, ResultsError, SceneName, SceneReport};

/// The name of every scene's result file inside its output folder.
pub const RECORD_FILE: &str = "eval.json";

/// The name of every scene's timing file inside its output folder.
pub const TIMING_FILE: &str = "timing.json";

/// The schema name and version of a scene's `eval.json`. Version 2 added the fingerprint;
/// records of version 1 are evaluated again.
pub const RECORD_SCHEMA: &str = "sceneeval.eval/2";

/// The content of one scene's `eval.json`: either its report or why it could not be evaluated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneRecord {
    /// Always [`RECORD_SCHEMA`].
    pub schema: String,
    /// The scene's name (the file stem, e.g. `scene_12`; the field `scene`) and benchmark id
    /// (the digits after its last `_`; the field `scene_id`).
    #[serde(flatten)]
    pub scene: SceneName,
    /// Everything the result depends on; a re-run reuses the record only when it still
    /// matches. `None` for records made in code (never reused).
    #[serde(default)]
    pub fingerprint: Option<Fingerprint>,
    /// What happened.
    #[serde(flatten)]
    pub outcome: Outcome,
}

/// Whether a scene was evaluated, and its report or error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome {
    /// Evaluated.
    Ok {
        /// The report.
        report: Box<SceneReport>,
    },
    /// Evaluated, but some metrics could not be computed ([`SceneReport::incomplete`] says
    /// which and why: a VLM request that got no answer, any other error of one metric); every
    /// other metric's result is kept. A re-run evaluates the scene again (with the response
    /// cache, asking only what is missing).
    Partial {
        /// The report.
        report: Box<SceneReport>,
    },
    /// Not evaluated.
    Failed {
        /// Where it failed.
        stage: Stage,
        /// The error message.
        error: String,
        /// The error's causes, outermost first.
        causes: Vec<String>,
    },
}

/// Where a scene failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Reading the scene file or its assets.
    Load,
    /// Running the metrics.
    Evaluate,
}

impl SceneRecord {
    /// A record of an evaluation: status `ok`, or `partial` when the report lists metrics
    /// that could not be computed ([`SceneReport::incomplete`]).
    pub fn ok(scene: SceneName, report: SceneReport) -> Self {
        let report = Box::new(report);
        SceneRecord {
            schema: RECORD_SCHEMA.to_owned(),
            scene,
            fingerprint: None,
            outcome: if report.incomplete.is_empty() {
                Outcome::Ok { report }
            } else {
                Outcome::Partial { report }
            },
        }
    }

    /// A record of a failure, keeping the whole error chain.
    pub fn failed(scene: SceneName, stage: Stage, error: &(dyn std::error::Error + 'static)) -> Self {
        SceneRecord {
            schema: RECORD_SCHEMA.to_owned(),
            scene,
            fingerprint: None,
            outcome: Outcome::Failed {
                stage,
                error: error.to_string(),
                causes: sceneeval_files::causes(error).map(|c| c.to_string()).collect(),
            },
        }
    }

    /// The record with `fingerprint`.
    pub fn with_fingerprint(mut self, fingerprint: Fingerprint) -> Self {
        self.fingerprint = Some(fingerprint);
        self
    }

    /// The report, if the scene was evaluated (completely or partly).
    pub fn report(&self) -> Option<&SceneReport> {
        match &self.outcome {
            Outcome::Ok { report } | Outcome::Partial { report } => Some(report),
            Outcome::Failed { .. } => None,
        }
    }

    /// The status as `eval.json` writes it: `ok`, `partial` or `failed`.
    pub fn status(&self) -> &'static str {
        match &self.outcome {
            Outcome::Ok { .. } => "ok",
            Outcome::Partial { .. } => "partial",
            Outcome::Failed { .. } => "failed",
        }
    }

    /// Reads a record, checking its schema.
    pub fn read(path: &Path) -> Result<Self, ResultsError> {
        let text = std::fs::read_to_string(path).map_err(|source| ResultsError::File {
            path: path.to_owned(),
            source,
        })?;
        let record: SceneRecord = serde_json::from_str(&text).map_err(|e| ResultsError::BadRecord {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        if record.schema != RECORD_SCHEMA {
            return Err(ResultsError::BadRecord {
                path: path.to_owned(),
                message: format!("schema {:?}, expected {RECORD_SCHEMA:?}", record.schema),
            });
        }
        Ok(record)
    }

    /// Writes the record as pretty JSON, atomically ([`sceneeval_files::write_atomic`]: a synced
    /// temporary file renamed into place), so an interrupted run never leaves a half-written
    /// file behind.
    ///
    /// # Errors
    /// [`ResultsError::File`] when the file cannot be written.
    pub fn write(&self, path: &Path) -> Result<(), ResultsError> {
        let mut text = serde_json::to_string_pretty(self).map_err(|e| ResultsError::BadRecord {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        text.push('\n');
        crate::error::write_atomic(path, text.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_record_keeps_chain_and_round_trips() {
        let inner = std::io::Error::new(std::io::ErrorKind::NotFound, "raw_model.obj missing");
        let outer = ResultsError::File {
            path: "assets/x".into(),
            source: inner,
        };
        let rec = SceneRecord::failed(SceneName::new("scene_3"), Stage::Load, &outer);
        let Outcome::Failed { stage, error, causes } = &rec.outcome else {
            panic!("expected a failure")
        };
        assert_eq!(*stage, Stage::Load);
        assert!(error.contains("assets/x"));
        assert_eq!(causes, &vec!["raw_model.obj missing".to_owned()]);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene_3").join("eval.json");
        rec.write(&path).unwrap();
        assert_eq!(SceneRecord::read(&path).unwrap(), rec);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("\"status\": \"failed\""), "{text}");
        std::fs::write(&path, text.replace(RECORD_SCHEMA, "other/9")).unwrap();
        assert!(matches!(
            SceneRecord::read(&path),
            Err(ResultsError::BadRecord { .. })
        ));
    }
}
