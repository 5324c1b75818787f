//! `sceneeval evaluate` with a VLM, against the mock endpoint of
//! `sceneeval_test_support::mock_endpoint` on 127.0.0.1: the endpoint check before the first
//! scene (an unreachable server or a refused key stops the run at once, writing nothing), VLM
//! options a geometry plan does not use, `--dry-run` (what the run would send, nothing sent),
//! an unwritable cache folder, and Ctrl-C keeping every answer already received.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use std::path::{Path, PathBuf};
use std::time::Duration;

use common::fixtures;
use sceneeval_test_support::fidelity_model::CSV;
use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion, error, generic_answer, task_of};
use serde_json::Value;

/// Fixture scenes 2 and 8 with their annotation rows, in a new folder.
fn setup() -> (tempfile::TempDir, PathBuf, PathBuf) {
    common::scenes_2_and_8(CSV)
}

/// `sceneeval evaluate` with the full plan and the VLM at `url`
/// ([`common::full_plan_command`]), without `OPENAI_API_KEY`.
fn full(scenes: &Path, csv: &Path, out: &Path, url: &str, extra: &[&str]) -> std::process::Output {
    common::full_plan_command(scenes, csv, out, url, extra)
        .env_remove("OPENAI_API_KEY")
        .output()
        .unwrap()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The rows of `--dry-run`'s table: task -> (requests, from the cache, to send).
fn dry_rows(stdout: &[u8]) -> Vec<(String, [u64; 3])> {
    String::from_utf8_lossy(stdout)
        .lines()
        .filter_map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            let n = |i: usize| cells.get(i)?.split(' ').next()?.parse::<u64>().ok();
            Some((cells.get(1)?.to_string(), [n(2)?, n(3)?, n(4)?]))
        })
        .collect()
}

fn row(rows: &[(String, [u64; 3])], task: &str) -> [u64; 3] {
    rows.iter()
        .find(|(t, _)| t == task)
        .map(|(_, r)| *r)
        .unwrap_or_else(|| panic!("no {task} in {rows:?}"))
}

#[test]
fn an_unreachable_endpoint_stops_the_run_before_the_first_scene() {
    if common::renderer().is_none() {
        return;
    }
    let (_keep, scenes, csv) = setup();
    let out = tempfile::tempdir().unwrap();
    // A port nothing listens on: bound, then closed.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let run = full(
        &scenes,
        &csv,
        out.path(),
        &format!("http://127.0.0.1:{port}/v1"),
        &[],
    );
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(
        err.contains("--vlm-base-url: the endpoint check before the first scene got no answer"),
        "{err}"
    );
    assert!(err.contains("could not reach"), "{err}");
    assert!(!out.path().join("scene_2/eval.json").exists());
    assert!(!out.path().join("scene_8/eval.json").exists());
}

#[test]
fn a_refused_key_stops_the_run_with_one_message() {
    if common::renderer().is_none() {
        return;
    }
    let (_keep, scenes, csv) = setup();
    let out = tempfile::tempdir().unwrap();
    let server = MockEndpoint::start(Duration::ZERO, |_, _| {
        error(401, "Incorrect API key provided: sk-cli-SECRET-key-0042")
    });
    let extra = ["--vlm-api-key-env", "MY_TEST_VLM_KEY", "-vv"];
    let run = common::full_plan_command(&scenes, &csv, out.path(), &server.url(), &extra)
        .env("MY_TEST_VLM_KEY", "sk-cli-SECRET-key-0042")
        .output()
        .unwrap();
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(err.contains("API key refused (HTTP 401)"), "{err}");
    assert!(
        err.contains("the key came from environment variable MY_TEST_VLM_KEY"),
        "{err}"
    );
    // Neither the message nor the debug log shows the key.
    assert!(!err.contains("SECRET"), "{err}");
    assert_eq!(server.requests(), 1, "one check, no retry, no scene");
    assert!(!out.path().join("scene_8/eval.json").exists());
}

#[test]
fn vlm_options_with_a_plan_that_asks_no_vlm_are_reported_unused_and_still_checked() {
    let (_keep, scenes, _csv) = setup();
    let out = tempfile::tempdir().unwrap();
    let server = MockEndpoint::start(Duration::ZERO, |_, body| completion(&generic_answer(body)));
    let vlm = [
        "--plan",
        "collision",
        "--vlm-base-url",
        &server.url(),
        "--vlm-model",
        "m",
    ];
    let run = common::evaluate(&scenes, &fixtures().join("assets"), out.path(), &vlm).success();
    let err = stderr(run.get_output());
    assert!(
        err.contains("warning: the plan runs no text-fidelity metric (cnt, atr, oor, oar), so the VLM options are not used"),
        "{err}"
    );
    assert_eq!(server.requests(), 0);
    // A bad value is refused all the same.
    let bad = common::evaluate(
        &scenes,
        &fixtures().join("assets"),
        out.path(),
        &[&vlm[..], &["--vlm-timeout-s", "0"]].concat(),
    )
    .failure();
    let err = stderr(bad.get_output());
    assert!(
        err.contains("--vlm-timeout-s: 0 is not a number of seconds above 0"),
        "{err}"
    );
}

