//! The full plan through the command line on fixture scenes 2 and 8: against a mock
//! OpenAI-compatible server on 127.0.0.1 (interrupted and resumed, sampling options), without a
//! VLM, sharded and summarised. The model and the annotation rows are
//! `sceneeval_test_support::fidelity_model`, shared with the facade's pipeline tests
//! (`crates/sceneeval-run/tests/pipeline.rs`, which run the same scenes through the library).
//! Expected values are worked out by hand in the comments.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;
#[path = "../../sceneeval-vlm-openai/tests/support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};

use base64::Engine;
use common::{fixtures, record};
use sceneeval_test_support::fidelity_model::{CSV, answer, pictured_category};
use serde_json::{Value, json};

fn setup() -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
    setup_with(CSV)
}

fn setup_with(csv_text: &str) -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
    common::scenes_2_and_8(csv_text)
}

fn scores(out: &Path, scene: &str) -> [Value; 4] {
    let s = &record(out, scene)["report"]["summary"];
    [
        s["cnt"].clone(),
        s["atr"].clone(),
        s["oor"].clone(),
        s["oar"].clone(),
    ]
}

/// A mock OpenAI-compatible server answering like [`answer`] (and the endpoint check a run
/// sends before its first scene, which is not counted); after `budget` answers it refuses
/// every request with 401 (a permanent error). `out` is the run's output folder: a matching
/// request's object is recognised by its front view there.
async fn mock_server(budget: usize, out: PathBuf) -> wiremock::MockServer {
    let server = wiremock::MockServer::start().await;
    let answered = std::sync::atomic::AtomicUsize::new(0);
    support::mount_sequence(&server, move |_, req| {
        let body: Value = req.body_json().unwrap();
        let task = body["response_format"]["json_schema"]["name"]
            .as_str()
            .unwrap_or("")
            .to_owned();
        if task == "endpoint_check" {
            return support::json_completion(&json!({"colour": "red", "reason": "a red square"}));
        }
        if answered.fetch_add(1, std::sync::atomic::Ordering::SeqCst) >= budget {
            return wiremock::ResponseTemplate::new(401)
                .set_body_json(json!({"error": {"message": "key revoked"}}));
        }
        let text = support::user_text(&body).to_owned();
        let pictured = body["messages"][1]["content"][1]["image_url"]["url"]
            .as_str()
            .and_then(|url| url.split_once("base64,"))
            .and_then(|(_, data)| base64::engine::general_purpose::STANDARD.decode(data).ok())
            .and_then(|png| pictured_category(&out, &png));
        support::json_completion(&answer(&task, &text, pictured.as_deref()))
    })
    .await;
    server
}

fn cli_run(scenes: &Path, csv: &Path, out: &Path, url: &str) -> assert_cmd::assert::Assert {
    cli_command(scenes, csv, out, url, &[]).assert()
}

/// `sceneeval evaluate` with the full plan, the VLM at `url`, and `extra` options.
fn cli_command(scenes: &Path, csv: &Path, out: &Path, url: &str, extra: &[&str]) -> assert_cmd::Command {
    common::full_plan_command(scenes, csv, out, url, extra)
}

#[tokio::test]
async fn interrupted_run_resumes_without_asking_again() {
    if common::renderer().is_none() {
        return;
    }
    let (_keep, scenes, csv) = setup();
    std::fs::remove_file(scenes.join("scene_2.json")).unwrap();
    let out = tempfile::tempdir().unwrap();
    // Scene 8 needs 7 requests (functional sides, 4 matching, 1 attribute, 1 mapping). The
    // first server answers 3, then the key is "revoked": the scene is partial (its geometry
    // results kept), the 3 answers are in the cache.
    let first = mock_server(3, out.path().to_owned()).await;
    let url = format!("{}/v1", first.uri());
    let (s, c, o) = (scenes.clone(), csv.clone(), out.path().to_owned());
    let a = tokio::task::spawn_blocking(move || cli_run(&s, &c, &o, &url).get_output().clone())
        .await
        .unwrap();
    assert!(!a.status.success());
    let partial = record(out.path(), "scene_8");
    assert_eq!(partial["status"], "partial");
    assert!(partial["report"]["collision"].is_object(), "{partial}");
    let answered_first = support::bodies(&first).await.len();
    assert!(
        answered_first >= 5,
        "the endpoint check, 3 answered and at least one refused: {answered_first}"
    );
    // The second run asks only the 4 questions not answered before (after its endpoint check).
    let second = mock_server(usize::MAX, out.path().to_owned()).await;
    let url = format!("{}/v1", second.uri());
    let (s, c, o) = (scenes.clone(), csv.clone(), out.path().to_owned());
    let b = tokio::task::spawn_blocking(move || cli_run(&s, &c, &o, &url).get_output().clone())
        .await
        .unwrap();
    assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    let second_tasks: Vec<Value> = support::bodies(&second)
        .await
        .iter()
        .map(|b| b["response_format"]["json_schema"]["name"].clone())
        .collect();
    assert_eq!(second_tasks.len(), 5, "{second_tasks:?}");
    assert_eq!(second_tasks[0], "endpoint_check");
    assert_eq!(
        scores(out.path(), "scene_8"),
        [json!(4.0 / 6.0), json!(1.0), json!(0.0), json!(1.0)]
    );
    let done = record(out.path(), "scene_8");
    assert_eq!(done["status"], "ok");
    assert_eq!(done["report"]["fidelity"]["vlm_usage"]["requests"], json!(7));
    // A third run of the finished run sends nothing at all, not even the endpoint check (the
    // record is reused).
    let third = mock_server(usize::MAX, out.path().to_owned()).await;
    let url = format!("{}/v1", third.uri());
    let (s, c, o) = (scenes.clone(), csv.clone(), out.path().to_owned());
    let t = tokio::task::spawn_blocking(move || cli_run(&s, &c, &o, &url).get_output().clone())
        .await
        .unwrap();
    assert!(t.status.success());
    assert_eq!(support::bodies(&third).await.len(), 0);
    let stderr = String::from_utf8_lossy(&t.stderr);
    assert!(stderr.contains("1 kept from an earlier run"), "{stderr}");
}

