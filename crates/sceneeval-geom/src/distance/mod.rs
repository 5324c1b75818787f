//! Exact distances between boxes, meshes and triangles: cheap exact bounds first, then GJK on
//! convex pieces, and branch and bound over the meshes' [`DistanceTree`]s. No allocation.
//!
//! The mesh searches are depth first and recursive (no stack to allocate or overflow: the
//! recursion is as deep as the trees, which median splits keep balanced). A node, or a pair of
//! nodes, is pruned when a lower bound on its distance is no less than the best distance
//! found so far; the bound is the largest of the gaps between bounding boxes measured in
//! several frames: each mesh's own frame (where its boxes are tight), the other shape's frame,
//! and a *witness frame* whose first axis joins the nearest points known so far. The witness
//! frame is what makes the search fast near its answer: two convex pieces facing each other
//! are separated along that axis by about the distance, and pieces that touch the same
//! supporting planes without being nearest (a flat face facing a flat or curved one ties
//! hundreds of triangle pairs along the axis) are told apart by their offsets across it. Each
//! remaining triangle pair or triangle-box pair is measured exactly, by GJK, or without it
//! when cheap bounds pin the distance down.
//!
//! One algorithm per file, as parry's `query::distance` does it:
//! - `box_box`: two solid boxes (exact bounds when they meet, else GJK);
//! - `box_triangle`: a solid box and a triangle;
//! - `tree`: the [`DistanceTree`] every mesh search walks, with the frames and boxes it uses;
//! - `mesh_convex`: a mesh against one convex shape (a box or a triangle);
//! - `mesh_mesh`: two meshes, by a simultaneous search of both trees.

mod box_box;
mod box_triangle;
mod mesh_convex;
mod mesh_mesh;
mod tree;

#[cfg(test)]
mod test_support;

pub(crate) use box_box::{box_box, box_box_closest, frame_gap};
pub(crate) use box_triangle::{box_triangle, box_triangle_closest};
pub(crate) use mesh_convex::{mesh_box, mesh_box_upper_bound, mesh_triangle};
pub(crate) use mesh_mesh::{mesh_mesh, mesh_mesh_upper_bound};
pub(crate) use tree::DistanceTree;

use crate::parry::math::{DEFAULT_EPSILON, Pose, Vector};
use crate::parry::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use crate::parry::shape::{SupportMap, Triangle};
use crate::parry_adapter::{point_from_parry, point_to_parry};
use crate::{Obb, Point3, Real};

/// The distance between two shapes with a pair of points realising it: the answer of the
/// `closest_points` queries ([`crate::Obb::closest_points_to_obb`],
/// [`crate::Mesh::closest_points`], ...), whose `distance` is bit for bit that of the
/// matching distance query.
///
/// ```
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
/// let a = Obb::from_yaw(Point3::new(0.0, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// let b = Obb::from_yaw(Point3::new(2.0, 0.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// let c = a.closest_points_to_obb(&b);
/// assert_eq!(c.distance, a.distance_to_obb(&b));
/// let (p, q) = c.points.unwrap();
/// assert!((p.x - 0.5).abs() < 1e-12 && (q.x - 1.5).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoints {
    /// The distance (metres); 0 when the shapes meet.
    pub distance: Real,
    /// A point of the first shape and a point of the second (world coordinates) `distance`
    /// apart; `None` when the shapes meet. Where several pairs are equally close, one of them.
    pub points: Option<(Point3, Point3)>,
}

impl ClosestPoints {
    /// Shapes that meet.
    pub const MEETING: ClosestPoints = ClosestPoints {
        distance: 0.0,
        points: None,
    };

    /// A search's answer: its distance and the points behind it given in the frame placed by
    /// `pose` (dropped when the distance is 0: a corner of a triangle inside a box is 0 away
    /// with a "pair" of one point).
    pub(crate) fn placed(distance: Real, points: Option<(Vector, Vector)>, pose: &crate::Isometry3) -> Self {
        let world = |v: Vector| pose * crate::parry_adapter::point_from_parry(v);
        ClosestPoints {
            distance,
            points: points
                .filter(|_| distance > 0.0)
                .map(|(p, q)| (world(p), world(q))),
        }
    }