#[test]
fn a_dry_run_sends_nothing_and_counts_what_the_run_sends() {
    if common::renderer().is_none() {
        return;
    }
    let (_keep, scenes, csv) = setup();
    let out = tempfile::tempdir().unwrap();
    let server = MockEndpoint::start(Duration::ZERO, |_, body| completion(&generic_answer(body)));
    // Nothing cached: every question to send; the attribute requests estimated (one per ObjAttr
    // entry: scene 8's wardrobe, scene 2's chairs).
    let dry = full(&scenes, &csv, out.path(), &server.url(), &["--dry-run"]);
    assert!(dry.status.success(), "{}", stderr(&dry));
    assert_eq!(server.requests(), 0, "a dry run sends nothing");
    assert!(!out.path().join("scene_8").exists(), "and writes nothing");
    let rows = dry_rows(&dry.stdout);
    // One matching request per object: 12 in scene 2, 4 in scene 8.
    assert_eq!(row(&rows, "obj_matching"), [16, 0, 16]);
    assert_eq!(row(&rows, "obj_attribute"), [2, 0, 2]);
    let text = String::from_utf8_lossy(&dry.stdout);
    assert!(text.contains("2 scenes, 2 to evaluate, 0 kept"), "{text}");
    assert!(text.contains("| 2 (2 estimated) |"), "{text}");

    // The run, then a dry run of the same again (--force): everything from the cache, and as
    // many requests as the run made (its `vlm_usage`).
    let run = full(&scenes, &csv, out.path(), &server.url(), &[]);
    assert!(run.status.success(), "{}", stderr(&run));
    let sent: Vec<String> = server.bodies().iter().map(|b| task_of(b).to_owned()).collect();
    assert_eq!(sent[0], "endpoint_check", "{sent:?}");
    let usage = |field: &str| -> u64 {
        ["scene_2", "scene_8"]
            .iter()
            .map(|s| {
                common::record(out.path(), s)["report"]["fidelity"]["vlm_usage"][field]
                    .as_u64()
                    .unwrap()
            })
            .sum()
    };
    // Identical requests (the six identical chairs' views) are answered by the cache after
    // the first: what the run made (the records' `requests`, fresh and cached answers alike)
    // is what it sent (but the check) and those, as its closing lines say.
    let made = usage("requests");
    let fresh = sent.len() as u64 - 1;
    let log = stderr(&run);
    let line = format!(" {fresh} VLM requests sent (");
    let cached = format!("), {} answered from the cache, 0 failed", made - fresh);
    assert!(
        log.contains(&line) && log.contains(&cached),
        "{made} made, {fresh} sent: {log}"
    );
    let again = full(
        &scenes,
        &csv,
        out.path(),
        &server.url(),
        &["--dry-run", "--force"],
    );
    assert!(again.status.success(), "{}", stderr(&again));
    let rows = dry_rows(&again.stdout);
    // A dry run does not count re-asks; the relation mappings the mock leaves empty (each
    // asked again once, then unanswered) have no usable answer, so none was cached: the only
    // questions a re-run sends again.
    let re_asks = usage("re_asks");
    assert!(re_asks > 0, "the mock leaves relation mappings empty");
    assert_eq!(row(&rows, "total"), [made - re_asks, made - 2 * re_asks, re_asks]);
    assert_eq!(server.requests(), sent.len(), "the dry runs sent nothing");
    // Without --force the results are kept: nothing to ask.
    let kept = full(&scenes, &csv, out.path(), &server.url(), &["--dry-run"]);
    let text = String::from_utf8_lossy(&kept.stdout);
    assert!(text.contains("2 scenes, 0 to evaluate, 2 kept"), "{text}");
}

#[test]
fn an_unwritable_cache_costs_a_warning_not_the_scenes() {
    if common::renderer().is_none() {
        return;
    }
    let (keep, scenes, csv) = setup();
    std::fs::remove_file(scenes.join("scene_2.json")).unwrap();
    let out = tempfile::tempdir().unwrap();
    // The cache folder would be below a regular file: it cannot be made.
    let blocker = keep.path().join("not-a-folder");
    std::fs::write(&blocker, "x").unwrap();
    let cache = blocker.join("cache");
    let server = MockEndpoint::start(Duration::ZERO, |_, body| completion(&generic_answer(body)));
    let run = full(
        &scenes,
        &csv,
        out.path(),
        &server.url(),
        &["--vlm-cache", cache.to_str().unwrap()],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let err = stderr(&run);
    assert!(err.contains("warning: the VLM cache folder"), "{err}");
    assert!(err.contains("cannot be written"), "{err}");
    assert_eq!(common::record(out.path(), "scene_8")["status"], "ok");
}

#[cfg(unix)]
#[test]
fn ctrl_c_keeps_every_answer_already_received() {
    if common::renderer().is_none() {
        return;
    }
    let (_keep, scenes, csv) = setup();
    std::fs::remove_file(scenes.join("scene_2.json")).unwrap();
    let out = tempfile::tempdir().unwrap();
    let cache = out.path().join("vlm-cache");
    // The check and two answers come at once; the third request is held for a minute.
    let server = MockEndpoint::start(Duration::ZERO, |n, body| {
        if n == 3 {
            std::thread::sleep(Duration::from_secs(60));
        }
        completion(&generic_answer(body))
    });
    let args = common::full_plan_args(&csv, &server.url(), &["--vlm-concurrency", "1"]);
    let assets = format!("fixture={}", fixtures().join("assets").display());
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("sceneeval"))
        .arg("evaluate")
        .arg(&scenes)
        .args(["--assets", &assets, "--no-progress", "--out"])
        .arg(out.path())
        .args(args)
        .env_remove("OPENAI_API_KEY")
        .stderr(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while server.requests() < 4 {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the run did not get to its 4th request"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    // The two answers were received before the held request was sent (one at a time).
    std::thread::sleep(Duration::from_millis(200));
    let sent = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let status = child.wait().unwrap();
    assert!(!status.success());
    let files: Vec<PathBuf> = walk(&cache)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    assert_eq!(files.len(), 2, "the two answers received: {files:?}");
    for f in &files {
        let record: Value = serde_json::from_str(&std::fs::read_to_string(f).unwrap()).unwrap();
        assert_eq!(record["format"], "sceneeval.vlm-cache/1");
    }
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}
