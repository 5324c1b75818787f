//! `sceneeval ensemble RUN... --out DIR`: runs made with different judges on the same scenes
//! and annotations combined into one run folder, each text-fidelity verdict the majority of
//! the runs' (`docs/judge.md`, "Ensembles of judges").

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::annotation::Annotations;
use sceneeval::run::{EnsembleOptions, ensemble};

/// Arguments of `sceneeval ensemble`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "Each RUN is an output folder of `sceneeval evaluate` (with its plan.json). The runs must have \
the same scenes, annotation rows and specs, and plans that differ only in the judge: the VLM, \
params.fidelity.matching, size_aware_matching and relation_mapping. Every spec's verdict is the majority of the \
runs' verdicts (a tie or no verdict: null, counted as unanswered); the fidelity scores are recounted as `evaluate` \
counts them. Geometry, stability and each spec's evidence are the first run's; where another run's geometry \
differs (support types, functional sides answered by another judge) a line says so here and in eval.json. \
The output is a run folder that summarize, compare and report read. Formats: docs/formats.md (\"Ensembles\")."
)]
pub struct Args {
    /// Run folders to combine (at least two), in vote order: the first gives the geometry.
    #[arg(value_name = "RUN", required = true, num_args = 2..)]
    pub runs: Vec<PathBuf>,
    /// The run folder to write (`plan.json`, `<scene>/eval.json`, the summaries).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    /// The annotation CSV (or JSON) the runs used: adds the summary's rows per difficulty.
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
}

/// Runs the subcommand: prints the summary's Markdown, and on standard error the votes' ties
/// and every geometry difference.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let annotations = args
        .annotations
        .as_deref()
        .map(|p| Annotations::read(p).with_context(|| format!("reading annotations {}", p.display())))
        .transpose()?;
    let done = ensemble(
        &args.runs,
        &EnsembleOptions {
            out_dir: args.out.clone(),
            annotations: annotations.as_ref(),
        },
    )?;
    for (scene, d) in &done.differences {
        eprintln!(
            "note: {scene}: {} differs in run {}: {} (the first run's is reported)",
            d.metric, d.run, d.detail
        );
    }
    eprintln!(
        "{} scenes combined from {} runs ({}); {} spec(s) tied (null, unanswered); {} geometry difference(s); \
         results in {}",
        done.records.len(),
        done.runs.len(),
        done.runs.join(", "),
        done.ties,
        done.differences.len(),
        args.out.display()
    );
    crate::print_stdout(&done.summary.to_markdown())?;
    Ok(ExitCode::SUCCESS)
}
