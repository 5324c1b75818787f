//! The gradient of `face_to`.
//!
//! The score is a function of the mean first-hit point `H` (target frame) alone: its plan
//! angle from the target's front, through `1 - angle / max`. Turning both objects together
//! changes nothing, so the anchor's centre and yaw follow from the target's derivatives.
//!
//! - **Box anchor**: `H` is `M / W` with `W` the total area of the cross-section pieces and
//!   `M` the integral over them of the hit point `(u, s(u, v), v)`, `s` the depth of the face
//!   the piece's lines meet (linear on the piece). Every edge of a piece lies on a line that
//!   the clipping labelled (a side of the cross-section, an edge of a face's projection, the
//!   mid-depth line, a slab of the anchor). By Leibniz's rule the derivative of an integral
//!   over a piece is the integral of the integrand's derivative plus, along each edge, the
//!   integrand times the edge's outward normal speed `(dc - da u - db v) / |(a, b)|` for its
//!   line `a u + b v <= c`. The integrands are linear, so each edge integral is exact from its
//!   end points. The integrand is the score's sensitivity to the mean (reverse mode), so each
//!   edge costs one pass over the parameters; the lines' derivatives come from closed forms
//!   for the anchor's corners and axes in the target's frame ([`D`] carries a value with its
//!   derivatives). The pieces (at most six) are kept on the stack by the score's pass.
//! - **Mesh anchor** (a fixed grid of rays): each counted ray's hit depth moves with the ray
//!   as `dt = -n . (do + t df) / (n . f)` for the hit triangle's normal `n`; rays starting or
//!   ceasing to hit make jumps, not derivatives.
//!
//! At angle 0 (the maximum) and beyond the clip the derivative is 0.

use std::ops::{Add, Mul, Neg, Sub};

use sceneeval_geom::{Matrix3, Obb, Point2, Point3, RayHit, Real, Vector3};

use super::{BoxGrad, PairGrad, pair_result};
use crate::face_to::{HitSink, Piece, angle_score, is_upright, line, mean_hit};
use crate::pairwise::effective_half;
use crate::{FaceToHeights, ObjectGeom, RelationParams};

/// The parameters differentiated: the target's centre (0-2), yaw (3), half width (4) and
/// half height (5), the anchor's half extents (6-8). The target's half depth moves nothing:
/// the lines start from its mid-depth plane.
const N: usize = 9;
const YAW: usize = 3;
const TARGET_HALF_X: usize = 4;
const TARGET_HALF_Z: usize = 5;
const ANCHOR_HALF: usize = 6;

/// A value with its derivatives with respect to the [`N`] parameters (forward mode).
#[derive(Debug, Clone, Copy)]
struct D {
    v: Real,
    d: [Real; N],
}

impl D {
    /// A value moving with its derivatives `d`.
    const fn with(v: Real, d: [Real; N]) -> D {
        D { v, d }
    }

    fn recip(self) -> D {
        let r = 1.0 / self.v;
        let k = -r * r;
        D {
            v: r,
            d: self.d.map(|x| x * k),
        }
    }
}

impl Add for D {
    type Output = D;
    #[inline]
    fn add(self, o: D) -> D {
        let mut d = self.d;
        for (x, y) in d.iter_mut().zip(o.d) {
            *x += y;
        }
        D { v: self.v + o.v, d }
    }
}

impl Sub for D {
    type Output = D;
    #[inline]
    fn sub(self, o: D) -> D {
        self + -o
    }
}

impl Neg for D {
    type Output = D;
    #[inline]
    fn neg(self) -> D {
        self * -1.0
    }
}

impl Mul<Real> for D {
    type Output = D;
    #[inline]
    fn mul(self, k: Real) -> D {
        D {
            v: self.v * k,
            d: self.d.map(|x| x * k),
        }
    }
}

impl Mul for D {
    type Output = D;
    #[inline]
    fn mul(self, o: D) -> D {
        let mut d = [0.0; N];
        for ((x, a), b) in d.iter_mut().zip(self.d).zip(o.d) {
            *x = a * o.v + b * self.v;
        }
        D { v: self.v * o.v, d }
    }
}

