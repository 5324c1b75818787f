//! Fixture scenes rendered at 128 x 128 and compared with the PNGs under `tests/reference/`
//! (per-pixel tolerance; a diff image is written on failure; `SCENEEVAL_BLESS=1` re-blesses).

use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_render::{PreparedScene, RenderSettings, View};

use crate::common::*;

/// Fixture scene `n` prepared for rendering; `None` (skipped) without a graphics driver.
fn fixture(n: u32) -> Option<(PreparedScene, AssetLibrary)> {
    let renderer = renderer()?;
    let assets =
        AssetLibrary::new().with_source("fixture", PlainFolderSource::new(fixtures().join("assets")));
    let path = fixtures().join(format!("scenes/scene_{n}.json"));
    let scene = read_scene_state(&path, &assets, &ReadOptions::default()).unwrap();
    let prepared = renderer.prepare(&scene, &assets).unwrap();
    Some((prepared, assets))
}

fn check(prepared: &PreparedScene, view: View, name: &str) {
    let image = prepared.render(&view, &RenderSettings::square(128)).unwrap();
    assert_matches_reference(name, &image);
}

#[test]
fn bedroom_views_match_their_references() {
    let Some((scene, assets)) = fixture(0) else { return };
    check(&scene, View::Top, "scene_0_top");
    check(
        &scene,
        View::Front("idx0_fixture.bed".into()),
        "scene_0_front_bed",
    );
    check(
        &scene,
        View::Surroundings("idx3_fixture.table_lamp".into()),
        "scene_0_surroundings_table_lamp",
    );
    check(
        &scene,
        View::Front("idx7_fixture.painting".into()),
        "scene_0_front_painting",
    );
    assert!(assets.appearances_loaded() > 0);
}

#[test]
fn living_room_and_office_views_match_their_references() {
    let Some((living, _)) = fixture(1) else { return };
    check(
        &living,
        View::Size("idx0_fixture.sofa".into()),
        "scene_1_size_sofa",
    );
    check(&living, View::Top, "scene_1_top");
    let Some((office, _)) = fixture(3) else { return };
    check(&office, View::Top, "scene_3_top");
    let Some((boxes, _)) = fixture(11) else { return };
    check(&boxes, View::Front("idx0_box".into()), "scene_11_front_box");
}
