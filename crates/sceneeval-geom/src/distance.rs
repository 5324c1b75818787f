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

use crate::parry::math::{Mat3, Pose, Vector};
use crate::parry::query::details;
use crate::parry::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use crate::parry::shape::{Cuboid, SupportMap, Triangle};
use crate::parry_adapter::{point_to_parry, to_parry_vec};
use crate::{Isometry3, Mesh, Obb, Point3, Real};

/// The gap between box `b` and the bounding box of `a` in `b`'s frame: a lower bound on the
/// distance between the solids.
#[inline]
pub(crate) fn frame_gap(b: &Obb, a: &Obb) -> Real {
    let rt = b.rotation.inverse();
    let m = (rt * a.rotation).into_inner();
    let t = rt * (a.center - b.center);
    let mut g2 = 0.0;
    for i in 0..3 {
        let reach = m[(i, 0)].abs() * a.half_extents.x
            + m[(i, 1)].abs() * a.half_extents.y
            + m[(i, 2)].abs() * a.half_extents.z;
        let gap = t[i].abs() - reach - b.half_extents[i];
        if gap > 0.0 {
            g2 += gap * gap;
        }
    }
    g2.sqrt()
}

/// The box-box distance when cheap bounds pin it down, else `None`.
///
/// Lower bound: the larger of the two frame gaps ([`frame_gap`] both ways). Upper bound: the
/// smallest distance from a corner of either box to the other box (a distance between two
/// points of the solids). When they agree to `1e-12` relative, the distance is the upper
/// bound: the closest points are a corner and a point of the other box, as for an object whose
/// nearest corner faces a wall. Otherwise (edge against edge, or overlapping boxes with no
/// corner inside the other) the caller runs GJK.
#[inline]
fn bracketed(a: &Obb, b: &Obb) -> Option<Real> {
    let lower = frame_gap(b, a).max(frame_gap(a, b));
    let mut upper2 = Real::INFINITY;
    for (x, y) in [(a, b), (b, a)] {
        for c in x.corners() {
            upper2 = upper2.min(y.distance_to_point_squared(&c));
        }
    }
    let upper = upper2.sqrt();
    (upper - lower <= 1e-12 * (1.0 + upper)).then_some(upper)
}

