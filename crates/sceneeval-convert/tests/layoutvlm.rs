//! LayoutVLM's fixture scenes converted: placements paired with assets by key, boxes and fronts
//! against hand-computed values, and the same room built directly evaluates the same.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{
    assert_box, assert_close, convert_into, native, plausibility, read, rectangle_room, specs,
    written_directly, yawed,
};
use sceneeval_convert::Format;
use sceneeval_fixtures::native::uid;
use sceneeval_geom::Vector3;
use sceneeval_io::AssetLibrary;

fn assets() -> Vec<sceneeval_io::assets::AssetSpec> {
    specs(&[("layoutvlm-objaverse", native("layoutvlm/assets"))])
}

#[test]
fn placements_pair_with_assets_by_key() {
    let (tmp, report) = convert_into(Format::LayoutVlm, &native("layoutvlm/scenes"), assets(), None);
    assert_eq!(report.scenes.len(), 2);
    let s0 = &report.scenes[0];
    // The bookshelf has no placement: skipped, and no other asset takes its place.
    assert_eq!(s0.objects, 3);
    assert_eq!(s0.skipped_objects.len(), 1);
    assert_eq!(
        (
            s0.skipped_objects[0].name.as_str(),
            s0.skipped_objects[0].pointer.as_str()
        ),
        ("bookshelf-0", "/assets/bookshelf-0")
    );

    let scene = read(&tmp.path().join("out/scene_0.json"), &assets());
    let o = scene.objects();
    let model = |asset: &str| format!("layoutvlm-objaverse.{}", uid(asset));
    assert_eq!(o[0].model_id(), Some(model("bed").as_str()));
    assert_eq!(o[1].model_id(), Some(model("chair").as_str()));
    assert_eq!(o[2].model_id(), Some(model("chair").as_str()));
    // Rotation (0, 0, 0): R = I, the object's front -y; the box centre at the position.
    assert_box(&o[0], [2.5, 3.95, 0.55], [1.6, 2.1, 1.1], [0.0, -1.0, 0.0]);
    // Rotation (0, 0, 90): Rz(90) turns the front -y to +x.
    assert_box(&o[1], [1.0, 1.0, 0.45], [0.44, 0.44, 0.9], [1.0, 0.0, 0.0]);
    assert_box(&o[2], [1.0, 2.0, 0.45], [0.44, 0.44, 0.9], [1.0, 0.0, 0.0]);
    assert_eq!(o[1].category(), Some("chair"));
    // One wall per floor edge, 2.6 m high, 0.025 m thick.
    let room = &scene.rooms()[0];
    assert_eq!(room.walls().len(), 4);
    assert!(
        room.walls()
            .iter()
            .all(|w| w.height() == 2.6 && w.thickness() == 0.025)
    );
    assert!((room.floor().area() - 20.0).abs() < 1e-12);

    // Scene 1: an older task file names the asset `<uid>-0` without a `uid` field; rotation
    // (0, 0, 180) turns the desk's front to +y, its back against nothing at y = 3.
    let scene = read(&tmp.path().join("out/scene_1.json"), &assets());
    assert_box(
        &scene.objects()[0],
        [1.5, 2.65, 0.375],
        [1.4, 0.7, 0.75],
        [0.0, 1.0, 0.0],
    );
}

#[test]
fn the_converted_room_evaluates_as_the_room_written_directly() {
    let (tmp, _) = convert_into(Format::LayoutVlm, &native("layoutvlm/scenes"), assets(), None);
    let converted = read(&tmp.path().join("out/scene_0.json"), &assets());
    let library = AssetLibrary::from_specs(&[format!(
        "layoutvlm-objaverse={}",
        native("layoutvlm/assets").display()
    )])
    .unwrap();
    let room = rectangle_room(
        "0",
        "floor_0",
        4.0,
        5.0,
        2.6,
        0.025,
        ["wall_0", "wall_1", "wall_2", "wall_3"],
    );
    let model = |asset: &str| format!("layoutvlm-objaverse.{}", uid(asset));
    let one = Vector3::repeat(1.0);
    // The assets' origins are their bottom centres: the box centre minus half the height.
    let placements = [
        (model("bed"), yawed(0.0, [2.5, 3.95, 0.0]), one),
        (model("chair"), yawed(90.0, [1.0, 1.0, 0.0]), one),
        (model("chair"), yawed(90.0, [1.0, 2.0, 0.0]), one),
    ];
    let dir = tempfile::tempdir().unwrap();
    let direct = written_directly(dir.path(), &library, vec![room], &placements);
    for (a, b) in converted.objects().iter().zip(direct.objects()) {
        assert_eq!(a.id(), b.id());
        assert!((a.obb().center - b.obb().center).norm() < 1e-6);
    }
    assert_close(&plausibility(&converted), &plausibility(&direct), 1e-6);
}
