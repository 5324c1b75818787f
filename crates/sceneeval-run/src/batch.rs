//! Evaluating a list of scene files: one `eval.json` per scene, written as each scene finishes,
//! so an interrupted run loses nothing and a re-run resumes where it stopped, reusing a result
//! only when nothing it depends on changed. The batch owns the files, the fingerprints, the
//! reuse and the parallelism; what happens to one scene is [`Evaluator::evaluate_scene`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};
use std::time::Instant;

use rayon::prelude::*;

use sceneeval_annotation::{AnnotationRow, Annotations};
use sceneeval_eval::schedule::{CpuSlots, SceneSchedule};
use sceneeval_eval::{EvalError, Evaluator, RequestField, SceneInputs, SharedVlm};
use sceneeval_fidelity::{MatchingMethod, matching_file_for};
use sceneeval_files::ErrorChain;
use sceneeval_io::{AssetLibrary, read_scene_state};
use sceneeval_plausibility::{Deadline, Metric};
use sceneeval_results::{Outcome, ResultsError, SceneRecord, SceneTiming, Stage, TIMING_SCHEMA};

use crate::dry_run::{DryRun, DryRunModel, SceneTally};
use crate::{Fingerprints, RunError, SceneFile, annotation_digest, matching_file_digest};

/// How a batch run treats its scenes.
#[derive(Debug, Clone, Default)]
pub struct BatchOptions<'a> {
    /// The folder receiving `<scene>/eval.json`.
    pub out_dir: PathBuf,
    /// Re-evaluate every scene, even those with a matching record.
    pub force: bool,
    /// Also write each scene's diagnostic images under `<scene>/diagnostics/`.
    pub diagnostics: bool,
    /// The SceneEval-500 annotations. Each scene's row ([`sceneeval_results::SceneName::annotation_row`])
    /// is part of its fingerprint and, when the plan runs text-fidelity metrics, what they
    /// check; a scene without a row gets no fidelity result (a warning is logged).
    pub annotations: Option<&'a Annotations>,
    /// How many scenes are evaluated at once. `None`: one per worker thread of the current
    /// rayon pool. With a VLM, more (the request sets threads + VLM concurrency) let scenes
    /// that wait for the model leave the CPU to others: the scenes then run on a pool of this
    /// many threads, and at most as many of them as the current pool has threads compute at
    /// once (the others wait for the model, or for a CPU slot). Ignored without a VLM, and
    /// when not above the pool's thread count. Each scene in flight holds its scene and object
    /// views in memory.
    pub scenes_in_flight: Option<usize>,
}

