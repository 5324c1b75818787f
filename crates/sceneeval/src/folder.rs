//! A whole evaluation run over a folder, as `sceneeval evaluate` and the Python package's
//! `sceneeval.evaluate` do it: [`run_batch`] with each scene's annotation digest, then the
//! summary grouped by the annotations' difficulty, written as `summary.csv` and `summary.md`.
//!
//! The front ends only choose the plan (read by [`crate::PlanChoice`]), the assets and how
//! progress is shown; what is written is decided here, once.

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::annotation::{AnnotationRow, Annotations};
use crate::fidelity::{MatchingMethod, matching_file_for};
use crate::io::AssetLibrary;
use crate::{
    BatchOptions, BatchOutcome, EvalError, Evaluator, SceneFile, SceneRecord, SceneStatus, Summary,
    annotation_digest, matching_file_digest, run_batch, write_atomic,
};

/// The name of the CSV summary written into the output folder.
pub const SUMMARY_CSV: &str = "summary.csv";

/// The name of the Markdown summary written into the output folder.
pub const SUMMARY_MD: &str = "summary.md";

/// How to run a folder of scenes (see [`FolderRun::run`]).
#[derive(Debug, Clone, Default)]
pub struct FolderRun<'a> {
    /// The output folder: `<scene>/eval.json`, `<scene>/timing.json`, the summaries.
    pub out_dir: PathBuf,
    /// Evaluate every scene again, even those whose earlier result still matches.
    pub force: bool,
    /// Also write diagnostic images under `<out_dir>/<scene>/diagnostics/`.
    pub diagnostics: bool,
    /// The SceneEval-500 annotations: rows per difficulty in the summary, each scene's row
    /// digest in its fingerprint, and, when the plan runs fidelity metrics, the row they read.
    pub annotations: Option<&'a Annotations>,
}

/// What a [`FolderRun`] did.
#[derive(Debug, Clone)]
pub struct FolderOutcome {
    /// The per-scene records, statuses and timings.
    pub batch: BatchOutcome,
    /// The summary written to `summary.csv` and `summary.md`.
    pub summary: Summary,
}

impl FolderRun<'_> {
    /// The annotation row of a scene: by its id (`12`), or without leading zeros (`012`).
    pub fn annotation_row(&self, scene_id: &str) -> Option<&AnnotationRow> {
        let annotations = self.annotations?;
        annotations
            .get(scene_id)
            .or_else(|| annotations.get(scene_id.trim_start_matches('0')))
    }

    /// Evaluates `scenes` on the current rayon pool with [`run_batch`] (calling `on_done`
    /// after each scene), then writes `summary.csv` and `summary.md` into the output folder
    /// (the summary's groups: all scenes, each difficulty of the annotations, unannotated).
    ///
    /// # Errors
    /// As [`run_batch`]; [`EvalError::File`] or [`EvalError::Csv`] when a summary cannot be
    /// written.
    pub fn run(
        &self,
        scenes: &[SceneFile],
        evaluator: &Evaluator,
        assets: &AssetLibrary,
        on_done: &(dyn Fn(&SceneFile, &SceneStatus, &SceneRecord) + Sync),
    ) -> Result<FolderOutcome, EvalError> {
        let fidelity = evaluator.plan().has_fidelity();
        let matching_file = match &evaluator.plan().fidelity.matching {
            MatchingMethod::File { path } if fidelity => Some(path),
            _ => None,
        };
        let mut digests = BTreeMap::new();
        let mut rows = BTreeMap::new();
        for s in scenes {
            if let Some(row) = self.annotation_row(&s.id.to_string()) {
                let mut digest = annotation_digest(row);
                if let Some(path) = matching_file {
                    digest = matching_file_digest(&digest, &matching_file_for(path, &s.name));
                }
                digests.insert(s.name.clone(), digest);
                if fidelity {
                    rows.insert(s.name.clone(), row.clone());
                }
            }
        }
        let options = BatchOptions {
            out_dir: self.out_dir.clone(),
            force: self.force,
            diagnostics: self.diagnostics,
            annotations: digests,
            rows,
        };
        let batch = run_batch(scenes, evaluator, assets, &options, on_done)?;
        let difficulty = |r: &SceneRecord| {
            self.annotation_row(r.scene_id.as_deref()?)
                .map(|row| row.difficulty.as_str().to_owned())
        };
        let summary = Summary::from_records(&batch.records, difficulty).with_plan(evaluator.plan());
        write_atomic(&self.out_dir.join(SUMMARY_CSV), summary.to_csv()?.as_bytes())?;
        write_atomic(&self.out_dir.join(SUMMARY_MD), summary.to_markdown().as_bytes())?;
        Ok(FolderOutcome { batch, summary })
    }
}
