//! `sceneeval settle` and `sceneeval evaluate --metrics stability` on the fixture rooms.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use assert_cmd::Command;
use common::{fixtures, record};
use predicates::prelude::*;

fn settle(scene: &std::path::Path, out: &std::path::Path, extra: &[&str]) -> assert_cmd::assert::Assert {
    let spec = format!("fixture={}", fixtures().join("assets").display());
    Command::cargo_bin("sceneeval")
        .unwrap()
        .arg("settle")
        .arg(scene)
        .args(["--assets", &spec, "--out"])
        .arg(out)
        .args(extra)
        .assert()
}

#[test]
fn settle_writes_the_fallen_chair_on_the_floor_and_the_result_is_stable() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("settled.json");
    // Fixture scene 6: the chair floats 0.25 m above the floor; it falls.
    settle(&fixtures().join("scenes/scene_6.json"), &out, &[])
        .success()
        .stdout(predicate::str::starts_with("idx1_fixture.chair\tmoved 0.25"))
        .stderr(predicate::str::contains("1 of"))
        .stderr(predicate::str::contains("written to"));
    let before: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixtures().join("scenes/scene_6.json")).unwrap())
            .unwrap();
    let after: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let z =
        |v: &serde_json::Value, i: usize| v["scene"]["object"][i]["transform"]["data"][14].as_f64().unwrap();
    // The chair's origin came down by the 0.25 m it floated (within 2 mm); the table stayed.
    assert!(
        (z(&before, 1) - z(&after, 1) - 0.25).abs() < 2e-3,
        "{} {}",
        z(&before, 1),
        z(&after, 1)
    );
    assert!((z(&before, 0) - z(&after, 0)).abs() < 1e-3);
    // Settling the settled scene moves nothing beyond the limits; no temporary file is left.
    let again = dir.path().join("again.json");
    settle(&out, &again, &[])
        .success()
        .stdout("")
        .stderr(predicate::str::contains(": 0 of"));
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn settle_takes_the_weld_mode_and_rejects_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("settled.json");
    // Scene 0, the tidy bedroom: without welds the painting and the ceiling lamp fall.
    settle(&fixtures().join("scenes/scene_0.json"), &out, &["--weld", "none"])
        .success()
        .stdout(predicate::str::contains("idx7_fixture.painting"))
        .stdout(predicate::str::contains("idx8_fixture.ceiling_lamp"))
        .stderr(predicate::str::contains("weld mode none"));
    settle(
        &fixtures().join("scenes/scene_0.json"),
        &out,
        &["--weld", "glued"],
    )
    .failure()
    .stderr(predicate::str::contains("unknown weld mode \"glued\""));
    let plan = dir.path().join("plan.json");
    std::fs::write(&plan, r#"{"stability": {"time_step_s": 1}}"#).unwrap();
    settle(
        &fixtures().join("scenes/scene_0.json"),
        &out,
        &["--plan", plan.to_str().unwrap()],
    )
    .failure()
    .stderr(predicate::str::contains("stability.time_step_s"));
    // A scene without rooms has no floor: a clear error, nothing written.
    let roomless = dir.path().join("roomless.json");
    std::fs::write(
        &roomless,
        r#"{"format": "sceneState", "scene": {"version": "scene@1.0.2", "arch": {"elements": []}, "object": [
            {"index": 0, "box": {"size": [0.4, 0.4, 0.4]},
             "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 1,1,0.2,1]}}]}}"#,
    )
    .unwrap();
    let nothing = dir.path().join("nothing.json");
    settle(&roomless, &nothing, &[])
        .failure()
        .stderr(predicate::str::contains("has no room"));
    assert!(!nothing.exists());
}

#[test]
fn evaluate_reports_stability_in_eval_json_and_the_summary() {
    let scenes = tempfile::tempdir().unwrap();
    for n in [0, 6] {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), scenes.path().join(&name)).unwrap();
    }
    let out = tempfile::tempdir().unwrap();
    common::evaluate(
        scenes.path(),
        &fixtures().join("assets"),
        out.path(),
        &["--metrics", "stability"],
    )
    .success();
    // Scene 6: 1 of its free objects (the floating chair) fell.
    let r6 = record(out.path(), "scene_6");
    let st = &r6["report"]["stability"];
    assert_eq!(st["weld"], "architectural");
    assert_eq!(st["objects"][1]["stable"], false);
    assert_eq!(st["objects"][1]["weld_reason"], serde_json::Value::Null);
    let free = st["num_free"].as_f64().unwrap();
    assert_eq!(st["num_unstable"], 1);
    let stab = r6["report"]["summary"]["stab"].as_f64().unwrap();
    assert!((stab - (1.0 - 1.0 / free)).abs() < 1e-12, "{stab}");
    // Scene 0: every free object stays; the painting and ceiling lamp are welded.
    let r0 = record(out.path(), "scene_0");
    assert_eq!(r0["report"]["summary"]["stab"], 1.0);
    assert_eq!(r0["report"]["stability"]["objects"][7]["weld_reason"], "wall");
    // STAB in the tables: the mean of 100 % and the scene 6 share.
    let csv = std::fs::read_to_string(out.path().join("summary.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let all: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let col = header.iter().position(|c| *c == "STAB").unwrap();
    let expected = 100.0 * (1.0 + stab) / 2.0;
    assert_eq!(all[col], format!("{expected:.4}"));
    let scenes_csv = std::fs::read_to_string(out.path().join("summary_scenes.csv")).unwrap();
    assert!(
        scenes_csv.lines().next().unwrap().contains(",STAB,"),
        "{scenes_csv}"
    );
    // The decompositions are kept for a re-run; the timing names the metric's time.
    assert!(
        out.path()
            .join("physics-cache")
            .read_dir()
            .unwrap()
            .next()
            .is_some()
    );
    let timing: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("scene_6/timing.json")).unwrap())
            .unwrap();
    assert!(timing["stability_seconds"].as_f64().is_some(), "{timing}");
}

