//! `sceneeval evaluate`: evaluate a folder of scenes, write `<out>/<scene>/eval.json` and
//! `<out>/<scene>/timing.json` as each scene finishes, then `<out>/summary.csv` and
//! `<out>/summary.md`. The flags are mapped onto one [`EvaluationRequest`] (each default is
//! the facade's), which the facade checks and runs.

use std::borrow::Cow;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use indicatif::{ProgressBar, ProgressStyle};
use sceneeval::{
    ErrorChain, EvaluationRequest, Metric, Outcome, PlanRequest, Preset, RequestField, RunEvent, RunOutcome,
    SceneStatus, Shard, VlmOptions,
};

use crate::vlm::VlmArgs;

/// Arguments of `sceneeval evaluate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Folder holding the `scene_<ID>.json` files to evaluate.
    pub scenes: PathBuf,
    /// Asset folder for a model-id prefix, as `PREFIX=DIR` (layout chosen from the prefix) or
    /// `PREFIX=LAYOUT:DIR` with LAYOUT one of 3d-future, objathor, hssd, layoutvlm, idesign,
    /// scene-agent, plain. Repeat for several prefixes.
    #[arg(long = "assets", value_name = "PREFIX=[LAYOUT:]DIR")]
    pub assets: Vec<String>,
    /// Output folder (created if missing; checked for writing before any scene is evaluated).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    /// SceneEval-500 annotation CSV (or JSON): the rows the fidelity metrics check (looked up
    /// by the scene's ID), and rows per difficulty in the summary.
    #[arg(long, value_name = "FILE")]
    pub annotations: Option<PathBuf>,
    /// What to evaluate: `geometry` (the default: the six geometry metrics, no VLM), `full`
    /// (the paper's ten metrics), a comma-separated metric list (`collision,cnt,oor`; the
    /// summary's column names work too: `COL_ob,OOB`), or a plan file (JSON or TOML: preset,
    /// metrics, parameters, limits, time budget; see docs/formats.md).
    #[arg(long, value_name = "geometry|full|LIST|FILE")]
    pub plan: Option<String>,
    /// The VLM for the fidelity metrics (matching, ATR, relation mapping).
    #[command(flatten)]
    pub vlm: VlmArgs,
    /// Object matching: `vlm` (default with a VLM), `labels` (default without), or a matching
    /// file or folder in the reference's obj_matching_result.json shape.
    #[arg(long, value_name = "vlm|labels|FILE")]
    pub matching: Option<String>,
    /// Relation mapping: `vlm` (default with a VLM) or `lexicon` (default without; unknown
    /// words still go to the VLM when one is configured).
    #[arg(long, value_name = "vlm|lexicon")]
    pub relation_mapping: Option<String>,
    /// Side of the square object views shown to the VLM, pixels (default
    /// `sceneeval::DEFAULT_RENDER_SIZE`, within `sceneeval::RENDER_SIZE_RANGE`).
    #[arg(long, value_name = "PX", requires = "vlm_base_url", help = crate::vlm::render_size_help())]
    pub render_size: Option<u32>,
    /// Evaluate only shard K of N (1-based): the scenes whose position in ID order is K-1
    /// modulo N. Merge the shards' folders with `sceneeval summarize`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Parameter preset: `default`, or `reference` for every reference-parity switch (to
    /// compare with published numbers). Replaces the plan file's `preset`; the plan's explicit
    /// values still apply on top.
    #[arg(long, value_name = "NAME")]
    pub preset: Option<Preset>,
    /// Run only these metrics (comma-separated names or summary columns), overriding the
    /// plan's list.
    #[arg(long, value_delimiter = ',', value_name = "METRIC,...")]
    pub metrics: Option<Vec<Metric>>,
    /// Wall-time budget per scene in seconds, overriding the plan's (default 600); a scene
    /// over it is recorded as failed and the run goes on. 0 means no budget.
    #[arg(long = "time-budget-s", alias = "time-budget", value_name = "SECONDS")]
    pub time_budget_s: Option<f64>,
    /// Evaluate every scene again, even those whose earlier result still matches.
    #[arg(long)]
    pub force: bool,
    /// Worker threads (default: one per core).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Also write diagnostic images under `<out>/<scene>/diagnostics/`.
    #[arg(long)]
    pub diagnostics: bool,
    /// After the run, write its static report into `<out>/report/` (as `sceneeval report`).
    #[arg(long)]
    pub report: bool,
    /// Refuse scene files with keys the sceneState format does not have (a misspelt key is
    /// read as absent): each such scene fails, instead of a warning about each key.
    #[arg(long)]
    pub strict: bool,
    /// Do not show a progress bar.
    #[arg(long)]
    pub no_progress: bool,
    /// Print the evaluation request these options make (JSON) and exit without evaluating:
    /// what the Python package's `sceneeval.evaluation_request` gives for the same options.
    #[arg(long)]
    pub print_request: bool,
    /// Print, per VLM task, the requests the run would send, how many the response cache
    /// already answers and their estimated input tokens, then exit: nothing is sent, computed
    /// or written (object views are rendered, to know what the cache holds).
    #[arg(long)]
    pub dry_run: bool,
}

