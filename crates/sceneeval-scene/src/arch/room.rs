//! Rooms: a floor polygon at a height, the walls around it and an optional ceiling, with
//! everything the relation and plausibility queries read prepared once.

use std::collections::HashMap;
use std::sync::Arc;

use sceneeval_geom::planar::convex_hull;
use sceneeval_geom::{Aabb, Mesh, Point2, Point3, Polygon2, Real, Vector2};

use super::PlacedOpening;
use super::wall::{InwardEvidence, Wall, WallSpec};
use crate::{Element, RoomId, SceneError};

/// A room's floor as given: an outline at a height.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Floor {
    /// The floor element's id (the reference uses `floor_<roomId>`).
    pub id: String,
    /// Its outline on the floor plan (either winding).
    pub polygon: Polygon2,
    /// World z of the floor surface.
    pub z: Real,
}

/// A room's ceiling given explicitly by the scene file.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Ceiling {
    /// The ceiling element's id.
    pub id: String,
    /// Its outline on the floor plan.
    pub polygon: Polygon2,
    /// World z of the ceiling surface.
    pub z: Real,
}

/// A room: a floor polygon at a height, the walls around it, and optionally a ceiling.
///
/// Construction prepares, once, everything queries need: each wall's orientation and its
/// solid (boxes and mesh, see [`Wall`]), the floor and ceiling triangulations and meshes, the
/// doors and windows as boxes ([`Room::openings`]), the floor's centroid, bounds, minimum-area
/// rectangle and, for a convex floor, its edges as half-planes. Queries about objects
/// (relations, plausibility metrics) only borrow the room, so moving objects never prepares a
/// room again.
#[derive(Debug, Clone, PartialEq)]
pub struct Room {
    id: RoomId,
    kind: Option<String>,
    floor: Floor,
    walls: Vec<Wall>,
    ceiling: Option<Ceiling>,
    ceiling_z: Option<Real>,
    floor_mesh: Arc<Mesh>,
    ceiling_mesh: Option<Arc<Mesh>>,
    floor_triangles: Vec<[Point2; 3]>,
    ceiling_triangles: Vec<[Point3; 3]>,
    centroid: Point2,
    bounds: (Point2, Point2),
    rectangle: (Point2, Vector2),
    convex_floor: Vec<(Vector2, Real)>,
    openings: Vec<PlacedOpening>,
}

impl Room {
    /// A room from its floor and its walls, each oriented into this floor, and an optional
    /// explicit ceiling.
    ///
    /// # Errors
    /// [`SceneError::NonFiniteRoom`] for a non-finite floor or ceiling height,
    /// [`SceneError::CeilingBelowFloor`] for an explicit ceiling at or below the floor, and the
    /// wall and opening errors of each wall (see [`SceneError`]), each naming its element.
    pub fn new(
        id: impl Into<RoomId>,
        floor: Floor,
        walls: Vec<WallSpec>,
        ceiling: Option<Ceiling>,
    ) -> Result<Self, SceneError> {
        let id = id.into();
        if !floor.z.is_finite() {
            return Err(SceneError::NonFiniteRoom {
                element: Box::new(Element::Floor { room: id }),
                what: "floor height",
            });
        }
        if let Some(c) = &ceiling {
            if !c.z.is_finite() {
                return Err(SceneError::NonFiniteRoom {
                    element: Box::new(Element::Ceiling { room: id }),
                    what: "ceiling height",
                });
            }
            if c.z <= floor.z {
                return Err(SceneError::CeilingBelowFloor {
                    room: id,
                    floor_z: floor.z,
                    ceiling_z: c.z,
                });
            }
        }
        let sides = FloorSides::new(&floor.polygon);
        let walls = walls
            .into_iter()
            .enumerate()
            .map(|(i, w)| Wall::new(w, &id, i, |a, b| sides.inward(&floor.polygon, a, b)))
            .collect::<Result<Vec<_>, _>>()?;
        warn_on_repeated_opening_ids(&walls);
        let mut openings = Vec::new();
        for (wi, w) in walls.iter().enumerate() {
            for (k, o) in w.openings().iter().enumerate() {
                openings.push(PlacedOpening {
                    wall: wi,
                    opening: k,
                    kind: o.kind,
                    obb: w.opening_obb(o),
                });
            }
        }

        let floor_element = || Element::Floor { room: id.clone() };
        let floor_tris = floor.polygon.triangulate();
        let floor_mesh =
            flat_mesh(&floor.polygon, &floor_tris, floor.z, true).map_err(|source| SceneError::Geometry {
                element: Box::new(floor_element()),
                source,
            })?;
        let floor_triangles = floor_tris
            .iter()
            .map(|t| t.map(|i| floor.polygon.points()[i]))
            .collect();

        let ceiling_z = ceiling
            .as_ref()
            .map(|c| c.z)
            .or_else(|| walls.iter().map(Wall::top_z).reduce(Real::max));
        if let (None, Some(z)) = (&ceiling, ceiling_z)
            && z <= floor.z
        {
            tracing::warn!(room = %id, floor_z = floor.z, walls_top = z, "the walls' tops are not above the floor");
        }
        let (ceiling_mesh, ceiling_triangles) = match ceiling_z {
            Some(z) => {
                let poly = ceiling.as_ref().map_or(&floor.polygon, |c| &c.polygon);
                let tris = if ceiling.is_some() {
                    poly.triangulate()
                } else {
                    floor_tris.clone()
                };
                let mesh = flat_mesh(poly, &tris, z, false).map_err(|source| SceneError::Geometry {
                    element: Box::new(Element::Ceiling { room: id.clone() }),
                    source,
                })?;
                let triangles = tris
                    .iter()
                    .map(|t| {
                        t.map(|i| {
                            let p = poly.points()[i];
                            Point3::new(p.x, p.y, z)
                        })
                    })
                    .collect();
                (Some(Arc::new(mesh)), triangles)
            }
            None => (None, Vec::new()),
        };
        Ok(Room {
            centroid: floor.polygon.centroid(),
            bounds: floor.polygon.bounds(),
            rectangle: min_area_rectangle(floor.polygon.points()),
            convex_floor: convex_half_planes(&floor.polygon),
            id,
            kind: None,
            floor,
            walls,
            ceiling,
            ceiling_z,
            floor_mesh: Arc::new(floor_mesh),
            ceiling_mesh,
            floor_triangles,
            ceiling_triangles,
            openings,
        })
    }

