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
//!   end points; the lines' coefficients and their derivatives come from a small forward-mode
//!   evaluation ([`D`]) of the face corners from the pose.
//! - **Mesh anchor** (a fixed grid of rays): each counted ray's hit depth moves with the ray
//!   as `dt = -n . (do + t df) / (n . f)` for the hit triangle's normal `n`; rays starting or
//!   ceasing to hit make jumps, not derivatives.
//!
//! At angle 0 (the maximum) and beyond the clip the derivative is 0.

use std::ops::{Add, Mul, Neg, Sub};

use sceneeval_geom::{Obb, Point2, Point3, RayHit, Real, Vector3};

use super::{BoxGrad, PairGrad, pair_result};
use crate::face_to::{HitSink, Piece, angle_score, is_upright, line, mean_hit};
use crate::pairwise::effective_half;
use crate::{ObjectGeom, RelationParams};

/// The parameters differentiated: the target's centre (0-2), yaw (3) and half extents (4-6),
/// the anchor's half extents (7-9).
const N: usize = 10;
const YAW: usize = 3;
const TARGET_HALF: usize = 4;
const ANCHOR_HALF: usize = 7;

/// A value with its derivatives with respect to the [`N`] parameters (forward mode).
#[derive(Debug, Clone, Copy)]
struct D {
    v: Real,
    d: [Real; N],
}

impl D {
    const fn constant(v: Real) -> D {
        D { v, d: [0.0; N] }
    }

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

/// A 3-vector of [`D`]s.
type V3 = [D; 3];

fn dot(a: &V3, b: &V3) -> D {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn add(a: &V3, b: &V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: &V3, k: D) -> V3 {
    [a[0] * k, a[1] * k, a[2] * k]
}

/// The pose of the anchor's box in the target's frame, moving with the parameters: its axes
/// (columns of `m`), its centre `c` and half extents `hb`, and the target's cross-section
/// half extents `hx`, `hz`.
struct Frame {
    m: [V3; 3],
    c: V3,
    hb: V3,
    hx: D,
    hz: D,
}

impl Frame {
    fn new(a: &Obb, b: &Obb, prism: bool, params: &RelationParams) -> Frame {
        let rt = a.rotation.inverse();
        let w = rt * Vector3::z();
        let m = (rt * b.rotation).into_inner();
        let cv = rt * (b.center - a.center);
        let free = |k: usize| a.half_extents[k] >= params.min_half_extent;
        // Turning the target by dtheta turns everything in its frame by -w x.
        let col = |j: usize| -> V3 {
            let mj = m.column(j).into_owned();
            let turn = -w.cross(&mj);
            std::array::from_fn(|r| {
                let mut d = [0.0; N];
                d[YAW] = turn[r];
                D::with(mj[r], d)
            })
        };
        let turn = -w.cross(&cv);
        let c = std::array::from_fn(|r| {
            let mut d = [0.0; N];
            for k in 0..3 {
                // A prism stands at the target's height: it rises with it.
                if !(prism && k == 2) {
                    d[k] = -rt[(r, k)];
                }
            }
            d[YAW] = turn[r];
            D::with(cv[r], d)
        });
        let h = effective_half(a, params);
        let unit = |v: Real, k: usize, slope: Real| {
            let mut d = [0.0; N];
            d[k] = slope;
            D::with(v, d)
        };
        let hb = std::array::from_fn(|l| {
            if prism && l == 2 {
                // prism_over: 2 * span + 1, span the target's (floored) half height.
                unit(b.half_extents.z, TARGET_HALF + 2, if free(2) { 2.0 } else { 0.0 })
            } else {
                unit(b.half_extents[l], ANCHOR_HALF + l, 1.0)
            }
        });
        Frame {
            m: [col(0), col(1), col(2)],
            c,
            hb,
            hx: unit(h.x, TARGET_HALF, if free(0) { 1.0 } else { 0.0 }),
            hz: unit(h.z, TARGET_HALF + 2, if free(2) { 1.0 } else { 0.0 }),
        }
    }
}

/// A face of the anchor in the target's frame: its normal, offset and projected corners, as
/// `mean_hit_on_box` builds them, with their derivatives.
struct Face {
    n: V3,
    delta: D,
    corners: [[D; 2]; 4],
    /// The winding of the projected quadrilateral (`+-1`).
    winding: Real,
}

impl Face {
    fn new(f: &Frame, axis: usize, sign: Real) -> Face {
        let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
        let n = scale(&f.m[axis], D::constant(sign));
        let fc = add(&f.c, &scale(&n, f.hb[axis]));
        let (ej, ek) = (scale(&f.m[j], f.hb[j]), scale(&f.m[k], f.hb[k]));
        let corner = |sj: Real, sk: Real| -> [D; 2] {
            let p = add(
                &add(&fc, &scale(&ej, D::constant(sj))),
                &scale(&ek, D::constant(sk)),
            );
            [p[0], p[2]]
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
            delta: dot(&n, &fc),
            n,
            corners,
            winding: if twice >= 0.0 { 1.0 } else { -1.0 },
        }
    }

    /// The line `a u + b v <= c` (inside the piece) of an edge labelled `label`.
    fn line(&self, f: &Frame, label: u8) -> [D; 3] {
        let (one, zero) = (D::constant(1.0), D::constant(0.0));
        match label {
            line::RECT_X_POS => [one, zero, f.hx],
            line::RECT_X_NEG => [-one, zero, f.hx],
            line::RECT_Z_POS => [zero, one, f.hz],
            line::RECT_Z_NEG => [zero, -one, f.hz],
            line::DEPTH => [-self.n[0], -self.n[2], -self.delta],
            l if (line::QUAD..line::QUAD + 4).contains(&l) => {
                let e = usize::from(l - line::QUAD);
                let (p, q) = (self.corners[e], self.corners[(e + 1) % 4]);
                let (dx, dy) = ((q[0] - p[0]) * self.winding, (q[1] - p[1]) * self.winding);
                [dy, -dx, dy * p[0] - dx * p[1]]
            }
            l => {
                let s = usize::from(l - line::SLAB);
                let (axis, upper) = (s / 2, s % 2 == 0);
                let col = &f.m[axis];
                let off = dot(col, &f.c);
                if upper {
                    [col[0], col[2], f.hb[axis] + off]
                } else {
                    [-col[0], -col[2], f.hb[axis] - off]
                }
            }
        }
    }
}

/// What the gradient needs of [`mean_hit`]'s pass: the pieces (box anchor; at most one per
/// face) or the sum of the counted rays' hit derivatives (mesh anchor).
struct Recorder<'a> {
    target: &'a Obb,
    params: &'a RelationParams,
    /// Whether the mesh grid casts its rays at the anchor's heights (as `mean_hit` decides).
    plan_view: bool,
    anchor: Option<(Obb, bool)>,
    pieces: [Option<Piece>; 6],
    count: usize,
    /// The rays counted.
    ray_count: usize,
    /// Per parameter, the sum over counted rays of the derivative of their hit point
    /// `(u, -t, v)`.
    rays: [Vector3; N],
}

impl HitSink for Recorder<'_> {
    fn anchor_box(&mut self, b: &Obb, prism: bool) {
        self.anchor = Some((*b, prism));
    }

