//! Predicate inputs on plain geometry: a room's floor, walls, openings and ceiling, prepared
//! once so that the architecture kernels allocate nothing per call.

use sceneeval_geom::planar::convex_hull;
use sceneeval_geom::{Obb, Point2, Point3, Polygon2, Real, Rotation3, Vector2, Vector3};
use sceneeval_scene::{OpeningKind, Room, RoomBuilder};

use crate::RelationError;

/// One wall as the kernels see it: its inner-face segment, inward normal, heights and
/// thickness (see `sceneeval_scene::arch` for the conventions).
#[derive(Debug, Clone, PartialEq)]
pub struct WallGeom {
    /// The wall's id.
    pub id: String,
    /// Start of the inner-face segment on the floor plan.
    pub start: Point2,
    /// End of the inner-face segment.
    pub end: Point2,
    /// Unit direction from start to end.
    pub direction: Vector2,
    /// Unit normal of the inner face, pointing into the room.
    pub inward: Vector2,
    /// Segment length (metres).
    pub length: Real,
    /// World z of the wall's bottom.
    pub base_z: Real,
    /// Height (metres).
    pub height: Real,
    /// Thickness away from the room (metres, may be 0).
    pub thickness: Real,
    /// The wall's frame: local -y into the room, z up.
    pub rotation: Rotation3,
    /// Indices into [`RoomGeometry::wall_cells`] of this wall's solid pieces.
    pub cells: std::ops::Range<usize>,
}

impl WallGeom {
    /// The inward normal as a 3-D vector.
    #[inline]
    pub fn inward_3d(&self) -> Vector3 {
        Vector3::new(self.inward.x, self.inward.y, 0.0)
    }

    /// The world point `along` metres from the start and `up` metres above the base, on the
    /// inner face.
    #[inline]
    pub fn point_on_inner_face(&self, along: Real, up: Real) -> Point3 {
        let p = self.start + self.direction * along;
        Point3::new(p.x, p.y, self.base_z + up)
    }
}

/// A door or window as the kernels see it.
#[derive(Debug, Clone, PartialEq)]
pub struct OpeningGeom {
    /// The opening's id.
    pub id: String,
    /// Door or window.
    pub kind: OpeningKind,
    /// Index of its wall in [`RoomGeometry::walls`].
    pub wall: usize,
    /// Start and end along the wall (metres from the wall's start).
    pub along: [Real; 2],
    /// Bottom and top above the wall's base (metres).
    pub height: [Real; 2],
    /// The opening's box: its rectangle on the inner face, through the wall's thickness
    /// (at least 1 mm deep).
    pub obb: Obb,
}

/// A plain description of a door or window for [`RoomGeometry::from_outline`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpeningSpec {
    /// Door or window.
    pub kind: OpeningKind,
    /// Wall index: wall `i` runs from outline point `i` to point `i + 1` (wrapping).
    pub wall: usize,
    /// Start and end along the wall, metres from its start point.
    pub along: [Real; 2],
    /// Bottom and top above the floor, metres.
    pub height: [Real; 2],
}

