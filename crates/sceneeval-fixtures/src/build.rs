//! Turning a [`SceneSpec`] into a [`Scene`].
//!
//! Asset objects get their object-frame mesh from the caller's mesh source (in the generator:
//! `sceneeval-io`'s asset library reading the GLB files just written, so that the asset-to-object
//! frame conversion is io's and nobody else's). Box objects are built directly.

use std::sync::Arc;

use sceneeval_geom::conventions::rotation_from_yaw;
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Mesh, Point3, Vector3};
use sceneeval_io::scene_state::derived_object_id;
use sceneeval_scene::{Scene, SceneObject};

use crate::FixtureError;
use crate::spec::{Model, Placement, SceneSpec};
use sceneeval_geom::conventions::pose_from_yaw;

/// The rigid pose of a placement: its yaw about +z and its bottom centre as translation.
pub fn placement_pose(p: &Placement) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::new(p.position[0], p.position[1], p.position[2]),
        UnitQuaternion::from_rotation_matrix(&rotation_from_yaw(p.yaw_deg.to_radians())),
    )
}

/// The id an object gets in the scene file: the reference's `idx<index>_<modelId>` (or
/// `idx<index>_box` for a box object), so that reading the file back gives the same ids.
pub fn object_id(index: usize, p: &Placement) -> String {
    derived_object_id(index as i64, p.model_id().as_deref())
}

/// Builds the scene of `spec`. `mesh` returns the object-frame mesh of a fixture asset scaled
/// by an object-frame scale.
///
/// # Errors
/// [`FixtureError::Scene`] for invalid rooms or poses, or whatever `mesh` returns.
pub fn build_scene<F>(spec: &SceneSpec, mut mesh: F) -> Result<Scene, FixtureError>
where
    F: FnMut(&str, &Vector3) -> Result<Arc<Mesh>, FixtureError>,
{
    let name = spec.name();
    let scene_err = |source| FixtureError::Scene {
        scene: name.clone(),
        source,
    };
    let mut builder = Scene::builder().name(name.clone());
    for room in &spec.rooms {
        builder = builder.room(room.clone().build().map_err(scene_err)?);
    }
    for (index, p) in spec.objects.iter().enumerate() {
        let id = object_id(index, p);
        let scale = Vector3::from(p.scale);
        let pose = placement_pose(p);
        let object = match &p.model {
            Model::Asset(asset) => {
                let m = mesh(asset, &scale)?;
                SceneObject::from_mesh(id, m, pose)
                    .map_err(scene_err)?
                    .with_model_id(p.model_id().unwrap_or_default())
                    .with_scale(scale)
            }
            Model::Box {
                size,
                category,
                description,
            } => {
                let size = Vector3::from(*size).component_mul(&scale);
                // The box's origin is its centre, half its height above the bottom centre.
                let center = pose * Point3::new(0.0, 0.0, 0.5 * size.z);
                SceneObject::new_box(id, size * 0.5, pose_from_yaw(center, p.yaw_deg.to_radians()))
                    .map_err(scene_err)?
                    .with_category(*category)
                    .with_description(*description)
            }
        };
        // Every fixture object states its support type, as a generator that knows what it placed
        // would; functional sides are left to the category tables.
        let object = object
            .with_index(index as i64)
            .with_support_type(p.support.support_type(p.intended_support));
        builder = builder.object(object);
    }
    builder.build().map_err(scene_err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::Placement;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn pose_puts_the_bottom_centre_at_the_position() {
        let p = Placement::asset("bed", "bed", [2.0, 3.95, 0.0], 90.0);
        let pose = placement_pose(&p);
        assert!((pose * Point3::origin() - Point3::new(2.0, 3.95, 0.0)).norm() < 1e-15);
        // Yaw 90 turns the front (-y) to +x.
        let front = pose.rotation * Vector3::new(0.0, -1.0, 0.0);
        assert!((front - Vector3::x()).norm() < 1e-15);
        assert!((pose.rotation.angle() - FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn ids_follow_the_reference_naming() {
        let asset = Placement::asset("bed", "bed", [0.0; 3], 0.0);
        assert_eq!(object_id(3, &asset), "idx3_fixture.bed");
        let boxed = Placement::boxed("b", "bed", "A bed.", [1.0; 3], [0.0; 3], 0.0);
        assert_eq!(object_id(0, &boxed), "idx0_box");
    }
}
