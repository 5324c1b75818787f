//! Architecture: rooms with a floor polygon, walls with door and window openings, ceilings.
//!
//! # Wall geometry
//! A wall is given by a segment on the floor plan (`start` to `end`), a base height, a height
//! and a thickness. **The segment is the wall's inner face**, the side toward its room; the
//! thickness extends away from the room. (The reference builds 1 mm walls centred on the
//! segment, so its inner face is 0.5 mm from ours.)
//!
//! Each wall is oriented against **its own room's floor polygon**: its inward normal points
//! into that room, for walls at any angle and in scenes with several rooms. The reference tests
//! every wall against the last floor it read and only handles axis-aligned walls
//! (reference notes Q8, Q9).
//!
//! The wall frame puts local -y into the room (a wall's front faces its room, as an object's
//! front is local -y), z up, and x completing a right-handed frame.
//!
//! Openings are rectangles in wall coordinates: `along` is measured from the wall's start
//! point toward its end, `height` above the wall's base.

use std::sync::Arc;

use sceneeval_geom::na::Matrix3;
use sceneeval_geom::{Aabb, Mesh, Obb, Plane, Point2, Point3, Polygon2, Real, Rotation3, Vector2, Vector3};

use crate::{RoomId, SceneError};

/// Whether an opening is a door or a window.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum OpeningKind {
    /// A door.
    Door,
    /// A window.
    Window,
}

impl OpeningKind {
    /// `"door"` or `"window"`.
    pub const fn name(self) -> &'static str {
        match self {
            OpeningKind::Door => "door",
            OpeningKind::Window => "window",
        }
    }
}

/// A door or window: a rectangular hole through a wall, in wall coordinates.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Opening {
    /// The opening's id (unique within its wall).
    pub id: String,
    /// Door or window.
    pub kind: OpeningKind,
    /// Start and end along the wall, metres from the wall's start point.
    pub along: [Real; 2],
    /// Bottom and top, metres above the wall's base.
    pub height: [Real; 2],
}

impl Opening {
    /// A door or window spanning `along` and `height` (wall coordinates, metres).
    pub fn new(id: impl Into<String>, kind: OpeningKind, along: [Real; 2], height: [Real; 2]) -> Self {
        Opening {
            id: id.into(),
            kind,
            along,
            height,
        }
    }

    /// Width along the wall.
    #[inline]
    pub fn width(&self) -> Real {
        self.along[1] - self.along[0]
    }

    /// Height of the hole.
    #[inline]
    pub fn hole_height(&self) -> Real {
        self.height[1] - self.height[0]
    }
}

/// The plain description of a wall, before it is oriented against its room.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WallSpec {
    /// The wall's id (unique in the scene).
    pub id: String,
    /// Start of the inner-face segment on the floor plan.
    pub start: Point2,
    /// End of the inner-face segment on the floor plan.
    pub end: Point2,
    /// World z of the wall's bottom.
    pub base_z: Real,
    /// Height in metres.
    pub height: Real,
    /// Thickness in metres, extending away from the room (0 for a zero-thickness sheet).
    pub thickness: Real,
    /// Doors and windows.
    pub openings: Vec<Opening>,
}

impl WallSpec {
    /// A wall without openings.
    pub fn new(
        id: impl Into<String>,
        start: Point2,
        end: Point2,
        base_z: Real,
        height: Real,
        thickness: Real,
    ) -> Self {
        WallSpec {
            id: id.into(),
            start,
            end,
            base_z,
            height,
            thickness,
            openings: Vec::new(),
        }
    }
}

/// How a wall's inward side was decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InwardEvidence {
    /// A point just off one side of the wall is in the room's floor and the mirrored point is not.
    Floor,
    /// Both or neither side is in the floor (a partition inside the room, or a wall far from
    /// its floor); the side facing the floor's centroid was taken.
    Centroid,
}

/// A wall oriented into its room, with its world-space mesh (openings cut out).
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    spec: WallSpec,
    length: Real,
    direction: Vector2,
    inward: Vector2,
    evidence: InwardEvidence,
    mesh: Arc<Mesh>,
}

