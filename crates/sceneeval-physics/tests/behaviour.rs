//! Determinism, meshes, the decomposition cache, settling and bad input.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::sync::Arc;
use std::time::Duration;

use common::{cuboid, evaluate, room};
use sceneeval_geom::{CUBOID_TRIANGLES, Isometry3, Mesh, Point3, cuboid_corner};
use sceneeval_physics::{
    DecompositionCache, DecompositionKind, MassModel, PhysicsError, Stability, StabilityParams,
    StabilityReport, WeldMode,
};
use sceneeval_scene::{Deadline, Scene, SceneObject, SupportType};

/// A table mesh with its origin at the floor: a 1 x 0.6 x 0.04 m top at z in [0.7, 0.74] on
/// four 0.04 m square legs from z = 0 (five closed boxes).
fn table_mesh() -> Arc<Mesh> {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    let mut add = |min: [f64; 3], max: [f64; 3]| {
        let base = vertices.len() as u32;
        vertices.extend((0..8).map(|k| Point3::from(cuboid_corner(k, min, max))));
        triangles.extend(
            CUBOID_TRIANGLES
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    };
    add([-0.5, -0.3, 0.7], [0.5, 0.3, 0.74]);
    for (x, y) in [(-0.5, -0.3), (0.46, -0.3), (-0.5, 0.26), (0.46, 0.26)] {
        add([x, y, 0.0], [x + 0.04, y + 0.04, 0.7]);
    }
    Arc::new(Mesh::new(vertices, triangles).unwrap())
}

/// A room with two tables (one mesh shared), a box on one of them, a box falling from 1 m and
/// a shelf on a wall.
fn furnished() -> (Scene, Vec<Option<SupportType>>) {
    let table = table_mesh();
    let objects = vec![
        SceneObject::from_mesh("table_1", table.clone(), Isometry3::translation(1.0, 1.0, 0.0)).unwrap(),
        SceneObject::from_mesh("table_2", table, Isometry3::translation(3.0, 1.0, 0.0)).unwrap(),
        cuboid("book", [0.1, 0.15, 0.02], [1.0, 1.0, 0.76]),
        cuboid("falling", [0.2; 3], [2.0, 3.5, 1.2]),
        cuboid("shelf", [0.3, 0.1, 0.15], [2.0, 4.9, 1.5]),
    ];
    let support = vec![
        Some(SupportType::Ground),
        Some(SupportType::Ground),
        Some(SupportType::Object),
        None,
        Some(SupportType::Wall),
    ];
    (room(objects), support)
}

fn run(scene: &Scene, support: &[Option<SupportType>], params: StabilityParams) -> StabilityReport {
    Stability::new(params)
        .unwrap()
        .evaluate(
            scene,
            support,
            &DecompositionCache::in_memory(),
            &Deadline::none(),
        )
        .unwrap()
}

#[test]
fn furniture_meshes_start_out_of_the_floor_and_stay() {
    let (scene, support) = furnished();
    let r = run(
        &scene,
        &support,
        StabilityParams {
            weld: WeldMode::Penetration,
            ..StabilityParams::default()
        },
    );
    for o in &r.objects[..3] {
        // Pieces never reach below the legs: no interpenetration with the floor, no weld.
        assert!(o.interpenetration.is_none() && !o.welded, "{o:?}");
        assert!(o.stable && o.displacement_m < 2e-3, "{o:?}");
    }
    assert_eq!(r.objects[0].body.kind, DecompositionKind::Vhacd);
    assert!(r.objects[0].body.pieces >= 2);
    assert_eq!(r.objects[2].body.kind, DecompositionKind::Box);
    assert!(!r.objects[3].stable);
    // The shelf is not welded under `penetration`: it falls.
    assert!(!r.objects[4].stable);
    // 2 of 5 unstable.
    assert_eq!(r.frac_unstable, Some(0.4));
}

#[test]
fn results_are_identical_across_runs_and_thread_counts() {
    let (scene, support) = furnished();
    let json = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let r = pool.install(|| run(&scene, &support, StabilityParams::default()));
        serde_json::to_string(&r).unwrap()
    };
    let one = json(1);
    assert_eq!(one, json(1));
    assert_eq!(one, json(2));
    assert_eq!(one, json(4));
    // JSON prints every f64 in its shortest round-trip form, so equal text is equal bits.
    assert!(one.contains("\"weld_reason\":\"wall\""), "{one}");
}