/// One room prepared for the architecture predicates: the floor polygon and its
/// triangulation, the walls with their solid pieces (the slab with doors and windows cut out,
/// as boxes), the openings' boxes and the ceiling.
///
/// Build it once per room (it allocates), then call the kernels in [`crate::arch`] as often
/// as needed; they only borrow it. It can be made from a scene's [`Room`] or from plain data
/// with [`RoomGeometry::from_outline`], without a scene.
///
/// ```
/// use sceneeval_relations::{OpeningSpec, RoomGeometry};
/// use sceneeval_scene::OpeningKind;
/// use sceneeval_geom::Point2;
///
/// let room = RoomGeometry::from_outline(
///     "bedroom",
///     vec![Point2::new(0.0, 0.0), Point2::new(4.0, 0.0), Point2::new(4.0, 5.0), Point2::new(0.0, 5.0)],
///     0.0, 2.8, 0.1,
///     &[OpeningSpec { kind: OpeningKind::Door, wall: 0, along: [1.0, 1.9], height: [0.0, 2.1] }],
/// ).unwrap();
/// assert_eq!(room.walls().len(), 4);
/// assert_eq!(room.openings().len(), 1);
/// // Wall 0 with a door is three solid pieces: left of, above and right of the door.
/// assert_eq!(room.walls()[0].cells.len(), 3);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RoomGeometry {
    room_id: String,
    floor_id: String,
    floor: Polygon2,
    floor_z: Real,
    ceiling_z: Option<Real>,
    floor_triangles: Vec<[Point2; 3]>,
    ceiling_triangles: Vec<[Point3; 3]>,
    centroid: Point2,
    bounds: (Point2, Point2),
    rectangle: (Point2, Vector2),
    walls: Vec<WallGeom>,
    wall_cells: Vec<Obb>,
    openings: Vec<OpeningGeom>,
    /// The openings' boxes, in the order of `openings`, for the distance kernels.
    opening_boxes: Vec<Obb>,
    /// For a convex floor: its edges as inward half-planes `n . p >= c` (else empty).
    convex_floor: Vec<(Vector2, Real)>,
}

impl RoomGeometry {
    /// The geometry of a scene room (its walls as oriented by the scene: inward normals
    /// decided against the room's own floor).
    pub fn from_room(room: &Room) -> Self {
        let mut walls = Vec::with_capacity(room.walls().len());
        let mut wall_cells = Vec::new();
        let mut openings = Vec::new();
        for (wi, w) in room.walls().iter().enumerate() {
            let first = wall_cells.len();
            let geom = WallGeom {
                id: w.id().to_owned(),
                start: w.start(),
                end: w.end(),
                direction: w.direction(),
                inward: w.inward_normal(),
                length: w.length(),
                base_z: w.base_z(),
                height: w.height(),
                thickness: w.thickness(),
                rotation: w.rotation(),
                cells: first..first,
            };
            let spans: Vec<([Real; 2], [Real; 2])> =
                w.openings().iter().map(|o| (o.along, o.height)).collect();
            solid_cells(&geom, &spans, &mut wall_cells);
            let cells = first..wall_cells.len();
            for o in w.openings() {
                openings.push(OpeningGeom {
                    id: o.id.clone(),
                    kind: o.kind,
                    wall: wi,
                    along: o.along,
                    height: o.height,
                    obb: w.opening_obb(o),
                });
            }
            walls.push(WallGeom { cells, ..geom });
        }
        let floor = room.floor().clone();
        let floor_triangles = floor
            .triangulate()
            .into_iter()
            .map(|t| t.map(|i| floor.points()[i]))
            .collect();
        let ceiling_z = room.ceiling_z();
        let ceiling_triangles = match ceiling_z {
            Some(z) => {
                let poly = room.ceiling_polygon();
                poly.triangulate()
                    .into_iter()
                    .map(|t| {
                        t.map(|i| {
                            let p = poly.points()[i];
                            Point3::new(p.x, p.y, z)
                        })
                    })
                    .collect()
            }
            None => Vec::new(),
        };
        let opening_boxes = openings.iter().map(|o: &OpeningGeom| o.obb).collect();
        let convex_floor = convex_half_planes(&floor);
        RoomGeometry {
            opening_boxes,
            convex_floor,
            room_id: room.id().to_string(),
            floor_id: room.floor_id().to_owned(),
            centroid: floor.centroid(),
            bounds: floor.bounds(),
            rectangle: min_area_rectangle(floor.points()),
            floor,
            floor_z: room.floor_z(),
            ceiling_z,
            floor_triangles,
            ceiling_triangles,
            walls,
            wall_cells,
            openings,
        }
    }

