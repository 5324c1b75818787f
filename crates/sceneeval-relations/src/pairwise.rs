//! The 13 object-object predicates as kernels on plain geometry.
//!
//! Every kernel takes the target `a` (the reference's "first other object") and the anchor
//! `b` (the reference's "reference object") and returns a score in `[0, 1]`; the relation
//! holds when the score is above [`RelationParams::threshold`].
//!
//! # Performance
//! No kernel allocates. The volume-fraction kernels (`inside_of`, `outside_of`, `side_of`,
//! `side_region`, `long_short_side_of`, `on_top`) clip the target's box by at most six planes
//! on the stack; `middle_of` and `surround` use centroids only; the distance kernels bracket
//! a box-box distance by corner distances (GJK when that does not pin it down), and for meshes
//! try cheap bounds before a branch and bound over their distance trees; `face_to` clips a few
//! quadrilaterals on the stack for a box anchor and casts a fixed grid of rays for a mesh
//! anchor.

use sceneeval_geom::{Obb, Point3, Real, Rotation3, Side, Vector3};

use crate::clip::{HalfSpace, MAX_PLANES, box_volume_inside};
use crate::distance::{distance_bounds, object_distance};
use crate::params::{DistanceBand, DistanceFrom, OnTopPlane, SurroundVariant};
use crate::{LongShort, ObjectGeom, RelationParams};

/// A region that is an axis-aligned box (possibly unbounded) in some frame: per local axis,
/// an interval `[lo, hi]` (infinite ends allowed).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameBox {
    pub lo: [Real; 3],
    pub hi: [Real; 3],
}

impl FrameBox {
    const ALL: FrameBox = FrameBox {
        lo: [Real::NEG_INFINITY; 3],
        hi: [Real::INFINITY; 3],
    };
}

/// How a [`FrameBox`] made from an anchor's box moves with the anchor's half extents:
/// `lo[i]` is the derivative of the region's `lo[i]` with respect to them (gradients only).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameBoxJacobian {
    pub lo: [Vector3; 3],
    pub hi: [Vector3; 3],
}

impl FrameBoxJacobian {
    pub(crate) const ZERO: FrameBoxJacobian = FrameBoxJacobian {
        lo: [Vector3::new(0.0, 0.0, 0.0); 3],
        hi: [Vector3::new(0.0, 0.0, 0.0); 3],
    };
}

/// The target's half extents with the flat-box floor applied.
#[inline]
pub(crate) fn effective_half(obb: &Obb, params: &RelationParams) -> Vector3 {
    obb.half_extents.map(|h| h.max(params.min_half_extent_m))
}

/// The fraction of `a`'s box volume inside `region`, given in the frame with rotation
/// `frame_rot` and origin `frame_origin`. Exact (convex clipping), continuous in both poses.
pub(crate) fn fraction_in_frame_box(
    a: &Obb,
    frame_rot: &Rotation3,
    frame_origin: &Point3,
    region: &FrameBox,
    params: &RelationParams,
) -> Real {
    BoxInFrame::new(a, frame_rot, frame_origin, params).fraction_in(region)
}

/// Which bound of a [`FrameBox`] a half-space of [`RegionPlanes`] comes from: its axis and
/// whether it is the upper one.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct PlaneOf {
    pub axis: usize,
    pub upper: bool,
}

/// The half-spaces of a [`FrameBox`] in the box's own frame (finite bounds only).
pub(crate) struct RegionPlanes {
    pub planes: [HalfSpace; MAX_PLANES],
    pub of: [PlaneOf; MAX_PLANES],
    pub len: usize,
}

/// A box seen from a frame, for the fractions of its volume in regions of that frame
/// ([`fraction_in_frame_box`] for one region; [`long_short_side_of`] asks about two).
pub(crate) struct BoxInFrame {
    /// The box's half extents, with the flat-box floor applied.
    pub h: Vector3,
    /// Columns: the frame's axes in the box's frame.
    m: Rotation3,
    /// The box's centre in the frame.
    t: Vector3,
}

impl BoxInFrame {
    pub(crate) fn new(
        a: &Obb,
        frame_rot: &Rotation3,
        frame_origin: &Point3,
        params: &RelationParams,
    ) -> Self {
        BoxInFrame {
            h: effective_half(a, params),
            m: a.rotation.inverse() * frame_rot,
            t: frame_rot.inverse_transform_vector(&(a.center - frame_origin)),
        }
    }

    /// The half-spaces bounding `region`, in the box's frame; `None` when an infinite bound
    /// excludes everything.
    pub(crate) fn planes(&self, region: &FrameBox) -> Option<RegionPlanes> {
        let (m, t) = (&self.m, &self.t);
        let mut out = RegionPlanes {
            planes: [HalfSpace::new(Vector3::zeros(), 0.0); MAX_PLANES],
            of: [PlaneOf::default(); MAX_PLANES],
            len: 0,
        };
        let mut k = 0;
        for i in 0..3 {
            let axis = m.matrix().column(i).into_owned();
            if region.hi[i].is_finite() {
                out.planes[k] = HalfSpace::new(axis, region.hi[i] - t[i]);
                out.of[k] = PlaneOf { axis: i, upper: true };
                k += 1;
            } else if region.hi[i] < 0.0 {
                return None;
            }
            if region.lo[i].is_finite() {
                out.planes[k] = HalfSpace::new(-axis, t[i] - region.lo[i]);
                out.of[k] = PlaneOf {
                    axis: i,
                    upper: false,
                };
                k += 1;
            } else if region.lo[i] > 0.0 {
                return None;
            }
        }
        out.len = k;
        Some(out)
    }

    /// The fraction of the box's volume inside `region`.
    pub(crate) fn fraction_in(&self, region: &FrameBox) -> Real {
        let h = &self.h;
        let Some(r) = self.planes(region) else {
            return 0.0;
        };
        let full = 8.0 * h.x * h.y * h.z;
        (box_volume_inside(h, &r.planes[..r.len]) / full).clamp(0.0, 1.0)
    }
}

/// The region of [`inside_of`]: the anchor's box with its faces moved out by the tolerance.
pub(crate) fn inside_box(b: &Obb, tol: Real) -> (FrameBox, FrameBoxJacobian) {
    let h = b.half_extents;
    let region = FrameBox {
        lo: [-h.x - tol, -h.y - tol, -h.z - tol],
        hi: [h.x + tol, h.y + tol, h.z + tol],
    };
    let mut jac = FrameBoxJacobian::ZERO;
    for i in 0..3 {
        jac.lo[i][i] = -1.0;
        jac.hi[i][i] = 1.0;
    }
    (region, jac)
}

