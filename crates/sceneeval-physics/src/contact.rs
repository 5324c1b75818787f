//! Contact points between convex pieces: the narrow phase's pair dispatcher.
//!
//! rapier asks its query dispatcher for the contact manifold of every pair of colliders that
//! may touch. parry's default dispatcher handles a pair of convex polyhedra (the V-HACD pieces,
//! the floor slabs) with GJK and EPA for the contact normal and then clips the two shapes'
//! support faces against each other. Two of its shortcuts give wrong contacts for objects
//! resting where the generator put them, and both changed verdicts (issue 34):
//!
//! - **The normal of an exact touch.** When two faces touch exactly (distance 0, the usual
//!   state of an object placed on the floor), the origin lies on the boundary of the shapes'
//!   Minkowski difference; GJK's simplex can then collapse into the contact face, and GJK
//!   reports "touching" with its last *search* direction as the normal, which lies in the
//!   contact plane instead of across it. A 0.5 x 0.4 x 0.6 m box at the centre of a 4 x 5 m
//!   room got the normal (-0.758, 0.652, 0) against the floor slab, and clipping the slab's and
//!   the box's side faces along it gave four contacts 3.626 m deep: a phantom
//!   interpenetration, and a sideways push in the simulation. 1e-9 m off centre the simplex
//!   did not collapse and the normal was right.
//! - **Faces of more than four vertices.** A convex polyhedron's support face is cut to its
//!   first four vertices (a `TODO` in parry 0.31), so the round base of a lamp or a plant pot
//!   (a 16-gon) touched the floor on a sliver of its rim: the centre of mass lay outside the
//!   contact patch, and whether the object rocked back or toppled depended on the last bits of
//!   its pose (a plant turned by one yaw moved 3 cm and 0.099 rad, by the yaw rounded to three
//!   decimals 0.0002 rad).
//!
//! [`ContactDispatcher`] is parry's dispatcher except for pairs of convex polyhedra (a
//! `ConvexPolyhedron` with a `ConvexPolyhedron` or a `Cuboid`; two cuboids keep parry's exact
//! box-box test), whose manifolds it computes as follows:
//!
//! 1. **Normal.** GJK (and EPA) as parry runs them; the normal `n` they give is then checked
//!    against the shapes themselves: along `n` the shapes must be as far apart as GJK's
//!    witness points say, `s(n) = min_B n.b - max_A n.a` (two support queries). A collapsed
//!    simplex fails the check (the phantom case: witnesses 0 apart, `s(n) = -3.626`), and the
//!    normal is then found exactly by the separating-axis test: the face normals of both
//!    shapes and the cross products of their edge directions (while there are at most
//!    [`MAX_SAT_EDGE_PAIRS`] pairs), keeping the axis of largest separation. For convex
//!    polyhedra the largest separation over all directions is attained on one of these axes,
//!    so a box resting on a slab gets the slab's face normal and depth 0.
//! 2. **Points.** The face of each shape most aligned with the normal (all its vertices), both
//!    projected onto the plane across the normal and intersected (Sutherland-Hodgman); every
//!    vertex of the intersection, lifted back onto each face along the normal, is a contact
//!    whose distance is the gap between the two faces there, kept when at most the prediction
//!    distance. rapier keeps four of them per manifold (the deepest, the farthest from it and
//!    the two extremes across), so a round base rests on a quadrilateral spanning it.
//!
//! The contact ids name the features (a vertex of one face inside the other, or two crossing
//! edges) so that rapier carries each contact's impulse from step to step.

use rapier3d_f64::parry::math::{Pose, Real, Vector};
use rapier3d_f64::parry::query::details::{
    NormalConstraints, contact_manifolds_composite_shape_composite_shape,
    contact_manifolds_composite_shape_shape, contact_support_map_support_map_with_params,
};
use rapier3d_f64::parry::query::gjk::{GJKResult, VoronoiSimplex};
use rapier3d_f64::parry::query::{
    ClosestPoints, Contact, ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher,
    NonlinearRigidMotion, PersistentQueryDispatcher, QueryDispatcher, ShapeCastHit, ShapeCastOptions,
    ShapeDistance, ShapeIntersection, TrackedContact, Unsupported,
};
use rapier3d_f64::parry::shape::{ConvexPolyhedron, Cuboid, PackedFeatureId, Shape, ShapeType, SupportMap};

/// Most pairs of edge directions the separating-axis test tries (a cuboid has 3 directions; a
/// V-HACD piece of 100 vertices about 300): beyond, only the face normals are tried, which
/// are exact for every contact between faces (resting, stacking) and for vertices on faces.
pub const MAX_SAT_EDGE_PAIRS: usize = 4096;

