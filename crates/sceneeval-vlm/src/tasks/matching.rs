//! `obj_matching`: does the pictured object belong to one of the annotated categories?

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use sceneeval_geom::Vector3;

use super::{check_labels, find_label, json_list, norm};
use crate::TaskKind;
use crate::prompt::Template;
use crate::task::{Single, Task, Validation};
use crate::{PngImage, VlmError};

const TASK: &str = TaskKind::ObjMatching.name();

/// The answer of `obj_matching` as the model writes it (the reference's fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObjMatchingResponse {
    /// The categories offered, echoed (not checked).
    pub provided_categories: Vec<String>,
    /// Whether the object belongs to one of them.
    pub matched: bool,
    /// The category it belongs to when `matched`, else `""`.
    pub matched_category: String,
    /// What the object actually is, in the model's words.
    pub actual_category: String,
    /// Why.
    pub reason: String,
}

/// The size of an object for the size-aware matching prompt: the extents of its box in its own
/// frame (x width, y depth, z height), in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObjectDimensions {
    /// Full extents in metres (not half extents).
    pub extents_m: Vector3,
}

impl ObjectDimensions {
    /// The prompt line, in centimetres with one decimal, as the SceneSmith fork writes it:
    /// `Width: 85.0 cm, Depth: 50.0 cm, Height: 95.0 cm`.
    ///
    /// ```
    /// use sceneeval_vlm::tasks::ObjectDimensions;
    /// use sceneeval_geom::Vector3;
    /// let d = ObjectDimensions { extents_m: Vector3::new(0.85, 0.5, 0.953) };
    /// assert_eq!(d.prompt_text(), "Width: 85.0 cm, Depth: 50.0 cm, Height: 95.3 cm");
    /// ```
    pub fn prompt_text(&self) -> String {
        let cm = self.extents_m * 100.0;
        format!(
            "Width: {:.1} cm, Depth: {:.1} cm, Height: {:.1} cm",
            cm.x, cm.y, cm.z
        )
    }
}

/// The `obj_matching` task for one object: its front view and the categories offered (the
/// annotation's ObjCount categories), optionally with its dimensions (the SceneSmith fork's
/// size-aware prompt, [`Template::ObjMatchingSized`](crate::prompt::Template::ObjMatchingSized)).
#[derive(Debug, Clone)]
pub struct ObjectMatchingTask {
    front: PngImage,
    categories: Vec<String>,
    dimensions: Option<ObjectDimensions>,
}

/// A validated `obj_matching` answer.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ObjectMatch {
    /// The offered category the object belongs to (in the caller's spelling), or `None`.
    pub category: Option<String>,
    /// What the object actually is, in the model's words.
    pub actual_category: String,
    /// The model's reason.
    pub reason: String,
}

impl ObjectMatchingTask {
    /// Matching of the object pictured in `front` against `categories`.
    ///
    /// # Errors
    /// [`VlmError::InvalidTask`] when no category is offered or two are the same (compared as
    /// in the [module docs](super)).
    pub fn new(
        front: PngImage,
        categories: impl IntoIterator<Item = impl Into<String>>,
    ) -> Result<Self, VlmError> {
        let categories: Vec<String> = categories.into_iter().map(Into::into).collect();
        if categories.is_empty() {
            return Err(VlmError::invalid_task(TASK, "no category offered"));
        }
        check_labels(TASK, "category", &categories, norm)?;
        Ok(ObjectMatchingTask {
            front,
            categories,
            dimensions: None,
        })
    }

    /// Uses the size-aware prompt with these dimensions.
    pub fn with_dimensions(mut self, dimensions: ObjectDimensions) -> Self {
        self.dimensions = Some(dimensions);
        self
    }

    /// The categories offered.
    pub fn categories(&self) -> &[String] {
        &self.categories
    }
}

impl Task for ObjectMatchingTask {
    type Response = ObjMatchingResponse;
    type Key = Single;
    type Item = ObjectMatch;

    fn kind(&self) -> TaskKind {
        TaskKind::ObjMatching
    }

    fn template(&self) -> Template {
        match self.dimensions {
            Some(_) => Template::ObjMatchingSized,
            None => Template::Task(TaskKind::ObjMatching),
        }
    }

    fn placeholders(&self) -> Vec<(&'static str, String)> {
        let mut values = vec![("TARGET_CATEGORIES", json_list(&self.categories))];
        if let Some(d) = &self.dimensions {
            values.push(("OBJECT_DIMENSIONS", d.prompt_text()));
        }
        values
    }

    fn images(&self) -> Vec<PngImage> {
        vec![self.front.clone()]
    }

    fn keys(&self) -> Vec<Single> {
        vec![Single]
    }

    fn validate(&self, r: ObjMatchingResponse, out: &mut Validation<Single, ObjectMatch>) {
        let category = if r.matched {
            match find_label(&self.categories, &r.matched_category) {
                Some(c) => Some(c.to_owned()),
                None => {
                    out.problem(
                        Single,
                        format!(
                            "matched_category {:?} is not one of the offered categories {}",
                            r.matched_category,
                            json_list(&self.categories)
                        ),
                    );
                    return;
                }
            }
        } else {
            if !r.matched_category.trim().is_empty() {
                tracing::debug!(matched_category = %r.matched_category, "matched is false; matched_category ignored");
            }
            None
        };
        out.answer(
            Single,
            ObjectMatch {
                category,
                actual_category: r.actual_category,
                reason: r.reason,
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::test_image;

    fn validate(task: &ObjectMatchingTask, r: ObjMatchingResponse) -> Validation<Single, ObjectMatch> {
        let mut v = Validation::new();
        task.validate(r, &mut v);
        v
    }

    fn response(matched: bool, category: &str) -> ObjMatchingResponse {
        ObjMatchingResponse {
            provided_categories: vec![],
            matched,
            matched_category: category.into(),
            actual_category: "chair".into(),
            reason: "r".into(),
        }
    }

    #[test]
    fn matched_category_must_be_offered() {
        let task = ObjectMatchingTask::new(test_image(), ["dining_chair", "table"]).unwrap();
        let v = validate(&task, response(true, "Dining Chair"));
        assert_eq!(v.item(&Single).unwrap().category.as_deref(), Some("dining_chair"));
        let v = validate(&task, response(true, "sofa"));
        assert!(v.item(&Single).is_none());
        assert!(v.problems_for(&Single)[0].contains("\"sofa\" is not one of"));
        let v = validate(&task, response(false, "whatever"));
        assert_eq!(v.item(&Single).unwrap().category, None);
    }

    #[test]
    fn builder_checks_and_prompt_variant() {
        assert!(ObjectMatchingTask::new(test_image(), Vec::<String>::new()).is_err());
        assert!(ObjectMatchingTask::new(test_image(), ["bed", "Bed"]).is_err());
        let task = ObjectMatchingTask::new(test_image(), ["bed"]).unwrap();
        assert_eq!(task.template(), Template::Task(TaskKind::ObjMatching));
        let sized = task.with_dimensions(ObjectDimensions {
            extents_m: Vector3::new(2.0, 1.6, 0.5),
        });
        assert_eq!(sized.template(), Template::ObjMatchingSized);
        assert!(
            sized
                .placeholders()
                .iter()
                .any(|(n, v)| *n == "OBJECT_DIMENSIONS" && v.contains("160.0 cm"))
        );
    }
}
