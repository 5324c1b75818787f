use std::path::PathBuf;

use sceneeval_io::IoError;
use sceneeval_scene::SceneError;
use thiserror::Error;

/// Everything that can go wrong while generating the fixtures. Each variant names the file,
/// scene or object it concerns.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum FixtureError {
    /// Creating a directory or writing a file failed.
    #[error("{}: {source}", .path.display())]
    File {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Writing an asset or scene, or loading an asset back, failed in `sceneeval-io`.
    #[error("{what}: {source}")]
    Io {
        /// What was being written or read (a file or an asset id).
        what: String,
        /// The io crate's error (boxed: it is large).
        #[source]
        source: Box<IoError>,
    },
    /// A scene spec produced an invalid scene (bad room, bad pose, duplicate id).
    #[error("scene {scene}: {source}")]
    Scene {
        /// The scene's name (`scene_<N>`).
        scene: String,
        /// The scene crate's error.
        #[source]
        source: SceneError,
    },
    /// A scene spec is inconsistent: it names an unknown object key, wall, door or asset, or a
    /// flaw cannot be measured as specified.
    #[error("scene {scene}: {reason}")]
    Spec {
        /// The scene's name (`scene_<N>`).
        scene: String,
        /// What is inconsistent.
        reason: String,
    },
    /// Serialising a JSON document failed.
    #[error("{}: {source}", .path.display())]
    Json {
        /// The file being written.
        path: PathBuf,
        /// serde_json's error.
        #[source]
        source: serde_json::Error,
    },
    /// Writing an annotation file failed.
    #[error("{}: {reason}", .path.display())]
    Annotation {
        /// The annotation file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}

impl FixtureError {
    pub(crate) fn file(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        FixtureError::File {
            path: path.into(),
            source,
        }
    }

    pub(crate) fn io(what: impl Into<String>, source: IoError) -> Self {
        FixtureError::Io {
            what: what.into(),
            source: Box::new(source),
        }
    }

    pub(crate) fn spec(scene: &str, reason: impl Into<String>) -> Self {
        FixtureError::Spec {
            scene: scene.to_owned(),
            reason: reason.into(),
        }
    }
}
