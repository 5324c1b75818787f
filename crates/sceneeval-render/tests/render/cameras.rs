//! Tests that would catch a wrong camera, a wrong figure, a wrong texture path or a wrong
//! readback: each checks a property a person could verify on the image.

use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Point2, Point3, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_render::{Camera, HUMAN_HEIGHT_M, RenderError, RenderSettings, View};
use sceneeval_scene::{RoomBuilder, Scene};

use crate::common::*;

fn pose(x: f64, y: f64, z: f64, yaw_deg: f64) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw_deg.to_radians()),
    )
}

/// A 0.8 x 0.5 x 0.6 m box (width, height, depth) whose front face alone is red, turned by
/// `yaw_deg`, standing in a room.
fn red_front_scene(dir: &std::path::Path, yaw_deg: f64) -> (Scene, AssetLibrary) {
    write_asset(
        dir,
        "cabinet",
        &box_asset([0.8, 0.5, 0.6], color([0.8, 0.02, 0.02]), color([0.5, 0.5, 0.5])),
    );
    let lib = library(dir);
    let scene = Scene::builder()
        .room_builder(RoomBuilder::rectangle(
            "r",
            Point2::new(-3.0, -3.0),
            Point2::new(3.0, 3.0),
        ))
        .object(object(&lib, "cabinet", "cabinet", pose(0.5, -0.4, 0.0, yaw_deg)))
        .build()
        .unwrap();
    (scene, lib)
}

#[test]
fn the_front_colour_shows_from_the_front_and_not_from_behind() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    for yaw in [0.0, 35.0, -120.0] {
        let (scene, lib) = red_front_scene(dir.path(), yaw);
        let prepared = renderer.prepare(&scene, &lib).unwrap();
        let settings = RenderSettings::square(96);
        let front = prepared
            .render(&View::Front("cabinet".into()), &settings)
            .unwrap();
        let red = count(&front, is_red);
        // The front face fills most of the frame's lower part (the top face shows above it).
        assert!(
            red > 96 * 96 / 4,
            "yaw {yaw}: only {red} red pixels in the front view"
        );

        // From behind: a camera 3 m behind the box (its local +y), 1 m up, looking at it.
        let obj = scene.object("cabinet").unwrap();
        let centre = obj.obb().center;
        let back = obj.pose().rotation * Vector3::y();
        let camera = Camera::looking_at(centre + back * 3.0 + Vector3::z(), centre, Vector3::z()).unwrap();
        let behind = View::Custom {
            camera,
            objects: None,
            architecture: false,
        };
        let image = prepared.render(&behind, &settings).unwrap();
        assert!(
            count(&image, |p| p[3] == 255) > 200,
            "yaw {yaw}: the box is in view"
        );
        assert_eq!(count(&image, is_red), 0, "yaw {yaw}: red seen from behind");
    }
}

