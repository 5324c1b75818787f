//! Gradients of the volume fractions: `inside_of`, `outside_of`, `side_of`, `side_region`,
//! `long_short_side_of`, `on_top` (and, through [`fraction_grad`], the architecture kernels
//! `inside_room` and the in-front factor of `on_wall` and `against_wall`).
//!
//! The fraction is `V / (8 hx hy hz)` with `V` the volume of the target box `[-h, h]` inside
//! half-spaces `n_j . u <= o_j` of its own frame. One clip gives `V` (bit for bit the score's)
//! and each face's area `A` and first moment `S`; by Reynolds' transport theorem
//! `dV = sum_j (A_j do_j - S_j . dn_j) / |n_j| + sum_k (A_+k + A_-k) dh_k`. The target's motion
//! moves every plane in its frame: a translation `dc` shifts the offsets by `-n_j . R^T dc`, a
//! turn by `dtheta` about the world vertical turns the normals by `-(R^T z) x n_j dtheta`.
//! Regions fixed to an anchor also move with the anchor's half extents (their bounds'
//! Jacobian); the anchor's centre and yaw follow from the invariance under moving both objects
//! together.

use sceneeval_geom::{Obb, Real, Side, Vector3};

use super::{BoxGrad, PairGrad, pair_result};
use crate::clip::{HalfSpace, MAX_PLANES, Moments, VolumeMoments, box_volume_moments, uncut_volume};
use crate::pairwise::{
    BoxInFrame, FrameBox, FrameBoxJacobian, inside_box, long_short_sides, side_half_box, side_region_box,
};
use crate::params::OnTopPlane;
use crate::{LongShort, ObjectGeom, RelationParams};

/// A fraction of a box's volume and its derivatives.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FractionGrad {
    /// The fraction, as the score computes it.
    pub value: Real,
    /// With respect to the box's centre, yaw about its centre and half extents.
    pub target: BoxGrad,
    /// With respect to each plane's offset (in the order given).
    pub offset: [Real; MAX_PLANES],
}

/// The volume `V` of `obb` (with half extents `h`, the flat-box floor applied) inside `planes`
/// (its own frame) and the derivatives of `V` with respect to the box's pose and half
/// extents and to each plane's offset: `(V, dV, dV/do)`. The planes are taken as fixed in
/// the world while the box moves.
pub(crate) fn volume_grad(
    obb: &Obb,
    h: &Vector3,
    planes: &[HalfSpace],
    params: &RelationParams,
) -> (Real, BoxGrad, [Real; MAX_PLANES]) {
    let (v, moments) = box_volume_moments(h, planes);
    let m = match moments {
        Moments::Cut(m) => m,
        Moments::Empty => return (v, BoxGrad::ZERO, [0.0; MAX_PLANES]),
        Moments::Whole => VolumeMoments {
            box_area: Vector3::new(8.0 * h.y * h.z, 8.0 * h.x * h.z, 8.0 * h.x * h.y),
            ..VolumeMoments::ZERO
        },
    };
    let w = obb.rotation.inverse_transform_vector(&Vector3::z());
    let mut d_centre_local = Vector3::zeros();
    let mut d_yaw = 0.0;
    for (j, p) in planes.iter().enumerate() {
        d_centre_local -= p.normal * m.plane_area[j];
        d_yaw += m.plane_moment[j].dot(&w.cross(&p.normal));
    }
    // The flat-box floor: a half extent below it does not move the box.
    let d_half = Vector3::from_fn(|k, _| {
        if obb.half_extents[k] >= params.min_half_extent_m {
            m.box_area[k]
        } else {
            0.0
        }
    });
    let grad = BoxGrad {
        center: obb.rotation * d_centre_local,
        half_extents: d_half,
        yaw: d_yaw,
    };
    (v, grad, m.plane_area)
}

/// A volume `v` of the box `obb` (half extents `h` after the flat-box floor) and its
/// derivatives `dv` as a fraction of the box's volume, clamped to `[0, 1]` as the scores do:
/// `d(V / full)/dh_k = (dV/dh_k - V / h_k) / full` where the half extent is free.
pub(crate) fn as_fraction(
    obb: &Obb,
    h: &Vector3,
    v: Real,
    dv: &BoxGrad,
    params: &RelationParams,
) -> (Real, BoxGrad) {
    let full = 8.0 * h.x * h.y * h.z;
    let value = (v / full).clamp(0.0, 1.0);
    let mut d = *dv * (1.0 / full);
    for k in 0..3 {
        if obb.half_extents[k] >= params.min_half_extent_m {
            d.half_extents[k] = (dv.half_extents[k] - v / h[k]) / full;
        }
    }
    (value, d)
}

