//! The batch forms: one relation scored for many objects into a caller-owned slice, through
//! the one dispatcher ([`crate::score`]).
//!
//! # Performance
//! The batch forms are plain loops over the kernels writing into a caller-owned slice: no
//! allocation, no threads (parallelise over chunks of the slices if needed; the results do not
//! depend on how the work is split).

use sceneeval_geom::Real;

use sceneeval_scene::Room;

use crate::dispatch::expect_kind;
use crate::{ObjectGeom, Operands, Relation, RelationError, RelationKind, RelationParams};

/// The score of a two-object relation: `target` relative to `anchor` ([`crate::score`] on
/// [`Operands::pair`]).
///
/// # Errors
/// [`RelationError::WrongKind`] for `surround` or an object-architecture relation.
#[inline]
pub fn score_pair(
    relation: Relation,
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    params: &RelationParams,
) -> Result<Real, RelationError> {
    expect_kind(relation, RelationKind::ObjectObject)?;
    crate::score(relation, &Operands::pair(*target, *anchor), params)
}

/// Scores one two-object relation for many (target, anchor) pairs into `out`
/// (`out[i]` for `targets[i]` relative to `anchors[i]`).
///
/// ```
/// use sceneeval_relations::{batch, ObjectGeom, Relation, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let boxes: Vec<Obb> = (0..4)
///     .map(|i| Obb::from_yaw(Point3::new(i as f64, 0.0, 0.5), Vector3::repeat(0.25), 0.0).unwrap())
///     .collect();
/// let views: Vec<ObjectGeom> = boxes.iter().map(ObjectGeom::from_box).collect();
/// let mut out = [0.0; 3];
/// // Each box relative to the next one: 0.5 m apart, next_to holds with score 1.
/// batch::score_pairs(Relation::NextTo, &views[..3], &views[1..], &RelationParams::default(), &mut out).unwrap();
/// assert_eq!(out, [1.0, 1.0, 1.0]);
/// ```
///
/// # Errors
/// [`RelationError::LengthMismatch`] when the slices differ in length,
/// [`RelationError::WrongKind`] as [`score_pair`].
pub fn score_pairs(
    relation: Relation,
    targets: &[ObjectGeom<'_>],
    anchors: &[ObjectGeom<'_>],
    params: &RelationParams,
    out: &mut [Real],
) -> Result<(), RelationError> {
    expect_kind(relation, RelationKind::ObjectObject)?;
    check_len("anchors", anchors.len(), targets.len())?;
    check_len("out", out.len(), targets.len())?;
    for ((a, b), o) in targets.iter().zip(anchors).zip(out.iter_mut()) {
        *o = crate::score(relation, &Operands::pair(*a, *b), params)?;
    }
    Ok(())
}

/// Scores one object-architecture relation for many objects against the same rooms into
/// `out` (the best room for each object, see [`crate::arch::score_rooms`]).
///
/// # Errors
/// [`RelationError::LengthMismatch`] when `out` and `objects` differ in length,
/// [`RelationError::WrongKind`] for an object-object relation.
pub fn score_objects_in_rooms(
    relation: Relation,
    objects: &[ObjectGeom<'_>],
    rooms: &[Room],
    params: &RelationParams,
    out: &mut [Real],
) -> Result<(), RelationError> {
    expect_kind(relation, RelationKind::ObjectArchitecture)?;
    check_len("out", out.len(), objects.len())?;
    for (a, o) in objects.iter().zip(out.iter_mut()) {
        *o = crate::score(relation, &Operands::in_rooms(*a, rooms), params)?;
    }
    Ok(())
}

fn check_len(what: &'static str, got: usize, expected: usize) -> Result<(), RelationError> {
    if got == expected {
        Ok(())
    } else {
        Err(RelationError::LengthMismatch { what, got, expected })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pairwise;
    use sceneeval_geom::{Obb, Point3, Side, Vector3};

    #[test]
    fn dispatch_matches_kernels_and_checks_kinds() {
        let p = RelationParams::default();
        let a = Obb::from_yaw(Point3::new(-1.0, 0.0, 0.5), Vector3::repeat(0.3), 0.2).unwrap();
        let b = Obb::from_yaw(Point3::new(0.0, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
        let (ga, gb) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
        for r in Relation::all().filter(|r| r.kind() == RelationKind::ObjectObject) {
            let s = score_pair(r, &ga, &gb, &p).unwrap();
            assert!((0.0..=1.0).contains(&s), "{r}: {s}");
        }
        assert_eq!(
            score_pair(Relation::SideOf(Side::Left), &ga, &gb, &p).unwrap(),
            pairwise::side_of(&ga, &gb, Side::Left, &p)
        );
        assert!(matches!(
            score_pair(Relation::Surround, &ga, &gb, &p),
            Err(RelationError::WrongKind { .. })
        ));
        assert!(score_pair(Relation::OnWall, &ga, &gb, &p).is_err());
        let mut out = [0.0; 2];
        assert!(matches!(
            score_pairs(Relation::Near, &[ga], &[gb], &p, &mut out),
            Err(RelationError::LengthMismatch { what: "out", .. })
        ));
        assert!(score_objects_in_rooms(Relation::Near, &[ga], &[], &p, &mut out[..1]).is_err());
        score_objects_in_rooms(Relation::InsideRoom, &[ga, gb], &[], &p, &mut out).unwrap();
        assert_eq!(out, [0.0, 0.0]);
    }
}
