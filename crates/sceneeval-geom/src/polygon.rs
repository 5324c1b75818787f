use crate::planar::{self, orient};
use crate::{GeomError, Point2, Real, Vector2};

/// A simple polygon in the plane (world x, y), such as a room's floor outline.
///
/// Points are kept in the order given (either winding); edge `i` runs from point `i` to point
/// `i + 1`, wrapping. A closing point equal to the first and consecutive duplicates are dropped
/// on construction. [`Polygon2::new`] rejects fewer than three distinct points, non-finite
/// coordinates, zero area and self-intersection.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Polygon2 {
    points: Vec<Point2>,
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for Polygon2 {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        struct Raw {
            points: Vec<Point2>,
        }
        let raw = Raw::deserialize(d)?;
        Polygon2::new(raw.points).map_err(serde::de::Error::custom)
    }
}

impl Polygon2 {
    /// A validated simple polygon.
    ///
    /// # Errors
    /// [`GeomError::NonFinitePoint`], [`GeomError::TooFewPoints`], [`GeomError::ZeroArea`],
    /// [`GeomError::SelfIntersecting`] (naming the first such pair of edges), and
    /// [`GeomError::TooComplex`] for an outline whose simplicity check would need more than
    /// [`MAX_EDGE_PAIRS`] edge pairs (see the cost note on the check below: only outlines with
    /// thousands of overlapping long edges come near it).
    pub fn new(points: Vec<Point2>) -> Result<Self, GeomError> {
        for (index, p) in points.iter().enumerate() {
            if !p.x.is_finite() || !p.y.is_finite() {
                return Err(GeomError::NonFinitePoint {
                    index,
                    value: [p.x, p.y],
                });
            }
        }
        let mut pts: Vec<Point2> = Vec::with_capacity(points.len());
        for p in points {
            if pts.last() != Some(&p) {
                pts.push(p);
            }
        }
        while pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        if pts.len() < 3 {
            return Err(GeomError::TooFewPoints { count: pts.len() });
        }
        let poly = Polygon2 { points: pts };
        if poly.signed_area().abs() <= Real::EPSILON * poly.bbox_diagonal_sq() {
            return Err(GeomError::ZeroArea);
        }
        if let Some((first, second)) = poly.find_self_intersection()? {
            return Err(GeomError::SelfIntersecting { first, second });
        }
        Ok(poly)
    }

    /// An axis-aligned rectangle, counter-clockwise from `min`.
    pub fn rectangle(min: Point2, max: Point2) -> Result<Self, GeomError> {
        Polygon2::new(vec![
            min,
            Point2::new(max.x, min.y),
            max,
            Point2::new(min.x, max.y),
        ])
    }

    /// The vertices, in the order given.
    #[inline]
    pub fn points(&self) -> &[Point2] {
        &self.points
    }

    /// Number of vertices (equal to the number of edges).
    #[inline]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false: a valid polygon has at least three points.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Edge `i`: from point `i` to point `(i + 1) % len`.
    #[inline]
    pub fn edge(&self, i: usize) -> (Point2, Point2) {
        let n = self.points.len();
        (self.points[i % n], self.points[(i + 1) % n])
    }

