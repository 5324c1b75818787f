//! [`OpenAiVlm`]: the chat-completions client.

use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, SystemTime};

use reqwest::header::{AUTHORIZATION, CONTENT_TYPE, HeaderMap, HeaderValue};
use serde::Serialize;

use sceneeval_vlm::{Answer, AnswerContent, Vlm, VlmError, VlmRequest};
use serde_json::Value;

use crate::limits::{Limiter, RateCaps, RateLimitHeaders, Verdict};
use crate::wire::{ChatResponse, ErrorBody, Sampling, request_body};
use crate::{ApiKey, OpenAiConfig, OpenAiError, RetryPolicy, TEMPERATURE_RANGE, estimate_prompt_tokens};

/// A [`Vlm`] backed by an OpenAI-compatible `POST {base_url}/chat/completions` endpoint:
/// OpenAI, vLLM, Ollama (`/v1`), LM Studio.
///
/// Each request is sent as a system message and one user message (text, then the images as
/// `data:image/png;base64` URLs with the configured `detail`), with
/// `response_format: {type: "json_schema", json_schema: {name, strict: true, schema}}`.
/// Failed attempts are retried as [`RetryPolicy`] says; 401 and 403 are not retried and are
/// reported as [`OpenAiError::KeyRefused`]. At most `max_concurrent_requests` attempts are in
/// flight at once; that limit halves when the server answers 429 and grows back by one after
/// as many successful attempts as it allows. Attempts wait while the server's
/// `x-ratelimit-remaining-requests` / `x-ratelimit-remaining-tokens` headers say its limit is
/// spent (until their `x-ratelimit-reset-*` time), and are spaced to keep under the optional
/// requests- and tokens-per-minute caps (tokens estimated by [`estimate_prompt_tokens`]).
/// A refusal (`message.refusal`) and a reply cut off at the token limit
/// (`finish_reason: "length"`) are answers of their own kinds, not errors.
///
/// Must be polled inside a tokio runtime (with the time driver enabled).
///
/// The API key goes only into the `Authorization` header (marked sensitive). It never appears
/// in `Debug` output, logs or errors; server error messages are shown with anything shaped
/// like a key (`sk-...`) or equal to it removed, and not at all for 401 and 403 (OpenAI's
/// message quotes part of the key). An answer that echoes the key has it replaced by
/// `[redacted]` before it is returned, so the key never reaches a cache file, a re-ask prompt
/// or a report. A base URL with credentials, a query string or a fragment is refused.
pub struct OpenAiVlm {
    url: String,
    base_url: String,
    model: String,
    key_source: Option<String>,
    key: Option<ApiKey>,
    sampling: Sampling,
    /// [`Vlm::settings`]: the sampling settings as canonical text.
    settings: String,
    timeout: Duration,
    retry: RetryPolicy,
    http: reqwest::Client,
    limiter: Limiter,
    stats: Counters,
}

#[derive(Debug, Default)]
struct Counters {
    attempts: AtomicU64,
    retries: AtomicU64,
    waited_us: AtomicU64,
    in_flight: AtomicU64,
    peak_in_flight: AtomicU64,
    jitter: AtomicU64,
}

/// Counts a request in flight for as long as it lives (also when its future is dropped).
struct InFlight<'a>(&'a Counters);

impl<'a> InFlight<'a> {
    fn enter(counters: &'a Counters) -> Self {
        let now = counters.in_flight.fetch_add(1, Ordering::Relaxed) + 1;
        counters.peak_in_flight.fetch_max(now, Ordering::Relaxed);
        InFlight(counters)
    }
}

impl Drop for InFlight<'_> {
    fn drop(&mut self) {
        self.0.in_flight.fetch_sub(1, Ordering::Relaxed);
    }
}

/// What an [`OpenAiVlm`] did so far, for the run report.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct ClientStats {
    /// HTTP requests sent (first attempts and retries).
    pub attempts: u64,
    /// Retries among them.
    pub retries: u64,
    /// Total wait before retries, as computed (backoff or `Retry-After`).
    pub waited: Duration,
    /// The most requests that were in flight at once.
    pub peak_in_flight: u64,
    /// Replies with status 429 (rate limited).
    pub rate_limited: u64,
    /// Total time attempts waited for the rate caps and the server's announced limits.
    pub paced: Duration,
    /// The concurrency limit now: `max_concurrent_requests`, or less after 429s.
    pub concurrency_limit: u64,
}

