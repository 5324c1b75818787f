//! `sceneeval evaluate`: evaluate a folder of scenes, write `<out>/<scene>/eval.json` and
//! `<out>/<scene>/timing.json` as each scene finishes, then `<out>/summary.csv` and
//! `<out>/summary.md`.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use sceneeval::annotation::Annotations;
use sceneeval::io::AssetLibrary;
use sceneeval::{
    EvaluationPlan, Evaluator, FolderOutcome, FolderRun, Metric, Outcome, Preset, SceneRecord, SceneStatus,
    check_output_dir, find_scenes,
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
    /// SceneEval-500 annotation CSV (or JSON): adds rows per difficulty to the summary.
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// Evaluation plan (JSON): preset, metrics, parameters, limits, time budget (see
    /// docs/formats.md and examples/plans/). Default: every geometry-only metric with this
    /// implementation's defaults.
    #[arg(long, value_name = "FILE")]
    pub plan: Option<PathBuf>,
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
    let scenes = set.scenes;
    if scenes.is_empty() {
        bail!("no scene_<ID>.json files in {}", args.scenes.display());
    }
    let mut plan = match &args.plan {
        Some(path) => EvaluationPlan::read_with_preset(path, args.preset)?,
        None => EvaluationPlan::with_preset(args.preset.unwrap_or_default()),
    };
    if let Some(metrics) = args.metrics {
        plan.metrics = metrics;
    }
    if let Some(b) = args.time_budget {
        plan.time_budget_seconds = (b != 0.0).then_some(b);
    }
    let evaluator = Evaluator::new(plan)?;
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
    if let Ok(style) = ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} scenes {msg}") {
        progress.set_style(style.progress_chars("=> "));
    }
    let run = FolderRun {
        out_dir: args.out.clone(),
        force: args.force,
        diagnostics: args.diagnostics,
        annotations: annotations.as_ref(),
    };
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
