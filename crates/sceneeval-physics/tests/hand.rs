//! Hand-computed cases: free fall, tipping, overhang, wall and ceiling mounting, resting,
//! floating, stacking, interpenetration and sinking. Units: metres, seconds, radians; g = 9.81.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{cuboid, evaluate, evaluate_with, final_position, room, tilted_cuboid};
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Vector3};
use sceneeval_physics::{StabilityParams, WeldMode, WeldReason};
use sceneeval_scene::{SceneObject, SupportType};

const G: f64 = 9.81;

#[test]
fn a_dropped_box_lands_at_the_free_fall_time() {
    // A 0.5 m cube whose bottom is 1 m above the floor lands after sqrt(2 h / g) =
    // sqrt(2 / 9.81) = 0.4515 s. Before that it has fallen 1/2 g t^2, up to the first-order
    // error of the integrator, g t dt; from then on it rests 1 m lower.
    let scene = room(vec![cuboid("box", [0.25; 3], [1.0, 2.5, 1.25])]);
    let fallen = |duration_s: f64| {
        let params = StabilityParams {
            weld: WeldMode::None,
            duration_s,
            ..StabilityParams::default()
        };
        evaluate_with(&scene, params, &[]).objects[0].displacement_m
    };
    for t in [0.2, 0.3, 0.44] {
        // E.g. t = 0.3: 1/2 9.81 0.09 = 0.441 m, within 9.81 x 0.3 x 0.001 = 2.9 mm.
        let expected = 0.5 * G * t * t;
        let d = fallen(t);
        assert!(
            (d - expected).abs() <= G * t * 0.001,
            "t = {t}: {d} vs {expected}"
        );
    }
    // At 10 ms resolution the box first rests on the floor at 0.46 s: at 0.45 s it is still
    // 1 - 1/2 9.81 0.45^2 = 6.7 mm up (less the integrator's 2.2 mm lead).
    assert!(fallen(0.45) < 0.999, "{}", fallen(0.45));
    let landed = fallen(0.46);
    assert!((landed - 1.0).abs() < 2e-3, "{landed}");
}

/// A 0.1 x 0.1 x 1 m post standing on a ramp tilted by `angle` (a 2 x 2 x 0.4 m slab half
/// sunk into the floor, welded for that interpenetration).
fn post_on_ramp(angle: f64) -> sceneeval_physics::StabilityReport {
    let tilt = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), angle);
    let ramp_centre = Vector3::new(2.0, 2.5, 0.0);
    // The post's centre: 0.2 (ramp half thickness) + 0.5 (post half height) along the ramp's
    // normal from the ramp's centre, so its bottom face lies on the ramp's top face.
    let post_centre = ramp_centre + tilt * Vector3::new(0.0, 0.0, 0.7);
    let ramp = SceneObject::new_box(
        "ramp",
        Vector3::new(1.0, 1.0, 0.2),
        Isometry3::from_parts(Translation3::from(ramp_centre), tilt),
    )
    .unwrap();
    let post = SceneObject::new_box(
        "post",
        Vector3::new(0.05, 0.05, 0.5),
        Isometry3::from_parts(Translation3::from(post_centre), tilt),
    )
    .unwrap();
    evaluate(&room(vec![ramp, post]), WeldMode::Penetration, &[])
}

#[test]
fn a_post_tilted_past_its_tipping_angle_topples_and_one_short_of_it_stays() {
    // The post tips when its centre of mass passes the downhill edge of its base:
    // tan(angle) > half width / half height = 0.05 / 0.5, angle > 5.71 degrees. It does not
    // slide first: friction 0.5 > tan(6 degrees) = 0.105.
    // Measured at the default 1 ms step: 5.70 degrees stays, 5.75 topples.
    let short = post_on_ramp(5.5_f64.to_radians());
    assert_eq!(short.objects[0].weld_reason, Some(WeldReason::Penetration));
    let post = &short.objects[1];
    assert!(!post.welded && post.stable, "{post:?}");
    assert!(post.displacement_m < 2e-3 && post.rotation_rad < 0.01, "{post:?}");

    let past = post_on_ramp(6.0_f64.to_radians());
    let post = &past.objects[1];
    assert!(!post.stable, "{post:?}");
    // It falls over: far more than the 0.1 rad limit.
    assert!(post.rotation_rad > 1.0, "{post:?}");
    assert_eq!(past.frac_unstable, Some(1.0));
}

