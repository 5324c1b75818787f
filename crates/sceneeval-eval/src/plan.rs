//! [`EvaluationPlan`]: what to evaluate and with which parameters, read from JSON or TOML.

use std::path::Path;

use sceneeval_fidelity::{FidelityMetric, FidelityParams};
use sceneeval_io::{Limits, ReadOptions};
use sceneeval_physics::StabilityParams;
use sceneeval_plausibility::{
    self as plausibility, Deadline, Footprint, PlausibilityError, PlausibilityParams,
};
use sceneeval_relations::RelationParams;
use sceneeval_results::{Metric, Preset};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::EvalError;

/// The default time budget per scene, in seconds (loading and every metric together).
pub const DEFAULT_TIME_BUDGET_SECONDS: f64 = 600.0;

/// What to evaluate and with which parameters.
///
/// Read from JSON with [`EvaluationPlan::from_json_str`] or [`EvaluationPlan::read`]: the
/// `preset` (default `default`) gives every parameter, then the file's values replace the
/// preset's one by one. Unknown fields at any depth are errors, and so are impossible values
/// ([`EvaluationPlan::validate`]), each named by its path (`params.collision.contact_tolerance_m`):
///
/// ```
/// use sceneeval_eval::{EvaluationPlan, Metric, Preset};
///
/// let plan = EvaluationPlan::from_json_str(r#"{
///     "preset": "reference",
///     "metrics": ["collision", "navigability"],
///     "params": { "collision": { "contact_tolerance_m": 0.01 } }
/// }"#).unwrap();
/// assert_eq!(plan.preset, Preset::Reference);
/// assert_eq!(plan.metrics, vec![Metric::Collision, Metric::Navigability]);
/// assert_eq!(plan.params.collision.contact_tolerance_m, 0.01);
/// // The preset's other values stay.
/// assert!(!plan.params.collision.exclude_floor_coverings);
///
/// let err = EvaluationPlan::from_json_str(
///     r#"{"params": {"collision": {"exclude_floor_covering": true}}}"#).unwrap_err();
/// assert!(err.to_string().contains("params.collision.exclude_floor_covering"));
/// ```
///
/// Every metric's parameters are under `params.<metric>`: the geometry metrics'
/// (`params.collision`, ...), `params.stability`, `params.fidelity` (the text-fidelity
/// metrics') and `params.relations` (the spatial predicates'). Plans written before had the
/// last three at the top level; they are still read, with a warning that names the new place.
/// Serialising a plan writes the new places.
#[derive(Debug, Clone, PartialEq)]
pub struct EvaluationPlan {
    /// The preset the parameters start from (recorded in `summary.md`).
    pub preset: Preset,
    /// The metrics to run, without repeats: geometry metrics and text-fidelity metrics (CNT,
    /// ATR, OOR, OAR, which need the scene's annotation row). They always run and are reported
    /// in the order of [`Metric::ALL`].
    pub metrics: Vec<Metric>,
    /// Parameters of the plausibility metrics (`params.collision`, ...).
    pub params: PlausibilityParams,
    /// Parameters of the fidelity metrics (`params.fidelity`): matching, relation mapping,
    /// reference switches.
    pub fidelity: FidelityParams,
    /// Parameters of the spatial predicates (`params.relations`), for the text-fidelity
    /// metrics (OOR, OAR) and recorded in every result's fingerprint.
    pub relations: RelationParams,
    /// How scene files are read (architecture, the simple architecture's walls and floor).
    pub read: ReadOptions,
    /// File-size, triangle and memory budgets per file and asset; an asset over them fails
    /// its scene, not the run.
    pub limits: Limits,
    /// Wall-time budget per scene in seconds (loading and metrics together); a scene over it
    /// is recorded as failed and the run goes on. `None` for no budget, written `0` in a plan
    /// file as on the command line and in Python (`null` is read too, in JSON). Default 600.
    pub time_budget_s: Option<f64>,
    /// Parameters of the stability metric (`params.stability.weld`,
    /// `params.stability.duration_s`, ...): the same under both presets. Read and checked in every build; a plan that runs the metric
    /// needs the feature `physics`.
    pub stability: StabilityParams,
}

impl Default for EvaluationPlan {
    fn default() -> Self {
        EvaluationPlan::geometry_only()
    }
}

impl EvaluationPlan {
    /// Every geometry-only metric with this implementation's default parameters: the plan that
    /// needs no VLM.
    pub fn geometry_only() -> Self {
        EvaluationPlan {
            preset: Preset::Default,
            metrics: plausibility::Metric::ALL.map(Metric::from).to_vec(),
            params: PlausibilityParams::default(),
            fidelity: FidelityParams::default(),
            relations: RelationParams::default(),
            read: ReadOptions::default(),
            limits: Limits::default(),
            time_budget_s: Some(DEFAULT_TIME_BUDGET_SECONDS),
            stability: StabilityParams::default(),
        }
    }

    /// Every geometry-only metric with every reference-parity switch on: floor coverings
    /// (rugs, carpets, mats) are tested for collisions like any object
    /// (`params.collision.exclude_floor_coverings = false`), no object is walked over by
    /// navigability, accessibility or opening clearance (`walkable_height_m = 0`), obstacles on
    /// the floor plan are the projected bounding boxes rather than the meshes' convex hulls
    /// (`footprint = bounding_box` for navigability and accessibility), and the
    /// spatial predicates use [`RelationParams::reference`]. Scene reading already follows
    /// the reference by default (simple architecture when a file has none, its floor at the
    /// lowest object).
    pub fn reference() -> Self {
        let mut plan = EvaluationPlan::geometry_only();
        plan.preset = Preset::Reference;
        plan.params.collision.exclude_floor_coverings = false;
        plan.params.navigability.walkable_height_m = 0.0;
        plan.params.accessibility.walkable_height_m = 0.0;
        plan.params.opening_clearance.walkable_height_m = 0.0;
        plan.params.navigability.footprint = Footprint::BoundingBox;
        plan.params.accessibility.footprint = Footprint::BoundingBox;
        plan.relations = RelationParams::reference();
        plan.fidelity = FidelityParams::reference();
        plan.read = ReadOptions::default();
        plan
    }

    /// The paper's ten metrics (the six geometry metrics and CNT, ATR, OOR, OAR; not
    /// stability, which the paper does not have) with the preset's parameters. The `default` preset matches by labels and maps relations with the
    /// lexicon (no VLM needed; ATR is then not judged); `reference` asks the VLM for both.
    ///
    /// ```
    /// use sceneeval_eval::{EvaluationPlan, Preset};
    /// use sceneeval_fidelity::{FidelityMetric, MatchingMethod};
    /// let full = EvaluationPlan::full(Preset::Default);
    /// assert_eq!(full.metrics.len(), 10);
    /// assert_eq!(full.fidelity.matching, MatchingMethod::Labels);
    /// assert_eq!(EvaluationPlan::full(Preset::Reference).fidelity.matching, MatchingMethod::Vlm);
    /// assert!(full.runs_fidelity(FidelityMetric::Atr));
    /// ```
    pub fn full(preset: Preset) -> Self {
        let mut plan = EvaluationPlan::with_preset(preset);
        plan.metrics = Metric::ALL
            .into_iter()
            .filter(|m| *m != Metric::Stability)
            .collect();
        plan
    }

