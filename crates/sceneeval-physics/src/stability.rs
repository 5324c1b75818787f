//! The entry point: [`Stability`] evaluates or settles one scene.

use std::collections::HashMap;
use std::sync::Arc;

use rayon::prelude::*;
use sceneeval_geom::Isometry3;
use sceneeval_scene::{Scene, SupportType};

use crate::cache::DecompositionCache;
use crate::decompose::Decomposition;
use crate::simulate::{Outcome, simulate};
use crate::{PhysicsError, StabilityParams, StabilityReport};

/// The stability metric with validated parameters.
///
/// Every call takes the scene, one support type per object (scene order; `None` for unknown,
/// treated as `ground`: never welded as architectural), the decomposition cache shared by
/// the run, and a stop signal polled between meshes during decomposition and every 64 time
/// steps (return `true` to stop with [`PhysicsError::Stopped`]).
#[derive(Debug, Clone)]
pub struct Stability {
    params: StabilityParams,
}

impl Stability {
    /// The metric with these parameters.
    ///
    /// # Errors
    /// [`PhysicsError::InvalidParameter`] (see [`StabilityParams::validate`]).
    pub fn new(params: StabilityParams) -> Result<Self, PhysicsError> {
        params.validate()?;
        Ok(Stability { params })
    }

    /// The parameters.
    pub fn params(&self) -> &StabilityParams {
        &self.params
    }

    /// Simulates the scene and says, per object, whether it stayed where it was put.
    ///
    /// # Errors
    /// [`PhysicsError::SupportTypeCount`], [`PhysicsError::NoFloor`] (a scene without rooms),
    /// [`PhysicsError::Stopped`], [`PhysicsError::Geometry`], [`PhysicsError::Diverged`].
    pub fn evaluate(
        &self,
        scene: &Scene,
        support_types: &[Option<SupportType>],
        cache: &DecompositionCache,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<StabilityReport, PhysicsError> {
        Ok(self.run(scene, support_types, cache, stop)?.report)
    }

    /// Every object's pose after the simulation (scene order; welded objects where they
    /// were), for writing the scene back settled, with the report that goes with it.
    ///
    /// # Errors
    /// As [`Stability::evaluate`].
    pub fn settle(
        &self,
        scene: &Scene,
        support_types: &[Option<SupportType>],
        cache: &DecompositionCache,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<(Vec<Isometry3>, StabilityReport), PhysicsError> {
        let Outcome { report, poses } = self.run(scene, support_types, cache, stop)?;
        Ok((poses, report))
    }

    fn run(
        &self,
        scene: &Scene,
        support_types: &[Option<SupportType>],
        cache: &DecompositionCache,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Outcome, PhysicsError> {
        if support_types.len() != scene.objects().len() {
            return Err(PhysicsError::SupportTypeCount {
                objects: scene.objects().len(),
                given: support_types.len(),
            });
        }
        if scene.rooms().is_empty() {
            return Err(PhysicsError::NoFloor {
                scene: scene.id().unwrap_or("<unnamed>").to_owned(),
            });
        }
        let bodies = decompose_objects(scene, &self.params, cache, stop)?;
        simulate(scene, support_types, &bodies, &self.params, stop)
    }
}

/// The convex pieces of every object (scene order): box objects one cuboid, meshes through
/// the cache, each distinct mesh once, distinct meshes in parallel (the result does not depend
/// on the thread count: each decomposition is a pure function of its mesh).
fn decompose_objects(
    scene: &Scene,
    params: &StabilityParams,
    cache: &DecompositionCache,
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Arc<Decomposition>>, PhysicsError> {
    // Objects of one asset at one scale share their mesh: decompose each shared mesh once.
    let mut distinct: Vec<usize> = Vec::new();
    let mut slot_of_mesh: HashMap<*const sceneeval_geom::Mesh, usize> = HashMap::new();
    let mut slot = Vec::with_capacity(scene.objects().len());
    for (i, o) in scene.objects().iter().enumerate() {
        if o.box_half_extents().is_some() {
            slot.push(None);
            continue;
        }
        let s = *slot_of_mesh.entry(Arc::as_ptr(o.mesh())).or_insert_with(|| {
            distinct.push(i);
            distinct.len() - 1
        });
        slot.push(Some(s));
    }
    let decomposed: Vec<Arc<Decomposition>> = distinct
        .par_iter()
        .map(|&i| {
            if stop() {
                return Err(PhysicsError::Stopped {
                    stage: "decomposition",
                });
            }
            Ok(cache.get(scene.objects()[i].mesh(), &params.decomposition))
        })
        .collect::<Result<_, _>>()?;
    Ok(scene
        .objects()
        .iter()
        .zip(slot)
        .map(|(o, s)| match (s, o.box_half_extents()) {
            (Some(s), _) => decomposed[s].clone(),
            (None, Some(h)) => Arc::new(Decomposition::cuboid(h)),
            // Unreachable: an object without a slot is a box object.
            (None, None) => cache.get(o.mesh(), &params.decomposition),
        })
        .collect())
}
