//! `sceneeval vlm`: commands about the vision-language model endpoint.
//!
//! `sceneeval vlm check --vlm-base-url URL --vlm-model NAME` sends one small structured request with
//! an image (a red square, "what colour is it?") and says whether the endpoint works: it
//! answers, follows the JSON schema and sees the image. Exit status 0 when it does, 1 with the
//! reason when it does not (a refused key, an unreachable server, a refusal, an answer that
//! ignores the schema or the image).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, bail};
use sceneeval::vlm::check::CHECK_MAX_RETRIES;
use sceneeval::vlm::check::{EndpointCheck, TEST_IMAGE_COLOUR};
use sceneeval::vlm::{Outcome, Session};
use sceneeval::{
    DEFAULT_RENDER_SIZE, DEFAULT_VLM_CONCURRENCY, DEFAULT_VLM_MAX_RETRIES, DEFAULT_VLM_TIMEOUT_SECONDS,
    MAX_VLM_TIMEOUT_SECONDS, RENDER_SIZE_RANGE, VlmOptions,
};

use crate::evaluate::OptionError;
use sceneeval::vlm_openai::{OpenAiVlm, RuntimeVlm};

/// `sceneeval vlm` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Check that an OpenAI-compatible endpoint answers a structured request with an image.
    Check(CheckArgs),
}

/// Arguments of `sceneeval vlm check`: the endpoint options of every command that asks a VLM
/// ([`VlmEndpointArgs`], the base URL and model required here), and `--vlm-retries`.
#[derive(Debug, clap::Args)]
#[command(
    mut_arg("vlm_base_url", |a| a.required(true).alias("base-url")),
    mut_arg("vlm_model", |a| a.required(true).alias("model")),
    mut_arg("vlm_api_key_env", |a| a.alias("api-key-env")),
    mut_arg("vlm_timeout_s", |a| a.alias("timeout")),
)]
pub struct CheckArgs {
    /// The endpoint, the key's variable, what is sent and the timeout (the same options as
    /// `evaluate`'s).
    #[command(flatten)]
    pub endpoint: VlmEndpointArgs,
    /// Retries after a failed attempt (429, 5xx, timeouts, connection errors); default
    /// `CHECK_MAX_RETRIES`, as the check `evaluate` makes before its first scene.
    #[arg(
        long = "vlm-retries",
        alias = "retries",
        default_value_t = CHECK_MAX_RETRIES,
        value_name = "N",
        help = format!(
            "Retries after a failed attempt (429, 5xx, timeouts, connection errors), as the check `evaluate` makes before its first scene; a run's requests retry up to {DEFAULT_VLM_MAX_RETRIES} times."
        )
    )]
    pub retries: u32,
}

/// The options that name a VLM endpoint and what is sent to it, the same on every command that
/// asks a VLM (`evaluate`, `settle`, `annotations annotate`, `annotations generate`,
/// `vlm check`): written once here, each default from the facade's constants.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct VlmEndpointArgs {
    /// OpenAI-compatible API base URL of the VLM, e.g. https://api.openai.com/v1,
    /// http://localhost:8000/v1 (vLLM) or http://localhost:11434/v1 (Ollama). The key is read
    /// from OPENAI_API_KEY (or `--vlm-api-key-env`).
    #[arg(long, value_name = "URL", requires = "vlm_model")]
    pub vlm_base_url: Option<String>,
    /// The VLM's model name, e.g. gpt-4o-2024-08-06 or Qwen/Qwen2.5-VL-7B-Instruct.
    #[arg(long, value_name = "NAME", requires = "vlm_base_url")]
    pub vlm_model: Option<String>,
    /// The environment variable holding the VLM's API key; it must then be set. Without this
    /// option OPENAI_API_KEY is used when set (local servers need no key).
    #[arg(long, value_name = "VAR", requires = "vlm_base_url")]
    pub vlm_api_key_env: Option<String>,
    /// What is sent with every VLM request.
    #[command(flatten)]
    pub vlm_sampling: SamplingArgs,
    /// Seconds one VLM request (each attempt) may take (default:
    /// `sceneeval::DEFAULT_VLM_TIMEOUT_SECONDS`); in `evaluate` the scene's time budget bounds
    /// the whole wait for the VLM, retries included.
    #[arg(long = "vlm-timeout-s", alias = "vlm-timeout", value_name = "SECONDS", requires = "vlm_base_url", help = format!(
        "Seconds one VLM request (each attempt) may take (default {DEFAULT_VLM_TIMEOUT_SECONDS}, at most {MAX_VLM_TIMEOUT_SECONDS}); in `evaluate` and `settle` the time budget (--time-budget-s) bounds the whole wait for the VLM, retries included."
    ))]
    pub vlm_timeout_s: Option<f64>,
}

