//! `OpenAiVlm` against a mock OpenAI-compatible server on 127.0.0.1 (wiremock): the request
//! shape, retries, timeouts, refusals, truncation, invalid answers, pairing by key, the cache
//! and the concurrency limit.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod support;

use std::sync::Arc;
use std::time::Duration;

use base64::Engine;
use sceneeval_relations::Relation;
use sceneeval_vlm::check::{EndpointCheck, test_image};
use sceneeval_vlm::tasks::{
    FunctionalSidesTask, ObjectMatchingTask, ObjectRelationSpec, ObjectRelationTask, ObjectToDescribe,
    SupportTypeTask,
};
use sceneeval_vlm::{Cached, Outcome, Session, Single, UnansweredKind, VlmError};
use sceneeval_vlm_openai::{ApiKey, OpenAiError, OpenAiVlm, TokenLimitField};
use serde_json::{Value, json};
use support::{bodies, completion, config, json_completion, mount_sequence, user_text};
use wiremock::{MockServer, ResponseTemplate};

fn openai_error(e: &VlmError) -> &OpenAiError {
    let VlmError::Backend { source, .. } = e else {
        panic!("not a backend error: {e}")
    };
    source.downcast_ref::<OpenAiError>().expect("an OpenAiError")
}

fn support_ok() -> Value {
    json!({"support_type": "ground", "reason": "It stands on the floor."})
}

#[tokio::test]
async fn request_has_the_documented_shape() {
    let server = MockServer::start().await;
    mount_sequence(&server, |_, _| json_completion(&support_ok())).await;
    let key = ApiKey::new("sk-shape-test-key", "a test");
    let vlm = OpenAiVlm::new(config(&server).with_api_key(Some(key))).unwrap();
    let session = Session::new(&vlm);
    let task = SupportTypeTask::new(test_image(), test_image());
    let expected = session.request(&task).unwrap();
    let answers = session.ask(&task).await.unwrap();
    assert!(answers.get(&Single).unwrap().is_answered());

    let requests = server.received_requests().await.unwrap();
    assert_eq!(requests.len(), 1);
    let r = &requests[0];
    assert_eq!(r.url.path(), "/v1/chat/completions");
    assert_eq!(
        r.headers.get("authorization").unwrap(),
        "Bearer sk-shape-test-key"
    );
    assert_eq!(r.headers.get("content-type").unwrap(), "application/json");
    let body: Value = r.body_json().unwrap();
    assert_eq!(body["model"], "test-model");
    assert_eq!(body["seed"], 42);
    assert_eq!(body["temperature"], 0.0);
    assert!(body.get("max_tokens").is_none());
    assert_eq!(
        body["messages"][0],
        json!({"role": "system", "content": expected.system})
    );
    let content = body["messages"][1]["content"].as_array().unwrap();
    assert_eq!(body["messages"][1]["role"], "user");
    assert_eq!(content.len(), 3, "text, then two images");
    assert_eq!(content[0], json!({"type": "text", "text": expected.user_text}));
    let png_b64 = base64::engine::general_purpose::STANDARD.encode(test_image().bytes());
    for part in &content[1..] {
        assert_eq!(part["type"], "image_url");
        assert_eq!(part["image_url"]["detail"], "low");
        assert_eq!(
            part["image_url"]["url"],
            format!("data:image/png;base64,{png_b64}")
        );
    }
    let format = &body["response_format"];
    assert_eq!(format["type"], "json_schema");
    assert_eq!(format["json_schema"]["name"], "obj_support_type");
    assert_eq!(format["json_schema"]["strict"], true);
    assert_eq!(format["json_schema"]["schema"], expected.schema.schema);
    // Properties are sent in declaration order.
    let text = String::from_utf8(r.body.clone()).unwrap();
    assert!(text.find("\"support_type\":{").unwrap() < text.find("\"reason\":{").unwrap());

    let usage = session.usage();
    assert_eq!(
        (usage.tokens.prompt_tokens, usage.tokens.completion_tokens),
        (100, 20)
    );
}

