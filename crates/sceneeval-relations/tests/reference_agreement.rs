//! Agreement with the reference's sampling estimators.
//!
//! The reference scores the volume-fraction predicates by drawing `max(floor(5000 V), 64)`
//! uniform points in the target's box and counting those its `contains` / `at_side` tests accept
//! (`spatial/bounding_box.py`, `spatial/spatial_relation.py` and `spatial/arch_relation.py` in
//! `3dlg-hcvc/SceneEval`), and measures distances as the minimum over samples of the smaller
//! box. This file re-implements those estimators independently, from their definitions
//! (points in the anchor's frame, the `1e-6` epsilons, the lateral margins, numpy's
//! `allclose`), with a fixed-seed generator, and checks on random box pairs that
//! - our exact fractions equal the estimators' expectations: within 5 standard errors of a
//!   4,000-sample estimate (a wrong plane, margin or side would be off by far more);
//! - our decisions (score above 0.5) agree with the reference's own sample count wherever its
//!   estimate is more than 4 standard errors from 0.5, i.e. wherever its noise does not
//!   straddle the threshold;
//! - `inside_room` is the expectation of the reference's downward-ray estimator in an L-shaped
//!   room;
//! - our box-box and box-wall distances are lower bounds of every sample's distance (the
//!   reference's sampled minimum can only overestimate a gap) and close to the best of many
//!   samples.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use sceneeval_geom::{Obb, Point3, Real, Rotation3, Side, Vector3};
use sceneeval_relations::{
    LongShort, ObjectGeom, RelationParams, inside_of, long_short_side_of, object_distance, on_top, side_of,
    side_region,
};

/// A small fixed-seed generator (SplitMix64): the test needs reproducible uniforms only.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    fn uniform(&mut self, lo: Real, hi: Real) -> Real {
        lo + (hi - lo) * ((self.next_u64() >> 11) as Real / (1u64 << 53) as Real)
    }
}

/// `sample_points()`: `centroid + axes (u * half)`, u uniform in [-1, 1]^3.
fn sample(o: &Obb, rng: &mut Rng) -> Point3 {
    let u = Vector3::new(
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
        rng.uniform(-1.0, 1.0),
    );
    o.center + o.rotation * u.component_mul(&o.half_extents)
}

/// The reference's sample count for a box: `max(floor(volume * 5000), 64)`, volume from the
/// full sizes clamped at `1e-6`.
fn reference_count(o: &Obb) -> usize {
    let volume: Real = o.half_extents.iter().map(|h| (2.0 * h).max(1e-6)).product();
    ((volume * 5000.0).floor() as usize).max(64)
}

/// `p` in the frame of `o` (`coord_axes^T (p - centroid)`).
fn local(o: &Obb, p: &Point3) -> Vector3 {
    o.rotation.inverse() * (p - o.center)
}

/// `contains(P)`: every `|local_i| <= half_i + 1e-6`.
fn contains(o: &Obb, p: &Point3) -> bool {
    let l = local(o, p);
    (0..3).all(|i| l[i].abs() <= o.half_extents[i] + 1e-6)
}

/// `at_side(P, side, no_contain, margin)` of the notes, for a side given as (axis, sign).
fn at_side(o: &Obb, p: &Point3, axis: usize, sign: Real, no_contain: bool, margin: Real) -> bool {
    let l = local(o, p);
    let along = sign * l[axis];
    let beyond = if no_contain {
        along >= o.half_extents[axis] - 1e-6
    } else {
        along >= -1e-6
    };
    let lateral = margin < 0.0
        || (0..3)
            .filter(|&i| i != axis)
            .all(|i| l[i].abs() <= o.half_extents[i] * (1.0 + margin));
    beyond && lateral
}

/// The six sides as (name, axis, sign) in the object convention (left = -x, front = -y).
const SIDES: [(Side, usize, Real); 6] = [
    (Side::Left, 0, -1.0),
    (Side::Right, 0, 1.0),
    (Side::Front, 1, -1.0),
    (Side::Back, 1, 1.0),
    (Side::Top, 2, 1.0),
    (Side::Bottom, 2, -1.0),
];

/// numpy's `allclose(a, b)`: `|a - b| <= 1e-8 + 1e-5 |b|`.
fn allclose(a: Real, b: Real) -> bool {
    (a - b).abs() <= 1e-8 + 1e-5 * b.abs()
}

