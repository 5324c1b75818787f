//! `obj_relationship_mapping`: free-text object-object relations onto the 13 object-object
//! predicates.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use sceneeval_relations::Relation;

use super::{
    KeyedAnswer, KeyedRelation, base_category, check_relations, keyed_lines, norm, pair_by_key, relation_keys,
};
use crate::TaskKind;
use crate::VlmError;
use crate::names::{ObjectRelationName, SideArgumentName};
use crate::schema::Nullable;
use crate::task::{Task, Validation};

const TASK: &str = TaskKind::ObjRelationshipMapping.name();

/// The answer of `obj_relationship_mapping` as the model writes it (the reference's fields,
/// plus `key`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObjRelationshipMappingResponse {
    /// One assessment per relation.
    pub assessments: Vec<ObjRelationshipAssessment>,
}

/// One assessment of an `obj_relationship_mapping` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObjRelationshipAssessment {
    /// *Added*: the key of the relation this assessment answers, copied from the prompt. Pairs
    /// the assessment with its relation (the reference pairs them by position).
    pub key: String,
    /// The relation text, echoed (not checked).
    pub relationship: String,
    /// The anchor's category (without a `:k` suffix).
    pub anchor_object: String,
    /// The categories of the other objects, each once.
    pub other_objects: Vec<String>,
    /// How many objects of each category of `other_objects` take part, in the same order.
    pub other_object_counts: Vec<i64>,
    /// The predicates that together express the relation, or `null` when none fits.
    #[schemars(with = "Nullable<Vec<ObjectRelationName>>")]
    pub relationship_types: Option<Vec<String>>,
    /// One entry per type: the side (`side_of`, `side_region`), `long`/`short`
    /// (`long_short_side_of`) or `null`.
    #[schemars(with = "Vec<Option<SideArgumentName>>")]
    pub sides: Vec<Option<String>>,
    /// Why.
    pub reason: String,
}

impl KeyedAnswer for ObjRelationshipAssessment {
    fn key(&self) -> &str {
        &self.key
    }
}

/// One object-object relation of the annotation (an OORel entry without its count).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ObjectRelationSpec {
    /// Identifies the relation within the task; copied into the answer's `key`. Any short
    /// single-line text (an index, the raw annotation entry, ...).
    pub key: String,
    /// The free-text relationship (`next`, `at_the_foot_of`, ...).
    pub relationship: String,
    /// The object references, `category` or `category:k` (at least two).
    pub objects: Vec<String>,
    /// Which reference is the anchor; `None` when the annotation leaves it open (its `-1`),
    /// in which case the first one is.
    pub anchor_index: Option<usize>,
}

impl ObjectRelationSpec {
    /// The relation as the prompt shows it (the reference's wording):
    /// `next - objects: table, chair, with the object with index: 0 being the anchor`.
    pub fn prompt_text(&self) -> String {
        let index = self.anchor_index.map_or(-1, |i| i as i64);
        format!(
            "{} - objects: {}, with the object with index: {index} being the anchor",
            self.relationship,
            self.objects.join(", ")
        )
    }

    /// The base category of the anchor (the first reference when unspecified).
    fn anchor_category(&self) -> &str {
        base_category(&self.objects[self.anchor_index.unwrap_or(0)])
    }
}

impl KeyedRelation for ObjectRelationSpec {
    fn key(&self) -> &str {
        &self.key
    }

    fn relationship(&self) -> &str {
        &self.relationship
    }

    fn prompt_text(&self) -> String {
        ObjectRelationSpec::prompt_text(self)
    }
}

/// The `obj_relationship_mapping` task for the relations of a scene (one call per scene).
#[derive(Debug, Clone)]
pub struct ObjectRelationTask {
    relations: Vec<ObjectRelationSpec>,
}

