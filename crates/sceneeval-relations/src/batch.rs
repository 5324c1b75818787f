//! Dispatch by [`Relation`] on plain geometry, one call or many.
//!
//! # Performance
//! The batch forms are plain loops over the kernels writing into a caller-owned slice: no
//! allocation, no threads (parallelise over chunks of the slices if needed; the results do not
//! depend on how the work is split).

use sceneeval_geom::Real;

use sceneeval_scene::Room;

use crate::{ObjectGeom, Relation, RelationError, RelationKind, RelationParams, arch, pairwise};

/// The score of a two-object relation: `target` relative to `anchor`.
///
/// # Errors
/// [`RelationError::WrongKind`] for `surround` or an object-architecture relation.
pub fn score_pair(
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
        other => return Err(wrong_kind(other, "a two-object relation")),
    })
}

pub(crate) fn wrong_kind(relation: Relation, expected: &'static str) -> RelationError {
    RelationError::WrongKind {
        relation: relation.to_string(),
        actual: relation.kind().describe(),
        expected,
    }
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
    if relation.kind() != RelationKind::ObjectObject {
        return Err(wrong_kind(relation, "a two-object relation"));
    }
    check_len("anchors", anchors.len(), targets.len())?;
    check_len("out", out.len(), targets.len())?;
    for ((a, b), o) in targets.iter().zip(anchors).zip(out.iter_mut()) {
        *o = score_pair(relation, a, b, params)?;
    }
    Ok(())
}

/// Scores one object-architecture relation for many objects against the same rooms into
/// `out` (the best room for each object, see [`arch::score_rooms`]).
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
    if !relation.is_architectural() {
        return Err(wrong_kind(relation, "an object-architecture relation"));
    }
    check_len("out", out.len(), objects.len())?;
    for (a, o) in objects.iter().zip(out.iter_mut()) {
        *o = arch::score_rooms(relation, a, rooms, params)?;
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
