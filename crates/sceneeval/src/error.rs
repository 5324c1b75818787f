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
    /// A field of an [`crate::EvaluationRequest`] is wrong or does not fit the others (a plan
    /// that cannot be read, fidelity metrics without annotations, a VLM setting out of range).
    /// Front ends show the field under their own name for it (`--plan`, `plan=`).
    #[error("{field}: {message}")]
    Request {
        /// The field at fault.
        field: crate::RequestField,
        /// What is wrong, without the field's name.
        message: String,
        /// The underlying error, if one.
        #[source]
        source: Option<Box<dyn std::error::Error + Send + Sync + 'static>>,
    },
    /// [`crate::Evaluator::evaluate`] with a plan that runs text-fidelity metrics, which need
    /// the scene's annotation row.
    #[error(
        "the plan runs text-fidelity metrics (cnt, atr, oor, oar), which need {scene}'s annotation row: pass it \
         to Evaluator::evaluate_scene"
    )]
    NoAnnotationRow {
        /// The scene.
        scene: String,
    },
    /// A metric failed: its parameters are invalid or the scene's time budget ran out. The
    /// message is the metric's own.
    #[error(transparent)]
    Plausibility(#[from] PlausibilityError),
    /// A fidelity metric failed (a malformed annotation entry, a matching file, a VLM that
    /// cannot be reached, a view that cannot be rendered).
    #[error(transparent)]
    Fidelity(#[from] sceneeval_fidelity::FidelityError),
    /// The stability metric failed (a scene without rooms, an object that cannot be made a
    /// rigid body, a simulation that diverged, the scene's time budget ran out; feature
    /// `physics`).
    #[cfg(feature = "physics")]
    #[error("stability: {0}")]
    Physics(#[from] crate::physics::PhysicsError),
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

    /// A request error without an underlying cause.
    pub(crate) fn request(field: crate::RequestField, message: impl Into<String>) -> Self {
        EvalError::Request {
            field,
            message: message.into(),
            source: None,
        }
    }

    /// A request error caused by `source`.
    pub(crate) fn request_caused(
        field: crate::RequestField,
        message: impl Into<String>,
        source: impl std::error::Error + Send + Sync + 'static,
    ) -> Self {
        EvalError::Request {
            field,
            message: message.into(),
            source: Some(Box::new(source)),
        }
    }

    /// The request field this error is about, if it is one ([`EvalError::Request`]).
    pub fn request_field(&self) -> Option<crate::RequestField> {
        match self {
            EvalError::Request { field, .. } => Some(*field),
            _ => None,
        }
    }
}
