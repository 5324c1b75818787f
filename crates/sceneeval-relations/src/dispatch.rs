//! The one dispatcher: a [`Relation`] and its [`Operands`] to the kernel that scores them.
//!
//! Every caller goes through [`score`]: the batch forms ([`crate::batch`]), the scene queries
//! ([`crate::SceneRelations`], by index or id) and the front ends that read queries as plain
//! data (`sceneeval relate`, the Python package, through the facade's `sceneeval::relate`).
//! It checks that the operands given are the ones the relation's kind uses, applies the one
//! limit on `surround`'s targets ([`SURROUND_REFERENCE_MAX_TARGETS`]), and calls the kernel:
//! the object-object kernels of the crate root, [`crate::surround`], or
//! [`crate::arch::score_rooms`].

use std::fmt;

use sceneeval_geom::{Point3, Real};
use sceneeval_scene::Room;

use crate::pairwise::{self, surround_centres};
use crate::{ObjectGeom, Relation, RelationError, RelationKind, RelationParams, SurroundVariant, arch};

/// Targets above which `surround` with [`crate::SurroundVariant::Reference`] is refused: that
/// variant compares every pair of targets (`O(N^2)`; 2,048 targets are about four million
/// comparisons). The paper variant sorts once (`O(N log N)`) and has no limit.
pub const SURROUND_REFERENCE_MAX_TARGETS: usize = 2048;

/// The targets of `surround`: objects, or only their box centres by index (`surround` reads
/// no more of them), which lets a caller pass objects wherever they are kept without
/// collecting them.
#[derive(Clone, Copy)]
pub enum Targets<'a> {
    /// The objects.
    Objects(&'a [ObjectGeom<'a>]),
    /// `count` objects whose box centres `centre(i)` gives.
    Centres {
        /// How many targets.
        count: usize,
        /// The box centre of target `i < count`.
        centre: &'a dyn Fn(usize) -> Point3,
    },
}

impl Targets<'_> {
    /// How many targets.
    pub fn len(&self) -> usize {
        match self {
            Targets::Objects(objects) => objects.len(),
            Targets::Centres { count, .. } => *count,
        }
    }

    /// Whether there is no target.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl fmt::Debug for Targets<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Targets::Objects(objects) => f.debug_tuple("Objects").field(objects).finish(),
            Targets::Centres { count, .. } => f
                .debug_struct("Centres")
                .field("count", count)
                .finish_non_exhaustive(),
        }
    }
}

/// What one relation is scored on, each operand given or not: a target and an anchor
/// (object-object relations), several targets and an anchor (`surround`), or a target and
/// rooms (object-architecture relations: the best of the rooms). [`score`] checks that the
/// operands given are exactly those the relation's kind uses.
#[derive(Debug, Clone, Copy, Default)]
pub struct Operands<'a> {
    /// The object being located.
    pub target: Option<ObjectGeom<'a>>,
    /// The reference object.
    pub anchor: Option<ObjectGeom<'a>>,
    /// The objects around the anchor (`surround` only).
    pub targets: Option<Targets<'a>>,
    /// The rooms (object-architecture relations only; one room is `std::slice::from_ref`).
    pub rooms: Option<&'a [Room]>,
}

impl<'a> Operands<'a> {
    /// `target` relative to `anchor`.
    #[inline]
    pub fn pair(target: ObjectGeom<'a>, anchor: ObjectGeom<'a>) -> Self {
        Operands {
            target: Some(target),
            anchor: Some(anchor),
            ..Operands::default()
        }
    }

    /// `targets` around `anchor`.
    #[inline]
    pub fn surround(targets: Targets<'a>, anchor: ObjectGeom<'a>) -> Self {
        Operands {
            anchor: Some(anchor),
            targets: Some(targets),
            ..Operands::default()
        }
    }

    /// `target` relative to the architecture of `rooms`.
    #[inline]
    pub fn in_rooms(target: ObjectGeom<'a>, rooms: &'a [Room]) -> Self {
        Operands {
            target: Some(target),
            rooms: Some(rooms),
            ..Operands::default()
        }
    }
}

