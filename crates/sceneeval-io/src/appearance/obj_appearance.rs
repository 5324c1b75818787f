//! OBJ / MTL appearance.

use std::collections::HashMap;
use std::io::{BufReader, Cursor};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use sceneeval_geom::{Matrix3, Point3, Real, Vector3};

use super::{
    AlphaMode, MAX_TEXTURE_FILE_BYTES, Material, RenderMesh, Sampler, Texture, TextureBinding, Wrap, texture,
    to_f32_normal, to_f32_point,
};
use crate::mesh_load::{bad, check_obj_indices, obj_faces_only, obj_options};
use crate::{IoError, Limits};

pub(super) fn load(
    model_id: &str,
    path: &Path,
    to_object: &Matrix3,
    limits: &Limits,
) -> Result<(RenderMesh, Vec<Material>), IoError> {
    let bytes = crate::uri::read_file_limited(path, limits.max_file_bytes)?;
    // `l` and `p` records are not faces; the counts are checked before anything is decoded.
    let (faces_only, vertices, triangles) = obj_faces_only(&String::from_utf8_lossy(&bytes));
    limits.check_mesh(path, vertices, triangles)?;
    let options = obj_options(true);
    // Material libraries are read through `crate::uri`, confined to the asset's folder; the
    // directory of each library is remembered so that its texture paths resolve against it.
    let libraries = std::sync::Mutex::new(Vec::<String>::new());
    let loader = |mtl: &Path| -> tobj::MTLLoadResult {
        let name = mtl.to_string_lossy().replace('\\', "/");
        let text = crate::uri::read_uri(path, &name, limits.max_file_bytes).map_err(|e| {
            tracing::warn!(model_id, file = %path.display(), library = %name, error = %e,
                "material library not read; faces keep the default grey");
            tobj::LoadError::OpenFileFailed
        })?;
        let result = tobj::load_mtl_buf(&mut BufReader::new(Cursor::new(text)));
        match &result {
            Ok((materials, _)) => {
                if let Ok(mut libs) = libraries.lock() {
                    libs.extend(std::iter::repeat_n(name.clone(), materials.len()));
                }
            }
            Err(e) => tracing::warn!(model_id, file = %path.display(), library = %name, error = ?e,
                "material library not parsed; faces keep the default grey"),
        }
        result
    };
    let (models, mtl) = tobj::load_obj_buf(&mut BufReader::new(Cursor::new(faces_only)), &options, loader)
        .map_err(|e| bad(path, e.to_string()))?;
    let libraries = libraries.into_inner().unwrap_or_default();
    let mtl_materials = mtl.unwrap_or_default();

    let mut textures: HashMap<PathBuf, Option<Arc<Texture>>> = HashMap::new();
    let mut materials: Vec<Material> = mtl_materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let library = libraries.get(i).map(String::as_str).unwrap_or("");
            material(model_id, path, library, m, &mut textures)
        })
        .collect();
    let mut default_material = None;

    let mut mesh = RenderMesh::default();
    for model in &models {
        check_obj_indices(path, model)?;
        let m = &model.mesh;
        let n = m.positions.len() / 3;
        let attribute = |what: &str, data: &[f32], width: usize| -> bool {
            if data.is_empty() {
                return false;
            }
            if data.len() != n * width {
                tracing::warn!(model_id, file = %path.display(), object = %model.name,
                    "{what} do not match the {n} vertices; ignored");
                return false;
            }
            true
        };
        let has_normals = attribute("normals", &m.normals, 3);
        let has_uvs = attribute("texture coordinates", &m.texcoords, 2);
        let has_colors = attribute("vertex colours", &m.vertex_color, 3);
        let material = match m.material_id {
            Some(i) if i < materials.len() => i,
            _ => *default_material.get_or_insert_with(|| {
                materials.push(Material::obj_default());
                materials.len() - 1
            }),
        };
        let base = mesh.positions.len() as u32;
        for v in 0..n {
            let p = Point3::new(
                Real::from(m.positions[3 * v]),
                Real::from(m.positions[3 * v + 1]),
                Real::from(m.positions[3 * v + 2]),
            );
            let normal = if has_normals {
                let nv = Vector3::new(
                    Real::from(m.normals[3 * v]),
                    Real::from(m.normals[3 * v + 1]),
                    Real::from(m.normals[3 * v + 2]),
                );
                to_f32_normal(to_object, &nv)
            } else {
                [0.0; 3]
            };
            // OBJ puts v = 0 at the bottom of the image, glTF at the top.
            let uv = if has_uvs {
                [m.texcoords[2 * v], 1.0 - m.texcoords[2 * v + 1]]
            } else {
                [0.0; 2]
            };
            let color = if has_colors {
                [
                    m.vertex_color[3 * v],
                    m.vertex_color[3 * v + 1],
                    m.vertex_color[3 * v + 2],
                    1.0,
                ]
            } else {
                [1.0; 4]
            };
            mesh.push_vertex(to_f32_point(to_object, &p), normal, uv, color);
        }
        let material = if !has_uvs && materials[material].base_color_texture.is_some() {
            let mut copy = materials[material].clone();
            copy.base_color_texture = None;
            materials.push(copy);
            materials.len() - 1
        } else {
            material
        };
        mesh.push_part(
            base,
            m.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]),
            material,
        );
    }
    Ok((mesh, materials))
}

