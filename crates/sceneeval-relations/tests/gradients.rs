//! The gradients of `sceneeval_relations::grad`: the score they return is the kernel's, bit
//! for bit, and their derivatives agree with central finite differences of the kernels, for
//! every one of the 23 predicates, on boxes and on meshes.
//!
//! Finite differences: for each of the 14 parameters (7 of the target, 7 of the anchor;
//! object-architecture relations: the target's 7) the central difference with step
//! `STEP = 1e-6` is compared with the analytic derivative to `|analytic - fd| <= 1e-5 +
//! 1e-3 |fd|`. A parameter whose forward and backward differences disagree, or whose central
//! differences with steps `STEP` and `4 STEP` do (by more than `1e-5 + 1e-3 |fd|`), lies
//! within a few micrometres of a kink or a jump, where the derivative is one-sided by design
//! (see the `grad` module docs): it is not compared, and every test checks that most
//! parameters were (and prints how many).
//!
//! Case counts: `PROPTEST_CASES` (default 256 random configurations per family, an eighth of
//! that for meshes; CI runs the default under its pinned seed; the gradients were also run
//! with `PROPTEST_CASES=4000`).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, clippy::print_stderr)]
// The 7 parameters are indexed alike in the gradient, the moved object and the messages.
#![allow(clippy::needless_range_loop)]

use std::cell::RefCell;
use std::collections::BTreeMap;

use proptest::prelude::*;
use sceneeval_geom::{Isometry3, Mesh, Obb, Point3, Real, Rotation3, Side, Vector3};
use sceneeval_relations::grad::{self, BoxGrad, PairGrad};
use sceneeval_relations::{
    ArchElement, LongShort, ObjectGeom, Relation, RelationKind, RelationParams, arch, batch, surround,
};
use sceneeval_scene::Room;

const STEP: Real = 1e-6;

/// `PROPTEST_CASES` (default 256) cases, divided by `divisor` (for the costlier meshes).
fn cases(divisor: u32) -> ProptestConfig {
    let n: u32 = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256);
    ProptestConfig::with_cases((n / divisor).max(1))
}

/// A runner of [`cases`] (failures are reported with their input; no file to persist them in).
fn runner(divisor: u32) -> proptest::test_runner::TestRunner {
    proptest::test_runner::TestRunner::new(ProptestConfig {
        failure_persistence: None,
        ..cases(divisor)
    })
}

/// An object as the tests move it: a box, or a mesh with its pose.
#[derive(Clone)]
struct Obj {
    mesh: Option<(std::sync::Arc<Mesh>, Isometry3)>,
    obb: Obb,
}

impl Obj {
    fn from_box(obb: Obb) -> Obj {
        Obj { mesh: None, obb }
    }

    fn with_mesh(mesh: std::sync::Arc<Mesh>, pose: Isometry3) -> Obj {
        let obb = Obb::from_local_aabb(mesh.aabb(), &pose);
        Obj {
            mesh: Some((mesh, pose)),
            obb,
        }
    }

    fn view(&self) -> ObjectGeom<'_> {
        match &self.mesh {
            None => ObjectGeom::from_box(&self.obb),
            Some((m, p)) => ObjectGeom::with_mesh(&self.obb, m, p),
        }
    }

    /// Parameter `k` of `(cx, cy, cz, hx, hy, hz, yaw)` moved by `e`; `None` for a mesh's half
    /// extents (not free).
    fn moved(&self, k: usize, e: Real) -> Option<Obj> {
        let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), e);
        match &self.mesh {
            None => {
                let mut o = self.obb;
                match k {
                    0..=2 => o.center[k] += e,
                    3..=5 => o.half_extents[k - 3] += e,
                    _ => o.rotation = turn * o.rotation,
                }
                Some(Obj::from_box(o))
            }
            Some((m, pose)) => {
                let mut p = *pose;
                match k {
                    0..=2 => p.translation.vector[k] += e,
                    3..=5 => return None,
                    _ => {
                        p.rotation =
                            sceneeval_geom::na::UnitQuaternion::from_rotation_matrix(&turn) * p.rotation
                    }
                }
                Some(Obj::with_mesh(m.clone(), p))
            }
        }
    }
}

/// Per relation: derivatives compared, compared and not 0 (finite difference above 1e-6 in
/// magnitude), and skipped near kinks.
#[derive(Default)]
struct Tally {
    counts: RefCell<BTreeMap<String, [usize; 3]>>,
}

