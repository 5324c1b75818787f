//! Hand-computed scores of every predicate in simple configurations: touching, overlapping,
//! nested, far apart, rotated 90 degrees and at an arbitrary yaw, stacked; every side.
//! The arithmetic behind each expected value is in the comment above it.

// Helpers outside `#[test]` functions build fixed, valid inputs.
#![allow(clippy::unwrap_used)]

use std::f64::consts::{FRAC_PI_2, PI};

use sceneeval_geom::{Isometry3, Mesh, Obb, Point3, Real, Rotation3, Side, Vector3};
use sceneeval_relations::{
    self as rel, ArchElement, LongShort, ObjectGeom, OnTopPlane, Relation, RelationParams, arch, batch,
};
use sceneeval_scene::Room;

fn bx(c: [Real; 3], h: [Real; 3], yaw: Real) -> Obb {
    Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::new(h[0], h[1], h[2]), yaw).unwrap()
}

fn g(o: &Obb) -> ObjectGeom<'_> {
    ObjectGeom::from_box(o)
}

fn pair(r: Relation, a: &Obb, b: &Obb) -> Real {
    batch::score_pair(r, &g(a), &g(b), &RelationParams::default()).unwrap()
}

fn close(actual: Real, expected: Real, tol: Real, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: got {actual}, expected {expected}"
    );
}

/// The same configuration turned by `yaw` about the world z axis through the origin.
fn turned(o: &Obb, yaw: Real) -> Obb {
    let r = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw);
    Obb {
        center: Point3::from(r * o.center.coords),
        half_extents: o.half_extents,
        rotation: r * o.rotation,
    }
}

/// The unit anchor used by the object-object cases: a 2 x 2 x 2 box at the origin.
fn anchor() -> Obb {
    bx([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], 0.0)
}

#[test]
fn inside_of_and_outside_of() {
    let b = anchor();
    let cases: [(&str, Obb, Real); 6] = [
        // Nested: a 0.4 cube well inside.
        ("nested", bx([0.3, -0.2, 0.1], [0.2, 0.2, 0.2], 0.0), 1.0),
        // Touching from outside: shares the face x = 1, nothing inside (up to the 1e-6 tolerance:
        // 1e-6 / 0.4 of the width = 2.5e-6).
        ("touching", bx([1.2, 0.0, 0.0], [0.2, 0.2, 0.2], 0.0), 2.5e-6),
        // Overlapping: x in [0.8, 1.2], 0.2 of 0.4 inside -> 0.5.
        ("overlapping", bx([1.0, 0.0, 0.0], [0.2, 0.2, 0.2], 0.0), 0.5),
        // Far apart.
        ("apart", bx([5.0, 5.0, 0.0], [0.2, 0.2, 0.2], 0.0), 0.0),
        // Rotated 90 degrees, a 0.2 x 1.6 slab straddling y = 1: y in [0.8, 1.0] of [0.8, 2.4]
        // after the turn -> 0.2 / 1.6 = 0.125.
        (
            "rotated 90",
            bx([0.0, 1.6, 0.0], [0.8, 0.1, 0.1], FRAC_PI_2),
            0.125,
        ),
        // Arbitrary yaw, centred on the face x = 1: half inside by mirror symmetry of the cube
        // (a cube turned about z is symmetric about the plane through its centre normal to x).
        ("yaw 0.7", bx([1.0, 0.0, 0.0], [0.3, 0.3, 0.3], 0.7), 0.5),
    ];
    for (what, a, expected) in cases {
        close(pair(Relation::InsideOf, &a, &b), expected, 1e-5, what);
        close(pair(Relation::OutsideOf, &a, &b), 1.0 - expected, 1e-5, what);
    }
}