    /// Sets the room type (e.g. `bedroom`), used to resolve annotations that name a room type.
    pub fn with_kind(mut self, kind: impl Into<String>) -> Self {
        self.kind = Some(kind.into());
        self
    }

    /// The room id.
    #[inline]
    pub fn id(&self) -> &RoomId {
        &self.id
    }

    /// The room type, if known.
    #[inline]
    pub fn kind(&self) -> Option<&str> {
        self.kind.as_deref()
    }

    /// The floor element's id.
    #[inline]
    pub fn floor_id(&self) -> &str {
        &self.floor.id
    }

    /// The floor outline.
    #[inline]
    pub fn floor(&self) -> &Polygon2 {
        &self.floor.polygon
    }

    /// The floor as given (id, outline, height).
    #[inline]
    pub fn floor_spec(&self) -> &Floor {
        &self.floor
    }

    /// World z of the floor surface.
    #[inline]
    pub fn floor_z(&self) -> Real {
        self.floor.z
    }

    /// The walls, oriented into this room.
    #[inline]
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// Every door and window of the room, in wall order, with its box.
    #[inline]
    pub fn openings(&self) -> &[PlacedOpening] {
        &self.openings
    }

    /// The explicit ceiling, if the scene gave one.
    #[inline]
    pub fn explicit_ceiling(&self) -> Option<&Ceiling> {
        self.ceiling.as_ref()
    }

    /// World z of the ceiling: the explicit ceiling's, else the highest wall top, else `None`
    /// (a room without walls or ceiling has no ceiling). The reference instead raises every
    /// floor by the tallest wall of the whole scene.
    #[inline]
    pub fn ceiling_z(&self) -> Option<Real> {
        self.ceiling_z
    }

    /// The ceiling's outline: the explicit ceiling's, else the floor's.
    pub fn ceiling_polygon(&self) -> &Polygon2 {
        self.ceiling.as_ref().map_or(&self.floor.polygon, |c| &c.polygon)
    }

    /// The floor as a flat triangulated surface at `floor_z` (normals up).
    #[inline]
    pub fn floor_mesh(&self) -> &Arc<Mesh> {
        &self.floor_mesh
    }

    /// The ceiling as a flat surface at [`Room::ceiling_z`] (normals down), if there is one.
    #[inline]
    pub fn ceiling_mesh(&self) -> Option<&Arc<Mesh>> {
        self.ceiling_mesh.as_ref()
    }

