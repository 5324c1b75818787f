//! Gradients of the distance bands: `next_to`, `near`, `across_from`, `far` (and the
//! distance terms of the architecture kernels).
//!
//! The distance between two solids is the minimum of `|x - y|` over their points; at the
//! closest points `p`, `q` (unit direction `n = (p - q) / d`) the envelope theorem gives its
//! derivative as that of `|x - y|` with the points held where they are on their shapes: moving
//! the first object by `dc` changes it by `n . dc`, turning it by `dtheta` about the vertical
//! through its centre by `n . (z x (p - c)) dtheta`, growing a box's half extent `h_i` (the
//! point `c + R diag(h) xi` with `xi` fixed) by `n . R e_i xi_i dh_i`. The band's slope then
//! scales it. Where the closest pair is not unique with different derivatives, or the
//! distance meets a band's end, the derivative is one-sided (the pair found, the Gaussian's
//! side).

use sceneeval_geom::{ClosestPoints, Obb, Point3, Real, Vector3};

use super::{BoxGrad, PairGrad, pair_result};
use crate::distance::{distance_bounds, object_closest};
use crate::pairwise::distance_views;
use crate::params::DistanceBand;
use crate::{ObjectGeom, RelationParams};

/// A band's score of `d` (bit for bit [`DistanceBand::score`]) and its derivative with
/// respect to `d`: 0 inside the range, the Gaussian's slope outside (at a range end itself,
/// where the score is 1, the derivative is 0).
#[inline]
pub(crate) fn band_slope(band: &DistanceBand, d: Real) -> (Real, Real) {
    let score = band.score(d);
    let s2 = band.sigma_m * band.sigma_m;
    let slope = if d < band.min_m {
        score * (band.min_m - d) / s2
    } else if d > band.max_m {
        -score * (d - band.max_m) / s2
    } else {
        0.0
    };
    (score, slope)
}

/// The derivative of a distance with respect to the box parameters of the shape whose
/// closest point is `p` (yaw about the box centre), `n` pointing from the other shape's
/// closest point to `p`. Half extents only for a solid box (`solid_box`), whose point moves
/// with them; a mesh's points do not.
pub(crate) fn point_grad(obb: &Obb, solid_box: bool, p: &Point3, n: &Vector3) -> BoxGrad {
    let r = p - obb.center;
    let half_extents = if solid_box {
        let local = obb.rotation.inverse_transform_vector(&r);
        Vector3::from_fn(|i, _| {
            let along = n.dot(&obb.axis(i));
            let h = obb.half_extents[i];
            if h > 0.0 {
                along * (local[i] / h).clamp(-1.0, 1.0)
            } else {
                // A flat box: the point may sit on either face; growing the box brings the
                // face toward the other shape nearer.
                -along.abs()
            }
        })
    } else {
        Vector3::zeros()
    };
    BoxGrad {
        center: *n,
        half_extents,
        yaw: n.dot(&Vector3::z().cross(&r)),
    }
}

/// The derivatives of the distance behind `c` between `x` (first) and `y`: with respect to
/// `x`'s box parameters and to `y`'s half extents. Zero when the shapes meet.
pub(crate) fn closest_grad(c: &ClosestPoints, x: &ObjectGeom<'_>, y: &ObjectGeom<'_>) -> (BoxGrad, Vector3) {
    let Some((p, q)) = c.points else {
        return (BoxGrad::ZERO, Vector3::zeros());
    };
    let n = (p - q) / c.distance;
    let dx = point_grad(x.obb, x.mesh.is_none(), &p, &n);
    let dy = point_grad(y.obb, y.mesh.is_none(), &q, &-n);
    (dx, dy.half_extents)
}

/// The band score of the pair's distance and its gradient (the kernel `band` of the crate
/// root, with the same cheap bounds first for meshes).
fn band_pair(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    band: &DistanceBand,
    params: &RelationParams,
) -> PairGrad {
    let (x, y) = distance_views(target, anchor, params);
    if target.mesh.is_some() || anchor.mesh.is_some() {
        let (lo, hi) = distance_bounds(&x, &y);
        if lo >= band.min_m && hi <= band.max_m {
            return PairGrad {
                score: 1.0,
                ..PairGrad::default()
            };
        }
    }
    let c = object_closest(&x, &y);
    let (score, slope) = band_slope(band, c.distance);
    if slope == 0.0 {
        return PairGrad {
            score,
            ..PairGrad::default()
        };
    }
    let (dx, dy_half) = closest_grad(&c, &x, &y);
    pair_result(score, dx * slope, dy_half * slope, target, anchor)
}

/// [`crate::next_to`] and its gradient.
///
/// ```
/// use sceneeval_relations::{grad, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let p = RelationParams::default();
/// let b = Obb::from_yaw(Point3::new(0.0, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// // Faces 0.75 m apart along x: 0.25 m past the [0, 0.5] m range, score exp(-0.5); moving
/// // the target away lowers it by score * 0.25 / 0.25^2 = 4 score per metre.
/// let a = Obb::from_yaw(Point3::new(1.75, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// let g = grad::next_to(&ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b), &p);
/// let s = (-0.5f64).exp();
/// assert!((g.score - s).abs() < 1e-12);
/// assert!((g.target.center.x + 4.0 * s).abs() < 1e-9);
/// // Growing the target's half width brings its face nearer: +4 score per metre.
/// assert!((g.target.half_extents.x - 4.0 * s).abs() < 1e-9);
/// ```
pub fn next_to(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    band_pair(target, anchor, &params.next_to, params)
}

/// [`crate::near`] and its gradient.
pub fn near(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    band_pair(target, anchor, &params.near, params)
}

/// [`crate::across_from`] and its gradient.
pub fn across_from(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    band_pair(target, anchor, &params.across_from, params)
}

/// [`crate::far`] and its gradient.
pub fn far(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    band_pair(target, anchor, &params.far, params)
}