/// The score of `relation` on `operands`: the one dispatcher from a relation and its operands
/// to the kernel (see the crate documentation).
///
/// ```
/// use sceneeval_relations::{self as rel, ObjectGeom, Operands, Relation, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let lamp = Obb::from_yaw(Point3::new(0.0, 0.0, 1.1), Vector3::repeat(0.1), 0.0).unwrap();
/// let table = Obb::from_yaw(Point3::new(0.0, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// let (lamp, table) = (ObjectGeom::from_box(&lamp), ObjectGeom::from_box(&table));
/// let p = RelationParams::default();
/// // The lamp rests on the table's top face (z = 1.0): all of it is above, score 1.
/// assert_eq!(rel::score(Relation::OnTop, &Operands::pair(lamp, table), &p).unwrap(), 1.0);
/// // An architecture relation needs a room, not an anchor.
/// let err = rel::score(Relation::OnWall, &Operands::pair(lamp, table), &p).unwrap_err();
/// assert_eq!(err.to_string(), "relation on_wall does not use \"anchor\"");
/// ```
///
/// # Errors
/// [`RelationError::MissingOperand`] and [`RelationError::UnexpectedOperand`] when the
/// operands do not match the relation's kind (a distance relation given rooms but no anchor
/// is told to name an architecture element, [`RelationError::MissingArgument`]),
/// [`RelationError::TooManyTargets`] for the reference `surround` beyond
/// [`SURROUND_REFERENCE_MAX_TARGETS`] targets.
#[inline]
pub fn score(
    relation: Relation,
    operands: &Operands<'_>,
    params: &RelationParams,
) -> Result<Real, RelationError> {
    let missing = |operand: &'static str| RelationError::MissingOperand {
        relation: relation.to_string(),
        operand,
    };
    let unexpected = |present: bool, operand: &'static str| {
        if present {
            Err(RelationError::UnexpectedOperand {
                relation: relation.to_string(),
                operand,
            })
        } else {
            Ok(())
        }
    };
    match relation.kind() {
        RelationKind::ObjectObject => {
            unexpected(operands.targets.is_some(), "targets")?;
            if operands.rooms.is_some()
                && operands.anchor.is_none()
                && matches!(
                    relation,
                    Relation::NextTo | Relation::Near | Relation::AcrossFrom | Relation::Far
                )
            {
                return Err(RelationError::MissingArgument {
                    relation: relation.name(),
                    expected: "\"arch\" (wall, door or window) to relate an object to a room",
                });
            }
            unexpected(operands.rooms.is_some(), "room")?;
            let target = operands.target.as_ref().ok_or_else(|| missing("target"))?;
            let anchor = operands.anchor.as_ref().ok_or_else(|| missing("anchor"))?;
            pair_kernel(relation, target, anchor, params)
        }
        RelationKind::MultiTarget => {
            unexpected(operands.target.is_some(), "target (surround takes targets)")?;
            unexpected(operands.rooms.is_some(), "room")?;
            let anchor = operands.anchor.as_ref().ok_or_else(|| missing("anchor"))?;
            let targets = operands.targets.as_ref().ok_or_else(|| missing("targets"))?;
            surround_limit(targets.len(), params)?;
            Ok(match targets {
                Targets::Objects(objects) => pairwise::surround(objects, anchor, params),
                Targets::Centres { count, centre } => {
                    surround_centres(*count, centre, &anchor.obb.center, params)
                }
            })
        }
        RelationKind::ObjectArchitecture => {
            unexpected(operands.anchor.is_some(), "anchor")?;
            unexpected(operands.targets.is_some(), "targets")?;
            let target = operands.target.as_ref().ok_or_else(|| missing("target"))?;
            let rooms = operands.rooms.ok_or_else(|| missing("room"))?;
            arch::score_rooms(relation, target, rooms, params)
        }
    }
}

/// `Ok` unless `surround` with `params`' variant refuses `count` targets
/// ([`SURROUND_REFERENCE_MAX_TARGETS`]): the one check for the score and the gradient.
pub(crate) fn surround_limit(count: usize, params: &RelationParams) -> Result<(), RelationError> {
    if params.surround_variant == SurroundVariant::Reference && count > SURROUND_REFERENCE_MAX_TARGETS {
        return Err(RelationError::TooManyTargets {
            relation: Relation::Surround.to_string(),
            got: count,
            limit: SURROUND_REFERENCE_MAX_TARGETS,
        });
    }
    Ok(())
}

