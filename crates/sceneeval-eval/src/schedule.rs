//! How scenes share the CPU while they wait for the VLM (see `docs/architecture.md`,
//! "Scenes waiting for the model").
//!
//! A run whose scenes ask a VLM evaluates more scenes at once than it has CPU workers: each
//! scene runs on a thread of its own, but only a scene holding one of the run's [`CpuSlots`]
//! (as many as worker threads) computes. While a scene waits for the model, its slot goes to
//! another scene; it takes one again when its answers are in. The scene's thread says which
//! scene it works for ([`SceneSchedule::enter`]); `wait_for_model` (what `SharedVlm` answers
//! through) gives the slot back while the model's answer is pending and ends the wait with an
//! error when the scene's time budget runs out.
//!
//! The evaluator's VLM ([`crate::SharedVlm`]) waits through this module, so it lives with the
//! evaluator; the batch of a run (`sceneeval_run::run_batch`) makes the slots and enters each
//! scene. Outside a batch nothing is lent or bounded.

use std::cell::RefCell;
use std::collections::BinaryHeap;
use std::future::Future;
use std::pin::Pin;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, OnceLock, PoisonError};
use std::task::{Context, Poll, Waker};
use std::time::{Duration, Instant};

use sceneeval_vlm::{Answer, VlmError};

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The places for scenes that compute: as many as the run's worker threads (made by the batch,
/// `sceneeval_run::run_batch`).
#[derive(Debug)]
pub struct CpuSlots {
    free: Mutex<usize>,
    freed: Condvar,
}

impl CpuSlots {
    /// `n` slots (at least one), shared by the scenes of a run.
    pub fn new(n: usize) -> Arc<Self> {
        Arc::new(CpuSlots {
            free: Mutex::new(n.max(1)),
            freed: Condvar::new(),
        })
    }

    /// Blocks until a slot is free and takes it.
    fn acquire(&self) {
        let mut free = lock(&self.free);
        while *free == 0 {
            free = self.freed.wait(free).unwrap_or_else(PoisonError::into_inner);
        }
        *free -= 1;
    }

    fn release(&self) {
        *lock(&self.free) += 1;
        self.freed.notify_one();
    }
}

/// One scene's place in the schedule: its CPU slot (held or lent out while it waits for the
/// model) and when its time budget ends.
#[derive(Debug)]
pub struct SceneSchedule {
    slots: Option<Arc<CpuSlots>>,
    state: Mutex<SlotState>,
    deadline: OnceLock<(Instant, Duration)>,
}

#[derive(Debug, Default)]
struct SlotState {
    held: bool,
    waiting: usize,
}

thread_local! {
    static CURRENT: RefCell<Option<Arc<SceneSchedule>>> = const { RefCell::new(None) };
}

/// While alive, the current thread works for a scene; dropping it gives the scene's CPU slot
/// back.
#[derive(Debug)]
pub struct Entered {
    schedule: Arc<SceneSchedule>,
    previous: Option<Arc<SceneSchedule>>,
}

impl SceneSchedule {
    /// Makes the current thread work for a scene that computes in one of `slots` (none: no
    /// limit) and whose waits for the model end at `deadline` (the instant and the budget it
    /// comes from; see also [`Entered::set_deadline`]); blocks until a slot is free.
    pub fn enter(slots: Option<Arc<CpuSlots>>, deadline: Option<(Instant, Duration)>) -> Entered {
        if let Some(s) = &slots {
            s.acquire();
        }
        let schedule = Arc::new(SceneSchedule {
            state: Mutex::new(SlotState {
                held: slots.is_some(),
                waiting: 0,
            }),
            slots,
            deadline: OnceLock::new(),
        });
        if let Some(d) = deadline {
            let _ = schedule.deadline.set(d);
        }
        let previous = CURRENT.with(|c| c.replace(Some(schedule.clone())));
        Entered { schedule, previous }
    }

    fn current() -> Option<Arc<SceneSchedule>> {
        CURRENT.with(|c| c.borrow().clone())
    }

    /// One more wait for the model: the first lends the slot out.
    fn begin_wait(&self) {
        let mut s = lock(&self.state);
        s.waiting += 1;
        if s.waiting == 1
            && s.held
            && let Some(slots) = &self.slots
        {
            s.held = false;
            slots.release();
        }
    }

