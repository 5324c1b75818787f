//! What a run evaluates, as a front end names it: `sceneeval evaluate --plan
//! geometry|full|LIST|FILE` with `--preset`, `--metrics`, `--time-budget`, `--matching` and
//! `--relation-mapping`, or the same keywords of the Python package's `sceneeval.evaluate`. One
//! reading of those choices for both, so that they accept the same plans and behave the same:
//! [`PlanSpec`] tells the four spellings of a plan apart, and [`PlanChoice::resolve`] turns
//! every choice into the [`EvaluationPlan`] to run, including the downgrade of a run without a
//! VLM (object matching by labels, relations mapped by the lexicon).
//!
//! ```
//! use sceneeval::{Metric, PlanChoice, Preset};
//! let mut choice = PlanChoice::new(PlanChoice::CLI);
//! choice.plan = Some("collision,out_of_bounds");
//! choice.preset = Some(Preset::Reference);
//! let chosen = choice.resolve().unwrap();
//! assert_eq!(chosen.plan.metrics, vec![Metric::Collision, Metric::OutOfBounds]);
//! assert_eq!(chosen.plan.preset, Preset::Reference);
//! assert!(chosen.fallback.is_none());
//! ```

use std::fmt;
use std::path::{Path, PathBuf};

use crate::fidelity::{MatchingMethod, RelationMapping};
use crate::{EvalError, EvaluationPlan, Metric, Preset};

/// A plan as named on the command line or from Python.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PlanSpec {
    /// `geometry`, or no plan given: the six geometry metrics.
    Geometry,
    /// `full`: the paper's ten metrics (the geometry metrics and CNT, ATR, OOR, OAR).
    Full,
    /// The path of an existing plan file (JSON, or TOML when it ends in `.toml`).
    File(PathBuf),
    /// Anything else: a comma-separated list of metric names (`collision,cnt,oor`).
    Metrics(String),
}

impl PlanSpec {
    /// The plan named by `spec` (surrounding white space ignored): `geometry` (also for
    /// `None`), `full`, an existing file, else a metric list. A file named `geometry` or
    /// `full` in the working folder is not read: those words always mean the built-in plans.
    ///
    /// ```
    /// use sceneeval::PlanSpec;
    /// assert_eq!(PlanSpec::parse(None), PlanSpec::Geometry);
    /// assert_eq!(PlanSpec::parse(Some(" full ")), PlanSpec::Full);
    /// assert_eq!(PlanSpec::parse(Some("cnt,oor")), PlanSpec::Metrics("cnt,oor".into()));
    /// ```
    pub fn parse(spec: Option<&str>) -> PlanSpec {
        match spec.map(str::trim) {
            None | Some("geometry") => PlanSpec::Geometry,
            Some("full") => PlanSpec::Full,
            Some(p) if Path::new(p).is_file() => PlanSpec::File(PathBuf::from(p)),
            Some(list) => PlanSpec::Metrics(list.to_owned()),
        }
    }

    /// The plan, its parameters starting from `preset` (for a file: replacing the file's
    /// `preset` when given; its explicit values still apply on top).
    ///
    /// # Errors
    /// As [`EvaluationPlan::read_with_preset`] for a file; for a metric list,
    /// [`EvalError::Choice`] saying the text is none of the four spellings, caused by the
    /// [`EvalError::Plan`] naming the unknown metric. `option` names the plan's option in
    /// that message (`--plan`, `plan`).
    pub fn plan(&self, preset: Option<Preset>, option: &str) -> Result<EvaluationPlan, EvalError> {
        let base = preset.unwrap_or_default();
        match self {
            PlanSpec::Geometry => Ok(EvaluationPlan::with_preset(base)),
            PlanSpec::Full => Ok(EvaluationPlan::full(base)),
            PlanSpec::File(path) => EvaluationPlan::read_with_preset(path, preset),
            PlanSpec::Metrics(list) => {
                EvaluationPlan::from_metric_list(list, base).map_err(|e| EvalError::Choice {
                    message: format!(
                        "{option} {list:?} is not geometry, full, a metric list or an existing file"
                    ),
                    source: Some(Box::new(e)),
                })
            }
        }
    }
}

