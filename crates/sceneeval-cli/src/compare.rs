//! `sceneeval compare RUN...`: the runs of several methods side by side, as a paper table
//! (Markdown, CSV, LaTeX or HTML) with ranks and rank points, compared only on what they share;
//! with `--paired`, paired differences and tests per pair of runs.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use sceneeval::annotation::Annotations;
use sceneeval::report::compare::{FailedScenes, Pairing, RankBy};
use sceneeval::report::{CompareOptions, ReportError, Run, compare};

/// Arguments of `sceneeval compare`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "Runs are compared on the scenes every run evaluated in full and on the metrics every run \
ran; every difference (scenes left out and why, metrics not shared, other plans, presets or tool versions) is a \
note under the table, and every table names, per run, the scenes it lacks or failed among every scene of any \
run. Ranks (--rank tested): 1 + the number of runs better in the column by a paired Wilcoxon test, Holm-adjusted \
across the pair's columns, p < --alpha; runs no test separates share a rank (--rank mean: competition ranks of \
the means). A run ranked r of N gets N - r + 1 points. Bold: best value, italic: second. --paired adds, per pair \
of runs and column, the mean paired difference b - a, its bootstrap interval, the Wilcoxon p-value and its Holm \
adjustment, and McNemar's test on the fidelity verdicts. The formats are described in docs/formats.md."
)]
pub struct Args {
    /// Output folders of `sceneeval evaluate`, one per method, in the order of the table's rows.
    #[arg(required = true, value_name = "RUN")]
    pub runs: Vec<PathBuf>,
    /// The runs' names in the table, comma-separated, one per RUN (default: each folder's name).
    #[arg(long, value_delimiter = ',', value_name = "A,B,...")]
    pub names: Option<Vec<String>>,
    /// Output format: md (GitHub Markdown), csv (one row per group, run and metric column),
    /// latex (a booktabs tabular a paper can \input), html (a page linking each run's report,
    /// with the specs satisfied in one run and not another).
    #[arg(long, value_enum, default_value_t = Format::Md)]
    pub format: Format,
    /// Also one table per difficulty (easy, medium, hard, ...), after the table of every scene.
    #[arg(long, value_enum, value_name = "difficulty")]
    pub by: Option<By>,
    /// Write into this file (atomically) instead of standard output.
    #[arg(long, short = 'o', value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The annotation CSV (or JSON) the runs used: each scene's difficulty (default: the
    /// difficulty in each run's summary_scenes.csv).
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// A bootstrap confidence interval at this level beside each value, e.g. 0.95 (resampling
    /// the scenes 1000 times with a fixed seed; percentile method); also the level of the
    /// paired differences' intervals (default there: 0.95).
    #[arg(long, value_name = "LEVEL")]
    pub ci: Option<f64>,
    /// Paired comparisons of every pair of runs on the scenes both evaluated: per column n, the
    /// mean difference b - a, its bootstrap interval, the Wilcoxon p-value and its Holm
    /// adjustment; McNemar's test on the fidelity verdicts. With --format csv, these rows.
    #[arg(long)]
    pub paired: bool,
    /// With --paired: each run against the first only.
    #[arg(long, requires = "paired")]
    pub against_first: bool,
    /// The significance level of the tested ranks and the paired tables' marks.
    #[arg(long, value_name = "ALPHA", default_value_t = 0.05)]
    pub alpha: f64,
    /// How runs are ranked: tested (runs a paired test does not separate share a rank) or
    /// mean (by the means alone).
    #[arg(long, value_enum, default_value_t = Rank::Tested)]
    pub rank: Rank,
    /// How failed and missing scenes count in the per-run means: skip (values over the scenes
    /// every run evaluated in full) or worst (every scene of any run, a failed or missing one
    /// at the column's worst value).
    #[arg(long, value_enum, default_value_t = Failed::Skip)]
    pub failed: Failed,
}

/// `--rank`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Rank {
    /// 1 + the number of runs better by a paired test (Holm-adjusted p < --alpha).
    Tested,
    /// Competition ranks of the means as printed.
    Mean,
}

