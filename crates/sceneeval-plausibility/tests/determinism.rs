//! Reports are identical across runs and rayon thread counts.

// Test helpers outside #[test] functions may unwrap too.
#![allow(clippy::unwrap_used)]

mod common;

use common::{at, check_invariants, scene, sphere};
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Point3, Vector3};
use sceneeval_plausibility::{Deadline, PlausibilityParams, PlausibilityReport, Sources, evaluate};
use sceneeval_scene::Category;
use sceneeval_scene::Scene;

fn busy_scene() -> Scene {
    let ball = sphere(0.25, 16);
    let mut b = scene();
    // A grid of balls and boxes, some overlapping, some floating, some resting.
    for k in 0..12 {
        let (x, y) = (0.5 + 0.6 * (k % 6) as f64, 1.0 + 1.2 * (k / 6) as f64);
        b = b.add_mesh(
            format!("ball{k}"),
            Category::new("ball"),
            ball.clone(),
            at(x, y, 0.25 + 0.01 * k as f64, 0.1 * k as f64),
        );
        b = b.add_box(
            format!("box{k}"),
            Category::new(if k % 2 == 0 { "table" } else { "chair" }),
            Vector3::new(0.2, 0.25, 0.3),
            pose_from_yaw(Point3::new(x + 0.2, y + 0.5, 0.3), 0.3 * k as f64),
        );
    }
    b.build().unwrap()
}

fn run(threads: usize, scene: &Scene) -> PlausibilityReport {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| evaluate(scene, &PlausibilityParams::default(), &Sources::default()).unwrap())
}

#[test]
fn identical_for_one_and_two_threads_and_across_runs() {
    let s = busy_scene();
    let one = run(1, &s);
    check_invariants(&one);
    assert_eq!(
        one.summary.col_sc,
        Some(true),
        "the scene is meant to have collisions"
    );
    let json = serde_json::to_string(&one).unwrap();
    for threads in [2, 1, 2] {
        let again = run(threads, &s);
        assert_eq!(again, one, "{threads} threads");
        assert_eq!(serde_json::to_string(&again).unwrap(), json);
    }
}

#[cfg(feature = "images")]
#[test]
fn diagnostic_images_are_deterministic() {
    let s = scene()
        .add_box(
            "wardrobe",
            Category::new("wardrobe"),
            Vector3::new(0.5, 0.3, 1.0),
            pose_from_yaw(Point3::new(1.45, 0.31, 1.0), 0.0),
        )
        .add_box(
            "bed",
            Category::new("bed"),
            Vector3::new(0.8, 1.0, 0.3),
            pose_from_yaw(Point3::new(3.2, 4.0, 0.3), 0.0),
        )
        .build()
        .unwrap();
    let params = PlausibilityParams::default();
    let a = tempfile::tempdir().unwrap();
    let b = tempfile::tempdir().unwrap();
    let files_a = sceneeval_plausibility::write_diagnostics(
        &s,
        &params,
        &Sources::default(),
        a.path(),
        &Deadline::none(),
    )
    .unwrap();
    let files_b = run_in_pool(2, || {
        sceneeval_plausibility::write_diagnostics(
            &s,
            &params,
            &Sources::default(),
            b.path(),
            &Deadline::none(),
        )
        .unwrap()
    });
    let names: Vec<String> = files_a
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        vec![
            "navigability.png",
            "accessibility.png",
            "opening_r0_wall_0_door_0_room.png"
        ]
    );
    for (fa, fb) in files_a.iter().zip(&files_b) {
        let (x, y) = (std::fs::read(fa).unwrap(), std::fs::read(fb).unwrap());
        assert!(x.starts_with(b"\x89PNG"));
        assert_eq!(x, y);
    }
}

#[cfg(feature = "images")]
fn run_in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[cfg(feature = "images")]
#[test]
fn two_writers_of_one_diagnostics_folder_never_fail_and_leave_whole_images() {
    // Two scenes (a wardrobe in front of the door, or a bed in the corner) written into one
    // folder 10 times each at once: every write succeeds and each image is one scene's whole
    // image (images are written through unique temporary names and renamed).
    let scene_with = |id: &str, x: f64, y: f64| {
        scene()
            .add_box(
                id,
                Category::new(id),
                Vector3::new(0.5, 0.3, 1.0),
                pose_from_yaw(Point3::new(x, y, 1.0), 0.0),
            )
            .build()
            .unwrap()
    };
    let scenes = [scene_with("wardrobe", 1.45, 0.31), scene_with("bed", 3.2, 4.0)];
    let params = PlausibilityParams::default();
    let alone: Vec<Vec<u8>> = scenes
        .iter()
        .map(|s| {
            let dir = tempfile::tempdir().unwrap();
            sceneeval_plausibility::write_diagnostics(
                s,
                &params,
                &Sources::default(),
                dir.path(),
                &Deadline::none(),
            )
            .unwrap();
            std::fs::read(dir.path().join("navigability.png")).unwrap()
        })
        .collect();
    assert_ne!(alone[0], alone[1]);
    let shared = tempfile::tempdir().unwrap();
    std::thread::scope(|t| {
        for s in &scenes {
            let (params, dir) = (&params, shared.path());
            t.spawn(move || {
                for _ in 0..10 {
                    sceneeval_plausibility::write_diagnostics(
                        s,
                        params,
                        &Sources::default(),
                        dir,
                        &Deadline::none(),
                    )
                    .unwrap();
                }
            });
        }
    });
    let written = std::fs::read(shared.path().join("navigability.png")).unwrap();
    assert!(written == alone[0] || written == alone[1]);
    let names = sceneeval_test_support::file_names(shared.path());
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
}