impl Tally {
    /// Compares `analytic` with central differences of `f` along `moved(e)`; `Err` with a
    /// message on a mismatch.
    fn compare(
        &self,
        relation: &str,
        what: &str,
        analytic: Real,
        f: impl Fn(Real) -> Option<Real>,
    ) -> Result<(), String> {
        let diff = |e: Real| -> Option<Real> { Some((f(e)? - f(-e)?) / (2.0 * e)) };
        let (Some(fd), Some(wide), Some(at), Some(ahead), Some(behind)) =
            (diff(STEP), diff(4.0 * STEP), f(0.0), f(STEP), f(-STEP))
        else {
            return Ok(());
        };
        let mut counts = self.counts.borrow_mut();
        let count = counts.entry(relation.to_owned()).or_default();
        let (forward, backward) = ((ahead - at) / STEP, (at - behind) / STEP);
        let tol = 1e-5 + 1e-3 * fd.abs();
        if (fd - wide).abs() > tol || (forward - backward).abs() > tol {
            count[2] += 1;
            return Ok(());
        }
        count[0] += 1;
        if fd.abs() > 1e-6 {
            count[1] += 1;
        }
        if (analytic - fd).abs() <= 1e-5 + 1e-3 * fd.abs() {
            Ok(())
        } else {
            Err(format!(
                "{relation} {what}: analytic {analytic} vs finite difference {fd} (wide {wide})"
            ))
        }
    }

    /// For every relation: at least `share` of its derivatives were compared, and (with
    /// `each_moves`) some of them are not 0; over all relations, at least one in ten is not
    /// 0.
    fn assert_mostly_checked(&self, share: Real, each_moves: bool) {
        let (mut all, mut all_nz) = (0, 0);
        for (relation, &[c, nz, s]) in self.counts.borrow().iter() {
            eprintln!("{relation}: {c} derivatives compared ({nz} not 0), {s} skipped near kinks");
            assert!(
                !each_moves || nz > 0,
                "{relation}: none of {c} derivatives compared is not 0"
            );
            assert!(
                c as Real >= share * (c + s) as Real,
                "{relation}: {c} derivatives compared, {s} skipped near kinks"
            );
            (all, all_nz) = (all + c, all_nz + nz);
        }
        assert!(10 * all_nz >= all, "{all_nz} of {all} derivatives not 0");
    }
}

/// Checks a pair's gradient against finite differences of `score` in all 14 parameters.
fn check_pair(
    tally: &Tally,
    name: &str,
    g: &PairGrad,
    a: &Obj,
    b: &Obj,
    score: &dyn Fn(&ObjectGeom<'_>, &ObjectGeom<'_>) -> Real,
) -> Result<(), String> {
    let (ta, tb) = (g.target.to_array(), g.anchor.to_array());
    for k in 0..7 {
        tally.compare(name, &format!("d/d target[{k}]"), ta[k], |e| {
            a.moved(k, e).map(|x| score(&x.view(), &b.view()))
        })?;
        tally.compare(name, &format!("d/d anchor[{k}]"), tb[k], |e| {
            b.moved(k, e).map(|y| score(&a.view(), &y.view()))
        })?;
    }
    Ok(())
}

/// Every two-object relation (one of each base name; sides and long/short in turn).
fn pair_relations(k: usize) -> [Relation; 12] {
    let side = Side::ALL[k % 6];
    let ls = if k.is_multiple_of(2) {
        LongShort::Long
    } else {
        LongShort::Short
    };
    [
        Relation::InsideOf,
        Relation::OutsideOf,
        Relation::FaceTo,
        Relation::SideOf(side),
        Relation::SideRegion(side),
        Relation::LongShortSideOf(ls),
        Relation::OnTop,
        Relation::MiddleOf,
        Relation::NextTo,
        Relation::Near,
        Relation::AcrossFrom,
        Relation::Far,
    ]
}

/// A box within 4 m of the origin, half extents 5 cm to 1 m, any yaw and (a quarter of the
/// time) a tilt.
fn any_box() -> impl Strategy<Value = Obb> {
    (
        (-2.5..2.5f64, -2.5..2.5f64, 0.0..1.5f64),
        (0.05..1.0f64, 0.05..1.0f64, 0.05..1.0f64),
        -3.2..3.2f64,
        prop_oneof![3 => Just((0.0, 0.0)), 1 => (-0.5..0.5f64, -0.5..0.5f64)],
    )
        .prop_map(|(c, h, yaw, (roll, pitch))| Obb {
            center: Point3::new(c.0, c.1, c.2),
            half_extents: Vector3::new(h.0, h.1, h.2),
            rotation: Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
                * Rotation3::from_euler_angles(roll, pitch, 0.0),
        })
}

