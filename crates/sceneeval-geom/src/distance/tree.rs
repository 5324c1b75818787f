//! The bounding-box hierarchy the mesh distance searches walk, and the boxes and rigid frames
//! they place its nodes with.

use crate::parry::math::{Mat3, Vector};
use crate::parry::shape::Triangle;
use crate::parry_adapter::{point_to_parry, to_parry_vec};
use crate::{Isometry3, Point3, Real};

/// An axis-aligned box as centre and half extents (all non-negative).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Bx {
    pub(super) c: Vector,
    pub(super) h: Vector,
}

impl Bx {
    /// The box from its lowest to its highest corner.
    #[inline]
    pub(super) fn from_bounds(lo: Vector, hi: Vector) -> Bx {
        Bx {
            c: (lo + hi) * 0.5,
            h: (hi - lo) * 0.5,
        }
    }

    /// The bounding box of a triangle.
    #[inline]
    pub(super) fn of_triangle(t: &Triangle) -> Bx {
        Bx::from_bounds(t.a.min(t.b).min(t.c), t.a.max(t.b).max(t.c))
    }

    /// A measure of the box's size, to decide which of two nodes to split.
    #[inline]
    pub(super) fn size(&self) -> Real {
        self.h.x + self.h.y + self.h.z
    }

    /// Squared distance between the two boxes (0 when they meet): a lower bound on the
    /// squared distance between anything inside them.
    #[inline]
    pub(super) fn gap2(&self, other: &Bx) -> Real {
        ((self.c - other.c).abs() - self.h - other.h)
            .max(Vector::ZERO)
            .length_squared()
    }
}

/// A rigid map between two frames as a rotation matrix (and its entrywise absolute value, to
/// move boxes) and a translation.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub(super) rot: Mat3,
    pub(super) abs: Mat3,
    pub(super) tr: Vector,
}

impl Frame {
    /// The map from the frame placed by `from` to the frame placed by `to` (`to^-1 * from`).
    pub(super) fn between(from: &Isometry3, to: &Isometry3) -> Frame {
        let rel = to.inv_mul(from);
        let m = rel.rotation.to_rotation_matrix();
        let m = m.matrix();
        let col = |j: usize| Vector::new(m[(0, j)], m[(1, j)], m[(2, j)]);
        let rot = Mat3::from_cols(col(0), col(1), col(2));
        Frame {
            rot,
            abs: rot.abs(),
            tr: to_parry_vec(&rel.translation.vector),
        }
    }

    /// A pure rotation.
    pub(super) fn rotation(rot: Mat3) -> Frame {
        Frame {
            rot,
            abs: rot.abs(),
            tr: Vector::ZERO,
        }
    }

    /// This map followed by `next`.
    pub(super) fn then(&self, next: &Frame) -> Frame {
        let rot = next.rot * self.rot;
        Frame {
            rot,
            abs: rot.abs(),
            tr: next.point(self.tr),
        }
    }

    /// The inverse map.
    pub(super) fn inverse(&self) -> Frame {
        let rot = self.rot.transpose();
        Frame {
            rot,
            abs: self.abs.transpose(),
            tr: -(rot * self.tr),
        }
    }

    /// The image of a point.
    #[inline]
    pub(super) fn point(&self, p: Vector) -> Vector {
        self.rot * p + self.tr
    }

    /// The image of a triangle.
    #[inline]
    pub(super) fn triangle(&self, t: &Triangle) -> Triangle {
        Triangle::new(self.point(t.a), self.point(t.b), self.point(t.c))
    }

    /// A box containing the image of `b`.
    #[inline]
    pub(super) fn boxed(&self, b: &Bx) -> Bx {
        Bx {
            c: self.point(b.c),
            h: self.abs * b.h,
        }
    }
}

/// Triangles per leaf of a [`DistanceTree`] at most. Measured: 4 to 16 search about as fast
/// (larger leaves trade node visits, the bulk of a search, for cheap per-triangle box tests);
/// 8 keeps the nodes small.
pub(super) const LEAF_SIZE: usize = 8;

/// A node of a [`DistanceTree`] with its index.
pub(super) type Indexed<'a> = (usize, &'a Node);

/// A node of a [`DistanceTree`].
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    /// Bounds of the node's triangles.
    pub(super) bx: Bx,
    /// Internal node: index of the right child (the left child is the next node). Leaf: index
    /// of the first triangle in [`DistanceTree::tris`].
    pub(super) index: u32,
    /// Number of triangles of a leaf; 0 for an internal node.
    pub(super) count: u32,
}

/// Puts the `mid` items with the lowest `(key(centroid), index)` first.
fn split_at_median(items: &mut [(Vector, u32)], mid: usize, key: impl Fn(&Vector) -> Real) {
    items.select_nth_unstable_by(mid, |(c, i), (d, j)| key(c).total_cmp(&key(d)).then(i.cmp(j)));
}

