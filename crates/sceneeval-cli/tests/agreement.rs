//! `sceneeval agreement` on a run of fixture scenes 2 and 8 (the full plan without a VLM: CNT,
//! OOR and OAR verdicts, ATR unanswered) and label files written from the run's own verdicts,
//! some changed. The statistics are worked out by hand in the comments (the formulas are
//! tested in `sceneeval-report` and `sceneeval-stats`).

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod common;

use std::path::{Path, PathBuf};
use std::sync::LazyLock;

use assert_cmd::Command;
use serde_json::{Value, json};

/// The run, made once for every test of this file: `<target tmp>/agreement/run`.
static RUN: LazyLock<PathBuf> = LazyLock::new(|| {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("agreement");
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let (keep, scenes, csv) = common::scenes_2_and_8(sceneeval_test_support::fidelity_model::CSV);
    let run = root.join("run");
    common::evaluate(
        &scenes,
        &common::fixtures().join("assets"),
        &run,
        &["--annotations", csv.to_str().unwrap(), "--plan", "full"],
    )
    .success();
    drop(keep);
    run
});

/// Every spec of the run with a verdict: (scene, metric, index, text, verdict), scene 2 first.
fn run_specs() -> Vec<(String, String, usize, String, bool)> {
    let mut out = Vec::new();
    for scene in ["scene_2", "scene_8"] {
        let record = common::record(&RUN, scene);
        for metric in ["cnt", "atr", "oor", "oar"] {
            let specs = record["report"]["fidelity"][metric]["specs"].as_array().unwrap();
            for (k, spec) in specs.iter().enumerate() {
                if let Some(v) = spec["satisfied"].as_bool() {
                    let text = spec["spec"].as_str().unwrap().to_owned();
                    out.push((scene.to_owned(), metric.to_owned(), k, text, v));
                }
            }
        }
    }
    out
}

/// JSON lines of `annotator` on every spec of the run with a verdict, `change` deciding each
/// label from the run's verdict.
fn labels(annotator: &str, change: impl Fn(&str, &str, usize, bool) -> Value) -> String {
    run_specs()
        .into_iter()
        .map(|(scene, metric, index, spec, v)| {
            json!({"scene": scene, "metric": metric, "index": index, "spec": spec,
                   "satisfied": change(&scene, &metric, index, v), "annotator": annotator})
            .to_string()
                + "\n"
        })
        .collect()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn sceneeval() -> Command {
    Command::cargo_bin("sceneeval").unwrap()
}

fn stdout(a: &assert_cmd::assert::Assert) -> String {
    String::from_utf8_lossy(&a.get_output().stdout).into_owned()
}

fn stderr(a: &assert_cmd::assert::Assert) -> String {
    String::from_utf8_lossy(&a.get_output().stderr).into_owned()
}

#[test]
fn the_run_against_two_people_and_a_second_judge() {
    // The run without a VLM: CNT 5/6 (scene 8) and 7/7, OOR 1/2 and 2/2, OAR 2/2 and 2/2:
    // 21 verdicts, 2 of them false.
    let specs = run_specs();
    assert_eq!(specs.len(), 21);
    assert_eq!(specs.iter().filter(|s| !s.4).count(), 2);
    let dir = tempfile::tempdir().unwrap();
    // alice agrees with the run; bob says scene 2's CNT 0 is not satisfied (a tie with alice:
    // left out) and could not tell scene 2's OAR 0 (alice alone decides it).
    let alice = labels("alice", |_, _, _, v| json!(v));
    let bob = labels("bob", |scene, metric, k, v| match (scene, metric, k) {
        ("scene_2", "cnt", 0) => json!(false),
        ("scene_2", "oar", 0) => Value::Null,
        _ => json!(v),
    });
    let reference = write(dir.path(), "people.jsonl", &(alice + &bob));
    // A second judge that says scene 2's OOR 0 is not satisfied. Against the reference (20
    // items; reference 18 true, 2 false): tt 17, tf 0, ft 1, ff 2; p_o = 19/20;
    // p_e = (17*18 + 3*2)/400 = 312/400; kappa = (380 - 312)/(400 - 312) = 68/88 = 17/22.
    let other = labels("local", |scene, metric, k, v| match (scene, metric, k) {
        ("scene_2", "oor", 0) => json!(false),
        _ => json!(v),
    });
    let other = write(dir.path(), "local.jsonl", &other);
    let a = sceneeval()
        .arg("agreement")
        .arg("--reference")
        .arg(&reference)
        .arg(&*RUN)
        .arg(&other)
        .args(["--format", "csv"])
        .assert()
        .success();
    let csv = stdout(&a);
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0][..9],
        [
            "kind",
            "a",
            "b",
            "metric",
            "n",
            "agreement",
            "kappa",
            "kappa_low",
            "kappa_high"
        ]
    );
    let row = |kind: &str, a: &str, metric: &str| {
        rows.iter()
            .find(|r| r[0] == kind && r[1] == a && r[3] == metric)
            .unwrap_or_else(|| panic!("no {kind} {a} {metric} in {csv}"))
            .clone()
    };
    // The run agrees with the reference on all 20 items it decides: kappa 1; ATR (no one
    // labelled it) has no row.
    let all = row("judge", "run", "all");
    assert_eq!(all[2], "reference");
    assert_eq!((all[4], all[5], all[6]), ("20", "1", "1"));
    assert_eq!(all[15], "1", "one tie left out: {all:?}");
    assert!(!csv.contains(",atr,"), "{csv}");
    let local = row("judge", "local", "all");
    assert_eq!(local[4], "20");
    assert_eq!(local[5].parse::<f64>().unwrap(), 19.0 / 20.0);
    assert_eq!(local[6].parse::<f64>().unwrap(), 17.0 / 22.0);
    // tt, tf, ft, ff.
    assert_eq!(local[10..14], ["17", "0", "1", "2"]);
    let (low, high) = (local[7].parse::<f64>().unwrap(), local[8].parse::<f64>().unwrap());
    assert!(low <= 17.0 / 22.0 && 17.0 / 22.0 <= high, "{local:?}");
    // alice vs bob: 20 items (bob's null left out); one disagreement.
    let pair = row("annotators", "alice", "all");
    assert_eq!((pair[2], pair[4], pair[14]), ("bob", "20", "1"));
    let fleiss = row("fleiss", "*", "all");
    assert_eq!((fleiss[2], fleiss[4], fleiss[5]), ("*", "20", ""));

    // Markdown: the paper's table, the annotators, the wrong items; the same with a seed is
    // the same text.
    let md = || {
        stdout(
            &sceneeval()
                .arg("agreement")
                .arg("--reference")
                .arg(&reference)
                .arg(&*RUN)
                .arg(&other)
                .args(["--bootstrap", "200", "--seed", "5"])
                .assert()
                .success(),
        )
    };
    let text = md();
    assert_eq!(text, md());
    assert!(
        text.contains("| Judge | CNT % | CNT κ | OOR % | OOR κ | OAR % | OAR κ | All % | All κ | n (all) |"),
        "{text}"
    );
    assert!(
        text.contains("Reference: the majority of alice, bob (1 item(s) with tied annotators left out)."),
        "{text}"
    );
    assert!(text.contains("### local (1)"), "{text}");
    assert!(text.contains("- scene\\_2, OOR 0: `"), "{text}");
    assert!(text.contains("### run (0)"), "{text}");
    // The OAR of every rater is all true: kappa is empty and the Markdown says why.
    assert!(text.contains("- run, OAR: one class only"), "{text}");
    // LaTeX and JSON.
    let tex = stdout(
        &sceneeval()
            .arg("agreement")
            .arg("--reference")
            .arg(&reference)
            .arg(&*RUN)
            .args(["--format", "latex", "--bootstrap", "0"])
            .assert()
            .success(),
    );
    assert!(tex.contains("\\begin{tabular}{l cc cc cc cc}"), "{tex}");
    assert!(
        tex.contains("run & 100.0 & 1.00 & 100.0 & 1.00 & 100.0 & -- & 100.0 & 1.00 \\\\"),
        "{tex}"
    );
    let json: Value = serde_json::from_str(&stdout(
        &sceneeval()
            .arg("agreement")
            .arg("--reference")
            .arg(&reference)
            .arg(&*RUN)
            .args(["--format", "json", "--bootstrap", "0"])
            .assert()
            .success(),
    ))
    .unwrap();
    assert_eq!(json["reference"], json!(["alice", "bob"]));
    assert_eq!(json["rows"][0]["kind"], "judge");
}

