//! Scene-level evaluation: relations between scene objects by id, against the scene's rooms.

use sceneeval_geom::Real;
use sceneeval_scene::Scene;

use crate::dispatch::expect_kind;
use crate::{ObjectGeom, Operands, Relation, RelationError, RelationKind, RelationParams, Targets};

/// A relation's score and whether it holds (`score > threshold`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Evaluation {
    /// The score in `[0, 1]`.
    pub score: Real,
    /// Whether the score is above the threshold (0.5 by default).
    pub holds: bool,
}

/// One question about a scene by object ids: a relation, its target object(s), its anchor,
/// and for the floor-based architecture relations an optional choice of floors. Build it with
/// [`Query::new`] and the named setters, so that a target and an anchor cannot be swapped
/// unnoticed:
///
/// ```
/// use sceneeval_relations::{Query, Relation};
/// let q = Query::new(Relation::NextTo).target("stand").anchor("bed");
/// assert_eq!((q.targets[0].as_str(), q.anchor.as_deref()), ("stand", Some("bed")));
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Query {
    /// The relation.
    pub relation: Relation,
    /// The target object id(s): one for a two-object or architecture relation (further ids
    /// are ignored there, as the reference uses the first "other" object), all of them for
    /// `surround`.
    pub targets: Vec<String>,
    /// The anchor object id (object-object relations only).
    #[cfg_attr(feature = "serde", serde(default))]
    pub anchor: Option<String>,
    /// Floor ids (or room ids) restricting `inside_room`, `middle_of_room`,
    /// `corner_of_room` and `hang_from_ceiling`; empty = every room. The other architecture
    /// relations consider every wall, door and window of the scene, as the reference does.
    #[cfg_attr(feature = "serde", serde(default))]
    pub floors: Vec<String>,
}

impl Query {
    /// A query of `relation` with no objects yet.
    pub fn new(relation: Relation) -> Self {
        Query {
            relation,
            targets: Vec::new(),
            anchor: None,
            floors: Vec::new(),
        }
    }

    /// Adds a target object (call once per target for `surround`).
    pub fn target(mut self, id: impl Into<String>) -> Self {
        self.targets.push(id.into());
        self
    }

    /// Sets the anchor object.
    pub fn anchor(mut self, id: impl Into<String>) -> Self {
        self.anchor = Some(id.into());
        self
    }

    /// Adds a floor (or room) id the floor-based architecture relations are restricted to.
    pub fn floor(mut self, id: impl Into<String>) -> Self {
        self.floors.push(id.into());
        self
    }
}

/// Evaluates relations between the objects of a scene, by object index or by id.
///
/// It holds only the validated parameters and borrows the scene per call, and scores through
/// the one dispatcher ([`crate::score`]): rooms were prepared
/// when they were built (`sceneeval_scene::Room`), objects are read where they are, so a
/// layout optimiser can move objects ([`Scene::set_pose`]) and ask again at once. The calls by
/// index ([`SceneRelations::pair`], [`SceneRelations::surround`], [`SceneRelations::arch`])
/// allocate nothing (`surround`: up to 64 targets); [`SceneRelations::evaluate`] looks ids up
/// in the scene's hash index. Unknown ids or indices, a missing anchor or target, and relations
/// of the wrong kind are errors naming the input.
///
/// ```
/// use sceneeval_relations::{Query, Relation, RelationParams, SceneRelations};
/// use sceneeval_scene::{Category, RoomBuilder, Scene};
/// use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Side, Vector3};
///
/// let mut scene = Scene::builder()
///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)))
///     .add_box("bed", Category::new("bed"), Vector3::new(0.8, 1.0, 0.3), pose_from_yaw(Point3::new(2.0, 4.0, 0.3), 0.0))
///     .add_box("stand", Category::new("nightstand"), Vector3::new(0.25, 0.2, 0.3),
///              pose_from_yaw(Point3::new(0.95, 4.7, 0.3), 0.0))
///     .build()
///     .unwrap();
/// let rel = SceneRelations::new(RelationParams::default()).unwrap();
/// // The bed spans x in [1.2, 2.8]; the stand (x in [0.7, 1.2]) touches its -x (left) side.
/// let q = Query::new(Relation::SideOf(Side::Left)).target("stand").anchor("bed");
/// let e = rel.evaluate(&scene, &q).unwrap();
/// assert!(e.holds && e.score == 1.0);
/// assert!(rel.evaluate(&scene, &Query::new(Relation::AgainstWall).target("bed")).unwrap().holds);
/// assert!(rel.evaluate(&scene, &Query::new(Relation::NextTo).target("stand").anchor("sofa")).is_err());
///
/// // By index, in a loop: move the stand in front of the bed (y < 3) and ask again.
/// let (stand, bed) = (scene.object_index("stand").unwrap(), scene.object_index("bed").unwrap());
/// scene.set_pose(stand, pose_from_yaw(Point3::new(2.0, 2.5, 0.3), 0.0)).unwrap();
/// assert!(!rel.pair(&scene, Relation::SideOf(Side::Left), stand, bed).unwrap().holds);
/// ```
#[derive(Debug, Clone)]
pub struct SceneRelations {
    params: RelationParams,
}

