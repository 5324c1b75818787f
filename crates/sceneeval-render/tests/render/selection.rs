//! What each view draws: the object alone, its surroundings with blockers hidden (the
//! reference's rules), the top view restricted to some objects.

use sceneeval_geom::na::Translation3;
use sceneeval_geom::{Isometry3, Point2};
use sceneeval_io::AssetLibrary;
use sceneeval_render::{RenderSettings, View};
use sceneeval_scene::{RoomBuilder, Scene};

use crate::common::*;

fn rgba(p: [u8; 4]) -> (i16, i16, i16, u8) {
    (i16::from(p[0]), i16::from(p[1]), i16::from(p[2]), p[3])
}
fn green(p: [u8; 4]) -> bool {
    let (r, g, b, a) = rgba(p);
    a == 255 && g > 80 && g > r + 40 && g > b + 40
}
fn yellow(p: [u8; 4]) -> bool {
    let (r, g, b, a) = rgba(p);
    a == 255 && r > 150 && g > 130 && b < 60
}
fn magenta(p: [u8; 4]) -> bool {
    let (r, g, b, a) = rgba(p);
    a == 255 && r > 120 && b > 120 && g < 50
}

/// A green table (1.0 x 0.75 x 0.6 m) with a yellow lamp on it and, if `screen`, a wide
/// magenta screen standing between the table and its front camera, in a 6 x 6 m room; the
/// table at `table_y` facing -y.
fn scene(dir: &std::path::Path, table_y: f64, screen: bool) -> (Scene, AssetLibrary) {
    let solid = |rgb| {
        let m = color(rgb);
        (m.clone(), m)
    };
    let (a, b) = solid([0.05, 0.5, 0.05]);
    write_asset(dir, "table", &box_asset([1.0, 0.75, 0.6], a, b));
    let (a, b) = solid([0.9, 0.8, 0.02]);
    write_asset(dir, "lamp", &box_asset([0.2, 0.4, 0.2], a, b));
    let (a, b) = solid([0.8, 0.02, 0.8]);
    write_asset(dir, "screen", &box_asset([1.6, 1.6, 0.1], a, b));
    let lib = library(dir);
    let at = |x, y, z| Isometry3::from_parts(Translation3::new(x, y, z), Default::default());
    let mut builder = Scene::builder()
        .room_builder(RoomBuilder::rectangle(
            "r",
            Point2::new(-3.0, -3.0),
            Point2::new(3.0, 3.0),
        ))
        .object(object(&lib, "table", "table", at(0.0, table_y, 0.0)))
        .object(object(&lib, "lamp", "lamp", at(0.2, table_y, 0.75)));
    if screen {
        builder = builder.object(object(&lib, "screen", "screen", at(0.0, table_y - 1.0, 0.0)));
    }
    (builder.build().unwrap(), lib)
}

#[test]
fn the_front_view_shows_the_object_alone() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = scene(dir.path(), 0.0, true);
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let img = prepared
        .render(&View::Front("table".into()), &RenderSettings::square(64))
        .unwrap();
    assert!(count(&img, green) > 500);
    assert_eq!(count(&img, yellow) + count(&img, magenta), 0);
    // Nothing but the table: every opaque pixel is green-ish (edges blend only with the
    // transparent background).
    assert_eq!(count(&img, |p| p[3] == 255 && !green(p)), 0);
}

#[test]
fn surroundings_show_what_stands_on_the_object_and_hide_blockers() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = scene(dir.path(), 0.0, true);
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let settings = RenderSettings::square(128);
    let view = View::Surroundings("table".into());
    let img = prepared.render(&view, &settings).unwrap();
    assert!(count(&img, green) > 1000, "the table is in view");
    assert!(count(&img, yellow) > 50, "the lamp on the table is in view");
    assert_eq!(count(&img, magenta), 0, "the screen in front is hidden");
    // The screen would cover the table from this camera.
    let camera = prepared.camera(&view, &settings).unwrap();
    let everything = View::Custom {
        camera,
        objects: None,
        architecture: true,
    };
    let img = prepared.render(&everything, &settings).unwrap();
    assert!(count(&img, magenta) > 1000);
    // The lamp (on the table, less than 0.2 m away, centre above) is part of the fit: the
    // camera frames the table and the lamp, not the table alone.
    let front = prepared.camera(&View::Front("table".into()), &settings).unwrap();
    assert!((camera.position - front.position).norm() > 0.1);
}

#[test]
fn surroundings_hide_a_wall_between_the_camera_and_the_object() {
    let Some(renderer) = renderer() else { return };
    // The table faces the wall at y = -3 from 0.4 m away: its front camera stands outside
    // the room, and the wall blocks all 8 rays to the table's corners.
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = scene(dir.path(), -2.4, false);
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let settings = RenderSettings::square(128);
    let view = View::Surroundings("table".into());
    let img = prepared.render(&view, &settings).unwrap();
    assert!(
        count(&img, green) > 1000,
        "the table shows through the hidden wall"
    );
    let camera = prepared.camera(&view, &settings).unwrap();
    assert!(camera.position.y < -3.0, "the camera is outside the room");
    let walls_kept = View::Custom {
        camera,
        objects: None,
        architecture: true,
    };
    let img = prepared.render(&walls_kept, &settings).unwrap();
    assert_eq!(count(&img, green), 0, "with the wall drawn the table is hidden");
}

#[test]
fn a_top_view_can_show_only_some_objects() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = scene(dir.path(), 0.0, true);
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let settings = RenderSettings::square(96);
    let all = prepared.render(&View::Top, &settings).unwrap();
    assert!(count(&all, green) > 0 && count(&all, yellow) > 0 && count(&all, magenta) > 0);
    let lamp_only = prepared
        .render(&View::TopOf(vec!["lamp".into()]), &settings)
        .unwrap();
    assert!(count(&lamp_only, yellow) > 0);
    assert_eq!(count(&lamp_only, green) + count(&lamp_only, magenta), 0);
    // The same camera: the lamp is where it is in the full view, and the floor and walls are
    // drawn (the whole frame is opaque apart from the corners).
    assert_eq!(
        centroid(&all, yellow).map(|c| c.0.round()),
        centroid(&lamp_only, yellow).map(|c| c.0.round())
    );
    assert!(count(&lamp_only, |p| p[3] == 255) > 96 * 96 * 3 / 4);
}
