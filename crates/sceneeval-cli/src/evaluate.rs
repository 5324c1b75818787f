//! `sceneeval evaluate` (being built).

use std::process::ExitCode;

/// Arguments of `sceneeval evaluate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs the subcommand.
pub fn run(_args: Args) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`sceneeval evaluate` is not available yet")
}