    /// A plan with the preset's parameters running exactly the metrics named in `list`
    /// (comma-separated names or summary columns, see [`Metric`]).
    ///
    /// # Errors
    /// [`EvalError::Plan`] naming an unknown metric (with the list of metrics and the closest
    /// name), or a metric listed twice.
    pub fn from_metric_list(list: &str, preset: Preset) -> Result<Self, EvalError> {
        let mut plan = EvaluationPlan::with_preset(preset);
        plan.metrics = list
            .split(',')
            .filter(|n| !n.trim().is_empty())
            .map(|name| name.parse::<Metric>())
            .collect::<Result<_, _>>()
            .map_err(|e| plan_error(Some("metrics"), e.to_string()))?;
        plan.validate()?;
        Ok(plan)
    }

    /// Whether the plan runs the fidelity metric `metric`.
    #[inline]
    pub fn runs_fidelity(&self, metric: FidelityMetric) -> bool {
        self.metrics.contains(&Metric::from(metric))
    }

    /// Whether the plan runs any fidelity metric (and so reads annotation rows).
    #[inline]
    pub fn has_fidelity(&self) -> bool {
        self.metrics.iter().any(|m| m.fidelity().is_some())
    }

    /// The geometry metrics the plan runs, in the order they run and are reported.
    pub fn geometry_metrics(&self) -> Vec<plausibility::Metric> {
        self.ordered_metrics()
            .into_iter()
            .filter_map(Metric::geometry)
            .collect()
    }

    /// The text-fidelity metrics the plan runs, in the order they are reported.
    pub fn fidelity_metrics(&self) -> Vec<FidelityMetric> {
        self.ordered_metrics()
            .into_iter()
            .filter_map(Metric::fidelity)
            .collect()
    }

    /// The plan of a preset.
    pub fn with_preset(preset: Preset) -> Self {
        match preset {
            Preset::Default => EvaluationPlan::geometry_only(),
            Preset::Reference => EvaluationPlan::reference(),
        }
    }

    /// A plan from JSON text (see the type docs).
    ///
    /// # Errors
    /// [`EvalError::Plan`] naming the field: malformed JSON (with line and column), an unknown
    /// field, a value of the wrong type, or an impossible value.
    pub fn from_json_str(text: &str) -> Result<Self, EvalError> {
        Self::from_json_str_with_preset(text, None)
    }

    /// A plan from JSON text; `preset`, when given, replaces the file's `preset` field (the
    /// file's explicit values still apply on top of it).
    ///
    /// # Errors
    /// As [`EvaluationPlan::from_json_str`].
    pub fn from_json_str_with_preset(text: &str, preset: Option<Preset>) -> Result<Self, EvalError> {
        let value: Value = serde_json::from_str(text).map_err(|e| EvalError::Plan {
            path: None,
            field: None,
            message: format!("malformed JSON at line {} column {}: {e}", e.line(), e.column()),
        })?;
        Self::from_value(value, preset)
    }

    /// A plan from TOML text: the fields of the JSON form, objects as tables (TOML has no
    /// `null`: leave a field out to keep the preset's value).
    ///
    /// ```
    /// use sceneeval_eval::{EvaluationPlan, Metric};
    /// let plan = EvaluationPlan::from_toml_str(
    ///     "metrics = [\"collision\", \"navigability\"]\n\
    ///      [params.navigability]\n\
    ///      robot_width_m = 0.3\n",
    /// ).unwrap();
    /// assert_eq!(plan.ordered_metrics(), vec![Metric::Collision, Metric::Navigability]);
    /// assert_eq!(plan.params.navigability.robot_width_m, 0.3);
    /// ```
    ///
    /// # Errors
    /// As [`EvaluationPlan::from_json_str`]; malformed TOML names its line and column.
    pub fn from_toml_str(text: &str) -> Result<Self, EvalError> {
        Self::from_toml_str_with_preset(text, None)
    }

    /// A plan from TOML text; `preset`, when given, replaces the file's `preset` field.
    ///
    /// # Errors
    /// As [`EvaluationPlan::from_toml_str`].
    pub fn from_toml_str_with_preset(text: &str, preset: Option<Preset>) -> Result<Self, EvalError> {
        let value: toml::Value = toml::from_str(text).map_err(|e| EvalError::Plan {
            path: None,
            field: None,
            message: format!("malformed TOML: {}", e.to_string().trim_end()),
        })?;
        Self::from_value(json_of_toml(value, "")?, preset)
    }

    fn from_value(value: Value, preset: Option<Preset>) -> Result<Self, EvalError> {
        let Value::Object(given) = value else {
            return Err(plan_error(None, "a plan must be a JSON object".into()));
        };
        let mut given = sections_under_params(given)?;
        read_renamed_keys(&mut given)?;
        matching_as_choice(&mut given);
        if given.contains_key("fidelity_metrics") {
            return Err(plan_error(
                Some("fidelity_metrics"),
                "unknown field: list the text-fidelity metrics (cnt, atr, oor, oar) in `metrics` with the \
                 geometry metrics"
                    .into(),
            ));
        }
        let preset = match (preset, given.get("preset")) {
            (Some(p), _) => p,
            (None, Some(v)) => Preset::deserialize(v).map_err(|_| {
                plan_error(
                    Some("preset"),
                    format!("unknown preset {v} (expected \"default\" or \"reference\")"),
                )
            })?,
            (None, None) => Preset::Default,
        };
        let base = EvaluationPlan::with_preset(preset);
        let mut merged = serde_json::to_value(&base).map_err(|e| plan_error(None, e.to_string()))?;
        let given = Value::Object(given);
        if let Some(path) = list_for_object(&given, &merged, "") {
            return Err(plan_error(
                Some(&path),
                "a list where the plan has an object: give its fields by name (a JSON object, a TOML table)"
                    .to_owned(),
            ));
        }
        merge(&mut merged, &given);
        if let Value::Object(m) = &mut merged {
            m.insert("preset".into(), Value::String(preset.name().into()));
        }
        let fields: PlanFields = serde_path_to_error::deserialize(&sections_at_top(merged)).map_err(|e| {
            let path = params_path(&e.path().to_string());
            plan_error(Some(&path), e.into_inner().to_string())
        })?;
        let plan = EvaluationPlan::from(fields);
        // Every key given must survive the round trip; one that does not is unknown.
        let back = serde_json::to_value(&plan).map_err(|e| plan_error(None, e.to_string()))?;
        if let Some(path) = unknown_key(&given, &back, "") {
            return Err(plan_error(Some(&path), "unknown field".to_owned()));
        }
        plan.validate()?;
        Ok(plan)
    }

    /// A plan from a file: TOML when its name ends in `.toml` (any case), JSON otherwise.
    ///
    /// # Errors
    /// As [`EvaluationPlan::from_json_str`], naming the file.
    pub fn read(path: &Path) -> Result<Self, EvalError> {
        Self::read_with_preset(path, None)
    }

