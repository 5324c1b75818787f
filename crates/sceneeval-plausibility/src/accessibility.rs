//! Accessibility (ACC): whether the functional sides of objects can be reached.

use std::sync::atomic::{AtomicU64, Ordering};

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
    pub strip_offset_m: Real,
    /// Width of the access strip away from the side, metres (reference `access_area_width`,
    /// 0.2). Range: finite, `> 0`.
    pub strip_width_m: Real,
    /// Objects with any part lower than this above their floor block strips, metres (reference
    /// `obj_height_threshold`, 2.0, applied there to the OBB centre). Range: finite, `>= 0`.
    pub height_cutoff_m: Real,
    /// Objects whose top is at most this above their floor (rugs) do not block, metres.
    /// Default [`DEFAULT_WALKABLE_HEIGHT`] (5 cm); the reference lets every object block (0).
    /// Range: finite, `>= 0`.
    pub walkable_height_m: Real,
    /// The blocking footprints: convex hulls of the projected meshes (default) or, as the
    /// reference, the projected bounding boxes ([`Footprint::BoundingBox`]).
    pub footprint: Footprint,
}

impl Default for AccessibilityParams {
    fn default() -> Self {
        AccessibilityParams {
            strip_offset_m: 0.05,
            strip_width_m: 0.2,
            height_cutoff_m: 2.0,
            walkable_height_m: DEFAULT_WALKABLE_HEIGHT,
            footprint: Footprint::ConvexHull,
        }
    }
}