    /// All edges in order.
    pub fn edges(&self) -> impl Iterator<Item = (Point2, Point2)> + '_ {
        (0..self.points.len()).map(move |i| self.edge(i))
    }

    /// Signed area (shoelace): positive when the points run counter-clockwise.
    pub fn signed_area(&self) -> Real {
        planar::signed_area(&self.points)
    }

    /// Enclosed area in square metres.
    #[inline]
    pub fn area(&self) -> Real {
        self.signed_area().abs()
    }

    /// Whether the points run counter-clockwise (seen from above, z up).
    #[inline]
    pub fn is_ccw(&self) -> bool {
        self.signed_area() > 0.0
    }

    /// The area centroid (centre of mass of the enclosed region).
    pub fn centroid(&self) -> Point2 {
        let o = self.points[0];
        let mut twice_area = 0.0;
        let mut acc = Vector2::zeros();
        for (a, b) in self.edges() {
            let (a, b) = (a - o, b - o);
            let cross = a.perp(&b);
            twice_area += cross;
            acc += (a + b) * cross;
        }
        o + acc / (3.0 * twice_area)
    }

    /// Lowest and highest corners of the bounding rectangle.
    pub fn bounds(&self) -> (Point2, Point2) {
        let mut min = self.points[0];
        let mut max = self.points[0];
        for p in &self.points[1..] {
            min = min.inf(p);
            max = max.sup(p);
        }
        (min, max)
    }

    fn bbox_diagonal_sq(&self) -> Real {
        let (min, max) = self.bounds();
        (max - min).norm_squared()
    }

    /// Whether `p` lies in the closed polygon (points on an edge count as inside).
    pub fn contains_point(&self, p: &Point2) -> bool {
        let mut inside = false;
        for (a, b) in self.edges() {
            if planar::point_segment_distance(p, &a, &b) == 0.0 {
                return true;
            }
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Distance from `p` to the polygon's boundary (regardless of inside or outside).
    pub fn distance_to_boundary(&self, p: &Point2) -> Real {
        self.edges()
            .map(|(a, b)| planar::point_segment_distance(p, &a, &b))
            .fold(Real::INFINITY, Real::min)
    }

    /// Signed distance to the boundary: negative inside, positive outside.
    pub fn signed_distance(&self, p: &Point2) -> Real {
        let d = self.distance_to_boundary(p);
        if self.contains_point(p) { -d } else { d }
    }

    /// A triangulation of the polygon as index triples into [`Polygon2::points`], each triangle
    /// counter-clockwise. Uses ear clipping (`earcutr`); the triangles' areas sum to
    /// [`Polygon2::area`].
    pub fn triangulate(&self) -> Vec<[usize; 3]> {
        let flat: Vec<Real> = self.points.iter().flat_map(|p| [p.x, p.y]).collect();
        let idx = earcutr::earcut(&flat, &[], 2).unwrap_or_default();
        idx.chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]];
                let (pa, pb, pc) = (self.points[a], self.points[b], self.points[c]);
                if (pb - pa).perp(&(pc - pa)) < 0.0 {
                    [a, c, b]
                } else {
                    [a, b, c]
                }
            })
            .collect()
    }

    /// Area of the intersection of this polygon with a convex polygon `convex` (either
    /// winding). Exact up to rounding: the polygon is triangulated and each triangle clipped
    /// against `convex` (Sutherland-Hodgman).
    pub fn intersection_area_with_convex(&self, convex: &[Point2]) -> Real {
        if convex.len() < 3 {
            return 0.0;
        }
        let clip = planar::ccw(convex.to_vec());
        self.triangulate()
            .iter()
            .map(|t| planar::area(&planar::clip_convex(&t.map(|i| self.points[i]), &clip)))
            .sum()
    }

    /// The fraction of the segment `a`-`b` that lies inside the closed polygon, in `[0, 1]`
    /// (1 for a degenerate segment whose point is inside).
    pub fn segment_fraction_inside(&self, a: &Point2, b: &Point2) -> Real {
        let d = b - a;
        let len2 = d.norm_squared();
        if len2 == 0.0 {
            return if self.contains_point(a) { 1.0 } else { 0.0 };
        }
        // Parameters where the segment crosses an edge line, then test each piece's midpoint.
        let mut ts = vec![0.0, 1.0];
        for (p, q) in self.edges() {
            let e = q - p;
            let denom = d.perp(&e);
            if denom == 0.0 {
                continue;
            }
            let w = p - a;
            let t = w.perp(&e) / denom;
            let s = w.perp(&d) / denom;
            if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&s) {
                ts.push(t);
            }
        }
        ts.sort_by(|x, y| x.total_cmp(y));
        let mut inside = 0.0;
        for w in ts.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            if t1 > t0 && self.contains_point(&(a + d * (0.5 * (t0 + t1)))) {
                inside += t1 - t0;
            }
        }
        inside.clamp(0.0, 1.0)
    }

    /// A pair of edges that makes the outline non-simple, if any: non-adjacent edges that
    /// touch or cross, or adjacent edges that fold back on each other.
    ///
    /// Sort and sweep along x: edges are visited by their lowest x, and each is tested only
    /// against the edges whose x range reaches it (edges whose x ranges are apart cannot
    /// meet). The cost is `O(n log n + k)` for `k` pairs of edges whose x ranges overlap: about
    /// `n` for a floor outline (a vertical line meets it a few times), quadratic only for
    /// outlines such as a comb of thousands of long teeth. Those are refused beyond
    /// [`MAX_EDGE_PAIRS`] candidate pairs rather than stall.
    fn find_self_intersection(&self) -> Result<Option<(usize, usize)>, GeomError> {
        let n = self.points.len();
        let x_range = |i: usize| {
            let (a, b) = self.edge(i);
            (a.x.min(b.x), a.x.max(b.x))
        };
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_unstable_by(|&i, &j| x_range(i).0.total_cmp(&x_range(j).0).then(i.cmp(&j)));
        // Count the candidate pairs first (n log n): edge `order[k]` meets the earlier edges
        // whose x range ends at or after its start, i.e. `k` minus those ending before it (an
        // edge ending before another's start also starts before it, so comes earlier).
        let mut ends: Vec<Real> = (0..n).map(|i| x_range(i).1).collect();
        ends.sort_unstable_by(Real::total_cmp);
        let pairs: usize = order
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let lo = x_range(i).0;
                k - ends.partition_point(|&e| e < lo)
            })
            .sum();
        if pairs > MAX_EDGE_PAIRS {
            return Err(GeomError::TooComplex {
                what: "polygon outline",
                limit: MAX_EDGE_PAIRS,
            });
        }
        let mut active: Vec<usize> = Vec::new();
        let mut found: Option<(usize, usize)> = None;
        for &i in &order {
            let (lo, _) = x_range(i);
            active.retain(|&j| x_range(j).1 >= lo);
            for &j in &active {
                let (first, second) = (i.min(j), i.max(j));
                if self.edges_conflict(first, second) && found.is_none_or(|f| (first, second) < f) {
                    found = Some((first, second));
                }
            }
            active.push(i);
        }
        #[cfg(test)]
        tests::EDGE_PAIRS.with(|c| c.set(c.get() + pairs));
        Ok(found)
    }

    /// Whether edges `i < j` make the outline non-simple.
    fn edges_conflict(&self, i: usize, j: usize) -> bool {
        let n = self.points.len();
        let (a, b) = self.edge(i);
        let (c, d) = self.edge(j);
        let adjacent = j == i + 1 || (i == 0 && j == n - 1);
        if adjacent {
            // Adjacent edges share one point; they are bad only if they fold back on each
            // other (collinear and overlapping beyond the shared point).
            let shared = if j == i + 1 { b } else { a };
            let (u, v) = if j == i + 1 {
                (a - shared, d - shared)
            } else {
                (b - shared, c - shared)
            };
            return u.perp(&v) == 0.0 && u.dot(&v) > 0.0;
        }
        segments_intersect(&a, &b, &c, &d)
    }
}

