//! `sceneeval inspect` (being built).

use std::process::ExitCode;

/// Arguments of `sceneeval inspect`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`sceneeval inspect` is not available yet")
}
