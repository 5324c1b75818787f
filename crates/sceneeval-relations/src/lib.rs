//! The 23 spatial-relation predicates of SceneEval (13 object-object, 10
//! object-architecture), deterministic, exact where the reference samples, and cheap enough
//! for a layout optimiser's inner loop.
//!
//! # Two tiers
//! - **Kernels on plain geometry**, callable without building a scene: objects are
//!   [`ObjectGeom`] views (an oriented box, optionally a mesh); rooms are
//!   `sceneeval_scene::Room`s, which prepare once, when built, everything the kernels read
//!   (walls' solids as boxes, floor and ceiling triangles, openings' boxes, the floor's
//!   centroid and rectangle), so the kernels only borrow them (build one from an outline with
//!   `sceneeval_scene::RoomBuilder`). The object-object kernels are at the crate root
//!   ([`side_of`], [`next_to`], [`surround`], ...), the object-architecture kernels in
//!   [`arch`], the batch forms in [`batch`]. Every kernel takes the **target** (the object
//!   being located) before the **anchor** (or the room).
//! - **One dispatcher**, [`score`]: a [`Relation`] and its [`Operands`] to the kernel, with
//!   the operands checked against the relation's kind and the one limit on `surround`'s
//!   targets ([`SURROUND_REFERENCE_MAX_TARGETS`]). The batch forms, [`SceneRelations`] and the
//!   front ends that read queries as plain data (`sceneeval relate`, the Python package,
//!   through the facade's `sceneeval::relate::Session`) all score through it.
//! - **Scene-level evaluation** by object index or id: [`SceneRelations`] with [`Query`] and
//!   [`Evaluation`]; unknown ids, missing anchors and relations of the wrong kind are
//!   [`RelationError`]s. It borrows the scene per call, so a loop can move objects
//!   (`Scene::set_pose`) and ask again without preparing anything.
//!
//! The vocabulary ([`Relation`]) parses and prints the snake_case names of the paper and the
//! reference's relationship-mapping prompts, and reads a query's `relation`, `side` and `arch`
//! fields ([`Relation::from_fields`]); every parameter, with its unit, is a field of
//! [`RelationParams`].
//!
//! **Gradients**: [`grad`] gives every score with its derivatives with respect to the
//! objects' box parameters (centre, half extents, yaw; a mesh object's pose), analytic and
//! bit-identical in the score, for optimisers. [`prelude`] and the re-exports [`geom`] and
//! [`scene`] let a program depend on this crate alone.
//!
//! # Conventions
//! World z up, metres; object front = local -y; sides left = -x, right = +x, front = -y,
//! back = +y, top = +z, bottom = -z of the **anchor's** frame (left is the left of a viewer
//! facing the anchor). Scores are in `[0, 1]`; a relation holds when its score is above 0.5.
//! The target is the object being located (the reference's first "other" object), the anchor
//! the reference object.
//!
//! # How the predicates compute
//! Same input, same bits: nothing is sampled at random.
//! - **Volume fractions** (`inside_of`, `outside_of`, `side_of`, `side_region`,
//!   `long_short_side_of`, `on_top`, the "in front of the wall" factor of `on_wall` and
//!   `against_wall`, and `inside_room`) are the exact fraction of the target box's volume in
//!   the region: the box, a convex polyhedron, is clipped by the region's planes on the stack
//!   and the clipped volume taken by the divergence theorem. They are continuous in both
//!   poses (Lipschitz with constant `area / volume` of the target box per metre of motion).
//!   `inside_room` clips the box against each floor triangle's vertical prism above the floor,
//!   so it is exact for any rotation, not only yaw.
//! - **Distances** are between the closest points of the two objects as solids (the paper's
//!   definition), 0 when the objects touch, overlap or nest ([`object_distance`]). Boxes:
//!   corner-to-box upper and frame-gap lower bounds, which agree in the usual corner-facing-face
//!   case, else GJK. Meshes: a branch and bound over both meshes' distance trees (see
//!   `sceneeval_geom::Mesh::distance`) with exact triangle distances, after cheap bounds that
//!   often decide a band's score on their own. Walls are
//!   solids with their doors and windows cut out; doors and windows are their openings' boxes
//!   (as deep as the wall); the ceiling is a surface.
//! - **Which geometry**: volume fractions, `middle_of`, `surround`, `inside_room`,
//!   `middle_of_room` and the "in front of the wall" factor use the objects' boxes, as the
//!   reference does; the distance relations and `face_to` use an object's mesh when it has
//!   one.
//! - **`face_to`** is exact for a box anchor (an analytic construction over the target's
//!   mid-depth cross-section) and a fixed ray grid for a mesh anchor; see [`face_to`].
//! - **Distance scores** are 1 inside the range and `exp(-delta^2 / (2 sigma^2))` outside
//!   ([`DistanceBand`]); closed or strict range ends give identical, continuous scores.
//!
//! # Ours versus the reference
//! | topic | reference (`3dlg-hcvc/SceneEval`) | here | switch to the reference |
//! |---|---|---|---|
//! | volume fractions | random samples of the target box (5000/m^3, at least 64) | exact clipped volume (the samples' expectation) | — |
//! | distance relations (Q3) | min over samples in the smaller object's minimum-volume box of the unsigned distance to the other mesh's surface | closest points of the solids | [`DistanceFrom::SmallerBox`] (the smaller object's metric box) |
//! | object-architecture distances | samples of the object's box | the object's geometry (mesh if given) | [`DistanceFrom::SmallerBox`] |
//! | `on_top` (Q1) | centre plane of the anchor (`no_contain: False`) | the anchor's top face, as the paper and prompts say | [`OnTopPlane::CentrePlane`] |
//! | `surround` (Q2) | median distance, signed 3-D angles | mean distance, plan-view gaps (paper) | [`SurroundVariant::Reference`] |
//! | `corner_of_room` (Q17) | perpendicularity of mean directions to the walls; no pair gives minus infinity | the walls' inward normals (paper); no pair gives 0 | [`CornerWalls::MeanDirections`] |
//! | `middle_of_room` centre | the floor's bounding-box centre | the floor's area centroid (paper) | [`RoomCentre::BoundsCentre`] |
//! | `middle_of_room` sigma | `o/2 + (1 - o/r)`, can reach 0 or go negative | the ratio term stops at 0 | — |
//! | `face_to` | rays from every sample; `1e-6` added to lengths; `arccos` unclipped (Q20) | exact over the mid-depth cross-section (box) or a fixed ray grid (mesh); exact normalisation, clipped cosine | — |
//! | `face_to` heights | rays only at the target's heights: a TV above the sofa's backrest is never hit | the anchor at any height (plan view, the angle's own view) | [`FaceToHeights::TargetSpan`] |
//! | `side_of` margin | lateral half extents x 1.25, unbounded outward | same (the paper says "25 % in each dimension") | — |
//! | distance-relation element types | floor, ceiling or room crash (Q19) | rejected with an error when parsing | — |
//! | `hang_from_ceiling` | every floor raised by the tallest wall of the scene | the room's ceiling (explicit, else its tallest wall) | — |
//! | walls | 1 mm slabs centred on the wall line | solid slabs whose inner face is the wall segment | — |
//!
//! [`RelationParams::reference`] sets every switch of the last column at once.
//!
//! **How our distance relates to the reference's.** For two boxes that do not overlap, the
//! reference's sampled minimum is the distance from finitely many points of the smaller box to
//! the other box, so it is never below ours and converges to ours as the sample count grows.
//! When a corner of the smaller box is closest, the excess is of the order of the distance
//! from that corner to its nearest sample: with `N` samples in a box of volume `V`, the median
//! of that distance is `(6 V ln 2 / (pi N))^(1/3)`, about 6 cm for any box of 12.8 L or more
//! (`N = 5000 V`) and `0.27 V^(1/3)` for smaller ones (`N = 64`; 2.7 cm for 1 L). When a face
//! is closest the excess is about `V / (N A)` for a face of area `A`, well under a millimetre.
//! For meshes the reference samples the smaller
//! object's minimum-volume box, which contains the mesh and sticks out of it, so its limit is
//! at most the true gap and can be well below it (a chair's box reaches past its legs). For
//! overlapping objects the reference reports the distance from interior points to the other
//! surface (positive); ours is 0. So `next_to` holds at least as often here for overlapping
//! or nested objects, and decisions otherwise agree except within a few centimetres of a
//! band's pass limit.
//!
//! `tests/reference_agreement.rs` re-implements the reference's estimators from its
//! definitions (samples, `contains`, `at_side` with its epsilons and margins) and checks, on
//! random box pairs, that our volume fractions are their expectations, that decisions agree
//! wherever the reference's sampling noise does not straddle 0.5, and that our box distance
//! bounds its sampled minimum from below.
//!
//! # Performance
//! Kernels allocate nothing per call: clipping runs on fixed-size buffers (on the stack, and a
//! per-thread polyhedron reused from call to call), mesh distance
//! searches recurse over trees built with the mesh, ray casts use parry's stack-allocated
//! traversal, rooms are prepared once (when the `sceneeval_scene::Room` is built), `surround`
//! sorts up to 64 targets on the stack, `corner_of_room` keeps up to 32 walls' bounds on the stack
//! (beyond those sizes each allocates one or two vectors, which keeps their cost `n log n`), and
//! the batch forms write into caller-owned slices. A test with a counting global allocator checks every relation on
//! boxes and on meshes, and the batch forms (package `sceneeval-alloc-check`). Box-only
//! predicates take 0.01-0.8 µs, distance predicates on boxes about 0.15 µs, architecture
//! predicates with a box in a four-wall room up to 2 µs, and every predicate on 5k-triangle
//! meshes at most about 20 µs. Measured figures and the command are in `docs/performance.md`
//! (`cargo bench -p sceneeval-benches --bench relations`).
//!
//! # Example
//! ```
//! use sceneeval_relations::{self as rel, arch, ObjectGeom, RelationParams};
//! use sceneeval_scene::RoomBuilder;
//! use sceneeval_geom::{Obb, Point2, Side, na::{Point3, Vector3}};
//!
//! let params = RelationParams::default();
//! let room = RoomBuilder::rectangle("bedroom", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
//!     .wall_height(2.8)
//!     .wall_thickness(0.1)
//!     .build()
//!     .unwrap();
//! // A 1.6 x 2 m bed with its head against the far wall (y = 5), facing -y.
//! let bed = Obb::from_yaw(Point3::new(2.0, 4.0, 0.3), Vector3::new(0.8, 1.0, 0.3), 0.0).unwrap();
//! // A nightstand 5 cm from the bed's -x side (its "left", seen from the foot of the bed).
//! let stand = Obb::from_yaw(Point3::new(0.9, 4.7, 0.3), Vector3::new(0.25, 0.2, 0.3), 0.0).unwrap();
//! let (bed, stand) = (ObjectGeom::from_box(&bed), ObjectGeom::from_box(&stand));
//!
//! assert_eq!(rel::side_of(&stand, &bed, Side::Left, &params), 1.0);
//! assert_eq!(rel::next_to(&stand, &bed, &params), 1.0);
//! assert!(params.holds(arch::against_wall(&bed, &room, &params)));
//! assert_eq!(arch::inside_room(&stand, &room, &params), 1.0);
//! ```

