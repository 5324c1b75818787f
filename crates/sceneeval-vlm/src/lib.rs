//! The VLM layer of SceneEval, without transport: typed tasks, prompts, strict JSON schemas,
//! answer validation with one re-ask, a content-addressed response cache, and replay and
//! scripted models.
//!
//! Object matching, attributes, support types, functional sides and the mapping of free-text
//! relations onto the 23 predicates all ask a vision-language model. This crate holds
//! everything about those questions except talking to a server:
//!
//! - [`Vlm`]: one structured request ([`VlmRequest`]: system prompt, user text, PNG images,
//!   the JSON Schema of the answer) to one [`Answer`] (parsed JSON, or a refusal, a truncated
//!   or non-JSON reply; plus token usage). Its future is `Send` and tied to no runtime.
//!   `sceneeval-vlm-openai` implements it over HTTP for OpenAI, vLLM, Ollama and LM Studio.
//! - [`tasks`]: the seven tasks of the reference (and the paper's two annotation tasks) as typed builders, wire answers with the
//!   reference's field names, and validated answers ([`Relation`](sceneeval_relations::Relation),
//!   [`Side`](sceneeval_geom::Side), [`SupportType`](sceneeval_scene::SupportType), the
//!   caller's category spelling).
//! - [`Session::ask`]: the protocol every model gets: ask, validate (categories among those
//!   offered, sides among front/back/left/right, predicates among the 23, every question
//!   answered exactly once, paired by key; by position only for items whose key the model left
//!   empty in an answer with one item per question), re-ask once (the questions without a valid
//!   answer) with the problems appended, and record what is still invalid as [`Unanswered`]
//!   with the reason (a category that was not offered, named twice: none of the offered).
//!   [`Usage`] sums requests, cache hits, re-asks, recoveries and tokens per run.
//! - [`prompt`]: the reference's prompts as template files shipped in the crate, overridable
//!   from a folder. [`schema`]: strict-mode schemas generated from the wire types.
//! - [`Cached`], [`Replay`] ([`cache`]): one readable JSON file per answer, keyed by a blake3
//!   hash of model, messages, images and schema, written atomically, and only for usable
//!   answers; replay answers only from the cache. [`Scripted`]: answers given in advance, for tests.
//!
//! # Example
//! A support-type question answered by a scripted model whose first answer is not one of the
//! four types: the task is asked again once, and the second answer is used.
//!
//! ```
//! use sceneeval_vlm::tasks::SupportTypeTask;
//! use sceneeval_vlm::{check::test_image, AnswerContent, Scripted, Session};
//! use sceneeval_scene::SupportType;
//! use serde_json::json;
//!
//! let vlm = Scripted::queue("scripted", [
//!     AnswerContent::Json { value: json!({"support_type": "shelf", "reason": "On a shelf."}) },
//!     AnswerContent::Json { value: json!({"support_type": "object", "reason": "On a shelf."}) },
//! ]);
//! let session = Session::new(&vlm);
//! let task = SupportTypeTask::new(test_image(), test_image());
//! let outcome = pollster::block_on(session.ask(&task)).unwrap().into_single().unwrap();
//! assert_eq!(outcome.answer().unwrap().support_type, SupportType::Object);
//!
//! let second = &vlm.requests()[1];
//! assert!(second.user_text.contains("support_type \"shelf\" is not one of ground, wall, ceiling, object"));
//! assert_eq!(second.images.len(), 2);
//! assert_eq!(session.usage().requests, 2);
//! ```

pub mod cache;
pub mod check;
mod error;
mod image;
mod names;
pub mod prompt;
mod request;
pub mod schema;
mod scripted;
mod session;
mod task;
mod task_kind;
pub mod tasks;
mod usage;
mod vlm;

pub use cache::{Cached, DiskCache, Replay};
pub use error::{BoxError, VlmError};
pub use image::{PngImage, encode_rgb_png};
pub use request::{Answer, AnswerContent, ResponseSchema, VlmRequest};
pub use scripted::Scripted;
pub use session::Session;
pub use task::{Answers, Outcome, Single, Task, Unanswered, UnansweredKind, Validation};
pub use task_kind::TaskKind;
pub use usage::{Meter, TokenUsage, Usage};
pub use vlm::Vlm;

/// How long one request to a model (each HTTP attempt, reading the reply included) may take
/// before it is abandoned and retried, unless the caller says otherwise: 60 s, written once
/// for the HTTP client's default, `sceneeval evaluate --vlm-timeout-s`, `vlm check` and
/// Python's `vlm["timeout_s"]`.
pub const DEFAULT_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(60);

/// Requests to one model in flight at once, over every task using it, unless the caller says
/// otherwise: the HTTP client's default and every run's.
pub const DEFAULT_CONCURRENCY: usize = 4;

/// Retries after a failed attempt of a request (a 429, 5xx, timeout or connection error),
/// unless the caller says otherwise: the HTTP client's default and every run's. The endpoint
/// check retries less ([`check::CHECK_MAX_RETRIES`]).
pub const DEFAULT_MAX_RETRIES: u32 = 5;