impl Args {
    /// The evaluation request these options make.
    ///
    /// # Errors
    /// A VLM sampling option without `--vlm-base-url`.
    pub fn request(&self) -> anyhow::Result<EvaluationRequest> {
        let vlm = self.vlm.options()?.map(|options| VlmOptions {
            render_size: self.render_size,
            ..options
        });
        Ok(EvaluationRequest {
            scenes: self.scenes.clone(),
            assets: self.assets.clone(),
            out: self.out.clone(),
            annotations: self.annotations.clone(),
            plan: PlanRequest {
                plan: self.plan.clone(),
                preset: self.preset,
                metrics: self.metrics.clone(),
                time_budget_s: self.time_budget_s,
                matching: self.matching.clone(),
                relation_mapping: self.relation_mapping.clone(),
            },
            vlm,
            threads: self.threads,
            force: self.force,
            shard: self.shard,
            diagnostics: self.diagnostics,
            strict: self.strict,
        })
    }
}

/// The request fields `sceneeval evaluate` does not name `--` + the kebab-case of their path
/// ([`RequestField::path`]), with the name it gives each and why. Every other field is
/// set by the option of its path (`vlm.max_tokens` by `--vlm-max-tokens`, `time_budget_s` by
/// `--time-budget-s`).
pub const OPTION_EXCEPTIONS: [(RequestField, &str, &str); 3] = [
    (RequestField::Scenes, "SCENES", "the positional argument"),
    (
        RequestField::Vlm,
        "--vlm-base-url",
        "the VLM options as a whole: the option that makes a run use a VLM",
    ),
    (
        RequestField::VlmRenderSize,
        "--render-size",
        "every command that renders names its image side --render-size (render, settle)",
    ),
];

/// The option of `sceneeval evaluate` that sets `field`: `--` and the kebab-case of the
/// request's name for it ([`RequestField::path`], the one table: `vlm.max_tokens` is
/// `--vlm-max-tokens`), but for the [`OPTION_EXCEPTIONS`].
pub fn option_name(field: RequestField) -> Cow<'static, str> {
    match OPTION_EXCEPTIONS.iter().find(|(f, _, _)| *f == field) {
        Some((_, name, _)) => Cow::Borrowed(name),
        None => format!("--{}", field.path().replace(['.', '_'], "-")).into(),
    }
}

/// An error of the facade shown as the CLI's: a request error names the option that sets the
/// field (`--plan: ...`, through `name`), keeping its causes; any other error is shown as it is.
#[derive(Debug)]
pub struct OptionError {
    /// The facade's error (a run's request error is kept as the evaluator's error it wraps).
    pub error: Box<dyn std::error::Error + Send + Sync + 'static>,
    /// The option of the command that sets a request field.
    pub name: fn(RequestField) -> Cow<'static, str>,
}

