//! Scene-level evaluation: relations between scene objects by id, against the scene's rooms.

use sceneeval_geom::Real;
use sceneeval_scene::Scene;

use crate::batch::{score_pair, wrong_kind};
use crate::{
    ObjectGeom, Relation, RelationError, RelationKind, RelationParams, RoomGeometry, arch, surround,
};

/// A relation's score and whether it holds (`score > threshold`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Evaluation {
    /// The score in `[0, 1]`.
    pub score: Real,
    /// Whether the score is above the threshold (0.5 by default).
    pub holds: bool,
}

/// One question about a scene: a relation, its target object(s), its anchor, and for the
/// floor-based architecture relations an optional choice of floors.
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
    /// A two-object (or `surround`, with one target) query.
    pub fn objects(relation: Relation, target: &str, anchor: &str) -> Self {
        Query {
            relation,
            targets: vec![target.to_owned()],
            anchor: Some(anchor.to_owned()),
            floors: Vec::new(),
        }
    }

    /// An object-architecture query over every room.
    pub fn architecture(relation: Relation, target: &str) -> Self {
        Query {
            relation,
            targets: vec![target.to_owned()],
            anchor: None,
            floors: Vec::new(),
        }
    }
}

/// Evaluates relations between the objects of one scene, by object id.
///
/// Construction prepares every room once ([`RoomGeometry::from_room`]); each evaluation then
/// looks objects up by id and calls the kernels. Unknown ids, a missing anchor or target, and
/// relations of the wrong kind are errors naming the input.
///
/// ```
/// use sceneeval_relations::{Relation, RelationParams, SceneRelations};
/// use sceneeval_scene::{RoomBuilder, Scene};
/// use sceneeval_geom::{Point2, Point3, Side, Vector3};
///
/// let scene = Scene::builder()
///     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)))
///     .add_box("bed", "bed", Point3::new(2.0, 4.0, 0.3), Vector3::new(1.6, 2.0, 0.6), 0.0)
///     .add_box("stand", "nightstand", Point3::new(0.95, 4.7, 0.3), Vector3::new(0.5, 0.4, 0.6), 0.0)
///     .build()
///     .unwrap();
/// let rel = SceneRelations::new(&scene, RelationParams::default()).unwrap();
/// // The bed spans x in [1.2, 2.8]; the stand (x in [0.7, 1.2]) touches its -x (left) side.
/// let e = rel.pair(Relation::SideOf(Side::Left), "stand", "bed").unwrap();
/// assert!(e.holds && e.score == 1.0);
/// assert!(rel.arch(Relation::AgainstWall, "bed", &[]).unwrap().holds);
/// assert!(rel.pair(Relation::NextTo, "stand", "sofa").is_err());
/// ```
#[derive(Debug, Clone)]
pub struct SceneRelations<'s> {
    scene: &'s Scene,
    rooms: Vec<RoomGeometry>,
    params: RelationParams,
}

impl<'s> SceneRelations<'s> {
    /// Prepares the scene's rooms and checks the parameters.
    ///
    /// # Errors
    /// [`RelationError::BadParameter`] from [`RelationParams::validate`].
    pub fn new(scene: &'s Scene, params: RelationParams) -> Result<Self, RelationError> {
        params.validate()?;
        let rooms: Vec<RoomGeometry> = scene.rooms().iter().map(RoomGeometry::from_room).collect();
        tracing::debug!(
            scene = scene.id().unwrap_or("<unnamed>"),
            rooms = rooms.len(),
            wall_pieces = rooms.iter().map(|r| r.wall_cells().len()).sum::<usize>(),
            objects = scene.objects().len(),
            "prepared the scene for relation queries"
        );
        Ok(SceneRelations { scene, rooms, params })
    }

    /// The parameters in use.
    #[inline]
    pub fn params(&self) -> &RelationParams {
        &self.params
    }

    /// The prepared rooms, in the scene's order.
    #[inline]
    pub fn rooms(&self) -> &[RoomGeometry] {
        &self.rooms
    }

