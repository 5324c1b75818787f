//! Dispatch by [`Relation`] to the gradient kernels: the gradient counterpart of the score
//! dispatcher ([`crate::score`]), with its errors.

use sceneeval_geom::Real;
use sceneeval_scene::Room;

use super::{ArchGrad, PairGrad};
use crate::dispatch::wrong_kind;
use crate::{ObjectGeom, Relation, RelationError, RelationKind, RelationParams};

/// A two-object relation's score (bit for bit `batch::score_pair`'s) and its gradient with
/// respect to the target and the anchor.
///
/// # Errors
/// [`RelationError::WrongKind`] for `surround` (use [`super::surround`]) or an
/// object-architecture relation (use [`arch_rooms`]).
///
/// ```
/// use sceneeval_relations::{grad, ObjectGeom, Relation, RelationParams};
/// use sceneeval_geom::{Obb, Side, na::{Point3, Vector3}};
/// let bed = Obb::from_yaw(Point3::new(0.0, 0.0, 0.3), Vector3::new(0.8, 1.0, 0.3), 0.0).unwrap();
/// // A nightstand straddling the bed's left face: a quarter of it is beyond the face.
/// let stand = Obb::from_yaw(Point3::new(-0.7, 0.0, 0.3), Vector3::new(0.2, 0.2, 0.3), 0.0).unwrap();
/// let (a, b) = (ObjectGeom::from_box(&stand), ObjectGeom::from_box(&bed));
/// let g = grad::pair(Relation::SideOf(Side::Left), &a, &b, &RelationParams::default()).unwrap();
/// assert!((g.score - 0.25).abs() < 1e-5);
/// // Moving the stand left (-x) by dx puts dx / 0.4 more of its width beyond the face.
/// assert!((g.target.center.x + 2.5).abs() < 1e-9);
/// ```
pub fn pair(
    relation: Relation,
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    params: &RelationParams,
) -> Result<PairGrad, RelationError> {
    use super::{centroid, distance, volume};
    Ok(match relation {
        Relation::InsideOf => volume::inside_of(target, anchor, params),
        Relation::OutsideOf => volume::outside_of(target, anchor, params),
        Relation::FaceTo => super::face_to::face_to(target, anchor, params),
        Relation::SideOf(side) => volume::side_of(target, anchor, side, params),
        Relation::SideRegion(side) => volume::side_region(target, anchor, side, params),
        Relation::LongShortSideOf(which) => volume::long_short_side_of(target, anchor, which, params),
        Relation::OnTop => volume::on_top(target, anchor, params),
        Relation::MiddleOf => centroid::middle_of(target, anchor, params),
        Relation::NextTo => distance::next_to(target, anchor, params),
        Relation::Near => distance::near(target, anchor, params),
        Relation::AcrossFrom => distance::across_from(target, anchor, params),
        Relation::Far => distance::far(target, anchor, params),
        other => return Err(wrong_kind(other, RelationKind::ObjectObject)),
    })
}

/// An object-architecture relation's score over several rooms (bit for bit
/// `arch::score_rooms`': the best room, 0 with none) and its gradient with respect to the
/// object: the best room's (the first of equal ones; zero with no room scoring above 0).
///
/// # Errors
/// [`RelationError::WrongKind`] for an object-object relation.
pub fn arch_rooms(
    relation: Relation,
    target: &ObjectGeom<'_>,
    rooms: &[Room],
    params: &RelationParams,
) -> Result<ArchGrad, RelationError> {
    use super::arch as g;
    let f: &dyn Fn(&Room) -> ArchGrad = match relation {
        Relation::NextToArch(e) => &move |r| g::next_to(target, r, e, params),
        Relation::NearArch(e) => &move |r| g::near(target, r, e, params),
        Relation::AcrossFromArch(e) => &move |r| g::across_from(target, r, e, params),
        Relation::FarArch(e) => &move |r| g::far(target, r, e, params),
        Relation::InsideRoom => &|r| g::inside_room(target, r, params),
        Relation::MiddleOfRoom => &|r| g::middle_of_room(target, r, params),
        Relation::CornerOfRoom => &|r| g::corner_of_room(target, r, params),
        Relation::OnWall => &|r| g::on_wall(target, r, params),
        Relation::AgainstWall => &|r| g::against_wall(target, r, params),
        Relation::HangFromCeiling => &|r| g::hang_from_ceiling(target, r, params),
        other => {
            debug_assert_ne!(other.kind(), RelationKind::ObjectArchitecture);
            return Err(wrong_kind(other, RelationKind::ObjectArchitecture));
        }
    };
    // As `rooms.iter().map(score).fold(0.0, Real::max)`, remembering the room behind it.
    let mut best = ArchGrad::default();
    for room in rooms {
        let g = f(room);
        let score: Real = best.score.max(g.score);
        if g.score > best.score {
            best = g;
        }
        best.score = score;
    }
    Ok(best)
}
