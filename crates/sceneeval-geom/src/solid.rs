//! The solid a mesh bounds: inside tests in time logarithmic in the triangle count, interior
//! balls and connected components. Built once per mesh on first use ([`Mesh::solid`]) and
//! shared by every object that places the mesh.
//!
//! **What "inside" means.** A closed mesh of one connected component bounds an ordinary solid;
//! a point is inside when it lies behind the angle-weighted pseudo-normal of its closest
//! surface feature (Baerentzen and Aanaes 2005): exact, and as cheap as a closest-point query.
//! Any other mesh (open, or several components that may touch or overlap) is inside where its
//! generalized winding number (Jacobson et al. 2013) is at least 1/2 in magnitude: 1 inside
//! and 0 outside each closed component, and for open meshes a smooth measure of how much of
//! the surface surrounds the point, so a box missing a face still holds its inside (the
//! missing face acts as a virtual lid) and a cavity closed on five sides counts as solid. The
//! winding number is summed over a bounding-volume hierarchy with the far clusters replaced
//! by dipoles (Barill et al. 2018) and an error bound per cluster; clusters are refined until
//! the bound can no longer change the answer, so the decision is the exact winding number's.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};

use crate::parry::math::Vector as PVector;
use crate::parry::query::RayCast;
use crate::parry::query::{PointQuery, PointQueryWithLocation};
use crate::parry::shape::TrianglePointLocation;
use crate::sort::bucket_sort;
use crate::{Aabb, Mesh, Point2, Point3, Real, Vector3};

/// Triangles per leaf of the [`TriangleTree`].
const LEAF_SIZE: usize = 8;
/// A cluster at least this many of its radii away is replaced by its dipole.
const DIPOLE_DISTANCE: Real = 2.0;
/// Boundary-edge clusters at least this many box diagonals away are bounded as a whole.
const EDGE_FAR: Real = 2.0;
/// Triangles whose inward ray seeds an interior ball.
const BALL_SEEDS: usize = 12;
/// Steps a ball takes away from its closest surface point.
const BALL_STEPS: usize = 4;
/// Interior balls kept per mesh.
const MAX_BALLS: usize = 8;
/// Probe vertices per connected component.
const COMPONENT_PROBES: usize = 7;
/// Closed meshes with at most this many components bound depths per component.
const MAX_REGIONS: usize = 64;
/// Components with at most this many planar patches are tested for convexity.
const MAX_REGION_PLANES: usize = 64;

/// Where a point lies relative to a mesh's solid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PointClass {
    /// Distance to the surface (mesh frame, metres); a lower bound when not `exact`.
    pub distance: Real,
    /// Whether `distance` is the distance (else the search radius it exceeds).
    pub exact: bool,
    /// Whether the point is inside the solid.
    pub inside: bool,
    /// The triangle holding the closest surface point, when the distance is exact.
    pub triangle: Option<u32>,
}

/// A ball inside a mesh's solid, in the mesh frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ball {
    pub centre: Point3,
    pub radius: Real,
}

/// A connected component of a mesh (triangles sharing welded edges), for nesting tests.
#[derive(Debug, Clone)]
pub(crate) struct Component {
    /// Bounds in the mesh frame.
    pub aabb: Aabb,
    /// A few of its vertices (indices), spread over its extremes.
    pub probes: Vec<u32>,
    /// Its triangles.
    members: Vec<u32>,
}

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

/// Tables behind the inside tests of one mesh. See the module docs.
#[derive(Debug, Clone)]
pub(crate) struct SolidTables {
    normals: Option<PseudoNormals>,
    pub(crate) tree: TriangleTree,
    boundary: EdgeTree,
    pub(crate) components: Vec<Component>,
    /// Interior balls, found on first use.
    balls: std::sync::OnceLock<Vec<Ball>>,
    patches: Patches,
    /// The solid as a union of its components, if the surface has no boundary and at most
    /// [`MAX_REGIONS`] components.
    pub(crate) regions: Option<Vec<Region>>,
    /// For such a mesh of several components: each component as a mesh of its own (`None`
    /// when all its triangles are degenerate), so that a point's side is decided by the
    /// pseudo-normals (or rays) of the few components whose box holds it instead of a winding
    /// number over the whole mesh. Each part is built when a point first falls in its
    /// component's box: a collision touching one leg of a table never builds the others.
    parts: Vec<std::sync::OnceLock<Option<Mesh>>>,
    /// Whether the mesh has such parts.
    has_parts: bool,
}

impl SolidTables {
    pub(crate) fn new(mesh: &Mesh) -> Self {
        let weld = weld_ids(mesh);
        let edges = half_edges(mesh, &weld);
        let (components, count) = components(mesh, &edges);
        let normals = (mesh.is_closed() && count == 1).then(|| pseudo_normals(mesh, &weld));
        let tree = TriangleTree::new(mesh);
        let boundary = EdgeTree::new(boundary_edges(mesh, &edges));
        let patches = Patches::new(mesh, &edges);
        // Without a boundary chain every component's winding number is an integer, and a
        // point inside the solid is enclosed by some component: its depth is at most its
        // distance to that component's boundary.
        let regions = (boundary.nodes.is_empty() && components.len() <= MAX_REGIONS).then(|| {
            let mut mark = vec![false; mesh.vertices().len()];
            components
                .iter()
                .map(|c| region(mesh, c, &patches, &mut mark))
                .collect()
        });
        let has_parts = regions.is_some() && components.len() > 1;
        let parts = if has_parts {
            components.iter().map(|_| std::sync::OnceLock::new()).collect()
        } else {
            Vec::new()
        };
        SolidTables {
            normals,
            tree,
            boundary,
            components,
            balls: std::sync::OnceLock::new(),
            patches,
            regions,
            parts,
            has_parts,
        }
    }

