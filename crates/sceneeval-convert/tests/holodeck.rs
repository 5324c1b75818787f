//! Holodeck's two fixture houses converted: boxes, fronts, walls and openings against values
//! computed by hand from `sceneeval_fixtures::native`, and the same bedroom built directly as
//! a scene evaluates to the same plausibility numbers.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::f64::consts::FRAC_PI_2;

use common::{assert_box, assert_close, convert_into, native, plausibility, read, specs};
use sceneeval_convert::Format;
use sceneeval_fixtures::native::uid;
use sceneeval_geom::na::{Translation3, UnitQuaternion};
use sceneeval_geom::{Isometry3, Point2, Vector3};
use sceneeval_io::scene_state::derived_object_id;
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state, write_scene_state};
use sceneeval_scene::{Floor, Opening, OpeningKind, Room, Scene, WallSpec};

fn assets() -> Vec<sceneeval_io::assets::AssetSpec> {
    specs(&[("objaverse", native("holodeck/objathor"))])
}

#[test]
fn the_bedroom_converts_to_hand_computed_boxes_and_openings() {
    let (tmp, report) = convert_into(Format::Holodeck, &native("holodeck/scenes"), assets(), None);
    // Scenes are keyed by their folders' order: bedroom-2024-05-01 (0), two_rooms (1).
    assert_eq!(
        report.scenes.iter().map(|s| (s.key, s.id)).collect::<Vec<_>>(),
        [(0, 0), (1, 1)]
    );
    let s0 = &report.scenes[0];
    assert_eq!((s0.objects, s0.rooms), (6, 1));
    // The AI2-THOR chair is skipped with its reason.
    assert_eq!(s0.skipped_objects.len(), 1);
    assert_eq!(s0.skipped_objects[0].pointer, "/objects/6");
    assert!(s0.skipped_objects[0].reason.contains("AI2-THOR"));

    let scene = read(&tmp.path().join("out/scene_0.json"), &assets());
    let o = scene.objects();
    // Unity (x, y, z) -> (x, z, y); a Unity yaw y gives the object the pose Rz(180 - y).
    // Bed, yaw 180 -> Rz(0): front -y; a floor object, so its lowest point is on the floor
    // and its centre half its 1.1 m height up.
    assert_box(&o[0], [2.0, 3.95, 0.55], [1.6, 2.1, 1.1], [0.0, -1.0, 0.0]);
    assert_box(&o[1], [3.3, 4.7, 0.275], [0.45, 0.42, 0.55], [0.0, -1.0, 0.0]);
    // The storage box, Euler (90, 90, 0): pose Rz(180 - 90) * Rx(90) * Ry(0) = Rz(90) Rx(90),
    // which sends local x -> world y, local y -> world z, local z -> world x: it lies on its
    // back, its front (local -y) facing down, 0.25 m (its depth) tall, so its centre is
    // 0.125 m up.
    assert_box(&o[2], [1.0, 1.0, 0.125], [0.3, 0.25, 0.2], [0.0, 0.0, -1.0]);
    let aabb = o[2].world_aabb();
    assert!(
        (aabb.max - aabb.min - Vector3::new(0.2, 0.3, 0.25)).norm() < 1e-6,
        "{aabb:?}"
    );
    // The painting (a wall object): box centre at the position, yaw 90 -> Rz(90): front +x.
    assert_box(&o[3], [0.02, 2.5, 1.5], [0.8, 0.04, 0.6], [1.0, 0.0, 0.0]);
    // The lamp (a small object), yaw 195 -> Rz(-15): front (-sin 15, -cos 15, 0).
    let (s, c) = 15f64.to_radians().sin_cos();
    assert_box(&o[4], [3.3, 4.7, 0.775], [0.24, 0.24, 0.45], [-s, -c, 0.0]);
    // The ceiling lamp, yaw 0 -> Rz(180): front +y; its top at 2.335 + 0.365 = 2.7.
    assert_box(&o[5], [2.0, 2.5, 2.335], [0.5, 0.5, 0.73], [0.0, 1.0, 0.0]);
    assert!((o[5].world_aabb().max.z - 2.7).abs() < 1e-6);
    // Ids are the reference's, categories come from the Objathor annotations.
    assert_eq!(
        o[0].id().as_str(),
        derived_object_id(0, Some(&format!("objaverse.{}", uid("bed"))))
    );
    assert_eq!(o[0].category(), Some("bed"));

    let room = &scene.rooms()[0];
    assert_eq!(
        (room.id().as_str(), room.kind(), room.floor_id()),
        ("bedroom", Some("Bedroom"), "floor|bedroom")
    );
    assert!((room.floor().area() - 20.0).abs() < 1e-12);
    // Four walls: the exterior twins are the same walls and are not written.
    let ids: Vec<&str> = room.walls().iter().map(|w| w.id()).collect();
    assert_eq!(
        ids,
        [
            "wall|bedroom|south|0",
            "wall|bedroom|east|0",
            "wall|bedroom|north|0",
            "wall|bedroom|west|0"
        ]
    );
    for w in room.walls() {
        assert_eq!((w.height(), w.thickness()), (2.7, 0.025));
    }
    // The door was given on the exterior face, x from its first point (4, 0): x 1.0 and 1.9
    // are world x 3.0 and 2.1, i.e. 2.1 to 3.0 along the interior wall from (0, 0).
    let door = &room.walls()[0].openings()[0];
    assert_eq!(door.kind, OpeningKind::Door);
    assert!(
        (door.along[0] - 2.1).abs() < 1e-12 && (door.along[1] - 3.0).abs() < 1e-12,
        "{:?}",
        door.along
    );
    assert_eq!(door.height, [0.0, 2.1]);
    // The window was given on the interior face: as it is.
    let window = &room.walls()[1].openings()[0];
    assert_eq!(
        (window.kind, window.along, window.height),
        (OpeningKind::Window, [1.5, 2.5], [0.9, 2.0])
    );
    assert!(room.walls()[2].openings().is_empty() && room.walls()[3].openings().is_empty());
}

