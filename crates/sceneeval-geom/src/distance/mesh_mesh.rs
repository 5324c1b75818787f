//! Distance between two meshes: a simultaneous branch and bound over both meshes'
//! [`DistanceTree`]s, seeded by alternating closest-point projections.

use super::tree::{Bx, DistanceTree, Frame, Indexed, Node, witness_rotation};
use super::{ClosestPoints, TURN, gjk, ordered, search_limit};
use crate::parry::math::Vector;
use crate::parry::shape::Triangle;
use crate::parry_adapter::point_to_parry;
use crate::{Isometry3, Mesh, Point3, Real};

/// The separation of `t` from the plane of `u` (0 if `t` touches or crosses it).
#[inline]
fn plane_gap(t: &Triangle, u: &Triangle) -> Real {
    let n = (u.b - u.a).cross(u.c - u.a);
    let len = n.length();
    if len == 0.0 {
        return 0.0;
    }
    let d = [n.dot(t.a - u.a), n.dot(t.b - u.a), n.dot(t.c - u.a)];
    let (lo, hi) = (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]));
    if lo > 0.0 {
        lo / len
    } else if hi < 0.0 {
        -hi / len
    } else {
        0.0
    }
}

/// A lower bound on the distance between two triangles: their separation along either
/// triangle's normal and along the line through their centroids (projections onto unit axes).
#[inline]
pub(super) fn triangle_gap(t: &Triangle, u: &Triangle) -> Real {
    let d = (u.a + u.b + u.c - t.a - t.b - t.c) / 3.0;
    let len = d.length();
    let along = if len > 0.0 {
        let t_max = d.dot(t.a).max(d.dot(t.b)).max(d.dot(t.c));
        let u_min = d.dot(u.a).min(d.dot(u.b)).min(d.dot(u.c));
        ((u_min - t_max) / len).max(0.0)
    } else {
        0.0
    };
    plane_gap(t, u).max(plane_gap(u, t)).max(along)
}

/// Branch and bound over the node pairs of two meshes' [`DistanceTree`]s (the simultaneous
/// traversal of [`mesh_mesh`]). Distances are compared squared.
///
/// A pair of internal nodes splits the larger one and visits the two child pairs nearer
/// first. Once one side is a leaf, each of its triangles, placed exactly in the other frame,
/// searches the other subtree alone with its own exact bounds. Triangle pairs pass the
/// witness-frame gap and cheap separating-axis bounds ([`triangle_gap`]) before GJK.
struct PairSearch<'a> {
    a: &'a DistanceTree,
    b: &'a DistanceTree,
    /// `a`'s frame to `b`'s frame: triangles of `a` are measured in `b`'s frame.
    ab: Frame,
    /// `b`'s frame to `a`'s frame.
    ba: Frame,
    /// `a`'s frame to the witness frame ([`witness_rotation`]).
    aw: Frame,
    /// `b`'s frame to the witness frame.
    bw: Frame,
    /// Incremented whenever the witness frame turns (boxes placed in an older one are
    /// placed again before use).
    version: u32,
    /// The distance between the points the witness frame was taken from.
    w_dist: Real,
    /// Pairs no nearer than this are pruned.
    best: Real,
    /// `best` squared.
    best2: Real,
    /// Whether a triangle pair nearer than the initial limit was found (`best` is its distance).
    found: bool,
    /// The closest points of that pair (`a`'s first, in `b`'s frame; none when they meet).
    points: Option<(Vector, Vector)>,
}

/// A node of one tree with its box moved into the other tree's frame and into the witness
/// frame (of the given version).
#[derive(Clone, Copy)]
struct Placed<'a> {
    at: usize,
    node: &'a Node,
    moved: Bx,
    w: Bx,
    version: u32,
}

/// A triangle of one mesh in `b`'s frame, with its bounds in the frame of the tree it is
/// searched against and in the witness frame (of the given version).
#[derive(Clone, Copy)]
struct Probe {
    t: Triangle,
    own: Bx,
    w: Bx,
    version: u32,
}

