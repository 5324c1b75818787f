//! `sceneeval.stats`: the statistics of `sceneeval-stats` for Python, each returning plain
//! dicts (or a list for `holm`). A statistic that is undefined for the input is `None` with
//! `undefined` (the reason's code: `no_items`, `one_class`, `too_few_raters`,
//! `too_few_differences`, `every_resample`) and `reason` (the sentence); bad input raises
//! `ValueError` naming the argument.

use pyo3::prelude::*;
use pyo3::types::{PyInt, PyString};
use sceneeval_stats::bootstrap::{DEFAULT_RESAMPLES, DEFAULT_SEED};
use sceneeval_stats::{
    Bootstrap, BootstrapInterval, Confusion, Decision, FleissTable, Majority, McNemar, StatsError, Undefined,
    Wilcoxon, WilcoxonP,
};
use serde_json::{Value, json};

use crate::convert::to_python;
use crate::errors::{chain, detached, value_error};

/// Statistics for checking judges and comparing methods, equal to scikit-learn's,
/// statsmodels' and SciPy's (docs/formats.md, "Statistics"): Cohen's and Fleiss' kappa, seeded
/// percentile bootstrap intervals, paired differences with the Wilcoxon signed-rank test,
/// Holm's adjustment, McNemar's exact test and majority votes.
#[pyo3::pymodule(submodule)]
pub mod stats {
    #[pymodule_export]
    use super::{bootstrap_mean, cohen_kappa, fleiss_kappa, holm, majority, mcnemar, paired, wilcoxon};
}

// The defaults written as literals in the signatures below (Python shows a default in a
// function's signature only when it is a literal): the crate's.
const _: () = assert!(DEFAULT_SEED == 20_261_121 && DEFAULT_RESAMPLES == 1000);

/// A `ValueError` for `e`, prefixed with the argument it concerns.
fn stats_error(what: &str, e: &StatsError) -> PyErr {
    value_error(format!("{what}: {}", chain(e)))
}

/// The code and sentence of an undefined statistic (`None`s when defined).
fn undefined_fields(reason: Option<Undefined>) -> (Value, Value) {
    match reason {
        Some(u) => (
            serde_json::to_value(u).unwrap_or(Value::Null),
            Value::String(u.to_string()),
        ),
        None => (Value::Null, Value::Null),
    }
}

/// A result's value and reason as dict fields: `{key: value or None, undefined, reason}`.
fn outcome(key: &str, value: Result<f64, Undefined>) -> serde_json::Map<String, Value> {
    let (undefined, reason) = undefined_fields(value.err());
    let mut map = serde_json::Map::new();
    map.insert(key.to_owned(), json!(value.ok()));
    map.insert("undefined".to_owned(), undefined);
    map.insert("reason".to_owned(), reason);
    map
}

fn interval_json(interval: &BootstrapInterval) -> Value {
    let mut map = outcome("low", interval.bounds.map(|b| b[0]));
    map.insert("high".to_owned(), json!(interval.bounds.ok().map(|b| b[1])));
    map.insert("level".to_owned(), json!(interval.level));
    map.insert("resamples".to_owned(), json!(interval.resamples));
    map.insert("undefined_resamples".to_owned(), json!(interval.undefined));
    Value::Object(map)
}

fn bootstrap(resamples: usize, seed: u64, level: f64) -> PyResult<Bootstrap> {
    Bootstrap::new(resamples, level)
        .map(|b| b.with_seed(seed))
        .map_err(|e| stats_error("bootstrap", &e))
}

/// A rater's label: `None` (no verdict), a bool, an int or a string.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
enum Label {
    Bool(bool),
    Int(i64),
    Str(String),
}

impl Label {
    fn kind(&self) -> &'static str {
        match self {
            Self::Bool(_) => "bool",
            Self::Int(_) => "int",
            Self::Str(_) => "str",
        }
    }

    fn to_json(&self) -> Value {
        match self {
            Self::Bool(b) => json!(b),
            Self::Int(i) => json!(i),
            Self::Str(s) => json!(s),
        }
    }
}

