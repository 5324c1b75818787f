//! `sceneeval convert`: from each generator's fixture batch folder to a folder `sceneeval
//! evaluate` reads, with what was skipped printed; `inspect --json` shows the turned fronts;
//! bad input fails naming the file and leaves no output.

// Set-up helpers outside `#[test]` functions may stop the test on failure.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use assert_cmd::cargo::cargo_bin_cmd;
use predicates::prelude::*;
use serde_json::Value;

fn native(sub: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/native")
        .join(sub)
}

fn spec(prefix: &str, dir: &Path) -> String {
    format!("{prefix}={}", dir.display())
}

#[test]
fn help_exits_zero_and_names_the_formats() {
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "--help"])
        .assert()
        .success()
        .stdout(predicate::str::contains("holodeck").and(predicate::str::contains("scene-agent")))
        .stdout(predicate::str::contains("--id-map"));
}

#[test]
fn holodeck_converts_prints_what_was_skipped_and_evaluates() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("holodeck");
    let objathor = spec("objaverse", &native("holodeck/objathor"));
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "holodeck"])
        .arg(native("holodeck/scenes"))
        .arg("--out")
        .arg(&out)
        .args(["--assets", &objathor, "--id-map", r#"{"0": 106, "1": 56}"#])
        .assert()
        .success()
        .stdout(predicate::str::contains("converted 2 holodeck scenes"))
        .stdout(predicate::str::contains(
            "bedroom-2024-05-01 -> scene_106.json: 6 objects, 1 room",
        ))
        .stdout(predicate::str::contains("skipped object \"Chair (bedroom)\""))
        .stdout(predicate::str::contains("AI2-THOR"))
        .stdout(predicate::str::contains(format!(
            "evaluate with: sceneeval evaluate {} --assets {objathor}",
            out.display()
        )));
    assert!(out.join("scene_106.json").is_file() && out.join("scene_56.json").is_file());
    let results = tmp.path().join("results");
    cargo_bin_cmd!("sceneeval")
        .arg("evaluate")
        .arg(&out)
        .args(["--assets", &objathor, "--no-progress", "--out"])
        .arg(&results)
        .assert()
        .success();
    for scene in ["scene_106", "scene_56"] {
        let record: Value =
            serde_json::from_str(&std::fs::read_to_string(results.join(scene).join("eval.json")).unwrap())
                .unwrap();
        assert!(record.is_object(), "{record}");
    }
    assert!(results.join("summary.csv").is_file());
}

#[test]
fn scene_agent_converts_and_inspect_shows_the_fronts() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("sceneagent");
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "scenesmith"])
        .arg(native("scene-agent/scenes"))
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("converted 1 scene-agent scene"))
        .stdout(predicate::str::contains(format!(
            "--assets scene-agent={}",
            out.display()
        )));
    let assets = spec("scene-agent", &out);
    let json = cargo_bin_cmd!("sceneeval")
        .arg("inspect")
        .arg(out.join("scene_0.json"))
        .args(["--assets", &assets, "--json"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let doc: Value = serde_json::from_slice(&json).unwrap();
    let objects = doc["objects"].as_array().unwrap();
    assert_eq!(objects.len(), 3);
    // The bed faces world -y once its declared front (+y) is turned; the desk faces -x.
    let close = |v: &Value, want: [f64; 3]| {
        v.as_array()
            .unwrap()
            .iter()
            .zip(want)
            .all(|(a, b)| (a.as_f64().unwrap() - b).abs() < 1e-9)
    };
    assert!(close(&objects[0]["front"], [0.0, -1.0, 0.0]), "{}", objects[0]);
    assert!(close(&objects[1]["front"], [-1.0, 0.0, 0.0]), "{}", objects[1]);
    assert!(
        close(&objects[0]["asset_front"], [0.0, 1.0, 0.0]),
        "{}",
        objects[0]
    );
    // The tables say it too.
    cargo_bin_cmd!("sceneeval")
        .arg("inspect")
        .arg(out.join("scene_0.json"))
        .args(["--assets", &assets])
        .assert()
        .success()
        .stdout(predicate::str::contains("asset front").and(predicate::str::contains("+y")));
    let results = tmp.path().join("results");
    cargo_bin_cmd!("sceneeval")
        .arg("evaluate")
        .arg(&out)
        .args(["--assets", &assets, "--no-progress", "--out"])
        .arg(&results)
        .assert()
        .success();
}

#[test]
fn bad_input_fails_naming_the_file_and_leaves_no_output() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("layoutvlm");
    std::fs::create_dir_all(input.join("scene_000")).unwrap();
    std::fs::write(input.join("scene_000/scene.json"), "{\"boundary\": ").unwrap();
    std::fs::write(input.join("scene_000/layout.json"), "{}").unwrap();
    let out = tmp.path().join("out");
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "layoutvlm"])
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .args([
            "--assets",
            &spec("layoutvlm-objaverse", &native("layoutvlm/assets")),
        ])
        .assert()
        .failure()
        .stderr(
            predicate::str::contains("scene_000/scene.json:1:")
                .and(predicate::str::contains("malformed JSON")),
        );
    assert!(!out.exists());
    let left: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, vec![std::ffi::OsString::from("layoutvlm")]);
    // An unknown format is a usage error.
    cargo_bin_cmd!("sceneeval")
        .args(["convert", "sceneweaver"])
        .arg(&input)
        .args(["--out", "x"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("unknown format"));
}
