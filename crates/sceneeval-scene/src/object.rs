use std::sync::Arc;

use sceneeval_geom::na::UnitQuaternion;
use sceneeval_geom::{Aabb, Isometry3, Mesh, Obb, Real, Vector3};

use sceneeval_geom::Side;

use crate::{Category, Element, ObjectId, SceneError, SupportType};

/// One object of a scene: a mesh in the object frame placed by a rigid pose, with the metadata
/// evaluation needs.
///
/// The object frame follows the project convention (z up, front = local -y). Any scale the
/// source applied is already baked into [`SceneObject::mesh`] (see [`SceneObject::scale`]),
/// so the pose is rigid and the OBB axes are orthonormal. The OBB and the world AABB are cached
/// and kept in step with the pose by [`SceneObject::set_pose`].
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    id: ObjectId,
    model_id: Option<String>,
    index: Option<i64>,
    category: Option<String>,
    description: Option<String>,
    support_type: Option<SupportType>,
    functional_sides: Option<Vec<Side>>,
    mesh: Arc<Mesh>,
    box_half_extents: Option<Vector3>,
    scale: Vector3,
    asset_front: Option<Vector3>,
    pose: Isometry3,
    obb: Obb,
    world_aabb: Aabb,
}

impl SceneObject {
    /// An object whose geometry is `mesh` (object frame), placed by `pose` (`world_from_object`).
    ///
    /// # Errors
    /// [`SceneError::NonFinitePose`] when the pose has a NaN or infinite component.
    pub fn from_mesh(id: impl Into<ObjectId>, mesh: Arc<Mesh>, pose: Isometry3) -> Result<Self, SceneError> {
        let id = id.into();
        let pose = checked_pose(&id, pose)?;
        let obb = Obb::from_local_aabb(mesh.aabb(), &pose);
        let world_aabb = mesh.world_aabb(&pose);
        Ok(SceneObject {
            id,
            model_id: None,
            index: None,
            category: None,
            description: None,
            support_type: None,
            functional_sides: None,
            mesh,
            box_half_extents: None,
            scale: Vector3::repeat(1.0),
            asset_front: None,
            pose,
            obb,
            world_aabb,
        })
    }

    /// A solid box object with half extents `half_extents` (metres along the object frame's
    /// x, y, z: half the width, depth and height, as for [`Obb`]), its centre at the object
    /// origin, placed by `pose` (`world_from_object`, the same pose type [`SceneObject::set_pose`]
    /// moves it with). Its mesh is the closed 12-triangle box. For an upright object turned by
    /// a yaw, build the pose with [`sceneeval_geom::conventions::pose_from_yaw`].
    ///
    /// ```
    /// use sceneeval_geom::{conventions::pose_from_yaw, Point3, Vector3};
    /// use sceneeval_scene::SceneObject;
    /// // A 1.6 x 2.0 x 0.6 m bed standing on the floor at (2, 3): its centre is 0.3 m up.
    /// let bed = SceneObject::new_box("bed", Vector3::new(0.8, 1.0, 0.3), pose_from_yaw(Point3::new(2.0, 3.0, 0.3), 0.0))
    ///     .unwrap();
    /// assert_eq!(bed.obb().half_extents, Vector3::new(0.8, 1.0, 0.3));
    /// assert_eq!(bed.world_aabb().min, Point3::new(1.2, 2.0, 0.0));
    /// ```
    ///
    /// # Errors
    /// [`SceneError::Geometry`] for negative or non-finite half extents,
    /// [`SceneError::NonFinitePose`] for a non-finite pose.
    pub fn new_box(
        id: impl Into<ObjectId>,
        half_extents: Vector3,
        pose: Isometry3,
    ) -> Result<Self, SceneError> {
        let id = id.into();
        let mesh = Mesh::cuboid(&half_extents).map_err(|source| SceneError::Geometry {
            element: Box::new(Element::Object(id.clone())),
            source,
        })?;
        let mut obj = SceneObject::from_mesh(id, Arc::new(mesh), pose)?;
        obj.box_half_extents = Some(half_extents);
        Ok(obj)
    }

    /// Sets the asset model id (`PREFIX.ID` in sceneState files).
    pub fn with_model_id(mut self, model_id: impl Into<String>) -> Self {
        self.model_id = Some(model_id.into());
        self
    }

    /// Sets the sceneState `index` of the object.
    pub fn with_index(mut self, index: i64) -> Self {
        self.index = Some(index);
        self
    }

    /// Sets the category (e.g. `nightstand`).
    pub fn with_category(mut self, category: impl Into<Category>) -> Self {
        self.category = Some(category.into().into_string());
        self
    }

    /// Sets the free-text description.
    pub fn with_description(mut self, description: impl Into<String>) -> Self {
        self.description = Some(description.into());
        self
    }

    /// States what the object should rest on (see [`crate::hints`]). The support metric checks
    /// the object against it; it is never inferred from the placement.
    pub fn with_support_type(mut self, support_type: SupportType) -> Self {
        self.support_type = Some(support_type);
        self
    }

