//! Evaluating a folder of scenes: one `eval.json` per scene, written as each scene finishes, so
//! an interrupted run loses nothing and a re-run resumes where it stopped, reusing a result
//! only when nothing it depends on changed.

use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::io::{AssetLibrary, read_scene_state};
use crate::plausibility::{Deadline, Metric, MetricTiming};
use crate::{EvalError, Evaluator, Fingerprints, Outcome, SceneRecord, Stage};

/// The name of every scene's result file inside its output folder.
pub const RECORD_FILE: &str = "eval.json";

/// The name of every scene's timing file inside its output folder.
pub const TIMING_FILE: &str = "timing.json";

/// The schema of a scene's `timing.json`.
pub const TIMING_SCHEMA: &str = "sceneeval.timing/1";

/// A scene file found by [`find_scenes`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneFile {
    /// The file stem, e.g. `scene_12`; also the name of its output folder.
    pub name: String,
    /// The benchmark id, the number in the name.
    pub id: u64,
    /// The file.
    pub path: PathBuf,
}

impl SceneFile {
    /// Where this scene's record goes under `out_dir`.
    pub fn record_path(&self, out_dir: &Path) -> PathBuf {
        out_dir.join(&self.name).join(RECORD_FILE)
    }

    /// Where this scene's timing file goes under `out_dir`.
    pub fn timing_path(&self, out_dir: &Path) -> PathBuf {
        out_dir.join(&self.name).join(TIMING_FILE)
    }
}

/// A file of the scene folder that looks like a scene file but is not evaluated.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkippedFile {
    /// The file.
    pub path: PathBuf,
    /// Why it is skipped.
    pub reason: String,
}

/// The scene files of a folder and the near misses that were skipped.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SceneSet {
    /// The `scene_<ID>.json` files, ordered by ID.
    pub scenes: Vec<SceneFile>,
    /// Files whose name starts with `scene_` and ends with `.json` (in any case) that are not
    /// of the form `scene_<digits>.json`, or whose name is not valid UTF-8.
    pub skipped: Vec<SkippedFile>,
}

/// The `scene_<ID>.json` files of a folder (not recursive), `<ID>` one or more ASCII digits
/// and `.json` lower case (as the reference names them), ordered by ID. Files that look like
/// scene files but are not of that form (`scene_1.JSON`, `scene_x.json`,
/// `scene_state_template.json`, a name that is not UTF-8) are listed as skipped, so that the
/// caller can warn.
///
/// # Errors
/// [`EvalError::File`] when the folder cannot be read; [`EvalError::DuplicateSceneId`] when
/// two files have the same ID (`scene_1.json` and `scene_01.json`), before any work is done.
pub fn find_scenes(dir: &Path) -> Result<SceneSet, EvalError> {
    let file_err = |source| EvalError::file(dir, source);
    let mut set = SceneSet::default();
    for entry in std::fs::read_dir(dir).map_err(file_err)? {
        let path = entry.map_err(file_err)?.path();
        let Some(file_name) = path.file_name() else {
            continue;
        };
        let looks_like_scene = {
            let lossy = file_name.to_string_lossy().to_ascii_lowercase();
            lossy.starts_with("scene_") && lossy.ends_with(".json")
        };
        if !looks_like_scene || !path.is_file() {
            continue;
        }
        let skip = |reason: &str| SkippedFile {
            path: path.clone(),
            reason: reason.to_owned(),
        };
        match scene_id_of(file_name) {
            Ok((name, id)) => set.scenes.push(SceneFile {
                name,
                id,
                path: path.clone(),
            }),
            Err(reason) => set.skipped.push(skip(reason)),
        }
    }
    set.scenes
        .sort_by(|a, b| a.id.cmp(&b.id).then_with(|| a.name.cmp(&b.name)));
    set.skipped.sort_by(|a, b| a.path.cmp(&b.path));
    for pair in set.scenes.windows(2) {
        if pair[0].id == pair[1].id {
            return Err(EvalError::DuplicateSceneId {
                id: pair[0].id,
                first: pair[0].path.clone(),
                second: pair[1].path.clone(),
            });
        }
    }
    Ok(set)
}

/// The stem and numeric ID of `scene_<digits>.json`, or why the name is not one.
fn scene_id_of(file_name: &OsStr) -> Result<(String, u64), &'static str> {
    let Some(name) = file_name.to_str() else {
        return Err("the file name is not valid UTF-8");
    };
    let Some(stem) = name.strip_suffix(".json") else {
        return Err("scene files end in lower-case .json");
    };
    let digits = stem.strip_prefix("scene_").unwrap_or("");
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err("not of the form scene_<ID>.json with a numeric ID");
    }
    let id = digits.parse::<u64>().map_err(|_| "the ID is too large")?;
    Ok((stem.to_owned(), id))
}

