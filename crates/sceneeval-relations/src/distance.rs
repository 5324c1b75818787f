//! Exact distances between objects (boxes or meshes, as solids) and architectural elements.

use sceneeval_geom::parry::bounding_volume::Aabb;
use sceneeval_geom::parry::math::{Pose, Rot3, Vector};
use sceneeval_geom::parry::query::details;
use sceneeval_geom::parry::shape::{Cuboid, SupportMap, Triangle};
use sceneeval_geom::{Isometry3, Mesh, Obb, Point3, Real};

use crate::ObjectGeom;

/// nalgebra isometry to parry pose (the geom crate keeps its own adapter private).
#[inline]
pub(crate) fn to_parry_pose(iso: &Isometry3) -> Pose {
    let q = iso.rotation.quaternion();
    let t = iso.translation.vector;
    Pose::from_parts(Vector::new(t.x, t.y, t.z), Rot3::from_xyzw(q.i, q.j, q.k, q.w))
}

#[inline]
fn to_parry_point(p: &Point3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// Squared distance from a point to a solid box.
#[inline]
fn point_box_sq(b: &Obb, p: &Point3) -> Real {
    let l = b.to_local(p);
    let mut d2 = 0.0;
    for i in 0..3 {
        let e = l[i].abs() - b.half_extents[i];
        if e > 0.0 {
            d2 += e * e;
        }
    }
    d2
}

/// The gap between box `b` and the bounding box of `a` in `b`'s frame: a lower bound on the
/// distance between the solids.
#[inline]
fn frame_gap(b: &Obb, a: &Obb) -> Real {
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
/// bound: the closest points are a corner and a point of the other box, as for an object
/// whose nearest corner faces a wall. Otherwise (edge against edge, or overlapping boxes
/// with no corner inside the other) the caller runs GJK.
#[inline]
fn bracketed(a: &Obb, b: &Obb) -> Option<Real> {
    let lower = frame_gap(b, a).max(frame_gap(a, b));
    let mut upper2 = Real::INFINITY;
    for (x, y) in [(a, b), (b, a)] {
        let r = x.rotation.matrix();
        let cols = [
            r.column(0) * x.half_extents.x,
            r.column(1) * x.half_extents.y,
            r.column(2) * x.half_extents.z,
        ];
        for k in 0..8 {
            let mut p = x.center;
            for (j, c) in cols.iter().enumerate() {
                if k & (1 << j) == 0 {
                    p -= c;
                } else {
                    p += c;
                }
            }
            upper2 = upper2.min(point_box_sq(y, &p));
        }
    }
    let upper = upper2.sqrt();
    (upper - lower <= 1e-12 * (1.0 + upper)).then_some(upper)
}

/// Distance between two solid boxes (0 when they touch or overlap): [`bracketed`] when its
/// bounds agree, else GJK on the two cuboids' support maps.
///
/// parry's dedicated `distance_cuboid_cuboid` (which `parry::query::distance`, and so
/// `Obb::distance_to_obb`, dispatches to) is not used: its separating-axis shortcut can
/// overestimate the distance by millimetres when an edge of one box is closest to an edge of
/// the other (see the test `box_distance_is_mirror_symmetric`).
#[inline]
pub(crate) fn box_box(a: &Obb, b: &Obb) -> Real {
    if let Some(d) = bracketed(a, b) {
        return d;
    }
    let (pa, ca) = a.to_parry();
    let (pb, cb) = b.to_parry();
    details::distance_support_map_support_map(&pa.inv_mul(&pb), &ca, &cb)
}

/// A box with its parry pose and shape computed once, for repeated distance queries (wall
/// pieces and openings of a prepared room, or the object of an architecture kernel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PreparedBox {
    pub obb: Obb,
    pose: Pose,
    cuboid: Cuboid,
}

impl PreparedBox {
    pub(crate) fn new(obb: &Obb) -> Self {
        let (pose, cuboid) = obb.to_parry();
        PreparedBox {
            obb: *obb,
            pose,
            cuboid,
        }
    }

    /// Exact distance to another prepared box: [`bracketed`] first, GJK when the bounds differ.
    #[inline]
    pub(crate) fn distance(&self, other: &PreparedBox) -> Real {
        bracketed(&self.obb, &other.obb).unwrap_or_else(|| {
            details::distance_support_map_support_map(
                &self.pose.inv_mul(&other.pose),
                &self.cuboid,
                &other.cuboid,
            )
        })
    }

    /// A lower bound on the distance from `other` (any solid inside that box) to this box: the
    /// gap between this box and `other`'s bounding box in this box's frame.
    #[inline]
    pub(crate) fn lower_bound(&self, other: &Obb) -> Real {
        frame_gap(&self.obb, other)
    }

    /// An upper bound on the distance from a solid containing the point `p` to this box.
    #[inline]
    pub(crate) fn upper_bound_from(&self, p: &Point3) -> Real {
        point_box_sq(&self.obb, p).sqrt()
    }
}

/// One side of a distance query as parry sees it.
enum Solid<'a> {
    Box(&'a Obb),
    Mesh(&'a Mesh, &'a Isometry3, &'a Obb),
}

impl<'a> Solid<'a> {
    fn of(o: &ObjectGeom<'a>) -> Self {
        match o.mesh {
            Some((m, pose)) => Solid::Mesh(m, pose, o.obb),
            None => Solid::Box(o.obb),
        }
    }

    /// Whether the world point lies in the solid (mesh: generalized winding number, after a
    /// cheap box test).
    fn contains(&self, p: &Point3) -> bool {
        match self {
            Solid::Box(b) => b.contains_point(p),
            Solid::Mesh(m, pose, obb) => obb.contains_point(p) && m.contains_point(pose, p),
        }
    }

    /// The solid's oriented box.
    fn bounding_box(&self) -> &Obb {
        match self {
            Solid::Box(b) => b,
            Solid::Mesh(_, _, obb) => obb,
        }
    }

    /// One point of the solid (a mesh vertex, or the box centre).
    fn some_point(&self) -> Point3 {
        match self {
            Solid::Box(b) => b.center,
            Solid::Mesh(m, pose, obb) => m.vertices().first().map_or(obb.center, |v| *pose * v),
        }
    }
}

/// Distance between two axis-aligned boxes (0 when they meet).
#[inline]
fn aabb_gap(a: &Aabb, b: &Aabb) -> Real {
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
fn triangle_aabb(t: &Triangle) -> Aabb {
    Aabb::new(t.a.min(t.b).min(t.c), t.a.max(t.b).max(t.c))
}

/// Distance from a placed mesh's surface to a convex shape given in its own frame at `pose`
/// (a cuboid or a triangle), by branch and bound over the mesh's BVH: nodes whose bounding
/// box (moved into the shape's frame) is no nearer than the best triangle so far are pruned;
/// each remaining triangle is measured exactly (GJK). No allocation.
///
/// `upper` is a known upper bound on the distance (the distance between two points of the
/// two surfaces), or infinity; it only speeds the search up.
fn mesh_convex<G: SupportMap>(
    mesh: &Mesh,
    mesh_pose: &Isometry3,
    shape: &G,
    shape_aabb: &Aabb,
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

/// An upper bound on the distance between two placed meshes' surfaces: the distance between
/// the points reached by alternating closest-point projections from `start` (a few BVH point
/// queries; often the exact distance).
fn seed_mesh_mesh(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3, start: &Point3) -> Real {
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
fn seed_mesh_box(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> Real {
    let q = mesh.closest_point(pose, &b.center);
    let q = mesh.closest_point(pose, &b.closest_point(&q));
    (q - b.closest_point(&q)).norm()
}

/// Distance between the surfaces of two placed meshes, by a two-level branch and bound: a node
/// of `a`'s BVH is bounded below by the nearest leaf box of `b` (itself found by a pruned
/// search of `b`'s BVH), and each remaining triangle of `a` searches `b` for its nearest
/// triangle, both searches pruned by the best distance so far. Exact; no allocation.
fn mesh_mesh(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3, start: &Point3) -> Real {
    let (ta, tb) = (a.parry_shape(), b.parry_shape());
    let upper = seed_mesh_mesh(a, pa, b, pb, start);
    // a's frame -> b's frame.
    let rel = to_parry_pose(pb).inv_mul(&to_parry_pose(pa));
    let root = tb.bvh().root_aabb();
    let nearest_leaf_box = |aabb: &Aabb, best: Real| -> Real {
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
fn mesh_box(mesh: &Mesh, pose: &Isometry3, b: &Obb) -> Real {
    let (pb, cb) = b.to_parry();
    let local = Aabb::new(-cb.half_extents, cb.half_extents);
    mesh_convex(mesh, pose, &cb, &local, &pb, seed_mesh_box(mesh, pose, b))
}

/// Whether every corner of `inner` lies in `outer`.
fn obb_within(inner: &Obb, outer: &Obb) -> bool {
    inner.corners().iter().all(|c| outer.contains_point(c))
}

/// Surface-level distance between two solids (0 when the surfaces touch or cross).
fn surface_distance(a: &Solid<'_>, b: &Solid<'_>) -> Real {
    match (a, b) {
        (Solid::Box(x), Solid::Box(y)) => box_box(x, y),
        (Solid::Mesh(m, p, _), Solid::Box(o)) | (Solid::Box(o), Solid::Mesh(m, p, _)) => mesh_box(m, p, o),
        (Solid::Mesh(m, p, _), Solid::Mesh(n, q, obb)) => mesh_mesh(m, p, n, q, &obb.center),
    }
}

/// Distance between two solids: 0 when they touch, overlap or one lies inside the other.
fn solid_distance(a: &Solid<'_>, b: &Solid<'_>) -> Real {
    if let (Solid::Box(x), Solid::Box(y)) = (a, b) {
        return box_box(x, y);
    }
    // One box inside the other suggests nesting: if a point of the inner object is inside the
    // outer one, the solids overlap (checking first avoids a surface search whose every
    // candidate is about equally far).
    let (ba, bb) = (a.bounding_box(), b.bounding_box());
    if (obb_within(ba, bb) && b.contains(&a.some_point()))
        || (obb_within(bb, ba) && a.contains(&b.some_point()))
    {
        return 0.0;
    }
    let d = surface_distance(a, b);
    // Surfaces apart: the solids are apart unless one is nested in the other.
    if d > 0.0 && (b.contains(&a.some_point()) || a.contains(&b.some_point())) {
        return 0.0;
    }
    d
}

/// The distance between the closest points of two objects as solids (metres): box to box
/// exactly, or through their meshes when given. 0 when they touch, overlap or nest.
///
/// # Performance
/// No allocation. Boxes: corner-to-box bounds that usually pin the distance down exactly,
/// else GJK. Meshes: branch and bound over the meshes' BVHs with exact triangle distances
/// (tens of microseconds for 5k-triangle meshes). When the surfaces are apart but one
/// object's box contains a point of the other, a winding-number test (linear in the triangle
/// count) decides whether they are nested.
pub fn object_distance(a: &ObjectGeom<'_>, b: &ObjectGeom<'_>) -> Real {
    solid_distance(&Solid::of(a), &Solid::of(b))
}

/// Cheap bounds `(lower, upper)` on [`object_distance`]: equal (and exact) for two boxes;
/// for meshes, the distance between the objects' boxes (the meshes lie inside them) and the
/// distance between two surface points found by closest-point projections.
pub(crate) fn distance_bounds(a: &ObjectGeom<'_>, b: &ObjectGeom<'_>) -> (Real, Real) {
    let lower = box_box(a.obb, b.obb);
    let upper = match (a.mesh, b.mesh) {
        (None, None) => return (lower, lower),
        (Some((m, p)), None) => seed_mesh_box(m, p, b.obb),
        (None, Some((m, p))) => seed_mesh_box(m, p, a.obb),
        (Some((m, p)), Some((n, q))) => seed_mesh_mesh(m, p, n, q, &b.obb.center),
    };
    (lower, upper.max(lower))
}

/// Distance from an object to a solid box (a wall piece or an opening).
#[inline]
pub(crate) fn object_box(a: &ObjectGeom<'_>, b: &Obb) -> Real {
    solid_distance(&Solid::of(a), &Solid::Box(b))
}

/// Distance from an object to a triangle (a piece of a ceiling), 0 when they meet.
pub(crate) fn object_triangle(a: &ObjectGeom<'_>, tri: &[Point3; 3]) -> Real {
    let t = Triangle::new(
        to_parry_point(&tri[0]),
        to_parry_point(&tri[1]),
        to_parry_point(&tri[2]),
    );
    match a.mesh {
        None => {
            let (pa, ca) = a.obb.to_parry();
            // The triangle is in world coordinates: its pose relative to the cuboid is pa^-1.
            details::distance_support_map_support_map(&pa.inverse(), &ca, &t)
        }
        Some((m, pose)) => mesh_convex(m, pose, &t, &triangle_aabb(&t), &Pose::IDENTITY, Real::INFINITY),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Vector3;
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
            sceneeval_geom::Rotation3::from_euler_angles(0.3, -0.2, 0.7),
        )
        .unwrap();
        for (i, yaw) in [0.0, 0.4, 1.1, 2.5].into_iter().enumerate() {
            let b = Obb::new(
                Point3::new(1.4, 0.5 + 0.1 * i as Real, 0.6),
                Vector3::new(0.3, 0.5, 0.4),
                sceneeval_geom::Rotation3::from_euler_angles(0.1 * i as Real, 0.5, yaw),
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
        // Found by the mirror law: parry's cuboid-cuboid shortcut gives 1.781161 for the
        // mirrored pair but 1.780385 for the original; both are 1.780385 (a 60^3 grid on the
        // second box's surface gives 1.780394).
        let r = |m: [Real; 4]| {
            sceneeval_geom::Rotation3::from_matrix_unchecked(sceneeval_geom::Matrix3::new(
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
        let m = rb * sceneeval_geom::Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0)) * rb.transpose();
        let flip = sceneeval_geom::Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0));
        let mirrored = Obb {
            center: b.center + m * (a.center - b.center),
            half_extents: a.half_extents,
            rotation: sceneeval_geom::Rotation3::from_matrix_unchecked(m * a.rotation.matrix() * flip),
        };
        let (d, dm) = (box_box(&a, &b), box_box(&mirrored, &b));
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
                let [a, b, c] = m.triangle(i).map(|p| to_parry_point(&(pose * p)));
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
            let fast = mesh_mesh(&a, &pa, &b, &pb, &Point3::new(0.5, 0.2, 0.1));
            assert!((fast - brute).abs() < 1e-9, "pose {k}: {fast} vs {brute}");
            let brute_box = ta
                .iter()
                .map(|x| details::distance_support_map_support_map(&pbx.inverse(), &cbx, x))
                .fold(Real::INFINITY, Real::min);
            let fast_box = mesh_box(&a, &pa, &bx);
            assert!(
                (fast_box - brute_box).abs() < 1e-9,
                "pose {k}: {fast_box} vs {brute_box}"
            );
        }
    }

    #[test]
    fn meshes_nest_and_separate() {
        let big = Mesh::cuboid(&Vector3::repeat(1.0)).unwrap();
        let small = Mesh::cuboid(&Vector3::repeat(0.2)).unwrap();
        let id = Isometry3::identity();
        let big_obb = Obb::from_local_aabb(big.aabb(), &id);
        let small_obb = Obb::from_local_aabb(small.aabb(), &id);
        let a = ObjectGeom::with_mesh(&big_obb, &big, &id);
        let b = ObjectGeom::with_mesh(&small_obb, &small, &id);
        // Nested: the surfaces are 0.8 apart but the solids overlap.
        assert_eq!(object_distance(&a, &b), 0.0);
        let far = Isometry3::translation(3.0, 0.0, 0.0);
        let far_obb = Obb::from_local_aabb(small.aabb(), &far);
        let c = ObjectGeom::with_mesh(&far_obb, &small, &far);
        assert!((object_distance(&a, &c) - 1.8).abs() < 1e-9);
        // Mixed box and mesh.
        let bx = cube([0.0, 2.5, 0.0], 0.5, 0.0);
        assert!((object_distance(&a, &ObjectGeom::from_box(&bx)) - 1.0).abs() < 1e-9);
        // Box nested in a mesh.
        let inner = cube([0.0, 0.0, 0.0], 0.1, 0.0);
        assert_eq!(object_distance(&ObjectGeom::from_box(&inner), &a), 0.0);
    }

    #[test]
    fn triangle_distance() {
        let a = cube([0.0, 0.0, 1.0], 0.5, 0.3);
        let tri = [
            Point3::new(-5.0, -5.0, 2.8),
            Point3::new(5.0, -5.0, 2.8),
            Point3::new(0.0, 5.0, 2.8),
        ];
        let d = object_triangle(&ObjectGeom::from_box(&a), &tri);
        assert!((d - 1.3).abs() < 1e-9, "{d}");
        let touching = cube([0.0, 0.0, 2.3], 0.5, 0.3);
        assert_eq!(object_triangle(&ObjectGeom::from_box(&touching), &tri), 0.0);
    }
}
