//! `arch_relationship_mapping`: free-text object-architecture relations onto the 10
//! object-architecture predicates.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use sceneeval_relations::Relation;
use sceneeval_scene::ArchElement;

use super::{
    KeyedAnswer, KeyedRelation, base_category, check_labels, check_relations, json_list, keyed_lines, norm,
    pair_by_key, relation_keys,
};
use crate::TaskKind;
use crate::VlmError;
use crate::names::{ArchRelationName, name_list};
use crate::schema::Nullable;
use crate::task::{Task, Validation};

const TASK: &str = TaskKind::ArchRelationshipMapping.name();

/// The answer of `arch_relationship_mapping` as the model writes it (the reference's fields,
/// plus `key`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ArchRelationshipMappingResponse {
    /// One assessment per relation.
    pub assessments: Vec<ArchRelationshipAssessment>,
}

/// One assessment of an `arch_relationship_mapping` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ArchRelationshipAssessment {
    /// *Added*: the key of the relation this assessment answers, copied from the prompt. Pairs
    /// the assessment with its relation (the reference pairs them by position).
    pub key: String,
    /// The relation text, echoed (not checked).
    pub relationship: String,
    /// The object's category (without a `:k` suffix).
    pub target_object: String,
    /// `wall`, `floor`, `ceiling`, `room`, `window` or `door`.
    #[schemars(with = "ArchElementName")]
    pub architectural_element_type: String,
    /// The predicate, or `null` when none fits.
    #[schemars(with = "Nullable<ArchRelationName>")]
    pub relationship_type: Option<String>,
    /// Floor ids the relation is about (from the list offered); empty means all floors.
    pub specific_floors: Vec<String>,
    /// Why.
    pub reason: String,
}

/// The architectural element types the prompt offers, in its order (all six; the distance
/// predicates accept only walls, doors and windows, `sceneeval_relations::DISTANCE_ELEMENTS`).
const OFFERED_ELEMENTS: [ArchElement; 6] = [
    ArchElement::Wall,
    ArchElement::Floor,
    ArchElement::Ceiling,
    ArchElement::Room,
    ArchElement::Window,
    ArchElement::Door,
];

name_list!(
    /// `architectural_element_type` values, in the prompt's order.
    ArchElementName => OFFERED_ELEMENTS.iter().map(|t| t.name()).collect()
);

/// The offered element type `name` stands for (ASCII case and surrounding whitespace
/// ignored), or the problem.
fn offered_element(name: &str) -> Result<ArchElement, String> {
    OFFERED_ELEMENTS
        .into_iter()
        .find(|t| t.name().eq_ignore_ascii_case(name.trim()))
        .ok_or_else(|| {
            let names: Vec<&str> = OFFERED_ELEMENTS.iter().map(|t| t.name()).collect();
            format!("{name:?} is not one of {}", names.join(", "))
        })
}

impl KeyedAnswer for ArchRelationshipAssessment {
    fn key(&self) -> &str {
        &self.key
    }
}

/// One object-architecture relation of the annotation (an OARel entry without its count).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArchRelationSpec {
    /// Identifies the relation within the task; copied into the answer's `key`.
    pub key: String,
    /// The free-text relationship (`against`, `on`, `corner`, ...).
    pub relationship: String,
    /// The object reference (`category` or `category:k`).
    pub object: String,
    /// The architecture references (`wall`, `window`, `bedroom`, ...).
    pub architecture: Vec<String>,
}

impl ArchRelationSpec {
    /// The relation as the prompt shows it (the reference's wording):
    /// `against - object: bookshelf, with respect to architectural element: wall`.
    pub fn prompt_text(&self) -> String {
        format!(
            "{} - object: {}, with respect to architectural element: {}",
            self.relationship,
            self.object,
            self.architecture.join(", ")
        )
    }
}

impl KeyedRelation for ArchRelationSpec {
    fn key(&self) -> &str {
        &self.key
    }

    fn relationship(&self) -> &str {
        &self.relationship
    }

    fn prompt_text(&self) -> String {
        ArchRelationSpec::prompt_text(self)
    }
}

