//! [`FidelityParams`]: how objects are matched, how relations are mapped, and the switches
//! that restore the reference's behaviour where this implementation fixes it.

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::FidelityError;

/// The four text-fidelity metrics of the paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FidelityMetric {
    /// CNT: object counts (`ObjCount`).
    Cnt,
    /// ATR: object attributes (`ObjAttr`), judged by the VLM.
    Atr,
    /// OOR: object-object relationships (`OORel`).
    Oor,
    /// OAR: object-architecture relationships (`OARel`).
    Oar,
}

impl FidelityMetric {
    /// All four, in the paper's order.
    pub const ALL: [FidelityMetric; 4] = [
        FidelityMetric::Cnt,
        FidelityMetric::Atr,
        FidelityMetric::Oor,
        FidelityMetric::Oar,
    ];

    /// The name in plans and on the command line (`cnt`, `atr`, `oor`, `oar`).
    pub const fn name(self) -> &'static str {
        match self {
            FidelityMetric::Cnt => "cnt",
            FidelityMetric::Atr => "atr",
            FidelityMetric::Oor => "oor",
            FidelityMetric::Oar => "oar",
        }
    }
}

impl fmt::Display for FidelityMetric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FidelityMetric {
    type Err = String;

    /// Parses `cnt`, `atr`, `oor`, `oar` (any case).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        FidelityMetric::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| format!("unknown fidelity metric {s:?} (expected cnt, atr, oor or oar)"))
    }
}

/// Where the matching of scene objects to annotated categories comes from.
///
/// Written as every choice of a plan is (serde's external tagging): the name of a choice
/// without data (`"labels"`, `"vlm"`), an object of one key, the choice's name, for a choice
/// with data (`{"file": "m.json"}`).
///
/// ```
/// use sceneeval_fidelity::MatchingMethod;
/// let m: MatchingMethod = serde_json::from_str(r#"{"file": "m.json"}"#).unwrap();
/// assert_eq!(m, MatchingMethod::File("m.json".into()));
/// assert_eq!(serde_json::to_string(&MatchingMethod::Vlm).unwrap(), r#""vlm""#);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MatchingMethod {
    /// The object's stated category (scene file or asset metadata) against the annotated
    /// categories, after normalisation and the synonym table ([`crate::labels`]); no VLM.
    #[default]
    Labels,
    /// One VLM request per object with its front view, as the reference.
    Vlm,
    /// A matching file in the reference's `obj_matching_result.json` shape: a file used for
    /// every scene, or a folder holding `<scene>/matching.json` or
    /// `<scene>/obj_matching_result.json` (an earlier output folder of either tool): the file
    /// or folder.
    File(PathBuf),
}

impl fmt::Display for MatchingMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MatchingMethod::Labels => f.write_str("labels"),
            MatchingMethod::Vlm => f.write_str("vlm"),
            MatchingMethod::File(path) => write!(f, "file {}", path.display()),
        }
    }
}

/// How free-text relationships are mapped onto predicates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RelationMapping {
    /// The built-in [`crate::lexicon`]; words it does not know go to the VLM when one is
    /// configured, else are unmapped.
    #[default]
    Lexicon,
    /// The VLM with the reference's prompts (one request per scene and field), as the
    /// reference.
    Vlm,
}

impl fmt::Display for RelationMapping {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RelationMapping::Lexicon => "lexicon",
            RelationMapping::Vlm => "vlm",
        })
    }
}

/// The default cap on OOR candidate groups per spec ([`FidelityParams::max_candidate_groups`]).
pub const DEFAULT_MAX_CANDIDATE_GROUPS: u64 = 1_000_000;