    /// The floor's triangulation on the plan: counter-clockwise triangles covering the outline
    /// exactly.
    #[inline]
    pub fn floor_triangles(&self) -> &[[Point2; 3]] {
        &self.floor_triangles
    }

    /// The ceiling's triangulation at the ceiling height (empty without a ceiling).
    #[inline]
    pub fn ceiling_triangles(&self) -> &[[Point3; 3]] {
        &self.ceiling_triangles
    }

    /// The floor polygon's area centroid.
    #[inline]
    pub fn floor_centroid(&self) -> Point2 {
        self.centroid
    }

    /// Lowest and highest corners of the floor's bounding rectangle (world axes).
    #[inline]
    pub fn floor_bounds(&self) -> (Point2, Point2) {
        self.bounds
    }

    /// The floor's minimum-area enclosing rectangle: its centre and its two side lengths
    /// (metres). For an axis-aligned room this is the bounding rectangle; unlike that, it does
    /// not change when the room is turned.
    #[inline]
    pub fn floor_rectangle(&self) -> (Point2, Vector2) {
        self.rectangle
    }

    /// Whether the plan point `(x, y)` lies in the (closed) floor, when the floor is convex
    /// (its edges prepared as half-planes: a handful of multiplications); `None` for a
    /// non-convex floor, which needs [`Polygon2::contains_point`].
    #[inline]
    pub fn convex_floor_contains(&self, x: Real, y: Real) -> Option<bool> {
        if self.convex_floor.is_empty() {
            return None;
        }
        Some(self.convex_floor.iter().all(|(n, c)| n.x * x + n.y * y >= *c))
    }

    /// The floor's bounding box in world coordinates (flat, at `floor_z`).
    pub fn floor_aabb(&self) -> Aabb {
        let (min, max) = self.bounds;
        Aabb::new(
            Point3::new(min.x, min.y, self.floor.z),
            Point3::new(max.x, max.y, self.floor.z),
        )
    }
}

/// Warns about two openings of one room (on different walls) that share an id: reports name
/// openings by id, so such a pair cannot be told apart there. (Within one wall it is an error.)
fn warn_on_repeated_opening_ids(walls: &[Wall]) {
    let mut seen: HashMap<&str, &Wall> = HashMap::new();
    for w in walls {
        for o in w.openings() {
            if let Some(first) = seen.insert(&o.id, w)
                && !std::ptr::eq(first, w)
            {
                tracing::warn!(opening = %o.id, first = %first.element(), second = %w.element(), "two walls of one room have an opening with this id");
            }
        }
    }
}

/// The floor's edges by their end points, for deciding a wall's inward side without a
/// point-in-polygon test when the wall lies on a floor edge (the usual case): the floor's
/// side of its edge `a -> b` is the left for a counter-clockwise outline.
struct FloorSides {
    /// Edge end points (bit patterns) to "the floor is left of start -> end".
    edges: HashMap<[u64; 4], bool>,
}

impl FloorSides {
    fn new(floor: &Polygon2) -> Self {
        let ccw = floor.is_ccw();
        let key = |a: &Point2, b: &Point2| [a.x.to_bits(), a.y.to_bits(), b.x.to_bits(), b.y.to_bits()];
        let mut edges = HashMap::with_capacity(2 * floor.len());
        for (a, b) in floor.edges() {
            edges.insert(key(&a, &b), ccw);
            edges.insert(key(&b, &a), !ccw);
        }
        FloorSides { edges }
    }

    /// The inward normal of the wall `start -> end` and how it was decided.
    fn inward(&self, floor: &Polygon2, start: &Point2, end: &Point2) -> (Vector2, InwardEvidence) {
        let d = end - start;
        let left = Vector2::new(-d.y, d.x) / d.norm();
        let key = [
            start.x.to_bits(),
            start.y.to_bits(),
            end.x.to_bits(),
            end.y.to_bits(),
        ];
        if let Some(&floor_on_left) = self.edges.get(&key) {
            let n = if floor_on_left { left } else { -left };
            return (n, InwardEvidence::Floor);
        }
        inward_by_floor(floor, start, end, left)
    }
}

