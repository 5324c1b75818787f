//! Where support types and functional sides come from.
//!
//! The support metric needs each object's **support type** (what it should rest on) and the
//! accessibility metric each object's **functional sides** (which sides must stay free). The
//! reference asks a VLM for both. Here they come from a source behind an object-safe trait, so
//! the same metric runs on answers given by the caller ([`GivenSupportTypes`],
//! [`GivenFunctionalSides`]), on answers the scene file states per object ([`Stated`], from
//! the sceneState fields `supportType` and `functionalSides`), on built-in category tables
//! ([`SupportTypePriors`], [`FunctionalSidePriors`]), or later on a VLM, and sources can be
//! chained with [`Chain`] (the first source that knows an object answers). The default
//! ([`crate::Sources::default`]) asks the scene first, then the category tables.
//!
//! A source never looks at the geometry the metric checks: deriving "resting on the floor" from
//! the fact that the object touches the floor would make the support metric vacuous.
//!
//! # Unknown answers
//! - Support: an object no source knows is checked as `ground`, the reference's handling of a
//!   VLM refusal, and its [`crate::ObjectSupport::type_source`] is `None`.
//! - Accessibility: an object no source knows is skipped, like the reference's `-1`, and
//!   reported with `sides_known = false`.

use std::collections::BTreeMap;

use sceneeval_geom::Side;
use sceneeval_scene::{ObjectId, Scene, SceneObject};
use serde::{Deserialize, Serialize};

pub use sceneeval_scene::SupportType;
pub use tables::{FUNCTIONAL_SIDES_TABLE, FunctionalSidePriors, SUPPORT_TYPE_TABLE, SupportTypePriors};

mod tables;

/// A source's answer together with the source's name, kept as evidence in the reports.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Answer<T> {
    /// The answer.
    pub value: T,
    /// Which source gave it (e.g. `given`, `category_prior`).
    pub source: String,
}

/// A question a [`Source`] answers about one object: [`SupportTypeOf`] or
/// [`FunctionalSidesOf`] (a VLM-backed source may answer both).
pub trait Question: 'static {
    /// The answer's type.
    type Value: Clone + std::fmt::Debug + Send + Sync + 'static;
}

/// The question "what should this object rest on?" ([`SupportType`]), asked by the support
/// metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SupportTypeOf {}

impl Question for SupportTypeOf {
    type Value = SupportType;
}

/// The question "which sides of this object must stay free to use it?" (a subset of front,
/// back, left and right; empty for an object without one, such as a cup), asked by the
/// accessibility metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FunctionalSidesOf {}

impl Question for FunctionalSidesOf {
    type Value = Vec<Side>;
}

/// Answers question `Q` about an object of a scene, or `None` when it does not know.
///
/// Implementations must not derive the answer from the object's placement (that is what the
/// metrics check). They get the scene so that a VLM-backed source can render it. Implement it
/// once per question the source answers; [`Chain`], `Box` and `Arc` forward it.
///
/// ```
/// use sceneeval_plausibility::{Answer, Source, SupportType, SupportTypeOf};
/// use sceneeval_scene::{Scene, SceneObject};
///
/// /// Everything hangs from the ceiling.
/// struct Ceilings;
///
/// impl Source<SupportTypeOf> for Ceilings {
///     fn answer(&self, _scene: &Scene, _object: &SceneObject) -> Option<Answer<SupportType>> {
///         Some(Answer { value: SupportType::Ceiling, source: "ceilings".into() })
///     }
/// }
/// # let _ = Ceilings;
/// ```
pub trait Source<Q: Question>: Send + Sync {
    /// The answer for `object` in `scene`, with the source's name.
    fn answer(&self, scene: &Scene, object: &SceneObject) -> Option<Answer<Q::Value>>;
}

/// Shorthand for a [`Source`] of support types (implemented for every one), with the
/// question in its method's name.
pub trait SupportTypeSource: Source<SupportTypeOf> {
    /// The support type of `object` in `scene`, with the source's name.
    fn support_type(&self, scene: &Scene, object: &SceneObject) -> Option<Answer<SupportType>> {
        self.answer(scene, object)
    }
}

impl<T: Source<SupportTypeOf>> SupportTypeSource for T {}

/// Shorthand for a [`Source`] of functional sides (implemented for every one), with the
/// question in its method's name.
pub trait FunctionalSidesSource: Source<FunctionalSidesOf> {
    /// The functional sides of `object` in `scene`, with the source's name.
    fn functional_sides(&self, scene: &Scene, object: &SceneObject) -> Option<Answer<Vec<Side>>> {
        self.answer(scene, object)
    }
}

impl<T: Source<FunctionalSidesOf>> FunctionalSidesSource for T {}

/// The first of two sources that knows the answer: `first`, else `second`.
///
/// ```
/// use sceneeval_plausibility::{Chain, GivenSupportTypes, SupportType, SupportTypePriors};
/// let mut given = GivenSupportTypes::default();
/// given.insert("lamp_1", SupportType::Ceiling);
/// let source = Chain::new(given, SupportTypePriors::default());
/// # let _ = source;
/// ```
#[derive(Debug, Clone, Default)]
pub struct Chain<A, B> {
    /// Asked first.
    pub first: A,
    /// Asked when `first` does not know.
    pub second: B,
}

impl<A, B> Chain<A, B> {
    /// `first`, falling back to `second`.
    pub fn new(first: A, second: B) -> Self {
        Chain { first, second }
    }
}

