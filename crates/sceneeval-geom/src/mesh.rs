use std::fmt;
use std::sync::{Arc, OnceLock};

use crate::distance::DistanceTree;
use crate::parry::query::{PointQuery, RayCast};
use crate::parry::shape::TriMesh;
use crate::parry_adapter::{point_from_parry, point_to_parry, to_parry_pose, to_parry_vec, vec_from_parry};
use crate::penetration::{Penetration, PenetrationQuery};
use crate::solid::SolidTables;
use crate::{Aabb, ClosestPoints, GeomError, Isometry3, Matrix3, Obb, Point3, Ray, Real, Vector3, parry};

/// A triangle mesh in its own frame (for a scene object: the object frame), with a parry
/// [`TriMesh`] and its bounding-volume hierarchy built once at construction, and a second,
/// balanced hierarchy for the exact distance queries ([`Mesh::distance`],
/// [`Mesh::distance_to_obb`], [`Mesh::distance_to_triangle`]), which costs about 90 bytes per
/// triangle and a tenth more construction time.
///
/// Construction drops zero-area triangles and makes the winding consistent across every
/// edge shared by exactly two triangles; a closed component is then turned outward (positive
/// volume). Triangles are otherwise kept as given, so a mesh loaded from a file keeps its
/// vertex order. Share one mesh between every object that uses the same asset by wrapping it
/// in an `Arc`.
///
/// A mesh is a surface, but it also bounds a solid: [`Mesh::contains_point`],
/// [`Mesh::signed_distance`] and [`Mesh::penetration`] answer "is this point inside the object"
/// and "do these objects interpenetrate". For a closed mesh of one connected component the
/// solid is the ordinary one (pseudo-normal test); for an open mesh, or several components,
/// a point is inside where the generalized winding number is at least 1/2 in magnitude, which
/// is exact for closed parts and degrades gracefully for meshes with holes (the usual state of
/// real furniture assets): a box missing a face still holds its inside, a cavity closed on
/// five sides (a drawer, a shelf compartment) counts as solid, a single sheet encloses
/// nothing. The tables behind these tests (a dipole hierarchy for the winding number,
/// pseudo-normals, the boundary edges, interior balls, connected components; about 60 bytes
/// per triangle) are built once, on first use, and shared by every clone and every object
/// placing the mesh through an `Arc`.
#[derive(Clone)]
pub struct Mesh {
    vertices: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
    aabb: Aabb,
    area: Real,
    closed: bool,
    shape: TriMesh,
    tree: DistanceTree,
    /// Behind an `Arc` so that clones share the tables instead of copying them.
    solid: Arc<OnceLock<SolidTables>>,
}

impl fmt::Debug for Mesh {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Mesh")
            .field("vertices", &self.vertices.len())
            .field("triangles", &self.triangles.len())
            .field("aabb", &self.aabb)
            .field("closed", &self.closed)
            .finish()
    }
}

impl PartialEq for Mesh {
    /// Meshes are equal when their vertices and triangles are.
    fn eq(&self, other: &Self) -> bool {
        self.vertices == other.vertices && self.triangles == other.triangles
    }
}

/// The first hit of a ray on a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayHit {
    /// Ray parameter of the hit (metres when the ray direction is unit length).
    pub toi: Real,
    /// Hit point in world coordinates.
    pub point: Point3,
    /// Unit normal of the hit triangle in world coordinates, turned toward the ray's origin
    /// (whichever side of the triangle the ray hits).
    pub normal: Vector3,
}

