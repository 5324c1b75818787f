//! Per-object geometry shared by several metrics, computed once per evaluation.

use std::collections::HashMap;
use std::sync::Arc;

use rayon::prelude::*;
use sceneeval_geom::{Mesh, Point2, Point3, Real, Vector3};
use sceneeval_scene::{Deadline, DeadlineExceeded, Scene, SceneObject};
use serde::{Deserialize, Serialize};

use crate::plane::{bounds, convex_hull_fast};

/// Default `walkable_height_m` of navigability, accessibility and opening clearance, metres:
/// objects whose top is at most this above their floor (rugs, carpets, doormats) are walked
/// over rather than obstacles. The same 5 cm a door sill may have and still be passable; the
/// reference (and the `reference` preset) uses 0, so a rug blocks.
pub const DEFAULT_WALKABLE_HEIGHT: Real = 0.05;

/// How an object's footprint on the floor plan is taken by navigability and accessibility.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Footprint {
    /// The convex hull of the object's mesh projected on the floor (default): a round or
    /// oval object (a bath, a round table) leaves its box's corners free. A deliberate
    /// deviation from the reference.
    #[default]
    ConvexHull,
    /// The projection of the object's bounding box (its OBB), as the reference draws it:
    /// round and L-shaped furniture block their whole rectangle.
    BoundingBox,
}

/// What the 2-D metrics need to know about one object.
#[derive(Debug, Clone)]
pub(crate) struct ObjectInfo {
    /// Convex hull of the world mesh projected on the floor plane, counter-clockwise.
    pub footprint: Vec<Point2>,
    /// Bounding rectangle of the footprint.
    pub bounds: (Point2, Point2),
    /// The projection of the object's OBB (convex hull of its eight projected corners),
    /// counter-clockwise.
    pub rectangle: Vec<Point2>,
    /// Bounding rectangle of `rectangle`.
    pub rectangle_bounds: (Point2, Point2),
    /// Floor height under the object: the floor of the room containing the centre of its world
    /// bounds, else the lowest floor of the scene, else 0.
    pub floor_z: Real,
    /// Lowest and highest world z of the mesh.
    pub min_z: Real,
    /// Highest world z of the mesh.
    pub max_z: Real,
}

impl ObjectInfo {
    /// The footprint of the given kind and its bounding rectangle.
    pub fn footprint_of(&self, kind: Footprint) -> (&[Point2], &(Point2, Point2)) {
        match kind {
            Footprint::ConvexHull => (&self.footprint, &self.bounds),
            Footprint::BoundingBox => (&self.rectangle, &self.rectangle_bounds),
        }
    }

    /// Whether the object obstructs the floor plan: some part of it is lower than `cutoff`
    /// above its floor (it would hit a person that tall), and its top is higher than
    /// `walkable` above the floor (so it is not a rug one walks over).
    pub fn obstructs(&self, cutoff: Real, walkable: Real) -> bool {
        self.min_z - self.floor_z < cutoff && self.max_z - self.floor_z > walkable
    }
}

/// The lowest floor of the scene, or 0 without rooms.
pub(crate) fn lowest_floor(scene: &Scene) -> Real {
    scene
        .rooms()
        .iter()
        .map(|r| r.floor_z())
        .reduce(Real::min)
        .unwrap_or(0.0)
}

/// Whether a pose keeps +z pointing up (a rotation about z only, up to rounding).
fn is_upright(object: &SceneObject) -> bool {
    (object.pose().rotation * Vector3::z() - Vector3::z()).norm() < 1e-12
}

/// The convex hull of a mesh's vertices projected on its own xy plane.
fn local_hull(mesh: &Mesh) -> Vec<Point2> {
    let local: Vec<Point2> = mesh.vertices().iter().map(|v| Point2::new(v.x, v.y)).collect();
    convex_hull_fast(&local)
}