#[tokio::test]
async fn token_limit_goes_in_the_chosen_field_and_unset_settings_are_not_sent() {
    let server = MockServer::start().await;
    mount_sequence(&server, |_, _| json_completion(&support_ok())).await;
    let task = SupportTypeTask::new(test_image(), test_image());
    for field in [TokenLimitField::MaxTokens, TokenLimitField::MaxCompletionTokens] {
        let mut c = config(&server);
        c.temperature = None;
        c.seed = None;
        c.max_tokens = Some(321);
        c.token_limit_field = field;
        let vlm = OpenAiVlm::new(c).unwrap();
        Session::new(&vlm).ask(&task).await.unwrap();
    }
    let requests = server.received_requests().await.unwrap();
    assert_eq!(requests.len(), 2);
    let bodies: Vec<Value> = requests.iter().map(|r| r.body_json().unwrap()).collect();
    for body in &bodies {
        assert!(body.get("temperature").is_none(), "{body}");
        assert!(body.get("seed").is_none(), "{body}");
    }
    assert_eq!(bodies[0]["max_tokens"], 321);
    assert!(bodies[0].get("max_completion_tokens").is_none());
    assert_eq!(bodies[1]["max_completion_tokens"], 321);
    assert!(bodies[1].get("max_tokens").is_none());
}

#[tokio::test]
async fn no_key_means_no_authorization_header() {
    let server = MockServer::start().await;
    mount_sequence(&server, |_, _| json_completion(&support_ok())).await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    Session::new(&vlm)
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap();
    let requests = server.received_requests().await.unwrap();
    assert!(requests[0].headers.get("authorization").is_none());
}

