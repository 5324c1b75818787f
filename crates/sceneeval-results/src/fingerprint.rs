//! [`Fingerprint`]: everything a scene's record depends on, as `eval.json` keeps it (the
//! files and their hashes, the plan's digest, the tool version), so that a re-run reuses a
//! result only when nothing it depends on changed.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::Preset;

/// The tool and version written into every fingerprint (`sceneeval 0.1.0`): results of
/// another version are never reused.
pub const TOOL_VERSION: &str = concat!("sceneeval ", env!("CARGO_PKG_VERSION"));

/// A file and the BLAKE3 hash of its bytes (`None`: the file did not exist).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileDigest {
    /// The path as it was read.
    pub path: String,
    /// Hex BLAKE3 of the content, `None` when the file was absent.
    pub blake3: Option<String>,
}

/// The files one asset was built from: mesh, external buffers, metadata (present or not).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AssetDigest {
    /// The model id `PREFIX.ID`.
    pub model_id: String,
    /// Its files, mesh first.
    pub files: Vec<FileDigest>,
}

/// Everything a scene's record depends on. A record is reused only when every part still
/// matches (`sceneeval_run::Fingerprints::why_stale`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fingerprint {
    /// [`TOOL_VERSION`] of the run that wrote the record.
    pub tool: String,
    /// The record schema ([`crate::RECORD_SCHEMA`]).
    pub schema: String,
    /// The scene file.
    pub scene: FileDigest,
    /// The digest of the plan (`sceneeval_eval::EvaluationPlan::result_digest`): the metrics
    /// and every parameter.
    pub plan: String,
    /// The plan's preset, recorded for the summary tables (`sceneeval summarize` shows it);
    /// not compared (the digest already holds every parameter). Absent in records of earlier
    /// versions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<Preset>,
    /// Hex BLAKE3 of the scene's annotation row (as JSON), when annotations were given and
    /// have a row for it. Compared only for metrics that read it (the text-fidelity metrics);
    /// the plausibility metrics do not.
    pub annotation: Option<String>,
    /// Every asset the scene's objects were loaded from, by model id.
    pub assets: Vec<AssetDigest>,
}

impl FileDigest {
    /// The digest of the file at `path` as it is now (`blake3` is `None` when it cannot be
    /// opened), named as given.
    pub fn of(path: &Path) -> FileDigest {
        FileDigest {
            path: path.display().to_string(),
            blake3: hash_file(path),
        }
    }
}

/// Hex BLAKE3 of a file's bytes, `None` when it cannot be opened (absent).
fn hash_file(path: &Path) -> Option<String> {
    let mut file = std::fs::File::open(path).ok()?;
    let mut hasher = blake3::Hasher::new();
    std::io::copy(&mut file, &mut hasher).ok()?;
    Some(hasher.finalize().to_hex().to_string())
}