impl fmt::Debug for OpenAiVlm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("OpenAiVlm")
            .field("url", &self.url)
            .field("model", &self.model)
            .field(
                "api_key",
                &self.key_source.as_deref().map_or("none", |_| "[redacted]"),
            )
            .field("sampling", &self.sampling)
            .field("timeout", &self.timeout)
            .field("retry", &self.retry)
            .finish_non_exhaustive()
    }
}

enum Attempt {
    Done(Answer),
    Retry {
        error: OpenAiError,
        retry_after: Option<Duration>,
    },
    Fail(OpenAiError),
}

impl OpenAiVlm {
    /// A client with `config`.
    ///
    /// # Errors
    /// [`OpenAiError::InvalidBaseUrl`] for a base URL that is not `http(s)://...` or that
    /// holds credentials (`user:pass@`), a query string or a fragment (not shown in the error),
    /// [`OpenAiError::InvalidSetting`] for zero concurrency or timeouts, a temperature outside
    /// 0 to 2, a token limit of 0 or a rate cap of 0,
    /// [`OpenAiError::Client`] when the HTTP client cannot be built.
    pub fn new(config: OpenAiConfig) -> Result<Self, OpenAiError> {
        let base = config.base_url.trim().trim_end_matches('/').to_owned();
        let parsed = reqwest::Url::parse(&base).map_err(|e| OpenAiError::InvalidBaseUrl {
            url: shown_url(&config.base_url),
            message: e.to_string(),
        })?;
        if !matches!(parsed.scheme(), "http" | "https") {
            return Err(OpenAiError::InvalidBaseUrl {
                url: shown_url(&config.base_url),
                message: format!("scheme {:?}; expected http or https", parsed.scheme()),
            });
        }
        if !parsed.username().is_empty() || parsed.password().is_some() {
            return Err(OpenAiError::InvalidBaseUrl {
                url: "(not shown: it contains credentials)".to_owned(),
                message: "credentials in the URL would be logged; give the key through the environment"
                    .to_owned(),
            });
        }
        if parsed.query().is_some() || parsed.fragment().is_some() {
            // The URL without them, so that a key passed as `?api-key=...` is never shown.
            let mut shown = parsed.clone();
            shown.set_query(None);
            shown.set_fragment(None);
            return Err(OpenAiError::InvalidBaseUrl {
                url: format!(
                    "{} (its query or fragment not shown)",
                    shown.as_str().trim_end_matches('/')
                ),
                message: "a query string or fragment would be logged and stored with the results, and \
                          `/chat/completions` would be appended after it; give the base URL without \
                          them and the key through the environment"
                    .to_owned(),
            });
        }
        if config.max_concurrent_requests == 0 {
            return Err(OpenAiError::InvalidSetting {
                setting: "max_concurrent_requests",
                message: "must be at least 1".to_owned(),
            });
        }
        if let Some(t) = config.temperature
            && !TEMPERATURE_RANGE.contains(&t)
        {
            return Err(OpenAiError::InvalidSetting {
                setting: "temperature",
                message: format!(
                    "{t} is not a number from {} to {}",
                    TEMPERATURE_RANGE.start(),
                    TEMPERATURE_RANGE.end()
                ),
            });
        }
        if config.max_tokens == Some(0) {
            return Err(OpenAiError::InvalidSetting {
                setting: "max_tokens",
                message: "must be at least 1".to_owned(),
            });
        }
        if config.requests_per_minute == Some(0) || config.tokens_per_minute == Some(0) {
            return Err(OpenAiError::InvalidSetting {
                setting: "rate cap",
                message: "requests and tokens per minute must be at least 1".to_owned(),
            });
        }
        if config.timeout.is_zero() || config.connect_timeout.is_zero() {
            return Err(OpenAiError::InvalidSetting {
                setting: "timeout",
                message: "must be longer than zero".to_owned(),
            });
        }
        // reqwest is built without a default TLS crypto provider (rustls-no-provider) so that
        // aws-lc-sys is not compiled; install ring's, unless the program installed one.
        let _ = rustls::crypto::ring::default_provider().install_default();
        let mut headers = HeaderMap::new();
        headers.insert(CONTENT_TYPE, HeaderValue::from_static("application/json"));
        let http = reqwest::Client::builder()
            .default_headers(headers)
            .connect_timeout(config.connect_timeout)
            .user_agent(concat!("sceneeval-vlm-openai/", env!("CARGO_PKG_VERSION")))
            .build()
            .map_err(|source| OpenAiError::Client { source })?;
        let sampling = Sampling {
            detail: config.detail,
            seed: config.seed,
            temperature: config.temperature,
            max_tokens: config.max_tokens,
            token_limit_field: config.token_limit_field,
        };
        Ok(OpenAiVlm {
            url: format!("{base}/chat/completions"),
            base_url: base,
            model: config.model,
            key_source: config.api_key.as_ref().map(|k| k.source().to_owned()),
            key: config.api_key,
            settings: sampling.canonical(),
            sampling,
            timeout: config.timeout,
            retry: config.retry,
            http,
            limiter: Limiter::new(
                config.max_concurrent_requests,
                RateCaps {
                    requests_per_minute: config.requests_per_minute,
                    tokens_per_minute: config.tokens_per_minute,
                },
            ),
            stats: Counters::default(),
        })
    }

