//! Whether two placed meshes interpenetrate by more than a tolerance ([`Mesh::penetration`]).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::solid::{PointClass, SolidTables};
use crate::{Aabb, Isometry3, Mesh, Point3, Real, Vector3};

/// A vertex this close to the other surface (metres) does not decide a nesting test.
const NEST_EPS: Real = 1e-6;
/// Components of a mesh probed for nesting, largest first.
const MAX_NEST_COMPONENTS: usize = 64;
/// Point queries of the witness pass that precedes the best-first search.
const WITNESS_QUERIES: u64 = 256;
/// Point queries of the witness pass's first look, before the balls are tried.
const FIRST_LOOK: u64 = 16;
/// Point queries per direction spent looking for a larger bound once a pair is known to
/// collide ([`DepthSearch::Colliding`]).
const REFINE_QUERIES: u64 = 64;

/// How [`Mesh::penetration`] searches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PenetrationQuery {
    /// Depth in metres above which the pair collides. A resting contact within it does not.
    pub tolerance: Real,
    /// Finest spacing in metres of the surface points examined: the largest sampled depth of
    /// a surface point falls short of the true one by at most this.
    pub spacing: Real,
    /// Most point queries (closest point plus inside test) per direction; a search that runs
    /// out is reported as undecided.
    pub budget: usize,
    /// Which pairs get their largest depth bound searched for.
    pub depth: DepthSearch,
}

/// How far [`Mesh::penetration`] searches once the verdict is known.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum DepthSearch {
    /// Stop at the first bound above the tolerance (the verdict alone; fastest): the depth
    /// reported is that of the first surface point found deeper than the tolerance (or of the
    /// first ball found inside both).
    #[default]
    Verdict,
    /// Once a pair is known to collide, spend a few more queries (64 per direction) on larger
    /// bounds, deepest candidates first: exact for box-like overlaps, a lower bound otherwise.
    /// A resting contact's depth stays unsearched below the tolerance.
    Colliding,
    /// Search every pair for its largest bound, resting contacts included (slowest: a flat
    /// contact is sampled down to the spacing).
    All,
}

impl Default for PenetrationQuery {
    fn default() -> Self {
        PenetrationQuery {
            tolerance: 0.005,
            spacing: 0.0025,
            budget: 8192,
            depth: DepthSearch::Verdict,
        }
    }
}

/// How two placed meshes meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Overlap {
    /// Their surfaces do not meet and neither lies inside the other.
    Apart,
    /// Their surfaces touch or cross (or coincide).
    Surface,
    /// Their surfaces do not meet, but a connected part of one lies inside the other.
    Nested {
        /// Whether the first mesh (the receiver of [`Mesh::penetration`]) is the one inside.
        first_inside: bool,
    },
}

/// The outcome of [`Mesh::penetration`].
///
/// The penetration depth of two solids is the length of the shortest translation that
/// separates them. It is not computed exactly (that is hard for non-convex meshes); instead the
/// search finds *certified lower bounds* on it, each of which is a proof:
///
/// - a point `p` of one surface inside the other solid at distance `d` from its surface: no
///   translation shorter than `d` moves `p` out, so the interiors still overlap;
/// - a ball of radius `r` inside both solids: a translation shorter than `2 r` leaves the moved
///   ball overlapping the unmoved one.
///
/// A pair collides when a bound exceeds the tolerance, so a pair whose true penetration is
/// within the tolerance is never reported colliding. The search is a best-first
/// branch and bound over the first mesh's triangle hierarchy, then over sub-triangles down to
/// the sample spacing, ordered by an upper bound on the depth any point of the item can reach
/// (from the second mesh's box, whose face planes bound the depth of every point inside it,
/// and from the distances already measured, the depth being 1-Lipschitz); an item whose whole
/// bounding ball lies on one side of the other surface is settled by one query. The verdict
/// stops at the first bound above the tolerance; a resting contact whose surfaces stay within
/// the tolerance of the other's box is settled without a single point query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Penetration {
    /// How the meshes meet.
    pub overlap: Overlap,
    /// A certified lower bound on the penetration depth in metres (see above): the largest
    /// found by the search [`PenetrationQuery::depth`] asks for (with
    /// [`DepthSearch::Verdict`], the first found above the tolerance).
    pub depth: Real,
    /// The sample spacing used (metres).
    pub spacing: Real,
    /// Whether the pair collides: nested, or a bound above the tolerance.
    pub colliding: bool,
    /// The search ran out of its budget before it could rule a collision out.
    pub undecided: bool,
    /// Point queries made (closest point plus inside test): the work of the narrow phase.
    pub queries: u64,
}

