//! [`SceneReport`]: everything measured on one scene, in the one shape `eval.json` writes
//! (`docs/formats.md`, "eval.json"), built once by [`SceneReport::new`] from what the
//! metrics found.

use serde::{Deserialize, Deserializer, Serialize};

use sceneeval_fidelity::{FidelityReport, FidelitySummary};
use sceneeval_geom::Side;
use sceneeval_physics::StabilityReport;
use sceneeval_plausibility::{PlausibilityReport, PlausibilitySummary};
use sceneeval_scene::{ObjectId, SupportType};

use crate::Metric;

/// The schema name and version written into every per-scene report.
/// Version 2 names the scene (its file stem) `scene`, where version 1 wrote `scene_id`; both
/// are read.
pub const SCENE_REPORT_SCHEMA: &str = "sceneeval.scene-report/2";

/// Everything measured on one scene: the `report` of its `eval.json`.
///
/// The JSON fields, in order: the schema, then the geometry metrics' report flattened in
/// ([`PlausibilityReport`]: the scene's name, its objects, the geometry metrics that ran, the
/// scene-level [`SceneSummary`], each geometry metric's section with its per-object evidence,
/// `null` when it did not run), then the text-fidelity report when fidelity metrics ran, the
/// stability metric's when it ran, where each object's support type and functional sides came
/// from when the VLM was asked for them, and the metrics that could not be computed (the
/// record's status is then `partial`).
///
/// The geometry part is [`SceneReport::geometry`]; the report derefs to it, so that
/// `report.summary`, `report.collision` and the others read as fields of the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneReport {
    /// Always [`SCENE_REPORT_SCHEMA`].
    pub schema: String,
    /// The geometry metrics' report, with the scene-level summary of every metric: the
    /// scene's name (its file stem, `scene_12`, the key `scene`; version 1 of the schema wrote
    /// it as `scene_id`, which is read too: the record's `scene_id` is the benchmark id, `12`),
    /// the object ids, the geometry
    /// metrics that ran (in the order of [`sceneeval_plausibility::Metric::ALL`]; the text-fidelity
    /// metrics that ran have their sections in [`SceneReport::fidelity`]), the summary and each
    /// geometry metric's section.
    #[serde(flatten)]
    pub geometry: PlausibilityReport<SceneSummary>,
    /// What the text-fidelity metrics found, when they ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fidelity: Option<FidelityReport>,
    /// What the stability metric found, when it ran (set by [`SceneReport::with_stability`]).
    /// Read and written in every build: the simulation is not needed to read it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stability: Option<StabilityReport>,
    /// Where each object's support type and functional sides came from, and why, when the VLM
    /// was asked for them (support or accessibility with a VLM and the default sources).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub placement: Option<Vec<ObjectPlacement>>,
    /// The metrics that could not be computed, or not completely, and why, in metric order
    /// (empty: the scene is complete). A metric listed here is left out of the summary
    /// averages, and the next run evaluates the scene again.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub incomplete: Vec<IncompleteMetric>,
    /// For a report made by an ensemble of runs (`sceneeval ensemble`): the runs, each spec's
    /// votes, and the geometry metrics the runs differ in. Absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<crate::EnsembleVotes>,
}

impl std::ops::Deref for SceneReport {
    type Target = PlausibilityReport<SceneSummary>;

    fn deref(&self) -> &Self::Target {
        &self.geometry
    }
}

impl std::ops::DerefMut for SceneReport {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut self.geometry
    }
}

/// A metric that could not be computed, or not completely: the failure of a VLM request it
/// needed (the endpoint down, a refused key, a time-out), or any other error it met. Its
/// section is absent from the report, except support and accessibility, which are computed
/// with the category tables for the objects whose question failed (see
/// [`SceneReport::placement`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IncompleteMetric {
    /// The metric.
    pub metric: Metric,
    /// Whether a VLM request failed (asking again later may complete the metric).
    pub vlm: bool,
    /// The error.
    pub error: String,
    /// The error's causes, outermost first.
    pub causes: Vec<String>,
}