    /// The endpoint requests go to.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The base URL.
    pub fn base_url(&self) -> &str {
        &self.base_url
    }

    /// What the client did so far.
    pub fn stats(&self) -> ClientStats {
        let s = &self.stats;
        let limits = self.limiter.stats();
        ClientStats {
            attempts: s.attempts.load(Ordering::Relaxed),
            retries: s.retries.load(Ordering::Relaxed),
            waited: Duration::from_micros(s.waited_us.load(Ordering::Relaxed)),
            peak_in_flight: s.peak_in_flight.load(Ordering::Relaxed),
            rate_limited: limits.rate_limited,
            paced: limits.paced,
            concurrency_limit: limits.limit as u64,
        }
    }

    /// The tokens an attempt of `request` is counted for under a tokens-per-minute cap: its
    /// input tokens estimated with this client's image detail ([`estimate_prompt_tokens`]),
    /// plus the reply's token limit when one is set (OpenAI counts it against the limit too).
    pub fn estimate_tokens(&self, request: &VlmRequest) -> u64 {
        estimate_prompt_tokens(request, self.sampling.detail)
            + u64::from(self.sampling.max_tokens.unwrap_or(0))
    }

    /// The image detail requests are sent with.
    pub fn detail(&self) -> crate::ImageDetail {
        self.sampling.detail
    }

    /// Sends one request, retrying as the policy says.
    ///
    /// # Errors
    /// An [`OpenAiError`] when no answer could be obtained.
    pub async fn send(&self, request: &VlmRequest) -> Result<Answer, OpenAiError> {
        let body =
            request_body(&self.model, request, self.sampling).map_err(|e| OpenAiError::InvalidSetting {
                setting: "request",
                message: format!("the request cannot be written as JSON: {e}"),
            })?;
        let tokens = self.estimate_tokens(request);
        let mut retry = 0u32;
        loop {
            let attempt = self.attempt(&request.task, body.clone(), tokens, retry).await;
            let (error, retry_after) = match attempt {
                Attempt::Done(answer) => return Ok(answer),
                Attempt::Fail(error) => return Err(error),
                Attempt::Retry { error, retry_after } => (error, retry_after),
            };
            if retry >= self.retry.max_retries {
                return Err(error.with_attempts(retry + 1));
            }
            let wait = match retry_after {
                Some(asked) if asked > self.retry.max_retry_after => {
                    return Err(OpenAiError::RetryAfterTooLong {
                        url: self.url.clone(),
                        retry_after: asked,
                        max: self.retry.max_retry_after,
                    });
                }
                Some(asked) => asked,
                None => self.retry.backoff(retry, self.jitter()),
            };
            tracing::warn!(task = %request.task, error = %error, retry = retry + 1, wait_ms = wait.as_millis() as u64, "request failed; retrying");
            self.stats.retries.fetch_add(1, Ordering::Relaxed);
            self.stats
                .waited_us
                .fetch_add(wait.as_micros() as u64, Ordering::Relaxed);
            tokio::time::sleep(wait).await;
            retry += 1;
        }
    }

