//! Physical stability for SceneEval: simulate a scene with rigid-body physics and say which
//! objects stay where the generator put them.
//!
//! A chair floating 3 mm above the floor and a vase balanced on a table's edge pass every
//! geometric check; a few seconds of gravity tell them apart. [`Stability::evaluate`] makes
//! each object a rigid body of convex pieces, welds what the [`WeldMode`] says, simulates
//! gravity (-z, [`params::GRAVITY`]) with [rapier](https://rapier.rs) (`rapier3d-f64`) until
//! every free object has come to rest or [`StabilityParams::duration_s`] has passed, and
//! reports per object how far its centre of mass moved and how far it turned from where it was
//! put to where it came to rest (or was at the end). An object that moved at most
//! [`StabilityParams::displacement_limit_m`] (1 cm) and turned at most
//! [`StabilityParams::rotation_limit_rad`] (0.1 rad) is stable; the scene figure is the share
//! of unstable objects among those free to move ([`StabilityReport::frac_unstable`]).
//! [`Stability::settle`] returns every object's final pose, to write the scene back settled.
//!
//! # The model
//! - **Bodies**: each object mesh is cut into convex pieces with parry's V-HACD, each piece the
//!   convex hull of the mesh's own surface in its part, so pieces never grow the mesh
//!   (furniture on the floor does not start in it); box objects are one exact cuboid; vertices
//!   are welded and repeated faces kept once first ([`decompose::decomposition_input`]); see
//!   [`decompose`] for the details and the stand-ins for meshes without volume. Decompositions
//!   are cached per mesh content and parameters, in memory and on disk
//!   ([`DecompositionCache`]).
//! - **Mass**: a uniform density (1000 kg/m³ by default, [`MassModel`]) over the pieces, so a
//!   wardrobe outweighs the vase on it and the centre of mass follows the shape; with one
//!   density for all objects the verdicts do not depend on its value.
//! - **Rooms** ([`arch`]): each floor a slab 1 m deep at the height the scene gives it,
//!   reaching 0.5 m beyond the outline, so a sunk object is pushed up; each wall's solid (doors
//!   and windows cut out) cuboids growing 0.5 m away from its room but never into a room (a
//!   wall two rooms share is a sheet on the shared line). A scene without rooms is an error ([`PhysicsError::NoFloor`]); an object over no floor falls and
//!   is unstable.
//! - **Welds** ([`WeldMode`]): `architectural` (default) fixes objects whose support type is
//!   `wall` or `ceiling`; `penetration` fixes objects interpenetrating another object, a floor
//!   or a wall by more than [`StabilityParams::penetration_depth_m`] (1 mm) at the start, as
//!   the narrow phase measures it on the convex pieces; `combined` both; `none` nothing.
//!   Support types are an input, one per object, from the same sources the support metric
//!   uses (unknown counts as `ground`).
//! - **Contacts**: between convex pieces (and the floor slabs) from the whole faces that
//!   touch, with a contact normal checked against the shapes and found by the
//!   separating-axis test when GJK's is degenerate; parry's own contacts took a direction in
//!   the contact plane as the normal of two faces touching exactly (a box resting at a room's
//!   centre was 3.6 m "into the floor") and cut every face to four vertices (a round base
//!   touched the floor on a quarter of its rim and rocked or toppled by the last bits of its
//!   yaw), so an object resting where it was put now touches at depth 0 and stays (the
//!   private `contact` module documents both). Friction 0.5 on every contact, no
//!   restitution; rapier's soft-constraint
//!   solver (4 iterations per step), its BVH broad phase, and sleeping: a body whose fastest
//!   point stays below 1 mm/s for 0.5 s sleeps, and once every free body sleeps nothing can
//!   move again, so the simulation stops early ([`StabilityReport::simulated_s`]).
//! - **Time step**: 1 ms, as the SceneSmith fork. A dropped box lands within one step of the
//!   free-fall time; with sleeping, a scene at rest costs about 0.5 s of simulated time, so
//!   the fine step is cheap (see `docs/performance.md`).
//!
//! # Determinism
//! The same scene and parameters give the same bits on every run and thread count of one
//! build: rapier steps one scene on one thread (no `parallel` feature). rapier's
//! `enhanced-determinism` (the same bits across platforms) is not enabled: it forces the
//! `libm` crate's trigonometry on nalgebra in every crate of a build, which would make the
//! other metrics' results depend on whether physics is compiled in;
//! decompositions run in parallel over distinct meshes but each is a pure function of its
//! mesh, and a cached decomposition is stored bit for bit.
//!
//! # Differences from the SceneSmith fork (`metrics/drake_utils.py`)
//! - The floor is at the height the scene gives it, not at the lowest object point (there a
//!   chair sunk 20 cm into the floor is "stable"; here it is pushed up and unstable, or welded
//!   for interpenetration under `penetration`).
//! - Displacement is measured at the object's centre of mass, not at the world origin (there
//!   an object 3 m from the origin that turns 0.2 degrees counts as moved 1 cm).
//! - Walls are oriented boxes outside every room, with doors and windows open, not
//!   axis-aligned boxes grown 0.5 m "away from the origin" (which grows them into rooms
//!   that do not straddle the origin).
//! - Every object is simulated: ids containing "wall" or "floor" are not skipped.
//! - Mass follows a uniform density instead of 1 kg per object ([`MassModel::PerObject`]
//!   restores the fork's choice); the fork also puts the centre of mass at the bounding
//!   box centre, here it is the pieces' volume centroid.
//! - V-HACD on the mesh's own surface instead of CoACD (threshold 0.03): no extra dependency,
//!   deterministic, cached; CoACD's pieces may also reach slightly outside the mesh.
//! - The simulation stops early once every free body sleeps (see above).
//! - The fork's `combined` variant also welds objects of support type `ground`; here
//!   `combined` is exactly `architectural` plus `penetration`.
//!
//! # Features
//! `simulate` (default) is the simulation itself and pulls in rapier. Without it the crate holds
//! the metric's parameters ([`StabilityParams`]), its report ([`StabilityReport`]) and errors:
//! what a program that reads or writes results needs (`sceneeval-results` depends on it so).
//!
//! # Example
//! ```
//! use sceneeval_geom::{conventions::pose_from_yaw, Point2, Point3, Vector3};
//! use sceneeval_physics::{DecompositionCache, Stability, StabilityParams, WeldReason};
//! use sceneeval_scene::{Category, Deadline, RoomBuilder, Scene, SupportType};
//!
//! let scene = Scene::builder()
//!     .room_builder(RoomBuilder::rectangle("r0", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)))
//!     // A 1 x 0.5 x 0.75 m desk on the floor, and a 0.6 x 0.2 x 0.3 m shelf hung on the
//!     // far wall (y = 5) 1.5 m up, touching nothing else.
//!     .add_box("desk", Category::new("desk"), Vector3::new(0.5, 0.25, 0.375),
//!              pose_from_yaw(Point3::new(1.0, 2.0, 0.375), 0.0))
//!     .add_box("shelf", Category::new("shelf"), Vector3::new(0.3, 0.1, 0.15),
//!              pose_from_yaw(Point3::new(2.0, 4.9, 1.5), 0.0))
//!     .build()
//!     .unwrap();
//! let support = [Some(SupportType::Ground), Some(SupportType::Wall)];
//! let cache = DecompositionCache::in_memory();
//! let report = Stability::new(StabilityParams::default()).unwrap()
//!     .evaluate(&scene, &support, &cache, &Deadline::none())
//!     .unwrap();
//! assert!(report.objects[0].stable && !report.objects[0].welded);
//! assert_eq!(report.objects[1].weld_reason, Some(WeldReason::Wall));
//! assert_eq!(report.frac_unstable, Some(0.0)); // 0 of the 1 free object moved
//! ```

#[cfg(feature = "simulate")]
pub mod arch;
#[cfg(feature = "simulate")]
mod cache;
#[cfg(feature = "simulate")]
mod contact;
#[cfg(feature = "simulate")]
pub mod decompose;
mod error;
pub mod params;
mod report;
#[cfg(feature = "simulate")]
mod simulate;
#[cfg(feature = "simulate")]
mod stability;

#[cfg(feature = "simulate")]
pub use cache::{CacheStats, DecompositionCache, MeshKey};
#[cfg(feature = "simulate")]
pub use decompose::{Decomposition, Piece};
pub use error::PhysicsError;
pub use params::{DecompositionParams, MassModel, StabilityParams, WeldMode};
pub use report::{
    BodyShape, DecompositionKind, Interpenetration, ObjectStability, Pose, StabilityReport, WeldReason,
};
#[cfg(feature = "simulate")]
pub use stability::Stability;
