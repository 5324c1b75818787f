//! The fidelity report of a scene: per metric, per spec, with the evidence behind each verdict.

use serde::{Deserialize, Serialize};

use crate::matching::MatchingSource;
use crate::params::{FidelityMetric, RelationMapping};

/// What the fidelity metrics found in one scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FidelityReport {
    /// The matching used (the full matching is in the scene's `matching.json`); absent when
    /// no matching could be made (the metrics are then listed as failed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matching: Option<MatchingSummary>,
    /// How relationships were mapped onto predicates (individual specs record their own
    /// mapping source: a lexicon run may have asked the VLM for unknown words).
    pub relation_mapping: RelationMapping,
    /// CNT, when the plan runs it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cnt: Option<MetricResult<CntSpec>>,
    /// ATR, when the plan runs it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atr: Option<MetricResult<AtrSpec>>,
    /// OOR, when the plan runs it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub oor: Option<MetricResult<OorSpec>>,
    /// OAR, when the plan runs it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub oar: Option<MetricResult<OarSpec>>,
    /// The satisfied share of each metric.
    pub summary: FidelitySummary,
    /// The VLM's usage for this scene, when one is configured (the session's
    /// [`Usage`](sceneeval_vlm::Usage): requests, failed requests, re-asks and the recoveries
    /// of imperfect answers, answered and unanswered questions, the tokens of every answer
    /// used).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vlm_usage: Option<sceneeval_vlm::Usage>,
    /// Views rendered for this scene.
    #[serde(default)]
    pub views_rendered: u64,
    /// Everything worth a second look: caps that bit, room types without a room, ...
    #[serde(default)]
    pub warnings: Vec<String>,
}

impl FidelityReport {
    /// The report of these metrics' results (`None`: the metric did not run), its summary
    /// counted from their scores, without a matching summary, VLM usage, views or warnings:
    /// the one way a report is put together, by the evaluation (which adds those) and by hand.
    ///
    /// ```
    /// use sceneeval_fidelity::{CntSpec, FidelityReport, MetricResult, RelationMapping, SpecCount};
    /// let eq_1 = || SpecCount { quantifier: "eq".into(), quantity: 1 };
    /// let cnt = MetricResult::new(
    ///     vec![
    ///         CntSpec::new("eq,1,bed", eq_1(), "bed", vec!["bed_0".into()], Some(true)),
    ///         CntSpec::new("eq,1,lamp", eq_1(), "lamp", Vec::new(), Some(false)),
    ///     ],
    ///     |s| s.satisfied,
    ///     "no specs",
    /// );
    /// let report = FidelityReport::of_results(RelationMapping::Lexicon, Some(cnt), None, None, None);
    /// assert_eq!(report.summary.cnt, Some(0.5));
    /// assert_eq!(report.cnt.as_ref().unwrap().message, "1/2 requirements are satisfied.");
    /// ```
    #[must_use]
    pub fn of_results(
        relation_mapping: RelationMapping,
        cnt: Option<MetricResult<CntSpec>>,
        atr: Option<MetricResult<AtrSpec>>,
        oor: Option<MetricResult<OorSpec>>,
        oar: Option<MetricResult<OarSpec>>,
    ) -> Self {
        let mut report = FidelityReport {
            matching: None,
            relation_mapping,
            cnt,
            atr,
            oor,
            oar,
            summary: FidelitySummary::default(),
            vlm_usage: None,
            views_rendered: 0,
            warnings: Vec::new(),
        };
        report.rescore();
        report
    }

    /// Each spec of `metric` as written in the annotation, with its verdict (`None`: no
    /// verdict), in the order of the metric's `specs` (a spec's position there is its index in
    /// label files); empty when the metric did not run.
    #[must_use]
    pub fn verdicts(&self, metric: FidelityMetric) -> Vec<(&str, Option<bool>)> {
        fn of<'a, T>(
            m: Option<&'a MetricResult<T>>,
            f: impl Fn(&'a T) -> (&'a str, Option<bool>),
        ) -> Vec<(&'a str, Option<bool>)> {
            m.map(|m| m.specs.iter().map(f).collect()).unwrap_or_default()
        }
        match metric {
            FidelityMetric::Cnt => of(self.cnt.as_ref(), |s| (s.spec.as_str(), s.satisfied)),
            FidelityMetric::Atr => of(self.atr.as_ref(), |s| (s.spec.as_str(), s.satisfied)),
            FidelityMetric::Oor => of(self.oor.as_ref(), |s| (s.spec.as_str(), s.satisfied)),
            FidelityMetric::Oar => of(self.oar.as_ref(), |s| (s.spec.as_str(), s.satisfied)),
        }
    }
}

