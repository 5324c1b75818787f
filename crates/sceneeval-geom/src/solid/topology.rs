//! How a mesh's triangles connect: vertices welded by position, half-edges sorted so that
//! triangles sharing an edge are neighbours, union-find over triangles, connected
//! [`Component`]s and the boundary chain's edges.

use std::collections::HashMap;

use crate::sort::bucket_sort;
use crate::{Aabb, Mesh, Point3, Real};

use super::edge_tree::Edge;

/// Probe vertices per connected component.
const COMPONENT_PROBES: usize = 7;

/// A connected component of a mesh (triangles sharing welded edges), for nesting tests.
#[derive(Debug, Clone)]
pub(crate) struct Component {
    /// Bounds in the mesh frame.
    pub aabb: Aabb,
    /// A few of its vertices (indices), spread over its extremes.
    pub probes: Vec<u32>,
    /// Its triangles.
    pub(super) members: Vec<u32>,
}

/// Ids of vertices merged by exact position.
pub(super) fn weld_ids(mesh: &Mesh) -> Vec<u32> {
    crate::weld_vertices(mesh.vertices()).0
}

/// A triangle's edge between welded vertices, for the sorting-based adjacency passes.
#[derive(Debug, Clone, Copy)]
pub(super) struct HalfEdge {
    /// The welded ends, smaller first.
    pub(super) key: (u32, u32),
    /// Whether the triangle runs it from `key.0` to `key.1`.
    forward: bool,
    pub(super) tri: u32,
    /// The original vertex indices, in the triangle's direction.
    from: u32,
    to: u32,
}

/// Every triangle's three edges (skipping edges whose ends weld together), sorted by welded
/// ends then triangle: triangles sharing an edge are neighbours in the list.
pub(super) fn half_edges(mesh: &Mesh, weld: &[u32]) -> Vec<HalfEdge> {
    let mut out = Vec::with_capacity(mesh.triangles().len() * 3);
    for (ti, t) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let (from, to) = (t[k], t[(k + 1) % 3]);
            let (a, b) = (weld[from as usize], weld[to as usize]);
            if a != b {
                out.push(HalfEdge {
                    key: (a.min(b), a.max(b)),
                    forward: a < b,
                    tri: ti as u32,
                    from,
                    to,
                });
            }
        }
    }
    // By lower end (a counting sort: linear), then each vertex's few edges by higher end and
    // triangle (and first vertex, which tells a degenerate triangle's two uses of one edge
    // apart).
    let vertices = weld.iter().copied().max().map_or(0, |m| m as usize + 1);
    bucket_sort(
        &mut out,
        vertices,
        |e| e.key.0 as usize,
        |e, f| (e.key.1, e.tri, e.from).cmp(&(f.key.1, f.tri, f.from)),
    );
    out
}

/// Calls `f` for every pair of consecutive half-edges on one welded edge.
pub(super) fn edge_neighbours(edges: &[HalfEdge], mut f: impl FnMut(&HalfEdge, &HalfEdge)) {
    for w in edges.windows(2) {
        if w[0].key == w[1].key {
            f(&w[0], &w[1]);
        }
    }
}

/// Union-find over `n` items, the smaller index as root.
pub(super) struct Sets(Vec<u32>);

impl Sets {
    pub(super) fn new(n: usize) -> Self {
        Sets((0..n as u32).collect())
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let up = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = up;
            x = up;
        }
        x
    }

    pub(super) fn union(&mut self, a: u32, b: u32) {
        let (x, y) = (self.find(a), self.find(b));
        if x != y {
            self.0[x.max(y) as usize] = x.min(y);
        }
    }

    /// Each item's set as a dense id numbered in order of the sets' smallest members.
    pub(super) fn ids(&mut self) -> (Vec<u32>, usize) {
        let n = self.0.len();
        let mut dense = vec![u32::MAX; n];
        let mut ids = Vec::with_capacity(n);
        let mut count = 0u32;
        for k in 0..n as u32 {
            let r = self.find(k) as usize;
            if dense[r] == u32::MAX {
                dense[r] = count;
                count += 1;
            }
            ids.push(dense[r]);
        }
        (ids, count as usize)
    }

    /// The items of each set, ascending, from [`Sets::ids`]' answer.
    pub(super) fn members(ids: &[u32], count: usize) -> Vec<Vec<u32>> {
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); count];
        for (item, &set) in ids.iter().enumerate() {
            members[set as usize].push(item as u32);
        }
        members
    }
}