impl Wall {
    fn new(mut spec: WallSpec, floor: &Polygon2) -> Result<Self, SceneError> {
        let id = spec.id.clone();
        let finite2 = |p: &Point2| p.x.is_finite() && p.y.is_finite();
        if !finite2(&spec.start) || !finite2(&spec.end) {
            return Err(SceneError::NonFiniteWall {
                wall: id,
                what: "end point",
            });
        }
        if !spec.base_z.is_finite() {
            return Err(SceneError::NonFiniteWall {
                wall: id,
                what: "base height",
            });
        }
        if !(spec.height.is_finite() && spec.height > 0.0) {
            return Err(SceneError::BadWallHeight {
                wall: id,
                height: spec.height,
            });
        }
        if !(spec.thickness.is_finite() && spec.thickness >= 0.0) {
            return Err(SceneError::BadWallThickness {
                wall: id,
                thickness: spec.thickness,
            });
        }
        let d = spec.end - spec.start;
        let length = d.norm();
        if length == 0.0 {
            return Err(SceneError::ZeroLengthWall { wall: id });
        }
        let direction = d / length;
        for opening in &mut spec.openings {
            clip_opening(&id, opening, length, spec.height)?;
        }
        let (inward, evidence) = inward_normal(&spec.start, &spec.end, floor);
        if evidence == InwardEvidence::Centroid {
            tracing::debug!(wall = %id, "wall inward side decided by the floor centroid");
        }
        let mesh = wall_mesh(&spec, length, direction, inward)
            .map_err(|e| SceneError::geometry(format!("wall {id:?} mesh"), e))?;
        Ok(Wall {
            spec,
            length,
            direction,
            inward,
            evidence,
            mesh: Arc::new(mesh),
        })
    }

    /// The wall's id.
    #[inline]
    pub fn id(&self) -> &str {
        &self.spec.id
    }

    /// The plain description the wall was built from (openings clipped to the wall).
    #[inline]
    pub fn spec(&self) -> &WallSpec {
        &self.spec
    }

    /// Start of the inner-face segment.
    #[inline]
    pub fn start(&self) -> Point2 {
        self.spec.start
    }

    /// End of the inner-face segment.
    #[inline]
    pub fn end(&self) -> Point2 {
        self.spec.end
    }

    /// World z of the wall's bottom.
    #[inline]
    pub fn base_z(&self) -> Real {
        self.spec.base_z
    }

    /// Height in metres.
    #[inline]
    pub fn height(&self) -> Real {
        self.spec.height
    }

    /// World z of the wall's top.
    #[inline]
    pub fn top_z(&self) -> Real {
        self.spec.base_z + self.spec.height
    }

    /// Thickness in metres (extending away from the room).
    #[inline]
    pub fn thickness(&self) -> Real {
        self.spec.thickness
    }

    /// Doors and windows, clipped to the wall.
    #[inline]
    pub fn openings(&self) -> &[Opening] {
        &self.spec.openings
    }

    /// Length of the segment.
    #[inline]
    pub fn length(&self) -> Real {
        self.length
    }

    /// Unit direction from start to end.
    #[inline]
    pub fn direction(&self) -> Vector2 {
        self.direction
    }

    /// Unit normal of the inner face, pointing into the room (floor plan).
    #[inline]
    pub fn inward_normal(&self) -> Vector2 {
        self.inward
    }

    /// The inward normal as a 3-D vector (z = 0).
    #[inline]
    pub fn inward_normal_3d(&self) -> Vector3 {
        Vector3::new(self.inward.x, self.inward.y, 0.0)
    }

    /// How the inward side was decided.
    #[inline]
    pub fn inward_evidence(&self) -> InwardEvidence {
        self.evidence
    }

    /// The plane of the inner face, its normal pointing into the room.
    pub fn inner_plane(&self) -> Plane {
        Plane {
            normal: self.inward_normal_3d(),
            offset: self.inward.dot(&self.spec.start.coords),
        }
    }

