//! Exact helpers on point loops in the plane (world x, y): orientation, areas, convex hulls,
//! convex clipping and subtraction, point distances; and clipping of polygons in the plane or
//! in space by a half space ([`clip_half_space`]). Unlike [`crate::Polygon2`] they take plain
//! slices and do not validate: "convex polygon" means a counter-clockwise loop without reflex
//! corners, and degenerate loops (fewer than three points) are handled as points or segments
//! where the function says so.

use crate::{Point2, Real, na};

/// Twice the signed area of the triangle `a b c` (positive counter-clockwise).
#[inline]
pub fn orient(a: &Point2, b: &Point2, c: &Point2) -> Real {
    (b - a).perp(&(c - a))
}

/// Signed area of a loop (positive counter-clockwise).
pub fn signed_area(poly: &[Point2]) -> Real {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    let o = poly[0];
    let mut twice = 0.0;
    for i in 1..n - 1 {
        twice += orient(&o, &poly[i], &poly[i + 1]);
    }
    twice * 0.5
}

/// Area of a loop.
#[inline]
pub fn area(poly: &[Point2]) -> Real {
    signed_area(poly).abs()
}

/// The loop made counter-clockwise.
pub fn ccw(mut poly: Vec<Point2>) -> Vec<Point2> {
    if signed_area(&poly) < 0.0 {
        poly.reverse();
    }
    poly
}