/// Something that happened during a run, as it happens (from a worker thread).
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub enum RunEvent<'a> {
    /// A scene is done: evaluated, reused or failed, its record written.
    SceneDone {
        /// The scene.
        scene: &'a SceneFile,
        /// What happened to it.
        status: &'a SceneStatus,
        /// Its record.
        record: &'a SceneRecord,
        /// Why it failed, as the error itself (the record keeps its text), so that a front end
        /// can give advice for the kind of error (a missing asset folder, say).
        error: Option<&'a (dyn std::error::Error + 'static)>,
    },
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
    /// The earlier record is partial: some metric could not be computed.
    Incomplete,
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
            Reason::Incomplete => f.write_str("incomplete before"),
            Reason::Unreadable(why) => write!(f, "earlier result unreadable: {why}"),
            Reason::Changed(why) => write!(f, "{why}"),
        }
    }
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
    /// Scenes evaluated in this run whose record is partial (counted in `evaluated` too).
    pub partial: usize,
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
/// as it is done (with `matching.json` and the VLM's views when the text-fidelity metrics ran),
/// and calling `on_event` (from the worker thread) after each.
///
/// An earlier record is reused only when its fingerprint still matches (the scene file, every
/// asset and metadata file it was built from, the plan, the tool version and the record
/// schema; see [`Fingerprints::why_stale`]) and unless `options.force`; failed and partial
/// scenes are always retried. A scene that fails to load, or runs past the plan's time budget
/// (while loading, waiting for the VLM or in any metric; the error names the stage), is
/// recorded as failed; a metric that fails otherwise (a VLM request without an answer, a
/// malformed annotation entry, ...) makes the scene partial, its other results kept
/// ([`Evaluator::evaluate_scene`]); the run goes on. The output folder is checked for
/// writing before any scene is evaluated.
///
/// Results do not depend on the number of threads: each scene is evaluated independently and
/// records are returned in input order.
///
/// # Errors
/// [`RunError::OutputNotWritable`] before any work when the output folder cannot be written;
/// [`RunError::File`] or [`RunError::Results`] when a record cannot be written later (the run
/// stops); [`RunError::Eval`] when the VLM's endpoint check fails.
pub fn run_batch(
    scenes: &[SceneFile],
    evaluator: &Evaluator,
    assets: &AssetLibrary,
    options: &BatchOptions<'_>,
    on_event: &(dyn Fn(&RunEvent<'_>) + Sync),
) -> Result<BatchOutcome, RunError> {
    crate::check_output_dir(&options.out_dir)?;
    let threads = rayon::current_num_threads().max(1);
    let in_flight = options
        .scenes_in_flight
        .unwrap_or(threads)
        .clamp(1, scenes.len().max(1));
    let lend_cpu = evaluator.vlm().is_some() && in_flight > threads;
    let batch = Batch::new(
        evaluator,
        assets,
        options,
        lend_cpu.then(|| CpuSlots::new(threads)),
    );
    let work = |scene: &SceneFile| -> Result<Done, RunError> {
        let (record, status, timing, error) = batch.process(scene)?;
        on_event(&RunEvent::SceneDone {
            scene,
            status: &status,
            record: &record,
            error: error.as_deref().map(|e| e as &(dyn std::error::Error + 'static)),
        });
        Ok((record, status, timing))
    };
    let results: Vec<Result<Done, RunError>> = if lend_cpu {
        // One long-lived loop per thread of a pool of `in_flight` threads, each taking the next
        // scene: the geometry metrics' own parallel loops run on the same pool, and a thread
        // that waits in one steals only their pieces, never another scene.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(in_flight)
            .thread_name(|i| format!("sceneeval-scene-{i}"))
            .build()
            .map_err(|e| {
                RunError::request(
                    RequestField::Threads,
                    format!("cannot start {in_flight} scene threads: {e}"),
                )
            })?;
        let next = AtomicUsize::new(0);
        let done: Vec<Mutex<Option<Result<Done, RunError>>>> =
            scenes.iter().map(|_| Mutex::new(None)).collect();
        pool.broadcast(|_| {
            loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(scene) = scenes.get(i) else { break };
                let result = work(scene);
                *done[i].lock().unwrap_or_else(PoisonError::into_inner) = Some(result);
            }
        });
        done.into_iter()
            .map(|d| {
                d.into_inner()
                    .unwrap_or_else(PoisonError::into_inner)
                    .unwrap_or_else(|| {
                        Err(RunError::request(RequestField::Threads, "a scene thread stopped"))
                    })
            })
            .collect()
    } else {
        scenes.par_iter().map(work).collect()
    };
    if let Some(e) = batch.endpoint.take_error() {
        return Err(e.into());
    }
    let mut outcome = BatchOutcome {
        records: Vec::with_capacity(scenes.len()),
        statuses: Vec::with_capacity(scenes.len()),
        timings: Vec::with_capacity(scenes.len()),
        evaluated: 0,
        reused: 0,
        failed: 0,
        partial: 0,
    };
    for r in results {
        let (record, status, timing) = r?;
        if matches!(
            (&status, &record.outcome),
            (SceneStatus::Evaluated { .. }, Outcome::Partial { .. })
        ) {
            outcome.partial += 1;
        }
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

type Done = (SceneRecord, SceneStatus, Option<SceneTiming>);

/// Why a scene failed, kept until its event is sent.
type Failure = Box<dyn std::error::Error + Send + Sync>;

struct Batch<'a> {
    evaluator: &'a Evaluator,
    assets: &'a AssetLibrary,
    options: &'a BatchOptions<'a>,
    fingerprints: Fingerprints,
    plan_digest: String,
    /// The CPU slots scenes take turns in, when they lend them while waiting for the VLM.
    slots: Option<Arc<CpuSlots>>,
    endpoint: EndpointGate,
}

/// The endpoint check, made once, before the first scene that is evaluated.
#[derive(Default)]
struct EndpointGate {
    passed: OnceLock<bool>,
    error: Mutex<Option<EvalError>>,
}

impl EndpointGate {
    /// Checks `vlm`'s endpoint unless it was checked (every caller waits for the one check).
    fn ensure(&self, vlm: Option<&SharedVlm>) -> Result<(), RunError> {
        let Some(vlm) = vlm else { return Ok(()) };
        let passed = *self.passed.get_or_init(|| match vlm.check_endpoint() {
            Ok(()) => true,
            Err(e) => {
                tracing::debug!(error = %ErrorChain::new(&e), "the VLM endpoint check failed; stopping");
                *self.error.lock().unwrap_or_else(PoisonError::into_inner) = Some(e);
                false
            }
        });
        if passed {
            Ok(())
        } else {
            Err(RunError::request(RequestField::Vlm, "the endpoint check failed"))
        }
    }

    fn take_error(&self) -> Option<EvalError> {
        self.error.lock().unwrap_or_else(PoisonError::into_inner).take()
    }
}

impl<'a> Batch<'a> {
    fn new(
        evaluator: &'a Evaluator,
        assets: &'a AssetLibrary,
        options: &'a BatchOptions<'a>,
        slots: Option<Arc<CpuSlots>>,
    ) -> Self {
        Batch {
            evaluator,
            assets,
            options,
            fingerprints: Fingerprints::new(),
            plan_digest: evaluator.result_digest(),
            slots,
            endpoint: EndpointGate::default(),
        }
    }

    /// The scene's annotation row and its digest for the fingerprint (extended by the matching
    /// file's contents when the plan matches objects from files).
    fn annotation(&self, scene: &SceneFile) -> Option<(&AnnotationRow, String)> {
        let row = scene.name.annotation_row(self.options.annotations?)?;
        let mut digest = annotation_digest(row);
        let plan = self.evaluator.plan();
        if let (true, MatchingMethod::File(path)) = (plan.has_fidelity(), &plan.fidelity.matching) {
            digest = matching_file_digest(&digest, &matching_file_for(path, scene.name.as_str()));
        }
        Some((row, digest))
    }

    /// Whether the earlier record can be reused; why not otherwise.
    fn reuse(&self, scene: &SceneFile, path: &Path, annotation: Option<&str>) -> Result<SceneRecord, Reason> {
        if self.options.force {
            return Err(Reason::Forced);
        }
        if !path.exists() {
            return Err(Reason::New);
        }
        let record = SceneRecord::read(path).map_err(|e| Reason::Unreadable(e.to_string()))?;
        match record.outcome {
            Outcome::Ok { .. } => {}
            Outcome::Partial { .. } => return Err(Reason::Incomplete),
            Outcome::Failed { .. } => return Err(Reason::FailedBefore),
        }
        let Some(old) = &record.fingerprint else {
            return Err(Reason::Unreadable("it has no fingerprint".into()));
        };
        // The fidelity metrics read the annotation row: a changed row invalidates the record.
        let compare_annotation = self.evaluator.plan().has_fidelity();
        match self.fingerprints.why_stale(
            old,
            &scene.path,
            self.assets,
            &self.plan_digest,
            annotation,
            compare_annotation,
        ) {
            None => Ok(record),
            Some(why) => Err(Reason::Changed(why)),
        }
    }

    fn process(
        &self,
        scene: &SceneFile,
    ) -> Result<(SceneRecord, SceneStatus, Option<SceneTiming>, Option<Failure>), RunError> {
        let path = scene.record_path(&self.options.out_dir);
        let annotation = self.annotation(scene);
        let digest = annotation.as_ref().map(|(_, d)| d.as_str());
        let why = match self.reuse(scene, &path, digest) {
            Ok(record) => return Ok((record, SceneStatus::Reused, None, None)),
            Err(why) => why,
        };
        // The scene computes in a CPU slot (lent out while it waits for the VLM).
        let slot = SceneSchedule::enter(self.slots.clone(), None);
        self.endpoint.ensure(self.evaluator.vlm())?;
        tracing::info!(scene = %scene.name, reason = %why, "evaluating");
        let plan = self.evaluator.plan();
        let deadline = plan.deadline();
        let start = Instant::now();
        // Waits for the VLM end with the budget too.
        slot.set_deadline(deadline.budget().and_then(|b| Some((start.checked_add(b)?, b))));
        let mut timing = SceneTiming {
            schema: TIMING_SCHEMA.to_owned(),
            scene: scene.name.to_string(),
            load_seconds: 0.0,
            metrics: Vec::new(),
            fidelity_seconds: None,
            stability_seconds: None,
            total_seconds: 0.0,
        };
        let dir = scene.out_dir(&self.options.out_dir);
        let loaded = read_scene_state(&scene.path, self.assets, &plan.read);
        timing.load_seconds = start.elapsed().as_secs_f64();
        let outcome: Result<SceneRecord, (Stage, Failure)> =
            match loaded {
                Err(e) => Err((Stage::Load, Box::new(e))),
                Ok(loaded) => match deadline.check("loading") {
                    Err(e) => Err((
                        Stage::Load,
                        Box::new(EvalError::from(sceneeval_plausibility::PlausibilityError::from(
                            e,
                        ))),
                    )),
                    Ok(()) => {
                        let views_dir = dir.join("views");
                        let inputs = SceneInputs {
                            name: Some(scene.name.as_str()),
                            row: annotation.as_ref().map(|(row, _)| *row),
                            assets: Some(self.assets),
                            views_dir: Some(&views_dir),
                            deadline: Some(&deadline),
                        };
                        let evaluated = self.evaluator.evaluate_scene(&loaded, &inputs).and_then(|done| {
                            if let Some(matching) = &done.matching {
                                matching.write(&dir.join(sceneeval_fidelity::MATCHING_FILE))?;
                            }
                            Ok(done)
                        });
                        match evaluated {
                            Err(e) => Err((Stage::Evaluate, Box::new(e))),
                            Ok(done) => {
                                timing.metrics = done.timings;
                                timing.fidelity_seconds = done.fidelity_seconds;
                                timing.stability_seconds = done.stability_seconds;
                                if self.options.diagnostics {
                                    self.diagnostics(scene, &loaded, &dir, &deadline);
                                }
                                let fingerprint = self.fingerprints.of_loaded(
                                    &scene.path,
                                    &loaded,
                                    self.assets,
                                    &self.plan_digest,
                                    plan.preset,
                                    annotation.map(|(_, d)| d),
                                );
                                Ok(SceneRecord::ok(scene.name.clone(), done.report)
                                    .with_fingerprint(fingerprint))
                            }
                        }
                    }
                },
            };
        let (record, failure) = match outcome {
            Ok(record) => (record, None),
            Err((stage, e)) => (
                SceneRecord::failed(scene.name.clone(), stage, e.as_ref()),
                Some(e),
            ),
        };
        timing.total_seconds = start.elapsed().as_secs_f64();
        if let Outcome::Failed { error, .. } = &record.outcome {
            tracing::info!(scene = %scene.name, %error, "scene failed");
        }
        record.write(&path)?;
        let timing_path = scene.timing_path(&self.options.out_dir);
        let mut text = serde_json::to_string_pretty(&timing).map_err(|e| ResultsError::BadRecord {
            path: timing_path.clone(),
            message: e.to_string(),
        })?;
        text.push('\n');
        sceneeval_files::write_atomic(&timing_path, text.as_bytes())
            .map_err(|e| RunError::file(&timing_path, e))?;
        let status = if matches!(record.outcome, Outcome::Failed { .. }) {
            SceneStatus::Failed { why }
        } else {
            SceneStatus::Evaluated { why }
        };
        Ok((record, status, Some(timing), failure))
    }

    /// The diagnostic images, under the scene's time budget (a warning when they cannot be
    /// drawn: they are not part of the record).
    fn diagnostics(
        &self,
        scene: &SceneFile,
        loaded: &sceneeval_scene::Scene,
        dir: &Path,
        deadline: &Deadline,
    ) {
        if let Err(e) = sceneeval_plausibility::write_diagnostics(
            loaded,
            &self.evaluator.plan().params,
            self.evaluator.sources(),
            &dir.join("diagnostics"),
            deadline,
        ) {
            tracing::warn!(scene = %scene.name, error = %e, "diagnostic images not written");
        }
    }
}

/// What a dry run found for one scene.
enum DryScene {
    /// Its earlier result would be kept.
    Reused,
    /// Gone through: its requests, whether its attribute requests are estimated, and why it
    /// would fail, if it would.
    Done(SceneTally, bool, Option<String>),
}

/// Goes through `scenes` as [`run_batch`] would (the same reuse decisions) with `evaluator`, a
/// dry run's (its VLM is `model`, no geometry metric), writing nothing: see [`DryRun`].
pub(crate) fn dry_run_batch(
    scenes: &[SceneFile],
    evaluator: &Evaluator,
    assets: &AssetLibrary,
    options: &BatchOptions<'_>,
    model: &DryRunModel,
) -> DryRun {
    let batch = Batch::new(evaluator, assets, options, None);
    let found: Vec<DryScene> = scenes.par_iter().map(|scene| batch.dry(scene, model)).collect();
    let mut run = DryRun {
        scenes: scenes.len(),
        vlm: true,
        ..DryRun::default()
    };
    for (scene, found) in scenes.iter().zip(found) {
        match found {
            DryScene::Reused => run.reused += 1,
            DryScene::Done(tally, estimated, failure) => {
                run.evaluated += 1;
                run.attributes_estimated += usize::from(estimated);
                run.add_scene(&tally);
                if let Some(why) = failure {
                    run.failed.push((scene.name.to_string(), why));
                }
            }
        }
    }
    run
}

impl Batch<'_> {
    fn dry(&self, scene: &SceneFile, model: &DryRunModel) -> DryScene {
        let path = scene.record_path(&self.options.out_dir);
        let annotation = self.annotation(scene);
        let digest = annotation.as_ref().map(|(_, d)| d.as_str());
        if self.reuse(scene, &path, digest).is_ok() {
            return DryScene::Reused;
        }
        let row = annotation.as_ref().map(|(row, _)| *row);
        let loaded = match read_scene_state(&scene.path, self.assets, &self.evaluator.plan().read) {
            Ok(l) => l,
            Err(e) => {
                return DryScene::Done(
                    SceneTally::default(),
                    false,
                    Some(ErrorChain::new(&e).to_string()),
                );
            }
        };
        let inputs = SceneInputs {
            name: Some(scene.name.as_str()),
            row,
            assets: Some(self.assets),
            views_dir: None,
            deadline: None,
        };
        SceneTally::start();
        let result = self.evaluator.evaluate_scene(&loaded, &inputs);
        let (tally, estimated) = model.settle(SceneTally::finish(), row);
        let failure = result.err().map(|e| ErrorChain::new(&e).to_string());
        DryScene::Done(tally, estimated, failure)
    }
}