/// A bounding-box hierarchy over a mesh's triangles for the exact distance searches, in the
/// mesh frame, built once with the mesh: nodes in depth-first order (a node's left child
/// follows it) with their boxes as centre and half extents, and the triangles' corners copied
/// in leaf order (at most [`LEAF_SIZE`] per leaf), so that a search reads both sequentially.
/// Median splits along the longest extent of the triangles' centroids keep it balanced: its
/// depth is at most `ceil(log2(n / LEAF_SIZE)) + 1` for `n` triangles, and the recursive
/// searches go no deeper than that on each mesh.
///
/// About 90 bytes per triangle (72 for the copied corners, the rest for the nodes); parry's
/// own BVH of the same mesh takes about 140.
#[derive(Clone, Debug)]
pub(crate) struct DistanceTree {
    pub(super) nodes: Vec<Node>,
    pub(super) tris: Vec<Triangle>,
}

impl DistanceTree {
    /// The hierarchy over `triangles` (indices into `vertices`; triangles with an index out of
    /// range are skipped). Deterministic: a leaf keeps its triangles in their mesh order, and
    /// the splits order centroids by coordinate, then by triangle index.
    pub(crate) fn new(vertices: &[Point3], triangles: &[[u32; 3]]) -> Self {
        let corner = |i: u32| vertices.get(i as usize).map(point_to_parry);
        let tris: Vec<Triangle> = triangles
            .iter()
            .filter_map(|t| Some(Triangle::new(corner(t[0])?, corner(t[1])?, corner(t[2])?)))
            .collect();
        let mut items: Vec<(Vector, u32)> = tris
            .iter()
            .zip(0u32..)
            .map(|(t, i)| ((t.a + t.b + t.c) / 3.0, i))
            .collect();
        let mut tree = DistanceTree {
            nodes: Vec::with_capacity(2 * tris.len().div_ceil(LEAF_SIZE)),
            tris: Vec::with_capacity(tris.len()),
        };
        if !items.is_empty() {
            tree.build(&tris, &mut items);
        }
        tree
    }

    /// Appends the subtree over `items` (centroid, triangle index) in depth-first order and
    /// returns its bounds (lowest and highest corner).
    pub(super) fn build(&mut self, tris: &[Triangle], items: &mut [(Vector, u32)]) -> (Vector, Vector) {
        let at = self.nodes.len();
        if items.len() <= LEAF_SIZE {
            items.sort_unstable_by_key(|&(_, i)| i);
            let first = self.tris.len();
            self.tris
                .extend(items.iter().filter_map(|&(_, i)| tris.get(i as usize)));
            let (mut lo, mut hi) = (Vector::splat(Real::INFINITY), Vector::splat(-Real::INFINITY));
            for t in self.tris.get(first..).unwrap_or(&[]) {
                lo = lo.min(t.a).min(t.b).min(t.c);
                hi = hi.max(t.a).max(t.b).max(t.c);
            }
            self.nodes.push(Node {
                bx: Bx::from_bounds(lo, hi),
                index: first as u32,
                count: (self.tris.len() - first) as u32,
            });
            return (lo, hi);
        }
        self.nodes.push(Node {
            bx: Bx::default(),
            index: 0,
            count: 0,
        });
        // Split at the median along the longest extent of the centroids.
        let (mut lo, mut hi) = (Vector::splat(Real::INFINITY), Vector::splat(-Real::INFINITY));
        for (c, _) in items.iter() {
            lo = lo.min(*c);
            hi = hi.max(*c);
        }
        let ext = hi - lo;
        let mid = items.len() / 2;
        if ext.x >= ext.y && ext.x >= ext.z {
            split_at_median(items, mid, |v| v.x);
        } else if ext.y >= ext.z {
            split_at_median(items, mid, |v| v.y);
        } else {
            split_at_median(items, mid, |v| v.z);
        }
        let (left, right) = items.split_at_mut(mid);
        let (llo, lhi) = self.build(tris, left);
        let right_index = self.nodes.len() as u32;
        let (rlo, rhi) = self.build(tris, right);
        let (lo, hi) = (llo.min(rlo), lhi.max(rhi));
        if let Some(node) = self.nodes.get_mut(at) {
            node.bx = Bx::from_bounds(lo, hi);
            node.index = right_index;
        }
        (lo, hi)
    }

    /// The root node (none for an empty tree).
    #[inline]
    pub(super) fn root(&self) -> Option<&Node> {
        self.nodes.first()
    }

