//! `sceneeval annotations` (being built).

use std::process::ExitCode;

/// Subcommands of `sceneeval annotations`.
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Validate an annotation file.
    Check {},
}

/// Runs the subcommand.
pub fn run(_cmd: Command) -> anyhow::Result<ExitCode> {
    anyhow::bail!("`sceneeval annotations` is not available yet")
}
