//! The floors as disjoint convex pieces and their exposed outline; the loop helpers and
//! polygon clipping come from `sceneeval_geom::planar`.

pub(crate) use sceneeval_geom::planar::{
    area, bounds, boxes_overlap, ccw, clip_convex, clip_half_space, clip_half_space_into, convex_contains,
    convex_hull, convex_hull_fast, is_convex, orient, subtract_convex,
};
use std::collections::HashMap;

use sceneeval_geom::{Point2, Point3, Polygon2, Real, Vector2};

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
    // Whether each piece was cut by an earlier room's floor.
    let mut cut: Vec<bool> = Vec::new();
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
            let mut split = false;
            for prev in &out[..earlier] {
                if prev.room == room {
                    continue;
                }
                parts = parts
                    .iter()
                    .flat_map(|p| {
                        if boxes_overlap(&bounds(p), &prev.bounds) {
                            split = true;
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
                    cut.push(split);
                }
            }
        }
    }
    mark_internal_edges(&mut out, &cut);
    out
}

/// Marks each piece edge that borders another piece as internal (`outer[k] = false`): one
/// whose outer side, probed 1e-6 m beyond its midpoint, lies in another piece.
///
/// Pieces of one room that come straight from its triangulation share their internal edges
/// exactly (end points swapped), which a hash of the edges finds without a probe; the probe is
/// tested only against the pieces that can contain it otherwise: those of other rooms and
/// those cut by another room's floor, each after a bounding-box test. A single room of `n`
/// vertices is thus marked in `O(n)`; the probes grow with the pieces of rooms that overlap
/// or touch.
fn mark_internal_edges(pieces: &mut [FloorPiece], cut: &[bool]) {
    let key = |a: &Point2, b: &Point2| [a.x.to_bits(), a.y.to_bits(), b.x.to_bits(), b.y.to_bits()];
    let mut edges: HashMap<[u64; 4], usize> = HashMap::new();
    for (i, piece) in pieces.iter().enumerate() {
        let n = piece.poly.len();
        for k in 0..n {
            edges.insert(key(&piece.poly[k], &piece.poly[(k + 1) % n]), i);
        }
    }
    // Pieces are stored room by room: the range of each room's pieces, and the cut ones.
    let mut rooms: Vec<(usize, std::ops::Range<usize>)> = Vec::new();
    for (j, piece) in pieces.iter().enumerate() {
        match rooms.last_mut() {
            Some((room, range)) if *room == piece.room => range.end = j + 1,
            _ => rooms.push((piece.room, j..j + 1)),
        }
    }
    let cut_pieces: Vec<usize> = (0..pieces.len()).filter(|&j| cut[j]).collect();
    let probe_candidates = |i: usize, probe: &Point2| {
        let room = pieces[i].room;
        let in_piece = |j: usize| {
            let other = &pieces[j];
            j != i
                && probe.x >= other.bounds.0.x
                && probe.x <= other.bounds.1.x
                && probe.y >= other.bounds.0.y
                && probe.y <= other.bounds.1.y
                && convex_contains(&other.poly, probe, 0.0)
        };
        let others = rooms
            .iter()
            .filter(|(r, _)| *r != room)
            .any(|(_, range)| range.clone().any(in_piece));
        // A cut piece may meet any piece of its room; other pieces only the cut ones.
        others
            || match rooms.iter().find(|(r, _)| *r == room) {
                Some((_, range)) if cut[i] => range.clone().any(in_piece),
                _ => cut_pieces
                    .iter()
                    .copied()
                    .filter(|&j| pieces[j].room == room)
                    .any(in_piece),
            }
    };
    let outer: Vec<Vec<bool>> = pieces
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
                    if let Some(&j) = edges.get(&key(&b, &a))
                        && j != i
                        && pieces[j].room == piece.room
                    {
                        return false;
                    }
                    // The piece is counter-clockwise: its outside is to the right of each edge.
                    let probe = a + d * 0.5 + Vector2::new(d.y, -d.x) * (1e-6 / len);
                    #[cfg(test)]
                    tests::PROBES.with(|c| c.set(c.get() + 1));
                    !probe_candidates(i, &probe)
                })
                .collect()
        })
        .collect();
    for (piece, outer) in pieces.iter_mut().zip(outer) {
        piece.outer = outer;
    }
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
    use sceneeval_geom::planar::signed_area;
    use std::cell::Cell;

    thread_local! {
        /// Edge probes made by `mark_internal_edges` on this thread.
        pub(super) static PROBES: Cell<usize> = const { Cell::new(0) };
    }

    #[test]
    fn one_large_concave_floor_is_split_without_pairwise_probes() {
        // A wobbly, concave 20,000-gon: 19,998 triangles. Internal edges are found by hashing;
        // only the outline's edges are probed, each against no piece of another room.
        let n = 20_000;
        let floor = Polygon2::new(sceneeval_test_support::wobbly_outline(n)).unwrap();
        PROBES.with(|c| c.set(0));
        let pieces = floor_pieces(&[(&floor, 0.0)]);
        assert_eq!(pieces.len(), n as usize - 2);
        assert_eq!(PROBES.with(Cell::get), n as usize, "one probe per outline edge");
        let outer = pieces.iter().flat_map(|p| &p.outer).filter(|&&o| o).count();
        assert_eq!(outer, n as usize, "exactly the outline's edges are outer");
        let total: Real = pieces.iter().map(|p| area(&p.poly)).sum();
        assert!((total - floor.area()).abs() < 1e-6 * floor.area());
    }

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
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
