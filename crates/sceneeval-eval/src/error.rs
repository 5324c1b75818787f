use std::path::PathBuf;

use thiserror::Error;

use sceneeval_plausibility::PlausibilityError;

/// What went wrong while planning or evaluating: a plan or request that cannot be used, or a
/// metric that failed.
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
        /// The path of the field at fault (`params.collision.contact_tolerance_m`), if one.
        field: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A field of a request (`sceneeval-run`'s `EvaluationRequest`, a [`crate::SettleRequest`])
    /// is wrong or does not fit the others (a plan that cannot be read, fidelity metrics
    /// without annotations, a VLM setting out of range). Front ends show the field under their own name for it (`--plan`, `plan=`).
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
    /// A metric failed: its parameters are invalid or the scene's time budget ran out. The
    /// message is the metric's own.
    #[error(transparent)]
    Plausibility(#[from] PlausibilityError),
    /// A fidelity metric failed (a malformed annotation entry, a matching file, a VLM that
    /// cannot be reached, a view that cannot be rendered).
    #[error(transparent)]
    Fidelity(#[from] sceneeval_fidelity::FidelityError),
    /// The stability metric failed (a scene without rooms, an object that cannot be made a
    /// rigid body, a simulation that diverged, the scene's time budget ran out).
    #[error("stability: {0}")]
    Physics(#[from] sceneeval_physics::PhysicsError),
}

impl EvalError {
    /// A request error without an underlying cause.
    pub fn request(field: crate::RequestField, message: impl Into<String>) -> Self {
        EvalError::Request {
            field,
            message: message.into(),
            source: None,
        }
    }

    /// A request error caused by `source`.
    pub fn request_caused(
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
