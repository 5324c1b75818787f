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
//!   against [`Limits::max_file_bytes`]. A node that is the child of several nodes is an
//!   error (invalid glTF; it would multiply the geometry).
//! - **OBJ** (`tobj` crate): `f` records triangulated, every object and group concatenated;
//!   `l` (polyline) and `p` (point) records are not faces and are dropped, so a file of lines
//!   only holds no triangles; material libraries are not read.
//!
//! Every accessor is checked against its buffer before it is read, so a corrupt file is an
//! error, never a panic. The declared vertex and triangle counts (every instance of a glTF
//! mesh counted; the `v` and `f` records of an OBJ) are checked against the triangle and
//! memory budgets of [`Limits`] before any geometry is decoded.

use std::path::{Path, PathBuf};

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use sceneeval_geom::na::Matrix4;
use sceneeval_geom::{Point3, Real};

use crate::{IoError, Limits};

/// Vertices and triangles as read from a file, in the file's coordinates.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawMesh {
    /// Vertex positions.
    pub positions: Vec<Point3>,
    /// Triangles as vertex index triples.
    pub triangles: Vec<[u32; 3]>,
    /// Every file read to build the mesh: the mesh file first, then any external glTF
    /// buffers in buffer order.
    pub files: Vec<PathBuf>,
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
/// case) within the default [`Limits`].
///
/// # Errors
/// As [`read_mesh_file_with`].
pub fn read_mesh_file(path: &Path) -> Result<RawMesh, IoError> {
    read_mesh_file_with(path, &Limits::default())
}

/// Reads the triangles of a `.glb`, `.gltf` or `.obj` file (chosen by extension, ignoring
/// case), refusing files, triangle counts and memory estimates over `limits` before
/// allocating for them.
///
/// # Errors
/// [`IoError::File`] when the file cannot be read, [`IoError::BadAssetFile`] when it cannot
/// be parsed or has an unsupported extension, [`IoError::EmptyMesh`] when it has no triangles,
/// [`IoError::TooLarge`], [`IoError::TooManyTriangles`] or [`IoError::OverMemoryBudget`] when
/// it is over a limit.
pub fn read_mesh_file_with(path: &Path, limits: &Limits) -> Result<RawMesh, IoError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let mesh = match ext.as_str() {
        "glb" | "gltf" => read_gltf(path, limits)?,
        "obj" => read_obj(path, limits)?,
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

fn read_gltf(path: &Path, limits: &Limits) -> Result<RawMesh, IoError> {
    let bytes = crate::uri::read_file_limited(path, limits.max_file_bytes)?;
    let gltf = parse_gltf(path, &bytes)?;
    let instances = mesh_instances(path, &gltf.document, limits)?;
    let (buffers, buffer_files) = load_buffers(path, &gltf, limits)?;
    let mut out = RawMesh {
        files: std::iter::once(path.to_owned()).chain(buffer_files).collect(),
        ..RawMesh::default()
    };
    for (mesh, global) in &instances {
        for prim in mesh.primitives() {
            if let Some(raw) = primitive_geometry(path, &buffers, &prim, global)? {
                out.append(raw.positions.into_iter(), raw.triangles.into_iter());
            }
        }
    }
    Ok(out)
}

/// The mesh instances of the default scene (every scene's roots if there is no default scene,
/// every root node if there are no scenes), depth first in file order, each with its node's
/// global transform. The declared vertex and triangle counts of every instance are checked
/// against `limits` as they are met, before any geometry is decoded.
///
/// # Errors
/// [`IoError::BadAssetFile`] for a node with two parents or a cyclic hierarchy;
/// [`IoError::TooManyTriangles`] or [`IoError::OverMemoryBudget`] over the limits.
pub(crate) fn mesh_instances<'a>(
    path: &Path,
    doc: &'a gltf::Document,
    limits: &Limits,
) -> Result<Vec<(gltf::Mesh<'a>, Matrix4<Real>)>, IoError> {
    // A node listed as the child of several nodes would be visited (and its geometry
    // duplicated) once per parent, exponentially in a deep enough hierarchy.
    let mut parent: Vec<Option<usize>> = vec![None; doc.nodes().len()];
    for n in doc.nodes() {
        for c in n.children() {
            if let Some(first) = parent[c.index()].replace(n.index())
                && first != n.index()
            {
                return Err(bad(
                    path,
                    format!(
                        "node {} is a child of both node {first} and node {} (invalid glTF)",
                        c.index(),
                        n.index()
                    ),
                ));
            }
        }
    }
    let mut roots: Vec<gltf::Node<'_>> = match doc.default_scene() {
        Some(scene) => scene.nodes().collect(),
        None if doc.scenes().len() > 0 => doc.scenes().flat_map(|s| s.nodes()).collect(),
        // No scenes: every node that is nobody's child is a root.
        None => doc.nodes().filter(|n| parent[n.index()].is_none()).collect(),
    };
    let mut seen_root = vec![false; doc.nodes().len()];
    roots.retain(|n| !std::mem::replace(&mut seen_root[n.index()], true));

    // The instances to read, in depth-first order, with their global transforms. A hierarchy
    // deeper than the number of nodes has a cycle (invalid glTF).
    let mut instances: Vec<(gltf::Mesh<'a>, Matrix4<Real>)> = Vec::new();
    let max_depth = doc.nodes().len();
    let mut stack: Vec<(gltf::Node<'_>, Matrix4<Real>, usize)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Matrix4::identity(), 0))
        .collect();
    let (mut vertices, mut triangles) = (0u64, 0u64);
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > max_depth {
            return Err(bad(path, "the node hierarchy has a cycle"));
        }
        let m = node.transform().matrix();
        let local = Matrix4::from_fn(|r, c| Real::from(m[c][r]));
        let global = parent * local;
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let (v, t) = declared_size(&prim);
                vertices = vertices.saturating_add(v);
                triangles = triangles.saturating_add(t);
            }
            // Checked per instance, so a mesh placed by a million nodes fails at once.
            limits.check_mesh(path, vertices, triangles)?;
            instances.push((mesh, global));
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, global, depth + 1));
        }
    }
    Ok(instances)
}