impl<Q: Question, A: Source<Q>, B: Source<Q>> Source<Q> for Chain<A, B> {
    fn answer(&self, scene: &Scene, object: &SceneObject) -> Option<Answer<Q::Value>> {
        self.first
            .answer(scene, object)
            .or_else(|| self.second.answer(scene, object))
    }
}

impl<Q: Question, T: Source<Q> + ?Sized> Source<Q> for Box<T> {
    fn answer(&self, scene: &Scene, object: &SceneObject) -> Option<Answer<Q::Value>> {
        (**self).answer(scene, object)
    }
}

impl<Q: Question, T: Source<Q> + ?Sized> Source<Q> for std::sync::Arc<T> {
    fn answer(&self, scene: &Scene, object: &SceneObject) -> Option<Answer<Q::Value>> {
        (**self).answer(scene, object)
    }
}

/// Support types given by the caller, by object id (for example a cached VLM assessment).
/// Answers carry the source name `given`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct GivenSupportTypes {
    /// Object id to support type.
    pub types: BTreeMap<ObjectId, SupportType>,
}

impl GivenSupportTypes {
    /// Sets the type of one object.
    pub fn insert(&mut self, id: impl Into<ObjectId>, support_type: SupportType) -> &mut Self {
        self.types.insert(id.into(), support_type);
        self
    }
}

impl Source<SupportTypeOf> for GivenSupportTypes {
    fn answer(&self, _scene: &Scene, object: &SceneObject) -> Option<Answer<SupportType>> {
        self.types.get(object.id()).map(|&value| Answer {
            value,
            source: "given".to_owned(),
        })
    }
}

/// Functional sides given by the caller, by object id. Only horizontal sides (front, back,
/// left, right) are meaningful; others are ignored by the metric. Source name `given`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct GivenFunctionalSides {
    /// Object id to functional sides (possibly empty).
    pub sides: BTreeMap<ObjectId, Vec<Side>>,
}

impl GivenFunctionalSides {
    /// Sets the sides of one object.
    pub fn insert(&mut self, id: impl Into<ObjectId>, sides: Vec<Side>) -> &mut Self {
        self.sides.insert(id.into(), sides);
        self
    }
}

impl Source<FunctionalSidesOf> for GivenFunctionalSides {
    fn answer(&self, _scene: &Scene, object: &SceneObject) -> Option<Answer<Vec<Side>>> {
        self.sides.get(object.id()).map(|s| Answer {
            value: s.clone(),
            source: "given".to_owned(),
        })
    }
}

/// The support types and functional sides the scene itself states per object
/// ([`SceneObject::support_type`], [`SceneObject::functional_sides`]; in a sceneState file the
/// object fields `supportType` and `functionalSides`), for generators that know what they
/// placed. Source name `scene`.
///
/// ```
/// use sceneeval_geom::{conventions::pose_from_yaw, Point3, Vector3};
/// use sceneeval_plausibility::{Stated, SupportType, SupportTypeSource};
/// use sceneeval_scene::{Scene, SceneObject};
///
/// let tv = SceneObject::new_box("tv", Vector3::new(0.6, 0.05, 0.35), pose_from_yaw(Point3::new(2.0, 4.95, 1.4), 0.0))
///     .unwrap()
///     .with_category("tv")
///     .with_support_type(SupportType::Wall);
/// let scene = Scene::builder().object(tv).build().unwrap();
/// let answer = Stated.support_type(&scene, &scene.objects()[0]).unwrap();
/// assert_eq!((answer.value, answer.source.as_str()), (SupportType::Wall, "scene"));
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stated;

impl Source<SupportTypeOf> for Stated {
    fn answer(&self, _scene: &Scene, object: &SceneObject) -> Option<Answer<SupportType>> {
        object.support_type().map(|value| Answer {
            value,
            source: "scene".to_owned(),
        })
    }
}

impl Source<FunctionalSidesOf> for Stated {
    fn answer(&self, _scene: &Scene, object: &SceneObject) -> Option<Answer<Vec<Side>>> {
        object.functional_sides().map(|sides| Answer {
            value: sides.to_vec(),
            source: "scene".to_owned(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::conventions::pose_from_yaw;

    #[test]
    fn default_sources_ask_the_scene_before_the_tables() {
        use sceneeval_geom::{Point3, Vector3};
        let tv = |id: &str| {
            SceneObject::new_box(
                id,
                Vector3::new(0.5, 0.05, 0.3),
                pose_from_yaw(Point3::new(0.0, 0.0, 1.0), 0.0),
            )
            .unwrap()
            .with_category("tv")
        };
        let scene = Scene::builder()
            .object(tv("stand_tv"))
            .object(
                tv("wall_tv")
                    .with_support_type(SupportType::Wall)
                    .with_functional_sides([]),
            )
            .build()
            .unwrap();
        let sources = crate::Sources::default();
        let support = |i: usize| sources.support_types.support_type(&scene, &scene.objects()[i]);
        let sides = |i: usize| {
            sources
                .functional_sides
                .functional_sides(&scene, &scene.objects()[i])
        };
        // Not stated: the category prior (a TV stands on furniture; no side prior for TVs).
        let prior = support(0).unwrap();
        assert_eq!(
            (prior.value, prior.source.as_str()),
            (SupportType::Object, "category_prior")
        );
        assert!(sides(0).is_none());
        // Stated in the scene: wins, even an empty side list.
        let stated = support(1).unwrap();
        assert_eq!(
            (stated.value, stated.source.as_str()),
            (SupportType::Wall, "scene")
        );
        let stated = sides(1).unwrap();
        assert_eq!((stated.value.len(), stated.source.as_str()), (0, "scene"));
    }
}
