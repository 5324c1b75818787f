//! `obj_attribute`: which pictured instances of a category satisfy the attributes?

use std::fmt;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{check_labels, find_label, json_list, json_str, norm};
use crate::TaskKind;
use crate::task::{Task, Validation};
use crate::{PngImage, VlmError};

const TASK: &str = TaskKind::ObjAttribute.name();

/// The answer of `obj_attribute` as the model writes it (the reference's fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObjAttributeResponse {
    /// The category, echoed (not checked).
    pub category: String,
    /// How many instances the model saw; a count different from the number pictured is logged
    /// as a warning (the per-instance assessments are what counts).
    pub num_instances: i64,
    /// One assessment per (instance, attribute).
    pub assessments: Vec<ObjAttributeAssessment>,
}

/// One assessment of an `obj_attribute` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObjAttributeAssessment {
    /// The instance, counting the pictured objects from 0 in image order.
    pub instance: i64,
    /// The attribute, echoed from the list of requirements.
    pub attribute: String,
    /// Whether the instance has the attribute.
    pub satisfied: bool,
    /// Why.
    pub reason: String,
}

/// The two views of one instance.
#[derive(Debug, Clone)]
pub struct InstanceViews {
    /// The front view.
    pub front: PngImage,
    /// The view with a 170 cm human figure for scale.
    pub size: PngImage,
}

/// The `obj_attribute` task for the matched instances of one category (one ObjAttr entry).
///
/// The reference asks with a single attribute per entry; several attributes are supported
/// here, each assessed per instance.
#[derive(Debug, Clone)]
pub struct AttributeTask {
    category: String,
    attributes: Vec<String>,
    instances: Vec<InstanceViews>,
}

/// The question "does instance `instance` have attribute `attribute`?".
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct AttributeKey {
    /// The instance, from 0, in the order the instances were given.
    pub instance: usize,
    /// The attribute, in the caller's spelling.
    pub attribute: String,
}

impl fmt::Display for AttributeKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "instance {} / attribute {:?}", self.instance, self.attribute)
    }
}

/// A validated assessment of one instance and attribute.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct AttributeVerdict {
    /// Whether the instance has the attribute.
    pub satisfied: bool,
    /// The model's reason.
    pub reason: String,
}

impl AttributeTask {
    /// Asks which of `instances` (all of category `category`) have each of `attributes`.
    ///
    /// # Errors
    /// [`VlmError::InvalidTask`] when the category is empty, there is no attribute or no
    /// instance, or two attributes are the same.
    pub fn new(
        category: impl Into<String>,
        attributes: impl IntoIterator<Item = impl Into<String>>,
        instances: Vec<InstanceViews>,
    ) -> Result<Self, VlmError> {
        let category = category.into();
        let attributes: Vec<String> = attributes.into_iter().map(Into::into).collect();
        check_labels(TASK, "category", std::slice::from_ref(&category), norm)?;
        if attributes.is_empty() {
            return Err(VlmError::invalid_task(TASK, "no attribute to assess"));
        }
        check_labels(TASK, "attribute", &attributes, norm)?;
        if instances.is_empty() {
            return Err(VlmError::invalid_task(TASK, "no instance pictured"));
        }
        Ok(AttributeTask {
            category,
            attributes,
            instances,
        })
    }
}

impl Task for AttributeTask {
    type Response = ObjAttributeResponse;
    type Key = AttributeKey;
    type Item = AttributeVerdict;

    fn kind(&self) -> TaskKind {
        TaskKind::ObjAttribute
    }

    fn placeholders(&self) -> Vec<(&'static str, String)> {
        vec![
            ("OBJ_ATTRIBUTES", json_list(&self.attributes)),
            ("OBJ_COUNT", self.instances.len().to_string()),
            ("OBJ_CATEGORY", json_str(&self.category)),
        ]
    }

    fn images(&self) -> Vec<PngImage> {
        self.instances
            .iter()
            .flat_map(|i| [i.front.clone(), i.size.clone()])
            .collect()
    }

    fn keys(&self) -> Vec<AttributeKey> {
        (0..self.instances.len())
            .flat_map(|instance| {
                self.attributes.iter().map(move |a| AttributeKey {
                    instance,
                    attribute: a.clone(),
                })
            })
            .collect()
    }

    fn validate(&self, r: ObjAttributeResponse, out: &mut Validation<AttributeKey, AttributeVerdict>) {
        let n = self.instances.len();
        if r.num_instances != n as i64 {
            tracing::warn!(category = %self.category, said = r.num_instances, pictured = n, "num_instances differs");
        }
        for a in r.assessments {
            let Some(attribute) = find_label(&self.attributes, &a.attribute) else {
                out.general_problem(format!(
                    "an assessment names attribute {:?}, which is not one of {}",
                    a.attribute,
                    json_list(&self.attributes)
                ));
                continue;
            };
            let instance = match usize::try_from(a.instance) {
                Ok(i) if i < n => i,
                _ => {
                    out.general_problem(format!(
                        "an assessment names instance {}, but the instances are numbered 0 to {}",
                        a.instance,
                        n - 1
                    ));
                    continue;
                }
            };
            let key = AttributeKey {
                instance,
                attribute: attribute.to_owned(),
            };
            out.answer(
                key,
                AttributeVerdict {
                    satisfied: a.satisfied,
                    reason: a.reason,
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::test_image;

    fn views() -> InstanceViews {
        InstanceViews {
            front: test_image(),
            size: test_image(),
        }
    }

    fn assessment(instance: i64, attribute: &str, satisfied: bool) -> ObjAttributeAssessment {
        ObjAttributeAssessment {
            instance,
            attribute: attribute.into(),
            satisfied,
            reason: String::new(),
        }
    }

    #[test]
    fn pairs_by_instance_and_attribute() {
        let task = AttributeTask::new("chair", ["red", "wooden"], vec![views(), views()]).unwrap();
        assert_eq!(task.images().len(), 4);
        assert_eq!(task.keys().len(), 4);
        let mut v = Validation::new();
        task.validate(
            ObjAttributeResponse {
                category: "chair".into(),
                num_instances: 2,
                assessments: vec![
                    assessment(1, "Wooden", true),
                    assessment(0, "red", false),
                    assessment(1, "red", true),
                    assessment(2, "red", true),
                    assessment(0, "blue", true),
                ],
            },
            &mut v,
        );
        v.finish(&task.keys());
        let key = |i, a: &str| AttributeKey {
            instance: i,
            attribute: a.into(),
        };
        assert!(v.item(&key(1, "wooden")).unwrap().satisfied);
        assert!(!v.item(&key(0, "red")).unwrap().satisfied);
        assert!(v.item(&key(1, "red")).unwrap().satisfied);
        assert_eq!(
            v.problems_for(&key(0, "wooden")),
            ["no answer for instance 0 / attribute \"wooden\""]
        );
        assert_eq!(v.general_problems().len(), 2, "instance 2 and attribute blue");
    }

    #[test]
    fn builder_checks() {
        assert!(AttributeTask::new("chair", Vec::<String>::new(), vec![views()]).is_err());
        assert!(AttributeTask::new("chair", ["red"], vec![]).is_err());
        assert!(AttributeTask::new("", ["red"], vec![views()]).is_err());
        assert!(AttributeTask::new("chair", ["red", "Red"], vec![views()]).is_err());
    }
}