#[test]
fn without_a_reference_the_run_against_a_label_file_in_csv() {
    let dir = tempfile::tempdir().unwrap();
    // The same labels as CSV, with every verdict the run's: one pair, agreement 1.
    let mut csv = String::from("scene,metric,index,spec,satisfied,annotator\n");
    for (scene, metric, index, spec, v) in run_specs() {
        csv.push_str(&format!("{scene},{metric},{index},\"{spec}\",{v},carol\n"));
    }
    let labels = write(dir.path(), "carol.csv", &csv);
    let a = sceneeval()
        .arg("agreement")
        .arg(&*RUN)
        .arg(&labels)
        .args(["--format", "csv", "--bootstrap", "0"])
        .assert()
        .success();
    let out = stdout(&a);
    assert!(out.contains("\npair,run,carol,all,21,1,1,,,"), "{out}");
}

#[test]
fn labels_that_do_not_fit_the_run_are_errors_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, metric, index, spec, _) = run_specs().remove(0);
    let line = |scene: &str, index: usize, spec: &str| {
        json!({"scene": scene, "metric": metric, "index": index, "spec": spec,
               "satisfied": true, "annotator": "dan"})
        .to_string()
    };
    let good = line(&scene, index, &spec);
    let cases = [
        (
            line(&scene, index, "eq,9,unicorn"),
            "labels.jsonl:2: cnt spec 0 of scene_2 is \"eq,9,unicorn\" here but",
        ),
        (line(&scene, 99, &spec), "labels.jsonl:2: cnt spec 99 of scene_2:"),
        (
            good.replace("\"cnt\"", "\"size\""),
            "labels.jsonl:2: not a label: unknown variant `size`",
        ),
        ("{not json".to_owned(), "labels.jsonl:2: not a label"),
    ];
    for (bad, expected) in cases {
        let path = write(dir.path(), "labels.jsonl", &format!("{good}\n{bad}\n"));
        let a = sceneeval()
            .arg("agreement")
            .arg(&*RUN)
            .arg(&path)
            .assert()
            .failure();
        let err = stderr(&a);
        assert!(err.contains(expected), "{bad}: {err}");
    }
    // Labels of a scene the run does not have: counted and listed, not an error.
    let elsewhere = line("scene_77", 0, "eq,1,bed");
    let path = write(dir.path(), "labels.jsonl", &format!("{good}\n{elsewhere}\n"));
    let a = sceneeval()
        .arg("agreement")
        .arg(&*RUN)
        .arg(&path)
        .args(["--format", "csv", "--bootstrap", "0"])
        .assert()
        .success();
    let err = stderr(&a);
    assert!(
        err.contains("labels for 1 scene(s) without fidelity verdicts in run"),
        "{err}"
    );
    assert!(err.contains("scene_77"), "{err}");
}
