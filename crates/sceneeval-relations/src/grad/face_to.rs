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
//!   end points. It is computed in reverse mode: each edge adds its sensitivities to the
//!   quantities its line is made of (a corner of the anchor's box, an axis, a face's offset,
//!   a side of the cross-section: [`Adjoint`]), and these are turned into the parameters'
//!   derivatives once at the end ([`Frame::derivatives`]), so an edge costs a few products
//!   whatever the number of parameters. The pieces (at most six) are kept on the stack by the
//!   score's pass.
//! - **Mesh anchor** (a fixed grid of rays): each counted ray's hit depth moves with the ray
//!   as `dt = -n . (do + t df) / (n . f)` for the hit triangle's normal `n`; rays starting or
//!   ceasing to hit make jumps, not derivatives.
//!
//! At angle 0 (the maximum) and beyond the clip the derivative is 0.

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
            if a.half_extents[k] >= params.min_half_extent_m {
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

    /// The point `c + sum_l s_l hb_l m_l` of the anchor's box.
    fn point(&self, s: [Real; 3]) -> Vector3 {
        self.c + self.m * Vector3::from_fn(|l, _| s[l] * self.hb[l])
    }

    /// The derivatives with respect to the [`N`] parameters of a function of the frame whose
    /// sensitivities to the frame's quantities are `adj`.
    fn derivatives(&self, adj: &Adjoint) -> [Real; N] {
        let mut d = [0.0; N];
        for (k, dc) in self.dc.iter().enumerate() {
            d[k] = adj.c.dot(dc);
        }
        // Turning the target turns the centre and the axes by -w x in its frame.
        let turn = |v: Vector3| -self.w.cross(&v);
        d[YAW] = adj.c.dot(&turn(self.c))
            + (0..3)
                .map(|l| adj.m.column(l).dot(&turn(self.m.column(l).into_owned())))
                .sum::<Real>();
        for (l, &(lane, rate)) in self.hb_lane.iter().enumerate() {
            d[lane] += adj.hb[l] * rate;
        }
        d[TARGET_HALF_X] += adj.hx * self.hx_rate;
        d[TARGET_HALF_Z] += adj.hz * self.hz_rate;
        d
    }
}

/// The score's sensitivities (reverse mode) to the quantities the pieces' lines are made of:
/// the anchor's centre `c`, axes (columns of `m`) and half extents `hb` in the target's frame,
/// and the cross-section's half width `hx` and half height `hz`.
#[derive(Default)]
struct Adjoint {
    c: Vector3,
    m: Matrix3,
    hb: Vector3,
    hx: Real,
    hz: Real,
}

impl Adjoint {
    /// Adds `(ax, az)`, sensitivities to the plan coordinates `(x, z)` of the box point
    /// [`Frame::point`]`(s)`.
    fn point(&mut self, f: &Frame, s: [Real; 3], ax: Real, az: Real) {
        let a = Vector3::new(ax, 0.0, az);
        self.c += a;
        for (l, &sl) in s.iter().enumerate() {
            if sl != 0.0 {
                let mut col = self.m.column_mut(l);
                col += a * (sl * f.hb[l]);
                self.hb[l] += sl * f.m.column(l).dot(&a);
            }
        }
    }

    /// Adds `a`, a sensitivity to the offset `m_l . c + sign hb_l` (the plane of the anchor's
    /// face on that side of its axis `l`).
    fn offset(&mut self, f: &Frame, l: usize, sign: Real, a: Real) {
        let axis = f.m.column(l).into_owned();
        let mut col = self.m.column_mut(l);
        col += f.c * a;
        self.c += axis * a;
        self.hb[l] += sign * a;
    }
}

/// A face of the anchor in the target's frame, as `mean_hit_on_box` builds it: its axis and
/// side, and its projected corners `(x, z)` with their positions on the box (`s` in
/// [`Frame::point`]).
struct Face {
    axis: usize,
    sign: Real,
    corners: [Point2; 4],
    at: [[Real; 3]; 4],
    /// The winding of the projected quadrilateral (`+-1`).
    winding: Real,
}

