//! Reading generators' files: folders, JSON with pointers (through `sceneeval-io`'s walker, so
//! errors name the file and pointer as the sceneState reader's do).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use sceneeval_io::AssetLibrary;
use sceneeval_io::scene_state::json_in::{self, Doc, ptr_key};
use serde_json::{Map, Value};

use crate::ConvertError;

/// The sub-folders of `dir` as `(name, path)`, sorted by name (names that are not UTF-8 are
/// skipped with a warning).
pub(crate) fn subfolders(dir: &Path) -> Result<Vec<(String, PathBuf)>, ConvertError> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| ConvertError::input(dir, format!("cannot list the folder: {e}")))?;
    let mut out = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| ConvertError::input(dir, format!("cannot list the folder: {e}")))?;
        let path = entry.path();
        if !path.is_dir() {
            continue;
        }
        match entry.file_name().into_string() {
            Ok(name) => out.push((name, path)),
            Err(name) => tracing::warn!(folder = ?name, "folder name is not UTF-8; ignored"),
        }
    }
    out.sort();
    Ok(out)
}

/// The parsed JSON file at `path`, within the library's file-size limit.
pub(crate) fn read_json(path: &Path, library: &AssetLibrary) -> Result<Value, ConvertError> {
    Ok(json_in::read_json_file(path, library.limits().max_file_bytes)?)
}

/// A Unity-style `{"x": .., "y": .., "z": ..}` vector: all three finite numbers required, or
/// (with `default`) each missing one taken from it.
pub(crate) fn xyz(
    doc: &Doc<'_>,
    v: &Value,
    ptr: &str,
    default: Option<[f64; 3]>,
) -> Result<[f64; 3], ConvertError> {
    let o = doc.object(v, ptr)?;
    let mut out = [0.0; 3];
    for (k, key) in ["x", "y", "z"].into_iter().enumerate() {
        out[k] = match (json_in::optional(o, key), default) {
            (Some(x), _) => doc.number(x, &ptr_key(ptr, key))?,
            (None, Some(d)) => d[k],
            (None, None) => {
                return Err(sceneeval_io::IoError::MissingField {
                    path: doc.path_buf(),
                    pointer: ptr.to_owned(),
                    field: ["x", "y", "z"][k],
                }
                .into());
            }
        };
    }
    Ok(out)
}

/// An optional string field.
pub(crate) fn text<'v>(
    doc: &Doc<'_>,
    o: &'v Map<String, Value>,
    ptr: &str,
    key: &str,
) -> Result<Option<&'v str>, ConvertError> {
    Ok(json_in::optional(o, key)
        .map(|v| doc.string(v, &ptr_key(ptr, key)))
        .transpose()?)
}

/// The object ids of a generator's file met so far, each with the pointer of its object.
pub(crate) struct Ids<'d> {
    doc: Doc<'d>,
    seen: HashMap<String, String>,
}

impl<'d> Ids<'d> {
    /// No id met yet in `doc`.
    pub(crate) fn new(doc: &Doc<'d>) -> Self {
        Ids {
            doc: *doc,
            seen: HashMap::new(),
        }
    }

    /// The object at `ptr` has `id`, which no earlier object may have.
    ///
    /// # Errors
    /// [`sceneeval_io::IoError::DuplicateObjectId`] naming the file, the id and both objects.
    pub(crate) fn add(&mut self, id: &str, ptr: &str) -> Result<(), ConvertError> {
        match self.seen.get(id) {
            Some(first) => Err(duplicate(&self.doc, id, first, ptr)),
            None => {
                self.seen.insert(id.to_owned(), ptr.to_owned());
                Ok(())
            }
        }
    }
}

/// Two objects of the file of `doc` (at `first` and `second`) have the id `id`.
pub(crate) fn duplicate(doc: &Doc<'_>, id: &str, first: &str, second: &str) -> ConvertError {
    sceneeval_io::IoError::DuplicateObjectId {
        path: doc.path_buf(),
        id: id.to_owned(),
        first: first.to_owned(),
        second: second.to_owned(),
    }
    .into()
}
