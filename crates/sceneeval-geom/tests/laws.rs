//! Geometric invariants of the geometry primitives, checked with proptest.

#![allow(clippy::expect_used)]

use proptest::prelude::*;
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Mesh, Obb, Point2, Point3, Polygon2, Side, Vector3, planar};

fn point() -> impl Strategy<Value = Point3> {
    (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64).prop_map(|(x, y, z)| Point3::new(x, y, z))
}

fn half_extents() -> impl Strategy<Value = Vector3> {
    (0.05..2.0f64, 0.05..2.0f64, 0.05..2.0f64).prop_map(|(x, y, z)| Vector3::new(x, y, z))
}

fn rotation() -> impl Strategy<Value = UnitQuaternion<f64>> {
    (-3.2..3.2f64, -3.2..3.2f64, -3.2..3.2f64)
        .prop_map(|(r, p, y)| UnitQuaternion::from_euler_angles(r, p, y))
}

fn motion() -> impl Strategy<Value = Isometry3> {
    (point(), rotation()).prop_map(|(t, r)| Isometry3::from_parts(Translation3::from(t.coords), r))
}

fn obb() -> impl Strategy<Value = Obb> {
    (point(), half_extents(), rotation())
        .prop_map(|(c, h, r)| Obb::new(c, h, r.to_rotation_matrix()).expect("valid by construction"))
}

/// A simple star-shaped polygon: radii at increasing angles around a centre.
fn star_polygon() -> impl Strategy<Value = Polygon2> {
    (
        prop::collection::vec(0.5..3.0f64, 3..10),
        -3.0..3.0f64,
        -3.0..3.0f64,
    )
        .prop_map(|(radii, cx, cy)| {
            let n = radii.len();
            let pts = radii
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    let a = std::f64::consts::TAU * i as f64 / n as f64;
                    Point2::new(cx + r * a.cos(), cy + r * a.sin())
                })
                .collect();
            Polygon2::new(pts).expect("star polygons are simple")
        })
}

