//! The VLM's answers for the plausibility metrics: each object's support type (from its front
//! and surroundings views, one request per object) and functional sides (from the objects'
//! descriptions, one request per scene), as the reference asks them. The facade slots them
//! into the plausibility metrics' sources after what the scene states and before the category
//! tables, and records per object where its values came from and why.
//!
//! Every question is asked together ([`ask_support_types`] and [`ask_functional_sides`] are
//! `async`; the facade awaits both at once, with the fidelity metrics' questions). Each object
//! gets an [`Asked`]: the answer, why there is none, or the failure of its request (which the
//! facade records as an incomplete metric).

use std::collections::BTreeMap;
use std::sync::Arc;

use futures_util::future::join_all;
use sceneeval_geom::Side;
use sceneeval_scene::{Scene, SceneObject, SupportType};
use sceneeval_vlm::tasks::{FunctionalSidesTask, ObjectToDescribe, SupportTypeTask};
use sceneeval_vlm::{Outcome, Session, Unanswered, Vlm};

use crate::FidelityError;
use crate::matching::{vlm_err, with_note};
use crate::views::{ObjectViews, ViewKind};

/// What asking the VLM about one object gave.
#[derive(Debug, Clone)]
pub enum Asked<T> {
    /// A valid answer and the model's reason (with the note of how an imperfect answer was
    /// recovered, if it was).
    Answered {
        /// The value.
        value: T,
        /// The model's reason.
        reason: String,
    },
    /// The model answered, but not validly (invalid twice, refused, truncated).
    Unanswered(Unanswered),
    /// The request got no answer at all, or its view could not be made.
    Failed(Arc<FidelityError>),
}

impl<T> Asked<T> {
    /// The value, when answered.
    pub fn value(&self) -> Option<&T> {
        match self {
            Asked::Answered { value, .. } => Some(value),
            Asked::Unanswered(_) | Asked::Failed(_) => None,
        }
    }

    fn from_outcome<I>(outcome: Outcome<I>, part: impl FnOnce(I) -> (T, String)) -> Self {
        match outcome {
            Outcome::Answered { answer, note, .. } => {
                let (value, reason) = part(answer);
                Asked::Answered {
                    value,
                    reason: with_note(reason, note),
                }
            }
            Outcome::Unanswered(why) => Asked::Unanswered(why),
        }
    }
}

/// The VLM's support type of every object for which `skip` does not hold (object id ->
/// what asking gave), all asked together.
pub async fn ask_support_types<V: Vlm>(
    scene: &Scene,
    session: &Session<V>,
    views: &dyn ObjectViews,
    skip: impl Fn(&SceneObject) -> bool,
) -> BTreeMap<String, Asked<SupportType>> {
    let objects: Vec<&SceneObject> = scene.objects().iter().filter(|o| !skip(o)).collect();
    let asks = objects.iter().map(|o| async move {
        let id = o.id().as_str();
        let task = SupportTypeTask::new(
            views.view(id, ViewKind::Front)?,
            views.view(id, ViewKind::Surroundings)?,
        );
        let answers = session
            .ask(&task)
            .await
            .map_err(|e| vlm_err("obj_support_type", e))?;
        Ok::<_, FidelityError>(answers.into_single())
    });
    let outcomes = join_all(asks).await;
    let mut out = BTreeMap::new();
    for (o, outcome) in objects.iter().zip(outcomes) {
        let id = o.id().as_str().to_owned();
        let asked = match outcome {
            Ok(Some(outcome)) => Asked::from_outcome(outcome, |a| (a.support_type, a.reason)),
            Ok(None) => continue,
            Err(e) => Asked::Failed(Arc::new(e)),
        };
        match &asked {
            Asked::Unanswered(why) => {
                tracing::warn!(object = %id, reason = %why, "no support type from the VLM")
            }
            Asked::Failed(e) => tracing::warn!(object = %id, error = %e, "the support type question failed"),
            Asked::Answered { .. } => {}
        }
        out.insert(id, asked);
    }
    out
}

/// The VLM's functional sides (object id -> what asking gave) of the objects that have a
/// description (else a category) and for which `skip` does not hold, in one request; the
/// others are not asked (not in the map).
pub async fn ask_functional_sides<V: Vlm>(
    scene: &Scene,
    session: &Session<V>,
    skip: impl Fn(&SceneObject) -> bool,
) -> BTreeMap<String, Asked<Vec<Side>>> {
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
        return BTreeMap::new();
    }
    let ids: Vec<String> = objects.iter().map(|o| o.id.clone()).collect();
    let answers = match FunctionalSidesTask::new(objects) {
        Ok(task) => session.ask(&task).await,
        Err(e) => Err(e),
    };
    match answers {
        Ok(answers) => answers
            .outcomes
            .into_iter()
            .map(|(id, outcome)| {
                if let Outcome::Unanswered(why) = &outcome {
                    tracing::warn!(object = %id, reason = %why, "no functional sides from the VLM");
                }
                (id, Asked::from_outcome(outcome, |a| (a.sides, a.reason)))
            })
            .collect(),
        Err(e) => {
            let e = Arc::new(vlm_err("obj_functional_sides", e));
            tracing::warn!(error = %e, "the functional sides question failed");
            ids.into_iter().map(|id| (id, Asked::Failed(e.clone()))).collect()
        }
    }
}
