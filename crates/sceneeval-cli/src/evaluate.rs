//! `sceneeval evaluate`: evaluate a folder of scenes, write `<out>/<scene>/eval.json` and
//! `<out>/<scene>/timing.json` as each scene finishes, then `<out>/summary.csv` and
//! `<out>/summary.md`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use sceneeval::annotation::Annotations;
use sceneeval::io::AssetLibrary;
use sceneeval::render::{RenderSettings, Renderer};
use sceneeval::vlm::Cached;
use sceneeval::vlm_openai::{OpenAiConfig, OpenAiVlm, RuntimeVlm};
use sceneeval::{
    ChosenPlan, Evaluator, FolderOutcome, FolderRun, Metric, Outcome, PlanChoice, Preset, SceneRecord,
    SceneStatus, SharedVlm, check_output_dir, find_scenes,
};

/// Arguments of `sceneeval evaluate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Folder holding the `scene_<ID>.json` files to evaluate.
    pub scenes: PathBuf,
    /// Asset folder for a model-id prefix, as `PREFIX=DIR` (layout chosen from the prefix) or
    /// `PREFIX=LAYOUT:DIR` with LAYOUT one of 3d-future, objathor, hssd, layoutvlm, plain.
    /// Repeat for several prefixes.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// Output folder (created if missing; checked for writing before any scene is evaluated).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    /// SceneEval-500 annotation CSV (or JSON): the rows the fidelity metrics check (looked up
    /// by the scene's ID), and rows per difficulty in the summary.
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// What to evaluate: `geometry` (the default: the six geometry metrics, no VLM), `full`
    /// (the paper's ten metrics), a comma-separated metric list (`collision,cnt,oor`), or a
    /// plan file (JSON: preset, metrics, parameters, limits, time budget; see docs/formats.md).
    #[arg(long, value_name = "geometry|full|LIST|FILE")]
    pub plan: Option<String>,
    /// OpenAI-compatible API base URL of the VLM for the fidelity metrics (matching, ATR,
    /// relation mapping), e.g. https://api.openai.com/v1. The key is read from OPENAI_API_KEY
    /// (or `--vlm-api-key-env`).
    #[arg(long, value_name = "URL", requires = "vlm_model")]
    pub vlm_base_url: Option<String>,
    /// The VLM's model name, e.g. gpt-4o-2024-08-06.
    #[arg(long, value_name = "NAME", requires = "vlm_base_url")]
    pub vlm_model: Option<String>,
    /// The environment variable holding the VLM's API key; it must then be set. Without this
    /// option OPENAI_API_KEY is used when set (local servers need no key).
    #[arg(long, value_name = "VAR", requires = "vlm_base_url")]
    pub vlm_api_key_env: Option<String>,
    /// What is sent with every VLM request.
    #[command(flatten)]
    pub vlm_sampling: crate::vlm::SamplingArgs,
    /// VLM requests in flight at once over the whole run.
    #[arg(long, default_value_t = 4, value_name = "N")]
    pub vlm_concurrency: usize,
    /// Folder of the VLM response cache (default `<out>/vlm-cache`): a re-run asks nothing
    /// already answered.
    #[arg(long, value_name = "DIR")]
    pub vlm_cache: Option<PathBuf>,
    /// Object matching: `vlm` (default with a VLM), `labels` (default without), or a matching
    /// file or folder in the reference's obj_matching_result.json shape.
    #[arg(long, value_name = "vlm|labels|FILE")]
    pub matching: Option<String>,
    /// Relation mapping: `vlm` (default with a VLM) or `lexicon` (default without; unknown
    /// words still go to the VLM when one is configured).
    #[arg(long, value_name = "vlm|lexicon")]
    pub relation_mapping: Option<String>,
    /// Side of the square object views shown to the VLM, pixels.
    #[arg(long, default_value_t = 512, value_name = "PX")]
    pub render_size: u32,
    /// Evaluate only shard K of N (1-based): the scenes whose position in ID order is K-1
    /// modulo N. Merge the shards' folders with `sceneeval summarize`.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Parameter preset: `default`, or `reference` for every reference-parity switch (to
    /// compare with published numbers). Replaces the plan file's `preset`; the plan's explicit
    /// values still apply on top.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<Preset>,
    /// Run only these metrics (comma-separated), overriding the plan's list.
    #[arg(long, value_delimiter = ',', value_name = "METRIC,...")]
    pub metrics: Option<Vec<Metric>>,
    /// Wall-time budget per scene in seconds, overriding the plan's (default 600); a scene
    /// over it is recorded as failed and the run goes on. 0 means no budget.
    #[arg(long, value_name = "SECONDS")]
    pub time_budget: Option<f64>,
    /// Evaluate every scene again, even those whose earlier result still matches.
    #[arg(long)]
    pub force: bool,
    /// Worker threads (default: one per core).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Also write diagnostic images under `<out>/<scene>/diagnostics/`.
    #[arg(long)]
    pub diagnostics: bool,
    /// Do not show a progress bar.
    #[arg(long)]
    pub no_progress: bool,
}