#[test]
fn offline_full_plan_says_so_and_tables_show_ten_metrics() {
    let (_keep, scenes, csv) = setup();
    let out = tempfile::tempdir().unwrap();
    let a = evaluate_full(&scenes, csv.to_str().unwrap(), out.path(), &[]);
    let stderr = String::from_utf8_lossy(&a.get_output().stderr).into_owned();
    assert!(stderr.contains("no VLM configured"), "{stderr}");
    let csv_out = std::fs::read_to_string(out.path().join("summary.csv")).unwrap();
    let header = csv_out.lines().next().unwrap();
    for col in [
        "CNT", "ATR", "OOR", "OAR", "COL_ob", "COL_sc", "SUP", "NAV", "ACC", "OOB",
    ] {
        assert!(header.split(',').any(|c| c == col), "{header}");
    }
    // all: CNT (5/6 + 1) / 2 = 91.6667 %, ATR none, OOR (0.5 + 1) / 2 = 75 %, OAR 100 %,
    // over 2 scenes each (ATR_n 0).
    let all = csv_out.lines().nth(1).unwrap();
    assert!(all.starts_with("all,2,2,0,0,91.6667,,75.0000,100.0000,"), "{all}");
    // CNT_n .. OAR_n, no unanswered spec, no fallback (no VLM asked).
    assert!(all.ends_with(",2,0,2,2,0,0,0,0,0,0"), "{all}");
    // Per difficulty: easy is scene 8, hard scene 2.
    assert!(
        csv_out.contains("\neasy,1,1,0,0,83.3333,,50.0000,100.0000,"),
        "{csv_out}"
    );
    assert!(
        csv_out.contains("\nhard,1,1,0,0,100.0000,,100.0000,100.0000,"),
        "{csv_out}"
    );
}

/// `sceneeval evaluate SCENES --plan full --annotations ANN` into `out`, with `extra` options;
/// it must succeed.
fn evaluate_full(scenes: &Path, ann: &str, out: &Path, extra: &[&str]) -> assert_cmd::assert::Assert {
    let args = [&["--annotations", ann, "--plan", "full"], extra].concat();
    common::evaluate(scenes, &fixtures().join("assets"), out, &args).success()
}

/// `sceneeval summarize DIRS... --annotations ANN --out OUT` (with both when given).
fn summarize(dirs: &[&Path], ann: Option<&str>, out: Option<&Path>) -> assert_cmd::assert::Assert {
    let mut cmd = assert_cmd::Command::cargo_bin("sceneeval").unwrap();
    cmd.arg("summarize").args(dirs);
    if let Some(ann) = ann {
        cmd.args(["--annotations", ann]);
    }
    if let Some(out) = out {
        cmd.arg("--out").arg(out);
    }
    cmd.assert()
}

/// The `summary.csv` in `dir`.
fn summary_csv(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("summary.csv")).unwrap()
}