    /// States the object's functional sides, the sides that must stay free to use it (see
    /// [`crate::hints`]); an empty list for an object without one. Only the horizontal sides
    /// (left, right, front, back) are meaningful: others are dropped, and the list is sorted
    /// and deduplicated.
    pub fn with_functional_sides(mut self, sides: impl IntoIterator<Item = Side>) -> Self {
        let (mut sides, vertical): (Vec<Side>, Vec<Side>) =
            sides.into_iter().partition(|s| Side::HORIZONTAL.contains(s));
        if !vertical.is_empty() {
            tracing::debug!(object = %self.id, ?vertical, "vertical functional sides dropped");
        }
        sides.sort_unstable();
        sides.dedup();
        self.functional_sides = Some(sides);
        self
    }

    /// Records the per-axis scale (object frame) that was baked into the mesh by the loader.
    /// Informational: the mesh already carries it.
    pub fn with_scale(mut self, scale: Vector3) -> Self {
        self.scale = scale;
        self
    }

    /// Records the front that the object's source declared for it in its own frame when that
    /// is not the model's -y (sceneState `objectFrontVector`, e.g. `+y` for SceneAgent
    /// assets). Informational, like [`SceneObject::with_scale`]: the loader has already turned
    /// the mesh and the pose so that local -y is the front; writers use it to write the
    /// file's convention back and renderers to turn the asset's look the same way.
    pub fn with_asset_front(mut self, front: Vector3) -> Self {
        self.asset_front = Some(front);
        self
    }

    /// Moves the object, updating its OBB and world AABB (no allocation; the mesh is shared and
    /// unchanged).
    ///
    /// # Errors
    /// [`SceneError::NonFinitePose`]; the object is then left where it was.
    pub fn set_pose(&mut self, pose: Isometry3) -> Result<(), SceneError> {
        let pose = checked_pose(&self.id, pose)?;
        self.pose = pose;
        self.obb = Obb::from_local_aabb(self.mesh.aabb(), &pose);
        self.world_aabb = self.mesh.world_aabb(&pose);
        Ok(())
    }

    /// The stable id.
    #[inline]
    pub fn id(&self) -> &ObjectId {
        &self.id
    }

    /// The asset model id, if the object came from an asset.
    #[inline]
    pub fn model_id(&self) -> Option<&str> {
        self.model_id.as_deref()
    }

    /// The sceneState `index`, if the object came from a sceneState file.
    #[inline]
    pub fn index(&self) -> Option<i64> {
        self.index
    }

    /// The category, if known (from the scene file or the asset's metadata).
    #[inline]
    pub fn category(&self) -> Option<&str> {
        self.category.as_deref()
    }

    /// The description, if known.
    #[inline]
    pub fn description(&self) -> Option<&str> {
        self.description.as_deref()
    }

    /// The mesh in the object frame (scale applied), shared between objects of the same asset.
    #[inline]
    pub fn mesh(&self) -> &Arc<Mesh> {
        &self.mesh
    }

    /// For a box object, its half extents (the mesh is then exactly that box).
    #[inline]
    pub fn box_half_extents(&self) -> Option<Vector3> {
        self.box_half_extents
    }

    /// The per-axis object-frame scale baked into the mesh (1, 1, 1 when unscaled).
    #[inline]
    pub fn scale(&self) -> Vector3 {
        self.scale
    }

    /// The front the object's source declared in its own frame, when not the model's -y
    /// (see [`SceneObject::with_asset_front`]); `None` for the model's convention.
    #[inline]
    pub fn asset_front(&self) -> Option<Vector3> {
        self.asset_front
    }

    /// `world_from_object`.
    #[inline]
    pub fn pose(&self) -> &Isometry3 {
        &self.pose
    }

    /// The object's oriented box: the mesh bounds in the object frame, placed by the pose.
    #[inline]
    pub fn obb(&self) -> &Obb {
        &self.obb
    }

    /// The exact world-axis-aligned bounds of the placed mesh.
    #[inline]
    pub fn world_aabb(&self) -> &Aabb {
        &self.world_aabb
    }

    /// The stated support type, if the scene's author gave one.
    #[inline]
    pub fn support_type(&self) -> Option<SupportType> {
        self.support_type
    }

    /// The stated functional sides (horizontal, sorted, no duplicates; possibly empty), if the
    /// scene's author gave them.
    #[inline]
    pub fn functional_sides(&self) -> Option<&[Side]> {
        self.functional_sides.as_deref()
    }

    /// The yaw of the pose (radians about +z; see `sceneeval_geom::conventions::yaw_of`).
    #[inline]
    pub fn yaw(&self) -> Real {
        self.obb.yaw()
    }
}

