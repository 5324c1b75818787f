//! Settings of the client and the API key.

use std::fmt;
use std::time::Duration;

use secrecy::{ExposeSecret, SecretString};
use serde::Serialize;

use crate::OpenAiError;

/// The sampling temperatures [`OpenAiConfig::temperature`] may take (OpenAI's range).
pub const TEMPERATURE_RANGE: std::ops::RangeInclusive<f32> = 0.0..=2.0;

/// The environment variable the API key is read from unless another one is named.
pub const DEFAULT_API_KEY_VAR: &str = "OPENAI_API_KEY";

/// An API key: kept as a secret (zeroed when dropped), never shown by `Debug` or `Display`,
/// and never written to logs, errors or files. It remembers where it came from so messages
/// can say so.
#[derive(Clone)]
pub struct ApiKey {
    secret: SecretString,
    source: String,
}

impl ApiKey {
    /// The key in environment variable `var`, or `None` when the variable is unset or empty
    /// (a local server needs no key).
    ///
    /// # Errors
    /// [`OpenAiError::ApiKeyVariable`] when the variable is set but not valid Unicode.
    pub fn from_env(var: &str) -> Result<Option<ApiKey>, OpenAiError> {
        match std::env::var(var) {
            Ok(value) if value.trim().is_empty() => Ok(None),
            Ok(value) => Ok(Some(ApiKey {
                secret: SecretString::from(value.trim().to_owned()),
                source: format!("environment variable {var}"),
            })),
            Err(std::env::VarError::NotPresent) => Ok(None),
            Err(std::env::VarError::NotUnicode(_)) => Err(OpenAiError::ApiKeyVariable {
                var: var.to_owned(),
                message: "the value is not valid Unicode".to_owned(),
            }),
        }
    }

    /// The key in the variable `named`, which must then be set, or else in
    /// [`DEFAULT_API_KEY_VAR`] if that is set (`None` when it is not: local servers need no
    /// key). How the CLI's `--api-key-env` and the Python package's `api_key_env` read it.
    ///
    /// # Errors
    /// [`OpenAiError::ApiKeyVariable`] when the named variable is unset or empty, or a
    /// variable is not valid Unicode.
    pub fn from_env_or_default(named: Option<&str>) -> Result<Option<ApiKey>, OpenAiError> {
        let Some(var) = named else {
            return ApiKey::from_env(DEFAULT_API_KEY_VAR);
        };
        ApiKey::from_env(var)?
            .map(Some)
            .ok_or_else(|| OpenAiError::ApiKeyVariable {
                var: var.to_owned(),
                message: "is not set or empty, but was named to hold the API key".to_owned(),
            })
    }

    /// A key given directly; `source` says where it came from (for messages).
    pub fn new(key: impl Into<String>, source: impl Into<String>) -> ApiKey {
        ApiKey {
            secret: SecretString::from(key.into()),
            source: source.into(),
        }
    }

    /// Where the key came from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The key itself, for the `Authorization` header only.
    pub(crate) fn expose(&self) -> &str {
        self.secret.expose_secret()
    }
}

impl fmt::Debug for ApiKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "ApiKey([redacted], from {})", self.source)
    }
}

/// The `detail` of image inputs: how many tokens the server spends on each image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ImageDetail {
    /// A 512 x 512 view (85 tokens per image with GPT-4o); the reference's setting.
    #[default]
    Low,
    /// Tiles at full resolution.
    High,
    /// The server decides.
    Auto,
}

impl std::str::FromStr for ImageDetail {
    type Err = String;

    /// `low`, `high` or `auto`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "low" => Ok(ImageDetail::Low),
            "high" => Ok(ImageDetail::High),
            "auto" => Ok(ImageDetail::Auto),
            other => Err(format!("image detail {other:?} is not one of low, high, auto")),
        }
    }
}

/// The request field that carries the reply's token limit ([`OpenAiConfig::max_tokens`]).
///
/// `max_tokens` is the field every OpenAI-compatible server knows (vLLM, Ollama, LM Studio,
/// OpenAI's GPT-4o); OpenAI's reasoning models (the o-series, GPT-5) refuse it and take
/// `max_completion_tokens`, which also counts their hidden reasoning tokens.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TokenLimitField {
    /// `max_tokens`.
    #[default]
    MaxTokens,
    /// `max_completion_tokens`.
    MaxCompletionTokens,
}

impl TokenLimitField {
    /// The field's name in the request.
    pub fn name(self) -> &'static str {
        match self {
            TokenLimitField::MaxTokens => "max_tokens",
            TokenLimitField::MaxCompletionTokens => "max_completion_tokens",
        }
    }
}

