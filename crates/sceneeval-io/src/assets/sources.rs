//! The five directory layouts.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use sceneeval_geom::{Matrix3, Rotation3, Vector3};
use serde_json::Value;

use super::{AssetInfo, AssetLocation, AssetSource, Layout};
use crate::IoError;

/// A metadata problem, kept so that every lookup can report it (an [`IoError`] is not `Clone`).
#[derive(Debug, Clone)]
pub(super) struct MetadataError {
    path: PathBuf,
    location: String,
    message: String,
}

impl MetadataError {
    pub(super) fn new(path: &Path, location: impl Into<String>, message: impl Into<String>) -> Self {
        MetadataError {
            path: path.to_owned(),
            location: location.into(),
            message: message.into(),
        }
    }

    pub(super) fn to_io(&self) -> IoError {
        IoError::BadMetadata {
            path: self.path.clone(),
            location: self.location.clone(),
            message: self.message.clone(),
        }
    }
}

/// Metadata read once, on first use.
type Lazy<T> = OnceLock<Result<HashMap<String, T>, MetadataError>>;

fn lazy_get<T>(
    cell: &Lazy<T>,
    load: impl FnOnce() -> Result<HashMap<String, T>, MetadataError>,
) -> Result<&HashMap<String, T>, IoError> {
    cell.get_or_init(load).as_ref().map_err(MetadataError::to_io)
}

/// Reads a JSON metadata file of at most [`crate::Limits::default`]'s `max_file_bytes`;
/// `Ok(None)` when it does not exist.
pub(super) fn read_json(path: &Path) -> Result<Option<Value>, MetadataError> {
    let bytes = match crate::uri::read_file_limited(path, crate::Limits::default().max_file_bytes) {
        Ok(b) => b,
        Err(IoError::File { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
            return Ok(None);
        }
        Err(IoError::File { source, .. }) => {
            return Err(MetadataError::new(path, "file", source.to_string()));
        }
        Err(IoError::TooLarge { size, limit, .. }) => {
            return Err(MetadataError::new(
                path,
                "file",
                format!("the file holds {size} bytes, over the limit of {limit}"),
            ));
        }
        Err(e) => return Err(MetadataError::new(path, "file", e.to_string())),
    };
    serde_json::from_slice::<Value>(&bytes).map(Some).map_err(|e| {
        MetadataError::new(
            path,
            format!("line {} column {}", e.line(), e.column()),
            format!("malformed JSON: {e}"),
        )
    })
}

/// A non-empty string field.
fn text<'a>(v: &'a Value, key: &str) -> Option<&'a str> {
    v.get(key)
        .and_then(Value::as_str)
        .map(str::trim)
        .filter(|s| !s.is_empty())
}

/// `head - dash, rest...`, leaving out missing parts (the reference's description strings,
/// without its `None` placeholders, quirk Q30).
fn describe(head: Option<&str>, dash: Option<&str>, rest: &[Option<&str>]) -> Option<String> {
    let mut out = head.unwrap_or_default().to_owned();
    if let Some(d) = dash {
        if !out.is_empty() {
            out.push_str(" - ");
        }
        out.push_str(d);
    }
    for r in rest.iter().flatten() {
        if !out.is_empty() {
            out.push_str(", ");
        }
        out.push_str(r);
    }
    (!out.is_empty()).then_some(out)
}

pub(super) fn not_found(model_id: &str, tried: Vec<PathBuf>) -> IoError {
    IoError::AssetNotFound {
        model_id: model_id.to_owned(),
        tried,
    }
}

/// The first of `tried` that exists, which must be a regular file (a named pipe or a folder
/// of that name is an error saying so, not a missing asset).
pub(super) fn mesh_file(model_id: &str, tried: Vec<PathBuf>) -> Result<PathBuf, IoError> {
    for path in &tried {
        match sceneeval_files::check_regular(path) {
            Ok(_) => return Ok(path.clone()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(IoError::file(path, e)),
        }
    }
    Err(not_found(model_id, tried))
}

folder_source! {
    /// 3D-FUTURE: `ROOT/ID/raw_model.obj`; metadata `ROOT/model_info.json`, a list of objects with
    /// `model_id`, `category`, `super-category`, `style`, `theme`, `material`.
    ///
    /// Category = `category` (else `super-category`); description = `category - super-category,
    /// style, theme, material` with missing fields left out.
    ThreeDFutureSource, Layout::ThreeDFuture, { metadata: Lazy<AssetInfo> = OnceLock::new() }
}

impl ThreeDFutureSource {
    fn load_metadata(&self) -> Result<HashMap<String, AssetInfo>, MetadataError> {
        let path = self.root.join("model_info.json");
        let Some(doc) = read_json(&path)? else {
            tracing::warn!(file = %path.display(), "3D-FUTURE metadata not found; assets get no category");
            return Ok(HashMap::new());
        };
        let Some(items) = doc.as_array() else {
            return Err(MetadataError::new(&path, "/", "expected a list of models"));
        };
        let mut out = HashMap::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let Some(id) = text(item, "model_id") else {
                return Err(MetadataError::new(&path, format!("/{i}"), "missing \"model_id\""));
            };
            let category = text(item, "category").or_else(|| text(item, "super-category"));
            let description = describe(
                text(item, "category"),
                text(item, "super-category"),
                &[text(item, "style"), text(item, "theme"), text(item, "material")],
            );
            out.insert(
                id.to_owned(),
                AssetInfo {
                    category: category.map(str::to_owned),
                    description,
                },
            );
        }
        Ok(out)
    }

    fn find(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
        let path = mesh_file(model_id, vec![self.root.join(asset_id).join("raw_model.obj")])?;
        let info = lazy_get(&self.metadata, || self.load_metadata())?
            .get(asset_id)
            .cloned()
            .unwrap_or_default();
        Ok(AssetLocation {
            path,
            info,
            alignment: None,
            metadata: vec![self.root.join("model_info.json")],
        })
    }
}