/// See [`Mesh::penetration`].
pub(crate) fn penetration(
    a: &Mesh,
    pa: &Isometry3,
    b: &Mesh,
    pb: &Isometry3,
    q: &PenetrationQuery,
) -> Penetration {
    let all = q.depth == DepthSearch::All;
    let mut s = Search {
        q: *q,
        deepest: all,
        best: 0.0,
        queries: 0,
        undecided: false,
    };
    let mut out = Penetration {
        overlap: Overlap::Apart,
        depth: 0.0,
        spacing: q.spacing,
        colliding: false,
        undecided: false,
        queries: 0,
    };
    if std::ptr::eq(a, b) && same_pose(pa, pb) {
        // One mesh placed twice at the same pose: the largest interior ball is shared.
        out.overlap = Overlap::Surface;
        out.colliding = true;
        out.depth = 2.0 * a.solid().balls(a).first().map_or(0.0, |ball| ball.radius);
        return out;
    }
    if surfaces_meet(a, pa, b, pb) {
        out.overlap = Overlap::Surface;
        // A deep penetration shows within a few queries of the witness passes; copies placed
        // on top of each other (coincident surfaces) only through their balls.
        let (mut spent_a, mut spent_b) = (0, 0);
        for limit in [FIRST_LOOK, WITNESS_QUERIES] {
            if !all && !s.found() {
                spent_a = s.witness(a, pa, b, pb, limit, spent_a);
            }
            if !all && !s.found() {
                spent_b = s.witness(b, pb, a, pa, limit, spent_b);
            }
            if limit == FIRST_LOOK && (all || !s.found()) {
                s.balls(a, pa, b, pb);
                s.balls(b, pb, a, pa);
            }
        }
        if all || !s.found() {
            s.surface(a, pa, b, pb, spent_a);
        }
        if all || !s.found() {
            s.surface(b, pb, a, pa, spent_b);
        }
        out.colliding = s.found();
        out.undecided = !out.colliding && s.undecided;
        if out.colliding && q.depth == DepthSearch::Colliding {
            // The verdict is in: look for a larger bound, with a short budget.
            s.deepest = true;
            s.balls(a, pa, b, pb);
            s.balls(b, pb, a, pa);
            let undecided = s.undecided;
            let spent = (q.budget as u64).saturating_sub(REFINE_QUERIES);
            s.surface(a, pa, b, pb, spent);
            s.surface(b, pb, a, pa, spent);
            s.undecided = undecided;
        }
    } else {
        for (first_inside, inner, pi, outer, po) in [(true, a, pa, b, pb), (false, b, pb, a, pa)] {
            if s.nested(inner, pi, outer, po) {
                out.overlap = Overlap::Nested { first_inside };
                out.colliding = true;
                if q.depth != DepthSearch::Verdict {
                    s.deepest = true;
                    s.balls(a, pa, b, pb);
                    s.balls(b, pb, a, pa);
                    s.surface(inner, pi, outer, po, 0);
                }
                break;
            }
        }
    }
    out.depth = s.best;
    out.queries = s.queries;
    out
}

/// Whether the two placed surfaces touch or cross.
fn surfaces_meet(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3) -> bool {
    crate::tritri::surfaces_meet(a, a.solid(), b, b.solid(), &(pa.inverse() * pb))
}

fn same_pose(a: &Isometry3, b: &Isometry3) -> bool {
    (a.translation.vector - b.translation.vector).norm() <= 1e-12 && a.rotation.angle_to(&b.rotation) <= 1e-12
}

struct Search {
    q: PenetrationQuery,
    /// Searching for the largest bound (else for the first above the tolerance).
    deepest: bool,
    /// Largest certified bound found.
    best: Real,
    queries: u64,
    undecided: bool,
}