#[test]
fn the_human_figure_measures_170_cm_against_an_object_of_known_height() {
    let Some(renderer) = renderer() else { return };
    // A thin blue panel 1.6 m tall (0.05 m deep, so its top face adds almost nothing at 10
    // degrees: 0.05 * sin 10 deg = 9 mm) beside the figure, both at the same depth. With the
    // camera tilted 10 degrees down, image height is not quite proportional to height: for
    // the camera about 2 m away at mid-height, a point at height z appears at
    // tan(atan((z - 1.1) / 2) + 10 deg), i.e. 0 m -> -0.340, 1.6 m -> 0.446, 1.7 m -> 0.503,
    // so the figure measures 1.6 * 0.843 / 0.786 = 1.716 m (+0.9 %). (Against a 0.9 m object
    // the same tilt makes it look about 8 % taller, as in the reference.)
    let dir = tempfile::tempdir().unwrap();
    write_asset(
        dir.path(),
        "panel",
        &box_asset(
            [0.6, 1.6, 0.05],
            color([0.02, 0.05, 0.8]),
            color([0.02, 0.05, 0.8]),
        ),
    );
    let lib = library(dir.path());
    for yaw in [0.0, 90.0, 200.0] {
        let scene = Scene::builder()
            .object(object(&lib, "panel", "panel", pose(1.0, 2.0, 0.3, yaw)))
            .build()
            .unwrap();
        let prepared = renderer.prepare(&scene, &lib).unwrap();
        let img = prepared
            .render(&View::Size("panel".into()), &RenderSettings::square(512))
            .unwrap();
        let blue = |p: [u8; 4]| p[3] == 255 && p[2] > 100 && u16::from(p[0]) * 3 < u16::from(p[2]);
        let (b0, b1) = row_span(&img, blue).expect("the panel is visible");
        let (h0, h1) = row_span(&img, is_grey).expect("the figure is visible");
        // The figure stands level with the panel's bottom, but its toes reach 16.5 cm towards
        // the camera and so appear lower: measure it from the top of its head down to the
        // panel's bottom row.
        let panel_px = f64::from(b1 - b0 + 1);
        let figure_px = f64::from(b1 - h0 + 1);
        let measured = figure_px / panel_px * 1.6;
        assert!(
            (measured / HUMAN_HEIGHT_M - 1.0).abs() < 0.03,
            "yaw {yaw}: the figure measures {measured:.3} m against the 1.6 m panel"
        );
        // Feet level with the panel's bottom (toes within 4 % of the image), figure on the left.
        assert!(
            h1 >= b1 && h1 - b1 <= 20,
            "yaw {yaw}: feet at row {h1}, panel bottom at {b1}"
        );
        let (fx, _) = centroid(&img, is_grey).unwrap();
        let (bx, _) = centroid(&img, blue).unwrap();
        assert!(fx < bx, "yaw {yaw}: the figure stands left of the panel");
    }
}

/// A scene without architecture: a grey 4 x 4 x 0.01 m slab with its corner at the origin
/// and a red 0.4 x 0.4 x 0.02 m tile centred at (1, 3) on it.
fn slab_scene(dir: &std::path::Path) -> (Scene, AssetLibrary) {
    let grey = color([0.5, 0.5, 0.5]);
    write_asset(dir, "slab", &box_asset([4.0, 0.01, 4.0], grey.clone(), grey));
    let red = color([0.8, 0.02, 0.02]);
    write_asset(dir, "tile", &box_asset([0.4, 0.02, 0.4], red.clone(), red));
    let lib = library(dir);
    let scene = Scene::builder()
        .object(object(&lib, "slab", "slab", pose(2.0, 2.0, 0.0, 0.0)))
        .object(object(&lib, "tile", "tile", pose(1.0, 3.0, 0.01, 0.0)))
        .build()
        .unwrap();
    (scene, lib)
}

#[test]
fn the_top_view_maps_pixels_to_the_floor_at_any_width() {
    let Some(renderer) = renderer() else { return };
    // Straight down, fitted to the slab: its top corners (z = 0.01) touch the left and right
    // edges, so the camera is at x = y = 2 and z = 0.01 + 2 / t with t = tan(half fov) =
    // 18 / 35. The tile's top (z = 0.03) at (1, 3) is 1 m left of and 1 m above the centre at
    // depth 2 / t - 0.02, so it appears at a fraction 0.5 - 0.5 / ((2 / t - 0.02) t) =
    // 0.5 - 0.5 / (2 - 0.02 t) = 0.24871 of the width from the left and of the height from
    // the top. Widths 101 and 130 are not multiples of 64: rows are padded on readback.
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = slab_scene(dir.path());
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let t: f64 = 18.0 / 35.0;
    let fraction = 0.5 - 0.5 / (2.0 - 0.02 * t);
    assert!((fraction - 0.24871).abs() < 1e-5);
    for size in [101u32, 130, 256] {
        let img = prepared
            .render(&View::Top, &RenderSettings::square(size))
            .unwrap();
        assert_eq!(img.dimensions(), (size, size));
        let (cx, cy) = centroid(&img, is_red).expect("the tile is visible");
        // Pixel indices: the pixel centre of index i is at i + 0.5.
        let expected = fraction * f64::from(size) - 0.5;
        assert!(
            (cx - expected).abs() < 0.75,
            "size {size}: tile at x {cx}, expected {expected}"
        );
        assert!(
            (cy - expected).abs() < 0.75,
            "size {size}: tile at y {cy}, expected {expected}"
        );
        // The slab spans the full width of the middle row, edge to edge.
        let mid = size / 2;
        assert_eq!(img.get_pixel(0, mid).0[3], 255, "size {size}");
        assert_eq!(img.get_pixel(size - 1, mid).0[3], 255, "size {size}");
        // And the camera agrees with the image.
        let cam = prepared
            .camera(&View::Top, &RenderSettings::square(size))
            .unwrap();
        let p = cam.project(&Point3::new(1.0, 3.0, 0.03), size, size).unwrap();
        // (To f32 rounding of the asset's vertices.)
        assert!((p.x - fraction * f64::from(size)).abs() < 1e-4);
    }
}

