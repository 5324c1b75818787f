//! What assets look like: materials, base colour textures and a render mesh, loaded **only when
//! a renderer asks** ([`crate::AssetLibrary::appearance`]).
//!
//! Geometry-only work (predicates, plausibility) never comes here: reading a scene loads each
//! asset's triangles and nothing else, decodes no image and builds no material. A renderer
//! calls [`crate::AssetLibrary::appearance`] per model id and gets an `Arc<Appearance>`
//! shared by every object of that asset.
//!
//! # What is read
//! - **glTF / GLB**: per primitive, the material's base colour factor (linear RGBA) and base
//!   colour texture (sRGB) with its `TEXCOORD_n` set, `KHR_texture_transform` and sampler;
//!   `KHR_materials_pbrSpecularGlossiness` (diffuse factor and texture stand in for the base
//!   colour); the alpha mode and cutoff; vertex colours `COLOR_0` (linear); normals. A
//!   primitive without a material gets the glTF default material (white, opaque).
//! - **OBJ / MTL**: `Kd` (linear RGB, 0.8 grey when absent, as Blender's importer does), `d`
//!   (alpha; see [`AlphaMode`]), `map_Kd`; texture coordinates (flipped to the glTF convention,
//!   `v` down); vertex colours (`v x y z r g b`, taken as linear); normals. Faces without a
//!   material get the 0.8 grey.
//! - Images are decoded with the `image` crate (PNG and JPEG) and downscaled to at most
//!   [`MAX_TEXTURE_DIMENSION`] texels per side: a 512-pixel render never needs more, and a
//!   run over many assets keeps its memory bounded.
//!
//! Every file an asset refers to (glTF buffers and image URIs, OBJ `mtllib`, `map_Kd`) is read
//! through [`crate::uri`], confined to the asset's folder and size-limited.
//!
//! # Failures
//! The mesh itself must load (the same checks as the geometry path; errors are [`IoError`]s).
//! A material library or texture that is missing, refused, too large or undecodable is **not**
//! an error: the material keeps its base colour and a `tracing` warning names the asset and
//! the file. A scene never fails to render because of a texture.
//!
//! # Frames
//! The render mesh is in the **object frame** (z up, front -y), unscaled: the same
//! conversion as the geometry ([`crate::frames::object_from_file`]), so its vertices are the
//! geometry mesh's vertices (duplicated where a vertex carries several normals or texture
//! coordinates, and without the geometry path's removal of zero-area triangles). A renderer
//! places it with the object's pose and its [`sceneeval_scene::SceneObject::scale`].

mod gltf_appearance;
mod obj_appearance;
mod texture;

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use sceneeval_geom::Rotation3;

use crate::{IoError, Limits};

pub use texture::{MAX_TEXTURE_DIMENSION, linear_to_srgb, srgb_to_linear};

/// Largest image file (or embedded image) read for a texture, in bytes; a larger one is
/// skipped with a warning.
pub const MAX_TEXTURE_FILE_BYTES: u64 = 256 << 20;

/// The look of one asset: a render mesh in the object frame and the materials its parts use.
#[derive(Debug, Clone, PartialEq)]
pub struct Appearance {
    /// The model id `PREFIX.ID`.
    pub model_id: String,
    /// The mesh file it was read from.
    pub path: PathBuf,
    /// Vertices with normals, texture coordinates and colours, in the object frame (unscaled).
    pub mesh: RenderMesh,
    /// Materials, indexed by [`MeshPart::material`].
    pub materials: Vec<Material>,
}

impl Appearance {
    /// The number of distinct decoded textures the materials use.
    pub fn texture_count(&self) -> usize {
        let mut seen: Vec<*const Texture> = Vec::new();
        for m in &self.materials {
            if let Some(t) = &m.base_color_texture {
                let p = Arc::as_ptr(&t.texture);
                if !seen.contains(&p) {
                    seen.push(p);
                }
            }
        }
        seen.len()
    }
}

