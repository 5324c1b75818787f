//! The in-memory scene model of SceneEval: objects with meshes, poses and oriented boxes, and
//! the architecture they stand in (rooms with floor polygons, walls with doors and windows,
//! ceilings).
//!
//! This crate knows no file format; `sceneeval-io` reads sceneState JSON and asset files into
//! these types, and a generator can assemble a [`Scene`] directly with [`Scene::builder`].
//! Every constructor validates its input and returns a [`SceneError`] naming the object, room,
//! wall or opening at fault.
//!
//! # Conventions
//! World z up, metres; object front = local -y; an object's OBB is its mesh's bounds in the
//! object frame placed by its pose (see `sceneeval_geom::conventions`). A wall's segment is its
//! inner face, its thickness extends away from its room, and its inward normal is decided
//! against its own room's floor (see [`arch`]).
//!
//! # Example
//! ```
//! use sceneeval_scene::{Category, RoomBuilder, Scene};
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3, Side};
//!
//! let scene = Scene::builder()
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!         .wall_height(2.8)
//!         .door(0, [1.0, 1.9], [0.0, 2.1]))
//!     // A 1.2 x 0.6 x 0.75 m desk (half extents 0.6, 0.3, 0.375) against the far wall
//!     // (y = 5), facing into the room (yaw 0: front = -y).
//!     .add_box("desk", Category::new("desk"), Vector3::new(0.6, 0.3, 0.375),
//!              pose_from_yaw(Point3::new(2.0, 4.7, 0.375), 0.0))
//!     .build()
//!     .unwrap();
//!
//! let desk = scene.object("desk").unwrap();
//! assert_eq!(desk.obb().side_direction(Side::Front), Vector3::new(0.0, -1.0, 0.0));
//! let far_wall = &scene.rooms()[0].walls()[2];
//! // The desk's back is 0.0 m from the far wall's inner face.
//! let gap = far_wall.inner_plane().signed_distance(&desk.obb().face_center(Side::Back));
//! assert!(gap.abs() < 1e-12);
//! let (_, _, door) = scene.openings().next().unwrap();
//! assert!((door.width() - 0.9).abs() < 1e-12);
//! ```
//!
//! # Sizes, poses and ids
//! Box sizes are **half extents** everywhere (as for `sceneeval_geom::Obb` and parry's
//! cuboids); objects are created and moved with the same pose type, `world_from_object`
//! (`sceneeval_geom::Isometry3`; `sceneeval_geom::conventions::pose_from_yaw` makes an
//! upright one); an object id and a category have different types ([`ObjectId`],
//! [`Category`]) so that they cannot be swapped.
//!
//! # Rooms are prepared once
//! A [`Room`] is built once, with everything that queries about objects read: its walls'
//! solids (as boxes and meshes, from one grid per wall), its floor and ceiling triangulations,
//! its doors and windows as boxes, and the floor's centroid, bounds and enclosing rectangle.
//! Relations (`sceneeval-relations`) and plausibility metrics (`sceneeval-plausibility`) borrow
//! it, as they borrow objects. Moving an object ([`Scene::set_pose`]) changes only that
//! object's pose and cached boxes: a layout optimiser can move objects and ask questions in a
//! loop without preparing anything again and without allocating.
//!
//! # Vocabulary
//! [`ArchElement`] is the one list of architectural element kinds (wall, floor, ceiling,
//! window, door, room) the crates above name architecture by, and [`label`] the one
//! normalisation of free-text labels (categories, attributes, relationship words) they compare
//! text in.
//!
//! # Inspection
//! [`inspect`] gives a scene's objects, rooms, walls and openings as plain values (centres,
//! sizes, yaws, fronts, areas), what `sceneeval inspect` prints and the report draws.
//!
//! # Errors
//! A [`SceneError`] names the element at fault as an [`Element`] (object, room, floor,
//! ceiling, wall or opening, with the wall's and opening's positions), so that a loader maps
//! it to a position in its file without reading the message.

pub mod arch;
mod deadline;
mod element;
mod error;
pub mod hints;
mod ids;
pub mod inspect;
pub mod label;
mod object;
mod scene;

pub use arch::{
    ArchElement, Ceiling, Floor, InwardEvidence, Opening, OpeningKind, OpeningSpec, PlacedOpening, Room,
    RoomBuilder, RoomSpec, RoomSpecError, Wall, WallSpec,
};
pub use deadline::{Deadline, DeadlineExceeded};
pub use element::Element;
pub use error::SceneError;
pub use hints::{SupportType, UnknownSupportType};
pub use ids::{Category, ObjectId, RoomId};
pub use object::SceneObject;
pub use scene::{Scene, SceneBuilder};

/// The side of a square rendered view of a scene, pixels, unless the caller says otherwise:
/// the reference's 512 (its object views shown to the VLM, OpenAI's low-detail image size).
/// Written once here, the lowest crate both the renderer (`sceneeval-render`'s
/// `RenderSettings::DEFAULT_SIZE`, `sceneeval render --render-size`) and the evaluator (the
/// VLM's object views, `--vlm-render-size`, Python's `vlm["render_size"]`) depend on; the
/// renderer is optional in the evaluator.
pub const DEFAULT_VIEW_SIZE: u32 = 512;
