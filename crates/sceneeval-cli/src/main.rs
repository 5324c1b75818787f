//! The `sceneeval` command line. This is the only crate of the workspace that prints.
//!
//! Each subcommand lives in its own module with an `Args` struct (clap) and a `run` function
//! returning the process exit code; `main` installs logging, dispatches, and prints the error
//! chain of a failed command to standard error.

#![allow(clippy::print_stdout, clippy::print_stderr)]

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Subcommand};

mod agreement;
mod annotations;
mod compare;
mod convert;
mod ensemble;
mod evaluate;
mod flags;
mod format;
mod inspect;
mod judge;
mod relate;
mod render;
mod report;
mod server;
mod settle;
mod summarize;
mod vlm;

/// Evaluate text-conditioned 3D indoor scenes (SceneEval): convert, inspect, render, evaluate and
/// settle scenes; summarize, compare and report runs; answer predicate queries; check, make and
/// review annotations; check a VLM endpoint.
#[derive(Debug, clap::Parser)]
#[command(name = "sceneeval", version, about, long_about = None)]
struct Cli {
    /// More log output on standard error (-v info, -vv debug, -vvv trace). `RUST_LOG` overrides.
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    verbose: u8,

    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Load a sceneState file and print its objects, rooms, walls and openings.
    Inspect(inspect::Args),
    /// Convert a generator's output (Holodeck, LayoutVLM, IDesign, SceneAgent) to sceneState files.
    Convert(convert::Args),
    /// Answer spatial-relation queries given as JSON lines.
    Relate(relate::Args),
    /// Check annotation files, print their statistics, or make annotation rows with a model.
    #[command(subcommand)]
    Annotations(annotations::Command),
    /// Evaluate a folder of scenes and write per-scene results and summary tables.
    Evaluate(Box<evaluate::Args>),
    /// Merge the per-scene results of output folders (e.g. shards) into the summary tables.
    Summarize(summarize::Args),
    /// Combine runs made with different judges: each fidelity verdict the majority of the runs'.
    Ensemble(ensemble::Args),
    /// Compare the runs of several methods: a paper table with ranks (Markdown, CSV, LaTeX, HTML).
    Compare(compare::Args),
    /// How far judges agree with people on the fidelity specs: agreement and Cohen's/Fleiss' kappa.
    Agreement(agreement::Args),
    /// Judge a run's fidelity specs by hand in the browser; every verdict goes to a label file.
    Judge(judge::Args),
    /// Write a browsable static report of a finished run (RUN/report/index.html).
    Report(report::Args),
    /// Render the reference's views of a scene (front, size, surroundings, top) as PNG files.
    Render(render::Args),
    /// Simulate a scene under gravity and write it with every object at its settled pose.
    Settle(settle::Args),
    /// Work with the vision-language model endpoint (check that it answers).
    #[command(subcommand)]
    Vlm(vlm::Command),
}

fn main() -> ExitCode {
    quiet_driver_probe();
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let mut command = Cli::command();
    let matches = command.clone().get_matches_from(&args);
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.format(&mut command).exit());
    init_logging(cli.verbose);
    for (old, new) in flags::old_spellings(&command, &matches, &args) {
        eprintln!("{}", flags::old_spelling_warning(&old, &new));
    }
    let result = match cli.command {
        Command::Inspect(args) => inspect::run(args),
        Command::Convert(args) => convert::run(args),
        Command::Relate(args) => relate::run(args),
        Command::Annotations(cmd) => annotations::run(cmd),
        Command::Evaluate(args) => evaluate::run(*args),
        Command::Render(args) => render::run(args),
        Command::Settle(args) => settle::run(args),
        Command::Summarize(args) => summarize::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Ensemble(args) => ensemble::run(args),
        Command::Report(args) => report::run(args),
        Command::Agreement(args) => agreement::run(args),
        Command::Judge(args) => judge::run(args),
        Command::Vlm(cmd) => vlm::run(cmd),
    };
    match result {
        Ok(code) => code,
        // The reader of the output went away (`sceneeval inspect --json | head`): end quietly
        // and successfully, as ripgrep and other command-line tools do.
        Err(err) if is_broken_pipe(err.as_ref()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {:#}", sceneeval::ErrorChain::new(err.as_ref()));
            if let Some(hint) = hint(err.as_ref()) {
                eprintln!("hint: {hint}");
            }
            ExitCode::FAILURE
        }
    }
}