/// The names under which a front end offers the choices of a [`PlanChoice`], so that its
/// error messages name what its user typed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OptionNames {
    /// The plan (`--plan`).
    pub plan: &'static str,
    /// The annotation file (`--annotations`).
    pub annotations: &'static str,
    /// The relation mapping (`--relation-mapping`).
    pub relation_mapping: &'static str,
}

/// Every choice a run makes about what to evaluate (see the module docs). The fields left
/// `None` keep the plan's own values.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanChoice<'a> {
    /// `geometry` (the default), `full`, a metric list or a plan file ([`PlanSpec::parse`]).
    pub plan: Option<&'a str>,
    /// The parameter preset; replaces a plan file's `preset`.
    pub preset: Option<Preset>,
    /// The metrics to run, replacing the plan's geometry metrics.
    pub metrics: Option<Vec<Metric>>,
    /// The wall-time budget per scene in seconds; 0 means no budget.
    pub time_budget_seconds: Option<f64>,
    /// Object matching: `vlm`, `labels`, or a matching file or folder (used only when the
    /// plan runs fidelity metrics).
    pub matching: Option<&'a str>,
    /// Relation mapping: `vlm` or `lexicon` (used only when the plan runs fidelity metrics).
    pub relation_mapping: Option<&'a str>,
    /// Whether a VLM will answer the fidelity metrics' questions. Without one, matching falls
    /// back to labels and relation mapping to the lexicon whatever was chosen, and
    /// [`ChosenPlan::fallback`] says so.
    pub vlm_configured: bool,
    /// Whether the run has annotation rows (the fidelity metrics need them).
    pub annotations: bool,
    /// How the front end names its options in errors.
    pub names: OptionNames,
}

/// The plan a [`PlanChoice`] resolves to.
#[derive(Debug, Clone, PartialEq)]
pub struct ChosenPlan {
    /// The plan to run.
    pub plan: EvaluationPlan,
    /// Present when the plan runs fidelity metrics without a VLM: what they run with instead.
    pub fallback: Option<NoVlmFallback>,
}

/// How the fidelity metrics run without a VLM. Its `Display` is the sentence the CLI prints
/// after "note: no VLM configured (...): ".
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
            MatchingMethod::File { path } => {
                write!(f, "fidelity runs with matching from {}", path.display())?
            }
            other => write!(f, "fidelity runs with {other} matching")?,
        }
        write!(f, " and the {} relation mapping", self.relation_mapping)?;
        if !self.replaced.is_empty() {
            write!(f, " ({} instead of the VLM)", self.replaced.join(", "))?;
        }
        f.write_str("; ATR is not judged.")
    }
}

impl<'a> PlanChoice<'a> {
    /// The option names of `sceneeval evaluate`.
    pub const CLI: OptionNames = OptionNames {
        plan: "--plan",
        annotations: "--annotations",
        relation_mapping: "--relation-mapping",
    };

    /// The keyword names of the Python package's `sceneeval.evaluate`.
    pub const PYTHON: OptionNames = OptionNames {
        plan: "plan",
        annotations: "annotations",
        relation_mapping: "relation_mapping",
    };

    /// No choice made (the geometry plan with the default preset, no VLM, no annotations),
    /// with errors naming the options as `names` does.
    pub fn new(names: OptionNames) -> Self {
        PlanChoice {
            plan: None,
            preset: None,
            metrics: None,
            time_budget_seconds: None,
            matching: None,
            relation_mapping: None,
            vlm_configured: false,
            annotations: false,
            names,
        }
    }

