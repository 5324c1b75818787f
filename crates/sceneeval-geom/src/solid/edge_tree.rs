//! The [`EdgeTree`]: a hierarchy over the boundary edges of an open mesh that bounds the
//! winding number's gradient over a ball, so that one winding number decides the side of a
//! whole ball that misses the surface.

use crate::planar::point_segment_distance;
use crate::{Point3, Real, Vector3};

use super::LEAF_SIZE;

/// Boundary-edge clusters at least this many box diagonals away are bounded as a whole.
const EDGE_FAR: Real = 2.0;

/// A boundary edge: its ends and its multiplicity.
pub(super) type Edge = (Point3, Point3, Real);

/// A hierarchy over the boundary edges, bounding the winding number's gradient: away from the
/// surface the gradient of the solid angle is the Biot-Savart field of the boundary curve, so
/// `|grad w(p)| <= (1 / 4 pi) sum_e len_e / dist(p, e)^2` (zero for a closed mesh).
#[derive(Debug, Clone)]
pub(super) struct EdgeTree {
    edges: Vec<Edge>,
    nodes: Vec<EdgeNode>,
}

#[derive(Debug, Clone, Copy)]
struct EdgeNode {
    lo: Point3,
    hi: Point3,
    /// Total length times multiplicity.
    length: Real,
    index: u32,
    count: u32,
}

impl EdgeTree {
    pub(super) fn new(mut edges: Vec<Edge>) -> Self {
        let mut tree = EdgeTree {
            edges: Vec::new(),
            nodes: Vec::new(),
        };
        if !edges.is_empty() {
            let mut out = Vec::with_capacity(edges.len());
            tree.build(&mut edges, &mut out);
            tree.edges = out;
        }
        tree
    }

    fn build(&mut self, items: &mut [Edge], out: &mut Vec<Edge>) {
        let at = self.nodes.len();
        let (mut lo, mut hi) = (
            Point3::from(Vector3::repeat(Real::INFINITY)),
            Point3::from(Vector3::repeat(Real::NEG_INFINITY)),
        );
        let mut length = 0.0;
        for (a, b, m) in items.iter() {
            lo = lo.inf(a).inf(b);
            hi = hi.sup(a).sup(b);
            length += (b - a).norm() * m;
        }
        let mut node = EdgeNode {
            lo,
            hi,
            length,
            index: 0,
            count: 0,
        };
        if items.len() <= LEAF_SIZE {
            node.index = out.len() as u32;
            node.count = items.len() as u32;
            out.extend_from_slice(items);
            self.nodes.push(node);
            return;
        }
        self.nodes.push(node);
        let axis = (hi - lo).imax();
        let mid = items.len() / 2;
        let key = |e: &Edge| e.0[axis] + e.1[axis];
        items.select_nth_unstable_by(mid, |x, y| key(x).total_cmp(&key(y)));
        let (left, right) = items.split_at_mut(mid);
        self.build(left, out);
        let right_index = self.nodes.len() as u32;
        self.build(right, out);
        self.nodes[at].index = right_index;
    }

    /// Whether there are no boundary edges (a closed, consistently wound surface).
    pub(super) fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// An upper bound on `|grad w|` over the ball `(c, rho)`, infinite when the ball reaches a
    /// boundary edge.
    pub(super) fn gradient_bound(&self, c: &Point3, rho: Real) -> Real {
        if self.nodes.is_empty() {
            return 0.0;
        }
        let mut total = 0.0;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            let gap = box_distance(&node.lo, &node.hi, c) - rho;
            let diag = (node.hi - node.lo).norm();
            if node.count > 0 || (gap > 0.0 && gap >= EDGE_FAR * diag) {
                if node.count > 0 {
                    let s = node.index as usize;
                    for (a, b, m) in &self.edges[s..s + node.count as usize] {
                        let g = point_segment_distance(c, a, b) - rho;
                        if g <= 0.0 {
                            return Real::INFINITY;
                        }
                        total += (b - a).norm() * m / (g * g);
                    }
                } else {
                    total += node.length / (gap * gap);
                }
            } else {
                stack.push(n + 1);
                stack.push(node.index as usize);
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

fn box_distance(lo: &Point3, hi: &Point3, p: &Point3) -> Real {
    let mut s = 0.0;
    for k in 0..3 {
        let d = (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0);
        s += d * d;
    }
    s.sqrt()
}
