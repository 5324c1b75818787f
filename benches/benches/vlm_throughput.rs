//! VLM throughput of a whole run: fixture scenes 0-5 (`fixtures/scenes`, their rows in
//! `fixtures/annotations/fixture_scenes.csv`) evaluated with the full plan through
//! `sceneeval::EvaluationRequest`, as `sceneeval evaluate` runs them, against the mock endpoint
//! of `sceneeval_test_support::mock_endpoint` on 127.0.0.1, which answers every request after a
//! fixed latency L and counts the requests in flight at the server. One run per configuration
//! (VLM concurrency C x worker threads), each with an empty output folder and cache; prints a
//! Markdown table: wall time, requests R, the most in flight at the server, the process's CPU
//! time, and the issue's target `1.3 x (R x L / C + chain x L) + CPU`.
//!
//! ```text
//! cargo bench -p sceneeval-benches --bench vlm_throughput -- [--latency SECS] [--concurrency 4,16] [--threads 1,2,6]
//! ```
//!
//! The model answers from the request alone (`mock_endpoint::generic_answer`): every object
//! matches an offered category, every attribute holds, relation mappings come back empty (asked
//! again once, then unanswered). Views are 64 px (rendering cost is not what is measured).

// A measurement binary prints its results and stops on a set-up failure.
#![allow(
    clippy::print_stdout,
    clippy::print_stderr,
    clippy::expect_used,
    clippy::unwrap_used
)]

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use sceneeval::{EvaluationRequest, PlanRequest, VlmOptions};
use sceneeval_test_support::mock_endpoint::{MockEndpoint, completion, generic_answer};

/// The longest chain of dependent requests of a run once each scene's independent questions
/// are asked together: the endpoint check before the first scene, the matching of every object,
/// then the attributes of the matched categories. (Support types, functional sides and the
/// relation mappings need no other answer: a mapping and its re-ask, 2, run beside them.)
const CHAIN: u32 = 3;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

/// The process's CPU time (user + system) so far, from `/proc/self/stat` (Linux, 100 ticks per
/// second); `None` elsewhere.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let after = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

struct Row {
    concurrency: usize,
    threads: usize,
    wall: f64,
    requests: usize,
    peak: usize,
    cpu: f64,
    per_scene_max: u64,
}

fn run(latency: Duration, concurrency: usize, threads: usize, scenes: &Path) -> Row {
    let server = MockEndpoint::start(latency, |_, body| completion(&generic_answer(body)));
    let out = tempfile::tempdir().expect("a temporary folder");
    let mut request = EvaluationRequest::new(scenes, out.path());
    request.assets = vec![format!("fixture={}", fixtures().join("assets").display())];
    request.annotations = Some(fixtures().join("annotations/fixture_scenes.csv"));
    request.plan = PlanRequest {
        plan: Some("full".into()),
        ..PlanRequest::default()
    };
    request.threads = Some(threads);
    request.vlm = Some(VlmOptions {
        base_url: server.url(),
        model: "mock".into(),
        api_key_env: None,
        cache: None,
        concurrency: Some(concurrency),
        render_size: Some(64),
        detail: None,
        temperature: None,
        seed: None,
        max_tokens: None,
        token_limit_field: None,
        timeout_s: None,
        rpm: None,
        tpm: None,
    });
    let cpu0 = cpu_seconds().unwrap_or(0.0);
    let start = Instant::now();
    let outcome = request
        .prepare()
        .expect("the run's settings")
        .run(&|_| {})
        .expect("the run");
    let wall = start.elapsed().as_secs_f64();
    let cpu = cpu_seconds().unwrap_or(0.0) - cpu0;
    assert_eq!(outcome.batch.failed, 0, "every scene evaluated");
    let per_scene_max = outcome
        .batch
        .records
        .iter()
        .filter_map(|r| r.report()?.fidelity.as_ref()?.vlm_usage.map(|u| u.requests))
        .max()
        .unwrap_or(0);
    Row {
        concurrency,
        threads,
        wall,
        requests: server.requests(),
        peak: server.peak_in_flight(),
        cpu,
        per_scene_max,
    }
}

fn list(args: &[String], name: &str, default: &[usize]) -> Vec<usize> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map(|v| v.split(',').filter_map(|n| n.trim().parse().ok()).collect())
        .unwrap_or_else(|| default.to_vec())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let latency = args
        .iter()
        .position(|a| a == "--latency")
        .and_then(|i| args.get(i + 1)?.parse::<f64>().ok())
        .unwrap_or(0.5);
    let concurrencies = list(&args, "--concurrency", &[4, 16]);
    let threads = list(&args, "--threads", &[1, 2, 6]);
    let dir = tempfile::tempdir().expect("a temporary folder");
    for n in 0..6 {
        let name = format!("scene_{n}.json");
        std::fs::copy(fixtures().join("scenes").join(&name), dir.path().join(&name))
            .expect("a fixture scene");
    }
    let l = Duration::from_secs_f64(latency);
    println!(
        "6 fixture scenes, full plan, latency {latency} s per request; chain {CHAIN} (a scene's dependent \
         requests once its independent ones are asked together)\n"
    );
    println!(
        "| --vlm-concurrency | --threads | wall | requests R | most in flight at the server | CPU time | \
         target 1.3 (R L / C + {CHAIN} L) + CPU | R L / C | most requests of one scene |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for &c in &concurrencies {
        for &t in &threads {
            let r = run(l, c, t, dir.path());
            let ideal = r.requests as f64 * latency / r.concurrency as f64;
            let target = 1.3 * (ideal + f64::from(CHAIN) * latency) + r.cpu;
            println!(
                "| {} | {} | {:.1} s | {} | {} | {:.1} s | {:.1} s | {:.1} s | {} |",
                r.concurrency, r.threads, r.wall, r.requests, r.peak, r.cpu, target, ideal, r.per_scene_max
            );
        }
    }
}
