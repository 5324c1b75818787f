//! Results a user can trust: a re-run reuses a result only when nothing it depends on
//! changed and says why it evaluated the others; scene names are strict and duplicates are
//! refused before any work; an unwritable output folder is found first; failures print their
//! whole cause chain; a scene over its time budget fails alone; timings stay out of
//! `eval.json`; `summary.md` names its preset.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::path::PathBuf;

use common::{evaluate, fixtures, record};
use predicates::prelude::*;
use serde_json::Value;

/// A scenes folder with fixture scenes 0 and 5, and a copy of the fixture assets.
fn setup() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let root = tempfile::tempdir().unwrap();
    let scenes = root.path().join("scenes");
    let assets = root.path().join("assets");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::create_dir_all(&assets).unwrap();
    for n in [0, 5] {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), scenes.join(&name)).unwrap();
    }
    for entry in std::fs::read_dir(fixtures().join("assets")).unwrap() {
        let p = entry.unwrap().path();
        std::fs::copy(&p, assets.join(p.file_name().unwrap())).unwrap();
    }
    (root, scenes, assets)
}

#[test]
fn results_are_reused_only_while_everything_they_depend_on_is_unchanged() {
    let (root, scenes, assets) = setup();
    let out = root.path().join("out");
    evaluate(&scenes, &assets, &out, &[])
        .success()
        .stderr(predicate::str::contains("2 evaluated, 0 kept"))
        .stderr(predicate::str::contains("evaluated because no earlier result: 2"));
    let first = std::fs::read(out.join("scene_5/eval.json")).unwrap();
    let rec = record(&out, "scene_5");
    let fp = &rec["fingerprint"];
    assert_eq!(fp["tool"], format!("sceneeval {}", env!("CARGO_PKG_VERSION")));
    assert!(fp["scene"]["blake3"].as_str().unwrap().len() == 64, "{fp}");
    assert!(!fp["assets"].as_array().unwrap().is_empty());

    // Nothing changed: both reused, records untouched.
    evaluate(&scenes, &assets, &out, &[])
        .success()
        .stderr(predicate::str::contains("0 evaluated, 2 kept"));
    assert!(std::fs::read(out.join("scene_5/eval.json")).unwrap() == first);
    // The same asset folder spelled another way is the same folder.
    evaluate(&scenes, &scenes.join("..").join(".").join("assets"), &out, &[])
        .success()
        .stderr(predicate::str::contains("0 evaluated, 2 kept"));

    // Edit scene 0 (move its first object by 1 mm): only it is evaluated again.
    let path = scenes.join("scene_0.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    let x = doc["scene"]["object"][0]["transform"]["data"][12]
        .as_f64()
        .unwrap();
    doc["scene"]["object"][0]["transform"]["data"][12] = serde_json::json!(x + 0.001);
    std::fs::write(&path, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    evaluate(&scenes, &assets, &out, &[])
        .success()
        .stderr(predicate::str::contains("1 evaluated, 1 kept"))
        .stderr(predicate::str::contains(
            "evaluated because the scene file changed: 1",
        ));

    // Change an asset's metadata used by scene 5: it is evaluated again.
    let model = record(&out, "scene_5")["fingerprint"]["assets"][0]["model_id"]
        .as_str()
        .unwrap()
        .to_owned();
    let id = model.strip_prefix("fixture.").unwrap();
    let sidecar = assets.join(format!("{id}.json"));
    let meta = std::fs::read_to_string(&sidecar).unwrap();
    std::fs::write(&sidecar, meta.replace('}', ", \"description\": \"edited\"}")).unwrap();
    evaluate(&scenes, &assets, &out, &[])
        .success()
        .stderr(predicate::str::contains(format!(
            "evaluated because asset {model} changed"
        )));
    let after_edit = std::fs::read(out.join("scene_5/eval.json")).unwrap();
    assert!(after_edit != first, "the fingerprint records the new metadata");

    // A collision-only run, then the full plan: the full plan is not served the partial record.
    evaluate(&scenes, &assets, &out, &["--metrics", "collision"])
        .success()
        .stderr(predicate::str::contains(
            "evaluated because the metrics or their parameters changed: 2",
        ));
    assert!(record(&out, "scene_5")["report"]["support"].is_null());
    evaluate(&scenes, &assets, &out, &[])
        .success()
        .stderr(predicate::str::contains("2 evaluated, 0 kept"));
    assert!(!record(&out, "scene_5")["report"]["summary"]["sup"].is_null());
    assert!(
        std::fs::read(out.join("scene_5/eval.json")).unwrap() == after_edit,
        "the same inputs give the same bytes"
    );

    // Another preset changes the parameters: evaluated again, and summary.md says which.
    evaluate(&scenes, &assets, &out, &["--preset", "reference"])
        .success()
        .stdout(predicate::str::contains("Preset: `reference`"))
        .stderr(predicate::str::contains("2 evaluated, 0 kept"));
    let md = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(
        md.contains("Preset: `reference`") && md.contains("higher is better"),
        "{md}"
    );

    // A record of an older schema (or without fingerprint) is never trusted.
    let path = out.join("scene_0/eval.json");
    let old = std::fs::read_to_string(&path)
        .unwrap()
        .replace("sceneeval.eval/3", "sceneeval.eval/1");
    std::fs::write(&path, old).unwrap();
    evaluate(&scenes, &assets, &out, &["--preset", "reference"])
        .success()
        .stderr(predicate::str::contains(
            "evaluated because earlier result unreadable",
        ));
}

#[test]
fn timings_go_to_their_own_file_and_eval_json_stays_identical() {
    let (root, scenes, assets) = setup();
    let out = root.path().join("out");
    evaluate(&scenes, &assets, &out, &[])
        .success()
        .stderr(predicate::str::contains(
            "time over the evaluated scenes: loading",
        ))
        .stderr(predicate::str::contains("collision"));
    let first = std::fs::read(out.join("scene_0/eval.json")).unwrap();
    let timing: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("scene_0/timing.json")).unwrap()).unwrap();
    assert_eq!(timing["schema"], "sceneeval.timing/1");
    assert_eq!(timing["metrics"].as_array().unwrap().len(), 6);
    assert!(timing["total_seconds"].as_f64().unwrap() >= timing["load_seconds"].as_f64().unwrap());
    evaluate(&scenes, &assets, &out, &["--force"])
        .success()
        .stderr(predicate::str::contains("evaluated because forced: 2"));
    assert!(std::fs::read(out.join("scene_0/eval.json")).unwrap() == first);
    assert!(!String::from_utf8(first).unwrap().contains("seconds"));
}