/// One volume-fraction predicate: its name, our exact score, and the reference's per-point
/// test. (`long_short_side_of`, the larger of two fractions, has its own test.)
struct Case<'a> {
    name: String,
    ours: Real,
    accepts: Box<dyn Fn(&Point3) -> bool + 'a>,
}

fn cases<'a>(target: &'a Obb, anchor: &'a Obb) -> Vec<Case<'a>> {
    let p = RelationParams::default();
    let reference = RelationParams::reference();
    let (a, b) = (ObjectGeom::from_box(target), ObjectGeom::from_box(anchor));
    let mut out: Vec<Case<'a>> = vec![Case {
        name: "inside_of".into(),
        ours: inside_of(&a, &b, &p),
        accepts: (Box::new(move |q| contains(anchor, q))),
    }];
    for (side, axis, sign) in SIDES {
        out.push(Case {
            name: format!("side_of({side})"),
            ours: side_of(&a, &b, side, &p),
            accepts: (Box::new(move |q| at_side(anchor, q, axis, sign, true, 0.25))),
        });
        out.push(Case {
            name: format!("side_region({side})"),
            ours: side_region(&a, &b, side, &p),
            accepts: (Box::new(move |q| contains(anchor, q) && at_side(anchor, q, axis, sign, false, 1e-9))),
        });
    }
    // on_top: the reference's configured centre plane, and the paper's top face (ours).
    out.push(Case {
        name: "on_top (reference: centre plane)".into(),
        ours: on_top(&a, &b, &reference),
        accepts: (Box::new(move |q| at_side(anchor, q, 2, 1.0, false, 1e-9))),
    });
    out.push(Case {
        name: "on_top (default: top face)".into(),
        ours: on_top(&a, &b, &p),
        accepts: (Box::new(move |q| at_side(anchor, q, 2, 1.0, true, 1e-9))),
    });
    out
}

/// The reference's score from `n` samples of `o`: the largest over `tests` of the fraction of
/// the samples a test accepts (the samples are shared, as the reference caches them on the
/// box).
fn estimate(o: &Obb, n: usize, tests: &[&dyn Fn(&Point3) -> bool], rng: &mut Rng) -> Real {
    let mut hits = vec![0usize; tests.len()];
    for _ in 0..n {
        let q = sample(o, rng);
        for (h, t) in hits.iter_mut().zip(tests) {
            *h += usize::from(t(&q));
        }
    }
    hits.into_iter().max().unwrap_or(0) as Real / n as Real
}

/// A box with half extents in `[lo, hi]`, centre in `[-spread, spread]^2 x [0, 1.5]` around
/// the origin, turned by a yaw or (one case in four) about all three axes.
fn random_box(rng: &mut Rng, lo: Real, hi: Real, spread: Real) -> Obb {
    let h = Vector3::new(rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi));
    let c = Point3::new(
        rng.uniform(-spread, spread),
        rng.uniform(-spread, spread),
        rng.uniform(0.0, 1.5),
    );
    let rotation = if rng.uniform(0.0, 1.0) < 0.25 {
        Rotation3::from_euler_angles(
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-3.2, 3.2),
        )
    } else {
        Rotation3::from_axis_angle(&Vector3::z_axis(), rng.uniform(-3.2, 3.2))
    };
    Obb::new(c, h, rotation).unwrap()
}

/// The standard error of a fraction `f` estimated from `n` samples (at least that of one
/// sample in `n`, so that an estimate of exactly 0 or 1 still allows a little slack).
fn standard_error(f: Real, n: usize) -> Real {
    (f * (1.0 - f)).max(1.0 / n as Real).sqrt() / (n as Real).sqrt()
}

/// Checks our exact score `ours` against the reference's estimator ([`estimate`]): close to a
/// 4,000-sample estimate, and the same decision as an estimate with the reference's own sample
/// count wherever that one is decided (more than 4 standard errors from 0.5). Returns 1 when
/// the decision was compared.
fn check(ours: Real, target: &Obb, tests: &[&dyn Fn(&Point3) -> bool], rng: &mut Rng, what: &str) -> usize {
    let n = 4000;
    let f = estimate(target, n, tests, rng);
    let se = standard_error(f, n);
    assert!(
        (ours - f).abs() <= 5.0 * se,
        "{what}: ours {ours} vs estimate {f} (standard error {se})"
    );
    let n = reference_count(target);
    let f = estimate(target, n, tests, rng);
    if (f - 0.5).abs() > 4.0 * standard_error(f, n) {
        assert_eq!(
            ours > 0.5,
            f > 0.5,
            "{what}: decisions differ (ours {ours}, reference estimate {f} of {n})"
        );
        1
    } else {
        0
    }
}