/// Distance between two solid boxes (0 when they touch or overlap): [`bracketed`] when its
/// bounds agree, else GJK on the two cuboids' support maps.
///
/// parry's dedicated `distance_cuboid_cuboid` (which `parry::query::distance` dispatches to)
/// is not used: its separating-axis shortcut can overestimate the distance by millimetres when
/// an edge of one box is closest to an edge of the other.
#[inline]
pub(crate) fn box_box(a: &Obb, b: &Obb) -> Real {
    if let Some(d) = bracketed(a, b) {
        return d;
    }
    let (pa, ca) = a.to_parry();
    let (pb, cb) = b.to_parry();
    details::distance_support_map_support_map(&pa.inv_mul(&pb), &ca, &cb)
}

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
fn triangle_gap(t: &Triangle, u: &Triangle) -> Real {
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

/// An axis-aligned box as centre and half extents (all non-negative).
#[derive(Clone, Copy, Debug, Default)]
struct Bx {
    c: Vector,
    h: Vector,
}

impl Bx {
    /// The box from its lowest to its highest corner.
    #[inline]
    fn from_bounds(lo: Vector, hi: Vector) -> Bx {
        Bx {
            c: (lo + hi) * 0.5,
            h: (hi - lo) * 0.5,
        }
    }

    /// The bounding box of a triangle.
    #[inline]
    fn of_triangle(t: &Triangle) -> Bx {
        Bx::from_bounds(t.a.min(t.b).min(t.c), t.a.max(t.b).max(t.c))
    }

    /// A measure of the box's size, to decide which of two nodes to split.
    #[inline]
    fn size(&self) -> Real {
        self.h.x + self.h.y + self.h.z
    }

    /// Squared distance between the two boxes (0 when they meet): a lower bound on the
    /// squared distance between anything inside them.
    #[inline]
    fn gap2(&self, other: &Bx) -> Real {
        ((self.c - other.c).abs() - self.h - other.h)
            .max(Vector::ZERO)
            .length_squared()
    }
}

/// A rigid map between two frames as a rotation matrix (and its entrywise absolute value, to
/// move boxes) and a translation.
#[derive(Clone, Copy, Debug)]
struct Frame {
    rot: Mat3,
    abs: Mat3,
    tr: Vector,
}

impl Frame {
    /// The map from the frame placed by `from` to the frame placed by `to` (`to^-1 * from`).
    fn between(from: &Isometry3, to: &Isometry3) -> Frame {
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
    fn rotation(rot: Mat3) -> Frame {
        Frame {
            rot,
            abs: rot.abs(),
            tr: Vector::ZERO,
        }
    }

    /// This map followed by `next`.
    fn then(&self, next: &Frame) -> Frame {
        let rot = next.rot * self.rot;
        Frame {
            rot,
            abs: rot.abs(),
            tr: next.point(self.tr),
        }
    }

    /// The inverse map.
    fn inverse(&self) -> Frame {
        let rot = self.rot.transpose();
        Frame {
            rot,
            abs: self.abs.transpose(),
            tr: -(rot * self.tr),
        }
    }

    /// The image of a point.
    #[inline]
    fn point(&self, p: Vector) -> Vector {
        self.rot * p + self.tr
    }

    /// The image of a triangle.
    #[inline]
    fn triangle(&self, t: &Triangle) -> Triangle {
        Triangle::new(self.point(t.a), self.point(t.b), self.point(t.c))
    }

    /// A box containing the image of `b`.
    #[inline]
    fn boxed(&self, b: &Bx) -> Bx {
        Bx {
            c: self.point(b.c),
            h: self.abs * b.h,
        }
    }
}

/// Triangles per leaf of a [`DistanceTree`] at most. Measured: 4 to 16 search about as fast
/// (larger leaves trade node visits, the bulk of a search, for cheap per-triangle box tests);
/// 8 keeps the nodes small.
const LEAF_SIZE: usize = 8;

/// A node of a [`DistanceTree`] with its index.
type Indexed<'a> = (usize, &'a Node);

/// A node of a [`DistanceTree`].
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Bounds of the node's triangles.
    bx: Bx,
    /// Internal node: index of the right child (the left child is the next node). Leaf: index
    /// of the first triangle in [`DistanceTree::tris`].
    index: u32,
    /// Number of triangles of a leaf; 0 for an internal node.
    count: u32,
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
    nodes: Vec<Node>,
    tris: Vec<Triangle>,
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
    fn build(&mut self, tris: &[Triangle], items: &mut [(Vector, u32)]) -> (Vector, Vector) {
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
    fn root(&self) -> Option<&Node> {
        self.nodes.first()
    }

    /// The two children of an internal node.
    #[inline]
    fn children(&self, at: usize, n: &Node) -> Option<(Indexed<'_>, Indexed<'_>)> {
        let r = n.index as usize;
        Some(((at + 1, self.nodes.get(at + 1)?), (r, self.nodes.get(r)?)))
    }

    /// The triangles of a leaf.
    #[inline]
    fn leaf(&self, n: &Node) -> &[Triangle] {
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
fn witness_rotation(n: Vector) -> Frame {
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

/// The two children of a node in the order to visit them (nearer first), with their bounds.
#[inline]
fn ordered<T>(l: (Real, T), r: (Real, T)) -> [(Real, T); 2] {
    if l.0 <= r.0 { [l, r] } else { [r, l] }
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
/// leaf reached gives the first bound and the witness frame.
fn mesh_convex<T: ConvexTarget>(
    mesh: &Mesh,
    mesh_pose: &Isometry3,
    target: &T,
    target_box: &Bx,
    target_pose: &Isometry3,
) -> Real {
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
    };
    if let Some(root) = tree.root() {
        search.visit((0, root));
    }
    search.best
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

/// An upper bound on the distance between a placed mesh's surface and a solid box: project
/// the box's centre onto the mesh, that point onto the box, and back onto the mesh.
pub(crate) fn mesh_box_upper_bound(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> Real {
    let q = mesh.closest_point(pose, &b.center);
    let q = mesh.closest_point(pose, &b.closest_point(&q));
    (q - b.closest_point(&q)).norm()
}

/// Distance between the surfaces of two placed meshes: a simultaneous branch and bound over
/// both [`DistanceTree`]s ([`PairSearch`]), seeded by alternating closest-point projections
/// ([`mesh_mesh_upper_bound`]), which give the first bound and the first witness frame. Exact:
/// the smallest GJK distance over the triangle pairs (up to the 1e-9 relative slack of
/// [`search_limit`] when the seed itself is the answer).
pub(crate) fn mesh_mesh(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3) -> Real {
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
    };
    if let (Some(ra), Some(rb)) = (ta.root(), tb.root()) {
        let (x, y) = (search.place_a((0, ra)), search.place_b((0, rb)));
        if PairSearch::bound2(&x, &y) < search.best2 {
            search.visit(&x, &y);
        }
    }
    if search.found { search.best } else { seed.upper }
}

/// Distance between a placed mesh's surface and a solid box ([`mesh_convex`], in the box's
/// frame).
pub(crate) fn mesh_box(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> Real {
    let target = BoxTarget {
        cuboid: Cuboid::new(to_parry_vec(&b.half_extents)),
    };
    let bx = Bx {
        c: Vector::ZERO,
        h: target.cuboid.half_extents,
    };
    mesh_convex(mesh, pose, &target, &bx, &b.pose())
}

fn parry_triangle(tri: &[Point3; 3]) -> Triangle {
    Triangle::new(
        point_to_parry(&tri[0]),
        point_to_parry(&tri[1]),
        point_to_parry(&tri[2]),
    )
}

/// Distance between a placed mesh's surface and a world triangle ([`mesh_convex`], in the
/// world frame).
pub(crate) fn mesh_triangle(mesh: &Mesh, pose: &Isometry3, tri: &[Point3; 3]) -> Real {
    let t = parry_triangle(tri);
    let bx = Bx::of_triangle(&t);
    mesh_convex(mesh, pose, &TriangleTarget { t, bx }, &bx, &Isometry3::identity())
}

/// Distance between a solid box and a world triangle.
pub(crate) fn box_triangle(b: &Obb, tri: &[Point3; 3]) -> Real {
    let (pb, cb) = b.to_parry();
    // The triangle is in world coordinates: its pose relative to the cuboid is pb^-1.
    details::distance_support_map_support_map(&pb.inverse(), &cb, &parry_triangle(tri))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Rotation3, Vector3};
    use std::f64::consts::FRAC_PI_4;

    fn cube(c: [Real; 3], h: Real, yaw: Real) -> Obb {
        Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::repeat(h), yaw).unwrap()
    }

    #[test]
    fn box_distances_are_exact() {
        let a = cube([0.0, 0.0, 0.0], 0.5, 0.0);
        // Face to face, 1 m gap.
        assert!((box_box(&a, &cube([2.0, 0.0, 0.0], 0.5, 0.0)) - 1.0).abs() < 1e-12);
        // Diagonal offset: gap 0.5 in x and 0.5 in y -> sqrt(0.5).
        let d = box_box(&a, &cube([1.5, 1.5, 0.0], 0.5, 0.0));
        assert!((d - 0.5f64.sqrt()).abs() < 1e-12, "{d}");
        // Corner of a 45-degree box toward a face: 1.3 - 0.5 sqrt(2) - 0.5.
        let d = box_box(&a, &cube([1.3, 0.0, 0.0], 0.5, FRAC_PI_4));
        assert!((d - (0.8 - 0.5 * 2f64.sqrt())).abs() < 1e-12, "{d}");
        // Overlapping and nested boxes are 0 apart.
        assert_eq!(box_box(&a, &cube([0.7, 0.0, 0.0], 0.5, 0.3)), 0.0);
        assert_eq!(box_box(&a, &cube([0.1, 0.0, 0.0], 0.1, 0.3)), 0.0);
    }

    #[test]
    fn box_distance_agrees_with_brute_force() {
        // Dense sampling of the second box's surface gives an upper bound that converges to
        // the exact distance; a coarse grid bounds the error by the grid spacing.
        let a = Obb::new(
            Point3::new(0.1, -0.2, 0.3),
            Vector3::new(0.6, 0.3, 0.2),
            Rotation3::from_euler_angles(0.3, -0.2, 0.7),
        )
        .unwrap();
        for (i, yaw) in [0.0, 0.4, 1.1, 2.5].into_iter().enumerate() {
            let b = Obb::new(
                Point3::new(1.4, 0.5 + 0.1 * i as Real, 0.6),
                Vector3::new(0.3, 0.5, 0.4),
                Rotation3::from_euler_angles(0.1 * i as Real, 0.5, yaw),
            )
            .unwrap();
            let exact = box_box(&a, &b);
            let n = 40;
            let mut best = Real::INFINITY;
            for ix in 0..=n {
                for iy in 0..=n {
                    for iz in 0..=n {
                        let l = Vector3::new(
                            (2.0 * ix as Real / n as Real - 1.0) * b.half_extents.x,
                            (2.0 * iy as Real / n as Real - 1.0) * b.half_extents.y,
                            (2.0 * iz as Real / n as Real - 1.0) * b.half_extents.z,
                        );
                        best = best.min(a.distance_to_point(&b.to_world(&l)));
                    }
                }
            }
            // Never above the sampled minimum, and within the grid's reach of it.
            assert!(exact <= best + 1e-12, "{exact} > {best}");
            assert!(best - exact < 0.03, "{exact} vs {best}");
        }
    }

    #[test]
    fn bracketing_agrees_with_gjk() {
        // Over a sweep of yaws and offsets, the shortcut (when it applies) equals GJK.
        let a = cube([0.0, 0.0, 0.5], 0.5, 0.0);
        let (pa, ca) = a.to_parry();
        let mut shortcuts = 0;
        for i in 0..60 {
            let yaw = 0.1 * i as Real;
            for dx in [0.9, 1.3, 2.0] {
                let b = Obb::from_yaw(
                    Point3::new(dx, 0.3 * (i % 7) as Real - 0.9, 0.4 + 0.05 * (i % 3) as Real),
                    Vector3::new(0.3, 0.2, 0.35),
                    yaw,
                )
                .unwrap();
                let (pb, cb) = b.to_parry();
                let gjk = details::distance_support_map_support_map(&pa.inv_mul(&pb), &ca, &cb);
                if let Some(d) = bracketed(&a, &b) {
                    shortcuts += 1;
                    assert!((d - gjk).abs() < 1e-9, "yaw {yaw} dx {dx}: {d} vs {gjk}");
                }
                assert!((box_box(&a, &b) - gjk).abs() < 1e-9);
            }
        }
        assert!(
            shortcuts > 60,
            "the shortcut should apply in most of these: {shortcuts}"
        );
    }

    #[test]
    fn box_distance_is_mirror_symmetric() {
        // Found by a mirror-symmetry law in the relations crate: parry's cuboid-cuboid
        // shortcut gives 1.781161 for the mirrored pair but 1.780385 for the original; both are
        // 1.780385 (a 60^3 grid on the second box's surface gives 1.780394).
        let r = |m: [Real; 4]| {
            Rotation3::from_matrix_unchecked(crate::Matrix3::new(
                m[0], m[1], 0.0, m[2], m[3], 0.0, 0.0, 0.0, 1.0,
            ))
        };
        let b = Obb {
            center: Point3::new(0.0, -2.375793039456613, 0.0),
            half_extents: Vector3::new(0.05, 0.4070422242028465, 0.05),
            rotation: r([
                -0.9925879607510085,
                -0.12152835131011316,
                0.12152835131011316,
                -0.9925879607510085,
            ]),
        };
        let a = Obb {
            center: Point3::new(-1.833736971811297, -1.8769287386567672, 0.0),
            half_extents: Vector3::repeat(0.05),
            rotation: r([
                0.11382045802485088,
                -0.9935013353463664,
                0.9935013353463664,
                0.11382045802485088,
            ]),
        };
        let rb = b.rotation.matrix();
        let flip = crate::Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0));
        let m = rb * flip * rb.transpose();
        let mirrored = Obb {
            center: b.center + m * (a.center - b.center),
            half_extents: a.half_extents,
            rotation: Rotation3::from_matrix_unchecked(m * a.rotation.matrix() * flip),
        };
        let (d, dm) = (a.distance_to_obb(&b), mirrored.distance_to_obb(&b));
        assert!((d - 1.780_384_815).abs() < 1e-8, "{d}");
        assert!((d - dm).abs() < 1e-9, "{d} vs {dm}");
    }

    /// A small closed UV sphere (2 * 8 * 5 = 80 triangles) with the given radii.
    fn sphere(r: Vector3) -> Mesh {
        uv_sphere(r, 8, 6)
    }

    fn world_triangles(m: &Mesh, pose: &Isometry3) -> Vec<Triangle> {
        (0..m.triangles().len())
            .map(|i| {
                let [a, b, c] = m.triangle(i).map(|p| point_to_parry(&(pose * p)));
                Triangle::new(a, b, c)
            })
            .collect()
    }

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

    /// A UV sphere with the given radii: `2 * segs * (rings - 1)` triangles.
    fn uv_sphere(r: Vector3, segs: u32, rings: u32) -> Mesh {
        let mut v = vec![Point3::new(0.0, 0.0, r.z)];
        for i in 1..rings {
            let th = std::f64::consts::PI * Real::from(i) / Real::from(rings);
            for j in 0..segs {
                let ph = std::f64::consts::TAU * Real::from(j) / Real::from(segs);
                v.push(Point3::new(
                    r.x * th.sin() * ph.cos(),
                    r.y * th.sin() * ph.sin(),
                    r.z * th.cos(),
                ));
            }
        }
        let south = v.len() as u32;
        v.push(Point3::new(0.0, 0.0, -r.z));
        let ring = |i: u32, j: u32| 1 + (i - 1) * segs + j % segs;
        let mut t = Vec::new();
        for j in 0..segs {
            t.push([0, ring(1, j), ring(1, j + 1)]);
            t.push([south, ring(rings - 1, j + 1), ring(rings - 1, j)]);
        }
        for i in 1..rings - 1 {
            for j in 0..segs {
                t.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
                t.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
            }
        }
        Mesh::new(v, t).unwrap()
    }

    /// A box whose faces are split into `n` x `n` grids: `12 n^2` triangles, flat faces with
    /// many coplanar triangles (ties everywhere).
    fn grid_box(h: Vector3, n: u32) -> Mesh {
        let mut v = Vec::new();
        let mut t = Vec::new();
        for (k, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            let (a, b) = if sign > 0.0 {
                ((k + 1) % 3, (k + 2) % 3)
            } else {
                ((k + 2) % 3, (k + 1) % 3)
            };
            let base = v.len() as u32;
            for i in 0..=n {
                for j in 0..=n {
                    let mut p = Vector3::zeros();
                    p[k] = sign * h[k];
                    p[a] = h[a] * (2.0 * Real::from(i) / Real::from(n) - 1.0);
                    p[b] = h[b] * (2.0 * Real::from(j) / Real::from(n) - 1.0);
                    v.push(Point3::from(p));
                }
            }
            let at = |i: u32, j: u32| base + i * (n + 1) + j;
            for i in 0..n {
                for j in 0..n {
                    t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                    t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
        Mesh::new(v, t).unwrap()
    }

    /// An open, wavy, non-convex sheet of `2 n^2` triangles over [-0.5, 0.5]^2, plus a small
    /// detached box floating above it (two components).
    fn sheet_and_box(n: u32) -> Mesh {
        let mut v = Vec::new();
        let mut t = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let (x, y) = (
                    Real::from(i) / Real::from(n) - 0.5,
                    Real::from(j) / Real::from(n) - 0.5,
                );
                v.push(Point3::new(x, y, 0.08 * (9.0 * x).sin() * (7.0 * y).cos()));
            }
        }
        let at = |i: u32, j: u32| i * (n + 1) + j;
        for i in 0..n {
            for j in 0..n {
                t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let cube = Mesh::cuboid(&Vector3::new(0.1, 0.05, 0.08)).unwrap();
        let base = v.len() as u32;
        v.extend(cube.vertices().iter().map(|p| p + Vector3::new(0.2, -0.1, 0.3)));
        t.extend(cube.triangles().iter().map(|tr| tr.map(|i| i + base)));
        Mesh::new(v, t).unwrap()
    }

    fn brute_mesh_mesh(a: &[Triangle], b: &[Triangle]) -> Real {
        let id = Pose::IDENTITY;
        let mut best = Real::INFINITY;
        for x in a {
            for y in b {
                best = best.min(details::distance_support_map_support_map(&id, x, y));
            }
        }
        best
    }

    fn brute_mesh_box(a: &[Triangle], b: &Obb) -> Real {
        let (pb, cb) = b.to_parry();
        a.iter()
            .map(|x| details::distance_support_map_support_map(&pb.inverse(), &cb, x))
            .fold(Real::INFINITY, Real::min)
    }

    /// A deterministic sequence in [0, 1).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> Real {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as Real / (1u64 << 53) as Real
        }

        fn pose(&mut self, centre: [Real; 3], spread: Real, tilt: Real) -> Isometry3 {
            let mut c = || (self.next() - 0.5) * 2.0;
            let t = Vector3::new(
                centre[0] + spread * c(),
                centre[1] + spread * c(),
                centre[2] + spread * c(),
            );
            let r = Vector3::new(tilt * c(), tilt * c(), 3.2 * c());
            Isometry3::new(t, r)
        }
    }

    #[test]
    fn distance_tree_is_a_balanced_partition() {
        for m in [
            uv_sphere(Vector3::new(0.6, 0.4, 0.3), 24, 13),
            grid_box(Vector3::new(0.3, 0.2, 0.4), 7),
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

    #[test]
    fn mesh_distances_equal_brute_force_on_larger_meshes() {
        // Meshes with several leaves per side, flat faces with coplanar triangles (ties), a
        // non-convex open sheet with a detached part, and random poses from crossing to apart.
        let ball = uv_sphere(Vector3::new(0.5, 0.35, 0.25), 16, 9);
        let slab = grid_box(Vector3::new(0.3, 0.2, 0.25), 5);
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
        let slab = grid_box(Vector3::new(0.4, 0.3, 0.1), 8);
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
        let bar = grid_box(Vector3::new(1.0, 0.05, 0.05), 6);
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
        let slab = grid_box(Vector3::new(0.5, 0.5, 0.1), 20);
        let ball = uv_sphere(Vector3::repeat(0.3), 100, 51);
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

    #[test]
    fn box_triangle_distance() {
        let a = cube([0.0, 0.0, 1.0], 0.5, 0.3);
        let tri = [
            Point3::new(-5.0, -5.0, 2.8),
            Point3::new(5.0, -5.0, 2.8),
            Point3::new(0.0, 5.0, 2.8),
        ];
        assert!((a.distance_to_triangle(&tri) - 1.3).abs() < 1e-9);
        assert_eq!(cube([0.0, 0.0, 2.3], 0.5, 0.3).distance_to_triangle(&tri), 0.0);
    }
}
