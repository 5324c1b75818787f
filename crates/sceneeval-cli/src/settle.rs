//! `sceneeval settle SCENE.json --assets PREFIX=DIR ... --out FILE [--plan FILE] [--weld MODE]`:
//! simulate the scene under gravity as the stability metric does and write it back with every
//! object at its settled pose (welded objects where they were), through the sceneState writer,
//! atomically. Prints one line per object that moved beyond the stability limits.
//!
//! The parameters are the plan's `stability` section (`--plan`, default the built-in plan),
//! with `--weld` replacing its weld mode; support types come from the scene file, then the
//! category tables; the plan's time budget applies.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::io::{AssetLibrary, read_scene_state, write_scene_state};
use sceneeval::physics::WeldMode;
use sceneeval::{EvaluationPlan, Evaluator};

/// Arguments of `sceneeval settle`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sceneState JSON file.
    pub scene: PathBuf,
    /// Asset folder for a model-id prefix, as `PREFIX=DIR` (layout chosen from the prefix) or
    /// `PREFIX=LAYOUT:DIR` with LAYOUT one of 3d-future, objathor, hssd, layoutvlm, plain.
    /// Repeat for several prefixes.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// The settled scene's file (sceneState JSON; replaced atomically; may be SCENE itself).
    #[arg(long, short = 'o', value_name = "FILE")]
    pub out: PathBuf,
    /// A plan file (JSON, or TOML ending in .toml) whose `stability` section, `read` options,
    /// `limits` and `time_budget_seconds` apply.
    #[arg(long, value_name = "FILE")]
    pub plan: Option<PathBuf>,
    /// What is fixed in place: architectural (objects on walls and ceilings, the default),
    /// penetration (objects interpenetrating another object or the architecture), combined
    /// (both) or none. Replaces the plan's `stability.weld`.
    #[arg(long, value_name = "MODE", value_parser = str::parse::<WeldMode>)]
    pub weld: Option<WeldMode>,
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let mut plan = match &args.plan {
        Some(path) => EvaluationPlan::read(path).context("invalid --plan")?,
        None => EvaluationPlan::geometry_only(),
    };
    if let Some(weld) = args.weld {
        plan.stability.weld = weld;
    }
    let evaluator = Evaluator::new(plan).context("invalid --plan")?;
    let plan = evaluator.plan();
    let library = AssetLibrary::from_specs(&args.assets)
        .context("invalid --assets")?
        .with_limits(plan.limits);
    let deadline = plan.deadline();
    let scene = read_scene_state(&args.scene, &library, &plan.read)
        .with_context(|| format!("cannot load scene {}", args.scene.display()))?;
    let (settled, report) = evaluator
        .settle(&scene, &deadline)
        .with_context(|| format!("cannot settle scene {}", args.scene.display()))?;
    write_scene_state(&settled, &args.out)?;
    let mut lines = String::new();
    for o in report.objects.iter().filter(|o| !o.stable) {
        lines.push_str(&format!(
            "{}\tmoved {:.3} m\tturned {:.3} rad\n",
            o.id, o.displacement_m, o.rotation_rad
        ));
    }
    crate::print_stdout(&lines)?;
    let welded = report.objects.len() - report.num_free;
    eprintln!(
        "{} objects ({welded} welded, weld mode {}): {} of {} free objects moved beyond the limits; \
         {:.2} s simulated; written to {}",
        report.objects.len(),
        report.weld.name(),
        report.num_unstable,
        report.num_free,
        report.simulated_s,
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