/// Decides which side of the segment faces into `floor` by point-in-polygon tests beside it
/// (see [`InwardEvidence`]).
fn inward_by_floor(
    floor: &Polygon2,
    start: &Point2,
    end: &Point2,
    left: Vector2,
) -> (Vector2, InwardEvidence) {
    let d = end - start;
    for frac in [0.5, 0.25, 0.75, 0.1, 0.9] {
        let m = start + d * frac;
        for delta in [1e-3, 1e-2, 5e-2, 0.2, 0.5] {
            #[cfg(test)]
            tests::SIDE_TESTS.with(|c| c.set(c.get() + 1));
            let a = floor.contains_point(&(m + left * delta));
            let b = floor.contains_point(&(m - left * delta));
            if a != b {
                return (if a { left } else { -left }, InwardEvidence::Floor);
            }
        }
    }
    let mid = start + d * 0.5;
    let toward = floor.centroid() - mid;
    (
        if left.dot(&toward) >= 0.0 { left } else { -left },
        InwardEvidence::Centroid,
    )
}

/// A flat triangulated polygon at height `z` from its triangulation, normals up (`up`) or down.
fn flat_mesh(
    poly: &Polygon2,
    triangulation: &[[usize; 3]],
    z: Real,
    up: bool,
) -> Result<Mesh, sceneeval_geom::GeomError> {
    let vertices = poly.points().iter().map(|p| Point3::new(p.x, p.y, z)).collect();
    let tris = triangulation
        .iter()
        .map(|&[a, b, c]| {
            if up {
                [a as u32, b as u32, c as u32]
            } else {
                [a as u32, c as u32, b as u32]
            }
        })
        .collect();
    Mesh::new(vertices, tris)
}

/// The inward half-planes of a convex polygon's edges, or nothing when it is not convex.
fn convex_half_planes(floor: &Polygon2) -> Vec<(Vector2, Real)> {
    let pts = floor.points();
    let n = pts.len();
    let sign = if floor.is_ccw() { 1.0 } else { -1.0 };
    let convex = (0..n).all(|i| {
        let (a, b, c) = (pts[i], pts[(i + 1) % n], pts[(i + 2) % n]);
        sign * (b - a).perp(&(c - b)) >= 0.0
    });
    if !convex {
        return Vec::new();
    }
    floor
        .edges()
        .map(|(a, b)| {
            let d = (b - a) * sign;
            // Left of a counter-clockwise edge: (-d.y, d.x) . p >= (-d.y, d.x) . a.
            let normal = Vector2::new(-d.y, d.x);
            (normal, normal.dot(&a.coords))
        })
        .collect()
}

/// Hulls up to this size are scanned in full for every edge direction; larger ones use
/// rotating calipers.
const FULL_SCAN_HULL: usize = 64;

/// The minimum-area rectangle enclosing `points`, over the convex hull's edge directions: its
/// centre and side lengths. The first minimum in hull order wins ties.
///
/// For each edge direction `u` (and its normal `v`) the extreme projections of the hull are
/// needed. Small hulls are scanned in full; for larger ones the four extreme points are
/// carried around the hull as `u` turns (rotating calipers: each only moves forward), so the
/// cost is linear after the hull's `n log n`.
fn min_area_rectangle(points: &[Point2]) -> (Point2, Vector2) {
    let hull = convex_hull(points);
    let m = hull.len();
    let mut best: Option<(Real, Point2, Vector2)> = None;
    // Indices of the points with the largest u, smallest u, largest v, smallest v.
    let mut calipers: Option<[usize; 4]> = None;
    for i in 0..m {
        let e = hull[(i + 1) % m] - hull[i];
        let Some(u) = e.try_normalize(0.0) else {
            continue;
        };
        let v = Vector2::new(-u.y, u.x);
        let (u0, u1, v0, v1) = if m <= FULL_SCAN_HULL {
            let (mut u0, mut u1, mut v0, mut v1) = (
                Real::INFINITY,
                Real::NEG_INFINITY,
                Real::INFINITY,
                Real::NEG_INFINITY,
            );
            for p in &hull {
                let (a, b) = (u.dot(&p.coords), v.dot(&p.coords));
                u0 = u0.min(a);
                u1 = u1.max(a);
                v0 = v0.min(b);
                v1 = v1.max(b);
            }
            (u0, u1, v0, v1)
        } else {
            // Signed projections to maximise: +u, -u, +v, -v.
            let f = |k: usize, p: usize| {
                let c = hull[p % m].coords;
                match k {
                    0 => u.dot(&c),
                    1 => -u.dot(&c),
                    2 => v.dot(&c),
                    _ => -v.dot(&c),
                }
            };
            let c = calipers.get_or_insert_with(|| {
                std::array::from_fn(|k| {
                    (0..m)
                        .reduce(|a, b| if f(k, b) > f(k, a) { b } else { a })
                        .unwrap_or(0)
                })
            });
            for (k, at) in c.iter_mut().enumerate() {
                for _ in 0..m {
                    if f(k, *at + 1) > f(k, *at) {
                        *at = (*at + 1) % m;
                    } else {
                        break;
                    }
                }
            }
            (-f(1, c[1]), f(0, c[0]), -f(3, c[3]), f(2, c[2]))
        };
        let area = (u1 - u0) * (v1 - v0);
        if best.is_none_or(|(a, _, _)| area < a) {
            let centre = Point2::from(u * (0.5 * (u0 + u1)) + v * (0.5 * (v0 + v1)));
            best = Some((area, centre, Vector2::new(u1 - u0, v1 - v0)));
        }
    }
    best.map_or((Point2::origin(), Vector2::zeros()), |(_, c, d)| (c, d))
}

