//! `category_matching_for_semantic_color`: scene categories onto the categories of a colour
//! reference.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{check_labels, find_label, json_list, norm};
use crate::TaskKind;
use crate::VlmError;
use crate::task::{Task, Validation};

const TASK: &str = TaskKind::CategoryMatchingForSemanticColor.name();

/// The answer of `category_matching_for_semantic_color` as the model writes it (the
/// reference's fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CategoryMatchingResponse {
    /// One assessment per input category.
    pub assessments: Vec<CategoryMatchingAssessment>,
}

/// One assessment of a `category_matching_for_semantic_color` answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CategoryMatchingAssessment {
    /// The input category, echoed: pairs the assessment with its question.
    pub input_category: String,
    /// Whether it matches a reference category.
    pub matched: bool,
    /// The reference category when `matched`, else `""`.
    pub matched_reference_category: String,
    /// Why.
    pub reason: String,
}

/// The `category_matching_for_semantic_color` task: which reference category each input
/// category corresponds to.
#[derive(Debug, Clone)]
pub struct CategoryMatchingTask {
    reference: Vec<String>,
    input: Vec<String>,
}

/// A validated match of one input category.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ReferenceMatch {
    /// The reference category (in the caller's spelling), or `None`.
    pub reference_category: Option<String>,
    /// The model's reason.
    pub reason: String,
}

impl CategoryMatchingTask {
    /// Matches each of `input` to one of `reference`.
    ///
    /// # Errors
    /// [`VlmError::InvalidTask`] when either list is empty or has two equal entries.
    pub fn new(
        reference: impl IntoIterator<Item = impl Into<String>>,
        input: impl IntoIterator<Item = impl Into<String>>,
    ) -> Result<Self, VlmError> {
        let reference: Vec<String> = reference.into_iter().map(Into::into).collect();
        let input: Vec<String> = input.into_iter().map(Into::into).collect();
        if reference.is_empty() || input.is_empty() {
            return Err(VlmError::invalid_task(
                TASK,
                "the reference and input lists must not be empty",
            ));
        }
        check_labels(TASK, "reference category", &reference, norm)?;
        check_labels(TASK, "input category", &input, norm)?;
        Ok(CategoryMatchingTask { reference, input })
    }
}

impl Task for CategoryMatchingTask {
    type Response = CategoryMatchingResponse;
    type Key = String;
    type Item = ReferenceMatch;

    fn kind(&self) -> TaskKind {
        TaskKind::CategoryMatchingForSemanticColor
    }

    fn placeholders(&self) -> Vec<(&'static str, String)> {
        vec![
            ("REFERENCE_CATEGORIES", json_list(&self.reference)),
            ("INPUT_CATEGORIES", json_list(&self.input)),
        ]
    }

    fn keys(&self) -> Vec<String> {
        self.input.clone()
    }

    fn validate(&self, r: CategoryMatchingResponse, out: &mut Validation<String, ReferenceMatch>) {
        for a in r.assessments {
            let Some(input) = find_label(&self.input, &a.input_category) else {
                out.general_problem(format!(
                    "an assessment has input_category {:?}, which is not one of {}",
                    a.input_category,
                    json_list(&self.input)
                ));
                continue;
            };
            let reference_category = if a.matched {
                match find_label(&self.reference, &a.matched_reference_category) {
                    Some(r) => Some(r.to_owned()),
                    None => {
                        out.problem(
                            input.to_owned(),
                            format!(
                                "matched_reference_category {:?} is not one of the reference categories {}",
                                a.matched_reference_category,
                                json_list(&self.reference)
                            ),
                        );
                        continue;
                    }
                }
            } else {
                None
            };
            out.answer(
                input.to_owned(),
                ReferenceMatch {
                    reference_category,
                    reason: a.reason,
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assessment(input: &str, matched: bool, reference: &str) -> CategoryMatchingAssessment {
        CategoryMatchingAssessment {
            input_category: input.into(),
            matched,
            matched_reference_category: reference.into(),
            reason: String::new(),
        }
    }

    #[test]
    fn matches_are_checked() {
        let task = CategoryMatchingTask::new(["chair", "table"], ["armchair", "desk", "rug"]).unwrap();
        let mut v = Validation::new();
        task.validate(
            CategoryMatchingResponse {
                assessments: vec![
                    assessment("rug", false, ""),
                    assessment("Armchair", true, "chair"),
                    assessment("desk", true, "bench"),
                    assessment("lamp", false, ""),
                ],
            },
            &mut v,
        );
        assert_eq!(
            v.item(&"armchair".to_owned())
                .unwrap()
                .reference_category
                .as_deref(),
            Some("chair")
        );
        assert_eq!(v.item(&"rug".to_owned()).unwrap().reference_category, None);
        assert!(v.problems_for(&"desk".to_owned())[0].contains("\"bench\""));
        assert!(v.general_problems()[0].contains("\"lamp\""));
        assert!(CategoryMatchingTask::new(Vec::<String>::new(), ["a"]).is_err());
    }
}