fn checked_pose(id: &ObjectId, pose: Isometry3) -> Result<Isometry3, SceneError> {
    let q = pose.rotation.quaternion();
    let finite =
        pose.translation.vector.iter().all(|v| v.is_finite()) && q.coords.iter().all(|v| v.is_finite());
    if !finite || q.norm() == 0.0 {
        return Err(SceneError::NonFinitePose {
            object: id.to_string(),
        });
    }
    // Renormalise a quaternion that drifted (e.g. in an optimiser) so it is still a rotation, but
    // leave one that is unit up to rounding bit for bit: poses must survive a write/read round
    // trip unchanged.
    let mut pose = pose;
    if (q.norm_squared() - 1.0).abs() > 1e-12 {
        pose.rotation = UnitQuaternion::new_normalize(*q);
    }
    Ok(pose)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Point3;
    use sceneeval_geom::conventions::pose_from_yaw;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn box_object_has_expected_obb() {
        let obj = SceneObject::new_box(
            "bed",
            Vector3::new(0.8, 1.0, 0.3),
            pose_from_yaw(Point3::new(2.0, 1.0, 0.3), FRAC_PI_2),
        )
        .unwrap()
        .with_category("bed");
        let obb = obj.obb();
        assert!((obb.center - Point3::new(2.0, 1.0, 0.3)).norm() < 1e-12);
        assert!((obb.half_extents - Vector3::new(0.8, 1.0, 0.3)).norm() < 1e-12);
        assert!((obj.yaw() - FRAC_PI_2).abs() < 1e-12);
        // Turned 90 degrees, the bed's 2 m depth lies along world x.
        let aabb = obj.world_aabb();
        assert!((aabb.extents() - Vector3::new(2.0, 1.6, 0.6)).norm() < 1e-12);
        assert_eq!(obj.box_half_extents(), Some(Vector3::new(0.8, 1.0, 0.3)));
        assert_eq!(obj.category(), Some("bed"));
    }

    #[test]
    fn placement_hints_are_kept_and_normalised() {
        let obj =
            SceneObject::new_box("tv", Vector3::repeat(0.5), pose_from_yaw(Point3::origin(), 0.0)).unwrap();
        assert_eq!(obj.support_type(), None);
        assert_eq!(obj.functional_sides(), None);
        let obj = obj.with_support_type(SupportType::Wall).with_functional_sides([
            Side::Left,
            Side::Top,
            Side::Front,
            Side::Left,
        ]);
        assert_eq!(obj.support_type(), Some(SupportType::Wall));
        // Vertical sides dropped; sorted in `Side` order; duplicates removed.
        assert_eq!(obj.functional_sides(), Some(&[Side::Left, Side::Front][..]));
        let none = obj.with_functional_sides([]);
        assert_eq!(none.functional_sides(), Some(&[][..]));
    }

    #[test]
    fn set_pose_moves_cached_boxes() {
        let mut obj =
            SceneObject::new_box("a", Vector3::repeat(0.5), pose_from_yaw(Point3::origin(), 0.0)).unwrap();
        obj.set_pose(Isometry3::translation(5.0, 0.0, 0.0)).unwrap();
        assert!((obj.obb().center - Point3::new(5.0, 0.0, 0.0)).norm() < 1e-12);
        assert!((obj.world_aabb().center() - Point3::new(5.0, 0.0, 0.0)).norm() < 1e-12);
        let mut bad = Isometry3::identity();
        bad.translation.vector.x = f64::NAN;
        assert!(matches!(obj.set_pose(bad), Err(SceneError::NonFinitePose { .. })));
    }

    #[test]
    fn rejects_bad_boxes() {
        assert!(
            SceneObject::new_box(
                "a",
                Vector3::new(-0.5, 0.5, 0.5),
                pose_from_yaw(Point3::origin(), 0.0)
            )
            .is_err()
        );
        assert!(
            SceneObject::new_box(
                "a",
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::origin(), f64::NAN)
            )
            .is_err()
        );
        assert!(
            SceneObject::new_box(
                "a",
                Vector3::repeat(0.5),
                pose_from_yaw(Point3::new(f64::INFINITY, 0.0, 0.0), 0.0)
            )
            .is_err()
        );
    }

    #[test]
    fn mesh_obb_is_local_bounds_placed_by_pose() {
        // A mesh whose bounds are off-centre in the object frame: x in [0, 2], y in [-1, 0], z in [0, 1].
        let mesh = Mesh::cuboid(&Vector3::new(1.0, 0.5, 0.5))
            .unwrap()
            .transformed(
                &sceneeval_geom::Matrix3::identity(),
                &Vector3::new(1.0, -0.5, 0.5),
            )
            .unwrap();
        let pose = Isometry3::new(Vector3::new(10.0, 0.0, 0.0), Vector3::z() * FRAC_PI_2);
        let obj = SceneObject::from_mesh("m", Arc::new(mesh), pose).unwrap();
        // Local centre (1, -0.5, 0.5) turned 90 degrees: (0.5, 1, 0.5), then moved by (10, 0, 0).
        assert!((obj.obb().center - Point3::new(10.5, 1.0, 0.5)).norm() < 1e-12);
        assert!((obj.obb().half_extents - Vector3::new(1.0, 0.5, 0.5)).norm() < 1e-12);
    }
}
