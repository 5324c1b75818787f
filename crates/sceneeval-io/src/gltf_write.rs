//! Writing binary glTF 2.0 (`.glb`) files: one node and one triangle mesh per [`GlbMesh`].
//!
//! The writer exists for generated test assets (the fixtures) and for exporting meshes. It
//! writes positions and indices, and on request vertex colours (`COLOR_0`), texture
//! coordinates (`TEXCOORD_0`) and a material ([`GlbMaterial`]: base colour factor, alpha mode,
//! a base colour texture embedded in the file or referred to by URI); never normals. Output is
//! deterministic: identical input gives byte-identical files.
//!
//! Layout of the file: one little-endian binary buffer holding, for each mesh in order, its
//! positions (`f32` x, y, z), its indices (`u32`), then its colours (`f32` RGBA) and texture
//! coordinates (`f32` u, v) if any, then an embedded image (padded to 4 bytes); per mesh a
//! `POSITION` accessor with `min`/`max`, an index accessor and one accessor per extra
//! attribute; per mesh one node (no transform, named like the mesh) that is a root of the
//! single, default scene; per mesh with a material one material (and one texture and image
//! when it has a texture; the default sampler).

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;

use crate::IoError;

/// A named triangle mesh for [`write_glb`], in the file's own coordinates (for assets: y up,
/// front toward +z, metres).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GlbMesh {
    /// The mesh's (and its node's) name.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Triangle vertex indices, three per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
    /// Linear RGBA vertex colours (`COLOR_0`), one per position, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colors: Option<Vec<[f32; 4]>>,
    /// Texture coordinates (`TEXCOORD_0`, `(0, 0)` = the image's top-left corner), one per
    /// position, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uvs: Option<Vec<[f32; 2]>>,
    /// The mesh's material, if any (without one, readers use glTF's default: white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<GlbMaterial>,
}

/// A material for [`GlbMesh::with_material`]: glTF's metallic-roughness model reduced to what
/// generated assets need.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GlbMaterial {
    /// Linear RGBA base colour factor.
    pub base_color: [f32; 4],
    /// `OPAQUE` (false) or `BLEND` (true) alpha mode.
    #[serde(default)]
    pub blend: bool,
    /// A base colour texture (sampled with `TEXCOORD_0`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<GlbImage>,
}

impl GlbMaterial {
    /// An opaque, untextured material of linear RGB colour `rgb`.
    pub fn color(rgb: [f32; 3]) -> Self {
        GlbMaterial {
            base_color: [rgb[0], rgb[1], rgb[2], 1.0],
            blend: false,
            texture: None,
        }
    }

    /// This material with a base colour texture.
    pub fn with_texture(mut self, image: GlbImage) -> Self {
        self.texture = Some(image);
        self
    }
}

/// Where a texture image comes from.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum GlbImage {
    /// PNG bytes stored in the file's binary buffer.
    EmbeddedPng(Vec<u8>),
    /// A URI written as is (a file next to the `.glb`, or a `data:` URI).
    Uri(String),
}

impl GlbMesh {
    /// A mesh from its parts.
    pub fn new(name: impl Into<String>, positions: Vec<[f32; 3]>, indices: Vec<u32>) -> Self {
        GlbMesh {
            name: name.into(),
            positions,
            indices,
            colors: None,
            uvs: None,
            material: None,
        }
    }

    /// This mesh with a material.
    pub fn with_material(mut self, material: GlbMaterial) -> Self {
        self.material = Some(material);
        self
    }

    /// This mesh with linear RGBA vertex colours (one per position).
    pub fn with_colors(mut self, colors: Vec<[f32; 4]>) -> Self {
        self.colors = Some(colors);
        self
    }

    /// This mesh with texture coordinates (one per position).
    pub fn with_uvs(mut self, uvs: Vec<[f32; 2]>) -> Self {
        self.uvs = Some(uvs);
        self
    }

