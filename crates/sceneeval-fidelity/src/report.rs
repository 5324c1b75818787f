//! The fidelity report of a scene: per metric, per spec, with the evidence behind each verdict.

use serde::{Deserialize, Serialize};

use crate::matching::MatchingSource;
use crate::params::RelationMapping;

/// What the fidelity metrics found in one scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FidelityReport {
    /// The matching used (the full matching is in the scene's `matching.json`).
    pub matching: MatchingSummary,
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
    /// [`Usage`](sceneeval_vlm::Usage): requests, cache hits, failed requests, re-asks,
    /// answered and unanswered questions, prompt and completion tokens).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vlm_usage: Option<sceneeval_vlm::Usage>,
    /// Views rendered for this scene.
    #[serde(default)]
    pub views_rendered: u64,
    /// Everything worth a second look: caps that bit, room types without a room, ...
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// The satisfied share of specs per metric: `null` when the scene has no such specs, or (ATR)
/// when they could not be judged (no VLM).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct FidelitySummary {
    /// CNT: satisfied ObjCount specs / specs.
    pub cnt: Option<f64>,
    /// ATR: satisfied ObjAttr specs / specs.
    pub atr: Option<f64>,
    /// OOR: satisfied OORel specs / specs.
    pub oor: Option<f64>,
    /// OAR: satisfied OARel specs / specs.
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
    /// "s/t requirements are satisfied.", or why nothing was evaluated.
    pub message: String,
    /// Satisfied specs; `null` when the specs were not judged (ATR without a VLM).
    pub satisfied: Option<usize>,
    /// Specs.
    pub total: usize,
    /// `satisfied / total`; `null` without specs or when not judged.
    pub score: Option<f64>,
    /// Why the specs were not judged (ATR without a VLM), if so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_judged: Option<String>,
    /// Every spec, in annotation order.
    pub specs: Vec<T>,
}

impl<T> MetricResult<T> {
    pub(crate) fn new(specs: Vec<T>, satisfied: impl Fn(&T) -> bool, empty_message: &str) -> Self {
        let total = specs.len();
        let s = specs.iter().filter(|x| satisfied(x)).count();
        MetricResult {
            message: if total == 0 {
                empty_message.to_owned()
            } else {
                format!("{s}/{total} requirements are satisfied.")
            },
            satisfied: Some(s),
            total,
            score: (total > 0).then(|| s as f64 / total as f64),
            not_judged: None,
            specs,
        }
    }

    pub(crate) fn not_judged(specs: Vec<T>, why: &str) -> Self {
        MetricResult {
            message: why.to_owned(),
            satisfied: None,
            total: specs.len(),
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
    /// Whether the count satisfies the quantifier.
    pub satisfied: bool,
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
    /// Set when some question got no valid answer (those instances count as not having the
    /// attributes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unanswered: Option<String>,
    /// Why the spec was decided without asking, if so.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// The verdict; `null` when the spec was not judged (no VLM to ask). A spec decided
    /// without asking (no object of its category) has a verdict either way.
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
    /// The VLM gave no valid mapping (counts as unsatisfied).
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
    /// The verdict.
    pub satisfied: bool,
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
    /// The verdict.
    pub satisfied: bool,
}
