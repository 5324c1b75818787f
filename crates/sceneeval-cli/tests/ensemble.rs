//! `sceneeval ensemble` on three runs of fixture scenes 2 and 8 (the full plan, matching by
//! labels, relations by the lexicon) whose VLMs, one mock endpoint on 127.0.0.1 answering by
//! model name, judge the attributes differently and (model `m3`) name other functional sides.
//! The votes worked out by hand:
//!
//! | spec | m1 | m2 | m3 | majority |
//! |---|---|---|---|---|
//! | scene 8 ATR 0 `eq,1,wardrobe,tall` | yes | no | yes | yes |
//! | scene 2 ATR 0 `eq,6,chair,wooden` | no (5 of 6 chairs) | yes | yes | yes |
//!
//! Every other verdict (CNT, OOR, OAR) does not involve the VLM and is the same in the three
//! runs, so the ensemble's verdicts are m3's, and its scores must equal m3's run exactly; its
//! geometry is m1's, and the accessibility m3 measured with other functional sides is noted.
//! The ensemble of m1 and m2 ties on both ATR specs: null, unanswered.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod common;

use std::path::{Path, PathBuf};
use std::time::Duration;

use assert_cmd::Command;
use sceneeval_test_support::fidelity_model::{CSV, answer};
use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion, generic_answer, task_of, user_text};
use serde_json::{Value, json};

/// What model `model` answers.
fn answer_of(model: &str, body: &Value) -> Value {
    let (task, text) = (task_of(body), user_text(body));
    match task {
        "endpoint_check" => generic_answer(body),
        "obj_attribute" if text.contains("\"wardrobe\"") => json!({
            "category": "wardrobe", "num_instances": 1,
            "assessments": [{"instance": 0, "attribute": "tall", "satisfied": model != "m2", "reason": "judged"}]}),
        "obj_attribute" => json!({
            "category": "chair", "num_instances": 6,
            "assessments": (0..6).map(|i| json!({"instance": i, "attribute": "wooden",
                "satisfied": model != "m1" || i != 5, "reason": format!("chair {i}")})).collect::<Vec<_>>()}),
        "obj_functional_sides" if model == "m3" => {
            let mut v = answer(task, text, None);
            for a in v["assessments"].as_array_mut().unwrap() {
                a["functional_sides"] = json!(["back"]);
            }
            v
        }
        _ => answer(task, text, None),
    }
}

fn sceneeval() -> Command {
    Command::cargo_bin("sceneeval").unwrap()
}

fn stderr(a: &assert_cmd::assert::Assert) -> String {
    String::from_utf8_lossy(&a.get_output().stderr).into_owned()
}

