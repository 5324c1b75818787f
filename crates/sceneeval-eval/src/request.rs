//! What a front end asks of the evaluator, in types with each default written once: the plan
//! ([`PlanRequest`]: `geometry`, `full`, a metric list or a plan file, with the preset, metric
//! list, time budget, matching and relation mapping that replace parts of it), the VLM
//! ([`VlmOptions`]) and a scene to settle ([`SettleRequest`]). A run's request
//! (`sceneeval_run::EvaluationRequest`) holds the first two.
//!
//! Errors about a request name its field ([`RequestField`]); a front end shows them under its
//! own name for the field (`--plan`, `plan=`).

use std::fmt;
use std::path::{Path, PathBuf};

use sceneeval_fidelity::{MatchingMethod, RelationMapping};
use sceneeval_results::{Metric, Preset};
use serde::{Deserialize, Deserializer, Serialize};

use crate::{EvalError, EvaluationPlan, Evaluator};

/// VLM requests in flight at once over a whole run, unless the request says otherwise:
/// [`sceneeval_vlm::DEFAULT_CONCURRENCY`].
pub const DEFAULT_VLM_CONCURRENCY: usize = sceneeval_vlm::DEFAULT_CONCURRENCY;

/// Seconds one VLM request (each HTTP attempt) may take before it is abandoned and retried,
/// unless the request says otherwise: [`sceneeval_vlm::DEFAULT_TIMEOUT`] in seconds.
pub const DEFAULT_VLM_TIMEOUT_SECONDS: f64 = sceneeval_vlm::DEFAULT_TIMEOUT.as_secs_f64();

/// Retries after a failed VLM request in a run (requests do not set it):
/// [`sceneeval_vlm::DEFAULT_MAX_RETRIES`]. The check before the first scene makes at most
/// [`sceneeval_vlm::check::CHECK_MAX_RETRIES`].
pub const DEFAULT_VLM_MAX_RETRIES: u32 = sceneeval_vlm::DEFAULT_MAX_RETRIES;

/// The longest VLM timeout a request may set, seconds (an hour).
pub const MAX_VLM_TIMEOUT_SECONDS: f64 = 3600.0;

/// The side of the square object views shown to the VLM, pixels, unless the request says
/// otherwise: [`sceneeval_scene::DEFAULT_VIEW_SIZE`], as the renderer's own default.
pub const DEFAULT_RENDER_SIZE: u32 = sceneeval_scene::DEFAULT_VIEW_SIZE;

/// The sides object views may have, pixels (a smaller view shows the VLM nothing; a larger
/// one costs more memory than any model takes).
pub const RENDER_SIZE_RANGE: std::ops::RangeInclusive<u32> = 16..=4096;

/// The VLM response cache's folder inside the output folder, unless the request names one.
pub const DEFAULT_VLM_CACHE_DIR: &str = "vlm-cache";

/// The folder under the output folder where a run keeps the stability metric's convex
/// decompositions, so that re-runs and other weld variants reuse them (feature `physics`).
pub const DEFAULT_PHYSICS_CACHE_DIR: &str = "physics-cache";

/// What a run evaluates: a plan (`geometry`, `full`, a metric list or a plan file) and what
/// replaces parts of it. Fields left `None` keep the plan's own values.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanRequest {
    /// `geometry` (the default: the six geometry metrics), `full` (the paper's ten), a
    /// comma-separated metric list (`collision,cnt,oor`) or the path of a plan file (JSON, or
    /// TOML when it ends in `.toml`). See [`PlanSpec::parse`].
    #[serde(default)]
    pub plan: Option<String>,
    /// The parameter preset; replaces a plan file's `preset`.
    #[serde(default)]
    pub preset: Option<Preset>,
    /// The metrics to run, replacing the plan's.
    #[serde(default)]
    pub metrics: Option<Vec<Metric>>,
    /// The wall-time budget per scene in seconds; 0 means no budget (`time_budget_seconds` in
    /// earlier versions: every name of a quantity ends in its unit, `_s` for seconds).
    #[serde(default)]
    pub time_budget_s: Option<f64>,
    /// Object matching: `vlm`, `labels`, or a matching file or folder (used only when the plan
    /// runs text-fidelity metrics).
    #[serde(default)]
    pub matching: Option<String>,
    /// Relation mapping: `vlm` or `lexicon` (used only when the plan runs text-fidelity
    /// metrics).
    #[serde(default)]
    pub relation_mapping: Option<String>,
}

impl PlanRequest {
    /// The plan `plan` (what [`PlanRequest::plan`] takes: `geometry`, `full`, a metric list or
    /// a plan file), nothing of it replaced.
    ///
    /// ```
    /// use sceneeval_eval::PlanRequest;
    /// assert_eq!(PlanRequest::named("full").plan.as_deref(), Some("full"));
    /// ```
    pub fn named(plan: impl Into<String>) -> Self {
        PlanRequest {
            plan: Some(plan.into()),
            ..PlanRequest::default()
        }
    }
}

