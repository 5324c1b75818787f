//! Distance between a mesh and one convex shape (a solid box or a triangle): branch and bound
//! over the mesh's [`DistanceTree`].

use super::mesh_mesh::triangle_gap;
use super::tree::{Bx, DistanceTree, Frame, Indexed, Node, witness_rotation};
use super::{ClosestPoints, TURN, gjk, ordered, parry_triangle};
use crate::parry::math::Vector;
use crate::parry::shape::{Cuboid, Triangle};
use crate::parry_adapter::to_parry_vec;
use crate::{Isometry3, Mesh, Obb, Point3, Real};

/// A convex shape that [`ConvexSearch`] measures a mesh against, in its own frame.
trait ConvexTarget {
    /// A lower bound on the squared distance from anything in the box `b` to the shape.
    fn gap2(&self, b: &Bx) -> Real;
    /// The distance from triangle `t` to the shape with a pair of closest points (triangle's
    /// first; none when they meet), or `None` when the distance is certainly no less than
    /// `best`.
    fn triangle(&self, t: &Triangle, best: Real) -> Option<(Real, Option<(Vector, Vector)>)>;
}

/// A solid box centred at the origin of its frame, axis-aligned.
struct BoxTarget {
    cuboid: Cuboid,
}

impl ConvexTarget for BoxTarget {
    #[inline]
    fn gap2(&self, b: &Bx) -> Real {
        (b.c.abs() - b.h - self.cuboid.half_extents)
            .max(Vector::ZERO)
            .length_squared()
    }

    /// Bracketed like [`bracketed`]: a lower bound from the triangle's bounds and its plane, an
    /// upper bound from its nearest corner; when they agree the corner is the closest point
    /// (the common case of a convex mesh facing a wall), otherwise GJK decides.
    #[inline]
    fn triangle(&self, t: &Triangle, best: Real) -> Option<(Real, Option<(Vector, Vector)>)> {
        let h = self.cuboid.half_extents;
        let lower = self.gap2(&Bx::of_triangle(t)).sqrt();
        if lower >= best {
            return None;
        }
        let n = (t.b - t.a).cross(t.c - t.a);
        let len = n.length();
        let lower = if len > 0.0 {
            lower.max((n.dot(t.a).abs() - n.abs().dot(h)) / len)
        } else {
            lower
        };
        if lower >= best {
            return None;
        }
        let corner = |p: Vector| (p, (p.abs() - h).max(Vector::ZERO).length_squared());
        let nearer = |x: (Vector, Real), y: (Vector, Real)| if y.1 < x.1 { y } else { x };
        let (v, d2) = nearer(nearer(corner(t.a), corner(t.b)), corner(t.c));
        let upper = d2.sqrt();
        if upper - lower <= 1e-12 * (1.0 + upper) {
            return Some((upper, Some((v, v.clamp(-h, h)))));
        }
        Some(gjk(t, &self.cuboid))
    }
}

/// A triangle.
struct TriangleTarget {
    t: Triangle,
    bx: Bx,
}

impl ConvexTarget for TriangleTarget {
    #[inline]
    fn gap2(&self, b: &Bx) -> Real {
        b.gap2(&self.bx)
    }

    #[inline]
    fn triangle(&self, t: &Triangle, best: Real) -> Option<(Real, Option<(Vector, Vector)>)> {
        if Bx::of_triangle(t).gap2(&self.bx) >= best * best || triangle_gap(t, &self.t) >= best {
            return None;
        }
        Some(gjk(t, &self.t))
    }
}

/// Branch and bound over one mesh's [`DistanceTree`] against a convex target (the search of
/// [`mesh_convex`]). Distances are compared squared.
struct ConvexSearch<'a, T> {
    tree: &'a DistanceTree,
    /// Mesh frame to the target's frame.
    to: Frame,
    /// Mesh frame to the witness frame ([`witness_rotation`]).
    mw: Frame,
    /// Bounds of the target in the mesh frame.
    back: Bx,
    /// Bounds of the target in the witness frame.
    target_w: Bx,
    /// Bounds of the target in its own frame.
    target_box: Bx,
    /// The distance between the points the witness frame was taken from.
    w_dist: Real,
    target: &'a T,
    /// The best distance so far (infinity before the first triangle).
    best: Real,
    /// `best` squared.
    best2: Real,
    /// The closest points behind `best` (the mesh's first, in the target's frame; none when
    /// they meet).
    points: Option<(Vector, Vector)>,
}

