//! Accessibility (ACC): whether the functional sides of objects can be reached.

use rayon::prelude::*;
use sceneeval_geom::{Point2, Point3, Real, Side};
use sceneeval_scene::{ObjectId, Scene, SceneObject};
use serde::{Deserialize, Serialize};

use crate::error::check_non_negative;
use crate::index::{BoxIndex, IndexWork, WorkCounter, flat};
use crate::objects::{DEFAULT_WALKABLE_HEIGHT, Footprint, ObjectInfo, object_infos};
use crate::plane::{
    FloorPiece, area, bounds, boxes_overlap, ccw, clip_convex, floor_pieces, subtract_convex,
};
use crate::sources::FunctionalSidesSource;
use crate::{Deadline, PlausibilityError};

/// Parameters of the accessibility metric (reference yaml `AccessibilityMetric`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct AccessibilityParams {
    /// Gap between a side of the object's box and its access strip, metres (reference
    /// `access_area_offset`, 0.05). Range: finite, `>= 0`.
    pub strip_offset: Real,
    /// Width of the access strip away from the side, metres (reference `access_area_width`,
    /// 0.2). Range: finite, `> 0`.
    pub strip_width: Real,
    /// Objects with any part lower than this above their floor block strips, metres (reference
    /// `obj_height_threshold`, 2.0, applied there to the OBB centre). Range: finite, `>= 0`.
    pub height_cutoff: Real,
    /// Objects whose top is at most this above their floor (rugs) do not block, metres.
    /// Default [`DEFAULT_WALKABLE_HEIGHT`] (5 cm); the reference lets every object block (0).
    /// Range: finite, `>= 0`.
    pub walkable_height: Real,
    /// The blocking footprints: convex hulls of the projected meshes (default) or, as the
    /// reference, the projected bounding boxes ([`Footprint::BoundingBox`]).
    pub footprint: Footprint,
}

impl Default for AccessibilityParams {
    fn default() -> Self {
        AccessibilityParams {
            strip_offset: 0.05,
            strip_width: 0.2,
            height_cutoff: 2.0,
            walkable_height: DEFAULT_WALKABLE_HEIGHT,
            footprint: Footprint::ConvexHull,
        }
    }
}

impl AccessibilityParams {
    fn validate(&self) -> Result<(), PlausibilityError> {
        let m = "accessibility";
        check_non_negative(m, "strip_offset", self.strip_offset, false)?;
        check_non_negative(m, "strip_width", self.strip_width, true)?;
        check_non_negative(m, "height_cutoff", self.height_cutoff, false)?;
        check_non_negative(m, "walkable_height", self.walkable_height, false)
    }
}

/// The access strip of one functional side.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SideAccess {
    /// The side.
    pub side: Side,
    /// The strip's corners on the floor plan (counter-clockwise).
    pub strip: Vec<Point2>,
    /// Strip area, square metres.
    pub strip_area: Real,
    /// Part of the strip over a floor, square metres.
    pub on_floor_area: Real,
    /// Part over a floor and outside every blocking footprint, square metres.
    pub free_area: Real,
    /// Objects whose footprint covers part of the strip, in scene order.
    pub blocked_by: Vec<ObjectId>,
    /// Free area over strip area, in [0, 1].
    pub score: Real,
}

/// Accessibility evidence of one object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectAccess {
    /// The object.
    pub id: ObjectId,
    /// The source that gave the functional sides; `None` when no source knew them (the
    /// object is skipped, like the reference's `-1`).
    pub sides_source: Option<String>,
    /// One entry per functional side, in the order the source gave them.
    pub sides: Vec<SideAccess>,
    /// The best side, if the object has one.
    pub best_side: Option<Side>,
    /// The best side's score; `None` for an object without functional sides.
    pub score: Option<Real>,
}

/// The accessibility metric of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AccessibilityReport {
    /// One entry per object, in scene order.
    pub objects: Vec<ObjectAccess>,
    /// Objects with at least one functional side (scored).
    pub num_scored: usize,
    /// Objects whose sides no source knew.
    pub num_unknown: usize,
    /// **ACC**: mean best-side score over scored objects; `None` when none is scored.
    pub acc: Option<Real>,
}

