//! The sstk sceneState JSON format: reading ([`read_scene_state`]) and writing
//! ([`write_scene_state`]). The format, with this crate's extensions, is described in
//! `docs/formats.md` and in the crate docs.

pub mod json_in;
mod keys;
mod read;
mod write;

pub use keys::{UnknownKey, unknown_keys};
pub use read::{ArchitectureMode, ReadOptions, SimpleFloorHeight, read_scene_state, read_scene_state_str};
pub use write::{scene_state_to_string, write_scene_state};

/// The value of the top-level `format` field.
pub const FORMAT: &str = "sceneState";
/// The `scene.version` written (and expected; other versions only warn).
pub const SCENE_VERSION: &str = "scene@1.0.2";
/// The `scene.arch.version` written (and expected; other versions only warn).
pub const ARCH_VERSION: &str = "arch@1.0.2";

/// The reference's object id: `idx<index>_<modelId>`, or `idx<index>_box` for a box object
/// without a model id.
///
/// ```
/// assert_eq!(sceneeval_io::scene_state::derived_object_id(3, Some("3dfModel.ab")), "idx3_3dfModel.ab");
/// assert_eq!(sceneeval_io::scene_state::derived_object_id(0, None), "idx0_box");
/// ```
pub fn derived_object_id(index: i64, model_id: Option<&str>) -> String {
    format!("idx{index}_{}", model_id.unwrap_or("box"))
}
