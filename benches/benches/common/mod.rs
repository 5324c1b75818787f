//! Procedural GLB assets shared by the loading (`io.rs`) and rendering (`render.rs`)
//! benchmarks, included by each with `mod common;`, and the rendering benchmark's grid scene,
//! which the `render-profile` example renders too.

use std::path::{Path, PathBuf};

use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Point2, Vector3};
use sceneeval_io::{AssetLibrary, GlbMaterial, GlbMesh, write_glb};
use sceneeval_scene::{RoomBuilder, Scene};

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

/// The repository's fixture assets.
#[allow(dead_code)] // Rendering only (render.rs, render-profile), not io.rs.
pub fn fixture_assets() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/assets")
}

/// An upright pose at `(x, y)` on the floor turned `yaw` radians.
#[allow(dead_code)] // Rendering only.
pub fn pose(x: f64, y: f64, yaw: f64) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::new(x, y, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw),
    )
}

/// 50 objects on a 10 x 5 grid in a 15 x 10 m room with a door and a window, cycling through
/// `ids` of `library`'s source `prefix`.
#[allow(dead_code)] // Rendering only.
pub fn grid_scene(library: &AssetLibrary, prefix: &str, ids: &[&str]) -> Scene {
    let mut builder = Scene::builder().room_builder(
        RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(15.0, 10.0))
            .door(0, [1.0, 2.0], [0.0, 2.1])
            .window(2, [4.0, 6.0], [0.9, 2.0]),
    );
    for i in 0..50usize {
        let (x, y) = (0.75 + 1.5 * (i % 10) as f64, 1.0 + 2.0 * (i / 10) as f64);
        let id = ids[i % ids.len()];
        let object = library
            .object(
                format!("o{i}"),
                &format!("{prefix}.{id}"),
                pose(x, y, 0.4 * i as f64),
                Vector3::repeat(1.0),
            )
            .expect("object");
        builder = builder.object(object);
    }
    builder.build().expect("scene")
}

/// The fixture assets the grid scene cycles through.
#[allow(dead_code)] // Rendering only.
pub const FIXTURE_IDS: [&str; 18] = [
    "bed",
    "nightstand",
    "desk",
    "chair",
    "dining_table",
    "sofa",
    "coffee_table",
    "wardrobe",
    "bookshelf",
    "table_lamp",
    "floor_lamp",
    "rug",
    "painting",
    "ceiling_lamp",
    "tv",
    "plant",
    "tv_stand",
    "storage_box",
];

/// Writes the five coloured assets of 2,000 triangles that the 100,000-triangle renders place
/// ten times each into `dir`: closed cylinders (`c0.glb` ... `c4.glb`: 2 * 40 * 24 sides and
/// 2 * 40 caps) or, with `open`, tubes without caps (`t0.glb` ... `t4.glb`: 2 * 40 * 25
/// sides). Returns their ids.
#[allow(dead_code)] // Rendering only.
pub fn heavy_assets(dir: &Path, open: bool) -> Vec<String> {
    let colours = [
        [0.6, 0.2, 0.1],
        [0.1, 0.4, 0.6],
        [0.5, 0.5, 0.1],
        [0.3, 0.3, 0.3],
        [0.7, 0.6, 0.5],
    ];
    let (prefix, bands) = if open { ("t", 25) } else { ("c", 24) };
    colours
        .iter()
        .enumerate()
        .map(|(k, rgb)| {
            let (radius, height) = (0.3 + 0.05 * k as f32, 0.6 + 0.2 * k as f32);
            let id = format!("{prefix}{k}");
            let mut mesh = cylinder(&id, radius, height, 40, bands).with_material(GlbMaterial::color(*rgb));
            if open {
                // The sides come first, then the caps.
                mesh.indices.truncate(6 * 40 * bands as usize);
            }
            #[allow(clippy::expect_used)] // A benchmark stops on a set-up failure.
            write_glb(&dir.join(format!("{id}.glb")), &[mesh]).expect("asset written");
            id
        })
        .collect()
}