    /// One wait fewer: after the last, the slot is taken back (blocking until one is free).
    fn end_wait(&self) {
        let take = {
            let mut s = lock(&self.state);
            s.waiting = s.waiting.saturating_sub(1);
            s.waiting == 0 && !s.held && self.slots.is_some()
        };
        if take && let Some(slots) = &self.slots {
            slots.acquire();
            lock(&self.state).held = true;
        }
    }
}

impl Entered {
    /// Sets when the scene's waits for the model end (the instant and the budget it comes
    /// from), unless already set.
    pub fn set_deadline(&self, deadline: Option<(Instant, Duration)>) {
        if let Some(d) = deadline {
            let _ = self.schedule.deadline.set(d);
        }
    }
}

impl Drop for Entered {
    fn drop(&mut self) {
        CURRENT.with(|c| c.replace(self.previous.take()));
        let mut s = lock(&self.schedule.state);
        if s.held
            && let Some(slots) = &self.schedule.slots
        {
            s.held = false;
            slots.release();
        }
    }
}

/// The scene's time budget ran out while it waited for the model.
#[derive(Debug, thiserror::Error)]
#[error("the scene's time budget of {} s ran out while waiting for the model", .budget.as_secs_f64())]
pub struct BudgetSpent {
    /// The budget.
    pub budget: Duration,
}

/// `answer` (the model's answer to a `task` request of `model`), awaited as the scene the
/// current thread works for waits for the model: its CPU slot lent out meanwhile, and the
/// wait ended by a [`BudgetSpent`] error (a transient [`VlmError::Backend`]) when its time
/// budget runs out first. Outside a scene (no [`SceneSchedule::enter`] on this thread) it is
/// `answer` itself.
pub(crate) fn wait_for_model<F>(answer: F, task: &str, model: &str) -> ModelWait<F>
where
    F: Future<Output = Result<Answer, VlmError>> + Unpin,
{
    ModelWait {
        answer,
        task: task.to_owned(),
        model: model.to_owned(),
        waiting: None,
        alarm_set: false,
    }
}

/// See [`wait_for_model`].
pub(crate) struct ModelWait<F> {
    answer: F,
    task: String,
    model: String,
    /// The scene this wait counts for, once it has waited.
    waiting: Option<Arc<SceneSchedule>>,
    alarm_set: bool,
}

impl<F> ModelWait<F> {
    fn done(&mut self) {
        if let Some(scene) = self.waiting.take() {
            scene.end_wait();
        }
    }
}

impl<F> Drop for ModelWait<F> {
    fn drop(&mut self) {
        self.done();
    }
}

impl<F> Future for ModelWait<F>
where
    F: Future<Output = Result<Answer, VlmError>> + Unpin,
{
    type Output = Result<Answer, VlmError>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        let this = self.get_mut();
        if let Poll::Ready(result) = Pin::new(&mut this.answer).poll(cx) {
            this.done();
            return Poll::Ready(result);
        }
        let scene = match &this.waiting {
            Some(s) => s.clone(),
            None => match SceneSchedule::current() {
                Some(s) => {
                    s.begin_wait();
                    this.waiting = Some(s.clone());
                    s
                }
                None => return Poll::Pending,
            },
        };
        if let Some(&(at, budget)) = scene.deadline.get() {
            if Instant::now() >= at {
                this.done();
                return Poll::Ready(Err(VlmError::Backend {
                    task: this.task.clone(),
                    model: this.model.clone(),
                    permanent: false,
                    source: Box::new(BudgetSpent { budget }),
                }));
            }
            if !this.alarm_set {
                this.alarm_set = true;
                wake_at(at, cx.waker().clone());
            }
        }
        Poll::Pending
    }
}

/// Wakes `waker` at `at`, from one timer thread shared by the process.
fn wake_at(at: Instant, waker: Waker) {
    let timer = TIMER.get_or_init(|| {
        let timer = Arc::new(Timer::default());
        let running = timer.clone();
        let started = std::thread::Builder::new()
            .name("sceneeval-timer".into())
            .spawn(move || running.run());
        if let Err(e) = started {
            tracing::warn!(error = %e, "no timer thread: waits for the VLM are not bounded by the time budget");
        }
        timer
    });
    lock(&timer.alarms).push(Alarm { at, waker });
    timer.changed.notify_one();
}

static TIMER: OnceLock<Arc<Timer>> = OnceLock::new();