#[test]
fn scene_names_are_strict_and_duplicate_ids_stop_the_run_before_any_work() {
    let (root, scenes, assets) = setup();
    let out = root.path().join("out");
    std::fs::copy(scenes.join("scene_0.json"), scenes.join("scene_7.JSON")).unwrap();
    std::fs::write(scenes.join("scene_state_template.json"), "{}").unwrap();
    evaluate(&scenes, &assets, &out, &[])
        .success()
        .stderr(predicate::str::contains("warning: skipped"))
        .stderr(predicate::str::contains("scene_7.JSON"))
        .stderr(predicate::str::contains("scene_state_template.json"))
        .stderr(predicate::str::contains("2 scenes: 2 evaluated"));

    std::fs::copy(scenes.join("scene_5.json"), scenes.join("scene_05.json")).unwrap();
    let out2 = root.path().join("out2");
    evaluate(&scenes, &assets, &out2, &[])
        .failure()
        .stderr(predicate::str::contains("have the same id 5"));
    assert!(!out2.exists(), "nothing was written");
}

#[test]
fn an_unwritable_output_folder_is_found_before_any_scene_is_evaluated() {
    let (root, scenes, assets) = setup();
    let file = root.path().join("a_file");
    std::fs::write(&file, "x").unwrap();
    evaluate(&scenes, &assets, &file.join("out"), &[])
        .failure()
        .stderr(predicate::str::contains("is not writable"))
        .stderr(predicate::str::contains("scenes:").not());
}