impl std::str::FromStr for TokenLimitField {
    type Err = String;

    /// `max_tokens` or `max_completion_tokens`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "max_tokens" => Ok(TokenLimitField::MaxTokens),
            "max_completion_tokens" => Ok(TokenLimitField::MaxCompletionTokens),
            other => Err(format!(
                "token limit field {other:?} is not one of max_tokens, max_completion_tokens"
            )),
        }
    }
}

/// When and how long to wait before retrying a failed request.
///
/// Retried: HTTP 408, 409, 429 and 5xx, connection failures and timeouts. The wait before
/// retry `n` (from 0) is `min(initial * 2^n, max) * f` with `f` in `[0.5, 1)` drawn from a
/// deterministic sequence seeded by `jitter_seed` ("equal jitter", so that parallel clients
/// spread out), unless the server says how long to wait (`retry-after-ms`, or `Retry-After`
/// in seconds): then exactly that, or an error when it exceeds `max_retry_after`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RetryPolicy {
    /// Retries after the first attempt (default [`sceneeval_vlm::DEFAULT_MAX_RETRIES`], 5).
    pub max_retries: u32,
    /// The first backoff (default 1 s).
    pub initial_backoff: Duration,
    /// The longest backoff (default 60 s).
    pub max_backoff: Duration,
    /// The longest server-requested wait that is honoured (default 120 s).
    pub max_retry_after: Duration,
    /// Seed of the jitter sequence (default 0).
    pub jitter_seed: u64,
}

impl Default for RetryPolicy {
    fn default() -> Self {
        RetryPolicy {
            max_retries: sceneeval_vlm::DEFAULT_MAX_RETRIES,
            initial_backoff: Duration::from_secs(1),
            max_backoff: Duration::from_secs(60),
            max_retry_after: Duration::from_secs(120),
            jitter_seed: 0,
        }
    }
}

impl RetryPolicy {
    /// The backoff before retry `retry` (from 0), with the jitter fraction `f` in `[0, 1)`.
    ///
    /// ```
    /// use std::time::Duration;
    /// use sceneeval_vlm_openai::RetryPolicy;
    /// let p = RetryPolicy::default();
    /// // retry 2: min(1 s * 2^2, 60 s) * (0.5 + 0.5 * 0.5) = 4 s * 0.75 = 3 s
    /// assert_eq!(p.backoff(2, 0.5), Duration::from_secs(3));
    /// // retry 10: capped at 60 s, times 0.5 at f = 0
    /// assert_eq!(p.backoff(10, 0.0), Duration::from_secs(30));
    /// ```
    pub fn backoff(&self, retry: u32, f: f64) -> Duration {
        let factor = 2f64.powi(retry.min(62) as i32);
        let base = self.initial_backoff.as_secs_f64() * factor;
        let capped = base.min(self.max_backoff.as_secs_f64());
        Duration::from_secs_f64(capped * (0.5 + 0.5 * f.clamp(0.0, 1.0)))
    }
}