impl IncompleteMetric {
    /// `metric` could not be computed because of `error`.
    pub fn new(metric: Metric, vlm: bool, error: &(dyn std::error::Error + 'static)) -> Self {
        IncompleteMetric {
            metric,
            vlm,
            error: error.to_string(),
            causes: sceneeval_files::causes(error).map(|c| c.to_string()).collect(),
        }
    }
}

/// Where one object's support type and functional sides came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectPlacement {
    /// The object.
    pub object: ObjectId,
    /// Its support type, when the support metric ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub support_type: Option<Provenance<SupportType>>,
    /// Its functional sides, when the accessibility metric ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub functional_sides: Option<Provenance<Vec<Side>>>,
}

/// A value an object's placement was checked with, where it came from and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance<T> {
    /// The value the metric used; `null` when no source knew it (support then checks the
    /// object as resting on the ground; accessibility skips it).
    pub value: Option<T>,
    /// Where it came from.
    pub source: PlacementSource,
    /// Why: the model's reason, or why the category table answered instead (the VLM's answer
    /// was not valid, its request failed, or it was not asked, with the reason).
    pub reason: String,
}

/// Where a support type or functional sides came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlacementSource {
    /// Stated in the scene file.
    Scene,
    /// Answered by the VLM.
    Vlm,
    /// The built-in category table, because the VLM gave no usable answer (a fallback).
    CategoryPrior,
    /// No source knew it (a fallback).
    None,
}

impl PlacementSource {
    /// Whether the value is a fallback: not stated and not answered by the VLM.
    pub fn is_fallback(self) -> bool {
        matches!(self, PlacementSource::CategoryPrior | PlacementSource::None)
    }
}

/// The scene-level numbers of a [`SceneReport`]: the geometry metrics' (`null` where a metric
/// did not run or does not apply), then, when text-fidelity metrics ran, their scores.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SceneSummary {
    /// The geometry metrics' numbers.
    #[serde(flatten)]
    pub geometry: PlausibilitySummary,
    /// CNT, ATR, OOR, OAR when text-fidelity metrics ran (the keys are absent otherwise).
    #[serde(
        flatten,
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "fidelity_keys"
    )]
    pub fidelity: Option<FidelitySummary>,
    /// STAB, the share of the objects free to move that stayed where they were put (0 to 1),
    /// when the stability metric ran: the key `stab` is absent when it did not run, `null`
    /// when no object was free to move (`report.stability.frac_unstable_missing` says why).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "present"
    )]
    pub stab: Option<Option<f64>>,
}

impl SceneReport {
    /// The report of a scene named `scene` from what the geometry metrics and, when they ran,
    /// the text-fidelity metrics found.
    pub fn new(
        scene: Option<String>,
        geometry: PlausibilityReport,
        fidelity: Option<FidelityReport>,
    ) -> Self {
        let scores = fidelity.as_ref().map(|f| f.summary);
        let mut geometry = geometry.with_summary(|summary| SceneSummary {
            geometry: summary,
            fidelity: scores,
            stab: None,
        });
        geometry.scene = scene;
        SceneReport {
            schema: SCENE_REPORT_SCHEMA.to_owned(),
            geometry,
            fidelity,
            stability: None,
            placement: None,
            incomplete: Vec::new(),
            ensemble: None,
        }
    }

    /// The report with the stability metric's section, and its STAB in the summary
    /// ([`StabilityReport::frac_stable`]).
    pub fn with_stability(mut self, stability: StabilityReport) -> Self {
        self.summary.stab = Some(stability.frac_stable());
        self.stability = Some(stability);
        self
    }

    /// The report with where each object's placement values came from.
    pub fn with_placement(mut self, placement: Vec<ObjectPlacement>) -> Self {
        self.placement = Some(placement);
        self
    }