/// `inside_of`: the fraction of the target's box inside the anchor's box.
///
/// Exact: the target's box is clipped by the anchor's six face planes (moved outward by
/// [`RelationParams::tolerance_m`], as the reference's containment test). The reference
/// estimates the same fraction from random samples.
///
/// ```
/// use sceneeval_relations::{inside_of, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let cabinet = Obb::from_yaw(Point3::new(0.0, 0.0, 1.0), Vector3::new(0.5, 0.3, 1.0), 0.0).unwrap();
/// // A cup of 0.1 m half size whose centre is 0.45 m right of the cabinet's: x in [0.35, 0.55],
/// // so 0.15 of its 0.2 m width is inside (plus the 1e-6 m tolerance).
/// let cup = Obb::from_yaw(Point3::new(0.45, 0.0, 1.0), Vector3::repeat(0.1), 0.0).unwrap();
/// let s = inside_of(&ObjectGeom::from_box(&cup), &ObjectGeom::from_box(&cabinet), &RelationParams::default());
/// assert!((s - 0.75).abs() < 1e-5);
/// ```
pub fn inside_of(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    let (region, _) = inside_box(anchor.obb, params.tolerance_m);
    fraction_in_frame_box(
        target.obb,
        &anchor.obb.rotation,
        &anchor.obb.center,
        &region,
        params,
    )
}

/// `outside_of`: `1 - inside_of`.
pub fn outside_of(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    1.0 - inside_of(target, anchor, params)
}

/// The region beyond the anchor's `side` face (or beyond its centre plane when
/// `from_centre`), unbounded outward, laterally within the anchor's half extents enlarged by
/// `margin` (relative).
pub(crate) fn side_region_box(
    b: &Obb,
    side: Side,
    from_centre: bool,
    margin: Real,
    tol: Real,
) -> (FrameBox, FrameBoxJacobian) {
    let (k, sign) = side.axis_and_sign();
    let h = b.half_extents;
    let mut region = FrameBox::ALL;
    let mut jac = FrameBoxJacobian::ZERO;
    for j in 0..3 {
        if j != k {
            region.lo[j] = -h[j] * (1.0 + margin);
            region.hi[j] = h[j] * (1.0 + margin);
            jac.lo[j][j] = -(1.0 + margin);
            jac.hi[j][j] = 1.0 + margin;
        }
    }
    let (start, d_start) = if from_centre {
        (-tol, 0.0)
    } else {
        (h[k] - tol, 1.0)
    };
    if sign > 0.0 {
        region.lo[k] = start;
        jac.lo[k][k] = d_start;
    } else {
        region.hi[k] = -start;
        jac.hi[k][k] = -d_start;
    }
    (region, jac)
}

/// The region of [`side_region`]: the `side` half of the anchor's box.
pub(crate) fn side_half_box(b: &Obb, side: Side, params: &RelationParams) -> (FrameBox, FrameBoxJacobian) {
    let (k, sign) = side.axis_and_sign();
    let h = b.half_extents;
    let tol = params.tolerance_m;
    let mut region = FrameBox::ALL;
    let mut jac = FrameBoxJacobian::ZERO;
    for j in 0..3 {
        let (scaled, padded) = (h[j] * (1.0 + params.region_margin), h[j] + tol);
        let lateral = scaled.min(padded);
        // The derivative of the branch `min` takes (the scaled one on a tie).
        let d = if scaled <= padded {
            1.0 + params.region_margin
        } else {
            1.0
        };
        region.lo[j] = -lateral;
        region.hi[j] = lateral;
        jac.lo[j][j] = -d;
        jac.hi[j][j] = d;
    }
    if sign > 0.0 {
        region.lo[k] = -tol;
        region.hi[k] = h[k] + tol;
        jac.lo[k][k] = 0.0;
        jac.hi[k][k] = 1.0;
    } else {
        region.lo[k] = -h[k] - tol;
        region.hi[k] = tol;
        jac.lo[k][k] = -1.0;
        jac.hi[k][k] = 0.0;
    }
    (region, jac)
}

/// The two sides `long_short_side_of(which)` compares for anchor `b`, or `None` when its width
/// and depth are equal (no long or short side).
pub(crate) fn long_short_sides(b: &Obb, which: LongShort) -> Option<(Side, Side)> {
    let full = b.extents();
    if (full.x - full.y).abs() <= 1e-8 + 1e-5 * full.y.abs() {
        return None;
    }
    Some(match (which, full.x < full.y) {
        // Longer along y: the long sides face +-x.
        (LongShort::Long, true) | (LongShort::Short, false) => (Side::Right, Side::Left),
        (LongShort::Long, false) | (LongShort::Short, true) => (Side::Back, Side::Front),
    })
}

/// `side_of(side)`: the fraction of the target's box beyond the anchor's `side` face, within
/// the face's extent enlarged sideways by [`RelationParams::side_of_margin`] (25 % of each
/// lateral half extent) and without limit away from the face.
///
/// This is what the reference computes (`at_side` with `no_contain`); the paper's wording
/// "extended by 25 % in each dimension" is looser. Sides follow the object convention: left is
/// the anchor's local -x (the left of a viewer facing the anchor's front).
///
/// ```
/// use sceneeval_relations::{side_of, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, Side, na::{Point3, Vector3}};
/// let bed = Obb::from_yaw(Point3::new(0.0, 0.0, 0.3), Vector3::new(0.8, 1.0, 0.3), 0.0).unwrap();
/// // A nightstand touching the bed's -x face: wholly on the bed's left.
/// let stand = Obb::from_yaw(Point3::new(-1.05, 0.7, 0.3), Vector3::new(0.25, 0.2, 0.3), 0.0).unwrap();
/// let p = RelationParams::default();
/// let (a, b) = (ObjectGeom::from_box(&stand), ObjectGeom::from_box(&bed));
/// assert_eq!(side_of(&a, &b, Side::Left, &p), 1.0);
/// assert_eq!(side_of(&a, &b, Side::Right, &p), 0.0);
/// ```
pub fn side_of(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    side: Side,
    params: &RelationParams,
) -> Real {
    let (region, _) = side_region_box(anchor.obb, side, false, params.side_of_margin, params.tolerance_m);
    fraction_in_frame_box(
        target.obb,
        &anchor.obb.rotation,
        &anchor.obb.center,
        &region,
        params,
    )
}

/// `side_region(side)`: the fraction of the target's box that is inside the anchor's box and
/// on the `side` half of it (beyond the anchor's centre plane perpendicular to that side).
pub fn side_region(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    side: Side,
    params: &RelationParams,
) -> Real {
    let (region, _) = side_half_box(anchor.obb, side, params);
    fraction_in_frame_box(
        target.obb,
        &anchor.obb.rotation,
        &anchor.obb.center,
        &region,
        params,
    )
}

