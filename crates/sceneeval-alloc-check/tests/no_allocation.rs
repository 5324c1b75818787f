//! The kernels documented as allocation-free allocate nothing per call.
//!
//! [`CountingAllocator`] counts the allocations (and reallocations) made by the current
//! thread; [`allocations_during`] calls a kernel once to warm up (a first call may register a
//! `tracing` callsite), then counts a second call: the count must be zero. Covered: every one
//! of the 23 relations through the dispatching kernels ([`batch::score_pair`], [`surround`],
//! [`arch::score_rooms`]) on boxes and on ~5k-triangle meshes, in several configurations
//! (touching, overlapping, nested, apart, far) so that the different code paths run; the batch
//! forms; every gradient kernel (`grad::pair`, `grad::surround`, `grad::arch_rooms`,
//! `grad::box_penetration`) on boxes and meshes; `sceneeval-geom`'s exact box and mesh
//! distances; and the optimisers' loops: moving objects in a scene and asking relations by
//! index ([`SceneRelations`]) and plausibility checks ([`LayoutChecks`]: out of bounds,
//! pairwise contacts, door blocking), as the `layout_optimizer` example's annealing steps and
//! the `gradient_layout` example's descent steps do.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use sceneeval_alloc_check::{CountingAllocator, allocations_during};
use sceneeval_examples::layout::{Annealer, Descent, Layout};
use sceneeval_geom::{Isometry3, Mesh, Obb, Point3, Real, Vector3};
use sceneeval_plausibility::{LayoutChecks, OutOfBoundsParams};
use sceneeval_relations::grad::{self, BoxGrad};
use sceneeval_relations::{
    ObjectGeom, Relation, RelationKind, RelationParams, SceneRelations, arch, batch, surround,
};
use sceneeval_scene::{Category, Room, Scene};

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

fn bx(c: [Real; 3], h: [Real; 3], yaw: Real) -> Obb {
    Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::new(h[0], h[1], h[2]), yaw).unwrap()
}

/// A mesh placed at `center` turned by `yaw`, with its box.
struct Placed {
    mesh: Mesh,
    pose: Isometry3,
    obb: Obb,
}

impl Placed {
    fn new(mesh: Mesh, center: [Real; 3], yaw: Real) -> Self {
        let pose = Isometry3::new(Vector3::new(center[0], center[1], center[2]), Vector3::z() * yaw);
        let obb = Obb::from_local_aabb(mesh.aabb(), &pose);
        Placed { mesh, pose, obb }
    }

    fn view(&self) -> ObjectGeom<'_> {
        ObjectGeom::with_mesh(&self.obb, &self.mesh, &self.pose)
    }
}

/// The test bedroom (door on wall 0) with a window on wall 1.
fn room() -> Room {
    sceneeval_test_support::bedroom("bedroom")
        .window(1, [1.5, 3.5], [0.9, 2.0])
        .build()
        .unwrap()
}