/// `Ok` when `relation` is of `kind`, else [`RelationError::WrongKind`] saying which kind the
/// call expected: for callers that accept one kind only (the batch forms, the scene queries
/// by index) and say so before they look at their operands.
pub(crate) fn expect_kind(relation: Relation, kind: RelationKind) -> Result<(), RelationError> {
    if relation.kind() == kind {
        Ok(())
    } else {
        Err(wrong_kind(relation, kind))
    }
}

/// [`RelationError::WrongKind`]: `relation` where a relation of `expected` was expected.
pub(crate) fn wrong_kind(relation: Relation, expected: RelationKind) -> RelationError {
    RelationError::WrongKind {
        relation: relation.to_string(),
        actual: relation.kind().describe(),
        expected: match expected {
            RelationKind::ObjectObject => "a two-object relation",
            RelationKind::MultiTarget => "a multi-target relation (surround)",
            RelationKind::ObjectArchitecture => "an object-architecture relation",
        },
    }
}

/// The object-object kernel of `relation`: the one match from a relation to its pair kernel.
#[inline]
fn pair_kernel(
    relation: Relation,
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    params: &RelationParams,
) -> Result<Real, RelationError> {
    Ok(match relation {
        Relation::InsideOf => pairwise::inside_of(target, anchor, params),
        Relation::OutsideOf => pairwise::outside_of(target, anchor, params),
        Relation::FaceTo => crate::face_to(target, anchor, params),
        Relation::SideOf(side) => pairwise::side_of(target, anchor, side, params),
        Relation::SideRegion(side) => pairwise::side_region(target, anchor, side, params),
        Relation::LongShortSideOf(which) => pairwise::long_short_side_of(target, anchor, which, params),
        Relation::OnTop => pairwise::on_top(target, anchor, params),
        Relation::MiddleOf => pairwise::middle_of(target, anchor, params),
        Relation::NextTo => pairwise::next_to(target, anchor, params),
        Relation::Near => pairwise::near(target, anchor, params),
        Relation::AcrossFrom => pairwise::across_from(target, anchor, params),
        Relation::Far => pairwise::far(target, anchor, params),
        other => return Err(wrong_kind(other, RelationKind::ObjectObject)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::{Obb, Point2, Vector3};
    use sceneeval_scene::RoomBuilder;

    fn unit_cube(x: Real) -> Obb {
        Obb::from_yaw(Point3::new(x, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap()
    }

    fn square_room() -> Room {
        RoomBuilder::rectangle("room", Point2::new(0.0, 0.0), Point2::new(4.0, 3.0))
            .build()
            .unwrap()
    }

    #[test]
    fn operands_must_match_the_relations_kind() {
        let params = RelationParams::default();
        let (a, b) = (unit_cube(0.0), unit_cube(1.3));
        let (a, b) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
        let room = square_room();
        let rooms = std::slice::from_ref(&room);
        let only_target = Operands {
            target: Some(a),
            ..Operands::default()
        };
        assert_eq!(
            score(Relation::NextTo, &only_target, &params).unwrap_err(),
            RelationError::MissingOperand {
                relation: "next_to".into(),
                operand: "anchor"
            }
        );
        // Rooms without an anchor on a distance relation: the caller meant the architecture.
        assert!(matches!(
            score(Relation::NextTo, &Operands::in_rooms(a, rooms), &params),
            Err(RelationError::MissingArgument { .. })
        ));
        let pair_and_room = Operands {
            rooms: Some(rooms),
            ..Operands::pair(a, b)
        };
        assert_eq!(
            score(Relation::NextTo, &pair_and_room, &params)
                .unwrap_err()
                .to_string(),
            "relation next_to does not use \"room\""
        );
        // Unit cubes 1.3 m apart centre to centre: a 0.3 m gap, inside next_to's [0, 0.5] m.
        assert_eq!(
            score(Relation::NextTo, &Operands::pair(a, b), &params).unwrap(),
            1.0
        );
        // Architecture relations take a target and rooms, nothing else.
        assert_eq!(
            score(Relation::OnWall, &Operands::pair(a, b), &params)
                .unwrap_err()
                .to_string(),
            "relation on_wall does not use \"anchor\""
        );
        assert_eq!(
            score(Relation::InsideRoom, &only_target, &params)
                .unwrap_err()
                .to_string(),
            "relation inside_room needs \"room\""
        );
        // The cube at the origin straddles the floor's corner (0, 0): a quarter of it is over
        // the floor.
        let inside = score(Relation::InsideRoom, &Operands::in_rooms(a, rooms), &params).unwrap();
        assert!((inside - 0.25).abs() < 1e-9, "{inside}");
        assert_eq!(
            score(Relation::InsideRoom, &Operands::in_rooms(a, &[]), &params).unwrap(),
            0.0
        );
        // surround takes targets and an anchor.
        let views = [a, b];
        assert_eq!(
            score(Relation::Surround, &Operands::pair(a, b), &params)
                .unwrap_err()
                .to_string(),
            "relation surround does not use \"target (surround takes targets)\""
        );
        assert_eq!(
            score(
                Relation::Surround,
                &Operands {
                    targets: Some(Targets::Objects(&views)),
                    ..Operands::default()
                },
                &params
            )
            .unwrap_err()
            .to_string(),
            "relation surround needs \"anchor\""
        );
        assert!(matches!(
            score(
                Relation::NearArch(crate::ArchElement::Door),
                &Operands::pair(a, b),
                &params
            ),
            Err(RelationError::UnexpectedOperand {
                operand: "anchor",
                ..
            })
        ));
    }

    #[test]
    fn the_reference_surround_refuses_more_targets_than_its_limit() {
        let anchor = unit_cube(0.0);
        let target = unit_cube(3.0);
        let views = vec![ObjectGeom::from_box(&target); SURROUND_REFERENCE_MAX_TARGETS + 1];
        let operands = Operands::surround(Targets::Objects(&views), ObjectGeom::from_box(&anchor));
        assert!(matches!(
            score(Relation::Surround, &operands, &RelationParams::reference()),
            Err(RelationError::TooManyTargets { .. })
        ));
        // Exactly the limit is accepted.
        let at_limit = Operands::surround(
            Targets::Objects(&views[..SURROUND_REFERENCE_MAX_TARGETS]),
            ObjectGeom::from_box(&anchor),
        );
        assert!(score(Relation::Surround, &at_limit, &RelationParams::reference()).is_ok());
        // The paper's variant is linear in the targets and takes any number. All targets at one
        // place: every distance equals the mean (distance term 1, weight 0.5) but no angle is
        // the ideal 360/n degrees (angle term 0, weight 0.5), so the score is 0.5.
        assert_eq!(
            score(Relation::Surround, &operands, &RelationParams::default()).unwrap(),
            0.5
        );
    }

    #[test]
    fn targets_as_objects_or_centres_score_alike() {
        let params = RelationParams::reference();
        let anchor = unit_cube(0.0);
        let chairs: Vec<Obb> = (0..5)
            .map(|i| {
                let t = Real::from(i) * 1.3;
                Obb::from_yaw(
                    Point3::new(1.2 * t.cos(), 1.1 * t.sin(), 0.4),
                    Vector3::repeat(0.2),
                    t,
                )
                .unwrap()
            })
            .collect();
        let views: Vec<ObjectGeom<'_>> = chairs.iter().map(ObjectGeom::from_box).collect();
        let centre = |i: usize| chairs[i].center;
        let by_objects = score(
            Relation::Surround,
            &Operands::surround(Targets::Objects(&views), ObjectGeom::from_box(&anchor)),
            &params,
        )
        .unwrap();
        let by_centres = score(
            Relation::Surround,
            &Operands::surround(
                Targets::Centres {
                    count: chairs.len(),
                    centre: &centre,
                },
                ObjectGeom::from_box(&anchor),
            ),
            &params,
        )
        .unwrap();
        assert_eq!(by_objects.to_bits(), by_centres.to_bits());
        assert_eq!(
            by_objects.to_bits(),
            pairwise::surround(&views, &ObjectGeom::from_box(&anchor), &params).to_bits()
        );
    }
}