#[test]
fn a_door_between_two_rooms_is_in_both_walls() {
    let (tmp, _) = convert_into(Format::Holodeck, &native("holodeck/scenes"), assets(), None);
    let scene = read(&tmp.path().join("out/scene_1.json"), &assets());
    let (kitchen, living) = (&scene.rooms()[0], &scene.rooms()[1]);
    assert_eq!(
        (kitchen.id().as_str(), living.id().as_str()),
        ("kitchen", "living room")
    );
    // On the kitchen's east wall ((3, 0) -> (3, 4)) as given: 1 to 2 m along.
    assert_eq!(kitchen.walls()[1].openings()[0].along, [1.0, 2.0]);
    // The living room's west wall runs (3, 4) -> (3, 0): world y 1..2 is 4 - y = 2..3 along,
    // the fork's mirror (width - x).
    assert_eq!(living.walls()[3].openings()[0].along, [2.0, 3.0]);
    let o = scene.objects();
    assert_box(&o[0], [1.5, 2.0, 0.38], [1.6, 0.9, 0.76], [1.0, 0.0, 0.0]);
    assert_box(&o[1], [5.0, 3.5, 0.425], [2.0, 0.9, 0.85], [0.0, -1.0, 0.0]);
}

/// The bedroom built directly (objects placed by their bottom centres, as in the fixture
/// scenes), written as sceneState and read back.
fn bedroom_written_natively(dir: &std::path::Path, library: &AssetLibrary) -> Scene {
    let rot = |yaw_deg: f64| UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw_deg.to_radians());
    let at =
        |x: f64, y: f64, z: f64, r: UnitQuaternion<f64>| Isometry3::from_parts(Translation3::new(x, y, z), r);
    // The tipped-over box: Rz(90) Rx(90); its bottom-centre origin is 0.1 m (half its 0.2 m
    // height, along local z = world x) from its centre (1, 1, 0.125).
    let tipped = rot(90.0) * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), FRAC_PI_2);
    let placements = [
        ("bed", at(2.0, 3.95, 0.0, rot(0.0))),
        ("nightstand", at(3.3, 4.7, 0.0, rot(0.0))),
        ("storage_box", at(0.9, 1.0, 0.125, tipped)),
        // Centre 1.5 m up, 0.3 m above its bottom.
        ("painting", at(0.02, 2.5, 1.2, rot(90.0))),
        ("table_lamp", at(3.3, 4.7, 0.55, rot(-15.0))),
        // Centre 2.335 m up, 0.365 m above its bottom.
        ("ceiling_lamp", at(2.0, 2.5, 1.97, rot(180.0))),
    ];
    let objects = placements
        .iter()
        .enumerate()
        .map(|(i, (asset, pose))| {
            let model_id = format!("objaverse.{}", uid(asset));
            library
                .object(
                    derived_object_id(i as i64, Some(&model_id)),
                    &model_id,
                    *pose,
                    Vector3::repeat(1.0),
                )
                .unwrap()
                .with_index(i as i64)
        })
        .collect();
    let wall = |id: &str, a: (f64, f64), b: (f64, f64), openings: Vec<Opening>| WallSpec {
        openings,
        ..WallSpec::new(id, Point2::new(a.0, a.1), Point2::new(b.0, b.1), 0.0, 2.7, 0.025)
    };
    let walls = vec![
        wall(
            "wall|bedroom|south|0",
            (0.0, 0.0),
            (4.0, 0.0),
            vec![Opening::new(
                "door|0|exterior|bedroom",
                OpeningKind::Door,
                [2.1, 3.0],
                [0.0, 2.1],
            )],
        ),
        wall(
            "wall|bedroom|east|0",
            (4.0, 0.0),
            (4.0, 5.0),
            vec![Opening::new(
                "window|wall|bedroom|east|0|0",
                OpeningKind::Window,
                [1.5, 2.5],
                [0.9, 2.0],
            )],
        ),
        wall("wall|bedroom|north|0", (4.0, 5.0), (0.0, 5.0), vec![]),
        wall("wall|bedroom|west|0", (0.0, 5.0), (0.0, 0.0), vec![]),
    ];
    let floor = Floor {
        id: "floor|bedroom".into(),
        polygon: sceneeval_geom::Polygon2::new(vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.0, 5.0),
            Point2::new(4.0, 5.0),
            Point2::new(4.0, 0.0),
        ])
        .unwrap(),
        z: 0.0,
    };
    let room = Room::new("bedroom", floor, walls, None)
        .unwrap()
        .with_kind("Bedroom");
    let scene = Scene::new(None, objects, vec![room]).unwrap();
    let path = dir.join("scene_0.json");
    write_scene_state(&scene, &path).unwrap();
    read_scene_state(&path, library, &ReadOptions::default()).unwrap()
}

