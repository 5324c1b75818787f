//! An OpenAI-compatible chat-completions client for `sceneeval-vlm`: [`OpenAiVlm`] implements
//! [`sceneeval_vlm::Vlm`] over reqwest (rustls) and tokio.
//!
//! One client talks to any server that speaks `POST /v1/chat/completions` with image inputs and
//! `response_format: json_schema`: OpenAI (GPT-4o, the reference's model), vLLM
//! (`vllm serve Qwen/Qwen2.5-VL-7B-Instruct`, the paper's open model), Ollama (`/v1`) and LM
//! Studio. `docs/vlm.md` in the repository has the commands for each.
//!
//! - Strict structured output, images as `data:image/png;base64` URLs with a configurable
//!   `detail` (default `low`, as the reference), `seed` (42) and `temperature` (0).
//! - Retries with exponential backoff and deterministic jitter on 408, 409, 429, 5xx,
//!   connection failures and timeouts, honouring `Retry-After`; a per-attempt timeout; a limit
//!   on requests in flight that halves on 429 and grows back; the server's
//!   `x-ratelimit-remaining-*` / `x-ratelimit-reset-*` headers honoured; optional requests- and
//!   tokens-per-minute caps pacing requests by an estimate of their tokens
//!   ([`estimate_prompt_tokens`]: text at [`CHARS_PER_TOKEN`] characters per token, images by
//!   OpenAI's rule for their detail). 401/403 are reported at once as
//!   [`OpenAiError::KeyRefused`].
//! - The API key ([`ApiKey`], from `OPENAI_API_KEY` or another variable, optional for local
//!   servers) never appears in logs, errors, `Debug` output or cache files.
//! - [`ClientStats`] counts attempts, retries and waits; token usage is summed by
//!   [`sceneeval_vlm::Session`].
//!
//! The futures must run inside a tokio runtime: in async code, the caller's; for synchronous
//! callers (such as `sceneeval::Evaluator`'s worker threads), [`RuntimeVlm`] wraps the client
//! with a runtime on a thread of its own.
//!
//! # Example
//! ```no_run
//! use sceneeval_vlm::{Cached, Session, check::EndpointCheck};
//! use sceneeval_vlm_openai::{ApiKey, OpenAiConfig, OpenAiVlm};
//!
//! # async fn run() -> Result<(), Box<dyn std::error::Error>> {
//! let config = OpenAiConfig::new("https://api.openai.com/v1", "gpt-4o-2024-08-06")
//!     .with_api_key(ApiKey::from_env("OPENAI_API_KEY")?);
//! let session = Session::new(Cached::new(OpenAiVlm::new(config)?, "vlm-cache"));
//! let answers = session.ask(&EndpointCheck::new()).await?;
//! println!("{answers:?}, {:?}", session.usage());
//! # Ok(()) }
//! ```
//!
//! A runnable check of the settings, without a server:
//! ```
//! use sceneeval_vlm_openai::{OpenAiConfig, OpenAiVlm};
//! let vlm = OpenAiVlm::new(OpenAiConfig::new("http://localhost:11434/v1/", "qwen2.5vl:7b")).unwrap();
//! assert_eq!(vlm.url(), "http://localhost:11434/v1/chat/completions");
//! assert!(OpenAiVlm::new(OpenAiConfig::new("localhost:11434", "m")).is_err());
//! ```

mod client;
mod config;
mod error;
mod estimate;
mod limits;
mod runtime;
mod wire;

pub use client::{ClientStats, OpenAiVlm};
pub use config::{
    ApiKey, DEFAULT_API_KEY_VAR, ImageDetail, OpenAiConfig, RetryPolicy, TEMPERATURE_RANGE, TokenLimitField,
};
pub use error::OpenAiError;
pub use estimate::{
    CHARS_PER_TOKEN, HIGH_DETAIL_TILE_TOKENS, LOW_DETAIL_IMAGE_TOKENS, estimate_prompt_tokens, image_tokens,
};
pub use limits::parse_reset_duration;
pub use runtime::RuntimeVlm;