#[derive(Default)]
struct Timer {
    alarms: Mutex<BinaryHeap<Alarm>>,
    changed: Condvar,
}

struct Alarm {
    at: Instant,
    waker: Waker,
}

impl PartialEq for Alarm {
    fn eq(&self, other: &Self) -> bool {
        self.at == other.at
    }
}
impl Eq for Alarm {}
impl PartialOrd for Alarm {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Alarm {
    /// The earliest alarm is the greatest (the top of the max-heap).
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other.at.cmp(&self.at)
    }
}

impl Timer {
    fn run(&self) {
        let mut alarms = lock(&self.alarms);
        loop {
            let now = Instant::now();
            while alarms.peek().is_some_and(|a| a.at <= now) {
                if let Some(a) = alarms.pop() {
                    a.waker.wake();
                }
            }
            alarms = match alarms.peek().map(|a| a.at - now) {
                Some(wait) => {
                    self.changed
                        .wait_timeout(alarms, wait)
                        .unwrap_or_else(PoisonError::into_inner)
                        .0
                }
                None => self.changed.wait(alarms).unwrap_or_else(PoisonError::into_inner),
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_vlm::{AnswerContent, TokenUsage};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Whether the answer came, and who to wake when it does; how often it was polled.
    type Shared = Arc<(Mutex<(bool, Option<Waker>)>, AtomicUsize)>;

    /// An answer that comes when the flag is raised (polled again by whoever raises it).
    struct Later(Shared);

    impl Future for Later {
        type Output = Result<Answer, VlmError>;
        fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
            let mut s = lock(&self.0.0);
            if s.0 {
                return Poll::Ready(Ok(Answer {
                    content: AnswerContent::Json {
                        value: serde_json::json!({}),
                    },
                    usage: TokenUsage::default(),
                    from_cache: false,
                }));
            }
            self.0.1.fetch_add(1, Ordering::SeqCst);
            s.1 = Some(cx.waker().clone());
            Poll::Pending
        }
    }

    #[test]
    fn a_scene_waiting_for_the_model_lends_its_slot() {
        let slots = CpuSlots::new(1);
        let shared = Arc::new((Mutex::new((false, None::<Waker>)), AtomicUsize::new(0)));
        let answer = Later(shared.clone());
        let s = slots.clone();
        let waiter = std::thread::spawn(move || {
            let _scene = SceneSchedule::enter(Some(s), None);
            pollster::block_on(wait_for_model(answer, "t", "m")).unwrap();
            // Back from the wait: the slot is held again.
            assert_eq!(*slots_free(&_scene), 0);
        });
        // Once the first scene waits, a second one gets the only slot.
        while shared.1.load(Ordering::SeqCst) == 0 {
            std::thread::yield_now();
        }
        let second = SceneSchedule::enter(Some(slots.clone()), None);
        assert_eq!(*lock(&slots.free), 0);
        // The answer comes; the first scene needs the slot back, which the second still holds.
        {
            let mut s = lock(&shared.0);
            s.0 = true;
            if let Some(w) = s.1.take() {
                w.wake();
            }
        }
        drop(second);
        waiter.join().unwrap();
        assert_eq!(*lock(&slots.free), 1);
    }

    fn slots_free(e: &Entered) -> MutexGuard<'_, usize> {
        lock(&e.schedule.slots.as_ref().unwrap().free)
    }

    #[test]
    fn the_budget_ends_a_wait() {
        let shared = Arc::new((Mutex::new((false, None::<Waker>)), AtomicUsize::new(0)));
        let budget = Duration::from_millis(50);
        let _scene = SceneSchedule::enter(None, Some((Instant::now() + budget, budget)));
        let err = pollster::block_on(wait_for_model(Later(shared), "obj_matching", "m")).unwrap_err();
        assert!(!err.is_permanent());
        let cause = std::error::Error::source(&err).unwrap().to_string();
        assert_eq!(
            cause,
            "the scene's time budget of 0.05 s ran out while waiting for the model"
        );
        // Outside a scene, nothing is lent and nothing bounds the wait.
        drop(_scene);
        let ready = Arc::new((Mutex::new((true, None::<Waker>)), AtomicUsize::new(0)));
        assert!(pollster::block_on(wait_for_model(Later(ready), "t", "m")).is_ok());
    }
}