/// A box and a second box near it: centred within about 1.5 m (overlapping, touching or
/// beside each other), so that regions and distances are partly met.
fn near_pair() -> impl Strategy<Value = (Obb, Obb)> {
    (any_box(), any_box(), (-1.5..1.5f64, -1.5..1.5f64, -0.8..0.8f64)).prop_map(|(a, mut b, d)| {
        b.center = a.center + Vector3::new(d.0, d.1, d.2);
        (a, b)
    })
}

/// A target and an anchor 0.5 to 4 m ahead of it (within 40 degrees of its front, at a
/// height within 1.5 m), for `face_to`.
fn facing_pair() -> impl Strategy<Value = (Obb, Obb)> {
    (any_box(), any_box(), 0.5..4.0f64, -0.7..0.7f64, -1.5..1.5f64).prop_map(
        |(a, mut b, dist, bearing, dz)| {
            let ahead = a.rotation * Vector3::new(0.0, -1.0, 0.0);
            let plan = Vector3::new(ahead.x, ahead.y, 0.0).normalize();
            let dir = Rotation3::from_axis_angle(&Vector3::z_axis(), bearing) * plan;
            b.center = a.center + dir * dist + Vector3::new(0.0, 0.0, dz);
            (a, b)
        },
    )
}

/// The test bedroom (door on wall 0) with a window on wall 1.
fn room() -> Room {
    sceneeval_test_support::bedroom("r")
        .window(1, [1.5, 3.5], [0.9, 2.0])
        .build()
        .unwrap()
}

/// A box in and around the 4 x 5 m bedroom, from the floor to the ceiling (half of them), or
/// up to 4 m outside it, so that every band of every element is met.
fn room_box() -> impl Strategy<Value = Obb> {
    let centre = prop_oneof![
        (-0.5..4.5f64, -0.5..5.5f64, 0.0..2.8f64),
        (-4.0..8.0f64, -4.0..9.0f64, 0.0..2.8f64),
    ];
    (
        centre,
        (0.05..0.8f64, 0.05..0.8f64, 0.05..0.8f64),
        -3.2..3.2f64,
        prop_oneof![3 => Just((0.0, 0.0)), 1 => (-0.4..0.4f64, -0.4..0.4f64)],
    )
        .prop_map(|(c, h, yaw, (roll, pitch))| Obb {
            center: Point3::new(c.0, c.1, c.2),
            half_extents: Vector3::new(h.0, h.1, h.2),
            rotation: Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
                * Rotation3::from_euler_angles(roll, pitch, 0.0),
        })
}

fn params(reference: bool) -> RelationParams {
    if reference {
        RelationParams::reference()
    } else {
        RelationParams::default()
    }
}

proptest! {
    #![proptest_config(cases(1))]

    /// The scores of the gradient kernels are the kernels', bit for bit, for every relation.
    #[test]
    fn gradient_scores_are_the_kernel_scores(a in any_box(), b in any_box(), c in any_box(), d in room_box(), k in 0usize..12, reference in any::<bool>()) {
        let p = params(reference);
        let (ga, gb) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
        for r in pair_relations(k) {
            let s = batch::score_pair(r, &ga, &gb, &p).unwrap();
            let g = grad::pair(r, &ga, &gb, &p).unwrap();
            prop_assert_eq!(g.score.to_bits(), s.to_bits(), "{}", r);
        }
        let targets = [ga, ObjectGeom::from_box(&c), ObjectGeom::from_box(&d)];
        let mut dt = [BoxGrad::ZERO; 3];
        let (s, _) = grad::surround(&targets, &gb, &p, &mut dt).unwrap();
        prop_assert_eq!(s.to_bits(), surround(&targets, &gb, &p).to_bits());
        let rooms = [room()];
        let gd = ObjectGeom::from_box(&d);
        for r in Relation::all().filter(Relation::is_architectural) {
            let s = arch::score_rooms(r, &gd, &rooms, &p).unwrap();
            let g = grad::arch_rooms(r, &gd, &rooms, &p).unwrap();
            prop_assert_eq!(g.score.to_bits(), s.to_bits(), "{}", r);
        }
    }
}