/// The `arch_relationship_mapping` task for the relations of a scene, with the ids of its
/// floors (one call per scene).
#[derive(Debug, Clone)]
pub struct ArchRelationTask {
    relations: Vec<ArchRelationSpec>,
    floor_ids: Vec<String>,
}

/// A validated mapping of one relation.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ArchRelationMapping {
    /// The object's category, in the caller's spelling.
    pub target_object: String,
    /// The element type the model chose.
    pub element_type: ArchElement,
    /// The predicate (the four distance predicates carry their element: wall, door or
    /// window), or `None` when the model found that none fits (quirk Q4, as for object
    /// relations).
    pub relation: Option<Relation>,
    /// The floors the relation is about, in the caller's spelling; empty means all floors.
    pub floors: Vec<String>,
    /// The model's reason.
    pub reason: String,
}

impl ArchRelationTask {
    /// Asks for the mapping of `relations` in a scene whose floors have ids `floor_ids`.
    ///
    /// # Errors
    /// [`VlmError::InvalidTask`] when there is no relation, keys repeat or are empty, a
    /// relation has no object or no architecture reference, or floor ids repeat.
    pub fn new(
        relations: Vec<ArchRelationSpec>,
        floor_ids: impl IntoIterator<Item = impl Into<String>>,
    ) -> Result<Self, VlmError> {
        check_relations(TASK, &relations, |r| {
            if base_category(&r.object).is_empty() {
                return Err("no object".into());
            }
            if r.architecture.is_empty() || r.architecture.iter().any(|a| a.trim().is_empty()) {
                return Err("no architecture reference".into());
            }
            Ok(())
        })?;
        let floor_ids: Vec<String> = floor_ids.into_iter().map(Into::into).collect();
        check_labels(TASK, "floor id", &floor_ids, |s| s.trim().to_owned())?;
        Ok(ArchRelationTask { relations, floor_ids })
    }

    fn check(
        &self,
        spec: &ArchRelationSpec,
        a: ArchRelationshipAssessment,
    ) -> Result<ArchRelationMapping, String> {
        let object = base_category(&spec.object);
        if norm(&a.target_object) != norm(object) {
            return Err(format!(
                "target_object {:?} is not this relation's object {object:?}",
                a.target_object
            ));
        }
        let element_type = offered_element(&a.architectural_element_type)
            .map_err(|e| format!("architectural_element_type {e}"))?;
        let relation = match a.relationship_type.as_deref().map(str::trim) {
            None => None,
            Some(t) if t.eq_ignore_ascii_case("none") => None,
            Some(t) => Some(
                Relation::from_arch_mapping(t, Some(element_type.name()))
                    .map_err(|e| format!("relationship_type {t:?} with element {element_type}: {e}"))?,
            ),
        };
        let mut floors: Vec<String> = Vec::new();
        for f in &a.specific_floors {
            let Some(id) = self.floor_ids.iter().find(|id| id.trim() == f.trim()) else {
                return Err(format!(
                    "specific floor {f:?} is not one of the floor ids {}",
                    json_list(&self.floor_ids)
                ));
            };
            if !floors.contains(id) {
                floors.push(id.clone());
            }
        }
        Ok(ArchRelationMapping {
            target_object: object.to_owned(),
            element_type,
            relation,
            floors,
            reason: a.reason,
        })
    }
}

impl Task for ArchRelationTask {
    type Response = ArchRelationshipMappingResponse;
    type Key = String;
    type Item = ArchRelationMapping;

    fn kind(&self) -> TaskKind {
        TaskKind::ArchRelationshipMapping
    }

    fn placeholders(&self) -> Vec<(&'static str, String)> {
        vec![
            ("RELATIONSHIPS", keyed_lines(&self.relations)),
            ("FLOOR_IDS", json_list(&self.floor_ids)),
        ]
    }

    fn keys(&self) -> Vec<String> {
        relation_keys(&self.relations)
    }

