//! [`SceneTiming`]: the wall times of one scene, `<scene>/timing.json`.

use sceneeval_plausibility::MetricTiming;
use serde::{Deserialize, Serialize};

/// The schema of a scene's `timing.json`.
pub const TIMING_SCHEMA: &str = "sceneeval.timing/1";

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
    /// The fidelity metrics together (matching, renders and VLM requests included), seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fidelity_seconds: Option<f64>,
    /// The stability metric (decomposition and simulation), seconds, when it ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stability_seconds: Option<f64>,
    /// The whole scene, seconds.
    pub total_seconds: f64,
}
