//! [`SharedVlm`]: any [`Vlm`] behind one shareable type, so that the evaluator needs no
//! type parameter; it counts the run's answers and waits for them as the scene's schedule
//! says (its CPU slot lent out meanwhile, bounded by its time budget).

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;

use crate::EvalError;
use sceneeval_vlm::{Answer, Meter, Usage, Vlm, VlmError, VlmRequest};

type BoxedAnswer<'a> = Pin<Box<dyn Future<Output = Result<Answer, VlmError>> + Send + 'a>>;

trait ErasedVlm: Send + Sync {
    fn model(&self) -> &str;
    fn settings(&self) -> &str;
    fn answer_boxed<'a>(&'a self, request: &'a VlmRequest) -> BoxedAnswer<'a>;
    fn judged(&self, request: &VlmRequest, answer: &Answer, usable: bool);
}

impl<T: Vlm> ErasedVlm for T {
    fn model(&self) -> &str {
        Vlm::model(self)
    }

    fn settings(&self) -> &str {
        Vlm::settings(self)
    }

    fn answer_boxed<'a>(&'a self, request: &'a VlmRequest) -> BoxedAnswer<'a> {
        Box::pin(self.answer(request))
    }

    fn judged(&self, request: &VlmRequest, answer: &Answer, usable: bool) {
        Vlm::judged(self, request, answer, usable);
    }
}

/// What checks that the endpoint answers before the first scene asks it.
type EndpointCheckFn = dyn Fn() -> Result<(), EvalError> + Send + Sync;

/// A [`Vlm`] of any type, cheap to clone (shared): what [`crate::Evaluator::with_vlm`] takes.
/// Wrap the model in [`sceneeval_vlm::Cached`] first so that a re-run asks nothing already
/// answered.
///
/// Its clones share the counts of the answers given so far ([`SharedVlm::usage`], what a
/// progress display shows while a run goes on) and, when one is set, the check of the
/// endpoint a batch makes before its first scene ([`SharedVlm::with_endpoint_check`]). In a
/// batch, a scene waiting for an answer lends its CPU worker to another scene, and the wait
/// ends with an error when the scene's time budget runs out ([`BudgetSpent`](crate::BudgetSpent)).
///
/// ```
/// use sceneeval_eval::SharedVlm;
/// use sceneeval_vlm::{AnswerContent, Scripted, Session, Vlm, check::EndpointCheck};
/// let vlm = SharedVlm::new(Scripted::queue("m", [
///     AnswerContent::Json { value: serde_json::json!({"colour": "red", "reason": "red"}) },
/// ]));
/// assert_eq!(vlm.clone().model(), "m");
/// pollster::block_on(Session::new(vlm.clone()).ask(&EndpointCheck::new())).unwrap();
/// assert_eq!(vlm.usage().requests, 1);
/// ```
#[derive(Clone)]
pub struct SharedVlm {
    inner: Arc<dyn ErasedVlm>,
    counts: Arc<Meter>,
    check: Option<Arc<EndpointCheckFn>>,
}

/// Counts `result` in `meter`: an answer (fresh or from the cache) or a failed request.
fn record(meter: &Meter, result: &Result<Answer, VlmError>) {
    match result {
        Ok(answer) => meter.answer(answer.usage, answer.from_cache),
        Err(_) => meter.failure(),
    }
}

impl std::fmt::Debug for SharedVlm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SharedVlm")
            .field("model", &self.inner.model())
            .field("settings", &self.inner.settings())
            .field("endpoint_check", &self.check.is_some())
            .finish()
    }
}

impl SharedVlm {
    /// Shares `vlm`.
    pub fn new(vlm: impl Vlm + 'static) -> Self {
        SharedVlm {
            inner: Arc::new(vlm),
            counts: Arc::default(),
            check: None,
        }
    }

    /// Sets what checks that the endpoint answers: a batch calls it once, before the first
    /// scene it evaluates (not when every scene's earlier result is reused), and stops with its
    /// error. [`crate::VlmOptions::attach`] sets one that sends one small request (as
    /// `sceneeval vlm check` does), so that an unreachable server or a refused key stops a run
    /// in seconds with one message.
    pub fn with_endpoint_check(
        mut self,
        check: impl Fn() -> Result<(), EvalError> + Send + Sync + 'static,
    ) -> Self {
        self.check = Some(Arc::new(check));
        self
    }

    /// Runs the endpoint check, if one is set.
    ///
    /// # Errors
    /// The check's error.
    pub fn check_endpoint(&self) -> Result<(), EvalError> {
        self.check.as_ref().map_or(Ok(()), |check| check())
    }

    /// The answers given so far through this model and its clones, over all scenes: requests
    /// answered (`requests`, of which `cache_hits` from the cache), requests that failed
    /// (`failed_requests`) and tokens (`tokens` of fresh answers, `cached_tokens` of cached
    /// ones). Questions and re-asks are counted by each scene's session, not here (zero).
    pub fn usage(&self) -> Usage {
        self.counts.usage()
    }
}

impl Vlm for SharedVlm {
    fn model(&self) -> &str {
        self.inner.model()
    }

    fn settings(&self) -> &str {
        self.inner.settings()
    }

    fn answer(&self, request: &VlmRequest) -> impl Future<Output = Result<Answer, VlmError>> + Send {
        // Owned copies (the images are shared, not copied): the future borrows nothing.
        let (inner, request, counts) = (self.inner.clone(), request.clone(), self.counts.clone());
        async move {
            let answer = inner.answer_boxed(&request);
            let result = crate::schedule::wait_for_model(answer, &request.task, inner.model()).await;
            record(&counts, &result);
            result
        }
    }

    fn judged(&self, request: &VlmRequest, answer: &Answer, usable: bool) {
        self.inner.judged(request, answer, usable);
    }
}
