//! `sceneeval.agreement`: the rows of `sceneeval agreement` as dicts, from the same code
//! (`sceneeval_report::agreement`).

use std::path::PathBuf;

use pyo3::prelude::*;
use sceneeval::report::agreement::{AgreementError, AgreementOptions, Source, agreement as compute};
use sceneeval::report::labels::LabelFile;
use sceneeval::stats::Bootstrap;

use crate::convert::to_python;
use crate::errors::{chain, detached, scene_error, value_error};

/// The references: one path or a list of paths.
#[derive(Debug, FromPyObject)]
pub enum Paths {
    /// One file.
    One(PathBuf),
    /// Several.
    Many(Vec<PathBuf>),
}

/// How far judges agree with people on the fidelity specs (`sceneeval agreement`,
/// docs/judge.md).
///
/// `sources`: run folders (each its VLM judge, named after the folder) and label files (one
/// rater per annotator). `reference`: a label file or a list of them whose annotators'
/// majority is the reference; `None` compares every pair of raters. `bootstrap`: resamples of
/// each kappa's 95 % percentile interval (0: none); `seed`: the bootstrap's seed.
///
/// Returns a list of dicts, one per rater pair and metric, with the keys of the CSV
/// (`kind`, `a`, `b`, `metric`, `n`, `agreement`, `kappa`, `kappa_low`, `kappa_high`,
/// `undefined`, `tt`, `tf`, `ft`, `ff`, `left_out_null`, `left_out_tie`, ...); a kappa that
/// does not exist is `None` with the reason in `undefined`.
///
/// Raises `SceneEvalError` for a file that cannot be read or a label that does not fit a run
/// (the message names the file and line), `ValueError` for bad arguments.
#[pyfunction]
#[pyo3(signature = (sources, reference=None, *, bootstrap=1000, seed=20261121))]
pub fn agreement<'py>(
    py: Python<'py>,
    sources: Vec<PathBuf>,
    reference: Option<Paths>,
    bootstrap: usize,
    seed: u64,
) -> PyResult<Bound<'py, PyAny>> {
    let reference = match reference {
        None => Vec::new(),
        Some(Paths::One(p)) => vec![p],
        Some(Paths::Many(p)) => p,
    };
    let bootstrap = (bootstrap > 0)
        .then(|| Bootstrap::new(bootstrap, 0.95).map(|b| b.with_seed(seed)))
        .transpose()
        .map_err(|e| value_error(format!("bootstrap: {}", chain(&e))))?;
    let table = detached(py, || {
        let error = |e: AgreementError| match e {
            AgreementError::Nothing(_) => value_error(chain(&e)),
            other => scene_error(&other),
        };
        let reference = reference
            .iter()
            .map(|p| LabelFile::read(p).map_err(|e| scene_error(&e)))
            .collect::<PyResult<Vec<_>>>()?;
        let sources = sources
            .iter()
            .map(|p| Source::open(p).map_err(error))
            .collect::<PyResult<Vec<_>>>()?;
        compute(&reference, &sources, &AgreementOptions { bootstrap }).map_err(error)
    })?;
    to_python(py, &table.rows)
}
