//! [`FidelityEvaluator`]: CNT, ATR, OOR and OAR of one scene against its annotation row.
//!
//! [`FidelityEvaluator::evaluate`] parses the row's entries, matches the scene's objects to
//! the annotated categories (labels, VLM or a file: [`crate::matching`]) and runs the metrics
//! the plan asks for, one file each:
//! - `cnt`: matched objects per category against the quantifier;
//! - `atr`: the VLM's verdicts on each matched instance's attributes;
//! - `oor`: relationships mapped onto predicates, every candidate group scored;
//! - `oar`: likewise for each matched object against the architecture;
//! - `mapping`: what OOR and OAR share: how a relationship's mapping is recorded, and the
//!   verdicts of specs whose objects are absent or whose relationship has no predicate.

mod atr;
mod cnt;
mod mapping;
mod oar;
mod oor;

pub use oor::MAX_RECORDED_GROUPS;

use sceneeval_annotation::{AnnotationRow, CountSpec, Entry, EntryKind, EntryProblem};
use sceneeval_relations::{RelationParams, SceneRelations};
use sceneeval_scene::Scene;
use sceneeval_vlm::{Session, Vlm};

use crate::matching::{MatchingRecord, match_by_labels, match_by_vlm, read_matching_file};
use crate::report::{FidelityReport, FidelitySummary, MatchingSummary, SpecCount};
use crate::views::ObjectViews;
use crate::{FidelityError, FidelityMetric, FidelityParams, MatchingMethod};

/// What a scene's evaluation may use besides the scene and its row: the VLM session, the
/// object views, and the matching file when the plan reads one.
pub struct Resources<'a, V> {
    /// The VLM, when configured.
    pub session: Option<&'a Session<V>>,
    /// The object views, when a renderer (or another source) is available.
    pub views: Option<&'a dyn ObjectViews>,
    /// The scene's name, to find its file when matching from a folder.
    pub scene_name: &'a str,
}

impl<V> std::fmt::Debug for Resources<'_, V> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Resources")
            .field("vlm", &self.session.is_some())
            .field("views", &self.views.is_some())
            .field("scene_name", &self.scene_name)
            .finish()
    }
}

/// A scene's fidelity report and the matching it used (to write as `matching.json`).
#[derive(Debug, Clone)]
pub struct FidelityOutcome {
    /// The report.
    pub report: FidelityReport,
    /// The matching.
    pub matching: MatchingRecord,
}

/// Runs the fidelity metrics with one set of parameters.
#[derive(Debug, Clone)]
pub struct FidelityEvaluator {
    params: FidelityParams,
    relations: SceneRelations,
}

impl FidelityEvaluator {
    /// An evaluator with these parameters and predicate parameters.
    ///
    /// # Errors
    /// [`FidelityError::InvalidParameter`] for invalid parameters (either kind).
    pub fn new(params: FidelityParams, relations: RelationParams) -> Result<Self, FidelityError> {
        params.validate()?;
        let relations = SceneRelations::new(relations).map_err(|e| FidelityError::InvalidParameter {
            name: "relations",
            message: e.to_string(),
        })?;
        Ok(FidelityEvaluator { params, relations })
    }

    /// The parameters.
    pub fn params(&self) -> &FidelityParams {
        &self.params
    }

