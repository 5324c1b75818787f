//! Procedural GLB assets shared by the loading (`io.rs`) and rendering (`render.rs`)
//! benchmarks, included by each with `mod common;`.

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