impl VlmEndpointArgs {
    /// The facade's VLM options these make (`None` without `--vlm-base-url`), every option
    /// they do not set at its default.
    ///
    /// # Errors
    /// A sampling option without `--vlm-base-url`.
    pub fn options(&self) -> anyhow::Result<Option<VlmOptions>> {
        match (&self.vlm_base_url, &self.vlm_model) {
            (Some(base_url), Some(model)) => Ok(Some(VlmOptions {
                api_key_env: self.vlm_api_key_env.clone(),
                timeout_s: self.vlm_timeout_s,
                ..self.vlm_sampling.options(base_url, model)
            })),
            _ => {
                if let Some(option) = self.vlm_sampling.first_given() {
                    bail!("{option} sets what is sent to the VLM; it needs --vlm-base-url and --vlm-model");
                }
                Ok(None)
            }
        }
    }
}

/// The VLM options of the commands that ask a model many times (`evaluate`, `settle`,
/// `annotations annotate`, `annotations generate`): the endpoint ([`VlmEndpointArgs`]) and the
/// client's limits and cache. Written once here; each command maps them onto the facade's
/// [`VlmOptions`].
#[derive(Debug, Clone, Default, clap::Args)]
pub struct VlmArgs {
    /// The endpoint, the key's variable, what is sent and the timeout.
    #[command(flatten)]
    pub endpoint: VlmEndpointArgs,
    /// VLM requests in flight at once over the whole run (default
    /// `sceneeval::DEFAULT_VLM_CONCURRENCY`), whatever the number of threads.
    #[arg(long, value_name = "N", requires = "vlm_base_url", help = format!(
        "VLM requests in flight at once over the whole run (default {DEFAULT_VLM_CONCURRENCY}), whatever the number of threads: scenes waiting for the VLM leave the CPU to others. Halved when the server answers 429 (too many requests), grown back after successes."
    ))]
    pub vlm_concurrency: Option<usize>,
    /// Cap on VLM requests per minute (default none): requests are spaced 60 s / N apart.
    #[arg(long, value_name = "N", requires = "vlm_base_url")]
    pub vlm_rpm: Option<u32>,
    /// Cap on VLM tokens per minute (default none): requests are spaced by an estimate of
    /// their tokens (text at 4 characters per token, images by OpenAI's rule for the detail).
    #[arg(long, value_name = "N", requires = "vlm_base_url")]
    pub vlm_tpm: Option<u64>,
    /// Folder of the VLM response cache: a re-run asks nothing already answered. `evaluate`:
    /// default `<out>/vlm-cache`; `annotations`: no cache unless given.
    #[arg(long, value_name = "DIR", requires = "vlm_base_url")]
    pub vlm_cache: Option<PathBuf>,
}

impl VlmArgs {
    /// The facade's VLM options these make (`None` without `--vlm-base-url`).
    ///
    /// # Errors
    /// A sampling option without `--vlm-base-url`.
    pub fn options(&self) -> anyhow::Result<Option<VlmOptions>> {
        Ok(self.endpoint.options()?.map(|options| VlmOptions {
            cache: self.vlm_cache.clone(),
            concurrency: self.vlm_concurrency,
            rpm: self.vlm_rpm,
            tpm: self.vlm_tpm,
            ..options
        }))
    }
}

