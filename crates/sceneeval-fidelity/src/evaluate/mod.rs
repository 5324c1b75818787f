//! [`FidelityEvaluator`]: CNT, ATR, OOR and OAR of one scene against its annotation row.
//!
//! [`FidelityEvaluator::evaluate_async`] parses the row's entries, then asks every question
//! that does not wait on another together: the matching of the scene's objects to the
//! annotated categories (labels, VLM or a file: [`crate::matching`]) and the mappings of the
//! relationships onto predicates (they need only the row); once the matching is known, the
//! attribute questions, together. Then it scores the metrics the plan asks for, one file each:
//! - `cnt`: matched objects per category against the quantifier;
//! - `atr`: the VLM's verdicts on each matched instance's attributes;
//! - `oor`: relationships mapped onto predicates, every candidate group scored;
//! - `oar`: likewise for each matched object against the architecture;
//! - `mapping`: what OOR and OAR share: how a relationship's mapping is recorded, and the
//!   verdicts of specs whose objects are absent or whose relationship has no predicate;
//! - `undecided`: verdicts when an answer is missing (no verdict rather than "not
//!   satisfied").
//!
//! A metric that cannot be computed (its entries are malformed, the matching or one of its
//! VLM requests failed) is listed in [`FidelityOutcome::failures`] with the reason and never
//! erases another metric's result.

mod atr;
mod cnt;
mod mapping;
mod oar;
mod oor;
mod undecided;

pub use oor::MAX_RECORDED_GROUPS;

use std::sync::Arc;

use futures_util::future::join3;
use sceneeval_annotation::{AnnotationRow, CountSpec, Entry, EntryKind, EntryProblem};
use sceneeval_relations::{RelationParams, SceneRelations};
use sceneeval_scene::Scene;
use sceneeval_vlm::{Session, Vlm};

use crate::matching::{MatchingRecord, match_by_labels, match_by_vlm, read_matching_file};
use crate::report::{FidelityReport, MatchingSummary, SpecCount};
use crate::views::ObjectViews;
use crate::{FidelityError, FidelityMetric, FidelityParams, MatchingMethod};
use undecided::Unknown;

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

/// A metric of the plan that could not be computed, and why.
#[derive(Debug, Clone)]
pub struct MetricFailure {
    /// The metric.
    pub metric: FidelityMetric,
    /// Why (shared: one failed matching fails every metric).
    pub error: Arc<FidelityError>,
}

impl MetricFailure {
    /// Whether the failure is the VLM's: a request that got no answer at all (the endpoint
    /// down, a refused key, a time-out). Asking again later may complete the metric.
    pub fn is_vlm(&self) -> bool {
        matches!(*self.error, FidelityError::Vlm { .. })
    }
}

/// A scene's fidelity report, the matching it used (to write as `matching.json`), and the
/// metrics that could not be computed.
#[derive(Debug, Clone)]
pub struct FidelityOutcome {
    /// The report: every metric that could be computed.
    pub report: FidelityReport,
    /// The matching, when one could be made.
    pub matching: Option<MatchingRecord>,
    /// The metrics of the plan that could not be computed, in metric order.
    pub failures: Vec<MetricFailure>,
}

/// Runs the fidelity metrics with one set of parameters.
#[derive(Debug, Clone)]
pub struct FidelityEvaluator {
    params: FidelityParams,
    relations: SceneRelations,
}