    /// A plan from a file (TOML or JSON, as [`EvaluationPlan::read`]), with `preset` replacing
    /// the file's `preset` field when given.
    ///
    /// # Errors
    /// As [`EvaluationPlan::from_json_str`], naming the file.
    pub fn read_with_preset(path: &Path, preset: Option<Preset>) -> Result<Self, EvalError> {
        let text = std::fs::read_to_string(path).map_err(|e| EvalError::Plan {
            path: Some(path.to_owned()),
            field: None,
            message: e.to_string(),
        })?;
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if matches!(extension.as_deref(), Some("yaml" | "yml")) {
            return Err(EvalError::Plan {
                path: Some(path.to_owned()),
                field: None,
                message: "YAML plan files are not read: write the plan as JSON, or as TOML in a file \
                          ending in .toml (docs/formats.md, \"Evaluation plan\")"
                    .into(),
            });
        }
        let is_toml = extension.as_deref() == Some("toml");
        let plan = if is_toml {
            Self::from_toml_str_with_preset(&text, preset)
        } else {
            Self::from_json_str_with_preset(&text, preset)
        };
        plan.map_err(|e| match e {
            EvalError::Plan { field, message, .. } => EvalError::Plan {
                path: Some(path.to_owned()),
                field,
                message,
            },
            other => other,
        })
    }

    /// Checks everything that can be checked without a scene: at least one metric and none
    /// twice, every metric parameter in its range (raster sizes included), the predicates'
    /// parameters, positive limits, a positive finite time budget and wall height.
    ///
    /// # Errors
    /// [`EvalError::Plan`] naming the field, e.g. `params.collision.contact_tolerance_m`.
    pub fn validate(&self) -> Result<(), EvalError> {
        if self.metrics.is_empty() {
            return Err(plan_error(Some("metrics"), "the plan lists no metric".into()));
        }
        self.fidelity.validate().map_err(|e| {
            let field = match &e {
                sceneeval_fidelity::FidelityError::InvalidParameter { name, .. } => {
                    format!("params.fidelity.{name}")
                }
                _ => "params.fidelity".to_owned(),
            };
            plan_error(Some(&field), e.to_string())
        })?;
        for (i, m) in self.metrics.iter().enumerate() {
            if self.metrics[..i].contains(m) {
                return Err(plan_error(
                    Some(&format!("metrics[{i}]")),
                    format!("metric {m} is listed twice"),
                ));
            }
            if *m == Metric::Stability && cfg!(not(feature = "physics")) {
                return Err(plan_error(Some(&format!("metrics[{i}]")), NO_PHYSICS.to_owned()));
            }
        }
        self.stability.validate().map_err(|e| {
            let field = match &e {
                sceneeval_physics::PhysicsError::InvalidParameter { name, .. } => {
                    format!("params.stability.{name}")
                }
                _ => "params.stability".to_owned(),
            };
            plan_error(Some(&field), e.to_string())
        })?;
        self.params.validate().map_err(|e| {
            let field = match &e {
                PlausibilityError::InvalidParameter { metric, name, .. } => format!("params.{metric}.{name}"),
                PlausibilityError::RasterTooLarge { metric, .. } => format!("params.{metric}.resolution"),
                _ => "params".to_owned(),
            };
            plan_error(Some(&field), e.to_string())
        })?;
        self.relations
            .validate()
            .map_err(|e| plan_error(Some("params.relations"), e.to_string()))?;
        self.limits
            .validate()
            .map_err(|m| plan_error(Some(&format!("limits.{}", m.split(' ').next().unwrap_or(""))), m))?;
        if let Some(b) = self.time_budget_s
            && !(b.is_finite() && b > 0.0)
        {
            return Err(plan_error(
                Some("time_budget_s"),
                format!("{b} must be a positive number of seconds (or 0 for no budget)"),
            ));
        }
        let h = self.read.simple_wall_height_m;
        if !(h.is_finite() && h > 0.0) {
            return Err(plan_error(
                Some("read.simple_wall_height_m"),
                format!("{h} must be a positive number of metres"),
            ));
        }
        Ok(())
    }

    /// A [`Deadline`] of [`EvaluationPlan::time_budget_s`] from now ([`Deadline::none`]
    /// without a budget, or with one too large for a `Duration`).
    ///
    /// ```
    /// use sceneeval_eval::EvaluationPlan;
    /// let mut plan = EvaluationPlan::geometry_only();
    /// assert_eq!(plan.deadline().budget().map(|b| b.as_secs()), Some(600));
    /// plan.time_budget_s = None;
    /// assert!(plan.deadline().budget().is_none());
    /// ```
    pub fn deadline(&self) -> Deadline {
        match self
            .time_budget_s
            .and_then(|b| std::time::Duration::try_from_secs_f64(b).ok())
        {
            Some(b) => Deadline::after(b),
            None => Deadline::none(),
        }
    }

    /// Whether the plan runs `metric`.
    #[inline]
    pub fn runs(&self, metric: Metric) -> bool {
        self.metrics.contains(&metric)
    }

    /// The metrics in the order they run and are reported.
    pub fn ordered_metrics(&self) -> Vec<Metric> {
        Metric::ALL.into_iter().filter(|m| self.runs(*m)).collect()
    }

    /// A digest of everything in the plan a result depends on: the metrics (as a set) and
    /// every parameter, the predicates' and the reading options included. The preset's name,
    /// the limits and the time budget are left out: they decide whether a scene is
    /// evaluated, not what its result is. Hex-encoded BLAKE3 of the canonical JSON.
    pub fn result_digest(&self) -> String {
        // The form of the digest predates `Metric`: the geometry metrics, then the fidelity
        // metrics apart (sorted), so that results of earlier versions stay reusable.
        #[derive(Serialize)]
        struct Semantic<'a> {
            metrics: Vec<plausibility::Metric>,
            params: &'a PlausibilityParams,
            #[serde(skip_serializing_if = "Vec::is_empty")]
            fidelity_metrics: Vec<FidelityMetric>,
            #[serde(skip_serializing_if = "Option::is_none")]
            fidelity: Option<&'a FidelityParams>,
            relations: &'a RelationParams,
            read: &'a ReadOptions,
            // Present only when the plan runs stability, so that other digests stay as they were.
            #[serde(skip_serializing_if = "Option::is_none")]
            stability: Option<&'a StabilityParams>,
        }
        let fidelity_metrics = self.fidelity_metrics();
        let s = Semantic {
            metrics: self.geometry_metrics(),
            params: &self.params,
            fidelity: (!fidelity_metrics.is_empty()).then_some(&self.fidelity),
            fidelity_metrics,
            relations: &self.relations,
            read: &self.read,
            stability: self.runs(Metric::Stability).then_some(&self.stability),
        };
        // Serialising plain data structs to a string cannot fail.
        let text = serde_json::to_string(&s).unwrap_or_default();
        blake3::hash(text.as_bytes()).to_hex().to_string()
    }
}

/// Why a plan of a build without the `physics` feature cannot run stability.
const NO_PHYSICS: &str = "the stability metric needs the rigid-body simulation, which this build of sceneeval \
                          does not have (the facade's feature `physics`; the sceneeval CLI and Python package have it)";