/// Runs the subcommand. Exits with failure when any scene failed to load or evaluate (each
/// failure is recorded in its `eval.json`, printed with its cause chain and counted in the
/// summary). Everything that can be checked before evaluating (the scene names, the plan, the
/// asset folders, the annotations, the output folder) is checked first.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let set = find_scenes(&args.scenes)?;
    for skipped in &set.skipped {
        eprintln!("warning: skipped {}: {}", skipped.path.display(), skipped.reason);
    }
    let mut scenes = set.scenes;
    if scenes.is_empty() {
        bail!("no scene_<ID>.json files in {}", args.scenes.display());
    }
    if let Some((k, n)) = args.shard {
        scenes = scenes
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % n == k - 1)
            .map(|(_, s)| s)
            .collect();
        eprintln!("shard {k}/{n}: {} scenes", scenes.len());
    }
    let vlm_configured = args.vlm_base_url.is_some();
    if let (false, Some(option)) = (vlm_configured, args.vlm_sampling.first_given()) {
        bail!("{option} sets what is sent to the VLM; it needs --vlm-base-url and --vlm-model");
    }
    let choice = PlanChoice {
        plan: args.plan.as_deref(),
        preset: args.preset,
        metrics: args.metrics.clone(),
        time_budget_seconds: args.time_budget,
        matching: args.matching.as_deref(),
        relation_mapping: args.relation_mapping.as_deref(),
        vlm_configured,
        annotations: args.annotations.is_some(),
        names: PlanChoice::CLI,
    };
    let ChosenPlan { plan, fallback } = choice.resolve()?;
    if let Some(fallback) = fallback {
        eprintln!("note: no VLM configured (--vlm-base-url, --vlm-model): {fallback}");
    }
    let mut evaluator = Evaluator::new(plan)?;
    if let (Some(url), Some(model), true) = (
        &args.vlm_base_url,
        &args.vlm_model,
        evaluator.plan().has_fidelity(),
    ) {
        let key = crate::vlm::api_key(args.vlm_api_key_env.as_deref(), "--vlm-api-key-env")?;
        let mut config = OpenAiConfig::new(url, model).with_api_key(key);
        args.vlm_sampling.apply(&mut config);
        config.max_concurrent_requests = args.vlm_concurrency.max(1);
        let client = OpenAiVlm::new(config).context("cannot set up the VLM client")?;
        let vlm = RuntimeVlm::start(client)?;
        let cache = args
            .vlm_cache
            .clone()
            .unwrap_or_else(|| args.out.join("vlm-cache"));
        let renderer =
            Renderer::new().context("the VLM needs object views, but the renderer cannot start")?;
        evaluator = evaluator
            .with_vlm(SharedVlm::new(Cached::new(vlm, cache)))
            .with_renderer(renderer, RenderSettings::square(args.render_size.max(16)));
    }
    let plan = evaluator.plan();
    let assets = AssetLibrary::from_specs(&args.assets)
        .context("invalid --assets")?
        .with_limits(plan.limits);
    let annotations = args
        .annotations
        .as_deref()
        .map(|p| Annotations::read(p).with_context(|| format!("reading annotations {}", p.display())))
        .transpose()?;
    check_output_dir(&args.out)?;

    let progress = if args.no_progress {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(scenes.len() as u64)
    };
    if let Ok(style) = ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} scenes{msg}") {
        progress.set_style(style.progress_chars("=> "));
    }
    let run = FolderRun {
        out_dir: args.out.clone(),
        force: args.force,
        diagnostics: args.diagnostics,
        annotations: annotations.as_ref(),
    };
    let (renders, requests, cached) = (AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0));
    let on_done = |scene: &sceneeval::SceneFile, status: &SceneStatus, record: &SceneRecord| {
        if let (SceneStatus::Failed { .. }, Outcome::Failed { stage, error, causes }) =
            (status, &record.outcome)
        {
            let mut text = format!(
                "failed: {} ({} stage): {error}",
                scene.path.display(),
                match stage {
                    sceneeval::Stage::Load => "load",
                    sceneeval::Stage::Evaluate => "evaluate",
                }
            );
            for cause in causes {
                text.push_str("\n  caused by: ");
                text.push_str(cause);
            }
            // `suspend` prints also when the bar is hidden (`println` would not).
            progress.suspend(|| eprintln!("{text}"));
        }
        if let (SceneStatus::Evaluated { .. }, Some(f)) =
            (status, record.report().and_then(|r| r.fidelity.as_ref()))
        {
            renders.fetch_add(f.views_rendered, Ordering::Relaxed);
            if let Some(u) = f.vlm_usage {
                requests.fetch_add(u.requests - u.cache_hits, Ordering::Relaxed);
                cached.fetch_add(u.cache_hits, Ordering::Relaxed);
            }
            progress.set_message(format!(
                ", {} renders, {} VLM requests ({} from the cache)",
                renders.load(Ordering::Relaxed),
                requests.load(Ordering::Relaxed),
                cached.load(Ordering::Relaxed)
            ));
        }
        progress.inc(1);
    };
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n.max(1));
    }
    let pool = pool.build().context("starting worker threads")?;
    let FolderOutcome {
        batch: outcome,
        summary,
    } = pool.install(|| run.run(&scenes, &evaluator, &assets, &on_done))?;
    progress.finish_and_clear();

    print!("{}", summary.to_markdown());
    eprintln!(
        "{} scenes: {} evaluated, {} kept from an earlier run, {} failed; preset {}; results in {}",
        scenes.len(),
        outcome.evaluated,
        outcome.reused,
        outcome.failed,
        plan.preset,
        args.out.display()
    );
    if evaluator.plan().has_fidelity() {
        eprintln!(
            "  fidelity: {} renders, {} VLM requests sent, {} answered from the cache",
            renders.load(Ordering::Relaxed),
            requests.load(Ordering::Relaxed),
            cached.load(Ordering::Relaxed)
        );
    }
    for (reason, n) in outcome.reasons() {
        eprintln!("  evaluated because {reason}: {n}");
    }
    let (load, per_metric) = outcome.time_per_metric();
    if outcome.evaluated + outcome.failed > 0 {
        let parts: Vec<String> = std::iter::once(format!("loading {load:.2} s"))
            .chain(per_metric.iter().map(|(m, s)| format!("{m} {s:.2} s")))
            .collect();
        eprintln!("  time over the evaluated scenes: {}", parts.join(", "));
    }
    Ok(if outcome.failed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (k, n) = s.split_once('/').ok_or("expected K/N, e.g. 2/8")?;
    let (k, n): (usize, usize) = (
        k.trim().parse().map_err(|_| "K is not a number")?,
        n.trim().parse().map_err(|_| "N is not a number")?,
    );
    if n == 0 || k == 0 || k > n {
        return Err(format!("shard {k}/{n}: need 1 <= K <= N"));
    }
    Ok((k, n))
}
