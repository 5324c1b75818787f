//! The 10 object-architecture predicates as kernels on one prepared room.
//!
//! Each kernel scores one object against one [`Room`]; over several rooms the
//! reference's "max over elements" is the maximum over rooms ([`score_rooms`]).
//!
//! # Performance
//! No kernel allocates (except `corner_of_room` in rooms of more than 32 walls, which sorts
//! their bounds in two vectors): a room's walls, wall pieces, openings and floor triangles
//! were prepared when the [`Room`] was built. Volume fractions clip
//! the object's box by at most five planes per wall or floor triangle. Elements are visited in
//! decreasing order of an upper bound on their score (from cheap lower and upper bounds on
//! their distance), and the search stops when no remaining element can beat the best score:
//! the result is the exact maximum, usually after one or two exact distance queries.

use sceneeval_geom::{ClosestPoints, Obb, Point3, Real, Vector3};

use crate::clip::{HalfSpace, box_volume_inside};
use crate::distance::{object_box_closest, object_triangle_closest};
use crate::pairwise::{FrameBox, effective_half, fraction_in_frame_box};
use crate::params::{CornerWalls, DistanceBand, DistanceFrom, RoomCentre};
use crate::{ArchElement, ObjectGeom, Relation, RelationError, RelationParams};
use sceneeval_scene::{Room, Wall};

/// The object as the distance terms see it (its box in [`DistanceFrom::SmallerBox`] mode),
/// and one point of it (for upper bounds on distances).
pub(crate) struct Probe<'a> {
    pub geom: ObjectGeom<'a>,
    point: Point3,
}

impl<'a> Probe<'a> {
    pub(crate) fn new(a: &ObjectGeom<'a>, params: &RelationParams) -> Self {
        let geom = match params.distance_from {
            DistanceFrom::Geometry => *a,
            DistanceFrom::SmallerBox => a.as_box(),
        };
        Probe::of(geom)
    }

    fn of(geom: ObjectGeom<'a>) -> Self {
        let point = match geom.mesh {
            None => geom.obb.center,
            Some((m, pose)) => m.vertices().first().map_or(geom.obb.center, |v| pose * v),
        };
        Probe { geom, point }
    }

    /// Exact distance to a solid box, with closest points (the object's first).
    #[inline]
    fn closest(&self, b: &Obb) -> ClosestPoints {
        object_box_closest(&self.geom, b)
    }

    /// A lower bound on [`Probe::distance`] (the object lies in its box).
    #[inline]
    fn lower_bound(&self, b: &Obb) -> Real {
        b.distance_lower_bound(self.geom.obb)
    }

    /// Exact distance to the union of `pieces`, skipping pieces that cannot be nearer than
    /// the nearest one found so far; with the closest points (the first of equally near
    /// pieces').
    fn closest_to_union(&self, pieces: &[Obb]) -> ClosestPoints {
        let mut best = ClosestPoints {
            distance: Real::INFINITY,
            points: None,
        };
        for piece in pieces {
            if self.lower_bound(piece) < best.distance {
                let c = self.closest(piece);
                if c.distance < best.distance {
                    best = c;
                }
            }
        }
        best
    }

    /// Lower and upper bounds on the distance to the union of `pieces` (the upper bound from
    /// one point of the object).
    fn bounds_union(&self, pieces: &[Obb]) -> (Real, Real) {
        pieces
            .iter()
            .fold((Real::INFINITY, Real::INFINITY), |(lo, hi), p| {
                (
                    lo.min(self.lower_bound(p)),
                    hi.min(p.distance_to_point(&self.point)),
                )
            })
    }

    /// Lower and upper bounds on the distance to one box.
    fn bounds(&self, b: &Obb) -> (Real, Real) {
        (self.lower_bound(b), b.distance_to_point(&self.point))
    }
}

/// The highest score `band` can give to a distance between `lo` and `hi`.
#[inline]
fn band_upper(band: &DistanceBand, (lo, hi): (Real, Real)) -> Real {
    if hi < band.min_m {
        band.score(hi)
    } else if lo > band.max_m {
        band.score(lo)
    } else {
        1.0
    }
}

/// Elements visited in decreasing order of an upper bound on their score, on the stack.
const ORDER_CAPACITY: usize = 32;

/// Calls `visit(i)` for `i` in `0..n` in decreasing order of `upper(i)` while `upper(i)` is
/// above the best score `visit` has returned so far; returns that best score (0 if none).
/// The element behind it is the first `visit` call that returned it.
/// Beyond [`ORDER_CAPACITY`] elements the rest are visited in index order, with the same
/// test. The result is the exact maximum: only elements that cannot beat it are skipped.
fn best_of(n: usize, upper: impl Fn(usize) -> Real, mut visit: impl FnMut(usize) -> Real) -> Real {
    let mut order = [(0.0, 0usize); ORDER_CAPACITY];
    let k = n.min(ORDER_CAPACITY);
    for (i, slot) in order.iter_mut().enumerate().take(k) {
        *slot = (upper(i), i);
    }
    order[..k].sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut best: Real = 0.0;
    for &(ub, i) in &order[..k] {
        if ub <= best {
            break;
        }
        best = best.max(visit(i));
    }
    for i in k..n {
        if upper(i) > best {
            best = best.max(visit(i));
        }
    }
    best
}

