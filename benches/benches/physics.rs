//! Criterion benchmarks of the stability metric (`sceneeval-physics`).
//!
//! - `physics/decompose/<mesh>`: the convex decomposition of one mesh, no cache: the four
//!   meshes of about 8,000 triangles of `sceneeval_test_support::scenes::mesh8k_set` (a
//!   table, a cabinet, a lamp, a painting) and the fixture chair (72 triangles).
//! - `physics/simulate/<set>/<n>`: one evaluation (weld mode `architectural`, default
//!   parameters) of a scaling room of `n` = 10, 100 and 1,000 objects
//!   (`sceneeval_test_support::scenes::scaling_scene`), made of boxes (`boxes`) or of the
//!   8k-triangle meshes (`mesh8k`), with the decompositions already cached: the simulation
//!   alone (building the bodies, the interpenetration check, stepping until every body
//!   sleeps or 5 s). Support types come from the category tables, as the support metric
//!   gets them. Every room has four distinct meshes, so decomposition per room does not grow
//!   with `n`: it is the sum of the four `decompose` figures.
//!
//! Run with `cargo bench -p sceneeval-benches --bench physics`.

// A benchmark binary may stop on a set-up failure.
#![allow(clippy::expect_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use sceneeval_geom::Mesh;
use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_physics::{Decomposition, DecompositionCache, DecompositionParams, Stability, StabilityParams};
use sceneeval_plausibility::{SupportTypePriors, SupportTypeSource};
use sceneeval_scene::{Scene, SupportType};
use sceneeval_test_support::scenes::{box_set, mesh8k_set, scaling_scene};

const SIZES: [usize; 3] = [10, 100, 1000];

fn fixture_chair() -> Mesh {
    let fixtures = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures");
    let library =
        AssetLibrary::new().with_source("fixture", PlainFolderSource::new(format!("{fixtures}/assets")));
    let scene = read_scene_state(
        std::path::Path::new(&format!("{fixtures}/scenes/scene_6.json")),
        &library,
        &ReadOptions::default(),
    )
    .expect("fixture scene 6");
    let chair = scene
        .object("idx1_fixture.chair")
        .expect("the chair of fixture scene 6");
    (**chair.mesh()).clone()
}

fn decompose(c: &mut Criterion) {
    let set = mesh8k_set();
    let params = DecompositionParams::default();
    let mut group = c.benchmark_group("physics/decompose");
    group.sample_size(10).measurement_time(Duration::from_secs(10));
    let meshes = [
        (set.table.0.clone(), (*set.table.1).clone()),
        (set.cabinet.0.clone(), (*set.cabinet.1).clone()),
        (set.lamp.0.clone(), (*set.lamp.1).clone()),
        (set.painting.0.clone(), (*set.painting.1).clone()),
        ("fixture_chair".to_owned(), fixture_chair()),
    ];
    for (name, mesh) in &meshes {
        group.bench_function(name.as_str(), |b| {
            b.iter(|| black_box(Decomposition::of_mesh(black_box(mesh), &params)))
        });
    }
    group.finish();
}

fn support_types(scene: &Scene) -> Vec<Option<SupportType>> {
    let priors = SupportTypePriors::default();
    scene
        .objects()
        .iter()
        .map(|o| priors.support_type(scene, o).map(|a| a.value))
        .collect()
}

fn simulate(c: &mut Criterion) {
    let stability = Stability::new(StabilityParams::default()).expect("default parameters");
    for set in [box_set(), mesh8k_set()] {
        let mut group = c.benchmark_group(format!("physics/simulate/{}", set.kind));
        group.sample_size(10).measurement_time(Duration::from_secs(20));
        let cache = DecompositionCache::in_memory();
        for n in SIZES {
            let scene = scaling_scene(n, &set);
            let support = support_types(&scene);
            // Warm the cache: the figure is the simulation alone.
            stability
                .evaluate(&scene, &support, &cache, &sceneeval_scene::Deadline::none())
                .expect("stability");
            group.bench_with_input(BenchmarkId::from_parameter(n), &scene, |b, s| {
                b.iter(|| {
                    black_box(
                        stability
                            .evaluate(s, &support, &cache, &sceneeval_scene::Deadline::none())
                            .expect("stability"),
                    )
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, decompose, simulate);
criterion_main!(benches);