/// A triangle mesh ready for a GPU: per-vertex attributes of equal length and triangles split
/// into parts of one material each.
#[derive(Clone, Default, PartialEq)]
pub struct RenderMesh {
    /// Positions in the object frame (metres).
    pub positions: Vec<[f32; 3]>,
    /// Unit normals in the object frame, or `[0, 0, 0]` where the file gives none (a renderer
    /// then shades the triangle flat, as glTF prescribes).
    pub normals: Vec<[f32; 3]>,
    /// The coordinates at which the vertex's material samples its base colour texture (glTF
    /// convention: `(0, 0)` is the image's top-left corner); `[0, 0]` when there are none.
    pub uvs: Vec<[f32; 2]>,
    /// Linear RGBA vertex colours multiplying the material's colour; `[1, 1, 1, 1]` when the
    /// file has none.
    pub colors: Vec<[f32; 4]>,
    /// Triangle vertex indices, three per triangle.
    pub indices: Vec<u32>,
    /// Consecutive index ranges drawn with one material each, covering `indices`.
    pub parts: Vec<MeshPart>,
}

impl fmt::Debug for RenderMesh {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RenderMesh")
            .field("vertices", &self.positions.len())
            .field("triangles", &(self.indices.len() / 3))
            .field("parts", &self.parts)
            .finish()
    }
}

impl RenderMesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The axis-aligned bounds `(min, max)` of the positions; `None` for an empty mesh.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        let mut lo = first;
        let mut hi = first;
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }

    /// Appends a vertex with all its attributes.
    fn push_vertex(&mut self, position: [f32; 3], normal: [f32; 3], uv: [f32; 2], color: [f32; 4]) {
        self.positions.push(position);
        self.normals.push(normal);
        self.uvs.push(uv);
        self.colors.push(color);
    }

    /// Appends triangles (indices relative to `base`) as one part of `material`.
    fn push_part(&mut self, base: u32, triangles: impl IntoIterator<Item = [u32; 3]>, material: usize) {
        let first_index = self.indices.len() as u32;
        for t in triangles {
            self.indices.extend(t.map(|i| i + base));
        }
        let index_count = self.indices.len() as u32 - first_index;
        if index_count > 0 {
            self.parts.push(MeshPart {
                first_index,
                index_count,
                material,
            });
        }
    }
}

/// A range of a [`RenderMesh`]'s indices drawn with one material.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshPart {
    /// First index (a multiple of 3).
    pub first_index: u32,
    /// Number of indices (a multiple of 3).
    pub index_count: u32,
    /// Index into [`Appearance::materials`].
    pub material: usize,
}

/// How a material's alpha is used.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is fully opaque.
    #[default]
    Opaque,
    /// Fragments with alpha below `cutoff` are not drawn; the others are opaque.
    Mask {
        /// The alpha threshold (glTF default 0.5).
        cutoff: f32,
    },
    /// The surface is blended over what lies behind it by its alpha.
    Blend,
}

/// A surface's base colour: a linear RGBA factor, optionally multiplied by an sRGB texture.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The material's name in the file, if any.
    pub name: Option<String>,
    /// Linear RGBA base colour (multiplied by the texture and the vertex colours).
    pub base_color: [f32; 4],
    /// The base colour texture, if the file names one and it could be read.
    pub base_color_texture: Option<TextureBinding>,
    /// How alpha is used.
    pub alpha_mode: AlphaMode,
}

impl Material {
    /// The glTF default material: white, opaque, untextured.
    pub fn gltf_default() -> Self {
        Material {
            name: None,
            base_color: [1.0, 1.0, 1.0, 1.0],
            base_color_texture: None,
            alpha_mode: AlphaMode::Opaque,
        }
    }

    /// The colour given to OBJ faces without a material (and MTL materials without `Kd`): 0.8
    /// grey, as Blender's OBJ importer does.
    pub fn obj_default() -> Self {
        Material {
            base_color: [0.8, 0.8, 0.8, 1.0],
            ..Material::gltf_default()
        }
    }
}

/// A decoded texture with the way it is sampled.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureBinding {
    /// The image, shared by every material that uses it.
    pub texture: Arc<Texture>,
    /// Wrapping and filtering.
    pub sampler: Sampler,
}

/// A decoded image: RGBA, 8 bits per channel, **sRGB-encoded** colour and linear alpha, rows
/// from the top.
#[derive(Clone, PartialEq)]
pub struct Texture {
    /// Where it came from (file name, URI or `image N`), for messages.
    pub label: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub pixels: Vec<u8>,
}