/// The run of model `model` into `<root>/<model>` (the full plan's options of the other CLI
/// tests, objects matched by their labels).
fn evaluate(root: &Path, scenes: &Path, csv: &Path, url: &str, model: &str) -> PathBuf {
    let out = root.join(model);
    let args = common::full_plan_args_of_model(csv, url, model, &["--matching", "labels"]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    common::evaluate(scenes, &common::fixtures().join("assets"), &out, &args).success();
    out
}

/// Each spec's verdict of `metric` in `scene`'s record.
fn verdicts(record: &Value, metric: &str) -> Vec<Value> {
    record["report"]["fidelity"][metric]["specs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["satisfied"].clone())
        .collect()
}

#[test]
fn three_judges_voted_and_read_by_summarize_compare_and_report() {
    if common::renderer().is_none() {
        return; // The attribute questions show rendered views.
    }
    let endpoint = MockEndpoint::start(Duration::ZERO, |_, body| {
        let model = body["model"].as_str().unwrap_or("").to_owned();
        completion(&answer_of(&model, body))
    });
    let (keep, scenes, csv) = common::scenes_2_and_8(CSV);
    let root = keep.path();
    let runs: Vec<PathBuf> = ["m1", "m2", "m3"]
        .iter()
        .map(|m| evaluate(root, &scenes, &csv, &endpoint.url(), m))
        .collect();
    let ens = root.join("ensemble");
    let a = sceneeval()
        .arg("ensemble")
        .args(&runs)
        .arg("--out")
        .arg(&ens)
        .arg("--annotations")
        .arg(&csv)
        .assert()
        .success();
    let err = stderr(&a);
    assert!(
        err.contains("2 scenes combined from 3 runs (m1, m2, m3); 0 spec(s) tied"),
        "{err}"
    );
    assert!(
        err.contains("note: scene_2: accessibility differs in run m3")
            && err.contains("the functional sides of"),
        "{err}"
    );
    for scene in ["scene_2", "scene_8"] {
        let (ours, m1, m3) = (
            common::record(&ens, scene),
            common::record(&runs[0], scene),
            common::record(&runs[2], scene),
        );
        assert_eq!(verdicts(&ours, "atr"), [json!(true)], "{scene}");
        // The scores are m3's, whose verdicts are the majority's; the geometry is m1's.
        for key in ["cnt", "atr", "oor", "oar"] {
            assert_eq!(
                ours["report"]["summary"][key], m3["report"]["summary"][key],
                "{scene} {key}"
            );
            assert_eq!(
                ours["report"]["fidelity"][key]["score"], m3["report"]["fidelity"][key]["score"],
                "{scene} {key}"
            );
        }
        assert_eq!(ours["report"]["summary"]["acc"], m1["report"]["summary"]["acc"]);
        assert_eq!(ours["report"]["ensemble"]["runs"], json!(["m1", "m2", "m3"]));
        let atr_votes = &ours["report"]["ensemble"]["atr"][0];
        let expected = if scene == "scene_8" {
            json!([true, false, true])
        } else {
            json!([false, true, true])
        };
        assert_eq!(*atr_votes, expected, "{scene}");
        let diffs = ours["report"]["ensemble"]["geometry_differences"]
            .as_array()
            .unwrap();
        assert!(
            diffs
                .iter()
                .any(|d| d["metric"] == "accessibility" && d["run"] == "m3"),
            "{diffs:?}"
        );
    }
    // The output is a run folder the other commands read.
    sceneeval().arg("summarize").arg(&ens).assert().success();
    let a = sceneeval()
        .arg("compare")
        .arg(&runs[0])
        .arg(&ens)
        .assert()
        .success();
    let table = String::from_utf8_lossy(&a.get_output().stdout).into_owned();
    assert!(table.contains("ensemble"), "{table}");
    sceneeval().arg("report").arg(&ens).assert().success();
    assert!(ens.join("report/index.html").is_file());
    // The report pages show the views the VLM was shown, as on a run's: the first run's views
    // and matching are the ensemble's, copied with its geometry.
    for scene in ["scene_2", "scene_8"] {
        let kept: Vec<String> = std::fs::read_dir(runs[0].join(scene).join("views"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".png"))
            .collect();
        assert!(!kept.is_empty(), "{scene}: the run kept no views");
        let page = std::fs::read_to_string(ens.join("report/scenes").join(format!("{scene}.html"))).unwrap();
        assert!(!page.contains("id=\"no-views\""), "{scene}");
        for name in &kept {
            assert!(
                page.contains(&format!("<img src=\"../../{scene}/views/{name}\"")),
                "{scene} {name}"
            );
            assert_eq!(
                std::fs::read(ens.join(scene).join("views").join(name)).unwrap(),
                std::fs::read(runs[0].join(scene).join("views").join(name)).unwrap(),
                "{scene} {name}"
            );
        }
        assert_eq!(
            std::fs::read(ens.join(scene).join("matching.json")).unwrap(),
            std::fs::read(runs[0].join(scene).join("matching.json")).unwrap(),
            "{scene}"
        );
    }

    // Two judges that disagree on both ATR specs: ties, null and unanswered.
    let tie = root.join("tie");
    let a = sceneeval()
        .arg("ensemble")
        .args(&runs[..2])
        .arg("--out")
        .arg(&tie)
        .assert()
        .success();
    assert!(stderr(&a).contains("2 spec(s) tied"), "{}", stderr(&a));
    for scene in ["scene_2", "scene_8"] {
        let r = common::record(&tie, scene);
        assert_eq!(verdicts(&r, "atr"), [Value::Null]);
        assert_eq!(r["report"]["fidelity"]["atr"]["unanswered"], 1);
        assert_eq!(r["report"]["summary"]["atr"], Value::Null);
    }
    drop(endpoint);
}