impl OptionError {
    /// `error` with the options of `sceneeval evaluate`.
    pub fn evaluate(error: impl Into<sceneeval::RunError>) -> Self {
        OptionError::new(error, option_name)
    }

    /// `error` with the options `name` gives for the request's fields.
    pub fn new(error: impl Into<sceneeval::RunError>, name: fn(RequestField) -> Cow<'static, str>) -> Self {
        let error: Box<dyn std::error::Error + Send + Sync> = match error.into() {
            sceneeval::RunError::Eval(e) => Box::new(e),
            other => Box::new(other),
        };
        OptionError { error, name }
    }

    /// The request error this is, if it is one.
    fn request(&self) -> Option<(RequestField, &str, Option<&(dyn std::error::Error + 'static)>)> {
        match self.error.downcast_ref::<sceneeval::EvalError>()? {
            sceneeval::EvalError::Request {
                field,
                message,
                source,
            } => Some((
                *field,
                message.as_str(),
                source.as_deref().map(|s| s as &(dyn std::error::Error + 'static)),
            )),
            _ => None,
        }
    }
}

impl std::fmt::Display for OptionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.request() {
            Some((field, message, _)) => write!(f, "{}: {message}", (self.name)(field)),
            None => self.error.fmt(f),
        }
    }
}

impl std::error::Error for OptionError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self.request() {
            Some((_, _, source)) => source,
            None => self.error.source(),
        }
    }
}

