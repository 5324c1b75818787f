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

pub(crate) use box_box::{box_box, frame_gap};
pub(crate) use box_triangle::box_triangle;
pub(crate) use mesh_convex::{mesh_box, mesh_box_upper_bound, mesh_triangle};
pub(crate) use mesh_mesh::{mesh_mesh, mesh_mesh_upper_bound};
pub(crate) use tree::DistanceTree;

use crate::parry::math::{Pose, Vector};
use crate::parry::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use crate::parry::shape::{SupportMap, Triangle};
use crate::parry_adapter::point_to_parry;
use crate::{Point3, Real};

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