/// An error shared by the metrics it stops.
type Shared<T> = Result<T, Arc<FidelityError>>;

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

    /// Evaluates `metrics` on `scene` against `row`, all or nothing: the outcome of
    /// [`FidelityEvaluator::evaluate_async`] (run with [`pollster::block_on`]) when every
    /// metric could be computed.
    ///
    /// # Errors
    /// The first metric's failure: a malformed entry ([`FidelityError::MalformedEntry`]), a
    /// matching source that is not available or fails ([`FidelityError::Unavailable`],
    /// [`FidelityError::MatchingFile`], [`FidelityError::MatchingFormat`]), a view that cannot
    /// be made, a VLM request without any answer, a predicate error.
    pub fn evaluate<V: Vlm>(
        &self,
        scene: &Scene,
        row: &AnnotationRow,
        metrics: &[FidelityMetric],
        res: &Resources<'_, V>,
    ) -> Result<FidelityOutcome, FidelityError> {
        let outcome = pollster::block_on(self.evaluate_async(scene, row, metrics, res));
        let Some(first) = outcome.failures.first().map(|f| f.error.clone()) else {
            return Ok(outcome);
        };
        drop(outcome);
        // Every other holder of the error is dropped: it is this one's alone.
        Err(
            Arc::try_unwrap(first).unwrap_or_else(|shared| FidelityError::Unavailable {
                what: shared.to_string(),
                needs: "an error held only once",
            }),
        )
    }

    /// Evaluates `metrics` on `scene` against `row`: every metric that can be computed, and
    /// why the others cannot ([`FidelityOutcome::failures`]).
    ///
    /// The questions that do not wait on each other are asked together (the matching of every
    /// object and the relation mappings, then every attribute question), in the same order
    /// whatever order their answers arrive in, so that the report does not depend on it; how
    /// many requests are really in flight is the model's limit.
    pub async fn evaluate_async<V: Vlm>(
        &self,
        scene: &Scene,
        row: &AnnotationRow,
        metrics: &[FidelityMetric],
        res: &Resources<'_, V>,
    ) -> FidelityOutcome {
        let runs = |x| metrics.contains(&x);
        let counts: Shared<_> = self.entries(row, &row.obj_count, |c| c.clone()).map_err(Arc::new);
        let attrs: Shared<_> = self.attr_entries(row).map_err(Arc::new);
        let oo: Shared<_> = self.entries(row, &row.oo_rel, |r| r.clone()).map_err(Arc::new);
        let oa: Shared<_> = self.entries(row, &row.oa_rel, |r| r.clone()).map_err(Arc::new);
        let floor_ids: Vec<String> = scene.rooms().iter().map(|r| r.floor_id().to_owned()).collect();

        // The matching and the relation mappings: none waits on another.
        let matching = async {
            let counts = counts.as_ref().map_err(Arc::clone)?;
            let mut categories: Vec<String> = Vec::new();
            for (_, c) in counts {
                if !categories.contains(&c.category) {
                    categories.push(c.category.clone());
                }
            }
            self.matching(scene, &categories, res).await.map_err(Arc::new)
        };
        let oor_mappings = async {
            if !runs(FidelityMetric::Oor) {
                return None;
            }
            Some(match &oo {
                Ok(rels) => self.oor_mappings(rels, res).await.map_err(Arc::new),
                Err(e) => Err(e.clone()),
            })
        };
        let oar_mappings = async {
            if !runs(FidelityMetric::Oar) {
                return None;
            }
            Some(match &oa {
                Ok(rels) => self.oar_mappings(rels, &floor_ids, res).await.map_err(Arc::new),
                Err(e) => Err(e.clone()),
            })
        };
        let (matching, oor_mappings, oar_mappings) = join3(matching, oor_mappings, oar_mappings).await;

        let unknown_ids: Vec<String> = match &matching {
            Ok(m) => m.unanswered.keys().cloned().collect(),
            Err(_) => Vec::new(),
        };
        let unknown = Unknown { ids: &unknown_ids };
        let m: Shared<_> = matching.as_ref().map(|r| &r.matching).map_err(Arc::clone);
        let mut warnings = Vec::new();
        let cnt = runs(FidelityMetric::Cnt).then(|| -> Shared<_> {
            let counts = counts.as_ref().map_err(Arc::clone)?;
            Ok(self.cnt(scene, m.clone()?, unknown, counts))
        });
        let atr = match runs(FidelityMetric::Atr) {
            false => None,
            true => Some(
                async {
                    let (m, attrs) = (m.clone()?, attrs.as_ref().map_err(Arc::clone)?);
                    self.atr(scene, m, unknown, attrs, res).await.map_err(Arc::new)
                }
                .await,
            ),
        };
        let oor = oor_mappings.map(|mappings| -> Shared<_> {
            let (m, rels) = (m.clone()?, oo.as_ref().map_err(Arc::clone)?);
            self.oor(scene, m, unknown, rels, mappings?, &mut warnings)
                .map_err(Arc::new)
        });
        let oar = oar_mappings.map(|mappings| -> Shared<_> {
            let (m, rels) = (m.clone()?, oa.as_ref().map_err(Arc::clone)?);
            self.oar(scene, m, unknown, rels, mappings?, &mut warnings)
                .map_err(Arc::new)
        });
        let mut failures = Vec::new();
        let cnt = kept(FidelityMetric::Cnt, cnt, &mut failures);
        let atr = kept(FidelityMetric::Atr, atr, &mut failures);
        let oor = kept(FidelityMetric::Oor, oor, &mut failures);
        let oar = kept(FidelityMetric::Oar, oar, &mut failures);
        let matching = matching.ok();
        let report = FidelityReport {
            matching: matching.as_ref().map(|m| MatchingSummary {
                source: m.source,
                message: m.matching.message(scene.objects().len()),
                unanswered: m.unanswered.len(),
            }),
            vlm_usage: res.session.map(|s| s.usage()),
            views_rendered: res.views.map_or(0, |v| v.made()),
            warnings,
            ..FidelityReport::of_results(self.params.relation_mapping, cnt, atr, oor, oar)
        };
        FidelityOutcome {
            report,
            matching,
            failures,
        }
    }

    /// The matching from the plan's source.
    async fn matching<V: Vlm>(
        &self,
        scene: &Scene,
        categories: &[String],
        res: &Resources<'_, V>,
    ) -> Result<MatchingRecord, FidelityError> {
        match &self.params.matching {
            MatchingMethod::Labels => Ok(match_by_labels(scene, categories)),
            MatchingMethod::Vlm => {
                let (Some(session), Some(views)) = (res.session, res.views) else {
                    return Err(FidelityError::Unavailable {
                        what: "matching by VLM".into(),
                        needs: "a VLM and object views",
                    });
                };
                match_by_vlm(scene, categories, session, views, self.params.size_aware_matching).await
            }
            MatchingMethod::File(path) => {
                let file = crate::matching::matching_file_for(path, res.scene_name);
                read_matching_file(&file, scene, categories)
            }
        }
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

/// A metric's result when it could be computed (`None` when it did not run); its failure
/// otherwise, added to `failures`.
fn kept<R>(
    metric: FidelityMetric,
    result: Option<Shared<R>>,
    failures: &mut Vec<MetricFailure>,
) -> Option<R> {
    match result? {
        Ok(r) => Some(r),
        Err(error) => {
            tracing::warn!(%metric, error = %error, "metric not computed");
            failures.push(MetricFailure { metric, error });
            None
        }
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