/// Runs the subcommand. Exits with failure when any scene failed to load or evaluate (each
/// failure is recorded in its `eval.json`, printed with its cause chain and counted in the
/// summary). Everything that can be checked before evaluating (the scene names, the plan, the
/// VLM settings, the asset folders, the annotations, the output folder) is checked first, and
/// the VLM's endpoint before the first scene that is evaluated.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let request = args.request()?;
    if args.print_request {
        crate::print_stdout(&format!("{}\n", serde_json::to_string_pretty(&request)?))?;
        return Ok(ExitCode::SUCCESS);
    }
    let prepared = request.prepare().map_err(OptionError::evaluate)?;
    for skipped in prepared.skipped() {
        eprintln!("warning: skipped {}: {}", skipped.path.display(), skipped.reason);
    }
    for warning in prepared.warnings() {
        eprintln!("warning: {warning}");
    }
    if args.dry_run {
        print_dry_run(&prepared.dry_run());
        return Ok(ExitCode::SUCCESS);
    }
    if let Some(shard) = request.shard {
        eprintln!("shard {shard}: {} scenes", prepared.scenes().len());
    }
    if prepared.replaced() > 0 {
        eprintln!(
            "warning: {} earlier results in {} were made with another plan, preset or VLM; this run replaces them \
             (write to another --out to keep them)",
            prepared.replaced(),
            args.out.display()
        );
    }
    if let Some(fallback) = prepared.fallback() {
        eprintln!("note: no VLM configured (--vlm-base-url, --vlm-model): {fallback}");
    }
    let has_fidelity = prepared.evaluator().plan().has_fidelity();
    let preset = prepared.evaluator().plan().preset;
    let vlm = prepared.evaluator().vlm().cloned();
    let total = prepared.scenes().len() as u64;

    let progress = if args.no_progress {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total)
    };
    let tracker = Tracker::new(&progress, total, vlm.is_some());
    let hinted = AtomicBool::new(false);
    let on_event = |event: &RunEvent<'_>| {
        let RunEvent::SceneDone {
            scene,
            status,
            record,
            error,
        } = *event
        else {
            return;
        };
        if let (SceneStatus::Failed { .. }, Outcome::Failed { stage, error, causes }) =
            (status, &record.outcome)
        {
            let chain = ErrorChain::from_parts(error.as_str(), causes);
            let text = format!(
                "failed: {} ({} stage): {chain:#}",
                scene.path.display(),
                match stage {
                    sceneeval::Stage::Load => "load",
                    sceneeval::Stage::Evaluate => "evaluate",
                }
            );
            // `suspend` prints also when the bar is hidden (`println` would not).
            progress.suspend(|| eprintln!("{text}"));
        }
        // Advice for an error an option fixes, once per run.
        if let Some(hint) = error.and_then(crate::hint)
            && !hinted.swap(true, Ordering::Relaxed)
        {
            progress.suspend(|| eprintln!("hint: {hint}"));
        }
        let fidelity = match status {
            SceneStatus::Evaluated { .. } => record.report().and_then(|r| r.fidelity.as_ref()),
            _ => None,
        };
        tracker.scene_done(fidelity);
        tracker.show(vlm.as_ref());
    };
    let finished = AtomicBool::new(false);
    let outcome = std::thread::scope(|scope| {
        // The bar advances per answered request: shown four times a second while a VLM answers.
        if let Some(vlm) = &vlm {
            scope.spawn(|| {
                while !finished.load(Ordering::Relaxed) {
                    tracker.show(Some(vlm));
                    std::thread::sleep(std::time::Duration::from_millis(250));
                }
            });
        }
        let outcome = prepared.run(&on_event);
        finished.store(true, Ordering::Relaxed);
        outcome
    });
    let RunOutcome {
        scenes,
        batch: outcome,
        summary,
        ..
    } = outcome.map_err(OptionError::evaluate)?;
    progress.finish_and_clear();

    crate::print_stdout(&summary.to_markdown())?;
    eprintln!(
        "{} scenes: {} evaluated, {} kept from an earlier run, {} failed, {} partial; preset {}; results in {}",
        scenes.len(),
        outcome.evaluated,
        outcome.reused,
        outcome.failed,
        outcome.partial,
        preset,
        args.out.display()
    );
    if has_fidelity {
        let renders = tracker.renders.load(Ordering::Relaxed);
        match vlm.as_ref().map(sceneeval::SharedVlm::usage) {
            Some(u) => eprintln!(
                "  fidelity: {renders} renders, {} VLM requests sent ({} tokens), {} answered from the cache, {} failed",
                u.requests - u.cache_hits,
                u.tokens.total(),
                u.cache_hits,
                u.failed_requests
            ),
            None => eprintln!("  fidelity: {renders} renders, no VLM"),
        }
    }
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
    if args.report {
        crate::report::after_evaluate(&args.out, &args.scenes, &args.assets, args.annotations.as_deref())?;
    }
    // A partial scene's results are incomplete too: a re-run completes them.
    Ok(if outcome.failed + outcome.partial > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

/// The progress bar: per scene without a VLM; per answered VLM request with one, with the
/// rate, an ETA (once a scene is done, from its requests per scene) and the tokens so far.
struct Tracker<'a> {
    bar: &'a ProgressBar,
    total: u64,
    done: AtomicU64,
    /// Requests of the scenes done, from their records.
    requests_done: AtomicU64,
    renders: AtomicU64,
    estimating: AtomicBool,
}

