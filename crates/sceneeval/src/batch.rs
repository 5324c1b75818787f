//! Evaluating a folder of scenes: one `eval.json` per scene, written as each scene finishes, so
//! an interrupted run loses nothing and a re-run resumes where it stopped.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::io::{AssetLibrary, ReadOptions, read_scene_state};
use crate::record::benchmark_id;
use crate::{EvalError, Evaluator, Outcome, SceneRecord, Stage};

/// The name of every scene's result file inside its output folder.
pub const RECORD_FILE: &str = "eval.json";

/// A scene file found by [`find_scenes`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneFile {
    /// The file stem, e.g. `scene_12`; also the name of its output folder.
    pub name: String,
    /// The file.
    pub path: PathBuf,
}

impl SceneFile {
    /// Where this scene's record goes under `out_dir`.
    pub fn record_path(&self, out_dir: &Path) -> PathBuf {
        out_dir.join(&self.name).join(RECORD_FILE)
    }
}

/// The `scene_<ID>.json` files of a folder (not recursive), ordered by their numeric id, then by
/// name for files whose id is not a number.
pub fn find_scenes(dir: &Path) -> Result<Vec<SceneFile>, EvalError> {
    let file_err = |source| EvalError::File {
        path: dir.to_owned(),
        source,
    };
    let mut scenes = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(file_err)? {
        let path = entry.map_err(file_err)?.path();
        let is_json = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let Some(name) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if is_json && name.starts_with("scene_") && path.is_file() {
            scenes.push(SceneFile {
                name: name.to_owned(),
                path,
            });
        }
    }
    let key = |s: &SceneFile| benchmark_id(&s.name).and_then(|id| id.parse::<u64>().ok());
    scenes.sort_by(|a, b| match (key(a), key(b)) {
        (Some(x), Some(y)) => x.cmp(&y).then_with(|| a.name.cmp(&b.name)),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => a.name.cmp(&b.name),
    });
    Ok(scenes)
}

/// How a batch run treats its scenes.
#[derive(Debug, Clone, Default)]
pub struct BatchOptions {
    /// The folder receiving `<scene>/eval.json`.
    pub out_dir: PathBuf,
    /// Re-evaluate scenes that already have a successful record.
    pub force: bool,
    /// How scene files are read.
    pub read: ReadOptions,
    /// Also write each scene's diagnostic images under `<scene>/diagnostics/`.
    pub diagnostics: bool,
}

/// What happened to one scene of a batch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneStatus {
    /// Evaluated in this run.
    Evaluated,
    /// A successful record from an earlier run was kept.
    Skipped,
    /// Failed to load or evaluate; the record says why.
    Failed,
}

/// The records of a batch, in scene order, with counts.
#[derive(Debug, Clone)]
pub struct BatchOutcome {
    /// One record per scene, in the order of the input list.
    pub records: Vec<SceneRecord>,
    /// Scenes evaluated in this run.
    pub evaluated: usize,
    /// Scenes kept from an earlier run.
    pub skipped: usize,
    /// Scenes that failed.
    pub failed: usize,
}

/// Evaluates `scenes` in parallel on the current rayon pool, writing each scene's record to
/// `<out_dir>/<scene>/eval.json` as soon as it is done and calling `on_done` (from the worker
/// thread) after each. A scene with a successful record from an earlier run is skipped unless
/// `options.force`; failed scenes are always retried. A scene that fails to load or evaluate is
/// recorded as failed and the run goes on.
///
/// Results do not depend on the number of threads: each scene is evaluated independently and
/// records are returned in input order.
///
/// # Errors
/// Only when a record cannot be written (the output folder is not writable): the run stops.
pub fn run_batch(
    scenes: &[SceneFile],
    evaluator: &Evaluator,
    assets: &AssetLibrary,
    options: &BatchOptions,
    on_done: &(dyn Fn(&SceneFile, SceneStatus) + Sync),
) -> Result<BatchOutcome, EvalError> {
    let results: Vec<Result<(SceneRecord, SceneStatus), EvalError>> = scenes
        .par_iter()
        .map(|scene| {
            let result = process(scene, evaluator, assets, options);
            if let Ok((_, status)) = &result {
                on_done(scene, *status);
            }
            result
        })
        .collect();
    let mut outcome = BatchOutcome {
        records: Vec::with_capacity(scenes.len()),
        evaluated: 0,
        skipped: 0,
        failed: 0,
    };
    for r in results {
        let (record, status) = r?;
        match status {
            SceneStatus::Evaluated => outcome.evaluated += 1,
            SceneStatus::Skipped => outcome.skipped += 1,
            SceneStatus::Failed => outcome.failed += 1,
        }
        outcome.records.push(record);
    }
    Ok(outcome)
}

fn process(
    scene: &SceneFile,
    evaluator: &Evaluator,
    assets: &AssetLibrary,
    options: &BatchOptions,
) -> Result<(SceneRecord, SceneStatus), EvalError> {
    let path = scene.record_path(&options.out_dir);
    if !options.force && path.exists() {
        match SceneRecord::read(&path) {
            Ok(rec) if matches!(rec.outcome, Outcome::Ok { .. }) => return Ok((rec, SceneStatus::Skipped)),
            Ok(_) => tracing::info!(scene = %scene.name, "retrying a scene that failed before"),
            Err(e) => {
                tracing::warn!(scene = %scene.name, error = %e, "unreadable earlier record; evaluating again")
            }
        }
    }
    let (record, status) = match read_scene_state(&scene.path, assets, &options.read) {
        Err(e) => {
            tracing::warn!(scene = %scene.name, error = %e, "scene failed to load");
            (
                SceneRecord::failed(&scene.name, Stage::Load, &e),
                SceneStatus::Failed,
            )
        }
        Ok(loaded) => match evaluator.evaluate(&loaded) {
            Err(e) => {
                tracing::warn!(scene = %scene.name, error = %e, "scene failed to evaluate");
                (
                    SceneRecord::failed(&scene.name, Stage::Evaluate, &e),
                    SceneStatus::Failed,
                )
            }
            Ok(mut report) => {
                report.scene_id = scene.name.clone();
                if options.diagnostics {
                    let dir = options.out_dir.join(&scene.name).join("diagnostics");
                    if let Err(e) = crate::plausibility::write_diagnostics(
                        &loaded,
                        &evaluator.plan().params,
                        evaluator.sources(),
                        &dir,
                    ) {
                        tracing::warn!(scene = %scene.name, error = %e, "diagnostic images not written");
                    }
                }
                (SceneRecord::ok(&scene.name, report), SceneStatus::Evaluated)
            }
        },
    };
    record.write(&path)?;
    Ok((record, status))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_scene_files_in_numeric_order() {
        let dir = tempfile::tempdir().unwrap();
        for name in [
            "scene_10.json",
            "scene_2.json",
            "scene_x.json",
            "notes.json",
            "scene_1.txt",
        ] {
            std::fs::write(dir.path().join(name), "{}").unwrap();
        }
        std::fs::create_dir(dir.path().join("scene_3.json")).unwrap();
        let names: Vec<String> = find_scenes(dir.path())
            .unwrap()
            .into_iter()
            .map(|s| s.name)
            .collect();
        assert_eq!(names, vec!["scene_2", "scene_10", "scene_x"]);
        assert!(matches!(
            find_scenes(&dir.path().join("missing")),
            Err(EvalError::File { .. })
        ));
    }
}