/// Convex hull (Andrew's monotone chain), counter-clockwise without collinear points. Fewer
/// than three points or collinear input give the distinct extreme points (0, 1 or 2).
pub fn convex_hull(points: &[Point2]) -> Vec<Point2> {
    let mut pts: Vec<Point2> = points.to_vec();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let mut hull: Vec<Point2> = Vec::with_capacity(pts.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point2>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2 && orient(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull
}

/// Convex hull of many points, first discarding the points strictly inside the octagon of
/// extreme points along x, y, x+y and x-y (Akl-Toussaint), which leaves few to sort.
pub fn convex_hull_fast(points: &[Point2]) -> Vec<Point2> {
    if points.len() < 64 {
        return convex_hull(points);
    }
    let keys: [fn(&Point2) -> Real; 4] = [|p| p.x, |p| p.y, |p| p.x + p.y, |p| p.x - p.y];
    let mut ext = [points[0]; 8];
    for p in points {
        for (k, key) in keys.iter().enumerate() {
            if key(p) < key(&ext[2 * k]) {
                ext[2 * k] = *p;
            }
            if key(p) > key(&ext[2 * k + 1]) {
                ext[2 * k + 1] = *p;
            }
        }
    }
    let octagon = convex_hull(&ext);
    if octagon.len() < 3 {
        return convex_hull(points);
    }
    let kept: Vec<Point2> = points
        .iter()
        .filter(|p| !strictly_inside_convex(&octagon, p))
        .copied()
        .collect();
    convex_hull(&kept)
}

fn strictly_inside_convex(poly: &[Point2], p: &Point2) -> bool {
    let n = poly.len();
    (0..n).all(|i| orient(&poly[i], &poly[(i + 1) % n], p) > 0.0)
}

/// Whether `p` lies in the closed convex counter-clockwise polygon, within `eps` metres.
pub fn convex_contains(poly: &[Point2], p: &Point2, eps: Real) -> bool {
    let n = poly.len();
    match n {
        0 => false,
        1 => (poly[0] - p).norm() <= eps,
        2 => point_segment_distance(p, &poly[0], &poly[1]) <= eps,
        _ => (0..n).all(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let len = (b - a).norm();
            len == 0.0 || orient(&a, &b, p) / len >= -eps
        }),
    }
}

/// Distance from `p` to the segment `a b`, in the plane (`Point2`) or in space (`Point3`: the
/// solids' edge tree measures with it too).
pub fn point_segment_distance<const D: usize>(
    p: &na::Point<Real, D>,
    a: &na::Point<Real, D>,
    b: &na::Point<Real, D>,
) -> Real {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

/// Distance from `p` to the closed convex counter-clockwise polygon (0 inside). One or two
/// points are a point or a segment.
pub fn convex_distance(poly: &[Point2], p: &Point2) -> Real {
    let n = poly.len();
    if n == 0 {
        return Real::INFINITY;
    }
    if n == 1 {
        return (poly[0] - p).norm();
    }
    if n >= 3 && convex_contains(poly, p, 0.0) {
        return 0.0;
    }
    (0..n)
        .map(|i| point_segment_distance(p, &poly[i], &poly[(i + 1) % n]))
        .fold(Real::INFINITY, Real::min)
}

/// Keeps the part of the polygon `poly` (its vertices in order, in the plane or in space)
/// where `f(p) >= 0` for the affine function `f`: one Sutherland-Hodgman step. Each edge that
/// crosses the boundary contributes its crossing point. A vertex on the boundary (`f = 0`) is
/// kept, and again as the crossing point of an edge between it and a vertex outside, so the
/// result may repeat points or be degenerate (callers test its size or area).
pub fn clip_half_space<const D: usize>(
    poly: &[nalgebra::Point<Real, D>],
    f: impl Fn(&nalgebra::Point<Real, D>) -> Real,
) -> Vec<nalgebra::Point<Real, D>> {
    let mut out = Vec::with_capacity(poly.len() + 2);
    clip_half_space_into(poly, f, &mut out);
    out
}

/// [`clip_half_space`] into `out` (cleared first), so that a caller clipping repeatedly can
/// reuse its buffers and allocate nothing once they have grown.
pub fn clip_half_space_into<const D: usize>(
    poly: &[nalgebra::Point<Real, D>],
    f: impl Fn(&nalgebra::Point<Real, D>) -> Real,
    out: &mut Vec<nalgebra::Point<Real, D>>,
) {
    out.clear();
    let n = poly.len();
    for i in 0..n {
        let (cur, next) = (poly[i], poly[(i + 1) % n]);
        let (fc, fn_) = (f(&cur), f(&next));
        if fc >= 0.0 {
            out.push(cur);
        }
        if (fc >= 0.0) != (fn_ >= 0.0) {
            let t = fc / (fc - fn_);
            out.push(cur + (next - cur) * t);
        }
    }
}

/// The intersection of a convex `subject` with the convex counter-clockwise `clip`.
pub fn clip_convex(subject: &[Point2], clip: &[Point2]) -> Vec<Point2> {
    let m = clip.len();
    let mut out = subject.to_vec();
    for k in 0..m {
        if out.len() < 3 {
            return Vec::new();
        }
        let (a, b) = (clip[k], clip[(k + 1) % m]);
        out = clip_half_space(&out, |p| orient(&a, &b, p));
    }
    if out.len() < 3 { Vec::new() } else { out }
}

/// Relative tolerance of [`subtract_convex`]: a point within `SNAP_REL * (1 + |coordinates|)`
/// metres of a hole edge's line counts as on it (about 1e-11 m at 10 m from the origin,
/// hundreds of times the rounding error of a clipped vertex there).
const SNAP_REL: Real = 1e-12;

/// `subject \ hole` for convex `subject` and convex counter-clockwise `hole`, as disjoint convex
/// pieces (for each edge of `hole`, the part of what is left beyond that edge).
///
/// Points within a rounding tolerance of an edge's line (`1e-12` times one plus the edge's
/// largest absolute coordinate, in metres) count as on the line, so the result does not depend
/// on the last bits of a vertex that an earlier clip put on a line:
/// - a `subject` that lies beyond some edge of `hole`, or has `hole` beyond one of its own
///   edges (the two are disjoint or only touch), comes back whole as the one piece;
/// - an edge whose line `subject` does not cross (all of it inside or on the line) splits off
///   nothing, and a part lying beyond or on a line goes whole.
///
/// Without this, subtracting a hole from pieces that an equal hole (a copy of an object at
/// the same place) cut before produced slivers of rounding-error width, each split again by
/// the next copy: the piece count grew exponentially with the copies. With it, every piece
/// lies in one cell of the arrangement of the holes' edge lines (up to the tolerance), so
/// subtracting `k` holes of `m` edges leaves at most `O((k m)^2)` pieces, and equal holes add
/// none after the first. A hole that overlaps `subject` by less than the tolerance is
/// ignored.
pub fn subtract_convex(subject: &[Point2], hole: &[Point2]) -> Vec<Vec<Point2>> {
    let m = hole.len();
    if m < 3 || subject.len() < 3 || separated(subject, hole) {
        return vec![subject.to_vec()];
    }
    let mut pieces = Vec::new();
    let mut rest = subject.to_vec();
    for k in 0..m {
        if rest.len() < 3 {
            break;
        }
        let (a, b) = (hole[k], hole[(k + 1) % m]);
        let Some(inside) = edge_distance(&a, &b) else {
            continue;
        };
        let (lo, hi) = rest
            .iter()
            .map(&inside)
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), d| {
                (lo.min(d), hi.max(d))
            });
        if lo >= 0.0 {
            // Inside or on the line: nothing of `rest` is beyond this edge.
            continue;
        }
        if hi <= 0.0 {
            // Beyond or on the line: `rest` does not meet the hole.
            pieces.push(rest);
            return pieces;
        }
        let outside = clip_half_space(&rest, |p| -inside(p));
        if outside.len() >= 3 && area(&outside) > 0.0 {
            pieces.push(outside);
        }
        rest = clip_half_space(&rest, &inside);
    }
    pieces
}

