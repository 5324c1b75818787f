//! Collision: reproducers of missed collisions with open meshes and nested yawed boxes, an
//! exact independent check on random poses, and the narrow phase's work counted on stacked
//! copies.

// Test helpers outside #[test] functions may unwrap too.
#![allow(clippy::unwrap_used)]

mod common;

use std::sync::Arc;

use common::{at, scene};
use proptest::prelude::*;
use sceneeval_geom::conventions::pose_from_yaw;
use sceneeval_geom::{Isometry3, Mesh, Point3, Rotation3, Vector3};
use sceneeval_plausibility::*;
use sceneeval_scene::{Category, Scene, SceneObject};

/// Faces of an axis-aligned box: -x, +x, -y, +y, -z, +z.
#[derive(Clone, Copy, PartialEq)]
enum Face {
    Bottom,
    Top,
    Front,
}

/// Appends an axis-aligned box `lo..hi` to a mesh under construction, each face split into
/// `n` x `n` squares, leaving out the faces in `omit`.
fn add_box(v: &mut Vec<Point3>, t: &mut Vec<[u32; 3]>, lo: [f64; 3], hi: [f64; 3], omit: &[Face], n: u32) {
    let faces = [(0, -1.0), (0, 1.0), (1, -1.0), (1, 1.0), (2, -1.0), (2, 1.0)];
    for (k, sign) in faces {
        let face = match (k, sign > 0.0) {
            (2, false) => Some(Face::Bottom),
            (2, true) => Some(Face::Top),
            (1, false) => Some(Face::Front),
            _ => None,
        };
        if face.is_some_and(|f| omit.contains(&f)) {
            continue;
        }
        let (u, w) = if sign > 0.0 {
            ((k + 1) % 3, (k + 2) % 3)
        } else {
            ((k + 2) % 3, (k + 1) % 3)
        };
        let base = v.len() as u32;
        for i in 0..=n {
            for j in 0..=n {
                let mut p = [0.0; 3];
                p[k] = if sign > 0.0 { hi[k] } else { lo[k] };
                p[u] = lo[u] + (hi[u] - lo[u]) * f64::from(i) / f64::from(n);
                p[w] = lo[w] + (hi[w] - lo[w]) * f64::from(j) / f64::from(n);
                v.push(Point3::new(p[0], p[1], p[2]));
            }
        }
        let at = |i: u32, j: u32| base + i * (n + 1) + j;
        for i in 0..n {
            for j in 0..n {
                t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
}

/// An open desk as real assets have it: a 1.4 x 0.7 m top 2 cm thick without its underside
/// (z from 0.73 to 0.75) on four 5 cm legs without top or bottom faces.
fn open_desk() -> Arc<Mesh> {
    let (mut v, mut t) = (Vec::new(), Vec::new());
    add_box(
        &mut v,
        &mut t,
        [-0.7, -0.35, 0.73],
        [0.7, 0.35, 0.75],
        &[Face::Bottom],
        8,
    );
    for (x, y) in [(-0.6, -0.25), (0.6, -0.25), (-0.6, 0.25), (0.6, 0.25)] {
        add_box(
            &mut v,
            &mut t,
            [x - 0.025, y - 0.025, 0.0],
            [x + 0.025, y + 0.025, 0.73],
            &[Face::Bottom, Face::Top],
            2,
        );
    }
    let m = Mesh::new(v, t).unwrap();
    assert!(!m.is_closed());
    Arc::new(m)
}

/// An open laptop: a 34 x 24 x 1.5 cm base without its underside and a 34 x 0.6 x 23 cm screen
/// standing at its back, origin at the bottom centre of the base.
fn open_laptop() -> Arc<Mesh> {
    let (mut v, mut t) = (Vec::new(), Vec::new());
    add_box(
        &mut v,
        &mut t,
        [-0.17, -0.12, 0.0],
        [0.17, 0.12, 0.015],
        &[Face::Bottom],
        6,
    );
    add_box(
        &mut v,
        &mut t,
        [-0.17, 0.114, 0.015],
        [0.17, 0.12, 0.245],
        &[Face::Bottom],
        6,
    );
    Arc::new(Mesh::new(v, t).unwrap())
}

/// An open armchair: seat, back and two arms as boxes without undersides (and the seat without
/// its front face), 0.8 m wide, 0.8 m deep, 0.8 m high, arms 15 cm wide.
fn open_armchair() -> Arc<Mesh> {
    let (mut v, mut t) = (Vec::new(), Vec::new());
    add_box(
        &mut v,
        &mut t,
        [-0.25, -0.4, 0.0],
        [0.25, 0.25, 0.42],
        &[Face::Bottom, Face::Front],
        4,
    );
    add_box(
        &mut v,
        &mut t,
        [-0.4, 0.25, 0.0],
        [0.4, 0.4, 0.8],
        &[Face::Bottom],
        4,
    );
    for x in [-0.4, 0.25] {
        add_box(
            &mut v,
            &mut t,
            [x, -0.4, 0.0],
            [x + 0.15, 0.25, 0.6],
            &[Face::Bottom],
            4,
        );
    }
    let m = Mesh::new(v, t).unwrap();
    assert!(!m.is_closed());
    Arc::new(m)
}

fn col(scene: &Scene) -> CollisionReport {
    collision(scene, &CollisionParams::default()).unwrap()
}

#[test]
fn laptop_sunk_into_an_open_desk_collides() {
    // The desk top spans z in [0.73, 0.75]; the laptop's base bottom is 5 cm below the top
    // surface (z = 0.70), so its base hangs 1.5 cm under the top and its screen passes
    // through the 2 cm top. Screen points inside the top lie up to 2 cm below its top face
    // (its underside is missing, so only the top face and the desk's box bound their depth).
    let s = scene()
        .add_mesh("desk", Category::new("desk"), open_desk(), at(2.0, 2.5, 0.0, 0.0))
        .add_mesh(
            "laptop",
            Category::new("laptop"),
            open_laptop(),
            at(2.0, 2.5, 0.70, 0.2),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert_eq!(r.contacts.len(), 1, "{r:?}");
    let c = &r.contacts[0];
    assert!(c.colliding, "{c:?}");
    assert!(c.depth > 0.005, "{c:?}");
    assert!(r.col_sc);
    // Resting on the top (base bottom at 0.75): a contact, not a collision.
    let s = scene()
        .add_mesh("desk", Category::new("desk"), open_desk(), at(2.0, 2.5, 0.0, 0.0))
        .add_mesh(
            "laptop",
            Category::new("laptop"),
            open_laptop(),
            at(2.0, 2.5, 0.75, 0.2),
        )
        .build()
        .unwrap();
    let r = col(&s);
    assert!(!r.col_sc, "{r:?}");
    assert!(r.contacts.iter().all(|c| !c.undecided));
    // Sunk 3 mm: within the tolerance.
    let s = scene()
        .add_mesh("desk", Category::new("desk"), open_desk(), at(2.0, 2.5, 0.0, 0.0))
        .add_mesh(
            "laptop",
            Category::new("laptop"),
            open_laptop(),
            at(2.0, 2.5, 0.747, 0.2),
        )
        .build()
        .unwrap();
    assert!(!col(&s).col_sc);
}

#[test]
fn open_armchairs_overlapping_by_11_6_cm_collide() {
    // Side by side along x, 0.8 m wide each: centres 0.8 - 0.116 = 0.684 m apart, so the right
    // arm of the first (x in [0.25, 0.4] local) and the left arm of the second overlap by
    // 11.6 cm; the overlapped arm points lie up to 15 - 11.6 = 3.4 cm inside the other arm.
    let chair = open_armchair();
    let s = scene()
        .add_mesh(
            "a",
            Category::new("armchair"),
            chair.clone(),
            at(1.5, 2.5, 0.0, 0.0),
        )
        .add_mesh(
            "b",
            Category::new("armchair"),
            chair.clone(),
            at(1.5 + 0.684, 2.5, 0.0, 0.0),
        )
        .build()
        .unwrap();
    let r = col(&s);
    let c = &r.contacts[0];
    assert!(c.colliding, "{c:?}");
    assert!(c.depth > 0.005, "{c:?}");
    let deep = collision(
        &s,
        &CollisionParams {
            depth_search: sceneeval_geom::DepthSearch::All,
            ..CollisionParams::default()
        },
    )
    .unwrap();
    // The largest bound: an arm's inner face 3.4 cm deep in the other arm, or a ball inside
    // both arms (radius up to 11.6 / 2 cm, bound 11.6 cm).
    assert!(deep.contacts[0].depth >= 0.034 - 0.0025, "{:?}", deep.contacts[0]);
    assert!(deep.contacts[0].depth <= 0.116 + 1e-9, "{:?}", deep.contacts[0]);
    // Arms flush (0.8 m apart): touching, not colliding.
    let s = scene()
        .add_mesh(
            "a",
            Category::new("armchair"),
            chair.clone(),
            at(1.5, 2.5, 0.0, 0.0),
        )
        .add_mesh("b", Category::new("armchair"), chair, at(2.3, 2.5, 0.0, 0.0))
        .build()
        .unwrap();
    assert!(!col(&s).col_sc);
}

#[test]
fn small_box_inside_a_yawed_box_on_the_same_floor_collides() {
    // A 2 x 1.6 x 0.6 m bed standing on the floor, turned by 15 to 45 degrees, and a box of
    // 0.3 m standing on the same floor inside it at several offsets.
    for yaw_deg in [15.0_f64, 22.5, 30.0, 37.5, 45.0] {
        let yaw = yaw_deg.to_radians();
        for (u, v) in [(0.0, 0.0), (0.5, 0.3), (-0.7, -0.5), (0.7, -0.5)] {
            let (c, s) = (yaw.cos(), yaw.sin());
            let (x, y) = (2.0 + c * u - s * v, 2.5 + s * u + c * v);
            let scene = scene()
                .add_box(
                    "bed",
                    Category::new("bed"),
                    Vector3::new(2.0, 1.6, 0.6) * 0.5,
                    pose_from_yaw(Point3::new(2.0, 2.5, 0.3), yaw),
                )
                .add_box(
                    "box",
                    Category::new("box"),
                    Vector3::new(0.3, 0.3, 0.3) * 0.5,
                    pose_from_yaw(Point3::new(x, y, 0.15), 0.4),
                )
                .build()
                .unwrap();
            let r = col(&scene);
            assert!(r.col_sc, "yaw {yaw_deg}, offset ({u}, {v}): {r:?}");
            assert_eq!(r.num_in_collision, 2);
        }
    }
}

#[test]
fn grid_with_pushed_objects_finds_every_nested_pair() {
    // A grid of yawed beds with a small box beside each; every tenth small box is pushed
    // into its bed (standing on the same floor). Exactly those pairs collide.
    let mut b = Scene::builder();
    let mut expected = 0;
    for k in 0..60 {
        let (gx, gy) = ((k % 10) as f64 * 3.0, (k / 10) as f64 * 3.0);
        let yaw = (15.0 + 0.5 * k as f64).to_radians();
        b = b.add_box(
            format!("bed{k}"),
            Category::new("bed"),
            Vector3::new(2.0, 1.6, 0.6) * 0.5,
            pose_from_yaw(Point3::new(gx, gy, 0.3), yaw),
        );
        let (cx, cy) = if k % 10 == 3 {
            expected += 1;
            (gx + 0.3 * yaw.cos(), gy + 0.3 * yaw.sin())
        } else {
            (gx + 1.45, gy + 1.45)
        };
        b = b.add_box(
            format!("box{k}"),
            Category::new("box"),
            Vector3::new(0.3, 0.3, 0.3) * 0.5,
            pose_from_yaw(Point3::new(cx, cy, 0.15), 0.0),
        );
    }
    let r = col(&b.build().unwrap());
    assert_eq!(r.num_colliding_pairs, expected, "{:?}", r.contacts);
}

/// The exact penetration depth of two boxes (separating axis theorem: the shortest push
/// along the 15 candidate axes), 0 when they are apart.
fn sat_depth(ha: &Vector3, pa: &Isometry3, hb: &Vector3, pb: &Isometry3) -> f64 {
    let ra = pa.rotation.to_rotation_matrix();
    let rb = pb.rotation.to_rotation_matrix();
    let axes_a: Vec<Vector3> = (0..3).map(|k| ra.matrix().column(k).into()).collect();
    let axes_b: Vec<Vector3> = (0..3).map(|k| rb.matrix().column(k).into()).collect();
    let mut axes: Vec<Vector3> = axes_a.iter().chain(&axes_b).copied().collect();
    for a in &axes_a {
        for b in &axes_b {
            if let Some(c) = a.cross(b).try_normalize(1e-9) {
                axes.push(c);
            }
        }
    }
    let radius =
        |h: &Vector3, ax: &[Vector3], l: &Vector3| (0..3).map(|k| h[k] * ax[k].dot(l).abs()).sum::<f64>();
    let (ca, cb) = (pa.translation.vector, pb.translation.vector);
    axes.iter()
        .map(|l| {
            let (a, b) = (ca.dot(l), cb.dot(l));
            let (r1, r2) = (radius(ha, &axes_a, l), radius(hb, &axes_b, l));
            ((a + r1) - (b - r2)).min((b + r2) - (a - r1)).max(0.0)
        })
        .fold(f64::INFINITY, f64::min)
}

fn pose(x: f64, y: f64, z: f64, rx: f64, ry: f64, rz: f64) -> Isometry3 {
    Isometry3::from_parts(
        Vector3::new(x, y, z).into(),
        Rotation3::from_euler_angles(rx, ry, rz).into(),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// For random poses of two boxes (subdivided, so the search goes through a deep hierarchy)
    /// the verdict agrees with the exact penetration depth: never colliding at or below the
    /// tolerance, and its depth never above the true one; always colliding above
    /// `sqrt 2 (tolerance + spacing)` (the deepest surface point of an edge crossing an edge
    /// lies `1 / sqrt 2` as deep as the penetration).
    #[test]
    fn verdict_agrees_with_the_exact_depth_of_random_box_pairs(
        ha in (0.05..0.6f64, 0.05..0.6f64, 0.05..0.6f64),
        hb in (0.05..0.6f64, 0.05..0.6f64, 0.05..0.6f64),
        ra in (-3.2..3.2f64, -3.2..3.2f64, -3.2..3.2f64),
        rb in (-3.2..3.2f64, -3.2..3.2f64, -3.2..3.2f64),
        dir in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        reach in 0.0..1.3f64,
        sub in 1u32..5,
    ) {
        let ha = Vector3::new(ha.0, ha.1, ha.2);
        let hb = Vector3::new(hb.0, hb.1, hb.2);
        let mk = |h: &Vector3| {
            let (mut v, mut t) = (Vec::new(), Vec::new());
            add_box(&mut v, &mut t, [-h.x, -h.y, -h.z], [h.x, h.y, h.z], &[], sub);
            Arc::new(Mesh::new(v, t).unwrap())
        };
        let d = Vector3::new(dir.0, dir.1, dir.2).try_normalize(1e-6).unwrap_or(Vector3::x());
        // Centres `reach` times the sum of the bounding radii apart: from nested to apart.
        let gap = reach * (ha.norm() + hb.norm());
        let pa = pose(2.0, 2.5, 1.0, ra.0, ra.1, ra.2);
        let pb = pose(2.0 + d.x * gap, 2.5 + d.y * gap, 1.0 + d.z * gap, rb.0, rb.1, rb.2);
        let s = Scene::builder()
            .object(SceneObject::from_mesh("a", mk(&ha), pa).unwrap())
            .object(SceneObject::from_mesh("b", mk(&hb), pb).unwrap())
            .build()
            .unwrap();
        let params = CollisionParams::default();
        let r = collision(&s, &params).unwrap();
        let exact = sat_depth(&ha, &pa, &hb, &pb);
        let tol = params.contact_tolerance_m;
        if let Some(c) = r.contacts.first() {
            prop_assert!(c.depth <= exact + 1e-9, "depth {} above the exact {exact}: {c:?}", c.depth);
        }
        if exact <= tol {
            prop_assert!(!r.col_sc, "exact {exact}: {:?}", r.contacts);
        }
        if exact > std::f64::consts::SQRT_2 * (tol + params.depth_sample_spacing_m) {
            prop_assert!(r.col_sc, "exact {exact}: {:?}", r.contacts);
        }
    }
}

/// A chair-like closed mesh of about 2,000 triangles (seat, back, legs; separate boxes).
fn chair() -> Arc<Mesh> {
    let (mut v, mut t) = (Vec::new(), Vec::new());
    add_box(&mut v, &mut t, [-0.22, -0.22, 0.42], [0.22, 0.22, 0.46], &[], 8);
    add_box(&mut v, &mut t, [-0.22, 0.18, 0.46], [0.22, 0.22, 0.9], &[], 8);
    for (x, y) in [(-0.2, -0.2), (0.18, -0.2), (-0.2, 0.18), (0.18, 0.18)] {
        add_box(&mut v, &mut t, [x, y, 0.0], [x + 0.02, y + 0.02, 0.42], &[], 4);
    }
    Arc::new(Mesh::new(v, t).unwrap())
}

#[test]
fn stacked_copies_cost_no_point_query_per_pair() {
    // 144 and 288 copies of one mesh at one pose: every pair collides (the reference's own
    // check would too), and the narrow phase settles each pair without a point query.
    let m = chair();
    for n in [144usize, 288] {
        let mut b = Scene::builder();
        for k in 0..n {
            b = b.add_mesh(
                format!("c{k}"),
                Category::new("chair"),
                m.clone(),
                at(1.0, 1.0, 0.0, 0.3),
            );
        }
        let (r, work) = collision_with_work(&b.build().unwrap(), &CollisionParams::default()).unwrap();
        assert_eq!(work.candidate_pairs, n * (n - 1) / 2);
        assert_eq!(r.num_colliding_pairs, n * (n - 1) / 2);
        assert_eq!(work.point_queries, 0);
    }
}

#[test]
fn broad_phase_work_grows_as_n_log_n() {
    // Square grids of yawed boxes 1.2 m apart, every eighth pushed into its neighbour:
    // sixteen times the objects cost about log n more box tests per object (log2 4096 /
    // log2 256 = 1.5), where a sweep along one axis would test sqrt(16) = 4 times as many
    // boxes per object and a scan 16 times as many.
    let mut per_object = Vec::new();
    for n in [256usize, 4096] {
        let cols = (n as f64).sqrt() as usize;
        let mut b = Scene::builder();
        for k in 0..n {
            let (mut x, y) = ((k % cols) as f64 * 1.2, (k / cols) as f64 * 1.2);
            if k % 8 == 7 {
                x -= 0.9;
            }
            b = b.add_box(
                format!("o{k}"),
                Category::new("cabinet"),
                Vector3::new(0.4, 0.3, 0.5),
                pose_from_yaw(Point3::new(x, y, 0.5), 0.1 * (k % 7) as f64),
            );
        }
        let (r, work) = collision_with_work(&b.build().unwrap(), &CollisionParams::default()).unwrap();
        // Each pushed box overlaps its western neighbour (except in the first column).
        assert!(r.num_colliding_pairs >= n / 8 - cols, "{}", r.num_colliding_pairs);
        assert_eq!(work.candidate_pairs, r.contacts.len());
        per_object.push(work.broad_phase_box_tests as f64 / n as f64);
    }
    assert!(per_object[1] <= 2.0 * per_object[0], "{per_object:?}");
}

#[test]
fn objects_sharing_poses_cost_a_bounded_number_of_queries_per_pair() {
    // 500 objects at 125 poses: four different meshes (chair, sphere, two boxes) stacked at
    // each point of a 25 x 5 grid whose neighbours overlap. Every pair at one pose collides;
    // the work per pair is bounded by a constant independent of the number of objects.
    let meshes = [
        chair(),
        common::sphere(0.3, 16),
        Arc::new(Mesh::cuboid(&Vector3::new(0.3, 0.2, 0.25)).unwrap()),
        {
            let (mut v, mut t) = (Vec::new(), Vec::new());
            add_box(&mut v, &mut t, [-0.25, -0.3, 0.0], [0.25, 0.3, 0.5], &[], 6);
            Arc::new(Mesh::new(v, t).unwrap())
        },
    ];
    let mut per_pair = Vec::new();
    for poses in [25usize, 125] {
        let mut b = Scene::builder();
        for p in 0..poses {
            let (x, y) = ((p % 25) as f64 * 0.5, (p / 25) as f64 * 0.5);
            for (k, m) in meshes.iter().enumerate() {
                b = b.add_mesh(
                    format!("o{p}_{k}"),
                    Category::new("thing"),
                    m.clone(),
                    at(x, y, 0.3, 0.1),
                );
            }
        }
        let params = CollisionParams::default();
        let (r, work) = collision_with_work(&b.build().unwrap(), &params).unwrap();
        // The six pairs at each pose collide.
        assert!(r.num_colliding_pairs >= 6 * poses);
        assert!(r.contacts.iter().all(|c| !c.undecided));
        // No pair needs more than its budget (both directions, plus balls and nesting probes).
        assert!(work.max_pair_queries <= 2 * params.depth_sample_budget as u64 + 16 + 2 * 64 * 7);
        per_pair.push(work.point_queries as f64 / work.candidate_pairs as f64);
    }
    // Five times the objects: about the same work per pair.
    assert!(per_pair[1] <= 1.5 * per_pair[0] + 1.0, "{per_pair:?}");
}

/// A closed L-shaped prism (the L of width 1 and arm 0.4, `h` high), scaled by `s`,
/// centred on its bounding box; subdivided sides so the hierarchy has depth.
fn l_prism(s: f64, h: f64) -> Arc<Mesh> {
    let outline = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 0.4),
        (0.4, 0.4),
        (0.4, 1.0),
        (0.0, 1.0),
    ];
    let n = outline.len() as u32;
    let at = |x: f64, y: f64, z: f64| Point3::new(s * (x - 0.5), s * (y - 0.5), z - 0.5 * h);
    let mut v: Vec<Point3> = Vec::new();
    for &(x, y) in &outline {
        v.push(at(x, y, 0.0));
    }
    for &(x, y) in &outline {
        v.push(at(x, y, h));
    }
    let mut t = Vec::new();
    // Caps: fans from the corner (0, 0), from which the L is star-shaped.
    for k in 1..n - 1 {
        t.push([0, k + 1, k]);
        t.push([n, n + k, n + k + 1]);
    }
    for k in 0..n {
        let j = (k + 1) % n;
        t.push([k, j, n + j]);
        t.push([k, n + j, n + k]);
    }
    let m = Mesh::new(v, t).unwrap();
    assert!(m.is_closed());
    Arc::new(m)
}

/// Distance from `p` to the nearest triangle of the placed mesh, by brute force over every
/// triangle (no hierarchy).
fn brute_distance(m: &Mesh, pose: &Isometry3, p: &Point3) -> f64 {
    use sceneeval_geom::parry::query::PointQuery;
    use sceneeval_geom::parry::shape::Triangle;
    let l = pose.inverse_transform_point(p);
    let q = sceneeval_geom::parry::math::Vector::new(l.x, l.y, l.z);
    (0..m.triangles().len())
        .map(|k| {
            let [a, b, c] = m.triangle(k);
            let v = |p: Point3| sceneeval_geom::parry::math::Vector::new(p.x, p.y, p.z);
            Triangle::new(v(a), v(b), v(c)).distance_to_local_point(q, false)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Whether some triangle of one placed mesh meets some triangle of the other, by brute force
/// over every pair (parry's GJK on single triangles, not the crate's own triangle test).
fn brute_triangles_meet(a: &Mesh, pa: &Isometry3, b: &Mesh, pb: &Isometry3) -> bool {
    use sceneeval_geom::parry::math::{Pose, Vector as PV};
    use sceneeval_geom::parry::shape::Triangle;
    let tri = |m: &Mesh, p: &Isometry3, k: usize| {
        let v = |q: Point3| {
            let w = p * q;
            PV::new(w.x, w.y, w.z)
        };
        let [x, y, z] = m.triangle(k);
        Triangle::new(v(x), v(y), v(z))
    };
    let id = Pose::IDENTITY;
    (0..a.triangles().len()).any(|i| {
        let ta = tri(a, pa, i);
        (0..b.triangles().len()).any(|j| {
            sceneeval_geom::parry::query::intersection_test(&id, &ta, &id, &tri(b, pb, j))
                .is_ok_and(|r| r.intersecting)
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Non-convex closed meshes at random poses against an independent check: whenever a
    /// vertex of one lies strictly inside the other (exact winding number) farther than the
    /// tolerance from its surface (distance to every triangle), the pair collides; and a pair
    /// reported colliding has a vertex strictly inside the other or crossing triangles (brute
    /// force over every triangle pair), so a pair with neither is never a collision.
    #[test]
    fn a_vertex_deep_inside_the_other_always_collides(
        sa in 0.3..1.2f64, sb in 0.3..1.2f64,
        ra in (-3.2..3.2f64, -3.2..3.2f64, -3.2..3.2f64),
        rb in (-3.2..3.2f64, -3.2..3.2f64, -3.2..3.2f64),
        dir in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        reach in 0.0..1.2f64,
    ) {
        let (a, b) = (l_prism(sa, 0.3), l_prism(sb, 0.25));
        let d = Vector3::new(dir.0, dir.1, dir.2).try_normalize(1e-6).unwrap_or(Vector3::x());
        let gap = reach * 0.5 * (sa + sb);
        let pa = pose(2.0, 2.5, 1.0, ra.0, ra.1, ra.2);
        let pb = pose(2.0 + d.x * gap, 2.5 + d.y * gap, 1.0 + d.z * gap, rb.0, rb.1, rb.2);
        let s = Scene::builder()
            .object(SceneObject::from_mesh("a", a.clone(), pa).unwrap())
            .object(SceneObject::from_mesh("b", b.clone(), pb).unwrap())
            .build()
            .unwrap();
        let params = CollisionParams::default();
        let r = collision(&s, &params).unwrap();
        let deep_vertex = |x: &Mesh, px: &Isometry3, y: &Mesh, py: &Isometry3| {
            x.vertices().iter().any(|v| {
                let w = px * v;
                let local = py.inverse_transform_point(&w);
                y.winding_number(&local) > 0.5 && brute_distance(y, py, &w) > params.contact_tolerance_m + 1e-9
            })
        };
        if deep_vertex(&a, &pa, &b, &pb) || deep_vertex(&b, &pb, &a, &pa) {
            prop_assert!(r.col_sc, "{:?}", r.contacts);
        }
        let inside_vertex = |x: &Mesh, px: &Isometry3, y: &Mesh, py: &Isometry3| {
            x.vertices()
                .iter()
                .any(|v| y.winding_number(&py.inverse_transform_point(&(px * v))) > 0.5)
        };
        if r.col_sc {
            prop_assert!(
                inside_vertex(&a, &pa, &b, &pb)
                    || inside_vertex(&b, &pb, &a, &pa)
                    || brute_triangles_meet(&a, &pa, &b, &pb),
                "colliding without any evidence: {:?}",
                r.contacts
            );
        }
    }
}
