//! `sceneeval.ensemble(runs, out, ...)`: `sceneeval ensemble` for Python. The runs are combined
//! by `sceneeval_run::ensemble`, the code the command runs, into the same run folder; what the
//! command prints comes back as a dict, and each geometry difference is also a `UserWarning`
//! (the command's `note:` lines).

use std::path::PathBuf;

use pyo3::prelude::*;
use sceneeval::annotation::Annotations;
use sceneeval::run::{EnsembleError, EnsembleOptions, ensemble as combine};
use serde::Serialize;

use crate::convert::to_python;
use crate::errors::{SceneEvalError, chain, detached, scene_error, user_warning, value_error};

/// A geometry metric in which a run differs from the first run, in one scene.
#[derive(Debug, Serialize)]
struct Difference<'a> {
    scene: &'a str,
    metric: &'a str,
    run: &'a str,
    detail: &'a str,
}

/// What `ensemble` returns.
#[derive(Debug, Serialize)]
struct Outcome<'a> {
    runs: &'a [String],
    scenes: usize,
    ties: usize,
    differences: Vec<Difference<'a>>,
    summary: &'a sceneeval::Summary,
}

/// Combines runs made with different judges on the same scenes into one run folder `out`, as
/// `sceneeval ensemble RUN... --out OUT` does (docs/judge.md, "Ensembles of judges"): every
/// text-fidelity verdict is the majority of the runs' (a tie or no verdict: `None`, counted as
/// unanswered), the scores recounted; geometry, views and matching are the first run's.
/// `annotations` (the runs' annotation file) adds the summary's rows per difficulty.
///
/// Returns a dict: `runs` (the runs' names, in vote order), `scenes`, `ties` (specs whose runs
/// tied), `differences` (one dict per scene and geometry metric in which a run differs from
/// the first: `scene`, `metric`, `run`, `detail`; each also a UserWarning) and `summary` (the
/// summary written, as `evaluate` returns it).
///
/// Raises ValueError for fewer than two runs, SceneEvalError when a run cannot be read, the
/// runs differ in more than the judge (the message names the runs and what differs) or the
/// folder cannot be written.
#[pyfunction]
#[pyo3(signature = (runs, out, *, annotations=None))]
pub fn ensemble<'py>(
    py: Python<'py>,
    runs: Vec<PathBuf>,
    out: PathBuf,
    annotations: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let done = detached(py, || {
        let annotations = annotations
            .as_deref()
            .map(|p| {
                Annotations::read(p)
                    .map_err(|e| sceneeval_error_in(&format!("reading annotations {}", p.display()), &e))
            })
            .transpose()?;
        let options = EnsembleOptions {
            out_dir: out,
            annotations: annotations.as_ref(),
        };
        combine(&runs, &options).map_err(|e| match e {
            EnsembleError::TooFewRuns { .. } => value_error(format!("runs: {}", chain(&e))),
            other => scene_error(&other),
        })
    })?;
    let differences: Vec<Difference<'_>> = done
        .differences
        .iter()
        .map(|(scene, d)| Difference {
            scene: scene.as_str(),
            metric: d.metric.name(),
            run: &d.run,
            detail: &d.detail,
        })
        .collect();
    for d in &differences {
        user_warning(
            py,
            &format!(
                "{}: {} differs in run {}: {} (the first run's is reported)",
                d.scene, d.metric, d.run, d.detail
            ),
        )?;
    }
    to_python(
        py,
        &Outcome {
            runs: &done.runs,
            scenes: done.records.len(),
            ties: done.ties,
            differences,
            summary: &done.summary,
        },
    )
}

/// A `SceneEvalError` saying `what` failed, with `e`'s message and causes.
fn sceneeval_error_in(what: &str, e: &(dyn std::error::Error + 'static)) -> PyErr {
    SceneEvalError::new_err(format!("{what}: {}", chain(e)))
}