fn plan_error(field: Option<&str>, message: String) -> EvalError {
    EvalError::Plan {
        path: None,
        field: field.filter(|f| !f.is_empty() && *f != ".").map(str::to_owned),
        message,
    }
}

/// The parameter sections a plan has under `params` beside the geometry metrics', which plans
/// written before had at the top level.
const PARAM_SECTIONS: [&str; 3] = ["fidelity", "relations", "stability"];

/// A plan as serde reads it once its parameter sections are back at the top level (every field
/// present: the preset's values merged with the file's).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlanFields {
    preset: Preset,
    metrics: Vec<Metric>,
    params: PlausibilityParams,
    // Absent only when `params` was replaced whole because of an unknown key, which serde then
    // names.
    #[serde(default)]
    fidelity: FidelityParams,
    #[serde(default)]
    relations: RelationParams,
    read: ReadOptions,
    limits: Limits,
    time_budget_s: Option<f64>,
    #[serde(default)]
    stability: StabilityParams,
}

/// The budget `seconds` gives: `0` is no budget, in a plan file, in a request (`--time-budget 0`,
/// Python's `time_budget_seconds=0`) alike.
pub(crate) fn time_budget(seconds: f64) -> Option<f64> {
    (seconds != 0.0).then_some(seconds)
}

impl From<PlanFields> for EvaluationPlan {
    fn from(f: PlanFields) -> Self {
        EvaluationPlan {
            preset: f.preset,
            metrics: f.metrics,
            params: f.params,
            fidelity: f.fidelity,
            relations: f.relations,
            read: f.read,
            limits: f.limits,
            // TOML has no `null`: a plan file says "no budget" with `0`.
            time_budget_s: f.time_budget_s.and_then(time_budget),
            stability: f.stability,
        }
    }
}

/// Writes the plan as a plan file has it: `params` holds every metric's parameters.
impl Serialize for EvaluationPlan {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Params<'a> {
            #[serde(flatten)]
            geometry: &'a PlausibilityParams,
            stability: &'a StabilityParams,
            fidelity: &'a FidelityParams,
            relations: &'a RelationParams,
        }
        #[derive(Serialize)]
        struct File<'a> {
            preset: Preset,
            metrics: &'a [Metric],
            params: Params<'a>,
            read: &'a ReadOptions,
            limits: &'a Limits,
            time_budget_s: Option<f64>,
        }
        File {
            preset: self.preset,
            metrics: &self.metrics,
            params: Params {
                geometry: &self.params,
                stability: &self.stability,
                fidelity: &self.fidelity,
                relations: &self.relations,
            },
            read: &self.read,
            limits: &self.limits,
            time_budget_s: self.time_budget_s,
        }
        .serialize(serializer)
    }
}

/// Reads a plan as [`EvaluationPlan::from_json_str`] does (the preset's values, then the
/// given ones).
impl<'de> Deserialize<'de> for EvaluationPlan {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let value = Value::deserialize(deserializer)?;
        EvaluationPlan::from_value(value, None).map_err(serde::de::Error::custom)
    }
}

/// `given` with the parameter sections written at the top level (the place of plans written
/// before) moved under `params`, each with a warning naming its new place.
///
/// # Errors
/// A section given in both places.
fn sections_under_params(mut given: Map<String, Value>) -> Result<Map<String, Value>, EvalError> {
    for key in PARAM_SECTIONS {
        let Some(old) = given.remove(key) else {
            continue;
        };
        let params = given.entry("params").or_insert_with(|| Value::Object(Map::new()));
        let Value::Object(params) = params else {
            // `params` is not an object: serde names it below.
            given.insert(key.to_owned(), old);
            continue;
        };
        if params.contains_key(key) {
            return Err(plan_error(
                Some(key),
                format!("given twice: here and as `params.{key}` (its place); remove this one"),
            ));
        }
        tracing::warn!(
            "plan: `{key}` at the top level is read as `params.{key}`, its place now: move it there"
        );
        params.insert(key.to_owned(), old);
    }
    Ok(given)
}

/// Every plan key renamed since plans were first written, as `(old path, new path)`: the
/// unit-suffix rule (docs/conventions.md, "Units in names") gave lengths `_m`, densities
/// `_per_m2` or `_kg_m3`, the time budget `_s`. A `*` segment stands for any key (the
/// relations' twelve distance bands). A row renames its last key in place: its parent path is
/// the new path's. Paths are those of the plan file: the parameter sections under `params`.
///
/// A plan using an old key is read as if it used the new one, with a warning naming the new
/// path ([`read_renamed_keys`]); both in one object is an error naming both.
#[rustfmt::skip]
pub const RENAMED_KEYS: &[(&str, &str)] = &[
    ("time_budget_seconds", "time_budget_s"),
    ("read.simple_wall_height", "read.simple_wall_height_m"),
    ("params.collision.contact_tolerance", "params.collision.contact_tolerance_m"),
    ("params.collision.depth_sample_spacing", "params.collision.depth_sample_spacing_m"),
    ("params.support.lift", "params.support.lift_m"),
    ("params.support.contact_distance", "params.support.contact_distance_m"),
    ("params.support.extreme_band", "params.support.extreme_band_m"),
    ("params.support.samples_per_square_metre", "params.support.samples_per_m2"),
    ("params.navigability.resolution.metres_per_pixel", "params.navigability.resolution.m_per_pixel"),
    ("params.navigability.margin", "params.navigability.margin_m"),
    ("params.navigability.robot_width", "params.navigability.robot_width_m"),
    ("params.navigability.height_cutoff", "params.navigability.height_cutoff_m"),
    ("params.navigability.walkable_height", "params.navigability.walkable_height_m"),
    ("params.navigability.door_max_sill", "params.navigability.door_max_sill_m"),
    ("params.navigability.door_strip_depth", "params.navigability.door_strip_depth_m"),
    ("params.accessibility.strip_offset", "params.accessibility.strip_offset_m"),
    ("params.accessibility.strip_width", "params.accessibility.strip_width_m"),
    ("params.accessibility.height_cutoff", "params.accessibility.height_cutoff_m"),
    ("params.accessibility.walkable_height", "params.accessibility.walkable_height_m"),
    ("params.out_of_bounds.below_floor_tolerance", "params.out_of_bounds.below_floor_tolerance_m"),
    ("params.out_of_bounds.boundary_tolerance", "params.out_of_bounds.boundary_tolerance_m"),
    ("params.opening_clearance.door_depth", "params.opening_clearance.door_depth_m"),
    ("params.opening_clearance.window_depth", "params.opening_clearance.window_depth_m"),
    ("params.opening_clearance.probe_offset", "params.opening_clearance.probe_offset_m"),
    ("params.opening_clearance.pixels_per_metre", "params.opening_clearance.pixels_per_m"),
    ("params.opening_clearance.touch_tolerance", "params.opening_clearance.touch_tolerance_m"),
    ("params.opening_clearance.walkable_height", "params.opening_clearance.walkable_height_m"),
    ("params.stability.mass.density", "params.stability.mass.density_kg_m3"),
    ("params.stability.mass.per_object", "params.stability.mass.per_object_kg"),
    ("params.relations.tolerance", "params.relations.tolerance_m"),
    ("params.relations.min_half_extent", "params.relations.min_half_extent_m"),
    ("params.relations.middle_of_sigma", "params.relations.middle_of_sigma_m"),
    ("params.relations.middle_of_room_base_sigma", "params.relations.middle_of_room_base_sigma_m"),
    ("params.relations.*.min", "params.relations.*.min_m"),
    ("params.relations.*.max", "params.relations.*.max_m"),
    ("params.relations.*.sigma", "params.relations.*.sigma_m"),
];

