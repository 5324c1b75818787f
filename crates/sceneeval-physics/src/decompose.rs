//! Convex decomposition of object meshes into the pieces a rigid body is made of.
//!
//! A rigid-body engine collides convex shapes; a chair is not convex. Each mesh is cut into
//! convex pieces with parry's V-HACD ([`rapier3d_f64::parry::transformation::vhacd`]): the mesh is
//! voxelised (`resolution` voxels along its longest side), the voxels are split recursively by
//! planes until every part is nearly convex (`concavity`) or there are `max_pieces` parts, and
//! each piece is then the **convex hull of the mesh's own surface inside the part's voxels**
//! (the triangles clipped to those voxels), never of the voxels themselves. So a piece lies
//! inside the convex hull of the mesh: pieces never reach below the mesh's lowest point, and
//! furniture standing on the floor does not start in it.
//!
//! A closed mesh that fills at least `1 - concavity` of its convex hull (a cabinet, a box) is
//! its hull, one piece. Pieces with less than [`MIN_PIECE_VOLUME`] are dropped (a flat canvas in a frame). When no
//! piece is left, the object is the convex hull of its whole mesh; when that has no volume
//! either (a single sheet, a rug of zero thickness), it is its bounding box in the object frame
//! made at least [`MIN_HALF_THICKNESS`] thick on each side, the only case where the body is
//! larger than the mesh. Box objects are one exact cuboid.

use std::borrow::Cow;
use std::collections::HashSet;
use std::panic::{AssertUnwindSafe, catch_unwind};

use rapier3d_f64::parry::shape::SharedShape;
use rapier3d_f64::parry::transformation::vhacd::{VHACD, VHACDParameters};
use sceneeval_geom::parry_adapter::{point_from_parry, point_to_parry};
use sceneeval_geom::{Mesh, Point3, Real, Vector3, weld_vertices};

use crate::DecompositionParams;
pub use crate::report::DecompositionKind;

/// Pieces with a smaller volume (m³) are dropped: a 1 mm cube.
pub const MIN_PIECE_VOLUME: Real = 1e-9;

/// Smallest half thickness (m) of the box that stands in for a mesh without volume.
pub const MIN_HALF_THICKNESS: Real = 5e-4;

/// One convex piece in the object frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Piece {
    /// An axis-aligned box (object frame) with its centre and half extents.
    Cuboid {
        /// Centre in the object frame.
        center: Point3,
        /// Half extents, all positive.
        half_extents: Vector3,
    },
    /// The convex hull of these points (the hull's vertices, object frame).
    Hull {
        /// The hull's vertices.
        points: Vec<Point3>,
    },
}

/// The convex pieces of one mesh, object frame, with the rapier shapes built from them.
#[derive(Clone)]
pub struct Decomposition {
    kind: DecompositionKind,
    pieces: Vec<Piece>,
    shapes: Vec<SharedShape>,
    volume: Real,
}

impl std::fmt::Debug for Decomposition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Decomposition")
            .field("kind", &self.kind)
            .field("pieces", &self.pieces.len())
            .field("volume", &self.volume)
            .finish()
    }
}

impl PartialEq for Decomposition {
    fn eq(&self, other: &Self) -> bool {
        self.kind == other.kind && self.pieces == other.pieces
    }
}

impl Decomposition {
    /// How the pieces were made.
    pub fn kind(&self) -> DecompositionKind {
        self.kind
    }