/// How much closer (metres) the shapes may be along a GJK normal than its witness points say
/// before the normal is rejected as degenerate.
const NORMAL_CHECK_TOLERANCE: Real = 1e-6;

/// A pose change below this (cosine of the normals' angle, squared point motion in m²) lets
/// a manifold update its points instead of computing them again, as parry's does.
const COHERENCE_COS: Real = 0.999_847_695_156_391_2; // cos(1 degree)
const COHERENCE_DIST_SQ: Real = 1e-6;

/// rapier's narrow-phase dispatcher: parry's, with the manifolds of pairs of convex polyhedra
/// computed as the module docs say. Compound shapes (objects of several pieces) are split
/// here, so each pair of pieces comes back through it.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ContactDispatcher;

impl QueryDispatcher for ContactDispatcher {
    fn intersection_test(
        &self,
        pos12: &Pose,
        g1: &dyn Shape,
        g2: &dyn Shape,
    ) -> Result<ShapeIntersection, Unsupported> {
        DefaultQueryDispatcher.intersection_test(pos12, g1, g2)
    }

    fn distance(&self, pos12: &Pose, g1: &dyn Shape, g2: &dyn Shape) -> Result<ShapeDistance, Unsupported> {
        DefaultQueryDispatcher.distance(pos12, g1, g2)
    }

    fn contact(
        &self,
        pos12: &Pose,
        g1: &dyn Shape,
        g2: &dyn Shape,
        prediction: Real,
    ) -> Result<Option<Contact>, Unsupported> {
        DefaultQueryDispatcher.contact(pos12, g1, g2, prediction)
    }

    fn closest_points(
        &self,
        pos12: &Pose,
        g1: &dyn Shape,
        g2: &dyn Shape,
        max_dist: Real,
    ) -> Result<ClosestPoints, Unsupported> {
        DefaultQueryDispatcher.closest_points(pos12, g1, g2, max_dist)
    }

    fn cast_shapes(
        &self,
        pos12: &Pose,
        local_vel12: Vector,
        g1: &dyn Shape,
        g2: &dyn Shape,
        options: ShapeCastOptions,
    ) -> Result<Option<ShapeCastHit>, Unsupported> {
        DefaultQueryDispatcher.cast_shapes(pos12, local_vel12, g1, g2, options)
    }

    fn cast_shapes_nonlinear(
        &self,
        motion1: &NonlinearRigidMotion,
        g1: &dyn Shape,
        motion2: &NonlinearRigidMotion,
        g2: &dyn Shape,
        start_time: Real,
        end_time: Real,
        stop_at_penetration: bool,
    ) -> Result<Option<ShapeCastHit>, Unsupported> {
        DefaultQueryDispatcher.cast_shapes_nonlinear(
            motion1,
            g1,
            motion2,
            g2,
            start_time,
            end_time,
            stop_at_penetration,
        )
    }
}

impl<M, C> PersistentQueryDispatcher<M, C> for ContactDispatcher
where
    M: Default + Clone + Send + Sync,
    C: Default + Copy + Send + Sync,
{
    fn contact_manifolds(
        &self,
        pos12: &Pose,
        g1: &dyn Shape,
        g2: &dyn Shape,
        prediction: Real,
        manifolds: &mut Vec<ContactManifold<M, C>>,
        workspace: &mut Option<ContactManifoldsWorkspace>,
    ) -> Result<(), Unsupported> {
        match (g1.as_composite_shape(), g2.as_composite_shape()) {
            (Some(c1), Some(c2)) => contact_manifolds_composite_shape_composite_shape(
                self, pos12, c1, c2, prediction, manifolds, workspace,
            ),
            (Some(c1), None) => contact_manifolds_composite_shape_shape(
                self, pos12, c1, g2, prediction, manifolds, workspace, false,
            ),
            (None, Some(c2)) => contact_manifolds_composite_shape_shape(
                self,
                &pos12.inverse(),
                c2,
                g1,
                prediction,
                manifolds,
                workspace,
                true,
            ),
            (None, None) if Polytope::pair(g1, g2).is_some() => {
                if manifolds.is_empty() {
                    manifolds.push(ContactManifold::new());
                }
                return self.contact_manifold_convex_convex(
                    pos12,
                    g1,
                    g2,
                    None,
                    None,
                    prediction,
                    &mut manifolds[0],
                );
            }
            // Every other pair (none in the scenes simulated here) is parry's.
            (None, None) => {
                return DefaultQueryDispatcher
                    .contact_manifolds(pos12, g1, g2, prediction, manifolds, workspace);
            }
        }
        Ok(())
    }

    fn contact_manifold_convex_convex(
        &self,
        pos12: &Pose,
        g1: &dyn Shape,
        g2: &dyn Shape,
        normal_constraints1: Option<&dyn NormalConstraints>,
        normal_constraints2: Option<&dyn NormalConstraints>,
        prediction: Real,
        manifold: &mut ContactManifold<M, C>,
    ) -> Result<(), Unsupported> {
        match Polytope::pair(g1, g2) {
            Some((a, b)) if normal_constraints1.is_none() && normal_constraints2.is_none() => {
                polytope_manifold(pos12, a, b, prediction, manifold);
                Ok(())
            }
            _ => DefaultQueryDispatcher.contact_manifold_convex_convex(
                pos12,
                g1,
                g2,
                normal_constraints1,
                normal_constraints2,
                prediction,
                manifold,
            ),
        }
    }
}