    /// Evaluates `metrics` on `scene` against `row`.
    ///
    /// # Errors
    /// A malformed entry ([`FidelityError::MalformedEntry`]), a matching source that is not
    /// available or fails ([`FidelityError::Unavailable`], [`FidelityError::MatchingFile`],
    /// [`FidelityError::MatchingFormat`]), a view that cannot be made, a VLM request without
    /// any answer, a predicate error.
    pub fn evaluate<V: Vlm>(
        &self,
        scene: &Scene,
        row: &AnnotationRow,
        metrics: &[FidelityMetric],
        res: &Resources<'_, V>,
    ) -> Result<FidelityOutcome, FidelityError> {
        let counts = self.entries(row, &row.obj_count, |c| c.clone())?;
        let attrs = self.attr_entries(row)?;
        let oo = self.entries(row, &row.oo_rel, |r| r.clone())?;
        let oa = self.entries(row, &row.oa_rel, |r| r.clone())?;
        let mut categories: Vec<String> = Vec::new();
        for (_, c) in &counts {
            if !categories.contains(&c.category) {
                categories.push(c.category.clone());
            }
        }
        let matching = match &self.params.matching {
            MatchingMethod::Labels => match_by_labels(scene, &categories),
            MatchingMethod::Vlm => {
                let (Some(session), Some(views)) = (res.session, res.views) else {
                    return Err(FidelityError::Unavailable {
                        what: "matching by VLM".into(),
                        needs: "a VLM and object views",
                    });
                };
                match_by_vlm(
                    scene,
                    &categories,
                    session,
                    views,
                    self.params.size_aware_matching,
                )?
            }
            MatchingMethod::File { path } => {
                let file = crate::matching::matching_file_for(path, res.scene_name);
                read_matching_file(&file, scene, &categories)?
            }
        };
        let m = &matching.matching;
        let mut warnings = Vec::new();
        let runs = |x| metrics.contains(&x);
        let cnt = runs(FidelityMetric::Cnt).then(|| self.cnt(scene, m, &counts));
        let atr = if runs(FidelityMetric::Atr) {
            Some(self.atr(scene, m, &attrs, res)?)
        } else {
            None
        };
        let oor = if runs(FidelityMetric::Oor) {
            Some(self.oor(scene, m, &oo, res, &mut warnings)?)
        } else {
            None
        };
        let oar = if runs(FidelityMetric::Oar) {
            Some(self.oar(scene, m, &oa, res, &mut warnings)?)
        } else {
            None
        };
        let summary = FidelitySummary {
            cnt: cnt.as_ref().and_then(|r| r.score),
            atr: atr.as_ref().and_then(|r| r.score),
            oor: oor.as_ref().and_then(|r| r.score),
            oar: oar.as_ref().and_then(|r| r.score),
        };
        let report = FidelityReport {
            matching: MatchingSummary {
                source: matching.source,
                message: m.message(scene.objects().len()),
                unanswered: matching.unanswered.len(),
            },
            relation_mapping: self.params.relation_mapping,
            cnt,
            atr,
            oor,
            oar,
            summary,
            vlm_usage: res.session.map(|s| s.usage()),
            views_rendered: res.views.map_or(0, |v| v.made()),
            warnings,
        };
        Ok(FidelityOutcome { report, matching })
    }

    /// The parsed entries of a field with their text (duplicates collapsed unless kept).
    fn entries<T: EntryKind, U>(
        &self,
        row: &AnnotationRow,
        entries: &[Entry<T>],
        f: impl Fn(&T) -> U,
    ) -> Result<Vec<(String, U)>, FidelityError> {
        let mut out: Vec<(String, U)> = Vec::new();
        for e in entries {
            match e {
                Entry::Parsed(v) => {
                    let text = v.to_string();
                    if !self.params.keep_duplicate_specs && out.iter().any(|(t, _)| *t == text) {
                        continue;
                    }
                    out.push((text, f(v)));
                }
                Entry::Malformed(m) => return Err(malformed(row, T::FIELD.as_str(), m.text(), m.problems())),
            }
        }
        Ok(out)
    }
}

/// The count part of a spec as the report writes it.
fn spec_count(c: &CountSpec) -> SpecCount {
    SpecCount {
        quantifier: c.quantifier.as_str().to_owned(),
        quantity: c.quantity,
    }
}

/// The ids of the objects at `idx`.
fn ids(scene: &Scene, idx: &[usize]) -> Vec<String> {
    idx.iter()
        .map(|&i| scene.objects()[i].id().as_str().to_owned())
        .collect()
}

/// The error for an entry that does not follow its grammar.
fn malformed(
    row: &AnnotationRow,
    field: &'static str,
    text: &str,
    problems: &[EntryProblem],
) -> FidelityError {
    FidelityError::MalformedEntry {
        row: row.id.clone(),
        field,
        entry: text.to_owned(),
        problems: problems
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("; "),
    }
}