/// An MTL material: `Kd`, `d` and `map_Kd`. `library` is the material library's path as
/// written in the OBJ (texture paths are relative to its folder).
fn material(
    model_id: &str,
    obj: &Path,
    library: &str,
    m: &tobj::Material,
    textures: &mut HashMap<PathBuf, Option<Arc<Texture>>>,
) -> Material {
    let mut material = Material::obj_default();
    material.name = Some(m.name.clone()).filter(|n| !n.is_empty());
    if let Some(kd) = m.diffuse {
        for (k, c) in kd.iter().enumerate() {
            material.base_color[k] = if c.is_finite() { c.clamp(0.0, 1.0) } else { 0.8 };
        }
    }
    match m.dissolve {
        Some(d) if d.is_finite() && d > 0.0 && d < 1.0 => {
            material.base_color[3] = d;
            material.alpha_mode = AlphaMode::Blend;
        }
        Some(d) if d <= 0.0 => {
            // Fully transparent materials are almost always exporter mistakes (`d 0` written
            // for "no transparency"); showing them is more useful than hiding the object.
            tracing::warn!(model_id, file = %obj.display(), material = %m.name,
                "material has d = {d} (fully transparent); drawn opaque");
        }
        _ => {}
    }
    let Some(map) = m.diffuse_texture.as_deref().and_then(texture_file_name) else {
        return material;
    };
    let folder = obj.parent().unwrap_or_else(|| Path::new("."));
    let relative = match library.rsplit_once('/') {
        Some((dir, _)) => format!("{dir}/{map}"),
        None => map.clone(),
    };
    let result = crate::uri::resolve_in_folder(folder, obj, &relative).map_err(|e| e.to_string());
    let texture = match result {
        Ok(file) => textures
            .entry(file.clone())
            .or_insert_with(|| {
                let decoded = crate::uri::read_file_limited(&file, MAX_TEXTURE_FILE_BYTES)
                    .map_err(|e| e.to_string())
                    .and_then(|bytes| texture::decode(map.clone(), &bytes));
                match decoded {
                    Ok(t) => Some(Arc::new(t)),
                    Err(reason) => {
                        tracing::warn!(model_id, file = %obj.display(), texture = %map,
                            "texture not used, the base colour is shown instead: {reason}");
                        None
                    }
                }
            })
            .clone(),
        Err(reason) => {
            tracing::warn!(model_id, file = %obj.display(), texture = %map,
                "texture not used, the base colour is shown instead: {reason}");
            None
        }
    };
    if let Some(texture) = texture {
        material.base_color_texture = Some(TextureBinding {
            texture,
            sampler: Sampler::linear(Wrap::Repeat),
        });
    }
    material
}

/// The file name of a `map_Kd` statement: options such as `-s 1 1 1` or `-bm 0.5` come first
/// and the file name last; Windows separators become `/`.
fn texture_file_name(value: &str) -> Option<String> {
    let value = value.trim();
    let name = if value.starts_with('-') {
        value.split_whitespace().last()?
    } else {
        value
    };
    let name = name.replace('\\', "/");
    (!name.is_empty()).then_some(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_statements_keep_the_file_name() {
        assert_eq!(texture_file_name("texture.png").as_deref(), Some("texture.png"));
        assert_eq!(
            texture_file_name("my texture.png").as_deref(),
            Some("my texture.png")
        );
        assert_eq!(
            texture_file_name("-s 1 1 1 -bm 0.2 wood.jpg").as_deref(),
            Some("wood.jpg")
        );
        assert_eq!(
            texture_file_name("textures\\wood.jpg").as_deref(),
            Some("textures/wood.jpg")
        );
        assert_eq!(texture_file_name("  "), None);
    }
}
