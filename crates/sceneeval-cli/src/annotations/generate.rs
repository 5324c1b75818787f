//! `sceneeval annotations annotate|generate`: annotation rows made by a model, the paper's
//! semi-automatic process (`sceneeval::annotate`). This module only maps options and prints.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use sceneeval::SharedVlm;
use sceneeval::annotate::{
    AnnotateAllOptions, AnnotateOutcome, DEFAULT_EXAMPLES_PER_REQUEST, GenerateEvent, GenerateOptions,
    RejectedCandidate, draw_examples, rejected_path,
};
use sceneeval::annotation::Annotations;
use sceneeval::annotation::similarity::DEFAULT_THRESHOLD;
use sceneeval::vlm::Session;
use sceneeval::vlm::tasks::AnnotationLevel;

use crate::evaluate::OptionError;
use crate::vlm::VlmArgs;

/// Arguments of `sceneeval annotations annotate`.
#[derive(Debug, clap::Args)]
pub struct AnnotateArgs {
    /// The scene description to annotate (kept word for word in the row).
    #[arg(required_unless_present = "descriptions", conflicts_with = "descriptions")]
    pub description: Option<String>,
    /// A file of your own descriptions, one per line (empty lines left out), annotated in
    /// order: rows appended to `--out`, rejected candidates to OUT.rejected.jsonl; a re-run
    /// continues with the descriptions not done yet.
    #[arg(long, value_name = "FILE", requires = "out")]
    pub descriptions: Option<PathBuf>,
    /// With `--descriptions`: the annotation file the rows are appended to (CSV; JSON for
    /// `.json`).
    #[arg(long, short = 'o', value_name = "FILE", requires = "descriptions")]
    pub out: Option<PathBuf>,
    /// The description's difficulty level (with `--descriptions`: of every description);
    /// without it the model chooses by the paper's rules.
    #[arg(long, value_name = "easy|medium|hard")]
    pub difficulty: Option<AnnotationLevel>,
    /// The row's ID; with `--descriptions`, the first description's (an integer: the others
    /// number on by line).
    #[arg(long, default_value = "0", value_name = "N")]
    pub id: String,
    /// With `--descriptions`: do not show a progress bar.
    #[arg(long)]
    pub no_progress: bool,
    /// Annotation file whose rows are shown as in-context examples (of the description's
    /// level when given and the file has such rows).
    #[arg(long, value_name = "FILE")]
    pub examples: Option<PathBuf>,
    /// In-context examples shown.
    #[arg(long, default_value_t = DEFAULT_EXAMPLES_PER_REQUEST, value_name = "K")]
    pub examples_per_request: usize,
    /// Seed of the draw of in-context examples (the same draw as `generate`'s).
    #[arg(long = "seed", id = "example_seed", default_value_t = 0, value_name = "S")]
    pub example_seed: u64,
    /// The VLM (required: `--vlm-base-url`, `--vlm-model`).
    #[command(flatten)]
    pub vlm: VlmArgs,
}

/// Arguments of `sceneeval annotations generate`.
#[derive(Debug, clap::Args)]
pub struct GenerateArgs {
    /// Annotation file of in-context examples (e.g. SceneEval-500's CSV); new descriptions are
    /// also compared with its descriptions.
    #[arg(long, value_name = "FILE")]
    pub examples: PathBuf,
    /// How many rows `--out` should hold in the end (rows already there count: a re-run
    /// continues).
    #[arg(long, value_name = "N")]
    pub count: usize,
    /// The annotation file accepted rows are appended to (CSV; JSON for `.json`); rejected
    /// candidates go to OUT.rejected.jsonl.
    #[arg(long, short = 'o', value_name = "FILE")]
    pub out: PathBuf,
    /// The level of every description (default: easy, medium and hard in turn).
    #[arg(long, value_name = "easy|medium|hard")]
    pub difficulty: Option<AnnotationLevel>,
    /// Seed of the draw of in-context examples.
    #[arg(long = "seed", id = "example_seed", default_value_t = 0, value_name = "S")]
    pub example_seed: u64,
    /// In-context examples per request (the paper showed three to five).
    #[arg(long, default_value_t = DEFAULT_EXAMPLES_PER_REQUEST, value_name = "K")]
    pub examples_per_request: usize,
    /// The first ID when `--out` has no rows (default: one more than the examples' largest ID);
    /// `--id` as in `annotate` (`--first-id` is its old spelling).
    #[arg(long = "id", alias = "first-id", value_name = "N")]
    pub first_id: Option<u64>,
    /// Jaccard similarity of content words at and above which a description is too similar to
    /// an existing one.
    #[arg(long, default_value_t = DEFAULT_THRESHOLD, value_name = "S")]
    pub similarity_threshold: f64,
    /// The most candidates this run asks for (default three per row still to make).
    #[arg(long, value_name = "N")]
    pub max_candidates: Option<usize>,
    /// Do not show a progress bar.
    #[arg(long)]
    pub no_progress: bool,
    /// The VLM (required: `--vlm-base-url`, `--vlm-model`).
    #[command(flatten)]
    pub vlm: VlmArgs,
}

