//! The bundled fixture scenes, read from their files with the fixture assets and evaluated with
//! every geometry-only metric, against the hand-checkable answers the fixtures program wrote to
//! `fixtures/expected.json` (its fields are described in `fixtures/README.md`): the colliding
//! pair and its depth, the floating object, the object outside the walls and its share, the
//! blocked door and its occluded share, the object inside another, and the navigable rooms.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use sceneeval_eval::{EvaluationPlan, Evaluator, SceneInputs};
use sceneeval_io::{AssetLibrary, ReadOptions, read_scene_state};
use sceneeval_results::SceneReport;
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn expected() -> Vec<Value> {
    let text = std::fs::read_to_string(fixtures().join("expected.json")).unwrap();
    let doc: Value = serde_json::from_str(&text).unwrap();
    doc["scenes"].as_array().unwrap().clone()
}

/// Evaluates one fixture scene with the default sources: the support types the scene file
/// states for its objects (`supportType`; a generator knows them, and the category priors alone
/// cannot tell a wall-mounted TV from one on a stand), functional sides from the category
/// tables.
fn evaluate(scene: &Value, assets: &AssetLibrary) -> Value {
    let path = fixtures().join(scene["file"].as_str().unwrap());
    let loaded = read_scene_state(&path, assets, &ReadOptions::default()).unwrap();
    let evaluator = Evaluator::new(EvaluationPlan::geometry_only()).unwrap();
    let report: SceneReport = evaluator
        .evaluate_scene(&loaded, &SceneInputs::default())
        .unwrap()
        .report;
    serde_json::to_value(&report).unwrap()
}

fn pair(a: &Value, b: &Value) -> (String, String) {
    let (a, b) = (a.as_str().unwrap().to_owned(), b.as_str().unwrap().to_owned());
    if a <= b { (a, b) } else { (b, a) }
}

fn close(actual: f64, expected: f64, tolerance: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tolerance,
        "{what}: {actual} vs expected {expected}"
    );
}

