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
    annotation_digest, benchmark_id, matching_file_digest, run_batch,
};

/// The annotation row of a scene: by its id (`12`), or by the number it writes with leading
/// zeros (scene files are often numbered `012`, or `000` for row `0`). One rule for every front
/// end: a run's fingerprints, fidelity rows and summary, and `sceneeval summarize`.
pub fn scene_annotation_row<'a>(annotations: &'a Annotations, scene_id: &str) -> Option<&'a AnnotationRow> {
    annotations.get(scene_id).or_else(|| {
        let number = scene_id.trim_start_matches('0');
        // All zeros is the number 0, not an empty id.
        let number = if number.is_empty() && !scene_id.is_empty() {
            "0"
        } else {
            number
        };
        annotations.get(number)
    })
}

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
    /// The annotation row of a scene ([`scene_annotation_row`] in the run's annotations).
    pub fn annotation_row(&self, scene_id: &str) -> Option<&AnnotationRow> {
        scene_annotation_row(self.annotations?, scene_id)
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
            // The id as the file writes it (`scene_007` -> `007`), as the summary reads it from
            // the record: both find the same row.
            let number = s.id.to_string();
            if let Some(row) = self.annotation_row(benchmark_id(&s.name).unwrap_or(&number)) {
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
        summary.write_to(&self.out_dir)?;
        Ok(FolderOutcome { batch, summary })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_numbered_with_leading_zeros_read_their_row() {
        let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
                   12,easy,A bedroom.,,,,\n\
                   0,hard,A kitchen.,,,,\n\
                   007,medium,A study.,,,,\n";
        let annotations = Annotations::from_csv_reader(csv.as_bytes()).unwrap();
        let difficulty = |id| scene_annotation_row(&annotations, id).map(|r| r.difficulty.as_str());
        assert_eq!(difficulty("12"), Some("easy"));
        assert_eq!(difficulty("012"), Some("easy"));
        assert_eq!(difficulty("0"), Some("hard"));
        assert_eq!(difficulty("000"), Some("hard"));
        // An id written with zeros in the annotations is found as written.
        assert_eq!(difficulty("007"), Some("medium"));
        assert_eq!(difficulty("7"), None);
        assert_eq!(difficulty("13"), None);
        assert_eq!(difficulty(""), None);
    }
}
