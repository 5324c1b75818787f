//! Ensembles of judges: runs made with different judges on the same scenes, annotations and
//! plan, combined into one run folder whose every text-fidelity verdict is the majority of the
//! runs' ([`ensemble`]).
//!
//! The ensemble lives here, beside the batch, because it writes a run folder as a run does
//! (`plan.json`, `<scene>/eval.json`, the summaries, through the same atomic writes and output
//! lock) and checks plans as [`EvaluationPlan`]s; the scores are recounted by the fidelity
//! crate's own counting ([`FidelityReport::revote`]), the majority is
//! [`sceneeval_stats::Majority`].

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use sceneeval_annotation::Annotations;
use sceneeval_eval::{EvalError, EvaluationPlan};
use sceneeval_fidelity::{FidelityMetric, FidelityReport, MatchingMethod, Revote};
use sceneeval_results::{
    EnsembleVotes, GeometryDifference, Metric, Outcome, RECORD_FILE, ResultsError, RunPlan, SceneName,
    SceneRecord, SceneReport, SourceRun, Summary,
};
use sceneeval_stats::{Decision, Majority};
use serde_json::Value;
use thiserror::Error;

use crate::{OutputLock, RunError, check_output_dir};

/// Why runs cannot be combined, or the ensemble cannot be written. Every variant names the
/// runs (as given) and what differs.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum EnsembleError {
    /// Fewer than two runs.
    #[error("an ensemble combines at least two runs; {given} given")]
    TooFewRuns {
        /// How many were given.
        given: usize,
    },
    /// A run folder or one of its files cannot be read.
    #[error("run {}: cannot read it", run.display())]
    Read {
        /// The run folder.
        run: PathBuf,
        /// Why.
        #[source]
        source: ResultsError,
    },
    /// A run folder holds no `<scene>/eval.json`.
    #[error("run {} holds no <scene>/eval.json", run.display())]
    NoRecords {
        /// The run folder.
        run: PathBuf,
    },
    /// A run has no `plan.json` (written before runs recorded their plan).
    #[error(
        "run {} has no plan.json (it was written before runs recorded their plan), so the ensemble cannot \
         check that it differs from the others only in the judge; run the same `sceneeval evaluate` on it \
         again: its results are reused and plan.json is written",
        run.display()
    )]
    NoPlan {
        /// The run folder.
        run: PathBuf,
    },
    /// A run's `plan.json` does not hold a valid plan.
    #[error("run {}: plan.json does not hold a valid plan", run.display())]
    BadPlan {
        /// The run folder.
        run: PathBuf,
        /// Why.
        #[source]
        source: Box<EvalError>,
    },
    /// Two runs' plans differ in something else than the judge.
    #[error(
        "runs {} and {} differ in the plan's `{field}` ({first_value} and {value}): an ensemble combines runs that \
         differ only in the judge (the VLM, params.fidelity.matching, params.fidelity.size_aware_matching, \
         params.fidelity.relation_mapping)",
        first.display(),
        run.display()
    )]
    PlansDiffer {
        /// The first run.
        first: PathBuf,
        /// The run that differs.
        run: PathBuf,
        /// The plan field, as a plan file names it (`params.collision.contact_tolerance_m`).
        field: String,
        /// Its value in the first run (JSON).
        first_value: String,
        /// Its value in `run` (JSON).
        value: String,
    },
    /// A scene is in one run and not in another.
    #[error("scene {scene} is in run {} but not in run {}: an ensemble combines runs of the same scenes",
        has.display(), lacks.display())]
    ScenesDiffer {
        /// The scene.
        scene: String,
        /// The run that has it.
        has: PathBuf,
        /// The run that does not.
        lacks: PathBuf,
    },
    /// A record was made with another plan than its run's `plan.json`.
    #[error(
        "run {}: {scene}/eval.json was made with another plan or VLM than the run's plan.json (an earlier run \
         in the same folder); evaluate the run again",
        run.display()
    )]
    StaleRecord {
        /// The run folder.
        run: PathBuf,
        /// The scene.
        scene: String,
    },
    /// Two runs checked a scene against different annotation rows.
    #[error("runs {} and {} checked scene {scene} against different annotation rows", first.display(), run.display())]
    AnnotationsDiffer {
        /// The first run.
        first: PathBuf,
        /// The run that differs.
        run: PathBuf,
        /// The scene.
        scene: String,
    },
    /// Two runs have different specs for a scene's metric.
    #[error("runs {} and {} have different {metric} specs for scene {scene}: {detail}", first.display(), run.display())]
    SpecsDiffer {
        /// The first run.
        first: PathBuf,
        /// The run that differs.
        run: PathBuf,
        /// The scene.
        scene: String,
        /// The metric.
        metric: FidelityMetric,
        /// What differs.
        detail: String,
    },
    /// The output folder is one of the runs.
    #[error("the output folder {} is one of the runs combined; write the ensemble to another folder", out.display())]
    OutputIsSource {
        /// The folder.
        out: PathBuf,
    },
    /// The output folder holds results of other scenes.
    #[error("the output folder {} already holds results of scene {scene}, which is not in the runs; use an empty folder", out.display())]
    OutputHasOtherScenes {
        /// The folder.
        out: PathBuf,
        /// A scene found there.
        scene: String,
    },
    /// Writing the output failed.
    #[error(transparent)]
    Write(Box<RunError>),
}

