//! Properties every predicate must satisfy, checked with proptest.

// Helpers outside `#[test]` functions build fixed, valid inputs.
#![allow(clippy::unwrap_used)]

use proptest::prelude::*;
use sceneeval_geom::na::Matrix3;
use sceneeval_geom::{Obb, Point2, Point3, Real, Rotation3, Side, Vector3};
use sceneeval_relations::{
    ArchElement, LongShort, ObjectGeom, Relation, RelationKind, RelationParams, arch, batch, pair_distance,
};
use sceneeval_scene::{OpeningKind, Room, RoomBuilder};

/// A box with its centre in a 6 x 6 m area, half extents 5 cm to 1 m, any yaw, and (a third
/// of the time) a tilt about x and y, so that general rotations are exercised too.
fn any_box() -> impl Strategy<Value = Obb> {
    (
        (-3.0..3.0f64, -3.0..3.0f64, 0.0..2.0f64),
        (0.05..1.0f64, 0.05..1.0f64, 0.05..1.0f64),
        -3.2..3.2f64,
        prop_oneof![2 => Just((0.0, 0.0)), 1 => (-0.6..0.6f64, -0.6..0.6f64)],
    )
        .prop_map(|(c, h, yaw, (roll, pitch))| Obb {
            center: Point3::new(c.0, c.1, c.2),
            half_extents: Vector3::new(h.0, h.1, h.2),
            rotation: Rotation3::from_euler_angles(roll, pitch, yaw),
        })
}

/// A box inside a 4 x 5 room (centre at least its plan radius from the walls is not required).
fn room_box() -> impl Strategy<Value = Obb> {
    (
        (-0.5..4.5f64, -0.5..5.5f64, 0.0..3.0f64),
        (0.05..0.8f64, 0.05..0.8f64, 0.05..0.8f64),
        -3.2..3.2f64,
    )
        .prop_map(|(c, h, yaw)| {
            Obb::from_yaw(Point3::new(c.0, c.1, c.2), Vector3::new(h.0, h.1, h.2), yaw).unwrap()
        })
}

const ROOM: [[Real; 2]; 4] = [[0.0, 0.0], [4.0, 0.0], [4.0, 5.0], [0.0, 5.0]];

fn room_moved(yaw: Real, shift: Vector3) -> Room {
    let r = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw);
    let outline = ROOM
        .iter()
        .map(|p| {
            let q = r * Vector3::new(p[0], p[1], 0.0) + shift;
            Point2::new(q.x, q.y)
        })
        .collect();
    RoomBuilder::polygon("r", outline)
        .floor_z(shift.z)
        .wall_height(2.8)
        .wall_thickness(0.1)
        .door(0, [1.0, 1.9], [0.0, 2.1])
        .window(1, [1.5, 3.5], [0.9, 2.0])
        .build()
        .unwrap()
}

fn moved(o: &Obb, yaw: Real, shift: Vector3) -> Obb {
    let r = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw);
    Obb {
        center: Point3::from(r * o.center.coords + shift),
        half_extents: o.half_extents,
        rotation: r * o.rotation,
    }
}

/// `a` reflected through the plane of the anchor's local axis `axis` (the plane through the
/// anchor's centre normal to that axis), keeping the reflected front as its front. A box is
/// symmetric, so the reflection is again a box: with `M` the world reflection and `F` the
/// reflection of the target's own x axis, its rotation is the proper rotation `M R F`, which
/// maps the target's front (local -y) to `M` times the original front.
fn mirrored(a: &Obb, anchor: &Obb, axis: usize) -> Obb {
    let mut d = Matrix3::identity();
    d[(axis, axis)] = -1.0;
    let rb = anchor.rotation.matrix();
    let m = rb * d * rb.transpose();
    let f = Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0));
    Obb {
        center: anchor.center + m * (a.center - anchor.center),
        half_extents: a.half_extents,
        rotation: Rotation3::from_matrix_unchecked(m * a.rotation.matrix() * f),
    }
}

fn pair_relations() -> impl Iterator<Item = Relation> {
    Relation::all().filter(|r| r.kind() == RelationKind::ObjectObject)
}

fn arch_relations() -> impl Iterator<Item = Relation> {
    Relation::all().filter(Relation::is_architectural)
}

