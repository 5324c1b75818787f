//! One simulation of a scene: bodies from the decompositions, welds, stepping, verdicts.

use std::sync::Arc;

use rapier3d_f64::prelude::*;
use sceneeval_geom::parry_adapter::{pose_from_parry, to_parry_pose, vec_from_parry};
use sceneeval_geom::{Isometry3, Point3, Real};
use sceneeval_scene::{Scene, SupportType};

use crate::arch::{ARCH_TAG, add_architecture};
use crate::contact::ContactDispatcher;
use crate::decompose::Decomposition;
use crate::params::GRAVITY;
use crate::report::{BodyShape, Interpenetration, ObjectStability, Pose, StabilityReport, WeldReason};
use crate::stability::Check;
use crate::{MassModel, PhysicsError, StabilityParams};

/// The deadline is checked every this many steps.
const POLL_STEPS: usize = 64;

/// What one simulation gives: the report and every object's final pose (scene order).
pub(crate) struct Outcome {
    pub report: StabilityReport,
    pub poses: Vec<Isometry3>,
}

/// Simulates `scene` whose objects are made of `bodies` (scene order).
pub(crate) fn simulate(
    scene: &Scene,
    support_types: &[Option<SupportType>],
    bodies: &[Arc<Decomposition>],
    params: &StabilityParams,
    check: &Check<'_>,
) -> Result<Outcome, PhysicsError> {
    let mut built = build_world(scene, bodies, params)?;

    // Contacts at the start, every body free: the deepest interpenetration of each object.
    built.world.detect_collisions(&(), &());
    let interpenetration =
        deepest_interpenetrations(&built.world, scene, &built.arch_names, params.penetration_depth_m);
    let weld_reasons: Vec<Option<WeldReason>> = (0..built.handles.len())
        .map(|i| weld_reason(params, support_types[i], interpenetration[i].as_ref()))
        .collect();
    built.weld(&weld_reasons);
    let local_com: Vec<Point3> = built.handles.iter().map(|&h| built.local_com(h)).collect();
    let free = weld_reasons.iter().filter(|r| r.is_none()).count();

    let max_steps = if free == 0 { 0 } else { params.steps() };
    let mut steps = 0;
    while steps < max_steps {
        if steps % POLL_STEPS == 0 {
            check("simulation")?;
        }
        built.world.step();
        steps += 1;
        if params.sleep_speed_m_s > 0.0 && built.world.islands.num_active_bodies() == 0 {
            tracing::debug!(steps, "every free body is asleep: the simulation stops early");
            break;
        }
    }

    let mut objects = Vec::with_capacity(built.handles.len());
    let mut poses = Vec::with_capacity(built.handles.len());
    let mut unstable = 0;
    for (i, object) in scene.objects().iter().enumerate() {
        let start = *object.pose();
        let welded = weld_reasons[i].is_some();
        let end = if welded {
            start
        } else {
            built
                .final_pose(built.handles[i])
                .ok_or_else(|| PhysicsError::Diverged {
                    object: object.id().to_string(),
                })?
        };
        let (displacement_m, rotation_rad) = motion(&start, &end, &local_com[i]);
        let stable = welded
            || (displacement_m <= params.displacement_limit_m && rotation_rad <= params.rotation_limit_rad);
        if !stable {
            unstable += 1;
        }
        objects.push(ObjectStability {
            id: object.id().clone(),
            stable,
            displacement_m,
            rotation_rad,
            welded,
            weld_reason: weld_reasons[i],
            final_pose: Pose::from_isometry(&end),
            support_type: support_types[i],
            interpenetration: interpenetration[i].clone(),
            body: BodyShape {
                kind: bodies[i].kind(),
                pieces: bodies[i].pieces().len(),
            },
        });
        poses.push(end);
    }
    let (frac_unstable, frac_unstable_missing) = if free > 0 {
        (Some(unstable as Real / free as Real), None)
    } else if objects.is_empty() {
        (None, Some("the scene has no objects".to_owned()))
    } else {
        (
            None,
            Some("every object is welded: none was free to move".to_owned()),
        )
    };
    let report = StabilityReport {
        weld: params.weld,
        objects,
        num_free: free,
        num_unstable: unstable,
        frac_unstable,
        frac_unstable_missing,
        simulated_s: steps as Real * params.time_step_s,
        steps,
    };
    Ok(Outcome { report, poses })
}

