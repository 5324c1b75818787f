//! Criterion benchmarks of the spatial predicates (`sceneeval-relations`).
//!
//! Every predicate on boxes and on ~5k-triangle meshes (`Mesh::uv_ellipsoid` and
//! `Mesh::subdivided_box`), the object-architecture predicates in a four-wall room with a
//! door and a window, the scene-level evaluation by id and by index, and the batch form over
//! 1,000 pairs; and each predicate's score with its gradient (`sceneeval_relations::grad`,
//! groups ending in `_grad`) on the same configurations, to set against the score alone. The
//! configurations are fixed (a nightstand beside a bed, four chairs around a table, a bed
//! against a wall); the target straddles region boundaries so that the clipping kernels do
//! real work. Run with
//! `cargo bench -p sceneeval-benches --bench relations -- --warm-up-time 1 --measurement-time 2`.

// A benchmark binary may stop on a set-up failure.
#![allow(clippy::expect_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
#[path = "relations_configs/mod.rs"]
mod configs;

use configs::{
    MeshObject, arch_relations, bed_and_stand, bx, mesh_bed_and_stand, pair_relations, room, sofa_and_tv,
    wall_bed,
};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Mesh, Obb, Point2, Point3, Real, Side, Vector3};
use sceneeval_relations::{ObjectGeom, Query, Relation, RelationParams, SceneRelations, arch, batch, grad};
use sceneeval_scene::{Category, RoomBuilder, Scene};

fn configure<'c>(
    c: &'c mut Criterion,
    name: &str,
) -> criterion::BenchmarkGroup<'c, criterion::measurement::WallTime> {
    let mut g = c.benchmark_group(name);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(2));
    g
}

fn object_object(c: &mut Criterion) {
    let p = RelationParams::default();
    // Bed 1.6 x 2 x 0.6 m; nightstand straddling the bed's left face and its height limit.
    let (bed, stand) = bed_and_stand();
    let (a, b) = (ObjectGeom::from_box(&stand), ObjectGeom::from_box(&bed));
    let mut g = configure(c, "relations/box");
    for (name, r) in pair_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| batch::score_pair(black_box(r), black_box(&a), black_box(&b), &p))
        });
    }
    g.finish();
    let mut g = configure(c, "relations/box_grad");
    for (name, r) in pair_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| grad::pair(black_box(r), black_box(&a), black_box(&b), &p))
        });
    }
    g.finish();
    let mut g = configure(c, "relations/box");
    // Worst case for the clipper: a box turned about all three axes, cut by all six faces.
    let tilted = Obb::new(
        Point3::new(2.3, 4.4, 0.4),
        Vector3::new(0.7, 0.5, 0.4),
        sceneeval_geom::Rotation3::from_euler_angles(0.5, -0.4, 0.8),
    )
    .expect("a valid box");
    let t = ObjectGeom::from_box(&tilted);
    g.bench_function("inside_of_six_cuts", |bench| {
        bench.iter(|| sceneeval_relations::inside_of(black_box(&t), black_box(&b), &p))
    });
    g.bench_function("inside_of_six_cuts_grad", |bench| {
        bench.iter(|| grad::inside_of(black_box(&t), black_box(&b), &p))
    });
    // face_to where lines hit (the nightstand above faces away from the bed).
    let (sofa, tv, mesh_tv) = sofa_and_tv();
    let (s, tv, mtv) = (
        ObjectGeom::from_box(&sofa),
        ObjectGeom::from_box(&tv),
        mesh_tv.view(),
    );
    g.bench_function("face_to_tv", |bench| {
        bench.iter(|| sceneeval_relations::face_to(black_box(&s), black_box(&tv), &p))
    });
    g.bench_function("face_to_tv_grad", |bench| {
        bench.iter(|| grad::face_to(black_box(&s), black_box(&tv), &p))
    });
    g.bench_function("face_to_mesh_tv", |bench| {
        bench.iter(|| sceneeval_relations::face_to(black_box(&s), black_box(&mtv), &p))
    });
    g.bench_function("face_to_mesh_tv_grad", |bench| {
        bench.iter(|| grad::face_to(black_box(&s), black_box(&mtv), &p))
    });
    // surround: four chairs around a table.
    let table = bx([2.0, 2.5, 0.375], [0.6, 0.6, 0.375], 0.0);
    let chairs: Vec<Obb> = (0..4)
        .map(|k| {
            let ang = Real::from(k) * std::f64::consts::FRAC_PI_2 + 0.1;
            bx([2.0 + ang.cos(), 2.5 + ang.sin(), 0.45], [0.25, 0.25, 0.45], ang)
        })
        .collect();
    let views: Vec<ObjectGeom<'_>> = chairs.iter().map(ObjectGeom::from_box).collect();
    let anchor = ObjectGeom::from_box(&table);
    g.bench_function("surround_4", |bench| {
        bench.iter(|| sceneeval_relations::surround(black_box(&views), black_box(&anchor), &p))
    });
    let mut d = [grad::BoxGrad::ZERO; 4];
    g.bench_function("surround_4_grad", |bench| {
        bench.iter(|| grad::surround(black_box(&views), black_box(&anchor), &p, &mut d))
    });
    g.finish();
}

