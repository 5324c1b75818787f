//! Everything a program that depends on `sceneeval-relations` alone needs to build boxes,
//! meshes and rooms and to call every predicate and gradient: `use
//! sceneeval_relations::prelude::*;`.
//!
//! The geometry and scene crates are re-exported whole as [`crate::geom`] and
//! [`crate::scene`]; this prelude names their common types, the relation vocabulary and
//! parameters, and the kernel modules ([`arch`], [`batch`], [`grad`]). The object-object
//! kernels are functions of the crate root (`sceneeval_relations::side_of`, ...), left out of
//! the prelude so that their short names (`near`, `far`) do not clash with a program's own.
//!
//! ```
//! use sceneeval_relations::prelude::*;
//!
//! let room = RoomBuilder::rectangle("r", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0)).build().unwrap();
//! let bed = Obb::from_yaw(Point3::new(2.0, 4.0, 0.3), Vector3::new(0.8, 1.0, 0.3), 0.0).unwrap();
//! let ball = Mesh::uv_ellipsoid(&Vector3::repeat(0.2), 12, 7).unwrap();
//! let pose = pose_from_yaw(Point3::new(2.0, 2.0, 0.2), 0.0);
//! let ball_box = Obb::from_local_aabb(ball.aabb(), &pose);
//! let (bed, ball) = (ObjectGeom::from_box(&bed), ObjectGeom::with_mesh(&ball_box, &ball, &pose));
//! let params = RelationParams::default();
//! let near = batch::score_pair(Relation::Near, &ball, &bed, &params).unwrap();
//! let g = grad::pair(Relation::Near, &ball, &bed, &params).unwrap();
//! assert_eq!(g.score, near);
//! assert_eq!(arch::inside_room(&ball, &room, &params), 1.0);
//! ```

pub use crate::geom::conventions::pose_from_yaw;
pub use crate::geom::{Isometry3, Mesh, Obb, Point2, Point3, Real, Rotation3, Side, Vector3};
pub use crate::grad::{ArchGrad, BoxGrad, PairGrad};
pub use crate::scene::{Category, OpeningKind, Room, RoomBuilder, Scene, SceneObject};
pub use crate::{
    ArchElement, DistanceBand, LongShort, ObjectGeom, Query, Relation, RelationError, RelationKind,
    RelationParams, SceneRelations, arch, batch, grad,
};