#[test]
fn the_cache_decomposes_each_mesh_once_and_reuses_it_across_variants() {
    let (scene, support) = furnished();
    let dir = tempfile::tempdir().unwrap();
    let cache = DecompositionCache::on_disk(dir.path()).unwrap();
    let mut reports = Vec::new();
    for weld in WeldMode::ALL {
        let s = Stability::new(StabilityParams {
            weld,
            ..StabilityParams::default()
        })
        .unwrap();
        reports.push(s.evaluate(&scene, &support, &cache, &Deadline::none()).unwrap());
    }
    // One mesh (shared by both tables), decomposed once; the other variants hit memory.
    let stats = cache.stats();
    assert_eq!((stats.decomposed, stats.memory_hits, stats.disk_hits), (1, 3, 0));
    let files: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(files.len(), 1);
    // A second run reads the file and gives the same report bit for bit.
    let again = DecompositionCache::on_disk(dir.path()).unwrap();
    let s = Stability::new(StabilityParams::default()).unwrap();
    let r = s.evaluate(&scene, &support, &again, &Deadline::none()).unwrap();
    assert_eq!(again.stats().disk_hits, 1);
    assert_eq!(
        serde_json::to_string(&r).unwrap(),
        serde_json::to_string(&reports[0]).unwrap()
    );
}

#[test]
fn settle_returns_every_pose_at_rest() {
    let (scene, support) = furnished();
    let s = Stability::new(StabilityParams::default()).unwrap();
    let (poses, report) = s
        .settle(
            &scene,
            &support,
            &DecompositionCache::in_memory(),
            &Deadline::none(),
        )
        .unwrap();
    assert_eq!(poses.len(), scene.objects().len());
    // The falling box lands on the floor: its centre 0.2 m up.
    assert!(
        (poses[3].translation.vector.z - 0.2).abs() < 2e-3,
        "{:?}",
        poses[3]
    );
    // The welded shelf is where it was, bit for bit; the report's final poses are the same.
    assert_eq!(poses[4], *scene.objects()[4].pose());
    for (p, o) in poses.iter().zip(&report.objects) {
        assert_eq!(sceneeval_physics::Pose::from_isometry(p), o.final_pose);
    }
    // Settling a settled scene moves nothing beyond the limits.
    let mut settled = scene.clone();
    for (i, p) in poses.iter().enumerate() {
        settled.set_pose(i, *p).unwrap();
    }
    let again = s
        .evaluate(
            &settled,
            &support,
            &DecompositionCache::in_memory(),
            &Deadline::none(),
        )
        .unwrap();
    assert!(again.objects.iter().all(|o| o.stable), "{again:?}");
}

#[test]
fn mass_models_give_the_same_verdicts_on_a_resting_scene() {
    let (scene, support) = furnished();
    let density = run(&scene, &support, StabilityParams::default());
    let per_object = run(
        &scene,
        &support,
        StabilityParams {
            mass: MassModel::PerObject(1.0),
            ..StabilityParams::default()
        },
    );
    let verdicts = |r: &StabilityReport| r.objects.iter().map(|o| o.stable).collect::<Vec<_>>();
    assert_eq!(verdicts(&density), verdicts(&per_object));
}

#[test]
fn an_empty_scene_has_no_share() {
    let r = evaluate(&room(vec![]), WeldMode::Architectural, &[]);
    assert!(r.objects.is_empty());
    assert_eq!(r.frac_unstable, None);
    assert_eq!(
        r.frac_unstable_missing.as_deref(),
        Some("the scene has no objects")
    );
    assert_eq!(r.frac_stable(), None);
}

