//! Maximal planar patches of a mesh, and the [`Region`]s of its closed components: each
//! bounded by its box or, when convex, by the planes of its patches.

use crate::{Aabb, Mesh, Point2, Point3, Real, Vector3};

use super::topology::{Component, HalfEdge, Sets, edge_neighbours, member_vertices};

/// Components with at most this many planar patches are tested for convexity.
const MAX_REGION_PLANES: usize = 64;

/// The solid of a mesh without boundary as a union of its components (each a closed surface),
/// each bounded by its box or, when convex, by the planes of its faces: the depth of a point
/// enclosed by a component is at most its distance to that component's surface.
#[derive(Debug, Clone)]
pub(crate) struct Region {
    pub aabb: Aabb,
    /// Outward unit normals and offsets (`n . x = offset` on the face) of a convex component;
    /// empty for a non-convex one.
    pub planes: Vec<(Vector3, Real)>,
}

/// Maximal planar patches of a mesh: triangles joined across welded edges when they lie in
/// one plane. Box faces split into grids become one patch each, so a surface lying flat just
/// inside a face is bounded by its height over the face whatever its size.
#[derive(Debug, Clone)]
pub(super) struct Patches {
    of: Vec<u32>,
    patches: Vec<Patch>,
}

#[derive(Debug, Clone)]
struct Patch {
    normal: Vector3,
    offset: Real,
    u: Vector3,
    v: Vector3,
    /// The patch in `(u, v)` coordinates, counter-clockwise, when it is convex.
    hull: Option<Vec<Point2>>,
}

impl Patches {
    pub(super) fn new(mesh: &Mesh, edges: &[HalfEdge]) -> Self {
        let tris = mesh.triangles();
        let scale = 1.0 + mesh.aabb().extents().norm();
        let planes: Vec<(Vector3, Real, Real)> = (0..tris.len())
            .map(|k| {
                let [a, b, c] = mesh.triangle(k);
                let n = (b - a).cross(&(c - a));
                let area = 0.5 * n.norm();
                let n = n.try_normalize(0.0).unwrap_or_else(Vector3::z);
                (n, n.dot(&a.coords), area)
            })
            .collect();
        let mut sets = Sets::new(tris.len());
        edge_neighbours(edges, |e, f| {
            let (p, q) = (&planes[e.tri as usize], &planes[f.tri as usize]);
            if p.0.dot(&q.0) >= 1.0 - 1e-12 && (p.1 - q.1).abs() <= 1e-9 * scale {
                sets.union(e.tri, f.tri);
            }
        });
        let (of, count) = sets.ids();
        let members = Sets::members(&of, count);
        let v = mesh.vertices();
        let mut mark = vec![false; v.len()];
        let patches = members
            .iter()
            .map(|m| {
                let (normal, offset, _) = planes[m[0] as usize];
                let helper = if normal.x.abs() < 0.9 {
                    Vector3::x()
                } else {
                    Vector3::y()
                };
                let u = normal.cross(&helper).normalize();
                let w = normal.cross(&u);
                let flat = |p: &Point3| Point2::new(p.coords.dot(&u), p.coords.dot(&w));
                // Each vertex once (a patch of a gridded face shares most of its corners
                // between six triangles), then the hull of few points after Akl-Toussaint.
                let ids = member_vertices(tris, m, &mut mark);
                let pts: Vec<Point2> = ids.iter().map(|&i| flat(&v[i as usize])).collect();
                let hull = crate::planar::convex_hull_fast(&pts);
                let patch_area: Real = m.iter().map(|&t| planes[t as usize].2).sum();
                let hull_area = crate::planar::area(&hull);
                let convex = hull.len() >= 3 && (hull_area - patch_area).abs() <= 1e-9 * hull_area.max(1e-12);
                Patch {
                    normal,
                    offset,
                    u,
                    v: w,
                    hull: convex.then_some(hull),
                }
            })
            .collect();
        Patches { of, patches }
    }

    /// See [`SolidTables::convex_bound`](super::SolidTables::convex_bound).
    pub(super) fn bound(&self, mesh: &Mesh, triangle: usize, corners: &[Point3]) -> Real {
        let Some(patch) = self.of.get(triangle).and_then(|&p| self.patches.get(p as usize)) else {
            return Real::INFINITY;
        };
        let owned;
        let region: &[Point2] = match &patch.hull {
            Some(h) => h,
            None => {
                let flat = |p: &Point3| Point2::new(p.coords.dot(&patch.u), p.coords.dot(&patch.v));
                let [a, b, c] = mesh.triangle(triangle);
                owned = crate::planar::ccw(vec![flat(&a), flat(&b), flat(&c)]);
                &owned
            }
        };
        corners
            .iter()
            .map(|p| {
                let h = patch.normal.dot(&p.coords) - patch.offset;
                let q = Point2::new(p.coords.dot(&patch.u), p.coords.dot(&patch.v));
                let d = crate::planar::convex_distance(region, &q);
                (h * h + d * d).sqrt()
            })
            .fold(0.0, Real::max)
    }
}

/// The [`Region`] of one closed component.
pub(super) fn region(mesh: &Mesh, c: &Component, patches: &Patches, mark: &mut [bool]) -> Region {
    let mut ids: Vec<u32> = c.members.iter().map(|&t| patches.of[t as usize]).collect();
    ids.sort_unstable();
    ids.dedup();
    let scale = 1.0 + c.aabb.extents().norm();
    let mut planes = Vec::new();
    if ids.len() <= MAX_REGION_PLANES {
        let vertices = member_vertices(mesh.triangles(), &c.members, mark);
        let convex = ids.iter().all(|&id| {
            let p = &patches.patches[id as usize];
            vertices
                .iter()
                .all(|&v| p.normal.dot(&mesh.vertices()[v as usize].coords) - p.offset <= 1e-9 * scale)
        });
        if convex {
            planes = ids
                .iter()
                .map(|&id| {
                    (
                        patches.patches[id as usize].normal,
                        patches.patches[id as usize].offset,
                    )
                })
                .collect();
        }
    }
    Region { aabb: c.aabb, planes }
}
