//! The seven tasks of the reference as typed request builders, their wire answers and their
//! validated answers.
//!
//! | task ([`TaskKind`](crate::TaskKind)) | builder | questions (key) | images | validated answer | used by |
//! |---|---|---|---|---|---|
//! | `obj_matching` | [`ObjectMatchingTask`] | one ([`Single`](crate::Single)) | front view | [`ObjectMatch`] | object matching |
//! | `obj_attribute` | [`AttributeTask`] | instance x attribute ([`AttributeKey`]) | front + size view per instance | [`AttributeVerdict`] | ATR |
//! | `obj_support_type` | [`SupportTypeTask`] | one | front view, surroundings | [`SupportTypeAnswer`] | support |
//! | `obj_functional_sides` | [`FunctionalSidesTask`] | object id | none | [`FunctionalSidesAnswer`] | accessibility |
//! | `obj_relationship_mapping` | [`ObjectRelationTask`] | relation key | none | [`ObjectRelationMapping`] | OOR |
//! | `arch_relationship_mapping` | [`ArchRelationTask`] | relation key | none | [`ArchRelationMapping`] | OAR |
//! | `category_matching_for_semantic_color` | [`CategoryMatchingTask`] | input category | none | [`ReferenceMatch`] | semantic colours |
//!
//! The wire types (`*Response`, `*Assessment`) keep the reference's field names, so answers
//! are comparable across implementations. Fields added here are marked *added* in their docs:
//! only `key` in the two relationship-mapping answers, which pairs an assessment with its
//! relation. Other answers are paired by the fields the reference already echoes: `obj_id`,
//! `input_category`, and `instance` with `attribute`.
//!
//! Echoed labels (categories, attributes) are compared after trimming, lower-casing and
//! treating spaces, hyphens and underscores alike (`Dining chair` = `dining_chair`); ids and
//! keys after trimming only. Validated answers always use the caller's spelling.

mod arch_relation;
mod attribute;
mod category;
mod functional;
mod matching;
mod object_relation;
mod support;

pub use arch_relation::{
    ArchElementType, ArchRelationMapping, ArchRelationSpec, ArchRelationTask, ArchRelationshipAssessment,
    ArchRelationshipMappingResponse,
};
pub use attribute::{
    AttributeKey, AttributeTask, AttributeVerdict, InstanceViews, ObjAttributeAssessment,
    ObjAttributeResponse,
};
pub use category::{
    CategoryMatchingAssessment, CategoryMatchingResponse, CategoryMatchingTask, ReferenceMatch,
};
pub use functional::{
    FunctionalSidesAnswer, FunctionalSidesAssessment, FunctionalSidesResponse, FunctionalSidesTask,
    ObjectToDescribe,
};
pub use matching::{ObjMatchingResponse, ObjectDimensions, ObjectMatch, ObjectMatchingTask};
pub use object_relation::{
    ObjRelationshipAssessment, ObjRelationshipMappingResponse, ObjectRelationMapping, ObjectRelationSpec,
    ObjectRelationTask,
};
pub use support::{SupportTypeAnswer, SupportTypeResponse, SupportTypeTask};

use crate::VlmError;

/// A label in comparable form: trimmed, lower case, runs of spaces, hyphens and underscores as
/// one `_`.
pub(crate) fn norm(label: &str) -> String {
    let mut out = String::with_capacity(label.len());
    let mut gap = false;
    for c in label.trim().chars() {
        if c == ' ' || c == '-' || c == '_' {
            gap = true;
        } else {
            if gap && !out.is_empty() {
                out.push('_');
            }
            gap = false;
            out.extend(c.to_lowercase());
        }
    }
    out
}

/// The offered label `label` stands for, in the offered spelling.
pub(crate) fn find_label<'a>(offered: &'a [String], label: &str) -> Option<&'a str> {
    let n = norm(label);
    offered.iter().find(|o| norm(o) == n).map(String::as_str)
}

/// The base category of an object reference (`chair:1` -> `chair`).
pub(crate) fn base_category(reference: &str) -> &str {
    reference
        .split_once(':')
        .map_or(reference, |(base, _)| base)
        .trim()
}