#[test]
fn side_of_each_side_touching_apart_overlapping_rotated() {
    let b = anchor();
    for side in Side::ALL {
        let dir = side.local_direction();
        // Touching the face, centred on it: fully on that side and on no other.
        let touching = bx((dir * 1.25).into(), [0.25, 0.25, 0.25], 0.0);
        // Far out along the side: still fully on it (no distance limit).
        let far = bx((dir * 9.0).into(), [0.25, 0.25, 0.25], 0.0);
        // Straddling the face: half beyond it.
        let straddle = bx((dir * 1.0).into(), [0.25, 0.25, 0.25], 0.0);
        for other in Side::ALL {
            let e = if other == side { 1.0 } else { 0.0 };
            close(pair(Relation::SideOf(other), &touching, &b), e, 1e-12, "touching");
            close(pair(Relation::SideOf(other), &far, &b), e, 1e-12, "far");
        }
        close(pair(Relation::SideOf(side), &straddle, &b), 0.5, 1e-5, "straddle");
        // Nested in the anchor: on no side.
        let nested = bx((dir * 0.3).into(), [0.2, 0.2, 0.2], 0.0);
        close(pair(Relation::SideOf(side), &nested, &b), 0.0, 1e-12, "nested");
    }
    // Lateral 25 % margin: left of the anchor but shifted in y so that y in [1.0, 1.5]; the region
    // reaches y = 1.25 -> 0.5.
    let shifted = bx([-1.5, 1.25, 0.0], [0.25, 0.25, 0.25], 0.0);
    close(
        pair(Relation::SideOf(Side::Left), &shifted, &b),
        0.5,
        1e-12,
        "margin",
    );
    // The anchor turned 90 degrees: its left (local -x) is world -y.
    let b90 = bx([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], FRAC_PI_2);
    let south = bx([0.0, -2.0, 0.0], [0.25, 0.25, 0.25], 0.0);
    close(
        pair(Relation::SideOf(Side::Left), &south, &b90),
        1.0,
        1e-12,
        "anchor 90",
    );
    close(
        pair(Relation::SideOf(Side::Front), &south, &b90),
        0.0,
        1e-12,
        "anchor 90",
    );
    // The whole configuration at an arbitrary yaw gives the same scores.
    for yaw in [0.3, 1.9, -2.6] {
        for side in Side::ALL {
            let t = bx((side.local_direction() * 1.25).into(), [0.25, 0.25, 0.25], 0.4);
            let s0 = pair(Relation::SideOf(side), &t, &b);
            let s1 = pair(Relation::SideOf(side), &turned(&t, yaw), &turned(&b, yaw));
            close(s1, s0, 1e-9, "arbitrary yaw");
        }
    }
}

#[test]
fn side_region_each_side() {
    let b = anchor();
    for side in Side::ALL {
        let dir = side.local_direction();
        // In the side's half of the anchor: 1 for that side, 0 for the opposite.
        let inner = bx((dir * 0.5).into(), [0.2, 0.2, 0.2], 0.0);
        close(pair(Relation::SideRegion(side), &inner, &b), 1.0, 1e-12, "inner");
        close(
            pair(Relation::SideRegion(side.opposite()), &inner, &b),
            0.0,
            1e-12,
            "inner opposite",
        );
        // Beyond the face (outside the anchor): 0, unlike side_of.
        let outside = bx((dir * 1.5).into(), [0.2, 0.2, 0.2], 0.0);
        close(
            pair(Relation::SideRegion(side), &outside, &b),
            0.0,
            1e-12,
            "outside",
        );
        // Straddling the face: x in [0.8, 1.2] -> 0.2 of 0.4 inside the half -> 0.5.
        let straddle = bx((dir * 1.0).into(), [0.2, 0.2, 0.2], 0.0);
        close(
            pair(Relation::SideRegion(side), &straddle, &b),
            0.5,
            1e-5,
            "straddle",
        );
    }
}

