//! A time budget checked cooperatively by long computations on a scene.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// When a computation must give up, and a flag another thread can raise to stop it early.
///
/// The crates that compute on a scene check it between their stages and inside their long
/// loops (the plausibility metrics per pair, object, raster chunk or opening; the stability
/// metric per decomposed mesh and per simulation step) and stop with [`DeadlineExceeded`]
/// once it has passed. It cannot interrupt one step of such a loop; every step is bounded by
/// a parameter range or a memory budget, so none runs unbounded. A check costs one clock read.
///
/// ```
/// use std::time::Duration;
/// use sceneeval_scene::Deadline;
///
/// assert!(!Deadline::none().expired());
/// let d = Deadline::after(Duration::ZERO);
/// assert!(d.expired());
/// assert!(d.check("collision").unwrap_err().to_string().contains("collision"));
/// let c = Deadline::none();
/// c.cancel();
/// assert!(c.expired());
/// ```
#[derive(Debug, Clone, Default)]
pub struct Deadline {
    at: Option<Instant>,
    budget: Option<Duration>,
    cancelled: Arc<AtomicBool>,
}

/// A [`Deadline`] has passed (or was cancelled) while `stage` was running or about to run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{stage} stopped: {}", match .budget_seconds {
    Some(b) => format!("the scene's time budget of {b} s is used up"),
    None => "the evaluation was cancelled".to_owned(),
})]
pub struct DeadlineExceeded {
    /// The stage (a metric's name) that was running or about to run.
    pub stage: &'static str,
    /// The budget in seconds, `None` when the deadline was cancelled without one.
    pub budget_seconds: Option<f64>,
}

impl Deadline {
    /// No time limit (it can still be cancelled).
    pub fn none() -> Self {
        Deadline::default()
    }

    /// A limit `budget` from now.
    pub fn after(budget: Duration) -> Self {
        Deadline {
            at: Instant::now().checked_add(budget),
            budget: Some(budget),
            cancelled: Arc::default(),
        }
    }

    /// The budget this deadline was made with, if any.
    pub fn budget(&self) -> Option<Duration> {
        self.budget
    }

    /// Stops every computation holding this deadline (or a clone of it) at its next check.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether the time is up or the deadline was cancelled.
    #[inline]
    pub fn expired(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed) || self.at.is_some_and(|at| Instant::now() >= at)
    }

    /// `Ok` while the deadline has not passed.
    ///
    /// # Errors
    /// [`DeadlineExceeded`] naming `stage` (the stage that was running or about to run).
    pub fn check(&self, stage: &'static str) -> Result<(), DeadlineExceeded> {
        if self.expired() {
            Err(DeadlineExceeded {
                stage,
                budget_seconds: self.budget.map(|b| b.as_secs_f64()),
            })
        } else {
            Ok(())
        }
    }
}