    fn piece(&mut self, piece: &Piece) {
        if let Some(slot) = self.pieces.get_mut(self.count) {
            *slot = Some(*piece);
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
            self.rays[TARGET_HALF].x += s;
            self.rays[TARGET_HALF].y -= dt(a.rotation * Vector3::new(s, 0.0, 0.0), Vector3::zeros());
        }
        if !plan_view && free(2) && h.z > 0.0 {
            let s = local.z / h.z;
            self.rays[TARGET_HALF + 2].z += s;
            self.rays[TARGET_HALF + 2].y -= dt(a.rotation * Vector3::new(0.0, 0.0, s), Vector3::zeros());
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
fn box_pieces_grad(rec: &Recorder<'_>, g: &Vector3, hit: &Vector3) -> [Real; N] {
    let mut total = [0.0; N];
    let Some((b, prism)) = rec.anchor else {
        return total;
    };
    let pieces = &rec.pieces[..rec.count];
    let w: Real = pieces.iter().flatten().map(|p| p.area).sum();
    if w.is_nan() || w <= 0.0 {
        return total;
    }
    let frame = Frame::new(rec.target, &b, prism, rec.params);
    // In the pieces' coordinates (u, s, v), s the depth: the mean is (H.x, -H.y, H.z).
    let gm = Vector3::new(g.x, -g.y, g.z);
    let mean = Vector3::new(hit.x, -hit.y, hit.z);
    let offset = gm.dot(&mean);
    let mut acc = |d: &D, k: Real| {
        for (t, x) in total.iter_mut().zip(d.d) {
            *t += x * k;
        }
    };
    for piece in pieces.iter().flatten() {
        let face = Face::new(&frame, piece.axis, piece.sign);
        let n = piece.normal;
        // The depth s(u, v) of the face: (n.x u + n.z v - delta) / n.y.
        let depth = |p: &Point2| (n.x * p.x + n.z * p.y - piece.delta) / n.y;
        let psi = |p: &Point2| (gm.x * p.x + gm.y * depth(p) + gm.z * p.y - offset) / w;
        // Inside: the integrand's own derivative, ds at the centroid times the area.
        let cen = piece.centroid;
        let s_at = (face.n[0] * cen.x + face.n[2] * cen.y - face.delta) * face.n[1].recip();
        acc(&s_at, gm.y * piece.area / w);
        // Along each edge: psi times the edge's outward normal speed.
        let (pts, labels) = (piece.poly.points(), piece.poly.labels());
        for (e, label) in labels.iter().enumerate() {
            let (p, q) = (pts[e], pts[(e + 1) % pts.len()]);
            let len = (q - p).norm();
            if len == 0.0 {
                continue;
            }
            let (fp, fq) = (psi(&p), psi(&q));
            let k0 = len * 0.5 * (fp + fq);
            let ku = len / 6.0 * (2.0 * fp * p.x + fp * q.x + fq * p.x + 2.0 * fq * q.x);
            let kv = len / 6.0 * (2.0 * fp * p.y + fp * q.y + fq * p.y + 2.0 * fq * q.y);
            let [a, bb, c] = face.line(&frame, *label);
            let norm = a.v.hypot(bb.v);
            if norm == 0.0 {
                continue;
            }
            let flux = c * k0 - a * ku - bb * kv;
            acc(&flux, 1.0 / norm);
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
        plan_view: params.face_to_heights == crate::FaceToHeights::Any && is_upright(target.obb),
        anchor: None,
        pieces: [None; 6],
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
        half_extents: Vector3::new(d[TARGET_HALF], d[TARGET_HALF + 1], d[TARGET_HALF + 2]),
        yaw: d[YAW],
    };
    let anchor_half = Vector3::new(d[ANCHOR_HALF], d[ANCHOR_HALF + 1], d[ANCHOR_HALF + 2]);
    pair_result(score, target_box, anchor_half, target, anchor)
}
