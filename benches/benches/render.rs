//! Criterion benchmarks of offscreen rendering (`sceneeval-render`) and of loading asset
//! appearances (`sceneeval-io`), on whatever adapter `Gpu::shared` opens (lavapipe on a
//! machine without a GPU).
//!
//! - `render/prepare_50_objects`: upload a 50-object scene of the fixture furniture (18
//!   coloured GLB assets, 2,700 triangles in all, one textured) plus floors and walls, and
//!   wait until the GPU has executed the uploads (and released the previous iteration's
//!   scene): otherwise the next benchmark's first renders would pay for thousands of them.
//! - `render/top_512_50_objects`: one 512 x 512 top view of it (render and read back).
//! - `render/front_size_surroundings_512_50_objects`: the three per-object views of every
//!   object, 150 images.
//! - `render/top_512_100k_triangles`: one 512 x 512 top view of 50 objects of 2,000 triangles
//!   (closed cylinders: the renderer culls the half of their triangles that faces away).
//! - `render/top_512_100k_triangles_open`: the same with 50 open tubes of 2,000 triangles
//!   (no caps, so nothing can be culled and their insides show).
//! - the same three renders with one sample per pixel instead of four (`..._1x`).
//! - `appearance/read_scene_geometry_only` and `appearance/read_scene_and_appearances`: read a
//!   40-object scene over 8 textured assets (1024 x 1024 PNGs) with a fresh asset library,
//!   without and with loading the assets' appearances.
//!
//! Run with `cargo bench -p sceneeval-benches --bench render -- --warm-up-time 1 --measurement-time 5`.

// A benchmark binary may stop on a set-up failure, and reports which adapter it measured.
#![allow(clippy::expect_used, clippy::print_stderr)]

mod common;

use std::hint::black_box;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};
use sceneeval_geom::{Point2, Vector3};
use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{
    AssetLibrary, GlbImage, GlbMaterial, ReadOptions, read_scene_state, write_glb, write_scene_state,
};
use sceneeval_render::{RenderSettings, Renderer, View, ViewKind};
use sceneeval_scene::{RoomBuilder, Scene};

/// A PNG of `size x size` texels of deterministic noise (so that it does not compress away).
fn noise_png(size: u32, seed: u32) -> Vec<u8> {
    let mut state = seed.wrapping_mul(2_654_435_761).wrapping_add(1);
    let img = image::RgbaImage::from_fn(size, size, |_, _| {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        let [a, b, c, _] = state.to_le_bytes();
        image::Rgba([a, b, c, 255])
    });
    let mut out = Vec::new();
    img.write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
        .expect("png");
    out
}

