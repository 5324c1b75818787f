//! What a person judges on a run (`sceneeval judge`): every fidelity spec of the run's
//! `eval.json` records as an item (scene, metric, index), with the spec's text, the spec in
//! words, the objects it names and the run's own verdict, in a fixed order; and a seeded
//! sample of the scenes.
//!
//! **Order.** Scenes in the run's order (natural order of their names: `scene_2` before
//! `scene_10`), then metrics CNT, ATR, OOR, OAR, then the spec's index. A metric's specs are
//! items only when the metric ran on the scene (its section is in the record), whatever their
//! verdicts (a spec the run left undecided, or ATR without a VLM, is still judged by people).
//!
//! **Sample.** `--sample N --seed S` keeps the items of N scenes drawn from the scenes that have
//! items (after the metric filter), by [`sceneeval_stats::sample::sample`] (a partial
//! Fisher–Yates shuffle driven by Xoshiro256++ seeded with S), kept in the run's order; N at
//! least the number of scenes keeps every scene.
//!
//! **Objects.** The objects a spec names are the run's own matching: CNT and ATR the objects
//! of the category, OOR the anchors and other objects of its recorded candidate groups, OAR
//! its candidate objects, each object once in the order first named.

use std::collections::BTreeSet;

use sceneeval_annotation::words::entry_in_words;
use sceneeval_annotation::{OaRel, ObjAttr, ObjCount, OoRel};
use sceneeval_fidelity::{FidelityMetric, FidelityReport};
use sceneeval_results::SceneRecord;
use serde::Serialize;

use crate::Run;
use crate::labels::{Item, metric_ran};

/// One spec of a run to judge.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct JudgeItem {
    /// The scene, metric and index.
    #[serde(flatten)]
    pub item: Item,
    /// The spec's text, as `eval.json` has it.
    pub spec: String,
    /// The spec in words ([`sceneeval_annotation::words`]).
    pub words: String,
    /// The objects the spec names, by the run's matching.
    pub objects: Vec<String>,
    /// The run's verdict (`None`: undecided). Never shown to a judge who judges blind.
    pub run_verdict: Option<bool>,
}

/// Which items to judge.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ItemFilter {
    /// The metrics whose specs are judged (empty: all four).
    pub metrics: Vec<FidelityMetric>,
    /// Judge the specs of this many scenes drawn with this seed (`None`: every scene).
    pub sample: Option<(usize, u64)>,
}

/// The items of `run` that `filter` keeps, in the order stated in [`crate::judge`].
#[must_use]
pub fn items(run: &Run, filter: &ItemFilter) -> Vec<JudgeItem> {
    let metrics: Vec<FidelityMetric> = FidelityMetric::ALL
        .into_iter()
        .filter(|m| filter.metrics.is_empty() || filter.metrics.contains(m))
        .collect();
    let per_scene: Vec<Vec<JudgeItem>> = run
        .records
        .iter()
        .map(|record| scene_items(record, &metrics))
        .filter(|items| !items.is_empty())
        .collect();
    let chosen: Vec<usize> = match filter.sample {
        Some((n, seed)) => sceneeval_stats::sample::sample(per_scene.len(), n, seed),
        None => (0..per_scene.len()).collect(),
    };
    let mut out = Vec::new();
    for (k, items) in per_scene.into_iter().enumerate() {
        if chosen.binary_search(&k).is_ok() {
            out.extend(items);
        }
    }
    out
}

/// The items of one scene's record for `metrics` (in that order).
fn scene_items(record: &SceneRecord, metrics: &[FidelityMetric]) -> Vec<JudgeItem> {
    let Some(fidelity) = record.report().and_then(|r| r.fidelity.as_ref()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for &metric in metrics {
        if !metric_ran(fidelity, metric) {
            continue;
        }
        for (index, (spec, verdict)) in fidelity.verdicts(metric).into_iter().enumerate() {
            out.push(JudgeItem {
                item: Item {
                    scene: record.scene.as_str().to_owned(),
                    metric,
                    index,
                },
                spec: spec.to_owned(),
                words: spec_in_words(metric, spec),
                objects: named_objects(fidelity, metric, index),
                run_verdict: verdict,
            });
        }
    }
    out
}

/// A spec of `metric` in words: the entry of the metric's annotation field.
#[must_use]
pub fn spec_in_words(metric: FidelityMetric, spec: &str) -> String {
    match metric {
        FidelityMetric::Cnt => entry_in_words::<ObjCount>(spec),
        FidelityMetric::Atr => entry_in_words::<ObjAttr>(spec),
        FidelityMetric::Oor => entry_in_words::<OoRel>(spec),
        FidelityMetric::Oar => entry_in_words::<OaRel>(spec),
    }
}

/// The objects spec `index` of `metric` names, by the run's matching, each once in the order
/// first named.
#[must_use]
pub fn named_objects(f: &FidelityReport, metric: FidelityMetric, index: usize) -> Vec<String> {
    let ids: Vec<&String> = match metric {
        FidelityMetric::Cnt => f
            .cnt
            .as_ref()
            .and_then(|m| m.specs.get(index))
            .map(|s| s.objects.iter().collect())
            .unwrap_or_default(),
        FidelityMetric::Atr => f
            .atr
            .as_ref()
            .and_then(|m| m.specs.get(index))
            .map(|s| s.objects.iter().collect())
            .unwrap_or_default(),
        FidelityMetric::Oor => f
            .oor
            .as_ref()
            .and_then(|m| m.specs.get(index))
            .map(|s| {
                s.groups
                    .iter()
                    .flat_map(|g| std::iter::once(&g.anchor).chain(&g.others))
                    .collect()
            })
            .unwrap_or_default(),
        FidelityMetric::Oar => f
            .oar
            .as_ref()
            .and_then(|m| m.specs.get(index))
            .map(|s| s.candidates.iter().map(|c| &c.object).collect())
            .unwrap_or_default(),
    };
    let mut seen = BTreeSet::new();
    ids.into_iter()
        .filter(|id| seen.insert(id.as_str()))
        .cloned()
        .collect()
}