    /// The same answer with the two shapes' roles exchanged.
    #[inline]
    pub fn swapped(self) -> ClosestPoints {
        ClosestPoints {
            distance: self.distance,
            points: self.points.map(|(p, q)| (q, p)),
        }
    }
}

/// GJK distance between two convex shapes with `g2` placed by `pos12` in `g1`'s frame, with
/// the closest points in `g1`'s frame: the computation of parry's
/// `distance_support_map_support_map` (so the same value), keeping its witnesses.
fn gjk_placed<G1: SupportMap, G2: SupportMap>(
    pos12: &Pose,
    g1: &G1,
    g2: &G2,
) -> (Real, Option<(Vector, Vector)>) {
    let dir = -pos12.translation;
    let normalized_dir = if dir.length_squared() > DEFAULT_EPSILON * DEFAULT_EPSILON {
        dir.normalize()
    } else {
        Vector::X
    };
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(pos12, g1, g2, normalized_dir));
    match gjk::closest_points(pos12, g1, g2, Real::MAX, true, &mut simplex) {
        GJKResult::ClosestPoints(p1, p2, _) => ((p1 - p2).length(), Some((p1, p2))),
        // parry's answer for GJK's other outcomes.
        _ => (0.0, None),
    }
}

/// GJK between the box `b` and the convex shape `other` placed by `pos` in the box's frame
/// ([`gjk_placed`]), with the closest points in world coordinates (the box's first).
fn gjk_from_box<G: SupportMap>(b: &Obb, pos: &Pose, other: &G) -> ClosestPoints {
    let (_, cuboid) = b.to_parry();
    let (distance, points) = gjk_placed(pos, &cuboid, other);
    let pose = b.pose();
    ClosestPoints {
        distance,
        points: points.map(|(p, q)| (pose * point_from_parry(p), pose * point_from_parry(q))),
    }
}

/// The cost limit for a branch-and-bound search given an upper bound on the answer: slightly
/// above it, so that the leaf achieving it is not excluded by the strict comparison (nor by
/// rounding in the bounds).
#[inline]
fn search_limit(upper: Real) -> Real {
    if upper.is_finite() {
        upper * (1.0 + 1e-9) + 1e-12
    } else {
        Real::MAX
    }
}

/// The searches turn their witness frame to a new closest pair when it is nearer than this
/// fraction of the pair the frame was taken from.
const TURN: Real = 0.999;

/// GJK distance between two convex shapes in one frame, with the closest points (none when
/// they meet): the same computation as parry's `distance_support_map_support_map` with
/// `pos12` the identity, so the same value.
fn gjk<G1: SupportMap, G2: SupportMap>(g1: &G1, g2: &G2) -> (Real, Option<(Vector, Vector)>) {
    let id = Pose::IDENTITY;
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(&id, g1, g2, Vector::X));
    match gjk::closest_points(&id, g1, g2, Real::MAX, true, &mut simplex) {
        GJKResult::ClosestPoints(p1, p2, _) => ((p1 - p2).length(), Some((p1, p2))),
        // parry's answer for GJK's other outcomes (it does not converge without meeting).
        _ => (0.0, None),
    }
}

/// The two children of a node in the order to visit them (nearer first), with their bounds.
#[inline]
fn ordered<T>(l: (Real, T), r: (Real, T)) -> [(Real, T); 2] {
    if l.0 <= r.0 { [l, r] } else { [r, l] }
}

/// A world triangle as parry's.
fn parry_triangle(tri: &[Point3; 3]) -> Triangle {
    Triangle::new(
        point_to_parry(&tri[0]),
        point_to_parry(&tri[1]),
        point_to_parry(&tri[2]),
    )
}

