//! Exact helpers on point loops in the plane (world x, y): orientation, areas, convex hulls,
//! convex clipping and subtraction, point distances; and clipping of polygons in the plane or
//! in space by a half space ([`clip_half_space`]). Unlike [`crate::Polygon2`] they take plain
//! slices and do not validate: "convex polygon" means a counter-clockwise loop without reflex
//! corners, and degenerate loops (fewer than three points) are handled as points or segments
//! where the function says so.

use crate::{Point2, Real};

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

/// Distance from `p` to the segment `a b`.
pub fn point_segment_distance(p: &Point2, a: &Point2, b: &Point2) -> Real {
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

/// `subject \ hole` for convex `subject` and convex counter-clockwise `hole`, as disjoint convex
/// pieces (for each edge of `hole`, the part of what is left beyond that edge).
pub fn subtract_convex(subject: &[Point2], hole: &[Point2]) -> Vec<Vec<Point2>> {
    let m = hole.len();
    if m < 3 {
        return vec![subject.to_vec()];
    }
    let mut pieces = Vec::new();
    let mut rest = subject.to_vec();
    for k in 0..m {
        if rest.len() < 3 {
            break;
        }
        let (a, b) = (hole[k], hole[(k + 1) % m]);
        let outside = clip_half_space(&rest, |p| -orient(&a, &b, p));
        if outside.len() >= 3 && area(&outside) > 0.0 {
            pieces.push(outside);
        }
        rest = clip_half_space(&rest, |p| orient(&a, &b, p));
    }
    pieces
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