/// A convex polyhedron as the contact generation reads it: vertices, faces (outward normal and
/// vertex loop) and edge directions.
#[derive(Debug, Clone, Copy)]
enum Polytope<'a> {
    Cuboid(&'a Cuboid),
    Hull(&'a ConvexPolyhedron),
}

/// A cuboid's faces: outward normal axis and sign, and the four corners (bit `i` of a corner
/// index is the sign of coordinate `i`) in order around the face.
const CUBOID_FACES: [(usize, Real, [u32; 4]); 6] = [
    (0, -1.0, [0, 4, 6, 2]),
    (0, 1.0, [1, 3, 7, 5]),
    (1, -1.0, [0, 1, 5, 4]),
    (1, 1.0, [2, 6, 7, 3]),
    (2, -1.0, [0, 2, 3, 1]),
    (2, 1.0, [4, 5, 7, 6]),
];

/// A vertex of a face loop: its position and the features it and the edge after it belong to.
#[derive(Debug, Clone, Copy)]
struct LoopVertex {
    point: Vector,
    vertex: PackedFeatureId,
    edge_after: PackedFeatureId,
}

impl<'a> Polytope<'a> {
    /// Both shapes as polytopes, when the pair is one this module handles (not two cuboids:
    /// parry's box-box test is exact).
    fn pair(g1: &'a dyn Shape, g2: &'a dyn Shape) -> Option<(Self, Self)> {
        let (a, b) = (Self::of(g1)?, Self::of(g2)?);
        match (a, b) {
            (Polytope::Cuboid(_), Polytope::Cuboid(_)) => None,
            _ => Some((a, b)),
        }
    }

    fn of(shape: &'a dyn Shape) -> Option<Self> {
        match shape.shape_type() {
            ShapeType::Cuboid => shape.as_cuboid().map(Polytope::Cuboid),
            ShapeType::ConvexPolyhedron => shape.as_convex_polyhedron().map(Polytope::Hull),
            _ => None,
        }
    }

    fn corner(c: &Cuboid, k: u32) -> Vector {
        let h = c.half_extents;
        Vector::new(
            if k & 1 == 0 { -h.x } else { h.x },
            if k & 2 == 0 { -h.y } else { h.y },
            if k & 4 == 0 { -h.z } else { h.z },
        )
    }

    fn num_faces(&self) -> usize {
        match self {
            Polytope::Cuboid(_) => CUBOID_FACES.len(),
            Polytope::Hull(h) => h.faces().len(),
        }
    }

    fn face_normal(&self, f: usize) -> Vector {
        match self {
            Polytope::Cuboid(_) => {
                let (axis, sign, _) = CUBOID_FACES[f];
                let mut n = Vector::ZERO;
                n[axis] = sign;
                n
            }
            Polytope::Hull(h) => h.faces()[f].normal,
        }
    }

    /// The face whose normal is closest to `dir` (the first of equals).
    fn best_face(&self, dir: Vector) -> usize {
        let mut best = (0, Real::NEG_INFINITY);
        for f in 0..self.num_faces() {
            let d = self.face_normal(f).dot(dir);
            if d > best.1 {
                best = (f, d);
            }
        }
        best.0
    }

    /// Face `f`'s vertices in order around it, into `out`.
    fn face_loop(&self, f: usize, out: &mut Vec<LoopVertex>) {
        out.clear();
        match self {
            Polytope::Cuboid(c) => {
                let corners = CUBOID_FACES[f].2;
                for (i, &k) in corners.iter().enumerate() {
                    let next = corners[(i + 1) % 4];
                    out.push(LoopVertex {
                        point: Self::corner(c, k),
                        vertex: PackedFeatureId::vertex(k),
                        // An edge of the cube, named by its two corners.
                        edge_after: PackedFeatureId::edge(k.min(next) * 8 + k.max(next)),
                    });
                }
            }
            Polytope::Hull(h) => {
                let face = &h.faces()[f];
                let range = face.first_vertex_or_edge as usize
                    ..(face.first_vertex_or_edge + face.num_vertices_or_edges) as usize;
                for (&v, &e) in h.vertices_adj_to_face()[range.clone()]
                    .iter()
                    .zip(&h.edges_adj_to_face()[range])
                {
                    out.push(LoopVertex {
                        point: h.points()[v as usize],
                        vertex: PackedFeatureId::vertex(v),
                        edge_after: PackedFeatureId::edge(e),
                    });
                }
            }
        }
    }

    /// Number of distinct edge directions.
    fn num_edge_dirs(&self) -> usize {
        match self {
            Polytope::Cuboid(_) => 3,
            Polytope::Hull(h) => h.edges().len(),
        }
    }

    fn edge_dir(&self, i: usize) -> Vector {
        match self {
            Polytope::Cuboid(_) => {
                let mut d = Vector::ZERO;
                d[i] = 1.0;
                d
            }
            Polytope::Hull(h) => h.edges()[i].dir,
        }
    }
}

impl SupportMap for Polytope<'_> {
    fn local_support_point(&self, dir: Vector) -> Vector {
        match self {
            Polytope::Cuboid(c) => c.local_support_point(dir),
            Polytope::Hull(h) => h.local_support_point(dir),
        }
    }
}