/// An OpenAI-compatible endpoint and what is sent to it. The key is never part of a request:
/// it is read from the environment variable `api_key_env` names (default `OPENAI_API_KEY`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VlmOptions {
    /// The API base URL, e.g. `https://api.openai.com/v1`.
    pub base_url: String,
    /// The model, e.g. `gpt-4o-2024-08-06`.
    pub model: String,
    /// The environment variable holding the API key; it must then be set. `None`: the key in
    /// `OPENAI_API_KEY` when set (local servers need none).
    #[serde(default)]
    pub api_key_env: Option<String>,
    /// The response cache's folder (default `<out>/vlm-cache`, [`DEFAULT_VLM_CACHE_DIR`]).
    #[serde(default)]
    pub cache: Option<PathBuf>,
    /// Requests in flight at once over the whole run (default [`DEFAULT_VLM_CONCURRENCY`]).
    #[serde(default)]
    pub concurrency: Option<usize>,
    /// The side of the object views shown, pixels (default [`DEFAULT_RENDER_SIZE`], within
    /// [`RENDER_SIZE_RANGE`]).
    #[serde(default)]
    pub render_size: Option<u32>,
    /// Image detail: `low` (the client's default, the reference's), `high` or `auto`.
    #[serde(default)]
    pub detail: Option<String>,
    /// Sampling temperature from 0 to 2; `Some(None)` sends none (OpenAI's reasoning models
    /// accept only their own); `None` keeps the client's default (0).
    #[serde(
        default,
        deserialize_with = "present",
        skip_serializing_if = "Option::is_none"
    )]
    pub temperature: Option<Option<f32>>,
    /// Sampling seed; `Some(None)` sends none; `None` keeps the client's default (42).
    #[serde(
        default,
        deserialize_with = "present",
        skip_serializing_if = "Option::is_none"
    )]
    pub seed: Option<Option<u64>>,
    /// Token limit of a reply (default: none sent).
    #[serde(default)]
    pub max_tokens: Option<u32>,
    /// The request field of the token limit: `max_tokens` (default) or `max_completion_tokens`.
    #[serde(default)]
    pub token_limit_field: Option<String>,
    /// Seconds one request (each HTTP attempt) may take (default
    /// [`DEFAULT_VLM_TIMEOUT_SECONDS`], at most [`MAX_VLM_TIMEOUT_SECONDS`]); the scene's time
    /// budget bounds the whole wait, retries included.
    #[serde(default)]
    pub timeout_s: Option<f64>,
    /// A cap on requests per minute (default none): requests start at least 60 s / `rpm` apart.
    #[serde(default)]
    pub rpm: Option<u32>,
    /// A cap on tokens per minute (default none): requests are spaced by an estimate of their
    /// tokens (`sceneeval_vlm_openai::estimate_prompt_tokens`, plus `max_tokens` when set).
    #[serde(default)]
    pub tpm: Option<u64>,
}

/// A key that is present, `null` included (`Some(None)`); an absent key is `None` through
/// `#[serde(default)]`.
fn present<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<Option<T>>, D::Error> {
    Option::<T>::deserialize(d).map(Some)
}

/// A field of a request (`sceneeval_run::EvaluationRequest`, [`SettleRequest`]), named in the
/// errors about it. `Display` writes the
/// request's own path (`plan`, `vlm.base_url`); front ends show their own name for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum RequestField {
    /// `EvaluationRequest::scenes`.
    Scenes,
    /// `EvaluationRequest::assets`.
    Assets,
    /// `EvaluationRequest::out`.
    Out,
    /// `EvaluationRequest::annotations`.
    Annotations,
    /// [`PlanRequest::plan`].
    Plan,
    /// [`PlanRequest::preset`].
    Preset,
    /// [`PlanRequest::metrics`].
    Metrics,
    /// [`PlanRequest::time_budget_s`].
    TimeBudget,
    /// [`PlanRequest::matching`].
    Matching,
    /// [`PlanRequest::relation_mapping`].
    RelationMapping,
    /// `EvaluationRequest::threads`.
    Threads,
    /// `EvaluationRequest::vlm` as a whole (e.g. given to a build without a VLM client).
    Vlm,
    /// [`VlmOptions::base_url`].
    VlmBaseUrl,
    /// [`VlmOptions::model`].
    VlmModel,
    /// [`VlmOptions::api_key_env`].
    VlmApiKeyEnv,
    /// [`VlmOptions::cache`].
    VlmCache,
    /// [`VlmOptions::concurrency`].
    VlmConcurrency,
    /// [`VlmOptions::render_size`].
    VlmRenderSize,
    /// [`VlmOptions::detail`].
    VlmDetail,
    /// [`VlmOptions::temperature`].
    VlmTemperature,
    /// [`VlmOptions::seed`].
    VlmSeed,
    /// [`VlmOptions::max_tokens`].
    VlmMaxTokens,
    /// [`VlmOptions::token_limit_field`].
    VlmTokenLimitField,
    /// [`VlmOptions::timeout_s`].
    VlmTimeout,
    /// [`VlmOptions::rpm`].
    VlmRpm,
    /// [`VlmOptions::tpm`].
    VlmTpm,
}

impl RequestField {
    /// Every field, in the order of the request (the one table front ends name their options
    /// and keywords from).
    pub const ALL: [RequestField; 26] = [
        RequestField::Scenes,
        RequestField::Assets,
        RequestField::Out,
        RequestField::Annotations,
        RequestField::Plan,
        RequestField::Preset,
        RequestField::Metrics,
        RequestField::TimeBudget,
        RequestField::Matching,
        RequestField::RelationMapping,
        RequestField::Threads,
        RequestField::Vlm,
        RequestField::VlmBaseUrl,
        RequestField::VlmModel,
        RequestField::VlmApiKeyEnv,
        RequestField::VlmCache,
        RequestField::VlmConcurrency,
        RequestField::VlmRenderSize,
        RequestField::VlmDetail,
        RequestField::VlmTemperature,
        RequestField::VlmSeed,
        RequestField::VlmMaxTokens,
        RequestField::VlmTokenLimitField,
        RequestField::VlmTimeout,
        RequestField::VlmRpm,
        RequestField::VlmTpm,
    ];

