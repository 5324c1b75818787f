//! [`Preset`]: the named starting points of an evaluation plan's parameters.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// A named starting point for an evaluation plan's parameters; a plan file's explicit values
/// are applied on top of it (`sceneeval_eval::EvaluationPlan`). Recorded in every result's
/// fingerprint and in `summary.md`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// This implementation's defaults: the reference's parameters with its quirks fixed
    /// (floor coverings are not obstacles, the paper's predicate definitions, ...).
    #[default]
    Default,
    /// Every switch that reproduces the authors' reference implementation where it differs
    /// (`sceneeval_eval::EvaluationPlan::reference`), for comparisons with published numbers.
    Reference,
}

impl Preset {
    /// Every preset.
    pub const ALL: [Preset; 2] = [Preset::Default, Preset::Reference];

    /// The name used in plan files, on the command line and in `summary.md`.
    pub const fn name(self) -> &'static str {
        match self {
            Preset::Default => "default",
            Preset::Reference => "reference",
        }
    }
}

impl fmt::Display for Preset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Preset {
    type Err = UnknownPreset;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Preset::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownPreset(s.to_owned()))
    }
}

/// A preset name that names no preset.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown preset {0:?} (expected default or reference)")]
pub struct UnknownPreset(pub String);
