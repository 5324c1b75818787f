//! Criterion benchmarks of the plausibility metrics (`sceneeval-plausibility`).
//!
//! Each metric on scenes of 5, 20, 50, 100 and 200 objects of about 5k triangles
//! (`sceneeval_test_support::scenes::scene`), on one rayon thread; all metrics together at 50 objects
//! on one and two threads; and `evaluate` on a fixture-size box scene (for the "500 scenes in
//! under a minute" target). Run with
//! `cargo bench -p sceneeval-benches --bench plausibility`.

// A benchmark binary may stop on a set-up failure.
#![allow(clippy::expect_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use sceneeval_plausibility::{
    AccessibilityParams, CollisionParams, FunctionalSidePriors, NavigabilityParams, OpeningClearanceParams,
    OutOfBoundsParams, PlausibilityParams, Sources, SupportParams, SupportTypePriors, accessibility,
    collision, evaluate, navigability, opening_clearance, out_of_bounds, support,
};
use sceneeval_scene::Scene;
use sceneeval_test_support::scenes;

const SIZES: [usize; 5] = [5, 20, 50, 100, 200];

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a rayon pool")
}

fn per_metric(c: &mut Criterion) {
    let meshes = scenes::meshes();
    let scenes: Vec<(usize, Scene)> = SIZES.iter().map(|&n| (n, scenes::scene(n, &meshes))).collect();
    let one = pool(1);
    type Metric = fn(&Scene);
    let metrics: [(&str, Metric); 6] = [
        ("collision", |s| {
            black_box(collision(s, &CollisionParams::default()).ok());
        }),
        ("support", |s| {
            black_box(support(s, &SupportParams::default(), &SupportTypePriors::default()).ok());
        }),
        ("navigability", |s| {
            black_box(navigability(s, &NavigabilityParams::default()).ok());
        }),
        ("accessibility", |s| {
            black_box(
                accessibility(
                    s,
                    &AccessibilityParams::default(),
                    &FunctionalSidePriors::default(),
                )
                .ok(),
            );
        }),
        ("out_of_bounds", |s| {
            black_box(out_of_bounds(s, &OutOfBoundsParams::default()).ok());
        }),
        ("opening_clearance", |s| {
            black_box(opening_clearance(s, &OpeningClearanceParams::default()).ok());
        }),
    ];
    for (name, metric) in metrics {
        let mut group = c.benchmark_group(format!("plausibility/{name}"));
        for (n, scene) in &scenes {
            group.bench_with_input(BenchmarkId::from_parameter(n), scene, |b, s| {
                one.install(|| b.iter(|| metric(s)));
            });
        }
        group.finish();
    }
}

fn all_metrics(c: &mut Criterion) {
    let meshes = scenes::meshes();
    let scene = scenes::scene(50, &meshes);
    let fixture = scenes::fixture_scene();
    let params = PlausibilityParams::default();
    let sources = Sources::default();
    let mut group = c.benchmark_group("plausibility/evaluate");
    for threads in [1, 2] {
        let p = pool(threads);
        group.bench_function(BenchmarkId::new("50_objects_threads", threads), |b| {
            p.install(|| b.iter(|| black_box(evaluate(&scene, &params, &sources).ok())));
        });
    }
    let p = pool(1);
    group.bench_function("fixture_scene_one_thread", |b| {
        p.install(|| b.iter(|| black_box(evaluate(&fixture, &params, &sources).ok())));
    });
    group.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(10)
}

criterion_group! {
    name = benches;
    config = config();
    targets = per_metric, all_metrics
}
criterion_main!(benches);