    /// The field's path in the request.
    pub const fn path(self) -> &'static str {
        match self {
            RequestField::Scenes => "scenes",
            RequestField::Assets => "assets",
            RequestField::Out => "out",
            RequestField::Annotations => "annotations",
            RequestField::Plan => "plan",
            RequestField::Preset => "preset",
            RequestField::Metrics => "metrics",
            RequestField::TimeBudget => "time_budget_s",
            RequestField::Matching => "matching",
            RequestField::RelationMapping => "relation_mapping",
            RequestField::Threads => "threads",
            RequestField::Vlm => "vlm",
            RequestField::VlmBaseUrl => "vlm.base_url",
            RequestField::VlmModel => "vlm.model",
            RequestField::VlmApiKeyEnv => "vlm.api_key_env",
            RequestField::VlmCache => "vlm.cache",
            RequestField::VlmConcurrency => "vlm.concurrency",
            RequestField::VlmRenderSize => "vlm.render_size",
            RequestField::VlmDetail => "vlm.detail",
            RequestField::VlmTemperature => "vlm.temperature",
            RequestField::VlmSeed => "vlm.seed",
            RequestField::VlmMaxTokens => "vlm.max_tokens",
            RequestField::VlmTokenLimitField => "vlm.token_limit_field",
            RequestField::VlmTimeout => "vlm.timeout_s",
            RequestField::VlmRpm => "vlm.rpm",
            RequestField::VlmTpm => "vlm.tpm",
        }
    }
}

impl fmt::Display for RequestField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.path())
    }
}

/// A plan as named in a request: [`PlanRequest::plan`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PlanSpec {
    /// `geometry`, or no plan given: the six geometry metrics.
    Geometry,
    /// `full`: the paper's ten metrics (the geometry metrics and CNT, ATR, OOR, OAR).
    Full,
    /// The path of a plan file (JSON, or TOML when it ends in `.toml`).
    File(PathBuf),
    /// Anything else: a comma-separated list of metric names (`collision,cnt,oor`).
    Metrics(String),
}

impl PlanSpec {
    /// The plan named by `spec` (surrounding white space ignored): `geometry` (also for
    /// `None`), `full`, an existing file, a path that names no file (one with a `/` or a plan
    /// file's extension: an error when read, rather than an unknown metric), else a metric
    /// list. A file named `geometry` or `full` in the working folder is not read: those words
    /// always mean the built-in plans.
    ///
    /// ```
    /// use sceneeval_eval::PlanSpec;
    /// use std::path::PathBuf;
    /// assert_eq!(PlanSpec::parse(None), PlanSpec::Geometry);
    /// assert_eq!(PlanSpec::parse(Some(" full ")), PlanSpec::Full);
    /// assert_eq!(PlanSpec::parse(Some("cnt,oor")), PlanSpec::Metrics("cnt,oor".into()));
    /// assert_eq!(PlanSpec::parse(Some("plans/quik.json")), PlanSpec::File(PathBuf::from("plans/quik.json")));
    /// ```
    pub fn parse(spec: Option<&str>) -> PlanSpec {
        match spec.map(str::trim) {
            None | Some("geometry") => PlanSpec::Geometry,
            Some("full") => PlanSpec::Full,
            Some(p) if Path::new(p).is_file() || looks_like_path(p) => PlanSpec::File(PathBuf::from(p)),
            Some(list) => PlanSpec::Metrics(list.to_owned()),
        }
    }

    /// The plan, its parameters starting from `preset` (for a file: replacing the file's
    /// `preset` when given; its explicit values still apply on top).
    ///
    /// # Errors
    /// As [`EvaluationPlan::read_with_preset`] for a file (a missing file says so); for a
    /// metric list, [`EvalError::Plan`] naming the unknown metric with the list of metrics
    /// and the closest name.
    pub fn plan(&self, preset: Option<Preset>) -> Result<EvaluationPlan, EvalError> {
        let base = preset.unwrap_or_default();
        match self {
            PlanSpec::Geometry => Ok(EvaluationPlan::with_preset(base)),
            PlanSpec::Full => Ok(EvaluationPlan::full(base)),
            PlanSpec::File(path) => EvaluationPlan::read_with_preset(path, preset),
            PlanSpec::Metrics(list) => EvaluationPlan::from_metric_list(list, base),
        }
    }
}

/// Whether a plan text that names no file was meant as a path: it has a folder separator or
/// ends like a plan file.
fn looks_like_path(text: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    text.contains('/')
        || text.contains('\\')
        || [".json", ".toml", ".yaml", ".yml"]
            .iter()
            .any(|e| lower.ends_with(e))
}

/// The plan a [`PlanRequest`] resolves to.
#[derive(Debug, Clone, PartialEq)]
pub struct ChosenPlan {
    /// The plan to run.
    pub plan: EvaluationPlan,
    /// Present when the plan runs fidelity metrics without a VLM: what they run with instead.
    pub fallback: Option<NoVlmFallback>,
}

/// How the text-fidelity metrics run without a VLM. Its `Display` is the sentence the front
/// ends show after "no VLM configured: ".
#[derive(Debug, Clone, PartialEq)]
pub struct NoVlmFallback {
    /// The matching method used (labels or a file).
    pub matching: MatchingMethod,
    /// The relation mapping used (the lexicon).
    pub relation_mapping: RelationMapping,
    /// What replaced a choice of the VLM, e.g. "matching by labels".
    pub replaced: Vec<&'static str>,
}

impl fmt::Display for NoVlmFallback {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.matching {
            MatchingMethod::File(path) => write!(f, "fidelity runs with matching from {}", path.display())?,
            other => write!(f, "fidelity runs with {other} matching")?,
        }
        write!(f, " and the {} relation mapping", self.relation_mapping)?;
        if !self.replaced.is_empty() {
            write!(f, " ({} instead of the VLM)", self.replaced.join(", "))?;
        }
        f.write_str("; ATR is not judged.")
    }
}