impl PairSearch<'_> {
    /// A lower bound on the squared distance between the triangles under `x` (of `a`) and `y`
    /// (of `b`): the largest gap between their boxes measured in `b`'s frame, in `a`'s frame
    /// and in the witness frame.
    #[inline]
    fn bound2(x: &Placed<'_>, y: &Placed<'_>) -> Real {
        x.moved
            .gap2(&y.node.bx)
            .max(x.node.bx.gap2(&y.moved))
            .max(x.w.gap2(&y.w))
    }

    #[inline]
    fn place_a<'t>(&self, (at, node): Indexed<'t>) -> Placed<'t> {
        Placed {
            at,
            node,
            moved: self.ab.boxed(&node.bx),
            w: self.aw.boxed(&node.bx),
            version: self.version,
        }
    }

    #[inline]
    fn place_b<'t>(&self, (at, node): Indexed<'t>) -> Placed<'t> {
        Placed {
            at,
            node,
            moved: self.ba.boxed(&node.bx),
            w: self.bw.boxed(&node.bx),
            version: self.version,
        }
    }

    /// `x` (of `a` if `of_a`) with its witness-frame box up to date.
    #[inline]
    fn refresh<'t>(&self, x: &Placed<'t>, of_a: bool) -> Placed<'t> {
        if x.version == self.version {
            return *x;
        }
        let frame = if of_a { &self.aw } else { &self.bw };
        Placed {
            w: frame.boxed(&x.node.bx),
            version: self.version,
            ..*x
        }
    }

    /// A probe for triangle `t` given in `b`'s frame; `own` bounds it in the frame it will be
    /// searched in.
    #[inline]
    fn probe(&self, t: Triangle, own: Bx) -> Probe {
        Probe {
            w: Bx::of_triangle(&self.bw.triangle(&t)),
            t,
            own,
            version: self.version,
        }
    }

    #[inline]
    fn refresh_probe(&self, p: &Probe) -> Probe {
        if p.version == self.version {
            *p
        } else {
            self.probe(p.t, p.own)
        }
    }

    /// Visits the node pair (`x` of `a`, `y` of `b`).
    fn visit(&mut self, x: &Placed<'_>, y: &Placed<'_>) {
        let (x, y) = (self.refresh(x, true), self.refresh(y, false));
        let (a, b) = (self.a, self.b);
        if x.node.count > 0 {
            // Each triangle of the leaf, exactly placed in `b`'s frame, against `y`'s subtree.
            for t in a.leaf(x.node) {
                let t = self.ab.triangle(t);
                let p = self.probe(t, Bx::of_triangle(&t));
                let y = self.refresh(&y, false);
                if p.own.gap2(&y.node.bx).max(p.w.gap2(&y.w)) < self.best2 {
                    self.visit_triangle_a(&p, (y.at, y.node));
                }
            }
            return;
        }
        if y.node.count > 0 {
            // Each triangle of the leaf, exactly placed in `a`'s frame, against `x`'s subtree.
            for u in b.leaf(y.node) {
                let p = self.probe(*u, Bx::of_triangle(&self.ba.triangle(u)));
                let x = self.refresh(&x, true);
                if x.node.bx.gap2(&p.own).max(x.w.gap2(&p.w)) < self.best2 {
                    self.visit_triangle_b(&p, (x.at, x.node));
                }
            }
            return;
        }
        if y.node.bx.size() > x.node.bx.size() {
            let Some((l, r)) = b.children(y.at, y.node) else {
                return;
            };
            let (l, r) = (self.place_b(l), self.place_b(r));
            for (g, n) in ordered((Self::bound2(&x, &l), l), (Self::bound2(&x, &r), r)) {
                if g < self.best2 {
                    self.visit(&x, &n);
                }
            }
        } else {
            let Some((l, r)) = a.children(x.at, x.node) else {
                return;
            };
            let (l, r) = (self.place_a(l), self.place_a(r));
            for (g, n) in ordered((Self::bound2(&l, &y), l), (Self::bound2(&r, &y), r)) {
                if g < self.best2 {
                    self.visit(&n, &y);
                }
            }
        }
    }

    /// Measures triangle `t` of `a` against triangle `u` of `b`, both in `b`'s frame; `tw` and
    /// `uw` are their bounds in the witness frame.
    #[inline]
    fn measure(&mut self, t: &Triangle, tw: &Bx, u: &Triangle, uw: &Bx) {
        // Cheap separating-axis bounds first: most candidates stop here.
        if tw.gap2(uw) >= self.best2 || triangle_gap(t, u) >= self.best {
            return;
        }
        let (d, witness) = gjk(t, u);
        if d < self.best {
            self.best = d;
            self.best2 = d * d;
            self.found = true;
            self.points = witness;
            // Turn the witness frame to the new closest points.
            if d < self.w_dist * TURN
                && let Some((p, q)) = witness
            {
                self.w_dist = d;
                self.bw = witness_rotation(q - p);
                self.aw = self.ab.then(&self.bw);
                self.version = self.version.wrapping_add(1);
            }
        }
    }

    /// Visits the pairs of triangle `p` of `a` (bounded in `b`'s frame) with the triangles
    /// under `nb`.
    fn visit_triangle_a(&mut self, p: &Probe, (ib, nb): Indexed<'_>) {
        let p = self.refresh_probe(p);
        let b = self.b;
        if nb.count > 0 {
            for u in b.leaf(nb) {
                if nb.count == 1 || p.own.gap2(&Bx::of_triangle(u)) < self.best2 {
                    let uw = Bx::of_triangle(&self.bw.triangle(u));
                    let tw = if p.version == self.version {
                        p.w
                    } else {
                        self.refresh_probe(&p).w
                    };
                    self.measure(&p.t, &tw, u, &uw);
                }
            }
            return;
        }
        let Some((l, r)) = b.children(ib, nb) else {
            return;
        };
        let bound2 = |n: &Node| p.own.gap2(&n.bx).max(p.w.gap2(&self.bw.boxed(&n.bx)));
        for (g, n) in ordered((bound2(l.1), l), (bound2(r.1), r)) {
            if g < self.best2 {
                self.visit_triangle_a(&p, n);
            }
        }
    }

    /// Visits the pairs of triangle `p` of `b` (bounded in `a`'s frame) with the triangles
    /// under `na`.
    fn visit_triangle_b(&mut self, p: &Probe, (ia, na): Indexed<'_>) {
        let p = self.refresh_probe(p);
        let a = self.a;
        if na.count > 0 {
            for t in a.leaf(na) {
                if na.count == 1 || Bx::of_triangle(t).gap2(&p.own) < self.best2 {
                    let t = self.ab.triangle(t);
                    let tw = Bx::of_triangle(&self.bw.triangle(&t));
                    let uw = if p.version == self.version {
                        p.w
                    } else {
                        self.refresh_probe(&p).w
                    };
                    self.measure(&t, &tw, &p.t, &uw);
                }
            }
            return;
        }
        let Some((l, r)) = a.children(ia, na) else {
            return;
        };
        let bound2 = |n: &Node| n.bx.gap2(&p.own).max(self.aw.boxed(&n.bx).gap2(&p.w));
        for (g, n) in ordered((bound2(l.1), l), (bound2(r.1), r)) {
            if g < self.best2 {
                self.visit_triangle_b(&p, n);
            }
        }
    }
}

