//! SceneAgent / SceneSmith's fixture scene converted: the state copied with model ids and SDF
//! paths rewritten (the `scenesmith.` prefix too), the assets of both rooms kept, fronts from
//! `objectFrontVector`, the `isArchitecture` entry left out, and the same rooms built from the
//! fixture furniture directly evaluate the same.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{
    assert_box, assert_close, convert_into, native, plausibility, read, specs, written_directly, yawed,
};
use sceneeval_convert::Format;
use sceneeval_geom::{Point2, Polygon2, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_scene::{Floor, Opening, OpeningKind, Room, WallSpec};
use serde_json::Value;

#[test]
fn the_state_is_copied_with_its_assets_from_every_room() {
    let (tmp, report) = convert_into(Format::SceneAgent, &native("scene-agent/scenes"), vec![], None);
    let out = tmp.path().join("out");
    let s = &report.scenes[0];
    assert_eq!((s.objects, s.rooms), (3, 2));
    // The architecture entry is listed as left out.
    assert_eq!(s.skipped_objects.len(), 1);
    assert_eq!(
        (
            s.skipped_objects[0].name.as_str(),
            s.skipped_objects[0].pointer.as_str()
        ),
        ("floor_bedroom", "/scene/object/3")
    );
    let files: Vec<String> = s.files.iter().map(|f| f.display().to_string()).collect();
    // The bed's folder comes from the bedroom, the desk's and the lamp's from the office (the
    // fork's copy keeps only the last room's `furniture/sdf`); files no object uses (the
    // rooms' asset registries) are not copied.
    for f in [
        "scene_0/assets/furniture/sdf/bed_1717171717/bed.sdf",
        "scene_0/assets/furniture/sdf/bed_1717171717/bed.gltf",
        "scene_0/assets/furniture/sdf/bed_1717171717/bed.bin",
        "scene_0/assets/furniture/sdf/desk_1717171718/desk.sdf",
        "scene_0/assets/manipuland/sdf/table_lamp_1717171719/table_lamp.gltf",
        "scene_0/assets/original_scene_agent.blend",
        "scene_0/floor_plan.sdf",
    ] {
        assert!(files.iter().any(|x| x == f), "{f} not in {files:?}");
        assert!(out.join(f).is_file(), "{f}");
    }
    assert!(!files.iter().any(|f| f.contains("asset_registry")));

    let doc: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("scene_0.json")).unwrap()).unwrap();
    let objects = doc["scene"]["object"].as_array().unwrap();
    // Both prefixes are rewritten; SDF paths are relative to scene_0/assets (the lamp's was
    // absolute); the architecture entry is copied as it is.
    assert_eq!(objects[0]["modelId"], "scene-agent.scene_0__bed_0");
    assert_eq!(objects[1]["modelId"], "scene-agent.scene_0__desk_0");
    assert_eq!(objects[2]["modelId"], "scene-agent.scene_0__table_lamp_0");
    assert_eq!(objects[0]["sdfPath"], "furniture/sdf/bed_1717171717/bed.sdf");
    assert_eq!(
        objects[2]["sdfPath"],
        "manipuland/sdf/table_lamp_1717171719/table_lamp.sdf"
    );
    assert_eq!(objects[3]["modelId"], "scenesmith.floor_bedroom");
    assert_eq!(doc["scene"]["objectFrontVector"], serde_json::json!([0, 1, 0]));

    let scene = read(&out.join("scene_0.json"), &specs(&[("scene-agent", out.clone())]));
    let o = scene.objects();
    assert_eq!(o.len(), 3, "the isArchitecture entry is left out");
    // The bed: Rz(180) in the file, turned back by its declared front (+y): the identity,
    // front -y; its mesh's bottom at the origin, so its centre is 0.55 m up.
    assert_box(&o[0], [2.0, 3.95, 0.55], [1.6, 2.1, 1.1], [0.0, -1.0, 0.0]);
    // The desk: Rz(90) * Rz(180)^-1 = Rz(-90): front (-1, 0, 0), facing the office.
    assert_box(&o[1], [7.65, 2.5, 0.375], [1.4, 0.7, 0.75], [-1.0, 0.0, 0.0]);
    // The lamp on the desk (0.75 m): centre 0.75 + 0.225 up.
    assert_box(&o[2], [7.65, 3.0, 0.975], [0.24, 0.24, 0.45], [-1.0, 0.0, 0.0]);
    assert_eq!(o[2].category(), Some("table lamp"));
    // The door is in both rooms' walls.
    assert_eq!(scene.rooms()[0].walls()[1].openings()[0].along, [2.0, 3.0]);
    assert_eq!(scene.rooms()[1].walls()[3].openings()[0].along, [2.0, 3.0]);
}