    /// The wall frame's rotation: local -y into the room, z up, x completing a right-handed frame.
    pub fn rotation(&self) -> Rotation3 {
        let y = -self.inward_normal_3d();
        let z = Vector3::z();
        let x = y.cross(&z);
        Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]))
    }

    /// The world point at `along` metres from the start, `up` metres above the base, on the
    /// inner face.
    pub fn point_on_inner_face(&self, along: Real, up: Real) -> Point3 {
        let p = self.spec.start + self.direction * along;
        Point3::new(p.x, p.y, self.spec.base_z + up)
    }

    /// The wall's solid box: the inner face at the segment, extending `thickness` away from the
    /// room (flat when the thickness is 0). Openings are not subtracted; see [`Wall::mesh`].
    pub fn obb(&self) -> Obb {
        let mid = self.point_on_inner_face(self.length * 0.5, self.spec.height * 0.5);
        Obb {
            center: mid - self.inward_normal_3d() * (self.spec.thickness * 0.5),
            half_extents: Vector3::new(
                self.length * 0.5,
                self.spec.thickness * 0.5,
                self.spec.height * 0.5,
            ),
            rotation: self.rotation(),
        }
    }

    /// The box of an opening: its rectangle on the inner face, as deep as the wall (at least
    /// 1 mm), in the wall's frame. Its local -y points into the room.
    pub fn opening_obb(&self, opening: &Opening) -> Obb {
        let depth = self.spec.thickness.max(1e-3);
        let mid_along = 0.5 * (opening.along[0] + opening.along[1]);
        let mid_up = 0.5 * (opening.height[0] + opening.height[1]);
        let face = self.point_on_inner_face(mid_along, mid_up);
        Obb {
            center: face - self.inward_normal_3d() * (depth * 0.5),
            half_extents: Vector3::new(opening.width() * 0.5, depth * 0.5, opening.hole_height() * 0.5),
            rotation: self.rotation(),
        }
    }

    /// The world-space mesh: a closed slab with the openings cut through (a single sheet when
    /// the thickness is 0).
    #[inline]
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }
}

/// Clips an opening to the wall rectangle; errors if nothing is left or it is malformed.
fn clip_opening(wall: &str, o: &mut Opening, length: Real, height: Real) -> Result<(), SceneError> {
    let bad = |reason: String| SceneError::BadOpening {
        wall: wall.to_owned(),
        opening: o.id.clone(),
        reason,
    };
    if !o.along.iter().chain(o.height.iter()).all(|v| v.is_finite()) {
        return Err(bad("coordinates are not finite".into()));
    }
    if o.along[0] >= o.along[1] || o.height[0] >= o.height[1] {
        return Err(bad(format!(
            "empty or inverted rectangle: along {:?}, height {:?}",
            o.along, o.height
        )));
    }
    let along = [o.along[0].max(0.0), o.along[1].min(length)];
    let up = [o.height[0].max(0.0), o.height[1].min(height)];
    if along[0] >= along[1] || up[0] >= up[1] {
        return Err(bad(format!(
            "lies outside the wall (along {:?} on a {length} m wall, height {:?} on a {height} m wall)",
            o.along, o.height
        )));
    }
    if along != o.along || up != o.height {
        tracing::warn!(wall, opening = %o.id, ?along, height = ?up, "opening clipped to its wall");
        o.along = along;
        o.height = up;
    }
    Ok(())
}

