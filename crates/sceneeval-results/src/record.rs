//! [`SceneRecord`]: one scene's `eval.json`.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::{Fingerprint, ResultsError, SceneName, SceneReport};

/// The name of every scene's result file inside its output folder.
pub const RECORD_FILE: &str = "eval.json";

/// The name of every scene's timing file inside its output folder.
pub const TIMING_FILE: &str = "timing.json";

/// The schema name and version of a scene's `eval.json`. Version 2 added the fingerprint;
/// records of version 1 are evaluated again. Version 3 writes the scene report's name of the
/// scene as `scene` (`sceneeval.scene-report/2`; `scene_id` is the benchmark id everywhere).
pub const RECORD_SCHEMA: &str = "sceneeval.eval/3";

/// The record schemas [`SceneRecord::read`] reads: [`RECORD_SCHEMA`] and version 2, whose
/// report names the scene under the key `scene_id` (read as `scene`). A run evaluates the
/// scenes of a version-2 record again (its fingerprint names the old schema); `report`,
/// `compare` and `summarize` read it as it is.
pub const READABLE_RECORD_SCHEMAS: [&str; 2] = ["sceneeval.eval/2", RECORD_SCHEMA];

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

    /// Reads a record, checking its schema (one of [`READABLE_RECORD_SCHEMAS`]).
    pub fn read(path: &Path) -> Result<Self, ResultsError> {
        let text = std::fs::read_to_string(path).map_err(|source| ResultsError::File {
            path: path.to_owned(),
            source,
        })?;
        let record: SceneRecord = serde_json::from_str(&text).map_err(|e| ResultsError::BadRecord {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        if !READABLE_RECORD_SCHEMAS.contains(&record.schema.as_str()) {
            return Err(ResultsError::BadRecord {
                path: path.to_owned(),
                message: format!(
                    "schema {:?}, expected one of {}",
                    record.schema,
                    READABLE_RECORD_SCHEMAS.map(|s| format!("{s:?}")).join(", ")
                ),
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

    /// An `eval.json` of schema `sceneeval.eval/2`, as version 0.1.0 wrote it (the report's
    /// `scene_id` held the file stem), reads with the stem as the report's `scene` and the
    /// benchmark id as the record's `scene_id`; written again, it has the new keys.
    #[test]
    fn a_record_of_schema_2_reads_with_the_stem_as_scene() {
        let old = r#"{
  "schema": "sceneeval.eval/2",
  "scene": "scene_007",
  "scene_id": "007",
  "fingerprint": null,
  "status": "ok",
  "report": {
    "schema": "sceneeval.scene-report/1",
    "scene_id": "scene_007",
    "object_ids": ["bed"],
    "metrics": ["out_of_bounds"],
    "summary": {"col_ob": null, "col_sc": null, "sup": null, "nav": null, "all_rooms_reachable": null, "acc": null, "oob": 0.0, "num_doors": null, "doors_blocked": null, "num_windows": null, "windows_blocked": null},
    "collision": null, "support": null, "navigability": null, "accessibility": null, "out_of_bounds": null, "opening_clearance": null
  }
}
"#;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("eval.json");
        std::fs::write(&path, old).unwrap();
        let record = SceneRecord::read(&path).unwrap();
        assert_eq!(record.schema, "sceneeval.eval/2");
        assert_eq!(
            (record.scene.as_str(), record.scene.id()),
            ("scene_007", Some("007"))
        );
        let Some(report) = record.report() else {
            panic!("expected a report")
        };
        assert_eq!(report.scene.as_deref(), Some("scene_007"));
        assert_eq!(report.summary.geometry.oob, Some(0.0));
        let written = serde_json::to_value(report).unwrap();
        assert_eq!(written["scene"], "scene_007");
        assert!(written.get("scene_id").is_none(), "{written}");
    }
}