/// `--failed`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Failed {
    /// Values over the scenes every run evaluated in full.
    Skip,
    /// Failed and missing scenes at the column's worst value.
    Worst,
}

/// The output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// GitHub Markdown.
    Md,
    /// CSV, one row per group, run and metric column.
    Csv,
    /// A booktabs tabular.
    Latex,
    /// An HTML page.
    Html,
}

/// What `--by` groups by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum By {
    /// The annotation rows' difficulty.
    Difficulty,
}

/// Runs the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if let Some(names) = &args.names
        && names.len() != args.runs.len()
    {
        bail!("--names gives {} names for {} runs", names.len(), args.runs.len());
    }
    let annotations = args
        .annotations
        .as_deref()
        .map(|p| Annotations::read(p).with_context(|| format!("reading annotations {}", p.display())))
        .transpose()?;
    let mut runs = Vec::new();
    for (k, dir) in args.runs.iter().enumerate() {
        let mut run = crate::report::open_run(dir)?;
        if let Some(names) = &args.names {
            run = run.with_name(names[k].trim());
        }
        if let Some(a) = &annotations {
            run = run.with_annotations(a);
        }
        if let Some(twin) = runs.iter().find(|r: &&Run| r.name == run.name) {
            bail!(
                "two runs are named {:?} ({} and {}): give --names",
                run.name,
                twin.dir.display(),
                dir.display()
            );
        }
        runs.push(run);
    }
    let comparison = compare(
        &runs,
        &CompareOptions {
            by_difficulty: args.by == Some(By::Difficulty),
            ci: args.ci,
            paired: args.paired.then_some(if args.against_first {
                Pairing::AgainstFirst
            } else {
                Pairing::All
            }),
            rank: match args.rank {
                Rank::Tested => RankBy::Tested,
                Rank::Mean => RankBy::Mean,
            },
            alpha: args.alpha,
            failed: match args.failed {
                Failed::Skip => FailedScenes::Skip,
                Failed::Worst => FailedScenes::Worst,
            },
        },
    )
    .map_err(|error| {
        // The library's error says what is wrong; the option that set it is the CLI's to name.
        let option = match error {
            ReportError::Alpha(_) => Some("--alpha"),
            ReportError::ConfidenceLevel(_) => Some("--ci"),
            _ => None,
        };
        // Neither error has a cause: one line, as the other commands' `--option: what` errors.
        match option {
            Some(option) => anyhow::anyhow!("{option}: {error}"),
            None => error.into(),
        }
    })?;
    // The folder the page will be in: links to the runs' reports are relative to it.
    let page_dir = args
        .out
        .as_deref()
        .and_then(std::path::Path::parent)
        .filter(|p| !p.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), PathBuf::from);
    let text = match args.format {
        Format::Md => comparison.to_markdown(),
        Format::Csv if args.paired => comparison.to_paired_csv()?,
        Format::Csv => comparison.to_csv()?,
        Format::Latex => comparison.to_latex(),
        Format::Html => comparison.to_html(&page_dir),
    };
    match &args.out {
        Some(out) => {
            sceneeval::files::write_atomic(out, text.as_bytes())
                .with_context(|| format!("writing {}", out.display()))?;
            eprintln!(
                "{} runs compared on {} scenes: {}",
                runs.len(),
                comparison.scenes.len(),
                out.display()
            );
        }
        None => print!("{text}"),
    }
    // CSV has no place for the notes: they go to standard error (every other format has them).
    if args.format == Format::Csv || args.out.is_some() {
        for note in &comparison.notes {
            eprintln!("note: {note}");
        }
        if args.format == Format::Csv {
            for line in comparison.coverage_lines() {
                eprintln!("note: {line}");
            }
        }
    }
    // Pairs of runs made with different plans, presets or annotation rows: always said.
    for note in comparison.pairs.iter().flat_map(|p| &p.notes) {
        eprintln!("warning: {note}");
    }
    Ok(ExitCode::SUCCESS)
}
