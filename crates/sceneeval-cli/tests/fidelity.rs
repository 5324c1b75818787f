//! The full plan end to end on fixture scenes: with labels and the lexicon (no VLM), with a
//! scripted VLM through the library (renders with lavapipe, 64 px), and through the CLI
//! against a mock OpenAI-compatible server on 127.0.0.1, interrupted and resumed.
//!
//! The annotation rows are written here (not the fixture CSV) so that they hold a spec that
//! fails, an absent object with `eq,0`, a `surround` group and an unmappable phrase. Expected
//! values are worked out by hand in the comments; the fixture geometry behind each relation
//! is described in `crates/sceneeval-fixtures/src/scene_annotations.rs`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;
#[path = "../../sceneeval-vlm-openai/tests/support/mod.rs"]
mod support;

use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

use common::{fixtures, record};
use sceneeval::annotation::Annotations;
use sceneeval::fidelity::{MatchingMethod, RelationMapping};
use sceneeval::io::AssetLibrary;
use sceneeval::render::{RenderSettings, Renderer};
use sceneeval::vlm::{AnswerContent, Scripted, VlmRequest};
use sceneeval::{
    BatchOptions, EvaluationPlan, Evaluator, Preset, SharedVlm, annotation_digest, find_scenes, run_batch,
};
use serde_json::{Value, json};

/// Scene 8: wardrobe, bed, nightstand, ceiling lamp. Scene 2: dining table, six chairs,
/// ceiling lamp, bookshelf, plant, floor lamp, painting.
const CSV: &str = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
8,easy,A small bedroom.,\"eq,1,wardrobe; eq,1,bed; eq,1,nightstand; eq,1,ceiling_lamp; eq,0,tv; eq,2,chair\",\
\"eq,1,wardrobe,tall\",\"eq,1,next_to,0,bed,nightstand; eq,1,in_harmony_with,0,bed,wardrobe\",\
\"eq,1,against,bed,wall; eq,1,next_to,wardrobe,door\"\n\
2,hard,A dining room.,\"eq,1,dining_table; eq,6,chair; eq,1,ceiling_lamp; eq,1,bookshelf; eq,1,plant; eq,1,floor_lamp; eq,1,painting\",\
\"eq,6,chair,wooden\",\"eq,1,surround,0,dining_table,chair:0,chair:1,chair:2,chair:3,chair:4,chair:5; eq,6,next_to,0,dining_table,chair\",\
\"eq,1,corner,plant,room; eq,1,hang,ceiling_lamp,ceiling\"\n";

/// The scene order of each scene's objects, by its matching prompt's category list.
const SCENE_8: [&str; 4] = ["wardrobe", "bed", "nightstand", "ceiling_lamp"];
const SCENE_2: [&str; 12] = [
    "dining_table",
    "chair",
    "chair",
    "chair",
    "chair",
    "chair",
    "chair",
    "ceiling_lamp",
    "bookshelf",
    "plant",
    "floor_lamp",
    "painting",
];

fn setup() -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
    setup_with(CSV)
}

fn setup_with(csv_text: &str) -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    for n in [2, 8] {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), scenes.join(&name)).unwrap();
    }
    let csv = dir.path().join("annotations.csv");
    std::fs::write(&csv, csv_text).unwrap();
    (dir, scenes, csv)
}

