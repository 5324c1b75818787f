//! `sceneeval vlm check` against a mock OpenAI-compatible server started by the test on
//! 127.0.0.1: success, a refused key, an unreachable endpoint, a model that does not see the
//! image.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use assert_cmd::Command;
use serde_json::{Value, json};
use wiremock::matchers::{method, path};
use wiremock::{Mock, MockServer, ResponseTemplate};

const KEY: &str = "sk-cli-test-SECRET-4242";

fn completion(answer: Value) -> ResponseTemplate {
    ResponseTemplate::new(200).set_body_json(json!({
        "choices": [{"message": {"role": "assistant", "content": answer.to_string()}, "finish_reason": "stop"}],
        "usage": {"prompt_tokens": 90, "completion_tokens": 12, "total_tokens": 102}
    }))
}

async fn server_answering(response: ResponseTemplate) -> MockServer {
    let server = MockServer::start().await;
    Mock::given(method("POST"))
        .and(path("/v1/chat/completions"))
        .respond_with(response)
        .mount(&server)
        .await;
    server
}

/// Runs `sceneeval -vvv vlm check` (off the async runtime) and returns (status, stdout, stderr).
async fn check(base_url: String, extra: &[&str], key_var: Option<(&str, &str)>) -> (i32, String, String) {
    let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let key_var = key_var.map(|(k, v)| (k.to_owned(), v.to_owned()));
    tokio::task::spawn_blocking(move || {
        let mut cmd = Command::cargo_bin("sceneeval").unwrap();
        cmd.args([
            "-vvv",
            "vlm",
            "check",
            "--vlm-base-url",
            &base_url,
            "--vlm-model",
            "test-vlm",
            "--vlm-timeout-s",
            "5",
        ])
        .args(&extra)
        .env_remove("OPENAI_API_KEY")
        .env_remove("RUST_LOG");
        if let Some((k, v)) = key_var {
            cmd.env(k, v);
        }
        let out = cmd.output().unwrap();
        (
            out.status.code().unwrap(),
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        )
    })
    .await
    .unwrap()
}

#[tokio::test]
async fn a_working_endpoint_passes() {
    let server = server_answering(completion(json!({"colour": "red", "reason": "A red square."}))).await;
    let (code, stdout, stderr) =
        check(format!("{}/v1", server.uri()), &[], Some(("OPENAI_API_KEY", KEY))).await;
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(
        stdout.starts_with("ok: ") && stdout.contains("sees images"),
        "{stdout}"
    );
    assert!(
        stdout.contains("tokens: 90 prompt, 12 completion; 1 HTTP request(s), 0 retries"),
        "{stdout}"
    );
    // The key was sent, and appears nowhere in the output, even at trace level.
    let requests = server.received_requests().await.unwrap();
    assert_eq!(
        requests[0].headers.get("authorization").unwrap(),
        &format!("Bearer {KEY}")
    );
    let body: Value = requests[0].body_json().unwrap();
    assert_eq!(body["model"], "test-vlm");
    assert_eq!(body["messages"][1]["content"][1]["image_url"]["detail"], "low");
    assert!(
        !stdout.contains("SECRET") && !stderr.contains("SECRET"),
        "{stderr}"
    );
    assert!(stderr.contains("sending request"), "the log was on: {stderr}");
}

#[tokio::test]
async fn a_refused_key_fails_with_the_reason() {
    let server = server_answering(ResponseTemplate::new(401).set_body_json(json!({"error": {
        "message": "Incorrect API key provided: sk-cli-t***4242.", "code": "invalid_api_key"}})))
    .await;
    let (code, stdout, stderr) = check(
        format!("{}/v1", server.uri()),
        &["--vlm-api-key-env", "MY_VLM_KEY"],
        Some(("MY_VLM_KEY", KEY)),
    )
    .await;
    assert_eq!(code, 1, "{stdout}{stderr}");
    assert!(stderr.contains("API key refused (HTTP 401)"), "{stderr}");
    assert!(stderr.contains("environment variable MY_VLM_KEY"), "{stderr}");
    assert!(!stderr.contains("SECRET") && !stderr.contains("4242"), "{stderr}");
    assert_eq!(
        server.received_requests().await.unwrap().len(),
        1,
        "401 is not retried"
    );
}