folder_source! {
    /// Objathor (Holodeck's Objaverse assets): `ROOT/ID/ID.glb`; metadata `ROOT/annotations.json`,
    /// an object keyed by asset id with `category`, `ref_category`, `description`,
    /// `description_auto`.
    ///
    /// Category = `category`; description = `category - ref_category, description` (or
    /// `description_auto` when `description` is empty).
    ObjathorSource, Layout::Objathor, { metadata: Lazy<AssetInfo> = OnceLock::new() }
}

impl ObjathorSource {
    fn load_metadata(&self) -> Result<HashMap<String, AssetInfo>, MetadataError> {
        let path = self.root.join("annotations.json");
        let Some(doc) = read_json(&path)? else {
            tracing::warn!(file = %path.display(), "Objathor annotations not found; assets get no category");
            return Ok(HashMap::new());
        };
        let Some(map) = doc.as_object() else {
            return Err(MetadataError::new(
                &path,
                "/",
                "expected an object keyed by asset id",
            ));
        };
        Ok(map
            .iter()
            .map(|(id, item)| {
                let desc = text(item, "description").or_else(|| text(item, "description_auto"));
                let info = AssetInfo {
                    category: text(item, "category").map(str::to_owned),
                    description: describe(text(item, "category"), text(item, "ref_category"), &[desc]),
                };
                (id.clone(), info)
            })
            .collect())
    }

    fn find(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
        let path = mesh_file(
            model_id,
            vec![self.root.join(asset_id).join(format!("{asset_id}.glb"))],
        )?;
        let info = lazy_get(&self.metadata, || self.load_metadata())?
            .get(asset_id)
            .cloned()
            .unwrap_or_default();
        Ok(AssetLocation {
            path,
            info,
            alignment: None,
            metadata: vec![self.root.join("annotations.json")],
        })
    }
}

/// One row of HSSD's `fpmodels.csv`.
#[derive(Debug, Clone)]
struct HssdRow {
    line: u64,
    info: AssetInfo,
    up: Option<(usize, String)>,
    front: Option<(usize, String)>,
}

folder_source! {
    /// HSSD: `ROOT/glb/<first char of ID>/ID.glb`, or `ROOT/decomposed/<ID up to the first _>/ID.glb`
    /// for ids containing `part`; metadata `ROOT/fpmodels.csv` with columns `id`, `wnsynsetkey`,
    /// `name`, `up`, `front` (others ignored).
    ///
    /// Category = `wnsynsetkey`; description = `wnsynsetkey - name` (`generic object category`
    /// when `wnsynsetkey` is empty, as in the reference).
    ///
    /// **Alignment.** A row with non-empty `up` and `front` (comma-separated vectors in the file's
    /// coordinates) gets the rotation that sends the declared up to +y and the declared front to
    /// +z, so the asset is in the standard y-up, front-+z convention before the usual conversion.
    /// (The reference builds a different matrix that does not send every up/front pair to the
    /// canonical pose and applies it in different frames in its two scene representations; quirk
    /// Q28.)
    HssdSource, Layout::Hssd, { metadata: Lazy<HssdRow> = OnceLock::new() }
}

