//! An endpoint that goes down mid-run and comes back: fixture scenes 2 and 8 with the full
//! plan against a mock OpenAI-compatible server on 127.0.0.1 (the model of
//! `sceneeval_test_support::fidelity_model`), through the HTTP client and the response cache as
//! `sceneeval evaluate` builds them.
//!
//! The first run's server answers 5 requests, then 503 on every request: the scenes are
//! `partial`, with every geometry result of a clean run and the metrics that needed a missing
//! answer listed with the reason. The server comes back: the second run asks exactly the
//! questions the first did not get answered (the cache has the rest), and every `eval.json` is
//! then byte for byte a clean run's.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[path = "../../sceneeval-vlm-openai/tests/support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use base64::Engine;
use sceneeval_annotation::Annotations;
use sceneeval_eval::{EvaluationPlan, Evaluator, Preset, SharedVlm};
use sceneeval_fidelity::{MatchingMethod, RelationMapping};
use sceneeval_io::AssetLibrary;
use sceneeval_render::{RenderSettings, Renderer};
use sceneeval_run::{BatchOptions, find_scenes, run_batch};
use sceneeval_test_support::fidelity_model::{CSV, answer, copy_scenes, pictured_category};
use sceneeval_vlm::Cached;
use sceneeval_vlm_openai::{OpenAiConfig, OpenAiVlm, RuntimeVlm};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// The PNG bytes of a request's first image (`data:image/png;base64,...`).
fn first_image(body: &Value) -> Option<Vec<u8>> {
    let url = body["messages"][1]["content"][1]["image_url"]["url"].as_str()?;
    let data = url.split_once("base64,")?.1;
    base64::engine::general_purpose::STANDARD.decode(data).ok()
}

/// The questions a mock endpoint answered: each request's messages, as JSON text.
type Answered = Arc<Mutex<Vec<String>>>;

/// A mock endpoint answering like the fixture model; after `budget` answers it is down (503 on
/// every request) until `up` is set. `views` is where the runs write their object views (the
/// model recognises a matching request's object by its front view).
async fn endpoint(
    budget: usize,
    up: Arc<AtomicBool>,
    views: Vec<PathBuf>,
) -> (wiremock::MockServer, Answered) {
    let server = wiremock::MockServer::start().await;
    let answered: Answered = Arc::default();
    let log = answered.clone();
    support::mount_sequence(&server, move |_, req| {
        let body: Value = req.body_json().unwrap();
        {
            let mut log = log.lock().unwrap();
            if !up.load(Ordering::SeqCst) && log.len() >= budget {
                return wiremock::ResponseTemplate::new(503);
            }
            log.push(body["messages"].to_string());
        }
        let task = body["response_format"]["json_schema"]["name"]
            .as_str()
            .unwrap_or("");
        let pictured =
            first_image(&body).and_then(|png| views.iter().find_map(|v| pictured_category(v, &png)));
        support::json_completion(&answer(task, support::user_text(&body), pictured.as_deref()))
    })
    .await;
    (server, answered)
}

/// Runs scenes 2 and 8 (from `scenes`) with the full plan against the server of `config` into
/// `out`, with the response cache in `<out>/vlm-cache`.
fn run(scenes: &Path, config: OpenAiConfig, out: &Path) -> sceneeval_run::BatchOutcome {
    let mut plan = EvaluationPlan::full(Preset::Default);
    plan.fidelity.matching = MatchingMethod::Vlm;
    plan.fidelity.relation_mapping = RelationMapping::Lexicon;
    let client = RuntimeVlm::start(OpenAiVlm::new(config).unwrap()).unwrap();
    let vlm = SharedVlm::new(Cached::new(client, out.join("vlm-cache")));
    let evaluator = Evaluator::new(plan)
        .unwrap()
        .with_vlm(vlm)
        .with_renderer(Renderer::new().unwrap(), RenderSettings::square(64));
    let annotations = Annotations::from_csv_str(CSV).unwrap();
    let options = BatchOptions {
        out_dir: out.to_owned(),
        annotations: Some(&annotations),
        ..BatchOptions::default()
    };
    let assets =
        AssetLibrary::from_specs(&[format!("fixture={}", fixtures().join("assets").display())]).unwrap();
    let set = find_scenes(scenes).unwrap();
    run_batch(&set.scenes, &evaluator, &assets, &options, &|_| {}).unwrap()
}

fn record_text(out: &Path, scene: &str) -> String {
    std::fs::read_to_string(out.join(scene).join("eval.json")).unwrap()
}