/// Runs the finite-difference check of `relations` on `cases` random pairs from `pairs`.
fn pair_family(pairs: impl Strategy<Value = (Obb, Obb)>, relations: &[fn(usize) -> Relation], share: Real) {
    let tally = Tally::default();
    let mut runner = runner(1);
    runner
        .run(&(pairs, 0usize..12, any::<bool>()), |((a, b), k, reference)| {
            let p = params(reference);
            let (a, b) = (Obj::from_box(a), Obj::from_box(b));
            for rel in relations {
                let r = rel(k);
                let g = grad::pair(r, &a.view(), &b.view(), &p).unwrap();
                let score = |x: &ObjectGeom<'_>, y: &ObjectGeom<'_>| batch::score_pair(r, x, y, &p).unwrap();
                check_pair(&tally, &r.to_string(), &g, &a, &b, &score).map_err(TestCaseError::fail)?;
            }
            Ok(())
        })
        .unwrap();
    tally.assert_mostly_checked(share, true);
}

#[test]
fn volume_fractions_match_finite_differences() {
    pair_family(
        near_pair(),
        &[
            |_| Relation::InsideOf,
            |_| Relation::OutsideOf,
            |k| Relation::SideOf(Side::ALL[k % 6]),
            |k| Relation::SideRegion(Side::ALL[k % 6]),
            |k| {
                Relation::LongShortSideOf(if k.is_multiple_of(2) {
                    LongShort::Long
                } else {
                    LongShort::Short
                })
            },
            |_| Relation::OnTop,
        ],
        0.9,
    );
}

#[test]
fn distance_bands_match_finite_differences() {
    pair_family(
        (any_box(), any_box()),
        &[
            |_| Relation::NextTo,
            |_| Relation::Near,
            |_| Relation::AcrossFrom,
            |_| Relation::Far,
        ],
        0.9,
    );
}

#[test]
fn middle_of_and_face_to_match_finite_differences() {
    pair_family(near_pair(), &[|_| Relation::MiddleOf], 0.9);
    pair_family(facing_pair(), &[|_| Relation::FaceTo], 0.9);
}

#[test]
fn surround_matches_finite_differences() {
    let tally = Tally::default();
    let mut runner = runner(1);
    let strategy = (
        proptest::collection::vec(any_box(), 3..7),
        any_box(),
        any::<bool>(),
    );
    runner
        .run(&strategy, |(targets, anchor, reference)| {
            let p = params(reference);
            let objs: Vec<Obj> = targets.into_iter().map(Obj::from_box).collect();
            let anchor = Obj::from_box(anchor);
            let views: Vec<ObjectGeom<'_>> = objs.iter().map(Obj::view).collect();
            let mut d = vec![BoxGrad::ZERO; objs.len()];
            let (_, da) = grad::surround(&views, &anchor.view(), &p, &mut d).unwrap();
            for (i, g) in d.iter().enumerate() {
                let ga = g.to_array();
                for k in 0..7 {
                    tally
                        .compare("surround", &format!("d/d target {i}[{k}]"), ga[k], |e| {
                            let mut moved: Vec<Obj> = objs.clone();
                            moved[i] = objs[i].moved(k, e)?;
                            let v: Vec<ObjectGeom<'_>> = moved.iter().map(Obj::view).collect();
                            Some(surround(&v, &anchor.view(), &p))
                        })
                        .map_err(TestCaseError::fail)?;
                }
            }
            let ga = da.to_array();
            for k in 0..7 {
                tally
                    .compare("surround", &format!("d/d anchor[{k}]"), ga[k], |e| {
                        Some(surround(&views, &anchor.moved(k, e)?.view(), &p))
                    })
                    .map_err(TestCaseError::fail)?;
            }
            Ok(())
        })
        .unwrap();
    tally.assert_mostly_checked(0.9, true);
}

#[test]
fn architecture_relations_match_finite_differences() {
    let rooms = [room()];
    let tally = Tally::default();
    let mut runner = runner(1);
    runner
        .run(&(room_box(), any::<bool>()), |(o, reference)| {
            let p = params(reference);
            let obj = Obj::from_box(o);
            for r in Relation::all().filter(Relation::is_architectural) {
                let g = grad::arch_rooms(r, &obj.view(), &rooms, &p)
                    .unwrap()
                    .target
                    .to_array();
                for k in 0..7 {
                    tally
                        .compare(&r.to_string(), &format!("d/d target[{k}]"), g[k], |e| {
                            Some(arch::score_rooms(r, &obj.moved(k, e)?.view(), &rooms, &p).unwrap())
                        })
                        .map_err(TestCaseError::fail)?;
                }
            }
            Ok(())
        })
        .unwrap();
    tally.assert_mostly_checked(0.9, true);
}

