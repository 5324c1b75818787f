//! `sceneeval settle SCENE.json --assets PREFIX=DIR ... --out FILE [--plan FILE] [--weld MODE]`:
//! simulate the scene under gravity as the stability metric does and write it back with every
//! object at its settled pose (welded objects where they were), through the sceneState writer,
//! atomically. Prints one line per object that moved beyond the stability limits.
//!
//! The parameters are the plan's `stability` section (`--plan`, default the built-in plan),
//! with `--weld` replacing its weld mode; support types come from the scene file, then (with
//! `--vlm-base-url`, as `evaluate` asks them) the VLM for the objects that state none, then the
//! category tables; the plan's time budget applies.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::io::{AssetLibrary, read_scene_state, write_scene_state};
use sceneeval::physics::WeldMode;
use sceneeval::{EvaluationPlan, Evaluator, PlacementSource, SceneInputs};

/// Arguments of `sceneeval settle`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The sceneState JSON file.
    pub scene: PathBuf,
    /// Asset folder for a model-id prefix, as `PREFIX=DIR` (layout chosen from the prefix) or
    /// `PREFIX=LAYOUT:DIR` with LAYOUT one of 3d-future, objathor, hssd, layoutvlm, idesign,
    /// scene-agent, plain. Repeat for several prefixes.
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
    /// The VLM asked for the support types the scene does not state, as `evaluate` asks them
    /// (it is shown each object's views; answers cached in `vlm-cache` beside FILE unless
    /// `--vlm-cache`).
    #[command(flatten)]
    pub vlm: crate::vlm::VlmArgs,
    /// Side of the square object views shown to the VLM, pixels (default 512; 16 to 4096).
    #[arg(long, value_name = "PX", requires = "vlm_base_url")]
    pub render_size: Option<u32>,
    /// Refuse a scene file with keys the sceneState format does not have (a misspelt key is
    /// read as absent) instead of warning about each.
    #[arg(long)]
    pub strict: bool,
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
    let vlm = args.vlm.options()?.map(|mut v| {
        v.render_size = args.render_size;
        v
    });
    let mut evaluator = Evaluator::new(plan).context("invalid --plan")?;
    if let Some(vlm) = &vlm {
        let beside = args
            .out
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        evaluator = vlm.attach(evaluator, beside)?;
    }
    let plan = evaluator.plan();
    let library = AssetLibrary::from_specs(&args.assets)
        .context("invalid --assets")?
        .with_limits(plan.limits);
    let deadline = plan.deadline();
    let scene = read_scene_state(&args.scene, &library, &plan.read.with_strict(args.strict))
        .with_context(|| format!("cannot load scene {}", args.scene.display()))?;
    let inputs = SceneInputs {
        assets: Some(&library),
        deadline: Some(&deadline),
        ..SceneInputs::default()
    };
    let (settled, report, placement) = evaluator
        .settle_scene(&scene, &inputs)
        .with_context(|| format!("cannot settle scene {}", args.scene.display()))?;
    if let Some(placement) = placement {
        let count = |source: PlacementSource| {
            placement
                .iter()
                .filter_map(|p| p.support_type.as_ref())
                .filter(|p| p.source == source)
                .count()
        };
        eprintln!(
            "support types: {} stated in the scene, {} answered by the VLM, {} from the category tables, {} unknown",
            count(PlacementSource::Scene),
            count(PlacementSource::Vlm),
            count(PlacementSource::CategoryPrior),
            count(PlacementSource::None)
        );
        for p in &placement {
            if let Some(s) = p.support_type.as_ref().filter(|s| s.source.is_fallback()) {
                tracing::warn!(object = %p.object, reason = %s.reason, "support type from the category tables");
            }
        }
    }
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