/// The pose of the anchor's box (or prism) in the target's frame and how it moves with the
/// parameters. In that frame everything turns by `-w x` when the target turns (`w` the world
/// vertical in the target's frame), translates by `dc[k]` when the target moves along world
/// axis `k`, and the box's faces move out along their axes as its half extents grow.
struct Frame {
    /// Columns: the anchor's axes.
    m: Matrix3,
    /// The anchor's centre and half extents.
    c: Vector3,
    hb: Vector3,
    /// The world vertical in the target's frame.
    w: Vector3,
    /// The derivative of `c` with respect to the target's centre along each world axis.
    dc: [Vector3; 3],
    /// For each of the anchor's half extents, the parameter it moves with and how fast.
    hb_lane: [(usize, Real); 3],
    /// How fast the target's cross-section half width and half height grow with its half
    /// extents (0 below the flat-box floor).
    hx_rate: Real,
    hz_rate: Real,
}

impl Frame {
    fn new(a: &Obb, b: &Obb, prism: bool, params: &RelationParams) -> Frame {
        let rt = a.rotation.inverse();
        let free = |k: usize| {
            if a.half_extents[k] >= params.min_half_extent {
                1.0
            } else {
                0.0
            }
        };
        // A prism stands at the target's height: it rises with it.
        let dc = std::array::from_fn(|k| {
            if prism && k == 2 {
                Vector3::zeros()
            } else {
                -(rt * Vector3::ith(k, 1.0))
            }
        });
        let hb_lane = std::array::from_fn(|l| {
            if prism && l == 2 {
                // prism_over: 2 * span + 1, span the target's (floored) half height.
                (TARGET_HALF_Z, 2.0 * free(2))
            } else {
                (ANCHOR_HALF + l, 1.0)
            }
        });
        Frame {
            m: (rt * b.rotation).into_inner(),
            c: rt * (b.center - a.center),
            hb: b.half_extents,
            w: rt * Vector3::z(),
            dc,
            hb_lane,
            hx_rate: free(0),
            hz_rate: free(2),
        }
    }

    /// The plan coordinates `(x, z)` of the point `c + sum_l s_l hb_l m_l` of the anchor's
    /// box, with their derivatives.
    fn point(&self, s: [Real; 3]) -> [D; 2] {
        let p = self.c + self.m * Vector3::from_fn(|l, _| s[l] * self.hb[l]);
        let turn = -self.w.cross(&p);
        [0, 2].map(|r| {
            let mut d = [0.0; N];
            for (k, dc) in self.dc.iter().enumerate() {
                d[k] = dc[r];
            }
            d[YAW] = turn[r];
            for (l, &(lane, rate)) in self.hb_lane.iter().enumerate() {
                d[lane] += s[l] * rate * self.m[(r, l)];
            }
            D::with(p[r], d)
        })
    }

    /// Component `r` of the anchor's axis `l`, turning with the target.
    fn axis(&self, l: usize, r: usize) -> D {
        let mut d = [0.0; N];
        d[YAW] = -self.w.cross(&self.m.column(l).into_owned())[r];
        D::with(self.m[(r, l)], d)
    }

    /// The offset `m_l . c + sign hb_l`: the plane of the anchor's face on that side of its
    /// axis `l`.
    fn offset(&self, l: usize, sign: Real) -> D {
        let axis = self.m.column(l).into_owned();
        let mut d = [0.0; N];
        for (k, dc) in self.dc.iter().enumerate() {
            d[k] = axis.dot(dc);
        }
        // Turning everything together leaves the dot product as it is.
        let (lane, rate) = self.hb_lane[l];
        d[lane] += sign * rate;
        D::with(axis.dot(&self.c) + sign * self.hb[l], d)
    }
}

/// A face of the anchor in the target's frame, as `mean_hit_on_box` builds it: its outward
/// normal `n` and offset `delta` (the plane `n . p = delta`) and its projected corners, with
/// their derivatives.
struct Face {
    n: [D; 3],
    delta: D,
    corners: [[D; 2]; 4],
    /// The winding of the projected quadrilateral (`+-1`).
    winding: Real,
}

impl Face {
    fn new(f: &Frame, axis: usize, sign: Real) -> Face {
        let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
        let corner = |sj: Real, sk: Real| {
            let mut s = [0.0; 3];
            s[axis] = sign;
            s[j] = sj;
            s[k] = sk;
            f.point(s)
        };
        let corners = [
            corner(1.0, 1.0),
            corner(1.0, -1.0),
            corner(-1.0, -1.0),
            corner(-1.0, 1.0),
        ];
        let mut twice = 0.0;
        for e in 0..4 {
            let (p, q) = (corners[e], corners[(e + 1) % 4]);
            twice += p[0].v * q[1].v - q[0].v * p[1].v;
        }
        Face {
            n: [0, 1, 2].map(|r| f.axis(axis, r) * sign),
            // n . fc = sign (m . c) + hb = sign (m . c + sign hb).
            delta: f.offset(axis, sign) * sign,
            corners,
            winding: if twice >= 0.0 { 1.0 } else { -1.0 },
        }
    }