/// The rapier world of a scene: the rooms' fixed colliders and one dynamic body per object
/// (scene order), placed at the object's pose with its pieces in the object frame.
struct Built {
    world: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
    arch_names: Vec<String>,
}

fn build_world(
    scene: &Scene,
    bodies: &[Arc<Decomposition>],
    params: &StabilityParams,
) -> Result<Built, PhysicsError> {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -GRAVITY),
        integration_parameters: IntegrationParameters {
            dt: params.time_step_s,
            // Rapier reuses a pair's contact points while the bodies barely move ("contact
            // recycling"); on convex polyhedra with many faces (a lamp's round base on a
            // cabinet) the stale points rock a resting object by 0.1 rad within seconds.
            // Computing them every step keeps it still (measured: under 0.001 rad over 3 s).
            contact_recycling: false,
            ..IntegrationParameters::default()
        },
        // Contacts between convex pieces from full faces with a checked normal (`contact`).
        narrow_phase: NarrowPhase::with_query_dispatcher(ContactDispatcher),
        ..PhysicsWorld::default()
    };
    let arch_names = add_architecture(&mut world, scene, params.friction);
    let mut handles = Vec::with_capacity(bodies.len());
    for (i, (object, body)) in scene.objects().iter().zip(bodies).enumerate() {
        let density = match params.mass {
            MassModel::Density(rho) => rho,
            MassModel::PerObject(kg) => kg / body.volume(),
        };
        if !(density.is_finite() && density > 0.0) {
            return Err(PhysicsError::Geometry {
                object: object.id().to_string(),
                reason: format!("its convex pieces have no usable volume ({} m³)", body.volume()),
            });
        }
        let sleeps = params.sleep_speed_m_s > 0.0;
        let handle = world.insert_body(
            RigidBodyBuilder::dynamic()
                .pose(to_parry_pose(object.pose()))
                .can_sleep(sleeps),
        );
        if let Some(b) = world.bodies.get_mut(handle).filter(|_| sleeps) {
            let a = b.activation_mut();
            a.normalized_linear_threshold = params.sleep_speed_m_s;
            a.time_until_sleep = params.sleep_time_s;
        }
        let mut shapes: Vec<(rapier3d_f64::math::Pose, SharedShape)> = body
            .piece_offsets()
            .zip(body.shapes())
            .map(|(offset, shape)| {
                let at = Isometry3::translation(offset.x, offset.y, offset.z);
                (to_parry_pose(&at), shape.clone())
            })
            .collect();
        let collider = match shapes.pop() {
            Some((at, shape)) if shapes.is_empty() => ColliderBuilder::new(shape).position(at),
            Some(last) => {
                shapes.push(last);
                ColliderBuilder::new(SharedShape::compound(shapes))
            }
            None => {
                return Err(PhysicsError::Geometry {
                    object: object.id().to_string(),
                    reason: "it has no convex piece".to_owned(),
                });
            }
        };
        world.insert_collider(
            collider
                .density(density)
                .friction(params.friction)
                .restitution(0.0)
                .user_data(i as u128),
            Some(handle),
        );
        handles.push(handle);
    }
    Ok(Built {
        world,
        handles,
        arch_names,
    })
}

impl Built {
    /// Fixes the bodies with a weld reason in place. Every body is touched through `get_mut`:
    /// rapier's collision-only pass consumed the bodies' "inserted" changes without giving
    /// them to the island manager, and a body the manager never saw is never simulated.
    fn weld(&mut self, reasons: &[Option<WeldReason>]) {
        for (&h, reason) in self.handles.iter().zip(reasons) {
            if let Some(b) = self.world.bodies.get_mut(h) {
                if reason.is_some() {
                    b.set_body_type(RigidBodyType::Fixed, false);
                } else {
                    b.set_linvel(Vector::ZERO, true);
                }
            }
        }
    }

