//! [`SolidTables`]: every table behind the inside tests of one mesh, built together, and the
//! tests that combine them: the distance to the surface and the side of a point
//! ([`PointClass`]), and the side of a whole ball when it is certain.

use crate::parry::math::Vector as PVector;
use crate::parry::query::PointQueryWithLocation;
use crate::parry::query::RayCast;
use crate::{Aabb, Mesh, Point3, Real, Vector3};

use super::TriangleTree;
use super::balls::{Ball, interior_balls};
use super::edge_tree::EdgeTree;
use super::patches::{Patches, Region, region};
use super::pseudo_normals::{PseudoNormals, pseudo_normals};
use super::topology::{Component, boundary_edges, components, half_edges, part_mesh, weld_ids};

/// Closed meshes with at most this many components bound depths per component.
const MAX_REGIONS: usize = 64;

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
        let regions = (boundary.is_empty() && components.len() <= MAX_REGIONS).then(|| {
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

#[cfg(test)]
mod tests {
    use super::super::test_support::open_box;
    use super::*;
    use crate::Isometry3;

    #[test]
    fn closed_box_uses_pseudo_normals_and_agrees_with_the_winding_number() {
        let mesh = Mesh::cuboid(&Vector3::new(0.5, 0.3, 0.2)).unwrap();
        let t = mesh.solid();
        assert!(t.is_simple_solid());
        assert!(t.boundary.is_empty());
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