#[test]
fn volume_fractions_are_the_reference_estimators_expectations() {
    let mut rng = Rng(20_261_121);
    let mut decided = 0;
    for k in 0..300 {
        let anchor = random_box(&mut rng, 0.1, 1.0, 0.0);
        // Targets near the anchor, so that fractions strictly between 0 and 1 are common.
        let target = random_box(&mut rng, 0.05, 0.8, 1.2);
        for case in cases(&target, &anchor) {
            let what = format!("case {k}, {}: target {target:?}, anchor {anchor:?}", case.name);
            decided += check(case.ours, &target, &[&*case.accepts], &mut rng, &what);
        }
    }
    // The comparison must have covered many decided cases, not vacuously few.
    assert!(decided > 3000, "only {decided} decided cases");
}

#[test]
fn long_short_side_of_is_the_larger_half() {
    let mut rng = Rng(7);
    let mut decided = 0;
    for k in 0..300 {
        let anchor = random_box(&mut rng, 0.1, 1.0, 0.0);
        let target = random_box(&mut rng, 0.05, 0.8, 1.2);
        let (fx, fy) = (2.0 * anchor.half_extents.x, 2.0 * anchor.half_extents.y);
        let (a, b) = (ObjectGeom::from_box(&target), ObjectGeom::from_box(&anchor));
        for which in [LongShort::Long, LongShort::Short] {
            let ours = long_short_side_of(&a, &b, which, &RelationParams::default());
            if allclose(fx, fy) {
                // No long or short side: the reference scores 0 without sampling.
                assert_eq!(ours, 0.0, "case {k}");
                continue;
            }
            let axis = match which {
                LongShort::Long if fx < fy => 0,
                LongShort::Long => 1,
                LongShort::Short if fx > fy => 0,
                LongShort::Short => 1,
            };
            // The reference's score: the larger of the fractions on either side of the centre
            // plane across `axis`.
            let plus = |q: &Point3| at_side(&anchor, q, axis, 1.0, false, 1e-9);
            let minus = |q: &Point3| at_side(&anchor, q, axis, -1.0, false, 1e-9);
            decided += check(
                ours,
                &target,
                &[&plus, &minus],
                &mut rng,
                &format!("case {k}, {which:?}"),
            );
        }
    }
    assert!(decided > 300, "only {decided} decided cases");
}

/// Distance from `p` to the solid box `o` (0 inside).
fn point_box_distance(o: &Obb, p: &Point3) -> Real {
    let l = local(o, p);
    let clamped = Vector3::from_fn(|i, _| l[i].clamp(-o.half_extents[i], o.half_extents[i]));
    (l - clamped).norm()
}

#[test]
fn box_distance_bounds_the_reference_sampled_minimum() {
    let mut rng = Rng(42);
    let mut separated = 0;
    for k in 0..300 {
        let a = random_box(&mut rng, 0.05, 0.8, 0.0);
        let b = random_box(&mut rng, 0.05, 0.8, 2.5);
        let ours = object_distance(&ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b));
        // The reference samples the smaller box (its metric box is the box itself).
        let volume = |o: &Obb| o.half_extents.product();
        let (small, other) = if volume(&a) < volume(&b) {
            (&a, &b)
        } else {
            (&b, &a)
        };
        let n = 20_000;
        let sampled = (0..n)
            .map(|_| point_box_distance(other, &sample(small, &mut rng)))
            .fold(Real::INFINITY, Real::min);
        if sampled == 0.0 {
            // A sample inside the other box: they overlap and ours must say so.
            assert_eq!(ours, 0.0, "case {k}");
            continue;
        }
        separated += 1;
        assert!(
            ours <= sampled + 1e-9,
            "case {k}: ours {ours} > sampled minimum {sampled}"
        );
        // 20,000 samples come within a few centimetres of the closest point of boxes this size.
        assert!(
            sampled - ours < 0.1,
            "case {k}: ours {ours}, sampled minimum {sampled}"
        );
    }
    assert!(separated > 150, "only {separated} separated pairs");
}

