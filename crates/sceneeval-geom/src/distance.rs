//! Exact distances between boxes, meshes and triangles: cheap exact bounds first, then GJK on
//! convex pieces, and branch and bound over the meshes' BVHs. No allocation.

use crate::parry::bounding_volume::Aabb as PAabb;
use crate::parry::math::{Pose, Vector};
use crate::parry::query::details;
use crate::parry::shape::{SupportMap, Triangle};
use crate::parry_adapter::{point_to_parry, to_parry_pose};
use crate::{Isometry3, Mesh, Obb, Point3, Real};

/// The gap between box `b` and the bounding box of `a` in `b`'s frame: a lower bound on the
/// distance between the solids.
#[inline]
pub(crate) fn frame_gap(b: &Obb, a: &Obb) -> Real {
    let rt = b.rotation.inverse();
    let m = (rt * a.rotation).into_inner();
    let t = rt * (a.center - b.center);
    let mut g2 = 0.0;
    for i in 0..3 {
        let reach = m[(i, 0)].abs() * a.half_extents.x
            + m[(i, 1)].abs() * a.half_extents.y
            + m[(i, 2)].abs() * a.half_extents.z;
        let gap = t[i].abs() - reach - b.half_extents[i];
        if gap > 0.0 {
            g2 += gap * gap;
        }
    }
    g2.sqrt()
}

/// The box-box distance when cheap bounds pin it down, else `None`.
///
/// Lower bound: the larger of the two frame gaps ([`frame_gap`] both ways). Upper bound: the
/// smallest distance from a corner of either box to the other box (a distance between two
/// points of the solids). When they agree to `1e-12` relative, the distance is the upper
/// bound: the closest points are a corner and a point of the other box, as for an object whose
/// nearest corner faces a wall. Otherwise (edge against edge, or overlapping boxes with no
/// corner inside the other) the caller runs GJK.
#[inline]
fn bracketed(a: &Obb, b: &Obb) -> Option<Real> {
    let lower = frame_gap(b, a).max(frame_gap(a, b));
    let mut upper2 = Real::INFINITY;
    for (x, y) in [(a, b), (b, a)] {
        for c in x.corners() {
            upper2 = upper2.min(y.distance_to_point_squared(&c));
        }
    }
    let upper = upper2.sqrt();
    (upper - lower <= 1e-12 * (1.0 + upper)).then_some(upper)
}

/// Distance between two solid boxes (0 when they touch or overlap): [`bracketed`] when its
/// bounds agree, else GJK on the two cuboids' support maps.
///
/// parry's dedicated `distance_cuboid_cuboid` (which `parry::query::distance` dispatches to)
/// is not used: its separating-axis shortcut can overestimate the distance by millimetres when
/// an edge of one box is closest to an edge of the other.
#[inline]
pub(crate) fn box_box(a: &Obb, b: &Obb) -> Real {
    if let Some(d) = bracketed(a, b) {
        return d;
    }
    let (pa, ca) = a.to_parry();
    let (pb, cb) = b.to_parry();
    details::distance_support_map_support_map(&pa.inv_mul(&pb), &ca, &cb)
}

/// Distance between two axis-aligned boxes (0 when they meet).
#[inline]
fn aabb_gap(a: &PAabb, b: &PAabb) -> Real {
    let mins = a.mins - b.maxs;
    let maxs = a.maxs - b.mins;
    mins.max(-maxs).max(Vector::ZERO).length()
}

/// The separation of `t` from the plane of `u` (0 if `t` touches or crosses it).
#[inline]
fn plane_gap(t: &Triangle, u: &Triangle) -> Real {
    let n = (u.b - u.a).cross(u.c - u.a);
    let len = n.length();
    if len == 0.0 {
        return 0.0;
    }
    let d = [n.dot(t.a - u.a), n.dot(t.b - u.a), n.dot(t.c - u.a)];
    let (lo, hi) = (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]));
    if lo > 0.0 {
        lo / len
    } else if hi < 0.0 {
        -hi / len
    } else {
        0.0
    }
}

/// A lower bound on the distance between two triangles: their separation along either
/// triangle's normal and along the line through their centroids (projections onto unit axes).
#[inline]
fn triangle_gap(t: &Triangle, u: &Triangle) -> Real {
    let d = (u.a + u.b + u.c - t.a - t.b - t.c) / 3.0;
    let len = d.length();
    let along = if len > 0.0 {
        let t_max = d.dot(t.a).max(d.dot(t.b)).max(d.dot(t.c));
        let u_min = d.dot(u.a).min(d.dot(u.b)).min(d.dot(u.c));
        ((u_min - t_max) / len).max(0.0)
    } else {
        0.0
    };
    plane_gap(t, u).max(plane_gap(u, t)).max(along)
}