#[test]
fn zero_padded_scene_files_read_the_rows_of_their_numbers() {
    // Scene 2 renamed `scene_000.json` and given row 0; scene 8 as `scene_008.json`. The run
    // (fidelity sections) and the summary (difficulty rows), and `summarize` after it, find
    // the same rows as with plain names: the summary equals the plain run's.
    let (_keep, plain, csv) = setup();
    let whole = tempfile::tempdir().unwrap();
    evaluate_full(&plain, csv.to_str().unwrap(), whole.path(), &[]);
    let padded = tempfile::tempdir().unwrap();
    std::fs::copy(plain.join("scene_2.json"), padded.path().join("scene_000.json")).unwrap();
    std::fs::copy(plain.join("scene_8.json"), padded.path().join("scene_008.json")).unwrap();
    let padded_csv = padded.path().join("annotations.csv");
    std::fs::write(&padded_csv, CSV.replace("\n2,hard,", "\n0,hard,")).unwrap();
    let padded_ann = padded_csv.to_str().unwrap();
    let out = tempfile::tempdir().unwrap();
    evaluate_full(padded.path(), padded_ann, out.path(), &[]);
    for scene in ["scene_000", "scene_008"] {
        let record = common::record(out.path(), scene);
        assert!(record["report"]["fidelity"].is_object(), "{scene}: {record}");
    }
    let summary = summary_csv(out.path());
    assert!(!summary.contains("unannotated"), "{summary}");
    assert_eq!(summary, summary_csv(whole.path()));
    let merged = tempfile::tempdir().unwrap();
    summarize(&[out.path()], Some(padded_ann), Some(merged.path())).success();
    assert_eq!(summary_csv(merged.path()), summary);
}

#[test]
fn shards_merged_by_summarize_equal_a_single_run() {
    let (_keep, scenes, csv) = setup();
    let ann = csv.to_str().unwrap();
    let whole = tempfile::tempdir().unwrap();
    evaluate_full(&scenes, ann, whole.path(), &[]);
    let shards: Vec<tempfile::TempDir> = (1..=2).map(|_| tempfile::tempdir().unwrap()).collect();
    for (k, dir) in shards.iter().enumerate() {
        evaluate_full(&scenes, ann, dir.path(), &["--shard", &format!("{}/2", k + 1)]);
        // Each shard evaluated one of the two scenes.
        let n = std::fs::read_dir(dir.path())
            .unwrap()
            .filter(|e| e.as_ref().unwrap().path().is_dir())
            .count();
        assert_eq!(n, 1);
    }
    let merged = tempfile::tempdir().unwrap();
    summarize(
        &[shards[0].path(), shards[1].path()],
        Some(ann),
        Some(merged.path()),
    )
    .success();
    assert_eq!(summary_csv(merged.path()), summary_csv(whole.path()));
    // The same folder twice overlaps: an error.
    summarize(&[shards[0].path(), shards[0].path()], None, None).failure();
}

#[tokio::test]
async fn sampling_options_reach_every_request_and_the_key_variable_is_used() {
    if common::renderer().is_none() {
        return;
    }
    let (_keep, scenes, csv) = setup();
    std::fs::remove_file(scenes.join("scene_2.json")).unwrap();
    let out = tempfile::tempdir().unwrap();
    let server = mock_server(usize::MAX, out.path().to_owned()).await;
    let url = format!("{}/v1", server.uri());
    let (s, c, o) = (scenes.clone(), csv.clone(), out.path().to_owned());
    let run = tokio::task::spawn_blocking(move || {
        let mut cmd = cli_command(
            &s,
            &c,
            &o,
            &url,
            &[
                "--vlm-temperature",
                "none",
                "--vlm-seed",
                "7",
                "--vlm-detail",
                "high",
                "--vlm-max-tokens",
                "500",
                "--vlm-token-limit-field",
                "max_completion_tokens",
                "--vlm-api-key-env",
                "MY_TEST_VLM_KEY",
            ],
        );
        cmd.env("MY_TEST_VLM_KEY", "sk-named-variable")
            .env_remove("OPENAI_API_KEY")
            .output()
            .unwrap()
    })
    .await
    .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let requests = server.received_requests().await.unwrap();
    assert_eq!(requests.len(), 8, "the endpoint check and scene 8's 7 questions");
    let mut images = 0;
    for r in &requests {
        assert_eq!(
            r.headers.get("authorization").unwrap(),
            "Bearer sk-named-variable"
        );
        let body: Value = r.body_json().unwrap();
        assert!(body.get("temperature").is_none(), "{body}");
        assert!(body.get("max_tokens").is_none(), "{body}");
        assert_eq!(
            (body["seed"].clone(), body["max_completion_tokens"].clone()),
            (json!(7), json!(500))
        );
        for part in body["messages"][1]["content"].as_array().unwrap() {
            if part["type"] == "image_url" {
                images += 1;
                assert_eq!(part["image_url"]["detail"], "high");
            }
        }
    }
    assert!(images > 0);
}

#[test]
fn sampling_options_need_a_vlm() {
    let (_keep, scenes, _csv) = setup();
    let out = tempfile::tempdir().unwrap();
    let run = common::evaluate(
        &scenes,
        &fixtures().join("assets"),
        out.path(),
        &["--vlm-temperature", "0.5"],
    );
    let output = run.get_output();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("--vlm-temperature sets what is sent to the VLM; it needs --vlm-base-url"),
        "{stderr}"
    );
}
