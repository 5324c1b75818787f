//! Meshes, brute-force references and a seeded sequence for the distance tests.

use crate::parry::math::Pose;
use crate::parry::query::details;
use crate::parry::shape::Triangle;
use crate::parry_adapter::point_to_parry;
use crate::{Isometry3, Mesh, Obb, Point3, Real, Vector3};

/// A small closed UV sphere (2 * 8 * 5 = 80 triangles) with the given radii.
pub(super) fn sphere(r: Vector3) -> Mesh {
    Mesh::uv_ellipsoid(&r, 8, 6).unwrap()
}

/// The triangles of a placed mesh, in the world frame, as parry's.
pub(super) fn world_triangles(m: &Mesh, pose: &Isometry3) -> Vec<Triangle> {
    (0..m.triangles().len())
        .map(|i| {
            let [a, b, c] = m.triangle(i).map(|p| point_to_parry(&(pose * p)));
            Triangle::new(a, b, c)
        })
        .collect()
}

/// An open, wavy, non-convex sheet of `2 n^2` triangles over [-0.5, 0.5]^2, plus a small
/// detached box floating above it (two components).
pub(super) fn sheet_and_box(n: u32) -> Mesh {
    let mut v = Vec::new();
    let mut t = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (
                Real::from(i) / Real::from(n) - 0.5,
                Real::from(j) / Real::from(n) - 0.5,
            );
            v.push(Point3::new(x, y, 0.08 * (9.0 * x).sin() * (7.0 * y).cos()));
        }
    }
    let at = |i: u32, j: u32| i * (n + 1) + j;
    for i in 0..n {
        for j in 0..n {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let cube = Mesh::cuboid(&Vector3::new(0.1, 0.05, 0.08)).unwrap();
    let base = v.len() as u32;
    v.extend(cube.vertices().iter().map(|p| p + Vector3::new(0.2, -0.1, 0.3)));
    t.extend(cube.triangles().iter().map(|tr| tr.map(|i| i + base)));
    Mesh::new(v, t).unwrap()
}

pub(super) fn brute_mesh_mesh(a: &[Triangle], b: &[Triangle]) -> Real {
    let id = Pose::IDENTITY;
    let mut best = Real::INFINITY;
    for x in a {
        for y in b {
            best = best.min(details::distance_support_map_support_map(&id, x, y));
        }
    }
    best
}

pub(super) fn brute_mesh_box(a: &[Triangle], b: &Obb) -> Real {
    let (pb, cb) = b.to_parry();
    a.iter()
        .map(|x| details::distance_support_map_support_map(&pb.inverse(), &cb, x))
        .fold(Real::INFINITY, Real::min)
}

/// A deterministic sequence in [0, 1).
pub(super) struct Lcg(pub(super) u64);

impl Lcg {
    pub(super) fn next(&mut self) -> Real {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as Real / (1u64 << 53) as Real
    }

    pub(super) fn pose(&mut self, centre: [Real; 3], spread: Real, tilt: Real) -> Isometry3 {
        let mut c = || (self.next() - 0.5) * 2.0;
        let t = Vector3::new(
            centre[0] + spread * c(),
            centre[1] + spread * c(),
            centre[2] + spread * c(),
        );
        let r = Vector3::new(tilt * c(), tilt * c(), 3.2 * c());
        Isometry3::new(t, r)
    }
}