/// Parameters of the fidelity metrics.
///
/// | field | default | reference | what |
/// |---|---|---|---|
/// | `matching` | `labels` | `vlm` | [`MatchingMethod`] |
/// | `size_aware_matching` | false | false | the SceneSmith fork's prompt with the object's dimensions |
/// | `relation_mapping` | `lexicon` | `vlm` | [`RelationMapping`] |
/// | `unmapped_is_satisfied` | false | true | Q4: a relation no predicate expresses counts as satisfied |
/// | `presence_gate_respects_quantifier` | true | false | Q5: with absent objects a spec holds when its quantifier allows zero |
/// | `keep_duplicate_specs` | true | false | Q21: identical entries are separate specs |
/// | `anchor_may_be_target` | false | true | Q22: one object may be both anchor and target of a group |
/// | `max_candidate_groups` | 1 000 000 | — | OOR groups evaluated per spec; more are not evaluated and a warning is recorded |
///
/// Fixed without a switch (they do not change the reference's published numbers, where it
/// does not crash): several attributes in one `ObjAttr` entry are all judged (Q6); VLM answers
/// are paired with their questions by key (Q7); an unknown quantifier is an error (Q18);
/// rows are looked up by ID (Q24, in the facade).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FidelityParams {
    /// Where the object matching comes from.
    pub matching: MatchingMethod,
    /// Use the size-aware matching prompt (object dimensions in centimetres).
    pub size_aware_matching: bool,
    /// How relationships are mapped onto predicates.
    pub relation_mapping: RelationMapping,
    /// Q4: count a relation that no predicate expresses as satisfied (the reference's
    /// "Skipped"). Default false: it is unmapped and unsatisfied.
    pub unmapped_is_satisfied: bool,
    /// Q5: when an object of a spec is absent, decide the spec by its quantifier applied to a
    /// count of 0 (`eq,0`, `lt`, `le` hold). False: such specs fail, as in the reference.
    pub presence_gate_respects_quantifier: bool,
    /// Q21: keep identical entries of one field as separate specs. False: they collapse into
    /// one, as the reference's results keyed by entry text do.
    pub keep_duplicate_specs: bool,
    /// Q22: let the anchor also be one of the other objects of its candidate group when both
    /// have the same category (the reference does). Default false.
    pub anchor_may_be_target: bool,
    /// The most OOR candidate groups evaluated per spec; beyond it the rest are not evaluated
    /// (counted as unsatisfied) and a warning is recorded.
    pub max_candidate_groups: u64,
}

impl Default for FidelityParams {
    fn default() -> Self {
        FidelityParams {
            matching: MatchingMethod::Labels,
            size_aware_matching: false,
            relation_mapping: RelationMapping::Lexicon,
            unmapped_is_satisfied: false,
            presence_gate_respects_quantifier: true,
            keep_duplicate_specs: true,
            anchor_may_be_target: false,
            max_candidate_groups: DEFAULT_MAX_CANDIDATE_GROUPS,
        }
    }
}

impl FidelityParams {
    /// The reference's behaviour: VLM matching and relation mapping, and every switch of the
    /// table in the type docs set to the reference's value.
    pub fn reference() -> Self {
        FidelityParams {
            matching: MatchingMethod::Vlm,
            relation_mapping: RelationMapping::Vlm,
            unmapped_is_satisfied: true,
            presence_gate_respects_quantifier: false,
            keep_duplicate_specs: false,
            anchor_may_be_target: true,
            ..FidelityParams::default()
        }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// [`FidelityError::InvalidParameter`] for a zero `max_candidate_groups`.
    pub fn validate(&self) -> Result<(), FidelityError> {
        if self.max_candidate_groups == 0 {
            return Err(FidelityError::InvalidParameter {
                name: "max_candidate_groups",
                message: "must be at least 1".into(),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_presets() {
        for m in FidelityMetric::ALL {
            assert_eq!(m.name().parse::<FidelityMetric>().unwrap(), m);
        }
        assert!("cnt2".parse::<FidelityMetric>().is_err());
        let r = FidelityParams::reference();
        assert!(r.unmapped_is_satisfied && !r.presence_gate_respects_quantifier);
        assert_eq!(r.matching, MatchingMethod::Vlm);
        let json = serde_json::to_value(&r).unwrap();
        assert_eq!(json["matching"], "vlm");
        let back: FidelityParams = serde_json::from_value(json).unwrap();
        assert_eq!(back, r);
        let file: FidelityParams = serde_json::from_str(r#"{"matching": {"file": "m.json"}}"#).unwrap();
        assert_eq!(file.matching, MatchingMethod::File("m.json".into()));
        assert!(
            FidelityParams {
                max_candidate_groups: 0,
                ..FidelityParams::default()
            }
            .validate()
            .is_err()
        );
    }
}
