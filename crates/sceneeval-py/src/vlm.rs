//! The `vlm=` argument of `sceneeval.evaluate`: an OpenAI-compatible endpoint for the
//! text-fidelity metrics, configured as `sceneeval evaluate --vlm-*` configures it.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::{Deserialize, Deserializer};

use sceneeval::render::{RenderSettings, Renderer};
use sceneeval::vlm::Cached;
use sceneeval::vlm_openai::{ApiKey, OpenAiConfig, OpenAiError, OpenAiVlm, RuntimeVlm};
use sceneeval::{Evaluator, SharedVlm};

use crate::convert::to_json;
use crate::errors::{chain, scene_error, value_error};

/// The keys of a `vlm` dict other than `cache` (read as a path), with the CLI's defaults.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct VlmOptions {
    /// `--vlm-base-url`.
    base_url: String,
    /// `--vlm-model`.
    model: String,
    /// `--vlm-api-key-env`.
    #[serde(default)]
    api_key_env: Option<String>,
    /// `--vlm-concurrency`.
    #[serde(default = "default_concurrency")]
    concurrency: usize,
    /// `--render-size`.
    #[serde(default = "default_render_size")]
    render_size: u32,
    /// `--vlm-detail`.
    #[serde(default)]
    detail: Option<String>,
    /// `--vlm-temperature`: absent keeps the default, `None` sends none.
    #[serde(default, deserialize_with = "present")]
    temperature: Option<Option<f32>>,
    /// `--vlm-seed`: absent keeps the default, `None` sends none.
    #[serde(default, deserialize_with = "present")]
    seed: Option<Option<u64>>,
    /// `--vlm-max-tokens`.
    #[serde(default)]
    max_tokens: Option<u32>,
    /// `--vlm-token-limit-field`.
    #[serde(default)]
    token_limit_field: Option<String>,
}

fn default_concurrency() -> usize {
    4
}

fn default_render_size() -> u32 {
    512
}

/// A key that is present, `null` included (`Some(None)`); an absent key is `None` through
/// `#[serde(default)]`.
fn present<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<Option<T>>, D::Error> {
    Option::<T>::deserialize(d).map(Some)
}

/// `evaluator` with the VLM `vlm` describes (answers cached in its `cache` folder, default
/// `out/vlm-cache`) and the renderer of its object views.
///
/// # Errors
/// `ValueError` for a bad dict (unknown key, missing `base_url` or `model`, a value out of
/// range, an unset key variable); `SceneEvalError` when the client, its runtime or the
/// renderer cannot start.
pub fn with_vlm(evaluator: Evaluator, vlm: &Bound<'_, PyDict>, out: &Path) -> PyResult<Evaluator> {
    let rest = vlm.copy()?;
    let cache: PathBuf = match rest.get_item("cache")? {
        Some(c) if !c.is_none() => c
            .extract()
            .map_err(|_| value_error("vlm[\"cache\"] must be a path (str or os.PathLike)"))?,
        _ => out.join("vlm-cache"),
    };
    if rest.contains("cache")? {
        rest.del_item("cache")?;
    }
    let options: VlmOptions = serde_json::from_value(to_json(rest.as_any(), "vlm")?)
        .map_err(|e| value_error(format!("vlm: {e}")))?;
    let key = ApiKey::from_env_or_default(options.api_key_env.as_deref()).map_err(|e| client_error(&e))?;
    let mut config = OpenAiConfig::new(&options.base_url, &options.model).with_api_key(key);
    config.max_concurrent_requests = options.concurrency.max(1);
    if let Some(detail) = &options.detail {
        config.detail = detail
            .parse()
            .map_err(|e| value_error(format!("vlm[\"detail\"]: {e}")))?;
    }
    if let Some(t) = options.temperature {
        config.temperature = t;
    }
    if let Some(seed) = options.seed {
        config.seed = seed;
    }
    if options.max_tokens.is_some() {
        config.max_tokens = options.max_tokens;
    }
    if let Some(field) = &options.token_limit_field {
        config.token_limit_field = field
            .parse()
            .map_err(|e| value_error(format!("vlm[\"token_limit_field\"]: {e}")))?;
    }
    let client = OpenAiVlm::new(config).map_err(|e| client_error(&e))?;
    let client = RuntimeVlm::start(client).map_err(|e| client_error(&e))?;
    let renderer = Renderer::new().map_err(|e| {
        crate::errors::SceneEvalError::new_err(format!(
            "the VLM needs object views, but the renderer cannot start: {}",
            chain(&e)
        ))
    })?;
    Ok(evaluator
        .with_vlm(SharedVlm::new(Cached::new(client, cache)))
        .with_renderer(renderer, RenderSettings::square(options.render_size.max(16))))
}

/// A client that cannot be set up: the caller's settings (`ValueError`) or the machine
/// (`SceneEvalError`).
fn client_error(e: &OpenAiError) -> PyErr {
    match e {
        OpenAiError::InvalidBaseUrl { .. }
        | OpenAiError::InvalidSetting { .. }
        | OpenAiError::ApiKeyVariable { .. } => value_error(format!("vlm: {}", chain(e))),
        other => scene_error(other),
    }
}