impl<'a> Tracker<'a> {
    fn new(bar: &'a ProgressBar, total: u64, vlm: bool) -> Self {
        let template = if vlm {
            "{elapsed_precise} {spinner} {pos} VLM requests answered ({per_sec}){msg}"
        } else {
            "{elapsed_precise} [{bar:40}] {pos}/{len} scenes{msg}"
        };
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("=> "));
        }
        if vlm {
            bar.set_length(0);
        }
        Tracker {
            bar,
            total,
            done: AtomicU64::new(0),
            requests_done: AtomicU64::new(0),
            renders: AtomicU64::new(0),
            estimating: AtomicBool::new(false),
        }
    }

    fn scene_done(&self, fidelity: Option<&sceneeval::fidelity::FidelityReport>) {
        self.done.fetch_add(1, Ordering::Relaxed);
        if let Some(f) = fidelity {
            self.renders.fetch_add(f.views_rendered, Ordering::Relaxed);
            if let Some(u) = f.vlm_usage {
                self.requests_done.fetch_add(u.requests, Ordering::Relaxed);
            }
        }
    }

    /// Shows the counts now.
    fn show(&self, vlm: Option<&sceneeval::SharedVlm>) {
        let done = self.done.load(Ordering::Relaxed);
        let Some(vlm) = vlm else {
            self.bar.set_position(done);
            self.bar
                .set_message(format!(", {} renders", self.renders.load(Ordering::Relaxed)));
            return;
        };
        let u = vlm.usage();
        self.bar.set_position(u.requests);
        if done > 0 {
            // Requests per scene so far, over every scene of the run.
            let per_scene = self.requests_done.load(Ordering::Relaxed) as f64 / done as f64;
            let estimate = (per_scene * self.total as f64).round() as u64;
            self.bar.set_length(estimate.max(u.requests));
            if !self.estimating.swap(true, Ordering::Relaxed)
                && let Ok(style) = ProgressStyle::with_template(
                    "{elapsed_precise} [{bar:30}] {pos}/~{len} VLM requests ({per_sec}, ETA {eta}){msg}",
                )
            {
                self.bar.set_style(style.progress_chars("=> "));
            }
        }
        self.bar.set_message(format!(
            ", {done}/{} scenes, {} tokens, {} from the cache, {} failed",
            self.total,
            u.tokens.total(),
            u.cache_hits,
            u.failed_requests
        ));
    }
}

/// `--dry-run`'s table.
fn print_dry_run(dry: &sceneeval::DryRun) {
    if !dry.vlm {
        println!(
            "dry run: {} scenes; no VLM would be asked (no VLM configured, or the plan asks none).",
            dry.scenes
        );
        return;
    }
    println!(
        "dry run: {} scenes, {} to evaluate, {} kept from an earlier run; nothing was sent.",
        dry.scenes, dry.evaluated, dry.reused
    );
    println!("| task | requests | from the cache | to send | estimated input tokens to send |");
    println!("|---|---:|---:|---:|---:|");
    for t in dry.tasks.iter().chain(std::iter::once(&dry.total())) {
        let estimated = if t.estimated > 0 {
            format!(" ({} estimated)", t.estimated)
        } else {
            String::new()
        };
        println!(
            "| {} | {} | {} | {}{estimated} | {} |",
            t.task,
            t.requests,
            t.cached,
            t.to_send(),
            t.prompt_tokens
        );
    }
    if dry.attributes_estimated > 0 {
        println!(
            "note: {} scenes have matching requests to send, so their attribute requests are estimated: one per \
             ObjAttr entry of the annotation row (the most the run sends), with as many instances as the entry's \
             quantity.",
            dry.attributes_estimated
        );
    }
    println!(
        "note: re-asks of invalid answers (at most one per request) are not counted; tokens are estimated at 4 \
         characters per token and by OpenAI's rule for images, plus --vlm-max-tokens when set."
    );
    for (scene, why) in &dry.failed {
        println!("note: {scene} would fail: {why}");
    }
}

#[cfg(test)]
mod tests {
    use clap::{CommandFactory, Parser};

    use super::*;

    /// A value of `field` on the command line, and the JSON the request holds for it.
    fn sample(field: RequestField) -> (&'static str, serde_json::Value) {
        use serde_json::json;
        match field {
            RequestField::Scenes => ("elsewhere", json!("elsewhere")),
            RequestField::Assets => ("p=dir", json!(["p=dir"])),
            RequestField::Out => ("o2", json!("o2")),
            RequestField::Annotations => ("a.csv", json!("a.csv")),
            RequestField::Plan => ("full", json!("full")),
            RequestField::Preset => ("reference", json!("reference")),
            RequestField::Metrics => ("cnt", json!(["cnt"])),
            RequestField::TimeBudget => ("30", json!(30.0)),
            RequestField::Matching => ("labels", json!("labels")),
            RequestField::RelationMapping => ("lexicon", json!("lexicon")),
            RequestField::Threads => ("3", json!(3)),
            RequestField::Vlm | RequestField::VlmBaseUrl => ("http://h/v1", json!("http://h/v1")),
            RequestField::VlmModel => ("m2", json!("m2")),
            RequestField::VlmApiKeyEnv => ("K", json!("K")),
            RequestField::VlmCache => ("c", json!("c")),
            RequestField::VlmConcurrency => ("7", json!(7)),
            RequestField::VlmRenderSize => ("256", json!(256)),
            RequestField::VlmDetail => ("high", json!("high")),
            RequestField::VlmTemperature => ("0.5", json!(0.5)),
            RequestField::VlmSeed => ("9", json!(9)),
            RequestField::VlmMaxTokens => ("300", json!(300)),
            RequestField::VlmTokenLimitField => ("max_completion_tokens", json!("max_completion_tokens")),
            RequestField::VlmTimeout => ("12", json!(12.0)),
            RequestField::VlmRpm => ("500", json!(500)),
            RequestField::VlmTpm => ("40000", json!(40000)),
            other => panic!("no sample value for {other:?}"),
        }
    }

