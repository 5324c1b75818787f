//! `sceneeval.compare(runs, ...)`: `sceneeval compare` for Python. The runs are read and
//! compared by `sceneeval-report` exactly as the command compares them; the rows come back as
//! dicts (the columns of `compare --format csv`, numbers as floats, `None` where there is no
//! value) and every note and warning of the comparison is a Python `UserWarning`.

use std::path::PathBuf;

use pyo3::prelude::*;
use sceneeval::report::compare::{FailedScenes, Pairing, RankBy};
use sceneeval::report::{CompareOptions, Comparison, Run, compare as compare_runs};
use serde::Serialize;

use crate::convert::to_python;
use crate::errors::{chain, detached, scene_error, user_warning as warn, value_error};

/// A run's value in one column of one table (`compare --format csv` without `--paired`).
#[derive(Debug, Serialize)]
struct RunRow<'a> {
    group: &'a str,
    scenes: usize,
    run: &'a str,
    column: &'a str,
    better: &'a str,
    value: Option<f64>,
    n: usize,
    ci_low: Option<f64>,
    ci_high: Option<f64>,
    rank: Option<usize>,
    points: usize,
    missing: &'a [String],
    failed: &'a [String],
}

fn run_rows(c: &Comparison) -> Vec<RunRow<'_>> {
    let mut out = Vec::new();
    for table in &c.tables {
        for ((run, row), coverage) in c.runs.iter().zip(&table.cells).zip(&c.coverage) {
            for (column, cell) in c.columns.iter().zip(row) {
                out.push(RunRow {
                    group: &table.group,
                    scenes: table.scenes,
                    run: &run.name,
                    column: column.name,
                    better: column.better.name(),
                    value: cell.value,
                    n: cell.n,
                    ci_low: cell.ci.map(|c| c[0]),
                    ci_high: cell.ci.map(|c| c[1]),
                    rank: cell.rank,
                    points: cell.points,
                    missing: &coverage.missing,
                    failed: &coverage.failed,
                });
            }
        }
    }
    out
}

/// Compares the runs (output folders of `evaluate`) as `sceneeval compare` does.
///
/// With `paired=True`, one dict per pair of runs (each against the first with
/// `against_first=True`) and metric column: `kind` (`paired`), `a`, `b`, `metric`, `n`,
/// `mean_diff` (b - a, percentage points), `diff_low`, `diff_high` (the paired bootstrap
/// interval at `ci`, default 0.95), `p_value` (two-sided Wilcoxon signed-rank; `None` from
/// fewer than two non-zero differences, `note` says why), `p_holm` (Holm across the pair's
/// columns), `better`, `method`, `zeros`, `favours`, `note`; and one per pair and fidelity
/// metric with `kind` `mcnemar` (McNemar's exact test on the specs both judged, `a_only`,
/// `b_only`). Without it, one dict per run and column: `group`, `scenes`, `run`, `column`,
/// `better`, `value`, `n`, `ci_low`, `ci_high`, `rank`, `points`, `missing`, `failed`.
/// `rank` is `tested` or `mean`, `failed` `skip` or `worst` (docs/formats.md).
///
/// Raises SceneEvalError when a folder cannot be read, ValueError for a bad option (the
/// message starts with the keyword).
#[pyfunction]
#[pyo3(signature = (runs, *, names=None, paired=false, against_first=false, ci=None, alpha=0.05, rank="tested", failed="skip", by_difficulty=false))]
#[allow(clippy::too_many_arguments)] // The keyword arguments of `sceneeval.compare`.
pub fn compare<'py>(
    py: Python<'py>,
    runs: Vec<PathBuf>,
    names: Option<Vec<String>>,
    paired: bool,
    against_first: bool,
    ci: Option<f64>,
    alpha: f64,
    rank: &str,
    failed: &str,
    by_difficulty: bool,
) -> PyResult<Bound<'py, PyAny>> {
    if let Some(names) = &names
        && names.len() != runs.len()
    {
        return Err(value_error(format!(
            "names: {} names for {} runs",
            names.len(),
            runs.len()
        )));
    }
    if against_first && !paired {
        return Err(value_error("against_first: needs paired=True"));
    }
    let rank = match rank {
        "tested" => RankBy::Tested,
        "mean" => RankBy::Mean,
        other => return Err(value_error(format!("rank: {other:?} is not tested or mean"))),
    };
    let failed = match failed {
        "skip" => FailedScenes::Skip,
        "worst" => FailedScenes::Worst,
        other => return Err(value_error(format!("failed: {other:?} is not skip or worst"))),
    };
    let options = CompareOptions {
        by_difficulty,
        ci,
        paired: paired.then_some(if against_first {
            Pairing::AgainstFirst
        } else {
            Pairing::All
        }),
        rank,
        alpha,
        failed,
    };
    let comparison = detached(py, || {
        let mut opened: Vec<Run> = Vec::new();
        for (k, dir) in runs.iter().enumerate() {
            let mut run = Run::open(dir).map_err(|e| scene_error(&e))?;
            if let Some(names) = &names {
                run = run.with_name(names[k].trim());
            }
            if let Some(twin) = opened.iter().find(|r| r.name == run.name) {
                return Err(value_error(format!(
                    "names: two runs are named {:?} ({} and {})",
                    run.name,
                    twin.dir.display(),
                    dir.display()
                )));
            }
            opened.push(run);
        }
        compare_runs(&opened, &options).map_err(|e| value_error(chain(&e)))
    })?;
    for note in comparison
        .notes
        .iter()
        .chain(comparison.pairs.iter().flat_map(|p| &p.notes))
    {
        warn(py, note)?;
    }
    if paired {
        to_python(py, &comparison.paired_records())
    } else {
        to_python(py, &run_rows(&comparison))
    }
}
