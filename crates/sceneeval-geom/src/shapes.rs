//! Procedural meshes (boxes, subdivided boxes, ellipsoids) and vertex welding: the one place
//! the workspace builds such meshes, for scene objects, test assets and benchmarks alike.

use std::collections::HashMap;

use crate::{GeomError, Mesh, Point3, Vector3};

/// The 12 outward triangles of a box whose 8 corners are numbered by bits: bit 0 selects +x,
/// bit 1 +y, bit 2 +z (corner `k` is `(k & 1, k & 2, k & 4)` toward the maximum). Each face
/// is counter-clockwise seen from outside. Use it with [`cuboid_corner`] to write box meshes
/// in any number type (asset writers use `f32`).
///
/// ```
/// use sceneeval_geom::{CUBOID_TRIANGLES, cuboid_corner};
/// // The first two triangles close the -z face: all their corners have bit 2 clear.
/// assert!(CUBOID_TRIANGLES[..2].iter().flatten().all(|&k| k & 4 == 0));
/// assert_eq!(cuboid_corner(5, [0.0, 0.0, 0.0], [1.0, 2.0, 3.0]), [1.0, 0.0, 3.0]);
/// ```
pub const CUBOID_TRIANGLES: [[u32; 3]; 12] = [
    [0, 2, 1],
    [1, 2, 3], // -z
    [4, 5, 6],
    [5, 7, 6], // +z
    [0, 1, 4],
    [1, 5, 4], // -y
    [2, 6, 3],
    [3, 6, 7], // +y
    [0, 4, 2],
    [2, 4, 6], // -x
    [1, 3, 5],
    [3, 7, 5], // +x
];

/// Corner `k` (0 to 7, see [`CUBOID_TRIANGLES`]) of the axis-aligned box from `min` to `max`.
#[inline]
pub fn cuboid_corner<T: Copy>(k: u32, min: [T; 3], max: [T; 3]) -> [T; 3] {
    [
        if k & 1 == 0 { min[0] } else { max[0] },
        if k & 2 == 0 { min[1] } else { max[1] },
        if k & 4 == 0 { min[2] } else { max[2] },
    ]
}

