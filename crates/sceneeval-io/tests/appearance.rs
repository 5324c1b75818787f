//! Appearance loading: materials, vertex colours, textures (embedded, external, missing,
//! refused), OBJ/MTL, the frame conversion shared with the geometry, and the guarantee that
//! reading scenes never loads appearances.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::io::Cursor;
use std::path::Path;

use sceneeval_geom::{Isometry3, Point2, Vector3};
use sceneeval_io::appearance::{AlphaMode, Material, Wrap};
use sceneeval_io::assets::{HssdSource, PlainFolderSource};
use sceneeval_io::{
    AssetLibrary, GlbImage, GlbMaterial, GlbMesh, ReadOptions, read_scene_state, write_glb, write_scene_state,
};
use sceneeval_scene::{RoomBuilder, Scene};

/// A PNG of `w x h` texels of one colour.
fn png(w: u32, h: u32, rgba: [u8; 4]) -> Vec<u8> {
    let img = image::RgbaImage::from_pixel(w, h, image::Rgba(rgba));
    let mut out = Vec::new();
    img.write_to(&mut Cursor::new(&mut out), image::ImageFormat::Png)
        .unwrap();
    out
}

/// A unit box `[0, 1]^3` (asset frame) with texture coordinates `u = x`, `v = 1 - y`.
fn textured_box(name: &str, material: GlbMaterial) -> GlbMesh {
    let m = common::box_mesh(name, [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
    let uvs = m.positions.iter().map(|p| [p[0], 1.0 - p[1]]).collect();
    m.with_uvs(uvs).with_material(material)
}

#[test]
fn glb_materials_colours_and_embedded_textures_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let red = GlbMaterial::color([0.8, 0.05, 0.02]);
    let body = common::box_mesh("body", [-0.5, 0.0, -0.2], [0.5, 0.5, 0.2]).with_material(red);
    let (mut p, mut i) = (Vec::new(), Vec::new());
    common::push_box(&mut p, &mut i, [-0.1, 0.1, 0.2], [0.1, 0.3, 0.3]);
    let colors = vec![[0.0, 0.0, 1.0, 1.0]; p.len()];
    let bump = GlbMesh::new("bump", p, i).with_colors(colors);
    let green = png(4, 2, [20, 200, 40, 255]);
    let top = textured_box(
        "top",
        GlbMaterial::color([1.0, 1.0, 1.0]).with_texture(GlbImage::EmbeddedPng(green)),
    );
    write_glb(&dir.path().join("thing.glb"), &[body, bump, top]).unwrap();

    let lib = common::fixture_library(dir.path());
    let a = lib.appearance("fixture.thing").unwrap();
    assert_eq!(a.model_id, "fixture.thing");
    // Three primitives: the red body, the bump (no material: glTF's white default) and the
    // textured box.
    assert_eq!(a.mesh.parts.len(), 3);
    let material = |part: usize| &a.materials[a.mesh.parts[part].material];
    assert_eq!(material(0).base_color, [0.8, 0.05, 0.02, 1.0]);
    assert!(material(0).base_color_texture.is_none());
    assert_eq!(*material(1), Material::gltf_default());
    let tex = material(2).base_color_texture.as_ref().unwrap();
    assert_eq!((tex.texture.width, tex.texture.height), (4, 2));
    assert_eq!(&tex.texture.pixels[..4], &[20, 200, 40, 255]);
    assert_eq!(tex.sampler.wrap_u, Wrap::Repeat);
    assert_eq!(a.texture_count(), 1);
    // Vertex colours of the bump (vertices 8..16); white elsewhere.
    assert_eq!(a.mesh.colors[8], [0.0, 0.0, 1.0, 1.0]);
    assert_eq!(a.mesh.colors[0], [1.0; 4]);
    // No normals in the file: zero (shade flat).
    assert!(a.mesh.normals.iter().all(|n| *n == [0.0; 3]));
    // Texture coordinates of the textured box's corner (1, 1, 0): u = 1, v = 1 - 1 = 0.
    let k = 16 + 3;
    assert_eq!(a.mesh.uvs[k], [1.0, 0.0]);

    // The render mesh is in the object frame, exactly where the geometry is: (x, y, z) ->
    // (x, -z, y). Corner (1, 1, 0) of the textured box becomes (1, 0, 1).
    assert_eq!(a.mesh.positions[k], [1.0, 0.0, 1.0]);
    let geometry = lib.asset("fixture.thing").unwrap();
    let (lo, hi) = a.mesh.bounds().unwrap();
    let aabb = geometry.mesh.aabb();
    for k in 0..3 {
        assert_eq!(f64::from(lo[k]), aabb.min[k]);
        assert_eq!(f64::from(hi[k]), aabb.max[k]);
    }
    // One load per model id, shared.
    let again = lib.appearance("fixture.thing").unwrap();
    assert!(std::sync::Arc::ptr_eq(&a, &again));
    assert_eq!(lib.appearances_loaded(), 1);
}

#[test]
fn broken_missing_and_refused_textures_fall_back_to_the_base_colour() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("assets");
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(root.path().join("outside.png"), png(2, 2, [255, 0, 0, 255])).unwrap();
    std::fs::write(dir.join("broken.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    std::fs::write(dir.join("ok.png"), png(2, 2, [0, 0, 255, 255])).unwrap();
    let blue = [0.1, 0.2, 0.9];
    for (id, uri) in [
        ("missing", "nope.png"),
        ("broken", "broken.png"),
        ("escape", "../outside.png"),
        ("absolute", "/etc/passwd"),
        ("ok", "ok.png"),
    ] {
        let mesh = textured_box(
            id,
            GlbMaterial::color(blue).with_texture(GlbImage::Uri(uri.into())),
        );
        write_glb(&dir.join(format!("{id}.glb")), &[mesh]).unwrap();
    }
    let lib = common::fixture_library(&dir);
    for id in ["missing", "broken", "escape", "absolute"] {
        let a = lib.appearance(&format!("fixture.{id}")).unwrap();
        assert_eq!(a.materials.len(), 1, "{id}");
        assert_eq!(a.materials[0].base_color, [0.1, 0.2, 0.9, 1.0], "{id}");
        assert!(a.materials[0].base_color_texture.is_none(), "{id}");
    }
    let ok = lib.appearance("fixture.ok").unwrap();
    let tex = ok.materials[0].base_color_texture.as_ref().unwrap();
    assert_eq!(tex.texture.label, "ok.png");
    assert_eq!(&tex.texture.pixels[..4], &[0, 0, 255, 255]);
}

#[test]
fn obj_mtl_colours_textures_and_fallbacks() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("assets");
    std::fs::create_dir_all(dir.join("mat")).unwrap();
    std::fs::write(dir.join("mat/wood.png"), png(2, 2, [120, 70, 30, 255])).unwrap();
    std::fs::write(
        dir.join("mat/lib.mtl"),
        "newmtl red\nKd 0.9 0.1 0.1\nnewmtl wood\nKd 1 1 1\nmap_Kd -s 1 1 1 wood.png\n\
         newmtl glass\nKd 0.5 0.5 0.5\nd 0.25\nnewmtl ghost\nKd 0.2 0.2 0.2\nd 0\n",
    )
    .unwrap();
    let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    std::fs::write(
        dir.join("chair.obj"),
        format!(
            "mtllib mat/lib.mtl\n{quad}o e\nf 1 2 3\no a\nusemtl red\nf 1/1 2/2 3/3\no b\nusemtl wood\n\
             f 1/1 3/3 4/4\no c\nusemtl glass\nf 1 2 4\no d\nusemtl ghost\nf 2 3 4\n"
        ),
    )
    .unwrap();
    let lib = AssetLibrary::new().with_source("obj", PlainFolderSource::new(&dir));
    let a = lib.appearance("obj.chair").unwrap();
    let by_name = |name: &str| {
        a.mesh
            .parts
            .iter()
            .map(|p| &a.materials[p.material])
            .find(|m| m.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no part with material {name}"))
    };
    assert_eq!(by_name("red").base_color, [0.9, 0.1, 0.1, 1.0]);
    let wood = by_name("wood").base_color_texture.as_ref().unwrap();
    assert_eq!(&wood.texture.pixels[..4], &[120, 70, 30, 255]);
    assert_eq!(by_name("glass").alpha_mode, AlphaMode::Blend);
    assert_eq!(by_name("glass").base_color[3], 0.25);
    // `d 0` is taken as an exporter mistake: opaque.
    assert_eq!(by_name("ghost").alpha_mode, AlphaMode::Opaque);
    // The face before any `usemtl` gets Blender's 0.8 grey.
    let first = a.mesh.parts[0];
    assert_eq!(a.materials[first.material], Material::obj_default());
    // OBJ v runs up, glTF's down: vt (1, 1) becomes (1, 0). The red part's third vertex.
    let red = a.mesh.parts[1];
    let third = a.mesh.indices[red.first_index as usize + 2] as usize;
    assert_eq!(a.mesh.uvs[third], [1.0, 0.0]);

    // A material library outside the asset's folder is refused: every face is grey.
    std::fs::write(root.path().join("evil.mtl"), "newmtl red\nKd 1 0 0\n").unwrap();
    std::fs::write(
        dir.join("sneaky.obj"),
        format!("mtllib ../evil.mtl\n{quad}usemtl red\nf 1 2 3\n"),
    )
    .unwrap();
    let s = lib.appearance("obj.sneaky").unwrap();
    assert!(
        s.mesh
            .parts
            .iter()
            .all(|p| s.materials[p.material] == Material::obj_default())
    );
}

/// A scene of textured assets, written to `dir`.
fn textured_scene(dir: &Path) -> std::path::PathBuf {
    let tex = GlbImage::EmbeddedPng(png(8, 8, [200, 30, 30, 255]));
    let mesh = textured_box("crate", GlbMaterial::color([1.0; 3]).with_texture(tex));
    write_glb(&dir.join("crate.glb"), &[mesh]).unwrap();
    let lib = common::fixture_library(dir);
    let mut builder = Scene::builder().room_builder(RoomBuilder::rectangle(
        "r",
        Point2::new(-5.0, -5.0),
        Point2::new(5.0, 5.0),
    ));
    for k in 0..3 {
        let pose = Isometry3::translation(f64::from(k) * 2.0, 0.0, 0.0);
        builder = builder.object(
            lib.object(format!("c{k}"), "fixture.crate", pose, Vector3::repeat(1.0))
                .unwrap(),
        );
    }
    let path = dir.join("scene_0.json");
    write_scene_state(&builder.build().unwrap(), &path).unwrap();
    path
}

#[test]
fn reading_scenes_never_loads_appearances() {
    let dir = tempfile::tempdir().unwrap();
    let path = textured_scene(dir.path());
    let lib = common::fixture_library(dir.path());
    let scene = read_scene_state(&path, &lib, &ReadOptions::default()).unwrap();
    assert_eq!(scene.objects().len(), 3);
    assert_eq!(lib.files_read(), 1);
    assert_eq!(lib.appearances_loaded(), 0, "geometry-only reads decode nothing");
    let a = lib.appearance("fixture.crate").unwrap();
    assert_eq!(a.texture_count(), 1);
    assert_eq!(lib.appearances_loaded(), 1);
}

#[test]
fn appearance_follows_the_sources_alignment() {
    // An HSSD asset stored z-up with its front toward -y (see the assets test of the same
    // layout): geometry and appearance agree after alignment.
    let dir = tempfile::tempdir().unwrap();
    let body = common::box_mesh("body", [-0.5, -0.2, 0.0], [0.5, 0.2, 0.5]);
    let bump = common::box_mesh("bump", [-0.1, -0.3, 0.1], [0.1, -0.2, 0.3]);
    std::fs::create_dir_all(dir.path().join("glb/f")).unwrap();
    write_glb(&dir.path().join("glb/f/f00d.glb"), &[body, bump]).unwrap();
    std::fs::write(
        dir.path().join("fpmodels.csv"),
        "id,name,up,front,wnsynsetkey\nf00d,Tall dresser,\"0,0,1\",\"0,-1,0\",dresser.n.01\n",
    )
    .unwrap();
    let lib = AssetLibrary::new().with_source("fpModel", HssdSource::new(dir.path()));
    let geometry = lib.asset("fpModel.f00d").unwrap();
    let look = lib.appearance("fpModel.f00d").unwrap();
    let (lo, hi) = look.mesh.bounds().unwrap();
    let aabb = geometry.mesh.aabb();
    for k in 0..3 {
        assert!((f64::from(lo[k]) - aabb.min[k]).abs() < 1e-6, "{lo:?} {aabb:?}");
        assert!((f64::from(hi[k]) - aabb.max[k]).abs() < 1e-6, "{hi:?} {aabb:?}");
    }
    // The bump is in front (object -y).
    assert!((f64::from(lo[1]) + 0.3).abs() < 1e-6);
}

#[test]
fn unknown_assets_are_errors() {
    let lib = AssetLibrary::new();
    assert!(lib.appearance("fixture.none").is_err());
    let dir = tempfile::tempdir().unwrap();
    let lib = common::fixture_library(dir.path());
    assert!(lib.appearance("fixture.none").is_err());
    assert_eq!(lib.appearances_loaded(), 0);
}