#[test]
fn non_square_and_odd_sizes_read_back_row_by_row() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = slab_scene(dir.path());
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    for (w, h) in [(1u32, 1u32), (65, 33), (97, 130), (300, 77)] {
        let settings = RenderSettings {
            width: w,
            height: h,
            ..RenderSettings::default()
        };
        let img = prepared.render(&View::Top, &settings).unwrap();
        assert_eq!(img.dimensions(), (w, h));
        if w < 8 {
            continue;
        }
        // A wrong row stride would shear the image: the tile must sit where the camera puts
        // it in every row it covers.
        let cam = prepared.camera(&View::Top, &settings).unwrap();
        let p = cam.project(&Point3::new(1.0, 3.0, 0.03), w, h).unwrap();
        let (cx, cy) = centroid(&img, is_red).expect("the tile is visible");
        assert!(
            (cx + 0.5 - p.x).abs() < 0.75 && (cy + 0.5 - p.y).abs() < 0.75,
            "{w}x{h}: {cx},{cy} vs {p}"
        );
    }
}

#[test]
fn textures_show_their_colour_and_missing_ones_fall_back() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let green = solid_png(4, 4, [40, 190, 60, 255]);
    write_asset(
        dir.path(),
        "crate",
        &box_asset([0.5, 0.5, 0.5], textured(green.clone()), textured(green)),
    );
    let missing = color([0.05, 0.1, 0.8]).with_texture(sceneeval_io::GlbImage::Uri("gone.png".into()));
    write_asset(
        dir.path(),
        "ghost",
        &box_asset([0.5, 0.5, 0.5], missing.clone(), missing),
    );
    let lib = library(dir.path());
    let scene = Scene::builder()
        .object(object(&lib, "crate", "crate", pose(0.0, 0.0, 0.0, 0.0)))
        .object(object(&lib, "ghost", "ghost", pose(2.0, 0.0, 0.0, 0.0)))
        .build()
        .unwrap();
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let settings = RenderSettings::square(64);
    let img = prepared.render(&View::Front("crate".into()), &settings).unwrap();
    let greenish = |p: [u8; 4]| p[3] == 255 && p[1] > 100 && p[1] > p[0] + 60 && p[1] > p[2] + 60;
    let opaque = count(&img, |p| p[3] == 255);
    assert!(
        count(&img, greenish) * 10 > opaque * 9,
        "the texture's green covers the crate"
    );
    let img = prepared.render(&View::Front("ghost".into()), &settings).unwrap();
    let blueish = |p: [u8; 4]| p[3] == 255 && p[2] > 100 && p[2] > p[0] + 60 && p[2] > p[1] + 60;
    let opaque = count(&img, |p| p[3] == 255);
    assert!(
        count(&img, blueish) * 10 > opaque * 9,
        "a missing texture shows the base colour"
    );
}

