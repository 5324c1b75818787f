use std::path::PathBuf;

use thiserror::Error;

use crate::plausibility::PlausibilityError;

/// What went wrong while planning, evaluating or summarising.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum EvalError {
    /// An evaluation plan could not be read or is inconsistent.
    #[error("evaluation plan{}{}: {message}",
        path.as_ref().map(|p| format!(" {}", p.display())).unwrap_or_default(),
        field.as_ref().map(|f| format!(": {f}")).unwrap_or_default())]
    Plan {
        /// The plan file, if it came from one.
        path: Option<PathBuf>,
        /// The path of the field at fault (`params.collision.contact_tolerance`), if one.
        field: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// The choices of a run do not fit together or name nothing (a plan that is none of
    /// `geometry`, `full`, a metric list or a file; fidelity metrics without annotations; an
    /// unknown relation mapping): see [`crate::PlanChoice`]. The message names the option as
    /// the front end spells it (`--plan`, `plan`).
    #[error("{message}")]
    Choice {
        /// What is wrong.
        message: String,
        /// The underlying plan error, if one.
        #[source]
        source: Option<Box<EvalError>>,
    },
    /// A metric failed: its parameters are invalid or the scene's time budget ran out. The
    /// message is the metric's own.
    #[error(transparent)]
    Plausibility(#[from] PlausibilityError),
    /// A fidelity metric failed (a malformed annotation entry, a matching file, a VLM that
    /// cannot be reached, a view that cannot be rendered).
    #[error(transparent)]
    Fidelity(#[from] sceneeval_fidelity::FidelityError),
    /// Reading or writing a result file failed.
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

impl EvalError {
    pub(crate) fn file(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        EvalError::File {
            path: path.into(),
            source,
        }
    }
}