/// Computes the accessibility metric.
///
/// For each functional side (front, back, left, right; others are ignored) the access strip
/// is the rectangle beside that face of the object's box: from [`AccessibilityParams::
/// strip_offset`] to `strip_offset + strip_width` away from the face, as long as the face, in
/// the object's frame at its centre height, projected on the floor plan (reference notes 7.4).
/// Its free part is computed exactly by polygon clipping: the strip intersected with the
/// floors, minus the footprints of the other objects that obstruct (as for navigability: some
/// part below the height cut-off, top above the walkable height). Footprints are the convex hulls
/// of the projected meshes, a deliberate deviation from the reference's bounding rectangles
/// ([`AccessibilityParams::footprint`] restores those). Off-floor area counts as blocked, as
/// in the reference. The footprints and floor pieces a strip can meet are found with a
/// bounding-volume hierarchy, so the metric grows as `n log n`.
///
/// A side's score is its free area over its strip area; an object's score is its best side's;
/// ACC is the mean over objects with at least one functional side.
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] for bad parameters.
pub fn accessibility(
    scene: &Scene,
    params: &AccessibilityParams,
    sides: &dyn FunctionalSidesSource,
) -> Result<AccessibilityReport, PlausibilityError> {
    accessibility_with_work(scene, params, sides).map(|(report, _)| report)
}

/// [`accessibility`] and the work of its spatial-index queries (boxes tested, candidate
/// footprints and floor pieces), for tests and profiling.
///
/// # Errors
/// As [`accessibility`].
pub fn accessibility_with_work(
    scene: &Scene,
    params: &AccessibilityParams,
    sides: &dyn FunctionalSidesSource,
) -> Result<(AccessibilityReport, IndexWork), PlausibilityError> {
    params.validate()?;
    let infos = object_infos(scene);
    let pieces = scene_floor_pieces(scene);
    let work = WorkCounter::default();
    let report = accessibility_counted(scene, params, sides, &infos, &pieces, &work, &Deadline::none())?;
    Ok((report, work.total()))
}

pub(crate) fn scene_floor_pieces(scene: &Scene) -> Vec<FloorPiece> {
    let floors: Vec<_> = scene.rooms().iter().map(|r| (r.floor(), r.floor_z())).collect();
    floor_pieces(&floors)
}

pub(crate) fn accessibility_with(
    scene: &Scene,
    params: &AccessibilityParams,
    source: &dyn FunctionalSidesSource,
    infos: &[ObjectInfo],
    pieces: &[FloorPiece],
    deadline: &Deadline,
) -> Result<AccessibilityReport, PlausibilityError> {
    accessibility_counted(
        scene,
        params,
        source,
        infos,
        pieces,
        &WorkCounter::default(),
        deadline,
    )
}

/// The footprints that block strips, their boxes indexed, and the floor pieces indexed.
struct Blockers<'a> {
    infos: &'a [ObjectInfo],
    kind: Footprint,
    /// Blocking objects (indices into `infos`), in scene order.
    members: Vec<usize>,
    index: BoxIndex,
    pieces: &'a [FloorPiece],
    piece_index: BoxIndex,
}

