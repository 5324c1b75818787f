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
/// one `_` (`"Dining  Table"` and `"dining-table"` are both `dining_table`).
///
/// ```
/// assert_eq!(sceneeval_vlm::tasks::norm(" Dining  Table "), "dining_table");
/// assert_eq!(sceneeval_vlm::tasks::norm("dining-table"), "dining_table");
/// ```
pub fn norm(label: &str) -> String {
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
/// validation message rather than a parse error), and their schemas carry these lists as
/// `enum`s so that schema-constrained decoding only produces valid names. Each list is taken
/// from the vocabulary's own crate, so there is one list per concept.
pub(crate) mod names {
    use std::borrow::Cow;

    use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};

    use sceneeval_geom::Side;
    use sceneeval_relations::{LongShort, OBJECT_ARCH_NAMES, OBJECT_OBJECT_NAMES};
    use sceneeval_scene::SupportType;

    use super::ArchElementType;

    macro_rules! name_list {
        ($(#[$doc:meta])* $name:ident => $names:expr) => {
            $(#[$doc])*
            pub struct $name;

            impl JsonSchema for $name {
                fn schema_name() -> Cow<'static, str> {
                    stringify!($name).into()
                }

                fn inline_schema() -> bool {
                    true
                }

                fn json_schema(_: &mut SchemaGenerator) -> Schema {
                    let names: Vec<&str> = $names;
                    json_schema!({"type": "string", "enum": names})
                }
            }
        };
    }

    name_list!(
        /// `support_type` values.
        SupportTypeName => SupportType::ALL.iter().map(|t| t.name()).collect()
    );
    name_list!(
        /// `functional_sides` values: the horizontal sides.
        HorizontalSideName => Side::HORIZONTAL.iter().map(|s| s.name()).collect()
    );
    name_list!(
        /// `relationship_types` values: the 13 object-object predicates.
        ObjectRelationName => OBJECT_OBJECT_NAMES.to_vec()
    );
    name_list!(
        /// `sides` values: a side of `side_of`/`side_region`, or `long`/`short`.
        SideArgumentName => Side::ALL
            .iter()
            .map(|s| s.name())
            .chain([LongShort::Long.name(), LongShort::Short.name()])
            .collect()
    );
    name_list!(
        /// `relationship_type` values: the 10 object-architecture predicates.
        ArchRelationName => OBJECT_ARCH_NAMES.to_vec()
    );
    name_list!(
        /// `architectural_element_type` values.
        ArchElementName => ArchElementType::ALL.iter().map(|t| t.name()).collect()
    );
    name_list!(
        /// `colour` values of the endpoint check.
        ColourName => crate::check::COLOURS.to_vec()
    );
}

/// The prompt lines of keyed relations: `- key "<key>": <text>`.
pub(crate) fn keyed_lines<'a>(relations: impl Iterator<Item = (&'a str, String)>) -> String {
    let lines: Vec<String> = relations
        .map(|(key, text)| format!("- key {}: {text}", json_str(key)))
        .collect();
    lines.join("\n")
}

/// Pairs keyed assessments with their relations (keys compared after trimming) and records
/// each checked mapping, or its problem, under the relation's key.
pub(crate) fn pair_by_key<S, A, I>(
    specs: &[S],
    spec_key: impl Fn(&S) -> &str,
    assessments: Vec<A>,
    answer_key: impl Fn(&A) -> &str,
    check: impl Fn(&S, A) -> Result<I, String>,
    out: &mut crate::Validation<String, I>,
) {
    for a in assessments {
        let Some(spec) = specs.iter().find(|s| spec_key(s).trim() == answer_key(&a).trim()) else {
            out.general_problem(format!(
                "an assessment has key {:?}, which is not one of the relation keys",
                answer_key(&a)
            ));
            continue;
        };
        let key = spec_key(spec).to_owned();
        match check(spec, a) {
            Ok(item) => out.answer(key, item),
            Err(problem) => out.problem(key, problem),
        }
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