/// `long_short_side_of(long|short)`: the larger of the fractions of the target's box on
/// either side of the anchor's centre plane across its long (or short) horizontal dimension,
/// within the anchor's extent along the other two axes (unbounded outward).
///
/// The long sides of an anchor that is longer along local y are at local +-x. An anchor whose
/// width and depth are equal (numpy's `allclose`: within `1e-8 + 1e-5 * depth`) has no long or
/// short side and scores 0, as in the reference.
pub fn long_short_side_of(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    which: LongShort,
    params: &RelationParams,
) -> Real {
    let Some(axis_side) = long_short_sides(anchor.obb, which) else {
        return 0.0;
    };
    // The target in the anchor's frame, once for both sides.
    let target_box = BoxInFrame::new(target.obb, &anchor.obb.rotation, &anchor.obb.center, params);
    let score = |side: Side| {
        let (region, _) = side_region_box(anchor.obb, side, true, params.region_margin, params.tolerance_m);
        target_box.fraction_in(&region)
    };
    score(axis_side.0).max(score(axis_side.1))
}

/// `on_top`: the fraction of the target's box above the anchor's top face (default) or its
/// centre plane ([`OnTopPlane::CentrePlane`], the reference's configured behaviour), within
/// the anchor's footprint, without a height limit.
///
/// ```
/// use sceneeval_relations::{on_top, ObjectGeom, OnTopPlane, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let table = Obb::from_yaw(Point3::new(0.0, 0.0, 0.375), Vector3::new(0.6, 0.4, 0.375), 0.0).unwrap();
/// // A book sunk 1 cm into the table top (z in [0.74, 0.78]): 3 of its 4 cm are above the top.
/// let book = Obb::from_yaw(Point3::new(0.1, 0.0, 0.76), Vector3::new(0.1, 0.15, 0.02), 0.0).unwrap();
/// let (a, b) = (ObjectGeom::from_box(&book), ObjectGeom::from_box(&table));
/// let top_face = on_top(&a, &b, &RelationParams::default());
/// assert!((top_face - 0.75).abs() < 1e-4);
/// let centre = on_top(&a, &b, &RelationParams { on_top_plane: OnTopPlane::CentrePlane, ..Default::default() });
/// assert_eq!(centre, 1.0);
/// ```
pub fn on_top(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    let from_centre = params.on_top_plane == OnTopPlane::CentrePlane;
    let (region, _) = side_region_box(
        anchor.obb,
        Side::Top,
        from_centre,
        params.region_margin,
        params.tolerance_m,
    );
    fraction_in_frame_box(
        target.obb,
        &anchor.obb.rotation,
        &anchor.obb.center,
        &region,
        params,
    )
}

/// `middle_of`: a Gaussian of the plan-view (x, y) distance between the two boxes' centres,
/// `exp(-d^2 / (2 sigma^2))` with [`RelationParams::middle_of_sigma_m`] (0.25 m; holds for
/// `d < 0.294` m).
pub fn middle_of(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    let d = target.obb.center - anchor.obb.center;
    let d2 = d.x * d.x + d.y * d.y;
    let s = params.middle_of_sigma_m;
    (-d2 / (2.0 * s * s)).exp()
}

/// The distance the four distance relations score (metres): between the objects' closest
/// points as solids ([`DistanceFrom::Geometry`]), or from the box of the object with the
/// smaller box volume to the other object ([`DistanceFrom::SmallerBox`], ties: from the
/// anchor's box, as the reference).
pub fn pair_distance(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    let (x, y) = distance_views(target, anchor, params);
    object_distance(&x, &y)
}

/// The band score of the pair's distance. With a mesh involved, cheap bounds on the distance
/// come first: when both lie in the band's range the score is exactly 1 without the exact
/// (branch-and-bound) distance.
fn band(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    band: &DistanceBand,
    params: &RelationParams,
) -> Real {
    if target.mesh.is_some() || anchor.mesh.is_some() {
        let (x, y) = distance_views(target, anchor, params);
        let (lo, hi) = distance_bounds(&x, &y);
        if lo >= band.min_m && hi <= band.max_m {
            return 1.0;
        }
    }
    band.score(pair_distance(target, anchor, params))
}

/// The two views the distance relations measure between (see [`pair_distance`]).
pub(crate) fn distance_views<'a>(
    target: &ObjectGeom<'a>,
    anchor: &ObjectGeom<'a>,
    params: &RelationParams,
) -> (ObjectGeom<'a>, ObjectGeom<'a>) {
    match params.distance_from {
        DistanceFrom::Geometry => (*target, *anchor),
        DistanceFrom::SmallerBox => {
            let m = params.min_half_extent_m;
            let vol = |o: &Obb| o.half_extents.map(|h| h.max(m)).product();
            if vol(target.obb) < vol(anchor.obb) {
                (target.as_box(), *anchor)
            } else {
                (*target, anchor.as_box())
            }
        }
    }
}

/// `next_to`: the objects' distance ([`pair_distance`]) in [0, 0.5] m scores 1, with a
/// Gaussian fall-off (sigma 0.25 m) outside; holds below about 0.794 m.
pub fn next_to(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    band(target, anchor, &params.next_to, params)
}

/// `near`: distance in [0.5, 1.5] m; holds between about 0.206 and 1.794 m.
pub fn near(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    band(target, anchor, &params.near, params)
}

/// `across_from`: distance in [1.5, 4] m; holds between about 1.206 and 4.294 m.
pub fn across_from(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    band(target, anchor, &params.across_from, params)
}

/// `far`: distance of at least 4 m; holds above about 3.706 m.
pub fn far(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    band(target, anchor, &params.far, params)
}

/// Targets handled in buffers on the stack by [`surround`]; beyond this many it sorts in a
/// vector (its only allocation).
const SURROUND_STACK: usize = 64;

/// Runs `f` on a zeroed scratch slice of length `n`: on the stack up to [`SURROUND_STACK`],
/// else in a vector.
pub(crate) fn with_scratch<T: Copy + Default, R>(n: usize, f: impl FnOnce(&mut [T]) -> R) -> R {
    if n <= SURROUND_STACK {
        let mut buf = [T::default(); SURROUND_STACK];
        f(&mut buf[..n])
    } else {
        f(&mut vec![T::default(); n])
    }
}