    /// A room from plain data, without a scene: a floor outline (either winding) at height
    /// `floor_z`, one wall per outline edge (wall `i` from point `i` to point `i + 1`,
    /// wrapping; its segment is the inner face) of the given height and thickness, and doors
    /// and windows by wall index. The ceiling is the outline at the top of the walls.
    ///
    /// # Errors
    /// [`RelationError::BadRoom`] when the outline is not a simple polygon, a value is not
    /// finite, a height is not positive, or an opening names a missing wall or lies outside
    /// its wall.
    pub fn from_outline(
        id: &str,
        outline: Vec<Point2>,
        floor_z: Real,
        wall_height: Real,
        wall_thickness: Real,
        openings: &[OpeningSpec],
    ) -> Result<Self, RelationError> {
        let mut builder = RoomBuilder::polygon(id, outline)
            .floor_z(floor_z)
            .wall_height(wall_height)
            .wall_thickness(wall_thickness);
        for o in openings {
            builder = match o.kind {
                OpeningKind::Door => builder.door(o.wall, o.along, o.height),
                OpeningKind::Window => builder.window(o.wall, o.along, o.height),
            };
        }
        let room = builder.build().map_err(|e| RelationError::BadRoom {
            reason: e.to_string(),
        })?;
        Ok(RoomGeometry::from_room(&room))
    }

    /// The room's id.
    #[inline]
    pub fn room_id(&self) -> &str {
        &self.room_id
    }

    /// The floor element's id (`floor_<room>` for rooms built by `RoomBuilder`).
    #[inline]
    pub fn floor_id(&self) -> &str {
        &self.floor_id
    }

    /// The floor outline.
    #[inline]
    pub fn floor(&self) -> &Polygon2 {
        &self.floor
    }

    /// World z of the floor.
    #[inline]
    pub fn floor_z(&self) -> Real {
        self.floor_z
    }

    /// World z of the ceiling (explicit, else the highest wall top), if any.
    #[inline]
    pub fn ceiling_z(&self) -> Option<Real> {
        self.ceiling_z
    }

    /// The floor's triangulation (counter-clockwise triangles covering the outline exactly).
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

    /// Lowest and highest corners of the floor's bounding rectangle.
    #[inline]
    pub fn floor_bounds(&self) -> (Point2, Point2) {
        self.bounds
    }

    /// The floor's minimum-area enclosing rectangle: its centre and its two side lengths
    /// (metres). For an axis-aligned room this is the bounding rectangle the reference uses;
    /// unlike that, it does not change when the room is turned.
    #[inline]
    pub fn floor_rectangle(&self) -> (Point2, Vector2) {
        self.rectangle
    }

    /// The walls.
    #[inline]
    pub fn walls(&self) -> &[WallGeom] {
        &self.walls
    }

    /// The solid pieces of every wall as boxes (a wall's are `cells` of its [`WallGeom`]).
    #[inline]
    pub fn wall_cells(&self) -> &[Obb] {
        &self.wall_cells
    }

    /// The solid pieces of one wall.
    #[inline]
    pub fn cells_of(&self, wall: &WallGeom) -> &[Obb] {
        self.wall_cells.get(wall.cells.clone()).unwrap_or(&[])
    }

    /// The doors and windows.
    #[inline]
    pub fn openings(&self) -> &[OpeningGeom] {
        &self.openings
    }

    /// The box of every opening, in the order of [`RoomGeometry::openings`].
    #[inline]
    pub(crate) fn opening_boxes(&self) -> &[Obb] {
        &self.opening_boxes
    }