/// The sampling settings sent with every VLM request, as options of `evaluate` and
/// `vlm check`; an option not given keeps the client's default. Values are checked by the
/// facade ([`VlmOptions::config`]), which both commands go through.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SamplingArgs {
    /// Image detail: low (default, the reference's), high or auto.
    #[arg(long = "vlm-detail", alias = "detail", value_name = "low|high|auto")]
    pub detail: Option<String>,
    /// Sampling temperature from 0 to 2 (default 0), or `none` to send none: OpenAI's
    /// reasoning models (o-series, GPT-5) accept only their own.
    #[arg(long = "vlm-temperature", value_name = "T|none", value_parser = parse_temperature)]
    pub temperature: Option<Sent<f32>>,
    /// Sampling seed (default 42, the reference's), or `none` to send none.
    #[arg(long = "vlm-seed", value_name = "N|none", value_parser = parse_seed)]
    pub seed: Option<Sent<u64>>,
    /// Token limit of a reply (default: none sent, the server's own); a reply cut off there
    /// is recorded as truncated.
    #[arg(long = "vlm-max-tokens", value_name = "N")]
    pub max_tokens: Option<u32>,
    /// The request field of the token limit: max_tokens (default, every OpenAI-compatible
    /// server) or max_completion_tokens (OpenAI's o-series and GPT-5 refuse max_tokens).
    #[arg(
        long = "vlm-token-limit-field",
        value_name = "max_tokens|max_completion_tokens"
    )]
    pub token_limit_field: Option<String>,
}

/// The help of a `--render-size` option of the VLM's object views: its default
/// ([`DEFAULT_RENDER_SIZE`], written once) and range.
pub fn render_size_help() -> String {
    format!(
        "Side of the square object views shown to the VLM, pixels (default {DEFAULT_RENDER_SIZE}; {} to {}).",
        RENDER_SIZE_RANGE.start(),
        RENDER_SIZE_RANGE.end()
    )
}

/// A setting given on the command line: a value, or `none` for "send none".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sent<T>(pub Option<T>);

impl SamplingArgs {
    /// The first option given, if any (`--vlm-detail`, ...).
    pub fn first_given(&self) -> Option<&'static str> {
        [
            (self.detail.is_some(), "--vlm-detail"),
            (self.temperature.is_some(), "--vlm-temperature"),
            (self.seed.is_some(), "--vlm-seed"),
            (self.max_tokens.is_some(), "--vlm-max-tokens"),
            (self.token_limit_field.is_some(), "--vlm-token-limit-field"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name))
    }

    /// The VLM at `base_url` serving `model` with these settings, every other option at its
    /// default.
    pub fn options(&self, base_url: &str, model: &str) -> VlmOptions {
        VlmOptions {
            base_url: base_url.to_owned(),
            model: model.to_owned(),
            api_key_env: None,
            cache: None,
            concurrency: None,
            render_size: None,
            detail: self.detail.clone(),
            temperature: self.temperature.map(|Sent(t)| t),
            seed: self.seed.map(|Sent(s)| s),
            max_tokens: self.max_tokens,
            token_limit_field: self.token_limit_field.clone(),
            timeout_s: None,
            rpm: None,
            tpm: None,
        }
    }
}

/// `none`, or what `value` makes of the text.
fn sent<T>(s: &str, value: impl FnOnce(&str) -> Result<T, String>) -> Result<Sent<T>, String> {
    if s.trim().eq_ignore_ascii_case("none") {
        Ok(Sent(None))
    } else {
        value(s.trim()).map(|v| Sent(Some(v)))
    }
}

fn parse_temperature(s: &str) -> Result<Sent<f32>, String> {
    sent(s, |t| {
        t.parse::<f32>()
            .map_err(|_| format!("{t:?} is not a temperature (a number from 0 to 2) or \"none\""))
    })
}

fn parse_seed(s: &str) -> Result<Sent<u64>, String> {
    sent(s, |t| {
        t.parse::<u64>()
            .map_err(|_| format!("{t:?} is not a seed (a whole number from 0) or \"none\""))
    })
}

/// Runs a `sceneeval vlm` subcommand.
pub fn run(command: Command) -> anyhow::Result<ExitCode> {
    match command {
        Command::Check(args) => check(args),
    }
}