/// A validated mapping of one relation.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ObjectRelationMapping {
    /// The anchor's category, in the caller's spelling.
    pub anchor_object: String,
    /// The other objects' categories with how many objects of each take part, in the caller's
    /// spelling. Together with the anchor they are exactly the relation's objects.
    pub other_objects: Vec<(String, usize)>,
    /// The predicates that must all hold, or `None` when the model found that no predefined
    /// relation fits (the reference then counts the relation as satisfied, quirk Q4; what to
    /// do is the caller's decision).
    pub relations: Option<Vec<Relation>>,
    /// The model's reason.
    pub reason: String,
}

impl ObjectRelationTask {
    /// Asks for the mapping of `relations`.
    ///
    /// # Errors
    /// [`VlmError::InvalidTask`] when there is no relation, a key is empty, spans lines or
    /// repeats, a relation has fewer than two objects, an empty object reference or an anchor
    /// index outside its objects.
    pub fn new(relations: Vec<ObjectRelationSpec>) -> Result<Self, VlmError> {
        check_relations(TASK, &relations, |r| {
            if r.objects.len() < 2 {
                return Err(format!(
                    "{} object(s); a relation needs at least two",
                    r.objects.len()
                ));
            }
            if r.objects.iter().any(|o| base_category(o).is_empty()) {
                return Err("an empty object reference".into());
            }
            if let Some(i) = r.anchor_index.filter(|&i| i >= r.objects.len()) {
                return Err(format!("anchor index {i} but {} objects", r.objects.len()));
            }
            Ok(())
        })?;
        Ok(ObjectRelationTask { relations })
    }

    fn check(
        &self,
        spec: &ObjectRelationSpec,
        a: ObjRelationshipAssessment,
    ) -> Result<ObjectRelationMapping, String> {
        // Participants: the spec's base categories with multiplicity, keyed by normalised name.
        let mut expected: BTreeMap<String, (String, usize)> = BTreeMap::new();
        for o in &spec.objects {
            let base = base_category(o);
            expected.entry(norm(base)).or_insert((base.to_owned(), 0)).1 += 1;
        }
        let anchor = spec.anchor_category();
        if norm(&a.anchor_object) != norm(anchor) {
            return Err(format!(
                "anchor_object {:?} is not this relation's anchor {anchor:?} (the object with index {})",
                a.anchor_object,
                spec.anchor_index.unwrap_or(0)
            ));
        }
        if a.other_objects.len() != a.other_object_counts.len() {
            return Err(format!(
                "{} other_objects but {} other_object_counts",
                a.other_objects.len(),
                a.other_object_counts.len()
            ));
        }
        let mut named: BTreeMap<String, usize> = BTreeMap::from([(norm(anchor), 1)]);
        let mut others = Vec::new();
        for (category, &count) in a.other_objects.iter().zip(&a.other_object_counts) {
            let Some((spelling, _)) = expected.get(&norm(category)) else {
                return Err(format!(
                    "other object {category:?} is not one of the relation's objects"
                ));
            };
            if count < 1 {
                return Err(format!(
                    "other_object_counts for {category:?} is {count}; counts are at least 1"
                ));
            }
            if others.iter().any(|(c, _): &(String, usize)| c == spelling) {
                return Err(format!(
                    "other object {category:?} is listed twice; list each category once"
                ));
            }
            *named.entry(norm(category)).or_default() += count as usize;
            others.push((spelling.clone(), count as usize));
        }
        let expected_counts: BTreeMap<String, usize> =
            expected.iter().map(|(k, (_, n))| (k.clone(), *n)).collect();
        if named != expected_counts {
            return Err(format!(
                "the anchor and other objects count {}, but the relation's objects are {}",
                counts_text(&named),
                counts_text(&expected_counts)
            ));
        }
        let relations = match a.relationship_types {
            None => None,
            Some(types) if types.len() == 1 && types[0].trim().eq_ignore_ascii_case("none") => None,
            Some(types) if types.is_empty() => {
                return Err("relationship_types is an empty list; use null when no type fits".into());
            }
            Some(types) => {
                if a.sides.len() != types.len() {
                    return Err(format!(
                        "{} relationship_types but {} sides; give one side (or null) per type",
                        types.len(),
                        a.sides.len()
                    ));
                }
                let mut relations = Vec::with_capacity(types.len());
                for (t, side) in types.iter().zip(&a.sides) {
                    let r = Relation::from_object_mapping(t, side.as_deref())
                        .map_err(|e| format!("relationship type {t:?} with side {side:?}: {e}"))?;
                    relations.push(r);
                }
                Some(relations)
            }
        };
        Ok(ObjectRelationMapping {
            anchor_object: expected
                .get(&norm(anchor))
                .map_or_else(|| anchor.to_owned(), |(s, _)| s.clone()),
            other_objects: others,
            relations,
            reason: a.reason,
        })
    }
}