#[tokio::test]
async fn a_named_key_variable_must_be_set() {
    let (code, _, stderr) = check(
        "http://127.0.0.1:9/v1".into(),
        // The old spelling of --vlm-api-key-env still works.
        &["--api-key-env", "UNSET_VLM_KEY_VAR"],
        None,
    )
    .await;
    assert_eq!(code, 1);
    assert!(stderr.contains("UNSET_VLM_KEY_VAR"), "{stderr}");
}

#[tokio::test]
async fn an_unreachable_endpoint_fails_with_the_reason() {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    drop(listener);
    // --retries: the old spelling of --vlm-retries.
    let (code, _, stderr) = check(format!("http://127.0.0.1:{port}/v1"), &["--retries", "0"], None).await;
    assert_eq!(code, 1);
    assert!(stderr.contains("error: the endpoint check failed"), "{stderr}");
    assert!(stderr.contains("could not reach"), "{stderr}");
    assert!(
        stderr.contains("warning: --retries is the old name of --vlm-retries"),
        "{stderr}"
    );
}

#[tokio::test]
async fn a_model_that_does_not_see_the_image_fails() {
    let server = server_answering(completion(
        json!({"colour": "white", "reason": "I see no square."}),
    ))
    .await;
    let (code, _, stderr) = check(format!("{}/v1", server.uri()), &[], None).await;
    assert_eq!(code, 1);
    assert!(stderr.contains("does not seem to get the image"), "{stderr}");
}

#[tokio::test]
async fn a_refusal_fails() {
    let server = server_answering(ResponseTemplate::new(200).set_body_json(json!({
        "choices": [{"message": {"role": "assistant", "content": null, "refusal": "I cannot help."},
                     "finish_reason": "stop"}]})))
    .await;
    let (code, _, stderr) = check(format!("{}/v1", server.uri()), &[], None).await;
    assert_eq!(code, 1);
    assert!(stderr.contains("the model refused: I cannot help."), "{stderr}");
}

#[tokio::test]
async fn sampling_options_are_sent() {
    let server = server_answering(completion(json!({"colour": "red", "reason": "A red square."}))).await;
    let (code, stdout, stderr) = check(
        format!("{}/v1", server.uri()),
        // `--detail` is the option's earlier name, still accepted.
        &[
            "--detail",
            "auto",
            "--vlm-temperature",
            "1",
            "--vlm-seed",
            "none",
            "--vlm-max-tokens",
            "64",
        ],
        None,
    )
    .await;
    assert_eq!(code, 0, "{stdout}{stderr}");
    let body: Value = server.received_requests().await.unwrap()[0].body_json().unwrap();
    assert_eq!(body["messages"][1]["content"][1]["image_url"]["detail"], "auto");
    assert_eq!(
        (body["temperature"].clone(), body["max_tokens"].clone()),
        (json!(1.0), json!(64))
    );
    assert!(body.get("seed").is_none(), "{body}");
    assert!(body.get("max_completion_tokens").is_none(), "{body}");
}

#[tokio::test]
async fn bad_sampling_options_are_refused_before_asking() {
    // Values the facade checks (`sceneeval::VlmOptions::config`, as for `evaluate` and
    // Python's `vlm=`) name the option; values that are not numbers at all are usage errors.
    for (option, value, code, expect) in [
        (
            "--vlm-temperature",
            "2.5",
            1,
            "--vlm-temperature: 2.5 is not from 0 to 2 (or none)",
        ),
        ("--vlm-temperature", "warm", 2, "not a temperature"),
        ("--vlm-seed", "1.5", 2, "not a seed"),
        ("--vlm-max-tokens", "0", 1, "--vlm-max-tokens: must be at least 1"),
        (
            "--vlm-detail",
            "medium",
            1,
            "--vlm-detail: image detail \"medium\" is not one of low, high, auto",
        ),
        (
            "--vlm-token-limit-field",
            "max_output_tokens",
            1,
            "not one of max_tokens, max_completion_tokens",
        ),
    ] {
        let (got, _, stderr) = check("http://127.0.0.1:9/v1".into(), &[option, value], None).await;
        assert_eq!(got, code, "{option} {value}: {stderr}");
        assert!(stderr.contains(expect), "{option} {value}: {stderr}");
    }
}