#[test]
fn long_short_side_of_table() {
    // Table 1.0 (x) by 2.0 (y): long sides face +-x, short sides +-y.
    let t = bx([0.0, 0.0, 0.4], [0.5, 1.0, 0.4], 0.0);
    let long = bx([-0.8, 0.3, 0.4], [0.25, 0.25, 0.3], 0.0);
    let short = bx([0.1, 1.3, 0.4], [0.25, 0.25, 0.3], 0.0);
    close(
        pair(Relation::LongShortSideOf(LongShort::Long), &long, &t),
        1.0,
        1e-12,
        "long",
    );
    close(
        pair(Relation::LongShortSideOf(LongShort::Short), &long, &t),
        0.0,
        1e-12,
        "long/short",
    );
    close(
        pair(Relation::LongShortSideOf(LongShort::Short), &short, &t),
        1.0,
        1e-12,
        "short",
    );
    // A chair taller than the table: z in [0, 1.0] vs the table's [0, 0.8] -> 0.8.
    let tall = bx([0.8, 0.0, 0.5], [0.25, 0.25, 0.5], 0.0);
    close(
        pair(Relation::LongShortSideOf(LongShort::Long), &tall, &t),
        0.8,
        1e-9,
        "tall",
    );
    // The table turned 90 degrees: its long sides face world +-y.
    let t90 = bx([0.0, 0.0, 0.4], [0.5, 1.0, 0.4], FRAC_PI_2);
    let north = bx([0.3, 0.8, 0.4], [0.25, 0.25, 0.3], 1.1);
    close(
        pair(Relation::LongShortSideOf(LongShort::Long), &north, &t90),
        1.0,
        1e-12,
        "t90",
    );
    // Square table: no long or short side.
    let sq = bx([0.0, 0.0, 0.4], [0.6, 0.6, 0.4], 0.0);
    close(
        pair(Relation::LongShortSideOf(LongShort::Long), &long, &sq),
        0.0,
        0.0,
        "square",
    );
}

#[test]
fn on_top_stacked_sunk_overhanging() {
    let table = bx([0.0, 0.0, 0.375], [0.6, 0.4, 0.375], 0.0);
    // Stacked exactly on the top face.
    let book = bx([0.2, -0.1, 0.775], [0.1, 0.15, 0.025], 0.6);
    close(pair(Relation::OnTop, &book, &table), 1.0, 1e-12, "stacked");
    // Sunk 2 cm into the top (z in [0.73, 0.78]): 3 of 5 cm above the face -> 0.6.
    let sunk = bx([0.2, -0.1, 0.755], [0.1, 0.15, 0.025], 0.0);
    close(pair(Relation::OnTop, &sunk, &table), 0.6, 1e-4, "sunk");
    // The reference's centre plane counts all of it.
    let centre = RelationParams {
        on_top_plane: OnTopPlane::CentrePlane,
        ..RelationParams::default()
    };
    close(
        rel::on_top(&g(&sunk), &g(&table), &centre),
        1.0,
        1e-12,
        "sunk, centre plane",
    );
    // Overhanging the +x edge by half: x in [0.5, 0.7] -> 0.5.
    let over = bx([0.6, 0.0, 0.775], [0.1, 0.1, 0.025], 0.0);
    close(pair(Relation::OnTop, &over, &table), 0.5, 1e-6, "overhang");
    // Beside the table at the same height: 0. Under it: 0.
    close(
        pair(
            Relation::OnTop,
            &bx([1.0, 0.0, 0.775], [0.1, 0.1, 0.025], 0.0),
            &table,
        ),
        0.0,
        0.0,
        "beside",
    );
    close(
        pair(
            Relation::OnTop,
            &bx([0.0, 0.0, 0.1], [0.1, 0.1, 0.1], 0.0),
            &table,
        ),
        0.0,
        0.0,
        "under",
    );
    // A table turned 90 degrees: footprint 0.8 (x) by 1.2 (y); a book at x = 0.35 is off it.
    let t90 = bx([0.0, 0.0, 0.375], [0.6, 0.4, 0.375], FRAC_PI_2);
    let off = bx([0.55, 0.0, 0.775], [0.05, 0.05, 0.025], 0.0);
    close(
        pair(Relation::OnTop, &off, &t90),
        0.0,
        0.0,
        "off the turned table",
    );
    close(
        pair(Relation::OnTop, &off, &table),
        1.0,
        1e-12,
        "on the unturned table",
    );
}