/// Support types the scene does not state come from the VLM when one is given, as `evaluate`
/// asks them: scene 0 without its stated types; the tables make the painting wall-mounted and
/// the ceiling lamp ceiling-mounted (welded, nothing moves), a model that answers `ground` for
/// every object makes both fall.
#[test]
fn settle_asks_the_vlm_for_the_support_types_the_scene_does_not_state() {
    use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion, task_of};
    if common::renderer().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixtures().join("scenes/scene_0.json")).unwrap())
            .unwrap();
    for o in scene["scene"]["object"].as_array_mut().unwrap() {
        o.as_object_mut().unwrap().remove("supportType");
    }
    let unstated = dir.path().join("scene_0.json");
    std::fs::write(&unstated, scene.to_string()).unwrap();
    let out = dir.path().join("settled.json");
    // Without a VLM: the category tables.
    settle(&unstated, &out, &[]).success().stdout("");

    let server = MockEndpoint::start(std::time::Duration::ZERO, |_, _| {
        completion(&serde_json::json!({"support_type": "ground", "reason": "it stands on the floor"}))
    });
    let url = server.url();
    settle(
        &unstated,
        &out,
        &[
            "--vlm-base-url",
            &url,
            "--vlm-model",
            "mock",
            "--render-size",
            "64",
        ],
    )
    .success()
    .stdout(predicate::str::contains("idx7_fixture.painting"))
    .stdout(predicate::str::contains("idx8_fixture.ceiling_lamp"))
    .stderr(predicate::str::contains(
        "support types: 0 stated in the scene, 9 answered by the VLM, 0 from the category tables, 0 unknown",
    ));
    // One support-type question per object, each shown its views; nothing else asked.
    let tasks: Vec<String> = server.bodies().iter().map(|b| task_of(b).to_owned()).collect();
    assert_eq!(tasks.len(), 9, "{tasks:?}");
    assert!(tasks.iter().all(|t| t == "obj_support_type"), "{tasks:?}");
    // Nothing is kept without `--vlm-cache` (as in Python's `Scene.settle`)...
    assert!(!dir.path().join("vlm-cache").exists());
    // ...and with it, the answers are kept there and a re-run asks nothing.
    let cache = dir.path().join("answers");
    let cache_arg = cache.to_str().unwrap();
    let args = [
        "--vlm-base-url",
        url.as_str(),
        "--vlm-model",
        "mock",
        "--render-size",
        "64",
        "--vlm-cache",
        cache_arg,
    ];
    settle(&unstated, &out, &args).success();
    assert!(cache.is_dir());
    assert_eq!(
        server.bodies().len(),
        18,
        "the first run with the cache asks again"
    );
    settle(&unstated, &out, &args).success();
    assert_eq!(
        server.bodies().len(),
        18,
        "the second run is answered from the cache"
    );
}
