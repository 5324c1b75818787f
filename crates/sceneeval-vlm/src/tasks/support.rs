//! `obj_support_type`: what does the pictured object rest on?

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use sceneeval_scene::SupportType;

use crate::PngImage;
use crate::TaskKind;
use crate::names::SupportTypeName;
use crate::task::{Single, Task, Validation};

/// The answer of `obj_support_type` as the model writes it (the reference's fields).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SupportTypeResponse {
    /// `ground`, `wall`, `ceiling` or `object` (the schema lists them).
    #[schemars(with = "SupportTypeName")]
    pub support_type: String,
    /// Why.
    pub reason: String,
}

/// The `obj_support_type` task for one object: its front view and a wider view of its
/// surroundings.
#[derive(Debug, Clone)]
pub struct SupportTypeTask {
    front: PngImage,
    surroundings: PngImage,
}

/// A validated `obj_support_type` answer.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SupportTypeAnswer {
    /// What the object rests on.
    pub support_type: SupportType,
    /// The model's reason.
    pub reason: String,
}

impl SupportTypeTask {
    /// Asks for the support type of the object pictured in `front` and `surroundings`.
    pub fn new(front: PngImage, surroundings: PngImage) -> Self {
        SupportTypeTask { front, surroundings }
    }
}

impl Task for SupportTypeTask {
    type Response = SupportTypeResponse;
    type Key = Single;
    type Item = SupportTypeAnswer;

    fn kind(&self) -> TaskKind {
        TaskKind::ObjSupportType
    }

    fn images(&self) -> Vec<PngImage> {
        vec![self.front.clone(), self.surroundings.clone()]
    }

    fn keys(&self) -> Vec<Single> {
        vec![Single]
    }

    fn validate(&self, r: SupportTypeResponse, out: &mut Validation<Single, SupportTypeAnswer>) {
        match r.support_type.parse::<SupportType>() {
            Ok(support_type) => out.answer(
                Single,
                SupportTypeAnswer {
                    support_type,
                    reason: r.reason,
                },
            ),
            Err(_) => out.problem(
                Single,
                format!(
                    "support_type {:?} is not one of ground, wall, ceiling, object",
                    r.support_type
                ),
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::test_image;

    #[test]
    fn support_type_names() {
        let task = SupportTypeTask::new(test_image(), test_image());
        let mut v = Validation::new();
        task.validate(
            SupportTypeResponse {
                support_type: "Wall".into(),
                reason: "hangs".into(),
            },
            &mut v,
        );
        assert_eq!(v.item(&Single).unwrap().support_type, SupportType::Wall);
        let mut v = Validation::new();
        task.validate(
            SupportTypeResponse {
                support_type: "shelf".into(),
                reason: String::new(),
            },
            &mut v,
        );
        assert!(v.problems_for(&Single)[0].contains("\"shelf\""));
    }
}