/// [`volume_grad`] as a fraction of the box's volume ([`as_fraction`]). A box wholly inside
/// or outside the half-spaces has a fraction of 1 or 0 that nothing moves: zero derivatives
/// at once.
pub(crate) fn fraction_grad(
    obb: &Obb,
    h: &Vector3,
    planes: &[HalfSpace],
    params: &RelationParams,
) -> FractionGrad {
    let full = 8.0 * h.x * h.y * h.z;
    if let Some(v) = uncut_volume(h, planes) {
        return FractionGrad {
            value: (v / full).clamp(0.0, 1.0),
            target: BoxGrad::ZERO,
            offset: [0.0; MAX_PLANES],
        };
    }
    let (v, dv, d_offset) = volume_grad(obb, h, planes, params);
    let (value, target) = as_fraction(obb, h, v, &dv, params);
    FractionGrad {
        value,
        target,
        offset: d_offset.map(|a| a / full),
    }
}

/// The fraction of `target`'s box in `region` of `anchor`'s frame with its derivatives with
/// respect to the target (yaw about its centre) and the anchor's half extents (through the
/// region's Jacobian `jac`): `(value, d target, d anchor half extents)`.
pub(crate) fn region_fraction_grad(
    inframe: &BoxInFrame,
    target: &Obb,
    region: &FrameBox,
    jac: &FrameBoxJacobian,
    params: &RelationParams,
) -> (Real, BoxGrad, Vector3) {
    let Some(r) = inframe.planes(region) else {
        return (0.0, BoxGrad::ZERO, Vector3::zeros());
    };
    let f = fraction_grad(target, &inframe.h, &r.planes[..r.len], params);
    // Offsets: `hi - t` for an upper bound, `t - lo` for a lower one.
    let mut d_anchor_half = Vector3::zeros();
    for (of, d) in r.of[..r.len].iter().zip(f.offset) {
        if of.upper {
            d_anchor_half += jac.hi[of.axis] * d;
        } else {
            d_anchor_half -= jac.lo[of.axis] * d;
        }
    }
    (f.value, f.target, d_anchor_half)
}

/// The fraction of the target's box in a region of the anchor's frame, as a [`PairGrad`].
fn pair_fraction(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    (region, jac): (FrameBox, FrameBoxJacobian),
    params: &RelationParams,
) -> PairGrad {
    let b = anchor.obb;
    let inframe = BoxInFrame::new(target.obb, &b.rotation, &b.center, params);
    let (value, d_target, d_half) = region_fraction_grad(&inframe, target.obb, &region, &jac, params);
    pair_result(value, d_target, d_half, target, anchor)
}

/// [`crate::inside_of`] and its gradient.
///
/// ```
/// use sceneeval_relations::{grad, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let cabinet = Obb::from_yaw(Point3::new(0.0, 0.0, 1.0), Vector3::new(0.5, 0.3, 1.0), 0.0).unwrap();
/// // A 0.2 m cube centred 0.45 m right of the cabinet's centre: x in [0.35, 0.55], 0.15 of
/// // its 0.2 m width inside (plus the 1e-6 m tolerance). Moving it right by dx loses dx / 0.2.
/// let cup = Obb::from_yaw(Point3::new(0.45, 0.0, 1.0), Vector3::repeat(0.1), 0.0).unwrap();
/// let g = grad::inside_of(&ObjectGeom::from_box(&cup), &ObjectGeom::from_box(&cabinet), &RelationParams::default());
/// assert!((g.score - 0.75).abs() < 1e-5);
/// assert!((g.target.center.x + 5.0).abs() < 1e-9);
/// assert!((g.anchor.center.x - 5.0).abs() < 1e-9);
/// // Widening the cabinet by dh moves its +x face out by dh: 5 per metre.
/// assert!((g.anchor.half_extents.x - 5.0).abs() < 1e-9);
/// ```
pub fn inside_of(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    pair_fraction(target, anchor, inside_box(anchor.obb, params.tolerance_m), params)
}

/// [`crate::outside_of`] and its gradient (the negated gradient of `inside_of`).
pub fn outside_of(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    let g = inside_of(target, anchor, params);
    PairGrad {
        score: 1.0 - g.score,
        target: -g.target,
        anchor: -g.anchor,
    }
}

/// [`crate::side_of`] and its gradient.
pub fn side_of(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    side: Side,
    params: &RelationParams,
) -> PairGrad {
    let region = side_region_box(anchor.obb, side, false, params.side_of_margin, params.tolerance_m);
    pair_fraction(target, anchor, region, params)
}

/// [`crate::side_region`] and its gradient.
pub fn side_region(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    side: Side,
    params: &RelationParams,
) -> PairGrad {
    pair_fraction(target, anchor, side_half_box(anchor.obb, side, params), params)
}