fn rendering(c: &mut Criterion) {
    let renderer = Renderer::new().expect("a renderer (install mesa-vulkan-drivers libvulkan1)");
    eprintln!("adapter: {:?}", renderer.gpu().adapter());
    let settings = RenderSettings::square(512);

    let fixtures =
        AssetLibrary::new().with_source("fixture", PlainFolderSource::new(common::fixture_assets()));
    let scene = common::grid_scene(&fixtures, "fixture", &common::FIXTURE_IDS);
    let prepared = renderer.prepare(&scene, &fixtures).expect("prepared");
    let ids: Vec<&str> = prepared.object_ids().collect();
    let per_object = View::standard(&[ViewKind::Front, ViewKind::Size, ViewKind::Surroundings], ids);
    assert_eq!(per_object.len(), 150);

    let dir = tempfile::tempdir().expect("temp dir");
    let heavy_ids = common::heavy_assets(dir.path(), false);
    let open_ids = common::heavy_assets(dir.path(), true);
    let heavy_lib = AssetLibrary::new().with_source("bench", PlainFolderSource::new(dir.path()));
    let grid_of = |ids: &[String]| {
        let refs: Vec<&str> = ids.iter().map(String::as_str).collect();
        renderer
            .prepare(&common::grid_scene(&heavy_lib, "bench", &refs), &heavy_lib)
            .expect("prepared")
    };
    let heavy = grid_of(&heavy_ids);
    let open = grid_of(&open_ids);

    let mut g = c.benchmark_group("render");
    g.sample_size(10);
    g.bench_function("prepare_50_objects", |b| {
        b.iter(|| {
            let prepared = renderer.prepare(black_box(&scene), &fixtures).expect("prepared");
            // Texture uploads run at the next submission; submit and wait for them.
            renderer.gpu().queue().submit([]);
            renderer
                .gpu()
                .device()
                .poll(wgpu::PollType::wait_indefinitely())
                .expect("uploads done");
            black_box(prepared)
        })
    });
    g.bench_function("top_512_50_objects", |b| {
        b.iter(|| black_box(prepared.render(&View::Top, &settings).expect("rendered")))
    });
    g.bench_function("front_size_surroundings_512_50_objects", |b| {
        b.iter(|| {
            for view in &per_object {
                black_box(prepared.render(view, &settings).expect("rendered"));
            }
        })
    });
    g.bench_function("top_512_100k_triangles", |b| {
        b.iter(|| black_box(heavy.render(&View::Top, &settings).expect("rendered")))
    });
    g.bench_function("top_512_100k_triangles_open", |b| {
        b.iter(|| black_box(open.render(&View::Top, &settings).expect("rendered")))
    });
    // The same without multisampling.
    let single = RenderSettings {
        samples: 1,
        ..settings
    };
    g.bench_function("top_512_50_objects_1x", |b| {
        b.iter(|| black_box(prepared.render(&View::Top, &single).expect("rendered")))
    });
    g.bench_function("front_size_surroundings_512_50_objects_1x", |b| {
        b.iter(|| {
            for view in &per_object {
                black_box(prepared.render(view, &single).expect("rendered"));
            }
        })
    });
    g.bench_function("top_512_100k_triangles_1x", |b| {
        b.iter(|| black_box(heavy.render(&View::Top, &single).expect("rendered")))
    });
    g.finish();
}

/// Writes 8 textured assets and a 40-object scene over them into `dir`; returns the scene.
fn textured_scene(dir: &Path) -> PathBuf {
    for k in 0..8u32 {
        let mut mesh =
            common::cylinder(&format!("t{k}"), 0.3, 0.8, 40, 11).with_material(GlbMaterial::color([1.0; 3]));
        let uvs = mesh
            .positions
            .iter()
            .map(|p| [0.5 + p[0], 1.0 - p[1] / 0.8])
            .collect();
        let material = GlbMaterial::color([1.0; 3]).with_texture(GlbImage::EmbeddedPng(noise_png(1024, k)));
        mesh = mesh.with_uvs(uvs).with_material(material);
        write_glb(&dir.join(format!("t{k}.glb")), &[mesh]).expect("asset");
    }
    let library = AssetLibrary::new().with_source("bench", PlainFolderSource::new(dir));
    let mut builder = Scene::builder().room_builder(RoomBuilder::rectangle(
        "r",
        Point2::new(0.0, 0.0),
        Point2::new(10.0, 8.0),
    ));
    for i in 0..40usize {
        let object = library
            .object(
                format!("o{i}"),
                &format!("bench.t{}", i % 8),
                common::pose(0.8 + 1.2 * (i % 8) as f64, 1.0 + 1.5 * (i / 8) as f64, 0.0),
                Vector3::repeat(1.0),
            )
            .expect("object");
        builder = builder.object(object);
    }
    let path = dir.join("scene_0.json");
    write_scene_state(&builder.build().expect("scene"), &path).expect("scene written");
    path
}

fn appearance(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = textured_scene(dir.path());
    let options = ReadOptions::default();
    let library = || AssetLibrary::new().with_source("bench", PlainFolderSource::new(dir.path()));
    let mut g = c.benchmark_group("appearance");
    g.sample_size(10);
    g.bench_function("read_scene_geometry_only", |b| {
        b.iter(|| {
            let lib = library();
            let scene = read_scene_state(&path, &lib, &options).expect("reads");
            assert_eq!(lib.appearances_loaded(), 0);
            black_box(scene)
        })
    });
    g.bench_function("read_scene_and_appearances", |b| {
        b.iter(|| {
            let lib = library();
            let scene = read_scene_state(&path, &lib, &options).expect("reads");
            for object in scene.objects() {
                if let Some(id) = object.model_id() {
                    black_box(lib.appearance(id).expect("appearance"));
                }
            }
            black_box(scene)
        })
    });
    g.finish();
}

criterion_group!(benches, rendering, appearance);
criterion_main!(benches);
