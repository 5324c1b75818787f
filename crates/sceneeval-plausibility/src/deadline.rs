//! A time budget checked cooperatively by the metrics.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::PlausibilityError;

/// When an evaluation must give up, and a flag another thread can raise to stop it early.
///
/// Metrics check it between metrics and inside their long loops (per candidate pair in
/// collision, per object in support, accessibility and out-of-bounds, per chunk of 64 raster
/// rows and per room in navigability, per opening and per polygon drawn into an occlusion map
/// in opening clearance) and stop with [`PlausibilityError::DeadlineExceeded`] once it has
/// passed. It cannot interrupt one step of such a loop (one pair's narrow phase, bounded by
/// `depth_sample_budget`; one object's rays, bounded by `max_face_samples`); every step is
/// bounded by a parameter range or the raster budget, so none runs unbounded. A check costs
/// one clock read.
///
/// ```
/// use std::time::Duration;
/// use sceneeval_plausibility::Deadline;
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

    /// Stops every evaluation holding this deadline (or a clone of it) at its next check.
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
    /// [`PlausibilityError::DeadlineExceeded`] naming `stage` (the metric that was running or
    /// about to run).
    pub fn check(&self, stage: &'static str) -> Result<(), PlausibilityError> {
        if self.expired() {
            Err(PlausibilityError::DeadlineExceeded {
                stage,
                budget_seconds: self.budget.map(|b| b.as_secs_f64()),
            })
        } else {
            Ok(())
        }
    }
}