/// Decides which side of the segment faces into `floor` (see [`InwardEvidence`]).
fn inward_normal(start: &Point2, end: &Point2, floor: &Polygon2) -> (Vector2, InwardEvidence) {
    let d = end - start;
    let len = d.norm();
    let left = Vector2::new(-d.y, d.x) / len;
    for frac in [0.5, 0.25, 0.75, 0.1, 0.9] {
        let m = start + d * frac;
        for delta in [1e-3, 1e-2, 5e-2, 0.2, 0.5] {
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

/// Builds the wall's world-space mesh with openings cut through, from a grid of cells between
/// every opening edge.
fn wall_mesh(
    spec: &WallSpec,
    length: Real,
    dir: Vector2,
    inward: Vector2,
) -> Result<Mesh, sceneeval_geom::GeomError> {
    let mut us = vec![0.0, length];
    let mut ws = vec![0.0, spec.height];
    for o in &spec.openings {
        us.extend(o.along);
        ws.extend(o.height);
    }
    for v in [&mut us, &mut ws] {
        v.sort_by(|a, b| a.total_cmp(b));
        v.dedup();
    }
    let solid = |i: usize, j: usize| -> bool {
        if i >= us.len() - 1 || j >= ws.len() - 1 {
            return false;
        }
        let (u, w) = (0.5 * (us[i] + us[i + 1]), 0.5 * (ws[j] + ws[j + 1]));
        !spec
            .openings
            .iter()
            .any(|o| u > o.along[0] && u < o.along[1] && w > o.height[0] && w < o.height[1])
    };
    let t = spec.thickness;
    let outward = -inward;
    let at = |u: Real, v: Real, w: Real| {
        let p = spec.start + dir * u + outward * v;
        Point3::new(p.x, p.y, spec.base_z + w)
    };
    let mut vertices: Vec<Point3> = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut quad = |a: Point3, b: Point3, c: Point3, d: Point3| {
        let base = vertices.len() as u32;
        vertices.extend([a, b, c, d]);
        tris.push([base, base + 1, base + 2]);
        tris.push([base, base + 2, base + 3]);
    };
    let (nu, nw) = (us.len() - 1, ws.len() - 1);
    for i in 0..nu {
        for j in 0..nw {
            if !solid(i, j) {
                continue;
            }
            let (u0, u1, w0, w1) = (us[i], us[i + 1], ws[j], ws[j + 1]);
            quad(at(u0, 0.0, w0), at(u1, 0.0, w0), at(u1, 0.0, w1), at(u0, 0.0, w1));
            if t > 0.0 {
                quad(at(u0, t, w0), at(u0, t, w1), at(u1, t, w1), at(u1, t, w0));
                // Side faces where the neighbouring cell is empty (an opening or outside the wall).
                if i == 0 || !solid(i - 1, j) {
                    quad(at(u0, 0.0, w0), at(u0, 0.0, w1), at(u0, t, w1), at(u0, t, w0));
                }
                if !solid(i + 1, j) {
                    quad(at(u1, 0.0, w0), at(u1, t, w0), at(u1, t, w1), at(u1, 0.0, w1));
                }
                if j == 0 || !solid(i, j - 1) {
                    quad(at(u0, 0.0, w0), at(u0, t, w0), at(u1, t, w0), at(u1, 0.0, w0));
                }
                if !solid(i, j + 1) {
                    quad(at(u0, 0.0, w1), at(u1, 0.0, w1), at(u1, t, w1), at(u0, t, w1));
                }
            }
        }
    }
    Mesh::new(vertices, tris)
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
#[derive(Debug, Clone, PartialEq)]
pub struct Room {
    id: RoomId,
    kind: Option<String>,
    floor_id: String,
    floor: Polygon2,
    floor_z: Real,
    walls: Vec<Wall>,
    ceiling: Option<Ceiling>,
    floor_mesh: Arc<Mesh>,
    ceiling_mesh: Option<Arc<Mesh>>,
}

impl Room {
    /// A room from its floor outline at height `floor_z` and its walls, each oriented into
    /// this floor. `floor_id` names the floor element (the reference uses `floor_<roomId>`).
    pub fn new(
        id: impl Into<RoomId>,
        floor_id: impl Into<String>,
        floor: Polygon2,
        floor_z: Real,
        walls: Vec<WallSpec>,
        ceiling: Option<Ceiling>,
    ) -> Result<Self, SceneError> {
        let id = id.into();
        if !floor_z.is_finite() {
            return Err(SceneError::NonFiniteRoom {
                room: id.to_string(),
                what: "floor height",
            });
        }
        if let Some(c) = &ceiling
            && !c.z.is_finite()
        {
            return Err(SceneError::NonFiniteRoom {
                room: id.to_string(),
                what: "ceiling height",
            });
        }
        let walls = walls
            .into_iter()
            .map(|w| Wall::new(w, &floor))
            .collect::<Result<Vec<_>, _>>()?;
        let floor_mesh = flat_mesh(&floor, floor_z, true)
            .map_err(|e| SceneError::geometry(format!("room {:?} floor", id.as_str()), e))?;
        let ceiling_z = ceiling
            .as_ref()
            .map(|c| c.z)
            .or_else(|| walls.iter().map(Wall::top_z).reduce(Real::max));
        let ceiling_mesh = match (ceiling_z, &ceiling) {
            (Some(z), c) => Some(Arc::new(
                flat_mesh(c.as_ref().map_or(&floor, |c| &c.polygon), z, false)
                    .map_err(|e| SceneError::geometry(format!("room {:?} ceiling", id.as_str()), e))?,
            )),
            (None, _) => None,
        };
        Ok(Room {
            id,
            kind: None,
            floor_id: floor_id.into(),
            floor,
            floor_z,
            walls,
            ceiling,
            floor_mesh: Arc::new(floor_mesh),
            ceiling_mesh,
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
        &self.floor_id
    }

    /// The floor outline.
    #[inline]
    pub fn floor(&self) -> &Polygon2 {
        &self.floor
    }

    /// World z of the floor surface.
    #[inline]
    pub fn floor_z(&self) -> Real {
        self.floor_z
    }

    /// The walls, oriented into this room.
    #[inline]
    pub fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// The explicit ceiling, if the scene gave one.
    #[inline]
    pub fn explicit_ceiling(&self) -> Option<&Ceiling> {
        self.ceiling.as_ref()
    }

    /// World z of the ceiling: the explicit ceiling's, else the highest wall top, else `None`
    /// (a room without walls or ceiling has no ceiling). The reference instead raises every
    /// floor by the tallest wall of the whole scene.
    pub fn ceiling_z(&self) -> Option<Real> {
        self.ceiling
            .as_ref()
            .map(|c| c.z)
            .or_else(|| self.walls.iter().map(Wall::top_z).reduce(Real::max))
    }

    /// The ceiling's outline: the explicit ceiling's, else the floor's.
    pub fn ceiling_polygon(&self) -> &Polygon2 {
        self.ceiling.as_ref().map_or(&self.floor, |c| &c.polygon)
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

    /// The floor's bounding box in world coordinates (flat, at `floor_z`).
    pub fn floor_aabb(&self) -> Aabb {
        let (min, max) = self.floor.bounds();
        Aabb::new(
            Point3::new(min.x, min.y, self.floor_z),
            Point3::new(max.x, max.y, self.floor_z),
        )
    }
}

/// A flat triangulated polygon at height `z`, normals up (`up`) or down.
fn flat_mesh(poly: &Polygon2, z: Real, up: bool) -> Result<Mesh, sceneeval_geom::GeomError> {
    let vertices = poly.points().iter().map(|p| Point3::new(p.x, p.y, z)).collect();
    let tris = poly
        .triangulate()
        .into_iter()
        .map(|[a, b, c]| {
            if up {
                [a as u32, b as u32, c as u32]
            } else {
                [a as u32, c as u32, b as u32]
            }
        })
        .collect();
    Mesh::new(vertices, tris)
}

/// Builds a room from a floor outline, with one wall per edge (wall `i` from point `i` to
/// point `i + 1`, wrapping) and doors and windows by wall index.
///
/// ```
/// use sceneeval_scene::{OpeningKind, RoomBuilder};
/// use sceneeval_geom::Point2;
///
/// let room = RoomBuilder::rectangle("bedroom", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
///     .wall_height(2.8)
///     .wall_thickness(0.1)
///     .door(0, [1.0, 1.9], [0.0, 2.1])
///     .window(2, [1.0, 2.5], [0.9, 2.0])
///     .build()
///     .unwrap();
/// assert_eq!(room.walls().len(), 4);
/// // Wall 0 runs along y = 0 from x = 0 to x = 4; the room is on its +y side.
/// assert_eq!(room.walls()[0].inward_normal(), sceneeval_geom::Vector2::new(0.0, 1.0));
/// assert_eq!(room.ceiling_z(), Some(2.8));
/// ```
#[derive(Debug, Clone)]
pub struct RoomBuilder {
    id: RoomId,
    kind: Option<String>,
    outline: Vec<Point2>,
    floor_z: Real,
    height: Real,
    thickness: Real,
    openings: Vec<(usize, OpeningKind, [Real; 2], [Real; 2])>,
    ceiling: bool,
}

impl RoomBuilder {
    /// A room whose floor is `outline` (either winding). Defaults: floor at z = 0, walls 2.8 m
    /// high and 0.1 m thick, no openings, ceiling implied by the walls.
    pub fn polygon(id: impl Into<RoomId>, outline: Vec<Point2>) -> Self {
        RoomBuilder {
            id: id.into(),
            kind: None,
            outline,
            floor_z: 0.0,
            height: 2.8,
            thickness: 0.1,
            openings: Vec::new(),
            ceiling: false,
        }
    }

    /// An axis-aligned rectangular room (counter-clockwise from `min`: wall 0 runs along
    /// `y = min.y` toward +x, then +x side, then `y = max.y`, then `x = min.x`).
    pub fn rectangle(id: impl Into<RoomId>, min: Point2, max: Point2) -> Self {
        RoomBuilder::polygon(
            id,
            vec![min, Point2::new(max.x, min.y), max, Point2::new(min.x, max.y)],
        )
    }

    /// Sets the room type (e.g. `bedroom`).
    pub fn kind(mut self, kind: impl Into<String>) -> Self {
        self.kind = Some(kind.into());
        self
    }

    /// Sets the floor height (world z).
    pub fn floor_z(mut self, z: Real) -> Self {
        self.floor_z = z;
        self
    }

    /// Sets every wall's height.
    pub fn wall_height(mut self, h: Real) -> Self {
        self.height = h;
        self
    }

    /// Sets every wall's thickness.
    pub fn wall_thickness(mut self, t: Real) -> Self {
        self.thickness = t;
        self
    }

    /// Adds an explicit ceiling over the floor outline at the top of the walls.
    pub fn with_ceiling(mut self) -> Self {
        self.ceiling = true;
        self
    }

    /// Adds a door in wall `wall` (see [`Opening`] for the coordinates).
    pub fn door(mut self, wall: usize, along: [Real; 2], height: [Real; 2]) -> Self {
        self.openings.push((wall, OpeningKind::Door, along, height));
        self
    }

    /// Adds a window in wall `wall`.
    pub fn window(mut self, wall: usize, along: [Real; 2], height: [Real; 2]) -> Self {
        self.openings.push((wall, OpeningKind::Window, along, height));
        self
    }

    /// Builds the room. Wall ids are `<room>_wall_<i>`, opening ids `<wall>_<door|window>_<k>`,
    /// the floor id `floor_<room>`.
    pub fn build(self) -> Result<Room, SceneError> {
        let room = self.id.to_string();
        let floor = Polygon2::new(self.outline)
            .map_err(|e| SceneError::geometry(format!("room {room:?} floor"), e))?;
        let n = floor.len();
        let mut walls: Vec<WallSpec> = (0..n)
            .map(|i| {
                let (a, b) = floor.edge(i);
                WallSpec::new(
                    format!("{room}_wall_{i}"),
                    a,
                    b,
                    self.floor_z,
                    self.height,
                    self.thickness,
                )
            })
            .collect();
        for (wall, kind, along, height) in self.openings {
            let w = walls.get_mut(wall).ok_or(SceneError::NoSuchWall {
                room: room.clone(),
                index: wall,
                count: n,
            })?;
            let k = w.openings.iter().filter(|o| o.kind == kind).count();
            let id = format!("{}_{}_{k}", w.id, kind.name());
            w.openings.push(Opening::new(id, kind, along, height));
        }
        let ceiling = self.ceiling.then(|| Ceiling {
            id: format!("ceiling_{room}"),
            polygon: floor.clone(),
            z: self.floor_z + self.height,
        });
        let built = Room::new(
            self.id,
            format!("floor_{room}"),
            floor,
            self.floor_z,
            walls,
            ceiling,
        )?;
        Ok(match self.kind {
            Some(k) => built.with_kind(k),
            None => built,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Isometry3;

    fn p(x: Real, y: Real) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn rectangle_walls_face_inward_either_winding() {
        for outline in [
            vec![p(0.0, 0.0), p(4.0, 0.0), p(4.0, 5.0), p(0.0, 5.0)],
            vec![p(0.0, 0.0), p(0.0, 5.0), p(4.0, 5.0), p(4.0, 0.0)],
        ] {
            let room = RoomBuilder::polygon("r", outline).build().unwrap();
            let centre = room.floor().centroid();
            for w in room.walls() {
                let mid = w.start() + w.direction() * (w.length() * 0.5);
                assert!(w.inward_normal().dot(&(centre - mid)) > 0.0, "{}", w.id());
                assert_eq!(w.inward_evidence(), InwardEvidence::Floor);
                // Frame: local -y is the inward normal, z up, right-handed.
                let r = w.rotation();
                assert!((r * -Vector3::y() - w.inward_normal_3d()).norm() < 1e-12);
                assert!((r.matrix().determinant() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn diagonal_wall_faces_inward() {
        // A right triangle: the hypotenuse from (4, 0) to (0, 4) is diagonal.
        let room = RoomBuilder::polygon("tri", vec![p(0.0, 0.0), p(4.0, 0.0), p(0.0, 4.0)])
            .build()
            .unwrap();
        let hyp = &room.walls()[1];
        let expected = Vector2::new(-1.0, -1.0) / 2f64.sqrt();
        assert!((hyp.inward_normal() - expected).norm() < 1e-12);
        // The wall box's inner face passes through the segment; the box lies outside the room.
        let obb = hyp.obb();
        let inner_face = obb.face_center(sceneeval_geom::Side::Front);
        assert!((inner_face - Point3::new(2.0, 2.0, 1.4)).norm() < 1e-12);
        assert!(
            !room
                .floor()
                .contains_point(&Point2::new(obb.center.x, obb.center.y))
        );
    }

    #[test]
    fn l_shaped_room_reflex_walls_face_inward() {
        let room = RoomBuilder::polygon(
            "l",
            vec![
                p(0.0, 0.0),
                p(4.0, 0.0),
                p(4.0, 2.0),
                p(2.0, 2.0),
                p(2.0, 4.0),
                p(0.0, 4.0),
            ],
        )
        .build()
        .unwrap();
        // Wall 2 runs (4,2) -> (2,2): the room is below it (-y). Wall 3 runs (2,2) -> (2,4): room at -x.
        assert_eq!(room.walls()[2].inward_normal(), Vector2::new(0.0, -1.0));
        assert_eq!(room.walls()[3].inward_normal(), Vector2::new(-1.0, 0.0));
    }

    #[test]
    fn wall_mesh_with_door_is_closed_and_has_a_hole() {
        let room = RoomBuilder::rectangle("r", p(0.0, 0.0), p(4.0, 5.0))
            .wall_thickness(0.1)
            .door(0, [1.0, 2.0], [0.0, 2.0])
            .build()
            .unwrap();
        let wall = &room.walls()[0];
        let mesh = wall.mesh();
        assert!(mesh.is_closed());
        // Volume: 4 x 2.8 x 0.1 minus the 1 x 2 x 0.1 door.
        assert!((mesh.volume().unwrap() - (4.0 * 2.8 - 2.0) * 0.1).abs() < 1e-9);
        let id = Isometry3::identity();
        // A ray through the door from inside the room passes; one beside it hits the wall.
        let through = sceneeval_geom::Ray::new(Point3::new(1.5, 1.0, 1.0), -Vector3::y());
        assert!(mesh.cast_ray(&id, &through, 5.0).is_none());
        let beside = sceneeval_geom::Ray::new(Point3::new(3.0, 1.0, 1.0), -Vector3::y());
        let hit = mesh.cast_ray(&id, &beside, 5.0).unwrap();
        assert!((hit.toi - 1.0).abs() < 1e-12, "hits the inner face at y = 0");
        let door = &wall.openings()[0];
        assert_eq!(door.id, "r_wall_0_door_0");
        let obb = wall.opening_obb(door);
        assert!((obb.center - Point3::new(1.5, -0.05, 1.0)).norm() < 1e-12);
        assert!((obb.half_extents - Vector3::new(0.5, 0.05, 1.0)).norm() < 1e-12);
    }

    #[test]
    fn zero_thickness_wall_is_a_sheet() {
        let room = RoomBuilder::rectangle("r", p(0.0, 0.0), p(2.0, 2.0))
            .wall_thickness(0.0)
            .window(1, [0.5, 1.5], [1.0, 2.0])
            .build()
            .unwrap();
        let w = &room.walls()[1];
        assert!((w.mesh().surface_area() - (2.0 * 2.8 - 1.0)).abs() < 1e-9);
        assert_eq!(w.obb().half_extents.y, 0.0);
    }

    #[test]
    fn bad_walls_and_openings_are_rejected() {
        let floor = Polygon2::rectangle(p(0.0, 0.0), p(2.0, 2.0)).unwrap();
        let mk = |spec: WallSpec| Room::new("r", "floor_r", floor.clone(), 0.0, vec![spec], None);
        assert!(matches!(
            mk(WallSpec::new("w", p(1.0, 1.0), p(1.0, 1.0), 0.0, 2.0, 0.1)),
            Err(SceneError::ZeroLengthWall { .. })
        ));
        assert!(matches!(
            mk(WallSpec::new("w", p(0.0, 0.0), p(2.0, 0.0), 0.0, 0.0, 0.1)),
            Err(SceneError::BadWallHeight { .. })
        ));
        assert!(matches!(
            mk(WallSpec::new("w", p(0.0, 0.0), p(2.0, 0.0), 0.0, 2.0, -0.1)),
            Err(SceneError::BadWallThickness { .. })
        ));
        let mut spec = WallSpec::new("w", p(0.0, 0.0), p(2.0, 0.0), 0.0, 2.0, 0.1);
        spec.openings
            .push(Opening::new("d", OpeningKind::Door, [3.0, 4.0], [0.0, 2.0]));
        assert!(matches!(mk(spec.clone()), Err(SceneError::BadOpening { .. })));
        spec.openings[0].along = [1.5, 2.5];
        let room = mk(spec).unwrap();
        assert_eq!(
            room.walls()[0].openings()[0].along,
            [1.5, 2.0],
            "clipped to the wall"
        );
        assert!(matches!(
            RoomBuilder::rectangle("r", p(0.0, 0.0), p(1.0, 1.0))
                .door(7, [0.0, 0.5], [0.0, 1.0])
                .build(),
            Err(SceneError::NoSuchWall {
                index: 7,
                count: 4,
                ..
            })
        ));
        assert!(matches!(
            RoomBuilder::polygon("r", vec![p(0.0, 0.0), p(1.0, 0.0)]).build(),
            Err(SceneError::Geometry { .. })
        ));
    }

    #[test]
    fn floor_and_ceiling_meshes() {
        let room = RoomBuilder::rectangle("r", p(0.0, 0.0), p(4.0, 5.0))
            .floor_z(0.5)
            .build()
            .unwrap();
        assert!((room.floor_mesh().surface_area() - 20.0).abs() < 1e-12);
        assert_eq!(room.ceiling_z(), Some(3.3));
        let id = Isometry3::identity();
        let up = sceneeval_geom::Ray::new(Point3::new(1.0, 1.0, 1.0), Vector3::z());
        let hit = room.ceiling_mesh().unwrap().cast_ray(&id, &up, 10.0).unwrap();
        assert!((hit.toi - 2.3).abs() < 1e-12);
    }
}