    /// A body's centre of mass in its own (the object's) frame.
    fn local_com(&self, h: RigidBodyHandle) -> Point3 {
        self.world
            .bodies
            .get(h)
            .map(|b| Point3::from(vec_from_parry(b.mass_properties().local_mprops.local_com)))
            .unwrap_or_else(Point3::origin)
    }

    /// A body's pose (`world_from_object`), `None` when it is no longer finite.
    fn final_pose(&self, h: RigidBodyHandle) -> Option<Isometry3> {
        let pose = pose_from_parry(self.world.bodies.get(h)?.position());
        let finite = pose.translation.vector.iter().all(|v| v.is_finite())
            && pose.rotation.coords.iter().all(|v| v.is_finite());
        finite.then_some(pose)
    }
}

/// How far a body moved from `start` to `end`: the distance its centre of mass (`local_com`,
/// body frame) travelled and the angle of the rotation between the two poses. Measured at the
/// centre of mass, a turn in place is not a displacement, wherever the body is.
fn motion(start: &Isometry3, end: &Isometry3, local_com: &Point3) -> (Real, Real) {
    (
        (end * local_com - start * local_com).norm(),
        start.rotation.angle_to(&end.rotation),
    )
}

/// Why an object is welded under `params.weld`, if it is.
fn weld_reason(
    params: &StabilityParams,
    support: Option<SupportType>,
    interpenetration: Option<&Interpenetration>,
) -> Option<WeldReason> {
    if params.weld.welds_architectural() {
        match support {
            Some(SupportType::Wall) => return Some(WeldReason::Wall),
            Some(SupportType::Ceiling) => return Some(WeldReason::Ceiling),
            _ => {}
        }
    }
    if params.weld.welds_penetrating() && interpenetration.is_some() {
        return Some(WeldReason::Penetration);
    }
    None
}