#[test]
fn a_bad_plan_is_refused_before_any_scene_is_read() {
    let (root, scenes, assets) = setup();
    let out = root.path().join("out");
    let plan = root.path().join("plan.json");
    std::fs::write(
        &plan,
        r#"{"params": {"collision": {"exclude_floor_covering": true}}}"#,
    )
    .unwrap();
    let plan_arg = plan.display().to_string();
    evaluate(&scenes, &assets, &out, &["--plan", &plan_arg])
        .failure()
        .stderr(predicate::str::contains(
            "params.collision.exclude_floor_covering",
        ))
        .stderr(predicate::str::contains("unknown field"));
    std::fs::write(
        &plan,
        r#"{"params": {"navigability": {"resolution": {"pixels": 100000}}}}"#,
    )
    .unwrap();
    evaluate(&scenes, &assets, &out, &["--plan", &plan_arg])
        .failure()
        .stderr(predicate::str::contains("params.navigability.resolution"));
    assert!(!out.exists(), "no scene was evaluated");
}

#[test]
fn failures_print_the_scene_file_and_the_whole_cause_chain() {
    let (root, scenes, assets) = setup();
    let out = root.path().join("out");
    let missing = r#"{"format": "sceneState", "scene": {"object": [
        {"index": 0, "modelId": "fixture.no_such_asset",
         "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}}]}}"#;
    std::fs::write(scenes.join("scene_21.json"), missing).unwrap();
    evaluate(&scenes, &assets, &out, &[])
        .failure()
        .stderr(predicate::str::contains("failed: "))
        .stderr(predicate::str::contains("scene_21.json (load stage)"))
        .stderr(predicate::str::contains("1 asset not found, used by 1 object"))
        .stderr(predicate::str::contains(
            "\"fixture.no_such_asset\" for /scene/object/0: looked for",
        ));
}

#[test]
fn a_scene_over_its_time_budget_fails_alone_and_the_run_goes_on() {
    let (root, scenes, assets) = setup();
    let out = root.path().join("out");
    evaluate(&scenes, &assets, &out, &["--time-budget-s", "0.000000001"])
        .failure()
        .stderr(predicate::str::contains("time budget of"))
        .stderr(predicate::str::contains(
            "0 evaluated, 0 kept from an earlier run, 2 failed",
        ));
    let rec = record(&out, "scene_0");
    assert_eq!(rec["status"], "failed");
    assert!(rec["error"].as_str().unwrap().contains("time budget"), "{rec}");
    assert!(out.join("summary.md").is_file());
    // A generous budget: both evaluate (failed records are always retried). Given by the
    // option's old name, which still works and says so.
    evaluate(&scenes, &assets, &out, &["--time-budget", "600"])
        .success()
        .stderr(predicate::str::contains(
            "warning: --time-budget is the old name of --time-budget-s; it still works, but use --time-budget-s",
        ))
        .stderr(predicate::str::contains("evaluated because failed before: 2"));
}

/// `sceneeval inspect --json | head`: a reader that closes the pipe ends the command quietly
/// and successfully, as for other command-line tools (it printed "error: writing to standard
/// output: Broken pipe" and failed).
#[test]
fn a_closed_pipe_ends_the_command_quietly() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("sceneeval"))
        .arg("inspect")
        .arg(fixtures().join("scenes/scene_0.json"))
        .arg("--assets")
        .arg(format!("fixture={}", fixtures().join("assets").display()))
        .args(["--format", "json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The reader goes away before the command writes anything.
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{:?}: {stderr}", output.status);
    assert!(stderr.is_empty(), "{stderr}");
}
