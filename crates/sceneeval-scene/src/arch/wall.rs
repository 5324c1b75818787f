//! Walls: a segment on the floor plan (the inner face), heights and thickness, openings, and
//! the solid that is left once the openings are cut out, prepared once as boxes and as a mesh.

use std::sync::Arc;

use sceneeval_geom::na::Matrix3;
use sceneeval_geom::{Mesh, Obb, Plane, Point2, Point3, Real, Rotation3, Vector2, Vector3};

use crate::{Element, Opening, RoomId, SceneError};

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
    /// Decided by the room's floor: the wall lies on an edge of the floor polygon and the
    /// inward side is the floor's side of that edge (from the outline's winding; no
    /// point-in-polygon test, so a room of `n` walls is prepared in `O(n)`), or a point just
    /// off one side of the wall is in the floor and the mirrored point is not.
    Floor,
    /// Both or neither side is in the floor (a partition inside the room, or a wall far from
    /// its floor); the side facing the floor's centroid was taken.
    Centroid,
}

/// A wall oriented into its room, with its solid (the slab with doors and windows cut out) as
/// boxes and as a world-space mesh, both prepared once from one grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    spec: WallSpec,
    element: Element,
    length: Real,
    direction: Vector2,
    inward: Vector2,
    rotation: Rotation3,
    evidence: InwardEvidence,
    solid: Vec<Obb>,
    mesh: Option<Arc<Mesh>>,
}

impl Wall {
    /// Builds wall number `index` of room `room`, with the inward side already decided.
    pub(super) fn new(
        mut spec: WallSpec,
        room: &RoomId,
        index: usize,
        inward: impl FnOnce(&Point2, &Point2) -> (Vector2, InwardEvidence),
    ) -> Result<Self, SceneError> {
        let element = Element::Wall {
            room: room.clone(),
            wall: index,
            id: spec.id.clone(),
        };
        let finite2 = |p: &Point2| p.x.is_finite() && p.y.is_finite();
        if !finite2(&spec.start) || !finite2(&spec.end) {
            return Err(SceneError::NonFiniteWall {
                wall: Box::new(element),
                what: "end point",
            });
        }
        if !spec.base_z.is_finite() {
            return Err(SceneError::NonFiniteWall {
                wall: Box::new(element),
                what: "base height",
            });
        }
        if !(spec.height.is_finite() && spec.height > 0.0) {
            return Err(SceneError::BadWallHeight {
                wall: Box::new(element),
                height: spec.height,
            });
        }
        if !(spec.thickness.is_finite() && spec.thickness >= 0.0) {
            return Err(SceneError::BadWallThickness {
                wall: Box::new(element),
                thickness: spec.thickness,
            });
        }
        let d = spec.end - spec.start;
        let length = d.norm();
        if length == 0.0 {
            return Err(SceneError::ZeroLengthWall {
                wall: Box::new(element),
            });
        }
        let direction = d / length;
        for (k, opening) in spec.openings.iter_mut().enumerate() {
            let at = Element::Opening {
                room: room.clone(),
                wall: index,
                wall_id: spec.id.clone(),
                opening: k,
                id: opening.id.clone(),
            };
            clip_opening(at, opening, length, spec.height)?;
        }
        for (k, o) in spec.openings.iter().enumerate() {
            if let Some(first) = spec.openings[..k].iter().position(|p| p.id == o.id) {
                let at = |i: usize| Element::Opening {
                    room: room.clone(),
                    wall: index,
                    wall_id: spec.id.clone(),
                    opening: i,
                    id: o.id.clone(),
                };
                return Err(SceneError::DuplicateOpeningId {
                    id: o.id.clone(),
                    first: Box::new(at(first)),
                    second: Box::new(at(k)),
                });
            }
        }
        let (inward, evidence) = inward(&spec.start, &spec.end);
        if evidence == InwardEvidence::Centroid {
            tracing::debug!(wall = %element, "wall inward side decided by the floor centroid");
        }
        let mut wall = Wall {
            spec,
            element,
            length,
            direction,
            inward,
            rotation: wall_rotation(inward),
            evidence,
            solid: Vec::new(),
            mesh: None,
        };
        let grid = Grid::new(&wall.spec, length);
        wall.solid = grid.boxes(&wall);
        wall.mesh = if wall.solid.is_empty() {
            tracing::warn!(wall = %wall.element, "doors and windows cover the whole wall: it has no solid part");
            None
        } else {
            let mesh = grid.mesh(&wall).map_err(|source| SceneError::Geometry {
                element: Box::new(wall.element.clone()),
                source,
            })?;
            Some(Arc::new(mesh))
        };
        Ok(wall)
    }