impl Mesh {
    /// A mesh from vertices and counter-clockwise (outward) triangles.
    ///
    /// # Errors
    /// [`GeomError::EmptyMesh`], [`GeomError::NonFiniteVertex`],
    /// [`GeomError::IndexOutOfRange`] or [`GeomError::DegenerateMesh`] (every triangle has zero
    /// area).
    pub fn new(vertices: Vec<Point3>, triangles: Vec<[u32; 3]>) -> Result<Self, GeomError> {
        if vertices.is_empty() || triangles.is_empty() {
            return Err(GeomError::EmptyMesh);
        }
        for (index, v) in vertices.iter().enumerate() {
            if !v.iter().all(|c| c.is_finite()) {
                return Err(GeomError::NonFiniteVertex {
                    index,
                    value: [v.x, v.y, v.z],
                });
            }
        }
        let n = vertices.len();
        for (triangle, t) in triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= n) {
                return Err(GeomError::IndexOutOfRange {
                    triangle,
                    index,
                    vertex_count: n,
                });
            }
        }
        let given = triangles.len();
        let mut triangles: Vec<[u32; 3]> = triangles
            .into_iter()
            .filter(|t| triangle_area(&vertices, t) > 0.0)
            .collect();
        if triangles.is_empty() {
            return Err(GeomError::DegenerateMesh { triangles: given });
        }
        let closed = orient_consistently(&vertices, &mut triangles);
        // Every vertex is finite, so the bounds exist.
        let aabb =
            Aabb::from_points(vertices.iter()).unwrap_or(Aabb::new(Point3::origin(), Point3::origin()));
        let area = triangles.iter().map(|t| triangle_area(&vertices, t)).sum();
        let shape = TriMesh::new(vertices.iter().map(point_to_parry).collect(), triangles.clone())
            .map_err(|_| GeomError::EmptyMesh)?;
        let tree = DistanceTree::new(&vertices, &triangles);
        Ok(Mesh {
            vertices,
            triangles,
            aabb,
            area,
            closed,
            shape,
            tree,
            solid: Arc::new(OnceLock::new()),
        })
    }

    /// This mesh mapped by the affine map `p -> linear * p + translation`. A map with negative
    /// determinant (a mirror) reverses every triangle so that the winding stays outward.
    pub fn transformed(&self, linear: &Matrix3, translation: &Vector3) -> Result<Self, GeomError> {
        if !linear.iter().chain(translation.iter()).all(|v| v.is_finite()) {
            return Err(GeomError::NonFinite {
                what: "mesh transform",
            });
        }
        let vertices = self
            .vertices
            .iter()
            .map(|p| Point3::from(linear * p.coords + translation))
            .collect();
        let mut triangles = self.triangles.clone();
        if linear.determinant() < 0.0 {
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        Mesh::new(vertices, triangles)
    }

    /// Vertex positions in the mesh frame.
    #[inline]
    pub fn vertices(&self) -> &[Point3] {
        &self.vertices
    }

    /// Triangles as vertex index triples (zero-area triangles removed, winding made consistent).
    #[inline]
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The three corners of triangle `i` in the mesh frame.
    #[inline]
    pub fn triangle(&self, i: usize) -> [Point3; 3] {
        let t = self.triangles[i];
        [
            self.vertices[t[0] as usize],
            self.vertices[t[1] as usize],
            self.vertices[t[2] as usize],
        ]
    }

    /// Bounds in the mesh frame.
    #[inline]
    pub fn aabb(&self) -> &Aabb {
        &self.aabb
    }

    /// Exact world bounds of the mesh placed by `pose` (every vertex transformed, by the
    /// pose's rotation matrix: the same bounds up to rounding as transforming each vertex with
    /// the pose's quaternion, at a third of the cost).
    pub fn world_aabb(&self, pose: &Isometry3) -> Aabb {
        let r = pose.rotation.to_rotation_matrix().into_inner();
        let t = pose.translation.vector;
        let (mut lo, mut hi) = ([Real::INFINITY; 3], [Real::NEG_INFINITY; 3]);
        for v in &self.vertices {
            for i in 0..3 {
                let w = r[(i, 0)] * v.x + r[(i, 1)] * v.y + r[(i, 2)] * v.z;
                lo[i] = lo[i].min(w);
                hi[i] = hi[i].max(w);
            }
        }
        if self.vertices.is_empty() {
            return Aabb::new(Point3::from(t), Point3::from(t));
        }
        Aabb::new(
            Point3::new(lo[0] + t.x, lo[1] + t.y, lo[2] + t.z),
            Point3::new(hi[0] + t.x, hi[1] + t.y, hi[2] + t.z),
        )
    }

    /// Total surface area in square metres.
    #[inline]
    pub fn surface_area(&self) -> Real {
        self.area
    }

    /// Whether the mesh is watertight: after merging vertices at identical positions, every
    /// edge is shared by exactly two consistently wound triangles.
    #[inline]
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// Enclosed volume for a closed mesh (divergence theorem), `None` for an open one.
    pub fn volume(&self) -> Option<Real> {
        self.closed
            .then(|| signed_volume(&self.vertices, self.triangles.iter()).abs())
    }

    /// The parry shape, for queries this type does not wrap (mesh frame).
    #[inline]
    pub fn parry_shape(&self) -> &TriMesh {
        &self.shape
    }

    /// The bounding-box hierarchy of the exact distance searches (mesh frame).
    #[inline]
    pub(crate) fn distance_tree(&self) -> &DistanceTree {
        &self.tree
    }

    /// Whether the surfaces of two placed meshes touch or cross. Surface test only: a mesh
    /// nested entirely inside another does not intersect it (combine with
    /// [`Mesh::contains_point`] to detect containment).
    pub fn intersects(&self, pose: &Isometry3, other: &Mesh, other_pose: &Isometry3) -> bool {
        parry::query::intersection_test(
            &to_parry_pose(pose),
            &self.shape,
            &to_parry_pose(other_pose),
            &other.shape,
        )
        .is_ok_and(|r| r.intersecting)
    }

    /// Distance between the surfaces of two placed meshes, 0 when they touch or cross. A mesh
    /// nested inside another is as far from it as their surfaces are (combine with
    /// [`Mesh::contains_point`] for solids).
    ///
    /// # Performance
    /// No allocation (the search recurses, at most as deep as the two meshes' distance trees
    /// together: a few dozen frames). A simultaneous branch and bound over both meshes'
    /// distance trees, seeded by alternating closest-point projections, with exact (GJK)
    /// triangle-triangle distances (0 for triangles that cross) for the few pairs that cheap
    /// bounds cannot rule out: about 15 µs for two 5k-triangle meshes 6 cm apart (a flat face
    /// against a curved one), tens of microseconds up to a metre apart, a few microseconds when
    /// they cross; where parry's generic mesh-mesh distance takes tens of milliseconds when
    /// they are close. No separate intersection test runs first: parry's costs hundreds of
    /// microseconds for surfaces a few centimetres apart.
    pub fn distance(&self, pose: &Isometry3, other: &Mesh, other_pose: &Isometry3) -> Real {
        self.closest_points(pose, other, other_pose).distance
    }

    /// [`Mesh::distance`] (the same value) with a pair of closest points, this mesh's first
    /// (none when the surfaces touch or cross). Same search, same cost.
    pub fn closest_points(&self, pose: &Isometry3, other: &Mesh, other_pose: &Isometry3) -> ClosestPoints {
        crate::distance::mesh_mesh(self, pose, other, other_pose)
    }

    /// An upper bound on [`Mesh::distance`]: the distance between two surface points reached by
    /// alternating closest-point projections starting from `start` (a handful of BVH point
    /// queries; often the exact distance). For pruning.
    pub fn distance_upper_bound(
        &self,
        pose: &Isometry3,
        other: &Mesh,
        other_pose: &Isometry3,
        start: &Point3,
    ) -> Real {
        crate::distance::mesh_mesh_upper_bound(self, pose, other, other_pose, start)
    }

    /// Distance between the placed mesh's surface and the solid box `obb` (0 when they meet).
    /// A mesh lying entirely inside the box is 0 away from it; a box inside a closed mesh is as
    /// far as the surface (combine with [`Mesh::contains_point`]).
    ///
    /// # Performance
    /// No allocation. A branch and bound over the mesh's distance tree in the box's frame; a
    /// triangle whose nearest corner is provably its nearest point to the box (the usual case
    /// of a convex part facing a wall) is measured without GJK: 1-6 µs for a 5k-triangle mesh
    /// against a wall piece 7 cm to 3.4 m away.
    pub fn distance_to_obb(&self, pose: &Isometry3, obb: &Obb) -> Real {
        self.closest_points_to_obb(pose, obb).distance
    }

    /// [`Mesh::distance_to_obb`] (the same value) with a pair of closest points, the mesh's
    /// first (none when they meet).
    pub fn closest_points_to_obb(&self, pose: &Isometry3, obb: &Obb) -> ClosestPoints {
        if obb.contains_point(&(pose * self.vertices[0])) {
            return ClosestPoints::MEETING;
        }
        crate::distance::mesh_box(self, pose, obb)
    }

    /// An upper bound on [`Mesh::distance_to_obb`] from two closest-point projections.
    pub fn distance_to_obb_upper_bound(&self, pose: &Isometry3, obb: &Obb) -> Real {
        crate::distance::mesh_box_upper_bound(self, pose, obb)
    }

    /// Distance between the placed mesh's surface and the world triangle `tri`.
    ///
    /// # Performance
    /// No allocation: a branch and bound over the mesh's distance tree, as
    /// [`Mesh::distance_to_obb`].
    pub fn distance_to_triangle(&self, pose: &Isometry3, tri: &[Point3; 3]) -> Real {
        self.closest_points_to_triangle(pose, tri).distance
    }

    /// [`Mesh::distance_to_triangle`] (the same value) with a pair of closest points, the
    /// mesh's first (none when they meet).
    pub fn closest_points_to_triangle(&self, pose: &Isometry3, tri: &[Point3; 3]) -> ClosestPoints {
        crate::distance::mesh_triangle(self, pose, tri)
    }

    /// The first hit of `ray` (world coordinates) on the placed mesh's surface within
    /// `max_toi`. A ray starting inside a closed mesh hits the surface from inside.
    ///
    /// A single ray can slip through an edge shared by two triangles (parry issue #444);
    /// never let one ray decide a contact.
    pub fn cast_ray(&self, pose: &Isometry3, ray: &Ray, max_toi: Real) -> Option<RayHit> {
        let pray = parry::query::Ray::new(point_to_parry(&ray.origin), to_parry_vec(&ray.dir));
        let hit = self
            .shape
            .cast_ray_and_get_normal(&to_parry_pose(pose), &pray, max_toi, false)?;
        Some(RayHit {
            toi: hit.time_of_impact,
            point: ray.point_at(hit.time_of_impact),
            normal: vec_from_parry(hit.normal),
        })
    }

    /// The point of the placed mesh's surface closest to the world point `p`.
    pub fn closest_point(&self, pose: &Isometry3, p: &Point3) -> Point3 {
        let proj = self
            .shape
            .project_point(&to_parry_pose(pose), point_to_parry(p), false);
        point_from_parry(proj.point)
    }

    /// Distance from the world point `p` to the placed mesh's surface (unsigned).
    pub fn distance_to_point(&self, pose: &Isometry3, p: &Point3) -> Real {
        (self.closest_point(pose, p) - p).norm()
    }

    /// Whether the world point `p` is inside the solid of the placed mesh (see the type's
    /// docs): the pseudo-normal test for a closed, connected mesh, otherwise the generalized
    /// winding number being at least 0.5 in magnitude, decided exactly (the dipole
    /// approximation of far clusters is refined until its error bound cannot change the
    /// answer). Points on the surface may go either way.
    ///
    /// # Performance
    /// Logarithmic in the triangle count away from the winding number's 1/2 level set: one
    /// closest-point query (about 1 µs on 5k triangles) plus, for other than closed connected
    /// meshes, a hierarchical winding number. The first call on a mesh builds its tables.
    pub fn contains_point(&self, pose: &Isometry3, p: &Point3) -> bool {
        let local = pose.inverse_transform_point(p);
        self.aabb.contains_point(&local) && self.solid().classify(self, &local).inside
    }

    /// Distance from the world point `p` to the placed mesh's surface, negative when `p` is
    /// inside its solid ([`Mesh::contains_point`]).
    pub fn signed_distance(&self, pose: &Isometry3, p: &Point3) -> Real {
        let local = pose.inverse_transform_point(p);
        let c = self.solid().classify(self, &local);
        if c.inside { -c.distance } else { c.distance }
    }

    /// Whether the solids of two placed meshes interpenetrate by more than
    /// `query.tolerance`, with a certified lower bound on the penetration depth (the length of
    /// the shortest translation that separates them); see [`Penetration`]. Surfaces that touch
    /// or cross within the tolerance are a resting contact; a connected part of one mesh lying
    /// inside the other with the surfaces apart is nested, which always collides; the same
    /// mesh placed twice at one pose collides.
    ///
    /// Bounds come from points of one surface deep inside the other solid and from balls
    /// inside both solids, found by a best-first search over the triangle hierarchy and its
    /// subdivision (see [`Penetration`]). A pair reported colliding
    /// always penetrates by more than the tolerance; one reported not colliding penetrates by
    /// at most the tolerance plus the sample spacing, except edge-on-edge crossings, whose
    /// deepest surface point may lie up to a factor `sqrt 2` less deep than the penetration.
    ///
    /// # Performance
    /// Cost bounded per pair by `query.budget` point queries per direction plus one surface
    /// intersection test; a deep collision is usually proven by its first few queries and a
    /// resting contact on a flat face of the other's box by none.
    pub fn penetration(
        &self,
        pose: &Isometry3,
        other: &Mesh,
        other_pose: &Isometry3,
        query: &PenetrationQuery,
    ) -> Penetration {
        crate::penetration::penetration(self, pose, other, other_pose, query)
    }

    /// The inside-test tables, built on first use.
    pub(crate) fn solid(&self) -> &SolidTables {
        self.solid.get_or_init(|| SolidTables::new(self))
    }

    /// The generalized winding number of the mesh-frame point `p` (Jacobson et al. 2013):
    /// 1 inside and 0 outside a closed outward mesh. Costs one solid angle per triangle (see
    /// [`Mesh::contains_point`] for the hierarchical decision).
    pub fn winding_number(&self, p: &Point3) -> Real {
        let mut total = 0.0;
        for k in 0..self.triangles.len() {
            total += crate::solid::solid_angle(&self.triangle(k), p);
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

fn triangle_area(v: &[Point3], t: &[u32; 3]) -> Real {
    let (a, b, c) = (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
    (b - a).cross(&(c - a)).norm() * 0.5
}

fn signed_volume<'a>(v: &[Point3], tris: impl Iterator<Item = &'a [u32; 3]>) -> Real {
    tris.map(|t| {
        let (a, b, c) = (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
        a.coords.dot(&b.coords.cross(&c.coords)) / 6.0
    })
    .sum()
}

/// The triangles using each undirected welded edge, over a list of uses `(lower end, higher
/// end, triangle)` sorted by edge: the edges as runs of that list, and each triangle's edges.
struct EdgeUsers {
    /// Start of each edge's run in the list, then the list's length.
    groups: Vec<usize>,
    /// Per triangle, its (up to three) edges as `(edge, run)`; unused entries hold `u32::MAX`.
    of_triangle: Vec<[((u32, u32), u32); 3]>,
}

impl EdgeUsers {
    fn new(uses: &[(u32, u32, u32)], triangles: usize) -> Self {
        let mut groups = Vec::with_capacity(uses.len() / 2 + 1);
        let mut of_triangle = vec![[((u32::MAX, u32::MAX), u32::MAX); 3]; triangles];
        for (i, u) in uses.iter().enumerate() {
            if i == 0 || (uses[i - 1].0, uses[i - 1].1) != (u.0, u.1) {
                groups.push(i);
            }
            let run = (groups.len() - 1) as u32;
            let slots = &mut of_triangle[u.2 as usize];
            // A triangle uses an edge at most three times; keep one entry per edge.
            if let Some(slot) = slots.iter_mut().find(|s| s.1 == u32::MAX || s.0 == (u.0, u.1)) {
                *slot = ((u.0, u.1), run);
            }
        }
        groups.push(uses.len());
        EdgeUsers { groups, of_triangle }
    }

    /// The uses of `edge`, which triangle `tri` has, in triangle order.
    fn users<'a>(
        &self,
        uses: &'a [(u32, u32, u32)],
        tri: usize,
        edge: (u32, u32),
    ) -> Option<&'a [(u32, u32, u32)]> {
        let run = self.of_triangle[tri]
            .iter()
            .find(|s| s.0 == edge && s.1 != u32::MAX)?
            .1 as usize;
        Some(&uses[self.groups[run]..self.groups[run + 1]])
    }
}

/// Makes triangle winding consistent across edges shared by exactly two triangles (breadth
/// first from the lowest-numbered triangle of each component), then turns each closed
/// component outward. Returns whether the whole mesh is closed and consistently orientable.
fn orient_consistently(vertices: &[Point3], triangles: &mut [[u32; 3]]) -> bool {
    // Weld vertices at identical positions so that split seams (normals, UVs) still connect.
    let (ids, count) = crate::weld_vertices(vertices);
    let welded = |t: &[u32; 3]| [ids[t[0] as usize], ids[t[1] as usize], ids[t[2] as usize]];

    // Undirected edge -> triangles using it: every (lower end, higher end, triangle), sorted,
    // so that the users of an edge are consecutive and in triangle order.
    let mut uses: Vec<(u32, u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    for (ti, t) in triangles.iter().enumerate() {
        let w = welded(t);
        for k in 0..3 {
            let (a, b) = (w[k], w[(k + 1) % 3]);
            if a != b {
                uses.push((a.min(b), a.max(b), ti as u32));
            }
        }
    }
    crate::sort::bucket_sort(
        &mut uses,
        count,
        |u| u.0 as usize,
        |u, v| (u.1, u.2).cmp(&(v.1, v.2)),
    );
    let edges = EdgeUsers::new(&uses, triangles.len());
    let mut closed = edges.groups.windows(2).all(|g| g[1] - g[0] == 2);

    let directed = |t: &[u32; 3], a: u32, b: u32| {
        let w = welded(t);
        (0..3).any(|k| w[k] == a && w[(k + 1) % 3] == b)
    };
    let mut component = vec![u32::MAX; triangles.len()];
    let mut components: Vec<Vec<u32>> = Vec::new();
    for seed in 0..triangles.len() {
        if component[seed] != u32::MAX {
            continue;
        }
        let cid = components.len() as u32;
        let mut members = vec![seed as u32];
        component[seed] = cid;
        let mut head = 0;
        while head < members.len() {
            let ti = members[head] as usize;
            head += 1;
            let w = welded(&triangles[ti]);
            for k in 0..3 {
                let (a, b) = (w[k], w[(k + 1) % 3]);
                let Some(users) = edges.users(&uses, ti, (a.min(b), a.max(b))) else {
                    continue;
                };
                if users.len() != 2 {
                    continue;
                }
                let other = if users[0].2 as usize == ti {
                    users[1].2
                } else {
                    users[0].2
                } as usize;
                // Consistent neighbours traverse the shared edge in opposite directions.
                let consistent = directed(&triangles[other], b, a);
                if component[other] == u32::MAX {
                    if !consistent {
                        triangles[other].swap(1, 2);
                    }
                    component[other] = cid;
                    members.push(other as u32);
                } else if !consistent {
                    // Non-orientable (or conflicting) surface: cannot be a closed solid.
                    closed = false;
                }
            }
        }
        components.push(members);
    }
    // Turn each closed component outward (positive signed volume).
    for members in &components {
        let component_closed = members.iter().all(|&ti| {
            let w = welded(&triangles[ti as usize]);
            (0..3).all(|k| {
                let (a, b) = (w[k], w[(k + 1) % 3]);
                edges
                    .users(&uses, ti as usize, (a.min(b), a.max(b)))
                    .is_some_and(|u| u.len() == 2)
            })
        });
        if component_closed
            && signed_volume(vertices, members.iter().map(|&ti| &triangles[ti as usize])) < 0.0
        {
            for &ti in members {
                triangles[ti as usize].swap(1, 2);
            }
        }
    }
    closed
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The earlier implementation of `orient_consistently` (edges in a hash map), as the
    /// oracle of the sorted-edge one: same flips, same closedness, on any triangle soup.
    fn orient_by_hash_map(vertices: &[Point3], triangles: &mut [[u32; 3]]) -> bool {
        // Weld vertices at identical positions so that split seams (normals, UVs) still connect.
        let (ids, _) = crate::weld_vertices(vertices);
        let welded = |t: &[u32; 3]| [ids[t[0] as usize], ids[t[1] as usize], ids[t[2] as usize]];

        // Undirected edge -> triangles using it.
        let mut edges: std::collections::HashMap<(u32, u32), Vec<u32>> =
            std::collections::HashMap::with_capacity(triangles.len() * 3 / 2);
        for (ti, t) in triangles.iter().enumerate() {
            let w = welded(t);
            for k in 0..3 {
                let (a, b) = (w[k], w[(k + 1) % 3]);
                if a != b {
                    edges.entry((a.min(b), a.max(b))).or_default().push(ti as u32);
                }
            }
        }
        let mut closed = edges.values().all(|users| users.len() == 2);

        let directed = |t: &[u32; 3], a: u32, b: u32| {
            let w = welded(t);
            (0..3).any(|k| w[k] == a && w[(k + 1) % 3] == b)
        };
        let mut component = vec![u32::MAX; triangles.len()];
        let mut components: Vec<Vec<u32>> = Vec::new();
        for seed in 0..triangles.len() {
            if component[seed] != u32::MAX {
                continue;
            }
            let cid = components.len() as u32;
            let mut members = vec![seed as u32];
            component[seed] = cid;
            let mut head = 0;
            while head < members.len() {
                let ti = members[head] as usize;
                head += 1;
                let w = welded(&triangles[ti]);
                for k in 0..3 {
                    let (a, b) = (w[k], w[(k + 1) % 3]);
                    let Some(users) = edges.get(&(a.min(b), a.max(b))) else {
                        continue;
                    };
                    if users.len() != 2 {
                        continue;
                    }
                    let other = if users[0] as usize == ti {
                        users[1]
                    } else {
                        users[0]
                    } as usize;
                    // Consistent neighbours traverse the shared edge in opposite directions.
                    let consistent = directed(&triangles[other], b, a);
                    if component[other] == u32::MAX {
                        if !consistent {
                            triangles[other].swap(1, 2);
                        }
                        component[other] = cid;
                        members.push(other as u32);
                    } else if !consistent {
                        // Non-orientable (or conflicting) surface: cannot be a closed solid.
                        closed = false;
                    }
                }
            }
            components.push(members);
        }
        // Turn each closed component outward (positive signed volume).
        for members in &components {
            let component_closed = members.iter().all(|&ti| {
                let w = welded(&triangles[ti as usize]);
                (0..3).all(|k| {
                    let (a, b) = (w[k], w[(k + 1) % 3]);
                    edges.get(&(a.min(b), a.max(b))).is_some_and(|u| u.len() == 2)
                })
            });
            if component_closed
                && signed_volume(vertices, members.iter().map(|&ti| &triangles[ti as usize])) < 0.0
            {
                for &ti in members {
                    triangles[ti as usize].swap(1, 2);
                }
            }
        }
        closed
    }

    proptest! {
        /// On a box and a tetrahedron (closed), with triangles flipped, dropped, repeated or
        /// given a seam's duplicate vertex, and random extra triangles.
        #[test]
        fn orientation_agrees_with_the_hash_map_version(
            flips in proptest::collection::vec(any::<bool>(), 16),
            seams in proptest::collection::vec(any::<bool>(), 16),
            drop in proptest::option::of(0usize..16),
            repeat in proptest::option::of(0usize..16),
            extra in proptest::collection::vec((0u32..12, 0u32..12, 0u32..12), 0..3),
        ) {
            let mut vertices: Vec<Point3> = (0..8)
                .map(|k| Point3::new(f64::from(k & 1), f64::from((k >> 1) & 1), f64::from(k >> 2)))
                .collect();
            vertices.extend([
                Point3::new(3.0, 0.0, 0.0),
                Point3::new(4.0, 0.0, 0.0),
                Point3::new(3.0, 1.0, 0.0),
                Point3::new(3.0, 0.0, 1.0),
            ]);
            // Seam copies of vertices 0..12, numbered 12..24.
            let copies: Vec<Point3> = vertices.clone();
            vertices.extend(copies);
            let mut tris: Vec<[u32; 3]> = crate::CUBOID_TRIANGLES.to_vec();
            tris.extend([[8, 10, 9], [8, 9, 11], [8, 11, 10], [9, 10, 11]]);
            for (k, t) in tris.iter_mut().enumerate() {
                if flips[k] {
                    t.swap(1, 2);
                }
                if seams[k] {
                    t[0] += 12;
                }
            }
            if let Some(k) = repeat {
                tris.push(tris[k]);
            }
            if let Some(k) = drop {
                tris.remove(k);
            }
            tris.extend(extra.iter().filter(|t| t.0 != t.1 && t.1 != t.2 && t.0 != t.2).map(|t| [t.0, t.1, t.2]));
            let mut ours = tris.clone();
            let mut theirs = tris;
            let closed = orient_consistently(&vertices, &mut ours);
            let expected = orient_by_hash_map(&vertices, &mut theirs);
            prop_assert_eq!(closed, expected);
            prop_assert_eq!(ours, theirs);
        }
    }

    #[test]
    fn clones_share_the_solid_tables() {
        // The tables are built once per mesh, not once per copy or per placed object.
        let m = Mesh::cuboid(&Vector3::new(0.5, 0.4, 0.3)).unwrap();
        let copy = m.clone();
        assert!(m.contains_point(&Isometry3::identity(), &Point3::origin()));
        assert!(std::ptr::eq(m.solid(), copy.solid()));
    }

    fn unit_box() -> Mesh {
        Mesh::cuboid(&Vector3::repeat(0.5)).unwrap()
    }

    #[test]
    fn cuboid_is_closed_with_expected_measures() {
        let m = unit_box();
        assert!(m.is_closed());
        assert!((m.volume().unwrap() - 1.0).abs() < 1e-12);
        assert!((m.surface_area() - 6.0).abs() < 1e-12);
        assert_eq!(m.triangles().len(), 12);
        assert!((m.winding_number(&Point3::origin()) - 1.0).abs() < 1e-9);
        assert!(m.winding_number(&Point3::new(2.0, 0.0, 0.0)).abs() < 1e-9);
    }

    #[test]
    fn inconsistent_winding_is_repaired() {
        let m = unit_box();
        let mut tris = m.triangles().to_vec();
        for t in tris.iter_mut().step_by(3) {
            t.swap(1, 2);
        }
        // Also turn the whole thing inside out.
        for t in &mut tris {
            t.swap(0, 1);
        }
        let fixed = Mesh::new(m.vertices().to_vec(), tris).unwrap();
        assert!(fixed.is_closed());
        assert!((fixed.winding_number(&Point3::origin()) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn split_seams_still_count_as_closed() {
        // Give every triangle its own three vertices, as glTF exporters do at UV seams.
        let m = unit_box();
        let mut vertices = Vec::new();
        let mut tris = Vec::new();
        for i in 0..m.triangles().len() {
            let base = vertices.len() as u32;
            vertices.extend(m.triangle(i));
            tris.push([base, base + 1, base + 2]);
        }
        let split = Mesh::new(vertices, tris).unwrap();
        assert!(split.is_closed());
        assert!((split.volume().unwrap() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn open_mesh_is_not_closed() {
        let m = unit_box();
        let open = Mesh::new(m.vertices().to_vec(), m.triangles()[2..].to_vec()).unwrap();
        assert!(!open.is_closed());
        assert_eq!(open.volume(), None);
        // Missing only the bottom, the box still wraps the centre five-sixths of the way.
        assert!((open.winding_number(&Point3::origin()) - 5.0 / 6.0).abs() < 1e-9);
        assert!(open.contains_point(&Isometry3::identity(), &Point3::origin()));
    }

    #[test]
    fn bad_input_is_rejected() {
        assert_eq!(Mesh::new(vec![], vec![]).unwrap_err(), GeomError::EmptyMesh);
        let v = vec![
            Point3::origin(),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        assert!(matches!(
            Mesh::new(v.clone(), vec![[0, 1, 3]]),
            Err(GeomError::IndexOutOfRange {
                triangle: 0,
                index: 3,
                vertex_count: 3
            })
        ));
        assert!(matches!(
            Mesh::new(v.clone(), vec![[0, 1, 1]]),
            Err(GeomError::DegenerateMesh { triangles: 1 })
        ));
        let mut nan = v.clone();
        nan[1].y = f64::NAN;
        assert!(matches!(
            Mesh::new(nan, vec![[0, 1, 2]]),
            Err(GeomError::NonFiniteVertex { index: 1, .. })
        ));
        assert!(Mesh::cuboid(&Vector3::new(-1.0, 1.0, 1.0)).is_err());
    }

    #[test]
    fn pairwise_queries() {
        let a = unit_box();
        let b = unit_box();
        let pa = Isometry3::identity();
        let pb = Isometry3::translation(1.5, 0.0, 0.0);
        assert!((a.distance(&pa, &b, &pb) - 0.5).abs() < 1e-9);
        assert!(!a.intersects(&pa, &b, &pb));
        let overlapping = Isometry3::translation(0.8, 0.0, 0.0);
        assert!(a.intersects(&pa, &b, &overlapping));
        assert_eq!(a.distance(&pa, &b, &overlapping), 0.0);
        // Nested: surfaces do not meet, but the small box's centre is inside the big one.
        let big = Mesh::cuboid(&Vector3::repeat(2.0)).unwrap();
        assert!(!big.intersects(&pa, &a, &pa));
        assert!(big.contains_point(&pa, &Point3::origin()));
    }

    #[test]
    fn rays_and_points() {
        let m = unit_box();
        let pose = Isometry3::translation(0.0, 0.0, 1.0);
        let down = Ray::new(Point3::new(0.1, 0.2, 3.0), -Vector3::z());
        let hit = m.cast_ray(&pose, &down, 10.0).unwrap();
        assert!((hit.toi - 1.5).abs() < 1e-12);
        assert!((hit.point - Point3::new(0.1, 0.2, 1.5)).norm() < 1e-12);
        assert!((hit.normal.z.abs() - 1.0).abs() < 1e-12);
        assert!(m.cast_ray(&pose, &down, 1.0).is_none());
        let p = Point3::new(0.0, 0.0, 3.0);
        assert!((m.distance_to_point(&pose, &p) - 1.5).abs() < 1e-12);
        assert!((m.closest_point(&pose, &p) - Point3::new(0.0, 0.0, 1.5)).norm() < 1e-12);
        let w = m.world_aabb(&pose);
        assert_eq!(
            w,
            Aabb::new(Point3::new(-0.5, -0.5, 0.5), Point3::new(0.5, 0.5, 1.5))
        );
    }

    proptest! {
        /// The world bounds are those of the vertices placed one by one (up to rounding), and
        /// a 45-degree turn of the unit box about z spans +-sqrt(1/2) exactly as computed.
        #[test]
        fn world_bounds_are_the_placed_vertices_bounds(
            axis in (-1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64),
            angle in -3.2..3.2f64,
            t in (-50.0..50.0f64, -50.0..50.0f64, -5.0..5.0f64),
        ) {
            let m = Mesh::uv_ellipsoid(&Vector3::new(0.9, 0.4, 0.6), 12, 8).unwrap();
            let pose = Isometry3::new(
                Vector3::new(t.0, t.1, t.2),
                Vector3::new(axis.0, axis.1, axis.2).normalize() * angle,
            );
            let placed = Aabb::from_points(m.vertices().iter().map(|v| pose * v).collect::<Vec<_>>().iter()).unwrap();
            let w = m.world_aabb(&pose);
            prop_assert!((w.min - placed.min).norm() < 1e-12 && (w.max - placed.max).norm() < 1e-12);
        }
    }

    #[test]
    fn world_bounds_of_a_turned_box() {
        let pose = Isometry3::new(
            Vector3::new(1.0, 2.0, 3.0),
            Vector3::z() * std::f64::consts::FRAC_PI_4,
        );
        let w = unit_box().world_aabb(&pose);
        let h = 0.5f64.sqrt();
        assert!((w.min - Point3::new(1.0 - h, 2.0 - h, 2.5)).norm() < 1e-15);
        assert!((w.max - Point3::new(1.0 + h, 2.0 + h, 3.5)).norm() < 1e-15);
    }

    #[test]
    fn mirror_transform_keeps_outward_winding() {
        let m = unit_box();
        let mirror = Matrix3::from_diagonal(&Vector3::new(-2.0, 1.0, 1.0));
        let t = m.transformed(&mirror, &Vector3::new(1.0, 0.0, 0.0)).unwrap();
        assert!((t.volume().unwrap() - 2.0).abs() < 1e-12);
        assert!((t.winding_number(&Point3::new(1.0, 0.0, 0.0)) - 1.0).abs() < 1e-9);
        assert_eq!(t.aabb().min, Point3::new(0.0, -0.5, -0.5));
    }
}
