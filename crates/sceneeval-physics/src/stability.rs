//! The entry point: [`Stability`] evaluates or settles one scene.

use std::collections::HashMap;
use std::sync::Arc;

use rayon::prelude::*;
use sceneeval_geom::Isometry3;
use sceneeval_scene::{Deadline, Scene, SupportType};

use crate::cache::DecompositionCache;
use crate::decompose::Decomposition;
use crate::simulate::{Outcome, simulate};
use crate::{PhysicsError, StabilityParams, StabilityReport};

/// The deadline's check as the stages call it: `Err` once the stage named must stop.
pub(crate) type Check<'a> = dyn Fn(&'static str) -> Result<(), PhysicsError> + Sync + 'a;

/// The stability metric with validated parameters.
///
/// Every call takes the scene, one support type per object (scene order; `None` for unknown,
/// treated as `ground`: never welded as architectural), the decomposition cache shared by
/// the run, and the scene's [`Deadline`], checked before each mesh is decomposed and every 64
/// time steps ([`PhysicsError::DeadlineExceeded`] once it has passed). One mesh's
/// decomposition is not interrupted; it is bounded by the decomposition parameters and the
/// mesh's distinct triangles (see [`crate::decompose`]).
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
    /// [`PhysicsError::DeadlineExceeded`], [`PhysicsError::Geometry`],
    /// [`PhysicsError::Diverged`].
    pub fn evaluate(
        &self,
        scene: &Scene,
        support_types: &[Option<SupportType>],
        cache: &DecompositionCache,
        deadline: &Deadline,
    ) -> Result<StabilityReport, PhysicsError> {
        Ok(self
            .run(scene, support_types, cache, &|stage| Ok(deadline.check(stage)?))?
            .report)
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
        deadline: &Deadline,
    ) -> Result<(Vec<Isometry3>, StabilityReport), PhysicsError> {
        let Outcome { report, poses } =
            self.run(scene, support_types, cache, &|stage| Ok(deadline.check(stage)?))?;
        Ok((poses, report))
    }

    /// The simulation, calling `check` with the stage's name at each of the deadline's checks.
    fn run(
        &self,
        scene: &Scene,
        support_types: &[Option<SupportType>],
        cache: &DecompositionCache,
        check: &Check<'_>,
    ) -> Result<Outcome, PhysicsError> {
        if support_types.len() != scene.objects().len() {
            return Err(PhysicsError::SupportTypeCount {
                objects: scene.objects().len(),
                given: support_types.len(),
            });
        }
        if scene.rooms().is_empty() {
            return Err(PhysicsError::NoFloor {
                scene: scene.name().unwrap_or("<unnamed>").to_owned(),
            });
        }
        let bodies = decompose_objects(scene, &self.params, cache, check)?;
        simulate(scene, support_types, &bodies, &self.params, check)
    }
}

/// The convex pieces of every object (scene order): box objects one cuboid, meshes through
/// the cache, each distinct mesh once, distinct meshes in parallel (the result does not depend
/// on the thread count: each decomposition is a pure function of its mesh).
fn decompose_objects(
    scene: &Scene,
    params: &StabilityParams,
    cache: &DecompositionCache,
    check: &Check<'_>,
) -> Result<Vec<Arc<Decomposition>>, PhysicsError> {
    check("decomposition")?;
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
            check("decomposition")?;
            Ok(cache.get(scene.objects()[i].mesh(), &params.decomposition))
        })
        .collect::<Result<_, PhysicsError>>()?;
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

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicUsize, Ordering};

    use sceneeval_geom::{Isometry3, Vector3};
    use sceneeval_scene::SceneObject;

    use super::*;

    #[test]
    fn the_deadline_is_checked_once_per_mesh_and_every_64_steps() {
        // A box falling in the bedroom for 1 s without sleeping: 1,000 steps, checked at
        // steps 0, 64, ..., 960 (16 checks), after the one check of the decomposition (no
        // mesh to decompose).
        let scene = Scene::builder()
            .room_builder(sceneeval_test_support::bedroom("r"))
            .object(
                SceneObject::new_box("box", Vector3::repeat(0.2), Isometry3::translation(2.0, 2.5, 1.0))
                    .unwrap(),
            )
            .build()
            .unwrap();
        let s = Stability::new(StabilityParams {
            duration_s: 1.0,
            sleep_speed_m_s: 0.0,
            ..StabilityParams::default()
        })
        .unwrap();
        let cache = DecompositionCache::in_memory();
        let checks = [AtomicUsize::new(0), AtomicUsize::new(0)];
        let counting = |stage: &'static str| {
            checks[usize::from(stage == "simulation")].fetch_add(1, Ordering::Relaxed);
            Ok(())
        };
        let out = s.run(&scene, &[None], &cache, &counting).unwrap();
        assert_eq!(out.report.steps, 1000);
        assert_eq!(checks.map(|c| c.into_inner()), [1, 16]);
        // A deadline passing after the decomposition stops the simulation at its first check.
        let late = |stage: &'static str| match stage {
            "simulation" => Err(PhysicsError::DeadlineExceeded {
                stage,
                budget_seconds: Some(2.0),
            }),
            _ => Ok(()),
        };
        let err = s.run(&scene, &[None], &cache, &late).err().unwrap();
        assert!(
            matches!(
                err,
                PhysicsError::DeadlineExceeded {
                    stage: "simulation",
                    ..
                }
            ),
            "{err}"
        );
        assert_eq!(
            err.to_string(),
            "stability stopped during simulation: time budget exceeded (the scene's 2 s are used up)"
        );
    }
}
