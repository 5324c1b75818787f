//! `sceneeval.evaluate` and `sceneeval.evaluation_request`: the keyword arguments mapped onto
//! the facade's [`EvaluationRequest`], as `sceneeval evaluate` maps its flags, then run by it.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sceneeval::{
    EvalError, EvaluationRequest, Metric, PlanRequest, Preset, RequestField, RunError, VlmOptions,
};
use serde::Serialize;

use crate::convert::{to_json, to_python};
use crate::errors::{SceneEvalError, chain, deprecation_warning, detached, user_warning, value_error};

/// The keyword of `sceneeval.evaluate` that sets `field`: the request's own name for it
/// ([`RequestField::path`], the one table), `vlm["key"]` for a key of the `vlm=` dict.
pub fn keyword(field: RequestField) -> Cow<'static, str> {
    let path = field.path();
    match path.strip_prefix("vlm.") {
        Some(key) => Cow::Owned(format!("vlm[\"{key}\"]")),
        None => Cow::Borrowed(path),
    }
}

/// The keyword arguments of earlier versions of `evaluate` and `evaluation_request`, with the
/// field whose request name ([`keyword`]) replaced each. They still work, with a
/// `DeprecationWarning` naming the new keyword.
pub const RENAMED: [(&str, RequestField); 3] = [
    ("scenes_dir", RequestField::Scenes),
    ("time_budget", RequestField::TimeBudget),
    ("time_budget_seconds", RequestField::TimeBudget),
];

/// The keys of the `vlm=` dict of earlier versions, with the field whose request name replaced
/// each. They still work, with a `DeprecationWarning` naming the new key.
pub const RENAMED_VLM_KEYS: [(&str, RequestField); 1] = [("timeout", RequestField::VlmTimeout)];

/// The values of the renamed keywords in `kwargs` (the `**kwargs` of `function`), each with a
/// `DeprecationWarning` naming its new keyword.
///
/// # Errors
/// `TypeError` for a keyword that is neither a parameter nor a renamed one, as Python raises
/// it for any function.
fn renamed<'py>(
    py: Python<'py>,
    function: &str,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Vec<(RequestField, String, Bound<'py, PyAny>)>> {
    let Some(kwargs) = kwargs else {
        return Ok(Vec::new());
    };
    let mut values = Vec::new();
    for (key, value) in kwargs.iter() {
        let key: String = key.extract()?;
        let Some(&(_, field)) = RENAMED.iter().find(|(old, _)| *old == key) else {
            return Err(PyTypeError::new_err(format!(
                "{function}() got an unexpected keyword argument '{key}'"
            )));
        };
        deprecation_warning(
            py,
            &format!(
                "{key}= is deprecated: pass {}= (the request's name, as `sceneeval evaluate --print-request` shows it)",
                keyword(field)
            ),
            1,
        )?;
        values.push((field, key, value));
    }
    Ok(values)
}

