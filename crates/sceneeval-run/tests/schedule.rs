//! A batch whose scenes ask a VLM evaluates more scenes at once than it has worker threads
//! (`BatchOptions::scenes_in_flight`), each scene lending its CPU slot while it waits; the
//! scene's time budget ends a wait for the model. The model here answers the functional-sides
//! question of fixture scene 8 (accessibility asks it), in process, only once enough requests
//! are pending at once: the test checks what is in flight together, not how fast.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::future::Future;
use std::path::{Path, PathBuf};
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Waker};
use std::time::Duration;

use sceneeval_eval::{EvaluationPlan, Evaluator, Metric, SharedVlm};
use sceneeval_io::AssetLibrary;
use sceneeval_run::{BatchOptions, find_scenes, run_batch};
use sceneeval_vlm::{Answer, AnswerContent, TokenUsage, Vlm, VlmError, VlmRequest};
use serde_json::json;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// Answers functional-sides requests once `quorum` of them are pending at once (or after
/// `fallback`, so that a broken schedule fails the test instead of hanging it).
struct Quorum {
    quorum: usize,
    fallback: Duration,
    state: Arc<QuorumState>,
}

#[derive(Default)]
struct QuorumState {
    pending: AtomicUsize,
    peak: AtomicUsize,
    answered: AtomicUsize,
    cancelled: AtomicUsize,
    open: AtomicBool,
    timed_out: AtomicBool,
    wakers: Mutex<Vec<Waker>>,
}

impl QuorumState {
    fn open(&self) {
        self.open.store(true, Ordering::SeqCst);
        for w in self.wakers.lock().unwrap().drain(..) {
            w.wake();
        }
    }
}

struct Pending {
    state: Arc<QuorumState>,
    ids: Vec<String>,
    registered: bool,
    done: bool,
}

impl Future for Pending {
    type Output = Result<Answer, VlmError>;

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        if !self.registered {
            self.registered = true;
            let now = self.state.pending.fetch_add(1, Ordering::SeqCst) + 1;
            self.state.peak.fetch_max(now, Ordering::SeqCst);
        }
        if self.state.open.load(Ordering::SeqCst) {
            self.done = true;
            self.state.pending.fetch_sub(1, Ordering::SeqCst);
            self.state.answered.fetch_add(1, Ordering::SeqCst);
            let assessments: Vec<_> = self
                .ids
                .iter()
                .map(|id| json!({"obj_id": id, "obj_description": "", "functional_sides": ["front"], "reason": "r"}))
                .collect();
            return Poll::Ready(Ok(Answer {
                content: AnswerContent::Json {
                    value: json!({ "assessments": assessments }),
                },
                usage: TokenUsage::default(),
                from_cache: false,
            }));
        }
        self.state.wakers.lock().unwrap().push(cx.waker().clone());
        // Re-checked after registering the waker, so that an opening in between is not missed.
        if self.state.open.load(Ordering::SeqCst) {
            cx.waker().wake_by_ref();
        }
        Poll::Pending
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if self.registered && !self.done {
            self.state.pending.fetch_sub(1, Ordering::SeqCst);
            self.state.cancelled.fetch_add(1, Ordering::SeqCst);
        }
    }
}

impl Vlm for Quorum {
    fn model(&self) -> &str {
        "quorum"
    }

    fn answer(&self, request: &VlmRequest) -> impl Future<Output = Result<Answer, VlmError>> + Send {
        assert_eq!(request.task, "obj_functional_sides");
        let ids: Vec<String> = request
            .user_text
            .split("obj_id: \"")
            .skip(1)
            .filter_map(|rest| rest.split('"').next())
            .map(str::to_owned)
            .collect();
        let state = self.state.clone();
        let (quorum, fallback, s) = (self.quorum, self.fallback, state.clone());
        std::thread::spawn(move || {
            let start = std::time::Instant::now();
            while !s.open.load(Ordering::SeqCst) {
                if s.pending.load(Ordering::SeqCst) >= quorum {
                    s.open();
                    break;
                }
                if start.elapsed() > fallback {
                    s.timed_out.store(true, Ordering::SeqCst);
                    s.open();
                    break;
                }
                std::thread::sleep(Duration::from_millis(2));
            }
        });
        Pending {
            state,
            ids,
            registered: false,
            done: false,
        }
    }
}

