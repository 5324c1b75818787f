//! Angle-weighted pseudo-normals (Baerentzen and Aanaes 2005): the inside test of a closed,
//! connected mesh, read at the closest surface feature of a point.

use crate::parry::shape::TrianglePointLocation;
use crate::sort::bucket_sort;
use crate::{Mesh, Vector3};

/// Angle-weighted pseudo-normals of a closed mesh's faces, edges and (welded) vertices.
#[derive(Debug, Clone)]
pub(super) struct PseudoNormals {
    weld: Vec<u32>,
    vertex: Vec<Vector3>,
    /// Summed face normals per welded edge, sorted by edge.
    edge: Vec<((u32, u32), Vector3)>,
    face: Vec<Vector3>,
}

impl PseudoNormals {
    pub(super) fn at(&self, mesh: &Mesh, tri: usize, loc: TrianglePointLocation) -> Vector3 {
        let t = mesh.triangles()[tri];
        let w = |k: usize| self.weld[t[k] as usize];
        match loc {
            TrianglePointLocation::OnVertex(i) => self.vertex[w(i as usize) as usize],
            TrianglePointLocation::OnEdge(i, _) => {
                let (a, b) = match i {
                    0 => (w(0), w(1)),
                    1 => (w(1), w(2)),
                    _ => (w(0), w(2)),
                };
                self.edge
                    .binary_search_by_key(&(a.min(b), a.max(b)), |e| e.0)
                    .map_or(self.face[tri], |k| self.edge[k].1)
            }
            TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid => self.face[tri],
        }
    }
}

pub(super) fn pseudo_normals(mesh: &Mesh, weld: &[u32]) -> PseudoNormals {
    let count = weld.iter().copied().max().map_or(0, |m| m as usize + 1);
    let mut vertex = vec![Vector3::zeros(); count];
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
    bucket_sort(&mut edges, count, |e| e.0.0 as usize, |e, f| e.0.1.cmp(&f.0.1));
    let mut edge: Vec<((u32, u32), Vector3)> = Vec::with_capacity(edges.len() / 2 + 1);
    for (key, n) in edges {
        match edge.last_mut() {
            Some((k, sum)) if *k == key => *sum += n,
            _ => edge.push((key, n)),
        }
    }
    PseudoNormals {
        weld: weld.to_vec(),
        vertex,
        edge,
        face,
    }
}
