//! Inside tests and surface distances for placed meshes.

use sceneeval_geom::parry::math::Vector as PVector;
use sceneeval_geom::parry::query::PointQueryWithLocation;
use sceneeval_geom::parry::shape::TrianglePointLocation;
use sceneeval_geom::{Isometry3, Mesh, Point3, Real, Vector3};

/// A placed mesh answering "how far is this point from the surface, and is it inside".
///
/// For a closed mesh (consistently wound outward by `sceneeval-geom`) the inside test is the
/// sign of the angle-weighted pseudo-normal at the closest surface feature (Baerentzen and
/// Aanaes 2005): exact, and as cheap as the closest-point query. For an open mesh it is the
/// generalized winding number ([`Mesh::contains_point`]), which degrades gracefully with holes
/// but costs one solid angle per triangle.
pub(crate) struct Solid<'a> {
    mesh: &'a Mesh,
    pose: &'a Isometry3,
    normals: Option<PseudoNormals>,
}

struct PseudoNormals {
    weld: Vec<u32>,
    vertex: Vec<Vector3>,
    /// Summed face normals per welded edge, sorted by edge.
    edge: Vec<((u32, u32), Vector3)>,
    face: Vec<Vector3>,
}

impl<'a> Solid<'a> {
    pub fn new(mesh: &'a Mesh, pose: &'a Isometry3) -> Self {
        let normals = mesh.is_closed().then(|| pseudo_normals(mesh));
        Solid { mesh, pose, normals }
    }

    /// Whether the inside test is the cheap, exact one.
    pub fn is_closed(&self) -> bool {
        self.normals.is_some()
    }

    /// Distance from the world point `p` to the surface, and for a closed mesh whether `p` is
    /// inside (`None` for an open mesh; use [`Solid::contains`]).
    pub fn query(&self, p: &Point3) -> (Real, Option<bool>) {
        let l = self.pose.inverse_transform_point(p);
        let (proj, (tri, loc)) = self
            .mesh
            .parry_shape()
            .project_local_point_and_get_location(PVector::new(l.x, l.y, l.z), false);
        let q = Point3::new(proj.point.x, proj.point.y, proj.point.z);
        let d = (l - q).norm();
        let Some(n) = &self.normals else {
            return (d, None);
        };
        let tri = tri as usize;
        let t = self.mesh.triangles()[tri];
        let w = |k: usize| n.weld[t[k] as usize];
        let normal = match loc {
            TrianglePointLocation::OnVertex(i) => n.vertex[w(i as usize) as usize],
            TrianglePointLocation::OnEdge(i, _) => {
                let (a, b) = match i {
                    0 => (w(0), w(1)),
                    1 => (w(1), w(2)),
                    _ => (w(0), w(2)),
                };
                n.edge
                    .binary_search_by_key(&(a.min(b), a.max(b)), |e| e.0)
                    .map_or(n.face[tri], |k| n.edge[k].1)
            }
            TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid => n.face[tri],
        };
        (d, Some((l - q).dot(&normal) < 0.0))
    }

    /// Whether the world point `p` is inside (pseudo-normal sign or winding number).
    pub fn contains(&self, p: &Point3) -> bool {
        match self.query(p) {
            (_, Some(inside)) => inside,
            (_, None) => self.mesh.contains_point(self.pose, p),
        }
    }
}

fn pseudo_normals(mesh: &Mesh) -> PseudoNormals {
    let (weld, distinct) = sceneeval_geom::weld_vertices(mesh.vertices());
    let mut vertex = vec![Vector3::zeros(); distinct];
    let mut edges: Vec<((u32, u32), Vector3)> = Vec::with_capacity(mesh.triangles().len() * 3);
    let mut face = Vec::with_capacity(mesh.triangles().len());
    for (k, t) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = mesh.triangle(k);
        let n = (b - a)
            .cross(&(c - a))
            .try_normalize(0.0)
            .unwrap_or_else(Vector3::zeros);
        face.push(n);
        let corners = [a, b, c];
        for i in 0..3 {
            let (p, q, r) = (corners[i], corners[(i + 1) % 3], corners[(i + 2) % 3]);
            let angle = (q - p).angle(&(r - p));
            vertex[weld[t[i] as usize] as usize] += n * angle;
            let (u, v) = (weld[t[i] as usize], weld[t[(i + 1) % 3] as usize]);
            edges.push(((u.min(v), u.max(v)), n));
        }
    }
    // Sum the face normals of each edge (sorting is faster than hashing here).
    edges.sort_unstable_by_key(|e| e.0);
    let mut edge: Vec<((u32, u32), Vector3)> = Vec::with_capacity(edges.len() / 2 + 1);
    for (key, n) in edges {
        match edge.last_mut() {
            Some((k, sum)) if *k == key => *sum += n,
            _ => edge.push((key, n)),
        }
    }
    PseudoNormals {
        weld,
        vertex,
        edge,
        face,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_box_inside_test_matches_winding_number() {
        let mesh = Mesh::cuboid(&Vector3::new(0.5, 0.5, 0.5)).unwrap();
        let pose = Isometry3::new(Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.2, 0.3, 0.4));
        let solid = Solid::new(&mesh, &pose);
        assert!(solid.is_closed());
        // Points near corners and edges, where the pseudo-normal matters.
        for k in 0..200 {
            let f = k as f64;
            let local = Point3::new(
                0.6 * (f * 0.37).sin(),
                0.6 * (f * 0.73).cos(),
                0.6 * (f * 1.31).sin(),
            );
            let p = pose * local;
            let (d, inside) = solid.query(&p);
            assert_eq!(inside, Some(mesh.contains_point(&pose, &p)), "{local}");
            assert!((d - mesh.distance_to_point(&pose, &p)).abs() < 1e-12);
        }
        // Just outside a corner (closest feature a vertex) and an edge.
        assert!(!solid.contains(&(pose * Point3::new(0.51, 0.51, 0.51))));
        assert!(!solid.contains(&(pose * Point3::new(0.51, 0.51, 0.0))));
        assert!(solid.contains(&(pose * Point3::new(0.49, 0.49, 0.49))));
    }
}