/// Per object, its deepest interpenetration deeper than `min_depth` with another object, a
/// floor or a wall, from the contacts the narrow phase found (ties go to the
/// lexicographically smaller name, so the result does not depend on the pairs' order).
fn deepest_interpenetrations(
    world: &PhysicsWorld,
    scene: &Scene,
    arch_names: &[String],
    min_depth: Real,
) -> Vec<Option<Interpenetration>> {
    let mut deepest: Vec<Option<Interpenetration>> = vec![None; scene.objects().len()];
    let name = |tag: u128| -> Option<String> {
        if tag >= ARCH_TAG {
            arch_names.get(usize::try_from(tag - ARCH_TAG).ok()?).cloned()
        } else {
            Some(scene.object_at(usize::try_from(tag).ok()?)?.id().to_string())
        }
    };
    let mut record = |tag: u128, other: u128, depth: Real| {
        let (Ok(i), Some(with)) = (usize::try_from(tag), name(other)) else {
            return;
        };
        if tag >= ARCH_TAG || i >= deepest.len() {
            return;
        }
        let better = match &deepest[i] {
            None => true,
            Some(d) => depth > d.depth_m || (depth == d.depth_m && with < d.with),
        };
        if better {
            deepest[i] = Some(Interpenetration { with, depth_m: depth });
        }
    };
    for pair in world.narrow_phase.contact_pairs() {
        let Some((_, contact)) = pair.find_deepest_contact() else {
            continue;
        };
        let depth = -contact.dist;
        if depth <= min_depth {
            continue;
        }
        let (Some(c1), Some(c2)) = (
            world.colliders.get(pair.collider1),
            world.colliders.get(pair.collider2),
        ) else {
            continue;
        };
        record(c1.user_data, c2.user_data, depth);
        record(c2.user_data, c1.user_data, depth);
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_geom::Vector3;
    use sceneeval_geom::na::{Translation3, UnitQuaternion};

    #[test]
    fn motion_is_measured_at_the_centre_of_mass() {
        // A body 3 m from the world origin (its centre of mass at its origin) turns 0.2 degrees
        // about its centre of mass: it did not move. Measured at the world origin, as the
        // SceneSmith fork does for its world-space meshes, the same turn would move a point
        // 3 m away by 3 x 0.00349 = 1.05 cm, over the 1 cm limit.
        let angle = 0.2_f64.to_radians();
        let start = Isometry3::translation(3.0, 0.0, 0.5);
        let end = Isometry3::from_parts(
            Translation3::new(3.0, 0.0, 0.5),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle),
        );
        let (d, r) = motion(&start, &end, &Point3::origin());
        assert!(d < 1e-15 && (r - angle).abs() < 1e-15, "{d} {r}");
        let world_origin = |p: &Isometry3| p * start.inverse() * Point3::origin();
        let fork = (world_origin(&end) - world_origin(&start)).norm();
        assert!((fork - 3.0 * angle).abs() < 1e-5 && fork > 0.01, "{fork}");
        // A drop of 5 cm with a centre of mass off the body origin: 5 cm, no turn.
        let dropped = Isometry3::translation(3.0, 0.0, 0.45);
        let (d, r) = motion(&start, &dropped, &Point3::new(0.2, -0.1, 0.3));
        assert!((d - 0.05).abs() < 1e-12 && r == 0.0, "{d} {r}");
    }

    #[test]
    fn bodies_carry_their_mass_at_the_pieces_centroid() {
        use crate::{Decomposition, MassModel, Piece};
        use sceneeval_scene::SceneObject;
        // An object whose origin is at its foot: one 0.2 m cube piece centred 0.5 m above it,
        // placed at (1, 2, 0) turned 90 degrees about z. Its centre of mass is the cube's
        // centre, (0, 0, 0.5) in the object frame; its mass 0.008 m³ x 1000 kg/m³ = 8 kg, or
        // 1 kg under the per-object model.
        let piece = Decomposition::from_pieces(
            crate::DecompositionKind::Vhacd,
            vec![Piece::Hull {
                points: (0..8)
                    .map(|k| {
                        Point3::from(sceneeval_geom::cuboid_corner(
                            k,
                            [-0.1, -0.1, 0.4],
                            [0.1, 0.1, 0.6],
                        ))
                    })
                    .collect(),
            }],
        )
        .unwrap();
        let pose = Isometry3::new(
            Vector3::new(1.0, 2.0, 0.0),
            Vector3::z() * std::f64::consts::FRAC_PI_2,
        );
        let object = SceneObject::new_box("o", Vector3::repeat(0.1), pose).unwrap();
        let scene = Scene::builder().object(object).build().unwrap();
        for (mass, kg) in [
            (MassModel::Density(1000.0), 8.0),
            (MassModel::PerObject(1.0), 1.0),
        ] {
            let params = StabilityParams {
                mass,
                ..StabilityParams::default()
            };
            let built = build_world(&scene, &[Arc::new(piece.clone())], &params).unwrap();
            let h = built.handles[0];
            let c = built.local_com(h);
            assert!((c - Point3::new(0.0, 0.0, 0.5)).norm() < 1e-12, "{c:?}");
            let m = built.world.bodies.get(h).unwrap().mass();
            assert!((m - kg).abs() < 1e-9, "{m}");
        }
    }

    #[test]
    fn weld_reasons_follow_the_mode() {
        let pen = Interpenetration {
            with: "b".into(),
            depth_m: 0.01,
        };
        let with = |weld| StabilityParams {
            weld,
            ..StabilityParams::default()
        };
        use crate::WeldMode as M;
        let cases = [
            (
                M::Architectural,
                Some(SupportType::Wall),
                Some(&pen),
                Some(WeldReason::Wall),
            ),
            (M::Architectural, Some(SupportType::Ground), Some(&pen), None),
            (M::Penetration, Some(SupportType::Ceiling), None, None),
            (M::Penetration, None, Some(&pen), Some(WeldReason::Penetration)),
            (
                M::Combined,
                Some(SupportType::Ceiling),
                Some(&pen),
                Some(WeldReason::Ceiling),
            ),
            (
                M::Combined,
                Some(SupportType::Object),
                Some(&pen),
                Some(WeldReason::Penetration),
            ),
            (M::None, Some(SupportType::Wall), Some(&pen), None),
        ];
        for (mode, support, pen, expected) in cases {
            assert_eq!(
                weld_reason(&with(mode), support, pen),
                expected,
                "{mode:?} {support:?}"
            );
        }
    }
}