    fn check(&self) -> Result<(), IoError> {
        let bad = |reason: String| IoError::BadGlbMesh {
            name: self.name.clone(),
            reason,
        };
        if self.positions.is_empty() || self.indices.is_empty() {
            return Err(bad("has no vertices or no triangles".into()));
        }
        if !self.indices.len().is_multiple_of(3) {
            return Err(bad(format!(
                "has {} indices, not a multiple of 3",
                self.indices.len()
            )));
        }
        if let Some((i, p)) = self
            .positions
            .iter()
            .enumerate()
            .find(|(_, p)| !p.iter().all(|c| c.is_finite()))
        {
            return Err(bad(format!("vertex {i} is not finite: {p:?}")));
        }
        let n = self.positions.len();
        if let Some((k, &i)) = self.indices.iter().enumerate().find(|&(_, &i)| i as usize >= n) {
            return Err(bad(format!("index {k} is {i}, but there are {n} vertices")));
        }
        if let Some(c) = &self.colors
            && c.len() != n
        {
            return Err(bad(format!("has {} colours for {n} vertices", c.len())));
        }
        if let Some(uv) = &self.uvs
            && uv.len() != n
        {
            return Err(bad(format!(
                "has {} texture coordinates for {n} vertices",
                uv.len()
            )));
        }
        let extra_finite = self
            .colors
            .iter()
            .flatten()
            .all(|c| c.iter().all(|v| v.is_finite()))
            && self.uvs.iter().flatten().all(|c| c.iter().all(|v| v.is_finite()))
            && self
                .material
                .as_ref()
                .is_none_or(|m| m.base_color.iter().all(|v| v.is_finite()));
        if !extra_finite {
            return Err(bad("has a colour or texture coordinate that is not finite".into()));
        }
        if self.material.as_ref().is_some_and(|m| m.texture.is_some()) && self.uvs.is_none() {
            return Err(bad("has a textured material but no texture coordinates".into()));
        }
        Ok(())
    }

    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        for p in &self.positions {
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        (min, max)
    }
}

/// Writes `meshes` as a binary glTF 2.0 file at `path`: one node (no transform, named like
/// the mesh) and one triangle mesh per [`GlbMesh`], all roots of the single, default scene;
/// one little-endian buffer holding each mesh's `f32` positions then its `u32` indices; a
/// `POSITION` accessor with `min`/`max` and an index accessor per mesh; no normals or
/// materials. Identical input gives byte-identical files. The file is written atomically
/// ([`sceneeval_files::write_atomic`]), its folder created if missing.
///
/// # Errors
/// [`IoError::BadGlbMesh`] when a mesh has no triangles, a non-finite vertex, an index out of
/// range or an index count that is not a multiple of 3 (also when `meshes` is empty);
/// [`IoError::File`] when the file cannot be written.
pub fn write_glb(path: &Path, meshes: &[GlbMesh]) -> Result<(), IoError> {
    let bytes = write_glb_to_vec(meshes)?;
    sceneeval_files::write_atomic(path, &bytes).map_err(|e| IoError::file(path, e))
}