impl AccessibilityParams {
    fn validate(&self) -> Result<(), PlausibilityError> {
        let m = "accessibility";
        check_non_negative(m, "strip_offset_m", self.strip_offset_m, false)?;
        check_non_negative(m, "strip_width_m", self.strip_width_m, true)?;
        check_non_negative(m, "height_cutoff_m", self.height_cutoff_m, false)?;
        check_non_negative(m, "walkable_height_m", self.walkable_height_m, false)
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

/// The most convex pieces the free part of one access strip may be split into while the
/// footprints are subtracted from it (about 100 bytes each). Subtraction leaves each piece in
/// one cell of the arrangement of the footprints' edge lines, so a strip met by `k` footprints
/// of `m` edges has at most `O((k m)^2)` pieces, and real strips have tens; the limit only
/// bounds the memory of a pathological scene, which fails with
/// [`PlausibilityError::TooManyPieces`] rather than allocating without bound.
pub const MAX_STRIP_PIECES: usize = 1 << 16;

/// The work of the accessibility metric ([`accessibility_with_work`]): deterministic counts
/// that bound its cost, unlike times.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AccessibilityWork {
    /// The spatial-index queries that found the footprints and floor pieces each strip can
    /// meet.
    pub index: IndexWork,
    /// Footprints subtracted from a strip's free part (candidates whose box meets the strip).
    pub subtractions: u64,
    /// Convex pieces the strips' free parts were left in after each subtraction, summed over
    /// every subtraction: the polygon work.
    pub pieces: u64,
    /// The most pieces any one strip's free part was split into at once (at most
    /// [`MAX_STRIP_PIECES`]).
    pub most_pieces: u64,
}

/// Counters of [`AccessibilityWork`] shared by the threads of one metric, and the limit on
/// pieces per strip.
#[derive(Debug)]
struct Counters {
    index: WorkCounter,
    subtractions: AtomicU64,
    pieces: AtomicU64,
    most_pieces: AtomicU64,
    max_pieces: usize,
}

impl Default for Counters {
    fn default() -> Self {
        Counters {
            index: WorkCounter::default(),
            subtractions: AtomicU64::default(),
            pieces: AtomicU64::default(),
            most_pieces: AtomicU64::default(),
            max_pieces: MAX_STRIP_PIECES,
        }
    }
}

impl Counters {
    fn total(&self) -> AccessibilityWork {
        AccessibilityWork {
            index: self.index.total(),
            subtractions: self.subtractions.load(Ordering::Relaxed),
            pieces: self.pieces.load(Ordering::Relaxed),
            most_pieces: self.most_pieces.load(Ordering::Relaxed),
        }
    }
}

/// Computes the accessibility metric.
///
/// For each functional side (front, back, left, right; others are ignored) the access strip
/// is the rectangle beside that face of the object's box: from [`AccessibilityParams::
/// strip_offset_m`] to `strip_offset_m + strip_width_m` away from the face, as long as the face, in
/// the object's frame at its centre height, projected on the floor plan (reference notes 7.4).
/// Its free part is computed exactly by polygon clipping: the strip intersected with the
/// floors, minus the footprints of the other objects that obstruct (as for navigability: some
/// part below the height cut-off, top above the walkable height). Footprints are the convex hulls
/// of the projected meshes, a deliberate deviation from the reference's bounding rectangles
/// ([`AccessibilityParams::footprint`] restores those). Off-floor area counts as blocked, as
/// in the reference. The footprints and floor pieces a strip can meet are found with a
/// bounding-volume hierarchy, so the metric grows as `n log n`. The free part is kept as
/// disjoint convex pieces; subtracting a footprint splits only the pieces it overlaps, and
/// copies of an object at one place split nothing after the first
/// ([`sceneeval_geom::planar::subtract_convex`]), so the pieces stay polynomial in the
/// footprints (at most [`MAX_STRIP_PIECES`] per strip).
///
/// A side's score is its free area over its strip area; an object's score is its best side's;
/// ACC is the mean over objects with at least one functional side.
///
/// # Errors
/// [`PlausibilityError::InvalidParameter`] for bad parameters,
/// [`PlausibilityError::TooManyPieces`] for a strip split beyond [`MAX_STRIP_PIECES`].
pub fn accessibility(
    scene: &Scene,
    params: &AccessibilityParams,
    sides: &dyn FunctionalSidesSource,
) -> Result<AccessibilityReport, PlausibilityError> {
    accessibility_with_work(scene, params, sides).map(|(report, _)| report)
}

/// [`accessibility`] and its work: the spatial-index queries (boxes tested, candidate
/// footprints and floor pieces) and the polygon pieces, for tests and profiling.
///
/// # Errors
/// As [`accessibility`].
pub fn accessibility_with_work(
    scene: &Scene,
    params: &AccessibilityParams,
    sides: &dyn FunctionalSidesSource,
) -> Result<(AccessibilityReport, AccessibilityWork), PlausibilityError> {
    params.validate()?;
    let infos = object_infos(scene);
    let pieces = scene_floor_pieces(scene);
    let work = Counters::default();
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
        &Counters::default(),
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
    /// The most pieces a strip's free part may be split into ([`MAX_STRIP_PIECES`]).
    max_pieces: usize,
}

fn accessibility_counted(
    scene: &Scene,
    params: &AccessibilityParams,
    source: &dyn FunctionalSidesSource,
    infos: &[ObjectInfo],
    pieces: &[FloorPiece],
    work: &Counters,
    deadline: &Deadline,
) -> Result<AccessibilityReport, PlausibilityError> {
    let members: Vec<usize> = (0..infos.len())
        .filter(|&i| {
            infos[i].obstructs(params.height_cutoff_m, params.walkable_height_m)
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
        max_pieces: work.max_pieces,
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
                .map(|&s| side_access(scene, k, o, s, params, &blockers, work, deadline))
                .collect::<Result<_, _>>()?;
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

/// The free part of one strip: the strip over the floors minus the blocking footprints, which
/// are subtracted one at a time in scene order (polling `deadline` before each).
#[allow(clippy::too_many_arguments)]
fn side_access(
    scene: &Scene,
    own: usize,
    o: &SceneObject,
    side: Side,
    params: &AccessibilityParams,
    blockers: &Blockers<'_>,
    work: &Counters,
    deadline: &Deadline,
) -> Result<SideAccess, PlausibilityError> {
    let strip = access_strip(o, side, params.strip_offset_m, params.strip_width_m);
    let strip_area = area(&strip);
    let sb = bounds(&strip);
    let mut parts: Vec<Vec<Point2>> = blockers
        .piece_index
        .query_flat(&sb, &work.index)
        .into_iter()
        .map(|k| &blockers.pieces[k])
        .filter(|p| boxes_overlap(&p.bounds, &sb))
        .map(|p| clip_convex(&strip, &p.poly))
        .filter(|p| p.len() >= 3)
        .collect();
    let on_floor_area = total_area(&parts);
    let mut blocked_by = Vec::new();
    let mut most = parts.len();
    for m in blockers.index.query_flat(&sb, &work.index) {
        let k = blockers.members[m];
        let (footprint, fb) = blockers.infos[k].footprint_of(blockers.kind);
        if k == own || !boxes_overlap(fb, &sb) {
            continue;
        }
        deadline.check("accessibility")?;
        let before = total_area(&parts);
        parts = parts.iter().flat_map(|p| subtract_convex(p, footprint)).collect();
        work.subtractions.fetch_add(1, Ordering::Relaxed);
        work.pieces.fetch_add(parts.len() as u64, Ordering::Relaxed);
        most = most.max(parts.len());
        if parts.len() > blockers.max_pieces {
            return Err(PlausibilityError::TooManyPieces {
                object: o.id().clone(),
                side,
                pieces: parts.len(),
                max: blockers.max_pieces,
            });
        }
        let after = total_area(&parts);
        if before - after > 1e-12 {
            blocked_by.push(scene.objects()[k].id().clone());
        }
    }
    work.most_pieces.fetch_max(most as u64, Ordering::Relaxed);
    let free_area = total_area(&parts);
    Ok(SideAccess {
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
    })
}

pub(crate) fn validate(params: &AccessibilityParams) -> Result<(), PlausibilityError> {
    params.validate()
}

/// Sum of the pieces' areas, starting from +0 (an empty float `sum` is -0).
fn total_area(parts: &[Vec<Point2>]) -> Real {
    parts.iter().fold(0.0, |acc, p| acc + area(p))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::GivenFunctionalSides;
    use sceneeval_geom::Vector3;
    use sceneeval_geom::conventions::pose_from_yaw;
    use sceneeval_scene::{Category, RoomBuilder};

    #[test]
    fn a_strip_split_beyond_the_limit_fails_with_the_object_and_side() {
        // A 2 m long strip in front of a cabinet, crossed by ten thin posts (0.05 m wide,
        // turned 45 degrees) spread along it: its free part is left in about three pieces
        // per post (the parts of the strip between posts and beside each one).
        let mut b = Scene::builder()
            .room_builder(RoomBuilder::rectangle(
                "r0",
                Point2::new(0.0, 0.0),
                Point2::new(6.0, 6.0),
            ))
            .add_box(
                "cabinet",
                Category::new("cabinet"),
                Vector3::new(1.0, 0.3, 0.5),
                pose_from_yaw(Point3::new(3.0, 3.0, 0.5), 0.0),
            );
        for k in 0..10 {
            b = b.add_box(
                format!("post{k}"),
                Category::new("post"),
                Vector3::new(0.025, 0.025, 1.0),
                pose_from_yaw(Point3::new(2.1 + 0.2 * f64::from(k), 2.6, 1.0), 0.785),
            );
        }
        let scene = b.build().unwrap();
        let mut sides = GivenFunctionalSides::default();
        sides.insert("cabinet", vec![Side::Front]);
        let params = AccessibilityParams::default();
        let infos = object_infos(&scene);
        let pieces = scene_floor_pieces(&scene);
        let run = |max_pieces| {
            let work = Counters {
                max_pieces,
                ..Counters::default()
            };
            let r = accessibility_counted(&scene, &params, &sides, &infos, &pieces, &work, &Deadline::none());
            (r, work.total())
        };
        let (report, work) = run(MAX_STRIP_PIECES);
        let front = &report.unwrap().objects[0].sides[0];
        assert_eq!(front.blocked_by.len(), 10);
        assert_eq!(work.subtractions, 10);
        let most = work.most_pieces as usize;
        assert!((10..=40).contains(&most), "{work:?}");
        // The same scene under a limit one below what its strip needs.
        let (err, _) = run(most - 1);
        let err = err.unwrap_err();
        assert!(
            matches!(&err, PlausibilityError::TooManyPieces { object, side: Side::Front, max, .. }
                if object.as_str() == "cabinet" && *max == most - 1),
            "{err}"
        );
        assert!(
            err.to_string().contains("front access strip of object cabinet"),
            "{err}"
        );
    }
}