#[test]
fn an_object_outside_every_room_falls() {
    // Standing at floor height 20 m away from the room: nothing under it.
    let r = evaluate(
        &room(vec![cuboid("outside", [0.2; 3], [20.0, 2.5, 0.2])]),
        WeldMode::Architectural,
        &[],
    );
    let o = &r.objects[0];
    // 5 s of free fall: 1/2 9.81 25 = 122.6 m.
    assert!(!o.stable && (o.displacement_m - 122.6).abs() < 0.5, "{o:?}");
    assert_eq!(r.steps, 5000);
}

#[test]
fn a_flat_mesh_lies_on_the_floor_as_a_thin_box() {
    // A 2 x 1.4 m rug of one sheet, on the floor.
    let sheet = Mesh::new(
        vec![
            Point3::new(-1.0, -0.7, 0.0),
            Point3::new(1.0, -0.7, 0.0),
            Point3::new(1.0, 0.7, 0.0),
            Point3::new(-1.0, 0.7, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap();
    let rug = SceneObject::from_mesh("rug", Arc::new(sheet), Isometry3::translation(2.0, 2.5, 0.0)).unwrap();
    let r = evaluate(&room(vec![rug]), WeldMode::Penetration, &[]);
    let o = &r.objects[0];
    assert_eq!(o.body.kind, DecompositionKind::FlatBox);
    // It starts 0.5 mm into the floor (under the 1 mm weld depth) and is pushed up 0.5 mm.
    assert!(!o.welded && o.stable && o.displacement_m < 1e-3, "{o:?}");
}

#[test]
fn bad_input_is_a_clear_error() {
    let (scene, support) = furnished();
    let s = Stability::new(StabilityParams::default()).unwrap();
    let cache = DecompositionCache::in_memory();
    let err = s
        .evaluate(&scene, &support[..2], &cache, &Deadline::none())
        .unwrap_err();
    assert!(
        matches!(err, PhysicsError::SupportTypeCount { objects: 5, given: 2 }),
        "{err}"
    );

    let no_rooms = Scene::builder()
        .name("bare")
        .object(cuboid("box", [0.2; 3], [0.0, 0.0, 0.2]))
        .build()
        .unwrap();
    let err = s
        .evaluate(&no_rooms, &[None], &cache, &Deadline::none())
        .unwrap_err();
    assert!(matches!(err, PhysicsError::NoFloor { .. }), "{err}");
    assert!(err.to_string().contains("bare"), "{err}");

    let err = Stability::new(StabilityParams {
        duration_s: -1.0,
        ..StabilityParams::default()
    })
    .unwrap_err();
    assert!(err.to_string().contains("duration_s"), "{err}");
}

#[test]
fn a_zero_time_budget_fails_the_scene_naming_the_stage() {
    let (scene, support) = furnished();
    let s = Stability::new(StabilityParams::default()).unwrap();
    let zero = Deadline::after(Duration::ZERO);
    for result in [
        s.evaluate(&scene, &support, &DecompositionCache::in_memory(), &zero)
            .map(|_| ()),
        s.settle(&scene, &support, &DecompositionCache::in_memory(), &zero)
            .map(|_| ()),
    ] {
        let err = result.unwrap_err();
        assert!(
            matches!(err, PhysicsError::DeadlineExceeded { stage: "decomposition", budget_seconds: Some(b) } if b == 0.0),
            "{err}"
        );
        assert_eq!(
            err.to_string(),
            "stability stopped during decomposition: time budget exceeded (the scene's 0 s are used up)"
        );
    }
    // A scene of boxes only decomposes no mesh: the budget is checked all the same.
    let boxes = room(vec![cuboid("box", [0.2; 3], [2.0, 2.5, 0.2])]);
    let err = s
        .evaluate(&boxes, &[None], &DecompositionCache::in_memory(), &zero)
        .unwrap_err();
    assert!(
        matches!(
            err,
            PhysicsError::DeadlineExceeded {
                stage: "decomposition",
                ..
            }
        ),
        "{err}"
    );
    // A cancelled run says so.
    let cancelled = Deadline::none();
    cancelled.cancel();
    let err = s
        .evaluate(&scene, &support, &DecompositionCache::in_memory(), &cancelled)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "stability stopped during decomposition: the run was cancelled"
    );
}
