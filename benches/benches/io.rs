//! Criterion benchmarks of scene loading (`sceneeval-io`).
//!
//! A generated 120-object scene (100 asset objects over 8 distinct GLB assets of about 1,000
//! triangles each, 20 at a non-unit scale; 20 box objects; two rooms with doors and windows)
//! is read with a warm asset cache (the per-scene cost in a batch run), with a cold cache (a
//! fresh `AssetLibrary`: every GLB read, converted and its BVH built), and written. Run with
//! `cargo bench -p sceneeval-benches --bench io -- --warm-up-time 1 --measurement-time 3`.

// A benchmark binary may stop on a set-up failure.
#![allow(clippy::expect_used)]

mod common;

use std::hint::black_box;
use std::path::Path;

use common::cylinder;
use criterion::{Criterion, criterion_group, criterion_main};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Isometry3, Point2, Point3, Vector3};
use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{
    AssetLibrary, ReadOptions, read_scene_state, scene_state_to_string, write_glb, write_scene_state,
};
use sceneeval_scene::Category;
use sceneeval_scene::{RoomBuilder, Scene};

/// Writes the assets and `scene_0.json` into `dir`; returns the scene's path.
fn setup(dir: &Path) -> std::path::PathBuf {
    for k in 0..8u32 {
        let mesh = cylinder(
            &format!("a{k}"),
            0.2 + 0.05 * k as f32,
            0.4 + 0.1 * k as f32,
            40,
            11,
        );
        write_glb(&dir.join(format!("a{k}.glb")), &[mesh]).expect("asset written");
        std::fs::write(
            dir.join(format!("a{k}.json")),
            format!("{{\"category\": \"thing{k}\"}}"),
        )
        .expect("sidecar");
    }
    let library = AssetLibrary::new().with_source("bench", PlainFolderSource::new(dir));
    let mut builder = Scene::builder()
        .room_builder(
            RoomBuilder::rectangle("a", Point2::new(0.0, 0.0), Point2::new(10.0, 12.0))
                .door(0, [1.0, 2.0], [0.0, 2.1])
                .window(2, [2.0, 4.0], [0.9, 2.0]),
        )
        .room_builder(
            RoomBuilder::rectangle("b", Point2::new(10.0, 0.0), Point2::new(16.0, 12.0)).door(
                3,
                [5.0, 6.0],
                [0.0, 2.1],
            ),
        );
    for i in 0..100u32 {
        let (x, y) = (0.7 + 1.4 * (i % 11) as f64, 0.7 + 1.2 * (i / 11) as f64);
        let pose = Isometry3::new(Vector3::new(x, y, 0.0), Vector3::z() * (0.3 * i as f64));
        let scale = if i % 5 == 0 {
            Vector3::new(1.1, 0.9, 1.2)
        } else {
            Vector3::repeat(1.0)
        };
        let object = library
            .object(format!("obj{i}"), &format!("bench.a{}", i % 8), pose, scale)
            .expect("asset object");
        builder = builder.object(object);
    }
    for i in 0..20u32 {
        let c = Point3::new(11.0 + 0.25 * (i % 5) as f64, 1.0 + 2.0 * (i / 5) as f64, 0.3);
        builder = builder.add_box(
            format!("box{i}"),
            Category::new("box"),
            Vector3::new(0.1, 0.15, 0.3),
            pose_from_yaw(c, 0.1 * i as f64),
        );
    }
    let scene = builder.build().expect("scene");
    let path = dir.join("scene_0.json");
    write_scene_state(&scene, &path).expect("scene written");
    path
}

fn loading(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = setup(dir.path());
    let options = ReadOptions::default();
    let library = || AssetLibrary::new().with_source("bench", PlainFolderSource::new(dir.path()));
    let warm = library();
    let scene = read_scene_state(&path, &warm, &options).expect("scene reads");

    let mut g = c.benchmark_group("io");
    g.bench_function("read_120_objects_warm_cache", |b| {
        b.iter(|| black_box(read_scene_state(black_box(&path), &warm, &options).expect("reads")))
    });
    g.bench_function("read_120_objects_cold_cache_8_assets", |b| {
        b.iter(|| {
            let fresh = library();
            black_box(read_scene_state(black_box(&path), &fresh, &options).expect("reads"))
        })
    });
    g.bench_function("write_120_objects_to_string", |b| {
        b.iter(|| black_box(scene_state_to_string(black_box(&scene)).expect("writes")))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = loading
}
criterion_main!(benches);