fn object_object_meshes(c: &mut Criterion) {
    let p = RelationParams::default();
    let (bed, stand) = mesh_bed_and_stand();
    let (a, b) = (stand.view(), bed.view());
    let mut g = configure(c, "relations/mesh_grad");
    for (name, r) in pair_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| grad::pair(black_box(r), black_box(&a), black_box(&b), &p))
        });
    }
    g.finish();
    let mut g = configure(c, "relations/mesh");
    for (name, r) in pair_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| batch::score_pair(black_box(r), black_box(&a), black_box(&b), &p))
        });
    }
    // Meshes whose surfaces cross (distance 0 by the intersection test) and nested meshes
    // (surfaces apart; the winding-number test decides).
    let crossing = MeshObject::new(
        Mesh::subdivided_box(&Vector3::new(0.25, 0.2, 0.35), 20).expect("mesh"),
        [1.3, 4.5, 0.35],
        0.3,
    );
    let nested = MeshObject::new(
        Mesh::subdivided_box(&Vector3::new(0.1, 0.1, 0.1), 20).expect("mesh"),
        [2.0, 4.0, 0.3],
        0.3,
    );
    // The same nightstand 0.79 m from the bed (the exact distance search grows with the gap).
    let apart = MeshObject::new(
        Mesh::subdivided_box(&Vector3::new(0.25, 0.2, 0.35), 20).expect("mesh"),
        [0.2, 4.5, 0.35],
        1.0,
    );
    let far_view = apart.view();
    g.bench_function("near_0.79m", |bench| {
        bench.iter(|| sceneeval_relations::near(black_box(&far_view), black_box(&b), &p))
    });
    g.bench_function("near_0.79m_grad", |bench| {
        bench.iter(|| grad::near(black_box(&far_view), black_box(&b), &p))
    });
    let (x, n) = (crossing.view(), nested.view());
    g.bench_function("next_to_crossing", |bench| {
        bench.iter(|| sceneeval_relations::next_to(black_box(&x), black_box(&b), &p))
    });
    g.bench_function("next_to_nested", |bench| {
        bench.iter(|| sceneeval_relations::next_to(black_box(&n), black_box(&b), &p))
    });
    g.finish();
}

