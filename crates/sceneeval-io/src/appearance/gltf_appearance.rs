//! glTF / GLB appearance: materials, textures, vertex attributes.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use gltf::Semantic;
use gltf::accessor::{DataType, Dimensions};
use gltf::texture::{MagFilter, MinFilter, WrappingMode};
use sceneeval_geom::na::Matrix4;
use sceneeval_geom::{Matrix3, Real, Vector3};

use super::{
    AlphaMode, Filter, MAX_TEXTURE_FILE_BYTES, Material, RenderMesh, Sampler, Texture, TextureBinding, Wrap,
    texture, to_f32_normal, to_f32_point,
};
use crate::IoError;
use crate::Limits;
use crate::mesh_load::{check_accessor, load_buffers, mesh_instances, parse_gltf, primitive_geometry};

/// Which texture coordinates a material samples, and how they are transformed.
#[derive(Debug, Clone, Copy)]
struct UvSource {
    set: u32,
    /// `KHR_texture_transform` as a 2x3 affine map `uv' = m * (u, v, 1)`.
    transform: Option<[[f32; 3]; 2]>,
}

pub(super) fn load(
    model_id: &str,
    path: &Path,
    to_object: &Matrix3,
    limits: &Limits,
) -> Result<(RenderMesh, Vec<Material>), IoError> {
    let bytes = crate::uri::read_file_limited(path, limits.max_file_bytes)?;
    let gltf = parse_gltf(path, &bytes)?;
    let doc = &gltf.document;
    let instances = mesh_instances(path, doc, limits)?;
    let (buffers, _files) = load_buffers(path, &gltf, limits)?;

    let mut images = ImageCache::new(model_id, path, &buffers);
    let mut materials: Vec<Material> = Vec::with_capacity(doc.materials().len() + 1);
    let mut uv_sources: Vec<Option<UvSource>> = Vec::with_capacity(doc.materials().len() + 1);
    for m in doc.materials() {
        let (material, uv) = material(&m, &mut images);
        materials.push(material);
        uv_sources.push(uv);
    }
    let mut default_material = None;

    let mut mesh = RenderMesh::default();
    for (gltf_mesh, global) in instances {
        // Normals go through the inverse transpose of the node transform, then into the
        // object frame.
        let normal_matrix = normal_matrix(&global).map(|nm| to_object * nm);
        for prim in gltf_mesh.primitives() {
            let Some(raw) = primitive_geometry(path, &buffers, &prim, &global)? else {
                continue;
            };
            let material = match prim.material().index() {
                Some(i) if i < materials.len() => i,
                _ => *default_material.get_or_insert_with(|| {
                    materials.push(Material::gltf_default());
                    uv_sources.push(None);
                    materials.len() - 1
                }),
            };
            let (points, tris) = (raw.positions, raw.triangles);
            let n = points.len();
            let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));

            let normals: Option<Vec<[f32; 3]>> = match (prim.get(&Semantic::Normals), &normal_matrix) {
                (Some(acc), Some(nm))
                    if attribute_ok(model_id, path, "NORMAL", &acc, n, &buffers)
                        && acc.data_type() == DataType::F32
                        && acc.dimensions() == Dimensions::Vec3 =>
                {
                    reader.read_normals().map(|it| {
                        it.map(|v| {
                            let v = Vector3::new(Real::from(v[0]), Real::from(v[1]), Real::from(v[2]));
                            to_f32_normal(nm, &v)
                        })
                        .collect()
                    })
                }
                _ => None,
            };

            let uv_source = uv_sources.get(material).copied().flatten();
            let uvs: Option<Vec<[f32; 2]>> = match uv_source {
                Some(src) => match prim.get(&Semantic::TexCoords(src.set)) {
                    Some(acc) if attribute_ok(model_id, path, "TEXCOORD", &acc, n, &buffers) => {
                        reader.read_tex_coords(src.set).map(|it| {
                            it.into_f32()
                                .map(|uv| match src.transform {
                                    Some(m) => [
                                        m[0][0] * uv[0] + m[0][1] * uv[1] + m[0][2],
                                        m[1][0] * uv[0] + m[1][1] * uv[1] + m[1][2],
                                    ],
                                    None => uv,
                                })
                                .collect()
                        })
                    }
                    Some(_) => None,
                    None => {
                        tracing::warn!(
                            model_id,
                            file = %path.display(),
                            set = src.set,
                            "a textured primitive has no TEXCOORD_{} attribute; its texture is not shown",
                            src.set
                        );
                        None
                    }
                },
                None => None,
            };

            let colors: Option<Vec<[f32; 4]>> = match prim.get(&Semantic::Colors(0)) {
                Some(acc) if attribute_ok(model_id, path, "COLOR_0", &acc, n, &buffers) => {
                    reader.read_colors(0).map(|it| it.into_rgba_f32().collect())
                }
                _ => None,
            };

            let base = mesh.positions.len() as u32;
            for (i, p) in points.iter().enumerate() {
                mesh.push_vertex(
                    to_f32_point(to_object, p),
                    normals
                        .as_ref()
                        .and_then(|v| v.get(i).copied())
                        .unwrap_or([0.0; 3]),
                    uvs.as_ref().and_then(|v| v.get(i).copied()).unwrap_or([0.0; 2]),
                    colors
                        .as_ref()
                        .and_then(|v| v.get(i).copied())
                        .unwrap_or([1.0; 4]),
                );
            }
            // A textured material on a primitive without coordinates would sample one texel
            // everywhere: show its base colour instead.
            let material = if uv_source.is_some() && uvs.is_none() {
                untextured_copy(&mut materials, &mut uv_sources, material)
            } else {
                material
            };
            mesh.push_part(base, tris, material);
        }
    }
    Ok((mesh, materials))
}

