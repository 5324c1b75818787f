use std::path::PathBuf;

use sceneeval_geom::GeomError;
use sceneeval_scene::SceneError;
use thiserror::Error;

/// Everything that can go wrong reading or writing scenes and assets.
///
/// Every variant says which input was wrong and where: the file (`path`), the RFC 6901 JSON
/// pointer of the offending value inside a sceneState file (`pointer`, e.g.
/// `/scene/object/3/transform/data/12`), and/or the asset's model id. Errors raised while
/// loading an asset for a scene object are wrapped in [`IoError::ObjectAsset`], which adds the
/// scene file and the object's pointer to the asset error (see [`std::error::Error::source`]).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoError {
    /// Reading, creating or writing a file failed.
    #[error("{}: {source}", .path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The text is not valid JSON.
    #[error("{}:{line}:{column}: malformed JSON: {message}", .path.display())]
    MalformedJson {
        /// The file.
        path: PathBuf,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// What the parser expected.
        message: String,
    },
    /// A JSON object gives one key twice: readers keep one of the two silently (serde_json
    /// and Python's `json` the last), so the file does not say which value it means.
    #[error("{}:{line}:{column}: {pointer}: key {key:?} appears twice in one object", .path.display(),
        pointer = if .pointer.is_empty() { "/" } else { .pointer.as_str() })]
    DuplicateKey {
        /// The file.
        path: PathBuf,
        /// Pointer to the object holding the key twice (empty for the document's root).
        pointer: String,
        /// The repeated key.
        key: String,
        /// 1-based line of the second occurrence.
        line: usize,
        /// 1-based column of the second occurrence.
        column: usize,
    },
    /// Keys a sceneState file has where the format knows no such key, refused because the
    /// reading was strict ([`crate::ReadOptions::strict`]); otherwise each is a warning. A
    /// misspelt key is read as absent, which can change the scene silently (an object whose
    /// `"transfrom"` is misspelt would stand at the origin).
    #[error("{}: {}", .path.display(), unknown_keys_message(.keys))]
    UnknownKeys {
        /// The file.
        path: PathBuf,
        /// Each unknown key once per place in the format, in document order.
        keys: Vec<crate::scene_state::UnknownKey>,
    },
    /// An object entry has no `transform`: it would stand at the origin, which is never what
    /// a generator means (the reference takes the identity silently).
    #[error("{}: {pointer}: object {id:?} (index {index}) has no \"transform\"{}", .path.display(),
        if .similar.is_empty() { String::new() } else { format!(" (it has the unknown key {:?})", .similar) })]
    MissingTransform {
        /// The file.
        path: PathBuf,
        /// Pointer to the object entry.
        pointer: String,
        /// The object's `index` (its position in the list when it has none).
        index: i64,
        /// The object's id (its `objectId`, or the derived `idx<index>_<modelId>`).
        id: String,
        /// An unknown key of the entry that looks like a misspelt `transform`, or empty.
        similar: String,
    },
    /// A required field is absent.
    #[error("{}: {pointer}: missing field {field:?}", .path.display())]
    MissingField {
        /// The file.
        path: PathBuf,
        /// Pointer to the JSON object that lacks the field.
        pointer: String,
        /// The field's name.
        field: &'static str,
    },
    /// A value has the wrong JSON type (or the wrong number of elements).
    #[error("{}: {pointer}: expected {expected}, found {found}", .path.display())]
    WrongType {
        /// The file.
        path: PathBuf,
        /// Pointer to the value.
        pointer: String,
        /// What was expected, e.g. `a number` or `an array of 16 numbers`.
        expected: &'static str,
        /// What was found, e.g. `a string` or `an array of 12 elements`.
        found: String,
    },
    /// A value has the right type but is not acceptable (non-finite, unknown enum value,
    /// too few points, ...).
    #[error("{}: {pointer}: {reason}", .path.display())]
    InvalidValue {
        /// The file.
        path: PathBuf,
        /// Pointer to the value.
        pointer: String,
        /// What is wrong with it.
        reason: String,
    },
    /// An object's `transform.data` cannot be turned into a pose (not finite, not affine,
    /// singular, or with shear).
    #[error("{}: {pointer}: bad transform: {reason}", .path.display())]
    BadTransform {
        /// The file.
        path: PathBuf,
        /// Pointer to the transform's `data` array (or one of its elements).
        pointer: String,
        /// What is wrong with it.
        reason: String,
    },
    /// Two object entries produce the same object id.
    #[error("{}: object id {id:?} is used by both {first} and {second}", .path.display())]
    DuplicateObjectId {
        /// The file.
        path: PathBuf,
        /// The repeated id.
        id: String,
        /// Pointer to the first object entry with that id.
        first: String,
        /// Pointer to the second one.
        second: String,
    },
    /// Two elements of one kind (e.g. two `Floor`s) claim the same room, or two walls share
    /// an id.
    #[error("{}: {pointer}: {what} (first given at {first})", .path.display())]
    DuplicateElement {
        /// The file.
        path: PathBuf,
        /// Pointer to the second element.
        pointer: String,
        /// Pointer to the first element.
        first: String,
        /// What is duplicated, e.g. `second Floor for room "r0"`.
        what: String,
    },
    /// The scene model rejected an element (zero-length wall, bad floor polygon, ...).
    #[error("{}: {pointer}: {source}", .path.display())]
    Scene {
        /// The file.
        path: PathBuf,
        /// Pointer to the element that caused the error.
        pointer: String,
        /// The scene model's error.
        #[source]
        source: SceneError,
    },
    /// An asset could not be loaded for the object at `pointer`.
    #[error("{}: {pointer}: cannot load asset {model_id:?}", .path.display())]
    ObjectAsset {
        /// The scene file.
        path: PathBuf,
        /// Pointer to the object entry.
        pointer: String,
        /// The object's model id.
        model_id: String,
        /// The asset error.
        #[source]
        source: Box<IoError>,
    },
    /// Assets of a scene that no source has a file for: every one of the scene, so that they
    /// can be fetched at once (the message lists the first [`MAX_LISTED_ASSETS`] with the
    /// objects using each and the files looked for, and counts the rest).
    #[error("{}: {}", .path.display(), missing_assets_message(.missing))]
    MissingAssets {
        /// The scene file.
        path: PathBuf,
        /// Each missing asset once, in the order of its first object.
        missing: Vec<MissingAsset>,
    },
    /// A model id is not of the form `PREFIX.ID`.
    #[error("model id {model_id:?} is not of the form PREFIX.ID")]
    BadModelId {
        /// The model id.
        model_id: String,
    },
    /// An asset id does not have the form its source's layout needs (e.g. the
    /// `scene_<ID>__<object id>` of the `idesign` and `scene-agent` layouts).
    #[error("model id {model_id:?}: the asset id must be {expected}")]
    BadAssetId {
        /// The model id.
        model_id: String,
        /// The form expected.
        expected: &'static str,
    },
    /// No asset source is registered for a model id's prefix.
    #[error("model id {model_id:?}: no asset source for prefix {prefix:?} (registered: {})",
        if .registered.is_empty() { "none".to_owned() } else { .registered.join(", ") })]
    UnknownPrefix {
        /// The model id.
        model_id: String,
        /// Its prefix.
        prefix: String,
        /// The prefixes that are registered.
        registered: Vec<String>,
    },
    /// An asset source has no file for an asset id.
    #[error("asset {model_id:?} not found (looked for {})",
        .tried.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", "))]
    AssetNotFound {
        /// The model id.
        model_id: String,
        /// The paths that were tried.
        tried: Vec<PathBuf>,
    },
    /// An asset file could not be parsed (corrupt GLB/glTF/OBJ, unsupported extension).
    #[error("{}: cannot read mesh: {message}", .path.display())]
    BadAssetFile {
        /// The asset file.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
    /// A file an asset refers to (a glTF buffer or image, an OBJ material library or texture)
    /// was refused: its URI has a scheme, is absolute, is malformed, or leads outside the
    /// asset's folder (see [`crate::uri`]). The message quotes the URI, never file contents.
    #[error("{}: refused to read {uri:?}: {reason}", .path.display())]
    RejectedUri {
        /// The file that holds the URI.
        path: PathBuf,
        /// The URI as written (shortened when long).
        uri: String,
        /// Why it was refused.
        reason: String,
    },
    /// A file an asset refers to (an external glTF buffer) could not be read; the cause names
    /// that file.
    #[error("{}: cannot read {what}", .path.display())]
    Reference {
        /// The asset file that refers to it.
        path: PathBuf,
        /// What was referred to, e.g. `buffer 0 ("tri.bin")`.
        what: String,
        /// Why it could not be read.
        #[source]
        source: Box<IoError>,
    },
    /// A file or a declared size is over a limit, checked before anything is allocated for it.
    #[error("{}: the {what} holds {size} bytes, over the limit of {limit}", .path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// What is too large (`file`, `buffer 0`, ...).
        what: String,
        /// Its size in bytes.
        size: u64,
        /// The limit in bytes.
        limit: u64,
    },
    /// An asset has more triangles than [`crate::Limits::max_triangles`] allows (every
    /// instance of a mesh counted), found from the declared sizes before decoding.
    #[error("{}: the asset has {triangles} triangles, over the budget of {limit}", .path.display())]
    TooManyTriangles {
        /// The asset file.
        path: PathBuf,
        /// Its triangle count.
        triangles: u64,
        /// The budget.
        limit: u64,
    },
    /// Loading an asset would need more memory than [`crate::Limits::max_asset_memory_bytes`]
    /// allows (estimated from the declared sizes before decoding).
    #[error("{}: loading {vertices} vertices and {triangles} triangles needs about {estimate} bytes, over the budget of {limit}", .path.display())]
    OverMemoryBudget {
        /// The asset file.
        path: PathBuf,
        /// Its vertex count.
        vertices: u64,
        /// Its triangle count.
        triangles: u64,
        /// The estimated peak memory in bytes.
        estimate: u64,
        /// The budget in bytes.
        limit: u64,
    },
    /// A text file (a scene file) is not valid UTF-8.
    #[error("{}:{line}:{column}: not valid UTF-8 (byte offset {offset})", .path.display())]
    InvalidUtf8 {
        /// The file.
        path: PathBuf,
        /// Offset of the first invalid byte from the start of the file.
        offset: usize,
        /// 1-based line of that byte.
        line: usize,
        /// 1-based column (in bytes) of that byte.
        column: usize,
    },
    /// An asset file holds no triangles.
    #[error("{}: the file holds no triangles", .path.display())]
    EmptyMesh {
        /// The asset file.
        path: PathBuf,
    },
    /// An asset's geometry was rejected (non-finite vertices, out-of-range indices, every
    /// triangle degenerate).
    #[error("{}: {source}", .path.display())]
    AssetGeometry {
        /// The asset file.
        path: PathBuf,
        /// The geometric problem.
        #[source]
        source: GeomError,
    },
    /// An asset metadata file (`model_info.json`, `annotations.json`, `fpmodels.csv`,
    /// `data.json`, a sidecar `ID.json`) is malformed.
    #[error("{}: {location}: {message}", .path.display())]
    BadMetadata {
        /// The metadata file.
        path: PathBuf,
        /// Where in the file: a JSON pointer, or `row N` / `row N, column C` for CSV.
        location: String,
        /// What is wrong.
        message: String,
    },
    /// An `--assets` specification could not be parsed.
    #[error("bad asset specification {spec:?}: {reason}")]
    BadAssetSpec {
        /// The specification as given.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A scale for an asset mesh has a zero or non-finite component.
    #[error("asset {model_id:?}: scale {scale:?} must be finite and non-zero along every axis")]
    BadScale {
        /// The model id.
        model_id: String,
        /// The scale asked for (object frame).
        scale: [f64; 3],
    },
    /// A scene object could not be made (e.g. its pose is not finite).
    #[error("object {object:?}: {source}")]
    BadObject {
        /// The object's id.
        object: String,
        /// The scene model's error.
        #[source]
        source: SceneError,
    },
    /// A scene object cannot be written to a sceneState file.
    #[error("object {object:?} cannot be written: {reason}")]
    Unwritable {
        /// The object's id (or the room/wall id for architecture).
        object: String,
        /// Why.
        reason: String,
    },
    /// A mesh handed to the GLB writer is invalid.
    #[error("GLB mesh {name:?}: {reason}")]
    BadGlbMesh {
        /// The mesh's name.
        name: String,
        /// What is wrong with it.
        reason: String,
    },
}

