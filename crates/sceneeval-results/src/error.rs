use std::path::PathBuf;

use thiserror::Error;

/// What went wrong reading or writing a result file.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ResultsError {
    /// Reading or writing a result file failed.
    #[error("{}: {source}", path.display())]
    File {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A result file is not valid JSON of the expected schema.
    #[error("{}: not a valid result file: {message}", path.display())]
    BadRecord {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// Writing the CSV summary failed.
    #[error("writing the CSV summary: {0}")]
    Csv(#[from] csv::Error),
}

impl ResultsError {
    /// The error of `path` caused by `source`.
    pub fn file(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        ResultsError::File {
            path: path.into(),
            source,
        }
    }
}

/// Writes `bytes` to `path` atomically ([`sceneeval_files::write_atomic`]), the error naming
/// the file.
pub(crate) fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> Result<(), ResultsError> {
    sceneeval_files::write_atomic(path, bytes).map_err(|e| ResultsError::file(path, e))
}