/// Reads the old keys of [`RENAMED_KEYS`] in `plan` (a plan file as JSON, its parameter
/// sections under `params`) as their new ones, each with a warning (`tracing`) naming the new
/// path; returns the `(old path, new path)` of every key renamed. Plan files are read through
/// it; so are parameters given elsewhere in a plan's shape (Python's `relation_params`, under
/// `params.relations`).
///
/// ```
/// use sceneeval_eval::read_renamed_keys;
/// let mut plan = serde_json::json!({"params": {"relations": {"near": {"sigma": 0.3}}}});
/// let renamed = read_renamed_keys(plan.as_object_mut().unwrap()).unwrap();
/// assert_eq!(renamed, [("params.relations.near.sigma".to_owned(), "params.relations.near.sigma_m".to_owned())]);
/// assert_eq!(plan["params"]["relations"]["near"]["sigma_m"], 0.3);
/// ```
///
/// # Errors
/// [`EvalError::Plan`] for an old key given beside its new one, naming both paths.
pub fn read_renamed_keys(plan: &mut Map<String, Value>) -> Result<Vec<(String, String)>, EvalError> {
    let mut renamed = Vec::new();
    for (old, new) in RENAMED_KEYS {
        let (parent, old_key) = old.rsplit_once('.').unwrap_or(("", old));
        let new_key = new.rsplit('.').next().unwrap_or(new);
        let segments: Vec<&str> = parent.split('.').filter(|s| !s.is_empty()).collect();
        rename_under(plan, &segments, "", (old_key, new_key), &mut renamed)?;
    }
    Ok(renamed)
}

/// Renames `old_key` to `new_key` in every object of `object` at `segments` (`*` any key),
/// `at` the path of `object`.
fn rename_under(
    object: &mut Map<String, Value>,
    segments: &[&str],
    at: &str,
    (old_key, new_key): (&str, &str),
    renamed: &mut Vec<(String, String)>,
) -> Result<(), EvalError> {
    let join = |key: &str| {
        if at.is_empty() {
            key.to_owned()
        } else {
            format!("{at}.{key}")
        }
    };
    let Some((first, rest)) = segments.split_first() else {
        let Some(value) = object.remove(old_key) else {
            return Ok(());
        };
        let (old, new) = (join(old_key), join(new_key));
        if object.contains_key(new_key) {
            return Err(plan_error(
                Some(&old),
                format!("given twice: as `{old}` and as `{new}` (its name now); remove `{old}`"),
            ));
        }
        tracing::warn!("plan: `{old}` is read as `{new}`: rename it");
        object.insert(new_key.to_owned(), value);
        renamed.push((old, new));
        return Ok(());
    };
    for (key, child) in object.iter_mut() {
        if (*first == "*" || first == key)
            && let Value::Object(child) = child
        {
            rename_under(child, rest, &join(key), (old_key, new_key), renamed)?;
        }
    }
    Ok(())
}

/// Reads `params.fidelity.matching` written as plans did before every choice was externally
/// tagged (`{"method": "labels"}`, `{"method": "file", "path": "m.json"}`) as the choice it
/// names (`"labels"`, `{"file": "m.json"}`), with a warning giving the new spelling. Anything
/// else is left for serde to read or refuse.
fn matching_as_choice(given: &mut Map<String, Value>) {
    let Some(Value::Object(params)) = given.get_mut("params") else {
        return;
    };
    let Some(Value::Object(fidelity)) = params.get_mut("fidelity") else {
        return;
    };
    let Some(Value::Object(old)) = fidelity.get("matching") else {
        return;
    };
    let new = match (
        old.get("method").and_then(Value::as_str),
        old.get("path"),
        old.len(),
    ) {
        (Some(method @ ("labels" | "vlm")), None, 1) => Value::String(method.to_owned()),
        (Some("file"), Some(path @ Value::String(_)), 2) => {
            Value::Object(Map::from_iter([("file".to_owned(), path.clone())]))
        }
        _ => return,
    };
    let old = Value::Object(old.clone());
    tracing::warn!("plan: `params.fidelity.matching` {old} is read as {new}: write it so");
    fidelity.insert("matching".to_owned(), new);
}

/// A merged plan (parameter sections under `params`) with those sections at the top level, as
/// [`PlanFields`] reads them.
fn sections_at_top(mut merged: Value) -> Value {
    if let Value::Object(plan) = &mut merged {
        let moved: Vec<(&str, Value)> = match plan.get_mut("params") {
            Some(Value::Object(params)) => PARAM_SECTIONS
                .iter()
                .filter_map(|&key| params.remove(key).map(|v| (key, v)))
                .collect(),
            _ => Vec::new(),
        };
        for (key, v) in moved {
            plan.insert(key.to_owned(), v);
        }
    }
    merged
}

/// The path a user wrote for the field at `path` of [`PlanFields`] (`stability.duration_s` is
/// `params.stability.duration_s`).
fn params_path(path: &str) -> String {
    match PARAM_SECTIONS
        .iter()
        .any(|k| path == *k || path.starts_with(&format!("{k}.")))
    {
        true => format!("params.{path}"),
        false => path.to_owned(),
    }
}

/// Replaces values of `base` by those of `over`, recursing into an object of `over` whose
/// keys all exist in `base`'s object (a struct given in part); any other object replaces the
/// base's whole (an enum switching variant, `{"pixels": 256}` to `{"m_per_pixel": 0.02}`).
fn merge(base: &mut Value, over: &Value) {
    match (base, over) {
        (Value::Object(b), Value::Object(o)) => {
            for (k, v) in o {
                match (b.get_mut(k), v) {
                    (Some(slot @ Value::Object(_)), Value::Object(vo))
                        if vo.keys().all(|key| slot.get(key).is_some()) =>
                    {
                        merge(slot, v)
                    }
                    _ => {
                        b.insert(k.clone(), v.clone());
                    }
                }
            }
        }
        (b, o) => *b = o.clone(),
    }
}

/// The path of the first key of `given` (in document order) that `back` lacks.
fn unknown_key(given: &Value, back: &Value, prefix: &str) -> Option<String> {
    let (Value::Object(g), Value::Object(b)) = (given, back) else {
        return None;
    };
    unknown_in(g, b, prefix)
}

fn unknown_in(g: &Map<String, Value>, b: &Map<String, Value>, prefix: &str) -> Option<String> {
    for (k, v) in g {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match b.get(k) {
            None => return Some(path),
            Some(w) => {
                if let Some(p) = unknown_key(v, w, &path) {
                    return Some(p);
                }
            }
        }
    }
    None
}