/// A verdict put on a spec from outside the evaluation (an ensemble's majority,
/// `sceneeval_run::ensemble`): the verdict, and why there is none when `None`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Revote {
    /// The spec's new verdict.
    pub satisfied: Option<bool>,
    /// Why it has none (recorded in the spec's `unanswered`); ignored with a verdict.
    pub unanswered: Option<String>,
}

/// The specs of every metric, whose verdict can be replaced ([`FidelityReport::revote`]).
trait Judged {
    fn verdict(&self) -> Option<bool>;
    fn set(&mut self, vote: &Revote);
}

macro_rules! judged {
    ($($t:ty),*) => {$(
        impl Judged for $t {
            fn verdict(&self) -> Option<bool> {
                self.satisfied
            }

            fn set(&mut self, vote: &Revote) {
                self.satisfied = vote.satisfied;
                self.unanswered = match vote.satisfied {
                    Some(_) => None,
                    None => vote.unanswered.clone(),
                };
            }
        }
    )*};
}
judged!(CntSpec, AtrSpec, OorSpec, OarSpec);

impl FidelityReport {
    /// Replaces the verdicts of `metric`'s specs, in the order of its `specs`, and recounts
    /// the metric (satisfied, unanswered, score and message) and the summary exactly as the
    /// evaluation counts them: a spec without a verdict is unanswered, left out of the score.
    /// The evidence of each spec (candidate groups, assessments) is left as it was. A metric
    /// that was not judged (ATR without a VLM) stays so.
    ///
    /// # Errors
    /// The number of specs the metric has (`0` when it did not run) when `votes` has another
    /// length; nothing is changed then.
    pub fn revote(&mut self, metric: FidelityMetric, votes: &[Revote]) -> Result<(), usize> {
        fn apply<T: Judged>(m: Option<&mut MetricResult<T>>, votes: &[Revote]) -> Result<(), usize> {
            let Some(m) = m else {
                return if votes.is_empty() { Ok(()) } else { Err(0) };
            };
            if m.specs.len() != votes.len() {
                return Err(m.specs.len());
            }
            for (spec, vote) in m.specs.iter_mut().zip(votes) {
                spec.set(vote);
            }
            if m.not_judged.is_none() {
                let empty = m.message.clone();
                let specs = std::mem::take(&mut m.specs);
                *m = MetricResult::new(specs, Judged::verdict, &empty);
            }
            Ok(())
        }
        match metric {
            FidelityMetric::Cnt => apply(self.cnt.as_mut(), votes)?,
            FidelityMetric::Atr => apply(self.atr.as_mut(), votes)?,
            FidelityMetric::Oor => {
                apply(self.oor.as_mut(), votes)?;
                if let Some(oor) = &mut self.oor {
                    oor.note_absent_objects();
                }
            }
            FidelityMetric::Oar => apply(self.oar.as_mut(), votes)?,
        }
        self.rescore();
        Ok(())
    }

    /// Sets the summary from each metric's score.
    pub(crate) fn rescore(&mut self) {
        self.summary = FidelitySummary {
            cnt: self.cnt.as_ref().and_then(|r| r.score),
            atr: self.atr.as_ref().and_then(|r| r.score),
            oor: self.oor.as_ref().and_then(|r| r.score),
            oar: self.oar.as_ref().and_then(|r| r.score),
        };
    }
}

impl MetricResult<OorSpec> {
    /// Says in the message when no spec has all its objects in the scene.
    pub(crate) fn note_absent_objects(&mut self) {
        const NOTE: &str = "No object-object relationship specs have all objects present in the scene.";
        if self.total > 0
            && self.specs.iter().all(|s| !s.all_objects_present)
            && !self.message.starts_with(NOTE)
        {
            self.message = format!("{NOTE} {}", self.message);
        }
    }
}