impl From<RunError> for EnsembleError {
    fn from(e: RunError) -> Self {
        EnsembleError::Write(Box::new(e))
    }
}

/// Per spec of a metric: the majority's verdict, every run's vote; and how many specs tied.
type Tally = (Vec<Revote>, Vec<Vec<Option<bool>>>, usize);

/// Where an ensemble is written and how its summary groups scenes.
#[derive(Debug, Clone, Default)]
pub struct EnsembleOptions<'a> {
    /// The run folder receiving the ensemble (created; it must not be one of the runs).
    pub out_dir: PathBuf,
    /// The annotations, for the summary's rows per difficulty (as `sceneeval summarize`).
    pub annotations: Option<&'a Annotations>,
}

/// What [`ensemble`] wrote.
#[derive(Debug, Clone)]
pub struct EnsembleOutcome {
    /// The source runs' names, in vote order.
    pub runs: Vec<String>,
    /// One record per scene, in scene order.
    pub records: Vec<SceneRecord>,
    /// Every geometry metric a run's result differs in from the first run's, per scene.
    pub differences: Vec<(SceneName, GeometryDifference)>,
    /// Specs whose runs tied (no verdict, counted as unanswered).
    pub ties: usize,
    /// The summary written to `summary.csv` and `summary.md`.
    pub summary: Summary,
}

/// One source run, read.
struct Source {
    path: PathBuf,
    name: String,
    plan: RunPlan,
    parsed: EvaluationPlan,
    records: BTreeMap<String, SceneRecord>,
}

/// Combines `runs` (run folders of `sceneeval evaluate`, each with its `plan.json`) into one run
/// folder at `options.out_dir`:
///
/// - checked first: the runs have the same scenes, each scene's annotation row (its digest in
///   the records' fingerprints; not compared when a run matches from a file, whose digest
///   holds the file) and the same spec texts per metric, and plans equal in everything but the
///   judge: the VLM (model and settings), `params.fidelity.matching`,
///   `params.fidelity.size_aware_matching` and `params.fidelity.relation_mapping` (the preset's
///   name, the limits and the time budget, which do not change a result, are not compared);
///   otherwise an [`EnsembleError`] naming the runs and the field, scene or spec;
/// - every spec's verdict is the majority of the runs' verdicts ([`Majority`]; runs without
///   one abstain); a tie, or no verdict at all, is `null` and counted as unanswered;
///   the scores are recounted by [`FidelityReport::revote`], the evaluation's own counting;
/// - everything else (geometry, stability, placement, each spec's evidence) is the first
///   run's; where another run's geometry metric differs (support types and functional sides
///   answered by another judge), a [`GeometryDifference`] is recorded in the scene's
///   `ensemble` section and logged as a warning;
/// - a scene that failed in any run fails in the ensemble (the error names the run); a metric
///   incomplete in the first run stays incomplete; a run where it is incomplete abstains.
///
/// Written: `plan.json` (the first run's plan, the sources), `<scene>/eval.json` with the
/// `ensemble` section (the runs and each spec's votes) and the summaries, atomically, under
/// the output folder's lock; and, from the first run as its geometry is, each scene's kept
/// files (`views/*.png`, the views shown to the VLM; `diagnostics/*.png`; `matching.json`), so
/// that the report of the ensemble shows them as a run's does.
///
/// # Errors
/// [`EnsembleError`].
pub fn ensemble(runs: &[PathBuf], options: &EnsembleOptions<'_>) -> Result<EnsembleOutcome, EnsembleError> {
    if runs.len() < 2 {
        return Err(EnsembleError::TooFewRuns { given: runs.len() });
    }
    let sources = read_sources(runs)?;
    check_same(&sources)?;
    let out = &options.out_dir;
    check_output_dir(out)?;
    let out_canonical = out.canonicalize().ok();
    if runs.iter().any(|r| r.canonicalize().ok() == out_canonical) {
        return Err(EnsembleError::OutputIsSource { out: out.clone() });
    }
    let _lock = OutputLock::acquire(out)?;
    let first = &sources[0];
    if let Some(scene) = scenes_in(out)
        .map_err(|source| EnsembleError::Read {
            run: out.clone(),
            source,
        })?
        .into_iter()
        .find(|s| !first.records.contains_key(s))
    {
        return Err(EnsembleError::OutputHasOtherScenes {
            out: out.clone(),
            scene,
        });
    }
    let digest = ensemble_digest(&sources);
    let mut plan = RunPlan::new(digest.clone(), first.plan.plan.clone(), None);
    plan.sources = sources
        .iter()
        .map(|s| SourceRun {
            name: s.name.clone(),
            path: s.path.display().to_string(),
            digest: s.plan.digest.clone(),
            plan: s.plan.plan.clone(),
            vlm: s.plan.vlm.clone(),
        })
        .collect();
    plan.write(out).map_err(RunError::from)?;
    let names: Vec<String> = sources.iter().map(|s| s.name.clone()).collect();
    let mut records = Vec::new();
    let mut differences = Vec::new();
    let mut ties = 0;
    for scene in first.records.keys() {
        let (record, tied, diffs) = combine(&sources, scene, &names, &digest)?;
        ties += tied;
        differences.extend(diffs.into_iter().map(|d| (record.scene.clone(), d)));
        let path = out.join(scene).join(RECORD_FILE);
        record.write(&path).map_err(RunError::from)?;
        // A scene's folder is named by the scene: only a plain name is followed to copy from.
        let mut parts = Path::new(scene).components();
        if let (Some(std::path::Component::Normal(_)), None) = (parts.next(), parts.next()) {
            copy_scene_files(&first.path.join(scene), &out.join(scene))?;
        }
        records.push(record);
    }
    let summary = Summary::from_records(&records, options.annotations).with_plan(first.parsed.preset, digest);
    summary.write_to(out).map_err(RunError::from)?;
    Ok(EnsembleOutcome {
        runs: names,
        records,
        differences,
        ties,
        summary,
    })
}