    /// Adds to `total` the derivatives of the integral of `psi` along an edge on the line
    /// labelled `label` (`a u + b v <= c` inside the piece) as the line moves: per parameter
    /// `dc k0 - da ku - db kv`, where `k0`, `ku`, `kv` are the integrals of `psi`, `psi u` and
    /// `psi v` along the edge over `|(a, b)|` ([`Face::line_norm`]).
    fn add_flux(&self, f: &Frame, label: u8, [k0, ku, kv]: [Real; 3], total: &mut [Real; N]) {
        match label {
            // u <= hx, -u <= hx: only hx moves.
            line::RECT_X_POS | line::RECT_X_NEG => total[TARGET_HALF_X] += f.hx_rate * k0,
            line::RECT_Z_POS | line::RECT_Z_NEG => total[TARGET_HALF_Z] += f.hz_rate * k0,
            line::DEPTH => {
                // -n.x u - n.z v <= -delta.
                let (nx, nz) = (&self.n[0].d, &self.n[2].d);
                for (lane, t) in total.iter_mut().enumerate() {
                    *t += -self.delta.d[lane] * k0 + nx[lane] * ku + nz[lane] * kv;
                }
            }
            l if (line::QUAD..line::QUAD + 4).contains(&l) => {
                // dy u - dx v <= dy p.x - dx p.z for the edge p -> q, (dx, dy) = (q - p) winding.
                let e = usize::from(l - line::QUAD);
                let (p, q) = (&self.corners[e], &self.corners[(e + 1) % 4]);
                let s = self.winding;
                let (dx, dy) = ((q[0].v - p[0].v) * s, (q[1].v - p[1].v) * s);
                for (lane, t) in total.iter_mut().enumerate() {
                    let ddx = (q[0].d[lane] - p[0].d[lane]) * s;
                    let ddy = (q[1].d[lane] - p[1].d[lane]) * s;
                    let dc = ddy * p[0].v + dy * p[0].d[lane] - ddx * p[1].v - dx * p[1].d[lane];
                    *t += dc * k0 - ddy * ku + ddx * kv;
                }
            }
            l => {
                // The anchor's slab l: m_l.x u + m_l.z v <= m_l . c + hb_l (upper side), or the
                // same negated with -hb_l.
                let s = usize::from(l - line::SLAB);
                let (axis, sign) = (s / 2, if s % 2 == 0 { 1.0 } else { -1.0 });
                let (mx, mz, off) = (f.axis(axis, 0), f.axis(axis, 2), f.offset(axis, sign));
                for (lane, t) in total.iter_mut().enumerate() {
                    *t += sign * (off.d[lane] * k0 - mx.d[lane] * ku - mz.d[lane] * kv);
                }
            }
        }
    }

    /// `|(a, b)|` of the line labelled `label`.
    fn line_norm(&self, f: &Frame, label: u8) -> Real {
        match label {
            line::RECT_X_POS | line::RECT_X_NEG | line::RECT_Z_POS | line::RECT_Z_NEG => 1.0,
            line::DEPTH => self.n[0].v.hypot(self.n[2].v),
            l if (line::QUAD..line::QUAD + 4).contains(&l) => {
                let e = usize::from(l - line::QUAD);
                let (p, q) = (&self.corners[e], &self.corners[(e + 1) % 4]);
                (q[0].v - p[0].v).hypot(q[1].v - p[1].v)
            }
            l => {
                let axis = usize::from(l - line::SLAB) / 2;
                f.m[(0, axis)].hypot(f.m[(2, axis)])
            }
        }
    }
}

/// What the gradient needs of [`mean_hit`]'s pass: for a box anchor the anchor's frame and the
/// pieces (at most one per face, kept on the stack); for a mesh anchor the sum of the counted
/// rays' hit-point derivatives, gathered as they come.
struct Recorder<'a> {
    target: &'a Obb,
    params: &'a RelationParams,
    /// Whether the mesh grid casts its rays at the anchor's heights (as `mean_hit` decides).
    plan_view: bool,
    frame: Option<Frame>,
    pieces: [Piece; 6],
    count: usize,
    /// The rays counted.
    ray_count: usize,
    /// Per parameter, the sum over counted rays of the derivative of their hit point
    /// `(u, -t, v)`.
    rays: [Vector3; N],
}