pub mod arch;
pub mod batch;
mod clip;
mod dispatch;
mod distance;
mod error;
mod face_to;
pub mod grad;
mod object;
mod pairwise;
mod params;
pub mod prelude;
mod relation;
mod scene_eval;

pub use dispatch::{Operands, SURROUND_REFERENCE_MAX_TARGETS, Targets, score};
pub use distance::object_distance;
pub use error::RelationError;
pub use face_to::face_to;
pub use object::ObjectGeom;
pub use pairwise::{
    across_from, far, inside_of, long_short_side_of, middle_of, near, next_to, on_top, outside_of,
    pair_distance, side_of, side_region, surround,
};
pub use params::{
    CornerWalls, DistanceBand, DistanceFrom, FaceToHeights, OnTopPlane, RelationParams, RoomCentre,
    SurroundVariant,
};
pub use relation::{
    DISTANCE_ELEMENTS, LongShort, OBJECT_ARCH_NAMES, OBJECT_OBJECT_NAMES, Relation, RelationKind,
};
pub use scene_eval::{Evaluation, Query, SceneRelations};
/// The geometry crate this one is built on (boxes, meshes, points), re-exported so that a
/// program depending on `sceneeval-relations` alone can build its inputs.
pub use sceneeval_geom as geom;
/// The scene crate (rooms, scenes), re-exported for the same reason.
pub use sceneeval_scene as scene;
/// The kinds of architectural element (the scene model's vocabulary); the distance relations
/// take [`DISTANCE_ELEMENTS`].
pub use sceneeval_scene::ArchElement;