/// The files of a scene's folder that an ensemble copies from its first run (the matching its
/// verdicts were made on), beside [`SCENE_IMAGE_DIRS`].
const SCENE_FILES: [&str; 1] = [sceneeval_fidelity::MATCHING_FILE];

/// The folders of a scene's images that an ensemble copies from its first run, their PNG files
/// only: the object views shown to the VLM and the diagnostic images.
const SCENE_IMAGE_DIRS: [&str; 2] = ["views", "diagnostics"];

/// Copies a scene's kept files ([`SCENE_FILES`], the PNGs of [`SCENE_IMAGE_DIRS`]) from the
/// first run's scene folder `from` into `to`, each atomically. Only regular files are copied:
/// a symbolic link (which could lead out of the run) is skipped with a warning, and what the
/// run did not keep is not an error.
fn copy_scene_files(from: &Path, to: &Path) -> Result<(), RunError> {
    let mut files: Vec<(PathBuf, PathBuf)> = SCENE_FILES.iter().map(|f| (from.join(f), to.join(f))).collect();
    for dir in SCENE_IMAGE_DIRS {
        let entries = match std::fs::read_dir(from.join(dir)) {
            Ok(entries) => entries,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
            Err(e) => return Err(RunError::file(from.join(dir), e)),
        };
        let mut names = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|e| RunError::file(from.join(dir), e))?;
            let name = entry.file_name();
            if Path::new(&name)
                .extension()
                .is_some_and(|x| x.eq_ignore_ascii_case("png"))
            {
                names.push(name);
            }
        }
        names.sort();
        files.extend(
            names
                .into_iter()
                .map(|n| (from.join(dir).join(&n), to.join(dir).join(&n))),
        );
    }
    for (source, target) in files {
        match std::fs::symlink_metadata(&source) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
            Err(e) => return Err(RunError::file(source, e)),
            Ok(meta) if !meta.is_file() => {
                tracing::warn!(file = %source.display(), "not a regular file: not copied into the ensemble");
                continue;
            }
            Ok(_) => {}
        }
        let mut bytes = Vec::new();
        sceneeval_files::open_regular(&source)
            .and_then(|mut f| std::io::Read::read_to_end(&mut f, &mut bytes))
            .map_err(|e| RunError::file(&source, e))?;
        sceneeval_files::write_atomic(&target, &bytes).map_err(|e| RunError::file(&target, e))?;
    }
    Ok(())
}

/// The scene name of a record, as the ensemble keys scenes.
fn scene_of(record: &SceneRecord) -> &str {
    record.scene.as_str()
}

/// The scenes with a record in `dir` (none when it does not exist).
fn scenes_in(dir: &Path) -> Result<Vec<String>, ResultsError> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| ResultsError::file(dir, e))?;
        if entry.path().join(RECORD_FILE).is_file() {
            out.push(entry.file_name().to_string_lossy().into_owned());
        }
    }
    Ok(out)
}

/// Reads each run's plan and records; names the runs by their folder names (by the paths as
/// given when two folder names are the same).
fn read_sources(runs: &[PathBuf]) -> Result<Vec<Source>, EnsembleError> {
    let folder_names: Vec<String> = runs
        .iter()
        .map(|r| {
            r.file_name()
                .map_or_else(|| r.display().to_string(), |n| n.to_string_lossy().into_owned())
        })
        .collect();
    let unique = folder_names.iter().collect::<BTreeSet<_>>().len() == runs.len();
    let mut sources = Vec::new();
    for (path, folder) in runs.iter().zip(folder_names) {
        let read = |source| EnsembleError::Read {
            run: path.clone(),
            source,
        };
        let plan = RunPlan::read(path)
            .map_err(read)?
            .ok_or_else(|| EnsembleError::NoPlan { run: path.clone() })?;
        let parsed: EvaluationPlan =
            EvaluationPlan::from_json_str(&plan.plan.to_string()).map_err(|source| {
                EnsembleError::BadPlan {
                    run: path.clone(),
                    source: Box::new(source),
                }
            })?;
        let mut records = BTreeMap::new();
        for scene in scenes_in(path).map_err(read)? {
            let record = SceneRecord::read(&path.join(&scene).join(RECORD_FILE)).map_err(read)?;
            if record.fingerprint.as_ref().is_some_and(|f| f.plan != plan.digest) {
                return Err(EnsembleError::StaleRecord {
                    run: path.clone(),
                    scene,
                });
            }
            records.insert(scene_of(&record).to_owned(), record);
        }
        if records.is_empty() {
            return Err(EnsembleError::NoRecords { run: path.clone() });
        }
        sources.push(Source {
            name: if unique {
                folder
            } else {
                path.display().to_string()
            },
            path: path.clone(),
            plan,
            parsed,
            records,
        });
    }
    Ok(sources)
}