/// Whether `(x, y)` lies inside the polygon `poly` (crossing number).
fn in_polygon(poly: &[(Real, Real)], x: Real, y: Real) -> bool {
    let mut inside = false;
    for (i, &(x0, y0)) in poly.iter().enumerate() {
        let (x1, y1) = poly[(i + 1) % poly.len()];
        if (y0 > y) != (y1 > y) && x < x0 + (y - y0) * (x1 - x0) / (y1 - y0) {
            inside = !inside;
        }
    }
    inside
}

#[test]
fn inside_room_is_the_reference_ray_estimator_expectation() {
    // The reference: the fraction of box samples whose ray straight down hits the floor mesh,
    // i.e. samples over the floor polygon and above the floor. An L-shaped room with its floor
    // at z = 0.2.
    let outline = [
        (0.0, 0.0),
        (4.0, 0.0),
        (4.0, 2.0),
        (2.0, 2.0),
        (2.0, 4.0),
        (0.0, 4.0),
    ];
    let room = sceneeval_scene::RoomBuilder::polygon(
        "l",
        outline
            .iter()
            .map(|&(x, y)| sceneeval_geom::Point2::new(x, y))
            .collect(),
    )
    .floor_z(0.2)
    .wall_height(2.8)
    .wall_thickness(0.1)
    .build()
    .unwrap();
    let params = RelationParams::default();
    let mut rng = Rng(99);
    let mut decided = 0;
    for k in 0..300 {
        let mut o = random_box(&mut rng, 0.1, 1.0, 0.0);
        // Around the room, often straddling its outline or its reflex corner.
        o.center = Point3::new(
            rng.uniform(-0.5, 4.5),
            rng.uniform(-0.5, 4.5),
            rng.uniform(-0.3, 1.0),
        );
        let ours = sceneeval_relations::arch::inside_room(&ObjectGeom::from_box(&o), &room, &params);
        let over_floor = |q: &Point3| q.z >= 0.2 && in_polygon(&outline, q.x, q.y);
        decided += check(ours, &o, &[&over_floor], &mut rng, &format!("case {k}: {o:?}"));
    }
    assert!(decided > 200, "only {decided} decided cases");
}

/// Distance from `p` to the vertical rectangle over the segment `p0`-`p1` from `z0` to `z1`.
fn point_wall_face_distance(p: &Point3, p0: (Real, Real), p1: (Real, Real), z0: Real, z1: Real) -> Real {
    let (dx, dy) = (p1.0 - p0.0, p1.1 - p0.1);
    let t = (((p.x - p0.0) * dx + (p.y - p0.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    let closest = Point3::new(p0.0 + t * dx, p0.1 + t * dy, p.z.clamp(z0, z1));
    (p - closest).norm()
}

#[test]
fn wall_distance_bounds_the_reference_sampled_minimum() {
    // The reference: the minimum over the object's box samples of the distance to the wall's
    // surface. For an object in the room the nearest part of our wall solid is its inner face,
    // the rectangle over the wall's segment, so our exact distance bounds every sample's from
    // below and the best of many samples comes close to it. A room with a diagonal wall.
    let outline = [(0.0, 0.0), (4.0, 0.0), (4.0, 3.0), (2.5, 4.5), (0.0, 4.5)];
    let room = sceneeval_scene::RoomBuilder::polygon(
        "r",
        outline
            .iter()
            .map(|&(x, y)| sceneeval_geom::Point2::new(x, y))
            .collect(),
    )
    .wall_height(2.8)
    .wall_thickness(0.1)
    .build()
    .unwrap();
    let mut rng = Rng(5);
    let mut checked = 0;
    for k in 0..200 {
        let mut o = random_box(&mut rng, 0.05, 0.5, 0.0);
        o.center = Point3::new(
            rng.uniform(0.6, 3.4),
            rng.uniform(0.6, 3.4),
            rng.uniform(0.6, 2.2),
        );
        let a = ObjectGeom::from_box(&o);
        for (i, wall) in room.walls().iter().enumerate() {
            let (p0, p1) = (outline[i], outline[(i + 1) % outline.len()]);
            let ours = sceneeval_relations::arch::wall_distance(&a, wall);
            let sampled = (0..20_000)
                .map(|_| point_wall_face_distance(&sample(&o, &mut rng), p0, p1, 0.0, 2.8))
                .fold(Real::INFINITY, Real::min);
            assert!(
                ours <= sampled + 1e-9,
                "case {k}, wall {i}: ours {ours} > sampled {sampled}"
            );
            assert!(
                sampled - ours < 0.1,
                "case {k}, wall {i}: ours {ours}, sampled {sampled}"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 1000);
}