/// How far apart the shapes are along the unit `n` (frame of `a`; negative: overlapping by
/// that much along `n`).
fn separation(pos12: &Pose, a: &Polytope<'_>, b: &Polytope<'_>, n: Vector) -> Real {
    let pa = a.local_support_point(n);
    let pb = pos12 * b.local_support_point(pos12.rotation.inverse() * -n);
    (pb - pa).dot(n)
}

/// What the normal search found.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Axis {
    /// Farther apart than the prediction distance: no contact; the direction is kept as the
    /// next search's start.
    Apart(Vector),
    /// The contact normal (frame of `a`, from `a` towards `b`), with GJK's witness points when
    /// its normal was kept.
    Contact {
        normal: Vector,
        witness: Option<(Vector, Vector)>,
    },
}

/// The contact normal of a pair (step 1 of the module docs).
fn contact_axis(pos12: &Pose, a: &Polytope<'_>, b: &Polytope<'_>, prediction: Real, cached: Vector) -> Axis {
    let gjk = contact_support_map_support_map_with_params(
        pos12,
        a,
        b,
        prediction,
        &mut VoronoiSimplex::new(),
        cached.try_normalize(),
    );
    match gjk {
        GJKResult::NoIntersection(dir) => return Axis::Apart(dir),
        GJKResult::ClosestPoints(p1, p2, dir) => {
            let witnessed = (p2 - p1).dot(dir);
            if separation(pos12, a, b, dir) >= witnessed - NORMAL_CHECK_TOLERANCE {
                return Axis::Contact {
                    normal: dir,
                    witness: Some((p1, p2)),
                };
            }
            tracing::trace!(
                ?dir,
                witnessed,
                "GJK's contact normal fails its check; separating axes used"
            );
        }
        GJKResult::Intersection | GJKResult::Proximity(_) => {}
    }
    let (normal, sep) = separating_axis(pos12, a, b);
    if sep > prediction {
        Axis::Apart(normal)
    } else {
        Axis::Contact {
            normal,
            witness: None,
        }
    }
}

/// The axis of largest separation among the face normals of both shapes and the cross
/// products of their edge directions (both signs), with that separation. The first of equal
/// candidates wins, in that order, so the result does not depend on anything but the shapes.
fn separating_axis(pos12: &Pose, a: &Polytope<'_>, b: &Polytope<'_>) -> (Vector, Real) {
    let mut best = (Vector::Z, Real::NEG_INFINITY);
    let mut consider = |n: Vector| {
        let s = separation(pos12, a, b, n);
        if s > best.1 {
            best = (n, s);
        }
    };
    for f in 0..a.num_faces() {
        consider(a.face_normal(f));
    }
    for f in 0..b.num_faces() {
        consider(-(pos12.rotation * b.face_normal(f)));
    }
    if a.num_edge_dirs().saturating_mul(b.num_edge_dirs()) <= MAX_SAT_EDGE_PAIRS {
        for i in 0..a.num_edge_dirs() {
            for j in 0..b.num_edge_dirs() {
                let n = a.edge_dir(i).cross(pos12.rotation * b.edge_dir(j));
                if let Some(n) = n.try_normalize() {
                    consider(n);
                    consider(-n);
                }
            }
        }
    }
    best
}