    /// The report with the metrics that could not be computed, sorted into metric order.
    pub fn with_incomplete(mut self, mut incomplete: Vec<IncompleteMetric>) -> Self {
        incomplete.sort_by_key(|m| m.metric);
        self.incomplete = incomplete;
        self
    }

    /// The report with `fidelity` in place of its text-fidelity section, and its scores in the
    /// summary (as [`SceneReport::new`] puts them).
    pub fn with_fidelity(mut self, fidelity: FidelityReport) -> Self {
        self.summary.fidelity = Some(fidelity.summary);
        self.fidelity = Some(fidelity);
        self
    }

    /// Whether `metric` could not be computed completely ([`SceneReport::incomplete`]).
    pub fn is_incomplete(&self, metric: Metric) -> bool {
        self.incomplete.iter().any(|m| m.metric == metric)
    }
}

/// `Some(value)` for a key that is present, `null` included.
fn present<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Option<f64>>, D::Error> {
    Option::<f64>::deserialize(d).map(Some)
}

/// The fidelity scores of a summary: `None` when none of the keys `cnt`, `atr`, `oor`, `oar`
/// is present (no fidelity metric ran), else each present value (`null` included).
fn fidelity_keys<'de, D: Deserializer<'de>>(d: D) -> Result<Option<FidelitySummary>, D::Error> {
    #[derive(Deserialize)]
    struct Keys {
        #[serde(default, deserialize_with = "present")]
        cnt: Option<Option<f64>>,
        #[serde(default, deserialize_with = "present")]
        atr: Option<Option<f64>>,
        #[serde(default, deserialize_with = "present")]
        oor: Option<Option<f64>>,
        #[serde(default, deserialize_with = "present")]
        oar: Option<Option<f64>>,
    }
    let k = Keys::deserialize(d)?;
    if [k.cnt, k.atr, k.oor, k.oar].iter().all(Option::is_none) {
        return Ok(None);
    }
    Ok(Some(FidelitySummary {
        cnt: k.cnt.flatten(),
        atr: k.atr.flatten(),
        oor: k.oor.flatten(),
        oar: k.oar.flatten(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> PlausibilityReport {
        PlausibilityReport {
            object_ids: vec![ObjectId::new("bed")],
            ..PlausibilityReport::of_summary(
                Some("ignored".into()),
                vec![sceneeval_plausibility::Metric::OutOfBounds],
                PlausibilitySummary {
                    oob: Some(0.0),
                    ..PlausibilitySummary::default()
                },
            )
        }
    }

    #[test]
    fn the_summary_holds_fidelity_keys_only_when_fidelity_ran() {
        let report = SceneReport::new(Some("scene_3".into()), geometry(), None);
        let json = serde_json::to_string(&report).unwrap();
        assert_eq!(
            json,
            r#"{"schema":"sceneeval.scene-report/2","scene":"scene_3","object_ids":["bed"],"metrics":["out_of_bounds"],"summary":{"col_ob":null,"col_sc":null,"sup":null,"nav":null,"all_rooms_reachable":null,"acc":null,"oob":0.0,"num_doors":null,"doors_blocked":null,"num_windows":null,"windows_blocked":null},"collision":null,"support":null,"navigability":null,"accessibility":null,"out_of_bounds":null,"opening_clearance":null}"#
        );
        let back: SceneReport = serde_json::from_str(&json).unwrap();
        assert_eq!(back, report);

        // A summary with fidelity keys, `null` ones included, reads back as written.
        let mut value: serde_json::Value = serde_json::from_str(&json).unwrap();
        value["summary"]["cnt"] = serde_json::json!(0.5);
        value["summary"]["atr"] = serde_json::Value::Null;
        let back: SceneReport = serde_json::from_value(value).unwrap();
        assert_eq!(
            back.summary.fidelity,
            Some(FidelitySummary {
                cnt: Some(0.5),
                ..FidelitySummary::default()
            })
        );
        assert_eq!(back.summary.geometry.oob, Some(0.0));
    }
}
