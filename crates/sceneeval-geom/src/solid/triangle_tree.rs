//! The [`TriangleTree`]: a bounding-volume hierarchy over a mesh's triangles, with each
//! node's dipole, and the hierarchical winding number summed over it (Barill et al. 2018).
//! The triangle-triangle intersection search walks the same tree.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::{Mesh, Point3, Real, Vector3};

use super::LEAF_SIZE;

/// A cluster at least this many of its radii away is replaced by its dipole.
const DIPOLE_DISTANCE: Real = 2.0;

/// A node of a [`TriangleTree`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct TreeNode {
    /// Bounds of the node's triangles (mesh frame).
    pub lo: Point3,
    /// Highest corner of the bounds.
    pub hi: Point3,
    /// Area-weighted centroid of the triangles.
    centre: Point3,
    /// Sum of the triangles' area vectors (half the cross product of two edges).
    normal: Vector3,
    /// Total area.
    area: Real,
    /// Largest distance from `centre` to a corner of the node's triangles.
    radius: Real,
    /// Internal node: index of the right child (the left child is the next node). Leaf: first
    /// entry in [`TriangleTree::order`].
    index: u32,
    /// Triangles of a leaf; 0 for an internal node.
    count: u32,
    /// The node's triangle whose centroid lies nearest `centre`: its representative.
    pub rep: u32,
}

impl TreeNode {
    /// Whether the node is a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A bounding-volume hierarchy over a mesh's triangles (median splits, depth-first order),
/// with each node's dipole (area vector and centroid) for the winding number.
#[derive(Debug, Clone)]
pub(crate) struct TriangleTree {
    pub(crate) nodes: Vec<TreeNode>,
    pub(crate) order: Vec<u32>,
}

impl TriangleTree {
    pub(super) fn new(mesh: &Mesh) -> Self {
        let mut items: Vec<(Point3, u32)> = (0..mesh.triangles().len())
            .map(|k| {
                let [a, b, c] = mesh.triangle(k);
                (Point3::from((a.coords + b.coords + c.coords) / 3.0), k as u32)
            })
            .collect();
        let mut tree = TriangleTree {
            nodes: Vec::with_capacity(2 * items.len().div_ceil(LEAF_SIZE)),
            order: Vec::with_capacity(items.len()),
        };
        if !items.is_empty() {
            tree.build(mesh, &mut items);
        }
        tree
    }

