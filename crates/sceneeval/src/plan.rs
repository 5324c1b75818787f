use std::fmt;
use std::path::Path;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::EvalError;
use crate::plausibility::PlausibilityParams;

/// A metric an evaluation plan can run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    /// Object collision (COL_ob, COL_sc).
    Collision,
    /// Object support (SUP).
    Support,
    /// Scene navigability (NAV).
    Navigability,
    /// Accessibility of functional sides (ACC).
    Accessibility,
    /// Objects out of bounds (OOB).
    OutOfBounds,
    /// Door and window clearance (reference v1.1).
    OpeningClearance,
}

impl Metric {
    /// Every geometry-only metric, in the order they run and are reported.
    pub const GEOMETRY_ONLY: [Metric; 6] = [
        Metric::Collision,
        Metric::Support,
        Metric::Navigability,
        Metric::Accessibility,
        Metric::OutOfBounds,
        Metric::OpeningClearance,
    ];

    /// The snake-case name used in plan files and on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            Metric::Collision => "collision",
            Metric::Support => "support",
            Metric::Navigability => "navigability",
            Metric::Accessibility => "accessibility",
            Metric::OutOfBounds => "out_of_bounds",
            Metric::OpeningClearance => "opening_clearance",
        }
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Metric {
    type Err = EvalError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        Metric::GEOMETRY_ONLY
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| EvalError::UnknownMetric(s.to_owned()))
    }
}

/// What to evaluate and with which parameters.
///
/// The default plan runs every geometry-only metric with the reference's parameters. A plan can be
/// read from JSON; missing fields take their defaults, unknown fields are rejected:
///
/// ```
/// use sceneeval::{EvaluationPlan, Metric};
///
/// let plan = EvaluationPlan::from_json_str(r#"{
///     "metrics": ["collision", "navigability"],
///     "params": { "collision": { "contact_tolerance": 0.01 } }
/// }"#).unwrap();
/// assert_eq!(plan.metrics, vec![Metric::Collision, Metric::Navigability]);
/// assert_eq!(plan.params.collision.contact_tolerance, 0.01);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EvaluationPlan {
    /// The metrics to run, without repeats. They always run and are reported in the order of
    /// [`Metric::GEOMETRY_ONLY`].
    pub metrics: Vec<Metric>,
    /// Parameters of the plausibility metrics.
    pub params: PlausibilityParams,
}

impl Default for EvaluationPlan {
    fn default() -> Self {
        EvaluationPlan::geometry_only()
    }
}

impl EvaluationPlan {
    /// Every geometry-only metric with default parameters: the plan that needs no VLM.
    pub fn geometry_only() -> Self {
        EvaluationPlan {
            metrics: Metric::GEOMETRY_ONLY.to_vec(),
            params: PlausibilityParams::default(),
        }
    }

    /// A plan from JSON text.
    pub fn from_json_str(text: &str) -> Result<Self, EvalError> {
        let plan: EvaluationPlan = serde_json::from_str(text).map_err(|e| EvalError::Plan {
            path: None,
            message: e.to_string(),
        })?;
        plan.validate()?;
        Ok(plan)
    }

    /// A plan from a JSON file.
    pub fn read(path: &Path) -> Result<Self, EvalError> {
        let text = std::fs::read_to_string(path).map_err(|e| EvalError::Plan {
            path: Some(path.to_owned()),
            message: e.to_string(),
        })?;
        Self::from_json_str(&text).map_err(|e| match e {
            EvalError::Plan { message, .. } => EvalError::Plan {
                path: Some(path.to_owned()),
                message,
            },
            other => other,
        })
    }

    /// Checks that at least one metric is listed and none twice.
    pub fn validate(&self) -> Result<(), EvalError> {
        if self.metrics.is_empty() {
            return Err(EvalError::Plan {
                path: None,
                message: "the plan lists no metric".into(),
            });
        }
        for (i, m) in self.metrics.iter().enumerate() {
            if self.metrics[..i].contains(m) {
                return Err(EvalError::Plan {
                    path: None,
                    message: format!("metric {m} is listed twice"),
                });
            }
        }
        Ok(())
    }

    /// Whether the plan runs `metric`.
    #[inline]
    pub fn runs(&self, metric: Metric) -> bool {
        self.metrics.contains(&metric)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metric_names_round_trip() {
        for m in Metric::GEOMETRY_ONLY {
            assert_eq!(m.name().parse::<Metric>().unwrap(), m);
            assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{}\"", m.name()));
        }
        assert!(matches!(
            "physics".parse::<Metric>(),
            Err(EvalError::UnknownMetric(_))
        ));
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
}