    /// Whether the plan point lies in the floor, when the floor is convex; `None` for a
    /// non-convex floor.
    #[inline]
    pub(crate) fn convex_floor_contains(&self, x: Real, y: Real) -> Option<bool> {
        if self.convex_floor.is_empty() {
            return None;
        }
        Some(self.convex_floor.iter().all(|(n, c)| n.x * x + n.y * y >= *c))
    }
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

/// The minimum-area rectangle enclosing `points` (rotating calipers over the convex hull's
/// edge directions): its centre and side lengths. The first minimum in hull order wins ties.
fn min_area_rectangle(points: &[Point2]) -> (Point2, Vector2) {
    let hull = convex_hull(points);
    let mut best: Option<(Real, Point2, Vector2)> = None;
    for i in 0..hull.len() {
        let e = hull[(i + 1) % hull.len()] - hull[i];
        let Some(u) = e.try_normalize(0.0) else {
            continue;
        };
        let v = Vector2::new(-u.y, u.x);
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
        let area = (u1 - u0) * (v1 - v0);
        if best.is_none_or(|(a, _, _)| area < a) {
            let centre = Point2::from(u * (0.5 * (u0 + u1)) + v * (0.5 * (v0 + v1)));
            best = Some((area, centre, Vector2::new(u1 - u0, v1 - v0)));
        }
    }
    best.map_or((Point2::origin(), Vector2::zeros()), |(_, c, d)| (c, d))
}

/// Splits a wall's slab into boxes around its openings: a grid on every opening edge, with
/// vertically adjacent solid cells merged into one box per column run.
fn solid_cells(wall: &WallGeom, openings: &[([Real; 2], [Real; 2])], out: &mut Vec<Obb>) {
    let mut us = vec![0.0, wall.length];
    let mut ws = vec![0.0, wall.height];
    for (along, up) in openings {
        us.extend(along);
        ws.extend(up);
    }
    for v in [&mut us, &mut ws] {
        v.sort_by(|a, b| a.total_cmp(b));
        v.dedup();
    }
    let solid = |u: Real, w: Real| {
        !openings
            .iter()
            .any(|(a, h)| u > a[0] && u < a[1] && w > h[0] && w < h[1])
    };
    let inward = wall.inward_3d();
    let push = |out: &mut Vec<Obb>, u0: Real, u1: Real, w0: Real, w1: Real| {
        let face = wall.point_on_inner_face(0.5 * (u0 + u1), 0.5 * (w0 + w1));
        out.push(Obb {
            center: face - inward * (0.5 * wall.thickness),
            half_extents: Vector3::new(0.5 * (u1 - u0), 0.5 * wall.thickness, 0.5 * (w1 - w0)),
            rotation: wall.rotation,
        });
    };
    for iu in 0..us.len() - 1 {
        let (u0, u1) = (us[iu], us[iu + 1]);
        let um = 0.5 * (u0 + u1);
        let mut run: Option<Real> = None;
        for iw in 0..ws.len() - 1 {
            let (w0, w1) = (ws[iw], ws[iw + 1]);
            if solid(um, 0.5 * (w0 + w1)) {
                run.get_or_insert(w0);
            } else if let Some(start) = run.take() {
                push(out, u0, u1, start, w0);
            }
        }
        if let Some(start) = run {
            push(out, u0, u1, start, wall.height);
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A 4 x 5 m room, 2.8 m high, 0.1 m walls, a door on wall 0 and a window on wall 2 (also
    /// used by the architecture kernels' tests).
    pub(crate) fn bedroom() -> RoomGeometry {
        RoomGeometry::from_outline(
            "r",
            vec![
                Point2::new(0.0, 0.0),
                Point2::new(4.0, 0.0),
                Point2::new(4.0, 5.0),
                Point2::new(0.0, 5.0),
            ],
            0.0,
            2.8,
            0.1,
            &[
                OpeningSpec {
                    kind: OpeningKind::Door,
                    wall: 0,
                    along: [1.0, 1.9],
                    height: [0.0, 2.1],
                },
                OpeningSpec {
                    kind: OpeningKind::Window,
                    wall: 2,
                    along: [1.0, 2.5],
                    height: [0.9, 2.0],
                },
            ],
        )
        .unwrap()
    }

    #[test]
    fn cells_cover_the_wall_minus_openings() {
        let room = bedroom();
        // Wall 0 (4 m x 2.8 m) minus the 0.9 x 2.1 door: 11.2 - 1.89 = 9.31 m^2 of face.
        let w0 = &room.walls()[0];
        let area: Real = room
            .cells_of(w0)
            .iter()
            .map(|c| 4.0 * c.half_extents.x * c.half_extents.z)
            .sum();
        assert!((area - 9.31).abs() < 1e-12, "{area}");
        // Wall 2 with a window: columns left, middle (below + above the window), right = 4 cells.
        assert_eq!(room.walls()[2].cells.len(), 4);
        // Every cell's inner face lies on the wall's inner face (y = 0 for wall 0) and the slab
        // extends outward (y < 0).
        for c in room.cells_of(w0) {
            assert!((c.center.y + 0.05).abs() < 1e-12);
            assert!((c.half_extents.y - 0.05).abs() < 1e-12);
        }
        assert_eq!(room.walls()[1].cells.len(), 1);
        assert_eq!(room.wall_cells().len(), 3 + 1 + 4 + 1);
    }

    #[test]
    fn floor_ceiling_and_openings() {
        let room = bedroom();
        let tri_area: Real = room
            .floor_triangles()
            .iter()
            .map(|[a, b, c]| 0.5 * (b - a).perp(&(c - a)))
            .sum();
        assert!((tri_area - 20.0).abs() < 1e-12);
        assert_eq!(room.ceiling_z(), Some(2.8));
        assert!(
            room.ceiling_triangles()
                .iter()
                .all(|t| t.iter().all(|p| p.z == 2.8))
        );
        assert_eq!(room.floor_centroid(), Point2::new(2.0, 2.5));
        let door = &room.openings()[0];
        assert_eq!(door.kind, OpeningKind::Door);
        assert!((door.obb.center - Point3::new(1.45, -0.05, 1.05)).norm() < 1e-12);
        assert_eq!(room.floor_id(), "floor_r");
        assert_eq!(
            room.floor_rectangle(),
            (Point2::new(2.0, 2.5), Vector2::new(4.0, 5.0))
        );
    }

    #[test]
    fn minimum_rectangle_of_turned_and_l_shaped_floors() {
        // A 4 x 5 rectangle turned by 0.5 rad: the rectangle is the room itself.
        let (c, s) = (0.5f64.cos(), 0.5f64.sin());
        let turned: Vec<Point2> = [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]]
            .iter()
            .map(|p| Point2::new(c * p[0] - s * p[1] + 1.0, s * p[0] + c * p[1] - 2.0))
            .collect();
        let (centre, dims) = min_area_rectangle(&turned);
        let mut d = [dims.x, dims.y];
        d.sort_by(|a, b| a.total_cmp(b));
        assert!((d[0] - 4.0).abs() < 1e-12 && (d[1] - 5.0).abs() < 1e-12, "{dims}");
        let expected = Point2::new(c * 2.0 - s * 2.5 + 1.0, s * 2.0 + c * 2.5 - 2.0);
        assert!((centre - expected).norm() < 1e-12);
        // An L inside the 4 x 4 square keeps the square.
        let l = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 2.0],
            [2.0, 2.0],
            [2.0, 4.0],
            [0.0, 4.0],
        ]
        .map(|p| Point2::new(p[0], p[1]));
        assert_eq!(
            min_area_rectangle(&l),
            (Point2::new(2.0, 2.0), Vector2::new(4.0, 4.0))
        );
    }

    #[test]
    fn bad_rooms_are_reported() {
        let square = vec![
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(1.0, 1.0),
            Point2::new(0.0, 1.0),
        ];
        let door_on_wall_9 = OpeningSpec {
            kind: OpeningKind::Door,
            wall: 9,
            along: [0.1, 0.5],
            height: [0.0, 2.0],
        };
        assert!(matches!(
            RoomGeometry::from_outline("r", square.clone(), 0.0, 2.8, 0.1, &[door_on_wall_9]),
            Err(RelationError::BadRoom { .. })
        ));
        assert!(RoomGeometry::from_outline("r", square.clone(), 0.0, -1.0, 0.1, &[]).is_err());
        assert!(RoomGeometry::from_outline("r", square[..2].to_vec(), 0.0, 2.8, 0.1, &[]).is_err());
    }
}