/// How a batch run treats its scenes.
#[derive(Debug, Clone, Default)]
pub struct BatchOptions {
    /// The folder receiving `<scene>/eval.json`.
    pub out_dir: PathBuf,
    /// Re-evaluate every scene, even those with a matching record.
    pub force: bool,
    /// Also write each scene's diagnostic images under `<scene>/diagnostics/`.
    pub diagnostics: bool,
    /// The annotation row digest of each scene (by scene name), part of its fingerprint.
    pub annotations: BTreeMap<String, String>,
}

/// What happened to one scene of a batch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SceneStatus {
    /// Evaluated in this run; `why` says why an earlier record was not reused.
    Evaluated {
        /// Why the scene was evaluated.
        why: Reason,
    },
    /// A matching record from an earlier run was reused.
    Reused,
    /// Failed to load or evaluate; the record says why.
    Failed {
        /// Why the scene was evaluated.
        why: Reason,
    },
}

/// Why a scene was evaluated rather than its earlier record reused.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reason {
    /// No earlier record.
    New,
    /// Asked to (`force`).
    Forced,
    /// The earlier record is a failure.
    FailedBefore,
    /// The earlier record cannot be read (or has no fingerprint).
    Unreadable(String),
    /// Something the result depends on changed.
    Changed(String),
}

impl std::fmt::Display for Reason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Reason::New => f.write_str("no earlier result"),
            Reason::Forced => f.write_str("forced"),
            Reason::FailedBefore => f.write_str("failed before"),
            Reason::Unreadable(why) => write!(f, "earlier result unreadable: {why}"),
            Reason::Changed(why) => write!(f, "{why}"),
        }
    }
}

/// Wall times of one scene, written to `<scene>/timing.json` (never into `eval.json`, which
/// is identical from run to run).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneTiming {
    /// Always [`TIMING_SCHEMA`].
    pub schema: String,
    /// The scene.
    pub scene: String,
    /// Reading the scene file and its assets, seconds.
    pub load_seconds: f64,
    /// Each metric that ran, in order.
    pub metrics: Vec<MetricTiming>,
    /// The whole scene, seconds.
    pub total_seconds: f64,
}

/// The records of a batch, in scene order, with counts.
#[derive(Debug, Clone)]
pub struct BatchOutcome {
    /// One record per scene, in the order of the input list.
    pub records: Vec<SceneRecord>,
    /// What happened to each scene, in the same order.
    pub statuses: Vec<SceneStatus>,
    /// The timing of each scene evaluated in this run (`None` for reused ones).
    pub timings: Vec<Option<SceneTiming>>,
    /// Scenes evaluated in this run.
    pub evaluated: usize,
    /// Scenes whose earlier record was reused.
    pub reused: usize,
    /// Scenes that failed.
    pub failed: usize,
}

impl BatchOutcome {
    /// How many scenes were evaluated (or failed) for each reason, sorted by reason.
    pub fn reasons(&self) -> BTreeMap<Reason, usize> {
        let mut out = BTreeMap::new();
        for s in &self.statuses {
            if let SceneStatus::Evaluated { why } | SceneStatus::Failed { why } = s {
                *out.entry(why.clone()).or_insert(0) += 1;
            }
        }
        out
    }

    /// Seconds spent per metric over the scenes evaluated in this run, in metric order, and
    /// the seconds spent loading.
    pub fn time_per_metric(&self) -> (f64, Vec<(Metric, f64)>) {
        let mut load = 0.0;
        let mut per: BTreeMap<Metric, f64> = BTreeMap::new();
        for t in self.timings.iter().flatten() {
            load += t.load_seconds;
            for m in &t.metrics {
                *per.entry(m.metric).or_insert(0.0) += m.seconds;
            }
        }
        (load, per.into_iter().collect())
    }
}