fn record(out: &Path, scene: &str) -> Value {
    serde_json::from_str(&record_text(out, scene)).unwrap()
}

/// Runs `f` (a blocking run) off the test's async runtime, which serves the mock endpoint.
async fn blocking<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    tokio::task::spawn_blocking(f).await.unwrap()
}

#[tokio::test]
async fn an_outage_costs_only_what_needed_the_vlm_and_heals_on_re_run() {
    if sceneeval_test_support::system::available(
        &sceneeval_test_support::system::GPU,
        Renderer::new(),
        sceneeval_render::RenderError::is_missing_driver,
    )
    .is_none()
    {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    copy_scenes(&scenes);
    let (clean_out, out) = (dir.path().join("clean"), dir.path().join("out"));
    let views = vec![clean_out.clone(), out.clone()];

    // A clean run: the endpoint never goes down.
    let (always, _) = endpoint(usize::MAX, Arc::new(AtomicBool::new(true)), views.clone()).await;
    let (s, o, c) = (scenes.clone(), clean_out.clone(), support::config(&always));
    let clean = blocking(move || run(&s, c, &o)).await;
    assert_eq!((clean.evaluated, clean.partial, clean.failed), (2, 0, 0));
    // Scene 8: functional sides, 4 matchings, 1 attribute, 1 mapping; scene 2: functional
    // sides, 12 matchings, 1 attribute (the six chairs' identical requests may be answered
    // from the cache: the server sees 16 to 21).
    let answers =
        |out: &Path, scene: &str| record(out, scene)["report"]["fidelity"]["vlm_usage"]["requests"].clone();
    assert_eq!(
        (answers(&clean_out, "scene_8"), answers(&clean_out, "scene_2")),
        (7.into(), 14.into())
    );

    // The endpoint answers 5 requests, then is down.
    let up = Arc::new(AtomicBool::new(false));
    let (flaky, answered) = endpoint(5, up.clone(), views).await;
    let (s, o, c) = (scenes.clone(), out.clone(), support::config(&flaky));
    let first = blocking(move || run(&s, c, &o)).await;
    assert_eq!((first.evaluated, first.partial, first.failed), (2, 2, 0));
    for scene in ["scene_2", "scene_8"] {
        let (r, c) = (record(&out, scene), record(&clean_out, scene));
        assert_eq!(r["status"], "partial", "{r}");
        // Every geometry result is the clean run's.
        for section in [
            "collision",
            "navigability",
            "out_of_bounds",
            "opening_clearance",
            "support",
        ] {
            assert_eq!(r["report"][section], c["report"][section], "{scene} {section}");
        }
        // What needed a missing answer is listed, with the VLM's error; nothing else is.
        let incomplete = r["report"]["incomplete"].as_array().unwrap();
        assert!(!incomplete.is_empty(), "{r}");
        for m in incomplete {
            assert_eq!(m["vlm"], true, "{m}");
            assert!(
                ["accessibility", "cnt", "atr", "oor", "oar"].contains(&m["metric"].as_str().unwrap()),
                "{m}"
            );
            assert!(
                m["error"]
                    .as_str()
                    .unwrap()
                    .starts_with("the VLM could not be asked"),
                "{m}"
            );
            assert!(m["causes"].to_string().contains("HTTP 503"), "{m}");
        }
    }
    let answered_first: Vec<String> = answered.lock().unwrap().clone();
    assert_eq!(answered_first.len(), 5);

    // The endpoint is back: the second run completes both scenes, asking only what the first
    // run did not get answered (its 5 answers are in the cache).
    up.store(true, Ordering::SeqCst);
    let (s, o, c) = (scenes.clone(), out.clone(), support::config(&flaky));
    let second = blocking(move || run(&s, c, &o)).await;
    assert_eq!((second.evaluated, second.partial, second.failed), (2, 0, 0));
    assert!(
        second.statuses.iter().all(|s| matches!(
            s,
            sceneeval_run::SceneStatus::Evaluated {
                why: sceneeval_run::Reason::Incomplete
            }
        )),
        "{:?}",
        second.statuses
    );
    let answered_second: Vec<String> = answered.lock().unwrap()[5..].to_vec();
    assert!(!answered_second.is_empty());
    assert!(
        answered_second.iter().all(|q| !answered_first.contains(q)),
        "a question answered in the first run was asked again"
    );
    for scene in ["scene_2", "scene_8"] {
        assert_eq!(
            record_text(&out, scene),
            record_text(&clean_out, scene),
            "{scene}"
        );
    }
}