    /// The request `sceneeval evaluate ARGS` makes, as JSON (parsed by the real command line).
    fn request_of(args: &[&str]) -> serde_json::Value {
        let argv = ["sceneeval", "evaluate"].iter().chain(args);
        let cli = crate::Cli::try_parse_from(argv).unwrap_or_else(|e| panic!("{args:?}: {e}"));
        let crate::Command::Evaluate(evaluate) = cli.command else {
            panic!("not evaluate");
        };
        serde_json::to_value(evaluate.request().unwrap()).unwrap()
    }

    /// The JSON at a request field's path.
    fn at(request: &serde_json::Value, field: RequestField) -> &serde_json::Value {
        let path = field.path();
        match path.strip_prefix("vlm.") {
            Some(key) => &request["vlm"][key],
            None if field == RequestField::Vlm => &request["vlm"]["base_url"],
            None if matches!(
                field,
                RequestField::Plan
                    | RequestField::Preset
                    | RequestField::Metrics
                    | RequestField::TimeBudget
                    | RequestField::Matching
                    | RequestField::RelationMapping
            ) =>
            {
                &request["plan"][path]
            }
            None => &request[path],
        }
    }

    /// Every request field is set by the option `option_name` gives it, parsed by the real
    /// `sceneeval evaluate` command: the value given to that option is the value at the
    /// field's path in the request it makes.
    #[test]
    fn every_request_field_names_an_option_of_evaluate() {
        let base = [
            "scenes",
            "--out",
            "out",
            "--vlm-base-url",
            "http://b/v1",
            "--vlm-model",
            "m",
        ];
        let command = crate::Cli::command();
        let evaluate = command.find_subcommand("evaluate").unwrap();
        for field in RequestField::ALL {
            let name = option_name(field);
            let (value, expected) = sample(field);
            let mut args: Vec<&str> = base.to_vec();
            if field == RequestField::Scenes {
                args[0] = value;
            } else {
                assert!(name.starts_with("--"), "{field:?}: {name}");
                match args.iter().position(|a| *a == name) {
                    // An option of the base: its value replaced.
                    Some(at) => args[at + 1] = value,
                    None => args.extend([&*name, value]),
                }
            }
            let request = request_of(&args);
            assert_eq!(at(&request, field), &expected, "{field:?} through {name} {value}");
            // The option is a visible argument of the command.
            let arg = evaluate
                .get_arguments()
                .find(|a| match name.strip_prefix("--") {
                    Some(long) => a.get_long() == Some(long),
                    None => a.get_value_names().is_some_and(|v| v.iter().any(|v| v == &*name)),
                })
                .unwrap_or_else(|| panic!("{field:?}: {name} is no argument of evaluate"));
            assert!(!arg.is_hide_set(), "{name}");
        }
        // The exceptions are the positional argument and two options, each said why.
        assert_eq!(option_name(RequestField::Scenes), "SCENES");
        assert_eq!(option_name(RequestField::TimeBudget), "--time-budget-s");
        assert_eq!(option_name(RequestField::VlmTimeout), "--vlm-timeout-s");
        assert_eq!(OPTION_EXCEPTIONS.len(), 3);
    }
}
