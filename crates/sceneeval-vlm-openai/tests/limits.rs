//! Requests in flight, rate limits and pacing against the mock endpoint of
//! `sceneeval_test_support::mock_endpoint` on 127.0.0.1, which counts the requests in flight at
//! the server: futures polled together are in flight together through `RuntimeVlm`, a 429 with
//! `x-ratelimit-*` headers halves the concurrency and holds the next attempt until the announced
//! reset, and the requests-per-minute cap spaces attempts.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod support;

use std::time::Duration;

use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion, error};
use sceneeval_vlm::tasks::SupportTypeTask;
use sceneeval_vlm::{Session, encode_rgb_png};
use sceneeval_vlm_openai::{OpenAiConfig, OpenAiVlm, RuntimeVlm};
use serde_json::json;

fn config(server: &MockEndpoint) -> OpenAiConfig {
    support::config_at(&server.url())
}

/// A support-type task with its own images (so that no two are the same request).
fn task(i: u8) -> SupportTypeTask {
    let png = encode_rgb_png(1, 1, &[i, i, i]).unwrap();
    SupportTypeTask::new(png.clone(), png)
}

fn support() -> serde_json::Value {
    json!({"support_type": "ground", "reason": "on the floor"})
}

#[test]
fn futures_polled_together_through_runtime_vlm_are_in_flight_together() {
    // Each request takes 400 ms at the server; six polled together by one synchronous thread
    // (as a scene's independent questions are) must all be at the server at once.
    let server = MockEndpoint::start(Duration::from_millis(400), |_, _| completion(&support()));
    let mut c = config(&server);
    c.max_concurrent_requests = 8;
    let vlm = RuntimeVlm::start(OpenAiVlm::new(c).unwrap()).unwrap();
    let session = Session::new(&vlm);
    let tasks: Vec<SupportTypeTask> = (0..6).map(task).collect();
    let (a, b, c2, d, e, f) = pollster::block_on(async {
        tokio::join!(
            session.ask(&tasks[0]),
            session.ask(&tasks[1]),
            session.ask(&tasks[2]),
            session.ask(&tasks[3]),
            session.ask(&tasks[4]),
            session.ask(&tasks[5]),
        )
    });
    for answers in [a, b, c2, d, e, f] {
        assert!(answers.unwrap().into_single().unwrap().is_answered());
    }
    assert_eq!(server.requests(), 6);
    assert_eq!(server.peak_in_flight(), 6, "all six at the server at once");
    assert_eq!(vlm.inner().stats().peak_in_flight, 6);
}

#[test]
fn a_dropped_request_is_cancelled_and_frees_its_place() {
    // One place. The first request is dropped while the server holds it (1.5 s): the second
    // is sent at once, so both are at the server together. Were the first not cancelled, the
    // second would wait for its place until the first's answer came.
    let server = MockEndpoint::start(Duration::from_millis(1500), |_, _| completion(&support()));
    let mut c = config(&server);
    c.max_concurrent_requests = 1;
    let vlm = RuntimeVlm::start(OpenAiVlm::new(c).unwrap()).unwrap();
    let session = Session::new(&vlm);
    let (first, second) = (task(1), task(2));
    pollster::block_on(async {
        let ask = session.ask(&first);
        tokio::pin!(ask);
        // Polled once: spawned and sent.
        assert!(poll_once(ask.as_mut()).await.is_none());
        while server.requests() == 0 {
            std::thread::sleep(Duration::from_millis(5));
        }
    });
    let answers = pollster::block_on(session.ask(&second)).unwrap();
    assert!(answers.into_single().unwrap().is_answered());
    assert_eq!(session.usage().requests, 1, "only the second was answered");
    assert_eq!(server.requests(), 2);
    assert_eq!(
        server.peak_in_flight(),
        2,
        "the second was sent while the first was held"
    );
}

/// Polls `fut` once: `Some` when it is ready.
async fn poll_once<F: std::future::Future + Unpin>(mut fut: F) -> Option<F::Output> {
    std::future::poll_fn(|cx| {
        std::task::Poll::Ready(match std::pin::Pin::new(&mut fut).poll(cx) {
            std::task::Poll::Ready(v) => Some(v),
            std::task::Poll::Pending => None,
        })
    })
    .await
}

#[test]
fn a_429_with_rate_limit_headers_halves_the_concurrency_and_waits_for_the_reset() {
    // The first reply: 429, no request left until 300 ms from now (OpenAI's duration format),
    // and the wait asked for in `retry-after-ms` is short. Then answers.
    let server = MockEndpoint::start(Duration::ZERO, |n, _| {
        if n == 0 {
            error(429, "Rate limit reached for requests")
                .with_header("retry-after-ms", "5")
                .with_header("x-ratelimit-limit-requests", "60")
                .with_header("x-ratelimit-remaining-requests", "0")
                .with_header("x-ratelimit-reset-requests", "300ms")
                .with_header("x-ratelimit-remaining-tokens", "150000")
                .with_header("x-ratelimit-reset-tokens", "6m0s")
        } else {
            completion(&support())
        }
    });
    let vlm = OpenAiVlm::new(config(&server)).unwrap();
    let vlm = RuntimeVlm::start(vlm).unwrap();
    let answers = pollster::block_on(Session::new(&vlm).ask(&task(0))).unwrap();
    assert!(answers.into_single().unwrap().is_answered());
    let stats = vlm.inner().stats();
    assert_eq!((stats.attempts, stats.retries, stats.rate_limited), (2, 1, 1));
    // 4 halved to 2 by the 429; one success since does not grow it (that takes 2).
    assert_eq!(stats.concurrency_limit, 2);
    // The retry waited for the announced reset, not only the 5 ms the server asked for: the
    // pacing wait is what remained of the 300 ms when the retry came.
    assert!(stats.paced > Duration::from_millis(200), "{stats:?}");
    assert!(stats.paced <= Duration::from_millis(300), "{stats:?}");
}

#[test]
fn a_requests_per_minute_cap_spaces_the_attempts() {
    // 600 requests per minute: one every 100 ms. Three asked at once: the second waits about
    // 100 ms, the third about 200 ms.
    let server = MockEndpoint::start(Duration::ZERO, |_, _| completion(&support()));
    let mut c = config(&server);
    c.requests_per_minute = Some(600);
    let vlm = RuntimeVlm::start(OpenAiVlm::new(c).unwrap()).unwrap();
    let session = Session::new(&vlm);
    let tasks: Vec<SupportTypeTask> = (0..3).map(task).collect();
    let (a, b, d) = pollster::block_on(async {
        tokio::join!(
            session.ask(&tasks[0]),
            session.ask(&tasks[1]),
            session.ask(&tasks[2])
        )
    });
    for answers in [a, b, d] {
        assert!(answers.unwrap().into_single().unwrap().is_answered());
    }
    let paced = vlm.inner().stats().paced;
    assert!(
        paced >= Duration::from_millis(250),
        "100 + 200 ms, less scheduling slack: {paced:?}"
    );
    let zero = OpenAiVlm::new(OpenAiConfig {
        tokens_per_minute: Some(0),
        ..config(&server)
    });
    assert!(zero.is_err());
}
