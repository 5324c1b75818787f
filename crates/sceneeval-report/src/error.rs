use std::path::PathBuf;

use thiserror::Error;

/// What went wrong while reading runs or writing a comparison or a report.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ReportError {
    /// A run folder holds no `<scene>/eval.json`.
    #[error("{}: no <scene>/eval.json in this folder (not the output folder of an evaluation)", dir.display())]
    NoRecords {
        /// The folder.
        dir: PathBuf,
    },
    /// A run folder holds records, but none can be read.
    #[error("{}: no record of this folder can be read; {}: {}", dir.display(), first.path.display(), first.reason)]
    NoReadableRecords {
        /// The folder.
        dir: PathBuf,
        /// The first record (in scene order) and why it cannot be read.
        first: Box<crate::Unreadable>,
    },
    /// A record could not be read, or a file written (the error names the file).
    #[error(transparent)]
    Results(#[from] sceneeval_results::ResultsError),
    /// An asset folder specification (`PREFIX=[LAYOUT:]DIR`) is wrong.
    #[error("asset folders: {0}")]
    Assets(#[source] sceneeval_io::IoError),
    /// A file or folder could not be read or written.
    #[error("{}: {source}", path.display())]
    File {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A run's `summary_scenes.csv` could not be read.
    #[error("{}: {source}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: csv::Error,
    },
    /// The names given for the runs do not fit them.
    #[error("{0}")]
    Names(String),
    /// A confidence level outside (0, 1).
    #[error("confidence level {0} is not between 0 and 1 (exclusive), e.g. 0.95")]
    ConfidenceLevel(f64),
    /// A significance level outside (0, 1).
    #[error("significance level {0} is not between 0 and 1 (exclusive), e.g. 0.05")]
    Alpha(f64),
    /// Nothing to compare.
    #[error("no run to compare")]
    NoRuns,
}

impl ReportError {
    /// A [`ReportError::File`] for `path`.
    pub(crate) fn file(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        ReportError::File {
            path: path.into(),
            source,
        }
    }
}