    fn validate(
        &self,
        r: ArchRelationshipMappingResponse,
        out: &mut Validation<String, ArchRelationMapping>,
    ) {
        pair_by_key(&self.relations, r.assessments, |s, a| self.check(s, a), out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn task() -> ArchRelationTask {
        ArchRelationTask::new(
            vec![
                ArchRelationSpec {
                    key: "0".into(),
                    relationship: "against".into(),
                    object: "bookshelf".into(),
                    architecture: vec!["wall".into()],
                },
                ArchRelationSpec {
                    key: "1".into(),
                    relationship: "corner".into(),
                    object: "chair:1".into(),
                    architecture: vec!["bedroom".into()],
                },
            ],
            ["floor_bedroom", "floor_hall"],
        )
        .unwrap()
    }

    fn answer(
        key: &str,
        object: &str,
        element: &str,
        ty: Option<&str>,
        floors: &[&str],
    ) -> ArchRelationshipAssessment {
        ArchRelationshipAssessment {
            key: key.into(),
            relationship: String::new(),
            target_object: object.into(),
            architectural_element_type: element.into(),
            relationship_type: ty.map(str::to_owned),
            specific_floors: floors.iter().map(|s| s.to_string()).collect(),
            reason: "r".into(),
        }
    }

    fn validate(a: Vec<ArchRelationshipAssessment>) -> Validation<String, ArchRelationMapping> {
        let task = task();
        let mut v = Validation::new();
        task.validate(ArchRelationshipMappingResponse { assessments: a }, &mut v);
        v.finish(&task.keys());
        v
    }

    #[test]
    fn valid_mappings() {
        let v = validate(vec![
            answer(
                "1",
                "chair",
                "room",
                Some("corner_of_room"),
                &["floor_bedroom", "floor_bedroom"],
            ),
            answer("0", "Bookshelf", "wall", Some("against_wall"), &[]),
        ]);
        let m0 = v.item(&"0".to_owned()).unwrap();
        assert_eq!(
            (m0.relation, m0.element_type),
            (Some(Relation::AgainstWall), ArchElement::Wall)
        );
        let m1 = v.item(&"1".to_owned()).unwrap();
        assert_eq!(m1.relation, Some(Relation::CornerOfRoom));
        assert_eq!(m1.floors, ["floor_bedroom"]);
        assert_eq!(m1.target_object, "chair");
        let v = validate(vec![
            answer("0", "bookshelf", "door", Some("near"), &[]),
            answer("1", "chair", "room", None, &[]),
        ]);
        assert_eq!(
            v.item(&"0".to_owned()).unwrap().relation,
            Some(Relation::NearArch(ArchElement::Door))
        );
        assert_eq!(v.item(&"1".to_owned()).unwrap().relation, None);
    }

    #[test]
    fn invalid_mappings() {
        let cases = [
            (
                answer("0", "lamp", "wall", Some("on_wall"), &[]),
                "not this relation's object",
            ),
            (answer("0", "bookshelf", "roof", Some("on_wall"), &[]), "\"roof\""),
            (answer("0", "bookshelf", "floor", Some("next_to"), &[]), "next_to"),
            (answer("0", "bookshelf", "wall", Some("face_to"), &[]), "face_to"),
            (
                answer("0", "bookshelf", "wall", Some("on_wall"), &["floor_kitchen"]),
                "floor_kitchen",
            ),
        ];
        for (a, expected) in cases {
            let v = validate(vec![a.clone()]);
            let p = v.problems_for(&"0".to_owned());
            assert!(p.len() == 1 && p[0].contains(expected), "{a:?}: {p:?}");
        }
    }

    #[test]
    fn prompt_and_builder() {
        let values = task().placeholders();
        assert_eq!(
            values[0].1.lines().next(),
            Some("- key \"0\": against - object: bookshelf, with respect to architectural element: wall")
        );
        assert_eq!(values[1].1, "[\"floor_bedroom\",\"floor_hall\"]");
        assert!(ArchRelationTask::new(vec![], ["f"]).is_err());
        assert!(
            ArchRelationTask::new(
                vec![ArchRelationSpec {
                    key: "0".into(),
                    relationship: "on".into(),
                    object: "x".into(),
                    architecture: vec![]
                }],
                Vec::<String>::new()
            )
            .is_err()
        );
    }
}
