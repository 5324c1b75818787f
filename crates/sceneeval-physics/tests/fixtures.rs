//! The repository's fixture rooms (`fixtures/`, furniture GLBs of 24-168 triangles) read as a
//! run reads them, with the support types their scene files state: the clean bedroom stays
//! put, and each deliberate flaw shows up as the unstable object it should.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;

use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_physics::{
    DecompositionCache, Stability, StabilityParams, StabilityReport, WeldMode, WeldReason,
};
use sceneeval_scene::{Deadline, Scene};

fn fixture(n: u32) -> Scene {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures"));
    let library = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(dir.join("assets")));
    read_scene_state(
        &dir.join(format!("scenes/scene_{n}.json")),
        &library,
        &ReadOptions::default(),
    )
    .unwrap()
}

fn evaluate(scene: &Scene, weld: WeldMode, cache: &DecompositionCache) -> StabilityReport {
    let support: Vec<_> = scene.objects().iter().map(|o| o.support_type()).collect();
    Stability::new(StabilityParams {
        weld,
        ..StabilityParams::default()
    })
    .unwrap()
    .evaluate(scene, &support, cache, &Deadline::none())
    .unwrap()
}

fn unstable(r: &StabilityReport) -> Vec<&str> {
    r.objects
        .iter()
        .filter(|o| !o.stable)
        .map(|o| o.id.as_str())
        .collect()
}

#[test]
fn the_tidy_bedroom_is_stable_and_its_furniture_starts_out_of_the_floor() {
    let cache = DecompositionCache::in_memory();
    let scene = fixture(0);
    let r = evaluate(&scene, WeldMode::Architectural, &cache);
    // The painting (wall) and the ceiling lamp are welded; the bed, nightstands, lamps on
    // them, wardrobe and rug stay.
    let welded: Vec<_> = r.objects.iter().filter_map(|o| o.weld_reason).collect();
    assert_eq!(welded, [WeldReason::Wall, WeldReason::Ceiling]);
    assert!(unstable(&r).is_empty(), "{r:?}");
    assert_eq!(r.frac_unstable, Some(0.0));
    // No piece of any furniture mesh starts in the floor or in its neighbour.
    let r = evaluate(&scene, WeldMode::Penetration, &cache);
    assert!(r.objects.iter().all(|o| o.interpenetration.is_none()), "{r:?}");
    // Without welds the painting and the ceiling lamp fall.
    assert_eq!(
        unstable(&r),
        ["idx7_fixture.painting", "idx8_fixture.ceiling_lamp"]
    );
}

#[test]
fn each_flaw_is_the_object_that_moves() {
    let cache = DecompositionCache::in_memory();
    // Scene 6: the chair floats 0.25 m above the floor and falls.
    let r = evaluate(&fixture(6), WeldMode::Architectural, &cache);
    assert_eq!(unstable(&r), ["idx1_fixture.chair"]);
    let chair = &r.objects[1];
    assert!((chair.displacement_m - 0.25).abs() < 2e-3, "{chair:?}");
    // Scene 9: the storage box inside the wardrobe is pushed out, unless welded for it.
    let scene = fixture(9);
    let r = evaluate(&scene, WeldMode::Architectural, &cache);
    assert_eq!(unstable(&r), ["idx1_fixture.storage_box"]);
    let r = evaluate(&scene, WeldMode::Combined, &cache);
    assert!(unstable(&r).is_empty(), "{r:?}");
    assert_eq!(r.objects[1].weld_reason, Some(WeldReason::Penetration));
    assert_eq!(
        r.objects[1].interpenetration.as_ref().unwrap().with,
        "idx0_fixture.wardrobe"
    );
}

#[test]
fn objects_flush_against_shared_walls_are_not_in_them() {
    // Scene 4: the TV stand of the living room stands against the wall it shares with the
    // bedroom; scene 12: two plants of the lounge against the wall it shares with the office.
    // Zero-thickness walls, which each room listed on the other's side as a 1 mm sheet: the
    // objects started 1.0 mm inside it, were welded under `penetration` and `combined`, and
    // pushed under the others.
    let cache = DecompositionCache::in_memory();
    for (n, ids) in [
        (4, &["idx8_fixture.tv_stand"][..]),
        (12, &["idx68_fixture.plant", "idx69_fixture.plant"][..]),
    ] {
        let scene = fixture(n);
        for weld in WeldMode::ALL {
            let r = evaluate(&scene, weld, &cache);
            assert!(
                r.objects.iter().all(|o| o.interpenetration.is_none()),
                "scene {n} {weld:?}: {r:?}"
            );
            for id in ids {
                let o = r.objects.iter().find(|o| o.id.as_str() == *id).unwrap();
                assert!(
                    !o.welded && o.stable && o.displacement_m < 1e-3,
                    "scene {n} {weld:?}: {o:?}"
                );
            }
        }
    }
}