#[inline]
fn triangle_aabb(t: &Triangle) -> PAabb {
    PAabb::new(t.a.min(t.b).min(t.c), t.a.max(t.b).max(t.c))
}

/// The cost limit for a branch-and-bound search given an upper bound on the answer: slightly
/// above it, so that the leaf achieving it is not excluded by the strict comparison.
#[inline]
fn search_limit(upper: Real) -> Real {
    if upper.is_finite() {
        upper * (1.0 + 1e-9) + 1e-12
    } else {
        Real::MAX
    }
}

/// Distance from a placed mesh's surface to a convex shape given in its own frame at `pose`
/// (a cuboid or a triangle), by branch and bound over the mesh's BVH: nodes whose bounding
/// box (moved into the shape's frame) is no nearer than the best triangle so far are pruned;
/// each remaining triangle is measured exactly (GJK).
///
/// `upper` is a known upper bound on the distance, or infinity; it only speeds the search up.
fn mesh_convex<G: SupportMap>(
    mesh: &Mesh,
    mesh_pose: &Isometry3,
    shape: &G,
    shape_aabb: &PAabb,
    pose: &Pose,
    upper: Real,
) -> Real {
    let tm = mesh.parry_shape();
    // Mesh frame -> shape frame.
    let rel = pose.inv_mul(&to_parry_pose(mesh_pose));
    tm.bvh()
        .find_best(
            search_limit(upper),
            |node, _| aabb_gap(&node.aabb().transform_by(&rel), shape_aabb),
            |leaf, _| {
                let t = tm.triangle(leaf);
                let t = Triangle::new(rel * t.a, rel * t.b, rel * t.c);
                Some(details::distance_support_map_support_map(
                    &Pose::IDENTITY,
                    &t,
                    shape,
                ))
            },
        )
        .map_or(upper, |(_, d)| d)
}

/// An upper bound on the distance between two placed meshes' surfaces: the distance between
/// the points reached by alternating closest-point projections from `start` (a few BVH point
/// queries; often the exact distance).
pub(crate) fn mesh_mesh_upper_bound(
    a: &Mesh,
    pa: &Isometry3,
    b: &Mesh,
    pb: &Isometry3,
    start: &Point3,
) -> Real {
    let mut qa = a.closest_point(pa, start);
    let mut qb = b.closest_point(pb, &qa);
    for _ in 0..2 {
        qa = a.closest_point(pa, &qb);
        qb = b.closest_point(pb, &qa);
    }
    (qa - qb).norm()
}

