//! What can go wrong when a scene is simulated.

use std::path::PathBuf;

use thiserror::Error;

/// What was wrong with the input of the stability metric, or why it stopped.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PhysicsError {
    /// A parameter is out of its documented range (see [`crate::StabilityParams`]).
    #[error("stability parameter `{name}` = {value} is invalid: {reason}")]
    InvalidParameter {
        /// The parameter's field name (`duration_s`, `decomposition.resolution`, ...).
        name: &'static str,
        /// The value given.
        value: f64,
        /// What the value must satisfy.
        reason: String,
    },
    /// The support types given do not match the scene's objects one for one.
    #[error("{given} support types given for a scene of {objects} objects (one per object, in scene order)")]
    SupportTypeCount {
        /// Objects in the scene.
        objects: usize,
        /// Support types given.
        given: usize,
    },
    /// The scene has no room, hence no floor for objects to stand on.
    #[error("scene {scene} has no room, so no floor to stand on: stability needs the scene's architecture")]
    NoFloor {
        /// The scene's name (`<unnamed>` when it has none).
        scene: String,
    },
    /// The scene's time budget ran out, or the run was cancelled, during `stage`: the
    /// [`sceneeval_scene::Deadline`] passed to [`crate::Stability`] had expired at one of its
    /// checks (before each mesh is decomposed, every 64 time steps).
    #[error("stability stopped during {stage}: {}", match budget_seconds {
        Some(b) => format!("time budget exceeded (the scene's {b} s are used up)"),
        None => "the run was cancelled".to_owned(),
    })]
    DeadlineExceeded {
        /// `decomposition` or `simulation`.
        stage: &'static str,
        /// The scene's budget in seconds; `None` when the deadline was cancelled without one.
        budget_seconds: Option<f64>,
    },
    /// An object's geometry could not be made into a rigid body.
    #[error("object {object}: {reason}")]
    Geometry {
        /// The object's id.
        object: String,
        /// What was wrong.
        reason: String,
    },
    /// The simulation produced a non-finite pose (it diverged).
    #[error("object {object}: the simulation diverged (its pose is no longer finite)")]
    Diverged {
        /// The object's id.
        object: String,
    },
    /// The decomposition cache's folder could not be created or read.
    #[error("decomposition cache {path}: {source}")]
    Cache {
        /// The folder or file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
}

impl From<sceneeval_scene::DeadlineExceeded> for PhysicsError {
    fn from(e: sceneeval_scene::DeadlineExceeded) -> Self {
        PhysicsError::DeadlineExceeded {
            stage: e.stage,
            budget_seconds: e.budget_seconds,
        }
    }
}