/// Surface area over volume of a box: the Lipschitz constant of its volume fractions.
fn area_over_volume(o: &Obb, p: &RelationParams) -> Real {
    let h = o.half_extents.map(|v| v.max(p.min_half_extent_m));
    (h.x * h.y + h.y * h.z + h.z * h.x) / (h.x * h.y * h.z)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Every score of every relation lies in [0, 1].
    #[test]
    fn scores_lie_in_the_unit_interval(a in any_box(), b in any_box(), c in any_box(), d in room_box()) {
        let p = RelationParams::default();
        let rp = RelationParams::reference();
        let (ga, gb) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
        for params in [&p, &rp] {
            for r in pair_relations() {
                let s = batch::score_pair(r, &ga, &gb, params).unwrap();
                prop_assert!((0.0..=1.0).contains(&s), "{} = {}", r, s);
            }
            let targets = [ga, ObjectGeom::from_box(&c), ObjectGeom::from_box(&d)];
            let s = sceneeval_relations::surround(&targets, &gb, params);
            prop_assert!((0.0..=1.0).contains(&s), "surround = {}", s);
            let room = room_moved(0.0, Vector3::zeros());
            for r in arch_relations() {
                let s = arch::score_rooms(r, &ObjectGeom::from_box(&d), std::slice::from_ref(&room), params).unwrap();
                prop_assert!((0.0..=1.0).contains(&s), "{} = {}", r, s);
            }
        }
    }

    /// Moving and turning the whole configuration about z changes no score.
    #[test]
    fn invariant_under_rigid_motion_about_z(
        a in any_box(), b in any_box(), c in any_box(), d in room_box(),
        yaw in -3.2..3.2f64, sx in -10.0..10.0f64, sy in -10.0..10.0f64, sz in -1.0..1.0f64,
    ) {
        let shift = Vector3::new(sx, sy, sz);
        let p = RelationParams::default();
        let (a2, b2, c2, d2) = (moved(&a, yaw, shift), moved(&b, yaw, shift), moved(&c, yaw, shift), moved(&d, yaw, shift));
        for r in pair_relations() {
            let s1 = batch::score_pair(r, &ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b), &p).unwrap();
            let s2 = batch::score_pair(r, &ObjectGeom::from_box(&a2), &ObjectGeom::from_box(&b2), &p).unwrap();
            prop_assert!((s1 - s2).abs() < 1e-7, "{}: {} vs {}", r, s1, s2);
        }
        let t1 = [ObjectGeom::from_box(&a), ObjectGeom::from_box(&c), ObjectGeom::from_box(&d)];
        let t2 = [ObjectGeom::from_box(&a2), ObjectGeom::from_box(&c2), ObjectGeom::from_box(&d2)];
        let s1 = sceneeval_relations::surround(&t1, &ObjectGeom::from_box(&b), &p);
        let s2 = sceneeval_relations::surround(&t2, &ObjectGeom::from_box(&b2), &p);
        prop_assert!((s1 - s2).abs() < 1e-9, "surround: {} vs {}", s1, s2);
        let (r1, r2) = (room_moved(0.0, Vector3::zeros()), room_moved(yaw, shift));
        // corner_of_room jumps where inside_room crosses its 0.5 gate: skip that boundary.
        let inside = arch::inside_room(&ObjectGeom::from_box(&d), &r1, &p);
        let at_gate = (inside - p.corner_min_inside_room).abs() < 1e-9;
        for r in arch_relations().filter(|r| !(at_gate && *r == Relation::CornerOfRoom)) {
            let s1 = arch::score_rooms(r, &ObjectGeom::from_box(&d), std::slice::from_ref(&r1), &p).unwrap();
            let s2 = arch::score_rooms(r, &ObjectGeom::from_box(&d2), std::slice::from_ref(&r2), &p).unwrap();
            prop_assert!((s1 - s2).abs() < 1e-7, "{}: {} vs {}", r, s1, s2);
        }
    }

    /// Mirroring the target through an upright anchor's x = 0 plane swaps left and right;
    /// through its y = 0 plane swaps front and back; the side-less relations do not change.
    /// (The anchor is upright so that the mirror planes are vertical and plan-view measures,
    /// used by `middle_of` and `face_to`, are mirrored too.)
    #[test]
    fn mirror_symmetry(a in any_box(), b in room_box()) {
        let p = RelationParams::default();
        let gb = ObjectGeom::from_box(&b);
        for (axis, (s1, s2)) in [(0, (Side::Left, Side::Right)), (1, (Side::Front, Side::Back))] {
            let m = mirrored(&a, &b, axis);
            let (ga, gm) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&m));
            for (x, y) in [(s1, s2), (s2, s1)] {
                for make in [Relation::SideOf, Relation::SideRegion] {
                    let u = batch::score_pair(make(x), &ga, &gb, &p).unwrap();
                    let v = batch::score_pair(make(y), &gm, &gb, &p).unwrap();
                    prop_assert!((u - v).abs() < 1e-9, "{} vs {}: {} {}", make(x), make(y), u, v);
                }
            }
            for r in [
                Relation::SideOf(Side::Top), Relation::SideOf(Side::Bottom), Relation::InsideOf,
                Relation::OnTop, Relation::MiddleOf, Relation::LongShortSideOf(LongShort::Long),
                Relation::LongShortSideOf(LongShort::Short), Relation::NextTo, Relation::Near,
                Relation::FaceTo,
            ] {
                let u = batch::score_pair(r, &ga, &gb, &p).unwrap();
                let v = batch::score_pair(r, &gm, &gb, &p).unwrap();
                prop_assert!((u - v).abs() < 1e-7, "{}: {} vs {}", r, u, v);
            }
        }
    }

    /// The four distance relations partition the distance axis as the paper defines: a
    /// relation scores exactly 1 if and only if the distance lies in its closed range, and
    /// every distance lies in at least one range.
    #[test]
    fn distance_bands_partition_the_axis(a in any_box(), b in any_box(), d in room_box(), scale in 0.1..3.0f64) {
        let p = RelationParams::default();
        // Spread the target out so that every band gets exercised.
        let a = Obb { center: b.center + (a.center - b.center) * scale, ..a };
        let (ga, gb) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
        let dist = pair_distance(&ga, &gb, &p);
        let ranges = [(0.0, 0.5), (0.5, 1.5), (1.5, 4.0), (4.0, Real::INFINITY)];
        let rels = [Relation::NextTo, Relation::Near, Relation::AcrossFrom, Relation::Far];
        let mut ones = 0;
        for (r, (lo, hi)) in rels.iter().zip(ranges) {
            let s = batch::score_pair(*r, &ga, &gb, &p).unwrap();
            prop_assert_eq!(s == 1.0, dist >= lo && dist <= hi, "{} at {}", r, dist);
            ones += usize::from(s == 1.0);
        }
        prop_assert!(ones >= 1);
        // The same for walls, against the distance to the nearest wall: the best wall's score
        // is 1 exactly when some wall's distance lies in the range.
        let room = room_moved(0.0, Vector3::zeros());
        let gd = ObjectGeom::from_box(&d);
        let dists: Vec<Real> = room.walls().iter().map(|w| arch::wall_distance(&gd, w)).collect();
        let arch_rels = [arch::next_to, arch::near, arch::across_from, arch::far];
        for (f, (lo, hi)) in arch_rels.iter().zip(ranges) {
            let s = f(&gd, &room, ArchElement::Wall, &p);
            prop_assert_eq!(s == 1.0, dists.iter().any(|&x| x >= lo && x <= hi));
        }
    }

    /// Volume fractions are Lipschitz in the poses: moving the target or the anchor by a
    /// vector of length t changes them by at most t times the target's area over volume / 2.
    #[test]
    fn volume_fractions_are_continuous(
        a in any_box(), b in any_box(), d in room_box(),
        dir in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), t in 0.0..2e-3f64, move_anchor in any::<bool>(),
    ) {
        let p = RelationParams::default();
        let step = Vector3::new(dir.0, dir.1, dir.2).try_normalize(1e-9).unwrap_or(Vector3::x()) * t;
        let (a2, b2) = if move_anchor {
            (a, Obb { center: b.center + step, ..b })
        } else {
            (Obb { center: a.center + step, ..a }, b)
        };
        let bound = t * area_over_volume(&a, &p) * (1.0 + 1e-6) + 1e-9;
        let fractions = [
            Relation::InsideOf, Relation::OutsideOf, Relation::OnTop,
            Relation::LongShortSideOf(LongShort::Long), Relation::LongShortSideOf(LongShort::Short),
        ]
        .into_iter()
        .chain(Side::ALL.into_iter().map(Relation::SideOf))
        .chain(Side::ALL.into_iter().map(Relation::SideRegion));
        for r in fractions {
            let s1 = batch::score_pair(r, &ObjectGeom::from_box(&a), &ObjectGeom::from_box(&b), &p).unwrap();
            let s2 = batch::score_pair(r, &ObjectGeom::from_box(&a2), &ObjectGeom::from_box(&b2), &p).unwrap();
            prop_assert!((s1 - s2).abs() <= bound, "{}: {} -> {} (bound {})", r, s1, s2, bound);
        }
        // inside_room: the room is the region.
        let room = room_moved(0.0, Vector3::zeros());
        let d2 = Obb { center: d.center + step, ..d };
        let bound = t * area_over_volume(&d, &p) * (1.0 + 1e-6) + 1e-9;
        let s1 = arch::inside_room(&ObjectGeom::from_box(&d), &room, &p);
        let s2 = arch::inside_room(&ObjectGeom::from_box(&d2), &room, &p);
        prop_assert!((s1 - s2).abs() <= bound, "inside_room: {} -> {}", s1, s2);
    }

    /// The architecture kernels skip walls, wall pieces and openings that cannot beat the best
    /// score found so far; the result equals the brute-force maximum over every element.
    #[test]
    fn pruned_architecture_scores_equal_brute_force(d in room_box(), yaw in -3.2..3.2f64) {
        let p = RelationParams::default();
        let room = room_moved(yaw, Vector3::new(0.3, -0.2, 0.0));
        let d = moved(&d, yaw, Vector3::new(0.3, -0.2, 0.0));
        let g = ObjectGeom::from_box(&d);
        let brute_wall = |w: &sceneeval_scene::Wall| {
            w.solid_boxes()
                .iter()
                .map(|c| sceneeval_relations::object_distance(&g, &ObjectGeom::from_box(c)))
                .fold(Real::INFINITY, Real::min)
        };
        let wall_d: Vec<Real> = room.walls().iter().map(brute_wall).collect();
        for (w, bd) in room.walls().iter().zip(&wall_d) {
            prop_assert!((arch::wall_distance(&g, w) - bd).abs() < 1e-12);
        }
        let bands = [(arch::next_to as fn(&ObjectGeom<'_>, &Room, ArchElement, &RelationParams) -> Real, p.arch_next_to),
            (arch::near, p.arch_near), (arch::across_from, p.arch_across_from), (arch::far, p.arch_far)];
        for (f, band) in bands {
            let walls = wall_d.iter().map(|&x| band.score(x)).fold(0.0, Real::max);
            prop_assert!((f(&g, &room, ArchElement::Wall, &p) - walls).abs() < 1e-12);
            for (el, kind) in [(ArchElement::Door, OpeningKind::Door), (ArchElement::Window, OpeningKind::Window)] {
                let brute = room.openings().iter().filter(|o| o.kind == kind)
                    .map(|o| band.score(sceneeval_relations::object_distance(&g, &ObjectGeom::from_box(&o.obb))))
                    .fold(0.0, Real::max);
                prop_assert!((f(&g, &room, el, &p) - brute).abs() < 1e-12);
            }
        }
        // corner_of_room with the inward normals.
        let mut corner: Real = 0.0;
        if arch::inside_room(&g, &room, &p) >= p.corner_min_inside_room {
            let walls = room.walls();
            for i in 0..walls.len() {
                for j in i + 1..walls.len() {
                    if walls[i].inward_normal_3d().dot(&walls[j].inward_normal_3d()).abs() < p.corner_perpendicular_threshold {
                        corner = corner.max(p.corner_wall.score(wall_d[i]) * p.corner_wall.score(wall_d[j]));
                    }
                }
            }
        }
        prop_assert!((arch::corner_of_room(&g, &room, &p) - corner).abs() < 1e-12);
        // hang_from_ceiling's shortcut for boxes agrees with the general path (the same box
        // as a mesh).
        let mesh = sceneeval_geom::Mesh::cuboid(&d.half_extents).unwrap();
        let pose = d.pose();
        let as_mesh = ObjectGeom::with_mesh(&d, &mesh, &pose);
        let (s1, s2) = (arch::hang_from_ceiling(&g, &room, &p), arch::hang_from_ceiling(&as_mesh, &room, &p));
        prop_assert!((s1 - s2).abs() < 1e-9, "{} vs {}", s1, s2);
    }

    /// Objects given as meshes (here, box meshes) score the distance relations as their boxes
    /// do: the mesh branch and bound, the bounds shortcut and the box-box path agree.
    #[test]
    fn mesh_distances_agree_with_box_distances(a in any_box(), b in any_box(), scale in 0.2..2.0f64) {
        let p = RelationParams::default();
        let a = Obb { center: b.center + (a.center - b.center) * scale, ..a };
        let (ma, mb) = (sceneeval_geom::Mesh::cuboid(&a.half_extents).unwrap(), sceneeval_geom::Mesh::cuboid(&b.half_extents).unwrap());
        let (pa, pb) = (a.pose(), b.pose());
        let boxes = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
        let meshes = (ObjectGeom::with_mesh(&a, &ma, &pa), ObjectGeom::with_mesh(&b, &mb, &pb));
        let mixed = (ObjectGeom::with_mesh(&a, &ma, &pa), ObjectGeom::from_box(&b));
        let d = pair_distance(&boxes.0, &boxes.1, &p);
        prop_assert!((pair_distance(&meshes.0, &meshes.1, &p) - d).abs() < 1e-9);
        prop_assert!((pair_distance(&mixed.0, &mixed.1, &p) - d).abs() < 1e-9);
        for r in [Relation::NextTo, Relation::Near, Relation::AcrossFrom, Relation::Far] {
            let s = batch::score_pair(r, &boxes.0, &boxes.1, &p).unwrap();
            let sm = batch::score_pair(r, &meshes.0, &meshes.1, &p).unwrap();
            let sx = batch::score_pair(r, &mixed.0, &mixed.1, &p).unwrap();
            prop_assert!((s - sm).abs() < 1e-9 && (s - sx).abs() < 1e-9, "{}: {} {} {}", r, s, sm, sx);
        }
    }

    /// Printing a relation and parsing it back gives the same relation.
    #[test]
    fn relation_names_round_trip(i in 0usize..42) {
        let r = Relation::all().nth(i).unwrap();
        prop_assert_eq!(r.to_string().parse::<Relation>().unwrap(), r);
        prop_assert_eq!(Relation::from_parts(r.name(), r.argument()).unwrap(), r);
    }
}

/// Same input, same bits, whichever thread computes it.
#[test]
fn deterministic_across_threads() {
    let a = Obb::from_yaw(Point3::new(0.3, -1.2, 0.4), Vector3::new(0.4, 0.3, 0.4), 0.7).unwrap();
    let b = Obb::new(
        Point3::new(0.1, 0.2, 0.5),
        Vector3::new(0.8, 0.6, 0.5),
        Rotation3::from_euler_angles(0.1, -0.2, 2.1),
    )
    .unwrap();
    let run = move || -> Vec<u64> {
        let p = RelationParams::default();
        let room = room_moved(0.3, Vector3::new(-1.0, -2.0, 0.0));
        let (ga, gb) = (ObjectGeom::from_box(&a), ObjectGeom::from_box(&b));
        let mut bits: Vec<u64> = pair_relations()
            .map(|r| batch::score_pair(r, &ga, &gb, &p).unwrap().to_bits())
            .collect();
        bits.extend(arch_relations().map(|r| {
            arch::score_rooms(r, &gb, std::slice::from_ref(&room), &p)
                .unwrap()
                .to_bits()
        }));
        bits
    };
    let first = run();
    let handles: Vec<_> = (0..4).map(|_| std::thread::spawn(run)).collect();
    for h in handles {
        assert_eq!(h.join().unwrap(), first);
    }
}