/// A mesh placed in another mesh's frame: `t` maps the first frame into the second, whose
/// box is `bx`.
struct Placed<'a> {
    x: &'a Mesh,
    tx: &'a SolidTables,
    y: &'a Mesh,
    ty: &'a SolidTables,
    t: Isometry3,
    rot_abs: nalgebra::Matrix3<Real>,
    bx: Aabb,
}

impl<'a> Placed<'a> {
    fn new(x: &'a Mesh, px: &Isometry3, y: &'a Mesh, py: &Isometry3) -> Self {
        let t = py.inverse() * px;
        Placed {
            x,
            tx: x.solid(),
            y,
            ty: y.solid(),
            rot_abs: t.rotation.to_rotation_matrix().matrix().abs(),
            t,
            bx: *y.aabb(),
        }
    }

    /// Signed distance of `p` (second frame) inside the second mesh's box: the smallest
    /// distance to one of its face planes, negative outside. An upper bound on the depth of
    /// any point inside the second solid, and 1-Lipschitz.
    #[inline]
    fn box_depth(&self, p: &Point3) -> Real {
        let (lo, hi) = (&self.bx.min, &self.bx.max);
        (0..3)
            .map(|k| (p[k] - lo[k]).min(hi[k] - p[k]))
            .fold(Real::INFINITY, Real::min)
    }

    /// The largest box depth any point of the box `lo..hi` (second frame) can have: each face
    /// plane's distance is affine, so its largest value over a box is at a corner.
    #[inline]
    fn box_bound(bx: &Aabb, lo: &Point3, hi: &Point3) -> Real {
        let (blo, bhi) = (&bx.min, &bx.max);
        (0..3)
            .map(|k| (hi[k] - blo[k]).min(bhi[k] - lo[k]))
            .fold(Real::INFINITY, Real::min)
            .max(0.0)
    }

    /// An upper bound on the depth in the second solid of every point in the convex hull of
    /// `corners` (second frame): the largest depth allowed by the second mesh's box or, for a
    /// closed mesh, by the boxes (or face planes, for convex ones) of the components the hull
    /// can reach. Each bound is a minimum of affine functions, whose largest value over a hull
    /// is found at its corners.
    fn region_bound(&self, corners: &[Point3]) -> Real {
        let Some(first) = corners.first() else {
            return 0.0;
        };
        let (lo, hi) = corners
            .iter()
            .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        let global = Self::box_bound(&self.bx, &lo, &hi);
        let Some(regions) = &self.ty.regions else {
            return global;
        };
        if global <= 0.0 {
            return 0.0;
        }
        let mut bound: Real = 0.0;
        for r in regions {
            let b = &r.aabb;
            if (0..3).any(|k| lo[k] > b.max[k] || hi[k] < b.min[k]) {
                continue;
            }
            let here = if r.planes.is_empty() {
                Self::box_bound(b, &lo, &hi)
            } else {
                r.planes
                    .iter()
                    .map(|(n, off)| {
                        corners
                            .iter()
                            .map(|c| off - n.dot(&c.coords))
                            .fold(Real::NEG_INFINITY, Real::max)
                    })
                    .fold(Real::INFINITY, Real::min)
                    .max(0.0)
            };
            bound = bound.max(here);
            if bound >= global {
                return global;
            }
        }
        bound
    }

    /// The bounds of tree node `n` of the first mesh, in the second frame: centre and half
    /// extents.
    fn node_box(&self, n: usize) -> (Point3, Vector3) {
        let node = &self.tx.tree.nodes[n];
        let c = self.t * nalgebra::center(&node.lo, &node.hi);
        let h = self.rot_abs * ((node.hi - node.lo) * 0.5);
        (c, h)
    }

    /// The corners of tree node `n`'s box, in the second frame.
    fn node_corners(&self, n: usize) -> [Point3; 8] {
        let node = &self.tx.tree.nodes[n];
        let (lo, hi) = (node.lo, node.hi);
        std::array::from_fn(|k| {
            self.t
                * Point3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                )
        })
    }

    fn triangle(&self, k: u32) -> [Point3; 3] {
        self.x.triangle(k as usize).map(|p| self.t * p)
    }
}