/// The most missing assets [`IoError::MissingAssets`] lists in its message (all are kept in
/// the error).
pub const MAX_LISTED_ASSETS: usize = 20;

/// An asset of a scene that was not found, and the objects that use it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MissingAsset {
    /// The model id (`PREFIX.ID`).
    pub model_id: String,
    /// JSON pointers of the objects using it, in scene order (`/scene/object/3`).
    pub objects: Vec<String>,
    /// The files looked for.
    pub tried: Vec<PathBuf>,
}

fn unknown_keys_message(keys: &[crate::scene_state::UnknownKey]) -> String {
    let mut text = format!(
        "{} the sceneState format does not have (strict reading):",
        plural(keys.len(), "unknown key")
    );
    for k in keys {
        text.push_str(&format!("\n  {k}"));
    }
    text
}

fn missing_assets_message(missing: &[MissingAsset]) -> String {
    let objects: usize = missing.iter().map(|m| m.objects.len()).sum();
    let mut text = format!(
        "{} not found, used by {} (every missing asset of the scene is listed):",
        plural(missing.len(), "asset"),
        plural(objects, "object")
    );
    for m in missing.iter().take(MAX_LISTED_ASSETS) {
        let first = m.objects.first().map_or("", String::as_str);
        let more = match m.objects.len() {
            0 | 1 => String::new(),
            n => format!(" and {}", plural(n - 1, "more object")),
        };
        let tried: Vec<String> = m.tried.iter().map(|p| p.display().to_string()).collect();
        text.push_str(&format!(
            "\n  {:?} for {first}{more}: looked for {}",
            m.model_id,
            tried.join(", ")
        ));
    }
    if missing.len() > MAX_LISTED_ASSETS {
        text.push_str(&format!(
            "\n  and {}",
            plural(missing.len() - MAX_LISTED_ASSETS, "more asset")
        ));
    }
    text
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

impl IoError {
    pub(crate) fn file(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        IoError::File {
            path: path.into(),
            source,
        }
    }

    /// Decodes `bytes` read from `path` as UTF-8, naming the byte offset, line and column of
    /// the first invalid byte otherwise.
    pub(crate) fn utf8<'b>(path: &std::path::Path, bytes: &'b [u8]) -> Result<&'b str, IoError> {
        std::str::from_utf8(bytes).map_err(|e| {
            let offset = e.valid_up_to();
            let before = &bytes[..offset];
            let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
            let line_start = before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
            IoError::InvalidUtf8 {
                path: path.to_owned(),
                offset,
                line,
                column: offset - line_start + 1,
            }
        })
    }

    /// The JSON pointer the error refers to, if it refers to a place in a sceneState file.
    pub fn pointer(&self) -> Option<&str> {
        match self {
            IoError::MissingField { pointer, .. }
            | IoError::WrongType { pointer, .. }
            | IoError::InvalidValue { pointer, .. }
            | IoError::BadTransform { pointer, .. }
            | IoError::DuplicateKey { pointer, .. }
            | IoError::MissingTransform { pointer, .. }
            | IoError::DuplicateElement { pointer, .. }
            | IoError::Scene { pointer, .. }
            | IoError::ObjectAsset { pointer, .. } => Some(pointer),
            IoError::DuplicateObjectId { second, .. } => Some(second),
            IoError::UnknownKeys { keys, .. } => keys.first().map(|k| k.pointer.as_str()),
            _ => None,
        }
    }

    /// The file the error refers to (the scene file for scene errors, the asset or metadata
    /// file for asset errors), if any.
    pub fn path(&self) -> Option<&std::path::Path> {
        match self {
            IoError::File { path, .. }
            | IoError::MalformedJson { path, .. }
            | IoError::DuplicateKey { path, .. }
            | IoError::UnknownKeys { path, .. }
            | IoError::MissingTransform { path, .. }
            | IoError::MissingField { path, .. }
            | IoError::WrongType { path, .. }
            | IoError::InvalidValue { path, .. }
            | IoError::BadTransform { path, .. }
            | IoError::DuplicateObjectId { path, .. }
            | IoError::DuplicateElement { path, .. }
            | IoError::Scene { path, .. }
            | IoError::ObjectAsset { path, .. }
            | IoError::MissingAssets { path, .. }
            | IoError::BadAssetFile { path, .. }
            | IoError::RejectedUri { path, .. }
            | IoError::Reference { path, .. }
            | IoError::TooLarge { path, .. }
            | IoError::TooManyTriangles { path, .. }
            | IoError::OverMemoryBudget { path, .. }
            | IoError::InvalidUtf8 { path, .. }
            | IoError::EmptyMesh { path }
            | IoError::AssetGeometry { path, .. }
            | IoError::BadMetadata { path, .. } => Some(path),
            _ => None,
        }
    }
}
