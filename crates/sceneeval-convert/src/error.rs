use std::path::PathBuf;

use sceneeval_io::IoError;
use sceneeval_scene::SceneError;
use thiserror::Error;

/// Everything that can stop a conversion. Each variant names the file (and, inside a JSON
/// file, the RFC 6901 pointer of the value) that was wrong; nothing is left in the output
/// folder when a conversion fails.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ConvertError {
    /// The input folder is not a folder, or holds no scene of the format.
    #[error("{}: {reason}", .path.display())]
    Input {
        /// The input folder (or the scene folder at fault).
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A generator's file is missing, unreadable, malformed JSON, or a value in it has the wrong
    /// type or is not acceptable (the error names the file and the JSON pointer), or two of its
    /// objects have one id ([`IoError::DuplicateObjectId`]: a SceneAgent object's id names its
    /// asset, so the second would show the first's mesh; Holodeck's `floor_objects` names
    /// objects by id; an IDesign id names the object's GLB).
    #[error(transparent)]
    Native(Box<IoError>),
    /// An object's asset could not be loaded (unknown asset, missing or corrupt mesh).
    #[error("{}: {pointer}: cannot load asset {model_id:?}", .path.display())]
    Asset {
        /// The generator's file that names the asset.
        path: PathBuf,
        /// Pointer to the object in that file.
        pointer: String,
        /// The model id the asset was looked up by.
        model_id: String,
        /// Why it could not be loaded.
        #[source]
        source: Box<IoError>,
    },
    /// The architecture or an object a generator's file describes is not a valid scene
    /// (zero-length wall, self-intersecting floor, non-finite pose, ...).
    #[error("{}: {pointer}: {source}", .path.display())]
    Scene {
        /// The generator's file.
        path: PathBuf,
        /// Pointer to the element at fault (or the file's root).
        pointer: String,
        /// The scene model's error.
        #[source]
        source: SceneError,
    },
    /// The format gives box centres (Holodeck, LayoutVLM), and only an asset's mesh says
    /// where its box centre is, but no asset folder was given for the format's prefix.
    #[error(
        "{format} gives box centres, and only the meshes say where an asset's box centre is: \
         the asset folder of prefix {prefix:?} is needed (the folder the evaluation will read \
         the assets from)"
    )]
    AssetsNeeded {
        /// The format.
        format: crate::Format,
        /// The model id prefix whose folder is needed.
        prefix: &'static str,
    },
    /// The conversion was interrupted ([`crate::ConvertOptions::with_interrupt`]); its
    /// temporary folder is removed and nothing is written.
    #[error("interrupted: the conversion stopped and its temporary folder is removed")]
    Interrupted,
    /// The id map is not a JSON object of scene keys to SceneEval-500 ids, or maps two scenes
    /// to one id.
    #[error("id map: {reason}")]
    IdMap {
        /// What is wrong.
        reason: String,
    },
    /// The output folder exists and is not empty (a conversion never writes into an existing
    /// folder's files).
    #[error("{}: the output folder exists and is not empty; choose a new folder or remove it", .path.display())]
    OutputExists {
        /// The output folder.
        path: PathBuf,
    },
    /// Creating, copying or renaming a file of the output failed.
    #[error("{}: {source}", .path.display())]
    Output {
        /// The file or folder.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// Two of a generator's files would be written to the same place with different contents
    /// (SceneAgent rooms that hold different files under one relative path).
    #[error("{} and {} would both become {}: {reason}", .first.display(), .second.display(), .target.display())]
    Conflict {
        /// The first source file.
        first: PathBuf,
        /// The second source file.
        second: PathBuf,
        /// Where both would go, relative to the output folder.
        target: PathBuf,
        /// Why that is a problem.
        reason: String,
    },
    /// Writing a converted scene failed, or the written file does not read back (a bug or an
    /// asset that the scene cannot use); the output folder is not created.
    #[error("{}: the converted scene does not read back", .path.display())]
    Verify {
        /// The converted file (in the temporary folder).
        path: PathBuf,
        /// The reader's error.
        #[source]
        source: Box<IoError>,
    },
}

impl From<IoError> for ConvertError {
    fn from(e: IoError) -> Self {
        ConvertError::Native(Box::new(e))
    }
}

impl ConvertError {
    pub(crate) fn input(path: impl Into<PathBuf>, reason: impl Into<String>) -> Self {
        ConvertError::Input {
            path: path.into(),
            reason: reason.into(),
        }
    }

    pub(crate) fn output(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        ConvertError::Output {
            path: path.into(),
            source,
        }
    }

    pub(crate) fn asset(
        path: impl Into<PathBuf>,
        pointer: impl Into<String>,
        model_id: &str,
        source: IoError,
    ) -> Self {
        ConvertError::Asset {
            path: path.into(),
            pointer: pointer.into(),
            model_id: model_id.to_owned(),
            source: Box::new(source),
        }
    }

    pub(crate) fn scene(path: impl Into<PathBuf>, pointer: impl Into<String>, source: SceneError) -> Self {
        ConvertError::Scene {
            path: path.into(),
            pointer: pointer.into(),
            source,
        }
    }
}