    /// A few large balls inside the solid (mesh frame), largest first; found on first use.
    pub(crate) fn balls(&self, mesh: &Mesh) -> &[Ball] {
        self.balls.get_or_init(|| interior_balls(mesh, self))
    }

    /// Whether the inside test is the pseudo-normal one (a closed, connected mesh).
    #[cfg(test)]
    pub(crate) fn is_simple_solid(&self) -> bool {
        self.normals.is_some()
    }

    /// Distance to the surface and the exact inside decision for a mesh-frame point.
    pub(crate) fn classify(&self, mesh: &Mesh, p: &Point3) -> PointClass {
        self.classify_within(mesh, p, Real::INFINITY)
    }

    /// [`SolidTables::classify`] with the distance resolved only up to `max_dist`: beyond it,
    /// `distance` is `max_dist` (a lower bound), `exact` is false and no triangle is known.
    /// The closest-point search then prunes everything farther than `max_dist`, which keeps
    /// a point deep inside a round object as cheap as one near its surface; the inside
    /// decision comes from the winding number.
    pub(crate) fn classify_within(&self, mesh: &Mesh, p: &Point3, max_dist: Real) -> PointClass {
        match self.closest(mesh, p, max_dist) {
            Some((distance, pseudo, triangle)) => PointClass {
                distance,
                exact: true,
                inside: pseudo.unwrap_or_else(|| self.winding_inside(mesh, p)),
                triangle: Some(triangle),
            },
            None => PointClass {
                distance: max_dist,
                exact: false,
                inside: self.far_inside(mesh, p),
                triangle: None,
            },
        }
    }

    /// The inside decision for a point known to lie farther than some radius from the
    /// surface: for a simple solid, the side of the surface two rays (in fixed, non-axis
    /// directions) first hit from, when they agree; otherwise the winding number.
    fn far_inside(&self, mesh: &Mesh, p: &Point3) -> bool {
        if !mesh.aabb().contains_point(p) {
            return false;
        }
        if self.normals.is_some() {
            let from_inside = |dir: Vector3| {
                let ray = crate::parry::query::Ray::new(
                    PVector::new(p.x, p.y, p.z),
                    PVector::new(dir.x, dir.y, dir.z),
                );
                // parry turns the hit normal toward the ray; the winding says which side.
                mesh.parry_shape()
                    .cast_local_ray_and_get_normal(&ray, Real::MAX, false)
                    .and_then(|hit| mesh.triangles().get(hit.subshape as usize).map(|_| hit.subshape))
                    .map(|t| {
                        let [a, b, c] = mesh.triangle(t as usize);
                        dir.dot(&(b - a).cross(&(c - a))) > 0.0
                    })
            };
            let first = from_inside(Vector3::new(0.5773, 0.6012, 0.5527));
            let second = from_inside(Vector3::new(-0.6403, 0.3512, -0.6832));
            match (first, second) {
                (Some(a), Some(b)) if a == b => return a,
                (None, None) => return false,
                _ => {}
            }
        }
        self.winding_inside(mesh, p)
    }

    fn winding_inside(&self, mesh: &Mesh, p: &Point3) -> bool {
        if !mesh.aabb().contains_point(p) {
            return false;
        }
        if self.has_parts {
            // No boundary: inside the solid is inside some component. A component's box is
            // its part's box (the part holds exactly the vertices of its triangles).
            return self.components.iter().zip(&self.parts).any(|(c, slot)| {
                c.aabb.contains_point(p)
                    && slot
                        .get_or_init(|| part_mesh(mesh, c))
                        .as_ref()
                        .is_some_and(|part| part.solid().classify_within(part, p, 0.0).inside)
            });
        }
        self.winding(mesh, p, 0.0).0.abs() >= 0.5
    }

    /// An upper bound on the distance to the surface of every point in the convex hull of
    /// `corners` (mesh frame): their largest distance to the planar patch holding `triangle`
    /// when it is convex, else to that triangle (distance to a convex set is convex, so its
    /// largest value over a hull is at a corner).
    pub(crate) fn convex_bound(&self, mesh: &Mesh, triangle: u32, corners: &[Point3]) -> Real {
        self.patches.bound(mesh, triangle as usize, corners)
    }

