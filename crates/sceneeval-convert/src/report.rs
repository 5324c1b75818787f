//! What a conversion did: the scenes written and everything left out, with reasons.

use std::path::PathBuf;

use serde::Serialize;

use crate::Format;

/// The result of [`crate::convert`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// The generator format read.
    pub format: Format,
    /// The generator's batch folder.
    pub input: PathBuf,
    /// The output folder.
    pub out: PathBuf,
    /// The scenes written, in key order.
    pub scenes: Vec<ConvertedScene>,
    /// Scenes of the input that were not converted, with the reason.
    pub skipped: Vec<SkippedScene>,
    /// Keys of `--id-map` that name no scene of the input.
    pub unused_id_map_keys: Vec<u64>,
}

/// One scene written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvertedScene {
    /// The scene's key: the `NNN` of `scene_NNN`, or its position for Holodeck.
    pub key: u64,
    /// The id it was written under (`scene_<ID>.json`).
    pub id: u64,
    /// The generator's scene folder.
    pub source: PathBuf,
    /// The files written for it, relative to the output folder: the scene file first.
    pub files: Vec<PathBuf>,
    /// Objects in the written scene (as read back).
    pub objects: usize,
    /// Rooms in the written scene.
    pub rooms: usize,
    /// Objects of the generator's file that the scene does not have, with the reason.
    pub skipped_objects: Vec<SkippedObject>,
}

/// An object left out of a scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SkippedObject {
    /// The generator's file.
    pub file: PathBuf,
    /// The object's JSON pointer in it.
    pub pointer: String,
    /// The object's name in that file (its id or key).
    pub name: String,
    /// Why it was left out.
    pub reason: String,
}

/// A scene folder of the input that was not converted.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SkippedScene {
    /// The scene folder.
    pub source: PathBuf,
    /// Its key.
    pub key: u64,
    /// Why it was not converted.
    pub reason: String,
}
