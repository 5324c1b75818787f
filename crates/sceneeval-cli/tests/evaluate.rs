//! `sceneeval evaluate` on copies of the bundled fixture scenes plus deliberately broken ones.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::path::Path;

use common::{fixtures, record};
use predicates::prelude::*;

/// A scenes folder with fixture scenes 0 and 5, a malformed file and a scene whose asset is
/// missing.
fn scenes_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for n in [0, 5] {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), dir.path().join(&name)).unwrap();
    }
    std::fs::write(dir.path().join("scene_20.json"), "{ \"format\": \"sceneState\", ").unwrap();
    let missing = r#"{"format": "sceneState", "scene": {"version": "scene@1.0.2", "object": [
        {"index": 0, "modelId": "fixture.no_such_asset",
         "transform": {"data": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}}]}}"#;
    std::fs::write(dir.path().join("scene_21.json"), missing).unwrap();
    dir
}

fn evaluate(scenes: &Path, out: &Path, extra: &[&str]) -> assert_cmd::assert::Assert {
    common::evaluate(scenes, &fixtures().join("assets"), out, extra)
}

#[test]
fn broken_scenes_are_recorded_and_the_run_goes_on() {
    let scenes = scenes_dir();
    let out = tempfile::tempdir().unwrap();
    evaluate(scenes.path(), out.path(), &[])
        .failure()
        .stdout(predicate::str::contains("| all | 4 | 2 | 2 |"))
        .stderr(predicate::str::contains(
            "2 evaluated, 0 kept from an earlier run, 2 failed",
        ));

    let ok = record(out.path(), "scene_5");
    assert_eq!(ok["status"], "ok");
    assert_eq!(ok["schema"], "sceneeval.eval/3");
    assert_eq!(ok["scene_id"], "5");
    assert_eq!(ok["report"]["schema"], "sceneeval.scene-report/2");
    // Fixture scene 5 is the colliding pair.
    assert_eq!(ok["report"]["summary"]["col_sc"], true);

    let malformed = record(out.path(), "scene_20");
    assert_eq!(malformed["status"], "failed");
    assert_eq!(malformed["stage"], "load");
    assert!(
        malformed["error"].as_str().unwrap().contains("scene_20.json"),
        "{malformed}"
    );

    let missing = record(out.path(), "scene_21");
    assert_eq!(missing["status"], "failed");
    let chain = format!("{} {}", missing["error"], missing["causes"]);
    assert!(chain.contains("no_such_asset"), "{chain}");

    let csv = std::fs::read_to_string(out.path().join("summary.csv")).unwrap();
    assert!(
        csv.starts_with(
            "group,scenes,evaluated,failed,partial,CNT,ATR,OOR,OAR,COL_ob,COL_sc,SUP,NAV,ACC,OOB,DOOR_blk,\
             WIN_blk,STAB,CNT_n,ATR_n,OOR_n,OAR_n,CNT_unanswered,ATR_unanswered,OOR_unanswered,\
             OAR_unanswered,SUP_fallback,ACC_fallback\n"
        ),
        "{csv}"
    );
    assert!(csv.contains("\nall,4,2,2,"), "{csv}");
    assert!(out.path().join("summary.md").is_file());
}

#[test]
fn rerun_skips_finished_scenes_unless_forced() {
    let scenes = scenes_dir();
    let out = tempfile::tempdir().unwrap();
    evaluate(scenes.path(), out.path(), &[]).failure();
    let first = std::fs::read(out.path().join("scene_0/eval.json")).unwrap();

    // Fix the malformed scene: it is retried, the finished ones are kept.
    std::fs::copy(
        fixtures().join("scenes/scene_1.json"),
        scenes.path().join("scene_20.json"),
    )
    .unwrap();
    evaluate(scenes.path(), out.path(), &[])
        .failure()
        .stderr(predicate::str::contains(
            "1 evaluated, 2 kept from an earlier run, 1 failed",
        ));
    assert_eq!(record(out.path(), "scene_20")["status"], "ok");

    evaluate(scenes.path(), out.path(), &["--force"])
        .failure()
        .stderr(predicate::str::contains(
            "3 evaluated, 0 kept from an earlier run, 1 failed",
        ));
    assert_eq!(
        std::fs::read(out.path().join("scene_0/eval.json")).unwrap(),
        first,
        "same result again"
    );
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let scenes = scenes_dir();
    let one = tempfile::tempdir().unwrap();
    let two = tempfile::tempdir().unwrap();
    evaluate(scenes.path(), one.path(), &["--threads", "1"]).failure();
    evaluate(scenes.path(), two.path(), &["--threads", "2"]).failure();
    for scene in ["scene_0", "scene_5", "scene_20", "scene_21"] {
        let a = std::fs::read(one.path().join(scene).join("eval.json")).unwrap();
        let b = std::fs::read(two.path().join(scene).join("eval.json")).unwrap();
        assert_eq!(a, b, "{scene}");
    }
    for file in ["summary.csv", "summary.md"] {
        assert_eq!(
            std::fs::read(one.path().join(file)).unwrap(),
            std::fs::read(two.path().join(file)).unwrap()
        );
    }
}

#[test]
fn annotations_add_rows_per_difficulty_and_metrics_can_be_chosen() {
    let scenes = scenes_dir();
    let out = tempfile::tempdir().unwrap();
    let ann = scenes.path().join("annotations.csv");
    std::fs::write(
        &ann,
        "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
         0,easy,A bedroom.,\"eq,1,bed\",,,\n\
         5,hard,A living room.,\"eq,1,sofa\",,,\n",
    )
    .unwrap();
    let ann = ann.to_str().unwrap().to_owned();
    evaluate(
        scenes.path(),
        out.path(),
        &["--annotations", &ann, "--metrics", "collision,out_of_bounds"],
    )
    .failure()
    .stdout(predicate::str::contains("| easy | 1 | 1 | 0 |"))
    .stdout(predicate::str::contains("| hard | 1 | 1 | 0 |"))
    .stdout(predicate::str::contains("| unannotated | 2 | 0 | 2 |"));
    let rec = record(out.path(), "scene_0");
    assert_eq!(
        rec["report"]["metrics"],
        serde_json::json!(["collision", "out_of_bounds"])
    );
    assert!(rec["report"]["support"].is_null());
}

#[test]
fn usage_errors_exit_non_zero_with_a_message() {
    let empty = tempfile::tempdir().unwrap();
    let out = tempfile::tempdir().unwrap();
    evaluate(empty.path(), out.path(), &[])
        .failure()
        .stderr(predicate::str::contains("no scene_<ID>.json files"));
    let scenes = scenes_dir();
    evaluate(scenes.path(), out.path(), &["--metrics", "physics"])
        .failure()
        .stderr(predicate::str::contains("unknown metric"));
}