/// The bytes of the binary glTF file [`write_glb`] would write.
///
/// ```
/// use sceneeval_io::{GlbMesh, write_glb_to_vec};
/// let tri = GlbMesh::new("tri", vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![0, 1, 2]);
/// let bytes = write_glb_to_vec(&[tri.clone()]).unwrap();
/// assert_eq!(&bytes[..4], b"glTF");
/// assert_eq!(bytes, write_glb_to_vec(&[tri]).unwrap(), "deterministic");
/// ```
///
/// # Errors
/// As [`write_glb`], without the file error.
pub fn write_glb_to_vec(meshes: &[GlbMesh]) -> Result<Vec<u8>, IoError> {
    if meshes.is_empty() {
        return Err(IoError::BadGlbMesh {
            name: String::new(),
            reason: "no meshes to write".into(),
        });
    }
    for m in meshes {
        m.check()?;
    }
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some("sceneeval-io".into()),
            ..Default::default()
        },
        ..Default::default()
    };
    let mut bin: Vec<u8> = Vec::new();
    // The buffer is pushed first so that it has index 0; its length is set at the end.
    let buffer = root.push(json::Buffer {
        byte_length: USize64(0),
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        uri: None,
    });
    let mut nodes = Vec::with_capacity(meshes.len());
    for m in meshes {
        let le = |c: &f32| c.to_le_bytes();
        let (positions_offset, positions_len) = append(&mut bin, m.positions.iter().flatten().map(le));
        let (indices_offset, indices_len) = append(&mut bin, m.indices.iter().map(|i| i.to_le_bytes()));
        let colors_range =
            (m.colors.as_ref()).map(|colors| append(&mut bin, colors.iter().flatten().map(le)));
        let uvs_range = (m.uvs.as_ref()).map(|uvs| append(&mut bin, uvs.iter().flatten().map(le)));
        let image_range = match m.material.as_ref().and_then(|mat| mat.texture.as_ref()) {
            Some(GlbImage::EmbeddedPng(png)) => {
                let offset = bin.len();
                bin.extend_from_slice(png);
                let len = bin.len() - offset;
                while !bin.len().is_multiple_of(4) {
                    bin.push(0);
                }
                Some((offset, len))
            }
            _ => None,
        };

        let view = |root: &mut json::Root, offset: usize, len: usize, target| {
            push_view(root, buffer, offset, len, Some(target))
        };
        let positions_view = view(
            &mut root,
            positions_offset,
            positions_len,
            json::buffer::Target::ArrayBuffer,
        );
        let indices_view = view(
            &mut root,
            indices_offset,
            indices_len,
            json::buffer::Target::ElementArrayBuffer,
        );
        let (min, max) = m.bounds();
        use json::accessor::{ComponentType, Type};
        let positions = push_accessor(
            &mut root,
            positions_view,
            m.positions.len(),
            (ComponentType::F32, Type::Vec3),
            Some((min.to_vec(), max.to_vec())),
        );
        let indices = push_accessor(
            &mut root,
            indices_view,
            m.indices.len(),
            (ComponentType::U32, Type::Scalar),
            None,
        );
        let mut attributes = BTreeMap::from([(Valid(json::mesh::Semantic::Positions), positions)]);
        let float_accessor = |root: &mut json::Root, (offset, len): (usize, usize), count, type_| {
            let attribute_view = view(root, offset, len, json::buffer::Target::ArrayBuffer);
            push_accessor(root, attribute_view, count, (ComponentType::F32, type_), None)
        };
        if let Some(range) = colors_range {
            let acc = float_accessor(&mut root, range, m.positions.len(), Type::Vec4);
            attributes.insert(Valid(json::mesh::Semantic::Colors(0)), acc);
        }
        if let Some(range) = uvs_range {
            let acc = float_accessor(&mut root, range, m.positions.len(), Type::Vec2);
            attributes.insert(Valid(json::mesh::Semantic::TexCoords(0)), acc);
        }
        let material = m
            .material
            .as_ref()
            .map(|mat| push_material(&mut root, buffer, &m.name, mat, image_range));
        let mesh = root.push(json::Mesh {
            extensions: Default::default(),
            extras: Default::default(),
            name: Some(m.name.clone()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: Default::default(),
                extras: Default::default(),
                indices: Some(indices),
                material,
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        });
        nodes.push(root.push(json::Node {
            mesh: Some(mesh),
            name: Some(m.name.clone()),
            ..Default::default()
        }));
    }
    root.buffers[0].byte_length = USize64::from(bin.len());
    let scene = root.push(json::Scene {
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        nodes,
    });
    root.scene = Some(scene);

    let text = json::serialize::to_string(&root).map_err(|e| IoError::BadGlbMesh {
        name: meshes[0].name.clone(),
        reason: format!("cannot serialise the glTF JSON: {e}"),
    })?;
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            // Recomputed by the writer.
            length: 0,
        },
        json: Cow::Owned(text.into_bytes()),
        bin: Some(Cow::Owned(bin)),
    };
    glb.to_vec().map_err(|e| IoError::BadGlbMesh {
        name: meshes[0].name.clone(),
        reason: format!("cannot assemble the binary glTF: {e}"),
    })
}

/// Appends `values` (each a little-endian number) to `bin`; returns their offset and length.
fn append<const N: usize>(bin: &mut Vec<u8>, values: impl Iterator<Item = [u8; N]>) -> (usize, usize) {
    let offset = bin.len();
    for v in values {
        bin.extend_from_slice(&v);
    }
    (offset, bin.len() - offset)
}

/// Adds an accessor of `count` elements of `kind` (component and element type) in `view` to
/// `root`, with the bounds `min_max` when given (glTF requires them for positions).
fn push_accessor(
    root: &mut json::Root,
    view: json::Index<json::buffer::View>,
    count: usize,
    kind: (json::accessor::ComponentType, json::accessor::Type),
    min_max: Option<(Vec<f32>, Vec<f32>)>,
) -> json::Index<json::Accessor> {
    let (min, max) = min_max.map_or((None, None), |(min, max)| {
        (Some(json::Value::from(min)), Some(json::Value::from(max)))
    });
    root.push(json::Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: USize64::from(count),
        component_type: Valid(json::accessor::GenericComponentType(kind.0)),
        extensions: Default::default(),
        extras: Default::default(),
        type_: Valid(kind.1),
        min,
        max,
        name: None,
        normalized: false,
        sparse: None,
    })
}

/// Adds a view of `len` bytes at `offset` of `buffer` to `root`.
fn push_view(
    root: &mut json::Root,
    buffer: json::Index<json::Buffer>,
    offset: usize,
    len: usize,
    target: Option<json::buffer::Target>,
) -> json::Index<json::buffer::View> {
    root.push(json::buffer::View {
        buffer,
        byte_length: USize64::from(len),
        byte_offset: Some(USize64::from(offset)),
        byte_stride: None,
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        target: target.map(Valid),
    })
}

