//! Reading triangle meshes from GLB/glTF and OBJ files, in the file's own coordinates.
//!
//! - **glTF / GLB** (`gltf` crate): the default scene's node hierarchy (every scene's roots if
//!   there is no default scene, every root node if there are no scenes) is flattened, each
//!   node's global transform baked into its mesh's positions (with the triangle winding
//!   reversed under a mirroring transform), and every triangle primitive concatenated
//!   (indexed or not; strips and fans converted). Point and line primitives are skipped with a
//!   warning. Textures are never decoded: only the buffers are loaded, from the GLB binary
//!   chunk, `data:` URIs, or files inside the asset's own folder ([`crate::uri`]); a buffer
//!   URI that leads anywhere else is an error, and no file is read before its size is checked
//!   against [`MAX_ASSET_FILE_BYTES`].
//! - **OBJ** (`tobj` crate): faces triangulated, every object and group concatenated; material
//!   libraries are not read.
//!
//! Every accessor is checked against its buffer before it is read, so a corrupt file is an
//! error, never a panic.

use std::path::Path;

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use sceneeval_geom::na::Matrix4;
use sceneeval_geom::{Point3, Real};

use crate::IoError;

/// Vertices and triangles as read from a file, in the file's coordinates.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawMesh {
    /// Vertex positions.
    pub positions: Vec<Point3>,
    /// Triangles as vertex index triples.
    pub triangles: Vec<[u32; 3]>,
}

impl RawMesh {
    fn append(&mut self, positions: impl Iterator<Item = Point3>, triangles: impl Iterator<Item = [u32; 3]>) {
        let base = self.positions.len() as u32;
        self.positions.extend(positions);
        self.triangles
            .extend(triangles.map(|t| [t[0] + base, t[1] + base, t[2] + base]));
    }
}

/// Reads the triangles of a `.glb`, `.gltf` or `.obj` file (chosen by extension, ignoring
/// case).
///
/// # Errors
/// [`IoError::File`] when the file cannot be read, [`IoError::BadAssetFile`] when it cannot
/// be parsed or has an unsupported extension, [`IoError::EmptyMesh`] when it has no triangles.
pub fn read_mesh_file(path: &Path) -> Result<RawMesh, IoError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let mesh = match ext.as_str() {
        "glb" | "gltf" => read_gltf(path)?,
        "obj" => read_obj(path)?,
        _ => {
            return Err(IoError::BadAssetFile {
                path: path.to_owned(),
                message: format!("unsupported mesh format {ext:?} (expected .glb, .gltf or .obj)"),
            });
        }
    };
    if mesh.triangles.is_empty() {
        return Err(IoError::EmptyMesh {
            path: path.to_owned(),
        });
    }
    Ok(mesh)
}

pub(crate) fn bad(path: &Path, message: impl Into<String>) -> IoError {
    IoError::BadAssetFile {
        path: path.to_owned(),
        message: message.into(),
    }
}

fn read_gltf(path: &Path) -> Result<RawMesh, IoError> {
    let bytes = crate::uri::read_file_limited(path, MAX_ASSET_FILE_BYTES)?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| bad(path, e.to_string()))?;
    let buffers = load_buffers(path, &gltf)?;
    let mut out = RawMesh::default();
    for (node, global) in mesh_nodes(path, &gltf.document)? {
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if let Some(raw) = primitive_geometry(path, &buffers, &prim, &global)? {
                    out.append(raw.positions.into_iter(), raw.triangles.into_iter());
                }
            }
        }
    }
    Ok(out)
}

/// The nodes of the default scene (every scene's roots if there is no default scene, every
/// root node if there are no scenes) that carry a mesh, depth first in file order, each with
/// its global transform.
pub(crate) fn mesh_nodes<'a>(
    path: &Path,
    doc: &'a gltf::Document,
) -> Result<Vec<(gltf::Node<'a>, Matrix4<Real>)>, IoError> {
    let roots: Vec<gltf::Node<'_>> = match doc.default_scene() {
        Some(scene) => scene.nodes().collect(),
        None if doc.scenes().len() > 0 => doc.scenes().flat_map(|s| s.nodes()).collect(),
        None => {
            // No scenes: every node that is nobody's child is a root.
            let mut is_child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            doc.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut out = Vec::new();
    // Depth-first with an explicit stack; a hierarchy deeper than the number of nodes has a
    // cycle (invalid glTF).
    let max_depth = doc.nodes().len();
    let mut stack: Vec<(gltf::Node<'_>, Matrix4<Real>, usize)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Matrix4::identity(), 0))
        .collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > max_depth {
            return Err(bad(path, "the node hierarchy has a cycle"));
        }
        let m = node.transform().matrix();
        let local = Matrix4::from_fn(|r, c| Real::from(m[c][r]));
        let global = parent * local;
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, global, depth + 1));
        }
        if node.mesh().is_some() {
            out.push((node, global));
        }
    }
    Ok(out)
}