impl PlanRequest {
    /// The plan to run: [`PlanSpec::plan`] of `plan` with `preset`, then `metrics` and the
    /// time budget applied; when it runs text-fidelity metrics (which need `annotations`),
    /// the matching and relation mapping chosen (the VLM by default when `vlm` is set), then,
    /// without a VLM, labels and the lexicon in place of the VLM. The plan is not validated
    /// again ([`Evaluator::new`] does).
    ///
    /// ```
    /// use sceneeval_eval::PlanRequest;
    /// use sceneeval_fidelity::RelationMapping;
    /// let request = PlanRequest { plan: Some("full".into()), relation_mapping: Some("vlm".into()), ..PlanRequest::default() };
    /// let chosen = request.resolve(false, true).unwrap();
    /// assert_eq!(chosen.plan.fidelity.relation_mapping, RelationMapping::Lexicon);
    /// let note = chosen.fallback.unwrap().to_string();
    /// assert!(note.contains("relations mapped by the lexicon instead of the VLM"), "{note}");
    /// ```
    ///
    /// # Errors
    /// [`EvalError::Request`] naming the field: a plan that cannot be read, a bad time budget,
    /// text-fidelity metrics without annotations, an unknown relation mapping.
    pub fn resolve(&self, vlm: bool, annotations: bool) -> Result<ChosenPlan, EvalError> {
        let mut plan = self.plan()?;
        if !plan.has_fidelity() {
            return Ok(ChosenPlan { plan, fallback: None });
        }
        if !annotations {
            return Err(EvalError::request(
                RequestField::Annotations,
                "is needed: the plan runs text-fidelity metrics (cnt, atr, oor, oar), which check each scene \
                 against its annotation row"
                    .to_owned()));
        }
        match self.matching.as_deref().map(str::trim) {
            None if vlm => plan.fidelity.matching = MatchingMethod::Vlm,
            None => {}
            Some("vlm") => plan.fidelity.matching = MatchingMethod::Vlm,
            Some("labels") => plan.fidelity.matching = MatchingMethod::Labels,
            Some(path) => plan.fidelity.matching = MatchingMethod::File(PathBuf::from(path)),
        }
        match self.relation_mapping.as_deref().map(str::trim) {
            None if vlm => plan.fidelity.relation_mapping = RelationMapping::Vlm,
            None => {}
            Some("vlm") => plan.fidelity.relation_mapping = RelationMapping::Vlm,
            Some("lexicon") => plan.fidelity.relation_mapping = RelationMapping::Lexicon,
            Some(other) => {
                return Err(EvalError::request(
                    RequestField::RelationMapping,
                    format!("{other:?}: expected vlm or lexicon"),
                ));
            }
        }
        if vlm {
            return Ok(ChosenPlan { plan, fallback: None });
        }
        let mut replaced = Vec::new();
        if plan.fidelity.matching == MatchingMethod::Vlm {
            plan.fidelity.matching = MatchingMethod::Labels;
            replaced.push("matching by labels");
        }
        if plan.fidelity.relation_mapping == RelationMapping::Vlm {
            plan.fidelity.relation_mapping = RelationMapping::Lexicon;
            replaced.push("relations mapped by the lexicon");
        }
        let fallback = NoVlmFallback {
            matching: plan.fidelity.matching.clone(),
            relation_mapping: plan.fidelity.relation_mapping,
            replaced,
        };
        Ok(ChosenPlan {
            plan,
            fallback: Some(fallback),
        })
    }
}

impl PlanRequest {
    /// The plan named by [`PlanRequest::plan`] with the preset, metrics and time budget of this
    /// request applied; the text-fidelity choices are [`PlanRequest::resolve`]'s. What a
    /// request to settle a scene uses (its stability parameters, reading options, limits and
    /// time budget).
    ///
    /// # Errors
    /// [`EvalError::Request`] naming the field: a plan that cannot be read, a bad time budget.
    pub fn plan(&self) -> Result<EvaluationPlan, EvalError> {
        let spec = PlanSpec::parse(self.plan.as_deref());
        let mut plan = spec.plan(self.preset).map_err(|e| plan_error(&spec, e))?;
        if let Some(metrics) = &self.metrics {
            plan.metrics.clone_from(metrics);
        }
        if let Some(b) = self.time_budget_s {
            if !(b.is_finite() && b >= 0.0) {
                return Err(EvalError::request(
                    RequestField::TimeBudget,
                    format!("{b} is not a number of seconds (0 for no budget)"),
                ));
            }
            plan.time_budget_s = crate::plan::time_budget(b);
        }
        Ok(plan)
    }
}

/// The request error for the plan named by `spec` that could not be made: the unknown metric
/// of a list or a missing file said in the message, any other plan error as its cause.
fn plan_error(spec: &PlanSpec, e: EvalError) -> EvalError {
    match (spec, e) {
        (PlanSpec::Metrics(list), EvalError::Plan { message, .. }) => EvalError::request(
            RequestField::Plan,
            format!("{list:?} is not geometry, full, a plan file or a metric list: {message}"),
        ),
        (PlanSpec::File(path), _) if !path.exists() => EvalError::request(
            RequestField::Plan,
            format!("plan file {} does not exist", path.display()),
        ),
        (PlanSpec::File(path), e) => {
            EvalError::request_caused(RequestField::Plan, format!("plan file {}", path.display()), e)
        }
        (_, e) => EvalError::request_caused(RequestField::Plan, "invalid plan", e),
    }
}