proptest! {
    /// Moving a box and a point together changes neither containment nor distance.
    #[test]
    fn obb_queries_are_rigid_motion_invariant(b in obb(), p in point(), m in motion()) {
        let moved = b.transformed(&m);
        let q = m * p;
        prop_assert_eq!(b.contains_point(&p), moved.contains_point(&q));
        prop_assert!((b.distance_to_point(&p) - moved.distance_to_point(&q)).abs() < 1e-9);
        prop_assert!((b.volume() - moved.volume()).abs() < 1e-12);
    }

    /// The world AABB of a box contains its corners and is tight on each axis.
    #[test]
    fn obb_aabb_is_tight(b in obb()) {
        let aabb = b.aabb();
        let corners = b.corners();
        for c in &corners {
            prop_assert!(aabb.loosened(1e-9).contains_point(c));
        }
        for i in 0..3 {
            let max = corners.iter().map(|c| c[i]).fold(f64::MIN, f64::max);
            prop_assert!((max - aabb.max[i]).abs() < 1e-9);
        }
    }

    /// Opposite faces lie on opposite sides of the centre, a full extent apart.
    #[test]
    fn obb_faces_are_symmetric(b in obb()) {
        for side in Side::ALL {
            let (axis, _) = side.axis_and_sign();
            let a = b.face_center(side);
            let o = b.face_center(side.opposite());
            prop_assert!(((a - o).norm() - 2.0 * b.half_extents[axis]).abs() < 1e-9);
            prop_assert!((((a.coords + o.coords) * 0.5) - b.center.coords).norm() < 1e-9);
        }
    }

    /// Box-box distance is symmetric, zero for intersecting boxes, and rigid-motion invariant.
    #[test]
    fn obb_pair_distance_laws(a in obb(), b in obb(), m in motion()) {
        let d = a.distance_to_obb(&b);
        prop_assert!((d - b.distance_to_obb(&a)).abs() < 1e-6);
        prop_assert!((d - a.transformed(&m).distance_to_obb(&b.transformed(&m))).abs() < 1e-6);
        prop_assert_eq!(a.intersects(&b), d <= 1e-9);
        prop_assert!(a.distance_lower_bound(&b) <= d + 1e-9);
        prop_assert!((a.distance_lower_bound(&b) - b.distance_lower_bound(&a)).abs() < 1e-12);
        prop_assert!(d <= a.aabb().distance_to_aabb(&b.aabb()) + a.aabb().extents().norm() + b.aabb().extents().norm());
    }

    /// A cuboid mesh agrees with the box it was made from on containment and surface distance.
    #[test]
    fn cuboid_mesh_matches_box(h in half_extents(), m in motion(), p in point()) {
        let mesh = Mesh::cuboid(&h).expect("valid box");
        let obb = Obb::from_local_aabb(mesh.aabb(), &m);
        let inside_box = obb.contains_point(&p);
        // Skip points within rounding of the surface.
        let surface = mesh.distance_to_point(&m, &p);
        prop_assume!(surface > 1e-7);
        prop_assert_eq!(mesh.contains_point(&m, &p), inside_box);
        if !inside_box {
            prop_assert!((surface - obb.distance_to_point(&p)).abs() < 1e-9);
        }
    }

    /// Polygon area and containment are invariant under rotation and translation in the plane,
    /// the triangulation covers the area, and clipping never exceeds either area.
    #[test]
    fn polygon_laws(poly in star_polygon(), angle in -3.2..3.2f64, dx in -5.0..5.0f64, dy in -5.0..5.0f64) {
        let (s, c) = angle.sin_cos();
        let moved = Polygon2::new(
            poly.points().iter().map(|p| Point2::new(c * p.x - s * p.y + dx, s * p.x + c * p.y + dy)).collect(),
        ).expect("a moved simple polygon is simple");
        prop_assert!((poly.area() - moved.area()).abs() < 1e-9);
        let tri_area: f64 = poly
            .triangulate()
            .iter()
            .map(|t| {
                let p = poly.points();
                ((p[t[1]] - p[t[0]]).perp(&(p[t[2]] - p[t[0]])) * 0.5).abs()
            })
            .sum();
        prop_assert!((tri_area - poly.area()).abs() < 1e-9 * poly.area().max(1.0));
        let centroid = poly.centroid();
        prop_assert!(poly.contains_point(&centroid), "star polygons contain their centroid");
        let square = [Point2::new(-1.0, -1.0), Point2::new(1.0, -1.0), Point2::new(1.0, 1.0), Point2::new(-1.0, 1.0)];
        let clipped = poly.intersection_area_with_convex(&square);
        prop_assert!((-1e-12..=4.0 + 1e-9).contains(&clipped) && clipped <= poly.area() + 1e-9);
    }

    /// Subtracting a convex hole from a convex subject leaves convex pieces that tile the
    /// subject outside the hole: their areas add up to the subject's minus the overlap, each
    /// lies in the subject and none overlaps the hole (its centroid is outside), and
    /// subtracting the same hole again changes nothing.
    #[test]
    fn subtraction_laws(
        a in convex_polygon(),
        b in convex_polygon(),
    ) {
        let pieces = planar::subtract_convex(&a, &b);
        let overlap = planar::area(&planar::clip_convex(&a, &b));
        let total: f64 = pieces.iter().map(|q| planar::area(q)).sum();
        prop_assert!((total + overlap - planar::area(&a)).abs() < 1e-9, "{} + {} vs {}", total, overlap, planar::area(&a));
        for q in &pieces {
            prop_assert!(planar::is_convex(q));
            let c = q.iter().fold(Point2::origin(), |acc, p| acc + p.coords / q.len() as f64);
            prop_assert!(planar::convex_contains(&a, &c, 1e-9));
            prop_assert!(planar::area(q) < 1e-9 || !planar::convex_contains(&b, &c, -1e-9));
        }
        let again: Vec<Vec<Point2>> = pieces.iter().flat_map(|q| planar::subtract_convex(q, &b)).collect();
        prop_assert_eq!(again, pieces);
    }
}

/// A convex counter-clockwise polygon: 3 to 12 points on an ellipse, at increasing angles.
fn convex_polygon() -> impl Strategy<Value = Vec<Point2>> {
    (
        prop::collection::vec(0.0..1.0f64, 3..12),
        0.2..2.0f64,
        0.2..2.0f64,
        -1.5..1.5f64,
        -1.5..1.5f64,
    )
        .prop_map(|(mut t, rx, ry, cx, cy)| {
            t.sort_by(f64::total_cmp);
            t.dedup();
            let pts: Vec<Point2> = t
                .iter()
                .map(|t| {
                    let a = std::f64::consts::TAU * t;
                    Point2::new(cx + rx * a.cos(), cy + ry * a.sin())
                })
                .collect();
            planar::convex_hull(&pts)
        })
        .prop_filter("a polygon with area", |p| p.len() >= 3 && planar::area(p) > 1e-6)
}