fn accessibility_counted(
    scene: &Scene,
    params: &AccessibilityParams,
    source: &dyn FunctionalSidesSource,
    infos: &[ObjectInfo],
    pieces: &[FloorPiece],
    work: &WorkCounter,
    deadline: &Deadline,
) -> Result<AccessibilityReport, PlausibilityError> {
    let members: Vec<usize> = (0..infos.len())
        .filter(|&i| {
            infos[i].obstructs(params.height_cutoff, params.walkable_height)
                && infos[i].footprint_of(params.footprint).0.len() >= 3
        })
        .collect();
    let blockers = Blockers {
        infos,
        kind: params.footprint,
        index: BoxIndex::new(
            &members
                .iter()
                .map(|&k| flat(infos[k].footprint_of(params.footprint).1))
                .collect::<Vec<_>>(),
        ),
        members,
        pieces,
        piece_index: BoxIndex::new(&pieces.iter().map(|p| flat(&p.bounds)).collect::<Vec<_>>()),
    };
    let objects: Vec<ObjectAccess> = scene
        .objects()
        .par_iter()
        .enumerate()
        .map(|(k, o)| {
            deadline.check("accessibility")?;
            let answer = source.functional_sides(scene, o);
            let sides_source = answer.as_ref().map(|a| a.source.clone());
            let mut wanted: Vec<Side> = answer.map(|a| a.value).unwrap_or_default();
            wanted.retain(|s| Side::HORIZONTAL.contains(s));
            wanted.dedup();
            let sides: Vec<SideAccess> = wanted
                .iter()
                .map(|&s| side_access(scene, k, o, s, params, &blockers, work))
                .collect();
            let best = sides.iter().fold(None::<&SideAccess>, |b, s| match b {
                Some(b) if b.score >= s.score => Some(b),
                _ => Some(s),
            });
            Ok(ObjectAccess {
                id: o.id().clone(),
                sides_source,
                best_side: best.map(|b| b.side),
                score: best.map(|b| b.score),
                sides,
            })
        })
        .collect::<Result<_, PlausibilityError>>()?;
    let scored: Vec<Real> = objects.iter().filter_map(|o| o.score).collect();
    Ok(AccessibilityReport {
        num_scored: scored.len(),
        num_unknown: objects.iter().filter(|o| o.sides_source.is_none()).count(),
        acc: (!scored.is_empty()).then(|| scored.iter().sum::<Real>() / scored.len() as Real),
        objects,
    })
}

/// The access strip of `side` on the floor plan (counter-clockwise).
pub(crate) fn access_strip(o: &SceneObject, side: Side, offset: Real, width: Real) -> Vec<Point2> {
    let local = o.mesh().aabb();
    let (c, h) = (local.center(), local.half_extents());
    let (a, sign) = side.axis_and_sign();
    let b = 1 - a.min(1);
    let near = c[a] + sign * (h[a] + offset);
    let far = c[a] + sign * (h[a] + offset + width);
    let corner = |along: Real, across: Real| {
        let mut p = Point3::new(c.x, c.y, c.z);
        p[a] = along;
        p[b] = across;
        let w = o.pose() * p;
        Point2::new(w.x, w.y)
    };
    ccw(vec![
        corner(near, c[b] - h[b]),
        corner(far, c[b] - h[b]),
        corner(far, c[b] + h[b]),
        corner(near, c[b] + h[b]),
    ])
}

fn side_access(
    scene: &Scene,
    own: usize,
    o: &SceneObject,
    side: Side,
    params: &AccessibilityParams,
    blockers: &Blockers<'_>,
    work: &WorkCounter,
) -> SideAccess {
    let strip = access_strip(o, side, params.strip_offset, params.strip_width);
    let strip_area = area(&strip);
    let sb = bounds(&strip);
    let mut parts: Vec<Vec<Point2>> = blockers
        .piece_index
        .query_flat(&sb, work)
        .into_iter()
        .map(|k| &blockers.pieces[k])
        .filter(|p| boxes_overlap(&p.bounds, &sb))
        .map(|p| clip_convex(&strip, &p.poly))
        .filter(|p| p.len() >= 3)
        .collect();
    let on_floor_area = total_area(&parts);
    let mut blocked_by = Vec::new();
    for m in blockers.index.query_flat(&sb, work) {
        let k = blockers.members[m];
        let (footprint, fb) = blockers.infos[k].footprint_of(blockers.kind);
        if k == own || !boxes_overlap(fb, &sb) {
            continue;
        }
        let before = total_area(&parts);
        parts = parts.iter().flat_map(|p| subtract_convex(p, footprint)).collect();
        let after = total_area(&parts);
        if before - after > 1e-12 {
            blocked_by.push(scene.objects()[k].id().clone());
        }
    }
    let free_area = total_area(&parts);
    SideAccess {
        side,
        score: if strip_area > 0.0 {
            (free_area / strip_area).clamp(0.0, 1.0)
        } else {
            0.0
        },
        strip,
        strip_area,
        on_floor_area,
        free_area,
        blocked_by,
    }
}

pub(crate) fn validate(params: &AccessibilityParams) -> Result<(), PlausibilityError> {
    params.validate()
}

/// Sum of the pieces' areas, starting from +0 (an empty float `sum` is -0).
fn total_area(parts: &[Vec<Point2>]) -> Real {
    parts.iter().fold(0.0, |acc, p| acc + area(p))
}