/// A seed for [`mesh_mesh`]: two surface points (world coordinates) and their distance, an
/// upper bound on the answer.
struct Seed {
    upper: Real,
    from: Point3,
    to: Point3,
}

/// The closest points reached by alternating closest-point projections between two placed
/// meshes, from `start` (`a`'s point first).
fn mesh_mesh_seed(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3, start: &Point3) -> Seed {
    let mut qa = a.closest_point(pa, start);
    let mut qb = b.closest_point(pb, &qa);
    for _ in 0..2 {
        qa = a.closest_point(pa, &qb);
        qb = b.closest_point(pb, &qa);
    }
    Seed {
        upper: (qa - qb).norm(),
        from: qa,
        to: qb,
    }
}

/// An upper bound on the distance between two placed meshes' surfaces: the distance between
/// the points reached by alternating closest-point projections from `start` (a few BVH point
/// queries; often the exact distance).
pub(crate) fn mesh_mesh_upper_bound(
    a: &Mesh,
    pa: &Isometry3,
    b: &Mesh,
    pb: &Isometry3,
    start: &Point3,
) -> Real {
    mesh_mesh_seed(a, pa, b, pb, start).upper
}

/// Distance between the surfaces of two placed meshes: a simultaneous branch and bound over
/// both [`DistanceTree`]s ([`PairSearch`]), seeded by alternating closest-point projections
/// ([`mesh_mesh_upper_bound`]), which give the first bound and the first witness frame. Exact:
/// the smallest GJK distance over the triangle pairs (up to the 1e-9 relative slack of
/// [`search_limit`] when the seed itself is the answer). With the closest points (`a`'s
/// first): those of the nearest triangle pair, or the seed's.
pub(crate) fn mesh_mesh(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3) -> ClosestPoints {
    let start = pb * b.aabb().center();
    let seed = mesh_mesh_seed(a, pa, b, pb, &start);
    let local = |p: &Point3| point_to_parry(&pb.inverse_transform_point(p));
    let (ta, tb) = (a.distance_tree(), b.distance_tree());
    let ab = Frame::between(pa, pb);
    let bw = witness_rotation(local(&seed.to) - local(&seed.from));
    let best = search_limit(seed.upper);
    let mut search = PairSearch {
        a: ta,
        b: tb,
        ab,
        ba: ab.inverse(),
        aw: ab.then(&bw),
        bw,
        version: 0,
        w_dist: seed.upper,
        best,
        best2: best * best,
        found: false,
        points: None,
    };
    if let (Some(ra), Some(rb)) = (ta.root(), tb.root()) {
        let (x, y) = (search.place_a((0, ra)), search.place_b((0, rb)));
        if PairSearch::bound2(&x, &y) < search.best2 {
            search.visit(&x, &y);
        }
    }
    if search.found {
        ClosestPoints::placed(search.best, search.points, pb)
    } else {
        ClosestPoints {
            distance: seed.upper,
            points: (seed.upper > 0.0).then_some((seed.from, seed.to)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::parry_triangle;
    use super::super::test_support::{
        Lcg, brute_mesh_box, brute_mesh_mesh, sheet_and_box, sphere, world_triangles,
    };
    use crate::parry::math::Pose;
    use crate::parry::query::details;
    use crate::{Isometry3, Mesh, Obb, Point3, Real, Rotation3, Vector3};
    use std::f64::consts::FRAC_PI_4;

    #[test]
    fn branch_and_bound_equals_brute_force() {
        let a = sphere(Vector3::new(0.6, 0.4, 0.3));
        let b = sphere(Vector3::new(0.3, 0.5, 0.4));
        let bx = Obb::from_yaw(Point3::new(0.2, -0.1, 0.0), Vector3::new(0.4, 0.2, 0.3), 0.4).unwrap();
        let (pbx, cbx) = bx.to_parry();
        let tri = [
            Point3::new(0.3, 1.0, -0.2),
            Point3::new(1.1, 1.3, 0.4),
            Point3::new(0.5, 1.6, 0.9),
        ];
        for k in 0..12 {
            let kf = Real::from(k);
            let pa = Isometry3::new(
                Vector3::new(0.1 * kf, -0.3, 0.2),
                Vector3::new(0.1, 0.2, 0.3 * kf),
            );
            let pb = Isometry3::new(
                Vector3::new(1.2 - 0.05 * kf, 0.4, 0.1 * kf),
                Vector3::new(0.0, -0.3, 0.5 * kf),
            );
            let (ta, tb) = (world_triangles(&a, &pa), world_triangles(&b, &pb));
            let id = Pose::IDENTITY;
            let mut brute = Real::INFINITY;
            for x in &ta {
                for y in &tb {
                    brute = brute.min(details::distance_support_map_support_map(&id, x, y));
                }
            }
            let fast = a.distance(&pa, &b, &pb);
            assert!((fast - brute).abs() < 1e-9, "pose {k}: {fast} vs {brute}");
            let brute_box = ta
                .iter()
                .map(|x| details::distance_support_map_support_map(&pbx.inverse(), &cbx, x))
                .fold(Real::INFINITY, Real::min);
            let fast_box = a.distance_to_obb(&pa, &bx);
            assert!(
                (fast_box - brute_box).abs() < 1e-9,
                "pose {k}: {fast_box} vs {brute_box}"
            );
            let t = parry_triangle(&tri);
            let brute_tri = ta
                .iter()
                .map(|x| details::distance_support_map_support_map(&id, x, &t))
                .fold(Real::INFINITY, Real::min);
            let fast_tri = a.distance_to_triangle(&pa, &tri);
            assert!(
                (fast_tri - brute_tri).abs() < 1e-9,
                "pose {k}: {fast_tri} vs {brute_tri}"
            );
        }
    }

    #[test]
    fn mesh_distances_equal_brute_force_on_larger_meshes() {
        // Meshes with several leaves per side, flat faces with coplanar triangles (ties), a
        // non-convex open sheet with a detached part, and random poses from crossing to apart.
        let ball = Mesh::uv_ellipsoid(&Vector3::new(0.5, 0.35, 0.25), 16, 9).unwrap();
        let slab = Mesh::subdivided_box(&Vector3::new(0.3, 0.2, 0.25), 5).unwrap();
        let sheet = sheet_and_box(9);
        let meshes = [&ball, &slab, &sheet];
        let mut rng = Lcg(7);
        let mut counts = [0usize; 2];
        for k in 0..72 {
            let (a, b) = (meshes[k % 3], meshes[(k / 3) % 3]);
            let pa = rng.pose([0.0, 0.0, 0.0], 0.1, 0.6);
            // From overlapping to about a metre apart.
            let x = 0.45 + 0.8 * rng.next();
            let pb = rng.pose([x, 0.0, 0.0], 0.3, 0.6);
            let (ta, tb) = (world_triangles(a, &pa), world_triangles(b, &pb));
            let brute = brute_mesh_mesh(&ta, &tb);
            let fast = a.distance(&pa, b, &pb);
            assert!((fast - brute).abs() < 1e-9, "case {k}: {fast} vs {brute}");
            let back = b.distance(&pb, a, &pa);
            assert!((back - brute).abs() < 1e-9, "case {k} swapped: {back} vs {brute}");
            assert_eq!(fast, a.distance(&pa, b, &pb), "case {k}: not deterministic");
            counts[usize::from(brute > 0.0)] += 1;
            // The same pose against a box, in the world frame.
            let bx = Obb::new(
                pb * Point3::new(0.05, -0.02, 0.03),
                Vector3::new(0.25, 0.1, 0.2),
                pb.rotation.to_rotation_matrix(),
            )
            .unwrap();
            let brute_box = brute_mesh_box(&ta, &bx);
            let fast_box = a.distance_to_obb(&pa, &bx);
            assert!(
                (fast_box - brute_box).abs() < 1e-9,
                "case {k}: {fast_box} vs {brute_box}"
            );
            assert!(a.distance_to_obb_upper_bound(&pa, &bx) >= fast_box - 1e-12);
            let tri = [
                pb * Point3::new(0.1, 0.0, 0.0),
                pb * Point3::new(-0.1, 0.2, 0.1),
                pb * Point3::new(0.0, -0.2, 0.2),
            ];
            let t = parry_triangle(&tri);
            let brute_tri = ta
                .iter()
                .map(|x| details::distance_support_map_support_map(&Pose::IDENTITY, x, &t))
                .fold(Real::INFINITY, Real::min);
            let fast_tri = a.distance_to_triangle(&pa, &tri);
            assert!(
                (fast_tri - brute_tri).abs() < 1e-9,
                "case {k}: {fast_tri} vs {brute_tri}"
            );
        }
        assert!(counts[0] >= 12 && counts[1] >= 36, "{counts:?}");
    }

    #[test]
    fn parallel_faces_and_edges_are_exact() {
        // Flat faces facing each other at an exact gap, offset and turned in their plane so
        // that hundreds of triangle pairs tie along the normal; edges crossing at a gap.
        let slab = Mesh::subdivided_box(&Vector3::new(0.4, 0.3, 0.1), 8).unwrap();
        let id = Isometry3::identity();
        for (k, (dz, yaw)) in [(0.25, 0.0), (0.2 + 1e-7, 0.3), (0.35, 1.2), (0.2, 0.7)]
            .into_iter()
            .enumerate()
        {
            let pb = Isometry3::new(Vector3::new(0.1 * k as Real, -0.05, dz), Vector3::z() * yaw);
            let expected = dz - 0.2;
            let d = slab.distance(&id, &slab, &pb);
            assert!((d - expected).abs() < 1e-12, "{k}: {d} vs {expected}");
            // A wall-like box above, parallel, wider than the slab.
            let wall =
                Obb::from_yaw(Point3::new(0.0, 0.0, dz + 0.4), Vector3::new(2.0, 2.0, 0.3), yaw).unwrap();
            let d = slab.distance_to_obb(&id, &wall);
            assert!((d - (dz - 0.0)).abs() < 1e-12, "{k}: box {d} vs {dz}");
        }
        // Two long thin boxes crossing like a plus sign, one above the other: edge to edge.
        let bar = Mesh::subdivided_box(&Vector3::new(1.0, 0.05, 0.05), 6).unwrap();
        let pb = Isometry3::new(Vector3::new(0.1, 0.0, 0.1 + 0.03), Vector3::new(0.0, 0.0, 1.0));
        let brute = brute_mesh_mesh(&world_triangles(&bar, &id), &world_triangles(&bar, &pb));
        let fast = bar.distance(&id, &bar, &pb);
        assert!(
            (fast - 0.03).abs() < 1e-12 && (fast - brute).abs() < 1e-12,
            "{fast} vs {brute}"
        );
        // Tilted about x so that the nearest features are edges.
        let pb = Isometry3::new(Vector3::new(0.0, 0.0, 0.2), Vector3::new(FRAC_PI_4, 0.0, 1.0));
        let brute = brute_mesh_mesh(&world_triangles(&bar, &id), &world_triangles(&bar, &pb));
        let fast = bar.distance(&id, &bar, &pb);
        assert!((fast - brute).abs() < 1e-9, "{fast} vs {brute}");
        let edge_box = Obb::new(
            Point3::new(0.0, 0.0, 0.2),
            Vector3::new(1.0, 0.05, 0.05),
            Rotation3::from_euler_angles(FRAC_PI_4, 0.0, 1.0),
        )
        .unwrap();
        let brute = brute_mesh_box(&world_triangles(&bar, &id), &edge_box);
        let fast = bar.distance_to_obb(&id, &edge_box);
        assert!((fast - brute).abs() < 1e-9, "{fast} vs {brute}");
    }

    #[test]
    fn deep_trees_measure_exactly() {
        // 9,600 and 10,000 triangles (a dozen levels on each side): the nearest points are a
        // pole of the sphere and the middle of the top face, known in closed form.
        let slab = Mesh::subdivided_box(&Vector3::new(0.5, 0.5, 0.1), 20).unwrap();
        let ball = Mesh::uv_ellipsoid(&Vector3::repeat(0.3), 100, 51).unwrap();
        let id = Isometry3::identity();
        for gap in [0.0, 1e-6, 0.01, 0.4] {
            let pb = Isometry3::translation(0.0, 0.0, 0.1 + 0.3 + gap);
            let d = slab.distance(&id, &ball, &pb);
            assert!((d - gap).abs() < 1e-12, "{gap}: {d}");
            let d = ball.distance(&pb, &slab, &id);
            assert!((d - gap).abs() < 1e-12, "{gap}: {d}");
            let bx = Obb::from_yaw(Point3::new(0.0, 0.0, -0.3), Vector3::new(1.0, 1.0, 0.2), 0.3).unwrap();
            let d = ball.distance_to_obb(&pb, &bx);
            assert!((d - (0.2 + gap)).abs() < 1e-12, "{gap}: box {d}");
        }
    }

    #[test]
    fn crossing_and_touching_meshes_are_zero_apart() {
        let a = sphere(Vector3::new(0.5, 0.5, 0.5));
        let id = Isometry3::identity();
        for (dx, expected) in [(0.6, 0.0), (0.3, 0.0), (1.0, 0.0), (1.25, 0.25)] {
            let pb = Isometry3::translation(dx, 0.0, 0.0);
            let d = a.distance(&id, &a, &pb);
            // Poles and equator vertices lie on the x axis: the gap between the spheres along
            // it is dx - 1 when positive.
            assert!((d - expected).abs() < 1e-12, "dx {dx}: {d}");
            assert_eq!(a.intersects(&id, &a, &pb), d == 0.0, "dx {dx}");
        }
    }
}
