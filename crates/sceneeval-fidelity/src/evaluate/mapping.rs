//! What OOR and OAR share: how a relationship's mapping onto predicates is recorded, and the
//! verdicts of specs that are not evaluated on the geometry.

use sceneeval_annotation::CountSpec;
use sceneeval_relations::Relation;
use sceneeval_vlm::Unanswered;

use super::FidelityEvaluator;
use crate::report::{MappingSource, MappingStatus, RelationMappingInfo};

/// A mapping without predicates: its status, source and why.
pub(super) fn info(status: MappingStatus, source: MappingSource, reason: &str) -> RelationMappingInfo {
    RelationMappingInfo {
        status,
        source,
        word: None,
        relations: Vec::new(),
        reason: reason.to_owned(),
    }
}

/// The lexicon mapped the relationship through table word `word` onto `relations`.
pub(super) fn by_lexicon(word: &str, relations: &[Relation]) -> RelationMappingInfo {
    RelationMappingInfo {
        status: MappingStatus::Mapped,
        source: MappingSource::Lexicon,
        word: Some(word.to_owned()),
        relations: relations.iter().map(ToString::to_string).collect(),
        reason: format!("lexicon word {word:?}"),
    }
}

/// The VLM mapped the relationship onto `relations`, for `reason`.
pub(super) fn by_vlm(relations: &[Relation], reason: String) -> RelationMappingInfo {
    RelationMappingInfo {
        status: MappingStatus::Mapped,
        source: MappingSource::Vlm,
        word: None,
        relations: relations.iter().map(ToString::to_string).collect(),
        reason,
    }
}

/// A relationship the lexicon does not know: asked of the VLM (`asked`; unanswered until its
/// answer arrives), or unmapped when there is no VLM to ask.
pub(super) fn not_in_lexicon(relationship: &str, asked: bool) -> RelationMappingInfo {
    if asked {
        info(MappingStatus::Unanswered, MappingSource::Vlm, "asked")
    } else {
        info(
            MappingStatus::Unmapped,
            MappingSource::None,
            &format!("{relationship:?} is not in the lexicon and no VLM is configured"),
        )
    }
}

/// The VLM gave no valid mapping.
pub(super) fn unanswered(why: &Unanswered) -> RelationMappingInfo {
    info(MappingStatus::Unanswered, MappingSource::Vlm, &why.to_string())
}

impl FidelityEvaluator {
    /// The verdict of a spec whose objects are absent: unsatisfied (the reference's presence
    /// gate, Q5), or decided by its quantifier on a count of 0 with
    /// `presence_gate_respects_quantifier`.
    pub(super) fn absent_verdict(&self, count: &CountSpec) -> bool {
        self.params.presence_gate_respects_quantifier && count.holds(0)
    }

    /// The verdict of a spec whose relationship was not mapped: satisfied only when no
    /// predicate expresses it and `unmapped_is_satisfied` (the reference, Q4); an unanswered
    /// mapping is unsatisfied.
    pub(super) fn unmapped_verdict(&self, mapping: &RelationMappingInfo) -> bool {
        mapping.status == MappingStatus::Unmapped && self.params.unmapped_is_satisfied
    }
}
