//! `sceneeval vlm`: commands about the vision-language model endpoint.
//!
//! `sceneeval vlm check --base-url URL --model NAME` sends one small structured request with
//! an image (a red square, "what colour is it?") and says whether the endpoint works: it
//! answers, follows the JSON schema and sees the image. Exit status 0 when it does, 1 with the
//! reason when it does not (a refused key, an unreachable server, a refusal, an answer that
//! ignores the schema or the image).

use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, bail};
use sceneeval_vlm::check::{EndpointCheck, TEST_IMAGE_COLOUR};
use sceneeval_vlm::{Outcome, Session};
use sceneeval_vlm_openai::{ApiKey, DEFAULT_API_KEY_VAR, ImageDetail, OpenAiConfig, OpenAiVlm};

/// `sceneeval vlm` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Check that an OpenAI-compatible endpoint answers a structured request with an image.
    Check(CheckArgs),
}

/// Arguments of `sceneeval vlm check`.
#[derive(Debug, clap::Args)]
pub struct CheckArgs {
    /// The API base URL, e.g. https://api.openai.com/v1, http://localhost:8000/v1 (vLLM) or
    /// http://localhost:11434/v1 (Ollama).
    #[arg(long, value_name = "URL")]
    pub base_url: String,
    /// The model name, e.g. gpt-4o-2024-08-06 or Qwen/Qwen2.5-VL-7B-Instruct.
    #[arg(long, value_name = "NAME")]
    pub model: String,
    /// The environment variable holding the API key; it must then be set. Without this option
    /// OPENAI_API_KEY is used when set (local servers need no key).
    #[arg(long, value_name = "VAR")]
    pub api_key_env: Option<String>,
    /// Image detail: low (the reference's), high or auto.
    #[arg(long, default_value = "low", value_parser = parse_detail)]
    pub detail: ImageDetail,
    /// Seconds to wait for the answer (per attempt).
    #[arg(long, default_value_t = 60.0, value_name = "SECS")]
    pub timeout: f64,
    /// Retries after a failed attempt (429, 5xx, timeouts, connection errors).
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub retries: u32,
}

fn parse_detail(s: &str) -> Result<ImageDetail, String> {
    s.parse()
}

/// Runs a `sceneeval vlm` subcommand.
pub fn run(command: Command) -> anyhow::Result<ExitCode> {
    match command {
        Command::Check(args) => check(args),
    }
}

fn check(args: CheckArgs) -> anyhow::Result<ExitCode> {
    let key = match &args.api_key_env {
        Some(var) => Some(
            ApiKey::from_env(var)?
                .with_context(|| format!("environment variable {var} (--api-key-env) is not set or empty"))?,
        ),
        None => ApiKey::from_env(DEFAULT_API_KEY_VAR)?,
    };
    if !(args.timeout.is_finite() && args.timeout > 0.0) {
        bail!("--timeout must be a positive number of seconds");
    }
    let mut config = OpenAiConfig::new(&args.base_url, &args.model).with_api_key(key);
    config.detail = args.detail;
    config.timeout = Duration::from_secs_f64(args.timeout);
    config.retry.max_retries = args.retries;
    let vlm = OpenAiVlm::new(config).context("cannot set up the client")?;

    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")?;
    let session = Session::new(&vlm);
    let answers = runtime
        .block_on(session.ask(&EndpointCheck::new()))
        .with_context(|| {
            format!(
                "the endpoint check failed for model {:?} at {}",
                args.model,
                vlm.url()
            )
        })?;
    let usage = session.usage();
    let stats = vlm.stats();
    let summary = format!(
        "tokens: {} prompt, {} completion; {} HTTP request(s), {} retr{}",
        usage.tokens.prompt_tokens,
        usage.tokens.completion_tokens,
        stats.attempts,
        stats.retries,
        if stats.retries == 1 { "y" } else { "ies" }
    );
    match answers.into_single() {
        Some(Outcome::Answered { answer, attempt }) if answer.correct => {
            println!(
                "ok: {} answers model {:?} with structured output and sees images (it called the {TEST_IMAGE_COLOUR} square {:?}{}).",
                vlm.url(),
                args.model,
                answer.colour,
                if attempt > 1 {
                    ", after one invalid answer"
                } else {
                    ""
                }
            );
            println!("{summary}");
            Ok(ExitCode::SUCCESS)
        }
        Some(Outcome::Answered { answer, .. }) => {
            eprintln!(
                "failed: {} answered, but called the {TEST_IMAGE_COLOUR} square {:?}: the model does not seem to get \
                 the image (a text-only model, or a server that drops images).",
                vlm.url(),
                answer.colour
            );
            eprintln!("{summary}");
            Ok(ExitCode::FAILURE)
        }
        Some(Outcome::Unanswered(why)) => {
            eprintln!("failed: {} answered, but not usably: {why}", vlm.url());
            eprintln!("{summary}");
            Ok(ExitCode::FAILURE)
        }
        None => bail!("the endpoint check asked no question"),
    }
}