/// Settings of an [`crate::OpenAiVlm`].
///
/// | setting | default | note |
/// |---|---|---|
/// | `base_url` | (required) | `https://api.openai.com/v1`, `http://localhost:8000/v1` (vLLM), `http://localhost:11434/v1` (Ollama), `http://localhost:1234/v1` (LM Studio) |
/// | `model` | (required) | `gpt-4o-2024-08-06` is the reference's model |
/// | `api_key` | none | read with [`ApiKey::from_env`]; local servers need none |
/// | `detail` | `low` | as the reference |
/// | `seed` | 42 | as the reference; OpenAI treats it as best effort |
/// | `temperature` | 0 | the reference sent none (API default 1.0); 0 makes answers as repeatable as the server allows; `None` sends none (OpenAI's reasoning models accept only their default) |
/// | `max_tokens` | none | the server's limit; a reply cut off there is reported as truncated |
/// | `token_limit_field` | `max_tokens` | the field `max_tokens` is sent in ([`TokenLimitField`]) |
/// | `timeout` | 60 s ([`sceneeval_vlm::DEFAULT_TIMEOUT`]) | per attempt, including reading the reply |
/// | `connect_timeout` | 10 s | |
/// | `retry` | [`RetryPolicy::default`] | |
/// | `max_concurrent_requests` | 4 ([`sceneeval_vlm::DEFAULT_CONCURRENCY`]) | requests in flight at once, over all tasks using this client; halved on 429, grown back by one per window of successes |
/// | `requests_per_minute` | none | attempts start at least 60 s / rpm apart |
/// | `tokens_per_minute` | none | an attempt of n estimated tokens ([`crate::OpenAiVlm::estimate_tokens`]) holds the next back by n x 60 s / tpm |
#[derive(Debug, Clone)]
pub struct OpenAiConfig {
    /// The API base URL, ending before `/chat/completions`.
    pub base_url: String,
    /// The model name sent with every request.
    pub model: String,
    /// The API key, if any.
    pub api_key: Option<ApiKey>,
    /// The image detail.
    pub detail: ImageDetail,
    /// The sampling seed, if any.
    pub seed: Option<u64>,
    /// The sampling temperature, if any: in [`TEMPERATURE_RANGE`].
    pub temperature: Option<f32>,
    /// The token limit of a reply, if any (at least 1), sent in the field
    /// `token_limit_field` names.
    pub max_tokens: Option<u32>,
    /// The request field of `max_tokens`.
    pub token_limit_field: TokenLimitField,
    /// The timeout of one attempt.
    pub timeout: Duration,
    /// The timeout of connecting.
    pub connect_timeout: Duration,
    /// The retry policy.
    pub retry: RetryPolicy,
    /// How many requests may be in flight at once.
    pub max_concurrent_requests: usize,
    /// A cap on attempts per minute (at least 1), if any.
    pub requests_per_minute: Option<u32>,
    /// A cap on estimated tokens per minute (at least 1), if any.
    pub tokens_per_minute: Option<u64>,
}

impl OpenAiConfig {
    /// The defaults of the table above for `model` at `base_url`, without a key.
    pub fn new(base_url: impl Into<String>, model: impl Into<String>) -> Self {
        OpenAiConfig {
            base_url: base_url.into(),
            model: model.into(),
            api_key: None,
            detail: ImageDetail::Low,
            seed: Some(42),
            temperature: Some(0.0),
            max_tokens: None,
            token_limit_field: TokenLimitField::MaxTokens,
            timeout: sceneeval_vlm::DEFAULT_TIMEOUT,
            connect_timeout: Duration::from_secs(10),
            retry: RetryPolicy::default(),
            max_concurrent_requests: sceneeval_vlm::DEFAULT_CONCURRENCY,
            requests_per_minute: None,
            tokens_per_minute: None,
        }
    }

    /// Sets the key.
    pub fn with_api_key(mut self, key: Option<ApiKey>) -> Self {
        self.api_key = key;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_named_key_variable_must_be_set() {
        let err = ApiKey::from_env_or_default(Some("SCENEEVAL_TEST_UNSET_KEY_VARIABLE")).unwrap_err();
        assert!(
            matches!(&err, OpenAiError::ApiKeyVariable { var, .. } if var == "SCENEEVAL_TEST_UNSET_KEY_VARIABLE"),
            "{err}"
        );
        assert!(err.to_string().contains("is not set or empty"), "{err}");
    }

    #[test]
    fn debug_never_shows_the_key() {
        let key = ApiKey::new("sk-test-very-secret-0123456789", "a test");
        let config = OpenAiConfig::new("http://localhost:1/v1", "m").with_api_key(Some(key.clone()));
        for text in [format!("{key:?}"), format!("{config:?}"), format!("{config:#?}")] {
            assert!(!text.contains("very-secret"), "{text}");
            assert!(text.contains("redacted"), "{text}");
        }
        assert_eq!(key.expose(), "sk-test-very-secret-0123456789");
    }

    #[test]
    fn detail_parses() {
        assert_eq!("LOW".parse::<ImageDetail>(), Ok(ImageDetail::Low));
        assert_eq!("auto".parse::<ImageDetail>(), Ok(ImageDetail::Auto));
        assert!("medium".parse::<ImageDetail>().is_err());
        assert_eq!(serde_json::to_string(&ImageDetail::High).unwrap(), "\"high\"");
    }

    #[test]
    fn backoff_doubles_and_caps() {
        let p = RetryPolicy {
            initial_backoff: Duration::from_millis(100),
            max_backoff: Duration::from_millis(350),
            ..RetryPolicy::default()
        };
        // f = 1 gives the full base: 100, 200, 350 (400 capped), 350 ms.
        let full: Vec<u128> = (0..4).map(|n| p.backoff(n, 1.0).as_millis()).collect();
        assert_eq!(full, [100, 200, 350, 350]);
        // f = 0 gives half: 50 ms.
        assert_eq!(p.backoff(0, 0.0), Duration::from_millis(50));
    }
}