    /// The wall's id.
    #[inline]
    pub fn id(&self) -> &str {
        &self.spec.id
    }

    /// The wall as an element of its room (for errors and warnings).
    #[inline]
    pub fn element(&self) -> &Element {
        &self.element
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
    #[inline]
    pub fn rotation(&self) -> Rotation3 {
        self.rotation
    }

    /// The world point at `along` metres from the start, `up` metres above the base, on the
    /// inner face.
    #[inline]
    pub fn point_on_inner_face(&self, along: Real, up: Real) -> Point3 {
        let p = self.spec.start + self.direction * along;
        Point3::new(p.x, p.y, self.spec.base_z + up)
    }

    /// The wall's solid box: the inner face at the segment, extending `thickness` away from the
    /// room (flat when the thickness is 0). Openings are not subtracted; see
    /// [`Wall::solid_boxes`] and [`Wall::mesh`].
    pub fn obb(&self) -> Obb {
        let mid = self.point_on_inner_face(self.length * 0.5, self.spec.height * 0.5);
        Obb {
            center: mid - self.inward_normal_3d() * (self.spec.thickness * 0.5),
            half_extents: Vector3::new(
                self.length * 0.5,
                self.spec.thickness * 0.5,
                self.spec.height * 0.5,
            ),
            rotation: self.rotation,
        }
    }

    /// The wall's solid with its doors and windows cut out, as boxes in the wall's frame: the
    /// slab split on every opening edge, vertically adjacent solid pieces merged into one box
    /// per column run. Empty when openings cover the whole wall.
    #[inline]
    pub fn solid_boxes(&self) -> &[Obb] {
        &self.solid
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
            rotation: self.rotation,
        }
    }

    /// The world-space mesh of the solid: a closed slab with the openings cut through (a single
    /// sheet when the thickness is 0); `None` when doors and windows cover the whole wall.
    #[inline]
    pub fn mesh(&self) -> Option<&Arc<Mesh>> {
        self.mesh.as_ref()
    }
}

/// The wall frame for an inward normal: local -y into the room, z up.
fn wall_rotation(inward: Vector2) -> Rotation3 {
    let y = -Vector3::new(inward.x, inward.y, 0.0);
    let z = Vector3::z();
    let x = y.cross(&z);
    Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]))
}

/// Clips an opening to the wall rectangle; errors if nothing is left or it is malformed.
fn clip_opening(at: Element, o: &mut Opening, length: Real, height: Real) -> Result<(), SceneError> {
    let bad = |at: Element, reason: String| SceneError::BadOpening {
        opening: Box::new(at),
        reason,
    };
    if !o.along.iter().chain(o.height.iter()).all(|v| v.is_finite()) {
        return Err(bad(at, "coordinates are not finite".into()));
    }
    if o.along[0] >= o.along[1] || o.height[0] >= o.height[1] {
        return Err(bad(
            at,
            format!(
                "empty or inverted rectangle: along {:?}, height {:?}",
                o.along, o.height
            ),
        ));
    }
    let along = [o.along[0].max(0.0), o.along[1].min(length)];
    let up = [o.height[0].max(0.0), o.height[1].min(height)];
    if along[0] >= along[1] || up[0] >= up[1] {
        return Err(bad(
            at,
            format!(
                "lies outside the wall (along {:?} on a {length} m wall, height {:?} on a {height} m wall)",
                o.along, o.height
            ),
        ));
    }
    if along != o.along || up != o.height {
        tracing::warn!(opening = %at, ?along, height = ?up, "opening clipped to its wall");
        o.along = along;
        o.height = up;
    }
    Ok(())
}