impl HitSink for Recorder<'_> {
    fn anchor_box(&mut self, b: &Obb, prism: bool) {
        self.frame = Some(Frame::new(self.target, b, prism, self.params));
    }

    fn piece(&mut self, piece: &Piece) {
        if let Some(slot) = self.pieces.get_mut(self.count) {
            *slot = *piece;
            self.count += 1;
        }
    }

    fn ray(&mut self, local: &Vector3, origin: &Point3, hit: &RayHit) {
        self.ray_count += 1;
        let a = self.target;
        let front = a.rotation * Vector3::new(0.0, -1.0, 0.0);
        let nf = hit.normal.dot(&front);
        if nf == 0.0 {
            return;
        }
        let plan_view = self.plan_view;
        let h = effective_half(a, self.params);
        let free = |k: usize| a.half_extents[k] >= self.params.min_half_extent;
        // dt for an origin moving by `d_origin` and a direction turning by `d_front`.
        let dt = |d_origin: Vector3, d_front: Vector3| -hit.normal.dot(&(d_origin + d_front * hit.toi)) / nf;
        let z = Vector3::z();
        for k in 0..3 {
            // In plan view the rays' heights are the anchor's: the target's height moves none.
            let d_origin = if plan_view && k == 2 {
                Vector3::zeros()
            } else {
                Vector3::ith(k, 1.0)
            };
            self.rays[k].y -= dt(d_origin, Vector3::zeros());
        }
        self.rays[YAW].y -= dt(z.cross(&(origin - a.center)), z.cross(&front));
        if free(0) && h.x > 0.0 {
            let s = local.x / h.x;
            self.rays[TARGET_HALF_X].x += s;
            self.rays[TARGET_HALF_X].y -= dt(a.rotation * Vector3::new(s, 0.0, 0.0), Vector3::zeros());
        }
        if !plan_view && free(2) && h.z > 0.0 {
            let s = local.z / h.z;
            self.rays[TARGET_HALF_Z].z += s;
            self.rays[TARGET_HALF_Z].y -= dt(a.rotation * Vector3::new(0.0, 0.0, s), Vector3::zeros());
        }
    }
}

/// The derivative of the score with respect to the mean hit point `hit` (target frame); 0 at
/// angle 0, beyond the clip and where the score is constant.
fn score_grad_wrt_hit(a: &Obb, hit: &Vector3, params: &RelationParams) -> Vector3 {
    let v = a.rotation * hit;
    let front = a.rotation * Vector3::new(0.0, -1.0, 0.0);
    let (f2, v2) = (Point2::new(front.x, front.y).coords, Point2::new(v.x, v.y).coords);
    let (nf, nv2) = (f2.norm(), v2.norm_squared());
    if nf == 0.0 || nv2 == 0.0 {
        return Vector3::zeros();
    }
    let cos = f2.dot(&v2) / (nf * nv2.sqrt());
    if !(cos > -1.0 && cos < 1.0) {
        return Vector3::zeros();
    }
    let angle_deg = cos.acos().to_degrees();
    let raw = 1.0 - angle_deg / params.face_to_max_deviation_deg;
    if !(raw > 0.0 && raw < 1.0) {
        return Vector3::zeros();
    }
    // The angle grows as v turns away from the front: d angle / d v2 = sign perp(v2) / |v2|^2.
    let sign = if f2.perp(&v2) > 0.0 { 1.0 } else { -1.0 };
    let d_angle = Vector3::new(-v2.y, v2.x, 0.0) * (sign / nv2);
    let k = -(180.0 / std::f64::consts::PI) / params.face_to_max_deviation_deg;
    a.rotation.inverse_transform_vector(&(d_angle * k))
}