/// The satisfied share of specs per metric: satisfied specs over the specs with a verdict;
/// `null` when the scene has no such specs, none has a verdict, or (ATR) they could not be
/// judged (no VLM). Specs without a verdict are counted in their [`MetricResult::unanswered`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct FidelitySummary {
    /// CNT: satisfied ObjCount specs / specs with a verdict.
    pub cnt: Option<f64>,
    /// ATR: satisfied ObjAttr specs / specs with a verdict.
    pub atr: Option<f64>,
    /// OOR: satisfied OORel specs / specs with a verdict.
    pub oor: Option<f64>,
    /// OAR: satisfied OARel specs / specs with a verdict.
    pub oar: Option<f64>,
}

/// The matching in short.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MatchingSummary {
    /// Where it came from.
    pub source: MatchingSource,
    /// The reference's message, "Matched a/b categories. Matched c/d objects."
    pub message: String,
    /// Objects the VLM gave no valid answer for.
    pub unanswered: usize,
}

/// One metric's result: the reference's message, the counts, and every spec.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricResult<T> {
    /// "s/t requirements are satisfied.", or why nothing was evaluated; with specs left
    /// undecided, "s/d requirements are satisfied; u not decided ...".
    pub message: String,
    /// Satisfied specs; `null` when the specs were not judged (ATR without a VLM).
    pub satisfied: Option<usize>,
    /// Specs.
    pub total: usize,
    /// Specs without a verdict because an answer they need is missing (the VLM gave no valid
    /// answer for a relation's mapping, an attribute, or an object's category, and the missing
    /// answer could change the verdict). They are left out of the score, never counted as
    /// unsatisfied; each says why in its own `unanswered`.
    #[serde(default)]
    pub unanswered: usize,
    /// `satisfied / (total - unanswered)`; `null` without specs with a verdict or when not
    /// judged.
    pub score: Option<f64>,
    /// Why the specs were not judged (ATR without a VLM), if so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_judged: Option<String>,
    /// Every spec, in annotation order.
    pub specs: Vec<T>,
}

impl<T> MetricResult<T> {
    /// The result of `specs`, each with its verdict (`verdict`: `None` when it has none
    /// because an answer is missing), counted as the evaluation counts (and
    /// [`FidelityReport::revote`] recounts): satisfied specs over the specs with a verdict;
    /// `empty_message` is the message when there are no specs.
    pub fn new(specs: Vec<T>, verdict: impl Fn(&T) -> Option<bool>, empty_message: &str) -> Self {
        let total = specs.len();
        let s = specs.iter().filter(|x| verdict(x) == Some(true)).count();
        let unanswered = specs.iter().filter(|x| verdict(x).is_none()).count();
        let decided = total - unanswered;
        MetricResult {
            message: match (total, unanswered) {
                (0, _) => empty_message.to_owned(),
                (_, 0) => format!("{s}/{total} requirements are satisfied."),
                _ => format!(
                    "{s}/{decided} requirements are satisfied; {unanswered} of {total} not decided (an answer they need is missing)."
                ),
            },
            satisfied: Some(s),
            total,
            unanswered,
            score: (decided > 0).then(|| s as f64 / decided as f64),
            not_judged: None,
            specs,
        }
    }

    pub(crate) fn not_judged(specs: Vec<T>, why: &str) -> Self {
        MetricResult {
            message: why.to_owned(),
            satisfied: None,
            total: specs.len(),
            unanswered: 0,
            score: None,
            not_judged: Some(why.to_owned()),
            specs,
        }
    }
}

/// The count part of a spec.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SpecCount {
    /// `eq`, `lt`, `gt`, `le` or `ge`.
    pub quantifier: String,
    /// The quantity.
    pub quantity: u64,
}

/// One CNT spec.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CntSpec {
    /// The entry as written.
    pub spec: String,
    /// The quantifier and quantity.
    #[serde(flatten)]
    pub count: SpecCount,
    /// The category.
    pub category: String,
    /// Objects matched to it.
    pub objects: Vec<String>,
    /// How many.
    pub count_in_scene: u64,
    /// Why the spec has no verdict: objects without a matching answer could be of the
    /// category and change the count.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unanswered: Option<String>,
    /// Whether the count satisfies the quantifier; `null` when undecided (see `unanswered`).
    pub satisfied: Option<bool>,
}