/// A 1 m plank (0.04 m thick) on a 0.6 x 0.6 x 0.8 m block, `share` of its length beyond the
/// block's edge at x = 2.3.
fn overhang(share: f64) -> sceneeval_physics::StabilityReport {
    let block = cuboid("block", [0.3, 0.3, 0.4], [2.0, 2.5, 0.4]);
    // The plank spans [2.3 - (1 - share), 2.3 + share]: its centre is at 2.3 + share - 0.5.
    let plank = cuboid("plank", [0.5, 0.1, 0.02], [2.3 + share - 0.5, 2.5, 0.82]);
    evaluate(&room(vec![block, plank]), WeldMode::None, &[])
}

#[test]
fn a_plank_overhanging_by_more_than_half_falls_and_by_less_stays() {
    // Overhanging 0.6 of its length, its centre of mass is 0.1 m past the edge: it tips off.
    let falls = overhang(0.6);
    assert!(falls.objects[0].stable, "the block stays: {:?}", falls.objects[0]);
    let plank = &falls.objects[1];
    assert!(!plank.stable && plank.displacement_m > 0.3, "{plank:?}");
    // Overhanging 0.4, its centre is 0.1 m inside: it stays.
    let stays = overhang(0.4);
    assert!(stays.objects.iter().all(|o| o.stable), "{stays:?}");
    assert!(stays.objects[1].displacement_m < 2e-3);
}

#[test]
fn a_shelf_on_a_wall_stays_only_when_welded() {
    // A 0.6 x 0.2 x 0.3 m shelf whose back touches the far wall (y = 5), 1.35 m above the
    // floor, and a lamp hanging from the 2.8 m ceiling.
    let scene = room(vec![
        cuboid("shelf", [0.3, 0.1, 0.15], [2.0, 4.9, 1.5]),
        cuboid("lamp", [0.2, 0.2, 0.1], [2.0, 2.5, 2.7]),
    ]);
    let support = [Some(SupportType::Wall), Some(SupportType::Ceiling)];
    let welded = evaluate(&scene, WeldMode::Architectural, &support);
    assert_eq!(welded.objects[0].weld_reason, Some(WeldReason::Wall));
    assert_eq!(welded.objects[1].weld_reason, Some(WeldReason::Ceiling));
    assert!(
        welded
            .objects
            .iter()
            .all(|o| o.stable && o.welded && o.displacement_m == 0.0)
    );
    assert_eq!(welded.num_free, 0);
    assert_eq!(welded.frac_unstable, None);
    assert!(
        welded
            .frac_unstable_missing
            .as_deref()
            .unwrap()
            .contains("welded")
    );
    assert_eq!(welded.steps, 0);

    // Free, both fall to the floor: the shelf's centre from 1.5 to 0.15 m (1.35 m), the
    // lamp's from 2.7 to 0.1 m (2.6 m).
    let free = evaluate(&scene, WeldMode::None, &support);
    for (o, drop) in free.objects.iter().zip([1.35, 2.6]) {
        assert!(!o.stable && o.weld_reason.is_none(), "{o:?}");
        assert!((o.displacement_m - drop).abs() < 0.02, "{o:?}");
    }
    assert_eq!(free.frac_unstable, Some(1.0));
    // The penetration mode does not weld them (they interpenetrate nothing).
    let penetration = evaluate(&scene, WeldMode::Penetration, &support);
    assert!(penetration.objects.iter().all(|o| !o.welded && !o.stable));
}

#[test]
fn resting_stacked_and_slightly_floating_objects_are_stable() {
    // A cabinet on the floor; three 0.2 m cubes stacked; a box 3 mm above the floor.
    let scene = room(vec![
        cuboid("cabinet", [0.4, 0.3, 0.35], [1.0, 1.0, 0.35]),
        cuboid("a", [0.1; 3], [3.0, 1.0, 0.1]),
        cuboid("b", [0.1; 3], [3.0, 1.0, 0.3]),
        cuboid("c", [0.1; 3], [3.0, 1.0, 0.5]),
        cuboid("floating", [0.2; 3], [2.0, 3.5, 0.203]),
    ]);
    let r = evaluate(&scene, WeldMode::Architectural, &[]);
    assert!(r.objects.iter().all(|o| o.stable && !o.welded), "{r:?}");
    assert_eq!(r.frac_unstable, Some(0.0));
    // Resting and stacked objects barely move (contacts settle by well under a millimetre
    // per layer).
    for o in &r.objects[..4] {
        assert!(o.displacement_m < 2e-3 && o.rotation_rad < 1e-3, "{o:?}");
    }
    // The floating box falls its 3 mm: within the 1 cm limit, so stable (the support metric,
    // not this one, reports the gap).
    let f = &r.objects[4];
    assert!((f.displacement_m - 0.003).abs() < 1e-3, "{f:?}");
    assert!((final_position(&r, 4).z - 0.2).abs() < 1e-3);
    // Everything came to rest and fell asleep long before 5 s.
    assert!(r.simulated_s < 1.5, "{}", r.simulated_s);
}