impl VlmOptions {
    /// The client's settings: `base_url`, `model` and the key, with the sampling settings given
    /// (the others keep [`sceneeval_vlm_openai::OpenAiConfig::new`]'s defaults) and the
    /// concurrency (default [`DEFAULT_VLM_CONCURRENCY`]). What `sceneeval vlm check` sends
    /// too.
    ///
    /// # Errors
    /// [`EvalError::Request`] naming the field: a bad detail, temperature, token limit (field),
    /// concurrency, timeout or rate cap, or an API key variable that is named but unset.
    #[cfg(feature = "openai")]
    pub fn config(&self) -> Result<sceneeval_vlm_openai::OpenAiConfig, EvalError> {
        use sceneeval_vlm_openai::{ApiKey, OpenAiConfig, TEMPERATURE_RANGE};
        let key = ApiKey::from_env_or_default(self.api_key_env.as_deref())
            .map_err(|e| EvalError::request_caused(RequestField::VlmApiKeyEnv, "no API key".to_owned(), e))?;
        let mut config = OpenAiConfig::new(&self.base_url, &self.model).with_api_key(key);
        if let Some(detail) = &self.detail {
            config.detail = detail
                .parse()
                .map_err(|e: String| EvalError::request(RequestField::VlmDetail, e))?;
        }
        if let Some(t) = self.temperature {
            if let Some(v) = t
                && !TEMPERATURE_RANGE.contains(&v)
            {
                return Err(EvalError::request(
                    RequestField::VlmTemperature,
                    format!(
                        "{v} is not from {} to {} (or none)",
                        TEMPERATURE_RANGE.start(),
                        TEMPERATURE_RANGE.end()
                    ),
                ));
            }
            config.temperature = t;
        }
        if let Some(seed) = self.seed {
            config.seed = seed;
        }
        if let Some(n) = self.max_tokens {
            if n == 0 {
                return Err(EvalError::request(
                    RequestField::VlmMaxTokens,
                    "must be at least 1".to_owned(),
                ));
            }
            config.max_tokens = Some(n);
        }
        if let Some(field) = &self.token_limit_field {
            config.token_limit_field = field
                .parse()
                .map_err(|e: String| EvalError::request(RequestField::VlmTokenLimitField, e))?;
        }
        let concurrency = self.concurrency();
        if concurrency == 0 {
            return Err(EvalError::request(
                RequestField::VlmConcurrency,
                "must be at least 1".to_owned(),
            ));
        }
        config.max_concurrent_requests = concurrency;
        let timeout = self.timeout_s.unwrap_or(DEFAULT_VLM_TIMEOUT_SECONDS);
        if !(timeout.is_finite() && timeout > 0.0 && timeout <= MAX_VLM_TIMEOUT_SECONDS) {
            return Err(EvalError::request(
                RequestField::VlmTimeout,
                format!("{timeout} is not a number of seconds above 0 and at most {MAX_VLM_TIMEOUT_SECONDS}"),
            ));
        }
        config.timeout = std::time::Duration::from_secs_f64(timeout);
        if self.rpm == Some(0) {
            return Err(EvalError::request(
                RequestField::VlmRpm,
                "must be at least 1 request per minute",
            ));
        }
        if self.tpm == Some(0) {
            return Err(EvalError::request(
                RequestField::VlmTpm,
                "must be at least 1 token per minute",
            ));
        }
        config.requests_per_minute = self.rpm;
        config.tokens_per_minute = self.tpm;
        Ok(config)
    }

    /// Why the response cache's folder for a run writing to `out` cannot be written, if it
    /// cannot (a probe file is written and removed): the run then goes on without keeping
    /// answers, using those already there.
    pub fn cache_problem(&self, out: &Path) -> Option<String> {
        let dir = self.cache_dir(out);
        sceneeval_files::check_writable_dir(&dir).err().map(|cause| {
            format!(
                "the VLM cache folder {} cannot be written ({cause}): this run keeps no answer for a re-run",
                dir.display()
            )
        })
    }

    /// The OpenAI-compatible client of these options ([`VlmOptions::config`]) (feature
    /// `openai`).
    ///
    /// # Errors
    /// As [`VlmOptions::config`]; a bad base URL names its field.
    #[cfg(feature = "openai")]
    pub fn client(&self) -> Result<sceneeval_vlm_openai::OpenAiVlm, EvalError> {
        client_of(self.config()?)
    }

    /// Requests in flight at once: [`VlmOptions::concurrency`] or [`DEFAULT_VLM_CONCURRENCY`].
    pub fn concurrency(&self) -> usize {
        self.concurrency.unwrap_or(DEFAULT_VLM_CONCURRENCY)
    }

    /// Checks every setting without starting anything: `VlmOptions::config` (with the
    /// feature `openai`) and [`VlmOptions::render_size`].
    ///
    /// # Errors
    /// As those.
    pub fn check(&self) -> Result<(), EvalError> {
        #[cfg(feature = "openai")]
        self.config()?;
        self.render_size()?;
        Ok(())
    }

    /// The side of the object views, checked against [`RENDER_SIZE_RANGE`].
    ///
    /// # Errors
    /// [`EvalError::Request`] for a size out of the range.
    pub fn render_size(&self) -> Result<u32, EvalError> {
        let size = self.render_size.unwrap_or(DEFAULT_RENDER_SIZE);
        if !RENDER_SIZE_RANGE.contains(&size) {
            return Err(EvalError::request(
                RequestField::VlmRenderSize,
                format!(
                    "{size} pixels is not from {} to {}",
                    RENDER_SIZE_RANGE.start(),
                    RENDER_SIZE_RANGE.end()
                ),
            ));
        }
        Ok(size)
    }

    /// The response cache's folder for a run writing to `out`.
    pub fn cache_dir(&self, out: &Path) -> PathBuf {
        self.cache
            .clone()
            .unwrap_or_else(|| out.join(DEFAULT_VLM_CACHE_DIR))
    }

    /// This VLM as one shareable model without a renderer, for tasks that send no image (the
    /// annotation tasks of `sceneeval-annotate`): the HTTP client on a tokio runtime of its own,
    /// its answers cached in [`VlmOptions::cache`] only when that is set.
    ///
    /// # Errors
    /// [`EvalError::Request`]: a bad setting (see [`VlmOptions::config`]) or a client or
    /// runtime that cannot start.
    #[cfg(feature = "openai")]
    pub fn shared_client(&self) -> Result<crate::SharedVlm, EvalError> {
        use sceneeval_vlm::Cached;
        use sceneeval_vlm_openai::RuntimeVlm;
        let client = RuntimeVlm::start(client_of(self.config()?)?).map_err(|e| {
            EvalError::request_caused(RequestField::Vlm, "cannot start the VLM client".to_owned(), e)
        })?;
        Ok(match &self.cache {
            Some(dir) => crate::SharedVlm::new(Cached::new(client, dir)),
            None => crate::SharedVlm::new(client),
        })
    }

