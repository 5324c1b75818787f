use std::path::PathBuf;

use sceneeval_eval::{EvalError, RequestField};
use sceneeval_results::ResultsError;
use thiserror::Error;

/// What went wrong in a run: its request, its scene folder, its output folder, or a result
/// file.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RunError {
    /// The plan, a request field or the evaluation went wrong ([`EvalError::Request`] names
    /// the request's field).
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// A result file could not be read or written.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// Reading or writing a file or folder failed.
    #[error("{}: {source}", path.display())]
    File {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The output folder cannot be written (checked before any scene is evaluated).
    #[error("output folder {} is not writable", path.display())]
    OutputNotWritable {
        /// The folder.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// Another run (of this or another process) is writing into the output folder.
    #[error(
        "another sceneeval run is writing to {} (it holds {}/.sceneeval.lock): wait for it to finish, or write \
         to another output folder",
        path.display(),
        path.display()
    )]
    OutputInUse {
        /// The output folder.
        path: PathBuf,
    },
    /// Two scene files have the same benchmark id (`scene_1.json` and `scene_01.json`): their
    /// results would be confused.
    #[error("scene files {} and {} have the same id {id}", first.display(), second.display())]
    DuplicateSceneId {
        /// The id.
        id: u64,
        /// The first file.
        first: PathBuf,
        /// The second file.
        second: PathBuf,
    },
}

impl RunError {
    pub(crate) fn file(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        RunError::File {
            path: path.into(),
            source,
        }
    }

    /// A request error without an underlying cause ([`EvalError::request`]).
    pub(crate) fn request(field: RequestField, message: impl Into<String>) -> Self {
        RunError::Eval(EvalError::request(field, message))
    }

    /// A request error caused by `source` ([`EvalError::request_caused`]).
    pub(crate) fn request_caused(
        field: RequestField,
        message: impl Into<String>,
        source: impl std::error::Error + Send + Sync + 'static,
    ) -> Self {
        RunError::Eval(EvalError::request_caused(field, message, source))
    }

    /// The request error this is, if it is one: the field at fault and what is wrong with it
    /// (front ends show it under their own name for the field, `--plan`, `plan=`).
    pub fn as_request(&self) -> Option<&EvalError> {
        match self {
            RunError::Eval(e @ EvalError::Request { .. }) => Some(e),
            _ => None,
        }
    }

    /// The request field at fault, if this is a request error ([`RunError::as_request`]).
    pub fn request_field(&self) -> Option<RequestField> {
        self.as_request().and_then(EvalError::request_field)
    }
}