/// `surround`: how evenly the targets are spread around the anchor, in `[0, 1]`; 0 with fewer
/// than three targets.
///
/// With `N` targets, centroid distances `r_i` to the anchor's centroid, ideal distance `D` and
/// ideal angle `A = 2 pi / N`: `d_i = min(|r_i - D| / D, 1)`, `a_i = min(|theta_i - A| / A, 1)`
/// and the score is `(1/N) sum_i [w_d (1 - d_i)^2 + w_a (1 - a_i)^2]` with both weights 0.5
/// (the paper's formula).
///
/// [`SurroundVariant::Paper`] (default): `D` is the mean of the `r_i` (3-D centroid
/// distances), and `theta_i` is target `i`'s counter-clockwise gap, seen from above, to the
/// next target around the anchor (the gaps of N targets sum to `2 pi`).
/// [`SurroundVariant::Reference`]: `D` is the median, `theta_i` the smallest positive signed
/// angle between 3-D directions (sign from the vertical), or the largest negative one when no
/// target lies counter-clockwise within 180 degrees (which always gives `a_i = 1`).
///
/// A target at the anchor's centroid (no direction) gets `a_i = 1`; `D = 0` gives `d_i = 1`.
///
/// # Cost
/// The paper variant sorts the targets' plan angles once: `O(N log N)`, on the stack for up
/// to 64 targets (no allocation) and in one vector beyond. The reference variant compares
/// every pair of directions, `O(N^2)`; `SceneRelations` refuses it beyond
/// [`crate::SURROUND_REFERENCE_MAX_TARGETS`] targets.
///
/// ```
/// use sceneeval_relations::{surround, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let table = Obb::from_yaw(Point3::new(0.0, 0.0, 0.4), Vector3::new(0.5, 0.5, 0.4), 0.0).unwrap();
/// let chair = |x: f64, y: f64| Obb::from_yaw(Point3::new(x, y, 0.4), Vector3::repeat(0.25), 0.0).unwrap();
/// let chairs = [chair(1.0, 0.0), chair(0.0, 1.0), chair(-1.0, 0.0), chair(0.0, -1.0)];
/// let targets: Vec<ObjectGeom> = chairs.iter().map(ObjectGeom::from_box).collect();
/// // Four chairs 1 m away at 90-degree gaps: every deviation is 0, the score 1.
/// assert_eq!(surround(&targets, &ObjectGeom::from_box(&table), &RelationParams::default()), 1.0);
/// ```
pub fn surround(targets: &[ObjectGeom<'_>], anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    surround_centres(
        targets.len(),
        |i| targets[i].obb.center,
        &anchor.obb.center,
        params,
    )
}

/// [`surround`] on the targets' box centres, given by index (`centre(i)` for `i < n`).
pub(crate) fn surround_centres(
    n: usize,
    centre: impl Fn(usize) -> Point3,
    anchor: &Point3,
    params: &RelationParams,
) -> Real {
    surround_core(n, centre, anchor, params, None)
}

/// [`surround_centres`], and with `grad` (of length `n`) the score's derivatives with respect
/// to each target's centre (see [`surround_gradient`]).
pub(crate) fn surround_core(
    n: usize,
    centre: impl Fn(usize) -> Point3,
    anchor: &Point3,
    params: &RelationParams,
    grad: Option<&mut [Vector3]>,
) -> Real {
    if n < 3 {
        return 0.0;
    }
    let offset = |i: usize| centre(i) - anchor;
    let r = |i: usize| offset(i).norm();
    let ideal_d = match params.surround_variant {
        SurroundVariant::Paper => (0..n).map(r).sum::<Real>() / n as Real,
        SurroundVariant::Reference => with_scratch(n, |rs: &mut [Real]| {
            for (i, slot) in rs.iter_mut().enumerate() {
                *slot = r(i);
            }
            rs.sort_unstable_by(Real::total_cmp);
            if n % 2 == 1 {
                rs[n / 2]
            } else {
                0.5 * (rs[n / 2 - 1] + rs[n / 2])
            }
        }),
    };
    let ideal_a = std::f64::consts::TAU / n as Real;
    let score = |thetas: &[Option<(Real, usize)>]| {
        let mut total = 0.0;
        for (i, theta) in thetas.iter().enumerate() {
            let d_i = if ideal_d > 0.0 {
                ((r(i) - ideal_d).abs() / ideal_d).min(1.0)
            } else {
                1.0
            };
            let a_i = match theta {
                Some((t, _)) => ((t - ideal_a).abs() / ideal_a).min(1.0),
                None => 1.0,
            };
            total += params.surround_distance_weight * (1.0 - d_i).powi(2)
                + params.surround_angle_weight * (1.0 - a_i).powi(2);
        }
        (total / n as Real).clamp(0.0, 1.0)
    };
    with_scratch(n, |thetas: &mut [Option<(Real, usize)>]| {
        match params.surround_variant {
            SurroundVariant::Paper => with_scratch(n, |angles: &mut [(Real, usize)]| {
                plan_gaps(&offset, angles, thetas);
            }),
            SurroundVariant::Reference => {
                for (i, theta) in thetas.iter_mut().enumerate() {
                    *theta = reference_neighbour_angle(&offset, n, i);
                }
            }
        }
        let value = score(thetas);
        if let Some(grad) = grad {
            let ideal = Ideal {
                d: ideal_d,
                a: ideal_a,
                median: match params.surround_variant {
                    SurroundVariant::Paper => None,
                    SurroundVariant::Reference => Some(median_indices(n, &r)),
                },
            };
            surround_gradient(&offset, &ideal, thetas, params, grad);
        }
        value
    })
}

/// The ideal distance and angle of [`surround`], and for the reference variant the targets
/// whose distances the median is taken of (the same one twice for an odd count).
struct Ideal {
    d: Real,
    a: Real,
    median: Option<(usize, usize)>,
}

/// The targets whose distances `r` make the median (as sorted by [`surround_core`]).
fn median_indices(n: usize, r: &impl Fn(usize) -> Real) -> (usize, usize) {
    with_scratch(n, |rs: &mut [(Real, usize)]| {
        for (i, slot) in rs.iter_mut().enumerate() {
            *slot = (r(i), i);
        }
        rs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        if n % 2 == 1 {
            (rs[n / 2].1, rs[n / 2].1)
        } else {
            (rs[n / 2 - 1].1, rs[n / 2].1)
        }
    })
}