    /// Appends the subtree over `items` (centroid, triangle) in depth-first order. Leaves are
    /// measured from their triangles; internal nodes aggregate their children (boxes, area
    /// vectors and areas add up; the radius is bounded through the children's), so the build
    /// costs `n log n` for the splits and `n` for the measures.
    fn build(&mut self, mesh: &Mesh, items: &mut [(Point3, u32)]) {
        let at = self.nodes.len();
        let mut node = TreeNode {
            lo: Point3::from(Vector3::repeat(Real::INFINITY)),
            hi: Point3::from(Vector3::repeat(Real::NEG_INFINITY)),
            centre: Point3::origin(),
            normal: Vector3::zeros(),
            area: 0.0,
            radius: 0.0,
            index: 0,
            count: 0,
            rep: 0,
        };
        if items.len() <= LEAF_SIZE {
            let mut weighted = Vector3::zeros();
            for &(g, k) in items.iter() {
                let [a, b, c] = mesh.triangle(k as usize);
                for p in [a, b, c] {
                    node.lo = node.lo.inf(&p);
                    node.hi = node.hi.sup(&p);
                }
                let n = (b - a).cross(&(c - a)) * 0.5;
                let area = n.norm();
                node.normal += n;
                node.area += area;
                weighted += g.coords * area;
            }
            node.centre = if node.area > 0.0 {
                Point3::from(weighted / node.area)
            } else {
                nalgebra::center(&node.lo, &node.hi)
            };
            let mut nearest = Real::INFINITY;
            for &(g, k) in items.iter() {
                for p in mesh.triangle(k as usize) {
                    node.radius = node.radius.max((p - node.centre).norm());
                }
                let d = (g - node.centre).norm_squared();
                if d < nearest || (d == nearest && k < node.rep) {
                    nearest = d;
                    node.rep = k;
                }
            }
            items.sort_unstable_by_key(|&(_, k)| k);
            node.index = self.order.len() as u32;
            node.count = items.len() as u32;
            self.order.extend(items.iter().map(|&(_, k)| k));
            self.nodes.push(node);
            return;
        }
        self.nodes.push(node);
        let (mut lo, mut hi) = (
            Vector3::repeat(Real::INFINITY),
            Vector3::repeat(Real::NEG_INFINITY),
        );
        for (c, _) in items.iter() {
            lo = lo.inf(&c.coords);
            hi = hi.sup(&c.coords);
        }
        let axis = (hi - lo).imax();
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |(c, i), (d, j)| c[axis].total_cmp(&d[axis]).then(i.cmp(j)));
        let (left, right) = items.split_at_mut(mid);
        self.build(mesh, left);
        let right_index = self.nodes.len();
        self.build(mesh, right);
        let (l, r) = (self.nodes[at + 1], self.nodes[right_index]);
        let area = l.area + r.area;
        let centre = if area > 0.0 {
            Point3::from((l.centre.coords * l.area + r.centre.coords * r.area) / area)
        } else {
            nalgebra::center(&l.lo.inf(&r.lo), &l.hi.sup(&r.hi))
        };
        let (dl, dr) = ((l.centre - centre).norm(), (r.centre - centre).norm());
        let node = &mut self.nodes[at];
        node.lo = l.lo.inf(&r.lo);
        node.hi = l.hi.sup(&r.hi);
        node.normal = l.normal + r.normal;
        node.area = area;
        node.centre = centre;
        node.radius = (dl + l.radius).max(dr + r.radius);
        node.rep = if dl <= dr { l.rep } else { r.rep };
        node.index = right_index as u32;
    }

    /// The children of internal node `n`.
    #[inline]
    pub(crate) fn children(&self, n: usize) -> [usize; 2] {
        [n + 1, self.nodes[n].index as usize]
    }

    /// The triangles of leaf `n`.
    #[inline]
    pub(crate) fn leaf(&self, n: usize) -> &[u32] {
        let node = &self.nodes[n];
        let s = node.index as usize;
        &self.order[s..s + node.count as usize]
    }

    /// Adds the exact winding numbers of leaf `n`'s triangles at `q` to `w`, one by one.
    fn add_leaf(&self, mesh: &Mesh, n: usize, q: &Point3, w: &mut Real) {
        for &k in self.leaf(n) {
            count_term();
            *w += solid_angle(&mesh.triangle(k as usize), q) / (4.0 * std::f64::consts::PI);
        }
    }

    /// See [`SolidTables::winding`](super::SolidTables::winding).
    pub(super) fn winding(&self, mesh: &Mesh, q: &Point3, margin: Real) -> (Real, Real) {
        if self.nodes.is_empty() {
            return (0.0, 0.0);
        }
        let mut w = 0.0;
        let mut err = 0.0;
        let mut approximated: BinaryHeap<Approx> = BinaryHeap::new();
        let mut stack: Vec<usize> = vec![0];
        let decided = |w: Real, err: Real| {
            let gap = (w.abs() - 0.5).abs();
            gap > err + margin
        };
        loop {
            while let Some(n) = stack.pop() {
                let node = &self.nodes[n];
                let d = (node.centre - q).norm();
                if d > DIPOLE_DISTANCE * node.radius && node.area > 0.0 {
                    let value =
                        node.normal.dot(&(node.centre - q)) / (4.0 * std::f64::consts::PI * d * d * d);
                    let gap = d - node.radius;
                    let e = node.area * 2.0 * node.radius / (4.0 * std::f64::consts::PI * gap * gap * gap);
                    w += value;
                    err += e;
                    count_term();
                    approximated.push(Approx {
                        err: e,
                        value,
                        node: n,
                    });
                } else if node.is_leaf() {
                    self.add_leaf(mesh, n, q, &mut w);
                } else {
                    let [l, r] = self.children(n);
                    stack.push(r);
                    stack.push(l);
                }
            }
            if decided(w, err) {
                return (w, err.max(0.0));
            }
            let Some(top) = approximated.pop() else {
                return (w, 0.0);
            };
            w -= top.value;
            err -= top.err;
            let node = &self.nodes[top.node];
            if node.is_leaf() {
                self.add_leaf(mesh, top.node, q, &mut w);
            } else {
                let [l, r] = self.children(top.node);
                // Children of a far node are farther relative to their size; the loop above
                // approximates them again or opens them.
                stack.push(r);
                stack.push(l);
            }
            if approximated.is_empty() && stack.is_empty() {
                err = 0.0;
            }
        }
    }
}

