//! The VLM's answers for the plausibility metrics: each object's support type (from its front
//! and surroundings views, one request per object) and functional sides (from the objects'
//! descriptions, one request per scene), as the reference asks them. The facade slots them
//! into the plausibility metrics' sources after what the scene states and before the category
//! tables.

use std::collections::BTreeMap;

use sceneeval_geom::Side;
use sceneeval_scene::{Scene, SceneObject, SupportType};
use sceneeval_vlm::tasks::{FunctionalSidesTask, ObjectToDescribe, SupportTypeTask};
use sceneeval_vlm::{Outcome, Session, Vlm};

use crate::FidelityError;
use crate::matching::vlm_err;
use crate::views::{ObjectViews, ViewKind};

/// The VLM's support types (object id -> type); objects without a valid answer are left out
/// (the next source answers for them). Objects for which `skip` holds are not asked.
///
/// # Errors
/// [`FidelityError::View`], [`FidelityError::Vlm`] (no answer at all).
pub fn ask_support_types<V: Vlm>(
    scene: &Scene,
    session: &Session<V>,
    views: &dyn ObjectViews,
    skip: impl Fn(&SceneObject) -> bool,
) -> Result<BTreeMap<String, SupportType>, FidelityError> {
    let mut out = BTreeMap::new();
    for o in scene.objects().iter().filter(|o| !skip(o)) {
        let id = o.id().as_str();
        let task = SupportTypeTask::new(
            views.view(id, ViewKind::Front)?,
            views.view(id, ViewKind::Surroundings)?,
        );
        let answers = pollster::block_on(session.ask(&task)).map_err(|e| vlm_err("obj_support_type", e))?;
        match answers.into_single() {
            Some(Outcome::Answered { answer, .. }) => {
                out.insert(id.to_owned(), answer.support_type);
            }
            Some(Outcome::Unanswered(why)) => {
                tracing::warn!(object = id, reason = %why, "no support type from the VLM");
            }
            None => {}
        }
    }
    Ok(out)
}

/// The VLM's functional sides (object id -> sides) of the objects that have a description
/// (else a category) and for which `skip` does not hold, in one request; objects without a
/// valid answer are left out.
///
/// # Errors
/// [`FidelityError::Vlm`] (no answer at all).
pub fn ask_functional_sides<V: Vlm>(
    scene: &Scene,
    session: &Session<V>,
    skip: impl Fn(&SceneObject) -> bool,
) -> Result<BTreeMap<String, Vec<Side>>, FidelityError> {
    let objects: Vec<ObjectToDescribe> = scene
        .objects()
        .iter()
        .filter(|o| !skip(o))
        .filter_map(|o| {
            let description = o.description().or(o.category())?;
            Some(ObjectToDescribe {
                id: o.id().as_str().to_owned(),
                description: description.to_owned(),
            })
        })
        .collect();
    if objects.is_empty() {
        return Ok(BTreeMap::new());
    }
    let task = FunctionalSidesTask::new(objects).map_err(|e| vlm_err("obj_functional_sides", e))?;
    let answers = pollster::block_on(session.ask(&task)).map_err(|e| vlm_err("obj_functional_sides", e))?;
    let mut out = BTreeMap::new();
    for (id, outcome) in answers.outcomes {
        match outcome {
            Outcome::Answered { answer, .. } => {
                out.insert(id, answer.sides);
            }
            Outcome::Unanswered(why) => {
                tracing::warn!(object = %id, reason = %why, "no functional sides from the VLM");
            }
        }
    }
    Ok(out)
}