#[test]
fn the_converted_bedroom_evaluates_as_the_bedroom_written_directly() {
    let (tmp, _) = convert_into(Format::Holodeck, &native("holodeck/scenes"), assets(), None);
    let converted = read(&tmp.path().join("out/scene_0.json"), &assets());
    let library =
        AssetLibrary::from_specs(&[format!("objaverse={}", native("holodeck/objathor").display())]).unwrap();
    let direct_dir = tempfile::tempdir().unwrap();
    let direct = bedroom_written_natively(direct_dir.path(), &library);
    for (a, b) in converted.objects().iter().zip(direct.objects()) {
        assert_eq!(a.id(), b.id());
        // To the f32 rounding of the assets' vertices (the direct route assumes the nominal
        // bounds).
        assert!(
            (a.obb().center - b.obb().center).norm() < 1e-6,
            "{} {} {}",
            a.id(),
            a.obb().center,
            b.obb().center
        );
        assert!(
            a.pose().rotation.angle_to(&b.pose().rotation) < 1e-9,
            "{}",
            a.id()
        );
    }
    let (a, b) = (&converted.rooms()[0], &direct.rooms()[0]);
    assert_eq!(
        (a.id(), a.floor(), a.walls().len()),
        (b.id(), b.floor(), b.walls().len())
    );
    for (p, q) in a.openings().iter().zip(b.openings()) {
        assert!((p.obb.center - q.obb.center).norm() < 1e-12);
    }
    assert_close(&plausibility(&converted), &plausibility(&direct), 1e-6);
}