impl<T: ConvexTarget> ConvexSearch<'_, T> {
    /// A lower bound on the squared distance from the triangles under `n` to the target: the
    /// largest of the gaps measured in the mesh frame, the target's frame and the witness
    /// frame.
    #[inline]
    fn bound2(&self, n: &Node) -> Real {
        n.bx.gap2(&self.back)
            .max(self.target.gap2(&self.to.boxed(&n.bx)))
            .max(self.mw.boxed(&n.bx).gap2(&self.target_w))
    }

    fn visit(&mut self, (i, n): Indexed<'_>) {
        let tree = self.tree;
        if n.count > 0 {
            for t in tree.leaf(n) {
                if Bx::of_triangle(&self.mw.triangle(t)).gap2(&self.target_w) >= self.best2 {
                    continue;
                }
                if let Some((d, witness)) = self.target.triangle(&self.to.triangle(t), self.best)
                    && d < self.best
                {
                    self.best = d;
                    self.best2 = d * d;
                    self.points = witness;
                    // Turn the witness frame to the new closest points.
                    if d < self.w_dist * TURN
                        && let Some((p, q)) = witness
                    {
                        self.w_dist = d;
                        let w = witness_rotation(p - q);
                        self.mw = self.to.then(&w);
                        self.target_w = w.boxed(&self.target_box);
                    }
                }
            }
            return;
        }
        let Some((l, r)) = tree.children(i, n) else {
            return;
        };
        for (g, n) in ordered((self.bound2(l.1), l), (self.bound2(r.1), r)) {
            if g < self.best2 {
                self.visit(n);
            }
        }
    }
}

/// Distance from a placed mesh's surface to a convex target placed at `target_pose` (bounded
/// by `target_box` in its own frame), by branch and bound over the mesh's [`DistanceTree`]:
/// depth first, nearer child first, a node pruned when its lower bound
/// ([`ConvexSearch::bound2`]) is no less than the best distance so far. No seed: the first
/// leaf reached gives the first bound and the witness frame. Returns the distance and the
/// closest points (the mesh's first, world coordinates).
fn mesh_convex<T: ConvexTarget>(
    mesh: &Mesh,
    mesh_pose: &Isometry3,
    target: &T,
    target_box: &Bx,
    target_pose: &Isometry3,
) -> ClosestPoints {
    let tree = mesh.distance_tree();
    let to = Frame::between(mesh_pose, target_pose);
    let w = witness_rotation(Vector::ZERO);
    let mut search = ConvexSearch {
        tree,
        to,
        mw: to.then(&w),
        back: to.inverse().boxed(target_box),
        target_w: w.boxed(target_box),
        target_box: *target_box,
        w_dist: Real::INFINITY,
        target,
        best: Real::INFINITY,
        best2: Real::INFINITY,
        points: None,
    };
    if let Some(root) = tree.root() {
        search.visit((0, root));
    }
    ClosestPoints::placed(search.best, search.points, target_pose)
}

/// An upper bound on the distance between a placed mesh's surface and a solid box: project
/// the box's centre onto the mesh, that point onto the box, and back onto the mesh.
pub(crate) fn mesh_box_upper_bound(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> Real {
    let q = mesh.closest_point(pose, &b.center);
    let q = mesh.closest_point(pose, &b.closest_point(&q));
    (q - b.closest_point(&q)).norm()
}

/// Distance between a placed mesh's surface and a solid box ([`mesh_convex`], in the box's
/// frame), with the closest points (the mesh's first).
pub(crate) fn mesh_box(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> ClosestPoints {
    let target = BoxTarget {
        cuboid: Cuboid::new(to_parry_vec(&b.half_extents)),
    };
    let bx = Bx {
        c: Vector::ZERO,
        h: target.cuboid.half_extents,
    };
    mesh_convex(mesh, pose, &target, &bx, &b.pose())
}

/// Distance between a placed mesh's surface and a world triangle ([`mesh_convex`], in the
/// world frame), with the closest points (the mesh's first).
pub(crate) fn mesh_triangle(mesh: &Mesh, pose: &Isometry3, tri: &[Point3; 3]) -> ClosestPoints {
    let t = parry_triangle(tri);
    let bx = Bx::of_triangle(&t);
    mesh_convex(mesh, pose, &TriangleTarget { t, bx }, &bx, &Isometry3::identity())
}
