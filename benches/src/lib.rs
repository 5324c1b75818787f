//! Shared scene builders of the SceneEval benchmarks and measurement binaries.
//!
//! - [`heavy`]: furniture-like non-convex meshes of realistic size (a few thousand to about
//!   50,000 triangles), generated at run time, and the five fixture rooms refurnished with them
//!   (the "rooms with real furniture meshes" of the stability measurement, issue 24).
//!
//! ```
//! use sceneeval_benches::heavy::{HeavyKind, heavy_mesh};
//! let chair = heavy_mesh(HeavyKind::Chair);
//! assert!(chair.triangles().len() > 2_000);
//! // Normalised to the unit footprint, standing on z = 0.
//! assert!(chair.aabb().min.z.abs() < 1e-12 && (chair.aabb().max.z - 1.0).abs() < 1e-12);
//! ```

pub mod heavy;
