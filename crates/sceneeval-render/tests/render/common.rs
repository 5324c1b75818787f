//! Test assets written with sceneeval-io's GLB writer, image measurements, and the
//! reference-image comparison.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use image::RgbaImage;
use sceneeval_geom::{Isometry3, Vector3};
use sceneeval_io::assets::PlainFolderSource;
use sceneeval_io::{AssetLibrary, GlbImage, GlbMaterial, GlbMesh, write_glb};
use sceneeval_render::{RenderError, Renderer};
use sceneeval_scene::SceneObject;
use sceneeval_test_support::system::{GPU, available};

/// The renderer on the process-wide device, or `None` (the test is skipped, the reason
/// printed once) on a machine without a Vulkan driver unless `SCENEEVAL_REQUIRE_GPU` is set,
/// as on CI, which installs lavapipe ([`sceneeval_test_support::system`]).
pub fn renderer() -> Option<Renderer> {
    available(&GPU, Renderer::new(), RenderError::is_missing_driver)
}

/// One face of the box `[-w/2, w/2] x [0, h] x [-d/2, d/2]` (asset frame: y up, front +z) as
/// a quad of two triangles, wound outward, with texture coordinates spanning the face.
fn face(name: &str, size: [f32; 3], axis: usize, positive: bool, material: GlbMaterial) -> GlbMesh {
    let [w, h, d] = size;
    let lo = [-w / 2.0, 0.0, -d / 2.0];
    let hi = [w / 2.0, h, d / 2.0];
    let (u, v) = match axis {
        0 => (2, 1),
        1 => (0, 2),
        _ => (0, 1),
    };
    let fixed = if positive { hi[axis] } else { lo[axis] };
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for (a, b) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
        let mut p = [0.0f32; 3];
        p[axis] = fixed;
        p[u] = if a == 0 { lo[u] } else { hi[u] };
        p[v] = if b == 0 { lo[v] } else { hi[v] };
        positions.push(p);
        uvs.push([a as f32, 1.0 - b as f32]);
    }
    // The quad runs counter-clockwise in the (u, v) plane, whose normal is u x v: +axis when
    // (u, v, axis) is right-handed. Wind it so the normal points out of the box (the renderer
    // draws both sides; this keeps the file tidy).
    let right_handed = (u + 1) % 3 == v;
    let indices = if right_handed == positive {
        vec![0, 1, 2, 0, 2, 3]
    } else {
        vec![0, 2, 1, 0, 3, 2]
    };
    let mesh = GlbMesh::new(name, positions, indices).with_material(material.clone());
    if material.texture.is_some() {
        mesh.with_uvs(uvs)
    } else {
        mesh
    }
}

/// A box asset of `size` = (width x, height y, depth z) in the asset frame whose front face
/// (+z, the object's front) has material `front` and every other face `other`.
pub fn box_asset(size: [f32; 3], front: GlbMaterial, other: GlbMaterial) -> Vec<GlbMesh> {
    let mut faces = Vec::new();
    for axis in 0..3 {
        for positive in [false, true] {
            let material = if axis == 2 && positive {
                front.clone()
            } else {
                other.clone()
            };
            faces.push(face(
                &format!("face_{axis}_{positive}"),
                size,
                axis,
                positive,
                material,
            ));
        }
    }
    faces
}

/// Writes `meshes` as `<dir>/<id>.glb`.
pub fn write_asset(dir: &Path, id: &str, meshes: &[GlbMesh]) {
    write_glb(&dir.join(format!("{id}.glb")), meshes).expect("asset written");
}

/// A library with a plain folder source `test` at `dir`.
pub fn library(dir: &Path) -> AssetLibrary {
    AssetLibrary::new().with_source("test", PlainFolderSource::new(dir))
}

/// An object showing asset `test.<id>` at `pose`.
pub fn object(library: &AssetLibrary, id: &str, asset: &str, pose: Isometry3) -> SceneObject {
    library
        .object(id, &format!("test.{asset}"), pose, Vector3::repeat(1.0))
        .expect("asset object")
}

/// A PNG of one colour.
pub fn solid_png(w: u32, h: u32, rgba: [u8; 4]) -> Vec<u8> {
    let mut out = Vec::new();
    RgbaImage::from_pixel(w, h, image::Rgba(rgba))
        .write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
        .expect("png");
    out
}

/// A matte material of linear colour `rgb`.
pub fn color(rgb: [f32; 3]) -> GlbMaterial {
    GlbMaterial::color(rgb)
}

/// An embedded texture on a white base colour.
pub fn textured(png: Vec<u8>) -> GlbMaterial {
    GlbMaterial::color([1.0; 3]).with_texture(GlbImage::EmbeddedPng(png))
}