/// The path of the first value of `given` that is a list (a JSON array, a TOML array of
/// tables) where the plan has an object: serde would read a struct from a list by position,
/// and an object inside it would escape the unknown-field check.
fn list_for_object(given: &Value, back: &Value, path: &str) -> Option<String> {
    match (given, back) {
        (Value::Array(_), Value::Object(_)) => Some(path.to_owned()),
        (Value::Object(g), Value::Object(b)) => g.iter().find_map(|(k, v)| {
            let path = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            list_for_object(v, b.get(k)?, &path)
        }),
        _ => None,
    }
}

/// A TOML value as JSON, refusing what JSON cannot hold instead of letting it become `null`
/// (which would mean "no value": a `nan` time budget would be no budget): non-finite floats
/// and dates, each named by its path.
fn json_of_toml(value: toml::Value, path: &str) -> Result<Value, EvalError> {
    let at = |key: &str| {
        if path.is_empty() {
            key.to_owned()
        } else {
            format!("{path}.{key}")
        }
    };
    Ok(match value {
        toml::Value::String(s) => Value::String(s),
        toml::Value::Integer(i) => Value::from(i),
        toml::Value::Float(f) if f.is_finite() => Value::from(f),
        toml::Value::Float(f) => {
            return Err(plan_error(Some(path), format!("{f} is not a finite number")));
        }
        toml::Value::Boolean(b) => Value::Bool(b),
        toml::Value::Datetime(d) => {
            return Err(plan_error(
                Some(path),
                format!("a date ({d}) is not a plan value"),
            ));
        }
        toml::Value::Array(items) => Value::Array(
            items
                .into_iter()
                .enumerate()
                .map(|(i, v)| json_of_toml(v, &format!("{path}[{i}]")))
                .collect::<Result<_, _>>()?,
        ),
        toml::Value::Table(table) => Value::Object(
            table
                .into_iter()
                .map(|(k, v)| {
                    let value = json_of_toml(v, &at(&k))?;
                    Ok((k, value))
                })
                .collect::<Result<_, EvalError>>()?,
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field_of(text: &str) -> (Option<String>, String) {
        match EvaluationPlan::from_json_str(text) {
            Err(EvalError::Plan { field, message, .. }) => (field, message),
            other => panic!("{text}: {other:?}"),
        }
    }

    #[test]
    fn metric_names_round_trip() {
        for m in Metric::ALL {
            assert_eq!(m.name().parse::<Metric>().unwrap(), m);
            assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{}\"", m.name()));
        }
    }

    #[test]
    fn plan_validation() {
        assert!(EvaluationPlan::from_json_str(r#"{"metrics": []}"#).is_err());
        assert!(EvaluationPlan::from_json_str(r#"{"metrics": ["support", "support"]}"#).is_err());
        assert!(
            EvaluationPlan::from_json_str(r#"{"metric": ["support"]}"#).is_err(),
            "unknown field"
        );
        let all = EvaluationPlan::from_json_str("{}").unwrap();
        assert_eq!(all, EvaluationPlan::geometry_only());
        let back: EvaluationPlan = serde_json::from_str(&serde_json::to_string(&all).unwrap()).unwrap();
        assert_eq!(back, all);
    }

    #[test]
    fn every_metrics_parameters_are_under_params_and_the_old_places_still_read() {
        let new = EvaluationPlan::from_json_str(
            r#"{"metrics": ["collision", "oor"],
                "params": {"stability": {"duration_s": 2.5}, "fidelity": {"size_aware_matching": true},
                           "relations": {"threshold": 0.4}, "collision": {"contact_tolerance_m": 0.01}}}"#,
        )
        .unwrap();
        assert_eq!(new.stability.duration_s, 2.5);
        assert!(new.fidelity.size_aware_matching);
        assert_eq!(new.relations.threshold, 0.4);
        assert_eq!(new.params.collision.contact_tolerance_m, 0.01);
        // The same plan written as before: the sections at the top level (a warning is logged).
        let old = EvaluationPlan::from_json_str(
            r#"{"metrics": ["collision", "oor"], "stability": {"duration_s": 2.5},
                "fidelity": {"size_aware_matching": true}, "relations": {"threshold": 0.4},
                "params": {"collision": {"contact_tolerance_m": 0.01}}}"#,
        )
        .unwrap();
        assert_eq!(old, new);
        assert_eq!(old.result_digest(), new.result_digest());
        // Written in the new places, read back the same.
        let value = serde_json::to_value(&new).unwrap();
        assert!(value.get("stability").is_none() && value.get("fidelity").is_none());
        assert_eq!(value["params"]["stability"]["duration_s"], 2.5);
        assert_eq!(value["params"]["relations"]["threshold"], 0.4);
        assert_eq!(value["params"]["collision"]["contact_tolerance_m"], 0.01);
        let back: EvaluationPlan = serde_json::from_value(value).unwrap();
        assert_eq!(back, new);
        // Both places at once is an error; errors name the new place.
        let (field, message) =
            field_of(r#"{"stability": {"duration_s": 1}, "params": {"stability": {"duration_s": 2}}}"#);
        assert_eq!(field.as_deref(), Some("stability"));
        assert!(message.contains("params.stability"), "{message}");
        for (text, path) in [
            (
                r#"{"params": {"stability": {"duration": 1}}}"#,
                "params.stability.duration",
            ),
            (r#"{"stability": {"duration": 1}}"#, "params.stability.duration"),
            (
                r#"{"params": {"stability": {"duration_s": "long"}}}"#,
                "params.stability.duration_s",
            ),
            (
                r#"{"params": {"stability": {"duration_s": -1}}}"#,
                "params.stability.duration_s",
            ),
            (
                r#"{"params": {"fidelity": {"matchng": "vlm"}}}"#,
                "params.fidelity.matchng",
            ),
        ] {
            assert_eq!(field_of(text).0.as_deref(), Some(path), "{text}");
        }
    }

    #[test]
    fn unknown_fields_are_named_at_every_depth() {
        for (text, path) in [
            (r#"{"metric": []}"#, "metric"),
            (
                r#"{"params": {"collision": {"exclude_floor_covering": true}}}"#,
                "params.collision.exclude_floor_covering",
            ),
            (r#"{"params": {"colision": {}}}"#, "params.colision"),
            (
                r#"{"params": {"navigability": {"resolution": {"pixels": 64}, "robot_widht": 0.3}}}"#,
                "params.navigability.robot_widht",
            ),
            (r#"{"limits": {"max_triangle": 5}}"#, "limits.max_triangle"),
            (r#"{"read": {"architecture": "file_only", "x": 1}}"#, "read.x"),
            (r#"{"relations": {"thresold": 0.4}}"#, "params.relations.thresold"),
        ] {
            let (field, message) = field_of(text);
            assert_eq!(field.as_deref(), Some(path), "{text}: {message}");
        }
    }

    #[test]
    fn wrong_types_and_impossible_values_are_named() {
        for (text, path, words) in [
            (
                r#"{"params": {"collision": {"contact_tolerance_m": "x"}}}"#,
                "params.collision.contact_tolerance_m",
                "invalid type",
            ),
            (
                r#"{"params": {"collision": {"contact_tolerance_m": -0.1}}}"#,
                "params.collision.contact_tolerance_m",
                "non-negative",
            ),
            (
                r#"{"params": {"navigability": {"resolution": {"pixels": 0}}}}"#,
                "params.navigability.resolution",
                "at least one pixel",
            ),
            (
                r#"{"params": {"navigability": {"resolution": {"pixels": 100000}}}}"#,
                "params.navigability.resolution",
                "exceeds the limit",
            ),
            (
                r#"{"params": {"navigability": {"resolution": {"metres_per_pixel": 0}}}}"#,
                "params.navigability.resolution",
                "positive",
            ),
            (r#"{"time_budget_s": -1}"#, "time_budget_s", "positive"),
            (
                r#"{"limits": {"max_triangles": 0}}"#,
                "limits.max_triangles",
                "at least 1",
            ),
            (
                r#"{"metrics": ["physics"]}"#,
                "metrics[0]",
                "unknown metric \"physics\"",
            ),
            (r#"{"preset": "paper"}"#, "preset", "unknown preset"),
            (
                r#"{"read": {"simple_wall_height_m": -3}}"#,
                "read.simple_wall_height_m",
                "positive",
            ),
        ] {
            let (field, message) = field_of(text);
            assert_eq!(field.as_deref(), Some(path), "{text}: {message}");
            assert!(message.contains(words), "{text}: {message}");
        }
        let e = EvaluationPlan::from_json_str("{\n  \"metrics\": [\n}").unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
        assert!(EvaluationPlan::from_json_str("[1]").is_err());
    }

    /// "No budget" is `0` in a plan file (JSON or TOML, which has no `null`) as on the command
    /// line and in Python; JSON's `null` is read too; both are the same plan.
    #[test]
    fn no_budget_is_zero_in_every_plan_file() {
        let json = EvaluationPlan::from_json_str(r#"{"time_budget_s": 0}"#).unwrap();
        let toml = EvaluationPlan::from_toml_str("time_budget_s = 0").unwrap();
        let null = EvaluationPlan::from_json_str(r#"{"time_budget_s": null}"#).unwrap();
        for plan in [&json, &toml, &null] {
            assert_eq!(plan.time_budget_s, None);
            assert!(plan.deadline().budget().is_none());
        }
        assert_eq!(json, toml);
        assert_eq!(json, null);
        let budget = EvaluationPlan::from_toml_str("time_budget_s = 30").unwrap();
        assert_eq!(budget.time_budget_s, Some(30.0));
    }

    #[test]
    fn stability_parameters_are_read_checked_and_digested() {
        use sceneeval_physics::{MassModel, WeldMode};
        let plan = EvaluationPlan::from_json_str(
            r#"{"metrics": ["STAB"], "stability": {"weld": "combined", "mass": {"per_object_kg": 1.0}}}"#,
        )
        .unwrap();
        assert_eq!(plan.ordered_metrics(), vec![Metric::Stability]);
        assert_eq!(plan.stability.weld, WeldMode::Combined);
        assert_eq!(plan.stability.mass, MassModel::PerObject(1.0));
        assert_eq!(plan.stability.duration_s, 5.0, "the rest stays the default");
        let toml = EvaluationPlan::from_toml_str(
            "metrics = [\"stability\"]\n[stability]\nweld = \"combined\"\n[stability.mass]\nper_object_kg = 1.0\n",
        )
        .unwrap();
        assert_eq!(toml, plan);
        for (text, path, words) in [
            (
                r#"{"stability": {"weld": "glued"}}"#,
                "params.stability.weld",
                "unknown variant",
            ),
            (
                r#"{"stability": {"duration_s": 0}}"#,
                "params.stability.duration_s",
                "(0, 60]",
            ),
            (
                r#"{"stability": {"time_step_s": 0.5}}"#,
                "params.stability.time_step_s",
                "[0.0001, 0.02]",
            ),
            (
                r#"{"stability": {"duraton_s": 1}}"#,
                "params.stability.duraton_s",
                "unknown field",
            ),
            (
                r#"{"stability": {"decomposition": {"resolution": 4}}}"#,
                "params.stability.decomposition.resolution",
                "[8, 128]",
            ),
            (
                r#"{"stability": {"mass": {"density_kg_m3": -1}}}"#,
                "params.stability.mass.density_kg_m3",
                "must lie in",
            ),
        ] {
            let (field, message) = field_of(text);
            assert_eq!(field.as_deref(), Some(path), "{text}: {message}");
            assert!(message.contains(words), "{text}: {message}");
        }
        // The stability parameters enter the digest only when the metric runs, so the
        // digests of plans without it are unchanged.
        let mut a = EvaluationPlan::geometry_only();
        let d = a.result_digest();
        a.stability.weld = WeldMode::None;
        assert_eq!(a.result_digest(), d);
        a.metrics.push(Metric::Stability);
        let with = a.result_digest();
        assert_ne!(with, d);
        a.stability.weld = WeldMode::Combined;
        assert_ne!(a.result_digest(), with);
        // The paper's ten metrics do not include it.
        assert!(!EvaluationPlan::full(Preset::Default).runs(Metric::Stability));
    }

    #[test]
    fn presets_start_the_parameters_and_the_file_overrides_them() {
        let r = EvaluationPlan::from_json_str(r#"{"preset": "reference"}"#).unwrap();
        assert_eq!(r, EvaluationPlan::reference());
        assert_eq!(r.relations, RelationParams::reference());
        assert!(!r.params.collision.exclude_floor_coverings);
        assert_eq!(r.params.navigability.footprint, Footprint::BoundingBox);
        assert_eq!(r.params.accessibility.footprint, Footprint::BoundingBox);
        let d = EvaluationPlan::geometry_only();
        assert_eq!(d.params.navigability.footprint, Footprint::ConvexHull);
        let r = EvaluationPlan::from_json_str_with_preset(
            r#"{"preset": "default", "params": {"collision": {"exclude_floor_coverings": true}}}"#,
            Some(Preset::Reference),
        )
        .unwrap();
        assert_eq!(r.preset, Preset::Reference, "the command line wins");
        assert!(
            r.params.collision.exclude_floor_coverings,
            "the file's explicit value wins"
        );
        assert_eq!(r.relations, RelationParams::reference());
        // The result digest ignores the preset's name, limits and budget, not parameters.
        let mut a = EvaluationPlan::geometry_only();
        let d = a.result_digest();
        a.time_budget_s = None;
        a.limits.max_triangles = 7;
        a.preset = Preset::Reference;
        assert_eq!(a.result_digest(), d);
        a.params.support.lift_m = 0.004;
        assert_ne!(a.result_digest(), d);
        let m = EvaluationPlan::from_json_str(
            r#"{"params": {"navigability": {"resolution": {"metres_per_pixel": 0.02}}}}"#,
        )
        .unwrap();
        assert_eq!(
            m.params.navigability.resolution,
            sceneeval_plausibility::Resolution::MetresPerPixel(0.02)
        );
        assert_eq!(
            m.params.navigability.robot_width_m, 0.2,
            "the rest of the struct stays"
        );
        let mut b = EvaluationPlan::geometry_only();
        b.metrics.reverse();
        assert_eq!(b.result_digest(), d, "metrics are a set");
    }

    /// The value at `path` (dot-separated) of `value`, when there is one.
    fn at<'v>(value: &'v Value, path: &str) -> Option<&'v Value> {
        path.split('.').try_fold(value, |v, key| v.get(key))
    }

    /// `value` with `leaf` set at `path` (objects made on the way).
    fn with(mut value: Value, path: &str, leaf: Value) -> Value {
        let mut slot = &mut value;
        for key in path.split('.') {
            if !slot.is_object() {
                *slot = Value::Object(Map::new());
            }
            slot = slot.as_object_mut().unwrap().entry(key).or_insert(Value::Null);
        }
        *slot = leaf;
        value
    }

    /// Every row of [`RENAMED_KEYS`] (`*` made each distance band): a plan giving the old key
    /// reads equal to the plan giving the new one, which differs from the default (so the value
    /// was read, not dropped), in JSON and in TOML; giving both is an error naming both paths.
    #[test]
    fn every_renamed_key_reads_as_its_new_name_and_both_is_an_error() {
        let default = EvaluationPlan::geometry_only();
        let written = serde_json::to_value(&default).unwrap();
        let bands: Vec<&String> = written["params"]["relations"]
            .as_object()
            .unwrap()
            .iter()
            .filter(|(_, v)| v.is_object())
            .map(|(k, _)| k)
            .collect();
        assert_eq!(bands.len(), 12, "{bands:?}");
        let mut rows = Vec::new();
        for (old, new) in RENAMED_KEYS {
            assert_eq!(
                old.rsplit_once('.').map(|p| p.0),
                new.rsplit_once('.').map(|p| p.0),
                "{old} -> {new} renames its last key in place"
            );
            if old.contains('*') {
                rows.extend(bands.iter().map(|b| (old.replace('*', b), new.replace('*', b))));
            } else {
                rows.push((old.to_string(), new.to_string()));
            }
        }
        assert_eq!(rows.len(), RENAMED_KEYS.len() - 3 + 3 * 12);
        for (old, new) in &rows {
            assert!(at(&written, old).is_none(), "{old} is no longer written");
            // A value other than the default: half again the default's, or one of the variant
            // the default does not use.
            let value = match at(&written, new).map(|v| (v.is_null(), v.as_f64())) {
                Some((_, Some(v))) if v != 0.0 => v * 1.5,
                // A band's lower end, below every band's upper end.
                Some((_, Some(_))) => 0.001,
                // The unbounded upper end of `far`, `arch_far`.
                Some((true, None)) => 10.0,
                None if new.ends_with("m_per_pixel") => 0.05,
                None if new.ends_with("per_object_kg") => 2.0,
                _ => panic!("{new}: not a number of the default plan"),
            };
            let plan = |path: &str| with(serde_json::json!({}), path, Value::from(value));
            let (by_old, by_new) = (plan(old), plan(new));
            let read = |v: &Value| EvaluationPlan::from_json_str(&v.to_string());
            let (a, b) = (read(&by_old).unwrap(), read(&by_new).unwrap());
            assert_eq!(a, b, "{old} -> {new}");
            assert_ne!(b, default, "{new} = {value} was read");
            let toml = EvaluationPlan::from_toml_str(&format!("{old} = {value:?}\n")).unwrap();
            assert_eq!(toml, b, "{old} in TOML");
            let both = with(by_old.clone(), new, Value::from(value));
            match read(&both) {
                Err(EvalError::Plan { field, message, .. }) => {
                    assert_eq!(field.as_deref(), Some(old.as_str()));
                    assert!(
                        message.contains(&format!("`{old}`")) && message.contains(&format!("`{new}`")),
                        "{message}"
                    );
                }
                other => panic!("{old} and {new} both given: {other:?}"),
            }
        }
        // The old top-level sections (their own warning) with old keys inside.
        let old = EvaluationPlan::from_json_str(
            r#"{"relations": {"near": {"min": 0.4}, "tolerance": 1e-5}, "time_budget_seconds": 30,
                "stability": {"mass": {"density": 500}}}"#,
        )
        .unwrap();
        let new = EvaluationPlan::from_json_str(
            r#"{"params": {"relations": {"near": {"min_m": 0.4}, "tolerance_m": 1e-5},
                           "stability": {"mass": {"density_kg_m3": 500}}}, "time_budget_s": 30}"#,
        )
        .unwrap();
        assert_eq!(old, new);
        assert_eq!(new.relations.near.min_m, 0.4);
        assert_eq!(new.relations.near.max_m, 1.5, "the band's other ends stay");
        assert_eq!(new.relations.tolerance_m, 1e-5);
        assert_eq!(new.time_budget_s, Some(30.0));
        assert_eq!(new.stability.mass, sceneeval_physics::MassModel::Density(500.0));
    }

    /// `matching` is externally tagged as every choice of a plan; the internally tagged form of
    /// earlier plans (`{"method": ...}`) reads the same.
    #[test]
    fn matching_is_externally_tagged_and_the_method_form_still_reads() {
        use sceneeval_fidelity::MatchingMethod;
        let read = |m: &str| {
            EvaluationPlan::from_json_str(&format!(r#"{{"params": {{"fidelity": {{"matching": {m}}}}}}}"#))
                .map(|p| p.fidelity.matching)
        };
        let file = MatchingMethod::File("runs/a".into());
        for (new, old, method) in [
            (r#""labels""#, r#"{"method": "labels"}"#, MatchingMethod::Labels),
            (r#""vlm""#, r#"{"method": "vlm"}"#, MatchingMethod::Vlm),
            (
                r#"{"file": "runs/a"}"#,
                r#"{"method": "file", "path": "runs/a"}"#,
                file.clone(),
            ),
        ] {
            assert_eq!(read(new).unwrap(), method, "{new}");
            assert_eq!(read(old).unwrap(), method, "{old}");
        }
        // Written externally tagged.
        let mut plan = EvaluationPlan::full(Preset::Default);
        plan.fidelity.matching = file.clone();
        let value = serde_json::to_value(&plan).unwrap();
        assert_eq!(
            value["params"]["fidelity"]["matching"],
            serde_json::json!({"file": "runs/a"})
        );
        assert_eq!(serde_json::from_value::<EvaluationPlan>(value).unwrap(), plan);
        // TOML, old and new.
        let toml = EvaluationPlan::from_toml_str("[params.fidelity.matching]\nfile = \"runs/a\"\n").unwrap();
        assert_eq!(toml.fidelity.matching, file);
        let toml =
            EvaluationPlan::from_toml_str("[fidelity.matching]\nmethod = \"file\"\npath = \"runs/a\"\n")
                .unwrap();
        assert_eq!(toml.fidelity.matching, file);
        // Neither form: named by serde.
        for bad in [
            r#"{"method": "file"}"#,
            r#"{"method": "labels", "path": "x"}"#,
            r#""files""#,
            r#"{"file": 3}"#,
        ] {
            match EvaluationPlan::from_json_str(&format!(
                r#"{{"params": {{"fidelity": {{"matching": {bad}}}}}}}"#
            )) {
                Err(EvalError::Plan { field, .. }) => {
                    assert!(field.unwrap().starts_with("params.fidelity.matching"), "{bad}")
                }
                other => panic!("{bad}: {other:?}"),
            }
        }
    }
}