/// Meshes: a 960-triangle ellipsoid anchor and a subdivided box target (every relation,
/// poses differentiated).
#[test]
fn relations_on_meshes_match_finite_differences() {
    let ball = std::sync::Arc::new(Mesh::uv_ellipsoid(&Vector3::new(0.6, 0.5, 0.4), 24, 21).unwrap());
    let cube = std::sync::Arc::new(Mesh::subdivided_box(&Vector3::new(0.3, 0.2, 0.35), 3).unwrap());
    let rooms = [room()];
    let tally = Tally::default();
    let pose = |r: Real| {
        ((-r..r, -r..r, 0.0..1.0f64), -3.2..3.2f64)
            .prop_map(|(c, yaw)| Isometry3::new(Vector3::new(c.0, c.1, c.2), Vector3::z() * yaw))
    };
    let mut runner = runner(8);
    runner
        .run(
            &(
                pose(0.3),
                prop_oneof![pose(1.6), pose(4.5)],
                0usize..12,
                any::<bool>(),
            ),
            |(pa, pb, k, reference)| {
                let p = params(reference);
                let a = Obj::with_mesh(cube.clone(), pa);
                let b = Obj::with_mesh(ball.clone(), pb);
                for (x, y) in [(&a, &b), (&a, &Obj::from_box(b.obb)), (&Obj::from_box(a.obb), &b)] {
                    for r in pair_relations(k) {
                        let g = grad::pair(r, &x.view(), &y.view(), &p).unwrap();
                        let s = batch::score_pair(r, &x.view(), &y.view(), &p).unwrap();
                        prop_assert_eq!(g.score.to_bits(), s.to_bits(), "{}", r);
                        let score =
                            |u: &ObjectGeom<'_>, v: &ObjectGeom<'_>| batch::score_pair(r, u, v, &p).unwrap();
                        let name = format!(
                            "{r} ({})",
                            if x.mesh.is_some() && y.mesh.is_some() {
                                "meshes"
                            } else {
                                "mesh and box"
                            }
                        );
                        check_pair(&tally, &name, &g, x, y, &score).map_err(TestCaseError::fail)?;
                    }
                }
                // The target in the room or up to 3 m outside it, moved by its pose.
                let mut inside = pa;
                // (and at heights up to the ceiling's).
                inside.translation.vector += Vector3::new(
                    2.0 + pb.translation.x,
                    2.5 + pb.translation.y,
                    2.2 * pb.translation.z,
                );
                let a = Obj::with_mesh(cube.clone(), inside);
                for r in Relation::all().filter(|r| r.kind() == RelationKind::ObjectArchitecture) {
                    let g = grad::arch_rooms(r, &a.view(), &rooms, &p).unwrap();
                    let s = arch::score_rooms(r, &a.view(), &rooms, &p).unwrap();
                    prop_assert_eq!(g.score.to_bits(), s.to_bits(), "{}", r);
                    let ga = g.target.to_array();
                    for k in 0..7 {
                        tally
                            .compare(&format!("{r} (mesh)"), &format!("d/d target[{k}]"), ga[k], |e| {
                                Some(arch::score_rooms(r, &a.moved(k, e)?.view(), &rooms, &p).unwrap())
                            })
                            .map_err(TestCaseError::fail)?;
                    }
                }
                Ok(())
            },
        )
        .unwrap();
    tally.assert_mostly_checked(0.8, false);
}

fn bx(c: [Real; 3], h: [Real; 3], yaw: Real) -> Obb {
    Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::new(h[0], h[1], h[2]), yaw).unwrap()
}

fn close(x: Real, y: Real) -> bool {
    (x - y).abs() < 1e-9
}