    /// The plan to run: [`PlanSpec::plan`] of `plan` with `preset`, then `metrics` and the
    /// time budget applied; when it runs fidelity metrics, the matching and relation mapping
    /// chosen (the VLM by default when one is configured), then, without a VLM, labels and the
    /// lexicon in place of the VLM. The plan is not validated again ([`crate::Evaluator::new`]
    /// does).
    ///
    /// ```
    /// use sceneeval::PlanChoice;
    /// use sceneeval::fidelity::{MatchingMethod, RelationMapping};
    /// let mut choice = PlanChoice::new(PlanChoice::PYTHON);
    /// choice.plan = Some("full");
    /// choice.relation_mapping = Some("vlm");
    /// choice.annotations = true;
    /// let chosen = choice.resolve().unwrap();
    /// assert_eq!(chosen.plan.fidelity.relation_mapping, RelationMapping::Lexicon);
    /// let note = chosen.fallback.unwrap().to_string();
    /// assert_eq!(note, "fidelity runs with labels matching and the lexicon relation mapping \
    ///                   (relations mapped by the lexicon instead of the VLM); ATR is not judged.");
    /// choice.annotations = false;
    /// assert!(choice.resolve().unwrap_err().to_string().contains("which need annotations"));
    /// ```
    ///
    /// # Errors
    /// As [`PlanSpec::plan`]; [`EvalError::Choice`] when the plan runs fidelity metrics
    /// without annotations, or for a relation mapping other than `vlm` or `lexicon`.
    pub fn resolve(&self) -> Result<ChosenPlan, EvalError> {
        let names = &self.names;
        let mut plan = PlanSpec::parse(self.plan).plan(self.preset, names.plan)?;
        if let Some(metrics) = &self.metrics {
            plan.metrics.clone_from(metrics);
        }
        if let Some(b) = self.time_budget_seconds {
            plan.time_budget_seconds = (b != 0.0).then_some(b);
        }
        if !plan.has_fidelity() {
            return Ok(ChosenPlan { plan, fallback: None });
        }
        if !self.annotations {
            return Err(choice_error(format!(
                "the plan runs fidelity metrics (cnt, atr, oor, oar), which need {}",
                names.annotations
            )));
        }
        let vlm = self.vlm_configured;
        match self.matching {
            None if vlm => plan.fidelity.matching = MatchingMethod::Vlm,
            None => {}
            Some("vlm") => plan.fidelity.matching = MatchingMethod::Vlm,
            Some("labels") => plan.fidelity.matching = MatchingMethod::Labels,
            Some(path) => {
                plan.fidelity.matching = MatchingMethod::File {
                    path: PathBuf::from(path),
                }
            }
        }
        match self.relation_mapping {
            None if vlm => plan.fidelity.relation_mapping = RelationMapping::Vlm,
            None => {}
            Some("vlm") => plan.fidelity.relation_mapping = RelationMapping::Vlm,
            Some("lexicon") => plan.fidelity.relation_mapping = RelationMapping::Lexicon,
            Some(other) => {
                return Err(choice_error(format!(
                    "{} {other:?}: expected vlm or lexicon",
                    names.relation_mapping
                )));
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

fn choice_error(message: String) -> EvalError {
    EvalError::Choice {
        message,
        source: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fidelity::FidelityMetric;

    fn choice(plan: &str) -> PlanChoice<'_> {
        let mut c = PlanChoice::new(PlanChoice::CLI);
        c.plan = Some(plan);
        c.annotations = true;
        c
    }

    #[test]
    fn the_four_spellings_of_a_plan() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plan.toml");
        std::fs::write(&file, "preset = \"reference\"\nmetrics = [\"support\"]\n").unwrap();
        let path = file.to_str().unwrap();
        assert_eq!(PlanSpec::parse(Some(path)), PlanSpec::File(file.clone()));
        assert_eq!(PlanSpec::parse(Some("geometry")), PlanSpec::Geometry);
        // A missing file is read as a metric list, which then fails naming the text.
        let missing = dir.path().join("nope.json");
        let missing = missing.to_str().unwrap();
        assert_eq!(
            PlanSpec::parse(Some(missing)),
            PlanSpec::Metrics(missing.to_owned())
        );

        let geometry = choice("geometry").resolve().unwrap().plan;
        assert_eq!(geometry, EvaluationPlan::geometry_only());
        let full = choice("full").resolve().unwrap().plan;
        assert_eq!(full.fidelity_metrics, FidelityMetric::ALL.to_vec());
        let from_file = choice(path).resolve().unwrap().plan;
        assert_eq!(
            (from_file.preset, from_file.metrics),
            (Preset::Reference, vec![Metric::Support])
        );
        // --preset replaces the file's preset; its explicit values stay.
        let mut c = choice(path);
        c.preset = Some(Preset::Default);
        let replaced = c.resolve().unwrap().plan;
        assert_eq!(
            (replaced.preset, replaced.metrics),
            (Preset::Default, vec![Metric::Support])
        );
        let list = choice("navigability, cnt").resolve().unwrap().plan;
        assert_eq!(list.metrics, vec![Metric::Navigability]);
        assert_eq!(list.fidelity_metrics, vec![FidelityMetric::Cnt]);

        let err = choice("colision").resolve().unwrap_err();
        assert_eq!(
            err.to_string(),
            "--plan \"colision\" is not geometry, full, a metric list or an existing file"
        );
        let cause = std::error::Error::source(&err).unwrap().to_string();
        assert!(cause.contains("unknown metric \"colision\""), "{cause}");
        let mut py = PlanChoice::new(PlanChoice::PYTHON);
        py.plan = Some("refrence");
        assert!(
            py.resolve()
                .unwrap_err()
                .to_string()
                .starts_with("plan \"refrence\" is not")
        );
    }

    #[test]
    fn metrics_and_time_budget_override_the_plan() {
        let mut c = choice("geometry");
        c.metrics = Some(vec![Metric::Collision]);
        c.time_budget_seconds = Some(0.0);
        let plan = c.resolve().unwrap().plan;
        assert_eq!(plan.metrics, vec![Metric::Collision]);
        assert_eq!(plan.time_budget_seconds, None);
        c.time_budget_seconds = Some(30.0);
        assert_eq!(c.resolve().unwrap().plan.time_budget_seconds, Some(30.0));
    }

    #[test]
    fn fidelity_needs_annotations_and_falls_back_without_a_vlm() {
        let mut c = choice("full");
        c.annotations = false;
        assert_eq!(
            c.resolve().unwrap_err().to_string(),
            "the plan runs fidelity metrics (cnt, atr, oor, oar), which need --annotations"
        );
        // Geometry plans need no annotations.
        assert!(choice("collision").resolve().is_ok());

        // The default preset already matches by labels and maps by the lexicon: nothing is
        // replaced, but the run is still told that it has no VLM.
        let chosen = choice("full").resolve().unwrap();
        let fallback = chosen.fallback.unwrap();
        assert!(fallback.replaced.is_empty());
        assert_eq!(
            fallback.to_string(),
            "fidelity runs with labels matching and the lexicon relation mapping; ATR is not judged."
        );
        // A matching file is named as such.
        let mut c = choice("full");
        c.matching = Some("runs/matching");
        assert_eq!(
            c.resolve().unwrap().fallback.unwrap().to_string(),
            "fidelity runs with matching from runs/matching and the lexicon relation mapping; ATR is not judged."
        );
        // The reference preset asks the VLM for both: both are replaced.
        let mut c = choice("full");
        c.preset = Some(Preset::Reference);
        let chosen = c.resolve().unwrap();
        assert_eq!(chosen.plan.fidelity.matching, MatchingMethod::Labels);
        assert_eq!(chosen.plan.fidelity.relation_mapping, RelationMapping::Lexicon);
        assert_eq!(
            chosen.fallback.unwrap().replaced,
            vec!["matching by labels", "relations mapped by the lexicon"]
        );
        // With a VLM, the VLM is the default for both, and nothing falls back.
        let mut c = choice("full");
        c.vlm_configured = true;
        let chosen = c.resolve().unwrap();
        assert_eq!(chosen.plan.fidelity.matching, MatchingMethod::Vlm);
        assert_eq!(chosen.plan.fidelity.relation_mapping, RelationMapping::Vlm);
        assert!(chosen.fallback.is_none());
        // A matching file is kept without a VLM.
        let mut c = choice("full");
        c.matching = Some("results/matching.json");
        let chosen = c.resolve().unwrap();
        assert_eq!(
            chosen.plan.fidelity.matching,
            MatchingMethod::File {
                path: PathBuf::from("results/matching.json")
            }
        );
        let mut c = choice("full");
        c.relation_mapping = Some("dictionary");
        assert_eq!(
            c.resolve().unwrap_err().to_string(),
            "--relation-mapping \"dictionary\": expected vlm or lexicon"
        );
    }
}