/// The index of a copy of material `i` without its texture (made once per material).
fn untextured_copy(materials: &mut Vec<Material>, uv_sources: &mut Vec<Option<UvSource>>, i: usize) -> usize {
    let mut copy = materials[i].clone();
    copy.base_color_texture = None;
    if let Some(j) = materials.iter().position(|m| *m == copy) {
        return j;
    }
    materials.push(copy);
    uv_sources.push(None);
    materials.len() - 1
}

/// True when an attribute accessor can be read safely and has one element per vertex; logs a
/// warning otherwise (the attribute is then ignored, not the asset).
fn attribute_ok(
    model_id: &str,
    path: &Path,
    what: &str,
    acc: &gltf::Accessor<'_>,
    vertices: usize,
    buffers: &[gltf::buffer::Data],
) -> bool {
    if let Err(e) = check_accessor(path, what, acc, buffers) {
        tracing::warn!(model_id, file = %path.display(), error = %e, "{what} ignored");
        return false;
    }
    if acc.count() != vertices {
        tracing::warn!(
            model_id,
            file = %path.display(),
            "{what} accessor {} has {} elements for {vertices} vertices; ignored",
            acc.index(),
            acc.count()
        );
        return false;
    }
    true
}

/// The inverse transpose of the linear part of `global` (maps normals), or `None` when it is
/// singular.
fn normal_matrix(global: &Matrix4<Real>) -> Option<Matrix3> {
    let linear: Matrix3 = global.fixed_view::<3, 3>(0, 0).into_owned();
    linear.try_inverse().map(|inv| inv.transpose())
}