/// Parses and validates a glTF document. `gltf`'s validation indexes the accessor list with
/// a primitive's POSITION index unchecked (gltf-json 1.4.1, `mesh.rs`), so a file naming an
/// accessor that does not exist would panic there: that index is checked first.
pub(crate) fn parse_gltf(path: &Path, bytes: &[u8]) -> Result<gltf::Gltf, IoError> {
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| bad(path, e.to_string()))?;
    let json = raw.document.as_json();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
            if let Some(index) = prim.attributes.get(&position)
                && index.value() >= json.accessors.len()
            {
                return Err(bad(
                    path,
                    format!(
                        "mesh {m} primitive {p}: POSITION names accessor {} but the file has {}",
                        index.value(),
                        json.accessors.len()
                    ),
                ));
            }
        }
    }
    let blob = raw.blob;
    let document =
        gltf::Document::from_json(raw.document.into_json()).map_err(|e| bad(path, e.to_string()))?;
    Ok(gltf::Gltf { document, blob })
}

/// The vertex and triangle counts a primitive declares (zero for points and lines).
fn declared_size(prim: &gltf::Primitive<'_>) -> (u64, u64) {
    let vertices = prim
        .get(&gltf::Semantic::Positions)
        .map_or(0, |a| a.count() as u64);
    let indices = prim.indices().map_or(vertices, |a| a.count() as u64);
    let triangles = match prim.mode() {
        Mode::Triangles => indices / 3,
        Mode::TriangleStrip | Mode::TriangleFan => indices.saturating_sub(2),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => return (0, 0),
    };
    (vertices, triangles)
}