    /// The pieces, object frame.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces
    }

    /// Total volume of the pieces in m³ (overlaps counted twice).
    pub fn volume(&self) -> Real {
        self.volume
    }

    /// The rapier shapes of the pieces, each in the object frame (a cuboid piece is placed by
    /// its centre, see [`Decomposition::piece_offsets`]).
    pub(crate) fn shapes(&self) -> &[SharedShape] {
        &self.shapes
    }

    /// Where each shape sits in the object frame (the cuboids' centres; zero for hulls).
    pub(crate) fn piece_offsets(&self) -> impl Iterator<Item = Vector3> + '_ {
        self.pieces.iter().map(|p| match p {
            Piece::Cuboid { center, .. } => center.coords,
            Piece::Hull { .. } => Vector3::zeros(),
        })
    }

    /// The decomposition of a box object with these half extents: one cuboid, each half
    /// extent at least [`MIN_HALF_THICKNESS`].
    pub fn cuboid(half_extents: Vector3) -> Self {
        Self::from_pieces(
            DecompositionKind::Box,
            vec![Piece::Cuboid {
                center: Point3::origin(),
                half_extents: half_extents.map(|h| h.max(MIN_HALF_THICKNESS)),
            }],
        )
        .unwrap_or_else(|| flat_box(&Point3::origin(), &Point3::origin()))
    }

    /// The convex decomposition of a mesh (object frame), as described in the module docs.
    pub fn of_mesh(mesh: &Mesh, params: &DecompositionParams) -> Self {
        let input = decomposition_input(mesh);
        let mesh = input.as_ref();
        if let Some(d) = Self::nearly_convex(mesh, params) {
            return d;
        }
        let hulls = vhacd_hulls(mesh, params);
        let pieces: Vec<Piece> = hulls
            .into_iter()
            .filter_map(|points| solid_hull(&points))
            .map(|points| Piece::Hull { points })
            .collect();
        if let Some(d) = Self::from_pieces(DecompositionKind::Vhacd, pieces) {
            return d;
        }
        if let Some(d) = solid_hull(mesh.vertices())
            .and_then(|points| Self::from_pieces(DecompositionKind::ConvexHull, vec![Piece::Hull { points }]))
        {
            tracing::debug!("no V-HACD piece has volume: the mesh's convex hull is used");
            return d;
        }
        tracing::debug!("the mesh has no volume: its bounding box, at least 1 mm thick, is used");
        let aabb = mesh.aabb();
        flat_box(&aabb.min, &aabb.max)
    }

    /// A closed mesh whose volume is at least `1 - concavity` of its hull's is its hull: one
    /// piece (V-HACD would cut even a cube into several voxel-aligned parts).
    fn nearly_convex(mesh: &Mesh, params: &DecompositionParams) -> Option<Self> {
        let volume = mesh.volume()?;
        let points = solid_hull(mesh.vertices())?;
        let hull = Self::from_pieces(DecompositionKind::ConvexHull, vec![Piece::Hull { points }])?;
        (volume >= (1.0 - params.concavity) * hull.volume()).then_some(hull)
    }

    /// A decomposition from stored pieces (the disk cache); `None` when a piece is not a
    /// solid.
    pub(crate) fn from_pieces(kind: DecompositionKind, pieces: Vec<Piece>) -> Option<Self> {
        let mut shapes = Vec::with_capacity(pieces.len());
        let mut volume = 0.0;
        for p in &pieces {
            let shape = match p {
                Piece::Cuboid { half_extents: h, .. } => {
                    if !(h.iter().all(|v| v.is_finite() && *v > 0.0)) {
                        return None;
                    }
                    SharedShape::cuboid(h.x, h.y, h.z)
                }
                Piece::Hull { points } => {
                    let pts: Vec<_> = points.iter().map(point_to_parry).collect();
                    SharedShape::convex_hull(&pts)?
                }
            };
            let v = shape.mass_properties(1.0).mass();
            if !(v.is_finite() && v > 0.0) {
                return None;
            }
            volume += v;
            shapes.push(shape);
        }
        if shapes.is_empty() {
            return None;
        }
        Some(Decomposition {
            kind,
            pieces,
            shapes,
            volume,
        })
    }
}

