//! The `sceneeval` command line. This is the only crate of the workspace that prints.
//!
//! Each subcommand lives in its own module with an `Args` struct (clap) and a `run` function
//! returning the process exit code; `main` installs logging, dispatches, and prints the error
//! chain of a failed command to standard error.

#![allow(clippy::print_stdout, clippy::print_stderr)]

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod annotations;
mod evaluate;
mod inspect;
mod relate;
mod render;
mod vlm;

/// Evaluate text-conditioned 3D indoor scenes (SceneEval) and query its spatial predicates.
#[derive(Debug, Parser)]
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
    /// Answer spatial-relation queries given as JSON lines.
    Relate(relate::Args),
    /// Check annotation files or print their statistics.
    #[command(subcommand)]
    Annotations(annotations::Command),
    /// Evaluate a folder of scenes and write per-scene results and summary tables.
    Evaluate(evaluate::Args),
    /// Render the reference's views of a scene (front, size, surroundings, top) as PNG files.
    Render(render::Args),
    /// Work with the vision-language model endpoint (check that it answers).
    #[command(subcommand)]
    Vlm(vlm::Command),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    init_logging(cli.verbose);
    let result = match cli.command {
        Command::Inspect(args) => inspect::run(args),
        Command::Relate(args) => relate::run(args),
        Command::Annotations(cmd) => annotations::run(cmd),
        Command::Evaluate(args) => evaluate::run(args),
        Command::Render(args) => render::run(args),
        Command::Vlm(cmd) => vlm::run(cmd),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err}");
            for cause in err.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::FAILURE
        }
    }
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