impl Face {
    fn new(f: &Frame, axis: usize, sign: Real) -> Face {
        let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
        let at = [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)].map(|(sj, sk)| {
            let mut s = [0.0; 3];
            s[axis] = sign;
            s[j] = sj;
            s[k] = sk;
            s
        });
        let corners = at.map(|s| {
            let p = f.point(s);
            Point2::new(p.x, p.z)
        });
        let mut twice = 0.0;
        for e in 0..4 {
            let (p, q) = (corners[e], corners[(e + 1) % 4]);
            twice += p.x * q.y - q.x * p.y;
        }
        Face {
            axis,
            sign,
            corners,
            at,
            winding: if twice >= 0.0 { 1.0 } else { -1.0 },
        }
    }

    /// Adds to `adj` the sensitivities of the integral of `psi` along an edge on the line
    /// labelled `label` (`a u + b v <= c` inside the piece) as the line moves, `dc k0 - da ku -
    /// db kv`, where `k0`, `ku`, `kv` are the integrals of `psi`, `psi u` and `psi v` along the
    /// edge over `|(a, b)|` ([`Face::line_norm`]); the face's own normal and offset (the depth
    /// line) go to `adj_n` and `adj_delta`.
    fn add_flux(
        &self,
        f: &Frame,
        label: u8,
        [k0, ku, kv]: [Real; 3],
        adj: &mut Adjoint,
        adj_n: &mut Vector3,
        adj_delta: &mut Real,
    ) {
        match label {
            // u <= hx, -u <= hx: only hx moves.
            line::RECT_X_POS | line::RECT_X_NEG => adj.hx += k0,
            line::RECT_Z_POS | line::RECT_Z_NEG => adj.hz += k0,
            line::DEPTH => {
                // -n.x u - n.z v <= -delta.
                *adj_delta -= k0;
                adj_n.x += ku;
                adj_n.z += kv;
            }
            l if (line::QUAD..line::QUAD + 4).contains(&l) => {
                // dy u - dx v <= dy p.x - dx p.z for the edge p -> q, (dx, dy) = (q - p) winding:
                // the flux is F = k0 (dy p.x - dx p.z) - ku dy + kv dx.
                let e = usize::from(l - line::QUAD);
                let (p, q) = (self.corners[e], self.corners[(e + 1) % 4]);
                let s = self.winding;
                let (dx, dy) = ((q.x - p.x) * s, (q.y - p.y) * s);
                let (f_dx, f_dy) = (kv - k0 * p.y, k0 * p.x - ku);
                adj.point(f, self.at[e], k0 * dy - s * f_dx, -k0 * dx - s * f_dy);
                adj.point(f, self.at[(e + 1) % 4], s * f_dx, s * f_dy);
            }
            l => {
                // The anchor's slab l: m_l.x u + m_l.z v <= m_l . c + hb_l (upper side), or the
                // same negated with -hb_l.
                let sl = usize::from(l - line::SLAB);
                let (axis, sign) = (sl / 2, if sl % 2 == 0 { 1.0 } else { -1.0 });
                let mut col = adj.m.column_mut(axis);
                col -= Vector3::new(ku, 0.0, kv) * sign;
                adj.offset(f, axis, sign, sign * k0);
            }
        }
    }

    /// `|(a, b)|` of the line labelled `label`, `n` the face's normal.
    fn line_norm(&self, f: &Frame, n: &Vector3, label: u8) -> Real {
        match label {
            line::RECT_X_POS | line::RECT_X_NEG | line::RECT_Z_POS | line::RECT_Z_NEG => 1.0,
            line::DEPTH => n.x.hypot(n.z),
            l if (line::QUAD..line::QUAD + 4).contains(&l) => {
                let e = usize::from(l - line::QUAD);
                (self.corners[(e + 1) % 4] - self.corners[e]).norm()
            }
            l => {
                let axis = usize::from(l - line::SLAB) / 2;
                f.m[(0, axis)].hypot(f.m[(2, axis)])
            }
        }
    }

    /// Adds to `adj` the sensitivities `adj_n` and `adj_delta` to the face's normal
    /// `n = sign m_axis` and offset `delta = sign (m_axis . c + sign hb_axis)`.
    fn add_plane(&self, f: &Frame, adj_n: &Vector3, adj_delta: Real, adj: &mut Adjoint) {
        let mut col = adj.m.column_mut(self.axis);
        col += adj_n * self.sign;
        adj.offset(f, self.axis, self.sign, self.sign * adj_delta);
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
        let free = |k: usize| a.half_extents[k] >= self.params.min_half_extent_m;
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
    let Some(frame) = &rec.frame else {
        return [0.0; N];
    };
    let pieces = &rec.pieces[..rec.count];
    let w: Real = pieces.iter().map(|p| p.area).sum();
    if w.is_nan() || w <= 0.0 {
        return [0.0; N];
    }
    let gm = Vector3::new(g.x, -g.y, g.z);
    let offset = gm.dot(&Vector3::new(hit.x, -hit.y, hit.z));
    let mut adj = Adjoint::default();
    for piece in pieces {
        let face = Face::new(frame, piece.axis, piece.sign);
        let (n, delta) = (piece.normal, piece.delta);
        // The depth s(u, v) of the face: (n.x u + n.z v - delta) / n.y.
        let depth = |p: &Point2| (n.x * p.x + n.z * p.y - delta) / n.y;
        let psi = |p: &Point2| (gm.x * p.x + gm.y * depth(p) + gm.z * p.y - offset) / w;
        // Inside: the depth's own change at the centroid, times the area, k ds:
        // ds = (dn.x u + dn.z v - ddelta - s dn.y) / n.y.
        let cen = piece.centroid;
        let k = gm.y * piece.area / w / n.y;
        let mut adj_n = Vector3::new(cen.x, -depth(&cen), cen.y) * k;
        let mut adj_delta = -k;
        // Along each edge: psi times its outward normal speed (dc - da u - db v) / |(a, b)|.
        let (pts, labels) = (piece.poly.points(), piece.poly.labels());
        for (e, &label) in labels.iter().enumerate() {
            let (p, q) = (pts[e], pts[(e + 1) % pts.len()]);
            let len = (q - p).norm();
            let norm = face.line_norm(frame, &n, label);
            if len == 0.0 || norm == 0.0 {
                continue;
            }
            // Integrals along the edge of psi, psi u and psi v (psi linear: exact).
            let (fp, fq) = (psi(&p), psi(&q));
            let l = len / (6.0 * norm);
            let k0 = 3.0 * l * (fp + fq);
            let ku = l * (2.0 * fp * p.x + fp * q.x + fq * p.x + 2.0 * fq * q.x);
            let kv = l * (2.0 * fp * p.y + fp * q.y + fq * p.y + 2.0 * fq * q.y);
            face.add_flux(frame, label, [k0, ku, kv], &mut adj, &mut adj_n, &mut adj_delta);
        }
        face.add_plane(frame, &adj_n, adj_delta, &mut adj);
    }
    frame.derivatives(&adj)
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