impl CntSpec {
    /// The spec written `spec` (its quantifier and quantity `count`, its `category`) with the
    /// `objects` matched to the category (so many are counted) and its verdict; without a
    /// reason for a missing verdict (set `unanswered` when `satisfied` is `None`).
    #[must_use]
    pub fn new(
        spec: impl Into<String>,
        count: SpecCount,
        category: impl Into<String>,
        objects: Vec<String>,
        satisfied: Option<bool>,
    ) -> Self {
        CntSpec {
            spec: spec.into(),
            count,
            category: category.into(),
            count_in_scene: objects.len() as u64,
            objects,
            unanswered: None,
            satisfied,
        }
    }
}

/// The VLM's verdict on one instance and attribute.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AttributeAssessment {
    /// The object.
    pub object: String,
    /// The attribute.
    pub attribute: String,
    /// Whether it has it; `null` when unanswered.
    pub satisfied: Option<bool>,
    /// The model's reason, or why it is unanswered.
    pub reason: String,
}

/// One ATR spec.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AtrSpec {
    /// The entry as written.
    pub spec: String,
    /// The quantifier and quantity.
    #[serde(flatten)]
    pub count: SpecCount,
    /// The category.
    pub category: String,
    /// The attributes (one in SceneEval-500; several are all required, Q6).
    pub attributes: Vec<String>,
    /// Objects matched to the category.
    pub objects: Vec<String>,
    /// Instances having every attribute; `null` when not asked.
    pub count_satisfied: Option<u64>,
    /// Per instance and attribute.
    pub assessments: Vec<AttributeAssessment>,
    /// Set when some question got no valid answer (or some object has no matching answer); the
    /// verdict is `null` when those answers could change it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unanswered: Option<String>,
    /// Why the spec was decided without asking, if so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// The verdict; `null` when the spec was not judged (no VLM to ask) or a missing answer
    /// could change it (see `unanswered`). A spec decided without asking (no object of its
    /// category) has a verdict either way.
    pub satisfied: Option<bool>,
}

/// How a relationship was mapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MappingStatus {
    /// Mapped onto predicates.
    Mapped,
    /// No predicate expresses it (counts as unsatisfied unless `unmapped_is_satisfied`).
    Unmapped,
    /// The VLM gave no valid mapping (the spec has no verdict unless its objects are absent).
    Unanswered,
    /// Not mapped because the spec failed its presence gate.
    NotNeeded,
}

/// Where a mapping came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MappingSource {
    /// The lexicon.
    Lexicon,
    /// The VLM.
    Vlm,
    /// Neither (presence gate failed, or no VLM for an unknown word).
    None,
}

/// The mapping of one relationship.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RelationMappingInfo {
    /// Mapped, unmapped or unanswered.
    pub status: MappingStatus,
    /// Lexicon or VLM.
    pub source: MappingSource,
    /// The lexicon word that matched.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub word: Option<String>,
    /// The predicates (all must hold), e.g. `side_of(left)`.
    pub relations: Vec<String>,
    /// Why (the VLM's reason, the lexicon's note).
    pub reason: String,
}

/// A predicate's verdict inside a candidate group.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PredicateResult {
    /// The predicate.
    pub relation: String,
    /// Its score in `[0, 1]`.
    pub score: f64,
    /// Whether it holds (score above the threshold).
    pub holds: bool,
}

/// One OOR candidate group.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CandidateGroup {
    /// The anchor object.
    pub anchor: String,
    /// The other objects (the first is the target of two-object predicates).
    pub others: Vec<String>,
    /// Each predicate.
    pub results: Vec<PredicateResult>,
    /// Whether every predicate holds.
    pub satisfied: bool,
}

/// One OOR spec.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OorSpec {
    /// The entry as written.
    pub spec: String,
    /// The quantifier and quantity.
    #[serde(flatten)]
    pub count: SpecCount,
    /// The relationship text.
    pub relationship: String,
    /// The annotation's anchor index (`-1` unspecified).
    pub anchor_index: i64,
    /// The object references.
    pub obj_references: Vec<String>,
    /// Whether the scene has enough matched objects of every referenced category.
    pub all_objects_present: bool,
    /// The anchor category and the other categories with their counts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub participants: Option<Participants>,
    /// The mapping.
    pub mapping: RelationMappingInfo,
    /// Candidate groups in total.
    pub num_candidate_groups: u64,
    /// Groups evaluated (less than the total when the cap bit).
    pub groups_evaluated: u64,
    /// The first groups evaluated, with every predicate's score (at most
    /// [`crate::MAX_RECORDED_GROUPS`]).
    pub groups: Vec<CandidateGroup>,
    /// Satisfied groups.
    pub count_satisfied: u64,
    /// Why the spec has no verdict (its mapping is unanswered, or objects without a matching
    /// answer could change it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unanswered: Option<String>,
    /// The verdict; `null` when undecided (see `unanswered`).
    pub satisfied: Option<bool>,
}

