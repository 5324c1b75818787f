//! Helpers shared by the integration tests: small procedural assets written with the crate's
//! own GLB writer.

#![allow(dead_code, clippy::unwrap_used)]

use std::path::Path;

use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, GlbMesh, write_glb};

/// The 8 corners and 12 outward triangles of the box `[min, max]`, appended to a mesh.
pub use sceneeval_test_support::push_cuboid as push_box;

/// A box mesh `[min, max]`.
pub fn box_mesh(name: &str, min: [f32; 3], max: [f32; 3]) -> GlbMesh {
    let (mut p, mut i) = (Vec::new(), Vec::new());
    push_box(&mut p, &mut i, min, max);
    GlbMesh::new(name, p, i)
}

/// The "front bump" asset, in asset coordinates (y up, front +z): a body x in [-0.5, 0.5],
/// y in [0, 0.5], z in [-0.2, 0.2], and a bump on its front face, x in [-0.1, 0.1],
/// y in [0.1, 0.3], z in [0.2, 0.3]. In the object frame (x, y, z) -> (x, -z, y): body
/// y in [-0.2, 0.2], bump y in [-0.3, -0.2] (the front, -y), z in [0, 0.5].
pub fn write_bump_asset(dir: &Path, id: &str) {
    let body = box_mesh("body", [-0.5, 0.0, -0.2], [0.5, 0.5, 0.2]);
    let bump = box_mesh("bump", [-0.1, 0.1, 0.2], [0.1, 0.3, 0.3]);
    write_glb(&dir.join(format!("{id}.glb")), &[body, bump]).unwrap();
}

/// Writes a plain-folder asset `id` (a box `[min, max]` in asset coordinates) with a sidecar.
pub fn write_box_asset(
    dir: &Path,
    id: &str,
    min: [f32; 3],
    max: [f32; 3],
    category: &str,
    description: &str,
) {
    write_glb(&dir.join(format!("{id}.glb")), &[box_mesh(id, min, max)]).unwrap();
    std::fs::write(
        dir.join(format!("{id}.json")),
        serde_json::json!({"category": category, "description": description}).to_string(),
    )
    .unwrap();
}

/// A library with a plain-folder source `fixture` rooted at `dir`.
pub fn fixture_library(dir: &Path) -> AssetLibrary {
    AssetLibrary::new().with_source("fixture", PlainFolderSource::new(dir))
}