/// Evaluates `scenes` in parallel on the current rayon pool, writing each scene's record to
/// `<out_dir>/<scene>/eval.json` and its wall times to `<out_dir>/<scene>/timing.json` as soon
/// as it is done, and calling `on_done` (from the worker thread) after each.
///
/// An earlier record is reused only when its fingerprint still matches (the scene file, every
/// asset and metadata file it was built from, the plan, the tool version and the record
/// schema; see [`Fingerprints::why_stale`]) and unless `options.force`; failed scenes are
/// always retried. A scene that fails to load or evaluate, or runs past the plan's time
/// budget, is recorded as failed and the run goes on. The output folder is checked for
/// writing before any scene is evaluated.
///
/// Results do not depend on the number of threads: each scene is evaluated independently and
/// records are returned in input order.
///
/// # Errors
/// [`EvalError::OutputNotWritable`] before any work when the output folder cannot be written;
/// [`EvalError::File`] when a record cannot be written later (the run stops).
pub fn run_batch(
    scenes: &[SceneFile],
    evaluator: &Evaluator,
    assets: &AssetLibrary,
    options: &BatchOptions,
    on_done: &(dyn Fn(&SceneFile, &SceneStatus, &SceneRecord) + Sync),
) -> Result<BatchOutcome, EvalError> {
    crate::check_output_dir(&options.out_dir)?;
    let fingerprints = Fingerprints::new();
    let plan_digest = evaluator.plan().result_digest();
    type Done = (SceneRecord, SceneStatus, Option<SceneTiming>);
    let results: Vec<Result<Done, EvalError>> = scenes
        .par_iter()
        .map(|scene| {
            let ctx = Ctx {
                evaluator,
                assets,
                options,
                fingerprints: &fingerprints,
                plan_digest: &plan_digest,
            };
            let result = ctx.process(scene);
            if let Ok((record, status, _)) = &result {
                on_done(scene, status, record);
            }
            result
        })
        .collect();
    let mut outcome = BatchOutcome {
        records: Vec::with_capacity(scenes.len()),
        statuses: Vec::with_capacity(scenes.len()),
        timings: Vec::with_capacity(scenes.len()),
        evaluated: 0,
        reused: 0,
        failed: 0,
    };
    for r in results {
        let (record, status, timing) = r?;
        match status {
            SceneStatus::Evaluated { .. } => outcome.evaluated += 1,
            SceneStatus::Reused => outcome.reused += 1,
            SceneStatus::Failed { .. } => outcome.failed += 1,
        }
        outcome.records.push(record);
        outcome.statuses.push(status);
        outcome.timings.push(timing);
    }
    Ok(outcome)
}

struct Ctx<'a> {
    evaluator: &'a Evaluator,
    assets: &'a AssetLibrary,
    options: &'a BatchOptions,
    fingerprints: &'a Fingerprints,
    plan_digest: &'a str,
}