/// An upper bound on the distance between a placed mesh's surface and a solid box: project
/// the box's centre onto the mesh, that point onto the box, and back onto the mesh.
pub(crate) fn mesh_box_upper_bound(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> Real {
    let q = mesh.closest_point(pose, &b.center);
    let q = mesh.closest_point(pose, &b.closest_point(&q));
    (q - b.closest_point(&q)).norm()
}

/// Distance between the surfaces of two placed meshes, by a two-level branch and bound: a node
/// of `a`'s BVH is bounded below by the nearest leaf box of `b` (itself found by a pruned
/// search of `b`'s BVH), and each remaining triangle of `a` searches `b` for its nearest
/// triangle, both searches pruned by the best distance so far. Exact.
pub(crate) fn mesh_mesh(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3) -> Real {
    let (ta, tb) = (a.parry_shape(), b.parry_shape());
    let start = pb * b.aabb().center();
    let upper = mesh_mesh_upper_bound(a, pa, b, pb, &start);
    // a's frame -> b's frame.
    let rel = to_parry_pose(pb).inv_mul(&to_parry_pose(pa));
    let root = tb.bvh().root_aabb();
    let nearest_leaf_box = |aabb: &PAabb, best: Real| -> Real {
        if aabb_gap(&root, aabb) >= best {
            return Real::MAX;
        }
        tb.bvh()
            .find_best(
                best,
                |nb, _| aabb_gap(&nb.aabb(), aabb),
                |leaf, _| tb.bvh().leaf_node(leaf).map(|n| aabb_gap(&n.aabb(), aabb)),
            )
            .map_or(Real::MAX, |(_, d)| d)
    };
    ta.bvh()
        .find_best(
            search_limit(upper),
            |na, best| nearest_leaf_box(&na.aabb().transform_by(&rel), best),
            |leaf, best| {
                let t = ta.triangle(leaf);
                let t = Triangle::new(rel * t.a, rel * t.b, rel * t.c);
                let t_aabb = triangle_aabb(&t);
                tb.bvh()
                    .find_best(
                        best,
                        |nb, _| aabb_gap(&nb.aabb(), &t_aabb),
                        |other, best| {
                            let u = tb.triangle(other);
                            // Cheap separating-axis bounds first: most candidates stop here.
                            if triangle_gap(&t, &u) >= best {
                                return None;
                            }
                            Some(details::distance_support_map_support_map(&Pose::IDENTITY, &t, &u))
                        },
                    )
                    .map(|(_, d)| d)
            },
        )
        .map_or(upper, |(_, d)| d)
}

/// Distance between a placed mesh's surface and a solid box.
pub(crate) fn mesh_box(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> Real {
    let (pb, cb) = b.to_parry();
    let local = PAabb::new(-cb.half_extents, cb.half_extents);
    mesh_convex(mesh, pose, &cb, &local, &pb, mesh_box_upper_bound(mesh, pose, b))
}

fn parry_triangle(tri: &[Point3; 3]) -> Triangle {
    Triangle::new(
        point_to_parry(&tri[0]),
        point_to_parry(&tri[1]),
        point_to_parry(&tri[2]),
    )
}

/// Distance between a placed mesh's surface and a world triangle.
pub(crate) fn mesh_triangle(mesh: &Mesh, pose: &Isometry3, tri: &[Point3; 3]) -> Real {
    let t = parry_triangle(tri);
    mesh_convex(
        mesh,
        pose,
        &t,
        &triangle_aabb(&t),
        &Pose::IDENTITY,
        Real::INFINITY,
    )
}

/// Distance between a solid box and a world triangle.
pub(crate) fn box_triangle(b: &Obb, tri: &[Point3; 3]) -> Real {
    let (pb, cb) = b.to_parry();
    // The triangle is in world coordinates: its pose relative to the cuboid is pb^-1.
    details::distance_support_map_support_map(&pb.inverse(), &cb, &parry_triangle(tri))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Rotation3, Vector3};
    use std::f64::consts::FRAC_PI_4;

    fn cube(c: [Real; 3], h: Real, yaw: Real) -> Obb {
        Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::repeat(h), yaw).unwrap()
    }

    #[test]
    fn box_distances_are_exact() {
        let a = cube([0.0, 0.0, 0.0], 0.5, 0.0);
        // Face to face, 1 m gap.
        assert!((box_box(&a, &cube([2.0, 0.0, 0.0], 0.5, 0.0)) - 1.0).abs() < 1e-12);
        // Diagonal offset: gap 0.5 in x and 0.5 in y -> sqrt(0.5).
        let d = box_box(&a, &cube([1.5, 1.5, 0.0], 0.5, 0.0));
        assert!((d - 0.5f64.sqrt()).abs() < 1e-12, "{d}");
        // Corner of a 45-degree box toward a face: 1.3 - 0.5 sqrt(2) - 0.5.
        let d = box_box(&a, &cube([1.3, 0.0, 0.0], 0.5, FRAC_PI_4));
        assert!((d - (0.8 - 0.5 * 2f64.sqrt())).abs() < 1e-12, "{d}");
        // Overlapping and nested boxes are 0 apart.
        assert_eq!(box_box(&a, &cube([0.7, 0.0, 0.0], 0.5, 0.3)), 0.0);
        assert_eq!(box_box(&a, &cube([0.1, 0.0, 0.0], 0.1, 0.3)), 0.0);
    }

    #[test]
    fn box_distance_agrees_with_brute_force() {
        // Dense sampling of the second box's surface gives an upper bound that converges to
        // the exact distance; a coarse grid bounds the error by the grid spacing.
        let a = Obb::new(
            Point3::new(0.1, -0.2, 0.3),
            Vector3::new(0.6, 0.3, 0.2),
            Rotation3::from_euler_angles(0.3, -0.2, 0.7),
        )
        .unwrap();
        for (i, yaw) in [0.0, 0.4, 1.1, 2.5].into_iter().enumerate() {
            let b = Obb::new(
                Point3::new(1.4, 0.5 + 0.1 * i as Real, 0.6),
                Vector3::new(0.3, 0.5, 0.4),
                Rotation3::from_euler_angles(0.1 * i as Real, 0.5, yaw),
            )
            .unwrap();
            let exact = box_box(&a, &b);
            let n = 40;
            let mut best = Real::INFINITY;
            for ix in 0..=n {
                for iy in 0..=n {
                    for iz in 0..=n {
                        let l = Vector3::new(
                            (2.0 * ix as Real / n as Real - 1.0) * b.half_extents.x,
                            (2.0 * iy as Real / n as Real - 1.0) * b.half_extents.y,
                            (2.0 * iz as Real / n as Real - 1.0) * b.half_extents.z,
                        );
                        best = best.min(a.distance_to_point(&b.to_world(&l)));
                    }
                }
            }
            // Never above the sampled minimum, and within the grid's reach of it.
            assert!(exact <= best + 1e-12, "{exact} > {best}");
            assert!(best - exact < 0.03, "{exact} vs {best}");
        }
    }

    #[test]
    fn bracketing_agrees_with_gjk() {
        // Over a sweep of yaws and offsets, the shortcut (when it applies) equals GJK.
        let a = cube([0.0, 0.0, 0.5], 0.5, 0.0);
        let (pa, ca) = a.to_parry();
        let mut shortcuts = 0;
        for i in 0..60 {
            let yaw = 0.1 * i as Real;
            for dx in [0.9, 1.3, 2.0] {
                let b = Obb::from_yaw(
                    Point3::new(dx, 0.3 * (i % 7) as Real - 0.9, 0.4 + 0.05 * (i % 3) as Real),
                    Vector3::new(0.3, 0.2, 0.35),
                    yaw,
                )
                .unwrap();
                let (pb, cb) = b.to_parry();
                let gjk = details::distance_support_map_support_map(&pa.inv_mul(&pb), &ca, &cb);
                if let Some(d) = bracketed(&a, &b) {
                    shortcuts += 1;
                    assert!((d - gjk).abs() < 1e-9, "yaw {yaw} dx {dx}: {d} vs {gjk}");
                }
                assert!((box_box(&a, &b) - gjk).abs() < 1e-9);
            }
        }
        assert!(
            shortcuts > 60,
            "the shortcut should apply in most of these: {shortcuts}"
        );
    }

    #[test]
    fn box_distance_is_mirror_symmetric() {
        // Found by a mirror-symmetry law in the relations crate: parry's cuboid-cuboid
        // shortcut gives 1.781161 for the mirrored pair but 1.780385 for the original; both are
        // 1.780385 (a 60^3 grid on the second box's surface gives 1.780394).
        let r = |m: [Real; 4]| {
            Rotation3::from_matrix_unchecked(crate::Matrix3::new(
                m[0], m[1], 0.0, m[2], m[3], 0.0, 0.0, 0.0, 1.0,
            ))
        };
        let b = Obb {
            center: Point3::new(0.0, -2.375793039456613, 0.0),
            half_extents: Vector3::new(0.05, 0.4070422242028465, 0.05),
            rotation: r([
                -0.9925879607510085,
                -0.12152835131011316,
                0.12152835131011316,
                -0.9925879607510085,
            ]),
        };
        let a = Obb {
            center: Point3::new(-1.833736971811297, -1.8769287386567672, 0.0),
            half_extents: Vector3::repeat(0.05),
            rotation: r([
                0.11382045802485088,
                -0.9935013353463664,
                0.9935013353463664,
                0.11382045802485088,
            ]),
        };
        let rb = b.rotation.matrix();
        let flip = crate::Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0));
        let m = rb * flip * rb.transpose();
        let mirrored = Obb {
            center: b.center + m * (a.center - b.center),
            half_extents: a.half_extents,
            rotation: Rotation3::from_matrix_unchecked(m * a.rotation.matrix() * flip),
        };
        let (d, dm) = (a.distance_to_obb(&b), mirrored.distance_to_obb(&b));
        assert!((d - 1.780_384_815).abs() < 1e-8, "{d}");
        assert!((d - dm).abs() < 1e-9, "{d} vs {dm}");
    }

    /// A small closed UV sphere (2 * 8 * 5 = 80 triangles) with the given radii.
    fn sphere(r: Vector3) -> Mesh {
        let (segs, rings) = (8u32, 6u32);
        let mut v = vec![Point3::new(0.0, 0.0, r.z)];
        for i in 1..rings {
            let th = std::f64::consts::PI * Real::from(i) / Real::from(rings);
            for j in 0..segs {
                let ph = std::f64::consts::TAU * Real::from(j) / Real::from(segs);
                v.push(Point3::new(
                    r.x * th.sin() * ph.cos(),
                    r.y * th.sin() * ph.sin(),
                    r.z * th.cos(),
                ));
            }
        }
        let south = v.len() as u32;
        v.push(Point3::new(0.0, 0.0, -r.z));
        let ring = |i: u32, j: u32| 1 + (i - 1) * segs + j % segs;
        let mut t = Vec::new();
        for j in 0..segs {
            t.push([0, ring(1, j), ring(1, j + 1)]);
            t.push([south, ring(rings - 1, j + 1), ring(rings - 1, j)]);
        }
        for i in 1..rings - 1 {
            for j in 0..segs {
                t.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
                t.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
            }
        }
        Mesh::new(v, t).unwrap()
    }

    fn world_triangles(m: &Mesh, pose: &Isometry3) -> Vec<Triangle> {
        (0..m.triangles().len())
            .map(|i| {
                let [a, b, c] = m.triangle(i).map(|p| point_to_parry(&(pose * p)));
                Triangle::new(a, b, c)
            })
            .collect()
    }

    #[test]
    fn branch_and_bound_equals_brute_force() {
        let a = sphere(Vector3::new(0.6, 0.4, 0.3));
        let b = sphere(Vector3::new(0.3, 0.5, 0.4));
        let bx = Obb::from_yaw(Point3::new(0.2, -0.1, 0.0), Vector3::new(0.4, 0.2, 0.3), 0.4).unwrap();
        let (pbx, cbx) = bx.to_parry();
        let tri = [
            Point3::new(0.3, 1.0, -0.2),
            Point3::new(1.1, 1.3, 0.4),
            Point3::new(0.5, 1.6, 0.9),
        ];
        for k in 0..12 {
            let kf = Real::from(k);
            let pa = Isometry3::new(
                Vector3::new(0.1 * kf, -0.3, 0.2),
                Vector3::new(0.1, 0.2, 0.3 * kf),
            );
            let pb = Isometry3::new(
                Vector3::new(1.2 - 0.05 * kf, 0.4, 0.1 * kf),
                Vector3::new(0.0, -0.3, 0.5 * kf),
            );
            let (ta, tb) = (world_triangles(&a, &pa), world_triangles(&b, &pb));
            let id = Pose::IDENTITY;
            let mut brute = Real::INFINITY;
            for x in &ta {
                for y in &tb {
                    brute = brute.min(details::distance_support_map_support_map(&id, x, y));
                }
            }
            let fast = a.distance(&pa, &b, &pb);
            assert!((fast - brute).abs() < 1e-9, "pose {k}: {fast} vs {brute}");
            let brute_box = ta
                .iter()
                .map(|x| details::distance_support_map_support_map(&pbx.inverse(), &cbx, x))
                .fold(Real::INFINITY, Real::min);
            let fast_box = a.distance_to_obb(&pa, &bx);
            assert!(
                (fast_box - brute_box).abs() < 1e-9,
                "pose {k}: {fast_box} vs {brute_box}"
            );
            let t = parry_triangle(&tri);
            let brute_tri = ta
                .iter()
                .map(|x| details::distance_support_map_support_map(&id, x, &t))
                .fold(Real::INFINITY, Real::min);
            let fast_tri = a.distance_to_triangle(&pa, &tri);
            assert!(
                (fast_tri - brute_tri).abs() < 1e-9,
                "pose {k}: {fast_tri} vs {brute_tri}"
            );
        }
    }

    #[test]
    fn crossing_and_touching_meshes_are_zero_apart() {
        let a = sphere(Vector3::new(0.5, 0.5, 0.5));
        let id = Isometry3::identity();
        for (dx, expected) in [(0.6, 0.0), (0.3, 0.0), (1.0, 0.0), (1.25, 0.25)] {
            let pb = Isometry3::translation(dx, 0.0, 0.0);
            let d = a.distance(&id, &a, &pb);
            // Poles and equator vertices lie on the x axis: the gap between the spheres along
            // it is dx - 1 when positive.
            assert!((d - expected).abs() < 1e-12, "dx {dx}: {d}");
            assert_eq!(a.intersects(&id, &a, &pb), d == 0.0, "dx {dx}");
        }
    }

    #[test]
    fn box_triangle_distance() {
        let a = cube([0.0, 0.0, 1.0], 0.5, 0.3);
        let tri = [
            Point3::new(-5.0, -5.0, 2.8),
            Point3::new(5.0, -5.0, 2.8),
            Point3::new(0.0, 5.0, 2.8),
        ];
        assert!((a.distance_to_triangle(&tri) - 1.3).abs() < 1e-9);
        assert_eq!(cube([0.0, 0.0, 2.3], 0.5, 0.3).distance_to_triangle(&tri), 0.0);
    }
}
