//! [`RuntimeVlm`]: a model that answers on a tokio runtime of its own, for synchronous callers.

use std::sync::Arc;

use sceneeval_vlm::{Answer, Vlm, VlmError, VlmRequest};
use tokio::runtime::Handle;
use tokio::sync::oneshot;

use crate::OpenAiError;

/// A [`Vlm`] whose answers run on a tokio runtime driven by a thread of its own.
///
/// [`crate::OpenAiVlm`]'s futures need a tokio runtime (reqwest's connections, timers), while
/// synchronous code, such as `sceneeval::Evaluator`'s worker threads, polls futures without
/// one. Wrapping the client in a `RuntimeVlm` makes its futures runnable anywhere: each
/// request is spawned onto the runtime when its future is first polled (so that futures polled
/// together, e.g. by `join_all`, are in flight together) and its answer awaited through a
/// channel; dropping the future before it is done cancels the request. The runtime has one
/// thread (requests wait on the network, not on the CPU); dropping the `RuntimeVlm` stops the
/// runtime and waits for its thread to end.
///
/// ```
/// use sceneeval_vlm::Vlm;
/// use sceneeval_vlm_openai::{OpenAiConfig, OpenAiVlm, RuntimeVlm};
/// let client = OpenAiVlm::new(OpenAiConfig::new("http://127.0.0.1:9/v1", "m")).unwrap();
/// let vlm = RuntimeVlm::start(client).unwrap();
/// assert_eq!((vlm.model(), vlm.settings()), ("m", "detail=low;seed=42;temperature=0"));
/// ```
#[derive(Debug)]
pub struct RuntimeVlm<V> {
    inner: Arc<V>,
    handle: Handle,
    /// Dropped (in `drop`) to tell the runtime's thread to stop.
    stop: Option<oneshot::Sender<()>>,
    /// The runtime's thread, joined in `drop`.
    thread: Option<std::thread::JoinHandle<()>>,
}

impl<V> Drop for RuntimeVlm<V> {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(thread) = self.thread.take()
            && thread.thread().id() != std::thread::current().id()
        {
            // The thread only runs the runtime; it ends once the runtime has shut down.
            let _ = thread.join();
        }
    }
}

impl<V: Vlm + 'static> RuntimeVlm<V> {
    /// Starts the runtime and its thread (named `vlm-runtime`) for `vlm`.
    ///
    /// # Errors
    /// [`OpenAiError::Runtime`] when the runtime or its thread cannot be started.
    pub fn start(vlm: V) -> Result<Self, OpenAiError> {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .map_err(|source| OpenAiError::Runtime { source })?;
        let handle = runtime.handle().clone();
        let (stop, stopped) = oneshot::channel::<()>();
        let thread = std::thread::Builder::new()
            .name("vlm-runtime".into())
            .spawn(move || {
                // Runs spawned requests until the sender is dropped (or sends).
                let _ = runtime.block_on(stopped);
            })
            .map_err(|source| OpenAiError::Runtime { source })?;
        Ok(RuntimeVlm {
            inner: Arc::new(vlm),
            handle,
            stop: Some(stop),
            thread: Some(thread),
        })
    }

    /// The wrapped model.
    pub fn inner(&self) -> &V {
        &self.inner
    }
}

impl<V: Vlm + 'static> Vlm for RuntimeVlm<V> {
    fn model(&self) -> &str {
        self.inner.model()
    }

    fn settings(&self) -> &str {
        self.inner.settings()
    }

    fn answer(&self, request: &VlmRequest) -> impl Future<Output = Result<Answer, VlmError>> + Send {
        let (inner, request, handle) = (Arc::clone(&self.inner), request.clone(), self.handle.clone());
        async move {
            // Spawned when first polled: in flight from then on, whoever polls next.
            let (task, model) = (request.task.clone(), inner.model().to_owned());
            let spawned = handle.spawn(async move { inner.answer(&request).await });
            // Dropped before the answer came (a scene's budget ran out): the request is
            // cancelled, so that it stops holding a place among those in flight.
            let _cancel = AbortOnDrop(spawned.abort_handle());
            spawned.await.map_err(|e| VlmError::Backend {
                task,
                model,
                permanent: true,
                source: Box::new(e),
            })?
        }
    }
}

/// Aborts a spawned task when dropped (a no-op once the task is done).
struct AbortOnDrop(tokio::task::AbortHandle);

impl Drop for AbortOnDrop {
    fn drop(&mut self) {
        self.0.abort();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_vlm::{AnswerContent, TokenUsage};

    /// Answers after a tokio timer of this many milliseconds (a timer panics outside a tokio
    /// runtime).
    struct NeedsTokio(u64);

    impl Vlm for NeedsTokio {
        fn model(&self) -> &str {
            "needs-tokio"
        }

        async fn answer(&self, _request: &VlmRequest) -> Result<Answer, VlmError> {
            tokio::time::sleep(std::time::Duration::from_millis(self.0)).await;
            Ok(Answer {
                content: AnswerContent::Json {
                    value: serde_json::json!({"ok": true}),
                },
                usage: TokenUsage::default(),
                from_cache: false,
            })
        }
    }

    fn request() -> VlmRequest {
        VlmRequest {
            task: "t".into(),
            system: "s".into(),
            user_text: "u".into(),
            images: Vec::new(),
            schema: sceneeval_vlm::ResponseSchema {
                name: "t".into(),
                schema: serde_json::json!({"type": "object"}),
            },
        }
    }

    /// How many threads of this process are named `vlm-runtime` (no other test of this
    /// binary starts one, so the counts below do not race).
    #[cfg(target_os = "linux")]
    fn runtime_threads() -> usize {
        std::fs::read_dir("/proc/self/task")
            .unwrap()
            .filter(|t| {
                std::fs::read_to_string(t.as_ref().unwrap().path().join("comm"))
                    .is_ok_and(|name| name.trim() == "vlm-runtime")
            })
            .count()
    }

    #[test]
    fn answers_come_from_its_own_runtime_thread_which_ends_when_dropped() {
        #[cfg(target_os = "linux")]
        assert_eq!(runtime_threads(), 0);
        let vlm = RuntimeVlm::start(NeedsTokio(1)).unwrap();
        assert_eq!(vlm.model(), "needs-tokio");
        // Polled by pollster on this thread, which has no runtime.
        for _ in 0..3 {
            let answer = pollster::block_on(vlm.answer(&request())).unwrap();
            assert_eq!(
                answer.content,
                AnswerContent::Json {
                    value: serde_json::json!({"ok": true})
                }
            );
        }
        #[cfg(target_os = "linux")]
        assert_eq!(runtime_threads(), 1);
        drop(vlm);
        #[cfg(target_os = "linux")]
        assert_eq!(runtime_threads(), 0);
    }
}