#[test]
fn hand_computed_volume_fractions() {
    let p = RelationParams::default();
    // A 2 x 2 x 2 anchor at the origin; a unit cube centred on its +x face (x in [0.5, 1.5]):
    // inside_of = 0.5 (plus the 1e-6 tolerance). Moving the cube by dx along x changes the
    // inside part's width by -dx of its 1 m width: d/dcx = -1; along y or z nothing is lost
    // (the cube is within the anchor's y and z ranges).
    let b = bx([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0);
    let a = bx([1.0, 0.0, 0.0], [0.5, 0.5, 0.5], 0.0);
    let g = grad::inside_of(&ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b), &p);
    assert!(
        close(g.target.center.x, -1.0) && close(g.target.center.y, 0.0),
        "{g:?}"
    );
    // Growing the cube's half width by dh: the inside part grows by dh (its face at 0.5 - dh),
    // the volume by 2 dh in total: f = (0.5 + 1e-6 + dh) / (1 + 2 dh) -> df/dh = 1 - 2 f.
    assert!(
        (g.target.half_extents.x - (1.0 - 2.0 * g.score)).abs() < 1e-9,
        "{g:?}"
    );
    // The anchor's +x face moves out with its half width: d/dhx(anchor) = +1.
    assert!(close(g.anchor.half_extents.x, 1.0) && close(g.anchor.center.x, 1.0));
    // Turning the cube about its centre: the face cuts it symmetrically, nothing changes to
    // first order (d/dyaw = 0), for the anchor's yaw likewise by symmetry.
    assert!(g.target.yaw.abs() < 1e-9 && g.anchor.yaw.abs() < 1e-9, "{g:?}");

    // on_top: a book sunk 1 cm into a table top (z in [0.74, 0.78], top face at 0.75): 0.75
    // above. Raising it by dz: +dz / 0.04 -> 25 per metre; the table growing taller by dh
    // (its top rises by dh; its centre fixed) -> -25.
    let table = bx([0.0, 0.0, 0.375], [0.6, 0.4, 0.375], 0.0);
    let book = bx([0.1, 0.0, 0.76], [0.1, 0.15, 0.02], 0.0);
    let g = grad::on_top(&ObjectGeom::from_box(&book), &ObjectGeom::from_box(&table), &p);
    assert!((g.score - 0.75).abs() < 1e-4);
    assert!(
        (g.target.center.z - 25.0).abs() < 1e-6 && (g.anchor.half_extents.z + 25.0).abs() < 1e-6,
        "{g:?}"
    );
}

#[test]
fn hand_computed_distance_bands() {
    let p = RelationParams::default();
    // Corner facing a face: a unit cube turned 45 degrees, centre 1.3 m from a unit cube's
    // centre along x: gap 1.3 - 0.5 - 0.5 sqrt(2) = 0.0929 (in next_to's range: score 1,
    // flat); near's range starts at 0.5: delta = 0.4071, score exp(-delta^2 / 0.125), slope
    // +score delta / 0.0625 per metre of distance. The corner points along x: d/dcx = +slope.
    let a = bx([1.3, 0.0, 0.0], [0.5, 0.5, 0.5], std::f64::consts::FRAC_PI_4);
    let b = bx([0.0, 0.0, 0.0], [0.5, 0.5, 0.5], 0.0);
    let (ga, gb) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
    let g = grad::next_to(&ga, &gb, &p);
    assert_eq!((g.score, g.target), (1.0, BoxGrad::ZERO));
    let g = grad::near(&ga, &gb, &p);
    let delta = 0.5 - (0.8 - 0.5 * 2f64.sqrt());
    let s = (-delta * delta / 0.125).exp();
    let slope = s * delta / 0.0625;
    assert!((g.score - s).abs() < 1e-12);
    assert!((g.target.center.x - slope).abs() < 1e-9 && g.target.center.y.abs() < 1e-9);
    // The corner is at local (-0.5, -0.5) (any z) of the turned cube: growing hx or hy moves
    // it by 0.5 sqrt(2) along -x... each half extent pushes the corner 1/sqrt(2) toward the
    // anchor: the distance shrinks by dh / sqrt(2): d/dh = -slope / sqrt(2).
    let k = -slope / 2f64.sqrt();
    assert!((g.target.half_extents.x - k).abs() < 1e-9 && (g.target.half_extents.y - k).abs() < 1e-9);
    // The anchor's +x face moves toward the target as it grows: -slope.
    assert!((g.anchor.half_extents.x + slope).abs() < 1e-9 && g.anchor.half_extents.y.abs() < 1e-9);
}

