//! Alpha blending, and objects whose asset does not match their mesh.

use std::sync::Arc;

use sceneeval_geom::na::Translation3;
use sceneeval_geom::{Isometry3, Mesh, Point3, Vector3};
use sceneeval_io::GlbMaterial;
use sceneeval_render::{Camera, PreparedScene, RenderSettings, View};
use sceneeval_scene::{Scene, SceneObject};

use crate::common::*;

fn at(x: f64, y: f64, z: f64) -> Isometry3 {
    Isometry3::from_parts(Translation3::new(x, y, z), Default::default())
}

/// A 64 x 64 view of everything, without architecture, from 3 m in front of the origin
/// (looking along +y at 0.2 m height).
fn from_the_front(prepared: &PreparedScene) -> image::RgbaImage {
    let camera = Camera::looking_at(
        Point3::new(0.0, -3.0, 0.2),
        Point3::new(0.0, 0.0, 0.2),
        Vector3::z(),
    )
    .unwrap();
    let view = View::Custom {
        camera,
        objects: None,
        architecture: false,
    };
    prepared.render(&view, &RenderSettings::square(64)).unwrap()
}

#[test]
fn blended_surfaces_mix_with_what_lies_behind_them() {
    let Some(renderer) = renderer() else { return };
    // A half-transparent blue pane (alpha 0.5) in front of an opaque red box, seen head-on.
    let dir = tempfile::tempdir().unwrap();
    let red = color([0.8, 0.02, 0.02]);
    write_asset(dir.path(), "box", &box_asset([0.4, 0.4, 0.4], red.clone(), red));
    let glass = GlbMaterial {
        base_color: [0.02, 0.05, 0.9, 0.5],
        blend: true,
        texture: None,
    };
    write_asset(
        dir.path(),
        "pane",
        &box_asset([1.2, 1.2, 0.01], glass.clone(), glass),
    );
    let lib = library(dir.path());
    let scene = Scene::builder()
        .object(object(&lib, "box", "box", at(0.0, 1.0, 0.0)))
        .object(object(&lib, "pane", "pane", at(0.0, 0.0, -0.4)))
        .build()
        .unwrap();
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let img = from_the_front(&prepared);
    // Through the pane: the red box tinted blue, fully opaque.
    let centre = img.get_pixel(32, 32).0;
    assert_eq!(centre[3], 255);
    assert!(centre[0] > 80 && centre[2] > 80, "red and blue mixed: {centre:?}");
    // Above the box (row 22: 0.6 m up on the pane, 0.72 m at the box's depth) the pane is
    // alone over the transparent background. Its front and back faces each let half through:
    // alpha 1 - 0.5 * 0.5 = 0.75, i.e. 191.
    let edge = img.get_pixel(32, 22).0;
    assert!(edge[3].abs_diff(191) <= 2, "two half-transparent faces: {edge:?}");
    assert!(edge[2] > edge[0] + 60, "blue: {edge:?}");
}

#[test]
fn multisampled_edges_keep_the_surface_colour() {
    let Some(renderer) = renderer() else { return };
    // A red box seen head-on: only its front face shows. Edge pixels are partly covered; the
    // samples are averaged in linear light and premultiplied, so un-premultiplied they show
    // the face's own colour. Averaging the sRGB bytes instead would darken them: the face's
    // red byte 200, half covered, would come back as about 138.
    let dir = tempfile::tempdir().unwrap();
    let red = color([0.8, 0.02, 0.02]);
    write_asset(dir.path(), "box", &box_asset([0.4, 0.4, 0.4], red.clone(), red));
    let lib = library(dir.path());
    let scene = Scene::builder()
        .object(object(&lib, "box", "box", at(0.0, 1.0, 0.0)))
        .build()
        .unwrap();
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let img = from_the_front(&prepared);
    let inside = img.get_pixel(32, 32).0;
    assert_eq!(inside[3], 255);
    let edges: Vec<[u8; 4]> = img
        .pixels()
        .map(|p| p.0)
        .filter(|p| (60..=200).contains(&p[3]))
        .collect();
    assert!(edges.len() >= 8, "{} partly covered pixels", edges.len());
    for e in edges {
        for k in 0..3 {
            assert!(e[k].abs_diff(inside[k]) <= 6, "edge {e:?} against {inside:?}");
        }
    }
}

#[test]
fn an_object_whose_mesh_is_not_its_assets_is_drawn_in_grey() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let red = color([0.8, 0.02, 0.02]);
    write_asset(dir.path(), "box", &box_asset([0.4, 0.4, 0.4], red.clone(), red));
    let lib = library(dir.path());
    // A scene built in code: the model id says `test.box`, the mesh is a 1 m cube.
    let cube = Arc::new(Mesh::cuboid(&Vector3::repeat(0.5)).unwrap());
    let odd = SceneObject::from_mesh("odd", cube, at(0.0, 0.0, 0.5))
        .unwrap()
        .with_model_id("test.box");
    let scene = Scene::builder().object(odd).build().unwrap();
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let img = prepared
        .render(&View::Front("odd".into()), &RenderSettings::square(48))
        .unwrap();
    assert_eq!(count(&img, is_red), 0);
    assert!(
        count(&img, |p| p[3] == 255) > 48 * 48 / 2,
        "the cube itself is drawn"
    );
}