#[cfg(test)]
thread_local! {
    /// Terms (triangle solid angles and cluster dipoles) summed by winding numbers on this
    /// thread, for tests that count work.
    pub(crate) static WINDING_TERMS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Counts one term of a winding-number sum (tests only).
#[inline]
fn count_term() {
    #[cfg(test)]
    WINDING_TERMS.with(|c| c.set(c.get() + 1));
}

/// An approximated cluster, largest error first.
#[derive(Debug, Clone, Copy)]
struct Approx {
    err: Real,
    value: Real,
    node: usize,
}

impl PartialEq for Approx {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Approx {}
impl PartialOrd for Approx {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Approx {
    fn cmp(&self, other: &Self) -> Ordering {
        self.err.total_cmp(&other.err).then(other.node.cmp(&self.node))
    }
}

/// The signed solid angle of a triangle seen from `q` (Van Oosterom and Strackee 1983).
#[inline]
pub(crate) fn solid_angle(t: &[Point3; 3], q: &Point3) -> Real {
    let a = t[0] - q;
    let b = t[1] - q;
    let c = t[2] - q;
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    let num = a.dot(&b.cross(&c));
    let den = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
    2.0 * num.atan2(den)
}

#[cfg(test)]
mod tests {
    use super::super::test_support::open_cube;
    use super::*;

    #[test]
    fn hierarchical_winding_decides_like_the_exact_sum() {
        // An open, finely subdivided box (missing its bottom): points near the virtual lid
        // have winding numbers close to 1/2, where the dipole error matters.
        let open = open_cube(12);
        assert!(!open.is_closed());
        let t = open.solid();
        assert!(!t.is_simple_solid());
        for k in 0..400 {
            let f = f64::from(k);
            let p = Point3::new(
                0.45 * (f * 0.37).sin(),
                0.45 * (f * 0.73).cos(),
                -0.5 + 0.02 * (f * 1.31).sin(),
            );
            let exact = open.winding_number(&p);
            let (w, err) = t.winding(&open, &p, 0.0);
            assert!((w - exact).abs() <= err + 1e-9, "{p}: {w} +- {err} vs {exact}");
            assert_eq!(t.classify(&open, &p).inside, exact.abs() >= 0.5, "{p}: {exact}");
        }
    }

    #[test]
    fn inside_tests_of_open_meshes_cost_about_log_n() {
        // Open boxes of 10,240 and 162,816 triangles (16 times as many): a point 0.15 m or
        // more inside sums the triangles and cluster dipoles near it, whose number depends on
        // its distance to the surface, not on the triangle count (measured: about 2,000 and
        // 3,300 terms), where a flat sum takes one term per triangle.
        let mut per_point = Vec::new();
        for n in [32u32, 128] {
            let open = open_cube(n);
            let t = open.solid();
            assert!(!t.is_simple_solid());
            WINDING_TERMS.with(|c| c.set(0));
            let mut count = 0u64;
            for k in 0..64 {
                let f = f64::from(k);
                let p = Point3::new(
                    0.35 * (f * 0.37).sin(),
                    0.35 * (f * 0.73).cos(),
                    0.3 * (f * 1.31).sin(),
                );
                assert!(t.classify(&open, &p).inside, "{p}");
                count += 1;
            }
            let terms = WINDING_TERMS.with(std::cell::Cell::get) as f64 / count as f64;
            assert!(
                terms < 0.25 * open.triangles().len() as f64,
                "{terms} terms per point"
            );
            per_point.push(terms);
        }
        assert!(per_point[1] <= 2.0 * per_point[0], "{per_point:?}");
    }
}