fn labels(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Option<Label>>> {
    let mut out = Vec::new();
    for (i, item) in obj.try_iter()?.enumerate() {
        let item = item?;
        // Python's bool and NumPy's (pyo3 accepts both as bool, and no int), then ints
        // (anything with __index__), then strings.
        let label = if item.is_none() {
            None
        } else if let Ok(b) = item.extract::<bool>() {
            Some(Label::Bool(b))
        } else if item.is_instance_of::<PyInt>() || item.hasattr("__index__")? {
            Some(Label::Int(item.extract()?))
        } else if item.is_instance_of::<PyString>() {
            Some(Label::Str(item.extract()?))
        } else {
            return Err(value_error(format!(
                "{what}[{i}]: a label is a bool, an int, a str or None, got a {}",
                item.get_type().name()?
            )));
        };
        out.push(label);
    }
    Ok(out)
}

/// Cohen's kappa of two raters on the same items, equal to scikit-learn's
/// cohen_kappa_score(a, b) (unweighted). a and b hold one label per item: bool, int or str
/// (one kind), None where that rater gave no verdict (the item is left out and counted in
/// left_out). Returns a dict: n (items both judged), left_out, labels (the categories,
/// sorted), confusion (rows: a's label, columns: b's), agreement, expected_agreement, kappa
/// (None when undefined: no items, or both raters used one and the same class, with undefined
/// and reason), and with bootstrap=N the percentile interval of kappa over N resamples of the
/// items (seeded; resamples where kappa is undefined are left out and counted in
/// undefined_resamples).
#[pyfunction]
#[pyo3(signature = (a, b, *, bootstrap=None, seed=20261121, level=0.95))]
pub fn cohen_kappa<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
    bootstrap: Option<usize>,
    seed: u64,
    level: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let (a, b) = (labels(a, "a")?, labels(b, "b")?);
    if a.len() != b.len() {
        return Err(stats_error(
            "a, b",
            &StatsError::LengthMismatch {
                a: a.len(),
                b: b.len(),
            },
        ));
    }
    let judged: Vec<(&Label, &Label)> = a
        .iter()
        .zip(&b)
        .filter_map(|(x, y)| Some((x.as_ref()?, y.as_ref()?)))
        .collect();
    let mut categories: Vec<&Label> = judged.iter().flat_map(|&(x, y)| [x, y]).collect();
    categories.sort();
    categories.dedup();
    if let Some(other) = categories.iter().find(|l| l.kind() != categories[0].kind()) {
        return Err(value_error(format!(
            "a, b: labels of one kind only (bool, int or str), got {} and {}",
            categories[0].kind(),
            other.kind()
        )));
    }
    let index = |l: &Label| categories.binary_search(&l).unwrap_or(0);
    let pairs: Vec<(usize, usize)> = judged.iter().map(|&(x, y)| (index(x), index(y))).collect();
    let k = categories.len();
    let table = Confusion::from_pairs(k, pairs.iter().copied()).map_err(|e| stats_error("a, b", &e))?;
    let interval = match bootstrap {
        Some(resamples) => {
            let boot = self::bootstrap(resamples, seed, level)?;
            let pairs = &pairs;
            let ci = detached(py, move || {
                boot.cohen_kappa(k, pairs).map_err(|e| stats_error("a, b", &e))
            })?;
            interval_json(&ci)
        }
        None => Value::Null,
    };
    let mut map = outcome("kappa", table.kappa());
    map.insert("n".to_owned(), json!(table.n()));
    map.insert("left_out".to_owned(), json!(a.len() - judged.len()));
    map.insert(
        "labels".to_owned(),
        Value::Array(categories.iter().map(|l| l.to_json()).collect()),
    );
    map.insert(
        "confusion".to_owned(),
        json!(table.rows().map(<[u64]>::to_vec).collect::<Vec<_>>()),
    );
    map.insert("agreement".to_owned(), json!(table.agreement()));
    map.insert("expected_agreement".to_owned(), json!(table.expected_agreement()));
    map.insert("interval".to_owned(), interval);
    to_python(py, &Value::Object(map))
}