#[test]
fn middle_of_plan_distance() {
    let bed = bx([1.0, 2.0, 0.3], [0.8, 1.0, 0.3], 0.4);
    // Centred (any height): 1.
    close(
        pair(
            Relation::MiddleOf,
            &bx([1.0, 2.0, 0.7], [0.3, 0.2, 0.1], 0.0),
            &bed,
        ),
        1.0,
        0.0,
        "centred",
    );
    // 0.3 m off in x and 0.4 in y: d = 0.5, exp(-0.25 / 0.125) = exp(-2) = 0.1353.
    close(
        pair(
            Relation::MiddleOf,
            &bx([1.3, 2.4, 0.7], [0.3, 0.2, 0.1], 0.0),
            &bed,
        ),
        (-2.0f64).exp(),
        1e-12,
        "offset",
    );
}

#[test]
fn face_to_cases() {
    // A sofa facing +y (yaw pi) toward a TV 3 m away.
    let sofa = bx([0.0, 0.0, 0.4], [1.0, 0.45, 0.4], PI);
    let tv = bx([0.0, 3.0, 1.0], [0.6, 0.05, 0.4], 0.0);
    close(pair(Relation::FaceTo, &sofa, &tv), 1.0, 1e-9, "head on");
    // TV shifted 1 m sideways (+x): the sofa's cross-section is x in [-1, 1] (turned 180, its
    // local x is world -x). Lines with world x in [0.4, 1.0] hit: mean x = 0.7 (z fully
    // covered: the TV spans z in [0.6, 1.4], the sofa [0, 0.8] -> lines z in [0.6, 0.8]).
    // Hit depth: 3 - 0.05 = 2.95 -> angle atan(0.7 / 2.95) = 13.35 deg -> 1 - 13.35/30.
    let shifted = bx([1.0, 3.0, 1.0], [0.6, 0.05, 0.4], 0.0);
    let expected = 1.0 - (0.7f64 / 2.95).atan().to_degrees() / 30.0;
    close(pair(Relation::FaceTo, &sofa, &shifted), expected, 1e-9, "shifted");
    // Facing away: 0.
    let away = bx([0.0, 0.0, 0.4], [1.0, 0.45, 0.4], 0.0);
    close(pair(Relation::FaceTo, &away, &tv), 0.0, 0.0, "away");
    // Turned 90 degrees (facing -x): the TV is to its side, no ray hits.
    let side = bx([0.0, 0.0, 0.4], [1.0, 0.45, 0.4], -FRAC_PI_2);
    close(pair(Relation::FaceTo, &side, &tv), 0.0, 0.0, "sideways");
    // Arbitrary yaw: the sofa turned by yaw about its centre, TV placed along its front.
    for yaw in [0.4, 2.0, -1.3] {
        let s = bx([0.0, 0.0, 0.4], [1.0, 0.45, 0.4], yaw);
        let front = s.side_direction(Side::Front);
        let t = Obb::from_yaw(
            Point3::new(3.0 * front.x, 3.0 * front.y, 1.0),
            Vector3::new(0.6, 0.05, 0.4),
            yaw + PI,
        )
        .unwrap();
        close(pair(Relation::FaceTo, &s, &t), 1.0, 1e-9, "arbitrary yaw");
    }
}