/// `plan` with the judge and the fields that do not change a result set to `like`'s, and its
/// metrics as a sorted set.
fn without_judge(plan: &EvaluationPlan, like: &EvaluationPlan) -> EvaluationPlan {
    let mut p = plan.clone();
    p.preset = like.preset;
    p.limits = like.limits;
    p.time_budget_s = like.time_budget_s;
    p.read.strict = like.read.strict;
    p.fidelity.matching = like.fidelity.matching.clone();
    p.fidelity.size_aware_matching = like.fidelity.size_aware_matching;
    p.fidelity.relation_mapping = like.fidelity.relation_mapping;
    p.metrics.sort();
    p
}

/// The first field (as a dotted path) where `a` and `b` differ, with both values.
fn first_difference(a: &Value, b: &Value, path: &str) -> Option<(String, String, String)> {
    if a == b {
        return None;
    }
    if let (Value::Object(x), Value::Object(y)) = (a, b) {
        let keys: BTreeSet<&String> = x.keys().chain(y.keys()).collect();
        for k in keys {
            let sub = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            let (va, vb) = (x.get(k).unwrap_or(&Value::Null), y.get(k).unwrap_or(&Value::Null));
            if let Some(d) = first_difference(va, vb, &sub) {
                return Some(d);
            }
        }
        return None;
    }
    Some((path.to_owned(), a.to_string(), b.to_string()))
}

/// The runs' plans, scenes, annotation rows and spec texts agree (see [`ensemble`]).
fn check_same(sources: &[Source]) -> Result<(), EnsembleError> {
    let first = &sources[0];
    let base = without_judge(&first.parsed, &first.parsed);
    for other in &sources[1..] {
        let theirs = without_judge(&other.parsed, &first.parsed);
        // The plans are compared as plans; their JSON only names the field that differs (or,
        // should a plan not serialize, the plan as a whole is named).
        if theirs != base {
            let json = |p: &EvaluationPlan| serde_json::to_value(p).ok();
            let (field, first_value, value) = json(&base)
                .zip(json(&theirs))
                .and_then(|(a, b)| first_difference(&a, &b, ""))
                .unwrap_or_else(|| ("plan".to_owned(), format!("{base:?}"), format!("{theirs:?}")));
            return Err(EnsembleError::PlansDiffer {
                first: first.path.clone(),
                run: other.path.clone(),
                field,
                first_value,
                value,
            });
        }
        for (has, lacks) in [(first, other), (other, first)] {
            if let Some(scene) = has.records.keys().find(|s| !lacks.records.contains_key(*s)) {
                return Err(EnsembleError::ScenesDiffer {
                    scene: scene.clone(),
                    has: has.path.clone(),
                    lacks: lacks.path.clone(),
                });
            }
        }
        let from_file = |s: &Source| matches!(s.parsed.fidelity.matching, MatchingMethod::File(_));
        if from_file(first) || from_file(other) {
            continue;
        }
        for (scene, record) in &first.records {
            let row = |r: &SceneRecord| r.fingerprint.as_ref().map(|f| f.annotation.clone());
            if let (Some(a), Some(b)) = (row(record), other.records.get(scene).and_then(row))
                && a != b
            {
                return Err(EnsembleError::AnnotationsDiffer {
                    first: first.path.clone(),
                    run: other.path.clone(),
                    scene: scene.clone(),
                });
            }
        }
    }
    Ok(())
}

/// The digest of an ensemble: of its sources' digests, in order.
fn ensemble_digest(sources: &[Source]) -> String {
    let mut text = String::from("ensemble");
    for s in sources {
        text.push('\n');
        text.push_str(&s.plan.digest);
    }
    blake3::hash(text.as_bytes()).to_hex().to_string()
}

