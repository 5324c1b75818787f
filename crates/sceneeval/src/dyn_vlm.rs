//! [`SharedVlm`]: any [`Vlm`] behind one shareable type, so that the evaluator needs no
//! type parameter.

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;

use crate::vlm::{Answer, Vlm, VlmError, VlmRequest};

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

/// A [`Vlm`] of any type, cheap to clone (shared): what [`crate::Evaluator::with_vlm`] takes.
/// Wrap the model in [`crate::vlm::Cached`] first so that a re-run asks nothing already
/// answered.
///
/// ```
/// use sceneeval::SharedVlm;
/// use sceneeval::vlm::{Scripted, Vlm};
/// let vlm = SharedVlm::new(Scripted::queue("m", []));
/// assert_eq!(vlm.clone().model(), "m");
/// ```
#[derive(Clone)]
pub struct SharedVlm {
    inner: Arc<dyn ErasedVlm>,
}

impl std::fmt::Debug for SharedVlm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SharedVlm")
            .field("model", &self.inner.model())
            .field("settings", &self.inner.settings())
            .finish()
    }
}

impl SharedVlm {
    /// Shares `vlm`.
    pub fn new(vlm: impl Vlm + 'static) -> Self {
        SharedVlm { inner: Arc::new(vlm) }
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
        let (inner, request) = (self.inner.clone(), request.clone());
        async move { inner.answer_boxed(&request).await }
    }

    fn judged(&self, request: &VlmRequest, answer: &Answer, usable: bool) {
        self.inner.judged(request, answer, usable);
    }
}