/// A piece of the first surface waiting to be examined.
#[derive(Debug, Clone, Copy)]
enum Item {
    Node(u32),
    Tri([Point3; 3]),
    Point(Point3),
}

/// A queued item: items of tier 0 (not yet seen outside the other solid) before those of
/// tier 1 (whose parent's probe lay outside it), each by decreasing bound, then in order of
/// creation. Tiers find a collision's witness early; every item is still examined (or ruled
/// out by its bound) before a pair is declared resting.
#[derive(Debug, Clone, Copy)]
struct Entry {
    tier: u8,
    bound: Real,
    seq: u64,
    item: Item,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .tier
            .cmp(&self.tier)
            .then(self.bound.total_cmp(&other.bound))
            .then(other.seq.cmp(&self.seq))
    }
}

fn centroid(t: &[Point3; 3]) -> Point3 {
    Point3::from((t[0].coords + t[1].coords + t[2].coords) / 3.0)
}

fn tri_radius(t: &[Point3; 3], g: &Point3) -> Real {
    t.iter().map(|p| (p - g).norm()).fold(0.0, Real::max)
}

impl Search {
    fn found(&self) -> bool {
        self.best > self.q.tolerance
    }

    /// Whether the search can stop: a collision is proven and the deepest bound is not wanted.
    fn done(&self) -> bool {
        !self.deepest && self.found()
    }

    /// Items whose bound does not exceed this cannot change the outcome.
    fn threshold(&self) -> Real {
        if self.deepest { self.best } else { self.q.tolerance }
    }

    /// How far a sample's query resolves its distance, given its box depth `bd` (its depth is
    /// `min(distance, bd)`, so farther distances never matter): up to `bd` when searching for
    /// the deepest bound, else up to a few tolerances as well (a deeper point is a witness
    /// either way). The bounded search stays cheap deep inside round objects.
    fn reach(&self, bd: Real) -> Real {
        let bd = bd.max(NEST_EPS);
        if self.deepest {
            bd
        } else {
            bd.min(4.0 * self.q.tolerance)
        }
    }

    /// Records the depth of a surface sample `pt` of the first mesh found inside the second:
    /// `min(distance, box depth)`; a witness whose distance was only bounded by a short reach
    /// is measured once more, up to its box depth, so that the bound reported is its depth.
    fn sample(&mut self, p: &Placed<'_>, pt: &Point3, class: &PointClass) {
        if !class.inside {
            return;
        }
        let bd = p.box_depth(pt);
        let mut depth = class.distance.min(bd);
        if !class.exact && depth < bd && depth > self.q.tolerance {
            self.queries += 1;
            depth = p.ty.classify_within(p.y, pt, bd).distance.min(bd);
        }
        self.raise(depth);
    }

    fn raise(&mut self, depth: Real) {
        if depth > self.best {
            self.best = depth;
        }
    }

    /// Interior balls of `x` inside `y`.
    fn balls(&mut self, x: &Mesh, px: &Isometry3, y: &Mesh, py: &Isometry3) {
        let p = Placed::new(x, px, y, py);
        // A ball inside both solids lies in both boxes: where their overlap is no thicker than
        // the bound to beat (a resting contact), no ball can help, and none are built.
        let (c, h) = p.node_box(0);
        let Some(overlap) = Aabb::from_center_half_extents(c, h).intersection(&p.bx) else {
            return;
        };
        let thinnest = overlap.extents().min();
        if thinnest <= self.threshold() {
            return;
        }
        for ball in p.tx.balls(p.x) {
            let c = p.t * ball.centre;
            if !p.bx.contains_point(&c) {
                continue;
            }
            self.queries += 1;
            let class = p.ty.classify_within(y, &c, ball.radius);
            if class.inside {
                let rho = ball.radius.min(class.distance).min(p.box_depth(&c));
                self.raise(2.0 * rho);
            }
            if self.done() {
                return;
            }
        }
    }