/// The ensemble's record of `scene`, the specs that tied, and the geometry differences.
fn combine(
    sources: &[Source],
    scene: &str,
    names: &[String],
    digest: &str,
) -> Result<(SceneRecord, usize, Vec<GeometryDifference>), EnsembleError> {
    let first = &sources[0];
    let base = &first.records[scene];
    // A scene that failed in any run fails in the ensemble, the error naming the run.
    for s in sources {
        let record = &s.records[scene];
        if let Outcome::Failed { stage, error, causes } = &record.outcome {
            let mut failed = base.clone();
            failed.fingerprint = None;
            failed.outcome = Outcome::Failed {
                stage: *stage,
                error: format!("in run {}: {error}", s.name),
                causes: causes.clone(),
            };
            return Ok((failed, 0, Vec::new()));
        }
    }
    let reports: Vec<&SceneReport> = sources.iter().filter_map(|s| s.records[scene].report()).collect();
    let mut report = reports[0].clone();
    let mut votes = EnsembleVotes {
        runs: names.to_vec(),
        ..EnsembleVotes::default()
    };
    let mut ties = 0;
    if let Some(mut fidelity) = report.fidelity.clone() {
        for metric in FidelityMetric::ALL {
            if report.is_incomplete(metric.into()) {
                continue;
            }
            let (revotes, table, tied) = vote(sources, &reports, scene, metric, &fidelity)?;
            ties += tied;
            fidelity
                .revote(metric, &revotes)
                .map_err(|n| EnsembleError::SpecsDiffer {
                    first: first.path.clone(),
                    run: first.path.clone(),
                    scene: scene.to_owned(),
                    metric,
                    detail: format!("{n} specs, {} votes", revotes.len()),
                })?;
            *votes.votes_mut(metric) = table;
        }
        report = report.with_fidelity(fidelity);
    }
    votes.geometry_differences = geometry_differences(&reports, names);
    for d in &votes.geometry_differences {
        tracing::warn!(scene, metric = %d.metric, run = %d.run, detail = %d.detail, "the runs' geometry differs; the first run's is reported");
    }
    report.ensemble = Some(votes);
    let mut record = SceneRecord::ok(base.scene.clone(), report);
    if let Some(mut f) = base.fingerprint.clone() {
        digest.clone_into(&mut f.plan);
        record = record.with_fingerprint(f);
    }
    let differences = record
        .report()
        .and_then(|r| r.ensemble.as_ref())
        .map(|e| e.geometry_differences.clone())
        .unwrap_or_default();
    Ok((record, ties, differences))
}

/// Every run's verdicts on `metric`'s specs of `scene` (a run where the metric is incomplete
/// abstains), the majority of each spec, and how many tied.
fn vote(
    sources: &[Source],
    reports: &[&SceneReport],
    scene: &str,
    metric: FidelityMetric,
    base: &FidelityReport,
) -> Result<Tally, EnsembleError> {
    let specs = base.verdicts(metric);
    let mut table: Vec<Vec<Option<bool>>> = vec![Vec::with_capacity(reports.len()); specs.len()];
    for (source, report) in sources.iter().zip(reports) {
        let theirs = if report.is_incomplete(metric.into()) {
            vec![None; specs.len()]
        } else {
            let verdicts = report
                .fidelity
                .as_ref()
                .map(|f| f.verdicts(metric))
                .unwrap_or_default();
            if let Some(detail) = spec_difference(&specs, &verdicts) {
                return Err(EnsembleError::SpecsDiffer {
                    first: sources[0].path.clone(),
                    run: source.path.clone(),
                    scene: scene.to_owned(),
                    metric,
                    detail,
                });
            }
            verdicts.into_iter().map(|(_, v)| v).collect()
        };
        for (row, v) in table.iter_mut().zip(theirs) {
            row.push(v);
        }
    }
    let mut ties = 0;
    let revotes = table
        .iter()
        .map(|row| {
            let m = Majority::of(row.iter().copied());
            let unanswered = match m.decision() {
                Decision::Verdict(_) => None,
                Decision::Tie => {
                    ties += 1;
                    Some(format!(
                        "the runs tied: {} satisfied, {} not satisfied, {} without a verdict",
                        m.yes, m.no, m.abstained
                    ))
                }
                Decision::NoVotes => Some("no run has a verdict".to_owned()),
            };
            Revote {
                satisfied: m.verdict(),
                unanswered,
            }
        })
        .collect();
    Ok((revotes, table, ties))
}

/// How two runs' spec lists differ, if they do.
fn spec_difference(a: &[(&str, Option<bool>)], b: &[(&str, Option<bool>)]) -> Option<String> {
    if a.len() != b.len() {
        return Some(format!("{} specs and {} specs", a.len(), b.len()));
    }
    a.iter()
        .zip(b)
        .position(|((x, _), (y, _))| x != y)
        .map(|i| format!("spec {i} is {:?} and {:?}", a[i].0, b[i].0))
}