    /// `evaluator` asking this VLM (through a runtime of its own, answers cached in the folder
    /// `cache` when given: a run gives [`VlmOptions::cache_dir`] of its output folder) and
    /// rendering the views it is shown. Before the first scene
    /// a batch evaluates, one small request checks the endpoint
    /// ([`crate::SharedVlm::with_endpoint_check`]; the request `sceneeval vlm check` sends,
    /// uncached, with at most [`sceneeval_vlm::check::CHECK_MAX_RETRIES`] retries): an
    /// unreachable server, a refused key or a model the server does not know stops the run with that error. An endpoint that answers but not
    /// usably (no JSON, or the wrong colour) is only warned about.
    ///
    /// # Errors
    /// [`EvalError::Request`]: a bad setting (see `VlmOptions::config`), a client, runtime or
    /// renderer that cannot start, or a build without the features `openai` and `render`.
    pub fn attach(&self, evaluator: Evaluator, cache: Option<&Path>) -> Result<Evaluator, EvalError> {
        #[cfg(all(feature = "openai", feature = "render"))]
        {
            use sceneeval_render::{RenderSettings, Renderer};
            use sceneeval_vlm::Cached;
            use sceneeval_vlm_openai::RuntimeVlm;
            let config = self.config()?;
            let size = self.render_size()?;
            let client = RuntimeVlm::start(client_of(config.clone())?).map_err(|e| {
                EvalError::request_caused(RequestField::Vlm, "cannot start the VLM client".to_owned(), e)
            })?;
            let renderer = Renderer::new().map_err(|e| {
                EvalError::request_caused(
                    RequestField::Vlm,
                    "the VLM needs object views, but the renderer cannot start".to_owned(),
                    e,
                )
            })?;
            let url = client.inner().url().to_owned();
            let vlm = match cache {
                Some(dir) => crate::SharedVlm::new(Cached::new(client, dir)),
                None => crate::SharedVlm::new(client),
            }
            .with_endpoint_check(move || endpoint_check(&config, &url));
            Ok(evaluator
                .with_vlm(vlm)
                .with_renderer(renderer, RenderSettings::square(size)))
        }
        #[cfg(not(all(feature = "openai", feature = "render")))]
        {
            let _ = (evaluator, cache);
            Err(EvalError::request(
                RequestField::Vlm,
                "this build of sceneeval has no VLM client (the features openai and render)".to_owned(),
            ))
        }
    }
}

/// A scene to settle under gravity (`sceneeval settle`, Python's `Scene.settle` and
/// `Scene.stability`): the plan whose `stability` section, reading options, limits and time
/// budget apply (named as for a run: `geometry`, `full`, a metric list or a plan file, with a
/// preset), the weld mode replacing the plan's, the asset folders, and the VLM asked for the
/// support types a scene does not state. Fields left out take the defaults documented on them.
///
/// ```
/// use sceneeval_eval::{PlanRequest, SettleRequest};
/// use sceneeval_physics::WeldMode;
/// let request = SettleRequest {
///     plan: PlanRequest { plan: Some("geometry".into()), ..PlanRequest::default() },
///     weld: Some(WeldMode::None),
///     ..SettleRequest::default()
/// };
/// let prepared = request.prepare().unwrap();
/// assert_eq!(prepared.evaluator().plan().stability.weld, WeldMode::None);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SettleRequest {
    /// Asset folders, each `PREFIX=DIR` or `PREFIX=LAYOUT:DIR` (see
    /// [`sceneeval_io::AssetLibrary::from_specs`]).
    #[serde(default)]
    pub assets: Vec<String>,
    /// The plan (default `geometry`: the built-in parameters).
    #[serde(default)]
    pub plan: PlanRequest,
    /// The weld mode, replacing the plan's `params.stability.weld`.
    #[serde(default)]
    pub weld: Option<sceneeval_physics::WeldMode>,
    /// The VLM asked for the support types the scene does not state, shown each object's views;
    /// its answers are kept in `vlm.cache` when given (default: not kept past the call).
    #[serde(default)]
    pub vlm: Option<VlmOptions>,
    /// Read the scene strictly ([`sceneeval_io::ReadOptions::strict`]): a key the sceneState
    /// format does not have is an error instead of a warning.
    #[serde(default)]
    pub strict: bool,
}

impl SettleRequest {
    /// Checks the request and sets up what settling needs: the plan, the VLM client and its
    /// renderer, the asset folders.
    ///
    /// # Errors
    /// [`EvalError::Request`] naming the field at fault.
    pub fn prepare(&self) -> Result<PreparedSettle, EvalError> {
        let mut plan = self.plan.plan()?;
        if let Some(weld) = self.weld {
            plan.stability.weld = weld;
        }
        plan.read.strict = self.strict;
        let mut evaluator = Evaluator::new(plan)
            .map_err(|e| EvalError::request_caused(RequestField::Plan, "invalid plan".to_owned(), e))?;
        if let Some(vlm) = &self.vlm {
            evaluator = vlm.attach(evaluator, vlm.cache.as_deref())?;
        }
        let assets = sceneeval_io::AssetLibrary::from_specs(&self.assets)
            .map_err(|e| {
                EvalError::request_caused(RequestField::Assets, "invalid asset folder".to_owned(), e)
            })?
            .with_limits(evaluator.plan().limits);
        Ok(PreparedSettle { evaluator, assets })
    }
}

/// A [`SettleRequest`] checked and set up by [`SettleRequest::prepare`].
#[derive(Debug)]
pub struct PreparedSettle {
    evaluator: Evaluator,
    assets: sceneeval_io::AssetLibrary,
}

impl PreparedSettle {
    /// The evaluator: the plan and what it runs with.
    pub fn evaluator(&self) -> &Evaluator {
        &self.evaluator
    }

    /// The asset library scenes are read with.
    pub fn assets(&self) -> &sceneeval_io::AssetLibrary {
        &self.assets
    }

