//! IDesign's fixture scene converted: GLBs copied and named `idesign.scene_<ID>__<obj>`, meshes
//! recentred and scaled to the scene graph's sizes, fronts from `objectFrontVector` [0, 1, 0],
//! and the same room built from the fixture furniture directly evaluates the same.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{
    assert_box, assert_close, convert_into, native, plausibility, read, rectangle_room, specs,
    written_directly, yawed,
};
use sceneeval_convert::Format;
use sceneeval_geom::Vector3;
use sceneeval_io::AssetLibrary;
use serde_json::Value;

#[test]
fn objects_are_recentred_scaled_and_turned_to_their_declared_front() {
    let (tmp, report) = convert_into(
        Format::IDesign,
        &native("idesign/scenes"),
        vec![],
        Some(r#"{"0": 106}"#),
    );
    let out = tmp.path().join("out");
    assert_eq!((report.scenes[0].key, report.scenes[0].id), (0, 106));
    let files: Vec<String> = report.scenes[0]
        .files
        .iter()
        .map(|f| f.display().to_string())
        .collect();
    assert_eq!(
        files,
        [
            "scene_106.json",
            "scene_106/assets/bed_1.glb",
            "scene_106/assets/nightstand_1.glb",
            "scene_106/assets/wardrobe_1.glb",
            "scene_106/assets/original_idesign.blend",
        ]
    );
    // The GLB is copied as it is (materials and all); the transform does the recentring.
    assert_eq!(
        std::fs::read(out.join("scene_106/assets/bed_1.glb")).unwrap(),
        std::fs::read(native("idesign/scenes/scene_000/Assets/bed_1.glb")).unwrap()
    );
    let text = std::fs::read_to_string(out.join("scene_106.json")).unwrap();
    let doc: Value = serde_json::from_str(&text).unwrap();
    // Every object faces +y in its file: written once for the scene, as the fork writes it.
    assert_eq!(
        doc["scene"]["objectFrontVector"],
        serde_json::json!([0.0, 1.0, 0.0])
    );
    let bed = &doc["scene"]["object"][0];
    assert_eq!(bed["modelId"], "idesign.scene_106__bed_1");
    assert_eq!(bed["description"], "Modern Wood bed");
    // The bed's mesh (z-up) is the catalog bed turned by pi, halved and moved by
    // (0.3, 0.1, -0.2) in the file (y up): its bounds x [-0.1, 0.7], y(up) [0.1, 0.65],
    // z [-0.725, 0.325], so its box centre in the z-up frame is c = (0.3, 0.2, 0.375) and its
    // size (0.8, 1.05, 0.55): scale 2 to 1.6 x 2.1 x 1.1. z_angle 0 + 180: R = Rz(180). The
    // translation puts the centre at (2, 3.95, 0.55): t = p - R * 2c
    // = (2, 3.95, 0.55) - (-0.6, -0.4, 0.75) = (2.6, 4.35, -0.2).
    let data: Vec<f64> = serde_json::from_value(bed["transform"]["data"].clone()).unwrap();
    for (got, want) in data[12..15].iter().zip([2.6, 4.35, -0.2]) {
        assert!((got - want).abs() < 1e-6, "{data:?}");
    }
    assert!(
        (data[0] + 2.0).abs() < 1e-6 && (data[5] + 2.0).abs() < 1e-6 && (data[10] - 2.0).abs() < 1e-6,
        "{data:?}"
    );

    let scene = read(&out.join("scene_106.json"), &specs(&[("idesign", out.clone())]));
    let o = scene.objects();
    // Rz(180) turned back by the declared front (+y): the model's pose is the identity.
    assert_box(&o[0], [2.0, 3.95, 0.55], [1.6, 2.1, 1.1], [0.0, -1.0, 0.0]);
    // z_angle 90: Rz(270) * Rz(180)^-1 = Rz(90): front +x; the mesh (0.225 x 0.21 x 0.275)
    // scaled to 0.42 x 0.45 x 0.55 (not uniformly).
    assert_box(&o[1], [0.225, 4.6, 0.275], [0.42, 0.45, 0.55], [1.0, 0.0, 0.0]);
    assert!(
        (o[1].scale() - Vector3::new(0.42 / 0.225, 0.45 / 0.21, 2.0)).norm() < 1e-5,
        "{}",
        o[1].scale()
    );
    // z_angle 180: Rz(360) * Rz(180)^-1 = Rz(180): front +y, its back on the south wall.
    assert_box(&o[2], [3.2, 0.3, 1.0], [1.0, 0.6, 2.0], [0.0, 1.0, 0.0]);
    assert_eq!(o[0].category(), Some("bed"));
    assert_eq!(o[0].asset_front(), Some(Vector3::y()));
    let room = &scene.rooms()[0];
    let ids: Vec<&str> = room.walls().iter().map(|w| w.id()).collect();
    assert_eq!(ids, ["south_wall", "east_wall", "north_wall", "west_wall"]);
    assert!(
        room.walls()
            .iter()
            .all(|w| w.height() == 2.5 && w.thickness() == 0.1)
    );
    assert_eq!(
        room.floor_bounds(),
        (
            sceneeval_geom::Point2::new(0.0, 0.0),
            sceneeval_geom::Point2::new(4.0, 5.0)
        )
    );
}

#[test]
fn the_converted_room_evaluates_as_the_room_written_directly() {
    let (tmp, _) = convert_into(Format::IDesign, &native("idesign/scenes"), vec![], None);
    let out = tmp.path().join("out");
    let converted = read(&out.join("scene_0.json"), &specs(&[("idesign", out.clone())]));
    // The catalog furniture of the fixtures folder, placed by bottom centres.
    let fixtures = sceneeval_fixtures::default_output_dir().join("assets");
    let library = AssetLibrary::from_specs(&[format!("fixture={}", fixtures.display())]).unwrap();
    let room = rectangle_room(
        "0",
        "floor_0",
        4.0,
        5.0,
        2.5,
        0.1,
        ["south_wall", "east_wall", "north_wall", "west_wall"],
    );
    let one = Vector3::repeat(1.0);
    let placements = [
        ("fixture.bed".to_owned(), yawed(0.0, [2.0, 3.95, 0.0]), one),
        // The catalog nightstand is 0.45 x 0.42: scaled to 0.42 x 0.45.
        (
            "fixture.nightstand".to_owned(),
            yawed(90.0, [0.225, 4.6, 0.0]),
            Vector3::new(0.42 / 0.45, 0.45 / 0.42, 1.0),
        ),
        ("fixture.wardrobe".to_owned(), yawed(180.0, [3.2, 0.3, 0.0]), one),
    ];
    let dir = tempfile::tempdir().unwrap();
    let direct = written_directly(dir.path(), &library, vec![room], &placements);
    for (a, b) in converted.objects().iter().zip(direct.objects()) {
        assert!((a.obb().center - b.obb().center).norm() < 1e-6, "{}", a.id());
        assert!(
            (a.obb().extents() - b.obb().extents()).norm() < 1e-6,
            "{}",
            a.id()
        );
        assert!(
            a.pose().rotation.angle_to(&b.pose().rotation) < 1e-9,
            "{}",
            a.id()
        );
    }
    // The same numbers (to the f32 rounding of the shrunk GLBs' vertices).
    assert_close(&plausibility(&converted), &plausibility(&direct), 1e-6);
}