#[tokio::test]
async fn rate_limit_honours_retry_after() {
    let server = MockServer::start().await;
    let count = mount_sequence(&server, |n, _| match n {
        0 => ResponseTemplate::new(429)
            .insert_header("Retry-After", "1")
            .set_body_json(json!({"error": {"message": "Rate limit reached", "type": "requests"}})),
        _ => json_completion(&support_ok()),
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let answers = Session::new(&vlm)
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap();
    assert!(answers.get(&Single).unwrap().is_answered());
    assert_eq!(count.load(std::sync::atomic::Ordering::SeqCst), 2);
    let stats = vlm.stats();
    assert_eq!((stats.attempts, stats.retries), (2, 1));
    assert_eq!(
        stats.waited,
        Duration::from_secs(1),
        "the server's Retry-After, not the 1 ms backoff"
    );
}

#[tokio::test]
async fn retry_after_ms_and_too_long_waits() {
    let server = MockServer::start().await;
    mount_sequence(&server, |n, _| match n {
        0 => ResponseTemplate::new(503).insert_header("retry-after-ms", "20"),
        1 => ResponseTemplate::new(429).insert_header("Retry-After", "3600"),
        _ => json_completion(&support_ok()),
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let err = Session::new(&vlm)
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap_err();
    let OpenAiError::RetryAfterTooLong { retry_after, .. } = openai_error(&err) else {
        panic!("{err:?}")
    };
    assert_eq!(*retry_after, Duration::from_secs(3600));
    assert_eq!(vlm.stats().waited, Duration::from_millis(20));
}

#[tokio::test]
async fn server_errors_are_retried_then_reported() {
    let server = MockServer::start().await;
    let count = mount_sequence(&server, |n, _| match n {
        0 => ResponseTemplate::new(500).set_body_string("internal error"),
        1 => ResponseTemplate::new(502),
        _ => json_completion(&support_ok()),
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let session = Session::new(&vlm);
    assert!(
        session
            .ask(&SupportTypeTask::new(test_image(), test_image()))
            .await
            .is_ok()
    );
    assert_eq!(count.load(std::sync::atomic::Ordering::SeqCst), 3);
    assert_eq!(vlm.stats().retries, 2);

    // Always 500: three attempts (two retries), then an error naming status and attempts.
    let server = MockServer::start().await;
    let count = mount_sequence(&server, |_, _| {
        ResponseTemplate::new(500).set_body_json(json!({"error": {"message": "The server had an error"}}))
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let session = Session::new(&vlm);
    let err = session
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap_err();
    assert!(!err.is_permanent());
    let e = openai_error(&err);
    assert!(
        matches!(
            e,
            OpenAiError::Status {
                status: 500,
                attempts: 3,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("The server had an error"), "{e}");
    assert_eq!(count.load(std::sync::atomic::Ordering::SeqCst), 3);
    assert_eq!(session.usage().failed_requests, 1);
}

#[tokio::test]
async fn slow_answers_time_out_and_are_retried() {
    let server = MockServer::start().await;
    mount_sequence(&server, |n, _| match n {
        0 => json_completion(&support_ok()).set_delay(Duration::from_secs(5)),
        _ => json_completion(&support_ok()),
    })
    .await;
    let mut c = config(&server);
    c.timeout = Duration::from_secs(1);
    let vlm = OpenAiVlm::new(c).unwrap();
    let answers = Session::new(&vlm)
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap();
    assert!(answers.get(&Single).unwrap().is_answered());
    assert_eq!(vlm.stats().retries, 1);

    let server = MockServer::start().await;
    mount_sequence(&server, |_, _| {
        json_completion(&support_ok()).set_delay(Duration::from_secs(3))
    })
    .await;
    let mut c = config(&server);
    c.retry.max_retries = 1;
    c.timeout = Duration::from_millis(200);
    let vlm = OpenAiVlm::new(c).unwrap();
    let err = Session::new(&vlm)
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap_err();
    let e = openai_error(&err);
    assert!(matches!(e, OpenAiError::Timeout { attempts: 2, .. }), "{e}");
}

#[tokio::test]
async fn key_refused_is_reported_at_once() {
    let server = MockServer::start().await;
    let count = mount_sequence(&server, |_, _| {
        ResponseTemplate::new(401).set_body_json(json!({"error": {
            "message": "Incorrect API key provided: sk-refu****-key. You can find your API key at https://platform.openai.com/account/api-keys.",
            "type": "invalid_request_error", "code": "invalid_api_key"}}))
    })
    .await;
    let key = ApiKey::new("sk-refused-test-key", "environment variable MY_KEY");
    let vlm = OpenAiVlm::new(config(&server).with_api_key(Some(key))).unwrap();
    let err = Session::new(&vlm).ask(&EndpointCheck::new()).await.unwrap_err();
    assert!(err.is_permanent());
    let e = openai_error(&err);
    let text = e.to_string();
    assert!(text.starts_with("API key refused (HTTP 401)"), "{text}");
    assert!(text.contains("MY_KEY") && !text.contains("sk-"), "{text}");
    assert_eq!(count.load(std::sync::atomic::Ordering::SeqCst), 1, "not retried");

    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let err = Session::new(&vlm).ask(&EndpointCheck::new()).await.unwrap_err();
    assert!(
        openai_error(&err)
            .to_string()
            .contains("no API key was sent (set OPENAI_API_KEY"),
        "{err}"
    );
}

#[tokio::test]
async fn not_found_is_permanent_and_unreachable_is_not() {
    let server = MockServer::start().await;
    let count = mount_sequence(&server, |_, _| {
        ResponseTemplate::new(404)
            .set_body_json(json!({"error": {"message": "The model `nope` does not exist"}}))
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let err = Session::new(&vlm).ask(&EndpointCheck::new()).await.unwrap_err();
    assert!(err.is_permanent());
    assert!(openai_error(&err).to_string().contains("does not exist"));
    assert_eq!(count.load(std::sync::atomic::Ordering::SeqCst), 1);

    // A port nobody listens on: the connection fails on every attempt.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    drop(listener);
    let mut c = config(&server);
    c.base_url = format!("http://127.0.0.1:{port}/v1");
    let vlm = OpenAiVlm::new(c).unwrap();
    let err = Session::new(&vlm).ask(&EndpointCheck::new()).await.unwrap_err();
    assert!(
        matches!(openai_error(&err), OpenAiError::Connection { attempts: 3, .. }),
        "{err:?}"
    );
    assert!(!err.is_permanent());
}

#[tokio::test]
async fn refusal_and_truncation_are_reported_as_such() {
    let server = MockServer::start().await;
    let count = mount_sequence(&server, |n, _| match n {
        0 => ResponseTemplate::new(200).set_body_json(json!({
            "choices": [{"message": {"role": "assistant", "content": null,
                                     "refusal": "I'm sorry, I can't assist with that."},
                         "finish_reason": "stop"}]})),
        _ => ResponseTemplate::new(200).set_body_json(json!({
            "choices": [{"message": {"role": "assistant", "content": "{\"support_type\": \"gro"},
                         "finish_reason": "length"}],
            "usage": {"prompt_tokens": 80, "completion_tokens": 5}})),
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let session = Session::new(&vlm);
    let task = SupportTypeTask::new(test_image(), test_image());
    let refused = session
        .ask(&task)
        .await
        .unwrap()
        .into_single()
        .unwrap()
        .into_result()
        .unwrap_err();
    assert_eq!(refused.kind, UnansweredKind::Refused);
    assert_eq!(refused.reason, "I'm sorry, I can't assist with that.");
    let truncated = session
        .ask(&task)
        .await
        .unwrap()
        .into_single()
        .unwrap()
        .into_result()
        .unwrap_err();
    assert_eq!(truncated.kind, UnansweredKind::Truncated);
    assert_eq!(
        count.load(std::sync::atomic::Ordering::SeqCst),
        2,
        "neither is asked again"
    );
}

#[tokio::test]
async fn malformed_json_is_asked_again() {
    let server = MockServer::start().await;
    mount_sequence(&server, |n, _| match n {
        0 => ResponseTemplate::new(200)
            .set_body_json(completion("{\"support_type\": \"ground\", reason: oops}")),
        _ => json_completion(&support_ok()),
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let answers = Session::new(&vlm)
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap();
    assert!(matches!(
        answers.get(&Single),
        Some(Outcome::Answered { attempt: 2, .. })
    ));
    let bodies = bodies(&server).await;
    assert_eq!(bodies.len(), 2);
    assert!(user_text(&bodies[1]).contains("the answer is not valid JSON"));
    assert!(
        user_text(&bodies[1]).contains("reason: oops"),
        "the previous answer is quoted"
    );

    // A reply that is not a chat completion at all is an error, not an answer.
    let server = MockServer::start().await;
    mount_sequence(&server, |_, _| {
        ResponseTemplate::new(200).set_body_string("<html>proxy page</html>")
    })
    .await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let err = Session::new(&vlm).ask(&EndpointCheck::new()).await.unwrap_err();
    assert!(
        matches!(openai_error(&err), OpenAiError::InvalidResponse { .. }),
        "{err:?}"
    );
}

fn matching(category: &str) -> Value {
    json!({"provided_categories": ["bed", "wardrobe"], "matched": true, "matched_category": category,
           "actual_category": category, "reason": "shape"})
}

#[tokio::test]
async fn category_not_offered_is_asked_again_once_then_recorded_as_unmatched() {
    let server = MockServer::start().await;
    mount_sequence(&server, |_, _| json_completion(&matching("armchair"))).await;
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let session = Session::new(&vlm);
    let task = ObjectMatchingTask::new(test_image(), ["bed", "wardrobe"]).unwrap();
    let answers = session.ask(&task).await.unwrap();
    // Named again after the re-ask: "none of the offered categories", with the reason.
    let Some(Outcome::Answered { answer, note, .. }) = answers.get(&Single) else {
        panic!("{answers:?}")
    };
    assert_eq!(answer.category, None);
    let note = note.as_deref().unwrap_or_default();
    assert!(
        note.contains("none of the offered categories")
            && note.contains("\"armchair\" is not one of the offered categories"),
        "{note}"
    );
    let bodies = bodies(&server).await;
    assert_eq!(bodies.len(), 2, "asked exactly twice");
    assert!(user_text(&bodies[1]).contains(
        "matched_category \"armchair\" is not one of the offered categories [\"bed\",\"wardrobe\"]"
    ));
    assert_eq!(
        bodies[1]["messages"][1]["content"].as_array().unwrap().len(),
        2,
        "the image is sent again"
    );
    let usage = session.usage();
    assert_eq!(
        (usage.re_asks, usage.unanswered, usage.unmatched_not_offered),
        (1, 0, 1)
    );
}

#[tokio::test]
async fn shuffled_answers_are_paired_by_key() {
    let server = MockServer::start().await;
    let reply = json!({"assessments": [
        {"key": "r2", "relationship": "", "anchor_object": "tv", "other_objects": ["sofa"], "other_object_counts": [1],
         "relationship_types": ["face_to"], "sides": [null], "reason": "faces"},
        {"key": "r0", "relationship": "", "anchor_object": "bed", "other_objects": ["nightstand"], "other_object_counts": [2],
         "relationship_types": ["next_to"], "sides": [null], "reason": "beside"},
        {"key": "r1", "relationship": "", "anchor_object": "table", "other_objects": ["chair"], "other_object_counts": [4],
         "relationship_types": ["surround"], "sides": [null], "reason": "around"}
    ]});
    mount_sequence(&server, move |_, _| json_completion(&reply)).await;
    let spec = |key: &str, rel: &str, objects: &[&str]| ObjectRelationSpec {
        key: key.into(),
        relationship: rel.into(),
        objects: objects.iter().map(|s| s.to_string()).collect(),
        anchor_index: Some(0),
    };
    let task = ObjectRelationTask::new(vec![
        spec("r0", "beside", &["bed", "nightstand:0", "nightstand:1"]),
        spec(
            "r1",
            "around",
            &["table", "chair:0", "chair:1", "chair:2", "chair:3"],
        ),
        spec("r2", "facing", &["tv", "sofa"]),
    ])
    .unwrap();
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let answers = Session::new(&vlm).ask(&task).await.unwrap();
    assert_eq!(answers.requests, 1);
    let get = |k: &str| answers.get(&k.to_owned()).unwrap().answer().unwrap().clone();
    assert_eq!(get("r0").relations, Some(vec![Relation::NextTo]));
    assert_eq!(get("r0").other_objects, [("nightstand".to_owned(), 2)]);
    assert_eq!(get("r1").relations, Some(vec![Relation::Surround]));
    assert_eq!(get("r2").relations, Some(vec![Relation::FaceTo]));
    let text = user_text(&bodies(&server).await[0]).to_owned();
    assert!(
        text.ends_with(
            "- key \"r2\": facing - objects: tv, sofa, with the object with index: 0 being the anchor"
        ),
        "{text}"
    );
}

#[tokio::test]
async fn second_run_is_served_from_the_cache() {
    let server = MockServer::start().await;
    mount_sequence(&server, |_, req| {
        let body: Value = req.body_json().unwrap();
        match body["response_format"]["json_schema"]["name"].as_str() {
            Some("obj_support_type") => json_completion(&support_ok()),
            Some("endpoint_check") => json_completion(&json!({"colour": "red", "reason": "red square"})),
            _ => json_completion(&json!({"assessments": [
                {"obj_id": "bed_1", "obj_description": "bed", "functional_sides": ["front", "left", "right"], "reason": "bed"}
            ]})),
        }
    })
    .await;
    let cache = tempfile::tempdir().unwrap();
    let functional = FunctionalSidesTask::new(vec![ObjectToDescribe {
        id: "bed_1".into(),
        description: "bed".into(),
    }])
    .unwrap();
    let support = SupportTypeTask::new(test_image(), test_image());
    let check = EndpointCheck::new();

    let run = || async {
        let session = Session::new(Cached::new(
            OpenAiVlm::new(config(&server)).unwrap(),
            cache.path(),
        ));
        let a = session.ask(&functional).await.unwrap();
        let b = session.ask(&support).await.unwrap();
        let c = session.ask(&check).await.unwrap();
        (format!("{a:?}{b:?}{c:?}"), session.usage())
    };
    let (first, usage1) = run().await;
    assert_eq!(server.received_requests().await.unwrap().len(), 3);
    assert_eq!(
        (usage1.requests, usage1.cache_hits, usage1.tokens.prompt_tokens),
        (3, 0, 300)
    );

    let (second, usage2) = run().await;
    assert_eq!(
        server.received_requests().await.unwrap().len(),
        3,
        "zero requests reached the server"
    );
    assert_eq!(first, second);
    assert_eq!(
        (usage2.requests, usage2.cache_hits, usage2.tokens.total()),
        (3, 3, 0)
    );
    assert_eq!(usage2.cached_tokens.prompt_tokens, 300);
}

#[tokio::test]
async fn concurrent_requests_respect_the_limit() {
    let server = MockServer::start().await;
    mount_sequence(&server, |_, _| {
        json_completion(&support_ok()).set_delay(Duration::from_millis(100))
    })
    .await;
    let mut c = config(&server);
    c.max_concurrent_requests = 2;
    let vlm = Arc::new(OpenAiVlm::new(c).unwrap());
    let mut set = tokio::task::JoinSet::new();
    for i in 0..6u8 {
        let vlm = vlm.clone();
        set.spawn(async move {
            let png = sceneeval_vlm::encode_rgb_png(1, 1, &[i, i, i]).unwrap();
            Session::new(vlm)
                .ask(&SupportTypeTask::new(png.clone(), png))
                .await
                .map(|a| a.requests)
        });
    }
    while let Some(r) = set.join_next().await {
        assert_eq!(r.unwrap().unwrap(), 1);
    }
    let stats = vlm.stats();
    assert_eq!(stats.attempts, 6);
    assert_eq!(stats.peak_in_flight, 2, "six requests, at most two at a time");
}
