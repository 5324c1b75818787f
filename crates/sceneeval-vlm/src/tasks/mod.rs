//! The seven tasks of the reference and the two of the paper's annotation generation as typed
//! request builders, their wire answers and their validated answers.
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
//! | `annotate_description` | [`AnnotationTask::annotate`] | one | none | [`AnnotatedDescription`] | `sceneeval annotations annotate` |
//! | `generate_annotated_description` | [`AnnotationTask::generate`] | one | none | [`AnnotatedDescription`] | `sceneeval annotations generate` |
//!
//! The wire types (`*Response`, `*Assessment`) keep the reference's field names, so answers
//! are comparable across implementations. Fields added here are marked *added* in their docs:
//! only `key` in the two relationship-mapping answers, which pairs an assessment with its
//! relation. Other answers are paired by the fields the reference already echoes: `obj_id`,
//! `input_category`, and `instance` with `attribute`.
//!
//! Echoed labels (categories, attributes) are compared in the one normalisation of labels,
//! [`sceneeval_scene::label::normalise`] (trimmed, lower case, whitespace, hyphens and
//! underscores alike: `Dining chair` = `dining_chair`); ids and keys after trimming only. Validated answers always use the caller's spelling.

mod annotation;
mod arch_relation;
mod attribute;
mod category;
mod functional;
mod matching;
mod object_relation;
mod support;

pub use annotation::{AnnotatedDescription, AnnotationLevel, AnnotationTask, EntryChecker};
pub use arch_relation::{
    ArchRelationMapping, ArchRelationSpec, ArchRelationTask, ArchRelationshipAssessment,
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

use sceneeval_scene::label::{Synset, normalise};

use crate::VlmError;

/// A label in the form echoed labels are compared in: the one normalisation of labels
/// ([`sceneeval_scene::label::normalise`]: trimmed, lower case, words joined by `_`), synset
/// suffixes kept (`bed.n.01` and `bed.n.02` are different labels to offer).
pub(crate) fn norm(label: &str) -> String {
    normalise(label, Synset::Keep)
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

/// A relation of the two relationship-mapping tasks: identified by a key the answer copies,
/// shown as one prompt line.
pub(crate) trait KeyedRelation {
    /// The key.
    fn key(&self) -> &str;
    /// The free-text relationship.
    fn relationship(&self) -> &str;
    /// The prompt line's text after the key.
    fn prompt_text(&self) -> String;
}

/// Checks the relations of a mapping task: at least one; keys non-empty, single-line and
/// distinct (after trimming); for each relation, `check` (the task's own rules, a problem in
/// words), then a non-empty, single-line relationship.
pub(crate) fn check_relations<R: KeyedRelation>(
    task: &'static str,
    relations: &[R],
    check: impl Fn(&R) -> Result<(), String>,
) -> Result<(), VlmError> {
    if relations.is_empty() {
        return Err(VlmError::invalid_task(task, "no relation to map"));
    }
    let keys = relation_keys(relations);
    check_labels(task, "relation key", &keys, |s| s.trim().to_owned())?;
    for r in relations {
        let bad = |m: &str| VlmError::invalid_task(task, format!("relation {:?}: {m}", r.key()));
        check(r).map_err(|m| bad(&m))?;
        if r.relationship().trim().is_empty() || r.relationship().contains('\n') {
            return Err(bad("the relationship is empty or spans lines"));
        }
    }
    Ok(())
}

/// The keys of the relations, in order (the task's questions).
pub(crate) fn relation_keys<R: KeyedRelation>(relations: &[R]) -> Vec<String> {
    relations.iter().map(|r| r.key().to_owned()).collect()
}

/// The prompt lines of keyed relations: `- key "<key>": <text>`.
pub(crate) fn keyed_lines<R: KeyedRelation>(relations: &[R]) -> String {
    let lines: Vec<String> = relations
        .iter()
        .map(|r| format!("- key {}: {}", json_str(r.key()), r.prompt_text()))
        .collect();
    lines.join("\n")
}

/// An assessment of a relationship-mapping answer: the key of the relation it answers, as the
/// model copied it (`None` when it left it out).
pub(crate) trait KeyedAnswer {
    /// The key.
    fn key(&self) -> Option<&str>;
}

/// Pairs keyed assessments with their relations (keys compared after trimming; an empty or
/// missing key by position, see [`crate::Validation::pair_items`]) and records each checked
/// mapping, or its problem, under the relation's key.
pub(crate) fn pair_by_key<R: KeyedRelation, A: KeyedAnswer, I>(
    relations: &[R],
    assessments: Vec<A>,
    check: impl Fn(&R, A) -> Result<I, String>,
    out: &mut crate::Validation<String, I>,
) {
    let keys = relation_keys(relations);
    let find = |k: &str| {
        relations
            .iter()
            .find(|r| r.key().trim() == k)
            .map(|r| r.key().to_owned())
    };
    for (key, a) in out.pair_items(&keys, assessments, KeyedAnswer::key, find, "key") {
        let Some(relation) = relations.iter().find(|r| r.key() == key) else {
            continue;
        };
        match check(relation, a) {
            Ok(item) => out.answer(key, item),
            Err(problem) => out.problem(key, problem),
        }
    }
}

/// The relations whose keys are among `keys`, in their order (a narrowed mapping task).
pub(crate) fn narrowed_relations<R: KeyedRelation + Clone>(relations: &[R], keys: &[String]) -> Vec<R> {
    relations
        .iter()
        .filter(|r| keys.iter().any(|k| k == r.key()))
        .cloned()
        .collect()
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