/// [`crate::long_short_side_of`] and its gradient: that of the larger of the two sides'
/// fractions (the first of the pair, right or back, on a tie). An anchor with equal width and
/// depth scores 0 with a zero gradient.
pub fn long_short_side_of(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    which: LongShort,
    params: &RelationParams,
) -> PairGrad {
    let b = anchor.obb;
    let Some((first, second)) = long_short_sides(b, which) else {
        return PairGrad::default();
    };
    let inframe = BoxInFrame::new(target.obb, &b.rotation, &b.center, params);
    let side = |s: Side| {
        let (region, jac) = side_region_box(b, s, true, params.region_margin, params.tolerance_m);
        region_fraction_grad(&inframe, target.obb, &region, &jac, params)
    };
    let (x, y) = (side(first), side(second));
    // The gradient of the larger (of `y` only when strictly larger); the score as the kernel's.
    let (_, d_target, d_half) = if y.0 > x.0 { y } else { x };
    pair_result(x.0.max(y.0), d_target, d_half, target, anchor)
}

/// [`crate::on_top`] and its gradient.
pub fn on_top(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    let from_centre = params.on_top_plane == OnTopPlane::CentrePlane;
    let region = side_region_box(
        anchor.obb,
        Side::Top,
        from_centre,
        params.region_margin,
        params.tolerance_m,
    );
    pair_fraction(target, anchor, region, params)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clip::box_volume_inside;

    /// The moments are the derivatives of the volume: central differences over each input.
    #[test]
    fn moments_are_the_volume_derivatives() {
        let h = Vector3::new(0.6, 0.4, 0.3);
        let planes = [
            HalfSpace::new(Vector3::new(0.8, 0.36, 0.48), 0.35),
            HalfSpace::new(Vector3::new(-0.2, 0.9, 0.1) * 2.0, 0.3),
            HalfSpace::new(Vector3::new(0.1, -0.3, -1.0), 0.2),
        ];
        let (v, Moments::Cut(m)) = box_volume_moments(&h, &planes) else {
            panic!("the planes cut the box");
        };
        assert_eq!(v.to_bits(), box_volume_inside(&h, &planes).to_bits());
        let e = 1e-6;
        for j in 0..planes.len() {
            let shifted = |d: Real| {
                let mut p = planes;
                p[j].offset += d;
                box_volume_inside(&h, &p)
            };
            let fd = (shifted(e) - shifted(-e)) / (2.0 * e);
            assert!(
                (fd - m.plane_area[j]).abs() < 1e-6,
                "offset {j}: {fd} vs {}",
                m.plane_area[j]
            );
            for c in 0..3 {
                let turned = |d: Real| {
                    let mut p = planes;
                    p[j].normal[c] += d;
                    box_volume_inside(&h, &p)
                };
                let fd = (turned(e) - turned(-e)) / (2.0 * e);
                assert!(
                    (fd + m.plane_moment[j][c]).abs() < 1e-6,
                    "normal {j}.{c}: {fd} vs {}",
                    -m.plane_moment[j][c]
                );
            }
        }
        for k in 0..3 {
            let grown = |d: Real| {
                let mut g = h;
                g[k] += d;
                box_volume_inside(&g, &planes)
            };
            let fd = (grown(e) - grown(-e)) / (2.0 * e);
            assert!(
                (fd - m.box_area[k]).abs() < 1e-6,
                "half {k}: {fd} vs {}",
                m.box_area[k]
            );
        }
    }

    #[test]
    fn a_box_clear_of_every_plane_has_only_its_own_faces() {
        // Whole box 2 x 1 x 0.5: dV/dhx = 2 * (2 hy)(2 hz) = 8 * 0.5 * 0.25 = 1.
        let h = Vector3::new(1.0, 0.5, 0.25);
        let obb = Obb::from_yaw(sceneeval_geom::Point3::origin(), h, 0.3).unwrap();
        let p = RelationParams::default();
        let (v, d, offsets) = volume_grad(&obb, &h, &[HalfSpace::new(Vector3::x(), 5.0)], &p);
        assert_eq!(v, 1.0);
        assert_eq!(d.half_extents, Vector3::new(1.0, 2.0, 4.0));
        assert_eq!((d.center, d.yaw, offsets[0]), (Vector3::zeros(), 0.0, 0.0));
        assert_eq!(uncut_volume(&h, &[HalfSpace::new(Vector3::x(), 5.0)]), Some(1.0));
        // Excluded: nothing.
        let (v, d, _) = volume_grad(&obb, &h, &[HalfSpace::new(Vector3::x(), -5.0)], &p);
        assert_eq!((v, d), (0.0, BoxGrad::ZERO));
        assert_eq!(uncut_volume(&h, &[HalfSpace::new(Vector3::x(), -5.0)]), Some(0.0));
    }
}