    /// Reads the scene file `path` with the request's assets and the plan's reading options.
    ///
    /// # Errors
    /// As [`sceneeval_io::read_scene_state`].
    pub fn read_scene(&self, path: &Path) -> Result<sceneeval_scene::Scene, sceneeval_io::IoError> {
        sceneeval_io::read_scene_state(path, &self.assets, &self.evaluator.plan().read)
    }

    /// `scene` settled ([`Evaluator::settle_scene`]), the VLM shown views drawn with the
    /// request's assets, within the plan's time budget (feature `physics`).
    ///
    /// # Errors
    /// As [`Evaluator::settle_scene`].
    #[cfg(feature = "physics")]
    pub fn settle(&self, scene: &sceneeval_scene::Scene) -> Result<crate::Settled, EvalError> {
        let deadline = self.evaluator.plan().deadline();
        let inputs = crate::SceneInputs {
            assets: Some(&self.assets),
            deadline: Some(&deadline),
            ..crate::SceneInputs::default()
        };
        self.evaluator.settle_scene(scene, &inputs)
    }
}

/// The OpenAI client of `config`; its errors as request errors (a bad base URL names its
/// field).
#[cfg(feature = "openai")]
fn client_of(
    config: sceneeval_vlm_openai::OpenAiConfig,
) -> Result<sceneeval_vlm_openai::OpenAiVlm, EvalError> {
    use sceneeval_vlm_openai::{OpenAiError, OpenAiVlm};
    OpenAiVlm::new(config).map_err(|e| {
        let field = match &e {
            OpenAiError::InvalidBaseUrl { .. } => RequestField::VlmBaseUrl,
            _ => RequestField::Vlm,
        };
        EvalError::request_caused(field, "cannot set up the VLM client".to_owned(), e)
    })
}

