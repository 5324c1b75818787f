//! [`EnsembleVotes`]: what an ensemble of runs (`sceneeval ensemble`) records per scene in
//! `eval.json`: the runs, each spec's votes, and where the runs' geometry metrics differ.

use serde::{Deserialize, Serialize};

use sceneeval_fidelity::FidelityMetric;

use crate::Metric;

/// The `ensemble` section of a scene report made by an ensemble: each spec's verdict there
/// is the majority of the `votes` (a tie, or no verdict at all: `null`, unanswered).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EnsembleVotes {
    /// The source runs' names, in vote order (the order they were given).
    pub runs: Vec<String>,
    /// CNT: per spec (in the order of the report's `fidelity.cnt.specs`), one vote per run
    /// (`null`: that run has no verdict for it).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cnt: Vec<Vec<Option<bool>>>,
    /// ATR, as `cnt`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub atr: Vec<Vec<Option<bool>>>,
    /// OOR, as `cnt`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub oor: Vec<Vec<Option<bool>>>,
    /// OAR, as `cnt`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub oar: Vec<Vec<Option<bool>>>,
    /// The geometry metrics whose result in another run differs from the first run's (the
    /// one reported): support types and functional sides answered by different judges.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub geometry_differences: Vec<GeometryDifference>,
}

/// A geometry metric whose result in one source run differs from the first run's.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct GeometryDifference {
    /// The metric.
    pub metric: Metric,
    /// The run whose result differs (its name).
    pub run: String,
    /// How: the scene values of both runs, or the objects whose values differ.
    pub detail: String,
}

impl EnsembleVotes {
    /// The votes of `metric`'s specs.
    pub fn votes(&self, metric: FidelityMetric) -> &[Vec<Option<bool>>] {
        match metric {
            FidelityMetric::Cnt => &self.cnt,
            FidelityMetric::Atr => &self.atr,
            FidelityMetric::Oor => &self.oor,
            FidelityMetric::Oar => &self.oar,
        }
    }

    /// The votes of `metric`'s specs, to fill in.
    pub fn votes_mut(&mut self, metric: FidelityMetric) -> &mut Vec<Vec<Option<bool>>> {
        match metric {
            FidelityMetric::Cnt => &mut self.cnt,
            FidelityMetric::Atr => &mut self.atr,
            FidelityMetric::Oor => &mut self.oor,
            FidelityMetric::Oar => &mut self.oar,
        }
    }
}