#[cfg(test)]
mod tests {
    use super::test_support::{Lcg, sheet_and_box, sphere};
    use crate::{ClosestPoints, Isometry3, Mesh, Obb, Point3, Real, Vector3};

    fn on_mesh<'a>(m: &'a Mesh, pose: &'a Isometry3) -> impl Fn(&Point3) -> Real + 'a {
        move |p| m.distance_to_point(pose, p)
    }

    /// The points lie `distance` apart, each on (or in) its own shape.
    fn check(c: &ClosestPoints, on_first: impl Fn(&Point3) -> Real, on_second: impl Fn(&Point3) -> Real) {
        match c.points {
            None => assert_eq!(c.distance, 0.0, "{c:?}"),
            Some((p, q)) => {
                assert!(((p - q).norm() - c.distance).abs() < 1e-9, "{c:?}");
                assert!(on_first(&p) < 1e-9, "{c:?}: first point off its shape");
                assert!(on_second(&q) < 1e-9, "{c:?}: second point off its shape");
            }
        }
    }

    #[test]
    fn closest_points_realise_every_distance() {
        let ball = sphere(Vector3::new(0.4, 0.3, 0.25));
        let sheet = sheet_and_box(6);
        let mut rng = Lcg(11);
        let tri = [
            Point3::new(0.3, 1.0, -0.2),
            Point3::new(1.1, 1.3, 0.4),
            Point3::new(0.5, 1.6, 0.9),
        ];
        let on_tri = |p: &Point3| {
            let t = crate::parry::shape::Triangle::new(
                crate::parry_adapter::point_to_parry(&tri[0]),
                crate::parry_adapter::point_to_parry(&tri[1]),
                crate::parry_adapter::point_to_parry(&tri[2]),
            );
            use crate::parry::query::PointQuery;
            t.distance_to_local_point(crate::parry_adapter::point_to_parry(p), true)
        };
        let mut apart = 0;
        for k in 0..48 {
            let pa = rng.pose([0.0, 0.0, 0.0], 0.1, 0.5);
            let x = 0.5 + 1.2 * rng.next();
            let pb = rng.pose([x, 0.2, 0.0], 0.3, 0.5);
            let a = Obb::from_local_aabb(ball.aabb(), &pa);
            let b = Obb::new(
                pb * Point3::new(0.1, 0.0, 0.0),
                Vector3::new(0.3, 0.2, 0.25),
                pb.rotation.to_rotation_matrix(),
            )
            .unwrap();
            let mesh = if k % 2 == 0 { &ball } else { &sheet };
            let in_a = |p: &Point3| a.distance_to_point(p);
            let in_b = |p: &Point3| b.distance_to_point(p);
            let c = a.closest_points_to_obb(&b);
            assert_eq!(c.distance.to_bits(), a.distance_to_obb(&b).to_bits());
            check(&c, in_a, in_b);
            apart += usize::from(c.points.is_some());
            let c = a.closest_points_to_triangle(&tri);
            assert_eq!(c.distance.to_bits(), a.distance_to_triangle(&tri).to_bits());
            check(&c, in_a, on_tri);
            let c = mesh.closest_points(&pa, &ball, &pb);
            assert_eq!(c.distance.to_bits(), mesh.distance(&pa, &ball, &pb).to_bits());
            check(&c, on_mesh(mesh, &pa), on_mesh(&ball, &pb));
            let c = mesh.closest_points_to_obb(&pa, &b);
            assert_eq!(c.distance.to_bits(), mesh.distance_to_obb(&pa, &b).to_bits());
            check(&c, on_mesh(mesh, &pa), in_b);
            let c = mesh.closest_points_to_triangle(&pb, &tri);
            assert_eq!(
                c.distance.to_bits(),
                mesh.distance_to_triangle(&pb, &tri).to_bits()
            );
            check(&c, on_mesh(mesh, &pb), on_tri);
        }
        assert!(apart > 24, "{apart} of 48 box pairs apart");
    }
}
