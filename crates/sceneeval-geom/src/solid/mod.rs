//! The solid a mesh bounds: inside tests in time logarithmic in the triangle count, interior
//! balls and connected components. Built once per mesh on first use
//! ([`Mesh::solid`](crate::Mesh::solid)) and shared by every object that places the mesh.
//!
//! **What "inside" means.** A closed mesh of one connected component bounds an ordinary solid;
//! a point is inside when it lies behind the angle-weighted pseudo-normal of its closest
//! surface feature (Baerentzen and Aanaes 2005): exact, and as cheap as a closest-point query.
//! Any other mesh (open, or several components that may touch or overlap) is inside where its
//! generalized winding number (Jacobson et al. 2013) is at least 1/2 in magnitude: 1 inside
//! and 0 outside each closed component, and for open meshes a smooth measure of how much of
//! the surface surrounds the point, so a box missing a face still holds its inside (the
//! missing face acts as a virtual lid) and a cavity closed on five sides counts as solid. The
//! winding number is summed over a bounding-volume hierarchy with the far clusters replaced
//! by dipoles (Barill et al. 2018) and an error bound per cluster; clusters are refined until
//! the bound can no longer change the answer, so the decision is the exact winding number's.
//!
//! One concept per file:
//! - `tables`: [`SolidTables`], the tables of one mesh, and the inside tests that combine
//!   them ([`PointClass`] for a point, a certain side for a ball);
//! - `topology`: welded half-edges, connected components, boundary edges and union-find;
//! - `patches`: maximal planar patches and the convex regions of closed components;
//! - `pseudo_normals`: the angle-weighted pseudo-normals of a closed, connected mesh;
//! - `triangle_tree`: the [`TriangleTree`] over the triangles, with the hierarchical winding
//!   number;
//! - `edge_tree`: the hierarchy over the boundary edges that bounds the winding number's
//!   gradient;
//! - `balls`: a few large balls inside the solid.

mod balls;
mod edge_tree;
mod patches;
mod pseudo_normals;
mod tables;
mod topology;
mod triangle_tree;

#[cfg(test)]
mod test_support;

pub(crate) use tables::{PointClass, SolidTables};
pub(crate) use triangle_tree::{TriangleTree, solid_angle};

/// Triangles per leaf of the [`TriangleTree`], and edges per leaf of the boundary edges' tree.
const LEAF_SIZE: usize = 8;