/// Largest asset file, external buffer or embedded buffer read (bytes). A larger one is
/// refused before anything is allocated for it.
pub const MAX_ASSET_FILE_BYTES: u64 = 1 << 30;

/// The glTF's buffers: the GLB blob, `data:` URIs, or files inside the asset's own folder
/// ([`crate::uri`]); never a file elsewhere. Each buffer must hold at least the `byteLength`
/// it declares.
pub(crate) fn load_buffers(path: &Path, gltf: &gltf::Gltf) -> Result<Vec<gltf::buffer::Data>, IoError> {
    let mut blob = gltf.blob.clone();
    let mut out = Vec::with_capacity(gltf.document.buffers().len());
    for buffer in gltf.document.buffers() {
        let declared = buffer.length() as u64;
        if declared > MAX_ASSET_FILE_BYTES {
            return Err(IoError::TooLarge {
                path: path.to_owned(),
                what: format!("buffer {}", buffer.index()),
                size: declared,
                limit: MAX_ASSET_FILE_BYTES,
            });
        }
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                bad(
                    path,
                    format!(
                        "buffer {} refers to a GLB binary chunk the file does not have",
                        buffer.index()
                    ),
                )
            })?,
            gltf::buffer::Source::Uri(uri) => crate::uri::read_uri(path, uri, MAX_ASSET_FILE_BYTES)?,
        };
        if (data.len() as u64) < declared {
            return Err(bad(
                path,
                format!(
                    "buffer {} declares {declared} bytes but holds {}",
                    buffer.index(),
                    data.len()
                ),
            ));
        }
        // Pad to 4 bytes, as `gltf::import_buffers` does.
        while data.len() % 4 != 0 {
            data.push(0);
        }
        out.push(gltf::buffer::Data(data));
    }
    Ok(out)
}

/// Checks that reading `count` elements of `size` bytes through `accessor` stays inside its
/// buffer, so that the `gltf` reader can neither panic nor silently stop early.
pub(crate) fn check_accessor(
    path: &Path,
    what: &str,
    accessor: &gltf::Accessor<'_>,
    buffers: &[gltf::buffer::Data],
) -> Result<(), IoError> {
    if accessor.sparse().is_some() {
        return Err(bad(
            path,
            format!("{what} accessor {} is sparse (not supported)", accessor.index()),
        ));
    }
    let Some(view) = accessor.view() else {
        return Err(bad(
            path,
            format!("{what} accessor {} has no buffer view", accessor.index()),
        ));
    };
    let count = accessor.count();
    if count == 0 {
        return Err(bad(
            path,
            format!("{what} accessor {} is empty", accessor.index()),
        ));
    }
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if stride < size {
        return Err(bad(
            path,
            format!(
                "{what} accessor {}: stride {stride} is less than the element size {size}",
                accessor.index()
            ),
        ));
    }
    let buffer_len = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
    let view_end = view.offset().checked_add(view.length());
    let end = stride
        .checked_mul(count - 1)
        .and_then(|v| v.checked_add(size))
        .and_then(|v| v.checked_add(accessor.offset()));
    match (view_end, end) {
        (Some(view_end), Some(end)) if view_end <= buffer_len && end <= view.length() => Ok(()),
        _ => Err(bad(
            path,
            format!(
                "{what} accessor {} reads outside its buffer (view {} of {} bytes at offset {}, buffer of {} bytes)",
                accessor.index(),
                view.index(),
                view.length(),
                view.offset(),
                buffer_len
            ),
        )),
    }
}