impl HssdSource {
    fn load_metadata(&self) -> Result<HashMap<String, HssdRow>, MetadataError> {
        let path = self.root.join("fpmodels.csv");
        if !path.exists() {
            tracing::warn!(file = %path.display(), "HSSD metadata not found; assets get no category or alignment");
            return Ok(HashMap::new());
        }
        let file = sceneeval_files::open_regular(&path)
            .map_err(|e| MetadataError::new(&path, "file", e.to_string()))?;
        let mut reader = csv::Reader::from_reader(std::io::BufReader::new(file));
        let headers = reader
            .headers()
            .map_err(|e| MetadataError::new(&path, "row 1", e.to_string()))?
            .clone();
        let column = |name: &str| headers.iter().position(|h| h.trim() == name);
        let Some(id_col) = column("id") else {
            return Err(MetadataError::new(&path, "row 1", "no \"id\" column"));
        };
        let (syn_col, name_col, up_col, front_col) = (
            column("wnsynsetkey"),
            column("name"),
            column("up"),
            column("front"),
        );
        let mut out = HashMap::new();
        for record in reader.records() {
            let record = record.map_err(|e| {
                let line = e.position().map_or(0, |p| p.line());
                MetadataError::new(&path, format!("row {line}"), e.to_string())
            })?;
            let line = record.position().map_or(0, |p| p.line());
            let field = |col: Option<usize>| {
                col.and_then(|c| record.get(c))
                    .map(str::trim)
                    .filter(|s| !s.is_empty())
            };
            let Some(id) = field(Some(id_col)) else {
                continue;
            };
            let synset = field(syn_col);
            let name = field(name_col);
            let info = AssetInfo {
                category: synset.map(str::to_owned),
                description: describe(Some(synset.unwrap_or("generic object category")), name, &[]),
            };
            let with_col = |col: Option<usize>| {
                let c = col?;
                field(Some(c)).map(|s| (c + 1, s.to_owned()))
            };
            out.insert(
                id.to_owned(),
                HssdRow {
                    line,
                    info,
                    up: with_col(up_col),
                    front: with_col(front_col),
                },
            );
        }
        Ok(out)
    }
}

/// The rotation sending `up` to +y and `front` to +z (front is first made orthogonal to up).
pub(crate) fn alignment_from_up_front(up: &Vector3, front: &Vector3) -> Result<Rotation3, String> {
    let u = up
        .try_normalize(1e-12)
        .ok_or_else(|| format!("up {up:?} has zero length"))?;
    let f = (front - u * u.dot(front))
        .try_normalize(1e-9)
        .ok_or_else(|| format!("front {front:?} is parallel to up {up:?}"))?;
    let r = u.cross(&f);
    // Rows r, u, f: r -> +x, u -> +y, f -> +z (right-handed, since x = y cross z).
    Ok(Rotation3::from_matrix_unchecked(Matrix3::from_rows(&[
        r.transpose(),
        u.transpose(),
        f.transpose(),
    ])))
}

fn parse_vector(s: &str) -> Option<Vector3> {
    let parts: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .ok()?;
    (parts.len() == 3 && parts.iter().all(|v| v.is_finite()))
        .then(|| Vector3::new(parts[0], parts[1], parts[2]))
}

impl HssdSource {
    fn find(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
        let path = if asset_id.contains("part") {
            let base = asset_id.split('_').next().unwrap_or(asset_id);
            self.root
                .join("decomposed")
                .join(base)
                .join(format!("{asset_id}.glb"))
        } else {
            let first: String = asset_id.chars().take(1).collect();
            self.root.join("glb").join(first).join(format!("{asset_id}.glb"))
        };
        let path = mesh_file(model_id, vec![path])?;
        let csv_path = self.root.join("fpmodels.csv");
        let Some(row) = lazy_get(&self.metadata, || self.load_metadata())?.get(asset_id) else {
            return Ok(AssetLocation {
                path,
                info: AssetInfo::default(),
                alignment: None,
                metadata: vec![csv_path],
            });
        };
        let alignment = match (&row.up, &row.front) {
            (Some((up_col, up)), Some((front_col, front))) => {
                let vector = |col: usize, s: &str| {
                    parse_vector(s).ok_or_else(|| IoError::BadMetadata {
                        path: csv_path.clone(),
                        location: format!("row {}, column {col}", row.line),
                        message: format!("{s:?} is not three comma-separated numbers"),
                    })
                };
                let (u, f) = (vector(*up_col, up)?, vector(*front_col, front)?);
                Some(
                    alignment_from_up_front(&u, &f).map_err(|message| IoError::BadMetadata {
                        path: csv_path.clone(),
                        location: format!("row {}", row.line),
                        message,
                    })?,
                )
            }
            _ => None,
        };
        Ok(AssetLocation {
            path,
            info: row.info.clone(),
            alignment,
            metadata: vec![csv_path],
        })
    }
}

folder_source! {
    /// LayoutVLM's Objathor subset: `ROOT/ID/ID.glb`; metadata `ROOT/ID/data.json` with an
    /// `annotations` object holding `category`, `description`, `materials`.
    ///
    /// Category = `category`; description = `category, description, materials`. A missing
    /// `data.json` leaves the asset without metadata (the reference refuses to load it).
    LayoutVlmSource, Layout::LayoutVlm, {}
}