fn check(args: CheckArgs) -> anyhow::Result<ExitCode> {
    let Some(options) = args.endpoint.options()? else {
        bail!("vlm check needs --vlm-base-url and --vlm-model");
    };
    let model = options.model.clone();
    let mut config = options
        .config()
        .map_err(|error| OptionError::new(error, crate::evaluate::option_name))?;
    config.retry.max_retries = args.retries;
    let vlm = RuntimeVlm::start(OpenAiVlm::new(config).context("cannot set up the client")?)?;
    let session = Session::new(&vlm);
    let answers = pollster::block_on(session.ask(&EndpointCheck::new())).with_context(|| {
        format!(
            "the endpoint check failed for model {:?} at {}",
            model,
            vlm.inner().url()
        )
    })?;
    let usage = session.usage();
    let stats = vlm.inner().stats();
    let summary = format!(
        "tokens: {} prompt, {} completion; {} HTTP request(s), {} retr{}",
        usage.tokens.prompt_tokens,
        usage.tokens.completion_tokens,
        stats.attempts,
        stats.retries,
        if stats.retries == 1 { "y" } else { "ies" }
    );
    match answers.into_single() {
        Some(Outcome::Answered { answer, attempt, .. }) if answer.correct => {
            crate::print_stdout(&format!(
                "ok: {} answers model {:?} with structured output and sees images (it called the {TEST_IMAGE_COLOUR} square {:?}{}).\n",
                vlm.inner().url(),
                model,
                answer.colour,
                if attempt > 1 {
                    ", after one invalid answer"
                } else {
                    ""
                }
            ))?;
            crate::print_stdout(&format!("{summary}\n"))?;
            Ok(ExitCode::SUCCESS)
        }
        Some(Outcome::Answered { answer, .. }) => {
            eprintln!(
                "failed: {} answered, but called the {TEST_IMAGE_COLOUR} square {:?}: the model does not seem to get \
                 the image (a text-only model, or a server that drops images).",
                vlm.inner().url(),
                answer.colour
            );
            eprintln!("{summary}");
            Ok(ExitCode::FAILURE)
        }
        Some(Outcome::Unanswered(why)) => {
            eprintln!("failed: {} answered, but not usably: {why}", vlm.inner().url());
            eprintln!("{summary}");
            Ok(ExitCode::FAILURE)
        }
        None => bail!("the endpoint check asked no question"),
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    /// The argument `id` of the subcommand at `path`.
    fn arg(path: &[&str], id: &str) -> clap::Arg {
        let mut command = crate::Cli::command();
        for name in path {
            command = command
                .find_subcommand(name)
                .unwrap_or_else(|| panic!("no subcommand {name}"))
                .clone();
        }
        command
            .get_arguments()
            .find(|a| a.get_id() == id)
            .unwrap_or_else(|| panic!("{path:?} has no argument {id}"))
            .clone()
    }

    fn help(path: &[&str], id: &str) -> String {
        arg(path, id)
            .get_help()
            .map(ToString::to_string)
            .unwrap_or_default()
    }

    fn default(path: &[&str], id: &str) -> Vec<String> {
        arg(path, id)
            .get_default_values()
            .iter()
            .map(|v| v.to_string_lossy().into_owned())
            .collect()
    }

    #[test]
    fn the_documented_defaults_are_the_constants() {
        let timeout = format!("(default {DEFAULT_VLM_TIMEOUT_SECONDS}, at most {MAX_VLM_TIMEOUT_SECONDS})");
        let size = format!("(default {DEFAULT_RENDER_SIZE}; 16 to 4096)");
        for command in [
            &["evaluate"][..],
            &["settle"],
            &["annotations", "annotate"],
            &["annotations", "generate"],
        ] {
            assert!(help(command, "vlm_timeout_s").contains(&timeout), "{command:?}");
            assert!(
                help(command, "vlm_concurrency").contains(&format!("(default {DEFAULT_VLM_CONCURRENCY})")),
                "{command:?}"
            );
        }
        for command in ["evaluate", "settle"] {
            assert!(help(&[command], "render_size").contains(&size), "{command}");
        }
        assert!(help(&["vlm", "check"], "vlm_timeout_s").contains(&timeout));
        assert_eq!(
            default(&["vlm", "check"], "retries"),
            [CHECK_MAX_RETRIES.to_string()]
        );
        assert!(
            help(&["vlm", "check"], "retries").contains(&format!("up to {DEFAULT_VLM_MAX_RETRIES} times"))
        );
        assert_eq!(
            default(&["render"], "render_size"),
            [DEFAULT_RENDER_SIZE.to_string()]
        );
        // One value each: the client's defaults are the evaluator's.
        let client = sceneeval::vlm_openai::OpenAiConfig::new("http://127.0.0.1:1/v1", "m");
        assert_eq!(client.timeout.as_secs_f64(), DEFAULT_VLM_TIMEOUT_SECONDS);
        assert_eq!(client.retry.max_retries, DEFAULT_VLM_MAX_RETRIES);
        assert_eq!(client.max_concurrent_requests, DEFAULT_VLM_CONCURRENCY);
        assert_eq!(
            sceneeval::render::RenderSettings::DEFAULT_SIZE,
            DEFAULT_RENDER_SIZE
        );
    }
}