/// Who takes part in a relation.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Participants {
    /// The anchor's category.
    pub anchor: String,
    /// The other categories and how many objects of each.
    pub others: Vec<(String, usize)>,
}

/// One OAR candidate object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArchCandidate {
    /// The object.
    pub object: String,
    /// The predicate's score.
    pub score: f64,
    /// Whether it holds.
    pub holds: bool,
}

/// One OAR spec.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OarSpec {
    /// The entry as written.
    pub spec: String,
    /// The quantifier and quantity.
    #[serde(flatten)]
    pub count: SpecCount,
    /// The relationship text.
    pub relationship: String,
    /// The object reference.
    pub obj_reference: String,
    /// The architecture references.
    pub arch_references: Vec<String>,
    /// Whether an object of the category is matched.
    pub obj_present: bool,
    /// The mapping.
    pub mapping: RelationMappingInfo,
    /// The floors (or rooms) the relation is restricted to; empty = all.
    pub floors: Vec<String>,
    /// Every candidate.
    pub candidates: Vec<ArchCandidate>,
    /// Satisfied candidates.
    pub count_satisfied: u64,
    /// Why the spec has no verdict (its mapping is unanswered, or objects without a matching
    /// answer could change it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unanswered: Option<String>,
    /// The verdict; `null` when undecided (see `unanswered`).
    pub satisfied: Option<bool>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cnt(spec: &str, satisfied: Option<bool>) -> CntSpec {
        let count = SpecCount {
            quantifier: "eq".into(),
            quantity: 1,
        };
        CntSpec::new(spec, count, "bed", vec!["bed_0".into()], satisfied)
    }

    fn report(specs: Vec<CntSpec>) -> FidelityReport {
        let cnt = MetricResult::new(specs, |s| s.satisfied, "none");
        FidelityReport::of_results(RelationMapping::Lexicon, Some(cnt), None, None, None)
    }

    fn vote(v: Option<bool>) -> Revote {
        Revote {
            satisfied: v,
            unanswered: v.is_none().then(|| "the judges tied".to_owned()),
        }
    }

    /// Three specs re-voted to yes, no, tie: 1 satisfied of 2 decided, 1 unanswered, CNT 0.5,
    /// equal to the report evaluated with those verdicts.
    #[test]
    fn revoting_recounts_as_the_evaluation_counts() {
        let mut r = report(vec![
            cnt("a", Some(false)),
            cnt("b", Some(true)),
            cnt("c", Some(true)),
        ]);
        assert_eq!(r.summary.cnt, Some(2.0 / 3.0));
        r.revote(
            FidelityMetric::Cnt,
            &[vote(Some(true)), vote(Some(false)), vote(None)],
        )
        .unwrap();
        let m = r.cnt.as_ref().unwrap();
        assert_eq!(
            (m.satisfied, m.total, m.unanswered, m.score),
            (Some(1), 3, 1, Some(0.5))
        );
        assert_eq!(r.summary.cnt, Some(0.5));
        assert_eq!(m.specs[2].unanswered.as_deref(), Some("the judges tied"));
        let mut tied = cnt("c", None);
        tied.unanswered = Some("the judges tied".into());
        let direct = report(vec![cnt("a", Some(true)), cnt("b", Some(false)), tied]);
        assert_eq!(r, direct);
        // Every spec tied: no score, as the evaluation gives without verdicts.
        r.revote(FidelityMetric::Cnt, &[vote(None), vote(None), vote(None)])
            .unwrap();
        assert_eq!(r.summary.cnt, None);
        // Wrong lengths and metrics that did not run are refused, nothing changed.
        let before = r.clone();
        assert_eq!(r.revote(FidelityMetric::Cnt, &[vote(None)]), Err(3));
        assert_eq!(r.revote(FidelityMetric::Oar, &[vote(None)]), Err(0));
        assert_eq!(r.revote(FidelityMetric::Oar, &[]), Ok(()));
        assert_eq!(r, before);
    }
}