/// The signed distance inside the line through `a` and `b` (positive to the left of `a -> b`),
/// snapped to 0 within the tolerance of [`subtract_convex`]; `None` for a zero-length edge.
fn edge_distance(a: &Point2, b: &Point2) -> Option<impl Fn(&Point2) -> Real> {
    let len = (b - a).norm();
    if len == 0.0 || !len.is_finite() {
        return None;
    }
    let tol = SNAP_REL * (1.0 + a.coords.amax().max(b.coords.amax()));
    let (a, b) = (*a, *b);
    Some(move |p: &Point2| {
        let d = orient(&a, &b, p) / len;
        if d.abs() <= tol { 0.0 } else { d }
    })
}

/// Whether two convex polygons are disjoint or only touch (within the tolerance of
/// [`subtract_convex`]): one lies beyond or on the line of an edge of the other. Either may
/// run clockwise.
fn separated(p: &[Point2], q: &[Point2]) -> bool {
    let beyond = |edges: &[Point2], pts: &[Point2]| {
        let n = edges.len();
        let sign = signed_area(edges).signum();
        (0..n).any(|k| {
            edge_distance(&edges[k], &edges[(k + 1) % n])
                .is_some_and(|inside| pts.iter().all(|x| sign * inside(x) <= 0.0))
        })
    };
    beyond(q, p) || beyond(p, q)
}

/// Bounding rectangle `(min, max)` of a non-empty loop.
pub fn bounds(poly: &[Point2]) -> (Point2, Point2) {
    let mut min = poly.first().copied().unwrap_or(Point2::origin());
    let mut max = min;
    for p in poly {
        min = min.inf(p);
        max = max.sup(p);
    }
    (min, max)
}

/// Whether two bounding rectangles overlap (closed).
#[inline]
pub fn boxes_overlap(a: &(Point2, Point2), b: &(Point2, Point2)) -> bool {
    a.0.x <= b.1.x && b.0.x <= a.1.x && a.0.y <= b.1.y && b.0.y <= a.1.y
}