/// The most candidate edge pairs [`Polygon2::new`] examines when checking that an outline is
/// simple (about half a second of work); outlines needing more are refused with
/// [`GeomError::TooComplex`].
pub const MAX_EDGE_PAIRS: usize = 100_000_000;

/// Whether the closed segments `a`-`b` and `c`-`d` share a point.
fn segments_intersect(a: &Point2, b: &Point2, c: &Point2, d: &Point2) -> bool {
    let o1 = orient(a, b, c);
    let o2 = orient(a, b, d);
    let o3 = orient(c, d, a);
    let o4 = orient(c, d, b);
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && on_segment(a, b, c))
        || (o2 == 0.0 && on_segment(a, b, d))
        || (o3 == 0.0 && on_segment(c, d, a))
        || (o4 == 0.0 && on_segment(c, d, b))
}

#[inline]
fn on_segment(a: &Point2, b: &Point2, p: &Point2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    thread_local! {
        /// Candidate edge pairs examined by `find_self_intersection` on this thread.
        pub(super) static EDGE_PAIRS: Cell<usize> = const { Cell::new(0) };
    }

    #[test]
    fn simplicity_check_examines_about_n_pairs_for_a_floor_outline() {
        // A wobbly 100,000-gon: the sweep examines a few pairs per edge.
        let n = 100_000;
        let pts = sceneeval_test_support::wobbly_outline(n);
        EDGE_PAIRS.with(|c| c.set(0));
        let poly = Polygon2::new(pts.clone()).unwrap();
        let pairs = EDGE_PAIRS.with(Cell::get);
        // About 7 pairs per edge (near the outline's leftmost and rightmost points its edges
        // run almost vertically, and a few hundred of them overlap in x), not n^2 / 2 = 5e9.
        assert!(pairs < 10 * n as usize, "{pairs} pairs");
        assert_eq!(poly.len(), n as usize);
        // The same outline with one vertex pulled across it is found.
        let mut bad = pts;
        bad[500] = p(-30.0, 0.1);
        assert!(matches!(
            Polygon2::new(bad),
            Err(GeomError::SelfIntersecting { .. })
        ));
    }

    #[test]
    fn a_comb_beyond_the_pair_budget_is_refused() {
        // 12,000 teeth spanning the whole width: every long edge overlaps every other in x
        // (about 2.9e8 candidate pairs), so the outline is refused instead of checked.
        let teeth = 12_000;
        let mut pts = vec![p(0.0, 0.0)];
        for k in 0..teeth {
            let y = f64::from(k) + 1.0;
            pts.push(p(100.0, y - 0.75));
            pts.push(p(100.0, y - 0.25));
            pts.push(p(0.5, y - 0.25));
            pts.push(p(0.5, y));
        }
        pts.push(p(0.0, f64::from(teeth)));
        assert_eq!(
            Polygon2::new(pts),
            Err(GeomError::TooComplex {
                what: "polygon outline",
                limit: MAX_EDGE_PAIRS,
            })
        );
    }

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    fn l_shape() -> Polygon2 {
        // 4 x 4 square minus the 2 x 2 top-right quadrant: area 12.
        Polygon2::new(vec![
            p(0.0, 0.0),
            p(4.0, 0.0),
            p(4.0, 2.0),
            p(2.0, 2.0),
            p(2.0, 4.0),
            p(0.0, 4.0),
        ])
        .unwrap()
    }

    #[test]
    fn area_centroid_orientation() {
        let l = l_shape();
        assert_eq!(l.area(), 12.0);
        assert!(l.is_ccw());
        // Centroid of the L: (3 squares of area 4 at (1,1), (3,1), (1,3)) -> (5/3, 5/3).
        let c = l.centroid();
        assert!((c - p(5.0 / 3.0, 5.0 / 3.0)).norm() < 1e-12);
        let mut rev = l.points().to_vec();
        rev.reverse();
        let cw = Polygon2::new(rev).unwrap();
        assert!(!cw.is_ccw());
        assert_eq!(cw.area(), 12.0);
        assert!((cw.centroid() - c).norm() < 1e-12);
    }

    #[test]
    fn containment_including_boundary() {
        let l = l_shape();
        assert!(l.contains_point(&p(1.0, 3.0)));
        assert!(!l.contains_point(&p(3.0, 3.0)), "the missing quadrant");
        assert!(l.contains_point(&p(4.0, 1.0)), "on an edge");
        assert!(l.contains_point(&p(2.0, 2.0)), "the reflex corner");
        assert!(!l.contains_point(&p(-0.1, 1.0)));
        assert!((l.distance_to_boundary(&p(3.0, 3.0)) - 1.0).abs() < 1e-12);
        assert!((l.signed_distance(&p(1.0, 1.0)) + 1.0).abs() < 1e-12);
    }

    #[test]
    fn triangulation_covers_area() {
        let l = l_shape();
        let tris = l.triangulate();
        assert_eq!(tris.len(), 4);
        let pts = l.points();
        let total: f64 = tris
            .iter()
            .map(|t| {
                let a = (pts[t[1]] - pts[t[0]]).perp(&(pts[t[2]] - pts[t[0]])) * 0.5;
                assert!(a > 0.0, "triangles are counter-clockwise");
                a
            })
            .sum();
        assert!((total - 12.0).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_polygons() {
        assert_eq!(
            Polygon2::new(vec![p(0.0, 0.0), p(1.0, 0.0)]),
            Err(GeomError::TooFewPoints { count: 2 })
        );
        assert_eq!(
            Polygon2::new(vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 0.0), p(0.0, 0.0)]),
            Err(GeomError::TooFewPoints { count: 2 })
        );
        assert_eq!(
            Polygon2::new(vec![p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0)]),
            Err(GeomError::ZeroArea)
        );
        assert!(matches!(
            Polygon2::new(vec![p(0.0, 0.0), p(2.0, 2.0), p(2.0, 0.0), p(0.0, 1.0)]),
            Err(GeomError::SelfIntersecting { .. })
        ));
        assert!(matches!(
            Polygon2::new(vec![p(0.0, f64::NAN), p(1.0, 1.0), p(1.0, 0.0)]),
            Err(GeomError::NonFinitePoint { index: 0, .. })
        ));
        // A closing duplicate point is accepted and dropped.
        let sq = Polygon2::new(vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 1.0),
            p(0.0, 1.0),
            p(0.0, 0.0),
        ])
        .unwrap();
        assert_eq!(sq.len(), 4);
    }

    #[test]
    fn clipping_areas() {
        let l = l_shape();
        // A unit square straddling the reflex corner: 3/4 of it is inside the L.
        let sq = [p(1.5, 1.5), p(2.5, 1.5), p(2.5, 2.5), p(1.5, 2.5)];
        assert!((l.intersection_area_with_convex(&sq) - 0.75).abs() < 1e-12);
        let mut cw = sq;
        cw.reverse();
        assert!((l.intersection_area_with_convex(&cw) - 0.75).abs() < 1e-12);
        let outside = [p(5.0, 5.0), p(6.0, 5.0), p(6.0, 6.0)];
        assert_eq!(l.intersection_area_with_convex(&outside), 0.0);
        // Segment from (1, 3) to (5, 3): inside for x in [1, 2] only.
        assert!((l.segment_fraction_inside(&p(1.0, 3.0), &p(5.0, 3.0)) - 0.25).abs() < 1e-12);
        assert_eq!(l.segment_fraction_inside(&p(1.0, 1.0), &p(1.0, 1.0)), 1.0);
    }
}
