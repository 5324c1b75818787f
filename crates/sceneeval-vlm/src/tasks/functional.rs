//! `obj_functional_sides`: which sides of each object must stay free to use it?

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use sceneeval_geom::Side;

use super::{check_labels, json_str};
use crate::TaskKind;
use crate::VlmError;
use crate::names::HorizontalSideName;
use crate::task::{Task, Validation};

const TASK: &str = TaskKind::ObjFunctionalSides.name();

/// The answer of `obj_functional_sides` as the model writes it (the reference's fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FunctionalSidesResponse {
    /// One assessment per object.
    pub assessments: Vec<FunctionalSidesAssessment>,
}

/// One assessment of an `obj_functional_sides` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FunctionalSidesAssessment {
    /// The object id, echoed: pairs the assessment with its object.
    pub obj_id: String,
    /// The object description, echoed (not checked).
    pub obj_description: String,
    /// Sides among `front`, `back`, `left`, `right`; empty for small objects.
    #[schemars(with = "Vec<HorizontalSideName>")]
    pub functional_sides: Vec<String>,
    /// Why.
    pub reason: String,
}

/// An object to assess: its id and its description (category and text).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ObjectToDescribe {
    /// The object id, echoed by the answer.
    pub id: String,
    /// A description of the object.
    pub description: String,
}

/// The `obj_functional_sides` task for all objects of a scene (one call per scene).
#[derive(Debug, Clone)]
pub struct FunctionalSidesTask {
    objects: Vec<ObjectToDescribe>,
}

/// A validated assessment of one object.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct FunctionalSidesAnswer {
    /// The functional sides: horizontal, without duplicates, in [`Side`] order; empty when the
    /// object has none.
    pub sides: Vec<Side>,
    /// The model's reason.
    pub reason: String,
}

impl FunctionalSidesTask {
    /// Asks for the functional sides of `objects`.
    ///
    /// # Errors
    /// [`VlmError::InvalidTask`] when there is no object, an id is empty or spans lines, or two
    /// objects have the same id.
    pub fn new(objects: Vec<ObjectToDescribe>) -> Result<Self, VlmError> {
        if objects.is_empty() {
            return Err(VlmError::invalid_task(TASK, "no object to assess"));
        }
        let ids: Vec<String> = objects.iter().map(|o| o.id.clone()).collect();
        check_labels(TASK, "object id", &ids, |s| s.trim().to_owned())?;
        Ok(FunctionalSidesTask { objects })
    }
}

impl Task for FunctionalSidesTask {
    type Response = FunctionalSidesResponse;
    type Key = String;
    type Item = FunctionalSidesAnswer;

    fn kind(&self) -> TaskKind {
        TaskKind::ObjFunctionalSides
    }

    fn placeholders(&self) -> Vec<(&'static str, String)> {
        let lines: Vec<String> = self
            .objects
            .iter()
            .map(|o| {
                format!(
                    "obj_id: {}, obj_description: {}",
                    json_str(&o.id),
                    json_str(&o.description)
                )
            })
            .collect();
        vec![("OBJ_INFO", lines.join("\n"))]
    }

    fn keys(&self) -> Vec<String> {
        self.objects.iter().map(|o| o.id.clone()).collect()
    }

    fn validate(&self, r: FunctionalSidesResponse, out: &mut Validation<String, FunctionalSidesAnswer>) {
        for a in r.assessments {
            let Some(object) = self.objects.iter().find(|o| o.id.trim() == a.obj_id.trim()) else {
                out.general_problem(format!(
                    "an assessment has obj_id {:?}, which is not one of the listed objects",
                    a.obj_id
                ));
                continue;
            };
            let mut sides = Vec::new();
            let mut bad = Vec::new();
            for name in &a.functional_sides {
                match name.parse::<Side>() {
                    Ok(s) if Side::HORIZONTAL.contains(&s) => sides.push(s),
                    _ => bad.push(name.as_str()),
                }
            }
            if !bad.is_empty() {
                out.problem(
                    object.id.clone(),
                    format!("functional_sides {bad:?} are not among front, back, left, right"),
                );
                continue;
            }
            sides.sort();
            sides.dedup();
            out.answer(
                object.id.clone(),
                FunctionalSidesAnswer {
                    sides,
                    reason: a.reason,
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn object(id: &str) -> ObjectToDescribe {
        ObjectToDescribe {
            id: id.into(),
            description: format!("{id} description"),
        }
    }

    fn assessment(id: &str, sides: &[&str]) -> FunctionalSidesAssessment {
        FunctionalSidesAssessment {
            obj_id: id.into(),
            obj_description: String::new(),
            functional_sides: sides.iter().map(|s| s.to_string()).collect(),
            reason: String::new(),
        }
    }

    #[test]
    fn sides_are_checked_and_paired_by_id() {
        let task =
            FunctionalSidesTask::new(vec![object("bed_0"), object("cup_1"), object("desk_2")]).unwrap();
        let mut v = Validation::new();
        task.validate(
            FunctionalSidesResponse {
                assessments: vec![
                    assessment("desk_2", &["front", "Front"]),
                    assessment("bed_0", &["right", "front", "left"]),
                    assessment("cup_1", &["up"]),
                    assessment("lamp_9", &[]),
                ],
            },
            &mut v,
        );
        assert_eq!(v.item(&"desk_2".to_owned()).unwrap().sides, [Side::Front]);
        assert_eq!(
            v.item(&"bed_0".to_owned()).unwrap().sides,
            [Side::Left, Side::Right, Side::Front]
        );
        assert!(v.problems_for(&"cup_1".to_owned())[0].contains("\"up\""));
        assert!(v.general_problems()[0].contains("lamp_9"));
        let lines = &task.placeholders()[0].1;
        assert_eq!(lines.lines().count(), 3);
        assert!(lines.starts_with("obj_id: \"bed_0\", obj_description: \"bed_0 description\""));
    }

    #[test]
    fn builder_checks() {
        assert!(FunctionalSidesTask::new(vec![]).is_err());
        assert!(FunctionalSidesTask::new(vec![object("a"), object("a ")]).is_err());
    }
}