/// The geometry metrics (and stability) whose section in a later run differs from the first
/// run's, with the scene values of both or the objects whose placement differs.
fn geometry_differences(reports: &[&SceneReport], names: &[String]) -> Vec<GeometryDifference> {
    let first = reports[0];
    let sections = |r: &SceneReport| {
        let mut v = serde_json::to_value(&r.geometry).unwrap_or_default();
        if let Some(obj) = v.as_object_mut() {
            obj.insert(
                "stability".to_owned(),
                serde_json::to_value(&r.stability).unwrap_or_default(),
            );
        }
        v
    };
    let base = sections(first);
    let base_summary = serde_json::to_value(&first.summary).unwrap_or_default();
    let mut out = Vec::new();
    for (report, name) in reports.iter().zip(names).skip(1) {
        let theirs = sections(report);
        let summary = serde_json::to_value(&report.summary).unwrap_or_default();
        for metric in Metric::ALL.into_iter().filter(|m| m.fidelity().is_none()) {
            let mut parts: Vec<String> = metric
                .columns()
                .iter()
                .filter_map(|c| {
                    let key = c.to_lowercase();
                    let (a, b) = (base_summary.get(&key)?, summary.get(&key)?);
                    (a != b).then(|| format!("{c} {a} in {}, {b} in {name}", names[0]))
                })
                .collect();
            if let Some(objects) = placement_difference(first, report, metric) {
                parts.push(objects);
            }
            let same_section = base.get(metric.name()) == theirs.get(metric.name());
            if same_section && parts.is_empty() {
                continue;
            }
            if parts.is_empty() {
                parts.push("the per-object results differ; the scene values are the same".to_owned());
            }
            out.push(GeometryDifference {
                metric,
                run: name.clone(),
                detail: parts.join("; "),
            });
        }
    }
    out
}