/// The grid every opening edge cuts the wall rectangle into: `us` along the wall, `ws` up
/// from its base, and which cells are solid (not inside an opening). The wall's boxes and its
/// mesh are both read from it.
struct Grid {
    us: Vec<Real>,
    ws: Vec<Real>,
    /// Row-major by column: `solid[i * (ws.len() - 1) + j]` for cell `[us[i], us[i+1]] x
    /// [ws[j], ws[j+1]]`.
    solid: Vec<bool>,
}

impl Grid {
    fn new(spec: &WallSpec, length: Real) -> Self {
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
        let (nu, nw) = (us.len() - 1, ws.len() - 1);
        let mut solid = Vec::with_capacity(nu * nw);
        for i in 0..nu {
            for j in 0..nw {
                let (u, w) = (0.5 * (us[i] + us[i + 1]), 0.5 * (ws[j] + ws[j + 1]));
                solid.push(
                    !spec
                        .openings
                        .iter()
                        .any(|o| u > o.along[0] && u < o.along[1] && w > o.height[0] && w < o.height[1]),
                );
            }
        }
        Grid { us, ws, solid }
    }

    /// Whether cell `(i, j)` is solid (false outside the grid).
    fn solid(&self, i: usize, j: usize) -> bool {
        let nw = self.ws.len() - 1;
        i < self.us.len() - 1 && j < nw && self.solid[i * nw + j]
    }

    /// The solid as boxes: per column, each vertical run of solid cells.
    fn boxes(&self, wall: &Wall) -> Vec<Obb> {
        let inward = wall.inward_normal_3d();
        let t = wall.spec.thickness;
        let make = |u0: Real, u1: Real, w0: Real, w1: Real| {
            let face = wall.point_on_inner_face(0.5 * (u0 + u1), 0.5 * (w0 + w1));
            Obb {
                center: face - inward * (0.5 * t),
                half_extents: Vector3::new(0.5 * (u1 - u0), 0.5 * t, 0.5 * (w1 - w0)),
                rotation: wall.rotation,
            }
        };
        let mut out = Vec::new();
        for i in 0..self.us.len() - 1 {
            let (u0, u1) = (self.us[i], self.us[i + 1]);
            let mut run: Option<Real> = None;
            for j in 0..self.ws.len() - 1 {
                if self.solid(i, j) {
                    run.get_or_insert(self.ws[j]);
                } else if let Some(start) = run.take() {
                    out.push(make(u0, u1, start, self.ws[j]));
                }
            }
            if let Some(start) = run {
                out.push(make(u0, u1, start, wall.spec.height));
            }
        }
        out
    }

    /// The solid as a world-space mesh: the inner and outer face of every solid cell, and side
    /// faces where the neighbouring cell is empty (an opening or outside the wall).
    fn mesh(&self, wall: &Wall) -> Result<Mesh, sceneeval_geom::GeomError> {
        let spec = &wall.spec;
        let (us, ws) = (&self.us, &self.ws);
        let t = spec.thickness;
        let outward = -wall.inward;
        let dir = wall.direction;
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
        for i in 0..us.len() - 1 {
            for j in 0..ws.len() - 1 {
                if !self.solid(i, j) {
                    continue;
                }
                let (u0, u1, w0, w1) = (us[i], us[i + 1], ws[j], ws[j + 1]);
                quad(at(u0, 0.0, w0), at(u1, 0.0, w0), at(u1, 0.0, w1), at(u0, 0.0, w1));
                if t > 0.0 {
                    quad(at(u0, t, w0), at(u0, t, w1), at(u1, t, w1), at(u1, t, w0));
                    if i == 0 || !self.solid(i - 1, j) {
                        quad(at(u0, 0.0, w0), at(u0, 0.0, w1), at(u0, t, w1), at(u0, t, w0));
                    }
                    if !self.solid(i + 1, j) {
                        quad(at(u1, 0.0, w0), at(u1, t, w0), at(u1, t, w1), at(u1, 0.0, w1));
                    }
                    if j == 0 || !self.solid(i, j - 1) {
                        quad(at(u0, 0.0, w0), at(u0, t, w0), at(u1, t, w0), at(u1, 0.0, w0));
                    }
                    if !self.solid(i, j + 1) {
                        quad(at(u0, 0.0, w1), at(u1, 0.0, w1), at(u1, t, w1), at(u0, t, w1));
                    }
                }
            }
        }
        Mesh::new(vertices, tris)
    }
}