/// A JSON list of strings, as the prompts show lists.
pub(crate) fn json_list(items: &[String]) -> String {
    serde_json::to_string(items).unwrap_or_default()
}

/// A JSON string literal.
pub(crate) fn json_str(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_default()
}

/// Checks that `labels` are non-empty, single-line and pairwise different (compared with
/// `same`); `what` names them in the error.
pub(crate) fn check_labels(
    task: &'static str,
    what: &str,
    labels: &[String],
    same: impl Fn(&str) -> String,
) -> Result<(), VlmError> {
    let mut seen = std::collections::BTreeMap::new();
    for (i, label) in labels.iter().enumerate() {
        if label.trim().is_empty() {
            return Err(VlmError::invalid_task(task, format!("{what} {i} is empty")));
        }
        if label.contains(['\n', '\r']) {
            return Err(VlmError::invalid_task(
                task,
                format!("{what} {label:?} spans several lines"),
            ));
        }
        if let Some(first) = seen.insert(same(label), label) {
            return Err(VlmError::invalid_task(
                task,
                format!("{what} {label:?} is the same as {first:?}; each must be distinct"),
            ));
        }
    }
    Ok(())
}

/// Schema-only name lists: the wire fields are strings (so an unexpected value gets a clear
/// validation message rather than a parse error), and their schemas carry these enums so that
/// schema-constrained decoding only produces valid names.
pub(crate) mod names {
    use schemars::JsonSchema;

    /// `support_type` values.
    #[allow(dead_code)]
    #[derive(JsonSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum SupportTypeName {
        Ground,
        Wall,
        Ceiling,
        Object,
    }

    /// `functional_sides` values.
    #[allow(dead_code)]
    #[derive(JsonSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum HorizontalSideName {
        Front,
        Back,
        Left,
        Right,
    }

    /// `relationship_types` values: the 13 object-object predicates.
    #[allow(dead_code)]
    #[derive(JsonSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum ObjectRelationName {
        InsideOf,
        OutsideOf,
        FaceTo,
        SideOf,
        SideRegion,
        LongShortSideOf,
        OnTop,
        MiddleOf,
        Surround,
        NextTo,
        Near,
        AcrossFrom,
        Far,
    }

    /// `sides` values: a side of `side_of`/`side_region`, or `long`/`short`.
    #[allow(dead_code)]
    #[derive(JsonSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum SideArgumentName {
        Left,
        Right,
        Front,
        Back,
        Top,
        Bottom,
        Long,
        Short,
    }

    /// `relationship_type` values: the 10 object-architecture predicates.
    #[allow(dead_code)]
    #[derive(JsonSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum ArchRelationName {
        NextTo,
        Near,
        AcrossFrom,
        Far,
        InsideRoom,
        MiddleOfRoom,
        CornerOfRoom,
        OnWall,
        AgainstWall,
        HangFromCeiling,
    }

    /// `architectural_element_type` values.
    #[allow(dead_code)]
    #[derive(JsonSchema)]
    #[serde(rename_all = "snake_case")]
    pub enum ArchElementName {
        Wall,
        Floor,
        Ceiling,
        Room,
        Window,
        Door,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_normalise() {
        assert_eq!(norm("  Dining  Chair "), "dining_chair");
        assert_eq!(norm("dining-chair"), "dining_chair");
        assert_eq!(norm("__x__"), "x");
        let offered = vec!["coffee_table".to_owned(), "sofa".to_owned()];
        assert_eq!(find_label(&offered, "Coffee Table"), Some("coffee_table"));
        assert_eq!(find_label(&offered, "table"), None);
        assert_eq!(base_category(" chair:2 "), "chair");
        assert_eq!(base_category("bed"), "bed");
    }

    #[test]
    fn label_checks() {
        let ok = vec!["a".to_owned(), "b".to_owned()];
        assert!(check_labels("t", "category", &ok, norm).is_ok());
        let dup = vec!["Dining chair".to_owned(), "dining_chair".to_owned()];
        let err = check_labels("t", "category", &dup, norm).unwrap_err().to_string();
        assert!(err.contains("same as"), "{err}");
        assert!(check_labels("t", "category", &[" ".to_owned()], norm).is_err());
        assert!(check_labels("t", "category", &["a\nb".to_owned()], norm).is_err());
    }
}