#[cfg(test)]
pub(super) mod tests {
    use std::cell::Cell;

    use super::*;
    use crate::RoomBuilder;

    thread_local! {
        /// Point-in-polygon side tests made by `inward_by_floor` on this thread.
        pub(in crate::arch) static SIDE_TESTS: Cell<usize> = const { Cell::new(0) };
    }

    #[test]
    fn walls_on_floor_edges_need_no_point_in_polygon_test() {
        // A concave 30,000-gon with one wall per edge: every wall lies on a floor edge, so no
        // side test runs (each would cost 30,000 edge checks, 9e8 for all).
        let n = 30_000;
        let outline = sceneeval_test_support::wobbly_outline(n);
        SIDE_TESTS.with(|c| c.set(0));
        let room = RoomBuilder::polygon("disc", outline).build().unwrap();
        assert_eq!(SIDE_TESTS.with(Cell::get), 0);
        assert_eq!(room.walls().len(), n as usize);
        // Inward = toward the centre.
        let w = &room.walls()[123];
        let mid = w.start() + w.direction() * (0.5 * w.length());
        assert!(w.inward_normal().dot(&(Point2::origin() - mid)) > 0.0);
        // A wall off the floor's edges still gets the side tests (one pair decides here).
        let floor = room.floor_spec().clone();
        let inner = WallSpec::new(
            "inner",
            Point2::new(-1.0, 0.0),
            Point2::new(1.0, 0.0),
            0.0,
            2.0,
            0.0,
        );
        SIDE_TESTS.with(|c| c.set(0));
        let r = Room::new("r", floor, vec![inner], None).unwrap();
        assert!(SIDE_TESTS.with(Cell::get) > 0);
        assert_eq!(r.walls()[0].inward_evidence(), InwardEvidence::Centroid);
    }

    #[test]
    fn rotating_calipers_match_the_full_scan() {
        // A convex 200-gon (ellipse, turned): the calipers give the same rectangle as scanning
        // every hull point for every edge direction.
        let pts: Vec<Point2> = (0..200)
            .map(|i| {
                let a = std::f64::consts::TAU * f64::from(i) / 200.0;
                let (x, y) = (3.0 * a.cos(), 1.5 * a.sin());
                Point2::new(0.8 * x - 0.6 * y + 1.0, 0.6 * x + 0.8 * y - 2.0)
            })
            .collect();
        let (c, d) = min_area_rectangle(&pts);
        let hull = convex_hull(&pts);
        let mut best = (Real::INFINITY, Point2::origin(), Vector2::zeros());
        for i in 0..hull.len() {
            let u = (hull[(i + 1) % hull.len()] - hull[i]).normalize();
            let v = Vector2::new(-u.y, u.x);
            let pu: Vec<Real> = hull.iter().map(|p| u.dot(&p.coords)).collect();
            let pv: Vec<Real> = hull.iter().map(|p| v.dot(&p.coords)).collect();
            let (u0, u1) = (
                pu.iter().copied().fold(Real::INFINITY, Real::min),
                pu.iter().copied().fold(Real::NEG_INFINITY, Real::max),
            );
            let (v0, v1) = (
                pv.iter().copied().fold(Real::INFINITY, Real::min),
                pv.iter().copied().fold(Real::NEG_INFINITY, Real::max),
            );
            let area = (u1 - u0) * (v1 - v0);
            if area < best.0 {
                best = (
                    area,
                    Point2::from(u * (0.5 * (u0 + u1)) + v * (0.5 * (v0 + v1))),
                    Vector2::new(u1 - u0, v1 - v0),
                );
            }
        }
        assert!(
            (c - best.1).norm() < 1e-12 && (d - best.2).norm() < 1e-12,
            "{c} {d} vs {:?}",
            best
        );
    }
}