/// What a model answers to each task (shared by the scripted model and the mock server): the
/// nightstand of scene 8 is not recognised; the wardrobe is tall; five of the six chairs are
/// wooden; "in_harmony_with" maps to no predicate; every object's functional side is its
/// front (the fixture scenes state every support type, so none is asked). `nth_matching` is the object's position in
/// its scene.
fn answer(task: &str, user_text: &str, nth_matching: usize) -> Value {
    match task {
        "obj_matching" => {
            let scene8 = user_text.contains("\"wardrobe\"");
            let category = if scene8 {
                SCENE_8[nth_matching]
            } else {
                SCENE_2[nth_matching]
            };
            let matched = category != "nightstand";
            json!({"provided_categories": [], "matched": matched,
                   "matched_category": if matched { category } else { "" },
                   "actual_category": category, "reason": format!("looks like a {category}")})
        }
        "obj_attribute" if user_text.contains("\"wardrobe\"") => json!({
            "category": "wardrobe", "num_instances": 1,
            "assessments": [{"instance": 0, "attribute": "tall", "satisfied": true, "reason": "2 m"}]}),
        "obj_attribute" => json!({
            "category": "chair", "num_instances": 6,
            "assessments": (0..6).map(|i| json!({"instance": i, "attribute": "wooden", "satisfied": i != 5,
                                                  "reason": format!("chair {i}")})).collect::<Vec<_>>()}),
        // Every object described in the prompt (`obj_id: "<id>", ...`) is used from the front.
        "obj_functional_sides" => json!({"assessments": user_text
            .split("obj_id: \"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
            .map(|id| json!({"obj_id": id, "obj_description": "", "functional_sides": ["front"], "reason": "used from the front"}))
            .collect::<Vec<_>>()}),
        "obj_support_type" => json!({"support_type": "ground", "reason": "on the floor"}),
        "obj_relationship_mapping" => json!({"assessments": [{
            "key": "1", "relationship": "in_harmony_with", "anchor_object": "bed",
            "other_objects": ["wardrobe"], "other_object_counts": [1],
            "relationship_types": null, "sides": [], "reason": "not spatial"}]}),
        other => panic!("unexpected task {other}"),
    }
}

/// Counts matching requests per category list (one list per scene), so that the n-th request
/// of a scene is its n-th object whatever the order scenes run in.
#[derive(Default)]
struct Nth(Mutex<HashMap<String, usize>>);

impl Nth {
    fn next(&self, task: &str, user_text: &str) -> usize {
        if task != "obj_matching" {
            return 0;
        }
        let mut m = self.0.lock().unwrap();
        let n = m.entry(user_text.to_owned()).or_default();
        *n += 1;
        *n - 1
    }
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

fn run_library(plan: EvaluationPlan, vlm: Option<SharedVlm>, out: &Path) -> sceneeval::BatchOutcome {
    run_library_with(CSV, plan, vlm, out)
}

fn run_library_with(
    csv_text: &str,
    plan: EvaluationPlan,
    vlm: Option<SharedVlm>,
    out: &Path,
) -> sceneeval::BatchOutcome {
    let (_keep, scenes, csv) = setup_with(csv_text);
    let annotations = Annotations::read(&csv).unwrap();
    let set = find_scenes(&scenes).unwrap();
    let mut options = BatchOptions {
        out_dir: out.to_owned(),
        ..BatchOptions::default()
    };
    for s in &set.scenes {
        let row = annotations.get(&s.id.to_string()).unwrap();
        options.annotations.insert(s.name.clone(), annotation_digest(row));
        options.rows.insert(s.name.clone(), row.clone());
    }
    let mut evaluator = Evaluator::new(plan).unwrap();
    if let Some(vlm) = vlm {
        evaluator = evaluator
            .with_vlm(vlm)
            .with_renderer(Renderer::new().unwrap(), RenderSettings::square(64));
    }
    let assets =
        AssetLibrary::from_specs(&[format!("fixture={}", fixtures().join("assets").display())]).unwrap();
    run_batch(&set.scenes, &evaluator, &assets, &options, &|_, _, _| {}).unwrap()
}

#[test]
fn full_plan_with_labels_and_the_lexicon() {
    let out = tempfile::tempdir().unwrap();
    let outcome = run_library(EvaluationPlan::full(Preset::Default), None, out.path());
    assert_eq!(outcome.failed, 0);
    // Scene 8. CNT: wardrobe, bed, nightstand, ceiling lamp 1 each (yes x4), tv eq,0 (yes),
    // chair eq,2 with none (no): 5/6. ATR: not judged without a VLM (null). OOR: the
    // nightstand stands 5 cm from the bed: 1 group of 1, satisfied (yes); in_harmony_with is not
    // in the lexicon and there is no VLM: unmapped (no): 1/2. OAR: bed against a wall, wardrobe
    // in front of the door: 2/2.
    assert_eq!(
        scores(out.path(), "scene_8"),
        [json!(5.0 / 6.0), Value::Null, json!(0.5), json!(1.0)]
    );
    // Scene 2. CNT 7/7; ATR null; OOR: surround of the six chairs (1 group of C(6,6), yes),
    // each chair next to the table (6 groups, 6 satisfied, yes): 2/2; OAR: plant in a corner,
    // lamp on the ceiling: 2/2.
    assert_eq!(
        scores(out.path(), "scene_2"),
        [json!(1.0), Value::Null, json!(1.0), json!(1.0)]
    );
    let r8 = record(out.path(), "scene_8");
    let oor = &r8["report"]["fidelity"]["oor"]["specs"];
    assert_eq!(oor[1]["mapping"]["status"], "unmapped");
    assert_eq!(r8["report"]["fidelity"]["atr"]["score"], Value::Null);
    let m: Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("scene_8/matching.json")).unwrap())
            .unwrap();
    assert_eq!(m["source"], "labels");
    assert_eq!(m["per_category"]["tv"], json!({}));
}

