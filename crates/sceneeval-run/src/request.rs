//! [`EvaluationRequest`]: everything one evaluation run is asked to do, in one type with each
//! default written once. `sceneeval evaluate` maps its flags onto it, the Python package's
//! `sceneeval.evaluate` its keyword arguments; [`EvaluationRequest::prepare`] checks everything
//! that can be checked before any work and [`PreparedRun::run`] evaluates the scenes, writing
//! `<out>/<scene>/eval.json` as each finishes and then the summary tables.
//!
//! Errors about the request name its field (`sceneeval_eval::RequestField`); a front end shows
//! them under its own name for the field (`--plan`, `plan=`).
//!
//! ```
//! use sceneeval_run::EvaluationRequest;
//! use sceneeval_eval::{Metric, Preset};
//! let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
//! let out = tempfile::tempdir().unwrap();
//! let mut request = EvaluationRequest::new(fixtures.join("scenes"), out.path());
//! request.assets = vec![format!("fixture={}", fixtures.join("assets").display())];
//! request.plan.plan = Some("collision,oob".into());
//! request.plan.preset = Some(Preset::Reference);
//! let prepared = request.prepare().unwrap();
//! assert_eq!(prepared.evaluator().plan().metrics, vec![Metric::Collision, Metric::OutOfBounds]);
//! let outcome = prepared.run(&|_| {}).unwrap();
//! assert_eq!(outcome.batch.failed, 0);
//! assert!(out.path().join("summary.md").is_file());
//! ```

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use sceneeval_annotation::Annotations;
use sceneeval_eval::{
    ChosenPlan, EvalError, Evaluator, NoVlmFallback, PlanRequest, RequestField, VlmOptions,
};
use sceneeval_io::AssetLibrary;
use sceneeval_results::Summary;
use serde::{Deserialize, Serialize};

use crate::dry_run::{DryRun, DryRunModel};
use crate::scene_file::check_annotation_rows;
use crate::{
    BatchOptions, BatchOutcome, OutputLock, RunError, RunEvent, SceneFile, SkippedFile, check_output_dir,
    find_scenes, run_batch,
};

/// One evaluation run: which scenes, with which assets and annotations, under which plan, with
/// which VLM, written where. Fields left `None` take the defaults documented on them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvaluationRequest {
    /// The folder holding the `scene_<ID>.json` files.
    pub scenes: PathBuf,
    /// Asset folders, each `PREFIX=DIR` or `PREFIX=LAYOUT:DIR` (see
    /// [`AssetLibrary::from_specs`]).
    #[serde(default)]
    pub assets: Vec<String>,
    /// The output folder: `<scene>/eval.json`, `<scene>/timing.json`, the summaries.
    pub out: PathBuf,
    /// The SceneEval-500 annotations (CSV or JSON): rows per difficulty in the summary, each
    /// scene's row digest in its fingerprint, and the rows the text-fidelity metrics check.
    #[serde(default)]
    pub annotations: Option<PathBuf>,
    /// What to evaluate.
    #[serde(default)]
    pub plan: PlanRequest,
    /// The VLM that answers the text-fidelity metrics' questions (and support types and
    /// functional sides), if any.
    #[serde(default)]
    pub vlm: Option<VlmOptions>,
    /// Worker threads (default: one per core).
    #[serde(default)]
    pub threads: Option<usize>,
    /// Evaluate every scene again, even those whose earlier result still matches.
    #[serde(default)]
    pub force: bool,
    /// Evaluate only this share of the scenes.
    #[serde(default)]
    pub shard: Option<Shard>,
    /// Also write diagnostic images under `<out>/<scene>/diagnostics/`.
    #[serde(default)]
    pub diagnostics: bool,
    /// Read the scene files strictly ([`sceneeval_io::ReadOptions::strict`]): a key the
    /// sceneState format does not have fails its scene instead of being a warning.
    #[serde(default)]
    pub strict: bool,
}

/// A share of a run's scenes: shard `index` of `count` (1-based) holds the scenes whose
/// position in ID order is `index - 1` modulo `count`. Written `K/N`.
///
/// ```
/// use sceneeval_run::Shard;
/// let s: Shard = "2/8".parse().unwrap();
/// assert_eq!((s.index, s.count), (2, 8));
/// assert!("9/8".parse::<Shard>().is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which shard, from 1.
    pub index: usize,
    /// How many shards.
    pub count: usize,
}