    /// Whether a connected part of `x` lies inside `y` (surfaces known not to meet); raises
    /// the bound by the depth of the deciding vertex.
    fn nested(&mut self, x: &Mesh, px: &Isometry3, y: &Mesh, py: &Isometry3) -> bool {
        let p = Placed::new(x, px, y, py);
        for comp in p.tx.components.iter().take(MAX_NEST_COMPONENTS) {
            let c = p.t * comp.aabb.center();
            let h = p.rot_abs * comp.aabb.half_extents();
            if !Aabb::from_center_half_extents(c, h).intersects(&p.bx) {
                continue;
            }
            for &v in &comp.probes {
                let point = p.t * x.vertices()[v as usize];
                if !p.bx.contains_point(&point) {
                    break;
                }
                self.queries += 1;
                // Distances beyond the box depth do not change the depth: resolve up to it.
                let class = p.ty.classify_within(y, &point, p.box_depth(&point).max(NEST_EPS));
                if class.distance <= NEST_EPS {
                    continue;
                }
                if class.inside {
                    self.raise(class.distance.min(p.box_depth(&point)));
                    return true;
                }
                break;
            }
        }
        false
    }

    /// A cheap first look for a collision's witness: the centroids of representative
    /// triangles of the hierarchy's nodes that can reach deeper than the tolerance into `y`,
    /// level by level (so the samples spread over the surface before they densify); a deep
    /// penetration shows at many of them, whatever the bounds' order. Returns the queries
    /// made.
    fn witness_pass(&mut self, p: &Placed<'_>, skip: u64, limit: u64) -> u64 {
        let tree = &p.tx.tree;
        if tree.nodes.is_empty() {
            return 0;
        }
        // The walk is deterministic: the first `skip` probes were made by an earlier look.
        let mut seen: u64 = 0;
        let mut spent = skip;
        let mut queue: std::collections::VecDeque<(usize, u32)> = std::collections::VecDeque::new();
        queue.push_back((0, u32::MAX));
        let probe = |s: &mut Search, k: u32, spent: &mut u64, seen: &mut u64| {
            *seen += 1;
            if *seen <= skip {
                return;
            }
            let g = centroid(&p.triangle(k));
            *spent += 1;
            s.queries += 1;
            let class = p.ty.classify_within(p.y, &g, s.reach(p.box_depth(&g)));
            s.sample(p, &g, &class);
        };
        while let Some((n, parent_rep)) = queue.pop_front() {
            if spent >= limit || self.done() {
                break;
            }
            if p.region_bound(&p.node_corners(n)) <= self.q.tolerance {
                continue;
            }
            let node = &tree.nodes[n];
            if node.is_leaf() {
                for &k in tree.leaf(n) {
                    if spent >= limit || self.done() {
                        break;
                    }
                    if p.region_bound(&p.triangle(k)) > self.q.tolerance {
                        probe(self, k, &mut spent, &mut seen);
                    }
                }
                continue;
            }
            if node.rep != parent_rep && p.region_bound(&p.triangle(node.rep)) > self.q.tolerance {
                probe(self, node.rep, &mut spent, &mut seen);
            }
            for child in tree.children(n) {
                queue.push_back((child, node.rep));
            }
        }
        spent
    }

    /// [`Search::witness_pass`] from `x` into `y` up to `limit` queries in all (`spent` of
    /// them already made by an earlier, shorter look): the queries spent.
    fn witness(&mut self, x: &Mesh, px: &Isometry3, y: &Mesh, py: &Isometry3, limit: u64, spent: u64) -> u64 {
        let p = Placed::new(x, px, y, py);
        let limit = (self.q.budget as u64).min(limit);
        if spent >= limit {
            return spent;
        }
        self.witness_pass(&p, spent, limit)
    }