/// The environment variable that turns off Mesa's implicit Vulkan layer
/// `VK_LAYER_MESA_device_select` (the Vulkan loader honours it).
pub const NODEVICE_SELECT: &str = "NODEVICE_SELECT";

/// Keeps Mesa's driver noise out of the output: sets [`NODEVICE_SELECT`]`=1` for this process
/// unless the environment sets it.
///
/// Without it, every render on a machine without `XDG_RUNTIME_DIR` (a container, CI, a service)
/// printed `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` on successful
/// runs: the layer asks libwayland for a display while it orders the adapters (see
/// `sceneeval_render::Gpu::new`). The renders are headless and wgpu chooses the adapter itself,
/// so the layer has nothing to do here.
#[allow(unsafe_code)]
fn quiet_driver_probe() {
    if std::env::var_os(NODEVICE_SELECT).is_none() {
        // SAFETY: the first statement of `main`, before this process starts any thread, so no
        // other thread reads or writes the environment meanwhile.
        unsafe { std::env::set_var(NODEVICE_SELECT, "1") };
    }
}

/// Writes `text` to standard output and flushes it: the commands print their results through
/// this (or their own writer), so that a closed pipe is an error [`main`] ends quietly on, not
/// a panic as with `println!`.
///
/// # Errors
/// The write's error, with the context "writing to standard output".
pub fn print_stdout(text: &str) -> anyhow::Result<()> {
    use anyhow::Context as _;
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .context("writing to standard output")
}

/// Whether `err` or one of its causes is a write to a closed pipe.
fn is_broken_pipe(err: &(dyn std::error::Error + 'static)) -> bool {
    std::iter::once(err).chain(sceneeval::causes(err)).any(|cause| {
        // serde_json's error does not list its I/O error as a cause: ask it.
        let kind = cause
            .downcast_ref::<std::io::Error>()
            .map(std::io::Error::kind)
            .or_else(|| cause.downcast_ref::<serde_json::Error>()?.io_error_kind());
        kind == Some(std::io::ErrorKind::BrokenPipe)
    })
}

/// What to do about an error that a command-line option fixes, if it is one (the error or one
/// of its causes).
pub fn hint(err: &(dyn std::error::Error + 'static)) -> Option<String> {
    use sceneeval::io::IoError;
    // Causes are `IoError`s, or boxed ones (an object's asset error boxes its cause).
    fn io<'e>(cause: &'e (dyn std::error::Error + 'static)) -> Option<&'e IoError> {
        cause
            .downcast_ref::<IoError>()
            .or_else(|| cause.downcast_ref::<Box<IoError>>().map(|b| &**b))
    }
    if let Some(hint) = std::iter::once(err)
        .chain(sceneeval::causes(err))
        .find_map(convert::hint)
    {
        return Some(hint);
    }
    std::iter::once(err).chain(sceneeval::causes(err)).find_map(|cause| {
        // The report crate's errors name no option: the command line adds them.
        match cause.downcast_ref::<sceneeval::report::ReportError>() {
            Some(sceneeval::report::ReportError::NoRecords { .. }) => {
                return Some("give the --out folder of sceneeval evaluate".to_owned());
            }
            Some(sceneeval::report::ReportError::Assets(_)) => {
                return Some("each --assets is PREFIX=DIR or PREFIX=LAYOUT:DIR".to_owned());
            }
            _ => {}
        }
        match io(cause)? {
            IoError::UnknownPrefix { prefix, .. } => Some(format!(
                "the scene names assets with the prefix {prefix:?}: pass --assets {prefix}=DIR with the folder \
                 that holds them ({prefix}=LAYOUT:DIR to choose its layout; README, \"Using real asset folders\")"
            )),
            _ => None,
        }
    })
}

fn init_logging(verbose: u8) {
    use tracing_subscriber::EnvFilter;
    let default = match verbose {
        0 => "warn",
        1 => "info",
        2 => "debug",
        _ => "trace",
    };
    let filter = EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(default));
    let ansi = std::io::IsTerminal::is_terminal(&std::io::stderr());
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(ansi)
        .init();
}