/// A material's base colour, texture and alpha mode, and where its texture coordinates come
/// from.
fn material(m: &gltf::Material<'_>, images: &mut ImageCache<'_>) -> (Material, Option<UvSource>) {
    let (factor, info) = match m.pbr_specular_glossiness() {
        Some(sg) => (sg.diffuse_factor(), sg.diffuse_texture()),
        None => {
            let pbr = m.pbr_metallic_roughness();
            (pbr.base_color_factor(), pbr.base_color_texture())
        }
    };
    let alpha_mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask {
            cutoff: m.alpha_cutoff().unwrap_or(0.5),
        },
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    let mut material = Material {
        name: m.name().map(str::to_owned),
        base_color: factor.map(|c| if c.is_finite() { c.clamp(0.0, 1.0) } else { 1.0 }),
        base_color_texture: None,
        alpha_mode,
    };
    let Some(info) = info else {
        return (material, None);
    };
    let transform = info.texture_transform();
    let set = transform
        .as_ref()
        .and_then(|t| t.tex_coord())
        .unwrap_or_else(|| info.tex_coord());
    let texture = info.texture();
    let Some(image) = images.get(texture.source().index(), &texture.source()) else {
        return (material, None);
    };
    material.base_color_texture = Some(TextureBinding {
        texture: image,
        sampler: sampler(&texture.sampler()),
    });
    let transform = transform.map(|t| {
        // KHR_texture_transform: uv' = T(offset) * R(rotation) * S(scale) * uv, with
        // R = [[cos, sin], [-sin, cos]].
        let (s, c) = t.rotation().sin_cos();
        let [sx, sy] = t.scale();
        let [ox, oy] = t.offset();
        [[c * sx, s * sy, ox], [-s * sx, c * sy, oy]]
    });
    (material, Some(UvSource { set, transform }))
}

fn sampler(s: &gltf::texture::Sampler<'_>) -> Sampler {
    let wrap = |w: WrappingMode| match w {
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::Repeat => Wrap::Repeat,
    };
    let magnify = match s.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        _ => Filter::Linear,
    };
    let (minify, mipmap) = match s.min_filter() {
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) | None => (Filter::Linear, Some(Filter::Linear)),
    };
    Sampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        magnify,
        minify,
        mipmap,
    }
}

/// Decodes each glTF image at most once per asset; a failure is logged once and remembered.
struct ImageCache<'a> {
    model_id: &'a str,
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    decoded: HashMap<usize, Option<Arc<Texture>>>,
}

impl<'a> ImageCache<'a> {
    fn new(model_id: &'a str, path: &'a Path, buffers: &'a [gltf::buffer::Data]) -> Self {
        ImageCache {
            model_id,
            path,
            buffers,
            decoded: HashMap::new(),
        }
    }

    fn get(&mut self, index: usize, image: &gltf::Image<'_>) -> Option<Arc<Texture>> {
        if let Some(t) = self.decoded.get(&index) {
            return t.clone();
        }
        let label = match image.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => uri.to_owned(),
            _ => format!("image {index}"),
        };
        let result = self
            .bytes(image)
            .and_then(|bytes| texture::decode(label.clone(), &bytes));
        let texture = match result {
            Ok(t) => Some(Arc::new(t)),
            Err(reason) => {
                tracing::warn!(
                    model_id = self.model_id,
                    file = %self.path.display(),
                    texture = %label,
                    "texture not used, the base colour is shown instead: {reason}"
                );
                None
            }
        };
        self.decoded.insert(index, texture.clone());
        texture
    }

    /// The encoded bytes of an image: a slice of a buffer view, a `data:` URI or a file inside
    /// the asset's folder.
    fn bytes(&self, image: &gltf::Image<'_>) -> Result<Vec<u8>, String> {
        match image.source() {
            gltf::image::Source::View { view, .. } => {
                let data = self
                    .buffers
                    .get(view.buffer().index())
                    .ok_or_else(|| format!("buffer {} does not exist", view.buffer().index()))?;
                let end = view.offset().checked_add(view.length());
                match end {
                    Some(end) if end <= data.len() => {
                        if view.length() as u64 > MAX_TEXTURE_FILE_BYTES {
                            return Err(format!(
                                "the image holds {} bytes, over the limit of {MAX_TEXTURE_FILE_BYTES}",
                                view.length()
                            ));
                        }
                        Ok(data[view.offset()..end].to_vec())
                    }
                    _ => Err(format!(
                        "buffer view {} reads outside buffer {}",
                        view.index(),
                        view.buffer().index()
                    )),
                }
            }
            gltf::image::Source::Uri { uri, .. } => {
                crate::uri::read_uri(self.path, uri, MAX_TEXTURE_FILE_BYTES).map_err(|e| e.to_string())
            }
        }
    }
}
