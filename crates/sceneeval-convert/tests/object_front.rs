//! `objectFrontVector` as the metrics see it: an object whose file says it faces +y gets the
//! same accessibility and `face_to` answers as the same object turned by pi with the default
//! front, and different ones from the same object read with the default front.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state_str};
use sceneeval_plausibility::{AccessibilityParams, Stated, accessibility};
use sceneeval_relations::{ObjectGeom, RelationParams, face_to};
use sceneeval_scene::Scene;
use serde_json::json;

/// A 4 x 5 m room with three box objects: the cabinet (1 x 0.6 x 0.8 m, centre (2, 1, 0.4),
/// functional side: front) placed by `cabinet`, a crate beside it and a TV.
fn scene(cabinet: serde_json::Value) -> Scene {
    let doc = json!({"format": "sceneState", "scene": {
        "arch": {"elements": [
            {"id": "floor", "roomId": "r", "type": "Floor", "points": [[0, 0, 0], [4, 0, 0], [4, 5, 0], [0, 5, 0]]},
        ]},
        "object": [
            cabinet,
            // The crate covers x 2.0..3.0, y 1.35..1.75: half the cabinet's +y access strip
            // (x 1.5..2.5, y 1.3 + 0.05 .. 1.3 + 0.25), none of its -y strip.
            {"objectId": "crate", "box": {"size": [1.0, 0.4, 0.5]},
             "transform": {"data": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2.5, 1.55, 0.25, 1]}},
            // The TV, 2 m away on the +y side, as wide as the cabinet.
            {"objectId": "tv", "box": {"size": [1.0, 0.1, 0.6]},
             "transform": {"data": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2.0, 3.0, 0.4, 1]}},
        ],
    }});
    read_scene_state_str(
        &doc.to_string(),
        Path::new("scene_0.json"),
        &AssetLibrary::new(),
        &ReadOptions::default(),
    )
    .unwrap()
}

/// The cabinet's entry: a 1 x 0.6 x 0.8 m box at (2, 1, 0.4) with `transform` columns
/// `x`, `y`, and extra fields.
fn cabinet(x: [f64; 2], y: [f64; 2], extra: serde_json::Value) -> serde_json::Value {
    let mut o = json!({"objectId": "cabinet", "box": {"size": [1.0, 0.6, 0.8]}, "functionalSides": ["front"],
        "transform": {"data": [x[0], x[1], 0, 0, y[0], y[1], 0, 0, 0, 0, 1, 0, 2.0, 1.0, 0.4, 1]}});
    if let (Some(o), Some(extra)) = (o.as_object_mut(), extra.as_object()) {
        o.extend(extra.clone());
    }
    o
}

fn answers(scene: &Scene) -> (f64, f64) {
    let acc = accessibility(scene, &AccessibilityParams::default(), &Stated).unwrap();
    let o = scene.objects();
    let f = face_to(
        &ObjectGeom::from_object(&o[0]),
        &ObjectGeom::from_object(&o[2]),
        &RelationParams::default(),
    );
    (acc.acc.unwrap(), f)
}

#[test]
fn a_plus_y_front_answers_as_the_object_turned_by_pi() {
    // (a) declared to face +y, placed unturned; (b) turned by pi (columns (-1, 0), (0, -1)),
    // default front; (c) placed unturned with the default front: it faces -y.
    let a = scene(cabinet(
        [1.0, 0.0],
        [0.0, 1.0],
        json!({"objectFrontVector": [0, 1, 0]}),
    ));
    let b = scene(cabinet([-1.0, 0.0], [0.0, -1.0], json!({})));
    let c = scene(cabinet([1.0, 0.0], [0.0, 1.0], json!({})));
    // Facing +y: the access strip (x 1.5..2.5, y 1.35..1.55, 0.2 m^2) is half under the crate
    // (x 2.0..2.5): ACC = 0.1 / 0.2 = 0.5. The front faces the TV squarely: face_to = 1.
    let (acc_a, face_a) = answers(&a);
    let (acc_b, face_b) = answers(&b);
    assert!((acc_a - 0.5).abs() < 1e-12, "{acc_a}");
    assert!((face_a - 1.0).abs() < 1e-9, "{face_a}");
    assert_eq!((acc_a, face_a), (acc_b, face_b));
    // Facing -y: its strip (y 0.45..0.65) is free and the TV is behind it.
    let (acc_c, face_c) = answers(&c);
    assert!((acc_c - 1.0).abs() < 1e-12, "{acc_c}");
    assert_eq!(face_c, 0.0);
}