/// Distance from an object to a wall's solid (its slab with doors and windows cut out),
/// as the architecture relations measure it (the mesh when given).
pub fn wall_distance(target: &ObjectGeom<'_>, wall: &Wall) -> Real {
    Probe::of(*target).closest_to_union(wall.solid_boxes()).distance
}

/// The best score over a room's elements and the closest points behind it (the object's
/// first; `None` when no element scores above 0 or the object meets the best one).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Best {
    pub score: Real,
    pub closest: ClosestPoints,
}

impl Best {
    const NONE: Best = Best {
        score: 0.0,
        closest: ClosestPoints::MEETING,
    };

    /// Keeps `score` with `closest` when it beats the best so far (as [`best_of`]'s maximum:
    /// the first of equal scores).
    #[inline]
    fn offer(&mut self, score: Real, closest: ClosestPoints) -> Real {
        if score > self.score {
            *self = Best { score, closest };
        }
        score
    }
}

/// The best score of `band` over the elements of one kind (0 when the room has none; floors,
/// ceilings and rooms are not measured, see [`crate::DISTANCE_ELEMENTS`]).
fn element_band(
    target: &ObjectGeom<'_>,
    room: &Room,
    element: ArchElement,
    band: &DistanceBand,
    params: &RelationParams,
) -> Real {
    element_band_best(target, room, element, band, params).0
}

/// [`element_band`] and the element behind it.
pub(crate) fn element_band_best(
    target: &ObjectGeom<'_>,
    room: &Room,
    element: ArchElement,
    band: &DistanceBand,
    params: &RelationParams,
) -> (Real, Best) {
    let probe = Probe::new(target, params);
    let mut winner = Best::NONE;
    let score = match element {
        ArchElement::Wall => {
            let walls = room.walls();
            best_of(
                walls.len(),
                |i| band_upper(band, probe.bounds_union(walls[i].solid_boxes())),
                |i| {
                    let c = probe.closest_to_union(walls[i].solid_boxes());
                    winner.offer(band.score(c.distance), c)
                },
            )
        }
        _ => {
            // Doors and windows: the openings of that kind (none for the other kinds).
            let kind = element.opening();
            let openings = room.openings();
            best_of(
                openings.len(),
                |i| {
                    if Some(openings[i].kind) == kind {
                        band_upper(band, probe.bounds(&openings[i].obb))
                    } else {
                        0.0
                    }
                },
                |i| {
                    let c = probe.closest(&openings[i].obb);
                    winner.offer(band.score(c.distance), c)
                },
            )
        }
    };
    (score, winner)
}

/// `next_to(element)`: the best [0, 0.5] m band score over the room's walls, doors or windows.
pub fn next_to(target: &ObjectGeom<'_>, room: &Room, element: ArchElement, params: &RelationParams) -> Real {
    element_band(target, room, element, &params.arch_next_to, params)
}

/// `near(element)`: the best [0.5, 1.5] m band score.
pub fn near(target: &ObjectGeom<'_>, room: &Room, element: ArchElement, params: &RelationParams) -> Real {
    element_band(target, room, element, &params.arch_near, params)
}

/// `across_from(element)`: the best [1.5, 4] m band score.
pub fn across_from(
    target: &ObjectGeom<'_>,
    room: &Room,
    element: ArchElement,
    params: &RelationParams,
) -> Real {
    element_band(target, room, element, &params.arch_across_from, params)
}

/// `far(element)`: the best [4, inf) m band score.
pub fn far(target: &ObjectGeom<'_>, room: &Room, element: ArchElement, params: &RelationParams) -> Real {
    element_band(target, room, element, &params.arch_far, params)
}

