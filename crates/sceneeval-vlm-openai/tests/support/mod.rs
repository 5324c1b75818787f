//! Helpers shared by the mock-server tests.

#![allow(dead_code)]

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use sceneeval_vlm_openai::{OpenAiConfig, RetryPolicy};
use serde_json::{Value, json};
use wiremock::matchers::{method, path};
use wiremock::{Mock, MockServer, Request, ResponseTemplate};

/// A chat completion whose message content is `content`.
pub fn completion(content: &str) -> Value {
    json!({
        "id": "chatcmpl-test",
        "object": "chat.completion",
        "model": "test-model",
        "choices": [{"index": 0, "message": {"role": "assistant", "content": content, "refusal": null},
                     "finish_reason": "stop"}],
        "usage": {"prompt_tokens": 100, "completion_tokens": 20, "total_tokens": 120}
    })
}

/// A chat completion answering `value` as JSON text.
pub fn json_completion(value: &Value) -> ResponseTemplate {
    ResponseTemplate::new(200).set_body_json(completion(&value.to_string()))
}

/// Settings for a mock server: fast retries, no key. The timeout is generous so that a loaded
/// test machine never times out a prompt reply; the timeout tests set their own.
pub fn config(server: &MockServer) -> OpenAiConfig {
    config_at(&format!("{}/v1", server.uri()))
}

/// [`config`] for the endpoint at `base_url`.
pub fn config_at(base_url: &str) -> OpenAiConfig {
    let mut c = OpenAiConfig::new(base_url, "test-model");
    c.timeout = Duration::from_secs(10);
    c.retry = RetryPolicy {
        max_retries: 2,
        initial_backoff: Duration::from_millis(1),
        max_backoff: Duration::from_millis(5),
        max_retry_after: Duration::from_secs(5),
        jitter_seed: 7,
    };
    c
}

/// Mounts a responder that answers the n-th request (from 0) with `f(n, request)`.
pub async fn mount_sequence<F>(server: &MockServer, f: F) -> Arc<AtomicUsize>
where
    F: Fn(usize, &Request) -> ResponseTemplate + Send + Sync + 'static,
{
    let count = Arc::new(AtomicUsize::new(0));
    let c = count.clone();
    Mock::given(method("POST"))
        .and(path("/v1/chat/completions"))
        .respond_with(move |req: &Request| f(c.fetch_add(1, Ordering::SeqCst), req))
        .mount(server)
        .await;
    count
}

/// The JSON bodies the server received.
pub async fn bodies(server: &MockServer) -> Vec<Value> {
    server
        .received_requests()
        .await
        .unwrap_or_default()
        .iter()
        .map(|r| r.body_json::<Value>().unwrap_or(Value::Null))
        .collect()
}

/// The user text of a received request body.
pub fn user_text(body: &Value) -> &str {
    body["messages"][1]["content"][0]["text"].as_str().unwrap_or("")
}