    /// [`SolidTables::classify_within`] at the centre `c` of a ball of radius `rho` (with
    /// `max_dist >= rho`), and the side of the whole ball when it is certain: `Some(true)` when
    /// every point of the ball is inside, `Some(false)` when every point is outside.
    pub(crate) fn classify_ball(
        &self,
        mesh: &Mesh,
        c: &Point3,
        rho: Real,
        max_dist: Real,
    ) -> (PointClass, Option<bool>) {
        let bx = mesh.aabb();
        let max_dist = max_dist.max(rho);
        if !bx.loosened(rho).contains_point(c) {
            // Outside the box grown by the radius: the whole ball is outside the box.
            let class = match self.closest(mesh, c, max_dist) {
                Some((distance, _, t)) => PointClass {
                    distance,
                    exact: true,
                    inside: false,
                    triangle: Some(t),
                },
                None => PointClass {
                    distance: max_dist,
                    exact: false,
                    inside: false,
                    triangle: None,
                },
            };
            return (class, Some(false));
        }
        let found = self.closest(mesh, c, max_dist);
        let (distance, exact, pseudo, triangle) = match found {
            Some((d, pseudo, t)) => (d, true, pseudo, Some(t)),
            None => (max_dist, false, None, None),
        };
        let clear = distance > rho;
        let class = |inside| PointClass {
            distance,
            exact,
            inside,
            triangle,
        };
        if found.is_none() && self.normals.is_some() {
            // A simple solid with no surface within the ball: one side throughout.
            let inside = self.far_inside(mesh, c);
            return (class(inside), Some(inside));
        }
        if let Some(inside) = pseudo {
            return (class(inside), clear.then_some(inside));
        }
        if clear && self.has_parts {
            // No boundary: the side is constant on a ball that misses the surface.
            let inside = self.winding_inside(mesh, c);
            return (class(inside), Some(inside));
        }
        // How far the winding number can move within the ball, if the ball misses the surface.
        let drift = if clear {
            rho * self.boundary.gradient_bound(c, rho)
        } else {
            Real::INFINITY
        };
        let (w, err) = self.winding(mesh, c, if drift.is_finite() { drift } else { 0.0 });
        let class = class(bx.contains_point(c) && w.abs() >= 0.5);
        let spread = err + drift;
        let side = if !spread.is_finite() {
            None
        } else if w - spread >= 0.5 || w + spread <= -0.5 {
            // Inside the solid everywhere; the box test is separate.
            bx_contains_ball(bx, c, rho).then_some(true)
        } else if w - spread > -0.5 && w + spread < 0.5 {
            Some(false)
        } else {
            None
        };
        (class, side)
    }

    /// Distance from a mesh-frame point to the surface (if at most `max_dist`), for a simple
    /// solid the pseudo-normal inside decision, and the closest triangle.
    fn closest(&self, mesh: &Mesh, p: &Point3, max_dist: Real) -> Option<(Real, Option<bool>, u32)> {
        let pt = PVector::new(p.x, p.y, p.z);
        let (proj, (tri, loc)) = if max_dist.is_finite() {
            mesh.parry_shape()
                .project_local_point_and_get_location_with_max_dist(pt, false, max_dist)?
        } else {
            mesh.parry_shape().project_local_point_and_get_location(pt, false)
        };
        let q = Point3::new(proj.point.x, proj.point.y, proj.point.z);
        let d = (p - q).norm();
        let Some(n) = &self.normals else {
            return Some((d, None, tri));
        };
        Some((d, Some((p - q).dot(&n.at(mesh, tri as usize, loc)) < 0.0), tri))
    }

    /// The winding number at `q` (mesh frame) and a bound on its error, refined until the
    /// bound plus `margin` cannot move it across +-1/2 (or it is exact).
    pub(crate) fn winding(&self, mesh: &Mesh, q: &Point3, margin: Real) -> (Real, Real) {
        self.tree.winding(mesh, q, margin)
    }
}

fn bx_contains_ball(b: &Aabb, c: &Point3, rho: Real) -> bool {
    (0..3).all(|k| c[k] - rho >= b.min[k] && c[k] + rho <= b.max[k])
}

