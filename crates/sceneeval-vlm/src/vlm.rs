//! The [`Vlm`] trait.

use std::future::Future;
use std::sync::Arc;

use crate::{Answer, VlmError, VlmRequest};

/// A vision-language model: answers one structured request.
///
/// The future is `Send` and tied to no runtime; an implementation that needs one (the HTTP
/// client of `sceneeval-vlm-openai` needs tokio) says so. Implementations answer independent
/// requests concurrently when polled concurrently.
///
/// Implemented here by [`crate::Cached`] (a disk cache in front of another model),
/// [`crate::Replay`] (the cache alone) and [`crate::Scripted`] (answers given in advance, for
/// tests); blanket implementations cover `&T`, `Arc<T>` and `Box<T>`.
pub trait Vlm: Send + Sync {
    /// The model name, part of every cache key.
    fn model(&self) -> &str;

    /// Everything besides the request and the model name that changes this model's answers
    /// (image detail, sampling temperature and seed, reply token limit), as canonical text
    /// such as `detail=low;seed=42;temperature=0`; part of every cache key and of the result
    /// digest, so that answers obtained with other settings are never reused. Empty (the
    /// default) for models without such settings.
    fn settings(&self) -> &str {
        ""
    }

    /// Answers one request.
    ///
    /// A reply that cannot be used (not JSON, refused, truncated) is an [`Answer`] with the
    /// matching [`crate::AnswerContent`]; an error means no reply was obtained.
    fn answer(&self, request: &VlmRequest) -> impl Future<Output = Result<Answer, VlmError>> + Send;
}

/// Implements [`Vlm`] for a pointer to a model by forwarding every method to the model.
macro_rules! forward_vlm {
    ($($pointer:ty),*) => {$(
        impl<T: Vlm + ?Sized> Vlm for $pointer {
            fn model(&self) -> &str {
                (**self).model()
            }

            fn settings(&self) -> &str {
                (**self).settings()
            }

            fn answer(&self, request: &VlmRequest) -> impl Future<Output = Result<Answer, VlmError>> + Send {
                (**self).answer(request)
            }
        }
    )*};
}

forward_vlm!(&T, Arc<T>, Box<T>);
