//! The one place that reads the scene model: everything the renderer needs from a
//! [`Scene`], copied into plain structures (meshes are shared, not copied).

use std::sync::Arc;

use sceneeval_geom::{Aabb, Isometry3, Mesh, Obb, Real, Vector3};
use sceneeval_scene::Scene;

/// An object as the renderer sees it.
#[derive(Debug, Clone)]
pub(crate) struct ObjectInput {
    /// The object's id (as `sceneeval inspect` prints it).
    pub id: String,
    /// The asset's model id, if the object shows an asset.
    pub model_id: Option<String>,
    /// The geometry in the object frame, scale applied.
    pub mesh: Arc<Mesh>,
    /// `world_from_object` (rigid).
    pub pose: Isometry3,
    /// The object-frame scale baked into `mesh`.
    pub scale: Vector3,
    /// The front the object's scene file declared (`objectFrontVector`), if not -y: its
    /// asset's look is turned the same way as its mesh.
    pub asset_front: Option<Vector3>,
    /// Whether the object is a plain box (no asset).
    pub is_box: bool,
    /// The oriented box (mesh bounds in the object frame, placed by the pose).
    pub obb: Obb,
    /// The exact world-axis-aligned bounds.
    pub world_aabb: Aabb,
}

/// A wall: its world-space mesh (openings cut out) and base height.
#[derive(Debug, Clone)]
pub(crate) struct WallInput {
    pub mesh: Arc<Mesh>,
    pub base_z: Real,
}

/// What a scene holds for rendering. Doors and windows are holes in the wall meshes and are
/// not drawn themselves (the reference hides their planes); ceilings are not drawn (the
/// reference builds none).
#[derive(Debug, Clone)]
pub(crate) struct SceneInput {
    pub objects: Vec<ObjectInput>,
    /// World-space floor meshes.
    pub floors: Vec<Arc<Mesh>>,
    pub walls: Vec<WallInput>,
}

impl SceneInput {
    pub(crate) fn from_scene(scene: &Scene) -> SceneInput {
        let objects = scene
            .objects()
            .iter()
            .map(|o| ObjectInput {
                id: o.id().to_string(),
                model_id: o.model_id().map(str::to_owned),
                mesh: Arc::clone(o.mesh()),
                pose: *o.pose(),
                scale: o.scale(),
                asset_front: o.asset_front(),
                is_box: o.box_half_extents().is_some(),
                obb: *o.obb(),
                world_aabb: *o.world_aabb(),
            })
            .collect();
        let floors = scene.rooms().iter().map(|r| Arc::clone(r.floor_mesh())).collect();
        // A wall whose openings cover it entirely has no solid left to draw.
        let walls = scene
            .walls()
            .filter_map(|(_, w)| {
                w.mesh().map(|mesh| WallInput {
                    mesh: Arc::clone(mesh),
                    base_z: w.base_z(),
                })
            })
            .collect();
        SceneInput {
            objects,
            floors,
            walls,
        }
    }

    pub(crate) fn object_index(&self, id: &str) -> Option<usize> {
        self.objects.iter().position(|o| o.id == id)
    }
}