/// The contact manifold of two convex polyhedra (the module docs' steps 1 and 2).
fn polytope_manifold<M, C>(
    pos12: &Pose,
    a: Polytope<'_>,
    b: Polytope<'_>,
    prediction: Real,
    manifold: &mut ContactManifold<M, C>,
) where
    C: Default + Copy,
{
    if manifold.try_update_contacts_eps(pos12, COHERENCE_COS, COHERENCE_DIST_SQ) {
        return;
    }
    let old = std::mem::take(&mut manifold.points);
    match contact_axis(pos12, &a, &b, prediction, manifold.local_n1) {
        Axis::Apart(dir) => manifold.local_n1 = dir,
        Axis::Contact { normal, witness } => {
            face_contacts(pos12, &a, &b, normal, prediction, &mut manifold.points);
            if manifold.points.is_empty() {
                // No face pair overlaps across the normal (edge against edge, to rounding):
                // the closest points themselves.
                let (p1, p2) = witness.unwrap_or_else(|| {
                    (
                        a.local_support_point(normal),
                        pos12 * b.local_support_point(pos12.rotation.inverse() * -normal),
                    )
                });
                let dist = (p2 - p1).dot(normal);
                if dist <= prediction {
                    manifold.points.push(TrackedContact::new(
                        p1,
                        pos12.inverse_transform_point(p2),
                        PackedFeatureId::UNKNOWN,
                        PackedFeatureId::UNKNOWN,
                        dist,
                    ));
                }
            }
            manifold.local_n1 = normal;
            manifold.local_n2 = pos12.rotation.inverse() * -normal;
        }
    }
    manifold.match_contacts(&old);
}

/// Step 2 of the module docs: the contacts between the faces of `a` and `b` most aligned with
/// `normal` (frame of `a`), within `prediction`, appended to `out`.
fn face_contacts<C: Default + Copy>(
    pos12: &Pose,
    a: &Polytope<'_>,
    b: &Polytope<'_>,
    normal: Vector,
    prediction: Real,
    out: &mut Vec<TrackedContact<C>>,
) {
    let fa = a.best_face(normal);
    let fb = b.best_face(pos12.rotation.inverse() * -normal);
    let (mut face_a, mut face_b) = (Vec::new(), Vec::new());
    a.face_loop(fa, &mut face_a);
    b.face_loop(fb, &mut face_b);
    for v in &mut face_b {
        v.point = pos12 * v.point;
    }
    let na = a.face_normal(fa);
    let nb = pos12.rotation * b.face_normal(fb);
    // Both faces face the normal by at least 1/3 (a convex polyhedron always has a face that
    // close to any direction), so lifting a point along the normal onto them is well posed.
    let (ca, cb) = (na.dot(normal), -nb.dot(normal));
    if !(ca > 1e-3 && cb > 1e-3) {
        return;
    }
    let (t1, t2) = normal.any_orthonormal_pair();
    let flat = |p: Vector| [p.dot(t1), p.dot(t2)];
    let polygon = clip_faces(&face_a, &face_b, &flat);
    let (fid_a, fid_b) = (PackedFeatureId::face(fa as u32), PackedFeatureId::face(fb as u32));
    let (oa, ob) = (face_a[0].point, face_b[0].point);
    for v in polygon {
        // The point of each face plane on the line through (u, v) along the normal.
        let base = t1 * v.uv[0] + t2 * v.uv[1];
        let pa = base + normal * (na.dot(oa - base) / na.dot(normal));
        let pb = base + normal * (nb.dot(ob - base) / nb.dot(normal));
        let dist = (pb - pa).dot(normal);
        if dist <= prediction {
            let (id_a, id_b) = v.features(fid_a, fid_b);
            out.push(TrackedContact::new(
                pa,
                pos12.inverse_transform_point(pb),
                id_a,
                id_b,
                dist,
            ));
        }
    }
}

/// A vertex of the intersection of the two projected faces, with the features it comes from.
#[derive(Debug, Clone, Copy)]
struct ClipVertex {
    uv: [Real; 2],
    /// A vertex of face `a` inside face `b`, or the crossing of an edge of `a` with an edge
    /// of `b`, or a vertex of `b` inside `a`.
    origin: Origin,
    /// The edge of the polygon after this vertex: on an edge of `a`, or on edge `k` of `b`.
    after: After,
}