/// The derivatives of the score with respect to the [`N`] parameters through the box pieces,
/// given `g`, its derivative with respect to the mean hit point `hit`.
///
/// In the pieces' coordinates `(u, s, v)` the mean is `M / W` (`(H.x, -H.y, H.z)`), so the
/// score moves with `gm . (dM - mean dW) / W`: the integral over the pieces' changing domains
/// of `psi = (gm . (u, s, v) - gm . mean) / W`, linear on each piece, plus that of `gm_s ds`
/// inside (the depth's own change).
fn box_pieces_grad(rec: &Recorder<'_>, g: &Vector3, hit: &Vector3) -> [Real; N] {
    let mut total = [0.0; N];
    let Some(frame) = &rec.frame else {
        return total;
    };
    let pieces = &rec.pieces[..rec.count];
    let w: Real = pieces.iter().map(|p| p.area).sum();
    if w.is_nan() || w <= 0.0 {
        return total;
    }
    let gm = Vector3::new(g.x, -g.y, g.z);
    let offset = gm.dot(&Vector3::new(hit.x, -hit.y, hit.z));
    for piece in pieces {
        let face = Face::new(frame, piece.axis, piece.sign);
        let n = piece.normal;
        // The depth s(u, v) of the face: (n.x u + n.z v - delta) / n.y.
        let depth = |p: &Point2| (n.x * p.x + n.z * p.y - piece.delta) / n.y;
        let psi = |p: &Point2| (gm.x * p.x + gm.y * depth(p) + gm.z * p.y - offset) / w;
        // Inside: the depth's own change at the centroid, times the area.
        let cen = piece.centroid;
        let s_at = (face.n[0] * cen.x + face.n[2] * cen.y - face.delta) * face.n[1].recip();
        let k = gm.y * piece.area / w;
        for (t, x) in total.iter_mut().zip(s_at.d) {
            *t += x * k;
        }
        // Along each edge: psi times its outward normal speed (dc - da u - db v) / |(a, b)|.
        let (pts, labels) = (piece.poly.points(), piece.poly.labels());
        for (e, &label) in labels.iter().enumerate() {
            let (p, q) = (pts[e], pts[(e + 1) % pts.len()]);
            let len = (q - p).norm();
            let norm = face.line_norm(frame, label);
            if len == 0.0 || norm == 0.0 {
                continue;
            }
            // Integrals along the edge of psi, psi u and psi v (psi linear: exact).
            let (fp, fq) = (psi(&p), psi(&q));
            let l = len / (6.0 * norm);
            let k0 = 3.0 * l * (fp + fq);
            let ku = l * (2.0 * fp * p.x + fp * q.x + fq * p.x + 2.0 * fq * q.x);
            let kv = l * (2.0 * fp * p.y + fp * q.y + fq * p.y + 2.0 * fq * q.y);
            face.add_flux(frame, label, [k0, ku, kv], &mut total);
        }
    }
    total
}

/// [`crate::face_to`] and its gradient (see the module docs of [`super`] for the kinks: the
/// score jumps where a line starts or stops hitting; 0 at angle 0 and beyond 30 degrees).
///
/// ```
/// use sceneeval_relations::{grad, ObjectGeom, RelationParams};
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// // A target facing -y and an anchor 2 m ahead, 0.6 m to the side: the lines with
/// // u in [0.1, 0.5] hit at depth 1.9, mean (0.3, -1.9), angle atan(0.3 / 1.9).
/// let a = Obb::from_yaw(Point3::new(0.0, 0.0, 0.5), Vector3::new(0.5, 0.3, 0.5), 0.0).unwrap();
/// let b = Obb::from_yaw(Point3::new(0.6, -2.0, 0.5), Vector3::new(0.5, 0.1, 0.5), 0.0).unwrap();
/// let g = grad::face_to(&ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b), &RelationParams::default());
/// // Turning the target toward the anchor (counter-clockwise seen from above) raises the
/// // score; moving the anchor further out to the side lowers it.
/// assert!(g.target.yaw > 0.0 && g.anchor.center.x < 0.0);
/// ```
pub fn face_to(target: &ObjectGeom<'_>, anchor: &ObjectGeom<'_>, params: &RelationParams) -> PairGrad {
    let mut rec = Recorder {
        target: target.obb,
        params,
        plan_view: params.face_to_heights == FaceToHeights::Any && is_upright(target.obb),
        frame: None,
        pieces: [Piece::EMPTY; 6],
        count: 0,
        ray_count: 0,
        rays: [Vector3::zeros(); N],
    };
    let hit = mean_hit(target, anchor, params, &mut rec);
    let score = angle_score(target.obb, hit, params);
    let Some(hit) = hit else {
        return PairGrad {
            score,
            ..PairGrad::default()
        };
    };
    let g = score_grad_wrt_hit(target.obb, &hit, params);
    if g == Vector3::zeros() {
        return PairGrad {
            score,
            ..PairGrad::default()
        };
    }
    let d = match anchor.mesh {
        None => box_pieces_grad(&rec, &g, &hit),
        // The mean of the counted rays' hit points.
        Some(_) => rec.rays.map(|dh| g.dot(&dh) / rec.ray_count as Real),
    };
    let target_box = BoxGrad {
        center: Vector3::new(d[0], d[1], d[2]),
        half_extents: Vector3::new(d[TARGET_HALF_X], 0.0, d[TARGET_HALF_Z]),
        yaw: d[YAW],
    };
    let anchor_half = Vector3::new(d[ANCHOR_HALF], d[ANCHOR_HALF + 1], d[ANCHOR_HALF + 2]);
    pair_result(score, target_box, anchor_half, target, anchor)
}