/// `inside_room`: the fraction of the object's box volume that lies over the floor polygon
/// and above the floor.
///
/// The reference casts a ray down from each random sample of the box and counts those that
/// hit the floor. Here the box is clipped, exactly, by the three vertical planes of each floor
/// triangle and the floor plane (moved down by [`RelationParams::tolerance_m`]); the triangles
/// partition the floor, so the volumes add up. Exact for any rotation of the box.
///
/// ```
/// use sceneeval_relations::{arch, ObjectGeom, RelationParams};
/// use sceneeval_scene::RoomBuilder;
/// use sceneeval_geom::{Obb, Point2, na::{Point3, Vector3}};
/// let room = RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
///     .wall_height(2.8)
///     .wall_thickness(0.1)
///     .build()
///     .unwrap();
/// // A 1 m cube whose centre is on the wall line x = 4: half of it is over the floor.
/// let cube = Obb::from_yaw(Point3::new(4.0, 2.0, 0.5), Vector3::repeat(0.5), 0.0).unwrap();
/// let s = arch::inside_room(&ObjectGeom::from_box(&cube), &room, &RelationParams::default());
/// assert!((s - 0.5).abs() < 1e-12);
/// ```
pub fn inside_room(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> Real {
    let h = effective_half(target.obb, params);
    let full = 8.0 * h.x * h.y * h.z;
    match over_floor(target.obb, &h, room, params, box_volume_inside) {
        None => 1.0,
        Some(inside) => (inside / full).clamp(0.0, 1.0),
    }
}

/// The sum of `measure(h, planes)` over the floor triangles near the box `obb` (with half
/// extents `h`, the flat-box floor applied), `planes` being the triangle's prism above the
/// floor in the box's frame; `None` when the box lies wholly over a convex floor (a fraction
/// of 1).
pub(crate) fn over_floor<T: std::ops::AddAssign + Default>(
    obb: &Obb,
    h: &Vector3,
    room: &Room,
    params: &RelationParams,
    mut measure: impl FnMut(&Vector3, &[HalfSpace]) -> T,
) -> Option<T> {
    let aabb = obb.aabb();
    // Shortcut for a convex floor: a box whose eight corners are over the floor and above it
    // lies wholly in the floor's prism.
    let lowest = obb.center.z - (0..3).map(|j| obb.rotation[(2, j)].abs() * h[j]).sum::<Real>();
    if lowest >= room.floor_z() - params.tolerance_m {
        let corners_over_floor = (0..8).all(|k| {
            let l = Vector3::from_fn(|j, _| if k & (1 << j) == 0 { -h[j] } else { h[j] });
            let p = obb.to_world(&l);
            room.convex_floor_contains(p.x, p.y) == Some(true)
        });
        if corners_over_floor {
            return None;
        }
    }
    let r_t = obb.rotation.inverse();
    let local = |n: Vector3, offset: Real| HalfSpace::new(r_t * n, offset - n.dot(&obb.center.coords));
    let floor = local(
        Vector3::new(0.0, 0.0, -1.0),
        -(room.floor_z() - params.tolerance_m),
    );
    let mut inside = T::default();
    for tri in room.floor_triangles() {
        let (lo, hi) = (tri[0].inf(&tri[1]).inf(&tri[2]), tri[0].sup(&tri[1]).sup(&tri[2]));
        if hi.x < aabb.min.x || lo.x > aabb.max.x || hi.y < aabb.min.y || lo.y > aabb.max.y {
            continue;
        }
        let mut planes = [floor; 4];
        for (e, plane) in planes.iter_mut().skip(1).enumerate() {
            let (p, q) = (tri[e], tri[(e + 1) % 3]);
            let d = q - p;
            // Left of p -> q (the triangle is counter-clockwise): d.y x - d.x y <= d.y p.x - d.x p.y.
            *plane = local(Vector3::new(d.y, -d.x, 0.0), d.y * p.x - d.x * p.y);
        }
        inside += measure(h, &planes);
    }
    Some(inside)
}

/// `middle_of_room`: `exp(-d^2 / (2 sigma^2))` of the plan-view distance `d` from the room's
/// centre to the object's box centre, with
/// `sigma = base * (size_weight * o + ratio_weight * max(0, 1 - o / r))`, `o` the longer plan
/// side of the object's box and `r` the mean side of the floor's minimum-area enclosing
/// rectangle (the paper's `o/2 + (1 - o/r)` with the defaults).
///
/// The room's centre is the floor's area centroid ([`RoomCentre::AreaCentroid`], the paper's
/// "room's centroid") or the enclosing rectangle's centre ([`RoomCentre::BoundsCentre`]). The
/// reference uses the floor's world-axis bounding box for both; that is the same rectangle
/// for axis-aligned rooms (all of the reference's scenes), and the minimum rectangle keeps
/// the score unchanged when a room is turned. The reference lets `1 - o/r` go negative, which
/// shrinks sigma to zero or flips its sign for objects larger than the room's mean dimension;
/// here that term stops at 0.
pub fn middle_of_room(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> Real {
    let (rect_centre, dims) = room.floor_rectangle();
    let centre = match params.room_centre {
        RoomCentre::AreaCentroid => room.floor_centroid(),
        RoomCentre::BoundsCentre => rect_centre,
    };
    let c = target.obb.center;
    let (dx, dy) = (c.x - centre.x, c.y - centre.y);
    let r = 0.5 * (dims.x + dims.y);
    let e = target.obb.extents();
    let o = e.x.max(e.y);
    let ratio = if r > 0.0 { (1.0 - o / r).max(0.0) } else { 0.0 };
    let sigma = params.middle_of_room_base_sigma_m
        * (params.middle_of_room_size_weight * o + params.middle_of_room_ratio_weight * ratio);
    let d2 = dx * dx + dy * dy;
    if sigma <= 0.0 {
        return if d2 == 0.0 { 1.0 } else { 0.0 };
    }
    (-d2 / (2.0 * sigma * sigma)).exp()
}

/// The region in front of a wall's inner face (on the room side), within its length and
/// height (enlarged by `margin`), unbounded into the room; in the wall's frame centred on the
/// inner face.
fn in_front_fraction(obb: &Obb, wall: &Wall, params: &RelationParams) -> Real {
    let (origin, region) = in_front_region(wall, params);
    fraction_in_frame_box(obb, &wall.rotation(), &origin, &region, params)
}

/// The origin of the region of [`in_front_fraction`] (in the wall's frame) and the region.
pub(crate) fn in_front_region(wall: &Wall, params: &RelationParams) -> (Point3, FrameBox) {
    let origin = wall.point_on_inner_face(0.5 * wall.length(), 0.5 * wall.height());
    let m = 1.0 + params.region_margin;
    let (hx, hz) = (0.5 * wall.length() * m, 0.5 * wall.height() * m);
    // The wall frame's local -y points into the room, so "in front" is y <= 0.
    let region = FrameBox {
        lo: [-hx, Real::NEG_INFINITY, -hz],
        hi: [hx, params.tolerance_m, hz],
    };
    (origin, region)
}

/// `on_wall` and `against_wall`: the best over walls of (fraction of the box in front of the
/// wall) x (band score of the distance to the wall's solid).
fn wall_contact(target: &ObjectGeom<'_>, room: &Room, band: &DistanceBand, params: &RelationParams) -> Real {
    wall_contact_best(target, room, band, params).0
}

/// [`wall_contact`], the best wall's index and the closest points to it (`None` when no wall
/// scores above 0).
pub(crate) fn wall_contact_best(
    target: &ObjectGeom<'_>,
    room: &Room,
    band: &DistanceBand,
    params: &RelationParams,
) -> (Real, Option<(usize, ClosestPoints)>) {
    let probe = Probe::new(target, params);
    let walls = room.walls();
    let mut winner = (0.0, None);
    let score = best_of(
        walls.len(),
        |i| band_upper(band, probe.bounds_union(walls[i].solid_boxes())),
        |i| {
            let front = in_front_fraction(target.obb, &walls[i], params);
            if front == 0.0 {
                return 0.0;
            }
            let c = probe.closest_to_union(walls[i].solid_boxes());
            let s = front * band.score(c.distance);
            if s > winner.0 {
                winner = (s, Some((i, c)));
            }
            s
        },
    );
    (score, winner.1)
}

/// `on_wall`: in front of a wall and touching it: fraction in front x the [0, 0.01] m band
/// (sigma 0.01 m) of the distance to the wall; best wall. Holds when fully in front and within
/// about 2.2 cm.
pub fn on_wall(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> Real {
    wall_contact(target, room, &params.on_wall, params)
}

/// `against_wall`: as [`on_wall`] with the [0, 0.3] m band (sigma 0.1 m): holds when fully
/// in front and within about 0.418 m.
///
/// ```
/// use sceneeval_relations::{arch, ObjectGeom, RelationParams};
/// use sceneeval_scene::RoomBuilder;
/// use sceneeval_geom::{Obb, Point2, na::{Point3, Vector3}};
/// let room = RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
///     .wall_height(2.8)
///     .wall_thickness(0.1)
///     .build()
///     .unwrap();
/// // A wardrobe 0.5 m from the far wall (y = 5): 0.2 m past the band, exp(-0.04 / 0.02).
/// let w = Obb::from_yaw(Point3::new(2.0, 4.2, 1.0), Vector3::new(0.5, 0.3, 1.0), 0.0).unwrap();
/// let s = arch::against_wall(&ObjectGeom::from_box(&w), &room, &RelationParams::default());
/// assert!((s - (-2.0f64).exp()).abs() < 1e-9);
/// ```
pub fn against_wall(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> Real {
    wall_contact(target, room, &params.against_wall, params)
}

/// `hang_from_ceiling`: the [0, 0.01] m band (sigma 0.03 m) of the distance from the object to
/// the room's ceiling surface (the explicit ceiling, else the floor outline at the top of the
/// tallest wall); 0 for a room without a ceiling.
pub fn hang_from_ceiling(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> Real {
    match ceiling_distance(target, room, params) {
        None => 0.0,
        Some(c) => params.hang_from_ceiling.score(c.distance),
    }
}

/// The distance `hang_from_ceiling` scores, with closest points (the object's first; for a box
/// under the ceiling its top point and the point above it); `None` without a ceiling.
pub(crate) fn ceiling_distance(
    target: &ObjectGeom<'_>,
    room: &Room,
    params: &RelationParams,
) -> Option<ClosestPoints> {
    let tris = room.ceiling_triangles();
    let (Some(ceiling_z), false) = (room.ceiling_z(), tris.is_empty()) else {
        return None;
    };
    let probe = Probe::new(target, params);
    let obb = probe.geom.obb;
    // Exact shortcut for a box below the ceiling: its highest point (the centre of its top
    // vertex, edge or face) is nearest to the ceiling plane; if it lies under the ceiling
    // polygon, the distance is the vertical gap.
    if probe.geom.mesh.is_none() {
        let m = obb.rotation.matrix();
        let local = Vector3::from_fn(|j, _| {
            let up = m[(2, j)];
            if up > 0.0 {
                obb.half_extents[j]
            } else if up < 0.0 {
                -obb.half_extents[j]
            } else {
                0.0
            }
        });
        let top = obb.to_world(&local);
        let under = tris.iter().any(|t| in_triangle(t, top.x, top.y));
        if top.z <= ceiling_z && under {
            let distance = ceiling_z - top.z;
            return Some(ClosestPoints {
                distance,
                points: (distance > 0.0).then(|| (top, Point3::new(top.x, top.y, ceiling_z))),
            });
        }
    }
    let aabb = obb.aabb();
    let mut best = ClosestPoints {
        distance: Real::INFINITY,
        points: None,
    };
    for t in tris {
        // Lower bound: the gap between the object's and the triangle's bounding boxes.
        let lo = t[0].inf(&t[1]).inf(&t[2]);
        let hi = t[0].sup(&t[1]).sup(&t[2]);
        let gap = Vector3::from_fn(|i, _| (lo[i] - aabb.max[i]).max(aabb.min[i] - hi[i]).max(0.0));
        if gap.norm() < best.distance {
            let c = object_triangle_closest(&probe.geom, t);
            if c.distance < best.distance {
                best = c;
            }
        }
    }
    Some(best)
}

/// Whether the plan point lies in the (closed) plan projection of a triangle, either winding.
fn in_triangle(t: &[Point3; 3], x: Real, y: Real) -> bool {
    let side = |a: &Point3, b: &Point3| (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
    let (d0, d1, d2) = (side(&t[0], &t[1]), side(&t[1], &t[2]), side(&t[2], &t[0]));
    (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0)
}

/// Walls whose per-wall bounds, scores and directions are kept on the stack in
/// `corner_of_room` (larger rooms use two vectors: the kernel's only allocation).
const CORNER_CACHE: usize = 32;

/// `corner_of_room`: the best product of two per-wall scores over pairs of perpendicular walls
/// of the room, 0 when the object is not in the room.
///
/// As in the reference, a room counts only when [`inside_room`] is at least
/// [`RelationParams::corner_min_inside_room`] (0.5) and it has two walls; each wall scores the
/// [0, 0.8] m band (sigma 0.25 m) of its distance to the object; two walls are perpendicular
/// when `|u . v| < 0.15` for their directions `u`, `v`. The directions are the walls' inward
/// normals ([`CornerWalls::WallNormals`], the paper) or the normalised mean of
/// `closest point on the wall - p` over a 4 x 4 x 4 midpoint grid `p` in the object's box
/// ([`CornerWalls::MeanDirections`], the reference, which uses random samples). Without a
/// perpendicular pair the score is 0 (the reference returns minus infinity).
pub fn corner_of_room(target: &ObjectGeom<'_>, room: &Room, params: &RelationParams) -> Real {
    corner_of_room_best(target, room, params).0
}

/// One wall of the best pair of `corner_of_room`: its score and the closest points to it.
pub(crate) type CornerWall = (Real, ClosestPoints);

/// [`corner_of_room`] and the pair of walls behind it (`None` when it is 0).
pub(crate) fn corner_of_room_best(
    target: &ObjectGeom<'_>,
    room: &Room,
    params: &RelationParams,
) -> (Real, Option<(CornerWall, CornerWall)>) {
    let walls = room.walls();
    if walls.len() < 2 || inside_room(target, room, params) < params.corner_min_inside_room {
        return (0.0, None);
    }
    let probe = Probe::new(target, params);
    let band = &params.corner_wall;
    let upper = |w: &Wall| band_upper(band, probe.bounds_union(w.solid_boxes()));
    let exact = |w: &Wall| {
        let c = probe.closest_to_union(w.solid_boxes());
        (band.score(c.distance), c)
    };
    let direction = |w: &Wall| match params.corner_walls {
        CornerWalls::WallNormals => w.inward_normal_3d(),
        CornerWalls::MeanDirections => mean_direction_to_wall(target.obb, w),
    };
    // Per wall: (upper bound, exact score once computed, direction once computed), and the
    // walls in decreasing order of their upper bound; on the stack for rooms of up to
    // CORNER_CACHE walls, in two vectors for larger ones.
    let n = walls.len();
    type Slot = (Real, Option<CornerWall>, Option<Vector3>);
    let (mut stack, mut stack_order) = ([(0.0, None, None); CORNER_CACHE], [0usize; CORNER_CACHE]);
    let (mut heap, mut heap_order): (Vec<Slot>, Vec<usize>) = (Vec::new(), Vec::new());
    let (cache, order): (&mut [Slot], &mut [usize]) = if n <= CORNER_CACHE {
        (&mut stack[..n], &mut stack_order[..n])
    } else {
        heap.resize(n, (0.0, None, None));
        heap_order.resize(n, 0);
        (&mut heap, &mut heap_order)
    };
    for (i, (slot, at)) in cache.iter_mut().zip(order.iter_mut()).enumerate() {
        *slot = (upper(&walls[i]), None, None);
        *at = i;
    }
    order.sort_unstable_by(|&x, &y| cache[y].0.total_cmp(&cache[x].0).then(x.cmp(&y)));
    // Every unordered pair once (i before j in that order); a pair cannot beat `best` once the
    // product of its upper bounds does not, and later pairs have smaller bounds: the result is
    // the exact maximum over perpendicular pairs, whatever the order.
    let mut best: Real = 0.0;
    let mut pair = None;
    for p in 0..n {
        let i = order[p];
        let ub_i = cache[i].0;
        if order.get(p + 1).is_none_or(|&j| ub_i * cache[j].0 <= best) {
            break;
        }
        for &j in &order[p + 1..] {
            let ub_j = cache[j].0;
            if ub_i * ub_j <= best {
                break;
            }
            #[cfg(test)]
            tests::CORNER_PAIRS.with(|c| c.set(c.get() + 1));
            let dir_i = *cache[i].2.get_or_insert_with(|| direction(&walls[i]));
            let dir_j = *cache[j].2.get_or_insert_with(|| direction(&walls[j]));
            if dir_i.dot(&dir_j).abs() >= params.corner_perpendicular_threshold {
                continue;
            }
            let wi = *cache[i].1.get_or_insert_with(|| exact(&walls[i]));
            if wi.0 * ub_j <= best {
                continue;
            }
            let wj = *cache[j].1.get_or_insert_with(|| exact(&walls[j]));
            if wi.0 * wj.0 > best {
                pair = Some((wi, wj));
            }
            best = best.max(wi.0 * wj.0);
        }
    }
    (best, pair)
}

/// The normalised mean of (closest point on the wall's solid - p) over a 4 x 4 x 4 midpoint
/// grid of points p in the box.
fn mean_direction_to_wall(obb: &Obb, wall: &Wall) -> Vector3 {
    const N: usize = 4;
    let cells = wall.solid_boxes();
    let mut acc = Vector3::zeros();
    for i in 0..N {
        for j in 0..N {
            for k in 0..N {
                let f = |n: usize, h: Real| -h + (n as Real + 0.5) * (2.0 * h / N as Real);
                let l = Vector3::new(
                    f(i, obb.half_extents.x),
                    f(j, obb.half_extents.y),
                    f(k, obb.half_extents.z),
                );
                let p = obb.to_world(&l);
                let mut best = (Real::INFINITY, Point3::origin());
                for c in cells {
                    let q = c.closest_point(&p);
                    let d = (q - p).norm_squared();
                    if d < best.0 {
                        best = (d, q);
                    }
                }
                if best.0.is_finite() {
                    acc += best.1 - p;
                }
            }
        }
    }
    acc.try_normalize(0.0).unwrap_or_else(Vector3::zeros)
}

/// One object-architecture relation for one object over several rooms: the best score over
/// the rooms (0 with no rooms), which is the reference's maximum over architectural elements.
///
/// # Errors
/// [`RelationError::WrongKind`] for an object-object relation.
pub fn score_rooms(
    relation: Relation,
    target: &ObjectGeom<'_>,
    rooms: &[Room],
    params: &RelationParams,
) -> Result<Real, RelationError> {
    let f: &dyn Fn(&Room) -> Real = match relation {
        Relation::NextToArch(e) => &move |r| next_to(target, r, e, params),
        Relation::NearArch(e) => &move |r| near(target, r, e, params),
        Relation::AcrossFromArch(e) => &move |r| across_from(target, r, e, params),
        Relation::FarArch(e) => &move |r| far(target, r, e, params),
        Relation::InsideRoom => &|r| inside_room(target, r, params),
        Relation::MiddleOfRoom => &|r| middle_of_room(target, r, params),
        Relation::CornerOfRoom => &|r| corner_of_room(target, r, params),
        Relation::OnWall => &|r| on_wall(target, r, params),
        Relation::AgainstWall => &|r| against_wall(target, r, params),
        Relation::HangFromCeiling => &|r| hang_from_ceiling(target, r, params),
        other => {
            return Err(RelationError::WrongKind {
                relation: other.to_string(),
                actual: other.kind().describe(),
                expected: "an object-architecture relation",
            });
        }
    };
    Ok(rooms.iter().map(f).fold(0.0, Real::max))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    thread_local! {
        /// Wall pairs `corner_of_room` looked at on this thread.
        pub(super) static CORNER_PAIRS: Cell<usize> = const { Cell::new(0) };
    }

    #[test]
    fn corner_of_room_in_a_room_of_many_walls_looks_at_few_pairs() {
        // A 4 x 4 m room whose walls are each split into 2,500 pieces (10,000 walls): an object
        // in a corner is near a few pieces only, so a handful of pairs decide, not 5e7.
        let n = 2500;
        let mut outline = Vec::new();
        for (a, b) in [
            ([0.0, 0.0], [4.0, 0.0]),
            ([4.0, 0.0], [4.0, 4.0]),
            ([4.0, 4.0], [0.0, 4.0]),
            ([0.0, 4.0], [0.0, 0.0]),
        ] {
            for k in 0..n {
                let t = f64::from(k) / f64::from(n);
                outline.push(Point2::new(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t));
            }
        }
        let room = RoomBuilder::polygon("big", outline).build().unwrap();
        assert_eq!(room.walls().len(), 4 * n as usize);
        let plant = bx([0.3, 0.3, 0.4], [0.2, 0.2, 0.4], 0.0);
        CORNER_PAIRS.with(|c| c.set(0));
        let s = corner_of_room(&g(&plant), &room, &RelationParams::default());
        // 0.1 m from both walls: inside the [0, 0.8] m band of each.
        assert_eq!(s, 1.0);
        let pairs = CORNER_PAIRS.with(Cell::get);
        assert!(pairs < 10_000, "{pairs} pairs");
    }
    use sceneeval_geom::Point2;
    use sceneeval_scene::RoomBuilder;

    /// The test bedroom with a window on wall 2 (y = 5), x in [1.0, 2.5], 0.9 to 2.0 m up.
    fn room() -> Room {
        sceneeval_test_support::bedroom("r")
            .window(2, [1.0, 2.5], [0.9, 2.0])
            .build()
            .unwrap()
    }
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

    fn bx(c: [Real; 3], h: [Real; 3], yaw: Real) -> Obb {
        Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::new(h[0], h[1], h[2]), yaw).unwrap()
    }

    fn g(o: &Obb) -> ObjectGeom<'_> {
        ObjectGeom::from_box(o)
    }

    #[test]
    fn inside_room_fractions() {
        let r = room();
        let p = RelationParams::default();
        assert_eq!(
            inside_room(&g(&bx([2.0, 2.5, 0.5], [0.5, 0.5, 0.5], 0.3)), &r, &p),
            1.0
        );
        // Over the corner (4, 5): a quarter of the plan over the floor.
        let s = inside_room(&g(&bx([4.0, 5.0, 0.5], [0.5, 0.5, 0.5], 0.0)), &r, &p);
        assert!((s - 0.25).abs() < 1e-12, "{s}");
        // Sunk 0.25 m below the floor (z in [-0.25, 0.75]): 0.75 above.
        let s = inside_room(&g(&bx([2.0, 2.0, 0.25], [0.5, 0.5, 0.5], 0.0)), &r, &p);
        assert!((s - 0.75).abs() < 1e-5, "{s}");
        // Outside the room.
        assert_eq!(
            inside_room(&g(&bx([7.0, 2.0, 0.5], [0.5, 0.5, 0.5], 0.0)), &r, &p),
            0.0
        );
        // A cube turned 45 degrees centred on the wall x = 0: half over the floor by symmetry.
        let s = inside_room(&g(&bx([0.0, 2.0, 0.5], [0.5, 0.5, 0.5], FRAC_PI_4)), &r, &p);
        assert!((s - 0.5).abs() < 1e-12, "{s}");
    }

    #[test]
    fn inside_an_l_shaped_room() {
        // L-shape: the 4 x 4 square minus the [2, 4] x [2, 4] quadrant.
        let l = RoomBuilder::polygon(
            "l",
            vec![
                Point2::new(0.0, 0.0),
                Point2::new(4.0, 0.0),
                Point2::new(4.0, 2.0),
                Point2::new(2.0, 2.0),
                Point2::new(2.0, 4.0),
                Point2::new(0.0, 4.0),
            ],
        )
        .wall_height(2.8)
        .wall_thickness(0.1)
        .build()
        .unwrap();
        let p = RelationParams::default();
        // A 2 x 2 box centred on the reflex corner (2, 2): three of its four quadrants are
        // over the floor.
        let s = inside_room(&g(&bx([2.0, 2.0, 0.5], [1.0, 1.0, 0.5], 0.0)), &l, &p);
        assert!((s - 0.75).abs() < 1e-12, "{s}");
        // The area centroid of the L is (5/3, 5/3), not the bounds centre (2, 2).
        assert!((l.floor_centroid() - Point2::new(5.0 / 3.0, 5.0 / 3.0)).norm() < 1e-12);
    }

    #[test]
    fn middle_of_room_sigma() {
        let r = room();
        let p = RelationParams::default();
        // Rug 2 x 1 at the centre (2, 2.5): score 1.
        let rug = bx([2.0, 2.5, 0.01], [1.0, 0.5, 0.01], 0.0);
        assert_eq!(middle_of_room(&g(&rug), &r, &p), 1.0);
        // Moved 1 m: o = 2, r = 4.5, sigma = 0.5 * 2 + (1 - 2/4.5) = 1.5556;
        // exp(-1 / (2 sigma^2)) = exp(-0.20663).
        let moved = bx([3.0, 2.5, 0.01], [1.0, 0.5, 0.01], 0.0);
        let sigma: Real = 1.0 + (1.0 - 2.0 / 4.5);
        let expected = (-1.0 / (2.0 * sigma * sigma)).exp();
        assert!((middle_of_room(&g(&moved), &r, &p) - expected).abs() < 1e-12);
    }

    #[test]
    fn against_and_on_wall() {
        let r = room();
        let p = RelationParams::default();
        // A bed's back touching the far wall (y = 5), turned so its front faces -y: 1.
        let bed = bx([2.0, 4.0, 0.3], [0.8, 1.0, 0.3], 0.0);
        assert_eq!(against_wall(&g(&bed), &r, &p), 1.0);
        // 0.3 m off the wall: still in the band.
        let bed2 = bx([2.0, 3.7, 0.3], [0.8, 1.0, 0.3], 0.0);
        assert_eq!(against_wall(&g(&bed2), &r, &p), 1.0);
        // In the middle of the room: nearest wall 1.2 m from the bed's side (x: 2 - 0.8 = 1.2)
        // -> 0.9 past the band: exp(-0.81 / 0.02) ~ 0.
        let mid = bx([2.0, 2.5, 0.3], [0.8, 1.0, 0.3], 0.0);
        assert!(against_wall(&g(&mid), &r, &p) < 1e-15);
        // A painting hanging on the side wall x = 0, 5 mm off it, turned to face +x.
        let painting = bx([0.025, 2.5, 1.5], [0.5, 0.02, 0.4], FRAC_PI_2);
        assert_eq!(on_wall(&g(&painting), &r, &p), 1.0);
        // 5 cm off: 0.04 past the band with sigma 0.01 -> exp(-8) ~ 3.4e-4.
        let off = bx([0.07, 2.5, 1.5], [0.5, 0.02, 0.4], FRAC_PI_2);
        assert!((on_wall(&g(&off), &r, &p) - (-8.0f64).exp()).abs() < 1e-9);
        // Half beyond the end of a wall: a box centred on the corner's vertical line but
        // outside the room has no part in front of any wall.
        let outside = bx([-0.5, 2.5, 1.0], [0.3, 0.3, 0.3], 0.0);
        assert_eq!(against_wall(&g(&outside), &r, &p), 0.0);
    }

    #[test]
    fn door_and_window_distances() {
        let r = room();
        let p = RelationParams::default();
        // A chair 0.2 m in front of the door (door on wall 0 at x in [1.0, 1.9], y = 0).
        let chair = bx([1.45, 0.45, 0.4], [0.25, 0.25, 0.4], 0.0);
        assert_eq!(next_to(&g(&chair), &r, ArchElement::Door, &p), 1.0);
        // The window is on wall 2 (y = 5, z in [0.9, 2.0]): the chair (y up to 0.7, z up to
        // 0.8) is sqrt(4.3^2 + 0.1^2) away: far.
        assert!((far(&g(&chair), &r, ArchElement::Window, &p) - 1.0).abs() < 1e-12);
        // The door is a hole in wall 0: the chair is 0.2 m from the door but the wall's solid
        // pieces start at x = 1.0 and 1.9: distance to wall 0 is still 0.2 m (its box spans
        // x in [1.2, 1.7], in front of the door only) -> the pieces beside the door are
        // sqrt(0.2^2 + 0.2^2) away.
        let wall0 = &r.walls()[0];
        assert!((wall_distance(&g(&chair), wall0) - (0.08f64).sqrt()).abs() < 1e-9);
        // A room without windows: window relations score 0.
        let plain = RoomBuilder::polygon(
            "p",
            vec![
                Point2::new(0.0, 0.0),
                Point2::new(3.0, 0.0),
                Point2::new(3.0, 3.0),
            ],
        )
        .wall_height(2.5)
        .wall_thickness(0.0)
        .build()
        .unwrap();
        assert_eq!(near(&g(&chair), &plain, ArchElement::Window, &p), 0.0);
        // Floors, ceilings and rooms are no distance targets (parsing refuses them): a
        // relation built with one directly finds no element and scores 0, even for `far`.
        for e in [ArchElement::Floor, ArchElement::Ceiling, ArchElement::Room] {
            assert_eq!(next_to(&g(&chair), &r, e, &p), 0.0);
            assert_eq!(far(&g(&chair), &r, e, &p), 0.0);
        }
    }

    #[test]
    fn corner_of_room_pairs() {
        let r = room();
        let p = RelationParams::default();
        // A plant 0.1 m from both walls at the corner (0, 5).
        let plant = bx([0.3, 4.7, 0.4], [0.2, 0.2, 0.4], 0.0);
        assert_eq!(corner_of_room(&g(&plant), &r, &p), 1.0);
        let rp = RelationParams {
            corner_walls: CornerWalls::MeanDirections,
            ..RelationParams::default()
        };
        assert_eq!(corner_of_room(&g(&plant), &r, &rp), 1.0);
        // Against the middle of the far wall: 1.8 m from the side walls -> 1.0 past the band:
        // exp(-1 / 0.125) = exp(-8).
        let mid = bx([2.0, 4.7, 0.4], [0.2, 0.2, 0.4], 0.0);
        assert!((corner_of_room(&g(&mid), &r, &p) - (-8.0f64).exp()).abs() < 1e-12);
        // Outside the room: 0.
        let out = bx([-1.0, 4.7, 0.4], [0.2, 0.2, 0.4], 0.0);
        assert_eq!(corner_of_room(&g(&out), &r, &p), 0.0);
    }

    #[test]
    fn hanging_lamp() {
        let r = room();
        let p = RelationParams::default();
        // A lamp whose top touches the 2.8 m ceiling.
        let lamp = bx([2.0, 2.5, 2.6], [0.2, 0.2, 0.2], 0.0);
        assert_eq!(hang_from_ceiling(&g(&lamp), &r, &p), 1.0);
        // 4 cm below: 0.03 past the band with sigma 0.03 -> exp(-0.5).
        let low = bx([2.0, 2.5, 2.56], [0.2, 0.2, 0.2], 0.0);
        assert!((hang_from_ceiling(&g(&low), &r, &p) - (-0.5f64).exp()).abs() < 1e-9);
    }

    #[test]
    fn several_rooms_take_the_best() {
        let a = room();
        let b = RoomBuilder::polygon(
            "b",
            vec![
                Point2::new(4.0, 0.0),
                Point2::new(8.0, 0.0),
                Point2::new(8.0, 5.0),
                Point2::new(4.0, 5.0),
            ],
        )
        .wall_height(2.8)
        .wall_thickness(0.1)
        .build()
        .unwrap();
        let p = RelationParams::default();
        let obj = bx([6.0, 2.5, 0.5], [0.5, 0.5, 0.5], 0.0);
        let rooms = [a, b];
        assert_eq!(
            score_rooms(Relation::InsideRoom, &g(&obj), &rooms, &p).unwrap(),
            1.0
        );
        assert_eq!(
            score_rooms(Relation::InsideRoom, &g(&obj), &rooms[..1], &p).unwrap(),
            0.0
        );
        assert_eq!(score_rooms(Relation::InsideRoom, &g(&obj), &[], &p).unwrap(), 0.0);
        assert!(score_rooms(Relation::OnTop, &g(&obj), &rooms, &p).is_err());
    }
}
