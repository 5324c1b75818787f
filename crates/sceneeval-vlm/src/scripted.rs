//! [`Scripted`]: a [`Vlm`] whose answers are given in advance, for tests and examples.

use std::collections::VecDeque;
use std::fmt;
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::{Answer, AnswerContent, TokenUsage, Vlm, VlmError, VlmRequest};

type Responder = dyn Fn(&VlmRequest) -> Result<AnswerContent, VlmError> + Send + Sync;

/// A [`Vlm`] that answers from a queue or a function, and records every request it gets.
///
/// Answers report zero tokens. Tests assert on [`Scripted::requests`] to see what was asked
/// (for example the re-ask note).
///
/// ```
/// use sceneeval_vlm::{AnswerContent, Scripted, Vlm, VlmRequest, ResponseSchema};
/// let vlm = Scripted::from_fn("m", |req: &VlmRequest| {
///     Ok(AnswerContent::Json { value: serde_json::json!({"echo": req.user_text}) })
/// });
/// let req = VlmRequest {
///     task: "t".into(), system: String::new(), user_text: "hi".into(), images: vec![],
///     schema: ResponseSchema { name: "t".into(), schema: serde_json::json!({}) },
/// };
/// let answer = pollster::block_on(vlm.answer(&req)).unwrap();
/// assert_eq!(answer.content, AnswerContent::Json { value: serde_json::json!({"echo": "hi"}) });
/// assert_eq!(vlm.requests().len(), 1);
/// ```
pub struct Scripted {
    model: String,
    settings: String,
    queue: Mutex<VecDeque<AnswerContent>>,
    responder: Option<Box<Responder>>,
    log: Mutex<Vec<VlmRequest>>,
}

impl fmt::Debug for Scripted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Scripted")
            .field("model", &self.model)
            .field("queued", &lock(&self.queue).len())
            .field("function", &self.responder.is_some())
            .field("answered", &lock(&self.log).len())
            .finish()
    }
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic while holding the lock cannot leave the queue or log half-updated.
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

impl Scripted {
    /// Answers `answers` in order, one per request; a request beyond them is a
    /// [`VlmError::ScriptExhausted`].
    pub fn queue(model: impl Into<String>, answers: impl IntoIterator<Item = AnswerContent>) -> Self {
        Scripted {
            model: model.into(),
            settings: String::new(),
            queue: Mutex::new(answers.into_iter().collect()),
            responder: None,
            log: Mutex::new(Vec::new()),
        }
    }

    /// Answers every request with `f(request)`.
    pub fn from_fn(
        model: impl Into<String>,
        f: impl Fn(&VlmRequest) -> Result<AnswerContent, VlmError> + Send + Sync + 'static,
    ) -> Self {
        Scripted {
            model: model.into(),
            settings: String::new(),
            queue: Mutex::new(VecDeque::new()),
            responder: Some(Box::new(f)),
            log: Mutex::new(Vec::new()),
        }
    }

    /// The same model reporting `settings` as its [`Vlm::settings`] (to test how settings
    /// reach cache keys and result digests).
    pub fn with_settings(mut self, settings: impl Into<String>) -> Self {
        self.settings = settings.into();
        self
    }

    /// The requests received so far, in order.
    pub fn requests(&self) -> Vec<VlmRequest> {
        lock(&self.log).clone()
    }

    fn respond(&self, request: &VlmRequest) -> Result<Answer, VlmError> {
        let answered = {
            let mut log = lock(&self.log);
            log.push(request.clone());
            log.len() - 1
        };
        let content = match &self.responder {
            Some(f) => f(request)?,
            None => lock(&self.queue)
                .pop_front()
                .ok_or_else(|| VlmError::ScriptExhausted {
                    task: request.task.clone(),
                    answered,
                })?,
        };
        Ok(Answer::new(content, TokenUsage::default()))
    }
}

impl Vlm for Scripted {
    fn model(&self) -> &str {
        &self.model
    }

    fn settings(&self) -> &str {
        &self.settings
    }

    async fn answer(&self, request: &VlmRequest) -> Result<Answer, VlmError> {
        self.respond(request)
    }
}