/// Whether a loop is convex (no reflex corner; collinear corners allowed).
pub fn is_convex(poly: &[Point2]) -> bool {
    let n = poly.len();
    let s = signed_area(poly).signum();
    (0..n).all(|i| orient(&poly[i], &poly[(i + 1) % n], &poly[(i + 2) % n]) * s >= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn clipping_by_a_half_space_in_the_plane_and_in_space() {
        // The unit square cut at x = 0.25: the right part, starting where the first kept
        // vertex is, with the two crossing points.
        let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
        let right = clip_half_space(&square, |q| q.x - 0.25);
        assert_eq!(right, vec![p(0.25, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.25, 1.0)]);
        assert!((area(&right) - 0.75).abs() < 1e-15);
        // Everything kept, nothing kept, a vertex on the boundary.
        assert_eq!(clip_half_space(&square, |q| q.x + 1.0), square.to_vec());
        assert!(clip_half_space(&square, |q| q.x - 2.0).is_empty());
        assert_eq!(
            clip_half_space(&square, |q| -q.x - q.y),
            vec![p(0.0, 0.0); 3],
            "only the corner where f = 0, kept and twice as a crossing point"
        );
        // A triangle standing across the floor z = 0, cut to its part above: the apex and the
        // two points where its sides cross z = 0, a third of the way from (3, 0, -1) up to
        // the apex (x = 3 - 3 / 3) and two thirds of the way from the apex down to (0, 0, -1)
        // (z = 2 - 3 * 2 / 3).
        let tri = [
            crate::Point3::new(0.0, 0.0, -1.0),
            crate::Point3::new(3.0, 0.0, -1.0),
            crate::Point3::new(0.0, 0.0, 2.0),
        ];
        let mut out = vec![crate::Point3::origin(); 7];
        clip_half_space_into(&tri, |q| q.z, &mut out);
        assert_eq!(
            out,
            vec![
                crate::Point3::new(2.0, 0.0, 0.0),
                crate::Point3::new(0.0, 0.0, 2.0),
                crate::Point3::new(0.0, 0.0, 0.0),
            ]
        );
    }

    fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point2> {
        vec![p(x0, y0), p(x1, y0), p(x1, y1), p(x0, y1)]
    }

    #[test]
    fn hull_drops_interior_and_collinear_points() {
        let mut pts = square(0.0, 0.0, 2.0, 1.0);
        pts.extend([p(1.0, 0.0), p(1.0, 0.5), p(0.5, 0.5)]);
        let h = convex_hull(&pts);
        assert_eq!(h.len(), 4);
        assert_eq!(area(&h), 2.0);
        assert!(signed_area(&h) > 0.0);
        // The fast path gives the same hull on many points (a 20 x 20 grid).
        let grid: Vec<Point2> = (0..400).map(|k| p((k % 20) as f64, (k / 20) as f64)).collect();
        assert_eq!(convex_hull_fast(&grid), convex_hull(&grid));
        assert_eq!(convex_hull(&[p(0.0, 0.0), p(1.0, 1.0), p(2.0, 2.0)]).len(), 2);
    }

    #[test]
    fn clip_and_subtract_areas() {
        let a = square(0.0, 0.0, 2.0, 2.0);
        let b = square(1.0, 1.0, 3.0, 3.0);
        assert_eq!(area(&clip_convex(&a, &b)), 1.0);
        let pieces = subtract_convex(&a, &b);
        let total: f64 = pieces.iter().map(|q| area(q)).sum();
        // 4 - 1 = 3.
        assert!((total - 3.0).abs() < 1e-12);
        assert!(subtract_convex(&b, &square(-1.0, -1.0, 5.0, 5.0)).is_empty());
        assert!(clip_convex(&a, &square(5.0, 5.0, 6.0, 6.0)).is_empty());
    }

    /// A regular `n`-gon of radius `r` around `(x, y)`, turned by `turn` radians.
    fn round(n: usize, r: f64, x: f64, y: f64, turn: f64) -> Vec<Point2> {
        (0..n)
            .map(|k| {
                let t = turn + std::f64::consts::TAU * k as f64 / n as f64;
                p(x + r * t.cos(), y + r * t.sin())
            })
            .collect()
    }

    /// Subtracts every hole from `subject` in turn, as the accessibility metric does.
    fn subtract_all(subject: &[Point2], holes: &[Vec<Point2>]) -> Vec<Vec<Point2>> {
        let mut parts = vec![subject.to_vec()];
        for h in holes {
            parts = parts.iter().flat_map(|q| subtract_convex(q, h)).collect();
        }
        parts
    }

    #[test]
    fn copies_of_a_hole_add_no_pieces() {
        // An access strip and 16 copies of a round footprint (a 24-gon) at one place, which
        // covers part of the strip. The first copy splits the strip; the others, on pieces
        // whose vertices lie on their edge lines up to rounding, split off nothing (each
        // copy used to split every piece again into slivers: 2^k pieces after k copies).
        let strip = square(0.5, 3.0, 1.2, 5.0);
        let plant = round(24, 0.25, 1.0, 3.95, 0.3);
        let once = subtract_convex(&strip, &plant);
        let copies = subtract_all(&strip, &vec![plant.clone(); 16]);
        assert_eq!(copies, once, "the later copies leave the pieces as they are");
        let expected = area(&strip) - area(&clip_convex(&strip, &plant));
        let total: f64 = copies.iter().map(|q| area(q)).sum();
        assert!((total - expected).abs() < 1e-12, "{total} vs {expected}");
        // The 24-gon's middle lies in the strip: every edge but those beyond the strip's
        // sides gives a piece, far fewer than the 24 + 1 an edge-by-edge split may give.
        assert!(once.len() <= 25, "{}", once.len());
    }

    #[test]
    fn copies_moved_by_rounding_errors_add_no_pieces() {
        // Copies whose poses differ in the last bits (a yaw of 0.3 and 0.3 + 1 ulp, positions
        // 1e-15 m apart): their edge lines coincide up to the tolerance.
        let strip = square(0.5, 3.0, 1.2, 5.0);
        let holes: Vec<Vec<Point2>> = (0..16)
            .map(|k| {
                let e = f64::from(k % 3) * 1e-15;
                round(24, 0.25, 1.0 + e, 3.95 - e, 0.3 + e)
            })
            .collect();
        let parts = subtract_all(&strip, &holes);
        let once = subtract_convex(&strip, &holes[0]);
        assert_eq!(parts.len(), once.len());
        let total: f64 = parts.iter().map(|q| area(q)).sum();
        let expected: f64 = once.iter().map(|q| area(q)).sum();
        assert!((total - expected).abs() < 1e-12, "{total} vs {expected}");
    }

    #[test]
    fn distinct_holes_leave_pieces_bounded_by_their_lines() {
        // 40 round holes 1 mm apart along a line through the strip: genuine, different
        // edges. Every piece lies in one cell of the arrangement of the 40 x 12 edge lines,
        // and in practice the count grows about linearly with the holes.
        let strip = square(0.0, 0.0, 4.0, 0.4);
        let holes: Vec<Vec<Point2>> = (0..40)
            .map(|k| round(12, 0.3, 1.0 + 0.001 * f64::from(k), 0.2, 0.1 * f64::from(k)))
            .collect();
        let parts = subtract_all(&strip, &holes);
        assert!(parts.len() < 40 * 12, "{} pieces", parts.len());
        // Area: the strip minus the union, which lies between the first hole's area in the
        // strip and the strip's span of the holes' x range.
        let total: f64 = parts.iter().map(|q| area(q)).sum();
        let first = area(&clip_convex(&strip, &holes[0]));
        assert!(total <= area(&strip) - first + 1e-12);
        assert!(total >= area(&strip) - 0.4 * (0.6 + 0.039) - 1e-12, "{total}");
    }

    #[test]
    fn a_touching_or_distant_hole_leaves_the_subject_whole() {
        let a = square(0.0, 0.0, 2.0, 2.0);
        // Touching along x = 2, at a corner, and 1 ulp short of touching.
        for hole in [
            square(2.0, 0.5, 3.0, 1.5),
            square(2.0, 2.0, 3.0, 3.0),
            square(2.0 - 2.0 * f64::EPSILON, 0.5, 3.0, 1.5),
        ] {
            assert_eq!(subtract_convex(&a, &hole), vec![a.clone()]);
        }
        // Far beyond the hole's last edge yet across the line of its first one: an
        // edge-by-edge split would cut the subject in two along that line.
        let diamond = vec![p(5.0, 4.0), p(6.0, 5.0), p(5.0, 6.0), p(4.0, 5.0)];
        let b = square(-1.0, 0.0, 3.0, 2.0);
        assert_eq!(subtract_convex(&b, &diamond), vec![b.clone()]);
        // A clockwise subject is as good as a counter-clockwise one.
        let mut cw = square(1.0, 1.0, 3.0, 3.0);
        cw.reverse();
        let total: f64 = subtract_convex(&cw, &a).iter().map(|q| area(q)).sum();
        assert!((total - 3.0).abs() < 1e-12, "{total}");
    }

    #[test]
    fn distances_and_containment() {
        let a = square(0.0, 0.0, 2.0, 2.0);
        assert_eq!(convex_distance(&a, &p(1.0, 1.0)), 0.0);
        assert!((convex_distance(&a, &p(3.0, 1.0)) - 1.0).abs() < 1e-12);
        assert!((convex_distance(&a, &p(3.0, 3.0)) - 2f64.sqrt()).abs() < 1e-12);
        assert!(convex_contains(&a, &p(2.0, 1.0), 0.0));
        assert!(!convex_contains(&a, &p(2.1, 1.0), 0.0));
        assert!(is_convex(&a));
        assert!(!is_convex(&[
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(1.0, 0.5),
            p(2.0, 2.0),
            p(0.0, 2.0)
        ]));
    }
}