/// Sends the endpoint check (`sceneeval vlm check`'s request) to the endpoint of `config`, at
/// `url`, with at most [`sceneeval_vlm::check::CHECK_MAX_RETRIES`] retries; an error when no answer comes (see [`VlmOptions::attach`]).
#[cfg(feature = "openai")]
fn endpoint_check(config: &sceneeval_vlm_openai::OpenAiConfig, url: &str) -> Result<(), EvalError> {
    use sceneeval_vlm::check::EndpointCheck;
    use sceneeval_vlm::{Outcome, Session};
    use sceneeval_vlm_openai::RuntimeVlm;
    let mut config = config.clone();
    config.retry.max_retries = config
        .retry
        .max_retries
        .min(sceneeval_vlm::check::CHECK_MAX_RETRIES);
    let model = config.model.clone();
    let client = RuntimeVlm::start(client_of(config)?).map_err(|e| {
        EvalError::request_caused(RequestField::Vlm, "cannot start the VLM client".to_owned(), e)
    })?;
    let session = Session::new(&client);
    let start = std::time::Instant::now();
    let answers = pollster::block_on(session.ask(&EndpointCheck::new())).map_err(|e| {
        EvalError::request_caused(
            RequestField::Vlm,
            format!("the endpoint check before the first scene got no answer from model {model:?} at {url}; no scene was evaluated"),
            e,
        )
    })?;
    match answers.into_single() {
        Some(Outcome::Answered { answer, .. }) if answer.correct => {
            tracing::info!(
                url,
                seconds = start.elapsed().as_secs_f64(),
                "the VLM endpoint answers"
            );
        }
        Some(Outcome::Answered { answer, .. }) => tracing::warn!(
            url,
            colour = %answer.colour,
            "the VLM endpoint answers, but called the red square of its check {:?}: does the model see images?",
            answer.colour
        ),
        Some(Outcome::Unanswered(why)) => {
            tracing::warn!(url, %why, "the VLM endpoint answers, but not usably (see `sceneeval vlm check`)");
        }
        None => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_fidelity::FidelityMetric;

    #[test]
    fn the_four_spellings_of_a_plan() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plan.toml");
        std::fs::write(&file, "preset = \"reference\"\nmetrics = [\"support\"]\n").unwrap();
        let path = file.to_str().unwrap();
        assert_eq!(PlanSpec::parse(Some(path)), PlanSpec::File(file.clone()));
        assert_eq!(PlanSpec::parse(Some("geometry")), PlanSpec::Geometry);

        let geometry = PlanRequest::named("geometry").resolve(false, true).unwrap().plan;
        assert_eq!(geometry, EvaluationPlan::geometry_only());
        let full = PlanRequest::named("full").resolve(false, true).unwrap().plan;
        assert_eq!(full.fidelity_metrics(), FidelityMetric::ALL.to_vec());
        let from_file = PlanRequest::named(path).resolve(false, true).unwrap().plan;
        assert_eq!(
            (from_file.preset, from_file.metrics),
            (Preset::Reference, vec![Metric::Support])
        );
        // The preset replaces the file's preset; its explicit values stay.
        let mut r = PlanRequest::named(path);
        r.preset = Some(Preset::Default);
        let replaced = r.resolve(false, true).unwrap().plan;
        assert_eq!(
            (replaced.preset, replaced.metrics),
            (Preset::Default, vec![Metric::Support])
        );
        let list = PlanRequest::named("navigability, cnt")
            .resolve(false, true)
            .unwrap()
            .plan;
        assert_eq!(list.metrics, vec![Metric::Navigability, Metric::Cnt]);

        let err = PlanRequest::named("colision").resolve(false, true).unwrap_err();
        assert_eq!(err.request_field(), Some(RequestField::Plan));
        let text = err.to_string();
        assert!(
            text.starts_with("plan: \"colision\" is not geometry, full, a plan file or a metric list"),
            "{text}"
        );
        assert!(text.contains("did you mean \"collision\""), "{text}");
        // A path that names no file says so instead of reading it as metrics.
        let missing = dir.path().join("nope.json");
        let err = PlanRequest::named(missing.to_str().unwrap())
            .resolve(false, true)
            .unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
        let yaml = dir.path().join("plan.yaml");
        std::fs::write(&yaml, "metrics: [collision]\n").unwrap();
        let err = PlanRequest::named(yaml.to_str().unwrap())
            .resolve(false, true)
            .unwrap_err();
        let text = sceneeval_files::ErrorChain::new(&err).to_string();
        assert!(text.contains("YAML plan files are not read"), "{text}");
    }

    /// `RequestField::ALL` is the table: every key a request serialises (every option set) is
    /// the path of one field of it, and no two fields share a path.
    #[test]
    fn every_request_key_is_the_path_of_one_field() {
        let paths: Vec<&str> = RequestField::ALL.iter().map(|f| f.path()).collect();
        let mut distinct = paths.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), paths.len(), "{paths:?}");
        let plan = PlanRequest {
            plan: Some("full".into()),
            preset: Some(Preset::Reference),
            metrics: Some(vec![Metric::Cnt]),
            time_budget_s: Some(30.0),
            matching: Some("labels".into()),
            relation_mapping: Some("lexicon".into()),
        };
        let vlm = VlmOptions {
            base_url: "http://127.0.0.1:9/v1".into(),
            model: "m".into(),
            api_key_env: Some("KEY".into()),
            cache: Some("cache".into()),
            concurrency: Some(2),
            render_size: Some(256),
            detail: Some("high".into()),
            temperature: Some(None),
            seed: Some(Some(7)),
            max_tokens: Some(300),
            token_limit_field: Some("max_tokens".into()),
            timeout_s: Some(30.0),
            rpm: Some(500),
            tpm: Some(30_000),
        };
        let keys_of = |value: serde_json::Value, prefix: &str| -> Vec<String> {
            value
                .as_object()
                .unwrap()
                .keys()
                .map(|k| format!("{prefix}{k}"))
                .collect()
        };
        let mut keys = keys_of(serde_json::to_value(&plan).unwrap(), "");
        keys.extend(keys_of(serde_json::to_value(&vlm).unwrap(), "vlm."));
        assert_eq!(keys.len(), 6 + 14);
        for key in &keys {
            assert!(paths.contains(&key.as_str()), "{key} is no RequestField's path");
        }
        assert!(keys.contains(&"time_budget_s".to_owned()));
        assert!(keys.contains(&"vlm.timeout_s".to_owned()));
    }

    #[test]
    fn metrics_and_time_budget_override_the_plan() {
        let mut r = PlanRequest::named("geometry");
        r.metrics = Some(vec![Metric::Collision]);
        r.time_budget_s = Some(0.0);
        let p = r.resolve(false, false).unwrap().plan;
        assert_eq!(p.metrics, vec![Metric::Collision]);
        assert_eq!(p.time_budget_s, None);
        r.time_budget_s = Some(30.0);
        assert_eq!(r.resolve(false, false).unwrap().plan.time_budget_s, Some(30.0));
        for bad in [f64::NAN, -1.0, f64::INFINITY] {
            r.time_budget_s = Some(bad);
            assert_eq!(
                r.resolve(false, false).unwrap_err().request_field(),
                Some(RequestField::TimeBudget)
            );
        }
        // Text-fidelity metrics through `metrics`, as through the plan.
        let mut r = PlanRequest::named("geometry");
        r.metrics = Some(vec![Metric::Cnt]);
        let p = r.resolve(false, true).unwrap().plan;
        assert_eq!(p.fidelity_metrics(), vec![FidelityMetric::Cnt]);
        assert!(p.geometry_metrics().is_empty());
    }

    #[test]
    fn fidelity_needs_annotations_and_falls_back_without_a_vlm() {
        let err = PlanRequest::named("full").resolve(false, false).unwrap_err();
        assert_eq!(err.request_field(), Some(RequestField::Annotations));
        assert!(err.to_string().contains("cnt, atr, oor, oar"), "{err}");
        // Geometry plans need no annotations.
        assert!(PlanRequest::named("collision").resolve(false, false).is_ok());

        // The default preset already matches by labels and maps by the lexicon: nothing is
        // replaced, but the run is still told that it has no VLM.
        let fallback = PlanRequest::named("full")
            .resolve(false, true)
            .unwrap()
            .fallback
            .unwrap();
        assert!(fallback.replaced.is_empty());
        assert_eq!(
            fallback.to_string(),
            "fidelity runs with labels matching and the lexicon relation mapping; ATR is not judged."
        );
        let mut r = PlanRequest::named("full");
        r.matching = Some("runs/matching".into());
        assert_eq!(
            r.resolve(false, true).unwrap().fallback.unwrap().to_string(),
            "fidelity runs with matching from runs/matching and the lexicon relation mapping; ATR is not judged."
        );
        // The reference preset asks the VLM for both: both are replaced.
        let mut r = PlanRequest::named("full");
        r.preset = Some(Preset::Reference);
        let chosen = r.resolve(false, true).unwrap();
        assert_eq!(chosen.plan.fidelity.matching, MatchingMethod::Labels);
        assert_eq!(chosen.plan.fidelity.relation_mapping, RelationMapping::Lexicon);
        assert_eq!(
            chosen.fallback.unwrap().replaced,
            vec!["matching by labels", "relations mapped by the lexicon"]
        );
        // With a VLM, the VLM is the default for both, and nothing falls back.
        let chosen = PlanRequest::named("full").resolve(true, true).unwrap();
        assert_eq!(chosen.plan.fidelity.matching, MatchingMethod::Vlm);
        assert_eq!(chosen.plan.fidelity.relation_mapping, RelationMapping::Vlm);
        assert!(chosen.fallback.is_none());
        let mut r = PlanRequest::named("full");
        r.relation_mapping = Some("dictionary".into());
        let err = r.resolve(false, true).unwrap_err();
        assert_eq!(err.request_field(), Some(RequestField::RelationMapping));
        assert_eq!(
            err.to_string(),
            "relation_mapping: \"dictionary\": expected vlm or lexicon"
        );
    }
}