#[test]
fn fixture_scenes_match_their_expected_answers() {
    let assets =
        AssetLibrary::from_specs(&[format!("fixture={}", fixtures().join("assets").display())]).unwrap();
    let scenes = expected();
    assert!(scenes.len() >= 12, "the fixtures have at least 12 scenes");
    for scene in &scenes {
        let name = format!("scene {} ({})", scene["id"], scene["title"]);
        let r = evaluate(scene, &assets);

        // Collisions: exactly the expected pairs, with their depth (a sampled lower bound, so at
        // most the exact depth and within a millimetre of it) or as containment.
        let colliding: Vec<&Value> = r["collision"]["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["colliding"] == true)
            .collect();
        let found: BTreeSet<(String, String)> = colliding.iter().map(|c| pair(&c["a"], &c["b"])).collect();
        let wanted: BTreeSet<(String, String)> = scene["collisions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| pair(&c["a"], &c["b"]))
            .collect();
        assert_eq!(found, wanted, "{name}: colliding pairs");
        for c in scene["collisions"].as_array().unwrap() {
            let key = pair(&c["a"], &c["b"]);
            let got = colliding.iter().find(|x| pair(&x["a"], &x["b"]) == key).unwrap();
            if c["kind"] == "containment" {
                // `b` lies entirely inside `a`.
                assert_eq!(got["kind"]["type"], "nested", "{name}: {got}");
                assert_eq!(got["kind"]["inner"], c["b"], "{name}: {got}");
            } else {
                let depth = got["depth"].as_f64().unwrap();
                let exact = c["depth"].as_f64().unwrap();
                assert!(depth <= exact + 1e-6, "{name}: depth {depth} above {exact}");
                close(depth, exact, 1e-3, &format!("{name}: penetration depth"));
            }
        }

        // Support: every object's verdict, with its declared support type.
        for o in scene["objects"].as_array().unwrap() {
            let got = r["support"]["objects"]
                .as_array()
                .unwrap()
                .iter()
                .find(|s| s["id"] == o["id"])
                .unwrap();
            assert_eq!(got["supported"], o["supported"], "{name}: support of {}", o["id"]);
            assert_eq!(
                got["support_type"], o["support_type"],
                "{name}: type of {}",
                o["id"]
            );
            assert_eq!(got["type_source"], "scene", "{name}: type source of {}", o["id"]);
        }
        for f in scene["floating"].as_array().unwrap() {
            let got = r["support"]["objects"]
                .as_array()
                .unwrap()
                .iter()
                .find(|s| s["id"] == f["object"])
                .unwrap();
            assert_eq!(got["supported"], false, "{name}: {} floats", f["object"]);
        }

        // Out of bounds: the listed objects with their share outside (the 1 mm boundary
        // tolerance moves the ratio by less than 1e-3 for these sizes), everything else inside.
        let bounds = r["out_of_bounds"]["objects"].as_array().unwrap();
        for b in bounds {
            let listed = scene["out_of_bounds"]
                .as_array()
                .unwrap()
                .iter()
                .find(|o| o["object"] == b["id"]);
            match listed {
                Some(o) => {
                    assert_eq!(b["out_of_bounds"], true, "{name}: {} is out of bounds", b["id"]);
                    let share = o["outside_share"].as_f64().unwrap();
                    close(
                        b["ratio_in_bounds"].as_f64().unwrap(),
                        1.0 - share,
                        1e-3,
                        &format!("{name}: {}", b["id"]),
                    );
                }
                None => assert_eq!(b["out_of_bounds"], false, "{name}: {} is inside: {b}", b["id"]),
            }
        }

        check_doors(&name, scene, &r);

        // Objects inside others are reported as containment collisions.
        for i in scene["inside"].as_array().unwrap() {
            assert!(
                found.contains(&pair(&i["inner"], &i["outer"])),
                "{name}: {} inside {}",
                i["inner"],
                i["outer"]
            );
        }

        // Navigability: one free region reaching every door, or (blocked door) not reachable.
        match scene["navigable"].as_bool() {
            Some(true) => {
                close(
                    r["summary"]["nav"].as_f64().unwrap(),
                    1.0,
                    1e-12,
                    &format!("{name}: NAV"),
                );
                assert_eq!(r["summary"]["all_rooms_reachable"], true, "{name}");
            }
            Some(false) => assert_eq!(r["summary"]["all_rooms_reachable"], false, "{name}"),
            None => {}
        }

        // Clean scenes have none of the flaws above.
        if scene["clean"] == true {
            assert_eq!(r["summary"]["col_sc"], false, "{name}");
            assert_eq!(r["summary"]["oob"].as_f64(), Some(0.0), "{name}");
            assert_eq!(r["summary"]["sup"].as_f64(), Some(1.0), "{name}");
        }
    }
}

/// Doors: exactly the listed ones blocked, by the listed objects, covering the listed
/// share of the door (on the 100 px/m occlusion raster).
fn check_doors(name: &str, scene: &Value, r: &Value) {
    let doors: Vec<&Value> = r["opening_clearance"]["openings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|o| o["kind"] == "door")
        .collect();
    for door in doors {
        let listed = scene["blocked_doors"]
            .as_array()
            .unwrap()
            .iter()
            .find(|d| d["door"] == door["opening"]);
        match listed {
            None => assert_eq!(
                door["blocked"], false,
                "{name}: door {} is clear: {door}",
                door["opening"]
            ),
            Some(d) => {
                assert_eq!(
                    door["blocked"], true,
                    "{name}: door {} is blocked",
                    door["opening"]
                );
                let side = door["sides"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .find(|s| s["blocked"] == true)
                    .unwrap();
                let by: BTreeSet<&str> = side["blocking"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|b| b["id"].as_str().unwrap())
                    .collect();
                let want: BTreeSet<&str> = d["blocked_by"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|b| b.as_str().unwrap())
                    .collect();
                assert_eq!(by, want, "{name}: blockers");
                close(
                    side["occluded_fraction"].as_f64().unwrap(),
                    d["occluded_fraction"].as_f64().unwrap(),
                    0.02,
                    &format!("{name}: occluded share of the door"),
                );
            }
        }
    }
}
