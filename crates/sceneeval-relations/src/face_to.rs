//! `face_to`: does the target's front point at the anchor?

use sceneeval_geom::{Isometry3, Mesh, Obb, Point2, Point3, Ray, RayHit, Real, Vector3};

use crate::clip::Poly2;
use crate::pairwise::effective_half;
use crate::{FaceToHeights, ObjectGeom, RelationParams};

/// `face_to`: whether the target's front (local -y) points at the anchor, in `[0, 1]`.
///
/// The reference casts a ray along the target's front from every random sample of the
/// target's box, takes the mean of the points where the rays first hit the anchor's mesh, and
/// scores the plan-view angle between the front and the direction from the target's centre to
/// that mean point: `1 - angle / 30 degrees`, clipped to `[0, 1]` (holds below 15 degrees); no
/// hit at all scores 0.
///
/// Rays from points on the same line along the front hit the same point as long as they start
/// before it, so the mean over the box equals the mean over the lines through the target's
/// **mid-depth cross-section** (the plane through its centre perpendicular to its front). This
/// kernel casts the rays from that cross-section:
///
/// - **Anchor as a box (exact):** the cross-section is split by which face of the anchor each
///   line enters first (or, for a line starting inside the anchor, leaves through); each piece
///   is a convex polygon, clipped exactly on the stack, and the hit depth is linear on it, so
///   the mean hit point is a sum of polygon areas and centroids. The score is continuous in
///   both poses except where the definition itself jumps (the first or last ray starting or
///   ceasing to hit, a line's start crossing the anchor's surface).
/// - **Anchor with a mesh:** a fixed grid of `face_to_mesh_rays` x `face_to_mesh_rays` rays at
///   the cells' centres (the midpoint rule), each ray first tested against the anchor's box;
///   a ray starting inside a closed mesh hits it from inside, as in the reference.
///
/// **Heights** ([`RelationParams::face_to_heights`]): by default the anchor counts at any
/// height. For an upright target (rotated about the vertical only) the rays are horizontal and
/// only the plan view of their first hits enters the angle, so the kernel takes the first hits
/// on the vertical prism over the anchor's footprint: a box anchor is extended vertically over
/// every ray (exact; an upright box's footprint is its own), a mesh anchor is probed by each
/// column of rays at the grid's heights spread over the anchor's own height, the column's
/// nearest hit counting. A sofa then faces the TV hung above its backrest, which the
/// reference's rays, leaving the sofa at the sofa's heights, never reach
/// ([`FaceToHeights::TargetSpan`], the reference preset). A tilted target, or a tilted box
/// anchor, is scored at the target's heights either way.
///
/// Differences from the reference: no sampling noise; where the anchor overlaps the target
/// along the rays, rays start from the mid-depth plane rather than from every depth; the
/// directions are normalised exactly (the reference adds `1e-6` to the lengths, which caps a
/// perfect alignment at about 0.996) and the cosine is clipped before `acos` (quirk Q20); the
/// heights above.
///
/// ```
/// use sceneeval_relations::{face_to, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let tv = Obb::from_yaw(Point3::new(0.0, 3.0, 1.0), Vector3::new(0.6, 0.05, 0.4), 0.0).unwrap();
/// // A sofa at the origin turned 180 degrees: its front (local -y) points to +y, at the TV.
/// let sofa = Obb::from_yaw(Point3::new(0.0, 0.0, 0.4), Vector3::new(1.0, 0.45, 0.4), std::f64::consts::PI).unwrap();
/// let p = RelationParams::default();
/// assert!((face_to(&ObjectGeom::from_box(&sofa), &ObjectGeom::from_box(&tv), &p) - 1.0).abs() < 1e-9);
/// // Turned away, no ray hits.
/// let away = Obb::from_yaw(Point3::new(0.0, 0.0, 0.4), Vector3::new(1.0, 0.45, 0.4), 0.0).unwrap();
/// assert_eq!(face_to(&ObjectGeom::from_box(&away), &ObjectGeom::from_box(&tv), &p), 0.0);
/// // A TV hung at 1.2-1.8 m, above the 0.8 m sofa: faced in plan view, missed by the
/// // reference's rays.
/// let high = Obb::from_yaw(Point3::new(0.0, 3.0, 1.5), Vector3::new(0.6, 0.05, 0.3), 0.0).unwrap();
/// assert!((face_to(&ObjectGeom::from_box(&sofa), &ObjectGeom::from_box(&high), &p) - 1.0).abs() < 1e-9);
/// let reference = RelationParams::reference();
/// assert_eq!(face_to(&ObjectGeom::from_box(&sofa), &ObjectGeom::from_box(&high), &reference), 0.0);
/// ```
pub fn face_to(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> Real {
    angle_score(target.obb, mean_hit(target, anchor, params, &mut ()), params)
}

/// What [`mean_hit`] reports to a gradient as it goes (nothing by default).
pub(crate) trait HitSink {
    /// The box the rays are cast at: the anchor, or (`prism`) the anchor extended vertically
    /// over every ray ([`prism_over`]).
    fn anchor_box(&mut self, _b: &Obb, _prism: bool) {}
    /// A piece of the cross-section with a positive area, in the order accumulated.
    fn piece(&mut self, _piece: &Piece) {}
    /// A ray of the mesh grid that counts: its origin's offset in the target's frame, the
    /// origin, and its hit.
    fn ray(&mut self, _local: &Vector3, _origin: &Point3, _hit: &RayHit) {}
}

impl HitSink for () {}

/// A piece of the target's mid-depth cross-section whose lines first meet the anchor's box on
/// one face (in the target's frame; `(u, v)` = local `(x, z)`).
#[derive(Clone, Copy)]
pub(crate) struct Piece {
    /// The anchor's face: its local axis and side (`+-1`).
    pub axis: usize,
    pub sign: Real,
    /// The piece, its edges labelled with [`line`] labels.
    pub poly: Poly2,
    pub area: Real,
    pub centroid: Point2,
    /// The face's outward normal in the target's frame and its offset: the plane `n . p = delta`.
    pub normal: Vector3,
    pub delta: Real,
}

impl Piece {
    /// No piece (a placeholder in fixed arrays).
    pub(crate) const EMPTY: Piece = Piece {
        axis: 0,
        sign: 1.0,
        poly: Poly2::EMPTY,
        area: 0.0,
        centroid: Point2::new(0.0, 0.0),
        normal: Vector3::new(0.0, 0.0, 0.0),
        delta: 0.0,
    };
}

/// Labels of the lines a [`Piece`]'s edges lie on.
pub(crate) mod line {
    /// The cross-section's sides `u <= hx`, `-u <= hx`, `v <= hz`, `-v <= hz`.
    pub const RECT_X_POS: u8 = 0;
    pub const RECT_X_NEG: u8 = 1;
    pub const RECT_Z_POS: u8 = 2;
    pub const RECT_Z_NEG: u8 = 3;
    /// Edge `k` (corner `k` to `k + 1`) of the face's projected quadrilateral: `QUAD + k`.
    pub const QUAD: u8 = 4;
    /// The mid-depth plane (entry faces: hits at a depth of at least 0).
    pub const DEPTH: u8 = 8;
    /// The anchor's slab of axis `l`, upper (`SLAB + 2 l`) or lower (`SLAB + 2 l + 1`) side.
    pub const SLAB: u8 = 9;
    /// The rectangle's edges in [`crate::clip::Poly2::rectangle`]'s order.
    pub const RECT: [u8; 4] = [RECT_Z_NEG, RECT_X_POS, RECT_Z_POS, RECT_X_NEG];
    /// The quadrilateral's edges.
    pub const QUADS: [u8; 4] = [QUAD, QUAD + 1, QUAD + 2, QUAD + 3];
}

/// The mean first-hit point of the lines through the target's mid-depth cross-section on the
/// anchor, in the target's frame (`None` when no line hits), reporting its pieces or rays to
/// `sink`.
pub(crate) fn mean_hit(
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    params: &RelationParams,
    sink: &mut impl HitSink,
) -> Option<Vector3> {
    let plan_view = params.face_to_heights == FaceToHeights::Any && is_upright(target.obb);
    match anchor.mesh {
        None if plan_view && is_upright(anchor.obb) => {
            let prism = prism_over(anchor.obb, target.obb, params);
            sink.anchor_box(&prism, true);
            mean_hit_on_box(target.obb, &prism, params, sink)
        }
        None => {
            sink.anchor_box(anchor.obb, false);
            mean_hit_on_box(target.obb, anchor.obb, params, sink)
        }
        Some((mesh, pose)) => mean_hit_on_mesh(target.obb, mesh, pose, anchor.obb, params, plan_view, sink),
    }
}

/// The score of a mean hit point `hit` (target frame): `1 - angle / max`, clipped, of the
/// plan-view angle between the target's front and the direction to the hit; 0 without a hit.
pub(crate) fn angle_score(a: &Obb, hit: Option<Vector3>, params: &RelationParams) -> Real {
    let Some(hit) = hit else {
        return 0.0;
    };
    let v = a.rotation * hit;
    let front = a.rotation * Vector3::new(0.0, -1.0, 0.0);
    let (fx, fy, vx, vy) = (front.x, front.y, v.x, v.y);
    let (nf, nv) = ((fx * fx + fy * fy).sqrt(), (vx * vx + vy * vy).sqrt());
    if nf == 0.0 || nv == 0.0 {
        // A vertical front or a hit straight above or below: 90 degrees in the reference.
        return (1.0 - 90.0 / params.face_to_max_deviation_deg).clamp(0.0, 1.0);
    }
    let cos = ((fx * vx + fy * vy) / (nf * nv)).clamp(-1.0, 1.0);
    let angle = cos.acos().to_degrees();
    (1.0 - angle / params.face_to_max_deviation_deg).clamp(0.0, 1.0)
}

/// Mean first-hit point on a box anchor, in the target's frame (relative to its centre), over
/// the target's mid-depth cross-section; `None` when no line hits.
fn mean_hit_on_box(a: &Obb, b: &Obb, params: &RelationParams, sink: &mut impl HitSink) -> Option<Vector3> {
    let h = effective_half(a, params);
    let rect = Poly2::rectangle(h.x, h.z, line::RECT);
    // The anchor in the target's frame: axes (columns of m), centre c, half extents hb.
    let m = (a.rotation.inverse() * b.rotation).into_inner();
    let c = a.rotation.inverse_transform_vector(&(b.center - a.center));
    let hb = b.half_extents;
    // The anchor's reach from its centre along the target's axes.
    let reach = |k: usize| -> Real { (0..3).map(|l| m[(k, l)].abs() * hb[l]).sum() };
    let reach_y = reach(1);
    // No line can hit an anchor wholly behind the mid-depth plane (the lines run along -y from
    // it) or wholly beside the cross-section: every piece below would be clipped away. Decided
    // here only with a margin far above the rounding of the pieces' corners, so that the score
    // is the one the construction gives.
    let clear = |centre: Real, reach: Real, half: Real| {
        centre.abs() - reach - half > 1e-9 * (1.0 + centre.abs() + reach + half)
    };
    if clear(c.x, reach(0), h.x)
        || clear(c.z, reach(2), h.z)
        || c.y - reach_y > 1e-9 * (1.0 + c.y.abs() + reach_y)
    {
        return None;
    }
    // Does the anchor reach across the mid-depth plane y = 0 (some lines start inside it)?
    let straddles = c.y - reach_y < 0.0 && c.y + reach_y > 0.0;

    // Accumulated area and area-weighted (u, s, v) of the hit points; u = x, v = z in the
    // target's frame and s = -y is the depth along the front.
    let mut w = 0.0;
    let mut acc = Vector3::zeros();
    for i in 0..3 {
        for sign in [1.0, -1.0] {
            let n = m.column(i) * sign;
            if n.y.abs() < 1e-12 {
                continue; // parallel to the rays: no projected area
            }
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let fc = c + n * hb[i];
            let (ej, ek) = (m.column(j) * hb[j], m.column(k) * hb[k]);
            let plan = |p: Vector3| Point2::new(p.x, p.z);
            let quad = Poly2::quad(
                [
                    plan(fc + ej + ek),
                    plan(fc + ej - ek),
                    plan(fc - ej - ek),
                    plan(fc - ej + ek),
                ],
                line::QUADS,
            );
            let delta = n.dot(&fc);
            // Depth of the face over (u, v): s = (n.x u + n.z v - delta) / n.y.
            let depth = |p: &Point2| (n.x * p.x + n.z * p.y - delta) / n.y;
            let piece = if n.y > 0.0 {
                // Entry face (its normal opposes the rays, which run along -y): lines that
                // enter here at depth s >= 0, i.e. ahead of the mid-depth plane.
                let mut poly = quad;
                clip_to_rect(&mut poly, h.x, h.z);
                poly.clip(-n.x, -n.z, -delta, line::DEPTH);
                poly
            } else if straddles {
                // Exit face: lines that start inside the anchor leave through it.
                let mut poly = rect;
                for l in 0..3 {
                    let (mx, mz) = (m[(0, l)], m[(2, l)]);
                    let off = m.column(l).dot(&c);
                    let upper = line::SLAB + 2 * l as u8;
                    poly.clip(mx, mz, hb[l] + off, upper);
                    poly.clip(-mx, -mz, hb[l] - off, upper + 1);
                }
                poly.clip_by_convex(&quad);
                poly
            } else {
                continue;
            };
            let (area, cen) = piece.area_centroid();
            if area > 0.0 {
                w += area;
                acc += Vector3::new(cen.x, depth(&cen), cen.y) * area;
                sink.piece(&Piece {
                    axis: i,
                    sign,
                    poly: piece,
                    area,
                    centroid: cen,
                    normal: n.into_owned(),
                    delta,
                });
            }
        }
    }
    (w > 0.0).then(|| {
        let mean = acc / w;
        Vector3::new(mean.x, -mean.y, mean.z)
    })
}

/// Whether the box is rotated about the vertical only (its local z is world z or its
/// opposite), so that its footprint is its own and its front is horizontal.
pub(crate) fn is_upright(obb: &Obb) -> bool {
    let z = obb.rotation * Vector3::z();
    z.x.abs() <= 1e-12 && z.y.abs() <= 1e-12
}

/// An upright `anchor` extended vertically over every ray from the upright `target`: its
/// footprint and orientation, centred at the target's height and taller than the target's
/// cross-section. The rays are horizontal and keep their heights, so every line meets it where
/// it meets the prism over the anchor's footprint.
fn prism_over(anchor: &Obb, target: &Obb, params: &RelationParams) -> Obb {
    let span = effective_half(target, params).z;
    let mut prism = *anchor;
    prism.center.z = target.center.z;
    prism.half_extents.z = 2.0 * span + 1.0;
    prism
}

fn clip_to_rect(poly: &mut Poly2, hx: Real, hz: Real) {
    poly.clip(1.0, 0.0, hx, line::RECT_X_POS);
    poly.clip(-1.0, 0.0, hx, line::RECT_X_NEG);
    poly.clip(0.0, 1.0, hz, line::RECT_Z_POS);
    poly.clip(0.0, -1.0, hz, line::RECT_Z_NEG);
}

/// Whether the ray meets the closed box (slab test).
fn ray_meets_box(obb: &Obb, origin: &Point3, dir: &Vector3) -> bool {
    let o = obb.to_local(origin);
    let d = obb.rotation.inverse_transform_vector(dir);
    let (mut t0, mut t1): (Real, Real) = (0.0, Real::INFINITY);
    for i in 0..3 {
        let h = obb.half_extents[i];
        if d[i] == 0.0 {
            if o[i].abs() > h {
                return false;
            }
            continue;
        }
        let (ta, tb) = ((-h - o[i]) / d[i], (h - o[i]) / d[i]);
        t0 = t0.max(ta.min(tb));
        t1 = t1.min(ta.max(tb));
        if t0 > t1 {
            return false;
        }
    }
    true
}

/// Mean first-hit point on a mesh anchor over a fixed grid of rays from the target's
/// mid-depth cross-section, in the target's frame; `None` when no ray hits.
///
/// With `plan_view` (an upright target), each column of the grid (one position across the
/// target's width) casts its rays at heights spread over the anchor's box instead of the
/// target's, and its nearest hit is the column's first hit in plan view.
fn mean_hit_on_mesh(
    a: &Obb,
    mesh: &Mesh,
    pose: &Isometry3,
    b_box: &Obb,
    params: &RelationParams,
    plan_view: bool,
    sink: &mut impl HitSink,
) -> Option<Vector3> {
    let h = effective_half(a, params);
    let n = params.face_to_mesh_rays.max(1);
    let step = |half: Real, i: u32| -half + (Real::from(i) + 0.5) * (2.0 * half / Real::from(n));
    let front = a.rotation * Vector3::new(0.0, -1.0, 0.0);
    let mut count = 0u32;
    let mut acc = Vector3::zeros();
    if plan_view {
        // The anchor's box spans b.z +- reach in world height.
        let r = b_box.rotation.matrix();
        let reach: Real = (0..3).map(|l| r[(2, l)].abs() * b_box.half_extents[l]).sum();
        for iu in 0..n {
            let across = step(h.x, iu);
            // The column's nearest hit (the first of equally near ones).
            let mut nearest: Option<(RayHit, Point3)> = None;
            for iv in 0..n {
                let mut origin = a.center + a.rotation * Vector3::new(across, 0.0, 0.0);
                origin.z = b_box.center.z + step(reach, iv);
                if !ray_meets_box(b_box, &origin, &front) {
                    continue;
                }
                if let Some(hit) = mesh.cast_ray(pose, &Ray::new(origin, front), Real::MAX)
                    && nearest.as_ref().is_none_or(|(best, _)| hit.toi < best.toi)
                {
                    nearest = Some((hit, origin));
                }
            }
            if let Some((hit, origin)) = nearest {
                count += 1;
                acc += Vector3::new(across, -hit.toi, 0.0);
                sink.ray(&Vector3::new(across, 0.0, 0.0), &origin, &hit);
            }
        }
        return (count > 0).then(|| acc / Real::from(count));
    }
    for iu in 0..n {
        for iv in 0..n {
            let local = Vector3::new(step(h.x, iu), 0.0, step(h.z, iv));
            let origin = a.center + a.rotation * local;
            if !ray_meets_box(b_box, &origin, &front) {
                continue;
            }
            if let Some(hit) = mesh.cast_ray(pose, &Ray::new(origin, front), Real::MAX) {
                count += 1;
                acc += Vector3::new(local.x, -hit.toi, local.z);
                sink.ray(&local, &origin, &hit);
            }
        }
    }
    (count > 0).then(|| acc / Real::from(count))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn bx(c: [Real; 3], h: [Real; 3], yaw: Real) -> Obb {
        Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::new(h[0], h[1], h[2]), yaw).unwrap()
    }

    fn score(a: &Obb, b: &Obb) -> Real {
        face_to(
            &ObjectGeom::from_box(a),
            &ObjectGeom::from_box(b),
            &RelationParams::default(),
        )
    }

    #[test]
    fn head_on_lateral_offset_and_away() {
        // Target at the origin facing -y (yaw 0); anchor 2 m ahead.
        let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
        let b = bx([0.0, -2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
        // Every line through the 1 x 1 cross-section hits the anchor's near face at depth 1.9
        // (2 - 0.1): mean hit straight ahead, angle 0.
        assert!((score(&a, &b) - 1.0).abs() < 1e-12);
        let hit = mean_hit_on_box(&a, &b, &RelationParams::default(), &mut ()).unwrap();
        assert!((hit - Vector3::new(0.0, -1.9, 0.0)).norm() < 1e-12);
        // Anchor shifted 0.6 m sideways: lines with x in [0.1, 0.5] hit, mean x = 0.3, depth
        // 1.9 -> angle atan(0.3 / 1.9) = 8.97 degrees -> score 1 - 8.97/30 = 0.7009.
        let b2 = bx([0.6, -2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
        let expected = 1.0 - (0.3f64 / 1.9).atan().to_degrees() / 30.0;
        assert!((score(&a, &b2) - expected).abs() < 1e-12, "{}", score(&a, &b2));
        // Behind the target: no line hits ahead.
        let behind = bx([0.0, 2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
        assert_eq!(score(&a, &behind), 0.0);
        // Completely beside (no overlap of the cross-sections): no hit.
        let beside = bx([3.0, -2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
        assert_eq!(score(&a, &beside), 0.0);
    }

    #[test]
    fn lines_grazing_the_edge_of_the_cross_section_still_hit() {
        // The anchor overlaps the target's 1 m wide cross-section by 1 micrometre at x = 0.5:
        // a strip of lines at x = 0.5 hits at depth 1.9, angle atan(0.5 / 1.9) = 14.74 degrees,
        // score 1 - 14.74 / 30 = 0.5086 (not the 0 of a miss).
        let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
        let b = bx([1.0 - 1e-6, -2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
        let expected = 1.0 - (0.5f64 / 1.9).atan().to_degrees() / 30.0;
        assert!((score(&a, &b) - expected).abs() < 1e-6, "{}", score(&a, &b));
        // 1 micrometre apart: no line hits.
        let apart = bx([1.0 + 1e-6, -2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
        assert_eq!(score(&a, &apart), 0.0);
        // Wholly behind the mid-depth plane, but for 1 micrometre: lines from that sliver of
        // the cross-section start inside the anchor and leave through its far face at y = -1e-6.
        let behind = bx([0.0, 1.0 - 1e-6, 0.5], [0.5, 1.0, 0.5], 0.0);
        assert!((score(&a, &behind) - 1.0).abs() < 1e-9);
        let wholly_behind = bx([0.0, 1.0 + 1e-6, 0.5], [0.5, 1.0, 0.5], 0.0);
        assert_eq!(score(&a, &wholly_behind), 0.0);
    }

    #[test]
    fn rotated_anchor_uses_both_visible_faces() {
        // Anchor: a unit cube turned 45 degrees, 3 m ahead. Its two visible faces are mirror
        // images about the target's axis, so the mean hit stays on the axis: score 1.
        let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
        let b = bx([0.0, -3.0, 0.5], [0.5, 0.5, 0.5], PI / 4.0);
        assert!((score(&a, &b) - 1.0).abs() < 1e-12);
        // Its nearest edge is at depth 3 - sqrt(0.5) = 2.2929; the faces recede linearly with
        // |x| up to x = 0.5 (depth 3 - sqrt(0.5) + 0.5), so the mean depth is 2.2929 + 0.25.
        let hit = mean_hit_on_box(&a, &b, &RelationParams::default(), &mut ()).unwrap();
        assert!((hit.y + (3.0 - 0.5f64.sqrt() + 0.25)).abs() < 1e-12, "{hit}");
    }

    #[test]
    fn target_yaw_and_partial_cross_section() {
        // Target turned 90 degrees faces +x; anchor to the +x side, offset in y by 0.2.
        let a = bx([0.0, 0.0, 0.5], [0.4, 0.3, 0.5], FRAC_PI_2);
        let b = bx([2.0, 0.2, 0.5], [0.1, 1.0, 0.5], 0.0);
        // The anchor's y-range [-0.8, 1.2] covers the whole 0.8-wide cross-section: mean hit on
        // the target's axis -> 1.
        assert!((score(&a, &b) - 1.0).abs() < 1e-12);
        // A narrow anchor covering only y in [0.1, 0.3]: mean lateral 0.2, depth 1.9.
        let narrow = bx([2.0, 0.2, 0.5], [0.1, 0.1, 0.5], 0.0);
        let expected = 1.0 - (0.2f64 / 1.9).atan().to_degrees() / 30.0;
        assert!((score(&a, &narrow) - expected).abs() < 1e-12);
    }

    #[test]
    fn lines_starting_inside_the_anchor_hit_its_exit_face() {
        // The anchor straddles the target's mid-depth plane: lines start inside it and leave
        // through its far face at y = -1.0 (depth 1.0).
        let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
        let b = bx([0.0, -0.4, 0.5], [1.0, 0.6, 1.0], 0.0);
        let hit = mean_hit_on_box(&a, &b, &RelationParams::default(), &mut ()).unwrap();
        assert!((hit - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-12, "{hit}");
        assert!((score(&a, &b) - 1.0).abs() < 1e-12);
    }

    fn score_with(a: &Obb, b: &Obb, params: &RelationParams) -> Real {
        face_to(&ObjectGeom::from_box(a), &ObjectGeom::from_box(b), params)
    }

    #[test]
    fn anchors_above_or_below_the_target_count_in_plan_view() {
        let any = RelationParams::default();
        let span = RelationParams::reference();
        assert_eq!(any.face_to_heights, FaceToHeights::Any);
        assert_eq!(span.face_to_heights, FaceToHeights::TargetSpan);
        // Target 0-1 m tall facing -y; anchor hung at 1.5-2.5 m, 2 m ahead and 0.6 m to the
        // side: the lines with x in [0.1, 0.5] reach its footprint at depth 1.9, as in
        // `head_on_lateral_offset_and_away`, so the angle is atan(0.3 / 1.9).
        let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
        let high = bx([0.6, -2.0, 2.0], [0.5, 0.1, 0.5], 0.0);
        let expected = 1.0 - (0.3f64 / 1.9).atan().to_degrees() / 30.0;
        assert!((score_with(&a, &high, &any) - expected).abs() < 1e-12);
        assert_eq!(score_with(&a, &high, &span), 0.0);
        // Below the target (a rug under a raised object) likewise.
        let low = bx([0.0, -2.0, -3.0], [0.5, 0.1, 0.5], 0.0);
        assert!((score_with(&a, &low, &any) - 1.0).abs() < 1e-12);
        assert_eq!(score_with(&a, &low, &span), 0.0);
        // An anchor behind the target stays unseen at any height.
        let behind = bx([0.0, 2.0, 2.0], [0.5, 0.1, 0.5], 0.0);
        assert_eq!(score_with(&a, &behind, &any), 0.0);
    }

    #[test]
    fn plan_view_changes_nothing_when_the_anchor_spans_the_target_height() {
        // Anchors whose height covers the target's: every ray meets them at the same point
        // either way, bit for bit.
        let a = bx([0.3, -0.2, 0.5], [0.5, 0.3, 0.5], 0.4);
        for (c, h, yaw) in [
            ([0.0, -2.0, 0.5], [0.5, 0.1, 0.6], 0.0),
            ([0.9, -2.5, 1.0], [0.7, 0.4, 1.0], 0.7),
            ([-1.5, -1.0, 0.4], [0.3, 0.9, 0.6], 2.0),
            ([0.0, -0.4, 0.5], [1.0, 0.6, 1.0], 0.0),
        ] {
            let b = bx(c, h, yaw);
            let (any, span) = (RelationParams::default(), RelationParams::reference());
            assert_eq!(score_with(&a, &b, &any), score_with(&a, &b, &span), "{b:?}");
        }
    }

    #[test]
    fn tilted_targets_keep_the_target_heights() {
        use sceneeval_geom::na::UnitQuaternion;
        // A target tipped 0.3 rad about its x axis: its rays are not horizontal, so the anchor
        // above it is scored as the reference does (not hit).
        let a = Obb::new(
            Point3::new(0.0, 0.0, 0.5),
            Vector3::new(0.5, 0.3, 0.5),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.3).to_rotation_matrix(),
        )
        .unwrap();
        let high = bx([0.0, -2.0, 4.0], [0.5, 0.1, 0.5], 0.0);
        assert_eq!(score_with(&a, &high, &RelationParams::default()), 0.0);
    }

    #[test]
    fn mesh_anchors_above_the_target_are_probed_at_their_own_heights() {
        let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
        let b = bx([0.6, -2.0, 2.0], [0.5, 0.1, 0.5], 0.0);
        let mesh = Mesh::cuboid(&b.half_extents).unwrap();
        let pose = b.pose();
        let grid = |params: &RelationParams| {
            face_to(
                &ObjectGeom::from_box(&a),
                &ObjectGeom::with_mesh(&b, &mesh, &pose),
                params,
            )
        };
        // As in `mesh_anchor_grid_matches_the_box_formula`: the columns at x = 0.1875,
        // 0.3125, 0.4375 hit at depth 1.9, mean 0.3125.
        let expected = 1.0 - (0.3125f64 / 1.9).atan().to_degrees() / 30.0;
        assert!((grid(&RelationParams::default()) - expected).abs() < 1e-9);
        assert_eq!(grid(&RelationParams::reference()), 0.0);
        // A column's nearest hit counts: a mesh whose lower half reaches 0.5 m nearer.
        let stepped = Mesh::new(
            vec![
                // Upper block: depth 1.9 .. 2.1 (y from -2.1 to -1.9), z 2.0 .. 2.5.
                Point3::new(0.1, -2.1, 2.0),
                Point3::new(1.1, -2.1, 2.0),
                Point3::new(1.1, -1.9, 2.0),
                Point3::new(0.1, -1.9, 2.0),
                Point3::new(0.1, -2.1, 2.5),
                Point3::new(1.1, -2.1, 2.5),
                Point3::new(1.1, -1.9, 2.5),
                Point3::new(0.1, -1.9, 2.5),
                // Lower block: depth 1.4 .. 2.1, z 1.5 .. 2.0.
                Point3::new(0.1, -2.1, 1.5),
                Point3::new(1.1, -2.1, 1.5),
                Point3::new(1.1, -1.4, 1.5),
                Point3::new(0.1, -1.4, 1.5),
                Point3::new(0.1, -2.1, 1.99),
                Point3::new(1.1, -2.1, 1.99),
                Point3::new(1.1, -1.4, 1.99),
                Point3::new(0.1, -1.4, 1.99),
            ],
            sceneeval_geom::CUBOID_TRIANGLES
                .iter()
                .flat_map(|t| [*t, t.map(|v| v + 8)])
                .collect(),
        )
        .unwrap();
        let identity = Isometry3::identity();
        let b2 = bx([0.6, -1.75, 2.0], [0.5, 0.35, 0.5], 0.0);
        let s = face_to(
            &ObjectGeom::from_box(&a),
            &ObjectGeom::with_mesh(&b2, &stepped, &identity),
            &RelationParams::default(),
        );
        let expected = 1.0 - (0.3125f64 / 1.4).atan().to_degrees() / 30.0;
        assert!((s - expected).abs() < 1e-9, "{s} vs {expected}");
    }

    #[test]
    fn mesh_anchor_grid_matches_the_box_formula() {
        let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
        let b = bx([0.6, -2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
        let mesh = Mesh::cuboid(&b.half_extents).unwrap();
        let pose = b.pose();
        let p = RelationParams::default();
        let exact = face_to(&ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b), &p);
        let grid = face_to(
            &ObjectGeom::from_box(&a),
            &ObjectGeom::with_mesh(&b, &mesh, &pose),
            &p,
        );
        // With 8 x 8 rays, the columns at x = 0.1875, 0.3125, 0.4375 hit (x >= 0.1): mean
        // 0.3125 vs the exact 0.3 -> a small difference in angle.
        let grid_expected = 1.0 - (0.3125f64 / 1.9).atan().to_degrees() / 30.0;
        assert!((grid - grid_expected).abs() < 1e-9, "{grid} vs {grid_expected}");
        assert!((grid - exact).abs() < 0.02);
    }
}
