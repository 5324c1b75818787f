//! Geometry primitives for SceneEval: oriented boxes, axis-aligned boxes, 2-D polygons, rays,
//! planes and triangle meshes, plus the one place where the project's frame conventions are
//! written down ([`conventions`]).
//!
//! Every public type uses [`nalgebra`] with `f64` scalars ([`Real`]). Mesh queries (distance,
//! intersection, contact, ray casts) run on [`parry3d_f64`] behind a small private adapter, so
//! callers never touch parry's glam-based math; [`parry`] re-exports the exact parry version for
//! the rare caller that needs a raw shape.
//!
//! Meshes also bound solids: [`Mesh::contains_point`] and [`Mesh::signed_distance`] decide
//! inside in time logarithmic in the triangle count (pseudo-normals for closed meshes, a
//! hierarchical winding number for open ones), and [`Mesh::penetration`] tells whether two
//! placed meshes interpenetrate beyond a tolerance, with a certified lower bound on the
//! penetration depth.
//!
//! # Conventions
//! World: right-handed, **z up**, metres. Object frame: **front = local -y**, right = +x,
//! up = +z. An [`Obb`] is the axis-aligned box of an object's mesh in its own frame, placed by
//! the object's pose, so its axes are orthonormal and its half extents are metres.
//! See [`conventions`] for the side table and the asset-to-object rotation.
//!
//! # Example
//! ```
//! use sceneeval_geom::{Obb, Side, na::{Point3, Vector3}};
//!
//! // A 2 m x 1 m x 0.5 m box turned 90 degrees about z: its local -y (front) now points +x.
//! let bed = Obb::from_yaw(Point3::new(0.0, 0.0, 0.25), Vector3::new(1.0, 0.5, 0.25),
//!                         std::f64::consts::FRAC_PI_2).unwrap();
//! let front = bed.side_direction(Side::Front);
//! assert!((front - Vector3::x()).norm() < 1e-12);
//! assert!((bed.volume() - 1.0).abs() < 1e-12);
//! assert!(bed.contains_point(&Point3::new(0.2, 0.9, 0.1)));
//! ```

pub use nalgebra as na;
pub use parry3d_f64 as parry;

mod aabb;
pub mod conventions;
mod distance;
mod error;
mod mesh;
mod obb;
pub mod parry_adapter;
mod penetration;
pub mod planar;
mod polygon;
mod ray;
mod shapes;
mod solid;
mod sort;
mod tritri;

pub use aabb::Aabb;
pub use conventions::Side;
pub use distance::ClosestPoints;
pub use error::GeomError;
pub use mesh::{Mesh, RayHit};
pub use obb::Obb;
pub use penetration::{DepthSearch, Overlap, Penetration, PenetrationQuery};
pub use polygon::{MAX_EDGE_PAIRS, Polygon2};
pub use ray::{Plane, Ray};
pub use shapes::{CUBOID_TRIANGLES, cuboid_corner, weld_vertices};

/// The scalar type of every public geometry value (metres, radians).
pub type Real = f64;
/// A point in 3-D space.
pub type Point3 = na::Point3<Real>;
/// A vector in 3-D space.
pub type Vector3 = na::Vector3<Real>;
/// A point in the plane (world x, y).
pub type Point2 = na::Point2<Real>;
/// A vector in the plane (world x, y).
pub type Vector2 = na::Vector2<Real>;
/// A rigid transform (rotation then translation), e.g. `world_from_object`.
pub type Isometry3 = na::Isometry3<Real>;
/// A 3-D rotation stored as a matrix (columns are the rotated frame's axes).
pub type Rotation3 = na::Rotation3<Real>;
/// A 3x3 matrix.
pub type Matrix3 = na::Matrix3<Real>;