#[test]
fn one_sample_per_pixel_gives_hard_edges_in_the_same_places() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = red_front_scene(dir.path(), 25.0);
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let view = View::Front("cabinet".into());
    let smooth = prepared.render(&view, &RenderSettings::square(64)).unwrap();
    let hard = RenderSettings {
        samples: 1,
        ..RenderSettings::square(64)
    };
    let aliased = prepared.render(&view, &hard).unwrap();
    // Multisampling blends edges with the background; one sample never does.
    assert!(count(&smooth, |p| p[3] > 0 && p[3] < 255) > 20);
    assert_eq!(count(&aliased, |p| p[3] > 0 && p[3] < 255), 0);
    // The same shape: coverage differs only along edges.
    let covered = |img: &image::RgbaImage| count(img, |p| p[3] >= 128) as i64;
    assert!(
        (covered(&smooth) - covered(&aliased)).abs() < 64,
        "{} vs {}",
        covered(&smooth),
        covered(&aliased)
    );
}

#[test]
fn views_are_byte_identical_on_repeat() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = red_front_scene(dir.path(), 20.0);
    let settings = RenderSettings::square(80);
    let first = renderer.prepare(&scene, &lib).unwrap();
    let second = renderer.prepare(&scene, &lib).unwrap();
    for view in [
        View::Front("cabinet".into()),
        View::Size("cabinet".into()),
        View::Surroundings("cabinet".into()),
        View::Top,
    ] {
        let a = first.render(&view, &settings).unwrap();
        let b = first.render(&view, &settings).unwrap();
        let c = second.render(&view, &settings).unwrap();
        assert!(a.as_raw() == b.as_raw() && a.as_raw() == c.as_raw(), "{view}");
        let png = |img: &image::RgbaImage| {
            let mut out = Vec::new();
            img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
                .unwrap();
            out
        };
        assert_eq!(png(&a), png(&c), "{view}: PNG bytes");
    }
}

#[test]
fn bad_requests_are_errors() {
    let Some(renderer) = renderer() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = red_front_scene(dir.path(), 0.0);
    let prepared = renderer.prepare(&scene, &lib).unwrap();
    let settings = RenderSettings::square(32);
    assert!(matches!(
        prepared.render(&View::Front("nope".into()), &settings),
        Err(RenderError::UnknownObject { id }) if id == "nope"
    ));
    assert!(matches!(
        prepared.render(&View::TopOf(vec!["cabinet".into(), "x".into()]), &settings),
        Err(RenderError::UnknownObject { .. })
    ));
    assert!(matches!(
        prepared.render(&View::Top, &RenderSettings::square(0)),
        Err(RenderError::BadSize { .. })
    ));
    let two_samples = RenderSettings {
        samples: 2,
        ..settings
    };
    assert!(matches!(
        prepared.render(&View::Top, &two_samples),
        Err(RenderError::BadSamples { samples: 2 })
    ));
    assert!(matches!(
        prepared.render(&View::Top, &RenderSettings::square(1 << 20)),
        Err(RenderError::BadSize { .. })
    ));
    let empty = renderer
        .prepare(&Scene::builder().build().unwrap(), &AssetLibrary::new())
        .unwrap();
    assert!(matches!(
        empty.render(&View::Top, &settings),
        Err(RenderError::EmptyView { .. })
    ));
}

#[test]
fn a_callers_own_device_works_and_agrees_with_the_shared_one() {
    let Some(renderer) = renderer() else { return };
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))
    .unwrap();
    let (device, queue) = pollster::block_on(adapter.request_device(&Default::default())).unwrap();
    let own =
        sceneeval_render::Renderer::with_gpu(sceneeval_render::Gpu::from_device(device, queue)).unwrap();
    let shared = renderer;
    let dir = tempfile::tempdir().unwrap();
    let (scene, lib) = red_front_scene(dir.path(), 10.0);
    let settings = RenderSettings::square(48);
    let view = View::Front("cabinet".into());
    let a = own
        .prepare(&scene, &lib)
        .unwrap()
        .render(&view, &settings)
        .unwrap();
    let b = shared
        .prepare(&scene, &lib)
        .unwrap()
        .render(&view, &settings)
        .unwrap();
    assert!(count(&a, is_red) > 48 * 48 / 4);
    if own.gpu().adapter() == shared.gpu().adapter() {
        assert_eq!(a.as_raw(), b.as_raw(), "same driver, same bytes");
    }
}