/// Maximal planar patches of a mesh: triangles joined across welded edges when they lie in
/// one plane. Box faces split into grids become one patch each, so a surface lying flat just
/// inside a face is bounded by its height over the face whatever its size.
#[derive(Debug, Clone)]
struct Patches {
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
    fn new(mesh: &Mesh, edges: &[HalfEdge]) -> Self {
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
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); count];
        for (ti, &p) in of.iter().enumerate() {
            members[p as usize].push(ti as u32);
        }
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

    /// See [`SolidTables::convex_bound`].
    fn bound(&self, mesh: &Mesh, triangle: usize, corners: &[Point3]) -> Real {
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

/// One component as a mesh of its own (its vertices renumbered), or `None` if it cannot be
/// built (every triangle degenerate).
fn part_mesh(mesh: &Mesh, c: &Component) -> Option<Mesh> {
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
fn member_vertices(tris: &[[u32; 3]], members: &[u32], mark: &mut [bool]) -> Vec<u32> {
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

/// The [`Region`] of one closed component.
fn region(mesh: &Mesh, c: &Component, patches: &Patches, mark: &mut [bool]) -> Region {
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

/// A triangle's edge between welded vertices, for the sorting-based adjacency passes.
#[derive(Debug, Clone, Copy)]
struct HalfEdge {
    /// The welded ends, smaller first.
    key: (u32, u32),
    /// Whether the triangle runs it from `key.0` to `key.1`.
    forward: bool,
    tri: u32,
    /// The original vertex indices, in the triangle's direction.
    from: u32,
    to: u32,
}

/// Every triangle's three edges (skipping edges whose ends weld together), sorted by welded
/// ends then triangle: triangles sharing an edge are neighbours in the list.
fn half_edges(mesh: &Mesh, weld: &[u32]) -> Vec<HalfEdge> {
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

/// Union-find over `n` items, the smaller index as root.
struct Sets(Vec<u32>);

impl Sets {
    fn new(n: usize) -> Self {
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

    fn union(&mut self, a: u32, b: u32) {
        let (x, y) = (self.find(a), self.find(b));
        if x != y {
            self.0[x.max(y) as usize] = x.min(y);
        }
    }

    /// Each item's set as a dense id numbered in order of the sets' smallest members.
    fn ids(&mut self) -> (Vec<u32>, usize) {
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
}

/// Calls `f` for every pair of consecutive half-edges on one welded edge.
fn edge_neighbours(edges: &[HalfEdge], mut f: impl FnMut(&HalfEdge, &HalfEdge)) {
    for w in edges.windows(2) {
        if w[0].key == w[1].key {
            f(&w[0], &w[1]);
        }
    }
}

/// Ids of vertices merged by exact position.
fn weld_ids(mesh: &Mesh) -> Vec<u32> {
    crate::weld_vertices(mesh.vertices()).0
}

/// Angle-weighted pseudo-normals of a closed mesh's faces, edges and (welded) vertices.
#[derive(Debug, Clone)]
struct PseudoNormals {
    weld: Vec<u32>,
    vertex: Vec<Vector3>,
    /// Summed face normals per welded edge, sorted by edge.
    edge: Vec<((u32, u32), Vector3)>,
    face: Vec<Vector3>,
}

impl PseudoNormals {
    fn at(&self, mesh: &Mesh, tri: usize, loc: TrianglePointLocation) -> Vector3 {
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

fn pseudo_normals(mesh: &Mesh, weld: &[u32]) -> PseudoNormals {
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

/// Connected components (triangles sharing a welded edge), largest first, and their count.
fn components(mesh: &Mesh, edges: &[HalfEdge]) -> (Vec<Component>, usize) {
    let tris = mesh.triangles();
    let mut sets = Sets::new(tris.len());
    edge_neighbours(edges, |e, f| sets.union(e.tri, f.tri));
    let (of, count) = sets.ids();
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); count];
    for (ti, &c) in of.iter().enumerate() {
        members[c as usize].push(ti as u32);
    }
    let count = members.len();
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

/// A boundary edge: its ends and its multiplicity.
type Edge = (Point3, Point3, Real);

/// Edges of the surface's boundary chain: welded edges whose directed uses do not cancel,
/// with the number of uncancelled uses. Empty for a closed, consistently wound mesh.
fn boundary_edges(mesh: &Mesh, edges: &[HalfEdge]) -> Vec<Edge> {
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

/// Balls inside the solid: from the largest triangles, the midpoint of the inward ray to the
/// opposite surface, with its distance to the surface as radius.
fn interior_balls(mesh: &Mesh, tables: &SolidTables) -> Vec<Ball> {
    let mut order: Vec<(Real, usize)> = (0..mesh.triangles().len())
        .map(|k| {
            let [a, b, c] = mesh.triangle(k);
            ((b - a).cross(&(c - a)).norm(), k)
        })
        .collect();
    order.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
    let scale = mesh.aabb().extents().norm().max(1e-9);
    let mut balls: Vec<Ball> = Vec::new();
    // The centre of the box is the deepest point of convex, box-like shapes. A point inside
    // is no farther from the surface than from the box's faces: search no farther.
    let bx = mesh.aabb();
    let centre = bx.center();
    let reach = (0..3)
        .map(|k| bx.half_extents()[k])
        .fold(Real::INFINITY, Real::min);
    let class = tables.classify_within(mesh, &centre, reach.max(1e-9) * (1.0 + 1e-9));
    if class.inside && class.exact && class.distance > 0.0 {
        balls.push(grow_ball(mesh, tables, centre, class.distance));
    }
    for &(_, k) in order.iter().take(BALL_SEEDS) {
        let [a, b, c] = mesh.triangle(k);
        let Some(n) = (b - a).cross(&(c - a)).try_normalize(0.0) else {
            continue;
        };
        let g = Point3::from((a.coords + b.coords + c.coords) / 3.0);
        for dir in [-n, n] {
            let start = g + dir * (1e-9 * scale);
            let ray = crate::parry::query::Ray::new(
                PVector::new(start.x, start.y, start.z),
                PVector::new(dir.x, dir.y, dir.z),
            );
            let Some(toi) = mesh.parry_shape().cast_local_ray(&ray, 2.0 * scale, false) else {
                continue;
            };
            // The hit lies half the ray away: the surface is no farther than that.
            let centre = start + dir * (0.5 * toi);
            let class = tables.classify_within(mesh, &centre, 0.5 * toi * (1.0 + 1e-9) + 1e-12);
            if class.inside && class.exact && class.distance > 0.0 {
                balls.push(grow_ball(mesh, tables, centre, class.distance));
                break;
            }
        }
    }
    balls.sort_by(|x, y| {
        y.radius
            .total_cmp(&x.radius)
            .then(x.centre.x.total_cmp(&y.centre.x))
            .then(x.centre.y.total_cmp(&y.centre.y))
            .then(x.centre.z.total_cmp(&y.centre.z))
    });
    // Keep balls whose centres lie outside the balls already kept.
    let mut kept: Vec<Ball> = Vec::new();
    for b in balls {
        if kept.len() < MAX_BALLS && kept.iter().all(|k| (k.centre - b.centre).norm() > k.radius) {
            kept.push(b);
        }
    }
    kept
}

/// A ball inside the solid grown by a few steps away from its closest surface point (every
/// search bounded by a little more than the current radius, so that a ball deep inside a
/// round object stays cheap).
fn grow_ball(mesh: &Mesh, tables: &SolidTables, mut centre: Point3, mut radius: Real) -> Ball {
    for _ in 0..BALL_STEPS {
        let Some(proj) = mesh.parry_shape().project_local_point_with_max_dist(
            PVector::new(centre.x, centre.y, centre.z),
            false,
            radius * (1.0 + 1e-9) + 1e-12,
        ) else {
            break;
        };
        let away = centre - Point3::new(proj.point.x, proj.point.y, proj.point.z);
        let Some(dir) = away.try_normalize(0.0) else {
            break;
        };
        let next = centre + dir * (0.5 * radius);
        // Moving by r/2 away, the surface is at most 1.5 r from the new centre.
        let class = tables.classify_within(mesh, &next, 1.5 * radius * (1.0 + 1e-9));
        if !(class.inside && class.exact && class.distance > radius) {
            break;
        }
        centre = next;
        radius = class.distance;
    }
    Ball { centre, radius }
}

/// A node of a [`TriangleTree`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct TreeNode {
    /// Bounds of the node's triangles (mesh frame).
    pub lo: Point3,
    /// Highest corner of the bounds.
    pub hi: Point3,
    /// Area-weighted centroid of the triangles.
    centre: Point3,
    /// Sum of the triangles' area vectors (half the cross product of two edges).
    normal: Vector3,
    /// Total area.
    area: Real,
    /// Largest distance from `centre` to a corner of the node's triangles.
    radius: Real,
    /// Internal node: index of the right child (the left child is the next node). Leaf: first
    /// entry in [`TriangleTree::order`].
    index: u32,
    /// Triangles of a leaf; 0 for an internal node.
    count: u32,
    /// The node's triangle whose centroid lies nearest `centre`: its representative.
    pub rep: u32,
}

impl TreeNode {
    /// Whether the node is a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A bounding-volume hierarchy over a mesh's triangles (median splits, depth-first order),
/// with each node's dipole (area vector and centroid) for the winding number.
#[derive(Debug, Clone)]
pub(crate) struct TriangleTree {
    pub(crate) nodes: Vec<TreeNode>,
    pub(crate) order: Vec<u32>,
}

impl TriangleTree {
    fn new(mesh: &Mesh) -> Self {
        let mut items: Vec<(Point3, u32)> = (0..mesh.triangles().len())
            .map(|k| {
                let [a, b, c] = mesh.triangle(k);
                (Point3::from((a.coords + b.coords + c.coords) / 3.0), k as u32)
            })
            .collect();
        let mut tree = TriangleTree {
            nodes: Vec::with_capacity(2 * items.len().div_ceil(LEAF_SIZE)),
            order: Vec::with_capacity(items.len()),
        };
        if !items.is_empty() {
            tree.build(mesh, &mut items);
        }
        tree
    }

    /// Appends the subtree over `items` (centroid, triangle) in depth-first order. Leaves are
    /// measured from their triangles; internal nodes aggregate their children (boxes, area
    /// vectors and areas add up; the radius is bounded through the children's), so the build
    /// costs `n log n` for the splits and `n` for the measures.
    fn build(&mut self, mesh: &Mesh, items: &mut [(Point3, u32)]) {
        let at = self.nodes.len();
        let mut node = TreeNode {
            lo: Point3::from(Vector3::repeat(Real::INFINITY)),
            hi: Point3::from(Vector3::repeat(Real::NEG_INFINITY)),
            centre: Point3::origin(),
            normal: Vector3::zeros(),
            area: 0.0,
            radius: 0.0,
            index: 0,
            count: 0,
            rep: 0,
        };
        if items.len() <= LEAF_SIZE {
            let mut weighted = Vector3::zeros();
            for &(g, k) in items.iter() {
                let [a, b, c] = mesh.triangle(k as usize);
                for p in [a, b, c] {
                    node.lo = node.lo.inf(&p);
                    node.hi = node.hi.sup(&p);
                }
                let n = (b - a).cross(&(c - a)) * 0.5;
                let area = n.norm();
                node.normal += n;
                node.area += area;
                weighted += g.coords * area;
            }
            node.centre = if node.area > 0.0 {
                Point3::from(weighted / node.area)
            } else {
                nalgebra::center(&node.lo, &node.hi)
            };
            let mut nearest = Real::INFINITY;
            for &(g, k) in items.iter() {
                for p in mesh.triangle(k as usize) {
                    node.radius = node.radius.max((p - node.centre).norm());
                }
                let d = (g - node.centre).norm_squared();
                if d < nearest || (d == nearest && k < node.rep) {
                    nearest = d;
                    node.rep = k;
                }
            }
            items.sort_unstable_by_key(|&(_, k)| k);
            node.index = self.order.len() as u32;
            node.count = items.len() as u32;
            self.order.extend(items.iter().map(|&(_, k)| k));
            self.nodes.push(node);
            return;
        }
        self.nodes.push(node);
        let (mut lo, mut hi) = (
            Vector3::repeat(Real::INFINITY),
            Vector3::repeat(Real::NEG_INFINITY),
        );
        for (c, _) in items.iter() {
            lo = lo.inf(&c.coords);
            hi = hi.sup(&c.coords);
        }
        let axis = (hi - lo).imax();
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |(c, i), (d, j)| c[axis].total_cmp(&d[axis]).then(i.cmp(j)));
        let (left, right) = items.split_at_mut(mid);
        self.build(mesh, left);
        let right_index = self.nodes.len();
        self.build(mesh, right);
        let (l, r) = (self.nodes[at + 1], self.nodes[right_index]);
        let area = l.area + r.area;
        let centre = if area > 0.0 {
            Point3::from((l.centre.coords * l.area + r.centre.coords * r.area) / area)
        } else {
            nalgebra::center(&l.lo.inf(&r.lo), &l.hi.sup(&r.hi))
        };
        let (dl, dr) = ((l.centre - centre).norm(), (r.centre - centre).norm());
        let node = &mut self.nodes[at];
        node.lo = l.lo.inf(&r.lo);
        node.hi = l.hi.sup(&r.hi);
        node.normal = l.normal + r.normal;
        node.area = area;
        node.centre = centre;
        node.radius = (dl + l.radius).max(dr + r.radius);
        node.rep = if dl <= dr { l.rep } else { r.rep };
        node.index = right_index as u32;
    }

    /// The children of internal node `n`.
    #[inline]
    pub(crate) fn children(&self, n: usize) -> [usize; 2] {
        [n + 1, self.nodes[n].index as usize]
    }

    /// The triangles of leaf `n`.
    #[inline]
    pub(crate) fn leaf(&self, n: usize) -> &[u32] {
        let node = &self.nodes[n];
        let s = node.index as usize;
        &self.order[s..s + node.count as usize]
    }

    /// See [`SolidTables::winding`].
    fn winding(&self, mesh: &Mesh, q: &Point3, margin: Real) -> (Real, Real) {
        if self.nodes.is_empty() {
            return (0.0, 0.0);
        }
        let mut w = 0.0;
        let mut err = 0.0;
        let mut approximated: BinaryHeap<Approx> = BinaryHeap::new();
        let mut stack: Vec<usize> = vec![0];
        let decided = |w: Real, err: Real| {
            let gap = (w.abs() - 0.5).abs();
            gap > err + margin
        };
        loop {
            while let Some(n) = stack.pop() {
                let node = &self.nodes[n];
                let d = (node.centre - q).norm();
                if d > DIPOLE_DISTANCE * node.radius && node.area > 0.0 {
                    let value =
                        node.normal.dot(&(node.centre - q)) / (4.0 * std::f64::consts::PI * d * d * d);
                    let gap = d - node.radius;
                    let e = node.area * 2.0 * node.radius / (4.0 * std::f64::consts::PI * gap * gap * gap);
                    w += value;
                    err += e;
                    count_term();
                    approximated.push(Approx {
                        err: e,
                        value,
                        node: n,
                    });
                } else if node.is_leaf() {
                    for &k in self.leaf(n) {
                        count_term();
                        w += solid_angle(&mesh.triangle(k as usize), q) / (4.0 * std::f64::consts::PI);
                    }
                } else {
                    let [l, r] = self.children(n);
                    stack.push(r);
                    stack.push(l);
                }
            }
            if decided(w, err) {
                return (w, err.max(0.0));
            }
            let Some(top) = approximated.pop() else {
                return (w, 0.0);
            };
            w -= top.value;
            err -= top.err;
            let node = &self.nodes[top.node];
            if node.is_leaf() {
                for &k in self.leaf(top.node) {
                    count_term();
                    w += solid_angle(&mesh.triangle(k as usize), q) / (4.0 * std::f64::consts::PI);
                }
            } else {
                let [l, r] = self.children(top.node);
                // Children of a far node are farther relative to their size; the loop above
                // approximates them again or opens them.
                stack.push(r);
                stack.push(l);
            }
            if approximated.is_empty() && stack.is_empty() {
                err = 0.0;
            }
        }
    }
}

#[cfg(test)]
thread_local! {
    /// Terms (triangle solid angles and cluster dipoles) summed by winding numbers on this
    /// thread, for tests that count work.
    pub(crate) static WINDING_TERMS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Counts one term of a winding-number sum (tests only).
#[inline]
fn count_term() {
    #[cfg(test)]
    WINDING_TERMS.with(|c| c.set(c.get() + 1));
}

/// An approximated cluster, largest error first.
#[derive(Debug, Clone, Copy)]
struct Approx {
    err: Real,
    value: Real,
    node: usize,
}

impl PartialEq for Approx {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Approx {}
impl PartialOrd for Approx {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Approx {
    fn cmp(&self, other: &Self) -> Ordering {
        self.err.total_cmp(&other.err).then(other.node.cmp(&self.node))
    }
}

/// The signed solid angle of a triangle seen from `q` (Van Oosterom and Strackee 1983).
#[inline]
pub(crate) fn solid_angle(t: &[Point3; 3], q: &Point3) -> Real {
    let a = t[0] - q;
    let b = t[1] - q;
    let c = t[2] - q;
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    let num = a.dot(&b.cross(&c));
    let den = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
    2.0 * num.atan2(den)
}

/// A hierarchy over the boundary edges, bounding the winding number's gradient: away from the
/// surface the gradient of the solid angle is the Biot-Savart field of the boundary curve, so
/// `|grad w(p)| <= (1 / 4 pi) sum_e len_e / dist(p, e)^2` (zero for a closed mesh).
#[derive(Debug, Clone)]
struct EdgeTree {
    edges: Vec<Edge>,
    nodes: Vec<EdgeNode>,
}

#[derive(Debug, Clone, Copy)]
struct EdgeNode {
    lo: Point3,
    hi: Point3,
    /// Total length times multiplicity.
    length: Real,
    index: u32,
    count: u32,
}

impl EdgeTree {
    fn new(mut edges: Vec<Edge>) -> Self {
        let mut tree = EdgeTree {
            edges: Vec::new(),
            nodes: Vec::new(),
        };
        if !edges.is_empty() {
            let mut out = Vec::with_capacity(edges.len());
            tree.build(&mut edges, &mut out);
            tree.edges = out;
        }
        tree
    }

    fn build(&mut self, items: &mut [Edge], out: &mut Vec<Edge>) {
        let at = self.nodes.len();
        let (mut lo, mut hi) = (
            Point3::from(Vector3::repeat(Real::INFINITY)),
            Point3::from(Vector3::repeat(Real::NEG_INFINITY)),
        );
        let mut length = 0.0;
        for (a, b, m) in items.iter() {
            lo = lo.inf(a).inf(b);
            hi = hi.sup(a).sup(b);
            length += (b - a).norm() * m;
        }
        let mut node = EdgeNode {
            lo,
            hi,
            length,
            index: 0,
            count: 0,
        };
        if items.len() <= LEAF_SIZE {
            node.index = out.len() as u32;
            node.count = items.len() as u32;
            out.extend_from_slice(items);
            self.nodes.push(node);
            return;
        }
        self.nodes.push(node);
        let axis = (hi - lo).imax();
        let mid = items.len() / 2;
        let key = |e: &Edge| e.0[axis] + e.1[axis];
        items.select_nth_unstable_by(mid, |x, y| key(x).total_cmp(&key(y)));
        let (left, right) = items.split_at_mut(mid);
        self.build(left, out);
        let right_index = self.nodes.len() as u32;
        self.build(right, out);
        self.nodes[at].index = right_index;
    }

    /// An upper bound on `|grad w|` over the ball `(c, rho)`, infinite when the ball reaches a
    /// boundary edge.
    fn gradient_bound(&self, c: &Point3, rho: Real) -> Real {
        if self.nodes.is_empty() {
            return 0.0;
        }
        let mut total = 0.0;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            let gap = box_distance(&node.lo, &node.hi, c) - rho;
            let diag = (node.hi - node.lo).norm();
            if node.count > 0 || (gap > 0.0 && gap >= EDGE_FAR * diag) {
                if node.count > 0 {
                    let s = node.index as usize;
                    for (a, b, m) in &self.edges[s..s + node.count as usize] {
                        let g = point_segment_distance(c, a, b) - rho;
                        if g <= 0.0 {
                            return Real::INFINITY;
                        }
                        total += (b - a).norm() * m / (g * g);
                    }
                } else {
                    total += node.length / (gap * gap);
                }
            } else {
                stack.push(n + 1);
                stack.push(node.index as usize);
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

fn box_distance(lo: &Point3, hi: &Point3, p: &Point3) -> Real {
    let mut s = 0.0;
    for k in 0..3 {
        let d = (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0);
        s += d * d;
    }
    s.sqrt()
}

fn point_segment_distance(p: &Point3, a: &Point3, b: &Point3) -> Real {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::Isometry3;

    #[test]
    fn member_vertices_lists_each_vertex_once_in_order_and_clears_its_marks() {
        let tris = [[4, 1, 2], [2, 1, 0], [5, 6, 7], [2, 4, 3]];
        let mut mark = vec![false; 8];
        assert_eq!(member_vertices(&tris, &[0, 1, 3], &mut mark), vec![0, 1, 2, 3, 4]);
        assert!(mark.iter().all(|m| !m));
        assert_eq!(member_vertices(&tris, &[2], &mut mark), vec![5, 6, 7]);
        assert_eq!(member_vertices(&tris, &[], &mut mark), Vec::<u32>::new());
    }

    /// A unit cube (half extent 0.5) whose faces are split into `n` x `n` squares.
    pub(crate) fn subdivided_cube(n: u32) -> Mesh {
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for (k, sign) in [(0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            let (u, v) = if sign > 0.0 {
                ((k + 1) % 3, (k + 2) % 3)
            } else {
                ((k + 2) % 3, (k + 1) % 3)
            };
            let base = vertices.len() as u32;
            for i in 0..=n {
                for j in 0..=n {
                    let mut p = Vector3::zeros();
                    p[k] = 0.5 * sign;
                    p[u] = f64::from(i) / f64::from(n) - 0.5;
                    p[v] = f64::from(j) / f64::from(n) - 0.5;
                    vertices.push(Point3::from(p));
                }
            }
            let at = |i: u32, j: u32| base + i * (n + 1) + j;
            for i in 0..n {
                for j in 0..n {
                    triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                    triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
        Mesh::new(vertices, triangles).unwrap()
    }

    fn open_box() -> Mesh {
        let cube = Mesh::cuboid(&Vector3::repeat(0.5)).unwrap();
        Mesh::new(cube.vertices().to_vec(), cube.triangles()[2..].to_vec()).unwrap()
    }

    #[test]
    fn closed_box_uses_pseudo_normals_and_agrees_with_the_winding_number() {
        let mesh = Mesh::cuboid(&Vector3::new(0.5, 0.3, 0.2)).unwrap();
        let t = mesh.solid();
        assert!(t.is_simple_solid());
        assert!(t.boundary.nodes.is_empty());
        for k in 0..300 {
            let f = f64::from(k);
            let p = Point3::new(
                0.6 * (f * 0.37).sin(),
                0.4 * (f * 0.73).cos(),
                0.3 * (f * 1.31).sin(),
            );
            let c = t.classify(&mesh, &p);
            assert_eq!(c.inside, mesh.winding_number(&p) > 0.5, "{p}");
            // Resolving distances only up to 1 mm: rays decide points farther than that.
            let far = t.classify_within(&mesh, &p, 1e-3);
            assert_eq!(far.inside, c.inside, "{p}");
            assert_eq!(far.exact, c.distance <= 1e-3);
            assert!((c.distance - mesh.distance_to_point(&Isometry3::identity(), &p)).abs() < 1e-12);
        }
        // One ball, the largest inscribed one for a box (radius = smallest half extent).
        assert!(
            (t.balls(&mesh)[0].radius - 0.2).abs() < 1e-9,
            "{:?}",
            t.balls(&mesh)
        );
        assert_eq!(t.components.len(), 1);
    }

    #[test]
    fn hierarchical_winding_decides_like_the_exact_sum() {
        // An open, finely subdivided box (missing its bottom): points near the virtual lid
        // have winding numbers close to 1/2, where the dipole error matters.
        let cube = subdivided_cube(12);
        let tris: Vec<[u32; 3]> = cube
            .triangles()
            .iter()
            .enumerate()
            .filter(|(k, _)| {
                let [a, b, c] = cube.triangle(*k);
                !(a.z < -0.49 && b.z < -0.49 && c.z < -0.49)
            })
            .map(|(_, t)| *t)
            .collect();
        let open = Mesh::new(cube.vertices().to_vec(), tris).unwrap();
        assert!(!open.is_closed());
        let t = open.solid();
        assert!(!t.is_simple_solid());
        for k in 0..400 {
            let f = f64::from(k);
            let p = Point3::new(
                0.45 * (f * 0.37).sin(),
                0.45 * (f * 0.73).cos(),
                -0.5 + 0.02 * (f * 1.31).sin(),
            );
            let exact = open.winding_number(&p);
            let (w, err) = t.winding(&open, &p, 0.0);
            assert!((w - exact).abs() <= err + 1e-9, "{p}: {w} +- {err} vs {exact}");
            assert_eq!(t.classify(&open, &p).inside, exact.abs() >= 0.5, "{p}: {exact}");
        }
    }

    /// `subdivided_cube(n)` without its bottom face: an open box.
    fn open_cube(n: u32) -> Mesh {
        let cube = subdivided_cube(n);
        let tris: Vec<[u32; 3]> = (0..cube.triangles().len())
            .filter(|&k| cube.triangle(k).iter().any(|p| p.z > -0.49))
            .map(|k| cube.triangles()[k])
            .collect();
        Mesh::new(cube.vertices().to_vec(), tris).unwrap()
    }

    #[test]
    fn inside_tests_of_open_meshes_cost_about_log_n() {
        // Open boxes of 10,240 and 162,816 triangles (16 times as many): a point 0.15 m or
        // more inside sums the triangles and cluster dipoles near it, whose number depends on
        // its distance to the surface, not on the triangle count (measured: about 2,000 and
        // 3,300 terms), where a flat sum takes one term per triangle.
        let mut per_point = Vec::new();
        for n in [32u32, 128] {
            let open = open_cube(n);
            let t = open.solid();
            assert!(!t.is_simple_solid());
            WINDING_TERMS.with(|c| c.set(0));
            let mut count = 0u64;
            for k in 0..64 {
                let f = f64::from(k);
                let p = Point3::new(
                    0.35 * (f * 0.37).sin(),
                    0.35 * (f * 0.73).cos(),
                    0.3 * (f * 1.31).sin(),
                );
                assert!(t.classify(&open, &p).inside, "{p}");
                count += 1;
            }
            let terms = WINDING_TERMS.with(std::cell::Cell::get) as f64 / count as f64;
            assert!(
                terms < 0.25 * open.triangles().len() as f64,
                "{terms} terms per point"
            );
            per_point.push(terms);
        }
        assert!(per_point[1] <= 2.0 * per_point[0], "{per_point:?}");
    }

    #[test]
    fn ball_sides_are_certain_only_when_true() {
        let open = open_box();
        let t = open.solid();
        // The gradient bound is finite away from the boundary (the bottom rim).
        assert!(
            t.boundary
                .gradient_bound(&Point3::new(0.0, 0.0, 0.3), 0.05)
                .is_finite()
        );
        assert!(
            t.boundary
                .gradient_bound(&Point3::new(0.5, 0.5, -0.5), 0.05)
                .is_infinite()
        );
        for k in 0..200 {
            let f = f64::from(k);
            let c = Point3::new(
                0.7 * (f * 0.37).sin(),
                0.7 * (f * 0.73).cos(),
                0.7 * (f * 1.31).sin(),
            );
            let rho = 0.02 + 0.1 * (f * 0.11).sin().abs();
            let (_, side) = t.classify_ball(&open, &c, rho, rho);
            if let Some(side) = side {
                // Every point of the ball agrees.
                for j in 0..20 {
                    let g = f64::from(j);
                    let dir = Vector3::new((g * 1.7).sin(), (g * 2.3).cos(), (g * 0.9).sin()).normalize();
                    let p = c + dir * rho * (f64::from(j % 4) / 3.0);
                    assert_eq!(
                        open.winding_number(&p).abs() >= 0.5 && open.aabb().contains_point(&p),
                        side
                    );
                }
            }
        }
    }

    #[test]
    fn components_and_balls_of_two_boxes() {
        let a = Mesh::cuboid(&Vector3::new(0.5, 0.5, 0.05)).unwrap();
        let mut v = a.vertices().to_vec();
        let mut tris = a.triangles().to_vec();
        let base = v.len() as u32;
        v.extend(
            a.vertices()
                .iter()
                .map(|p| Point3::new(p.x * 0.2, p.y * 0.2, p.z * 4.0 - 0.3)),
        );
        tris.extend(a.triangles().iter().map(|t| t.map(|i| i + base)));
        let m = Mesh::new(v, tris).unwrap();
        let t = m.solid();
        assert_eq!(t.components.len(), 2);
        // Two overlapping closed parts: the winding number decides.
        assert!(!t.is_simple_solid());
        assert!(t.classify(&m, &Point3::new(0.0, 0.0, -0.3)).inside);
        assert!(t.classify(&m, &Point3::new(0.0, 0.0, 0.0)).inside);
        assert!(!t.classify(&m, &Point3::new(0.3, 0.3, -0.3)).inside);
        // The thin slab's ball has radius 0.05 (half its thickness).
        assert!(
            t.balls(&m).iter().any(|b| (b.radius - 0.05).abs() < 1e-6),
            "{:?}",
            t.balls(&m)
        );
    }
}