/// The glTF's buffers: the GLB blob, `data:` URIs, or files inside the asset's own folder
/// ([`crate::uri`]); never a file elsewhere. Each buffer must hold at least the `byteLength`
/// it declares. Also returns the external files read.
pub(crate) fn load_buffers(
    path: &Path,
    gltf: &gltf::Gltf,
    limits: &Limits,
) -> Result<(Vec<gltf::buffer::Data>, Vec<PathBuf>), IoError> {
    let max = limits.max_file_bytes;
    let mut blob = gltf.blob.clone();
    let mut out = Vec::with_capacity(gltf.document.buffers().len());
    let mut files = Vec::new();
    for buffer in gltf.document.buffers() {
        let declared = buffer.length() as u64;
        if declared > max {
            return Err(IoError::TooLarge {
                path: path.to_owned(),
                what: format!("buffer {}", buffer.index()),
                size: declared,
                limit: max,
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
            gltf::buffer::Source::Uri(uri) => {
                if !uri.starts_with("data:") {
                    let folder = path.parent().unwrap_or_else(|| Path::new("."));
                    files.push(crate::uri::resolve_in_folder(folder, path, uri)?);
                }
                match crate::uri::read_uri(path, uri, max) {
                    Ok(data) => data,
                    // Refusals already name this file; a missing or unreadable buffer file is
                    // reported as this file's problem, with the buffer's error as the cause.
                    Err(e @ IoError::RejectedUri { .. }) => return Err(e),
                    Err(e) => {
                        return Err(IoError::Reference {
                            path: path.to_owned(),
                            what: format!("buffer {} ({})", buffer.index(), crate::uri::quoted(uri)),
                            source: Box::new(e),
                        });
                    }
                }
            }
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
    Ok((out, files))
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
/// line primitive (skipped with a warning). Triangles are wound counter-clockwise even under
/// a mirroring `global`.
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
        files: Vec::new(),
    }))
}

/// The OBJ text without its `l` (polyline) and `p` (point) records, which `tobj` would
/// otherwise turn into triangles when they list three or more vertices; blank lines keep
/// the line numbers. Also counts the `v` records and the triangles of the `f` records (a
/// polygon of `k` corners gives `k - 2`).
pub(crate) fn obj_faces_only(text: &str) -> (String, u64, u64) {
    let mut out = String::with_capacity(text.len());
    let (mut vertices, mut triangles) = (0u64, 0u64);
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("l" | "p") => {}
            Some(keyword) => {
                if keyword == "v" {
                    vertices += 1;
                } else if keyword == "f" {
                    triangles += (words.count() as u64).saturating_sub(2);
                }
                out.push_str(line);
            }
            None => out.push_str(line),
        }
        out.push('\n');
    }
    (out, vertices, triangles)
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

fn read_obj(path: &Path, limits: &Limits) -> Result<RawMesh, IoError> {
    let bytes = crate::uri::read_file_limited(path, limits.max_file_bytes)?;
    let text = String::from_utf8_lossy(&bytes);
    let (faces_only, vertices, triangles) = obj_faces_only(&text);
    limits.check_mesh(path, vertices, triangles)?;
    let mut reader = std::io::Cursor::new(faces_only.as_bytes());
    // Material libraries are not needed for geometry: do not read them.
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &obj_options(false), |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| bad(path, e.to_string()))?;
    let mut out = RawMesh {
        files: vec![path.to_owned()],
        ..RawMesh::default()
    };
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

        // A missing buffer file is this file's error, caused by the buffer's.
        std::fs::write(&path, gltf_with_buffer_uri("missing.bin")).unwrap();
        let err = read_mesh_file(&path).unwrap_err();
        assert!(matches!(err, IoError::Reference { .. }), "{err}");
        assert!(
            err.to_string()
                .contains("a.gltf: cannot read buffer 0 (missing.bin)"),
            "{err}"
        );
        let cause = std::error::Error::source(&err).unwrap().to_string();
        assert!(cause.contains("missing.bin"), "{cause}");

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
    fn a_position_accessor_that_does_not_exist_is_an_error_not_a_panic() {
        // gltf-json 1.4.1 validation indexes the accessor list with this index unchecked.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.gltf");
        let text = gltf_with_buffer_uri("x.bin").replace(r#""POSITION":0"#, r#""POSITION":5"#);
        std::fs::write(&path, text).unwrap();
        let err = read_mesh_file(&path).unwrap_err();
        assert!(
            err.to_string()
                .contains("POSITION names accessor 5 but the file has 1"),
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