/// `given` (the argument under its request name) or the value of its old name in `old`; a
/// `TypeError` when both, or two old names of it, are given.
fn given_or_renamed<'py, T: FromPyObjectOwned<'py>>(
    function: &str,
    field: RequestField,
    given: Option<T>,
    old: &[(RequestField, String, Bound<'py, PyAny>)],
) -> PyResult<Option<T>> {
    let mut olds = old.iter().filter(|(f, _, _)| *f == field);
    let Some((_, name, value)) = olds.next() else {
        return Ok(given);
    };
    if given.is_some() {
        return Err(PyTypeError::new_err(format!(
            "{function}() got {}= and its old name {name}=: give {0}= only",
            keyword(field)
        )));
    }
    if let Some((_, other, _)) = olds.next() {
        return Err(PyTypeError::new_err(format!(
            "{function}() got {name}= and {other}=, two old names of {}=: give {0}= only",
            keyword(field)
        )));
    }
    if value.is_none() {
        return Ok(None);
    }
    value.extract::<T>().map(Some).map_err(|e| {
        let e: PyErr = e.into();
        PyTypeError::new_err(format!("{}: {e}", keyword(field)))
    })
}

/// A facade error as a Python exception: a request error names the keyword (`plan: ...`) and
/// is a `ValueError` (the caller's argument), except what the machine or its files refuse (a
/// scene folder or annotation file that cannot be read, a VLM client or renderer that cannot
/// start), which is a `SceneEvalError`; anything else as `eval_error`.
pub fn request_error(e: &EvalError) -> PyErr {
    let EvalError::Request {
        field,
        message,
        source,
    } = e
    else {
        return crate::errors::eval_error(e);
    };
    let mut text = format!("{}: {message}", keyword(*field));
    if let Some(cause) = source {
        let cause = chain(cause.as_ref());
        if !text.contains(&cause) {
            text.push_str(": ");
            text.push_str(&cause);
        }
    }
    let machine = matches!(field, RequestField::Scenes | RequestField::Vlm)
        || (*field == RequestField::Annotations && source.is_some());
    if machine {
        SceneEvalError::new_err(text)
    } else {
        value_error(text)
    }
}

/// A run's error as a Python exception: its request and evaluation errors as
/// [`request_error`] raises them, anything else (the scene folder, the output folder, a result
/// file) a `SceneEvalError`.
pub fn run_error(e: &RunError) -> PyErr {
    match e {
        RunError::Eval(e) => request_error(e),
        other => crate::errors::scene_error(other),
    }
}

/// `plan` and `preset` as given, except that a preset name given as the plan (`plan="reference"`,
/// which earlier versions of the package documented) is read as that preset with the default
/// plan, with a `DeprecationWarning`, unless a file of that name exists.
pub fn plan_and_preset(
    py: Python<'_>,
    plan: Option<&str>,
    preset: Option<&str>,
) -> PyResult<(Option<String>, Option<Preset>)> {
    let given = preset
        .map(|p| Preset::from_str(p).map_err(|e| value_error(format!("preset: {}", chain(&e)))))
        .transpose()?;
    if let Some(name) = plan
        && !Path::new(name).exists()
        && let Ok(as_preset) = Preset::from_str(name)
    {
        if given.is_some_and(|p| p != as_preset) {
            return Err(value_error(format!(
                "plan={name:?} names a preset, and preset={:?} another: give the preset once, as preset=",
                preset.unwrap_or_default()
            )));
        }
        deprecation_warning(
            py,
            &format!(
                "plan={name:?} is a preset name: pass preset={name:?} (plan= takes geometry, full, a metric list or a plan file)"
            ),
            2,
        )?;
        return Ok((None, Some(as_preset)));
    }
    Ok((plan.map(str::to_owned), given))
}

/// Metrics by name (or summary column).
pub fn metrics_of(metrics: Option<Vec<String>>) -> PyResult<Option<Vec<Metric>>> {
    metrics
        .map(|names| {
            names
                .iter()
                .map(|n| {
                    n.parse::<Metric>()
                        .map_err(|e| value_error(format!("metrics: {e}")))
                })
                .collect::<PyResult<Vec<Metric>>>()
        })
        .transpose()
}

/// `{prefix: folder}` as the request's `PREFIX=DIR` asset specifications (a folder may be
/// written `LAYOUT:folder`), in prefix order.
pub fn asset_specs(assets: Option<BTreeMap<String, PathBuf>>) -> Vec<String> {
    assets
        .unwrap_or_default()
        .into_iter()
        .map(|(prefix, dir)| format!("{prefix}={}", dir.display()))
        .collect()
}

/// The `vlm=` dict as the request's VLM options: the keys are the fields of
/// [`VlmOptions`] (unknown keys are refused); `cache` may be any path-like. A key of earlier
/// versions ([`RENAMED_VLM_KEYS`]) is read as its new one, with a `DeprecationWarning`.
pub(crate) fn vlm_options(vlm: &Bound<'_, PyDict>) -> PyResult<VlmOptions> {
    let rest = vlm.copy()?;
    for (old, field) in RENAMED_VLM_KEYS {
        let Some(value) = rest.get_item(old)? else {
            continue;
        };
        let new = field.path().strip_prefix("vlm.").unwrap_or(field.path());
        if rest.contains(new)? {
            return Err(PyTypeError::new_err(format!(
                "vlm has \"{new}\" and its old name \"{old}\": give \"{new}\" only"
            )));
        }
        deprecation_warning(
            vlm.py(),
            &format!(
                "vlm[\"{old}\"] is deprecated: use {} (the request's name, as `sceneeval evaluate --print-request` shows it)",
                keyword(field)
            ),
            1,
        )?;
        rest.del_item(old)?;
        rest.set_item(new, value)?;
    }
    let cache: Option<PathBuf> = match rest.get_item("cache")? {
        Some(c) if !c.is_none() => Some(
            c.extract()
                .map_err(|_| value_error("vlm[\"cache\"] must be a path (str or os.PathLike)"))?,
        ),
        _ => None,
    };
    if rest.contains("cache")? {
        rest.del_item("cache")?;
    }
    let mut options: VlmOptions = serde_json::from_value(to_json(rest.as_any(), "vlm")?)
        .map_err(|e| value_error(format!("vlm: {e}")))?;
    options.cache = cache;
    Ok(options)
}

/// The request `function` (`evaluate` or `evaluation_request`) makes of its arguments (see
/// `evaluate`), the renamed keywords in `old` included.
#[allow(clippy::too_many_arguments)] // The keyword arguments of `sceneeval.evaluate`.
fn request(
    py: Python<'_>,
    function: &str,
    scenes: Option<PathBuf>,
    assets: Option<BTreeMap<String, PathBuf>>,
    out: PathBuf,
    annotations: Option<PathBuf>,
    plan: Option<&str>,
    preset: Option<&str>,
    metrics: Option<Vec<String>>,
    matching: Option<PathBuf>,
    relation_mapping: Option<&str>,
    time_budget_s: Option<f64>,
    vlm: Option<&Bound<'_, PyDict>>,
    force: bool,
    threads: Option<usize>,
    strict: bool,
    old: Option<&Bound<'_, PyDict>>,
) -> PyResult<EvaluationRequest> {
    let old = renamed(py, function, old)?;
    let scenes = given_or_renamed(function, RequestField::Scenes, scenes, &old)?
        .ok_or_else(|| PyTypeError::new_err(format!("{function}() missing 1 required argument: 'scenes'")))?;
    let time_budget_s = given_or_renamed(function, RequestField::TimeBudget, time_budget_s, &old)?;
    let matching = matching
        .map(|m| {
            m.into_os_string()
                .into_string()
                .map_err(|m| value_error(format!("matching {m:?} is not valid Unicode")))
        })
        .transpose()?;
    let (plan, preset) = plan_and_preset(py, plan, preset)?;
    Ok(EvaluationRequest {
        scenes,
        assets: asset_specs(assets),
        out,
        annotations,
        plan: PlanRequest {
            plan,
            preset,
            metrics: metrics_of(metrics)?,
            time_budget_s,
            matching,
            relation_mapping: relation_mapping.map(str::to_owned),
        },
        vlm: vlm.map(vlm_options).transpose()?,
        threads,
        force,
        shard: None,
        diagnostics: false,
        strict,
    })
}

/// The evaluation request evaluate() makes of the same arguments, as a dict: what
/// `sceneeval evaluate --print-request` prints for the same options. Nothing is read or run.
/// dry_run is accepted as evaluate() takes it; it is not part of the request.
#[pyfunction]
#[pyo3(signature = (scenes=None, *, assets, out, annotations=None, plan=None, preset=None, metrics=None, matching=None, relation_mapping=None, time_budget_s=None, vlm=None, force=false, threads=None, strict=false, dry_run=false, **renamed))]
#[allow(clippy::too_many_arguments)] // The keyword arguments of `sceneeval.evaluate`.
pub fn evaluation_request<'py>(
    py: Python<'py>,
    scenes: Option<PathBuf>,
    assets: Option<BTreeMap<String, PathBuf>>,
    out: PathBuf,
    annotations: Option<PathBuf>,
    plan: Option<&str>,
    preset: Option<&str>,
    metrics: Option<Vec<String>>,
    matching: Option<PathBuf>,
    relation_mapping: Option<&str>,
    time_budget_s: Option<f64>,
    vlm: Option<Bound<'py, PyDict>>,
    force: bool,
    threads: Option<usize>,
    strict: bool,
    dry_run: bool,
    renamed: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let _ = dry_run;
    let request = request(
        py,
        "evaluation_request",
        scenes,
        assets,
        out,
        annotations,
        plan,
        preset,
        metrics,
        matching,
        relation_mapping,
        time_budget_s,
        vlm.as_ref(),
        force,
        threads,
        strict,
        renamed.as_ref(),
    )?;
    to_python(py, &request)
}

/// What `evaluate(dry_run=True)` returns.
#[derive(Debug, Serialize)]
struct DryRunReport {
    #[serde(flatten)]
    run: sceneeval::DryRun,
    total: sceneeval::TaskCost,
}

/// What `evaluate` returns: the summary and what happened to each scene.
#[derive(Debug, Serialize)]
struct RunReport {
    out: PathBuf,
    scenes: usize,
    evaluated: usize,
    reused: usize,
    failed: usize,
    partial: usize,
    skipped: Vec<Skipped>,
    failures: Vec<Failure>,
    incomplete: Vec<Incomplete>,
    note: Option<String>,
    summary: sceneeval::Summary,
}

#[derive(Debug, Serialize)]
struct Skipped {
    path: PathBuf,
    reason: String,
}

#[derive(Debug, Serialize)]
struct Failure {
    scene: String,
    error: String,
    causes: Vec<String>,
}

/// A metric a partial scene could not compute.
#[derive(Debug, Serialize)]
struct Incomplete {
    scene: String,
    metric: &'static str,
    vlm: bool,
    error: String,
    causes: Vec<String>,
}

/// Evaluates every `scene_<ID>.json` of the folder scenes as `sceneeval evaluate` does, writing the same files into out: `<scene>/eval.json` and `<scene>/timing.json` as each scene finishes, then summary.csv and summary.md.
///
/// assets: as for load_scene. annotations: a SceneEval-500 annotation CSV (or JSON): the rows
/// the text-fidelity metrics check, and rows per difficulty in the summary. plan: exactly what
/// `sceneeval evaluate --plan` accepts: "geometry" (the default: the six geometry metrics),
/// "full" (the paper's ten metrics, adding cnt, atr, oor, oar, which need annotations), a
/// comma-separated metric list ("collision,cnt,oor") or the path of a plan file (JSON or
/// TOML). preset: "default" or "reference" (every reference-parity switch), as --preset:
/// the parameters start from it (it replaces a plan file's preset; a preset name given as
/// plan=, the spelling of earlier versions, is read as preset= with a DeprecationWarning).
/// metrics: run only these metrics (names or summary columns, e.g. "collision", "OOB", "cnt"),
/// as --metrics. matching: "vlm", "labels" or a matching file or folder in
/// the reference's obj_matching_result.json shape (`<folder>/<scene>/obj_matching_result.json`),
/// as --matching; relation_mapping: "vlm" or "lexicon", as --relation-mapping. time_budget_s:
/// seconds per scene, as --time-budget-s (a scene over it is recorded as failed; 0: no budget).
/// vlm: the OpenAI-compatible endpoint the text-fidelity metrics ask, as the --vlm-* options: a
/// dict with base_url and model (required), api_key_env (the variable holding the key, which
/// must then be set; default OPENAI_API_KEY when set), cache (default out/vlm-cache),
/// concurrency (4: requests in flight over the whole run, whatever the threads; halved on a 429
/// and grown back), render_size (512, the object views shown), detail ("low"), temperature (0;
/// None sends none, as OpenAI's reasoning models need), seed (42; None sends none), max_tokens,
/// token_limit_field ("max_tokens" or "max_completion_tokens"), timeout_s (60: seconds per
/// request attempt; time_budget_s bounds a scene's whole wait for the VLM), rpm and tpm (caps on
/// requests and estimated tokens per minute; none by default). The dict is checked whatever the
/// plan; VLM settings a plan without text-fidelity metrics does not use are reported with a
/// UserWarning. Before the first scene evaluated, one small request checks the endpoint: an
/// unreachable server or a refused key raises SceneEvalError at once. Without a VLM the
/// text-fidelity metrics match objects by labels (or a matching file) and map relations with the
/// lexicon (ATR is not judged), as the CLI does without one, and say so with a UserWarning and
/// the run's note. A re-run into the same out reuses a scene's result while nothing it depends
/// on changed (force=True evaluates every scene again). threads: worker threads (default one
/// per core). strict=True fails each scene file that has keys the sceneState format does not
/// have (a misspelt key is read as absent), as --strict; by default each is a warning. dry_run=True evaluates nothing, writes nothing and sends nothing: it returns what
/// the run would ask the VLM (see below). Runs with the GIL released.
///
/// With dry_run=True, returns scenes, evaluated (scenes the run would evaluate), reused,
/// attributes_estimated (scenes whose attribute requests are estimated: one per ObjAttr entry,
/// as their matching is not cached), failed ([scene, why] pairs), vlm (whether a VLM would be
/// asked), tasks (per task: task, requests, cached, estimated, prompt_tokens: the estimated
/// input tokens of the requests to send) and total (the same, summed), as
/// `sceneeval evaluate --dry-run` prints them. Otherwise returns the run: out, scenes, evaluated, reused, failed, partial (scenes
/// with status partial: some metrics could not be computed, the others kept), skipped (files
/// that look like scenes but are not `scene_<ID>.json`), failures (scene, error, causes),
/// incomplete (scene, metric, vlm: whether a VLM request failed, error, causes: each metric a
/// partial scene could not compute), note (what the text-fidelity metrics ran with instead of
/// a VLM, or None) and summary (the table of summary.csv as a dict). A scene that fails is
/// recorded, not raised.
/// Raises SceneEvalError when the folder, the annotations or the output cannot be used, and
/// ValueError for a bad plan, preset, metric, assets mapping or vlm dict; the message starts
/// with the keyword at fault (`plan: ...`, `vlm["detail"]: ...`). The keywords are the
/// request's names (`sceneeval evaluate --print-request`); scenes_dir, time_budget and
/// time_budget_seconds, and vlm["timeout"], their names in earlier versions, still work with a
/// DeprecationWarning.
#[pyfunction]
#[pyo3(signature = (scenes=None, *, assets, out, annotations=None, plan=None, preset=None, metrics=None, matching=None, relation_mapping=None, time_budget_s=None, vlm=None, force=false, threads=None, strict=false, dry_run=false, **renamed))]
#[allow(clippy::too_many_arguments)] // The keyword arguments of `sceneeval.evaluate`.
pub fn evaluate<'py>(
    py: Python<'py>,
    scenes: Option<PathBuf>,
    assets: Option<BTreeMap<String, PathBuf>>,
    out: PathBuf,
    annotations: Option<PathBuf>,
    plan: Option<&str>,
    preset: Option<&str>,
    metrics: Option<Vec<String>>,
    matching: Option<PathBuf>,
    relation_mapping: Option<&str>,
    time_budget_s: Option<f64>,
    vlm: Option<Bound<'py, PyDict>>,
    force: bool,
    threads: Option<usize>,
    strict: bool,
    dry_run: bool,
    renamed: Option<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let request = request(
        py,
        "evaluate",
        scenes,
        assets,
        out,
        annotations,
        plan,
        preset,
        metrics,
        matching,
        relation_mapping,
        time_budget_s,
        vlm.as_ref(),
        force,
        threads,
        strict,
        renamed.as_ref(),
    )?;
    let prepared = detached(py, || request.prepare().map_err(|e| run_error(&e)))?;
    for warning in prepared.warnings() {
        user_warning(py, warning)?;
    }
    if dry_run {
        let dry = detached(py, || Ok::<_, PyErr>(prepared.dry_run()))?;
        return to_python(
            py,
            &DryRunReport {
                total: dry.total(),
                run: dry,
            },
        );
    }
    let note = prepared
        .fallback()
        .map(|f| format!("no VLM configured (the Python package runs without one): {f}"));
    if let Some(note) = &note {
        user_warning(py, note)?;
    }
    let outcome = detached(py, || prepared.run(&|_| {}).map_err(|e| run_error(&e)))?;
    let failures = outcome
        .batch
        .records
        .iter()
        .filter_map(|r| match &r.outcome {
            sceneeval::Outcome::Failed { error, causes, .. } => Some(Failure {
                scene: r.scene.to_string(),
                error: error.clone(),
                causes: causes.clone(),
            }),
            _ => None,
        })
        .collect();
    let incomplete = outcome
        .batch
        .records
        .iter()
        .filter_map(|r| match &r.outcome {
            sceneeval::Outcome::Partial { report } => Some((r, report)),
            _ => None,
        })
        .flat_map(|(r, report)| {
            report.incomplete.iter().map(|m| Incomplete {
                scene: r.scene.to_string(),
                metric: m.metric.name(),
                vlm: m.vlm,
                error: m.error.clone(),
                causes: m.causes.clone(),
            })
        })
        .collect();
    let report = RunReport {
        out: request.out,
        scenes: outcome.scenes.len(),
        evaluated: outcome.batch.evaluated,
        reused: outcome.batch.reused,
        failed: outcome.batch.failed,
        partial: outcome.batch.partial,
        skipped: outcome
            .skipped
            .into_iter()
            .map(|s| Skipped {
                path: s.path,
                reason: s.reason,
            })
            .collect(),
        failures,
        incomplete,
        note,
        summary: outcome.summary,
    };
    to_python(py, &report)
}