impl SceneRelations {
    /// Checks the parameters.
    ///
    /// # Errors
    /// [`RelationError::BadParameter`] from [`RelationParams::validate`].
    pub fn new(params: RelationParams) -> Result<Self, RelationError> {
        params.validate()?;
        Ok(SceneRelations { params })
    }

    /// The parameters in use.
    #[inline]
    pub fn params(&self) -> &RelationParams {
        &self.params
    }

    /// The index of the object with this id (see [`Scene::object_index`]).
    ///
    /// # Errors
    /// [`RelationError::UnknownObject`].
    pub fn object_index(scene: &Scene, id: &str) -> Result<usize, RelationError> {
        scene
            .object_index(id)
            .ok_or_else(|| RelationError::UnknownObject { id: id.to_owned() })
    }

    /// The predicate view of the object at `index`.
    ///
    /// # Errors
    /// [`RelationError::NoSuchObject`].
    pub fn object(scene: &Scene, index: usize) -> Result<ObjectGeom<'_>, RelationError> {
        scene
            .object_at(index)
            .map(ObjectGeom::from_object)
            .ok_or(RelationError::NoSuchObject {
                index,
                count: scene.objects().len(),
            })
    }

    fn evaluation(&self, score: Real) -> Evaluation {
        Evaluation {
            score,
            holds: self.params.holds(score),
        }
    }

    /// A two-object relation: the object at `target` relative to the one at `anchor`.
    ///
    /// # Errors
    /// [`RelationError::NoSuchObject`], [`RelationError::WrongKind`] for `surround` or an
    /// architecture relation.
    pub fn pair(
        &self,
        scene: &Scene,
        relation: Relation,
        target: usize,
        anchor: usize,
    ) -> Result<Evaluation, RelationError> {
        expect_kind(relation, RelationKind::ObjectObject)?;
        let (t, a) = (Self::object(scene, target)?, Self::object(scene, anchor)?);
        crate::score(relation, &Operands::pair(t, a), &self.params).map(|s| self.evaluation(s))
    }

    /// `surround`: the objects at `targets` around the one at `anchor`.
    ///
    /// # Errors
    /// [`RelationError::NoSuchObject`]; [`RelationError::TooManyTargets`] for the reference
    /// variant beyond [`crate::SURROUND_REFERENCE_MAX_TARGETS`] targets.
    pub fn surround(
        &self,
        scene: &Scene,
        targets: &[usize],
        anchor: usize,
    ) -> Result<Evaluation, RelationError> {
        let anchor = Self::object(scene, anchor)?;
        for &t in targets {
            Self::object(scene, t)?;
        }
        let objects = scene.objects();
        let centre = |i: usize| objects[targets[i]].obb().center;
        let targets = Targets::Centres {
            count: targets.len(),
            centre: &centre,
        };
        crate::score(
            Relation::Surround,
            &Operands::surround(targets, anchor),
            &self.params,
        )
        .map(|s| self.evaluation(s))
    }

    /// An object-architecture relation for the object at `target`. `floors` (floor ids such as
    /// `floor_r0`, or room ids) restricts the floor-based relations (`inside_room`,
    /// `middle_of_room`, `corner_of_room`, `hang_from_ceiling`) to those rooms; empty means
    /// every room. The wall, door and window relations always consider the whole scene.
    ///
    /// # Errors
    /// [`RelationError::NoSuchObject`], [`RelationError::UnknownFloor`],
    /// [`RelationError::WrongKind`] for an object-object relation,
    /// [`RelationError::NoArchitecture`] for a scene without rooms.
    pub fn arch(
        &self,
        scene: &Scene,
        relation: Relation,
        target: usize,
        floors: &[&str],
    ) -> Result<Evaluation, RelationError> {
        self.arch_in(scene, relation, target, floors.iter().copied())
    }

    fn arch_in<'f>(
        &self,
        scene: &Scene,
        relation: Relation,
        target: usize,
        floors: impl Iterator<Item = &'f str> + Clone,
    ) -> Result<Evaluation, RelationError> {
        expect_kind(relation, RelationKind::ObjectArchitecture)?;
        let a = Self::object(scene, target)?;
        let rooms = scene.rooms();
        if rooms.is_empty() {
            return Err(RelationError::NoArchitecture {
                relation: relation.to_string(),
            });
        }
        let floor_based = matches!(
            relation,
            Relation::InsideRoom
                | Relation::MiddleOfRoom
                | Relation::CornerOfRoom
                | Relation::HangFromCeiling
        );
        let score = if floor_based && floors.clone().next().is_some() {
            let mut best: Real = 0.0;
            for id in floors {
                let room = rooms
                    .iter()
                    .find(|r| r.floor_id() == id || r.id().as_str() == id)
                    .ok_or_else(|| RelationError::UnknownFloor { id: id.to_owned() })?;
                best = best.max(crate::score(
                    relation,
                    &Operands::in_rooms(a, std::slice::from_ref(room)),
                    &self.params,
                )?);
            }
            best
        } else {
            crate::score(relation, &Operands::in_rooms(a, rooms), &self.params)?
        };
        Ok(self.evaluation(score))
    }

    /// Evaluates a [`Query`] of any kind, by object ids.
    ///
    /// # Errors
    /// As [`SceneRelations::pair`], [`SceneRelations::surround`] and
    /// [`SceneRelations::arch`] (with [`RelationError::UnknownObject`] for an unknown id),
    /// plus [`RelationError::NotEnoughTargets`] for a query without targets and
    /// [`RelationError::MissingArgument`] for an object-object query without an anchor.
    pub fn evaluate(&self, scene: &Scene, query: &Query) -> Result<Evaluation, RelationError> {
        let relation = query.relation;
        let first = query
            .targets
            .first()
            .ok_or_else(|| RelationError::NotEnoughTargets {
                relation: relation.to_string(),
                needed: 1,
                got: 0,
            })?;
        let anchor = || {
            let id = query.anchor.as_deref().ok_or(RelationError::MissingArgument {
                relation: relation.name(),
                expected: "an anchor object",
            })?;
            Self::object_index(scene, id)
        };
        match relation.kind() {
            RelationKind::ObjectObject => {
                let target = Self::object_index(scene, first)?;
                self.pair(scene, relation, target, anchor()?)
            }
            RelationKind::MultiTarget => {
                let anchor = Self::object(scene, anchor()?)?;
                for id in &query.targets {
                    Self::object_index(scene, id)?;
                }
                let centre = |i: usize| {
                    scene
                        .object(&query.targets[i])
                        .map_or(anchor.obb.center, |o| o.obb().center)
                };
                let targets = Targets::Centres {
                    count: query.targets.len(),
                    centre: &centre,
                };
                crate::score(relation, &Operands::surround(targets, anchor), &self.params)
                    .map(|s| self.evaluation(s))
            }
            RelationKind::ObjectArchitecture => {
                let target = Self::object_index(scene, first)?;
                self.arch_in(scene, relation, target, query.floors.iter().map(String::as_str))
            }
        }
    }

    /// Evaluates many queries; each gets its own result, so one bad query does not stop the
    /// others. A plain loop: callers parallelise if they wish (results do not depend on it).
    pub fn evaluate_batch(&self, scene: &Scene, queries: &[Query]) -> Vec<Result<Evaluation, RelationError>> {
        queries.iter().map(|q| self.evaluate(scene, q)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::conventions::pose_from_yaw;
    use sceneeval_geom::{Point2, Point3, Side, Vector3};
    use sceneeval_scene::{Category, RoomBuilder};

    fn scene() -> Scene {
        Scene::builder()
            .room_builder(RoomBuilder::rectangle(
                "r0",
                Point2::new(0.0, 0.0),
                Point2::new(4.0, 5.0),
            ))
            .room_builder(RoomBuilder::rectangle(
                "r1",
                Point2::new(4.0, 0.0),
                Point2::new(8.0, 5.0),
            ))
            .add_box(
                "table",
                Category::new("table"),
                Vector3::new(0.5, 0.5, 0.375),
                pose_from_yaw(Point3::new(2.0, 2.5, 0.375), 0.0),
            )
            .add_box(
                "c0",
                Category::new("chair"),
                Vector3::new(0.25, 0.25, 0.45),
                pose_from_yaw(Point3::new(3.0, 2.5, 0.45), 0.0),
            )
            .add_box(
                "c1",
                Category::new("chair"),
                Vector3::new(0.25, 0.25, 0.45),
                pose_from_yaw(Point3::new(2.0, 3.5, 0.45), 0.0),
            )
            .add_box(
                "c2",
                Category::new("chair"),
                Vector3::new(0.25, 0.25, 0.45),
                pose_from_yaw(Point3::new(1.0, 2.5, 0.45), 0.0),
            )
            .add_box(
                "c3",
                Category::new("chair"),
                Vector3::new(0.25, 0.25, 0.45),
                pose_from_yaw(Point3::new(2.0, 1.5, 0.45), 0.0),
            )
            .add_box(
                "sofa",
                Category::new("sofa"),
                Vector3::new(1.0, 0.45, 0.4),
                pose_from_yaw(Point3::new(6.0, 4.5, 0.4), 0.0),
            )
            .build()
            .unwrap()
    }

    #[test]
    fn queries_of_every_kind() {
        let s = scene();
        let rel = SceneRelations::new(RelationParams::default()).unwrap();
        let idx = |id: &str| s.object_index(id).unwrap();
        let chairs = ["c0", "c1", "c2", "c3"].map(idx);
        let e = rel.surround(&s, &chairs, idx("table")).unwrap();
        assert!((e.score - 1.0).abs() < 1e-12 && e.holds);
        let q = Query {
            relation: Relation::Surround,
            targets: vec!["c0".into(), "c1".into(), "c2".into()],
            anchor: Some("table".into()),
            floors: vec![],
        };
        // Three of four chairs: gaps 90, 90, 180 -> 0.5 + 0.5 (0.5625 * 2 + 0.25) / 3.
        let e = rel.evaluate(&s, &q).unwrap();
        assert!((e.score - (0.5 + 0.5 * 1.375 / 3.0)).abs() < 1e-12);
        assert!(
            rel.evaluate(
                &s,
                &Query::new(Relation::SideOf(Side::Right))
                    .target("c0")
                    .anchor("table")
            )
            .unwrap()
            .holds
        );
        // The sofa is in room r1 only.
        assert!(
            rel.evaluate(&s, &Query::new(Relation::InsideRoom).target("sofa"))
                .unwrap()
                .holds
        );
        assert!(
            !rel.arch(&s, Relation::InsideRoom, idx("sofa"), &["floor_r0"])
                .unwrap()
                .holds
        );
        assert!(
            rel.arch(&s, Relation::InsideRoom, idx("sofa"), &["r1"])
                .unwrap()
                .holds
        );
        assert!(
            rel.arch(&s, Relation::AgainstWall, idx("sofa"), &["floor_r0"])
                .unwrap()
                .holds
        );
    }

    #[test]
    fn errors_name_the_input() {
        let s = scene();
        let rel = SceneRelations::new(RelationParams::default()).unwrap();
        let idx = |id: &str| s.object_index(id).unwrap();
        assert_eq!(
            rel.evaluate(&s, &Query::new(Relation::Near).target("c0").anchor("bed"))
                .unwrap_err(),
            RelationError::UnknownObject { id: "bed".into() }
        );
        assert!(matches!(
            rel.arch(&s, Relation::InsideRoom, idx("c0"), &["floor_x"]),
            Err(RelationError::UnknownFloor { .. })
        ));
        assert!(matches!(
            rel.pair(&s, Relation::OnWall, idx("c0"), idx("table")),
            Err(RelationError::WrongKind { .. })
        ));
        let no_anchor = Query {
            relation: Relation::Near,
            targets: vec!["c0".into()],
            anchor: None,
            floors: vec![],
        };
        let results = rel.evaluate_batch(
            &s,
            &[
                no_anchor,
                Query::new(Relation::Near).target("c0").anchor("c2"),
                Query {
                    targets: vec![],
                    ..Query::new(Relation::OnWall).target("c0")
                },
            ],
        );
        assert!(matches!(results[0], Err(RelationError::MissingArgument { .. })));
        // c0 and c2 are 1.5 m apart (x 2.75 -> 1.25): near scores 1.
        assert_eq!(results[1].as_ref().unwrap().score, 1.0);
        assert!(matches!(results[2], Err(RelationError::NotEnoughTargets { .. })));
        let empty = Scene::builder()
            .add_box(
                "x",
                Category::new("box"),
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::origin(), 0.0),
            )
            .build()
            .unwrap();
        let rel = SceneRelations::new(RelationParams::default()).unwrap();
        assert!(matches!(
            rel.arch(&empty, Relation::InsideRoom, 0, &[]),
            Err(RelationError::NoArchitecture { .. })
        ));
        let bad = RelationParams {
            middle_of_sigma_m: -1.0,
            ..Default::default()
        };
        assert!(SceneRelations::new(bad).is_err());
        assert_eq!(
            rel.pair(&empty, Relation::Near, 0, 5).unwrap_err(),
            RelationError::NoSuchObject { index: 5, count: 1 }
        );
    }
}
