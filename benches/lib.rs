//! Shared set-up for the benchmarks under `benches/benches/`.

pub mod scenes;

pub mod assets {
    //! Procedural GLB assets for the loading and rendering benchmarks.

    use sceneeval_io::GlbMesh;

    /// A closed cylinder (asset frame: y up, origin at the bottom centre) of `segments` sides
    /// and `bands` height bands: `2 * segments * bands + 2 * segments` triangles.
    pub fn cylinder(name: &str, radius: f32, height: f32, segments: u32, bands: u32) -> GlbMesh {
        let mut positions = Vec::new();
        for b in 0..=bands {
            let y = height * b as f32 / bands as f32;
            for s in 0..segments {
                let a = std::f32::consts::TAU * s as f32 / segments as f32;
                positions.push([radius * a.cos(), y, radius * a.sin()]);
            }
        }
        let bottom = positions.len() as u32;
        positions.push([0.0, 0.0, 0.0]);
        positions.push([0.0, height, 0.0]);
        let mut indices = Vec::new();
        let at = |b: u32, s: u32| b * segments + s % segments;
        for b in 0..bands {
            for s in 0..segments {
                indices.extend([at(b, s), at(b + 1, s), at(b, s + 1)]);
                indices.extend([at(b, s + 1), at(b + 1, s), at(b + 1, s + 1)]);
            }
        }
        for s in 0..segments {
            indices.extend([bottom, at(0, s), at(0, s + 1)]);
            indices.extend([bottom + 1, at(bands, s + 1), at(bands, s)]);
        }
        GlbMesh::new(name, positions, indices)
    }
}

pub mod meshes {
    //! Procedural meshes of about 5,000 triangles for the predicate benchmarks
    //! (`benches/benches/relations.rs`): closed, outward, centred at the origin of their frame.

    use sceneeval_geom::{GeomError, Mesh, Point3, Vector3};

    /// An ellipsoid with the given half extents as a UV sphere of `segments` around and `rings`
    /// bands from pole to pole: `2 * segments * (rings - 1)` triangles (50 and 51 give 5,000).
    ///
    /// # Errors
    /// [`GeomError`] for non-finite or zero half extents, or fewer than 3 segments or 2 rings.
    pub fn uv_ellipsoid(half_extents: &Vector3, segments: u32, rings: u32) -> Result<Mesh, GeomError> {
        let (s, r) = (segments.max(3), rings.max(2));
        let mut vertices = vec![Point3::new(0.0, 0.0, half_extents.z)];
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

    /// A box with the given half extents whose faces are each split into an `n` x `n` grid:
    /// `12 n^2` triangles (20 gives 4,800). Its bounds are exactly the box.
    ///
    /// # Errors
    /// [`GeomError`] for non-finite or zero half extents.
    pub fn subdivided_box(half_extents: &Vector3, n: u32) -> Result<Mesh, GeomError> {
        let n = n.max(1);
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        // For each face: normal axis k, sign, and the two in-face axes (right-handed with the normal).
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

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn meshes_have_the_advertised_size_and_are_closed() {
            let e = uv_ellipsoid(&Vector3::new(1.0, 0.5, 0.3), 50, 51).unwrap();
            assert_eq!(e.triangles().len(), 5000);
            assert!(e.is_closed());
            assert!((e.aabb().max - Point3::new(1.0, 0.5, 0.3)).norm() < 1e-2);
            let b = subdivided_box(&Vector3::new(0.4, 0.25, 0.6), 20).unwrap();
            assert_eq!(b.triangles().len(), 4800);
            assert!(b.is_closed());
            assert!((b.volume().unwrap() - 0.8 * 0.5 * 1.2).abs() < 1e-9);
        }
    }
}