#[test]
fn the_converted_house_evaluates_as_the_house_written_directly() {
    let (tmp, _) = convert_into(Format::SceneAgent, &native("scene-agent/scenes"), vec![], None);
    let out = tmp.path().join("out");
    let converted = read(&out.join("scene_0.json"), &specs(&[("scene-agent", out.clone())]));
    let fixtures = sceneeval_fixtures::default_output_dir().join("assets");
    let library = AssetLibrary::from_specs(&[format!("fixture={}", fixtures.display())]).unwrap();
    // (wall number, start, end, has the door)
    type WallDef = (usize, (f64, f64), (f64, f64), bool);
    let room = |id: &str, x0: f64, walls: [WallDef; 4]| {
        let c = vec![
            Point2::new(x0, 0.0),
            Point2::new(x0 + 4.0, 0.0),
            Point2::new(x0 + 4.0, 5.0),
            Point2::new(x0, 5.0),
        ];
        let specs = walls
            .iter()
            .map(|&(k, a, b, door)| WallSpec {
                openings: if door {
                    vec![Opening::new(
                        "door_bedroom_office",
                        OpeningKind::Door,
                        [2.0, 3.0],
                        [0.0, 2.1],
                    )]
                } else {
                    vec![]
                },
                ..WallSpec::new(
                    format!("wall|{id}|{k}"),
                    Point2::new(a.0, a.1),
                    Point2::new(b.0, b.1),
                    0.0,
                    2.5,
                    0.05,
                )
            })
            .collect();
        let floor = Floor {
            id: format!("floor|{id}"),
            polygon: Polygon2::new(c).unwrap(),
            z: 0.0,
        };
        Room::new(id, floor, specs, None).unwrap()
    };
    let rooms = vec![
        room(
            "bedroom",
            0.0,
            [
                (1, (0.0, 0.0), (4.0, 0.0), false),
                (2, (4.0, 0.0), (4.0, 5.0), true),
                (3, (4.0, 5.0), (0.0, 5.0), false),
                (4, (0.0, 5.0), (0.0, 0.0), false),
            ],
        ),
        room(
            "office",
            4.0,
            [
                (6, (4.0, 0.0), (8.0, 0.0), false),
                (7, (8.0, 0.0), (8.0, 5.0), false),
                (8, (8.0, 5.0), (4.0, 5.0), false),
                (9, (4.0, 5.0), (4.0, 0.0), true),
            ],
        ),
    ];
    let one = Vector3::repeat(1.0);
    let placements = [
        ("fixture.bed".to_owned(), yawed(0.0, [2.0, 3.95, 0.0]), one),
        ("fixture.desk".to_owned(), yawed(-90.0, [7.65, 2.5, 0.0]), one),
        (
            "fixture.table_lamp".to_owned(),
            yawed(-90.0, [7.65, 3.0, 0.75]),
            one,
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    let direct = written_directly(dir.path(), &library, rooms, &placements);
    for (a, b) in converted.objects().iter().zip(direct.objects()) {
        assert!((a.obb().center - b.obb().center).norm() < 1e-6, "{}", a.id());
        assert!(
            a.pose().rotation.angle_to(&b.pose().rotation) < 1e-9,
            "{}",
            a.id()
        );
    }
    assert_close(&plausibility(&converted), &plausibility(&direct), 1e-6);
}