/// Scores every relation for `target` against `anchor` (and, for `surround`, `around`) and the
/// room, asserting that no call allocates.
fn assert_no_allocation(
    what: &str,
    target: &ObjectGeom<'_>,
    anchor: &ObjectGeom<'_>,
    around: &[ObjectGeom<'_>],
    rooms: &[Room],
    params: &RelationParams,
) {
    for relation in Relation::all() {
        let n = match relation.kind() {
            RelationKind::ObjectObject => {
                allocations_during(|| batch::score_pair(relation, target, anchor, params).unwrap())
            }
            RelationKind::MultiTarget => allocations_during(|| surround(around, anchor, params)),
            RelationKind::ObjectArchitecture => {
                allocations_during(|| arch::score_rooms(relation, target, rooms, params).unwrap())
            }
        };
        assert_eq!(n, 0, "{what}: {relation} allocated {n} times");
        let mut d = [BoxGrad::ZERO; 8];
        let d = &mut d[..around.len()];
        let n = match relation.kind() {
            RelationKind::ObjectObject => {
                allocations_during(|| grad::pair(relation, target, anchor, params).unwrap())
            }
            RelationKind::MultiTarget => {
                allocations_during(|| grad::surround(around, anchor, params, d).unwrap())
            }
            RelationKind::ObjectArchitecture => {
                allocations_during(|| grad::arch_rooms(relation, target, rooms, params).unwrap())
            }
        };
        assert_eq!(n, 0, "{what}: the gradient of {relation} allocated {n} times");
    }
    let n = allocations_during(|| grad::box_penetration(target.obb, anchor.obb));
    assert_eq!(n, 0, "{what}: box_penetration allocated {n} times");
}

/// Target positions around a bed at (2, 4): overlapping its side, touching it, nested in it,
/// 6 cm and 0.8 m away, 3 m away, and straddling a wall.
const TARGETS: [([Real; 3], Real); 7] = [
    ([1.0, 4.5, 0.35], 0.3),
    ([0.95, 4.0, 0.35], 0.0),
    ([2.0, 4.0, 0.3], 0.3),
    ([0.9, 4.5, 0.35], 0.3),
    ([0.2, 4.5, 0.35], 1.0),
    ([2.0, 1.0, 0.35], 2.0),
    ([3.9, 2.5, 1.2], 0.7),
];

#[test]
fn relation_kernels_on_boxes_allocate_nothing() {
    let rooms = [room()];
    let bed = bx([2.0, 4.0, 0.3], [0.8, 1.0, 0.3], 0.05);
    let chairs: Vec<Obb> = (0..4)
        .map(|k| {
            let angle = Real::from(k) * std::f64::consts::FRAC_PI_2 + 0.1;
            bx(
                [2.0 + 1.2 * angle.cos(), 4.0 + 1.4 * angle.sin(), 0.45],
                [0.25, 0.25, 0.45],
                angle,
            )
        })
        .collect();
    let around: Vec<ObjectGeom<'_>> = chairs.iter().map(ObjectGeom::from_box).collect();
    let anchor = ObjectGeom::from_box(&bed);
    for params in [RelationParams::default(), RelationParams::reference()] {
        for (center, yaw) in TARGETS {
            let stand = bx(center, [0.25, 0.2, 0.35], yaw);
            let target = ObjectGeom::from_box(&stand);
            let what = format!("box at {center:?}");
            assert_no_allocation(&what, &target, &anchor, &around, &rooms, &params);
        }
    }
}

#[test]
fn relation_kernels_on_meshes_allocate_nothing() {
    let rooms = [room()];
    let bed = Placed::new(
        Mesh::uv_ellipsoid(&Vector3::new(0.8, 1.0, 0.3), 50, 51).unwrap(),
        [2.0, 4.0, 0.3],
        0.05,
    );
    let chairs: Vec<Placed> = (0..3)
        .map(|k| {
            let angle = Real::from(k) * std::f64::consts::TAU / 3.0;
            Placed::new(
                Mesh::subdivided_box(&Vector3::new(0.25, 0.25, 0.45), 6).unwrap(),
                [2.0 + 1.2 * angle.cos(), 4.0 + 1.4 * angle.sin(), 0.45],
                angle,
            )
        })
        .collect();
    let around: Vec<ObjectGeom<'_>> = chairs.iter().map(Placed::view).collect();
    let anchor = bed.view();
    for params in [RelationParams::default(), RelationParams::reference()] {
        for (center, yaw) in TARGETS {
            let half = if center == [2.0, 4.0, 0.3] {
                // Nested inside the ellipsoid.
                Vector3::new(0.1, 0.1, 0.1)
            } else {
                Vector3::new(0.25, 0.2, 0.35)
            };
            let stand = Placed::new(Mesh::subdivided_box(&half, 20).unwrap(), center, yaw);
            let target = stand.view();
            let what = format!("mesh at {center:?}");
            assert_no_allocation(&what, &target, &anchor, &around, &rooms, &params);
        }
    }
}

#[test]
fn batch_forms_allocate_nothing() {
    let params = RelationParams::default();
    let rooms = [room()];
    let boxes: Vec<Obb> = (0..64)
        .map(|i| {
            let t = Real::from(i);
            bx([0.3 + 0.05 * t, 0.4 + 0.07 * t, 0.4], [0.2, 0.3, 0.4], 0.1 * t)
        })
        .collect();
    let views: Vec<ObjectGeom<'_>> = boxes.iter().map(ObjectGeom::from_box).collect();
    let mut out = vec![0.0; 63];
    for relation in Relation::all() {
        let n = match relation.kind() {
            RelationKind::ObjectObject => allocations_during(|| {
                batch::score_pairs(relation, &views[..63], &views[1..], &params, &mut out).unwrap()
            }),
            RelationKind::MultiTarget => continue,
            RelationKind::ObjectArchitecture => allocations_during(|| {
                batch::score_objects_in_rooms(relation, &views[..63], &rooms, &params, &mut out).unwrap()
            }),
        };
        assert_eq!(n, 0, "batch {relation} allocated {n} times");
    }
}

#[test]
fn geometry_distances_allocate_nothing() {
    let a = Placed::new(
        Mesh::uv_ellipsoid(&Vector3::new(0.8, 1.0, 0.3), 50, 51).unwrap(),
        [2.0, 4.0, 0.3],
        0.05,
    );
    let tri = [
        Point3::new(0.0, 5.0, 0.0),
        Point3::new(4.0, 5.0, 0.0),
        Point3::new(4.0, 5.0, 2.8),
    ];
    for (center, yaw) in TARGETS {
        let b = Placed::new(
            Mesh::subdivided_box(&Vector3::new(0.25, 0.2, 0.35), 20).unwrap(),
            center,
            yaw,
        );
        let cases: [(&str, &dyn Fn() -> Real); 5] = [
            ("Obb::distance_to_obb", &|| b.obb.distance_to_obb(&a.obb)),
            ("Obb::distance_to_triangle", &|| b.obb.distance_to_triangle(&tri)),
            ("Mesh::distance", &|| b.mesh.distance(&b.pose, &a.mesh, &a.pose)),
            ("Mesh::distance_to_obb", &|| {
                b.mesh.distance_to_obb(&b.pose, &a.obb)
            }),
            ("Mesh::distance_to_triangle", &|| {
                b.mesh.distance_to_triangle(&b.pose, &tri)
            }),
        ];
        for (name, f) in cases {
            let n = allocations_during(f);
            assert_eq!(n, 0, "{name} at {center:?} allocated {n} times");
        }
    }
}

#[test]
fn the_optimiser_loop_allocates_nothing_per_step() {
    // The layout_optimizer example's loop: each step moves one object (Scene::set_pose), asks
    // 27 goals (relations by index, the plausibility in-bounds check) and moves it back or
    // not. After a warm-up (the checks' clip buffers grow once), 200 more steps allocate
    // nothing.
    let mut layout = Layout::new().unwrap();
    let mut annealer = Annealer::new(&mut layout, 1, 6_000).unwrap();
    for _ in 0..50 {
        annealer.step(&mut layout).unwrap();
    }
    let n = allocations_during(|| {
        for _ in 0..100 {
            annealer.step(&mut layout).unwrap();
        }
    });
    assert_eq!(n, 0, "200 annealing steps allocated {n} times");
}

#[test]
fn the_gradient_descent_loop_allocates_nothing_per_step() {
    // The gradient_layout example's loop: each step takes every goal's score and gradient and
    // moves every object (or restarts from a random layout).
    let mut layout = Layout::new().unwrap();
    let mut descent = Descent::new(&mut layout, 1).unwrap();
    for _ in 0..20 {
        descent.step(&mut layout).unwrap();
    }
    let n = allocations_during(|| {
        for _ in 0..50 {
            descent.step(&mut layout).unwrap();
        }
    });
    assert_eq!(n, 0, "100 descent steps allocated {n} times");
}

#[test]
fn scene_queries_by_index_and_layout_checks_allocate_nothing() {
    // Every relation by index on a scene (surround over four chairs), and the out-of-bounds
    // check, for an object moved between calls.
    let mut builder = Scene::builder().room(room());
    let pose = |c: [Real; 3], yaw: Real| {
        sceneeval_geom::conventions::pose_from_yaw(Point3::new(c[0], c[1], c[2]), yaw)
    };
    builder = builder.add_box(
        "bed",
        Category::new("bed"),
        Vector3::new(0.8, 1.0, 0.3),
        pose([2.0, 4.0, 0.3], 0.05),
    );
    for k in 0..4 {
        let a = Real::from(k) * std::f64::consts::FRAC_PI_2 + 0.1;
        builder = builder.add_box(
            format!("chair{k}"),
            Category::new("chair"),
            Vector3::new(0.25, 0.25, 0.45),
            pose([2.0 + 1.2 * a.cos(), 4.0 + 1.4 * a.sin(), 0.45], a),
        );
    }
    // A mesh object by the door (x in [1.0, 1.9] on y = 0), for contacts with meshes.
    builder = builder.add_mesh(
        "ball",
        Category::new("ball"),
        std::sync::Arc::new(Mesh::uv_ellipsoid(&Vector3::repeat(0.3), 24, 13).unwrap()),
        pose([1.4, 0.5, 0.3], 0.0),
    );
    let mut scene = builder.build().unwrap();
    let rel = SceneRelations::new(RelationParams::default()).unwrap();
    let checks = LayoutChecks::new(scene.rooms(), &OutOfBoundsParams::default()).unwrap();
    let mut scratch = checks.scratch();
    let chairs = [1, 2, 3, 4];
    for (center, yaw) in TARGETS {
        scene.set_pose(1, pose(center, yaw)).unwrap();
        for relation in Relation::all() {
            let n = allocations_during(|| match relation.kind() {
                RelationKind::ObjectObject => rel.pair(&scene, relation, 1, 0).unwrap().score,
                RelationKind::MultiTarget => rel.surround(&scene, &chairs, 0).unwrap().score,
                RelationKind::ObjectArchitecture => rel.arch(&scene, relation, 1, &[]).unwrap().score,
            });
            assert_eq!(n, 0, "{relation} at {center:?} allocated {n} times");
        }
        let n = allocations_during(|| checks.in_bounds_ratio(&scene.objects()[1], &mut scratch));
        assert_eq!(n, 0, "in_bounds_ratio at {center:?} allocated {n} times");
        for other in [0, 2, 5] {
            let n = allocations_during(|| checks.contact(&scene.objects()[1], &scene.objects()[other]));
            assert_eq!(n, 0, "contact with {other} at {center:?} allocated {n} times");
        }
        for k in [1, 5] {
            let n = allocations_during(|| checks.blocks_door(&scene.objects()[k]));
            assert_eq!(n, 0, "blocks_door of {k} at {center:?} allocated {n} times");
        }
        let n = allocations_during(|| scene.set_pose(2, pose(center, -yaw)).unwrap());
        assert_eq!(n, 0, "set_pose allocated {n} times");
    }
}

#[test]
fn the_counter_sees_allocations() {
    // Guards against a counter that always reads zero.
    let n = allocations_during(|| vec![1u8; 16]);
    assert_eq!(n, 1);
}