impl LayoutVlmSource {
    fn find(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
        let dir = self.root.join(asset_id);
        let path = mesh_file(model_id, vec![dir.join(format!("{asset_id}.glb"))])?;
        let data_path = dir.join("data.json");
        let info = match read_json(&data_path).map_err(|e| e.to_io())? {
            None => AssetInfo::default(),
            Some(doc) => {
                let Some(a) = doc.get("annotations").filter(|a| a.is_object()) else {
                    return Err(IoError::BadMetadata {
                        path: data_path,
                        location: "/annotations".into(),
                        message: "missing \"annotations\" object".into(),
                    });
                };
                AssetInfo {
                    category: text(a, "category").map(str::to_owned),
                    description: describe(
                        text(a, "category"),
                        None,
                        &[text(a, "description"), text(a, "materials")],
                    ),
                }
            }
        };
        Ok(AssetLocation {
            path,
            info,
            alignment: None,
            metadata: vec![data_path],
        })
    }
}

folder_source! {
    /// A plain folder: `ROOT/ID.glb`, `ROOT/ID.gltf` or `ROOT/ID.obj` (the first that exists), with
    /// an optional sidecar `ROOT/ID.json` = `{"category": "...", "description": "..."}` (both
    /// optional). The generated fixtures use this layout.
    PlainFolderSource, Layout::Plain, {}
}

impl PlainFolderSource {
    fn find(&self, model_id: &str, asset_id: &str) -> Result<AssetLocation, IoError> {
        let tried: Vec<PathBuf> = ["glb", "gltf", "obj"]
            .iter()
            .map(|ext| self.root.join(format!("{asset_id}.{ext}")))
            .collect();
        let path = mesh_file(model_id, tried)?;
        let sidecar = self.root.join(format!("{asset_id}.json"));
        let info = match read_json(&sidecar).map_err(|e| e.to_io())? {
            None => AssetInfo::default(),
            Some(doc) => {
                if !doc.is_object() {
                    return Err(IoError::BadMetadata {
                        path: sidecar,
                        location: "/".into(),
                        message: "expected {\"category\": ..., \"description\": ...}".into(),
                    });
                }
                for key in ["category", "description"] {
                    if let Some(v) = doc.get(key).filter(|v| !v.is_null() && !v.is_string()) {
                        return Err(IoError::BadMetadata {
                            path: sidecar,
                            location: format!("/{key}"),
                            message: format!("expected a string, found {v}"),
                        });
                    }
                }
                AssetInfo {
                    category: text(&doc, "category").map(str::to_owned),
                    description: text(&doc, "description").map(str::to_owned),
                }
            }
        };
        Ok(AssetLocation {
            path,
            info,
            alignment: None,
            metadata: vec![sidecar],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptions_skip_missing_parts() {
        assert_eq!(
            describe(
                Some("Bed"),
                Some("King-size Bed"),
                &[Some("Modern"), None, Some("Wood")]
            )
            .as_deref(),
            Some("Bed - King-size Bed, Modern, Wood")
        );
        assert_eq!(describe(None, Some("x"), &[Some("y")]).as_deref(), Some("x, y"));
        assert_eq!(describe(None, None, &[]), None);
    }

    #[test]
    fn alignment_sends_declared_axes_to_canonical_ones() {
        // The reference's failing case (Q28): up = +y, front = +x must give front -> +z.
        for (up, front) in [
            (Vector3::y(), Vector3::x()),
            (Vector3::z(), -Vector3::y()),
            (Vector3::new(0.0, 0.0, 2.0), Vector3::new(1.0, 0.1, 0.0)),
            (Vector3::y(), Vector3::z()),
        ] {
            let r = alignment_from_up_front(&up, &front).unwrap();
            assert!((r * up.normalize() - Vector3::y()).norm() < 1e-12, "{up} {front}");
            let f = (front - up.normalize() * up.normalize().dot(&front)).normalize();
            assert!((r * f - Vector3::z()).norm() < 1e-12, "{up} {front}");
            assert!((r.matrix().determinant() - 1.0).abs() < 1e-12);
        }
        // Already canonical: the identity.
        let r = alignment_from_up_front(&Vector3::y(), &Vector3::z()).unwrap();
        assert!((r.matrix() - Matrix3::identity()).norm() < 1e-15);
        assert!(alignment_from_up_front(&Vector3::zeros(), &Vector3::z()).is_err());
        assert!(alignment_from_up_front(&Vector3::y(), &Vector3::y()).is_err());
    }

    #[test]
    fn vectors_parse_from_csv_cells() {
        assert_eq!(parse_vector("0, 1,0"), Some(Vector3::y()));
        assert_eq!(parse_vector("0,1"), None);
        assert_eq!(parse_vector("a,b,c"), None);
    }
}