    /// The two children of an internal node.
    #[inline]
    pub(super) fn children(&self, at: usize, n: &Node) -> Option<(Indexed<'_>, Indexed<'_>)> {
        let r = n.index as usize;
        Some(((at + 1, self.nodes.get(at + 1)?), (r, self.nodes.get(r)?)))
    }

    /// The triangles of a leaf.
    #[inline]
    pub(super) fn leaf(&self, n: &Node) -> &[Triangle] {
        let start = n.index as usize;
        self.tris.get(start..start + n.count as usize).unwrap_or(&[])
    }
}

/// The rotation onto a frame whose first axis is the unit vector `n` (rows `n`, `m1`, `m2`,
/// orthonormal), or the identity when `n` is zero.
///
/// The searches take `n` along the segment between their seed's two points. The gap between
/// two sets' bounds in this frame is a lower bound on their distance like any other, but it is
/// the one that stays tight near the closest points: two convex pieces facing each other are
/// separated along `n` by about the distance, and pieces that are not the closest ones but
/// touch the same supporting planes (ties along `n`, as when a flat face faces a curved one)
/// are told apart by their offsets along `m1` and `m2`.
pub(super) fn witness_rotation(n: Vector) -> Frame {
    let n = n.normalize_or_zero();
    if n == Vector::ZERO {
        return Frame::rotation(Mat3::IDENTITY);
    }
    // The world axis least aligned with n, crossed with it, completes the frame.
    let a = n.abs();
    let e = if a.x <= a.y && a.x <= a.z {
        Vector::X
    } else if a.y <= a.z {
        Vector::Y
    } else {
        Vector::Z
    };
    let m1 = n.cross(e).normalize_or_zero();
    let m2 = n.cross(m1);
    Frame::rotation(Mat3::from_cols(n, m1, m2).transpose())
}

#[cfg(test)]
mod tests {
    use super::super::test_support::sheet_and_box;
    use super::*;
    use crate::{Mesh, Vector3};

    #[test]
    pub(super) fn distance_tree_is_a_balanced_partition() {
        for m in [
            Mesh::uv_ellipsoid(&Vector3::new(0.6, 0.4, 0.3), 24, 13).unwrap(),
            Mesh::subdivided_box(&Vector3::new(0.3, 0.2, 0.4), 7).unwrap(),
            sheet_and_box(12),
            Mesh::cuboid(&Vector3::repeat(0.5)).unwrap(),
        ] {
            let tree = m.distance_tree();
            let n = m.triangles().len();
            assert_eq!(tree.tris.len(), n);
            // Every triangle of the mesh is in exactly one leaf.
            let key = |t: &Triangle| [t.a, t.b, t.c].map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]);
            let mut ours: Vec<_> = tree.tris.iter().map(key).collect();
            let mut theirs: Vec<_> = (0..n)
                .map(|i| {
                    key(&Triangle::new(
                        point_to_parry(&m.triangle(i)[0]),
                        point_to_parry(&m.triangle(i)[1]),
                        point_to_parry(&m.triangle(i)[2]),
                    ))
                })
                .collect();
            ours.sort_unstable();
            theirs.sort_unstable();
            assert_eq!(ours, theirs);
            // Boxes contain their contents; leaves hold at most LEAF_SIZE triangles; the depth
            // is that of a balanced tree.
            fn check(tree: &DistanceTree, at: usize, depth: usize, max_depth: &mut usize) -> usize {
                let n = tree.nodes[at];
                *max_depth = (*max_depth).max(depth);
                let inside = |b: &Bx| {
                    let lo = n.bx.c - n.bx.h;
                    let hi = n.bx.c + n.bx.h;
                    let (blo, bhi) = (b.c - b.h, b.c + b.h);
                    let eps = 1e-12;
                    (blo - lo).min_element() >= -eps && (hi - bhi).min_element() >= -eps
                };
                if n.count > 0 {
                    assert!(n.count as usize <= LEAF_SIZE);
                    assert!(tree.leaf(&n).iter().all(|t| inside(&Bx::of_triangle(t))));
                    return n.count as usize;
                }
                let ((l, ln), (r, rn)) = tree.children(at, &n).unwrap();
                assert!(inside(&ln.bx) && inside(&rn.bx));
                let (cl, cr) = (
                    check(tree, l, depth + 1, max_depth),
                    check(tree, r, depth + 1, max_depth),
                );
                assert!(cl.abs_diff(cr) <= 1, "median split: {cl} vs {cr}");
                cl + cr
            }
            let mut depth = 0;
            assert_eq!(check(tree, 0, 0, &mut depth), n);
            let leaves = n.div_ceil(LEAF_SIZE);
            assert!(
                depth <= (leaves as Real).log2().ceil() as usize + 1,
                "depth {depth} for {n}"
            );
        }
    }
}