impl Shard {
    /// Whether the scene at `position` (in ID order, from 0) belongs to this shard.
    pub fn holds(&self, position: usize) -> bool {
        position % self.count == self.index - 1
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (k, n) = s.split_once('/').ok_or("expected K/N, e.g. 2/8")?;
        let (index, count): (usize, usize) = (
            k.trim().parse().map_err(|_| "K is not a number")?,
            n.trim().parse().map_err(|_| "N is not a number")?,
        );
        if count == 0 || index == 0 || index > count {
            return Err(format!("shard {index}/{count}: need 1 <= K <= N"));
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl EvaluationRequest {
    /// A request for the scenes of `scenes` written to `out`, every other field at its
    /// default (the geometry plan, no assets, annotations or VLM).
    pub fn new(scenes: impl Into<PathBuf>, out: impl Into<PathBuf>) -> Self {
        EvaluationRequest {
            scenes: scenes.into(),
            assets: Vec::new(),
            out: out.into(),
            annotations: None,
            plan: PlanRequest::default(),
            vlm: None,
            threads: None,
            force: false,
            shard: None,
            diagnostics: false,
            strict: false,
        }
    }

    /// Checks everything that can be checked before any scene is evaluated, in order: the
    /// scene names, the plan, the VLM settings (and sets up its client and the renderer), the
    /// asset folders, the annotations, the output folder (a probe file is written and
    /// removed), the worker threads.
    ///
    /// # Errors
    /// [`RunError::Eval`] with an [`EvalError::Request`] naming the field at fault, or
    /// [`RunError::DuplicateSceneId`], [`RunError::OutputNotWritable`], [`RunError::OutputInUse`].
    pub fn prepare(&self) -> Result<PreparedRun, RunError> {
        let set = find_scenes(&self.scenes).map_err(|e| match e {
            RunError::File { .. } => RunError::request_caused(
                RequestField::Scenes,
                format!("cannot read the folder {}", self.scenes.display()),
                e,
            ),
            other => other,
        })?;
        if set.scenes.is_empty() {
            return Err(RunError::request(
                RequestField::Scenes,
                format!("no scene_<ID>.json files in {}", self.scenes.display()),
            ));
        }
        let mut scenes = set.scenes;
        if let Some(shard) = self.shard {
            scenes = scenes
                .into_iter()
                .enumerate()
                .filter(|(i, _)| shard.holds(*i))
                .map(|(_, s)| s)
                .collect();
        }
        let ChosenPlan { mut plan, fallback } = self
            .plan
            .resolve(self.vlm.is_some(), self.annotations.is_some())?;
        plan.read.strict = self.strict;
        let mut evaluator = Evaluator::new(plan)
            .map_err(|e| EvalError::request_caused(RequestField::Plan, "invalid plan".to_owned(), e))?;
        let mut warnings = Vec::new();
        let mut dry = None;
        if let Some(vlm) = &self.vlm {
            if evaluator.plan().has_fidelity() {
                evaluator = vlm.attach(evaluator, Some(&vlm.cache_dir(&self.out)))?;
                warnings.extend(vlm.cache_problem(&self.out));
                dry = dry_run_model(vlm, &self.out)?;
            } else {
                // Checked whatever the plan, so that a mistake is not found only in the run
                // that needs the VLM.
                vlm.check()?;
                warnings.push(
                    "the plan runs no text-fidelity metric (cnt, atr, oor, oar), so the VLM options are not used"
                        .to_owned(),
                );
            }
        }
        for w in &warnings {
            tracing::warn!("{w}");
        }
        let assets = AssetLibrary::from_specs(&self.assets)
            .map_err(|e| {
                EvalError::request_caused(RequestField::Assets, "invalid asset folder".to_owned(), e)
            })?
            .with_limits(evaluator.plan().limits);
        let annotations = self
            .annotations
            .as_deref()
            .map(|p| {
                Annotations::read(p).map_err(|e| {
                    EvalError::request_caused(
                        RequestField::Annotations,
                        format!("cannot read {}", p.display()),
                        e,
                    )
                })
            })
            .transpose()?;
        if let Some(annotations) = &annotations {
            check_annotation_rows(annotations, &scenes, evaluator.plan().has_fidelity())?;
        }
        check_output_dir(&self.out)?;
        let lock = OutputLock::acquire(&self.out)?;
        #[cfg(feature = "physics")]
        if evaluator.plan().runs(sceneeval_eval::Metric::Stability) {
            let dir = self.out.join(sceneeval_eval::DEFAULT_PHYSICS_CACHE_DIR);
            let cache = sceneeval_physics::DecompositionCache::on_disk(&dir).map_err(|e| {
                RunError::request_caused(
                    RequestField::Out,
                    format!("cannot create the decomposition cache {}", dir.display()),
                    e,
                )
            })?;
            evaluator = evaluator.with_decomposition_cache(std::sync::Arc::new(cache));
        }
        let replaced = earlier_results_of_other_plans(&scenes, &self.out, &evaluator.result_digest());
        let mut pool = rayon::ThreadPoolBuilder::new();
        if let Some(n) = self.threads {
            if n == 0 {
                return Err(RunError::request(
                    RequestField::Threads,
                    "must be at least 1".to_owned(),
                ));
            }
            pool = pool.num_threads(n);
        }
        let pool = pool.build().map_err(|e| {
            RunError::request(
                RequestField::Threads,
                format!("cannot start the worker threads: {e}"),
            )
        })?;
        // Scenes waiting for the model leave the CPU to others: as many more scenes in flight
        // as requests may be.
        let scenes_in_flight = match (&self.vlm, evaluator.vlm()) {
            (Some(v), Some(_)) => Some(pool.current_num_threads() + v.concurrency()),
            _ => None,
        };
        Ok(PreparedRun {
            warnings,
            dry,
            scenes_in_flight,
            scenes,
            skipped: set.skipped,
            fallback,
            evaluator,
            assets,
            annotations,
            options: (self.out.clone(), self.force, self.diagnostics),
            pool,
            replaced,
            _lock: lock,
        })
    }

    /// [`EvaluationRequest::prepare`], then [`PreparedRun::run`].
    ///
    /// # Errors
    /// As both.
    pub fn run(&self, on_event: &(dyn Fn(&RunEvent<'_>) + Sync)) -> Result<RunOutcome, RunError> {
        self.prepare()?.run(on_event)
    }
}

/// The model a dry run asks in place of the VLM of `vlm` (the same model name, settings, cache
/// and token estimate); `None` in a build without the feature `openai`.
///
/// # Errors
/// As [`VlmOptions::config`].
fn dry_run_model(vlm: &VlmOptions, out: &Path) -> Result<Option<DryRunModel>, EvalError> {
    #[cfg(feature = "openai")]
    {
        use sceneeval_vlm::Vlm;
        let client = vlm.client()?;
        let (model, settings) = (client.model().to_owned(), client.settings().to_owned());
        Ok(Some(DryRunModel::new(
            &model,
            &settings,
            vlm.cache_dir(out),
            move |r| client.estimate_tokens(r),
            vlm.render_size()?,
        )))
    }
    #[cfg(not(feature = "openai"))]
    {
        let _ = (vlm, out);
        Ok(None)
    }
}

/// A request checked and set up by [`EvaluationRequest::prepare`], ready to run.
#[derive(Debug)]
pub struct PreparedRun {
    warnings: Vec<String>,
    dry: Option<DryRunModel>,
    scenes_in_flight: Option<usize>,
    scenes: Vec<SceneFile>,
    skipped: Vec<SkippedFile>,
    fallback: Option<NoVlmFallback>,
    evaluator: Evaluator,
    assets: AssetLibrary,
    annotations: Option<Annotations>,
    options: (PathBuf, bool, bool),
    pool: rayon::ThreadPool,
    replaced: usize,
    _lock: OutputLock,
}

/// How many of `scenes` have a result in `out` made with another plan, preset or VLM (their
/// plan digest differs from `digest`): the run replaces them.
fn earlier_results_of_other_plans(scenes: &[SceneFile], out: &Path, digest: &str) -> usize {
    #[derive(Deserialize)]
    struct Plan {
        plan: String,
    }
    #[derive(Deserialize)]
    struct Record {
        fingerprint: Option<Plan>,
    }
    scenes
        .iter()
        .filter_map(|s| std::fs::read(s.record_path(out)).ok())
        .filter_map(|bytes| serde_json::from_slice::<Record>(&bytes).ok()?.fingerprint)
        .filter(|f| f.plan != digest)
        .count()
}

/// What a run did: what [`PreparedRun::run`] returns.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// The scenes evaluated or reused, in ID order (this shard's when sharded).
    pub scenes: Vec<SceneFile>,
    /// Files that look like scene files but are not evaluated, and why.
    pub skipped: Vec<SkippedFile>,
    /// What the text-fidelity metrics ran with instead of a VLM, if so.
    pub fallback: Option<NoVlmFallback>,
    /// The per-scene records, statuses and timings.
    pub batch: BatchOutcome,
    /// The summary written to `summary.csv` and `summary.md`.
    pub summary: Summary,
}

impl PreparedRun {
    /// The scenes to evaluate (this shard's when sharded), in ID order.
    pub fn scenes(&self) -> &[SceneFile] {
        &self.scenes
    }

    /// Files that look like scene files but are not evaluated, and why.
    pub fn skipped(&self) -> &[SkippedFile] {
        &self.skipped
    }

    /// What the text-fidelity metrics run with instead of a VLM, if so.
    pub fn fallback(&self) -> Option<&NoVlmFallback> {
        self.fallback.as_ref()
    }

    /// What a front end should warn about before the run (each also logged): VLM options
    /// that the plan does not use, a VLM cache folder that cannot be written.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// How many scenes are evaluated at once ([`BatchOptions::scenes_in_flight`]): the worker
    /// threads plus the VLM concurrency when the plan asks a VLM, else `None` (one per worker
    /// thread).
    pub fn scenes_in_flight(&self) -> Option<usize> {
        self.scenes_in_flight
    }

    /// The VLM's answers so far, over all scenes (see [`sceneeval_eval::SharedVlm::usage`]), while the
    /// run goes on; `None` without a VLM.
    pub fn vlm_usage(&self) -> Option<sceneeval_vlm::Usage> {
        self.evaluator.vlm().map(sceneeval_eval::SharedVlm::usage)
    }

    /// The evaluator: the plan and what it runs with.
    pub fn evaluator(&self) -> &Evaluator {
        &self.evaluator
    }

    /// How many scenes already have a result in the output folder made with another plan,
    /// preset or VLM: the run replaces them (a front end says so before it starts).
    pub fn replaced(&self) -> usize {
        self.replaced
    }

    /// What the run would ask the VLM, per task, without asking it, computing any metric or
    /// writing anything: [`DryRun`] (see its module docs for how attribute requests are
    /// estimated). Without a VLM nothing would be asked: the scenes are only counted.
    pub fn dry_run(self) -> DryRun {
        let Some(model) = self.dry else {
            return DryRun {
                scenes: self.scenes.len(),
                ..DryRun::default()
            };
        };
        let (out_dir, force, diagnostics) = self.options;
        let options = BatchOptions {
            out_dir,
            force,
            diagnostics,
            annotations: self.annotations.as_ref(),
            scenes_in_flight: None,
        };
        let evaluator = self
            .evaluator
            .with_vlm(sceneeval_eval::SharedVlm::new(model.clone()))
            .without_geometry();
        self.pool
            .install(|| crate::batch::dry_run_batch(&self.scenes, &evaluator, &self.assets, &options, &model))
    }

    /// Writes the run's plan (`plan.json`, [`sceneeval_results::RunPlan`]), evaluates the
    /// scenes on the request's worker threads with [`run_batch`] (calling
    /// `on_event` as each scene is done), then writes `summary.csv` and `summary.md` into the
    /// output folder (groups: all scenes, each difficulty of the annotations, unannotated).
    ///
    /// # Errors
    /// As [`run_batch`]; [`RunError::Results`] when a summary cannot be
    /// written.
    pub fn run(self, on_event: &(dyn Fn(&RunEvent<'_>) + Sync)) -> Result<RunOutcome, RunError> {
        let (out_dir, force, diagnostics) = self.options;
        // Before the first scene, so that an interrupted run says what it was made with.
        self.evaluator.run_plan().write(&out_dir)?;
        let options = BatchOptions {
            out_dir: out_dir.clone(),
            force,
            diagnostics,
            annotations: self.annotations.as_ref(),
            scenes_in_flight: self.scenes_in_flight,
        };
        let batch = self
            .pool
            .install(|| run_batch(&self.scenes, &self.evaluator, &self.assets, &options, on_event))?;
        let plan = self.evaluator.plan();
        let summary = Summary::from_records(&batch.records, self.annotations.as_ref())
            .with_plan(plan.preset, plan.result_digest());
        summary.write_to(&out_dir)?;
        Ok(RunOutcome {
            scenes: self.scenes,
            skipped: self.skipped,
            fallback: self.fallback,
            batch,
            summary,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_eval::DEFAULT_RENDER_SIZE;

    #[test]
    fn requests_round_trip_through_json_and_refuse_unknown_fields() {
        let mut request = EvaluationRequest::new("scenes", "out");
        request.plan = PlanRequest::named("full");
        request.shard = Some("2/3".parse().unwrap());
        request.vlm = Some(VlmOptions {
            base_url: "http://127.0.0.1:1/v1".into(),
            model: "m".into(),
            api_key_env: None,
            cache: None,
            concurrency: Some(8),
            render_size: None,
            detail: None,
            temperature: Some(None),
            seed: None,
            max_tokens: None,
            token_limit_field: None,
            timeout_s: Some(30.0),
            rpm: None,
            tpm: Some(30_000),
        });
        let json = serde_json::to_string(&request).unwrap();
        assert!(json.contains(r#""temperature":null"#), "{json}");
        assert!(!json.contains(r#""seed""#), "{json}");
        let back: EvaluationRequest = serde_json::from_str(&json).unwrap();
        assert_eq!(back, request);
        assert!(
            serde_json::from_str::<EvaluationRequest>(r#"{"scenes":"s","out":"o","forse":true}"#).is_err()
        );
        let vlm = request.vlm.as_ref().unwrap();
        assert_eq!(
            vlm.cache_dir(Path::new("out")),
            Path::new("out").join("vlm-cache")
        );
        assert_eq!(vlm.render_size().unwrap(), DEFAULT_RENDER_SIZE);
        for bad in [0, 15, 4097, 20_000] {
            let v = VlmOptions {
                render_size: Some(bad),
                ..vlm.clone()
            };
            assert_eq!(
                v.render_size().unwrap_err().request_field(),
                Some(RequestField::VlmRenderSize)
            );
        }
    }

    /// The run folder records the resolved plan (`plan.json`): its digest is the records',
    /// and it reads back as the plan the run was made with.
    #[test]
    fn a_run_records_its_plan() {
        let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        let out = tempfile::tempdir().unwrap();
        let mut request = EvaluationRequest::new(fixtures.join("scenes"), out.path());
        request.assets = vec![format!("fixture={}", fixtures.join("assets").display())];
        request.plan.plan = Some("oob".into());
        request.plan.preset = Some(sceneeval_eval::Preset::Reference);
        request.shard = Some("1/12".parse().unwrap());
        let prepared = request.prepare().unwrap();
        let plan = prepared.evaluator().plan().clone();
        let outcome = prepared.run(&|_| {}).unwrap();
        let recorded = sceneeval_results::RunPlan::read(out.path()).unwrap().unwrap();
        assert_eq!(recorded.vlm, None);
        assert!(recorded.sources.is_empty());
        let record = &outcome.batch.records[0];
        assert_eq!(recorded.digest, record.fingerprint.as_ref().unwrap().plan);
        let back: sceneeval_eval::EvaluationPlan = serde_json::from_value(recorded.plan).unwrap();
        assert_eq!(back, plan);
        assert_eq!(back.preset, sceneeval_eval::Preset::Reference);
    }

    #[test]
    fn prepare_checks_the_scene_folder_and_the_threads() {
        let dir = tempfile::tempdir().unwrap();
        let empty = EvaluationRequest::new(dir.path(), dir.path().join("out"));
        let err = empty.prepare().unwrap_err();
        assert_eq!(err.request_field(), Some(RequestField::Scenes));
        assert!(err.to_string().contains("no scene_<ID>.json files"), "{err}");
        std::fs::write(dir.path().join("scene_1.json"), "{}").unwrap();
        let mut request = EvaluationRequest::new(dir.path(), dir.path().join("out"));
        request.threads = Some(0);
        assert_eq!(
            request.prepare().unwrap_err().request_field(),
            Some(RequestField::Threads)
        );
        request.threads = Some(1);
        request.shard = Some("2/2".parse().unwrap());
        assert!(
            request.prepare().unwrap().scenes().is_empty(),
            "scene 1 is in shard 1/2"
        );
    }
}