/// The model of the VLM options: the OpenAI-compatible client, cached only with `--vlm-cache`.
fn model(vlm: &VlmArgs, command: &str) -> anyhow::Result<SharedVlm> {
    let Some(options) = vlm.options()? else {
        bail!("annotations {command} asks a model: pass --vlm-base-url and --vlm-model");
    };
    Ok(options.shared_client().map_err(OptionError::evaluate)?)
}

fn read(file: &std::path::Path) -> anyhow::Result<Annotations> {
    Annotations::read(file).with_context(|| format!("cannot read annotation file {}", file.display()))
}

fn print_rejected(candidate: &RejectedCandidate) {
    eprintln!(
        "rejected: {}",
        serde_json::to_string(candidate).unwrap_or_else(|e| format!("(cannot show: {e})"))
    );
}

/// Runs `annotations annotate`: prints the row as CSV with its header, or the rejected
/// candidate on standard error with exit status 1; with `--descriptions`, [`annotate_all`].
pub fn annotate(args: AnnotateArgs) -> anyhow::Result<ExitCode> {
    if let (Some(list), Some(out)) = (&args.descriptions, &args.out) {
        return annotate_all(&args, list, out);
    }
    let Some(description) = &args.description else {
        bail!("annotations annotate needs a DESCRIPTION or --descriptions FILE --out FILE");
    };
    let examples = match &args.examples {
        Some(file) => draw_examples(
            &read(file)?.rows,
            args.difficulty,
            args.examples_per_request,
            args.example_seed,
        ),
        None => Vec::new(),
    };
    let vlm = model(&args.vlm, "annotate")?;
    let session = Session::new(vlm);
    let outcome = pollster::block_on(sceneeval::annotate::annotate(
        &session,
        description,
        args.difficulty,
        examples,
        &args.id,
    ))
    .context("the model gave no answer")?;
    match outcome {
        AnnotateOutcome::Accepted { row, attempt } => {
            tracing::info!(attempt, "annotation row accepted");
            let csv = Annotations::from_rows(vec![row])
                .to_csv_string()
                .context("the row cannot be written as CSV")?;
            crate::print_stdout(&csv)?;
            Ok(ExitCode::SUCCESS)
        }
        AnnotateOutcome::Rejected(candidate) => {
            print_rejected(&candidate);
            Ok(ExitCode::FAILURE)
        }
    }
}