/// Adds `material` (and its texture and image) to `root`; `image_range` is where an embedded
/// image lies in the binary buffer.
fn push_material(
    root: &mut json::Root,
    buffer: json::Index<json::Buffer>,
    name: &str,
    material: &GlbMaterial,
    image_range: Option<(usize, usize)>,
) -> json::Index<json::Material> {
    let texture = material.texture.as_ref().map(|image| {
        let (buffer_view, mime_type, uri) = match (image, image_range) {
            (GlbImage::EmbeddedPng(_), Some((offset, len))) => {
                let view = push_view(root, buffer, offset, len, None);
                (Some(view), Some(json::image::MimeType("image/png".into())), None)
            }
            (GlbImage::Uri(uri), _) => (None, None, Some(uri.clone())),
            (GlbImage::EmbeddedPng(_), None) => (None, None, None),
        };
        let source = root.push(json::Image {
            buffer_view,
            mime_type,
            name: Some(name.to_owned()),
            uri,
            extensions: Default::default(),
            extras: Default::default(),
        });
        let texture = root.push(json::Texture {
            name: None,
            sampler: None,
            source,
            extensions: Default::default(),
            extras: Default::default(),
        });
        json::texture::Info {
            index: texture,
            tex_coord: 0,
            extensions: Default::default(),
            extras: Default::default(),
        }
    });
    root.push(json::Material {
        name: Some(name.to_owned()),
        alpha_mode: Valid(if material.blend {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(material.base_color),
            base_color_texture: texture,
            // A matte, non-metallic surface: the base colour is what a viewer sees.
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(1.0),
            ..Default::default()
        },
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(name: &str, offset: f32) -> GlbMesh {
        let positions = (0..8)
            .map(|k| {
                [
                    if k & 1 == 0 { -0.5 } else { 0.5 } + offset,
                    if k & 2 == 0 { 0.0 } else { 1.0 },
                    if k & 4 == 0 { -0.25 } else { 0.25 },
                ]
            })
            .collect();
        let indices = vec![
            0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3,
            5, 3, 7, 5,
        ];
        GlbMesh::new(name, positions, indices)
    }

    #[test]
    fn output_is_a_valid_deterministic_glb() {
        let meshes = [cube("a", 0.0), cube("b", 2.0)];
        let bytes = write_glb_to_vec(&meshes).unwrap();
        assert_eq!(bytes, write_glb_to_vec(&meshes).unwrap());
        assert_eq!(&bytes[0..4], b"glTF");
        assert_eq!(u32::from_le_bytes(bytes[4..8].try_into().unwrap()), 2);
        assert_eq!(
            u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
            bytes.len()
        );
        assert_eq!(bytes.len() % 4, 0);

        // Read it back with the gltf crate and check the accessors.
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        let blob = gltf.blob.clone().unwrap();
        // Two meshes of 8 vertices (96 bytes) and 36 indices (144 bytes).
        assert_eq!(blob.len(), 2 * (96 + 144));
        assert_eq!(gltf.meshes().count(), 2);
        assert_eq!(gltf.nodes().count(), 2);
        let scene = gltf.default_scene().unwrap();
        assert_eq!(scene.nodes().count(), 2);
        let names: Vec<_> = gltf.nodes().map(|n| n.name().unwrap().to_owned()).collect();
        assert_eq!(names, ["a", "b"]);
        let mesh_b = gltf.meshes().nth(1).unwrap();
        let prim = mesh_b.primitives().next().unwrap();
        let bounds = prim.bounding_box();
        assert_eq!(bounds.min, [1.5, 0.0, -0.25]);
        assert_eq!(bounds.max, [2.5, 1.0, 0.25]);
        let reader = prim.reader(|_| Some(&blob[..]));
        let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        assert_eq!(pos, meshes[1].positions);
        let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
        assert_eq!(idx, meshes[1].indices);
    }

    #[test]
    fn materials_colours_and_textures_round_trip() {
        let plain = cube("plain", 0.0);
        let json_of = |bytes: &[u8]| gltf::Gltf::from_slice(bytes).unwrap().document.into_json();
        // Geometry-only meshes write no material, texture or image entries.
        let root = json_of(&write_glb_to_vec(std::slice::from_ref(&plain)).unwrap());
        assert!(root.materials.is_empty() && root.textures.is_empty() && root.images.is_empty());

        let n = plain.positions.len();
        let png = vec![0x89, b'P', b'N', b'G', 1, 2, 3];
        let textured = cube("textured", 2.0)
            .with_uvs(vec![[0.25, 0.75]; n])
            .with_colors(vec![[0.5, 0.25, 1.0, 1.0]; n])
            .with_material(
                GlbMaterial::color([0.9, 0.1, 0.1]).with_texture(GlbImage::EmbeddedPng(png.clone())),
            );
        let linked = cube("linked", 4.0).with_uvs(vec![[0.0, 0.0]; n]).with_material(
            GlbMaterial::color([0.1, 0.9, 0.1]).with_texture(GlbImage::Uri("wood.png".into())),
        );
        let bytes = write_glb_to_vec(&[plain, textured, linked]).unwrap();
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        let blob = gltf.blob.clone().unwrap();
        assert_eq!(gltf.materials().count(), 2);
        let prim = gltf.meshes().nth(1).unwrap().primitives().next().unwrap();
        let material = prim.material();
        let pbr = material.pbr_metallic_roughness();
        assert_eq!(pbr.base_color_factor(), [0.9, 0.1, 0.1, 1.0]);
        let image = pbr.base_color_texture().unwrap().texture().source();
        match image.source() {
            gltf::image::Source::View { view, mime_type } => {
                assert_eq!(mime_type, "image/png");
                assert_eq!(&blob[view.offset()..view.offset() + view.length()], &png[..]);
            }
            other => panic!("{other:?}"),
        }
        let reader = prim.reader(|_| Some(&blob[..]));
        let uvs: Vec<[f32; 2]> = reader.read_tex_coords(0).unwrap().into_f32().collect();
        assert_eq!(uvs, vec![[0.25, 0.75]; n]);
        let colors: Vec<[f32; 4]> = reader.read_colors(0).unwrap().into_rgba_f32().collect();
        assert_eq!(colors[0], [0.5, 0.25, 1.0, 1.0]);
        let linked = gltf
            .meshes()
            .nth(2)
            .unwrap()
            .primitives()
            .next()
            .unwrap()
            .material();
        let image = linked
            .pbr_metallic_roughness()
            .base_color_texture()
            .unwrap()
            .texture()
            .source();
        assert!(matches!(
            image.source(),
            gltf::image::Source::Uri { uri: "wood.png", .. }
        ));
        // Every accessor stays 4-byte aligned after the 7-byte image.
        assert!(gltf.accessors().all(|a| a.view().unwrap().offset() % 4 == 0));
    }

    #[test]
    fn invalid_meshes_are_rejected() {
        let err = |m: GlbMesh| match write_glb_to_vec(&[m]) {
            Err(IoError::BadGlbMesh { reason, .. }) => reason,
            other => panic!("expected BadGlbMesh, got {other:?}"),
        };
        let mut m = cube("c", 0.0);
        m.indices.push(0);
        assert!(err(m).contains("multiple of 3"));
        let mut m = cube("c", 0.0);
        m.indices[5] = 8;
        assert!(err(m).contains("8 vertices"));
        let mut m = cube("c", 0.0);
        m.positions[3][1] = f32::NAN;
        assert!(err(m).contains("vertex 3"));
        assert!(err(GlbMesh::new("e", vec![], vec![])).contains("no vertices"));
        assert!(err(cube("c", 0.0).with_colors(vec![[1.0; 4]; 3])).contains("3 colours"));
        assert!(err(cube("c", 0.0).with_uvs(vec![[0.0; 2]])).contains("1 texture coordinates"));
        let textured = GlbMaterial::color([1.0; 3]).with_texture(GlbImage::Uri("t.png".into()));
        assert!(err(cube("c", 0.0).with_material(textured)).contains("no texture coordinates"));
        assert!(write_glb_to_vec(&[]).is_err());
    }

    #[test]
    fn writes_a_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cube.glb");
        write_glb(&path, &[cube("c", 0.0)]).unwrap();
        assert_eq!(
            std::fs::read(&path).unwrap(),
            write_glb_to_vec(&[cube("c", 0.0)]).unwrap()
        );
        // Missing folders are created; a folder that cannot be (a file is in its way) is an
        // error naming the file, and nothing is left behind.
        write_glb(&dir.path().join("new/dir/cube.glb"), &[cube("c", 0.0)]).unwrap();
        std::fs::write(dir.path().join("file"), "x").unwrap();
        let blocked = dir.path().join("file/cube.glb");
        assert!(matches!(
            write_glb(&blocked, &[cube("c", 0.0)]),
            Err(IoError::File { path, .. }) if path == blocked
        ));
    }
}