/// The vertices (transformed by `global`) and triangles of a triangle primitive, in the order
/// the file stores them (triangles index the primitive's own vertices); `None` for a point or
/// line primitive (skipped with a warning).
/// Triangles are wound counter-clockwise even under a mirroring `global`.
pub(crate) fn primitive_geometry(
    path: &Path,
    buffers: &[gltf::buffer::Data],
    prim: &gltf::Primitive<'_>,
    global: &Matrix4<Real>,
) -> Result<Option<RawMesh>, IoError> {
    let mode = prim.mode();
    if matches!(
        mode,
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
    ) {
        tracing::warn!(file = %path.display(), ?mode, "skipping a point or line primitive");
        return Ok(None);
    }
    let Some(positions) = prim.get(&gltf::Semantic::Positions) else {
        return Err(bad(path, "a triangle primitive has no POSITION attribute"));
    };
    if positions.data_type() != DataType::F32 || positions.dimensions() != Dimensions::Vec3 {
        return Err(bad(
            path,
            format!(
                "POSITION accessor {} is {:?} {:?}; only float VEC3 is supported",
                positions.index(),
                positions.data_type(),
                positions.dimensions()
            ),
        ));
    }
    check_accessor(path, "POSITION", &positions, buffers)?;
    let indices_accessor = prim.indices();
    if let Some(acc) = &indices_accessor {
        if !matches!(acc.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
            || acc.dimensions() != Dimensions::Scalar
        {
            return Err(bad(
                path,
                format!(
                    "index accessor {} is {:?} {:?}; expected unsigned integer scalars",
                    acc.index(),
                    acc.data_type(),
                    acc.dimensions()
                ),
            ));
        }
        check_accessor(path, "index", acc, buffers)?;
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let Some(read) = reader.read_positions() else {
        return Err(bad(path, "cannot read positions"));
    };
    let points: Vec<Point3> = read
        .map(|p| global.transform_point(&Point3::new(Real::from(p[0]), Real::from(p[1]), Real::from(p[2]))))
        .collect();
    let n = points.len();
    let indices: Vec<u32> = match &indices_accessor {
        Some(_) => match reader.read_indices() {
            Some(read) => read.into_u32().collect(),
            None => return Err(bad(path, "cannot read indices")),
        },
        None => (0..n as u32).collect(),
    };
    if let Some(&i) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(bad(path, format!("index {i} is out of range ({n} vertices)")));
    }
    let mut tris = triangles(mode, &indices);
    if global.fixed_view::<3, 3>(0, 0).determinant() < 0.0 {
        for t in &mut tris {
            t.swap(1, 2);
        }
    }
    Ok(Some(RawMesh {
        positions: points,
        triangles: tris,
    }))
}

/// Triangles of a triangle list, strip or fan.
fn triangles(mode: Mode, idx: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (2..idx.len())
            .map(|i| {
                if i % 2 == 0 {
                    [idx[i - 2], idx[i - 1], idx[i]]
                } else {
                    [idx[i - 1], idx[i - 2], idx[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..idx.len()).map(|i| [idx[0], idx[i - 1], idx[i]]).collect(),
        _ => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    }
}

/// tobj options: faces triangulated, points and lines ignored; `single_index` gives one index
/// per vertex for positions, normals and texture coordinates together.
pub(crate) fn obj_options(single_index: bool) -> tobj::LoadOptions {
    // The struct update covers fields that exist only with some tobj features.
    #[allow(clippy::needless_update)]
    tobj::LoadOptions {
        triangulate: true,
        single_index,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    }
}

/// Checks that every index of an OBJ model names one of its vertices.
pub(crate) fn check_obj_indices(path: &Path, model: &tobj::Model) -> Result<(), IoError> {
    let m = &model.mesh;
    let n = m.positions.len() / 3;
    match m.indices.iter().find(|&&i| i as usize >= n) {
        Some(&i) => Err(bad(
            path,
            format!(
                "object {:?}: index {i} is out of range ({n} vertices)",
                model.name
            ),
        )),
        None => Ok(()),
    }
}

fn read_obj(path: &Path) -> Result<RawMesh, IoError> {
    let file = std::fs::File::open(path).map_err(|e| IoError::file(path, e))?;
    let mut reader = std::io::BufReader::new(file);
    // Material libraries are not needed for geometry: do not read them.
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &obj_options(false), |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| bad(path, e.to_string()))?;
    let mut out = RawMesh::default();
    for model in &models {
        check_obj_indices(path, model)?;
        let m = &model.mesh;
        out.append(
            m.positions
                .chunks_exact(3)
                .map(|p| Point3::new(Real::from(p[0]), Real::from(p[1]), Real::from(p[2]))),
            m.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]),
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{GlbMesh, write_glb};

    #[test]
    fn strips_and_fans_become_triangles() {
        assert_eq!(
            triangles(Mode::TriangleStrip, &[0, 1, 2, 3, 4]),
            vec![[0, 1, 2], [2, 1, 3], [2, 3, 4]]
        );
        assert_eq!(
            triangles(Mode::TriangleFan, &[0, 1, 2, 3]),
            vec![[0, 1, 2], [0, 2, 3]]
        );
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 3, 4]), vec![[0, 1, 2]]);
    }

    #[test]
    fn reads_back_a_written_glb() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.GLB");
        let a = GlbMesh::new(
            "a",
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![0, 1, 2],
        );
        let b = GlbMesh::new(
            "b",
            vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
            vec![0, 2, 1],
        );
        write_glb(&path, &[a, b]).unwrap();
        let m = read_mesh_file(&path).unwrap();
        assert_eq!(m.positions.len(), 6);
        assert_eq!(m.triangles, vec![[0, 1, 2], [3, 5, 4]]);
        assert_eq!(m.positions[4], Point3::new(1.0, 0.0, 1.0));
    }

    #[test]
    fn reads_obj_groups_and_polygons() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("q.obj");
        let text = "mtllib missing.mtl\no a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n\
                    o b\nv 0 0 2\nv 1 0 2\nv 0 1 2\nf 5 6 7\nl 1 2\n";
        std::fs::write(&path, text).unwrap();
        let m = read_mesh_file(&path).unwrap();
        // A quad (two triangles) and a triangle; the line is ignored.
        assert_eq!(m.triangles.len(), 3);
        assert_eq!(m.positions.len(), 7);
        let zs: Vec<f64> = m.triangles[2]
            .iter()
            .map(|&i| m.positions[i as usize].z)
            .collect();
        assert_eq!(zs, [2.0, 2.0, 2.0]);
    }

    /// A `.gltf` with one triangle whose buffer is the file `uri`.
    fn gltf_with_buffer_uri(uri: &str) -> String {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"scene":0,
            "nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
            "min":[0,0,0],"max":[1,1,0]}}],"bufferViews":[{{"buffer":0,"byteLength":36}}],
            "buffers":[{{"uri":{uri:?},"byteLength":36}}]}}"#
        )
    }

    fn triangle_bytes() -> Vec<u8> {
        [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect()
    }

    #[test]
    fn gltf_buffers_are_read_only_inside_the_asset_folder() {
        let root = tempfile::tempdir().unwrap();
        let folder = root.path().join("asset");
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(folder.join("tri.bin"), triangle_bytes()).unwrap();
        std::fs::write(root.path().join("outside.bin"), triangle_bytes()).unwrap();
        let path = folder.join("a.gltf");

        std::fs::write(&path, gltf_with_buffer_uri("tri.bin")).unwrap();
        assert_eq!(read_mesh_file(&path).unwrap().triangles.len(), 1);

        let outside = root.path().join("outside.bin").display().to_string();
        for uri in [
            "../outside.bin".to_owned(),
            "%2e%2e/outside.bin".to_owned(),
            outside.clone(),
            format!("file://{outside}"),
        ] {
            std::fs::write(&path, gltf_with_buffer_uri(&uri)).unwrap();
            let err = read_mesh_file(&path).unwrap_err();
            assert!(matches!(err, IoError::RejectedUri { .. }), "{uri}: {err}");
        }

        // A buffer shorter than it declares is an error, not a short read.
        std::fs::write(folder.join("short.bin"), &triangle_bytes()[..20]).unwrap();
        std::fs::write(&path, gltf_with_buffer_uri("short.bin")).unwrap();
        let err = read_mesh_file(&path).unwrap_err();
        assert!(
            err.to_string().contains("declares 36 bytes but holds 20"),
            "{err}"
        );
    }

    #[test]
    fn corrupt_and_empty_files_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let glb = dir.path().join("bad.glb");
        std::fs::write(&glb, b"glTF\x02\x00\x00\x00garbage").unwrap();
        assert!(matches!(read_mesh_file(&glb), Err(IoError::BadAssetFile { .. })));
        let obj = dir.path().join("empty.obj");
        std::fs::write(&obj, "v 0 0 0\nv 1 0 0\n").unwrap();
        assert!(matches!(read_mesh_file(&obj), Err(IoError::EmptyMesh { .. })));
        let obj = dir.path().join("bad.obj");
        std::fs::write(&obj, "v 0 0 0\nf 1 2 3\n").unwrap();
        assert!(matches!(read_mesh_file(&obj), Err(IoError::BadAssetFile { .. })));
        let other = dir.path().join("x.ply");
        std::fs::write(&other, "ply").unwrap();
        assert!(matches!(
            read_mesh_file(&other),
            Err(IoError::BadAssetFile { .. })
        ));
        assert!(matches!(
            read_mesh_file(&dir.path().join("missing.glb")),
            Err(IoError::File { .. })
        ));
    }
}