    /// The best-first search for points of `x`'s surface deep inside `y`, `spent` queries of
    /// this direction's budget already used.
    fn surface(&mut self, x: &Mesh, px: &Isometry3, y: &Mesh, py: &Isometry3, spent: u64) {
        let p = Placed::new(x, px, y, py);
        if p.tx.tree.nodes.is_empty() {
            return;
        }
        let budget = self.q.budget as u64;
        let mut spent: u64 = spent;
        let mut heap: BinaryHeap<Entry> = BinaryHeap::new();
        let mut seq: u64 = 0;
        let mut push = |heap: &mut BinaryHeap<Entry>, tier: u8, bound: Real, item: Item, threshold: Real| {
            if bound > threshold {
                seq += 1;
                heap.push(Entry {
                    tier,
                    bound,
                    seq,
                    item,
                });
            }
        };
        push(
            &mut heap,
            0,
            p.region_bound(&p.node_corners(0)),
            Item::Node(0),
            self.threshold(),
        );
        while let Some(top) = heap.pop() {
            if self.done() {
                return;
            }
            if top.bound <= self.threshold() {
                continue;
            }
            let needs_query = !matches!(top.item, Item::Node(n) if p.tx.tree.nodes[n as usize].is_leaf());
            if needs_query && spent >= budget {
                self.undecided = true;
                return;
            }
            match top.item {
                Item::Node(n) => {
                    let n = n as usize;
                    if p.tx.tree.nodes[n].is_leaf() {
                        let leaf = p.tx.tree.leaf(n);
                        let mut seen: Vec<u32> = Vec::with_capacity(3 * leaf.len());
                        for &k in leaf {
                            let t = p.triangle(k);
                            let bound = p.region_bound(&t).min(top.bound);
                            push(&mut heap, top.tier, bound, Item::Tri(t), self.threshold());
                            for (i, corner) in x.triangles()[k as usize].iter().zip(t) {
                                if !seen.contains(i) {
                                    seen.push(*i);
                                    let bound = p.region_bound(&[corner]).min(top.bound);
                                    push(&mut heap, top.tier, bound, Item::Point(corner), self.threshold());
                                }
                            }
                        }
                        continue;
                    }
                    let (c, h) = p.node_box(n);
                    let rho = h.norm();
                    spent += 1;
                    self.queries += 1;
                    let (class, side) = p.ty.classify_ball(p.y, &c, rho, 2.0 * rho);
                    let bd = p.box_depth(&c);
                    // An upper bound on the depth at the centre (for the children's bounds) and
                    // a lower bound (for a certified bound when the whole ball is inside).
                    let near = if class.exact { class.distance.min(bd) } else { bd };
                    match side {
                        Some(false) => continue,
                        Some(true) => {
                            self.raise(class.distance.min(bd) - rho);
                            if self.done() {
                                return;
                            }
                        }
                        None => {}
                    }
                    let tier = u8::from(!class.inside);
                    for child in p.tx.tree.children(n) {
                        let (cc, ch) = p.node_box(child);
                        let corners = p.node_corners(child);
                        let lipschitz = (near + (cc - c).norm() + ch.norm()).max(0.0);
                        let mut bound = p.region_bound(&corners).min(lipschitz);
                        if let Some(t) = class.triangle
                            && bound > self.threshold()
                        {
                            bound = bound.min(p.ty.convex_bound(p.y, t, &corners));
                        }
                        push(&mut heap, tier, bound, Item::Node(child as u32), self.threshold());
                    }
                }
                Item::Tri(t) => {
                    let g = centroid(&t);
                    let rho = tri_radius(&t, &g);
                    spent += 1;
                    self.queries += 1;
                    let bd = p.box_depth(&g);
                    let (class, side) = p.ty.classify_ball(p.y, &g, rho, (2.0 * rho).max(self.reach(bd)));
                    let certain = class.distance.min(bd);
                    let near = if class.exact { certain } else { bd };
                    self.sample(&p, &g, &class);
                    match side {
                        Some(false) => continue,
                        Some(true) => self.raise(certain - rho),
                        None => {}
                    }
                    if self.done() || rho <= self.q.spacing {
                        continue;
                    }
                    if let Some(tri) = class.triangle
                        && p.ty.convex_bound(p.y, tri, &t) <= self.threshold()
                    {
                        continue;
                    }
                    let tier = u8::from(!class.inside);
                    let m = [
                        Point3::from((t[0].coords + t[1].coords) * 0.5),
                        Point3::from((t[1].coords + t[2].coords) * 0.5),
                        Point3::from((t[2].coords + t[0].coords) * 0.5),
                    ];
                    for child in [
                        [t[0], m[0], m[2]],
                        [m[0], t[1], m[1]],
                        [m[2], m[1], t[2]],
                        [m[0], m[1], m[2]],
                    ] {
                        let cg = centroid(&child);
                        let lipschitz = (near + (cg - g).norm() + tri_radius(&child, &cg)).max(0.0);
                        let mut bound = p.region_bound(&child).min(lipschitz);
                        if let Some(tri) = class.triangle
                            && bound > self.threshold()
                        {
                            bound = bound.min(p.ty.convex_bound(p.y, tri, &child));
                        }
                        push(&mut heap, tier, bound, Item::Tri(child), self.threshold());
                    }
                }
                Item::Point(pt) => {
                    spent += 1;
                    self.queries += 1;
                    let class = p.ty.classify_within(p.y, &pt, self.reach(p.box_depth(&pt)));
                    self.sample(&p, &pt, &class);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(h: Real) -> Mesh {
        Mesh::cuboid(&Vector3::repeat(h)).unwrap()
    }

    fn at(x: Real, y: Real, z: Real) -> Isometry3 {
        Isometry3::translation(x, y, z)
    }

    #[test]
    fn face_to_face_overlap_is_its_depth() {
        // Two unit cubes overlapping by 1 cm along x: the penetration depth is 0.01, found at
        // the corners of each inside the other.
        let (a, b) = (cube(0.5), cube(0.5));
        let q = PenetrationQuery {
            depth: DepthSearch::All,
            ..PenetrationQuery::default()
        };
        let r = a.penetration(&at(0.0, 0.0, 0.0), &b, &at(0.99, 0.3, 0.2), &q);
        assert_eq!(r.overlap, Overlap::Surface);
        assert!(r.colliding);
        assert!((r.depth - 0.01).abs() < 1e-9, "{r:?}");
        // 3 mm: a resting contact, settled without a point query (the overlap lies within the
        // tolerance of each box's face).
        let r = a.penetration(
            &at(0.0, 0.0, 0.0),
            &b,
            &at(0.997, 0.3, 0.2),
            &PenetrationQuery::default(),
        );
        assert!(!r.colliding && !r.undecided);
        assert_eq!(r.queries, 0, "{r:?}");
    }

    #[test]
    fn coincident_and_offset_copies_collide() {
        let a = cube(0.5);
        let r = a.penetration(
            &at(1.0, 2.0, 3.0),
            &a,
            &at(1.0, 2.0, 3.0),
            &PenetrationQuery::default(),
        );
        // The same mesh twice at one pose: the inscribed ball (radius 0.5) proves 1 m.
        assert!(r.colliding);
        assert!((r.depth - 1.0).abs() < 1e-9);
        assert_eq!(r.queries, 0);
        // Offset by 1 mm: every surface point is within 1 mm of the other surface, but the
        // inscribed ball lies 0.499 m deep in the other cube.
        let b = cube(0.5);
        let r = a.penetration(
            &at(0.0, 0.0, 0.0),
            &b,
            &at(0.001, 0.0, 0.0),
            &PenetrationQuery::default(),
        );
        assert!(r.colliding, "{r:?}");
        assert!((r.depth - 2.0 * 0.499).abs() < 1e-9, "{r:?}");
    }

    #[test]
    fn nested_box_on_the_same_floor_as_a_yawed_box() {
        // A 0.3 m box standing inside a 2 x 1.6 x 0.6 m bed turned by 30 degrees, both on z = 0:
        // the bottoms are coplanar.
        let bed = Mesh::cuboid(&Vector3::new(1.0, 0.8, 0.3)).unwrap();
        let small = cube(0.15);
        let yaw = Isometry3::new(
            Vector3::new(0.0, 0.0, 0.3),
            Vector3::z() * std::f64::consts::FRAC_PI_6,
        );
        let r = small.penetration(&at(0.3, 0.1, 0.15), &bed, &yaw, &PenetrationQuery::default());
        assert!(r.colliding, "{r:?}");
        assert_ne!(r.overlap, Overlap::Apart);
        // Lifted off the floor: surfaces apart, nested.
        let r = small.penetration(&at(0.3, 0.1, 0.3), &bed, &yaw, &PenetrationQuery::default());
        assert_eq!(r.overlap, Overlap::Nested { first_inside: true });
        assert!(r.colliding);
        // Beside the bed: apart.
        let r = small.penetration(&at(3.0, 0.1, 0.3), &bed, &yaw, &PenetrationQuery::default());
        assert_eq!(r.overlap, Overlap::Apart);
        assert!(!r.colliding);
    }
}