/// For each vertex, the index of the first vertex at the bit-identical position, renumbered
/// densely from 0 in order of first appearance, and the number of distinct positions. Meshes
/// loaded from files split vertices along seams (normals, texture coordinates); welding joins
/// them again so that edges are shared.
///
/// ```
/// use sceneeval_geom::{Point3, weld_vertices};
/// let p = [Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 0.0, 0.0)];
/// assert_eq!(weld_vertices(&p), (vec![0, 1, 0], 2));
/// ```
pub fn weld_vertices(vertices: &[Point3]) -> (Vec<u32>, usize) {
    let mut ids: HashMap<[u64; 3], u32> = HashMap::with_capacity(vertices.len());
    let welded = vertices
        .iter()
        .map(|p| {
            let next = ids.len() as u32;
            *ids.entry([p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
                .or_insert(next)
        })
        .collect();
    (welded, ids.len())
}

impl Mesh {
    /// A closed box centred at the origin with the given half extents (8 vertices, 12
    /// outward triangles). Zero half extents are allowed along at most one axis (a flat box).
    ///
    /// # Errors
    /// [`GeomError::NonFinite`] or [`GeomError::NegativeExtent`] for bad half extents, and what
    /// [`Mesh::new`] rejects (a box flat along two axes has no area).
    pub fn cuboid(half_extents: &Vector3) -> Result<Self, GeomError> {
        check_half_extents(half_extents)?;
        let h = half_extents;
        let (min, max) = ([-h.x, -h.y, -h.z], [h.x, h.y, h.z]);
        let vertices = (0..8).map(|k| Point3::from(cuboid_corner(k, min, max))).collect();
        Mesh::new(vertices, CUBOID_TRIANGLES.to_vec())
    }

    /// A box with the given half extents, centred at the origin, whose six faces are each split
    /// into an `n` x `n` grid (`n` at least 1): `12 n^2` triangles (20 gives 4,800) with many
    /// coplanar neighbours. Its bounds are exactly the box.
    ///
    /// ```
    /// use sceneeval_geom::{Mesh, Vector3};
    /// let b = Mesh::subdivided_box(&Vector3::new(0.4, 0.25, 0.6), 20).unwrap();
    /// assert_eq!(b.triangles().len(), 4800);
    /// assert!(b.is_closed());
    /// assert!((b.volume().unwrap() - 0.8 * 0.5 * 1.2).abs() < 1e-9);
    /// ```
    ///
    /// # Errors
    /// As [`Mesh::cuboid`].
    pub fn subdivided_box(half_extents: &Vector3, n: u32) -> Result<Self, GeomError> {
        check_half_extents(half_extents)?;
        let n = n.max(1);
        let mut vertices = Vec::with_capacity(6 * (n as usize + 1).pow(2));
        let mut triangles = Vec::with_capacity(12 * (n as usize).pow(2));
        // For each face: normal axis k, sign, and the two in-face axes (right-handed with the
        // normal).
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
                    p[k] = sign * half_extents[k];
                    p[u] = half_extents[u] * (2.0 * f64::from(i) / f64::from(n) - 1.0);
                    p[v] = half_extents[v] * (2.0 * f64::from(j) / f64::from(n) - 1.0);
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
        Mesh::new(vertices, triangles)
    }

    /// An ellipsoid with the given half extents, centred at the origin, as a UV sphere of
    /// `segments` around (at least 3) and `rings` bands from pole to pole (at least 2):
    /// `2 * segments * (rings - 1)` triangles (50 and 51 give 5,000). The poles lie on the z
    /// axis and the first segment's vertices in the +x half of the xz plane.
    ///
    /// ```
    /// use sceneeval_geom::{Mesh, Point3, Vector3};
    /// let e = Mesh::uv_ellipsoid(&Vector3::new(1.0, 0.5, 0.3), 50, 51).unwrap();
    /// assert_eq!(e.triangles().len(), 5000);
    /// assert!(e.is_closed());
    /// assert!((e.aabb().max - Point3::new(1.0, 0.5, 0.3)).norm() < 1e-2);
    /// ```
    ///
    /// # Errors
    /// As [`Mesh::cuboid`]; zero half extents give a degenerate mesh [`Mesh::new`] may reject.
    pub fn uv_ellipsoid(half_extents: &Vector3, segments: u32, rings: u32) -> Result<Self, GeomError> {
        check_half_extents(half_extents)?;
        let (s, r) = (segments.max(3), rings.max(2));
        let mut vertices = Vec::with_capacity((s * (r - 1) + 2) as usize);
        vertices.push(Point3::new(0.0, 0.0, half_extents.z));
        for i in 1..r {
            let theta = std::f64::consts::PI * f64::from(i) / f64::from(r);
            for j in 0..s {
                let phi = std::f64::consts::TAU * f64::from(j) / f64::from(s);
                vertices.push(Point3::new(
                    half_extents.x * theta.sin() * phi.cos(),
                    half_extents.y * theta.sin() * phi.sin(),
                    half_extents.z * theta.cos(),
                ));
            }
        }
        let south = vertices.len() as u32;
        vertices.push(Point3::new(0.0, 0.0, -half_extents.z));
        let ring = |i: u32, j: u32| 1 + (i - 1) * s + j % s;
        let mut triangles = Vec::with_capacity((2 * s * (r - 1)) as usize);
        for j in 0..s {
            triangles.push([0, ring(1, j), ring(1, j + 1)]);
            triangles.push([south, ring(r - 1, j + 1), ring(r - 1, j)]);
        }
        for i in 1..r - 1 {
            for j in 0..s {
                let (a, b, c, d) = (ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1));
                triangles.push([a, c, d]);
                triangles.push([a, d, b]);
            }
        }
        Mesh::new(vertices, triangles)
    }
}

fn check_half_extents(half_extents: &Vector3) -> Result<(), GeomError> {
    if !half_extents.iter().all(|v| v.is_finite()) {
        return Err(GeomError::NonFinite {
            what: "box half extents",
        });
    }
    if half_extents.iter().any(|&v| v < 0.0) {
        return Err(GeomError::NegativeExtent((*half_extents).into()));
    }
    Ok(())
}