impl Ctx<'_> {
    /// Whether the earlier record can be reused; why not otherwise.
    fn reuse(&self, scene: &SceneFile, path: &Path) -> Result<SceneRecord, Reason> {
        if self.options.force {
            return Err(Reason::Forced);
        }
        if !path.exists() {
            return Err(Reason::New);
        }
        let record = SceneRecord::read(path).map_err(|e| Reason::Unreadable(e.to_string()))?;
        if !matches!(record.outcome, Outcome::Ok { .. }) {
            return Err(Reason::FailedBefore);
        }
        let Some(old) = &record.fingerprint else {
            return Err(Reason::Unreadable("it has no fingerprint".into()));
        };
        // No metric of this crate reads the annotation row yet; the text-fidelity metrics will.
        let compare_annotation = false;
        match self.fingerprints.why_stale(
            old,
            &scene.path,
            self.assets,
            self.plan_digest,
            self.options.annotations.get(&scene.name).map(String::as_str),
            compare_annotation,
        ) {
            None => Ok(record),
            Some(why) => Err(Reason::Changed(why)),
        }
    }

    fn process(
        &self,
        scene: &SceneFile,
    ) -> Result<(SceneRecord, SceneStatus, Option<SceneTiming>), EvalError> {
        let path = scene.record_path(&self.options.out_dir);
        let why = match self.reuse(scene, &path) {
            Ok(record) => return Ok((record, SceneStatus::Reused, None)),
            Err(why) => why,
        };
        tracing::info!(scene = %scene.name, reason = %why, "evaluating");
        let plan = self.evaluator.plan();
        // A budget too large for a `Duration` (validated finite and positive) is no budget.
        let deadline = match plan
            .time_budget_seconds
            .and_then(|b| Duration::try_from_secs_f64(b).ok())
        {
            Some(b) => Deadline::after(b),
            None => Deadline::none(),
        };
        let start = Instant::now();
        let mut timing = SceneTiming {
            schema: TIMING_SCHEMA.to_owned(),
            scene: scene.name.clone(),
            load_seconds: 0.0,
            metrics: Vec::new(),
            total_seconds: 0.0,
        };
        let loaded = read_scene_state(&scene.path, self.assets, &plan.read);
        timing.load_seconds = start.elapsed().as_secs_f64();
        let failed =
            |stage, e: &(dyn std::error::Error + 'static)| SceneRecord::failed(&scene.name, stage, e);
        let (record, ok) = match loaded {
            Err(e) => (failed(Stage::Load, &e), false),
            Ok(loaded) => match deadline.check("loading") {
                Err(e) => (failed(Stage::Load, &EvalError::from(e)), false),
                Ok(()) => match self
                    .evaluator
                    .evaluate_within(&loaded, &deadline, &mut timing.metrics)
                {
                    Err(e) => (failed(Stage::Evaluate, &e), false),
                    Ok(mut report) => {
                        report.plausibility.scene_id = Some(scene.name.clone());
                        if self.options.diagnostics {
                            self.diagnostics(scene, &loaded);
                        }
                        let fingerprint = self.fingerprints.of_loaded(
                            &scene.path,
                            &loaded,
                            self.assets,
                            self.plan_digest,
                            self.options.annotations.get(&scene.name).cloned(),
                        );
                        (
                            SceneRecord::ok(&scene.name, report).with_fingerprint(fingerprint),
                            true,
                        )
                    }
                },
            },
        };
        timing.total_seconds = start.elapsed().as_secs_f64();
        if let Outcome::Failed { error, .. } = &record.outcome {
            tracing::info!(scene = %scene.name, %error, "scene failed");
        }
        record.write(&path)?;
        let mut text = serde_json::to_string_pretty(&timing).map_err(|e| EvalError::BadRecord {
            path: scene.timing_path(&self.options.out_dir),
            message: e.to_string(),
        })?;
        text.push('\n');
        crate::write_atomic(&scene.timing_path(&self.options.out_dir), text.as_bytes())?;
        let status = if ok {
            SceneStatus::Evaluated { why }
        } else {
            SceneStatus::Failed { why }
        };
        Ok((record, status, Some(timing)))
    }

    fn diagnostics(&self, scene: &SceneFile, loaded: &crate::scene::Scene) {
        let dir = self.options.out_dir.join(&scene.name).join("diagnostics");
        if let Err(e) = crate::plausibility::write_diagnostics(
            loaded,
            &self.evaluator.plan().params,
            self.evaluator.sources(),
            &dir,
        ) {
            tracing::warn!(scene = %scene.name, error = %e, "diagnostic images not written");
        }
    }
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
            "scene_3.JSON",
            "scene_state_template.json",
        ] {
            std::fs::write(dir.path().join(name), "{}").unwrap();
        }
        std::fs::create_dir(dir.path().join("scene_4.json")).unwrap();
        let set = find_scenes(dir.path()).unwrap();
        let names: Vec<(&str, u64)> = set.scenes.iter().map(|s| (s.name.as_str(), s.id)).collect();
        assert_eq!(names, vec![("scene_2", 2), ("scene_10", 10)]);
        let skipped: Vec<String> = set
            .skipped
            .iter()
            .map(|s| s.path.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            skipped,
            vec!["scene_3.JSON", "scene_state_template.json", "scene_x.json"]
        );
        assert!(set.skipped[0].reason.contains("lower-case .json"));
        assert!(matches!(
            find_scenes(&dir.path().join("missing")),
            Err(EvalError::File { .. })
        ));
    }

    #[test]
    fn duplicate_ids_are_an_error_before_any_work() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["scene_1.json", "scene_01.json", "scene_2.json"] {
            std::fs::write(dir.path().join(name), "{}").unwrap();
        }
        let err = find_scenes(dir.path()).unwrap_err();
        assert!(matches!(err, EvalError::DuplicateSceneId { id: 1, .. }), "{err}");
        let text = err.to_string();
        assert!(
            text.contains("scene_01.json") && text.contains("scene_1.json") && text.contains("same id 1"),
            "{text}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn names_that_are_not_utf8_are_reported() {
        use std::os::unix::ffi::OsStrExt;
        let dir = tempfile::tempdir().unwrap();
        let name = OsStr::from_bytes(b"scene_\xff1.json");
        std::fs::write(dir.path().join(name), "{}").unwrap();
        let set = find_scenes(dir.path()).unwrap();
        assert!(set.scenes.is_empty());
        assert_eq!(set.skipped.len(), 1);
        assert!(set.skipped[0].reason.contains("not valid UTF-8"));
    }
}