    /// A jitter fraction in `[0, 1)` from a splitmix64 sequence seeded by the policy.
    fn jitter(&self) -> f64 {
        let n = self.stats.jitter.fetch_add(1, Ordering::Relaxed);
        let mut z = self
            .retry
            .jitter_seed
            .wrapping_add(n.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    async fn attempt(&self, task: &str, body: Vec<u8>, tokens: u64, retry: u32) -> Attempt {
        let slot = self.limiter.acquire(tokens).await;
        let in_flight = InFlight::enter(&self.stats);
        self.stats.attempts.fetch_add(1, Ordering::Relaxed);
        tracing::debug!(task, url = %self.url, model = %self.model, retry, tokens, "sending request");
        let (attempt, status) = self.exchange(body).await;
        drop(in_flight);
        slot.finish(match (&attempt, status) {
            (_, Some(429)) => Verdict::RateLimited,
            (Attempt::Done(_), _) => Verdict::Success,
            _ => Verdict::Other,
        });
        attempt
    }

    /// One HTTP exchange: what it gives, and the reply's status when there was one.
    async fn exchange(&self, body: Vec<u8>) -> (Attempt, Option<u16>) {
        let mut builder = self.http.post(&self.url).timeout(self.timeout).body(body);
        if let Some(key) = &self.key {
            match HeaderValue::from_str(&format!("Bearer {}", key.expose())) {
                Ok(mut value) => {
                    value.set_sensitive(true);
                    builder = builder.header(AUTHORIZATION, value);
                }
                Err(_) => {
                    let error = OpenAiError::ApiKeyVariable {
                        var: key.source().to_owned(),
                        message: "the key contains characters not allowed in an HTTP header".to_owned(),
                    };
                    return (Attempt::Fail(error), None);
                }
            }
        }
        let response = match builder.send().await {
            Ok(r) => r,
            Err(e) => return (self.transport_error(e, 1), None),
        };
        let status = response.status();
        let code = status.as_u16();
        let retry_after = retry_after(response.headers());
        self.limiter.observe(RateLimitHeaders::read(response.headers()));
        let text = match response.text().await {
            Ok(t) => t,
            Err(e) => return (self.transport_error(e, 1), Some(code)),
        };
        tracing::debug!(status = status.as_u16(), bytes = text.len(), "reply received");
        if status.is_success() {
            let attempt = match serde_json::from_str::<ChatResponse>(&text).map_err(|e| e.to_string()) {
                Ok(reply) => match reply.into_answer() {
                    Ok((content, usage)) => Attempt::Done(Answer::new(self.redact_content(content), usage)),
                    Err(message) => Attempt::Fail(self.invalid_response(message)),
                },
                Err(message) => {
                    Attempt::Fail(self.invalid_response(format!("not a chat completion ({message})")))
                }
            };
            return (attempt, Some(code));
        }
        if code == 401 || code == 403 {
            let error = OpenAiError::KeyRefused {
                status: code,
                url: self.url.clone(),
                key: match &self.key_source {
                    Some(source) => format!("the key came from {source}"),
                    None => format!(
                        "no API key was sent (set {} or name another variable that holds it)",
                        crate::DEFAULT_API_KEY_VAR
                    ),
                },
            };
            return (Attempt::Fail(error), Some(code));
        }
        let error = OpenAiError::Status {
            status: code,
            url: self.url.clone(),
            attempts: 1,
            message: self.server_message(&text, status.canonical_reason().unwrap_or("")),
        };
        let attempt = if matches!(code, 408 | 409 | 429) || status.is_server_error() {
            Attempt::Retry { error, retry_after }
        } else {
            Attempt::Fail(error)
        };
        (attempt, Some(code))
    }

    fn transport_error(&self, e: reqwest::Error, attempts: u32) -> Attempt {
        let e = e.without_url();
        if e.is_timeout() {
            Attempt::Retry {
                error: OpenAiError::Timeout {
                    url: self.url.clone(),
                    timeout: self.timeout,
                    attempts,
                },
                retry_after: None,
            }
        } else {
            Attempt::Retry {
                error: OpenAiError::Connection {
                    url: self.url.clone(),
                    attempts,
                    source: e,
                },
                retry_after: None,
            }
        }
    }

    fn invalid_response(&self, message: String) -> OpenAiError {
        OpenAiError::InvalidResponse {
            url: self.url.clone(),
            message: self.redact(&message),
        }
    }

    /// The server's error message (or the status text), without anything key-shaped, at most
    /// 500 characters.
    fn server_message(&self, body: &str, fallback: &str) -> String {
        let message = serde_json::from_str::<ErrorBody>(body)
            .ok()
            .and_then(|b| b.error.message)
            .unwrap_or_else(|| {
                if body.trim().is_empty() {
                    fallback.to_owned()
                } else {
                    body.to_owned()
                }
            });
        let redacted = self.redact(&message);
        let mut short: String = redacted.chars().take(500).collect();
        if short.len() < redacted.len() {
            short.push_str("...");
        }
        short
    }

    /// The answer with every occurrence of the key replaced by `[redacted]`: in the reply's
    /// text and, for a JSON answer, in every string and object key of the parsed value (so a
    /// key echoed with JSON escapes is caught too). Nothing above the client (the session's
    /// re-ask prompt, the response cache, reports, logs) ever sees the key.
    fn redact_content(&self, content: AnswerContent) -> AnswerContent {
        let Some(key) = self.key.as_ref().map(ApiKey::expose).filter(|k| !k.is_empty()) else {
            return content;
        };
        let scrub = |text: String| {
            if text.contains(key) {
                text.replace(key, "[redacted]")
            } else {
                text
            }
        };
        fn scrub_value(v: Value, scrub: &dyn Fn(String) -> String) -> Value {
            match v {
                Value::String(s) => Value::String(scrub(s)),
                Value::Array(items) => {
                    Value::Array(items.into_iter().map(|i| scrub_value(i, scrub)).collect())
                }
                Value::Object(map) => Value::Object(
                    map.into_iter()
                        .map(|(k, v)| (scrub(k), scrub_value(v, scrub)))
                        .collect(),
                ),
                other => other,
            }
        }
        match content {
            AnswerContent::Json { value } => AnswerContent::Json {
                value: scrub_value(value, &scrub),
            },
            AnswerContent::NotJson { text, error } => AnswerContent::NotJson {
                text: scrub(text),
                error: scrub(error),
            },
            AnswerContent::Refusal { text } => AnswerContent::Refusal { text: scrub(text) },
            AnswerContent::Truncated { text } => AnswerContent::Truncated { text: scrub(text) },
        }
    }

    /// Removes the key and words shaped like keys (`sk-...`, `Bearer ...`) from a text.
    fn redact(&self, text: &str) -> String {
        let text = match &self.key {
            Some(k) if !k.expose().is_empty() => text.replace(k.expose(), "[redacted]"),
            _ => text.to_owned(),
        };
        let mut out = Vec::new();
        let mut after_bearer = false;
        for word in text.split(' ') {
            let bare = word.trim_matches(|c: char| !c.is_ascii_alphanumeric() && c != '-' && c != '*');
            if after_bearer || bare.starts_with("sk-") || bare.starts_with("sk_") {
                out.push("[redacted]");
            } else {
                out.push(word);
            }
            after_bearer = bare.eq_ignore_ascii_case("bearer");
        }
        out.join(" ")
    }
}

/// A base URL as an error may show it: without anything from the first `?` or `#` on, and not
/// at all when it may hold credentials (an `@`).
fn shown_url(url: &str) -> String {
    let head = url.split(['?', '#']).next().unwrap_or_default();
    if head.contains('@') {
        "(not shown: it may contain credentials)".to_owned()
    } else if head.len() < url.len() {
        format!("{head} (its query or fragment not shown)")
    } else {
        url.to_owned()
    }
}

/// How long the server asks to wait: `retry-after-ms` (milliseconds, OpenAI), else
/// `Retry-After` in seconds. An HTTP-date `Retry-After` is ignored (backoff applies).
/// The wait a server asks for: `retry-after-ms` (milliseconds, OpenAI), else `Retry-After` as
/// seconds or as an HTTP date (RFC 9110; a date in the past means no wait).
fn retry_after(headers: &HeaderMap) -> Option<Duration> {
    retry_after_at(headers, SystemTime::now())
}

/// [`retry_after`] with the current time given.
fn retry_after_at(headers: &HeaderMap, now: SystemTime) -> Option<Duration> {
    let text = |name: &str| headers.get(name).and_then(|v| v.to_str().ok()).map(str::trim);
    let seconds = |v: &str| {
        v.parse::<f64>()
            .ok()
            .filter(|v| *v >= 0.0)
            .and_then(|v| Duration::try_from_secs_f64(v).ok())
    };
    if let Some(ms) = text("retry-after-ms").and_then(seconds) {
        return Some(ms / 1000);
    }
    let value = text("retry-after")?;
    seconds(value).or_else(|| {
        let date = httpdate::parse_http_date(value).ok()?;
        Some(date.duration_since(now).unwrap_or(Duration::ZERO))
    })
}

impl Vlm for OpenAiVlm {
    fn model(&self) -> &str {
        &self.model
    }

    /// `detail=low;seed=42;temperature=0` with the default configuration; a setting that is
    /// not sent (`None`) is left out, the token limit appears when set, under the name of its
    /// field (`max_tokens=300`, `max_completion_tokens=300`).
    fn settings(&self) -> &str {
        &self.settings
    }

    async fn answer(&self, request: &VlmRequest) -> Result<Answer, VlmError> {
        self.send(request).await.map_err(|e| VlmError::Backend {
            task: request.task.clone(),
            model: self.model.clone(),
            permanent: e.is_permanent(),
            source: Box::new(e),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TokenLimitField;

    fn client(key: Option<&str>) -> OpenAiVlm {
        let config = OpenAiConfig::new("http://127.0.0.1:9/v1/", "m")
            .with_api_key(key.map(|k| ApiKey::new(k, "a test")));
        OpenAiVlm::new(config).unwrap()
    }

    #[test]
    fn urls_and_settings() {
        let c = client(None);
        assert_eq!(c.url(), "http://127.0.0.1:9/v1/chat/completions");
        assert!(OpenAiVlm::new(OpenAiConfig::new("ftp://x/v1", "m")).is_err());
        assert!(OpenAiVlm::new(OpenAiConfig::new("not a url", "m")).is_err());
        let err = OpenAiVlm::new(OpenAiConfig::new("https://user:pw@x/v1", "m"))
            .unwrap_err()
            .to_string();
        assert!(!err.contains("pw"), "{err}");
        // A key in the query or fragment is refused without being shown; a URL built from
        // it would also be wrong (`.../v1?api-key=S/chat/completions`).
        for url in [
            "https://x.example/v1?api-key=S3CRET",
            "https://x.example/v1/?api-key=S3CRET#frag",
            "https://x.example/v1#S3CRET",
            "https://x.example/v1?",
        ] {
            let err = OpenAiVlm::new(OpenAiConfig::new(url, "m")).unwrap_err();
            let text = format!("{err} {err:?}");
            assert!(!text.contains("S3CRET") && !text.contains("api-key"), "{text}");
            assert!(matches!(err, OpenAiError::InvalidBaseUrl { .. }), "{text}");
            assert!(
                text.contains("https://x.example/v1 (its query or fragment not shown)"),
                "{text}"
            );
        }
        // Nor when the URL does not parse or has another scheme.
        for url in [
            "ftp://x/v1?key=S3CRET",
            "http//x/v1?key=S3CRET",
            "not a url#S3CRET",
        ] {
            let err = OpenAiVlm::new(OpenAiConfig::new(url, "m"))
                .unwrap_err()
                .to_string();
            assert!(!err.contains("S3CRET") && err.contains("not shown"), "{err}");
        }
        let mut zero = OpenAiConfig::new("http://x/v1", "m");
        zero.max_concurrent_requests = 0;
        assert!(OpenAiVlm::new(zero).is_err());
    }

    #[test]
    fn sampling_settings_are_checked() {
        let with = |f: &dyn Fn(&mut OpenAiConfig)| {
            let mut config = OpenAiConfig::new("http://x/v1", "m");
            f(&mut config);
            OpenAiVlm::new(config)
        };
        for bad in [-0.1, 2.5, f32::NAN, f32::INFINITY] {
            let err = with(&|c| c.temperature = Some(bad)).unwrap_err();
            assert!(
                matches!(
                    err,
                    OpenAiError::InvalidSetting {
                        setting: "temperature",
                        ..
                    }
                ),
                "{bad}: {err}"
            );
        }
        for good in [0.0, 1.0, 2.0] {
            assert!(with(&|c| c.temperature = Some(good)).is_ok());
        }
        let err = with(&|c| c.max_tokens = Some(0)).unwrap_err();
        assert!(matches!(
            err,
            OpenAiError::InvalidSetting {
                setting: "max_tokens",
                ..
            }
        ));
        let vlm = with(&|c| {
            c.temperature = None;
            c.max_tokens = Some(256);
            c.token_limit_field = TokenLimitField::MaxCompletionTokens;
        })
        .unwrap();
        assert_eq!(vlm.settings(), "detail=low;seed=42;max_completion_tokens=256");
        assert_eq!(
            "MAX_completion_tokens".parse::<TokenLimitField>(),
            Ok(TokenLimitField::MaxCompletionTokens)
        );
        assert!(
            "max_output_tokens"
                .parse::<TokenLimitField>()
                .unwrap_err()
                .contains("max_tokens")
        );
    }

    #[test]
    fn redaction() {
        let c = client(Some("sk-proj-abcdef123456"));
        let text = "Incorrect API key provided: sk-proj-****3456. Also sk-proj-abcdef123456 and Bearer xyz.";
        let r = c.redact(text);
        assert!(
            !r.contains("sk-") && !r.contains("3456") && !r.contains("xyz"),
            "{r}"
        );
        assert!(r.starts_with("Incorrect API key provided: [redacted]"), "{r}");
        assert!(!format!("{c:?}").contains("abcdef"));
    }

    #[test]
    fn jitter_is_deterministic_and_in_range() {
        let (a, b) = (client(None), client(None));
        let xs: Vec<f64> = (0..100).map(|_| a.jitter()).collect();
        let ys: Vec<f64> = (0..100).map(|_| b.jitter()).collect();
        assert_eq!(xs, ys);
        assert!(xs.iter().all(|x| (0.0..1.0).contains(x)));
        assert!(xs.windows(2).any(|w| w[0] != w[1]));
    }

    #[test]
    fn retry_after_headers() {
        let mut h = HeaderMap::new();
        h.insert("retry-after", HeaderValue::from_static("2"));
        assert_eq!(retry_after(&h), Some(Duration::from_secs(2)));
        h.insert("retry-after-ms", HeaderValue::from_static("150"));
        assert_eq!(retry_after(&h), Some(Duration::from_millis(150)));
        // An HTTP date: the wait is the time until then, none for a date in the past.
        let mut d = HeaderMap::new();
        d.insert(
            "retry-after",
            HeaderValue::from_static("Wed, 21 Oct 2015 07:28:00 GMT"),
        );
        let date = httpdate::parse_http_date("Wed, 21 Oct 2015 07:28:00 GMT").unwrap();
        assert_eq!(
            retry_after_at(&d, date - Duration::from_secs(3)),
            Some(Duration::from_secs(3))
        );
        assert_eq!(
            retry_after_at(&d, date + Duration::from_secs(3)),
            Some(Duration::ZERO)
        );
        // Nonsense and values no duration can hold are ignored (the backoff applies).
        for bad in ["soon", "-1", "1e300", "NaN"] {
            let mut b = HeaderMap::new();
            b.insert("retry-after", HeaderValue::from_static(bad));
            assert_eq!(retry_after(&b), None, "{bad}");
        }
    }
}