#[derive(Debug, Clone, Copy)]
enum Origin {
    VertexA(PackedFeatureId),
    Crossing(PackedFeatureId, PackedFeatureId),
    VertexB(PackedFeatureId),
}

#[derive(Debug, Clone, Copy)]
enum After {
    EdgeA(PackedFeatureId),
    EdgeB(usize),
}

impl ClipVertex {
    /// The contact's feature ids on `a` and on `b`.
    fn features(
        &self,
        face_a: PackedFeatureId,
        face_b: PackedFeatureId,
    ) -> (PackedFeatureId, PackedFeatureId) {
        match self.origin {
            Origin::VertexA(v) => (v, face_b),
            Origin::Crossing(ea, eb) => (ea, eb),
            Origin::VertexB(v) => (face_a, v),
        }
    }
}

/// The intersection of face `a` and face `b` (both in `a`'s frame) projected by `flat`:
/// `a`'s polygon clipped by each edge of `b`'s (Sutherland-Hodgman), each vertex knowing its
/// features. Either winding is accepted.
fn clip_faces(a: &[LoopVertex], b: &[LoopVertex], flat: &impl Fn(Vector) -> [Real; 2]) -> Vec<ClipVertex> {
    let mut poly: Vec<ClipVertex> = a
        .iter()
        .map(|v| ClipVertex {
            uv: flat(v.point),
            origin: Origin::VertexA(v.vertex),
            after: After::EdgeA(v.edge_after),
        })
        .collect();
    let pb: Vec<[Real; 2]> = b.iter().map(|v| flat(v.point)).collect();
    let m = pb.len();
    // Twice the signed area: which side of each edge of `b` is inside.
    let orientation: Real = (0..m)
        .map(|k| {
            let (p, q) = (pb[k], pb[(k + 1) % m]);
            p[0] * q[1] - p[1] * q[0]
        })
        .sum();
    let sign = if orientation >= 0.0 { 1.0 } else { -1.0 };
    let mut next = Vec::with_capacity(poly.len() + m);
    for k in 0..m {
        if poly.is_empty() {
            break;
        }
        let (p, q) = (pb[k], pb[(k + 1) % m]);
        let side = |uv: [Real; 2]| sign * ((q[0] - p[0]) * (uv[1] - p[1]) - (q[1] - p[1]) * (uv[0] - p[0]));
        next.clear();
        let n = poly.len();
        for i in 0..n {
            let (cur, nxt) = (poly[i], poly[(i + 1) % n]);
            let (sc, sn) = (side(cur.uv), side(nxt.uv));
            if sc >= 0.0 {
                // On edge `k`'s line and leaving the inside: the polygon goes on along it.
                let after = if sc == 0.0 && sn < 0.0 {
                    After::EdgeB(k)
                } else {
                    cur.after
                };
                next.push(ClipVertex { after, ..cur });
            }
            // A crossing strictly between the two (a vertex on the line is kept as itself).
            if (sc > 0.0 && sn < 0.0) || (sc < 0.0 && sn > 0.0) {
                let t = sc / (sc - sn);
                let uv = [
                    cur.uv[0] + (nxt.uv[0] - cur.uv[0]) * t,
                    cur.uv[1] + (nxt.uv[1] - cur.uv[1]) * t,
                ];
                let origin = match cur.after {
                    After::EdgeA(ea) => Origin::Crossing(ea, b[k].edge_after),
                    // Where edge `j` of `b` meets edge `k`: their shared vertex.
                    After::EdgeB(j) => Origin::VertexB(b[if (j + 1) % m == k { k } else { j }].vertex),
                };
                let after = if sc > 0.0 { After::EdgeB(k) } else { cur.after };
                next.push(ClipVertex { uv, origin, after });
            }
        }
        std::mem::swap(&mut poly, &mut next);
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The floor slab of the 4 x 5 m room: the outline grown by 0.5 m, 1 m deep.
    fn slab() -> ConvexPolyhedron {
        let mut pts = Vec::new();
        for (x, y) in [(-0.5, -0.5), (4.5, -0.5), (4.5, 5.5), (-0.5, 5.5)] {
            pts.push(Vector::new(x, y, 0.0));
            pts.push(Vector::new(x, y, -1.0));
        }
        ConvexPolyhedron::from_convex_hull(&pts).unwrap()
    }

    /// An upright prism with an `n`-gon of radius `r` as its base, from z = 0 to `h`.
    fn prism(n: usize, r: Real, h: Real) -> ConvexPolyhedron {
        let pts: Vec<Vector> = (0..n)
            .flat_map(|k| {
                let a = std::f64::consts::TAU * k as Real / n as Real;
                [0.0, h].map(|z| Vector::new(r * a.cos(), r * a.sin(), z))
            })
            .collect();
        ConvexPolyhedron::from_convex_hull(&pts).unwrap()
    }

    fn manifold(
        pos12: &Pose,
        g1: &dyn Shape,
        g2: &dyn Shape,
        prediction: Real,
        ours: bool,
    ) -> ContactManifold<(), ()> {
        let mut manifolds = Vec::new();
        let mut workspace = None;
        if ours {
            ContactDispatcher.contact_manifolds(pos12, g1, g2, prediction, &mut manifolds, &mut workspace)
        } else {
            DefaultQueryDispatcher.contact_manifolds(
                pos12,
                g1,
                g2,
                prediction,
                &mut manifolds,
                &mut workspace,
            )
        }
        .unwrap();
        manifolds.pop().unwrap_or_default()
    }

    fn deepest(m: &ContactManifold<(), ()>) -> Real {
        m.points.iter().map(|p| p.dist).fold(Real::INFINITY, Real::min)
    }

    #[test]
    fn a_box_touching_the_slab_at_its_centre_gets_the_face_normal_and_depth_0() {
        // The box (0.5 x 0.4 x 0.6 m) standing on the floor at the room's centre.
        let (slab, bx) = (slab(), Cuboid::new(Vector::new(0.25, 0.2, 0.3)));
        let at_centre = Pose::translation(2.0, 2.5, 0.3);
        // The cause, with parry 0.31's own dispatcher: GJK's simplex collapses into the
        // contact face and its normal lies in the floor's plane; the side faces clipped along
        // it are 3.626 m "deep".
        let parry = manifold(&at_centre, &slab, &bx, 0.002, false);
        assert!(
            parry.local_n1.z.abs() < 1e-9 && deepest(&parry) < -3.0,
            "{parry:?}"
        );
        // Here: the slab's normal, every corner of the box's base at depth 0.
        for dx in [0.0, 1e-9, 0.3] {
            let m = manifold(&Pose::translation(2.0 + dx, 2.5, 0.3), &slab, &bx, 0.002, true);
            assert!((m.local_n1 - Vector::Z).length() < 1e-12, "{dx}: {m:?}");
            assert_eq!(m.points.len(), 4, "{dx}: {m:?}");
            for p in &m.points {
                assert!(p.dist.abs() < 1e-12, "{dx}: {p:?}");
                // On the slab's top, under the box's base corners (x 2 +- 0.25, y 2.5 +- 0.2).
                assert!(p.local_p1.z.abs() < 1e-12 && ((p.local_p1.x - 2.0 - dx).abs() - 0.25).abs() < 1e-12);
                assert!(((p.local_p1.y - 2.5).abs() - 0.2).abs() < 1e-12, "{p:?}");
            }
        }
    }

    #[test]
    fn depths_and_gaps_are_the_distances_between_the_faces() {
        let (slab, bx) = (slab(), Cuboid::new(Vector::new(0.25, 0.2, 0.3)));
        // Sunk 0.2 m, centred: four contacts 0.2 m deep; 1 mm above: four at +1 mm within a
        // 2 mm prediction, none beyond it.
        for (z, expected) in [(0.1, Some(-0.2)), (0.301, Some(0.001)), (0.31, None)] {
            let m = manifold(&Pose::translation(2.0, 2.5, z), &slab, &bx, 0.002, true);
            match expected {
                Some(d) => {
                    assert_eq!(m.points.len(), 4, "{z}: {m:?}");
                    assert!(m.points.iter().all(|p| (p.dist - d).abs() < 1e-12), "{z}: {m:?}");
                }
                None => assert!(m.points.is_empty(), "{z}: {m:?}"),
            }
        }
        // The slab as the second shape: the normal from the box down into the slab.
        let m = manifold(&Pose::translation(-2.0, -2.5, -0.1), &bx, &slab, 0.002, true);
        assert!(
            (m.local_n1 + Vector::Z).length() < 1e-12 && (deepest(&m) + 0.2).abs() < 1e-12,
            "{m:?}"
        );
    }

    #[test]
    fn a_round_base_rests_on_its_whole_face() {
        // A 16-gon pot base of radius 0.15 m standing on the slab at (1.3, 3.1).
        let (slab, pot) = (slab(), prism(16, 0.15, 0.4));
        let pos12 = Pose::translation(1.3, 3.1, 0.0);
        // The cause: parry's support face keeps the base's first four vertices, a quarter of
        // its rim, plus one point from GJK.
        let parry = manifold(&pos12, &slab, &pot, 0.002, false);
        assert!(parry.points.len() <= 5, "{parry:?}");
        // Here: all 16 vertices of the base, at depth 0, around the pot's axis.
        let m = manifold(&pos12, &slab, &pot, 0.002, true);
        assert_eq!(m.points.len(), 16, "{m:?}");
        let centre = m.points.iter().map(|p| p.local_p1).sum::<Vector>() / 16.0;
        assert!(
            (centre - Vector::new(1.3, 3.1, 0.0)).length() < 1e-12,
            "{centre:?}"
        );
        assert!(m.points.iter().all(|p| p.dist.abs() < 1e-12));
        // Each contact names a vertex of the pot's base on the slab's top face.
        let mut vertices: Vec<_> = m.points.iter().map(|p| p.fid2).collect();
        vertices.sort_by_key(|f| f.0);
        vertices.dedup();
        assert_eq!(vertices.len(), 16);
    }

    #[test]
    fn a_tilted_box_rests_on_its_edge() {
        // A 0.2 m cube turned 30 degrees about x, its lowest edge on the slab: two contacts,
        // the edge's ends (x = 1.9 and 2.1), at depth 0.
        let (slab, bx) = (slab(), Cuboid::new(Vector::splat(0.1)));
        let a = 30_f64.to_radians();
        let z = 0.1 * (a.sin() + a.cos());
        let pos12 = Pose::from_parts(
            Vector::new(2.0, 2.5, z),
            rapier3d_f64::parry::math::Rotation::from_rotation_x(a),
        );
        let m = manifold(&pos12, &slab, &bx, 0.002, true);
        assert!((m.local_n1 - Vector::Z).length() < 1e-9, "{m:?}");
        let mut xs: Vec<Real> = m
            .points
            .iter()
            .filter(|p| p.dist < 1e-9)
            .map(|p| p.local_p1.x)
            .collect();
        xs.sort_by(Real::total_cmp);
        assert_eq!(xs.len(), 2, "{m:?}");
        assert!((xs[0] - 1.9).abs() < 1e-9 && (xs[1] - 2.1).abs() < 1e-9, "{xs:?}");
    }

    #[test]
    fn clipped_points_name_their_features() {
        // Two unit squares in the plane z = 0, offset by (0.5, 0.5): their intersection is
        // [0.5, 1]^2, with one vertex of each square inside the other and two crossings.
        let square = |o: Real, ids: u32| -> Vec<LoopVertex> {
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                .iter()
                .enumerate()
                .map(|(k, &(x, y))| LoopVertex {
                    point: Vector::new(x + o, y + o, 0.0),
                    vertex: PackedFeatureId::vertex(ids + k as u32),
                    edge_after: PackedFeatureId::edge(ids + k as u32),
                })
                .collect()
        };
        let (a, b) = (square(0.0, 0), square(0.5, 10));
        let flat = |p: Vector| [p.x, p.y];
        for b in [b.clone(), b.iter().rev().copied().collect()] {
            let poly = clip_faces(&a, &b, &flat);
            let area: Real = (0..poly.len())
                .map(|i| {
                    let (p, q) = (poly[i].uv, poly[(i + 1) % poly.len()].uv);
                    p[0] * q[1] - p[1] * q[0]
                })
                .sum::<Real>()
                / 2.0;
            assert!((area.abs() - 0.25).abs() < 1e-12, "{poly:?}");
            let (fa, fb) = (PackedFeatureId::face(100), PackedFeatureId::face(200));
            let features: Vec<_> = poly.iter().map(|v| (v.uv, v.features(fa, fb))).collect();
            let at = |x: Real, y: Real| {
                features
                    .iter()
                    .find(|(uv, _)| (uv[0] - x).abs() + (uv[1] - y).abs() < 1e-12)
                    .unwrap()
                    .1
            };
            // A's corner (1, 1) lies in B; B's corner (0.5, 0.5) (its vertex 10) lies in A.
            assert_eq!(at(1.0, 1.0), (PackedFeatureId::vertex(2), fb));
            assert_eq!(at(0.5, 0.5), (fa, PackedFeatureId::vertex(10)));
            // A's right edge (edge 1) crosses B's bottom edge at (1, 0.5); A's top edge (edge
            // 2) crosses B's left edge at (0.5, 1); B's edges are named as in its loop.
            assert_eq!(at(1.0, 0.5).0, PackedFeatureId::edge(1));
            assert_eq!(at(0.5, 1.0).0, PackedFeatureId::edge(2));
            assert_eq!(poly.len(), 4);
        }
    }
}
