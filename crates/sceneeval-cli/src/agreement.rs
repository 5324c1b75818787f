//! `sceneeval agreement [--reference LABELS]... SOURCE...`: how far judges (runs, people) agree
//! on the fidelity specs, as the paper's human check measures it: agreement and Cohen's kappa
//! per metric against the reference annotators' majority, Cohen's kappa of every annotator
//! pair and Fleiss' kappa (`docs/judge.md`).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::report::agreement::{AgreementOptions, Source, agreement};
use sceneeval::report::labels::LabelFile;
use sceneeval::stats::Bootstrap;

/// Arguments of `sceneeval agreement`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "SOURCE is a run folder (its VLM judge, named after the folder) or a label file (one rater \
per annotator; JSON Lines, or CSV when the name ends in .csv). With --reference, the reference verdict of a spec is \
the majority of the reference annotators (ties left out and counted) and every SOURCE is a judge measured against \
it; the annotators get Cohen's kappa per pair and Fleiss' kappa over the specs all of them judged. Without \
--reference, every pair of raters is compared. A null verdict on either side leaves the spec out, counted. Kappa is \
empty where it does not exist (no spec, one class only), with the reason. The formats are described in \
docs/formats.md (\"Label files\", \"Agreement tables\") and the workflow in docs/judge.md."
)]
pub struct Args {
    /// Run folders (`sceneeval evaluate --out`) and label files to measure.
    #[arg(value_name = "SOURCE")]
    pub sources: Vec<PathBuf>,
    /// A label file whose annotators make the reference (repeatable; their majority decides).
    #[arg(long, value_name = "LABELS")]
    pub reference: Vec<PathBuf>,
    /// Output format: md (the paper's table, the annotators, the items each judge got wrong),
    /// csv (one line per rater pair and metric), latex (booktabs tabulars and the wrong items),
    /// json (everything).
    #[arg(long, value_enum, default_value_t = Format::Md)]
    pub format: Format,
    /// Bootstrap resamples of each kappa's 95 % percentile interval (items resampled); 0: no
    /// intervals.
    #[arg(long, value_name = "N", default_value_t = sceneeval::stats::bootstrap::DEFAULT_RESAMPLES)]
    pub bootstrap: usize,
    /// The bootstrap's seed (the same seed gives the same intervals).
    #[arg(long, value_name = "S", default_value_t = sceneeval::stats::bootstrap::DEFAULT_SEED)]
    pub seed: u64,
    /// Write into this file (atomically) instead of standard output.
    #[arg(long, short = 'o', value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// GitHub Markdown.
    Md,
    /// CSV, one line per rater pair and metric.
    Csv,
    /// Booktabs tabulars.
    Latex,
    /// JSON.
    Json,
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if args.sources.is_empty() {
        anyhow::bail!("give at least one SOURCE (a run folder or a label file) to measure");
    }
    let reference = args
        .reference
        .iter()
        .map(|path| LabelFile::read(path))
        .collect::<Result<Vec<_>, _>>()?;
    let mut sources = Vec::new();
    for path in &args.sources {
        let source = Source::open(path)?;
        if let Source::Run(run) = &source {
            crate::report::warn_unreadable(run);
        }
        sources.push(source);
    }
    let bootstrap = (args.bootstrap > 0)
        .then(|| Bootstrap::new(args.bootstrap, 0.95).map(|b| b.with_seed(args.seed)))
        .transpose()?;
    let table = agreement(&reference, &sources, &AgreementOptions { bootstrap })?;
    let text = match args.format {
        Format::Md => table.to_markdown(),
        Format::Csv => table.to_csv()?,
        Format::Latex => table.to_latex(),
        Format::Json => table.to_json(),
    };
    match &args.out {
        Some(out) => {
            sceneeval::files::write_atomic(out, text.as_bytes())
                .with_context(|| format!("writing {}", out.display()))?;
            eprintln!("agreement: {}", out.display());
        }
        None => crate::print_stdout(&text)?,
    }
    // Markdown has the notes in it; the other formats say them on standard error.
    if args.format != Format::Md || args.out.is_some() {
        for note in &table.notes {
            eprintln!("note: {note}");
        }
    }
    Ok(ExitCode::SUCCESS)
}