#[test]
fn full_plan_with_a_scripted_vlm() {
    if common::renderer().is_none() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let nth = Nth::default();
    let vlm = Scripted::from_fn("scripted", move |req: &VlmRequest| {
        let n = nth.next(&req.task, &req.user_text);
        Ok(AnswerContent::Json {
            value: answer(&req.task, &req.user_text, n),
        })
    });
    let mut plan = EvaluationPlan::full(Preset::Default);
    plan.fidelity.matching = MatchingMethod::Vlm;
    plan.fidelity.relation_mapping = RelationMapping::Lexicon;
    let outcome = run_library(plan, Some(SharedVlm::new(vlm)), out.path());
    assert_eq!(outcome.failed, 0, "{:?}", outcome.records);
    // Scene 8, the nightstand unrecognised. CNT: wardrobe, bed, ceiling lamp (yes x3),
    // nightstand 0 (no), tv eq,0 (yes), chair (no): 4/6. ATR: the wardrobe is tall, 1 of eq,1
    // (yes): 1/1. OOR: next_to fails its presence gate (no nightstand; eq,1 does not allow 0);
    // in_harmony_with goes to the VLM, which finds no predicate (no): 0/2. OAR 2/2.
    assert_eq!(
        scores(out.path(), "scene_8"),
        [json!(4.0 / 6.0), json!(1.0), json!(0.0), json!(1.0)]
    );
    // Scene 2. CNT 7/7; ATR: 5 wooden chairs of eq,6 (no): 0/1; OOR 2/2; OAR 2/2.
    assert_eq!(
        scores(out.path(), "scene_2"),
        [json!(1.0), json!(0.0), json!(1.0), json!(1.0)]
    );
    let r8 = record(out.path(), "scene_8");
    let f8 = &r8["report"]["fidelity"];
    // Requests: 1 functional sides (for accessibility) + 4 matching + 1 attribute + 1 mapping;
    // views: 4 front + 1 size, each once.
    assert_eq!(f8["vlm_usage"]["requests"], 7);
    // Accessibility used the VLM's sides: between the scene (states none) and the tables.
    let acc = &r8["report"]["accessibility"]["objects"];
    assert!(
        acc.as_array().unwrap().iter().all(|o| o["sides_source"] == "vlm"),
        "{acc}"
    );
    assert_eq!(f8["views_rendered"], 5);
    assert_eq!(f8["oor"]["specs"][1]["mapping"]["source"], "vlm");
    let f2 = &record(out.path(), "scene_2")["report"]["fidelity"];
    // 1 functional sides + 12 matching + 1 attribute; 12 front + 6 size views.
    assert_eq!(f2["vlm_usage"]["requests"], 14);
    assert_eq!(f2["views_rendered"], 18);
    assert_eq!(f2["atr"]["specs"][0]["count_satisfied"], 5);
    let pngs = std::fs::read_dir(out.path().join("scene_2/views"))
        .unwrap()
        .count();
    assert_eq!(pngs, 18, "every view written once");
}

/// A mock OpenAI-compatible server answering like [`answer`]; after `budget` answers it
/// refuses every request with 401 (a permanent error: the run stops asking). `nth` counts
/// the matching requests over all servers of a test (the cache answers the others).
async fn mock_server(budget: usize, nth: Arc<Nth>) -> wiremock::MockServer {
    let server = wiremock::MockServer::start().await;
    support::mount_sequence(&server, move |i, req| {
        if i >= budget {
            return wiremock::ResponseTemplate::new(401)
                .set_body_json(json!({"error": {"message": "key revoked"}}));
        }
        let body: Value = req.body_json().unwrap();
        let task = body["response_format"]["json_schema"]["name"]
            .as_str()
            .unwrap_or("")
            .to_owned();
        let text = support::user_text(&body).to_owned();
        let n = nth.next(&task, &text);
        support::json_completion(&answer(&task, &text, n))
    })
    .await;
    server
}

