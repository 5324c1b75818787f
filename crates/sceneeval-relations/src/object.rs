//! Predicate inputs on plain geometry: objects as boxes with optional meshes.

use sceneeval_geom::{Isometry3, Mesh, Obb};
use sceneeval_scene::SceneObject;

/// A borrowed view of one object as the predicates see it: its oriented box and, optionally,
/// its mesh with the pose placing it (`world_from_object`).
///
/// Without a mesh the object **is** its box (a solid cuboid). With a mesh, the distance
/// relations and `face_to` use the mesh; every other relation uses the box, as the reference
/// does (its volume fractions sample the box, never the mesh).
///
/// The box must be valid (finite, non-negative half extents, a proper rotation), as
/// [`Obb::new`] guarantees; the kernels do not re-check it.
///
/// ```
/// use sceneeval_relations::ObjectGeom;
/// use sceneeval_geom::{Obb, na::{Point3, Vector3}};
///
/// let bed = Obb::from_yaw(Point3::new(2.0, 3.9, 0.3), Vector3::new(0.8, 1.0, 0.3), 0.0).unwrap();
/// let view = ObjectGeom::from_box(&bed);
/// assert!(view.mesh.is_none());
/// ```
#[derive(Debug, Clone, Copy)]
pub struct ObjectGeom<'a> {
    /// The object's oriented box (its mesh bounds in the object frame, placed by its pose).
    pub obb: &'a Obb,
    /// The mesh in the object frame and `world_from_object`, or `None` when the object is its
    /// box.
    pub mesh: Option<(&'a Mesh, &'a Isometry3)>,
}

impl<'a> ObjectGeom<'a> {
    /// A solid box object.
    #[inline]
    pub fn from_box(obb: &'a Obb) -> Self {
        ObjectGeom { obb, mesh: None }
    }

    /// An object with a mesh (object frame) placed by `pose`; `obb` must be its box.
    #[inline]
    pub fn with_mesh(obb: &'a Obb, mesh: &'a Mesh, pose: &'a Isometry3) -> Self {
        ObjectGeom {
            obb,
            mesh: Some((mesh, pose)),
        }
    }

    /// The view of a scene object. Box objects (made with `SceneObject::new_box`) are
    /// handled as exact boxes; other objects carry their mesh.
    pub fn from_object(object: &'a SceneObject) -> Self {
        if object.box_half_extents().is_some() {
            ObjectGeom::from_box(object.obb())
        } else {
            ObjectGeom::with_mesh(object.obb(), object.mesh(), object.pose())
        }
    }

    /// This object seen as its box only (the mesh dropped).
    #[inline]
    pub fn as_box(&self) -> ObjectGeom<'a> {
        ObjectGeom::from_box(self.obb)
    }
}