fn object_architecture(c: &mut Criterion) {
    let p = RelationParams::default();
    let rooms = [room()];
    // A bed 5 cm from the head wall, a little turned, and a mesh version of it.
    let (bed, mesh_bed) = wall_bed();
    let a = ObjectGeom::from_box(&bed);
    let mut g = configure(c, "relations/room_box");
    for (name, r) in arch_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| arch::score_rooms(black_box(r), black_box(&a), &rooms, &p))
        });
    }
    g.finish();
    let mut g = configure(c, "relations/room_box_grad");
    for (name, r) in arch_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| grad::arch_rooms(black_box(r), black_box(&a), &rooms, &p))
        });
    }
    g.finish();
    let m = mesh_bed.view();
    let mut g = configure(c, "relations/room_mesh");
    for (name, r) in arch_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| arch::score_rooms(black_box(r), black_box(&m), &rooms, &p))
        });
    }
    g.finish();
    let mut g = configure(c, "relations/room_mesh_grad");
    for (name, r) in arch_relations() {
        g.bench_function(name, |bench| {
            bench.iter(|| grad::arch_rooms(black_box(r), black_box(&m), &rooms, &p))
        });
    }
    g.finish();
}

fn scene_level_and_batch(c: &mut Criterion) {
    let p = RelationParams::default();
    let scene = Scene::builder()
        .room_builder(RoomBuilder::rectangle(
            "r0",
            Point2::new(0.0, 0.0),
            Point2::new(4.0, 5.0),
        ))
        .add_box(
            "bed",
            Category::new("bed"),
            Vector3::new(0.8, 1.0, 0.3),
            pose_from_yaw(Point3::new(2.0, 4.0, 0.3), 0.0),
        )
        .add_box(
            "stand",
            Category::new("nightstand"),
            Vector3::new(0.25, 0.2, 0.35),
            pose_from_yaw(Point3::new(1.0, 4.5, 0.35), 0.3),
        )
        .build()
        .expect("a valid scene");
    let rel = SceneRelations::new(p).expect("valid parameters");
    let mut g = configure(c, "relations/scene");
    let side_of = Query::new(Relation::SideOf(Side::Left))
        .target("stand")
        .anchor("bed");
    g.bench_function("pair_side_of_by_id", |bench| {
        bench.iter(|| rel.evaluate(&scene, black_box(&side_of)))
    });
    let against = Query::new(Relation::AgainstWall).target("bed");
    g.bench_function("arch_against_wall_by_id", |bench| {
        bench.iter(|| rel.evaluate(&scene, black_box(&against)))
    });
    let (stand, bed) = (
        scene.object_index("stand").expect("stand"),
        scene.object_index("bed").expect("bed"),
    );
    g.bench_function("pair_side_of_by_index", |bench| {
        bench.iter(|| rel.pair(&scene, black_box(Relation::SideOf(Side::Left)), stand, bed))
    });
    g.finish();

    // 1,000 pairs of boxes from a fixed linear congruential sequence.
    let mut rng = sceneeval_test_support::Lcg(0x5EED_5EED);
    let mut next = || rng.next();
    let boxes: Vec<Obb> = (0..2000)
        .map(|_| {
            bx(
                [4.0 * next(), 5.0 * next(), 0.5 * next()],
                [0.1 + 0.5 * next(), 0.1 + 0.5 * next(), 0.1 + 0.4 * next()],
                std::f64::consts::TAU * next(),
            )
        })
        .collect();
    let views: Vec<ObjectGeom<'_>> = boxes.iter().map(ObjectGeom::from_box).collect();
    let (targets, anchors) = views.split_at(1000);
    let mut out = vec![0.0; 1000];
    let mut g = configure(c, "relations/batch");
    g.throughput(Throughput::Elements(1000));
    for (name, r) in [
        ("next_to_x1000", Relation::NextTo),
        ("side_of_x1000", Relation::SideOf(Side::Front)),
        ("inside_of_x1000", Relation::InsideOf),
    ] {
        g.bench_function(name, |bench| {
            bench.iter(|| batch::score_pairs(black_box(r), targets, anchors, &p, &mut out))
        });
    }
    let rooms = [room()];
    g.bench_function("against_wall_x1000", |bench| {
        bench.iter(|| {
            batch::score_objects_in_rooms(black_box(Relation::AgainstWall), targets, &rooms, &p, &mut out)
        })
    });
    g.finish();
}

criterion_group!(
    relations,
    object_object,
    object_object_meshes,
    object_architecture,
    scene_level_and_batch
);
criterion_main!(relations);