/// Fleiss' kappa of several raters, equal to statsmodels' fleiss_kappa(table,
/// method='fleiss'). table: items x categories counts (how many raters chose each category for
/// the item), the same number of ratings on every item. Returns a dict: items, raters,
/// agreement (mean observed agreement), expected_agreement, kappa (None when undefined: no
/// items, fewer than two raters, or every rating in one category, with undefined and reason).
#[pyfunction]
pub fn fleiss_kappa<'py>(py: Python<'py>, table: Vec<Vec<u64>>) -> PyResult<Bound<'py, PyAny>> {
    let table = &table;
    let t = detached(py, move || {
        FleissTable::from_counts(table).map_err(|e| stats_error("table", &e))
    })?;
    let mut map = outcome("kappa", t.kappa());
    map.insert("items".to_owned(), json!(t.items()));
    map.insert("raters".to_owned(), json!(t.raters()));
    map.insert("agreement".to_owned(), json!(t.agreement()));
    map.insert("expected_agreement".to_owned(), json!(t.expected_agreement()));
    to_python(py, &Value::Object(map))
}

/// The percentile bootstrap interval of the mean of values (one per item): resamples of the
/// items drawn with replacement from the seeded Xoshiro256++ generator, quantiles (1 - level)/2
/// and (1 + level)/2 interpolated linearly. Returns a dict: low, high (None without values,
/// with undefined and reason), level, resamples, undefined_resamples.
#[pyfunction]
#[pyo3(signature = (values, *, resamples=1000, seed=20261121, level=0.95))]
pub fn bootstrap_mean(
    py: Python<'_>,
    values: Vec<f64>,
    resamples: usize,
    seed: u64,
    level: f64,
) -> PyResult<Bound<'_, PyAny>> {
    let b = bootstrap(resamples, seed, level)?;
    let values = &values;
    let ci = detached(py, move || b.mean(values).map_err(|e| stats_error("values", &e)))?;
    to_python(py, &interval_json(&ci))
}

fn wilcoxon_json(w: &Wilcoxon) -> Value {
    let mut map = outcome("p_value", w.p.value());
    map.insert("statistic".to_owned(), json!(w.statistic));
    map.insert("r_plus".to_owned(), json!(w.r_plus));
    map.insert("r_minus".to_owned(), json!(w.r_minus));
    map.insert("n".to_owned(), json!(w.n));
    map.insert("zeros".to_owned(), json!(w.zeros));
    map.insert("ties".to_owned(), json!(w.ties));
    map.insert("method".to_owned(), json!(w.p.method()));
    let z = match w.p {
        WilcoxonP::Normal { z, .. } => Some(z),
        WilcoxonP::Exact { .. } | WilcoxonP::Undefined { .. } => None,
    };
    map.insert("z".to_owned(), json!(z));
    Value::Object(map)
}

/// The two-sided Wilcoxon signed-rank test of paired differences (b - a per item):
/// differences rounded to 1e-9, zeros dropped and counted, average ranks of |d|; the exact
/// distribution with at most 50 non-zero differences and no ties among their |d|, else the
/// normal approximation with tie and continuity correction. Equal to SciPy's
/// wilcoxon(np.round(d, 9), zero_method='wilcox', correction=True, method='exact' or
/// 'asymptotic'). Returns a dict: statistic (min(R+, R-)), r_plus, r_minus, n (non-zero
/// differences), zeros, ties, method ('exact', 'normal' or 'none'), z (normal only), p_value
/// (None with fewer than two non-zero differences, with undefined and reason).
#[pyfunction]
pub fn wilcoxon(py: Python<'_>, differences: Vec<f64>) -> PyResult<Bound<'_, PyAny>> {
    let differences = &differences;
    let w = detached(py, move || {
        sceneeval_stats::wilcoxon(differences).map_err(|e| stats_error("differences", &e))
    })?;
    to_python(py, &wilcoxon_json(&w))
}

/// A paired comparison of b with a on the same items (`a[i]` and `b[i]` the same item): n, the
/// mean difference b - a, its percentile bootstrap interval (pairs resampled, seeded) and the
/// Wilcoxon signed-rank test of the differences. Returns a dict: n, mean_difference (None
/// without pairs), interval (as bootstrap_mean gives it) and wilcoxon (as wilcoxon gives it).
#[pyfunction]
#[pyo3(signature = (a, b, *, resamples=1000, seed=20261121, level=0.95))]
pub fn paired(
    py: Python<'_>,
    a: Vec<f64>,
    b: Vec<f64>,
    resamples: usize,
    seed: u64,
    level: f64,
) -> PyResult<Bound<'_, PyAny>> {
    let boot = bootstrap(resamples, seed, level)?;
    let (a, b) = (&a, &b);
    let r = detached(py, move || {
        sceneeval_stats::paired(a, b, &boot).map_err(|e| stats_error("a, b", &e))
    })?;
    let value = json!({
        "n": r.n,
        "mean_difference": r.mean_difference,
        "interval": interval_json(&r.interval),
        "wilcoxon": wilcoxon_json(&r.wilcoxon),
    });
    to_python(py, &value)
}

