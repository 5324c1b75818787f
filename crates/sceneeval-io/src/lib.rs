//! sceneState JSON, asset sources and GLB/glTF/OBJ loading for SceneEval.
//!
//! - [`read_scene_state`] turns an sstk sceneState file (the input format of the reference
//!   implementation) into a [`sceneeval_scene::Scene`]; [`write_scene_state`] and
//!   [`scene_state_to_string`] write one back. Writing, reading and writing again gives the
//!   same bytes, and the scene read back equals the one written (poses to 1e-12).
//! - [`assets`]: a model id `PREFIX.ID` resolves through the [`AssetSource`] registered for
//!   `PREFIX` in an [`AssetLibrary`], which loads each asset once per run and shares its mesh.
//!   Sources exist for the 3D-FUTURE, Objathor, HSSD and LayoutVLM folder layouts and for a
//!   plain folder (`ID.glb` / `ID.gltf` / `ID.obj` with an optional `ID.json` sidecar).
//! - [`mesh_load`]: GLB/glTF (node hierarchy flattened, transforms baked) and OBJ (every group).
//! - [`appearance`]: materials, textures and render meshes, loaded only when a renderer asks
//!   ([`AssetLibrary::appearance`]); scene reading never decodes a texture.
//! - [`frames`]: the asset-to-object frame conversion, which happens in this crate and nowhere
//!   else.
//! - [`write_glb`]: a small deterministic binary glTF writer for generated assets.
//! - [`Limits`]: file-size, triangle and memory budgets, checked against declared sizes before
//!   anything is allocated; an asset over budget fails with [`IoError::TooLarge`],
//!   [`IoError::TooManyTriangles`] or [`IoError::OverMemoryBudget`].
//!
//! # Conventions
//! sstk `transform.data` is 16 numbers in column-major order and maps **asset** coordinates
//! (y up, front +z) to the world (z up). The object frame (front = local -y, z up) is
//! `T * Rx(-90 deg)` with the scale of `T` moved into the mesh: an object's pose is always
//! rigid and its mesh carries the scale ([`frames`] has the details). Box objects (our
//! extension, `"box": {"size": [w, d, h]}`) have no asset and their transform is already in the
//! object frame. Floors, ceilings and wall bases take their height from the points' z (the
//! reference instead puts the floor under the lowest object, quirk Q10).
//!
//! # Errors
//! Every failure is an [`IoError`] that names the file and the RFC 6901 JSON pointer of the
//! offending value (e.g. `/scene/object/3/transform/data/12`) or the asset id: malformed JSON
//! (with line and column), missing or mistyped fields, non-finite, singular, sheared or
//! projective transforms, an object without `transform`, a key given twice in one JSON object,
//! unknown model prefixes, missing or corrupt asset files, empty meshes, zero-length walls,
//! floors with fewer than 3 points, duplicate ids. Keys the sceneState format does not have are
//! a warning each (per key, file and place of the format), or with [`ReadOptions::strict`] an
//! error ([`scene_state::unknown_keys`]). A scene whose assets are
//! missing fails with [`IoError::MissingAssets`], which lists every missing asset of the scene
//! with its objects and the files looked for. Only regular files are read: a named pipe, a
//! device or a folder where an input file is expected is refused before it is opened
//! ([`sceneeval_files::open_regular`]), so reading never blocks. Every file written goes
//! through a unique temporary name and an atomic rename ([`sceneeval_files::write_atomic`]).
//! Nothing panics on any input; the library never prints and logs warnings with `tracing`.
//!
//! # Example
//! ```
//! use sceneeval_geom::{Isometry3, Point2, Side, Vector3};
//! use sceneeval_io::{AssetLibrary, GlbMesh, ReadOptions, read_scene_state, write_glb, write_scene_state};
//! use sceneeval_io::assets::PlainFolderSource;
//! use sceneeval_scene::{RoomBuilder, Scene};
//!
//! let dir = tempfile::tempdir().unwrap();
//! // An asset in the usual convention: y up, front toward +z. A 1 x 0.8 x 0.5 m block whose
//! // front is at z = +0.25.
//! let (mut positions, mut indices) = (Vec::new(), Vec::new());
//! for k in 0..8u32 {
//!     positions.push([
//!         if k & 1 == 0 { -0.5 } else { 0.5 },
//!         if k & 2 == 0 { 0.0 } else { 0.8 },
//!         if k & 4 == 0 { -0.25 } else { 0.25 },
//!     ]);
//! }
//! for t in [[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
//!           [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]] {
//!     indices.extend(t);
//! }
//! write_glb(&dir.path().join("dresser.glb"), &[GlbMesh::new("dresser", positions, indices)]).unwrap();
//! std::fs::write(dir.path().join("dresser.json"), r#"{"category": "dresser"}"#).unwrap();
//!
//! let assets = AssetLibrary::new().with_source("fixture", PlainFolderSource::new(dir.path()));
//! // Place it in code (the library does the frame conversion) against the far wall (y = 3) of
//! // a 4 x 3 m room, facing into the room (yaw 0: front = world -y).
//! let dresser = assets
//!     .object("dresser", "fixture.dresser", Isometry3::translation(2.0, 2.75, 0.0), Vector3::repeat(1.0))
//!     .unwrap();
//! let scene = Scene::builder()
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 3.0)))
//!     .object(dresser)
//!     .build()
//!     .unwrap();
//!
//! let path = dir.path().join("scene_0.json");
//! write_scene_state(&scene, &path).unwrap();
//! let back = read_scene_state(&path, &assets, &ReadOptions::default()).unwrap();
//! let obj = back.object("dresser").unwrap();
//! assert_eq!(obj.category(), Some("dresser"));
//! // The asset's front (+z) is the object's front, world -y; its back touches the wall.
//! assert!((obj.obb().side_direction(Side::Front) + Vector3::y()).norm() < 1e-12);
//! assert!((obj.obb().face_center(Side::Back).y - 3.0).abs() < 1e-12);
//! assert_eq!(back.rooms(), scene.rooms());
//! ```

pub mod appearance;
pub mod assets;
mod error;
pub mod frames;
mod gltf_write;
mod json_out;
mod limits;
pub mod mesh_load;
pub mod scene_state;
pub mod uri;

pub use appearance::Appearance;
pub use assets::{Asset, AssetInfo, AssetLibrary, AssetSource, AssetSpec, Layout};
pub use error::{IoError, MAX_LISTED_ASSETS, MissingAsset};
pub use gltf_write::{GlbImage, GlbMaterial, GlbMesh, write_glb, write_glb_to_vec};
pub use limits::{ESTIMATED_BYTES_PER_TRIANGLE, ESTIMATED_BYTES_PER_VERTEX, Limits};
pub use scene_state::{
    ArchitectureMode, ReadOptions, SimpleFloorHeight, read_scene_state, read_scene_state_str,
    scene_state_to_string, write_scene_state,
};