/// The footprint of one placed object (see [`ObjectInfo::footprint`]). For an upright object
/// the hull is taken in the object frame (`local`, if already known for its mesh) and placed:
/// a rotation about z commutes with the projection.
pub(crate) fn footprint(object: &SceneObject, local: Option<&[Point2]>) -> Vec<Point2> {
    let pose = object.pose();
    if is_upright(object) {
        let place = |p: &Point2| {
            let w = pose * sceneeval_geom::Point3::new(p.x, p.y, 0.0);
            Point2::new(w.x, w.y)
        };
        match local {
            Some(hull) => hull.iter().map(place).collect(),
            None => local_hull(object.mesh()).iter().map(place).collect(),
        }
    } else {
        let world: Vec<Point2> = object
            .mesh()
            .vertices()
            .iter()
            .map(|v| {
                let w = pose * v;
                Point2::new(w.x, w.y)
            })
            .collect();
        convex_hull_fast(&world)
    }
}

/// The projection of an object's OBB on the floor plan (see [`Footprint::BoundingBox`]).
pub(crate) fn rectangle(object: &SceneObject) -> Vec<Point2> {
    let b = object.mesh().aabb();
    let corners: Vec<Point2> = (0..8)
        .map(|k| {
            let p = Point3::new(
                if k & 1 == 0 { b.min.x } else { b.max.x },
                if k & 2 == 0 { b.min.y } else { b.max.y },
                if k & 4 == 0 { b.min.z } else { b.max.z },
            );
            let w = object.pose() * p;
            Point2::new(w.x, w.y)
        })
        .collect();
    convex_hull_fast(&corners)
}

/// [`ObjectInfo`] for every object, in scene order.
pub(crate) fn object_infos(scene: &Scene) -> Vec<ObjectInfo> {
    let infos = object_infos_within(scene, &Deadline::none(), "");
    // Without a deadline nothing can stop it.
    infos.unwrap_or_default()
}

/// [`object_infos`] for `stage` (the metric that needs them), polling `deadline` per mesh
/// hull and per object.
pub(crate) fn object_infos_within(
    scene: &Scene,
    deadline: &Deadline,
    stage: &'static str,
) -> Result<Vec<ObjectInfo>, DeadlineExceeded> {
    let lowest = lowest_floor(scene);
    // Objects sharing a mesh (the same asset placed several times) share its local hull.
    let mut meshes: Vec<&Arc<Mesh>> = Vec::new();
    let mut seen: HashMap<*const Mesh, usize> = HashMap::new();
    let slot: Vec<Option<usize>> = scene
        .objects()
        .iter()
        .map(|o| {
            is_upright(o).then(|| {
                *seen.entry(Arc::as_ptr(o.mesh())).or_insert_with(|| {
                    meshes.push(o.mesh());
                    meshes.len() - 1
                })
            })
        })
        .collect();
    let hulls: Vec<Vec<Point2>> = meshes
        .par_iter()
        .map(|m| {
            deadline.check(stage)?;
            Ok(local_hull(m))
        })
        .collect::<Result<_, _>>()?;
    scene
        .objects()
        .par_iter()
        .zip(slot.par_iter())
        .map(|(o, slot)| {
            deadline.check(stage)?;
            let fp = footprint(o, slot.map(|k| hulls[k].as_slice()));
            let aabb = o.world_aabb();
            let c = aabb.center();
            let floor_z = scene
                .room_at(&Point2::new(c.x, c.y))
                .map_or(lowest, |r| r.floor_z());
            let bounds_of = |poly: &[Point2]| {
                if poly.is_empty() {
                    (Point2::new(c.x, c.y), Point2::new(c.x, c.y))
                } else {
                    bounds(poly)
                }
            };
            let rect = rectangle(o);
            Ok(ObjectInfo {
                bounds: bounds_of(&fp),
                footprint: fp,
                rectangle_bounds: bounds_of(&rect),
                rectangle: rect,
                floor_z,
                min_z: aabb.min.z,
                max_z: aabb.max.z,
            })
        })
        .collect()
}
