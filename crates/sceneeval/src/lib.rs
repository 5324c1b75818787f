//! SceneEval facade: one dependency that re-exports the member crates as modules.
//!
//! | module | crate | what |
//! |---|---|---|
//! | [`geom`] | `sceneeval-geom` | boxes, meshes, polygons, conventions |
//! | [`scene`] | `sceneeval-scene` | the scene model |
//! | [`relations`] | `sceneeval-relations` | the 23 spatial predicates |
//! | [`io`] | `sceneeval-io` | sceneState files and assets |
//! | [`annotation`] | `sceneeval-annotation` | the SceneEval-500 annotation schema |
//! | [`plausibility`] | `sceneeval-plausibility` | collision, support, navigability, ... |

pub use sceneeval_annotation as annotation;
pub use sceneeval_geom as geom;
pub use sceneeval_io as io;
pub use sceneeval_plausibility as plausibility;
pub use sceneeval_relations as relations;
pub use sceneeval_scene as scene;