/// Connected components (triangles sharing a welded edge), largest first, and their count.
pub(super) fn components(mesh: &Mesh, edges: &[HalfEdge]) -> (Vec<Component>, usize) {
    let tris = mesh.triangles();
    let mut sets = Sets::new(tris.len());
    edge_neighbours(edges, |e, f| sets.union(e.tri, f.tri));
    let (of, count) = sets.ids();
    let members = Sets::members(&of, count);
    let v = mesh.vertices();
    let mut mark = vec![false; v.len()];
    let mut out: Vec<(usize, Component)> = members
        .iter()
        .map(|m| {
            let ids = member_vertices(tris, m, &mut mark);
            let aabb = Aabb::from_points(ids.iter().map(|&i| &v[i as usize]))
                .unwrap_or(Aabb::new(Point3::origin(), Point3::origin()));
            // The first vertex and the extremes along each axis.
            let mut probes: Vec<u32> = ids.first().copied().into_iter().collect();
            for axis in [0, 1, 2] {
                for pick in [true, false] {
                    let best = ids.iter().copied().reduce(|a, b| {
                        let (pa, pb) = (v[a as usize][axis], v[b as usize][axis]);
                        if (pick && pb > pa) || (!pick && pb < pa) {
                            b
                        } else {
                            a
                        }
                    });
                    if let Some(b) = best
                        && !probes.contains(&b)
                    {
                        probes.push(b);
                    }
                }
            }
            probes.truncate(COMPONENT_PROBES);
            (
                m.len(),
                Component {
                    aabb,
                    probes,
                    members: m.clone(),
                },
            )
        })
        .collect();
    out.sort_by_key(|c| std::cmp::Reverse(c.0));
    (out.into_iter().map(|(_, c)| c).collect(), count)
}

/// Edges of the surface's boundary chain: welded edges whose directed uses do not cancel,
/// with the number of uncancelled uses. Empty for a closed, consistently wound mesh.
pub(super) fn boundary_edges(mesh: &Mesh, edges: &[HalfEdge]) -> Vec<Edge> {
    let v = mesh.vertices();
    let mut out = Vec::new();
    for group in edges.chunk_by(|a, b| a.key == b.key) {
        let net: i32 = group.iter().map(|e| if e.forward { 1 } else { -1 }).sum();
        if net != 0 {
            let e = &group[0];
            out.push((v[e.from as usize], v[e.to as usize], Real::from(net.abs())));
        }
    }
    out
}

/// One component as a mesh of its own (its vertices renumbered), or `None` if it cannot be
/// built (every triangle degenerate).
pub(super) fn part_mesh(mesh: &Mesh, c: &Component) -> Option<Mesh> {
    let mut index: HashMap<u32, u32> = HashMap::new();
    let mut vertices = Vec::new();
    let triangles: Vec<[u32; 3]> = c
        .members
        .iter()
        .map(|&t| {
            mesh.triangles()[t as usize].map(|v| {
                *index.entry(v).or_insert_with(|| {
                    vertices.push(mesh.vertices()[v as usize]);
                    (vertices.len() - 1) as u32
                })
            })
        })
        .collect();
    Mesh::new(vertices, triangles).ok()
}

/// The distinct vertices of the triangles `members`, ascending. `mark` is scratch space with
/// one flag per vertex of `tris`' mesh, all `false` on entry and again on return.
pub(super) fn member_vertices(tris: &[[u32; 3]], members: &[u32], mark: &mut [bool]) -> Vec<u32> {
    let mut ids = Vec::new();
    for &t in members {
        for v in tris[t as usize] {
            let seen = &mut mark[v as usize];
            if !*seen {
                *seen = true;
                ids.push(v);
            }
        }
    }
    for &v in &ids {
        mark[v as usize] = false;
    }
    ids.sort_unstable();
    ids
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn member_vertices_lists_each_vertex_once_in_order_and_clears_its_marks() {
        let tris = [[4, 1, 2], [2, 1, 0], [5, 6, 7], [2, 4, 3]];
        let mut mark = vec![false; 8];
        assert_eq!(member_vertices(&tris, &[0, 1, 3], &mut mark), vec![0, 1, 2, 3, 4]);
        assert!(mark.iter().all(|m| !m));
        assert_eq!(member_vertices(&tris, &[2], &mut mark), vec![5, 6, 7]);
        assert_eq!(member_vertices(&tris, &[], &mut mark), Vec::<u32>::new());
    }
}
