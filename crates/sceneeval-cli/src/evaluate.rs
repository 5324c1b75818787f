//! `sceneeval evaluate`: evaluate a folder of scenes, write `<out>/<scene>/eval.json` as each
//! scene finishes, then `<out>/summary.csv` and `<out>/summary.md`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use sceneeval::annotation::Annotations;
use sceneeval::io::AssetLibrary;
use sceneeval::{
    BatchOptions, EvaluationPlan, Evaluator, Metric, SceneRecord, SceneStatus, Summary, find_scenes,
    run_batch,
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
    /// Output folder (created if missing).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    /// SceneEval-500 annotation CSV (or JSON): adds rows per difficulty to the summary.
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// Evaluation plan (JSON): metrics and parameters. Default: every geometry-only metric with
    /// the reference's parameters.
    #[arg(long, value_name = "FILE")]
    pub plan: Option<PathBuf>,
    /// Run only these metrics (comma-separated), overriding the plan's list.
    #[arg(long, value_delimiter = ',', value_name = "METRIC,...")]
    pub metrics: Option<Vec<Metric>>,
    /// Evaluate again scenes that already have a successful `eval.json`.
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
/// failure is recorded in its `eval.json` and counted in the summary).
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let scenes = find_scenes(&args.scenes)?;
    if scenes.is_empty() {
        bail!("no scene_<ID>.json files in {}", args.scenes.display());
    }
    let assets = AssetLibrary::from_specs(&args.assets).context("invalid --assets")?;
    let mut plan = match &args.plan {
        Some(path) => EvaluationPlan::read(path)?,
        None => EvaluationPlan::geometry_only(),
    };
    if let Some(metrics) = args.metrics {
        plan.metrics = metrics;
    }
    let evaluator = Evaluator::new(plan)?;
    let annotations = args
        .annotations
        .as_deref()
        .map(|p| Annotations::read(p).with_context(|| format!("reading annotations {}", p.display())))
        .transpose()?;
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;

    let progress = if args.no_progress {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(scenes.len() as u64)
    };
    if let Ok(style) = ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} scenes {msg}") {
        progress.set_style(style.progress_chars("=> "));
    }
    let options = BatchOptions {
        out_dir: args.out.clone(),
        force: args.force,
        diagnostics: args.diagnostics,
        ..BatchOptions::default()
    };
    let on_done = |scene: &sceneeval::SceneFile, status: SceneStatus| {
        if status == SceneStatus::Failed {
            progress.println(format!("failed: {} (see its eval.json)", scene.name));
        }
        progress.inc(1);
    };
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n.max(1));
    }
    let pool = pool.build().context("starting worker threads")?;
    let outcome = pool.install(|| run_batch(&scenes, &evaluator, &assets, &options, &on_done))?;
    progress.finish_and_clear();

    let difficulty = |r: &SceneRecord| {
        let ann = annotations.as_ref()?;
        let id = r.scene_id.as_deref()?;
        ann.get(id)
            .or_else(|| ann.get(id.trim_start_matches('0')))
            .map(|row| row.difficulty.as_str().to_owned())
    };
    let summary = Summary::from_records(&outcome.records, difficulty);
    write(&args.out.join("summary.csv"), &summary.to_csv()?)?;
    let markdown = summary.to_markdown();
    write(&args.out.join("summary.md"), &markdown)?;

    print!("{markdown}");
    eprintln!(
        "{} scenes: {} evaluated, {} kept from an earlier run, {} failed; results in {}",
        scenes.len(),
        outcome.evaluated,
        outcome.skipped,
        outcome.failed,
        args.out.display()
    );
    Ok(if outcome.failed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}