#[test]
fn an_object_floating_more_than_the_limit_is_unstable() {
    // 5 cm above the floor: it falls 5 cm.
    let r = evaluate(
        &room(vec![cuboid("box", [0.2; 3], [2.0, 2.5, 0.25])]),
        WeldMode::Architectural,
        &[],
    );
    let o = &r.objects[0];
    assert!(!o.stable && (o.displacement_m - 0.05).abs() < 1e-3, "{o:?}");
}

#[test]
fn interpenetrating_objects_are_pushed_apart_unless_welded() {
    // Two 0.5 m cubes overlapping by 0.05 m along x.
    let scene = room(vec![
        cuboid("a", [0.25; 3], [1.0, 2.5, 0.25]),
        cuboid("b", [0.25; 3], [1.45, 2.5, 0.25]),
    ]);
    let free = evaluate(&scene, WeldMode::Architectural, &[]);
    // Both report the 5 cm overlap (as evidence, even unwelded) and end apart.
    for (o, other) in free.objects.iter().zip(["b", "a"]) {
        let i = o.interpenetration.as_ref().unwrap();
        assert_eq!(i.with, other);
        assert!((i.depth_m - 0.05).abs() < 1e-6, "{i:?}");
        assert!(!o.welded);
    }
    let gap = final_position(&free, 1).x - final_position(&free, 0).x;
    assert!(gap >= 0.5 - 2e-3, "{gap}");
    assert!(free.num_unstable >= 1, "{free:?}");

    let welded = evaluate(&scene, WeldMode::Penetration, &[]);
    assert!(
        welded
            .objects
            .iter()
            .all(|o| o.welded && o.stable && o.weld_reason == Some(WeldReason::Penetration))
    );
    assert_eq!(welded.frac_unstable, None);
    // Combined: the same, and architectural reasons come first.
    let support = [Some(SupportType::Wall), None];
    let combined = evaluate(&scene, WeldMode::Combined, &support);
    assert_eq!(combined.objects[0].weld_reason, Some(WeldReason::Wall));
    assert_eq!(combined.objects[1].weld_reason, Some(WeldReason::Penetration));
}

#[test]
fn a_sunk_object_is_pushed_up_or_welded() {
    // A 0.5 m cube sunk 0.2 m into the floor (centre at 0.05 instead of 0.25).
    let scene = room(vec![cuboid("sunk", [0.25; 3], [2.0, 2.5, 0.05])]);
    let floor = scene.rooms()[0].floor_id().to_owned();
    let free = evaluate(&scene, WeldMode::Architectural, &[]);
    let o = &free.objects[0];
    let i = o.interpenetration.as_ref().unwrap();
    assert_eq!(i.with, floor);
    assert!((i.depth_m - 0.2).abs() < 1e-6, "{i:?}");
    // The floor pushes it straight up onto its surface.
    assert!(!o.stable && (o.displacement_m - 0.2).abs() < 5e-3, "{o:?}");
    assert!(o.rotation_rad < 1e-3);
    assert!((final_position(&free, 0).z - 0.25).abs() < 5e-3);

    let welded = evaluate(&scene, WeldMode::Penetration, &[]);
    assert_eq!(welded.objects[0].weld_reason, Some(WeldReason::Penetration));
    assert!(welded.objects[0].stable);
}

#[test]
fn a_tilted_box_resting_on_its_edge_falls_flat() {
    // A 0.2 x 0.2 x 1 m post turned 30 degrees about x, its lowest edge on the floor: its
    // centre of mass is far outside that edge, so it falls.
    let a = 30_f64.to_radians();
    // Lowest point of the turned post: 0.1 sin(a) + 0.5 cos(a) below its centre.
    let z = 0.1 * a.sin() + 0.5 * a.cos();
    let r = evaluate(
        &room(vec![tilted_cuboid("post", [0.1, 0.1, 0.5], [2.0, 2.5, z], a)]),
        WeldMode::None,
        &[],
    );
    assert!(!r.objects[0].stable && r.objects[0].rotation_rad > 0.5, "{r:?}");
}
