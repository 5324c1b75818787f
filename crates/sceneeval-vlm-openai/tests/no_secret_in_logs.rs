//! A run with an API key set, logging everything at TRACE level (including the `log` records of
//! reqwest and hyper), against a server that echoes the key in its answers (in JSON, escaped,
//! in text that is not JSON, in a refusal) and in its error bodies: neither the log, nor the
//! errors (with their causes), nor `Debug` output, nor the cache files, nor the requests sent
//! back (the re-ask prompt quotes the previous answer) contain the key or a part of it; nor on
//! the rate-limit path (a 429 quoting the key, rate-limit headers, the per-minute caps). Its own
//! test binary, because it installs the global log subscriber.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod support;

use sceneeval_test_support::logs::SharedBuffer;
use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion as mock_completion, error};
use sceneeval_vlm::check::{EndpointCheck, test_image};
use sceneeval_vlm::tasks::SupportTypeTask;
use sceneeval_vlm::{Cached, Outcome, Session, Single};
use sceneeval_vlm_openai::{ApiKey, OpenAiConfig, OpenAiVlm};
use serde_json::json;
use std::time::Duration;
use support::{bodies, completion, config, mount_sequence, user_text};
use wiremock::{MockServer, ResponseTemplate};

const KEY: &str = "sk-proj-Zq8TESTSECRETxY41mN0pLw";

fn assert_no_key(what: &str, text: &str) {
    // The whole key, its distinctive middle, and OpenAI's masked form's tail.
    for needle in [KEY, "TESTSECRET", "Zq8T", "pLw"] {
        assert!(!text.contains(needle), "{what} contains {needle:?}:\n{text}");
    }
}

#[tokio::test]
async fn the_key_never_reaches_logs_errors_or_files() {
    let buffer = SharedBuffer::default();
    let writer = buffer.clone();
    tracing_subscriber::fmt()
        .with_max_level(tracing::Level::TRACE)
        .with_writer(move || writer.clone())
        .with_ansi(false)
        .try_init()
        .unwrap();

    // The server: an invalid answer echoing the key (as a support type, and with a JSON escape
    // in its reason), so the task is asked again quoting it; a valid answer whose reason echoes
    // the key (usable: cached); a reply that is not JSON echoing the key, so the next task is
    // asked again; a refusal echoing it; a 500 whose body echoes it; then a 401 quoting a
    // masked key.
    let escaped = KEY.replace('Z', "\\u005a");
    let server = MockServer::start().await;
    mount_sequence(&server, move |n, _| match n {
        0 => ResponseTemplate::new(200).set_body_json(completion(&format!(
            r#"{{"support_type": "{KEY}", "reason": "my key is {escaped}"}}"#
        ))),
        1 => ResponseTemplate::new(200).set_body_json(completion(&format!(
            r#"{{"support_type": "ground", "reason": "on the floor, says {escaped}"}}"#
        ))),
        2 => ResponseTemplate::new(200).set_body_json(completion(&format!("Sure! Your key is {KEY}."))),
        3 => ResponseTemplate::new(200).set_body_json(json!({
            "choices": [{"index": 0, "finish_reason": "stop",
                         "message": {"role": "assistant", "content": null, "refusal": format!("I cannot use {KEY}")}}]})),
        4 => ResponseTemplate::new(500).set_body_string(format!("upstream rejected Bearer {KEY} from proxy")),
        _ => ResponseTemplate::new(401).set_body_json(json!({"error": {
            "message": "Incorrect API key provided: sk-proj-****pLw. You can find your API key at https://platform.openai.com/account/api-keys.",
            "code": "invalid_api_key"}})),
    })
    .await;
    let cache = tempfile::tempdir().unwrap();
    let key = ApiKey::new(KEY, "environment variable SCENEEVAL_TEST_KEY");
    let vlm = OpenAiVlm::new(config(&server).with_api_key(Some(key.clone()))).unwrap();
    let session = Session::new(Cached::new(&vlm, cache.path()));

    let ok = session
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap();
    assert_eq!(ok.requests, 2, "the invalid answer was asked again");
    assert!(ok.get(&Single).is_some_and(Outcome::is_answered), "{ok:?}");
    let refused = session.ask(&EndpointCheck::new()).await.unwrap();
    assert!(!refused.into_single().unwrap().is_answered());
    // Asked again without the cache: the 500, then the 401.
    let err = Session::new(&vlm).ask(&EndpointCheck::new()).await.unwrap_err();
    assert!(err.is_permanent(), "ends with the 401: {err}");

    // What was sent back: the re-ask quotes the previous answer, redacted.
    let sent = bodies(&server).await;
    assert_eq!(sent.len(), 6);
    assert!(
        user_text(&sent[1]).contains("[redacted]"),
        "{}",
        user_text(&sent[1])
    );
    for body in &sent {
        assert_no_key("a request body", &body.to_string());
    }

    // Errors with their whole cause chain, in Display and Debug form.
    let mut chain = format!("{err}\n{err:?}\n");
    let mut source = std::error::Error::source(&err);
    while let Some(s) = source {
        chain.push_str(&format!("{s}\n{s:?}\n"));
        source = s.source();
    }
    assert!(chain.contains("API key refused"), "{chain}");
    assert_no_key("the error chain", &chain);
    assert_no_key(
        "Debug output",
        &format!("{vlm:?} {key:?} {ok:?} {:?}", session.usage()),
    );
    assert!(format!("{ok:?}").contains("[redacted]"), "{ok:?}");

    // Cache files: only the usable answer (what was not usable is never cached), redacted.
    let files = walk(cache.path());
    assert_eq!(files.len(), 1, "{files:?}");
    for entry in files {
        assert_no_key(
            &entry.display().to_string(),
            &std::fs::read_to_string(&entry).unwrap(),
        );
    }

    // The rate-limit path: a 429 whose body quotes the key, with rate-limit headers, then an
    // answer, through a client with both caps (its token estimate) and the key.
    let limited = MockEndpoint::start(Duration::ZERO, |n, _| {
        if n == 0 {
            error(429, &format!("Rate limit reached for key {KEY}"))
                .with_header("x-ratelimit-remaining-requests", "0")
                .with_header("x-ratelimit-reset-requests", "10ms")
        } else {
            mock_completion(&json!({"support_type": "ground", "reason": "on the floor"}))
        }
    });
    let mut c = OpenAiConfig::new(limited.url(), "m").with_api_key(Some(key.clone()));
    c.retry = config(&server).retry;
    c.requests_per_minute = Some(6_000);
    c.tokens_per_minute = Some(10_000_000);
    let paced = OpenAiVlm::new(c).unwrap();
    let answer = Session::new(&paced)
        .ask(&SupportTypeTask::new(test_image(), test_image()))
        .await
        .unwrap();
    assert_eq!(paced.stats().rate_limited, 1);
    assert_no_key(
        "Debug output of the paced client",
        &format!("{paced:?} {:?} {answer:?}", paced.stats()),
    );

    // The log: it recorded the run (retries included) and nothing of the key.
    let log = buffer.text();
    assert!(
        log.contains("sending request") && log.contains("retrying"),
        "{log}"
    );
    assert_no_key("the log", &log);
}

fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}