/// The derivatives of [`surround`]'s score with respect to the targets' centres, into `grad`,
/// given each target's neighbour angle and neighbour (`thetas`). A deviation clipped at 1
/// contributes nothing; at a deviation of exactly 0 (where `|x|` turns) its derivative is
/// taken as 0, the mean of the two one-sided ones.
fn surround_gradient(
    offset: &impl Fn(usize) -> Vector3,
    ideal: &Ideal,
    thetas: &[Option<(Real, usize)>],
    params: &RelationParams,
    grad: &mut [Vector3],
) {
    let n = thetas.len();
    for g in grad.iter_mut() {
        *g = Vector3::zeros();
    }
    let sign = |x: Real| {
        if x > 0.0 {
            1.0
        } else if x < 0.0 {
            -1.0
        } else {
            0.0
        }
    };
    let unit = |i: usize| offset(i).try_normalize(0.0).unwrap_or_else(Vector3::zeros);
    // The total before clamping: outside [0, 1] the score is flat.
    let mut total = 0.0;
    // Sum over targets of d(term_i)/dD, the ideal distance's share.
    let mut through_ideal = 0.0;
    for (i, theta) in thetas.iter().enumerate() {
        let (r_i, ideal_d) = (offset(i).norm(), ideal.d);
        let d_i = if ideal_d > 0.0 {
            ((r_i - ideal_d).abs() / ideal_d).min(1.0)
        } else {
            1.0
        };
        if ideal_d > 0.0 && d_i < 1.0 {
            let e = r_i - ideal_d;
            let coef = -2.0 * params.surround_distance_weight * (1.0 - d_i);
            grad[i] += unit(i) * (coef * sign(e) / ideal_d);
            through_ideal -= coef * (sign(e) / ideal_d + e.abs() / (ideal_d * ideal_d));
        }
        let mut a_i = 1.0;
        if let Some((t, j)) = *theta {
            a_i = ((t - ideal.a).abs() / ideal.a).min(1.0);
            if a_i < 1.0 {
                let coef = -2.0 * params.surround_angle_weight * (1.0 - a_i) * sign(t - ideal.a) / ideal.a;
                let (di, dj) = match ideal.median {
                    // The gap phi_j - phi_i (mod 2 pi).
                    None => (-plan_angle_grad(&offset(i)), plan_angle_grad(&offset(j))),
                    Some(_) => spatial_angle_grad(&offset(i), &offset(j), t),
                };
                grad[i] += di * coef;
                grad[j] += dj * coef;
            }
        }
        total += params.surround_distance_weight * (1.0 - d_i).powi(2)
            + params.surround_angle_weight * (1.0 - a_i).powi(2);
    }
    let mean = total / n as Real;
    if !(0.0..=1.0).contains(&mean) {
        for g in grad.iter_mut() {
            *g = Vector3::zeros();
        }
        return;
    }
    // The ideal distance: the mean of every distance, or the median's one or two.
    match ideal.median {
        None => {
            for (k, g) in grad.iter_mut().enumerate() {
                *g += unit(k) * (through_ideal / n as Real);
            }
        }
        Some((m1, m2)) => {
            grad[m1] += unit(m1) * (0.5 * through_ideal);
            grad[m2] += unit(m2) * (0.5 * through_ideal);
        }
    }
    for g in grad.iter_mut() {
        *g /= n as Real;
    }
}

/// The derivative of the plan angle `atan2(o.y, o.x)` with respect to `o` (0 on the axis).
fn plan_angle_grad(o: &Vector3) -> Vector3 {
    let q = o.x * o.x + o.y * o.y;
    if q > 0.0 {
        Vector3::new(-o.y / q, o.x / q, 0.0)
    } else {
        Vector3::zeros()
    }
}

/// The derivatives of the signed 3-D angle `t` from direction `oi` to `oj` (the reference's
/// neighbour angle, `+-acos` of their cosine) with respect to `oi` and `oj` (0 where the
/// cosine is +-1).
fn spatial_angle_grad(oi: &Vector3, oj: &Vector3, t: Real) -> (Vector3, Vector3) {
    let (li, lj) = (oi.norm(), oj.norm());
    let (ui, uj) = (oi / li, oj / lj);
    let c = ui.dot(&uj);
    let s = (1.0 - c * c).sqrt();
    if s.is_nan() || s <= 0.0 {
        return (Vector3::zeros(), Vector3::zeros());
    }
    let k = -t.signum() / s;
    ((uj - ui * c) * (k / li), (ui - uj * c) * (k / lj))
}

/// For every target `i`, its counter-clockwise plan-view gap to the next target with a
/// direction and that target (`None` without a direction or without another target with
/// one), into `gaps[i]`; `angles` is scratch of the same length.
///
/// The gap from `i` to `j` is `(phi_j - phi_i) mod 2 pi` for plan angles `phi` (`atan2`). Over
/// the `j` with `phi_j >= phi_i` it is smallest for the next angle in sorted order (or 0 for
/// an equal one just before it), over the others for the smallest angle: both are monotone in
/// `phi_j` in floating point too, so three candidates per target after one sort give exactly
/// the minimum over all pairs.
fn plan_gaps(
    offset: &impl Fn(usize) -> Vector3,
    angles: &mut [(Real, usize)],
    gaps: &mut [Option<(Real, usize)>],
) {
    let mut m = 0;
    for (i, gap) in gaps.iter_mut().enumerate() {
        *gap = None;
        let o = offset(i);
        if !(o.x == 0.0 && o.y == 0.0) {
            angles[m] = (o.y.atan2(o.x), i);
            m += 1;
        }
    }
    let angles = &mut angles[..m];
    angles.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let tau = std::f64::consts::TAU;
    for p in 0..m {
        let (phi, i) = angles[p];
        let gap_to = |q: usize| {
            #[cfg(test)]
            tests::GAPS.with(|c| c.set(c.get() + 1));
            ((angles[q].0 - phi).rem_euclid(tau), angles[q].1)
        };
        let mut best: Option<(Real, usize)> = None;
        // The smallest gap (the first of equal ones).
        let mut take = |(g, j): (Real, usize)| {
            best = Some(best.map_or((g, j), |b: (Real, usize)| if g < b.0 { (g, j) } else { b }));
        };
        if p + 1 < m {
            take(gap_to(p + 1));
        }
        if p > 0 && angles[p - 1].0 == phi {
            take(gap_to(p - 1));
        }
        if p > 0 && angles[0].0 < phi {
            take(gap_to(0));
        }
        gaps[i] = best;
    }
}