#[test]
fn hand_computed_face_to() {
    let p = RelationParams::default();
    // Target facing -y; anchor 2 m ahead, 0.6 m to the side: lines with u in [0.1, 0.5] hit
    // its near face at depth 1.9; mean u = 0.3, angle atan(0.3 / 1.9). Moving the anchor by
    // dx along x: the lit interval is [0.1 + dx, 0.5], mean u = (0.6 + dx) / 2, du = dx / 2;
    // d angle / du = 1.9 / (1.9^2 + u^2) (radians); the score 1 - angle / 30 degrees.
    let a = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
    let b = bx([0.6, -2.0, 0.5], [0.5, 0.1, 0.5], 0.0);
    let g = grad::face_to(&ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b), &p);
    let per_rad = 180.0 / std::f64::consts::PI / 30.0;
    let d_angle = 1.9 / (1.9 * 1.9 + 0.09);
    assert!(
        (g.anchor.center.x + per_rad * d_angle * 0.5).abs() < 1e-9,
        "{g:?}"
    );
    // Moving the target by dx along x moves the anchor by -dx in its frame: the same, negated.
    assert!(
        (g.target.center.x - per_rad * d_angle * 0.5).abs() < 1e-9,
        "{g:?}"
    );
    // Widening the anchor by dh (its near face at depth 1.9 - 0 ... its left edge at
    // 0.1 - dh): du = -dh / 2; and its depth moves the hit nearer: depth 1.9 - dhy.
    // d angle / d depth = -u / (1.9^2 + u^2).
    assert!(
        (g.anchor.half_extents.x - per_rad * d_angle * 0.5).abs() < 1e-9,
        "{g:?}"
    );
    let d_depth = -0.3 / (1.9 * 1.9 + 0.09);
    assert!(
        (g.anchor.half_extents.y - per_rad * d_depth).abs() < 1e-9,
        "{g:?}"
    );
}

#[test]
fn hand_computed_surround_and_middle_of() {
    let p = RelationParams::default();
    let table = bx([0.0, 0.0, 0.4], [0.5, 0.5, 0.4], 0.0);
    let at = |deg: Real, r: Real| {
        let a = deg.to_radians();
        bx([r * a.cos(), r * a.sin(), 0.4], [0.2, 0.2, 0.4], 0.0)
    };
    // Radii 1, 1, 2 at 0, 120, 240 degrees: mean D = 4/3, d = 1/4, 1/4, 1/2, angles ideal.
    // Moving the third outward by dr: dD = dr / 3; d3 = (r3 - D) / D ->
    // d(d3)/dr = (2/3) / D - (r3 - D) / D^2 / 3 = 1/2 - 1/8 = 3/8; d1 = 1 - r1 / D ->
    // d(d1)/dr = r1 / D^2 / 3 = 3/16 (d2 likewise). dS/dr = (1/3) * 0.5 * sum -2 (1 - d_i) d(d_i)
    // = -(1/3) (2 * 0.75 * 3/16 + 0.5 * 3/8) = -5/32.
    let targets = [at(0.0, 1.0), at(120.0, 1.0), at(240.0, 2.0)];
    let views: Vec<ObjectGeom<'_>> = targets.iter().map(ObjectGeom::from_box).collect();
    let mut d = [BoxGrad::ZERO; 3];
    grad::surround(&views, &ObjectGeom::from_box(&table), &p, &mut d).unwrap();
    let radial = Vector3::new(240f64.to_radians().cos(), 240f64.to_radians().sin(), 0.0);
    assert!((d[2].center.dot(&radial) + 5.0 / 32.0).abs() < 1e-12, "{d:?}");
    // Plan angles do not change moving along the radius, so the angle term adds nothing.

    // middle_of, 0.25 m off along y: d/dy = -score * 0.25 / 0.0625 = -4 score.
    let pillow = bx([0.0, 0.25, 0.9], [0.3, 0.2, 0.1], 0.0);
    let g = grad::middle_of(&ObjectGeom::from_box(&pillow), &ObjectGeom::from_box(&table), &p);
    assert!((g.target.center.y + 4.0 * g.score).abs() < 1e-12 && close(g.anchor.center.y, 4.0 * g.score));
}

