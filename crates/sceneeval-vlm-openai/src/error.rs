use std::time::Duration;

use thiserror::Error;

/// What can go wrong talking to an OpenAI-compatible server.
///
/// No variant ever holds the API key, and server messages are shown only after known key
/// shapes are removed from them (see [`crate::OpenAiVlm`]).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum OpenAiError {
    /// The base URL is not an `http` or `https` URL.
    #[error("base URL {url:?} is not usable: {message}")]
    InvalidBaseUrl {
        /// The URL given.
        url: String,
        /// What is wrong.
        message: String,
    },
    /// The environment variable meant to hold the API key exists but is not valid Unicode, or
    /// a variable that must be set is not.
    #[error("environment variable {var}: {message}")]
    ApiKeyVariable {
        /// The variable's name.
        var: String,
        /// What is wrong (never the value).
        message: String,
    },
    /// A setting is out of range (zero concurrency, zero timeout, ...).
    #[error("invalid setting {setting}: {message}")]
    InvalidSetting {
        /// The setting.
        setting: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The HTTP client could not be built (TLS initialisation).
    #[error("could not build the HTTP client")]
    Client {
        /// The cause.
        #[source]
        source: reqwest::Error,
    },
    /// The server answered 401 or 403: the key is wrong, expired, or missing. Not retried.
    #[error("API key refused (HTTP {status}) by {url}; {key}")]
    KeyRefused {
        /// 401 or 403.
        status: u16,
        /// The endpoint.
        url: String,
        /// Where the key came from, or that none was sent.
        key: String,
    },
    /// The server answered with an error status that is not retried (400, 404, 422, ...) or
    /// kept failing with a retried one (429, 5xx) until the retries ran out.
    #[error("HTTP {status} from {url} after {attempts} attempt(s): {message}")]
    Status {
        /// The status code.
        status: u16,
        /// The endpoint.
        url: String,
        /// How many attempts were made.
        attempts: u32,
        /// The server's error message (known key shapes removed), or the status text.
        message: String,
    },
    /// Every attempt timed out.
    #[error("no answer from {url} within {timeout:?}, {attempts} attempt(s)")]
    Timeout {
        /// The endpoint.
        url: String,
        /// The per-request timeout.
        timeout: Duration,
        /// How many attempts were made.
        attempts: u32,
    },
    /// The server could not be reached (connection refused, DNS, TLS, reset), on every
    /// attempt.
    #[error("could not reach {url} ({attempts} attempt(s))")]
    Connection {
        /// The endpoint.
        url: String,
        /// How many attempts were made.
        attempts: u32,
        /// The last cause.
        #[source]
        source: reqwest::Error,
    },
    /// The server asked to retry later than the configured maximum wait.
    #[error("{url} asked to retry after {retry_after:?}, longer than the maximum wait of {max:?}")]
    RetryAfterTooLong {
        /// The endpoint.
        url: String,
        /// What the server asked for.
        retry_after: Duration,
        /// The configured maximum.
        max: Duration,
    },
    /// The tokio runtime of a [`crate::RuntimeVlm`], or its thread, could not be started.
    #[error("could not start the runtime of the VLM client")]
    Runtime {
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// The server's success reply is not a chat completion.
    #[error("unexpected reply from {url}: {message}")]
    InvalidResponse {
        /// The endpoint.
        url: String,
        /// What is wrong with it.
        message: String,
    },
}

impl OpenAiError {
    /// The same error, saying it happened after `n` attempts.
    pub(crate) fn with_attempts(mut self, n: u32) -> Self {
        match &mut self {
            OpenAiError::Status { attempts, .. }
            | OpenAiError::Timeout { attempts, .. }
            | OpenAiError::Connection { attempts, .. } => *attempts = n,
            _ => {}
        }
        self
    }

    /// Whether every later request would fail the same way: the key was refused, the endpoint
    /// or model does not exist (404), or the configuration is wrong.
    pub fn is_permanent(&self) -> bool {
        match self {
            OpenAiError::InvalidBaseUrl { .. }
            | OpenAiError::ApiKeyVariable { .. }
            | OpenAiError::InvalidSetting { .. }
            | OpenAiError::Client { .. }
            | OpenAiError::Runtime { .. }
            | OpenAiError::KeyRefused { .. } => true,
            OpenAiError::Status { status, .. } => *status == 404,
            _ => false,
        }
    }
}