fn counts_text(counts: &BTreeMap<String, usize>) -> String {
    let parts: Vec<String> = counts.iter().map(|(c, n)| format!("{n} {c}")).collect();
    parts.join(", ")
}

impl Task for ObjectRelationTask {
    type Response = ObjRelationshipMappingResponse;
    type Key = String;
    type Item = ObjectRelationMapping;

    fn kind(&self) -> TaskKind {
        TaskKind::ObjRelationshipMapping
    }

    fn placeholders(&self) -> Vec<(&'static str, String)> {
        vec![("RELATIONSHIPS", keyed_lines(&self.relations))]
    }

    fn keys(&self) -> Vec<String> {
        relation_keys(&self.relations)
    }

    fn validate(
        &self,
        r: ObjRelationshipMappingResponse,
        out: &mut Validation<String, ObjectRelationMapping>,
    ) {
        pair_by_key(&self.relations, r.assessments, |s, a| self.check(s, a), out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Side;

    fn spec(key: &str, relationship: &str, objects: &[&str], anchor: Option<usize>) -> ObjectRelationSpec {
        ObjectRelationSpec {
            key: key.into(),
            relationship: relationship.into(),
            objects: objects.iter().map(|s| s.to_string()).collect(),
            anchor_index: anchor,
        }
    }

    fn answer(
        key: &str,
        anchor: &str,
        others: &[(&str, i64)],
        types: Option<&[&str]>,
        sides: &[Option<&str>],
    ) -> ObjRelationshipAssessment {
        ObjRelationshipAssessment {
            key: key.into(),
            relationship: String::new(),
            anchor_object: anchor.into(),
            other_objects: others.iter().map(|(c, _)| c.to_string()).collect(),
            other_object_counts: others.iter().map(|(_, n)| *n).collect(),
            relationship_types: types.map(|t| t.iter().map(|s| s.to_string()).collect()),
            sides: sides.iter().map(|s| s.map(str::to_owned)).collect(),
            reason: "r".into(),
        }
    }

    fn task() -> ObjectRelationTask {
        ObjectRelationTask::new(vec![
            spec("foot", "at_the_foot_of", &["bed", "table"], Some(0)),
            spec(
                "ring",
                "surround",
                &["table", "chair:0", "chair:1", "chair:2", "sofa"],
                Some(0),
            ),
            spec("diag", "diagonally_across", &["table", "chair"], None),
        ])
        .unwrap()
    }

    #[test]
    fn shuffled_assessments_pair_by_key() {
        let task = task();
        let mut v = Validation::new();
        task.validate(
            ObjRelationshipMappingResponse {
                assessments: vec![
                    answer("diag", "Table", &[("chair", 1)], None, &[None]),
                    answer(
                        "ring",
                        "table",
                        &[("chair", 3), ("sofa", 1)],
                        Some(&["surround"]),
                        &[None],
                    ),
                    answer(
                        "foot",
                        "bed",
                        &[("table", 1)],
                        Some(&["side_of", "next_to"]),
                        &[Some("front"), None],
                    ),
                ],
            },
            &mut v,
        );
        v.finish(&task.keys());
        let foot = v.item(&"foot".to_owned()).unwrap();
        assert_eq!(
            foot.relations,
            Some(vec![Relation::SideOf(Side::Front), Relation::NextTo])
        );
        assert_eq!(foot.other_objects, [("table".to_owned(), 1)]);
        let ring = v.item(&"ring".to_owned()).unwrap();
        assert_eq!(ring.relations, Some(vec![Relation::Surround]));
        assert_eq!(
            ring.other_objects,
            [("chair".to_owned(), 3), ("sofa".to_owned(), 1)]
        );
        let diag = v.item(&"diag".to_owned()).unwrap();
        assert_eq!(
            (diag.anchor_object.as_str(), diag.relations.clone()),
            ("table", None)
        );
    }

    #[test]
    fn invalid_mappings_name_the_problem() {
        let task = task();
        let cases: Vec<(ObjRelationshipAssessment, &str)> = vec![
            (
                answer("foot", "table", &[("bed", 1)], Some(&["next_to"]), &[None]),
                "not this relation's anchor",
            ),
            (
                answer(
                    "ring",
                    "table",
                    &[("chair", 1), ("sofa", 1)],
                    Some(&["surround"]),
                    &[None],
                ),
                "count",
            ),
            (
                answer("foot", "bed", &[("lamp", 1)], Some(&["next_to"]), &[None]),
                "\"lamp\"",
            ),
            (
                answer("foot", "bed", &[("table", 1)], Some(&[]), &[]),
                "empty list",
            ),
            (
                answer("foot", "bed", &[("table", 1)], Some(&["side_of"]), &[]),
                "1 relationship_types but 0 sides",
            ),
            (
                answer("foot", "bed", &[("table", 1)], Some(&["side_of"]), &[None]),
                "side_of",
            ),
            (
                answer("foot", "bed", &[("table", 1)], Some(&["beside"]), &[None]),
                "\"beside\"",
            ),
            (
                answer("foot", "bed", &[("table", 1)], Some(&["on_wall"]), &[None]),
                "on_wall",
            ),
            (
                answer("foot", "bed", &[("table", 0)], Some(&["near"]), &[None]),
                "at least 1",
            ),
            (
                answer("foot", "bed", &[("table", 1)], Some(&["near"]), &[None, None]),
                "sides",
            ),
        ];
        for (a, expected) in cases {
            let mut v = Validation::new();
            task.validate(
                ObjRelationshipMappingResponse {
                    assessments: vec![a.clone()],
                },
                &mut v,
            );
            let problems = v.problems_for(&"foot".to_owned()).to_vec();
            let problems = if problems.is_empty() {
                v.problems_for(&"ring".to_owned()).to_vec()
            } else {
                problems
            };
            assert!(
                problems.len() == 1 && problems[0].contains(expected),
                "{a:?}: {problems:?}"
            );
        }
        // A lone "None" in the list means no relation fits, as null does.
        let mut v = Validation::new();
        let a = answer("foot", "bed", &[("table", 1)], Some(&["None"]), &[None]);
        task.validate(ObjRelationshipMappingResponse { assessments: vec![a] }, &mut v);
        assert_eq!(v.item(&"foot".to_owned()).unwrap().relations, None);
    }

    #[test]
    fn prompt_lines_and_builder_checks() {
        let text = &task().placeholders()[0].1;
        assert_eq!(
            text.lines().nth(2),
            Some(
                "- key \"diag\": diagonally_across - objects: table, chair, with the object with index: -1 being the anchor"
            )
        );
        assert!(ObjectRelationTask::new(vec![]).is_err());
        assert!(ObjectRelationTask::new(vec![spec("a", "near", &["bed"], None)]).is_err());
        assert!(ObjectRelationTask::new(vec![spec("a", "near", &["bed", "lamp"], Some(2))]).is_err());
        assert!(
            ObjectRelationTask::new(vec![
                spec("a", "near", &["bed", "lamp"], None),
                spec("a", "far", &["bed", "lamp"], None)
            ])
            .is_err()
        );
    }
}