#[test]
fn hand_computed_architecture() {
    let p = RelationParams::default();
    let rooms = [room()];
    // against_wall: a wardrobe 0.5 m from the far wall (y = 5): 0.2 m past the [0, 0.3] m
    // band (sigma 0.1): score exp(-2), slope -score * 0.2 / 0.01 = -20 score per metre of
    // distance; moving toward the wall (+y) shortens it: d/dy = +20 score.
    let w = bx([2.0, 4.2, 1.0], [0.5, 0.3, 1.0], 0.0);
    let g = grad::arch_rooms(Relation::AgainstWall, &ObjectGeom::from_box(&w), &rooms, &p).unwrap();
    let s = (-2.0f64).exp();
    assert!(
        (g.score - s).abs() < 1e-12 && (g.target.center.y - 20.0 * s).abs() < 1e-9,
        "{g:?}"
    );
    // Its depth half extent brings its back nearer: +20 score too.
    assert!((g.target.half_extents.y - 20.0 * s).abs() < 1e-9);
    // hang_from_ceiling: a lamp 4 cm below the 2.8 m ceiling: 0.03 past the [0, 0.01] m band
    // (sigma 0.03): score exp(-0.5), slope -score * 0.03 / 0.0009 = -33.3 score; raising it
    // shortens the gap: d/dz = +33.3 score; its half height likewise.
    let lamp = bx([2.0, 2.5, 2.56], [0.2, 0.2, 0.2], 0.3);
    let g = grad::arch_rooms(
        Relation::HangFromCeiling,
        &ObjectGeom::from_box(&lamp),
        &rooms,
        &p,
    )
    .unwrap();
    let k = (-0.5f64).exp() / 0.03;
    assert!(
        (g.target.center.z - k).abs() < 1e-6 && (g.target.half_extents.z - k).abs() < 1e-6,
        "{g:?}"
    );
    // near(door): the door (x in [1.0, 1.9] on y = 0) as deep as the wall: a chair whose
    // front is 1.8 m from it is 0.3 m past near's [0.5, 1.5] m range... moving toward it
    // (-y) raises the score: d/dy = -(score * 0.3 / 0.0625).
    let chair = bx([1.45, 2.05, 0.4], [0.25, 0.25, 0.4], 0.0);
    let g = grad::arch_rooms(
        Relation::NearArch(ArchElement::Door),
        &ObjectGeom::from_box(&chair),
        &rooms,
        &p,
    )
    .unwrap();
    let s = (-0.09f64 / 0.125).exp();
    assert!(
        (g.score - s).abs() < 1e-9 && (g.target.center.y + s * 0.3 / 0.0625).abs() < 1e-6,
        "{g:?}"
    );
    // middle_of_room at the centre: 1 with a zero gradient.
    let rug = bx([2.0, 2.5, 0.01], [1.0, 0.5, 0.01], 0.0);
    let g = grad::arch_rooms(Relation::MiddleOfRoom, &ObjectGeom::from_box(&rug), &rooms, &p).unwrap();
    assert_eq!((g.score, g.target.center), (1.0, Vector3::zeros()));
}

/// The penetration depth of two boxes against finite differences, and against the depth the
/// boxes must be moved apart along its normal to separate.
#[test]
fn box_penetration_matches_finite_differences() {
    let tally = Tally::default();
    let mut runner = runner(1);
    runner
        .run(&near_pair(), |(a, b)| {
            let Some(p) = grad::box_penetration(&a, &b) else {
                return Ok(());
            };
            // Moving b out along the normal by the depth (plus a hair) separates them.
            let mut apart = b;
            apart.center += p.normal * (p.depth + 1e-9);
            prop_assert!(grad::box_penetration(&a, &apart).is_none_or(|q| q.depth < 1e-8));
            let depth = |x: &Obb, y: &Obb| grad::box_penetration(x, y).map_or(0.0, |q| q.depth);
            let (oa, ob) = (Obj::from_box(a), Obj::from_box(b));
            let (ga, gb) = (p.a.to_array(), p.b.to_array());
            for k in 0..7 {
                tally
                    .compare("box_penetration", &format!("d/d a[{k}]"), ga[k], |e| {
                        Some(depth(&oa.moved(k, e)?.obb, &b))
                    })
                    .map_err(TestCaseError::fail)?;
                tally
                    .compare("box_penetration", &format!("d/d b[{k}]"), gb[k], |e| {
                        Some(depth(&a, &ob.moved(k, e)?.obb))
                    })
                    .map_err(TestCaseError::fail)?;
            }
            Ok(())
        })
        .unwrap();
    tally.assert_mostly_checked(0.9, true);
}

#[test]
fn gradient_dispatch_refuses_the_wrong_kind() {
    let a = bx([0.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
    let g = ObjectGeom::from_box(&a);
    let p = RelationParams::default();
    assert!(grad::pair(Relation::InsideRoom, &g, &g, &p).is_err());
    assert!(grad::pair(Relation::Surround, &g, &g, &p).is_err());
    assert!(grad::arch_rooms(Relation::OnTop, &g, &[room()], &p).is_err());
    let mut short = [BoxGrad::ZERO; 1];
    assert!(grad::surround(&[g, g], &g, &p, &mut short).is_err());
}