fn cli_run(scenes: &Path, csv: &Path, out: &Path, url: &str) -> assert_cmd::assert::Assert {
    cli_command(scenes, csv, out, url, &[]).assert()
}

/// `sceneeval evaluate` with the full plan, the VLM at `url`, and `extra` options.
fn cli_command(scenes: &Path, csv: &Path, out: &Path, url: &str, extra: &[&str]) -> assert_cmd::Command {
    let mut args = vec![
        "--annotations",
        csv.to_str().unwrap(),
        "--plan",
        "full",
        "--vlm-base-url",
        url,
        "--vlm-model",
        "test-model",
        "--relation-mapping",
        "lexicon",
        "--render-size",
        "64",
        "--threads",
        "1",
    ];
    args.extend_from_slice(extra);
    common::evaluate_command(scenes, &fixtures().join("assets"), out, &args)
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
    // first server answers 3, then the key is "revoked": the scene fails, the 3 answers are in
    // the cache.
    let nth = Arc::new(Nth::default());
    let first = mock_server(3, nth.clone()).await;
    let url = format!("{}/v1", first.uri());
    let (s, c, o) = (scenes.clone(), csv.clone(), out.path().to_owned());
    let a = tokio::task::spawn_blocking(move || cli_run(&s, &c, &o, &url).get_output().clone())
        .await
        .unwrap();
    assert!(!a.status.success());
    assert_eq!(record(out.path(), "scene_8")["status"], "failed");
    let answered_first = support::bodies(&first).await.len();
    assert!(
        answered_first >= 4,
        "3 answered and at least one refused: {answered_first}"
    );
    // The second run asks only the 4 questions not answered before.
    let second = mock_server(usize::MAX, nth.clone()).await;
    let url = format!("{}/v1", second.uri());
    let (s, c, o) = (scenes.clone(), csv.clone(), out.path().to_owned());
    let b = tokio::task::spawn_blocking(move || cli_run(&s, &c, &o, &url).get_output().clone())
        .await
        .unwrap();
    assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    assert_eq!(support::bodies(&second).await.len(), 4);
    assert_eq!(
        scores(out.path(), "scene_8"),
        [json!(4.0 / 6.0), json!(1.0), json!(0.0), json!(1.0)]
    );
    let usage = &record(out.path(), "scene_8")["report"]["fidelity"]["vlm_usage"];
    assert_eq!(
        (usage["requests"].clone(), usage["cache_hits"].clone()),
        (json!(7), json!(3))
    );
    // A third run of the finished run sends nothing at all (the record is reused).
    let third = mock_server(usize::MAX, nth).await;
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
    assert!(all.starts_with("all,2,2,0,91.6667,,75.0000,100.0000,"), "{all}");
    assert!(all.ends_with(",2,0,2,2"), "{all}");
    // Per difficulty: easy is scene 8, hard scene 2.
    assert!(
        csv_out.contains("\neasy,1,1,0,83.3333,,50.0000,100.0000,"),
        "{csv_out}"
    );
    assert!(
        csv_out.contains("\nhard,1,1,0,100.0000,,100.0000,100.0000,"),
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

#[test]
fn a_changed_annotation_row_invalidates_only_its_record() {
    let out = tempfile::tempdir().unwrap();
    let plan = || EvaluationPlan::full(Preset::Default);
    assert_eq!(run_library(plan(), None, out.path()).evaluated, 2);
    assert_eq!(run_library(plan(), None, out.path()).reused, 2);
    // Scene 8 now asks for one chair less; scene 2's row is unchanged.
    let changed = CSV.replace("eq,0,tv; eq,2,chair", "eq,0,tv; eq,1,chair");
    let again = run_library_with(&changed, plan(), None, out.path());
    assert_eq!((again.evaluated, again.reused), (1, 1));
    assert!(again.statuses.iter().any(|s| matches!(
        s,
        sceneeval::SceneStatus::Evaluated { why: sceneeval::Reason::Changed(w) } if w.contains("annotation row")
    )));
}

#[tokio::test]
async fn sampling_options_reach_every_request_and_the_key_variable_is_used() {
    if common::renderer().is_none() {
        return;
    }
    let (_keep, scenes, csv) = setup();
    std::fs::remove_file(scenes.join("scene_2.json")).unwrap();
    let out = tempfile::tempdir().unwrap();
    let server = mock_server(usize::MAX, Arc::new(Nth::default())).await;
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
    assert_eq!(requests.len(), 7, "scene 8's questions");
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