/// Pixels satisfying `pred`.
pub fn count(img: &RgbaImage, pred: impl Fn([u8; 4]) -> bool) -> usize {
    img.pixels().filter(|p| pred(p.0)).count()
}

/// Mean (x, y) of the pixels satisfying `pred`, in pixel-index coordinates.
pub fn centroid(img: &RgbaImage, pred: impl Fn([u8; 4]) -> bool) -> Option<(f64, f64)> {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for (x, y, p) in img.enumerate_pixels() {
        if pred(p.0) {
            sx += f64::from(x);
            sy += f64::from(y);
            n += 1.0;
        }
    }
    (n > 0.0).then(|| (sx / n, sy / n))
}

/// Rows containing at least one pixel satisfying `pred`: (first, last).
pub fn row_span(img: &RgbaImage, pred: impl Fn([u8; 4]) -> bool) -> Option<(u32, u32)> {
    let rows: Vec<u32> = (0..img.height())
        .filter(|&y| (0..img.width()).any(|x| pred(img.get_pixel(x, y).0)))
        .collect();
    Some((*rows.first()?, *rows.last()?))
}

/// Strongly red, opaque.
pub fn is_red(p: [u8; 4]) -> bool {
    p[3] == 255
        && p[0] > 120
        && u16::from(p[1]) * 3 < u16::from(p[0])
        && u16::from(p[2]) * 3 < u16::from(p[0])
}

/// Opaque and grey (equal channels within 6), not near black or white.
pub fn is_grey(p: [u8; 4]) -> bool {
    let (r, g, b) = (i16::from(p[0]), i16::from(p[1]), i16::from(p[2]));
    p[3] == 255 && (r - g).abs() <= 6 && (g - b).abs() <= 6 && (r - b).abs() <= 6 && (60..240).contains(&r)
}

/// The fixtures folder of the workspace.
pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// Largest per-channel difference (RGBA) counted as equal, and the share of pixels allowed
/// to differ more: lavapipe versions rasterise edges slightly differently.
const CHANNEL_TOLERANCE: u8 = 24;
const DIFFERING_SHARE: f64 = 0.005;

/// Compares `actual` with `tests/reference/<name>.png`. With `SCENEEVAL_BLESS=1` the
/// reference is (re)written instead. On failure the actual image, the reference and a diff
/// (differing pixels red over a faded copy of the reference) are written to
/// `<target>/tmp/render-diffs/` and the message names them.
pub fn assert_matches_reference(name: &str, actual: &RgbaImage) {
    let reference = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/reference")
        .join(format!("{name}.png"));
    if std::env::var_os("SCENEEVAL_BLESS").is_some_and(|v| v == "1") {
        actual.save(&reference).expect("reference written");
        return;
    }
    let expected = image::open(&reference)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e}; run with SCENEEVAL_BLESS=1 to create it",
                reference.display()
            )
        })
        .to_rgba8();
    let mut differing = 0usize;
    let mut diff = RgbaImage::new(actual.width(), actual.height());
    let same_size = expected.dimensions() == actual.dimensions();
    if same_size {
        for (x, y, a) in actual.enumerate_pixels() {
            let e = expected.get_pixel(x, y);
            let worst = (0..4).map(|k| a.0[k].abs_diff(e.0[k])).max().unwrap_or(0);
            let faded = |c: u8| 200 + c / 5;
            if worst > CHANNEL_TOLERANCE {
                differing += 1;
                diff.put_pixel(x, y, image::Rgba([255, 0, 0, 255]));
            } else {
                diff.put_pixel(
                    x,
                    y,
                    image::Rgba([faded(e.0[0]), faded(e.0[1]), faded(e.0[2]), 255]),
                );
            }
        }
    }
    let share = differing as f64 / f64::from(actual.width() * actual.height());
    if !same_size || share > DIFFERING_SHARE {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("render-diffs");
        std::fs::create_dir_all(&dir).expect("diff folder");
        let path = |kind: &str| dir.join(format!("{name}.{kind}.png"));
        actual.save(path("actual")).expect("actual written");
        expected.save(path("expected")).expect("expected written");
        diff.save(path("diff")).expect("diff written");
        panic!(
            "{name}: {} pixels ({:.2} %) differ by more than {CHANNEL_TOLERANCE} (sizes {:?} vs {:?}); \
             see {} (re-bless with SCENEEVAL_BLESS=1 if the change is intended)",
            differing,
            100.0 * share,
            actual.dimensions(),
            expected.dimensions(),
            path("diff").display()
        );
    }
}
