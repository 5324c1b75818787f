use std::path::PathBuf;

use thiserror::Error;

use crate::Metric;
use crate::plausibility::PlausibilityError;

/// What went wrong while planning, evaluating or summarising.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum EvalError {
    /// A metric name that is not one of [`Metric::GEOMETRY_ONLY`].
    #[error(
        "unknown metric {0:?}: expected one of collision, support, navigability, accessibility, out_of_bounds, opening_clearance"
    )]
    UnknownMetric(String),
    /// An evaluation plan could not be read or is inconsistent.
    #[error("evaluation plan{}: {message}", path.as_ref().map(|p| format!(" {}", p.display())).unwrap_or_default())]
    Plan {
        /// The plan file, if it came from one.
        path: Option<PathBuf>,
        /// What is wrong.
        message: String,
    },
    /// One metric failed (its parameters are invalid).
    #[error("metric {metric} failed")]
    Metric {
        /// The metric.
        metric: Metric,
        /// Why.
        #[source]
        source: PlausibilityError,
    },
    /// The combined plausibility evaluation failed (its parameters are invalid).
    #[error("plausibility evaluation failed")]
    Plausibility(#[source] PlausibilityError),
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