/// The objects whose support type (support) or functional sides (accessibility) differ
/// between two reports, as text.
fn placement_difference(a: &SceneReport, b: &SceneReport, metric: Metric) -> Option<String> {
    let what = match metric {
        Metric::Support => "support types",
        Metric::Accessibility => "functional sides",
        _ => return None,
    };
    let value = |r: &SceneReport| -> BTreeMap<String, Value> {
        r.placement
            .iter()
            .flatten()
            .map(|p| {
                let v = match metric {
                    Metric::Support => serde_json::to_value(p.support_type.as_ref().map(|s| &s.value)),
                    _ => serde_json::to_value(p.functional_sides.as_ref().map(|s| &s.value)),
                };
                (p.object.as_str().to_owned(), v.unwrap_or_default())
            })
            .collect()
    };
    let (x, y) = (value(a), value(b));
    let objects: BTreeSet<&String> = x
        .keys()
        .chain(y.keys())
        .filter(|k| x.get(*k) != y.get(*k))
        .collect();
    (!objects.is_empty()).then(|| {
        let list: Vec<&str> = objects.iter().map(|s| s.as_str()).collect();
        format!("the {what} of {} differ", list.join(", "))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_fidelity::{CntSpec, MetricResult, RelationMapping, SpecCount};
    use sceneeval_plausibility::{PlausibilityReport, PlausibilitySummary};
    use sceneeval_results::{FileDigest, Fingerprint, JudgeModel, RECORD_SCHEMA, TOOL_VERSION};

    const SPECS: [&str; 3] = ["eq,1,bed", "eq,2,nightstand", "ge,1,lamp"];

    /// A CNT result of `SPECS` with these verdicts.
    fn cnt(verdicts: &[Option<bool>]) -> MetricResult<CntSpec> {
        let specs = SPECS
            .iter()
            .zip(verdicts)
            .map(|(spec, v)| {
                let count = SpecCount {
                    quantifier: "eq".into(),
                    quantity: 1,
                };
                CntSpec {
                    unanswered: v.is_none().then(|| "no answer".to_owned()),
                    ..CntSpec::new(*spec, count, "bed", vec!["bed_0".into()], *v)
                }
            })
            .collect();
        MetricResult::new(specs, |s| s.satisfied, "no specs")
    }

    fn record(scene: &str, digest: &str, verdicts: &[Option<bool>], sup: f64) -> SceneRecord {
        let fidelity =
            FidelityReport::of_results(RelationMapping::Lexicon, Some(cnt(verdicts)), None, None, None);
        let geometry = PlausibilityReport::of_summary(
            None,
            vec![sceneeval_plausibility::Metric::Support],
            PlausibilitySummary {
                sup: Some(sup),
                ..PlausibilitySummary::default()
            },
        );
        let report = SceneReport::new(Some(scene.into()), geometry, Some(fidelity));
        SceneRecord::ok(SceneName::new(scene), report).with_fingerprint(Fingerprint {
            tool: TOOL_VERSION.into(),
            schema: RECORD_SCHEMA.into(),
            scene: FileDigest {
                path: format!("{scene}.json"),
                blake3: None,
            },
            plan: digest.into(),
            preset: None,
            annotation: Some(format!("row of {scene}")),
            assets: Vec::new(),
        })
    }

    fn plan() -> EvaluationPlan {
        EvaluationPlan::from_metric_list("support,cnt", sceneeval_results::Preset::Default).unwrap()
    }

    /// Writes a run named `name` under `root` with scene_1's CNT verdicts `verdicts` and SUP
    /// `sup`, and scene_2 all satisfied.
    fn run(root: &Path, name: &str, plan: &EvaluationPlan, verdicts: &[Option<bool>], sup: f64) -> PathBuf {
        let dir = root.join(name);
        let digest = format!("digest of {name}");
        RunPlan::new(
            digest.clone(),
            serde_json::to_value(plan).unwrap(),
            Some(JudgeModel {
                model: name.into(),
                settings: String::new(),
            }),
        )
        .write(&dir)
        .unwrap();
        for (scene, v) in [("scene_1", verdicts), ("scene_2", &[Some(true); 3][..])] {
            record(scene, &digest, v, sup)
                .write(&dir.join(scene).join(RECORD_FILE))
                .unwrap();
        }
        dir
    }

    fn options(out: PathBuf) -> EnsembleOptions<'static> {
        EnsembleOptions {
            out_dir: out,
            annotations: None,
        }
    }

    /// Three judges: spec 0 yes/yes/no -> yes; spec 1 no/yes/null -> tie -> null (unanswered);
    /// spec 2 null/no/no -> no. CNT = 1 satisfied of 2 decided = 0.5, one unanswered; the
    /// votes and the sources recorded; the output reads back as a run.
    #[test]
    fn majority_ties_and_scores() {
        let root = tempfile::tempdir().unwrap();
        let p = plan();
        let runs = vec![
            run(root.path(), "a", &p, &[Some(true), Some(false), None], 0.5),
            run(root.path(), "b", &p, &[Some(true), Some(true), Some(false)], 0.5),
            run(root.path(), "c", &p, &[Some(false), None, Some(false)], 0.5),
        ];
        let out = root.path().join("ens");
        let done = ensemble(&runs, &options(out.clone())).unwrap();
        assert_eq!(done.runs, ["a", "b", "c"]);
        assert_eq!(done.ties, 1);
        assert!(done.differences.is_empty());
        let back = SceneRecord::read(&out.join("scene_1").join(RECORD_FILE)).unwrap();
        assert_eq!(back, done.records[0]);
        let report = back.report().unwrap();
        let cnt = report.fidelity.as_ref().unwrap().cnt.as_ref().unwrap();
        let verdicts: Vec<Option<bool>> = cnt.specs.iter().map(|s| s.satisfied).collect();
        assert_eq!(verdicts, [Some(true), None, Some(false)]);
        assert_eq!(
            (cnt.satisfied, cnt.unanswered, cnt.score),
            (Some(1), 1, Some(0.5))
        );
        assert_eq!(report.summary.fidelity.unwrap().cnt, Some(0.5));
        assert!(
            cnt.specs[1]
                .unanswered
                .as_deref()
                .unwrap()
                .contains("tied: 1 satisfied, 1 not")
        );
        // Counted by the evaluation's own counting (its message for undecided specs).
        assert_eq!(
            cnt.message,
            "1/2 requirements are satisfied; 1 of 3 not decided (an answer they need is missing)."
        );
        let votes = report.ensemble.as_ref().unwrap();
        assert_eq!(votes.runs, ["a", "b", "c"]);
        assert_eq!(
            votes.cnt,
            vec![
                vec![Some(true), Some(true), Some(false)],
                vec![Some(false), Some(true), None],
                vec![None, Some(false), Some(false)],
            ]
        );
        // The record's digest is the ensemble's plan.json's; the sources are listed.
        let recorded = RunPlan::read(&out).unwrap().unwrap();
        assert_eq!(back.fingerprint.as_ref().unwrap().plan, recorded.digest);
        let names: Vec<&str> = recorded.sources.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["a", "b", "c"]);
        assert_eq!(recorded.vlm, None);
        // The summary averages the scenes: CNT (50 + 100) / 2 = 75.
        assert_eq!(done.summary.groups[0].cnt, Some(75.0));
        assert!(out.join("summary.csv").is_file());
    }

    /// Each scene's views, diagnostic images and `matching.json` are the first run's, copied
    /// byte for byte; another run's are not, nor anything but PNGs in the image folders, nor a
    /// symbolic link; a scene whose first run kept nothing gets nothing.
    #[test]
    fn the_first_runs_views_diagnostics_and_matching_are_copied() {
        let root = tempfile::tempdir().unwrap();
        let p = plan();
        let v = [Some(true); 3];
        let (a, b) = (
            run(root.path(), "a", &p, &v, 0.5),
            run(root.path(), "b", &p, &v, 0.5),
        );
        let put = |path: PathBuf, bytes: &[u8]| {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, bytes).unwrap();
        };
        put(a.join("scene_1/views/front_bed.png"), b"front of a");
        put(a.join("scene_1/views/notes.txt"), b"not an image");
        put(a.join("scene_1/diagnostics/navigability.png"), b"grid of a");
        put(a.join("scene_1/matching.json"), b"{\"matching of\": \"a\"}");
        put(b.join("scene_1/views/front_bed.png"), b"front of b");
        put(b.join("scene_1/views/size_bed.png"), b"size of b");
        put(b.join("scene_1/matching.json"), b"{\"matching of\": \"b\"}");
        put(root.path().join("outside.png"), b"outside the run");
        #[cfg(unix)]
        std::os::unix::fs::symlink(root.path().join("outside.png"), a.join("scene_1/views/link.png"))
            .unwrap();
        let out = root.path().join("ens");
        ensemble(&[a, b], &options(out.clone())).unwrap();
        let read = |rel: &str| std::fs::read(out.join(rel)).ok();
        assert_eq!(
            read("scene_1/views/front_bed.png").as_deref(),
            Some(&b"front of a"[..])
        );
        assert_eq!(
            read("scene_1/diagnostics/navigability.png").as_deref(),
            Some(&b"grid of a"[..])
        );
        assert_eq!(
            read("scene_1/matching.json").as_deref(),
            Some(&b"{\"matching of\": \"a\"}"[..])
        );
        for absent in [
            "scene_1/views/size_bed.png",
            "scene_1/views/notes.txt",
            "scene_1/views/link.png",
        ] {
            assert_eq!(read(absent), None, "{absent}");
        }
        assert!(!out.join("scene_2/views").exists());
        assert!(!out.join("scene_2/matching.json").exists());
    }

    #[test]
    fn geometry_differences_are_noted() {
        let root = tempfile::tempdir().unwrap();
        let p = plan();
        let v = [Some(true); 3];
        let runs = vec![
            run(root.path(), "a", &p, &v, 0.5),
            run(root.path(), "b", &p, &v, 0.75),
        ];
        let done = ensemble(&runs, &options(root.path().join("ens"))).unwrap();
        assert_eq!(done.differences.len(), 2, "{:?}", done.differences);
        let (scene, d) = &done.differences[0];
        assert_eq!(scene.as_str(), "scene_1");
        assert_eq!((d.metric, d.run.as_str()), (Metric::Support, "b"));
        assert_eq!(d.detail, "SUP 0.5 in a, 0.75 in b");
        // The first run's value is reported, the difference recorded in eval.json.
        let report = done.records[0].report().unwrap();
        assert_eq!(report.summary.geometry.sup, Some(0.5));
        assert_eq!(report.ensemble.as_ref().unwrap().geometry_differences[0], *d);
    }

    #[test]
    fn runs_that_differ_in_more_than_the_judge_are_refused() {
        let root = tempfile::tempdir().unwrap();
        let p = plan();
        let v = [Some(true); 3];
        let a = run(root.path(), "a", &p, &v, 0.5);
        let out = || options(root.path().join("ens"));
        // The judge may differ: matching and relation mapping.
        let mut judge = p.clone();
        judge.fidelity.matching = MatchingMethod::Vlm;
        judge.fidelity.relation_mapping = RelationMapping::Vlm;
        let b = run(root.path(), "b", &judge, &v, 0.5);
        assert!(ensemble(&[a.clone(), b], &out()).is_ok());
        // A geometry parameter may not.
        let mut other = p.clone();
        other.params.collision.contact_tolerance_m += 0.01;
        let c = run(root.path(), "c", &other, &v, 0.5);
        let err = ensemble(&[a.clone(), c], &out()).unwrap_err();
        assert!(
            matches!(&err, EnsembleError::PlansDiffer { field, .. } if field == "params.collision.contact_tolerance_m"),
            "{err}"
        );
        assert!(
            err.to_string().contains("a and") && err.to_string().contains("/c differ"),
            "{err}"
        );
        // Another scene set.
        let d = run(root.path(), "d", &p, &v, 0.5);
        std::fs::remove_dir_all(d.join("scene_2")).unwrap();
        let err = ensemble(&[a.clone(), d], &out()).unwrap_err();
        assert!(
            matches!(&err, EnsembleError::ScenesDiffer { scene, .. } if scene == "scene_2"),
            "{err}"
        );
        // Another annotation row.
        let e = run(root.path(), "e", &p, &v, 0.5);
        let path = e.join("scene_2").join(RECORD_FILE);
        let mut r = SceneRecord::read(&path).unwrap();
        r.fingerprint.as_mut().unwrap().annotation = Some("another row".into());
        r.write(&path).unwrap();
        let err = ensemble(&[a.clone(), e], &out()).unwrap_err();
        assert!(
            matches!(&err, EnsembleError::AnnotationsDiffer { scene, .. } if scene == "scene_2"),
            "{err}"
        );
        // Another spec text.
        let f = run(root.path(), "f", &p, &v, 0.5);
        let path = f.join("scene_1").join(RECORD_FILE);
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replace("ge,1,lamp", "ge,2,lamp");
        std::fs::write(&path, text).unwrap();
        let err = ensemble(&[a.clone(), f], &out()).unwrap_err();
        assert!(
            err.to_string()
                .contains("spec 2 is \"ge,1,lamp\" and \"ge,2,lamp\""),
            "{err}"
        );
        // A run without plan.json (written before runs recorded their plan).
        let g = run(root.path(), "g", &p, &v, 0.5);
        std::fs::remove_file(g.join(sceneeval_results::RUN_PLAN_FILE)).unwrap();
        let err = ensemble(&[a.clone(), g], &out()).unwrap_err();
        assert!(matches!(err, EnsembleError::NoPlan { .. }), "{err}");
        // One run, and the output folder being a source.
        assert!(matches!(
            ensemble(std::slice::from_ref(&a), &out()),
            Err(EnsembleError::TooFewRuns { given: 1 })
        ));
        let b2 = run(root.path(), "b2", &p, &v, 0.5);
        let err = ensemble(&[a.clone(), b2.clone()], &options(b2)).unwrap_err();
        assert!(matches!(err, EnsembleError::OutputIsSource { .. }), "{err}");
    }
}