/// The reference's neighbour angle: signed 3-D angles, smallest positive, else largest; with
/// the target it is taken to.
fn reference_neighbour_angle(
    offset: &impl Fn(usize) -> Vector3,
    n: usize,
    i: usize,
) -> Option<(Real, usize)> {
    let ui = offset(i).try_normalize(0.0)?;
    let mut smallest_positive: Option<(Real, usize)> = None;
    let mut largest: Option<(Real, usize)> = None;
    for j in (0..n).filter(|&j| j != i) {
        let Some(uj) = offset(j).try_normalize(0.0) else {
            continue;
        };
        let mut theta = ui.dot(&uj).clamp(-1.0, 1.0).acos();
        if Vector3::z().dot(&ui.cross(&uj)) < 0.0 {
            theta = -theta;
        }
        if theta > 0.0 {
            smallest_positive =
                Some(smallest_positive.map_or((theta, j), |b| if theta < b.0 { (theta, j) } else { b }));
        }
        largest = Some(largest.map_or((theta, j), |b| if theta > b.0 { (theta, j) } else { b }));
    }
    smallest_positive.or(largest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    thread_local! {
        /// Angle gaps evaluated by `plan_gaps` on this thread.
        pub(super) static GAPS: Cell<usize> = const { Cell::new(0) };
    }

    fn gap_values(gaps: &[Option<(Real, usize)>]) -> Vec<Option<Real>> {
        gaps.iter().map(|g| g.map(|(v, _)| v)).collect()
    }

    /// The pairwise definition of the plan gaps: the minimum over every other target.
    fn brute_gaps(offsets: &[Vector3]) -> Vec<Option<Real>> {
        (0..offsets.len())
            .map(|i| {
                let oi = offsets[i];
                if oi.x == 0.0 && oi.y == 0.0 {
                    return None;
                }
                let phi = oi.y.atan2(oi.x);
                let mut best: Option<Real> = None;
                for (j, oj) in offsets.iter().enumerate() {
                    if j == i || (oj.x == 0.0 && oj.y == 0.0) {
                        continue;
                    }
                    let gap = (oj.y.atan2(oj.x) - phi).rem_euclid(std::f64::consts::TAU);
                    best = Some(best.map_or(gap, |b| b.min(gap)));
                }
                best
            })
            .collect()
    }

    #[test]
    fn sorted_plan_gaps_equal_the_pairwise_minimum_in_linear_work() {
        // Scattered targets with repeated angles, one at the centre, angles of exactly +-pi,
        // and more targets than fit on the stack.
        let mut offsets: Vec<Vector3> = (0..8000)
            .map(|k| {
                let t = f64::from(k);
                let r = 0.5 + (t * 0.37).sin().abs();
                let a = (t * 2.399_963).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
                Vector3::new(r * a.cos(), r * a.sin(), 0.1 * (t * 0.11).cos())
            })
            .collect();
        offsets[10] = offsets[3] * 2.0;
        offsets[11] = Vector3::zeros();
        offsets[12] = Vector3::new(-1.0, 0.0, 0.0);
        offsets[13] = Vector3::new(-1.0, -0.0, 0.0);
        let offset = |i: usize| offsets[i];
        let n = offsets.len();
        let mut angles = vec![(0.0, 0); n];
        let mut gaps = vec![None; n];
        GAPS.with(|c| c.set(0));
        plan_gaps(&offset, &mut angles, &mut gaps);
        // At most three candidates per target, not n - 1.
        assert!(GAPS.with(Cell::get) <= 3 * n, "{}", GAPS.with(Cell::get));
        assert_eq!(gap_values(&gaps), brute_gaps(&offsets));
        // Small cases, including ties, a single directed target and all at the centre.
        for offs in [
            vec![
                Vector3::new(1.0, 0.0, 0.0),
                Vector3::new(2.0, 0.0, 0.0),
                Vector3::new(0.0, 1.0, 0.0),
            ],
            vec![Vector3::new(1.0, 0.0, 0.0), Vector3::zeros(), Vector3::zeros()],
            vec![Vector3::zeros(); 3],
            vec![
                Vector3::new(0.0, -1.0, 0.0),
                Vector3::new(0.0, 1.0, 0.0),
                Vector3::new(-1.0, 0.0, 0.0),
                Vector3::new(-1.0, 0.0, 0.0),
            ],
        ] {
            let mut angles = vec![(0.0, 0); offs.len()];
            let mut gaps = vec![None; offs.len()];
            plan_gaps(&|i| offs[i], &mut angles, &mut gaps);
            assert_eq!(gap_values(&gaps), brute_gaps(&offs), "{offs:?}");
            // The neighbour named is one the gap is to.
            for (i, g) in gaps.iter().enumerate() {
                if let Some((gap, j)) = *g {
                    let phi = |k: usize| offs[k].y.atan2(offs[k].x);
                    assert_eq!(gap, (phi(j) - phi(i)).rem_euclid(std::f64::consts::TAU));
                }
            }
        }
    }
    use std::f64::consts::{FRAC_PI_2, PI};

    fn bx(c: [Real; 3], h: [Real; 3], yaw: Real) -> Obb {
        Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::new(h[0], h[1], h[2]), yaw).unwrap()
    }

    fn g(o: &Obb) -> ObjectGeom<'_> {
        ObjectGeom::from_box(o)
    }

    const EPS: Real = 1e-9;

    #[test]
    fn inside_outside_nested_overlapping_apart() {
        let p = RelationParams::default();
        let big = bx([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0);
        let small = bx([0.2, 0.3, -0.1], [0.2, 0.2, 0.2], 0.7);
        // Nested: the small box's corners reach 0.2 sqrt(2) = 0.283 from its centre; all inside.
        assert_eq!(inside_of(&g(&small), &g(&big), &p), 1.0);
        assert_eq!(outside_of(&g(&small), &g(&big), &p), 0.0);
        // Reversed: the small box holds 0.4^3 / 2^3 = 0.008 of the big one.
        assert!((inside_of(&g(&big), &g(&small), &p) - 0.008).abs() < 1e-6);
        // Overlapping by half along x: a at x in [0.5, 1.5] vs [-1, 1] -> 0.5 of 1.0 (+ tol).
        let half = bx([1.0, 0.0, 0.0], [0.5, 0.5, 0.5], 0.0);
        assert!((inside_of(&g(&half), &g(&big), &p) - 0.5).abs() < 1e-5);
        // Apart.
        let apart = bx([5.0, 0.0, 0.0], [0.5, 0.5, 0.5], 0.0);
        assert_eq!(inside_of(&g(&apart), &g(&big), &p), 0.0);
        assert_eq!(outside_of(&g(&apart), &g(&big), &p), 1.0);
        // Turned 45 degrees at the edge: a unit cube centred on the big box's +x face, rotated
        // about z, has exactly half its volume inside by symmetry about the face plane.
        let diag = bx([1.0, 0.0, 0.0], [0.5, 0.5, 0.5], PI / 4.0);
        assert!((inside_of(&g(&diag), &g(&big), &p) - 0.5).abs() < 1e-5);
    }

    #[test]
    fn side_of_every_side_and_margin() {
        let p = RelationParams::default();
        // Anchor 2 x 2 x 2 at the origin.
        let b = bx([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0);
        let cases = [
            (Side::Left, [-1.5, 0.0, 0.0]),
            (Side::Right, [1.5, 0.0, 0.0]),
            (Side::Front, [0.0, -1.5, 0.0]),
            (Side::Back, [0.0, 1.5, 0.0]),
            (Side::Top, [0.0, 0.0, 1.5]),
            (Side::Bottom, [0.0, 0.0, -1.5]),
        ];
        for (side, c) in cases {
            let a = bx(c, [0.5, 0.5, 0.5], 0.0);
            for other in Side::ALL {
                let s = side_of(&g(&a), &g(&b), other, &p);
                let expected = if other == side { 1.0 } else { 0.0 };
                assert!((s - expected).abs() < EPS, "{side} vs {other}: {s}");
            }
        }
        // Lateral margin: a target on the left, shifted along y so it spans y in [0.9, 1.9].
        // The region reaches y = 1.25, so 0.35 of its 1.0 depth counts.
        let a = bx([-1.5, 1.4, 0.0], [0.5, 0.5, 0.5], 0.0);
        assert!((side_of(&g(&a), &g(&b), Side::Left, &p) - 0.35).abs() < 1e-12);
        // Far away beyond the face still counts (no distance limit).
        let a = bx([-30.0, 0.0, 0.0], [0.5, 0.5, 0.5], 0.0);
        assert_eq!(side_of(&g(&a), &g(&b), Side::Left, &p), 1.0);
        // Straddling the face: a spans x in [-1.5, -0.5]; half of it is beyond x = -1.
        let a = bx([-1.0, 0.0, 0.0], [0.5, 0.5, 0.5], 0.0);
        assert!((side_of(&g(&a), &g(&b), Side::Left, &p) - 0.5).abs() < 1e-5);
    }

    #[test]
    fn side_of_follows_the_anchor_frame() {
        let p = RelationParams::default();
        // Anchor turned 90 degrees: its local -x (left) points to world -y.
        let b = bx([0.0, 0.0, 0.0], [1.0, 0.5, 0.5], FRAC_PI_2);
        let a = bx([0.0, -2.0, 0.0], [0.3, 0.3, 0.3], 0.4);
        assert_eq!(side_of(&g(&a), &g(&b), Side::Left, &p), 1.0);
        assert_eq!(side_of(&g(&a), &g(&b), Side::Front, &p), 0.0);
        // At an arbitrary yaw the same relative placement gives the same score.
        let yaw: Real = 2.2;
        let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw);
        let b2 = Obb {
            rotation: rot * b.rotation,
            ..b
        };
        let a2 = Obb {
            center: Point3::from(rot * a.center.coords),
            rotation: rot * a.rotation,
            ..a
        };
        assert!((side_of(&g(&a2), &g(&b2), Side::Left, &p) - 1.0).abs() < EPS);
    }

    #[test]
    fn side_region_halves() {
        let p = RelationParams::default();
        let b = bx([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0);
        // A book in the left half of a shelf: x in [-0.9, -0.3].
        let a = bx([-0.6, 0.0, 0.0], [0.3, 0.2, 0.2], 0.0);
        assert_eq!(side_region(&g(&a), &g(&b), Side::Left, &p), 1.0);
        assert_eq!(side_region(&g(&a), &g(&b), Side::Right, &p), 0.0);
        // Centred: half left, half right (each side gets 0.5 plus the tolerance sliver).
        let a = bx([0.0, 0.0, 0.0], [0.3, 0.2, 0.2], 0.0);
        assert!((side_region(&g(&a), &g(&b), Side::Left, &p) - 0.5).abs() < 1e-5);
        // Outside the anchor (beyond its left face) is not in the region.
        let a = bx([-1.5, 0.0, 0.0], [0.3, 0.2, 0.2], 0.0);
        assert_eq!(side_region(&g(&a), &g(&b), Side::Left, &p), 0.0);
        // Bottom half, under a table top region.
        let a = bx([0.0, 0.0, -0.5], [0.3, 0.3, 0.3], 0.0);
        assert_eq!(side_region(&g(&a), &g(&b), Side::Bottom, &p), 1.0);
    }

    #[test]
    fn long_and_short_sides() {
        let p = RelationParams::default();
        // A table 2 m long along y, 1 m wide along x: long sides at +-x.
        let t = bx([0.0, 0.0, 0.4], [0.5, 1.0, 0.4], 0.0);
        let chair_long = bx([0.8, 0.2, 0.4], [0.25, 0.25, 0.4], 0.0);
        let chair_short = bx([0.0, -1.3, 0.4], [0.25, 0.25, 0.4], 0.0);
        let ls = |a: &Obb, w| long_short_side_of(&g(a), &g(&t), w, &p);
        assert_eq!(ls(&chair_long, LongShort::Long), 1.0);
        assert_eq!(ls(&chair_short, LongShort::Short), 1.0);
        // The short-side chair is beyond the table's y extent, outside both long-side regions.
        assert_eq!(ls(&chair_short, LongShort::Long), 0.0);
        // A box centred on the table's long axis is split by the plane x = 0: max(0.5, 0.5)
        // (plus the tolerance sliver).
        let centred = bx([0.0, 0.5, 0.4], [0.25, 0.25, 0.4], 0.0);
        assert!((ls(&centred, LongShort::Long) - 0.5).abs() < 1e-5);
        assert_eq!(ls(&chair_long, LongShort::Short), 0.0);
        // Turned 90 degrees, the table's long sides face world +-y.
        let t90 = bx([0.0, 0.0, 0.4], [0.5, 1.0, 0.4], FRAC_PI_2);
        let c = bx([0.2, 0.8, 0.4], [0.25, 0.25, 0.4], 0.0);
        assert_eq!(long_short_side_of(&g(&c), &g(&t90), LongShort::Long, &p), 1.0);
        // A square table has neither.
        let sq = bx([0.0, 0.0, 0.4], [0.5, 0.5, 0.4], 0.0);
        assert_eq!(
            long_short_side_of(&g(&chair_long), &g(&sq), LongShort::Long, &p),
            0.0
        );
    }

    #[test]
    fn on_top_stacked_and_floating() {
        let p = RelationParams::default();
        let table = bx([0.0, 0.0, 0.375], [0.6, 0.4, 0.375], 0.0);
        // Resting exactly on the top (z from 0.75 up): 1.
        let book = bx([0.1, 0.0, 0.77], [0.1, 0.15, 0.02], 1.0);
        assert_eq!(on_top(&g(&book), &g(&table), &p), 1.0);
        // Half hanging over the table's +x edge (x in [0.5, 0.7]): 0.5 within the footprint.
        let over = bx([0.6, 0.0, 0.77], [0.1, 0.1, 0.02], 0.0);
        assert!((on_top(&g(&over), &g(&table), &p) - 0.5).abs() < 1e-6);
        // Under the table: 0.
        let under = bx([0.0, 0.0, 0.2], [0.1, 0.1, 0.1], 0.0);
        assert_eq!(on_top(&g(&under), &g(&table), &p), 0.0);
        // Stacked boxes of a tower: each on top of the one below.
        let b0 = bx([0.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
        let b1 = bx([0.0, 0.0, 1.25], [0.25, 0.25, 0.25], 0.3);
        assert_eq!(on_top(&g(&b1), &g(&b0), &p), 1.0);
        assert_eq!(on_top(&g(&b0), &g(&b1), &p), 0.0);
    }

    #[test]
    fn middle_of_gaussian() {
        let p = RelationParams::default();
        let bed = bx([1.0, 2.0, 0.3], [0.8, 1.0, 0.3], 0.0);
        let pillow = bx([1.0, 2.0, 0.7], [0.3, 0.2, 0.1], 0.0);
        assert_eq!(middle_of(&g(&pillow), &g(&bed), &p), 1.0);
        // 0.25 m off in the plan: exp(-0.0625 / 0.125) = exp(-0.5); height does not matter.
        let off = bx([1.15, 2.2, 3.0], [0.3, 0.2, 0.1], 0.0);
        assert!((middle_of(&g(&off), &g(&bed), &p) - (-0.5f64).exp()).abs() < 1e-12);
    }

    #[test]
    fn distance_relations_by_gap() {
        let p = RelationParams::default();
        let b = bx([0.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
        // Gap g between the faces: target centre at 1.0 + g.
        let at = |gap: Real| bx([1.0 + gap, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
        let s = |f: fn(&ObjectGeom<'_>, &ObjectGeom<'_>, &RelationParams) -> Real, gap: Real| {
            f(&g(&at(gap)), &g(&b), &p)
        };
        assert_eq!(s(next_to, 0.0), 1.0);
        assert_eq!(s(next_to, -0.3), 1.0, "overlapping is distance 0");
        assert!((s(next_to, 0.75) - (-0.5f64).exp()).abs() < 1e-9, "0.25 past 0.5");
        assert_eq!(s(near, 1.0), 1.0);
        assert!(
            (s(near, 0.0) - (-2.0f64).exp()).abs() < 1e-9,
            "0.5 short: exp(-0.25/0.125)"
        );
        assert_eq!(s(across_from, 2.0), 1.0);
        assert!((s(across_from, 4.5) - (-2.0f64).exp()).abs() < 1e-9);
        assert_eq!(s(far, 4.0), 1.0);
        assert_eq!(s(far, 40.0), 1.0);
        assert!((s(far, 3.75) - (-0.5f64).exp()).abs() < 1e-9);
        // Rotated 90 degrees: a 2 x 0.5 box turned so its long side faces the anchor.
        let long = bx([0.5 + 0.25 + 0.3, 0.0, 0.5], [1.0, 0.25, 0.5], FRAC_PI_2);
        assert!((pair_distance(&g(&long), &g(&b), &p) - 0.3).abs() < 1e-9);
    }

    #[test]
    fn smaller_box_distance_mode() {
        let p = RelationParams {
            distance_from: DistanceFrom::SmallerBox,
            ..RelationParams::default()
        };
        let b = bx([0.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
        let a = bx([2.0, 0.0, 0.5], [0.2, 0.2, 0.2], 0.0);
        // Boxes only: identical to the exact distance (2 - 0.5 - 0.2 = 1.3).
        assert!((pair_distance(&g(&a), &g(&b), &p) - 1.3).abs() < 1e-9);
    }

    #[test]
    fn surround_variants() {
        let p = RelationParams::default();
        let t = bx([0.0, 0.0, 0.4], [0.5, 0.5, 0.4], 0.0);
        let at = |deg: Real, r: Real| {
            let a = deg.to_radians();
            bx([r * a.cos(), r * a.sin(), 0.4], [0.2, 0.2, 0.4], 0.0)
        };
        let score = |objs: &[Obb], p: &RelationParams| {
            let v: Vec<ObjectGeom<'_>> = objs.iter().map(ObjectGeom::from_box).collect();
            surround(&v, &g(&t), p)
        };
        // Three at 120-degree gaps, same radius: 1.
        let even = [at(0.0, 1.0), at(120.0, 1.0), at(240.0, 1.0)];
        assert!((score(&even, &p) - 1.0).abs() < 1e-12);
        // Two targets: 0 by definition.
        assert_eq!(score(&even[..2], &p), 0.0);
        // Three at 0, 90, 200 degrees, radius 1: gaps 90, 110, 160; ideal 120, so
        // a = 30/120, 10/120, 40/120 and d = 0: score = 0.5 + 0.5 mean((1 - a)^2).
        let three = [at(0.0, 1.0), at(90.0, 1.0), at(200.0, 1.0)];
        let mean_sq =
            ((0.75 as Real).powi(2) + (11.0 / 12.0 as Real).powi(2) + (2.0 / 3.0 as Real).powi(2)) / 3.0;
        assert!((score(&three, &p) - (0.5 + 0.5 * mean_sq)).abs() < 1e-12);
        // The reference's signed 3-D angles agree while every gap is below 180 degrees.
        let rp = RelationParams::reference();
        assert!((score(&three, &rp) - (0.5 + 0.5 * mean_sq)).abs() < 1e-12);
        // 0, 30, 150 degrees: gaps 30, 120, 210. Paper: a = 0.75, 0, 0.75 ->
        // 0.5 + 0.5 (0.0625 + 1 + 0.0625) / 3 = 0.6875. Reference: the target at 150 has every
        // other target clockwise of it (-150, -120), so a = 1 -> 0.5 + 0.5 (0.0625 + 1) / 3.
        let skew = [at(0.0, 1.0), at(30.0, 1.0), at(150.0, 1.0)];
        assert!((score(&skew, &p) - 0.6875).abs() < 1e-12);
        assert!((score(&skew, &rp) - (0.5 + 0.5 * 1.0625 / 3.0)).abs() < 1e-12);
        // Distances: radii 1, 1, 2 (mean 4/3, median 1) at even angles.
        let radii = [at(0.0, 1.0), at(120.0, 1.0), at(240.0, 2.0)];
        // Paper: 3-D distances from the anchor centre (same height): d = 0.25, 0.25, 0.5.
        let expected = (0.5 * (0.75f64.powi(2) * 2.0 + 0.25) + 0.5 * 3.0) / 3.0;
        assert!((score(&radii, &p) - expected).abs() < 1e-12);
        // Reference: median 1 -> d = 0, 0, 1 -> (0.5 + 0.5 + 0 + 1.5) / 3.
        assert!((score(&radii, &rp) - (2.5 / 3.0)).abs() < 1e-12);
        // A bunched group: all three within 20 degrees. Paper gaps 10, 10, 340 -> a = 11/12,
        // 11/12, 1 (clipped).
        let bunched = [at(0.0, 1.0), at(10.0, 1.0), at(20.0, 1.0)];
        let a1: Real = 1.0 - 110.0 / 120.0;
        let expected = 0.5 + 0.5 * (2.0 * a1 * a1) / 3.0;
        assert!((score(&bunched, &p) - expected).abs() < 1e-12);
    }

    #[test]
    fn flat_boxes_use_the_thickness_floor() {
        let p = RelationParams::default();
        let floor_box = bx([0.0, 0.0, 0.0], [2.0, 2.0, 0.5], 0.0);
        // A rug of zero height inside the box: still inside (not NaN).
        let rug = bx([0.0, 0.0, 0.1], [1.0, 0.5, 0.0], 0.0);
        assert_eq!(inside_of(&g(&rug), &g(&floor_box), &p), 1.0);
    }
}