    /// The predicate view of an object.
    ///
    /// # Errors
    /// [`RelationError::UnknownObject`].
    pub fn object(&self, id: &str) -> Result<ObjectGeom<'s>, RelationError> {
        self.scene
            .object(id)
            .map(ObjectGeom::from_object)
            .ok_or_else(|| RelationError::UnknownObject { id: id.to_owned() })
    }

    fn evaluation(&self, score: Real) -> Evaluation {
        Evaluation {
            score,
            holds: self.params.holds(score),
        }
    }

    /// A two-object relation: `target` relative to `anchor`.
    ///
    /// # Errors
    /// [`RelationError::UnknownObject`], [`RelationError::WrongKind`] for `surround` or an
    /// architecture relation.
    pub fn pair(&self, relation: Relation, target: &str, anchor: &str) -> Result<Evaluation, RelationError> {
        if relation.kind() != RelationKind::ObjectObject {
            return Err(wrong_kind(relation, "a two-object relation"));
        }
        let (a, b) = (self.object(target)?, self.object(anchor)?);
        score_pair(relation, &a, &b, &self.params).map(|s| self.evaluation(s))
    }

    /// `surround`: the targets around the anchor.
    ///
    /// # Errors
    /// [`RelationError::UnknownObject`].
    pub fn surround(&self, anchor: &str, targets: &[&str]) -> Result<Evaluation, RelationError> {
        let b = self.object(anchor)?;
        let views = targets
            .iter()
            .map(|id| self.object(id))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(self.evaluation(surround(&b, &views, &self.params)))
    }

    /// An object-architecture relation. `floors` (floor ids such as `floor_r0`, or room ids)
    /// restricts the floor-based relations (`inside_room`, `middle_of_room`,
    /// `corner_of_room`, `hang_from_ceiling`) to those rooms; empty means every room. The
    /// wall, door and window relations always consider the whole scene.
    ///
    /// # Errors
    /// [`RelationError::UnknownObject`], [`RelationError::UnknownFloor`],
    /// [`RelationError::WrongKind`] for an object-object relation,
    /// [`RelationError::NoArchitecture`] for a scene without rooms.
    pub fn arch(
        &self,
        relation: Relation,
        target: &str,
        floors: &[&str],
    ) -> Result<Evaluation, RelationError> {
        if !relation.is_architectural() {
            return Err(wrong_kind(relation, "an object-architecture relation"));
        }
        let a = self.object(target)?;
        if self.rooms.is_empty() {
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
        let score = if floor_based && !floors.is_empty() {
            let mut best: Real = 0.0;
            for id in floors {
                let room = self
                    .rooms
                    .iter()
                    .find(|r| r.floor_id() == *id || r.room_id() == *id)
                    .ok_or_else(|| RelationError::UnknownFloor { id: (*id).to_owned() })?;
                best = best.max(arch::score_rooms(
                    relation,
                    &a,
                    std::slice::from_ref(room),
                    &self.params,
                )?);
            }
            best
        } else {
            arch::score_rooms(relation, &a, &self.rooms, &self.params)?
        };
        Ok(self.evaluation(score))
    }

    /// Evaluates a [`Query`] of any kind.
    ///
    /// # Errors
    /// As [`SceneRelations::pair`], [`SceneRelations::surround`] and
    /// [`SceneRelations::arch`], plus [`RelationError::NotEnoughTargets`] for a query
    /// without targets and [`RelationError::MissingArgument`] for an object-object query
    /// without an anchor.
    pub fn evaluate(&self, query: &Query) -> Result<Evaluation, RelationError> {
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
            query.anchor.as_deref().ok_or(RelationError::MissingArgument {
                relation: relation.name(),
                expected: "an anchor object",
            })
        };
        match relation.kind() {
            RelationKind::ObjectObject => self.pair(relation, first, anchor()?),
            RelationKind::MultiTarget => {
                let ids: Vec<&str> = query.targets.iter().map(String::as_str).collect();
                self.surround(anchor()?, &ids)
            }
            RelationKind::ObjectArchitecture => {
                let floors: Vec<&str> = query.floors.iter().map(String::as_str).collect();
                self.arch(relation, first, &floors)
            }
        }
    }

    /// Evaluates many queries; each gets its own result, so one bad query does not stop the
    /// others. A plain loop: callers parallelise if they wish (results do not depend on it).
    pub fn evaluate_batch(&self, queries: &[Query]) -> Vec<Result<Evaluation, RelationError>> {
        queries.iter().map(|q| self.evaluate(q)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::{Point2, Point3, Side, Vector3};
    use sceneeval_scene::RoomBuilder;

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
                "table",
                Point3::new(2.0, 2.5, 0.375),
                Vector3::new(1.0, 1.0, 0.75),
                0.0,
            )
            .add_box(
                "c0",
                "chair",
                Point3::new(3.0, 2.5, 0.45),
                Vector3::new(0.5, 0.5, 0.9),
                0.0,
            )
            .add_box(
                "c1",
                "chair",
                Point3::new(2.0, 3.5, 0.45),
                Vector3::new(0.5, 0.5, 0.9),
                0.0,
            )
            .add_box(
                "c2",
                "chair",
                Point3::new(1.0, 2.5, 0.45),
                Vector3::new(0.5, 0.5, 0.9),
                0.0,
            )
            .add_box(
                "c3",
                "chair",
                Point3::new(2.0, 1.5, 0.45),
                Vector3::new(0.5, 0.5, 0.9),
                0.0,
            )
            .add_box(
                "sofa",
                "sofa",
                Point3::new(6.0, 4.5, 0.4),
                Vector3::new(2.0, 0.9, 0.8),
                0.0,
            )
            .build()
            .unwrap()
    }

    #[test]
    fn queries_of_every_kind() {
        let s = scene();
        let rel = SceneRelations::new(&s, RelationParams::default()).unwrap();
        let e = rel.surround("table", &["c0", "c1", "c2", "c3"]).unwrap();
        assert!((e.score - 1.0).abs() < 1e-12 && e.holds);
        let q = Query {
            relation: Relation::Surround,
            targets: vec!["c0".into(), "c1".into(), "c2".into()],
            anchor: Some("table".into()),
            floors: vec![],
        };
        // Three of four chairs: gaps 90, 90, 180 -> 0.5 + 0.5 (0.5625 * 2 + 0.25) / 3.
        let e = rel.evaluate(&q).unwrap();
        assert!((e.score - (0.5 + 0.5 * 1.375 / 3.0)).abs() < 1e-12);
        assert!(
            rel.evaluate(&Query::objects(Relation::SideOf(Side::Right), "c0", "table"))
                .unwrap()
                .holds
        );
        // The sofa is in room r1 only.
        assert!(
            rel.evaluate(&Query::architecture(Relation::InsideRoom, "sofa"))
                .unwrap()
                .holds
        );
        assert!(
            !rel.arch(Relation::InsideRoom, "sofa", &["floor_r0"])
                .unwrap()
                .holds
        );
        assert!(rel.arch(Relation::InsideRoom, "sofa", &["r1"]).unwrap().holds);
        assert!(
            rel.arch(Relation::AgainstWall, "sofa", &["floor_r0"])
                .unwrap()
                .holds
        );
    }

    #[test]
    fn errors_name_the_input() {
        let s = scene();
        let rel = SceneRelations::new(&s, RelationParams::default()).unwrap();
        assert_eq!(
            rel.pair(Relation::Near, "c0", "bed").unwrap_err(),
            RelationError::UnknownObject { id: "bed".into() }
        );
        assert!(matches!(
            rel.arch(Relation::InsideRoom, "c0", &["floor_x"]),
            Err(RelationError::UnknownFloor { .. })
        ));
        assert!(matches!(
            rel.pair(Relation::OnWall, "c0", "table"),
            Err(RelationError::WrongKind { .. })
        ));
        let no_anchor = Query {
            relation: Relation::Near,
            targets: vec!["c0".into()],
            anchor: None,
            floors: vec![],
        };
        let results = rel.evaluate_batch(&[
            no_anchor,
            Query::objects(Relation::Near, "c0", "c2"),
            Query {
                targets: vec![],
                ..Query::architecture(Relation::OnWall, "c0")
            },
        ]);
        assert!(matches!(results[0], Err(RelationError::MissingArgument { .. })));
        // c0 and c2 are 1.5 m apart (x 2.75 -> 1.25): near scores 1.
        assert_eq!(results[1].as_ref().unwrap().score, 1.0);
        assert!(matches!(results[2], Err(RelationError::NotEnoughTargets { .. })));
        let empty = Scene::builder()
            .add_box("x", "box", Point3::origin(), Vector3::repeat(1.0), 0.0)
            .build()
            .unwrap();
        let rel = SceneRelations::new(&empty, RelationParams::default()).unwrap();
        assert!(matches!(
            rel.arch(Relation::InsideRoom, "x", &[]),
            Err(RelationError::NoArchitecture { .. })
        ));
        let bad = RelationParams {
            middle_of_sigma: -1.0,
            ..Default::default()
        };
        assert!(SceneRelations::new(&empty, bad).is_err());
    }
}