/// Runs `annotations generate`: rows appended to `--out` as they are accepted, a progress bar,
/// a final summary line. Exit status 1 when the run stopped short of `--count`.
pub fn generate(args: GenerateArgs) -> anyhow::Result<ExitCode> {
    let examples = read(&args.examples)?;
    if !(args.similarity_threshold > 0.0 && args.similarity_threshold <= 1.0) {
        bail!("--similarity-threshold must be above 0 and at most 1");
    }
    let mut options = GenerateOptions::new(&args.out, args.count);
    options.difficulty = args.difficulty;
    options.seed = args.example_seed;
    options.examples_per_request = args.examples_per_request;
    options.first_id = args.first_id;
    options.threshold = args.similarity_threshold;
    let vlm = model(&args.vlm, "generate")?;
    let session = Session::new(vlm);
    let bar = progress_bar(args.no_progress, args.count, "rows");
    let rejected = std::cell::Cell::new(0usize);
    let on_event = |event: &GenerateEvent<'_>| on_progress(&bar, &rejected, event, false);
    // Rows already in the file count; the limit is on this run's candidates.
    let existing = if args.out.exists() {
        read(&args.out)?.rows.len()
    } else {
        0
    };
    options.max_candidates = args
        .max_candidates
        .unwrap_or_else(|| args.count.saturating_sub(existing).saturating_mul(3));
    let summary = sceneeval::annotate::generate(&session, &examples, &options, &on_event);
    bar.finish_and_clear();
    let summary = summary?;
    crate::print_stdout(&format!(
        "{}: {} rows ({} accepted now, {} already there), {} rejected now (in {}){}\n",
        args.out.display(),
        summary.total,
        summary.accepted,
        summary.existing,
        summary.rejected,
        rejected_path(&args.out).display(),
        if summary.stopped_early {
            format!(
                "; stopped after {} candidates, short of {}",
                options.max_candidates, args.count
            )
        } else {
            String::new()
        }
    ))?;
    Ok(if summary.stopped_early {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// The progress bar of `generate` and `annotate --descriptions`: `len` of `unit`.
fn progress_bar(hidden: bool, len: usize, unit: &str) -> ProgressBar {
    let bar = if hidden {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(len as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{bar:30}} {{pos}}/{{len}} {unit}, {{msg}} [{{elapsed_precise}}, ETA {{eta}}]"
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message("0 rejected");
    bar
}

/// Moves the bar on an event; `every_candidate`: a rejected candidate moves it too (each
/// description is done either way).
fn on_progress(
    bar: &ProgressBar,
    rejected: &std::cell::Cell<usize>,
    event: &GenerateEvent<'_>,
    every_candidate: bool,
) {
    match event {
        GenerateEvent::Started { existing, target } => {
            bar.set_position(*existing as u64);
            tracing::info!(existing, target, "run starts");
        }
        GenerateEvent::Accepted(row) => {
            bar.inc(1);
            tracing::debug!(id = %row.id, "accepted");
        }
        GenerateEvent::Rejected(candidate) => {
            rejected.set(rejected.get() + 1);
            if every_candidate {
                bar.inc(1);
            }
            bar.set_message(format!("{} rejected", rejected.get()));
            bar.suspend(|| print_rejected(candidate));
        }
    }
}

/// Runs `annotations annotate --descriptions LIST --out OUT`: every description of LIST
/// annotated in order ([`sceneeval::annotate::annotate_all`]), a progress bar, a final summary
/// line. Exit status 1 when some description has a rejected candidate instead of a row (to
/// review: `sceneeval annotations review OUT`).
fn annotate_all(
    args: &AnnotateArgs,
    list: &std::path::Path,
    out: &std::path::Path,
) -> anyhow::Result<ExitCode> {
    let first_id: u64 = args.id.parse().map_err(|_| {
        anyhow::anyhow!(
            "--id {:?}: with --descriptions the first ID must be a non-negative integer (the others number on by line)",
            args.id
        )
    })?;
    let descriptions = sceneeval::annotate::read_descriptions(list).context("--descriptions")?;
    if descriptions.is_empty() {
        bail!(
            "--descriptions: {} holds no description (one per line)",
            list.display()
        );
    }
    let examples = match &args.examples {
        Some(file) => read(file)?,
        None => Annotations::new(),
    };
    let mut options = AnnotateAllOptions::new(out);
    options.difficulty = args.difficulty;
    options.first_id = first_id;
    options.seed = args.example_seed;
    options.examples_per_request = args.examples_per_request;
    let vlm = model(&args.vlm, "annotate")?;
    let session = Session::new(vlm);
    let bar = progress_bar(args.no_progress, descriptions.len(), "descriptions");
    let rejected = std::cell::Cell::new(0usize);
    let on_event = |event: &GenerateEvent<'_>| on_progress(&bar, &rejected, event, true);
    let summary = sceneeval::annotate::annotate_all(&session, &descriptions, &examples, &options, &on_event);
    bar.finish_and_clear();
    let summary = summary?;
    let rejected_file = rejected_path(out);
    let rows = sceneeval::annotate::read_rows(out)?;
    let undone = (0..descriptions.len() as u64)
        .filter(|n| rows.get(&first_id.saturating_add(*n).to_string()).is_none())
        .count();
    crate::print_stdout(&format!(
        "{}: {} rows ({} accepted now); {} descriptions of {} without a row ({} rejected now, in {}){}\n",
        out.display(),
        summary.total,
        summary.accepted,
        undone,
        descriptions.len(),
        summary.rejected,
        rejected_file.display(),
        if undone > 0 {
            format!("; fix them in `sceneeval annotations review {}`", out.display())
        } else {
            String::new()
        }
    ))?;
    Ok(if undone > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}
