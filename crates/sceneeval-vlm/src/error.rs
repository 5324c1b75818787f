use std::path::PathBuf;

use thiserror::Error;

/// The boxed error an implementation of [`crate::Vlm`] reports as the cause of a failed request.
pub type BoxError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// Everything that can go wrong in the VLM layer.
///
/// An answer the model gave but that cannot be used (invalid, refused, truncated) is *not* an
/// error: [`crate::Session::ask`] records it per question as [`crate::Unanswered`]. Errors are
/// what stops a request from being answered at all, and mistakes in the caller's input.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum VlmError {
    /// Image bytes that are not a PNG file.
    #[error("image {what} is not a PNG file ({len} bytes): {reason}")]
    NotPng {
        /// Which image (a file path, or a description of its role).
        what: String,
        /// Its length in bytes.
        len: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A task built from inconsistent input (no categories offered, two questions with one
    /// key, an anchor index outside the object list, ...).
    #[error("invalid {task} task: {message}")]
    InvalidTask {
        /// The task name (`obj_matching`, ...).
        task: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A prompt template that cannot be used: an override file with an unknown name, an unknown
    /// placeholder, or without a placeholder the task needs.
    #[error("prompt template {template:?}{}: {message}", .path.as_ref().map(|p| format!(" ({})", p.display())).unwrap_or_default())]
    Prompt {
        /// The template name (the file stem of an override file).
        template: String,
        /// The override file, when the template came from one.
        path: Option<PathBuf>,
        /// What is wrong.
        message: String,
    },
    /// A file or folder could not be read or written.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// A cache file that is not a valid cache record.
    #[error("cache file {}: {message}", .path.display())]
    CacheRecord {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// [`crate::Replay`] found no cached answer for a request.
    #[error(
        "no cached answer for {task} request {key} (model {model:?}) in {}; the request ends with {text_tail:?}",
        .dir.display()
    )]
    CacheMiss {
        /// The task name.
        task: String,
        /// The model the cache was asked for.
        model: String,
        /// The content hash of the request (the cache file is `<dir>/<key[..2]>/<key>.json`).
        key: String,
        /// The cache folder.
        dir: PathBuf,
        /// The last characters of the request's user text (its scene-specific part).
        text_tail: String,
    },
    /// The implementation behind [`crate::Vlm`] failed to answer (HTTP error, timeout, key
    /// refused, ...). The cause is kept as the source.
    #[error("{task} request to model {model:?} failed")]
    Backend {
        /// The task name.
        task: String,
        /// The model.
        model: String,
        /// Whether every later request would fail in the same way (the API key was refused,
        /// the model does not exist, the server rejected the request format), so that a caller
        /// should stop rather than go on with the next item.
        permanent: bool,
        /// What went wrong.
        #[source]
        source: BoxError,
    },
    /// A JSON Schema that cannot be used in strict mode.
    #[error("response schema {name:?}: {message}")]
    Schema {
        /// The schema name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A [`crate::Scripted`] VLM was asked more often than it has answers.
    #[error("scripted VLM has no answer left for the {task} request (it answered {answered} before)")]
    ScriptExhausted {
        /// The task name.
        task: String,
        /// How many requests it answered before.
        answered: usize,
    },
}

impl VlmError {
    /// Whether the error will repeat for every later request (see [`VlmError::Backend`]); a
    /// cache miss in replay is not permanent (other requests may be cached).
    pub fn is_permanent(&self) -> bool {
        matches!(self, VlmError::Backend { permanent: true, .. })
    }

    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        VlmError::Io {
            path: path.into(),
            source,
        }
    }

    pub(crate) fn invalid_task(task: &'static str, message: impl Into<String>) -> Self {
        VlmError::InvalidTask {
            task,
            message: message.into(),
        }
    }
}
