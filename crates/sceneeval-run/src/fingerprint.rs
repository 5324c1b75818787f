//! Fingerprints of everything a scene's result depends on, so that a re-run reuses a result
//! only when nothing it depends on changed.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use sceneeval_io::AssetLibrary;
use sceneeval_results::{AssetDigest, FileDigest, Fingerprint, Preset, RECORD_SCHEMA, TOOL_VERSION};
use sceneeval_scene::Scene;

/// Hashes files once per run (a metadata file shared by thousands of assets is read once).
#[derive(Debug, Default)]
pub struct Fingerprints {
    cache: Mutex<HashMap<PathBuf, Option<String>>>,
}

impl Fingerprints {
    /// An empty cache.
    pub fn new() -> Self {
        Fingerprints::default()
    }

    /// The digest of a file, `None` when it does not exist or cannot be read.
    pub fn file(&self, path: &Path) -> FileDigest {
        let cached = self
            .cache
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .get(path)
            .cloned();
        let hash = match cached {
            Some(h) => h,
            None => {
                let h = FileDigest::of(path).blake3;
                self.cache
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .insert(path.to_owned(), h.clone());
                h
            }
        };
        FileDigest {
            path: path.display().to_string(),
            blake3: hash,
        }
    }

    /// The fingerprint of a scene just loaded from `scene_file` through `assets`.
    pub fn of_loaded(
        &self,
        scene_file: &Path,
        scene: &Scene,
        assets: &AssetLibrary,
        plan_digest: &str,
        preset: Preset,
        annotation: Option<String>,
    ) -> Fingerprint {
        let model_ids: BTreeSet<&str> = scene.objects().iter().filter_map(|o| o.model_id()).collect();
        let assets = model_ids
            .into_iter()
            // Box objects may name a model id that is never loaded.
            .filter_map(|id| assets.loaded(id))
            .map(|a| AssetDigest {
                model_id: a.model_id.clone(),
                files: a.files.iter().map(|f| self.file(f)).collect(),
            })
            .collect();
        Fingerprint {
            tool: TOOL_VERSION.to_owned(),
            schema: RECORD_SCHEMA.to_owned(),
            scene: self.file(scene_file),
            plan: plan_digest.to_owned(),
            preset: Some(preset),
            annotation,
            assets,
        }
    }

    /// Why a record with fingerprint `old` cannot be reused for `scene_file` under the
    /// current plan and assets, or `None` when it can: every file it lists has the same
    /// content, each asset still resolves to the same files, and the tool, schema and plan
    /// are the same. `compare_annotation` says whether the record's metrics read the
    /// annotation row.
    pub fn why_stale(
        &self,
        old: &Fingerprint,
        scene_file: &Path,
        assets: &AssetLibrary,
        plan_digest: &str,
        annotation: Option<&str>,
        compare_annotation: bool,
    ) -> Option<String> {
        if old.tool != TOOL_VERSION {
            return Some(format!("written by {}, this is {TOOL_VERSION}", old.tool));
        }
        if old.schema != RECORD_SCHEMA {
            return Some(format!("record schema {}, expected {RECORD_SCHEMA}", old.schema));
        }
        if old.plan != plan_digest {
            return Some("the metrics or their parameters changed".to_owned());
        }
        if compare_annotation && old.annotation.as_deref() != annotation {
            return Some("the annotation row changed".to_owned());
        }
        let now = self.file(scene_file);
        if now.blake3.is_none() || now.blake3 != old.scene.blake3 {
            return Some("the scene file changed".to_owned());
        }
        for asset in &old.assets {
            let location = match assets.locate(&asset.model_id) {
                Ok(l) => l,
                Err(e) => return Some(format!("asset {}: {e}", asset.model_id)),
            };
            for p in std::iter::once(&location.path).chain(&location.metadata) {
                if !asset.files.iter().any(|f| same_file(Path::new(&f.path), p)) {
                    return Some(format!(
                        "asset {} now resolves to {}",
                        asset.model_id,
                        p.display()
                    ));
                }
            }
            for f in &asset.files {
                if self.file(Path::new(&f.path)).blake3 != f.blake3 {
                    return Some(format!("asset {} changed: {}", asset.model_id, f.path));
                }
            }
        }
        None
    }
}

/// Whether `a` and `b` name the same file: the same text, or the same canonical path (an asset
/// folder given as `assets`, `./assets` or through a symbolic link is one folder).
fn same_file(a: &Path, b: &Path) -> bool {
    a == b
        || match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
}

/// The digest of an annotation row for [`Fingerprint::annotation`]: hex BLAKE3 of the row's
/// JSON form, so that reformatting the CSV without changing the row keeps it.
pub fn annotation_digest(row: &sceneeval_annotation::AnnotationRow) -> String {
    annotation_text_digest(row)
}

/// An annotation row's digest extended by the contents of the scene's matching file (the
/// plan's `params.fidelity.matching` is a file): editing the file invalidates the scene's record as
/// editing the row does. A missing or unreadable file digests as such; reading it for the
/// metrics then fails the scene with the reason.
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let file = dir.path().join("matching.json");
/// std::fs::write(&file, r#"{"bed": ["a"]}"#).unwrap();
/// let first = sceneeval_run::matching_file_digest("row", &file);
/// assert_eq!(first, sceneeval_run::matching_file_digest("row", &file));
/// std::fs::write(&file, r#"{"bed": ["b"]}"#).unwrap();
/// assert_ne!(first, sceneeval_run::matching_file_digest("row", &file));
/// assert_ne!(first, sceneeval_run::matching_file_digest("other row", &file));
/// ```
pub fn matching_file_digest(row_digest: &str, file: &Path) -> String {
    let mut hasher = blake3::Hasher::new();
    hasher.update(row_digest.as_bytes());
    match std::fs::read(file) {
        Ok(bytes) => {
            hasher.update(b"\nmatching file\n");
            hasher.update(&bytes);
        }
        Err(e) => {
            hasher.update(format!("\nmatching file unreadable: {:?}", e.kind()).as_bytes());
        }
    }
    hasher.finalize().to_hex().to_string()
}

fn annotation_text_digest(row: &sceneeval_annotation::AnnotationRow) -> String {
    // Rows serialise to a JSON object of strings and lists of strings: this cannot fail.
    let text = serde_json::to_string(row).unwrap_or_default();
    blake3::hash(text.as_bytes()).to_hex().to_string()
}