/// `n` copies of fixture scene 8 (`scene_801.json`, ...) in a new folder.
fn scenes(n: usize) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for i in 0..n {
        std::fs::copy(
            fixtures().join("scenes/scene_8.json"),
            dir.path().join(format!("scene_{}.json", 801 + i)),
        )
        .unwrap();
    }
    dir
}

fn plan(budget: Option<f64>) -> EvaluationPlan {
    EvaluationPlan {
        metrics: vec![Metric::Accessibility],
        time_budget_s: budget,
        ..EvaluationPlan::default()
    }
}

/// Runs `n` copies of scene 8 (accessibility, time budget `budget`) on `threads` worker
/// threads with `scenes_in_flight`, asking a [`Quorum`] of `quorum`: the output folder, the
/// outcome, the model's counts and the evaluator's VLM.
fn run(
    n: usize,
    threads: usize,
    scenes_in_flight: Option<usize>,
    quorum: usize,
    budget: Option<f64>,
) -> (
    tempfile::TempDir,
    sceneeval_run::BatchOutcome,
    Arc<QuorumState>,
    SharedVlm,
) {
    let dir = scenes(n);
    let out = tempfile::tempdir().unwrap();
    let state = Arc::new(QuorumState::default());
    let model = Quorum {
        quorum,
        fallback: Duration::from_secs(60),
        state: state.clone(),
    };
    let vlm = SharedVlm::new(model);
    let evaluator = Evaluator::new(plan(budget)).unwrap().with_vlm(vlm.clone());
    let assets =
        AssetLibrary::from_specs(&[format!("fixture={}", fixtures().join("assets").display())]).unwrap();
    let set = find_scenes(dir.path()).unwrap();
    let options = BatchOptions {
        out_dir: out.path().to_owned(),
        scenes_in_flight,
        ..BatchOptions::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let outcome = pool
        .install(|| run_batch(&set.scenes, &evaluator, &assets, &options, &|_| {}))
        .unwrap();
    (out, outcome, state, vlm)
}

#[test]
fn scenes_waiting_for_the_model_do_not_hold_the_only_worker() {
    // One worker thread, five scenes in flight: the five questions are pending together.
    let (out, outcome, state, vlm) = run(5, 1, Some(5), 5, None);
    assert_eq!((outcome.evaluated, outcome.failed), (5, 0));
    assert!(
        !state.timed_out.load(Ordering::SeqCst),
        "the quorum of 5 was never reached"
    );
    assert_eq!(state.peak.load(Ordering::SeqCst), 5);
    assert_eq!(state.answered.load(Ordering::SeqCst), 5);
    // The answers went where they belong: every scene's accessibility is the same, each
    // object's sides from the VLM.
    let report = |i: usize| -> serde_json::Value {
        let text = std::fs::read_to_string(out.path().join(format!("scene_{}/eval.json", 801 + i))).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["report"]["accessibility"].clone()
    };
    let first = report(0);
    assert_eq!(first["objects"][0]["sides_source"], "vlm");
    for i in 1..5 {
        assert_eq!(report(i), first);
    }
    let usage = vlm.usage();
    assert_eq!((usage.requests, usage.failed_requests), (5, 0));
}

#[test]
fn the_time_budget_ends_a_wait_for_the_model() {
    // A quorum never reached: the model answers only after 60 s; the budget is 0.5 s.
    let (out, _, state, _) = run(1, 1, None, 2, Some(0.5));
    assert_eq!(state.cancelled.load(Ordering::SeqCst), 1, "the wait was given up");
    assert_eq!(state.answered.load(Ordering::SeqCst), 0);
    // The scene over its budget failed, the error naming the stage that was stopped.
    let text = std::fs::read_to_string(out.path().join("scene_801/eval.json")).unwrap();
    let record: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(record["status"], "failed", "{text}");
    assert_eq!(
        record["error"], "vlm stopped: the scene's time budget of 0.5 s is used up",
        "{text}"
    );
}
