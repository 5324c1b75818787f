//! `sceneeval settle SCENE.json --assets PREFIX=DIR ... --out FILE [--plan PLAN] [--weld MODE]`:
//! simulate the scene under gravity as the stability metric does and write it back with every
//! object at its settled pose (welded objects where they were), through the sceneState writer,
//! atomically. Prints one line per object that moved beyond the stability limits.
//!
//! The options make one `sceneeval::SettleRequest` (the Python package's `Scene.settle` makes
//! the same): the plan as `evaluate --plan` takes it (its `stability` section, reading options,
//! limits and time budget apply), `--weld` replacing its weld mode; support types come from
//! the scene file, then (with `--vlm-base-url`, as `evaluate` asks them) the VLM for the objects
//! that state none, then the category tables.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::io::write_scene_state;
use sceneeval::physics::WeldMode;
use sceneeval::{PlacementSource, PlanRequest, Preset, SettleRequest, VlmOptions};

use crate::evaluate::OptionError;

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
    /// The plan, as `evaluate --plan` takes it: `geometry` (the default: the built-in
    /// parameters), `full`, a metric list, or a plan file (JSON or TOML) whose stability
    /// parameters, reading options, limits and time budget apply.
    #[arg(long, value_name = "geometry|full|LIST|FILE")]
    pub plan: Option<String>,
    /// Parameter preset: `default` or `reference`, as for `evaluate`.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<Preset>,
    /// Wall-time budget in seconds, overriding the plan's (default 600); 0 means no budget.
    #[arg(long = "time-budget-s", alias = "time-budget", value_name = "SECONDS")]
    pub time_budget_s: Option<f64>,
    /// What is fixed in place: architectural (objects on walls and ceilings, the default),
    /// penetration (objects interpenetrating another object or the architecture), combined
    /// (both) or none. Replaces the plan's `params.stability.weld`.
    #[arg(long, value_name = "MODE", value_parser = str::parse::<WeldMode>)]
    pub weld: Option<WeldMode>,
    /// The VLM asked for the support types the scene does not state, as `evaluate` asks them
    /// (it is shown each object's views; answers kept only in `--vlm-cache` when given).
    #[command(flatten)]
    pub vlm: crate::vlm::VlmArgs,
    /// Side of the square object views shown to the VLM, pixels (default
    /// `sceneeval::DEFAULT_RENDER_SIZE`, within `sceneeval::RENDER_SIZE_RANGE`).
    #[arg(long, value_name = "PX", requires = "vlm_base_url", help = crate::vlm::render_size_help())]
    pub render_size: Option<u32>,
    /// Refuse a scene file with keys the sceneState format does not have (a misspelt key is
    /// read as absent) instead of warning about each.
    #[arg(long)]
    pub strict: bool,
}

impl Args {
    /// The settle request these options make.
    ///
    /// # Errors
    /// A VLM sampling option without `--vlm-base-url`.
    pub fn request(&self) -> anyhow::Result<SettleRequest> {
        Ok(SettleRequest {
            assets: self.assets.clone(),
            plan: PlanRequest {
                plan: self.plan.clone(),
                preset: self.preset,
                time_budget_s: self.time_budget_s,
                ..PlanRequest::default()
            },
            weld: self.weld,
            vlm: self.vlm.options()?.map(|options| VlmOptions {
                render_size: self.render_size,
                ..options
            }),
            strict: self.strict,
        })
    }
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let prepared = args.request()?.prepare().map_err(OptionError::evaluate)?;
    let scene = prepared
        .read_scene(&args.scene)
        .with_context(|| format!("cannot load scene {}", args.scene.display()))?;
    let settled = prepared
        .settle(&scene)
        .with_context(|| format!("cannot settle scene {}", args.scene.display()))?;
    if let Some(placement) = &settled.placement {
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
        for p in placement {
            if let Some(s) = p.support_type.as_ref().filter(|s| s.source.is_fallback()) {
                tracing::warn!(object = %p.object, reason = %s.reason, "support type from the category tables");
            }
        }
    }
    write_scene_state(&settled.scene, &args.out)?;
    let report = &settled.report;
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