impl fmt::Debug for Texture {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Texture")
            .field("label", &self.label)
            .field("width", &self.width)
            .field("height", &self.height)
            .finish_non_exhaustive()
    }
}

/// How texture coordinates outside `[0, 1]` are treated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    /// The image repeats (the glTF and OBJ default).
    #[default]
    Repeat,
    /// The image repeats, mirrored every other time.
    MirroredRepeat,
    /// The edge texels extend outwards.
    ClampToEdge,
}

/// Texel filtering.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Filter {
    /// The nearest texel.
    Nearest,
    /// Bilinear interpolation.
    #[default]
    Linear,
}

/// Texture sampling parameters (glTF sampler semantics). Unspecified filters are linear with
/// linear mipmaps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Sampler {
    /// Wrapping along u (horizontal).
    pub wrap_u: Wrap,
    /// Wrapping along v (vertical).
    pub wrap_v: Wrap,
    /// Filter when a texel covers more than a pixel.
    pub magnify: Filter,
    /// Filter when a texel covers less than a pixel.
    pub minify: Filter,
    /// Filter between mipmap levels; `None` samples the full-size image only.
    pub mipmap: Option<Filter>,
}

impl Sampler {
    /// Linear filtering with linear mipmaps and the given wrapping.
    pub fn linear(wrap: Wrap) -> Self {
        Sampler {
            wrap_u: wrap,
            wrap_v: wrap,
            magnify: Filter::Linear,
            minify: Filter::Linear,
            mipmap: Some(Filter::Linear),
        }
    }
}

/// Loads the appearance of the mesh file at `path` (`.glb`, `.gltf` or `.obj`, chosen by
/// extension ignoring case) for `model_id`, converting it into the object frame with the
/// source's `alignment` (see [`crate::frames::object_from_file`]).
///
/// Most callers use [`crate::AssetLibrary::appearance`], which locates the file and caches
/// the result per model id.
///
/// # Errors
/// The mesh reader's errors ([`IoError::File`], [`IoError::BadAssetFile`],
/// [`IoError::EmptyMesh`], [`IoError::RejectedUri`] and [`IoError::TooLarge`] for buffers).
/// Problems with material libraries and textures are logged, not returned.
pub fn load_appearance(
    model_id: &str,
    path: &Path,
    alignment: Option<&Rotation3>,
    limits: &Limits,
) -> Result<Appearance, IoError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let to_object = crate::frames::object_from_file(alignment);
    let (mesh, materials) = match ext.as_str() {
        "glb" | "gltf" => gltf_appearance::load(model_id, path, &to_object, limits)?,
        "obj" => obj_appearance::load(model_id, path, &to_object, limits)?,
        _ => {
            return Err(IoError::BadAssetFile {
                path: path.to_owned(),
                message: format!("unsupported mesh format {ext:?} (expected .glb, .gltf or .obj)"),
            });
        }
    };
    if mesh.indices.is_empty() {
        return Err(IoError::EmptyMesh {
            path: path.to_owned(),
        });
    }
    let appearance = Appearance {
        model_id: model_id.to_owned(),
        path: path.to_owned(),
        mesh,
        materials,
    };
    tracing::debug!(
        model_id,
        file = %path.display(),
        vertices = appearance.mesh.vertex_count(),
        materials = appearance.materials.len(),
        textures = appearance.texture_count(),
        "appearance loaded"
    );
    Ok(appearance)
}

/// Maps a file-frame point by `m` into `f32` object-frame coordinates.
fn to_f32_point(m: &sceneeval_geom::Matrix3, p: &sceneeval_geom::Point3) -> [f32; 3] {
    let q = m * p.coords;
    [q.x as f32, q.y as f32, q.z as f32]
}

/// Normalises `n` mapped by `m`; `[0, 0, 0]` when it is zero or not finite.
fn to_f32_normal(m: &sceneeval_geom::Matrix3, n: &sceneeval_geom::Vector3) -> [f32; 3] {
    let q = m * n;
    let len = q.norm();
    if len.is_finite() && len > 1e-12 {
        let u = q / len;
        [u.x as f32, u.y as f32, u.z as f32]
    } else {
        [0.0; 3]
    }
}
