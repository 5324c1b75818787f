//! `sceneeval annotations check|stats|annotate|generate|review`: validate a SceneEval-500
//! annotation file, print its statistics (the paper's Table 1), make annotation rows with a
//! model (`generate.rs`), or review generated candidates in a local web page (`review.rs`).

mod generate;
mod review;

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use sceneeval::annotation::{Annotations, Finding, Summary};
use serde::Serialize;

/// Subcommands of `sceneeval annotations`.
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Validate an annotation file and print every finding. Exits with status 1 when there is
    /// at least one error (warnings alone exit 0), and 1 with a message when the file cannot
    /// be read.
    Check {
        /// The annotation file: `.json` for the JSON form, anything else is read as CSV.
        file: PathBuf,
        /// `--format json`: one JSON document (file, rows, errors, warnings, findings) instead
        /// of text.
        #[command(flatten)]
        format: crate::format::FormatArgs,
    },
    /// Print the paper's Table 1 per difficulty: scenes, words per description, objects
    /// specified, and entries per field (averages per scene).
    Stats {
        /// The annotation file: `.json` for the JSON form, anything else is read as CSV.
        file: PathBuf,
        /// `--format json`: JSON instead of a Markdown table.
        #[command(flatten)]
        format: crate::format::FormatArgs,
    },
    /// Ask a model for the annotation row of a scene description and print it as CSV (with its
    /// header), or (`--descriptions LIST --out FILE`) for every description of a list, appending
    /// the rows to FILE. Every answer is checked as `check` does; one with findings is asked
    /// again once, then rejected (printed on standard error, exit status 1).
    Annotate(Box<generate::AnnotateArgs>),
    /// Generate new scene descriptions with their annotations (the paper's process: in-context
    /// examples, validation, a near-duplicate filter), appending accepted rows to `--out` and
    /// rejected candidates to OUT.rejected.jsonl; a re-run continues.
    Generate(Box<generate::GenerateArgs>),
    /// Review candidates (the rows of FILE, typically `generate`'s output, and the candidates
    /// of FILE.rejected.jsonl) in a local web page: edit, accept, reject. Serves 127.0.0.1 only
    /// and prints the URL; every decision is written at once (accepted rows to
    /// FILE.accepted.EXT, rejected ones to its .rejected.jsonl), so a second run continues.
    Review(Box<review::ReviewArgs>),
}

/// The JSON document of `check --format json`.
#[derive(Debug, Serialize)]
struct CheckReport<'a> {
    file: &'a Path,
    rows: usize,
    errors: usize,
    warnings: usize,
    findings: &'a [Finding],
}

/// Runs the subcommand.
pub fn run(cmd: Command) -> anyhow::Result<ExitCode> {
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let code = match cmd {
        Command::Check { file, format } => check(&file, format.json(), &mut out)?,
        Command::Stats { file, format } => stats(&file, format.json(), &mut out)?,
        Command::Annotate(args) => generate::annotate(*args)?,
        Command::Generate(args) => generate::generate(*args)?,
        Command::Review(args) => review::review(*args)?,
    };
    out.flush().context("writing to standard output")?;
    Ok(code)
}

fn read(file: &Path) -> anyhow::Result<Annotations> {
    Annotations::read(file).with_context(|| format!("cannot read annotation file {}", file.display()))
}

fn check(file: &Path, json: bool, out: &mut impl Write) -> anyhow::Result<ExitCode> {
    let annotations = read(file)?;
    let findings = annotations.validate();
    let summary = Summary::of(&findings);
    tracing::info!(
        rows = annotations.rows.len(),
        errors = summary.errors,
        warnings = summary.warnings,
        "checked"
    );
    if json {
        let report = CheckReport {
            file,
            rows: annotations.rows.len(),
            errors: summary.errors,
            warnings: summary.warnings,
            findings: &findings,
        };
        serde_json::to_writer_pretty(&mut *out, &report).context("writing JSON")?;
        writeln!(out)?;
    } else {
        for f in &findings {
            writeln!(out, "{f}")?;
        }
        writeln!(
            out,
            "{}: {} rows, {} error(s), {} warning(s)",
            file.display(),
            annotations.rows.len(),
            summary.errors,
            summary.warnings
        )?;
    }
    Ok(if summary.errors > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn stats(file: &Path, json: bool, out: &mut impl Write) -> anyhow::Result<ExitCode> {
    let stats = read(file)?.stats();
    if json {
        serde_json::to_writer_pretty(&mut *out, &stats).context("writing JSON")?;
        writeln!(out)?;
    } else {
        write!(out, "{}", stats.to_markdown())?;
    }
    Ok(ExitCode::SUCCESS)
}