/// The mesh as the decomposition reads it: vertices at one position welded into one
/// ([`sceneeval_geom::weld_vertices`]) and each face kept once, whatever the order of its
/// corners (a face repeated, or given both ways round); triangles whose corners weld together
/// are dropped. The mesh itself when no face is dropped: welding alone changes nothing the
/// decomposition reads ([`Mesh`] joins split seams for its closedness and volume, V-HACD reads
/// triangles), and rebuilding a mesh costs about a millisecond per thousand triangles.
///
/// Meshes are loaded with their vertices split along seams (normals, texture coordinates), and
/// some assets repeat their faces: a cube's 12 faces repeated 500 times is a 6,000-triangle
/// mesh that is not closed (every edge has 1,000 faces), so it went through V-HACD, which
/// clipped each copy of each face into every voxel it touches (3.3 GB). Welded, it is the
/// cube: 8 vertices, 12 faces, closed, one piece.
///
/// ```
/// use sceneeval_geom::{CUBOID_TRIANGLES, Mesh, Point3, cuboid_corner};
/// use sceneeval_physics::decompose::decomposition_input;
///
/// let corners: Vec<Point3> = (0..8).map(|k| Point3::from(cuboid_corner(k, [0.0; 3], [1.0; 3]))).collect();
/// let repeated: Vec<[u32; 3]> = (0..500).flat_map(|_| CUBOID_TRIANGLES).collect();
/// let mesh = Mesh::new(corners, repeated).unwrap();
/// assert_eq!(mesh.triangles().len(), 6000);
/// let input = decomposition_input(&mesh);
/// assert_eq!((input.vertices().len(), input.triangles().len()), (8, 12));
/// assert!((input.volume().unwrap() - 1.0).abs() < 1e-12); // closed: 1 m³
/// ```
pub fn decomposition_input(mesh: &Mesh) -> Cow<'_, Mesh> {
    let (ids, count) = weld_vertices(mesh.vertices());
    let mut seen = HashSet::with_capacity(mesh.triangles().len());
    let triangles: Vec<[u32; 3]> = mesh
        .triangles()
        .iter()
        .map(|t| t.map(|i| ids[i as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .filter(|t| {
            let mut key = *t;
            key.sort_unstable();
            seen.insert(key)
        })
        .collect();
    if triangles.len() == mesh.triangles().len() {
        return Cow::Borrowed(mesh);
    }
    let mut vertices = vec![Point3::origin(); count];
    for (v, &id) in mesh.vertices().iter().zip(&ids) {
        vertices[id as usize] = *v;
    }
    match Mesh::new(vertices, triangles) {
        Ok(welded) => Cow::Owned(welded),
        // Unreachable: welding keeps every position, so a triangle of area keeps it.
        Err(e) => {
            tracing::warn!(error = %e, "welding the mesh for its decomposition failed; decomposing it as given");
            Cow::Borrowed(mesh)
        }
    }
}

/// The box `[min, max]` (object frame) made at least [`MIN_HALF_THICKNESS`] thick each way.
fn flat_box(min: &Point3, max: &Point3) -> Decomposition {
    let center = nalgebra_center(min, max);
    let half_extents = ((max - min) * 0.5).map(|h| h.max(MIN_HALF_THICKNESS));
    let shape = SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z);
    let volume = shape.mass_properties(1.0).mass();
    Decomposition {
        kind: DecompositionKind::FlatBox,
        pieces: vec![Piece::Cuboid { center, half_extents }],
        shapes: vec![shape],
        volume,
    }
}

fn nalgebra_center(min: &Point3, max: &Point3) -> Point3 {
    Point3::from((min.coords + max.coords) * 0.5)
}

/// The hull vertices of `points` when their hull has at least [`MIN_PIECE_VOLUME`].
fn solid_hull(points: &[Point3]) -> Option<Vec<Point3>> {
    let pts: Vec<_> = points.iter().map(point_to_parry).collect();
    let shape = SharedShape::convex_hull(&pts)?;
    let v = shape.mass_properties(1.0).mass();
    if !(v.is_finite() && v >= MIN_PIECE_VOLUME) {
        return None;
    }
    let poly = shape.as_convex_polyhedron()?;
    Some(poly.points().iter().map(|p| point_from_parry(*p)).collect())
}

/// V-HACD's parts of the mesh, each as the points of the mesh's surface clipped to the part's
/// voxels. Empty when V-HACD fails (it is then treated as one piece by the caller's
/// fallbacks); a panic inside parry is caught and logged, never passed on.
fn vhacd_hulls(mesh: &Mesh, params: &DecompositionParams) -> Vec<Vec<Point3>> {
    let points: Vec<_> = mesh.vertices().iter().map(point_to_parry).collect();
    let indices = mesh.triangles();
    let vhacd_params = VHACDParameters {
        resolution: params.resolution,
        concavity: params.concavity,
        max_convex_hulls: params.max_pieces,
        ..VHACDParameters::default()
    };
    let run = || {
        let decomposition = VHACD::decompose(&vhacd_params, &points, indices, true);
        decomposition.compute_primitive_intersections(&points, indices)
    };
    match catch_unwind(AssertUnwindSafe(run)) {
        Ok(parts) => parts
            .into_iter()
            .map(|part| part.into_iter().map(point_from_parry).collect())
            .collect(),
        Err(_) => {
            tracing::warn!(
                triangles = indices.len(),
                "V-HACD failed on a mesh: its convex hull is used instead"
            );
            Vec::new()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table: a 1 x 0.6 x 0.04 m top at z in [0.7, 0.74] on four 0.04 m square legs from
    /// z = 0 (meshes of five boxes).
    fn table() -> Mesh {
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        let mut add = |min: [Real; 3], max: [Real; 3]| {
            let base = vertices.len() as u32;
            for k in 0..8 {
                vertices.push(Point3::from(sceneeval_geom::cuboid_corner(k, min, max)));
            }
            triangles.extend(
                sceneeval_geom::CUBOID_TRIANGLES
                    .iter()
                    .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
            );
        };
        add([-0.5, -0.3, 0.7], [0.5, 0.3, 0.74]);
        for (x, y) in [(-0.46, -0.26), (0.42, -0.26), (-0.46, 0.22), (0.42, 0.22)] {
            add([x, y, 0.0], [x + 0.04, y + 0.04, 0.7]);
        }
        Mesh::new(vertices, triangles).unwrap()
    }

    #[test]
    fn pieces_stay_inside_the_mesh_bounds_and_follow_its_concavity() {
        let mesh = table();
        let d = Decomposition::of_mesh(&mesh, &DecompositionParams::default());
        assert_eq!(d.kind(), DecompositionKind::Vhacd);
        assert!(d.pieces().len() >= 2, "{d:?}");
        let aabb = mesh.aabb();
        for p in d.pieces() {
            let Piece::Hull { points } = p else {
                panic!("hull pieces")
            };
            for q in points {
                // Never below the legs' feet (z = 0) nor outside the bounds, up to rounding.
                assert!(q.z >= -1e-12, "{q:?}");
                for i in 0..3 {
                    assert!(
                        q[i] >= aabb.min[i] - 1e-12 && q[i] <= aabb.max[i] + 1e-12,
                        "{q:?}"
                    );
                }
            }
        }
        // The solid is 0.024 m³ (top) + 4 x 0.00112 m³ (legs) = 0.02848 m³; the hull of the
        // whole table is 1 x 0.6 x 0.74 = 0.444 m³. Pieces that follow the legs stay far below.
        assert!(d.volume() < 0.2, "{}", d.volume());
        assert!(d.volume() > 0.02, "{}", d.volume());
    }

    #[test]
    fn flat_and_box_meshes_get_documented_stand_ins() {
        // A single 1 x 1 m sheet at z = 0: no volume, so a box 1 mm thick (0.5 mm each side).
        let sheet = Mesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(1.0, 1.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let d = Decomposition::of_mesh(&sheet, &DecompositionParams::default());
        assert_eq!(d.kind(), DecompositionKind::FlatBox);
        // 1 x 1 x 0.001 m.
        assert!((d.volume() - 1e-3).abs() < 1e-12, "{}", d.volume());
        let b = Decomposition::cuboid(Vector3::new(0.5, 0.25, 0.0));
        assert_eq!(b.kind(), DecompositionKind::Box);
        // 1 x 0.5 x 0.001 m.
        assert!((b.volume() - 5e-4).abs() < 1e-12, "{}", b.volume());
    }

    #[test]
    fn a_convex_mesh_is_one_piece_equal_to_itself() {
        let cube = Mesh::cuboid(&Vector3::new(0.5, 0.5, 0.5)).unwrap();
        let d = Decomposition::of_mesh(&cube, &DecompositionParams::default());
        // The whole cube (1 m³) with no growth.
        assert!((d.volume() - 1.0).abs() < 1e-9, "{d:?}");
        assert_eq!(d.pieces().len(), 1, "{d:?}");
        assert_eq!(d.kind(), DecompositionKind::ConvexHull);
    }

    #[test]
    fn repeated_faces_are_decomposed_once() {
        // The issue's degenerate mesh: a 1 m cube's 12 faces repeated 500 times (6,000
        // triangles), once over its 8 corners and once with 8 corners of its own per copy.
        let corners: Vec<Point3> = (0..8)
            .map(|k| Point3::from(sceneeval_geom::cuboid_corner(k, [0.0; 3], [1.0; 3])))
            .collect();
        let shared: Vec<[u32; 3]> = (0..500).flat_map(|_| sceneeval_geom::CUBOID_TRIANGLES).collect();
        let own: Vec<[u32; 3]> = (0..500u32)
            .flat_map(|c| sceneeval_geom::CUBOID_TRIANGLES.map(|t| t.map(|i| i + 8 * c)))
            .collect();
        let meshes = [
            Mesh::new(corners.clone(), shared).unwrap(),
            Mesh::new(corners.repeat(500), own).unwrap(),
        ];
        for mesh in &meshes {
            assert_eq!(mesh.triangles().len(), 6000);
            // What the decomposition reads: the cube, 8 vertices and 12 faces, closed.
            let input = decomposition_input(mesh);
            assert!(matches!(input, Cow::Owned(_)));
            assert_eq!((input.vertices().len(), input.triangles().len()), (8, 12));
            assert!((input.volume().unwrap() - 1.0).abs() < 1e-12);
            // So it is its hull, one piece of 1 m³ (V-HACD never runs).
            let d = Decomposition::of_mesh(mesh, &DecompositionParams::default());
            assert_eq!((d.kind(), d.pieces().len()), (DecompositionKind::ConvexHull, 1));
            assert!((d.volume() - 1.0).abs() < 1e-12, "{d:?}");
        }
        // A face given both ways round is one face; a mesh without repeats is read as given,
        // also when its vertices are split along seams (each face of a box with corners of
        // its own: 24 vertices for 8 positions).
        let both_ways = Mesh::new(corners[..4].to_vec(), vec![[0, 1, 3], [3, 1, 0], [0, 3, 2]]).unwrap();
        assert_eq!(decomposition_input(&both_ways).triangles().len(), 2);
        let cube = Mesh::cuboid(&Vector3::repeat(0.5)).unwrap();
        assert!(matches!(decomposition_input(&cube), Cow::Borrowed(_)));
        let split = Mesh::subdivided_box(&Vector3::repeat(0.5), 1).unwrap();
        assert!(split.vertices().len() > 8);
        assert!(matches!(decomposition_input(&split), Cow::Borrowed(_)));
    }
}
