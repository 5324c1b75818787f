//! `sceneeval relate` (being built).

use std::process::ExitCode;

/// Arguments of `sceneeval relate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`sceneeval relate` is not available yet")
}
