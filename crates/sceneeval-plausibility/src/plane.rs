//! Small exact 2-D helpers on convex polygons (counter-clockwise point loops): hull, clipping,
//! subtraction, areas and distances. Written here because `sceneeval-geom` keeps its clipper
//! private and works on validated simple polygons only.

use sceneeval_geom::{Point2, Point3, Polygon2, Real, Vector2};

/// Twice the signed area of the triangle `a b c` (positive counter-clockwise).
#[inline]
pub(crate) fn orient(a: &Point2, b: &Point2, c: &Point2) -> Real {
    (b - a).perp(&(c - a))
}

/// Signed area of a loop (positive counter-clockwise).
pub(crate) fn signed_area(poly: &[Point2]) -> Real {
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
pub(crate) fn area(poly: &[Point2]) -> Real {
    signed_area(poly).abs()
}

/// The loop made counter-clockwise.
pub(crate) fn ccw(mut poly: Vec<Point2>) -> Vec<Point2> {
    if signed_area(&poly) < 0.0 {
        poly.reverse();
    }
    poly
}

/// Convex hull (Andrew's monotone chain), counter-clockwise without collinear points. Fewer
/// than three points or collinear input give the distinct extreme points (0, 1 or 2).
pub(crate) fn convex_hull(points: &[Point2]) -> Vec<Point2> {
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
pub(crate) fn convex_hull_fast(points: &[Point2]) -> Vec<Point2> {
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
pub(crate) fn convex_contains(poly: &[Point2], p: &Point2, eps: Real) -> bool {
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
pub(crate) fn point_segment_distance(p: &Point2, a: &Point2, b: &Point2) -> Real {
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
pub(crate) fn convex_distance(poly: &[Point2], p: &Point2) -> Real {
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

/// Keeps the part of `poly` where `f(p) >= 0` for the affine function `f` (one
/// Sutherland-Hodgman step).
pub(crate) fn clip_half_plane(poly: &[Point2], f: impl Fn(&Point2) -> Real) -> Vec<Point2> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
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
    out
}

/// The intersection of a convex `subject` with the convex counter-clockwise `clip`.
pub(crate) fn clip_convex(subject: &[Point2], clip: &[Point2]) -> Vec<Point2> {
    let m = clip.len();
    let mut out = subject.to_vec();
    for k in 0..m {
        if out.len() < 3 {
            return Vec::new();
        }
        let (a, b) = (clip[k], clip[(k + 1) % m]);
        out = clip_half_plane(&out, |p| orient(&a, &b, p));
    }
    if out.len() < 3 { Vec::new() } else { out }
}

/// `subject \ hole` for convex `subject` and convex counter-clockwise `hole`, as disjoint convex
/// pieces (for each edge of `hole`, the part of what is left beyond that edge).
pub(crate) fn subtract_convex(subject: &[Point2], hole: &[Point2]) -> Vec<Vec<Point2>> {
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
        let outside = clip_half_plane(&rest, |p| -orient(&a, &b, p));
        if outside.len() >= 3 && area(&outside) > 0.0 {
            pieces.push(outside);
        }
        rest = clip_half_plane(&rest, |p| orient(&a, &b, p));
    }
    pieces
}

/// Bounding rectangle `(min, max)` of a non-empty loop.
pub(crate) fn bounds(poly: &[Point2]) -> (Point2, Point2) {
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
pub(crate) fn boxes_overlap(a: &(Point2, Point2), b: &(Point2, Point2)) -> bool {
    a.0.x <= b.1.x && b.0.x <= a.1.x && a.0.y <= b.1.y && b.0.y <= a.1.y
}

/// Whether a loop is convex (no reflex corner; collinear corners allowed).
pub(crate) fn is_convex(poly: &[Point2]) -> bool {
    let n = poly.len();
    let s = signed_area(poly).signum();
    (0..n).all(|i| orient(&poly[i], &poly[(i + 1) % n], &poly[(i + 2) % n]) * s >= 0.0)
}

/// Keeps the part of a 3-D polygon where `f(p) >= 0`.
pub(crate) fn clip_half_space(poly: &[Point3], f: impl Fn(&Point3) -> Real) -> Vec<Point3> {
    let n = poly.len();
    let mut out = Vec::with_capacity(n + 2);
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
    out
}

/// Area of a planar 3-D polygon.
pub(crate) fn area3(poly: &[Point3]) -> Real {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    let o = poly[0];
    let mut acc = sceneeval_geom::Vector3::zeros();
    for i in 1..n - 1 {
        acc += (poly[i] - o).cross(&(poly[i + 1] - o));
    }
    acc.norm() * 0.5
}

/// One piece of the union of all floors: a convex counter-clockwise polygon, disjoint from
/// every other piece, with the floor height of the room it came from.
#[derive(Debug, Clone)]
pub(crate) struct FloorPiece {
    pub poly: Vec<Point2>,
    pub floor_z: Real,
    pub room: usize,
    pub bounds: (Point2, Point2),
    /// Per edge `k` (from `poly[k]` to `poly[k + 1]`): whether it lies on the outline of the
    /// union of floors (its outer side, probed 1e-6 m from its midpoint, is in no piece) rather
    /// than between two pieces.
    pub outer: Vec<bool>,
}

impl FloorPiece {
    /// Signed distance of `p` inside edge `k`'s line (positive inside), with the edge moved
    /// `margin` outward if it is on the outline of the floors. Internal edges never move, so
    /// neighbouring pieces never overlap.
    pub fn inside_edge(&self, k: usize, p: &Point2, margin: Real) -> Real {
        let n = self.poly.len();
        let (a, b) = (self.poly[k], self.poly[(k + 1) % n]);
        let len = (b - a).norm();
        if len == 0.0 {
            return Real::INFINITY;
        }
        orient(&a, &b, p) / len + if self.outer[k] { margin } else { 0.0 }
    }

    /// Whether `p` lies in the piece with its outline edges moved `margin` outward.
    pub fn contains(&self, p: &Point2, margin: Real) -> bool {
        (0..self.poly.len()).all(|k| self.inside_edge(k, p, margin) >= 0.0)
    }
}

/// Splits the union of the rooms' floors into disjoint convex pieces. A convex floor is one
/// piece, a concave one is triangulated; where floors overlap in plan, the earlier room keeps
/// the overlap.
pub(crate) fn floor_pieces(floors: &[(&Polygon2, Real)]) -> Vec<FloorPiece> {
    let mut out: Vec<FloorPiece> = Vec::new();
    for (room, (poly, z)) in floors.iter().enumerate() {
        let pts = ccw(poly.points().to_vec());
        let own: Vec<Vec<Point2>> = if is_convex(&pts) {
            vec![pts]
        } else {
            poly.triangulate()
                .iter()
                .map(|t| ccw(t.iter().map(|&i| poly.points()[i]).collect()))
                .collect()
        };
        let earlier = out.len();
        for piece in own {
            let mut parts = vec![piece];
            for prev in &out[..earlier] {
                if prev.room == room {
                    continue;
                }
                parts = parts
                    .iter()
                    .flat_map(|p| {
                        if boxes_overlap(&bounds(p), &prev.bounds) {
                            subtract_convex(p, &prev.poly)
                        } else {
                            vec![p.clone()]
                        }
                    })
                    .collect();
            }
            for p in parts {
                if p.len() >= 3 && area(&p) > 0.0 {
                    let b = bounds(&p);
                    out.push(FloorPiece {
                        outer: vec![true; p.len()],
                        poly: p,
                        floor_z: *z,
                        room,
                        bounds: b,
                    });
                }
            }
        }
    }
    // An edge is internal when just beyond its midpoint lies another piece.
    let outer: Vec<Vec<bool>> = out
        .iter()
        .enumerate()
        .map(|(i, piece)| {
            let n = piece.poly.len();
            (0..n)
                .map(|k| {
                    let (a, b) = (piece.poly[k], piece.poly[(k + 1) % n]);
                    let d = b - a;
                    let len = d.norm();
                    if len == 0.0 {
                        return true;
                    }
                    // The piece is counter-clockwise: its outside is to the right of each edge.
                    let probe = a + d * 0.5 + Vector2::new(d.y, -d.x) * (1e-6 / len);
                    !out.iter()
                        .enumerate()
                        .any(|(j, other)| j != i && convex_contains(&other.poly, &probe, 0.0))
                })
                .collect()
        })
        .collect();
    for (piece, outer) in out.iter_mut().zip(outer) {
        piece.outer = outer;
    }
    out
}

/// The parts of the floors' outlines that border no other floor: pieces of edges whose outer
/// side (probed 1e-6 m away) lies in no floor. Shared edges between adjacent rooms are not
/// exposed.
pub(crate) fn exposed_boundary(floors: &[&Polygon2]) -> Vec<(Point2, Point2)> {
    let mut out = Vec::new();
    for (i, poly) in floors.iter().enumerate() {
        let pts = ccw(poly.points().to_vec());
        let n = pts.len();
        for k in 0..n {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            let d = b - a;
            let len = d.norm();
            if len == 0.0 {
                continue;
            }
            let mut ts = vec![0.0, 1.0];
            for (j, other) in floors.iter().enumerate() {
                if j == i {
                    continue;
                }
                for (c, e) in other.edges() {
                    ts.extend(split_params(&a, &b, &c, &e));
                }
            }
            ts.sort_by(|x, y| x.total_cmp(y));
            ts.dedup();
            // Outward of a counter-clockwise loop is to the right of the edge.
            let outward = sceneeval_geom::Vector2::new(d.y, -d.x) / len;
            for w in ts.windows(2) {
                let (t0, t1) = (w[0], w[1]);
                if (t1 - t0) * len <= 1e-9 {
                    continue;
                }
                let mid = a + d * (0.5 * (t0 + t1)) + outward * 1e-6;
                let covered = floors
                    .iter()
                    .enumerate()
                    .any(|(j, f)| j != i && f.contains_point(&mid));
                if !covered {
                    push_merged(&mut out, a + d * t0, a + d * t1);
                }
            }
        }
    }
    out
}

fn push_merged(out: &mut Vec<(Point2, Point2)>, p: Point2, q: Point2) {
    if let Some(last) = out.last_mut()
        && last.1 == p
        && orient(&last.0, &last.1, &q).abs() <= 1e-12 * (q - last.0).norm_squared()
    {
        last.1 = q;
        return;
    }
    out.push((p, q));
}

/// Parameters in (0, 1) along `a b` where the segment `c e` crosses or starts/ends on it.
fn split_params(a: &Point2, b: &Point2, c: &Point2, e: &Point2) -> Vec<Real> {
    let d = b - a;
    let len2 = d.norm_squared();
    let f = e - c;
    let denom = d.perp(&f);
    let tol = 1e-9 * len2.sqrt().max(1.0);
    let mut out = Vec::new();
    let dist_c = orient(a, b, c) / len2.sqrt();
    let dist_e = orient(a, b, e) / len2.sqrt();
    if dist_c.abs() <= tol && dist_e.abs() <= tol {
        // Collinear: the other segment's end points split this one.
        for p in [c, e] {
            let t = (p - a).dot(&d) / len2;
            if t > 0.0 && t < 1.0 {
                out.push(t);
            }
        }
        return out;
    }
    if denom != 0.0 {
        let w = c - a;
        let t = w.perp(&f) / denom;
        let s = w.perp(&d) / denom;
        if t > 0.0 && t < 1.0 && (-1e-12..=1.0 + 1e-12).contains(&s) {
            out.push(t);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
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

    #[test]
    fn floor_pieces_are_disjoint_and_cover_the_union() {
        let l = Polygon2::new(vec![
            p(0.0, 0.0),
            p(4.0, 0.0),
            p(4.0, 2.0),
            p(2.0, 2.0),
            p(2.0, 4.0),
            p(0.0, 4.0),
        ])
        .unwrap();
        let overlap = Polygon2::rectangle(p(1.0, 1.0), p(5.0, 3.0)).unwrap();
        let pieces = floor_pieces(&[(&l, 0.0), (&overlap, 0.0)]);
        let total: f64 = pieces.iter().map(|q| area(&q.poly)).sum();
        // L = 12, rectangle = 8, overlap with the L = [1,4]x[1,2] + [1,2]x[2,3] = 3 + 1 = 4.
        assert!((total - 16.0).abs() < 1e-9, "{total}");
        assert!(
            pieces
                .iter()
                .all(|q| is_convex(&q.poly) && signed_area(&q.poly) > 0.0)
        );
    }

    #[test]
    fn shared_edges_are_not_exposed() {
        let a = Polygon2::rectangle(p(0.0, 0.0), p(4.0, 4.0)).unwrap();
        let b = Polygon2::rectangle(p(4.0, 1.0), p(7.0, 3.0)).unwrap();
        let segs = exposed_boundary(&[&a, &b]);
        let total: f64 = segs.iter().map(|(s, e)| (e - s).norm()).sum();
        // Perimeters 16 + 10, minus the shared 2 m counted on both sides.
        assert!((total - 22.0).abs() < 1e-9, "{total}");
        let shared = segs.iter().any(|(s, e)| {
            let m = s + (e - s) * 0.5;
            (m.x - 4.0).abs() < 1e-12 && m.y > 1.0 && m.y < 3.0
        });
        assert!(!shared);
    }

    #[test]
    fn clip3_keeps_upper_part() {
        let tri = [
            Point3::new(0.0, 0.0, -1.0),
            Point3::new(2.0, 0.0, -1.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        let up = clip_half_space(&tri, |q| q.z);
        // The part above z = 0 is the triangle (0,0,0) (1,0,0) (0,0,1): area 0.5 of 2.
        assert!((area3(&up) - 0.5).abs() < 1e-12);
        assert!((area3(&tri) - 2.0).abs() < 1e-12);
    }
}