/// Holm's step-down adjustment, equal to statsmodels' `multipletests(p, method='holm')[1]`:
/// the i-th smallest (from 0) of the m p-values becomes min(1, max over j <= i of (m - j)
/// p_(j)), returned in the input's order. None entries stay None and are not counted in m.
#[pyfunction]
pub fn holm(py: Python<'_>, p_values: Vec<Option<f64>>) -> PyResult<Vec<Option<f64>>> {
    let p_values = &p_values;
    detached(py, move || {
        sceneeval_stats::holm(p_values).map_err(|e| stats_error("p_values", &e))
    })
}

/// McNemar's exact test on the discordant counts of paired binary outcomes: b items true in
/// the first and false in the second, c the other way round. The two-sided p-value is
/// min(1, 2 P(X <= min(b, c))) for X ~ Binomial(b + c, 1/2), equal to statsmodels'
/// mcnemar([[a, b], [c, d]], exact=True).pvalue; 1 without discordant items. Returns a dict:
/// b, c, statistic (min(b, c)), p_value.
#[pyfunction]
pub fn mcnemar(py: Python<'_>, b: u64, c: u64) -> PyResult<Bound<'_, PyAny>> {
    let t = McNemar::exact(b, c);
    to_python(
        py,
        &json!({"b": t.b, "c": t.c, "statistic": t.statistic, "p_value": t.p}),
    )
}

/// The majority of verdicts (True, False or None for no verdict; None ignored). Returns a
/// dict: verdict (True, False, or None for a tie or without votes), decision ('true',
/// 'false', 'tie' or 'no_votes'), yes, no, abstained.
#[pyfunction]
pub fn majority(py: Python<'_>, votes: Vec<Option<bool>>) -> PyResult<Bound<'_, PyAny>> {
    let m = Majority::of(votes);
    let decision = match m.decision() {
        Decision::Verdict(true) => "true",
        Decision::Verdict(false) => "false",
        Decision::Tie => "tie",
        Decision::NoVotes => "no_votes",
    };
    to_python(
        py,
        &json!({
            "verdict": m.verdict(),
            "decision": decision,
            "yes": m.yes,
            "no": m.no,
            "abstained": m.abstained,
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_sort_within_their_kind() {
        assert!(Label::Bool(false) < Label::Bool(true));
        assert!(Label::Int(-3) < Label::Int(2));
        assert!(Label::Str("no".into()) < Label::Str("yes".into()));
        assert_eq!(Label::Int(1).kind(), "int");
    }

    #[test]
    fn undefined_reasons_have_a_code_and_a_sentence() {
        let fields = outcome("kappa", Err(Undefined::OneClass));
        assert_eq!(fields["kappa"], Value::Null);
        assert_eq!(fields["undefined"], json!("one_class"));
        assert!(fields["reason"].as_str().is_some_and(|r| r.contains("one class")));
        let fields = outcome("kappa", Ok(0.5));
        assert_eq!(fields["kappa"], json!(0.5));
        assert_eq!(fields["undefined"], Value::Null);
    }
}
