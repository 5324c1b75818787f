//! Typos in the inputs change no number silently (issue 34, item 4): a scene whose object
//! misspells `transform` fails naming the object instead of being scored with the object at the
//! origin; keys the sceneState format does not have are warned about once each on standard
//! error by default and refused with `--strict`; the annotation rows a run uses are validated
//! before its first scene, and a bad one stops it with the findings listed.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::path::{Path, PathBuf};

use assert_cmd::cargo::cargo_bin_cmd;
use common::{evaluate, fixtures, record, scenes_2_and_8};
use predicates::prelude::*;

/// Fixture scene `n` copied into `<tmp>/scenes` with `edit` applied to its text.
fn scene_with(n: u32, edit: impl Fn(&str) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    let name = format!("scene_{n}.json");
    let text = std::fs::read_to_string(fixtures().join("scenes").join(&name)).unwrap();
    let edited = edit(&text);
    assert_ne!(edited, text, "the edit changed nothing");
    std::fs::write(scenes.join(&name), edited).unwrap();
    (dir, scenes)
}

fn assets() -> PathBuf {
    fixtures().join("assets")
}

/// Every object of the scene text gets `"colour": "red"`.
fn with_colour(text: &str) -> String {
    text.replace("\"index\":", "\"colour\": \"red\",\n      \"index\":")
}

#[test]
fn a_misspelt_transform_fails_the_scene_instead_of_moving_the_object_to_the_origin() {
    let (dir, scenes) = scene_with(0, |t| t.replacen("\"transform\"", "\"transfrom\"", 1));
    let out = dir.path().join("out");
    evaluate(&scenes, &assets(), &out, &[])
        .failure()
        .stderr(predicate::str::contains(
            "/scene/object/0: unknown key \"transfrom\"; did you mean \"transform\"?",
        ))
        .stderr(predicate::str::contains("scene_0.json (load stage)"))
        .stderr(predicate::str::contains(
            "(index 0) has no \"transform\" (it has the unknown key \"transfrom\")",
        ))
        .stderr(predicate::str::contains(
            "0 evaluated, 0 kept from an earlier run, 1 failed",
        ));
    let rec = record(&out, "scene_0");
    assert_eq!(rec["status"], "failed");
    let error = rec["error"].as_str().unwrap();
    assert!(
        error.contains("scene_0.json: /scene/object/0: object") && error.contains("has no \"transform\""),
        "{error}"
    );
}

#[test]
fn unknown_keys_are_warned_about_once_by_default_and_refused_with_strict() {
    let (_dir, scenes) = scene_with(0, with_colour);
    let scene = scenes.join("scene_0.json");
    let spec = format!("fixture={}", assets().display());
    let run = cargo_bin_cmd!("sceneeval")
        .arg("inspect")
        .arg(&scene)
        .args(["--assets", &spec])
        .assert()
        .success();
    // Shown without -v, once for every object that has it.
    let stderr = String::from_utf8(run.get_output().stderr.clone()).unwrap();
    assert_eq!(stderr.matches("unknown key \"colour\"").count(), 1, "{stderr}");
    assert!(
        stderr.contains("WARN") && stderr.contains("/scene/object/0: unknown key \"colour\" (and in"),
        "{stderr}"
    );
    cargo_bin_cmd!("sceneeval")
        .arg("inspect")
        .arg(&scene)
        .args(["--assets", &spec, "--strict"])
        .assert()
        .failure()
        .stderr(predicate::str::contains(
            "1 unknown key the sceneState format does not have (strict reading)",
        ))
        .stderr(predicate::str::contains(
            "/scene/object/0: unknown key \"colour\"",
        ));
    // `evaluate --strict`: the scene fails, with the same list.
    let out = scenes.parent().unwrap().join("out");
    evaluate(&scenes, &assets(), &out, &["--strict"])
        .failure()
        .stderr(predicate::str::contains("unknown key \"colour\""));
    assert_eq!(record(&out, "scene_0")["status"], "failed");
    // Without it, the scene is evaluated.
    evaluate(&scenes, &assets(), &out, &[]).success();
    assert_eq!(record(&out, "scene_0")["status"], "ok");
}

/// The rows of scenes 2 and 8 (a bed and a desk room): row 8 counts no chair but gives one an
/// attribute; a row of a scene the run does not have is broken too.
const ROWS: &str = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
2,easy,a bedroom,\"eq,1,bed\",,,\n\
8,easy,a study,\"eq,1,desk\",\"eq,1,chair,red\",,\n\
9,hard,elsewhere,\"eq,1,sofa\",\"eq,1,table,wooden\",,\n";

#[test]
fn a_bad_annotation_row_the_run_uses_stops_it_before_the_first_scene() {
    let (dir, scenes, rows) = scenes_2_and_8(ROWS);
    let out = dir.path().join("out");
    evaluate(
        &scenes,
        &assets(),
        &out,
        &["--annotations", rows.to_str().unwrap(), "--plan", "full"],
    )
    .failure()
    .stderr(predicate::str::contains("--annotations"))
    .stderr(predicate::str::contains(
        "1 of the 2 rows this run uses has 1 error(s); nothing was evaluated",
    ))
    .stderr(predicate::str::contains("error[undefined-category] row \"8\""))
    // Row 9 is not used by this run.
    .stderr(predicate::str::contains("row \"9\"").not());
    assert!(!out.join("scene_2").exists() && !out.join("scene_8").exists());
    // A geometry plan reads only a row's ID and difficulty: the run goes on.
    evaluate(
        &scenes,
        &assets(),
        &out,
        &["--annotations", rows.to_str().unwrap()],
    )
    .success();
    // ... unless those are wrong.
    std::fs::write(&rows, ROWS.replace("8,easy", "8,eazy")).unwrap();
    let out2 = dir.path().join("out2");
    evaluate(
        &scenes,
        &assets(),
        &out2,
        &["--annotations", rows.to_str().unwrap()],
    )
    .failure()
    .stderr(predicate::str::contains("error[unknown-difficulty] row \"8\""));
    // A file whose rows for these scenes are right runs the full plan.
    std::fs::write(&rows, ROWS.replace("\"eq,1,chair,red\"", "")).unwrap();
    let out3 = dir.path().join("out3");
    evaluate(
        &scenes,
        &assets(),
        &out3,
        &["--annotations", rows.to_str().unwrap(), "--plan", "full"],
    )
    .success();
    assert!(Path::new(&out3.join("scene_8/eval.json")).is_file());
}