#[test]
fn face_to_a_mesh_anchor() {
    // A pyramid (square base 1 x 1, apex 1 m up) 2 m ahead of a box facing -y.
    let pyramid = Mesh::new(
        vec![
            Point3::new(-0.5, -0.5, 0.0),
            Point3::new(0.5, -0.5, 0.0),
            Point3::new(0.5, 0.5, 0.0),
            Point3::new(-0.5, 0.5, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ],
        vec![[0, 2, 1], [0, 3, 2], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
    )
    .unwrap();
    let pose = Isometry3::translation(0.0, -2.0, 0.0);
    let obb = Obb::from_local_aabb(pyramid.aabb(), &pose);
    let viewer = bx([0.0, 0.0, 0.5], [0.5, 0.3, 0.5], 0.0);
    // Symmetric about the viewer's axis: the mean hit is straight ahead.
    let s = rel::face_to(
        &g(&viewer),
        &ObjectGeom::with_mesh(&obb, &pyramid, &pose),
        &RelationParams::default(),
    );
    close(s, 1.0, 1e-9, "pyramid ahead");
}

#[test]
fn distance_relations_boxes_and_meshes() {
    let b = bx([0.0, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
    // Gap g along x; expected scores from the bands (sigma 0.25, 2 sigma^2 = 0.125).
    let at = |gap: Real| bx([1.0 + gap, 0.0, 0.5], [0.5, 0.5, 0.5], 0.0);
    let e = |delta: Real| (-(delta * delta) / 0.125).exp();
    let rows: [(Real, [Real; 4]); 6] = [
        // Overlapping (distance 0), touching, 1 m, 2.5 m, 4 m, 6 m.
        (-0.4, [1.0, e(0.5), e(1.5), e(4.0)]),
        (0.0, [1.0, e(0.5), e(1.5), e(4.0)]),
        (1.0, [e(0.5), 1.0, e(0.5), e(3.0)]),
        (2.5, [e(2.0), e(1.0), 1.0, e(1.5)]),
        (4.0, [e(3.5), e(2.5), 1.0, 1.0]),
        (6.0, [e(5.5), e(4.5), e(2.0), 1.0]),
    ];
    let rels = [
        Relation::NextTo,
        Relation::Near,
        Relation::AcrossFrom,
        Relation::Far,
    ];
    for (gap, expected) in rows {
        for (r, x) in rels.iter().zip(expected) {
            close(pair(*r, &at(gap), &b), x, 1e-9, &format!("{r} at gap {gap}"));
        }
    }
    // Nested: distance 0.
    close(
        rel::object_distance(&g(&bx([0.0, 0.0, 0.5], [0.1, 0.1, 0.1], 0.3)), &g(&b)),
        0.0,
        0.0,
        "nested",
    );
    // Corner to corner after a 45-degree turn: the turned cube's corner reaches
    // 0.5 sqrt(2) = 0.7071 toward the anchor: centre at 2.0 -> gap 2.0 - 0.5 - 0.7071.
    let turned45 = bx([2.0, 0.0, 0.5], [0.5, 0.5, 0.5], PI / 4.0);
    close(
        rel::pair_distance(&g(&turned45), &g(&b), &RelationParams::default()),
        1.5 - 0.5f64.sqrt(),
        1e-9,
        "45 degrees",
    );
    // A sphere-like mesh is farther than its box: an octahedron of radius 0.5 placed with its
    // tip toward the anchor behaves like its box there, but diagonally its face is farther.
    let octa = Mesh::new(
        vec![
            Point3::new(0.5, 0.0, 0.0),
            Point3::new(-0.5, 0.0, 0.0),
            Point3::new(0.0, 0.5, 0.0),
            Point3::new(0.0, -0.5, 0.0),
            Point3::new(0.0, 0.0, 0.5),
            Point3::new(0.0, 0.0, -0.5),
        ],
        vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
    )
    .unwrap();
    // Placed at (1.5, 1.5, 0.5): its box (corner at (1.0, 1.0)) is sqrt(0.5^2 + 0.5^2) = 0.7071
    // from the anchor's corner edge at (0.5, 0.5); the octahedron's nearest face point toward
    // (0.5, 0.5) is on the edge from (1.0, 1.5) to (1.5, 1.0), whose midpoint (1.25, 1.25) is
    // 0.75 sqrt(2) = 1.0607 away.
    let pose = Isometry3::translation(1.5, 1.5, 0.5);
    let obb = Obb::from_local_aabb(octa.aabb(), &pose);
    let mesh = ObjectGeom::with_mesh(&obb, &octa, &pose);
    close(
        rel::object_distance(&mesh, &g(&b)),
        0.75 * 2f64.sqrt(),
        1e-9,
        "octahedron",
    );
    close(
        rel::object_distance(&ObjectGeom::from_box(&obb), &g(&b)),
        0.5f64.sqrt(),
        1e-9,
        "its box",
    );
}

#[test]
fn surround_three_and_four() {
    let t = bx([0.0, 0.0, 0.4], [0.5, 0.5, 0.4], 0.0);
    let chair = |deg: Real, r: Real| {
        let a = deg.to_radians();
        bx([r * a.cos(), r * a.sin(), 0.4], [0.2, 0.2, 0.4], a)
    };
    let run = |objs: &[Obb]| {
        let v: Vec<ObjectGeom<'_>> = objs.iter().map(ObjectGeom::from_box).collect();
        rel::surround(&v, &g(&t), &RelationParams::default())
    };
    close(
        run(&[chair(10.0, 1.2), chair(130.0, 1.2), chair(250.0, 1.2)]),
        1.0,
        1e-12,
        "three even",
    );
    close(
        run(&[
            chair(0.0, 1.0),
            chair(90.0, 1.0),
            chair(180.0, 1.0),
            chair(270.0, 1.0),
        ]),
        1.0,
        1e-12,
        "four even",
    );
    // Four at 0, 90, 180 and 270 degrees but radii 1, 1, 1, 2: mean 1.25; d = 0.2, 0.2, 0.2, 0.6;
    // score = 0.5 + 0.5 (3 * 0.64 + 0.16) / 4 = 0.5 + 0.26 = 0.76.
    close(
        run(&[
            chair(0.0, 1.0),
            chair(90.0, 1.0),
            chair(180.0, 1.0),
            chair(270.0, 2.0),
        ]),
        0.76,
        1e-12,
        "radii",
    );
    close(run(&[chair(0.0, 1.0), chair(90.0, 1.0)]), 0.0, 0.0, "two");
}

/// The test bedroom with a window on wall 1 (x = 4) spanning y in [1.5, 3.5], 0.9 to 2.0 m up.
fn bedroom() -> Room {
    sceneeval_test_support::bedroom("bedroom")
        .window(1, [1.5, 3.5], [0.9, 2.0])
        .build()
        .unwrap()
}

#[test]
fn architecture_distances_to_each_element() {
    let room = bedroom();
    let p = RelationParams::default();
    let e = |delta: Real| (-(delta * delta) / 0.125).exp();
    // A desk 0.2 m from the window wall (x = 4), in front of the window (y in [1.5, 3.5]):
    // x in [3.2, 3.8], y in [1.9, 3.1], z in [0, 0.75].
    let desk = bx([3.5, 2.5, 0.375], [0.3, 0.6, 0.375], 0.0);
    // x in [3.2, 3.8]: 0.2 m from the wall's inner face; the window (z in [0.9, 2.0]) is above
    // the desk top (0.75): distance sqrt(0.2^2 + 0.15^2) = 0.25.
    close(
        arch::next_to(&g(&desk), &room, ArchElement::Wall, &p),
        1.0,
        0.0,
        "wall",
    );
    close(
        arch::next_to(&g(&desk), &room, ArchElement::Window, &p),
        1.0,
        0.0,
        "window 0.25 m",
    );
    // The door (wall 0 at x in [1.0, 1.9], y = 0) is 1.9 m away in y and 1.3 m in x from the
    // desk's corner (3.2, 1.9): sqrt(1.3^2 + 1.9^2) = 2.3022 -> across_from 1, near e(0.8022).
    let d_door = (1.3f64 * 1.3 + 1.9 * 1.9).sqrt();
    close(
        arch::across_from(&g(&desk), &room, ArchElement::Door, &p),
        1.0,
        0.0,
        "door across",
    );
    close(
        arch::near(&g(&desk), &room, ArchElement::Door, &p),
        e(d_door - 1.5),
        1e-9,
        "door near",
    );
    // Far from a wall: the best wall is the farthest one; in a 4 x 5 room nothing is 4 m away
    // except from the desk to wall 3 (x = 0): 3.2 m -> e(0.8).
    close(
        arch::far(&g(&desk), &room, ArchElement::Wall, &p),
        e(0.8),
        1e-9,
        "far wall",
    );
}

#[test]
fn architecture_placement_relations() {
    let room = bedroom();
    let p = RelationParams::default();
    // Bed against the head wall y = 5, facing -y.
    let bed = bx([2.0, 4.0, 0.3], [0.8, 1.0, 0.3], 0.0);
    close(arch::against_wall(&g(&bed), &room, &p), 1.0, 0.0, "bed against");
    close(arch::inside_room(&g(&bed), &room, &p), 1.0, 0.0, "bed inside");
    close(
        arch::on_wall(&g(&bed), &room, &p),
        1.0,
        0.0,
        "bed touches: on_wall too",
    );
    // The bed turned 90 degrees in the middle of the room: 2 m along x, x in [1, 3], y in
    // [1.7, 3.3]: nearest wall 1.0 m away -> against_wall e(0.7) with sigma 0.1: exp(-0.49/0.02).
    let bed90 = bx([2.0, 2.5, 0.3], [0.8, 1.0, 0.3], FRAC_PI_2);
    close(
        arch::against_wall(&g(&bed90), &room, &p),
        (-0.49f64 / 0.02).exp(),
        1e-15,
        "bed 90",
    );
    // A painting on the door wall beside the door, 1 cm off the wall.
    let painting = bx([3.0, 0.03, 1.5], [0.4, 0.02, 0.3], PI);
    close(arch::on_wall(&g(&painting), &room, &p), 1.0, 0.0, "painting");
    // The same painting over the door opening, 1 cm off the wall plane.
    let over_door = bx([1.45, 0.03, 1.5], [0.4, 0.02, 0.3], PI);
    // Its x range [1.05, 1.85] lies inside the door's [1.0, 1.9]; the nearest solid pieces are
    // the jambs beside the door, 0.05 m sideways and 0.01 m out: d = sqrt(0.0026) = 0.05099,
    // 0.04099 past the band (sigma 0.01): exp(-0.04099^2 / 0.0002) = 2.2e-4.
    let d: Real = 0.0026f64.sqrt();
    close(
        arch::on_wall(&g(&over_door), &room, &p),
        (-(d - 0.01).powi(2) / 0.0002).exp(),
        1e-12,
        "painting over the door hole",
    );
    // A lamp hanging from the 2.8 m ceiling.
    let lamp = bx([2.0, 2.5, 2.5], [0.2, 0.2, 0.3], 0.9);
    close(arch::hang_from_ceiling(&g(&lamp), &room, &p), 1.0, 0.0, "lamp");
    // A plant in the corner (0, 5).
    let plant = bx([0.25, 4.75, 0.5], [0.2, 0.2, 0.5], 0.3);
    close(arch::corner_of_room(&g(&plant), &room, &p), 1.0, 0.0, "plant");
    // A rug in the middle: 1.
    let rug = bx([2.0, 2.5, 0.005], [1.0, 0.7, 0.005], 0.2);
    close(arch::middle_of_room(&g(&rug), &room, &p), 1.0, 0.0, "rug");
}
