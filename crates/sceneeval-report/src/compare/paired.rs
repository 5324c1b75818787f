//! Paired comparisons (`compare --paired`): for a pair of runs and a metric column, the scenes
//! both runs evaluated with a value, the mean of the per-scene differences `b - a` (percent, as
//! the per-scene table shows them, from the full-precision values), its paired bootstrap
//! interval, the two-sided Wilcoxon signed-rank p-value and Holm's adjustment across the
//! columns of the pair; for the fidelity metrics, McNemar's exact test on the per-spec verdicts.
//! Every statistic is `sceneeval-stats`' ([`sceneeval_stats::paired()`], [`holm`],
//! [`McNemar`]); this module only chooses the items.

use std::collections::BTreeSet;

use sceneeval_results::{Better, Metric, Outcome, SceneRecord};
use sceneeval_stats::bootstrap::{Bootstrap, DEFAULT_RESAMPLES};
use sceneeval_stats::{McNemar, Undefined, holm, paired as paired_stats};

use super::{Column, MAX_LISTED, Verdict, list, spec_verdicts};
use crate::run::{Run, scene_order, scene_values};

/// Which pairs of runs `--paired` compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pairing {
    /// Every pair `(a, b)` with `a` before `b` in the order given.
    All,
    /// Each run against the first (`--against-first`): `(first, b)` for every later `b`.
    AgainstFirst,
}

impl Pairing {
    /// The pairs of run indices among `n` runs, `a` before `b`.
    pub fn pairs(self, n: usize) -> Vec<(usize, usize)> {
        match self {
            Pairing::All => (0..n).flat_map(|a| (a + 1..n).map(move |b| (a, b))).collect(),
            Pairing::AgainstFirst => (1..n).map(|b| (0, b)).collect(),
        }
    }
}

/// The comparison of two runs: a row per metric column, a McNemar test per fidelity metric and
/// the warnings about what differs between them.
#[derive(Debug, Clone, PartialEq)]
pub struct PairComparison {
    /// The first run (index into [`super::Comparison::runs`]).
    pub a: usize,
    /// The second run; differences are `b - a`.
    pub b: usize,
    /// One row per column of the comparison, in its order.
    pub rows: Vec<PairedRow>,
    /// McNemar's test per fidelity metric the runs share.
    pub verdicts: Vec<VerdictRow>,
    /// Warnings: different plans, presets or annotation rows, scenes only one run has.
    pub notes: Vec<String>,
    /// The scenes' own differences behind [`PairComparison::rows`] (every scene and column
    /// with a value in both runs), the largest `|b - a|` first; equal sizes in column order,
    /// then scene order.
    pub scenes: Vec<SceneDifference>,
}

/// One scene's values of one column in two runs: an item of a [`PairedRow`].
#[derive(Debug, Clone, PartialEq)]
pub struct SceneDifference {
    /// The scene.
    pub scene: String,
    /// The column.
    pub column: Column,
    /// The scene's value in run `a`, in percent (as the per-scene table shows it).
    pub a: f64,
    /// Its value in run `b`.
    pub b: f64,
}

impl SceneDifference {
    /// `b - a`, in percentage points, from the full-precision values.
    pub fn difference(&self) -> f64 {
        self.b - self.a
    }
}

/// The paired statistics of one column for one pair of runs.
#[derive(Debug, Clone, PartialEq)]
pub struct PairedRow {
    /// The column.
    pub column: Column,
    /// Scenes both runs evaluated with a value in the column.
    pub n: usize,
    /// Of those, scenes whose difference is zero (after rounding to 1e-9): left out of the test.
    pub zeros: usize,
    /// The mean of `b - a` over the `n` scenes, in percentage points; `None` without scenes.
    pub mean_difference: Option<f64>,
    /// Its percentile bootstrap interval (scenes resampled), when there are scenes.
    pub interval: Option<[f64; 2]>,
    /// The two-sided Wilcoxon signed-rank p-value, or why there is none.
    pub p: Result<f64, Undefined>,
    /// `exact`, `normal` or `none`.
    pub method: &'static str,
    /// The p-value adjusted by Holm across the columns of the pair that have one.
    pub p_holm: Option<f64>,
}

impl PairedRow {
    /// Which run the mean difference favours (`Some(true)`: `b`, `Some(false)`: `a`), in the
    /// column's direction; `None` without a difference.
    pub fn favours_b(&self) -> Option<bool> {
        let d = self.mean_difference.filter(|d| *d != 0.0)?;
        Some(match self.column.better {
            Better::Higher => d > 0.0,
            Better::Lower => d < 0.0,
        })
    }

    /// Whether the Holm-adjusted p-value is below `alpha`.
    pub fn significant(&self, alpha: f64) -> bool {
        self.p_holm.is_some_and(|p| p < alpha)
    }

    /// Why there is no p-value, for the tables' notes.
    pub fn note(&self) -> Option<String> {
        match self.p {
            Ok(_) => None,
            Err(Undefined::TooFewDifferences) => Some(format!(
                "no p-value: {} non-zero difference(s) of {} scene(s), a test needs at least two",
                self.n - self.zeros,
                self.n
            )),
            Err(why) => Some(format!("no p-value: {why}")),
        }
    }
}

/// McNemar's exact test of two runs' verdicts on the same fidelity specs.
#[derive(Debug, Clone, PartialEq)]
pub struct VerdictRow {
    /// CNT, ATR, OOR or OAR.
    pub metric: Metric,
    /// Specs both runs judged (a verdict, not null, in both), on scenes both evaluated with the
    /// same annotation row.
    pub n: usize,
    /// The test: `b` = satisfied in run a only, `c` = satisfied in run b only.
    pub test: McNemar,
    /// The p-value adjusted by Holm across the pair's McNemar tests.
    pub p_holm: Option<f64>,
}

impl VerdictRow {
    /// The difference in the share of satisfied specs, `b - a`, in percentage points.
    pub fn difference(&self) -> Option<f64> {
        (self.n > 0).then(|| (self.test.c as f64 - self.test.b as f64) / self.n as f64 * 100.0)
    }
}

/// A record with a report (evaluated, fully or partly).
fn evaluated(record: Option<&SceneRecord>) -> Option<&SceneRecord> {
    record.filter(|r| !matches!(r.outcome, Outcome::Failed { .. }))
}

/// The annotation row digest a record's fidelity was computed against.
fn annotation(record: &SceneRecord) -> Option<&str> {
    record.fingerprint.as_ref()?.annotation.as_deref()
}

/// Compares runs `a` and `b` on `columns` (scenes both have; see the module documentation).
pub(crate) fn compare_pair(
    runs: &[Run],
    a: usize,
    b: usize,
    columns: &[Column],
    level: f64,
) -> PairComparison {
    let (ra, rb) = (&runs[a], &runs[b]);
    let mut notes = pair_differences(ra, rb);
    // Every scene either run has, in scene order.
    let mut scenes: Vec<_> = ra
        .records
        .iter()
        .chain(&rb.records)
        .map(|r| &r.scene)
        .chain(ra.unreadable.iter().chain(&rb.unreadable).map(|u| &u.scene))
        .collect();
    scenes.sort_by(|x, y| scene_order(x, y));
    scenes.dedup();
    let mut both = Vec::new();
    let mut lacking = Vec::new();
    let mut other_rows = Vec::new();
    for scene in scenes {
        let s = scene.as_str();
        match (evaluated(ra.record(s)), evaluated(rb.record(s))) {
            (Some(x), Some(y)) => {
                if annotation(x) != annotation(y) && (annotation(x).is_some() || annotation(y).is_some()) {
                    other_rows.push(s);
                }
                both.push((s, x, y));
            }
            (x, y) => {
                let why = |run: &Run, r: Option<&SceneRecord>| match (run.record(s), r) {
                    (_, Some(_)) => None,
                    (Some(_), None) => Some(format!("failed in {}", run.name)),
                    (None, _) if run.unreadable.iter().any(|u| u.scene == *scene) => {
                        Some(format!("unreadable in {}", run.name))
                    }
                    (None, _) => Some(format!("not in {}", run.name)),
                };
                let reasons: Vec<String> = [why(ra, x), why(rb, y)].into_iter().flatten().collect();
                lacking.push(format!("{s} ({})", reasons.join(", ")));
            }
        }
    }
    if !lacking.is_empty() {
        let shown = lacking.len().min(MAX_LISTED);
        notes.push(format!(
            "{} and {}: {} scene(s) not evaluated by both, left out of their paired statistics: {}{}.",
            ra.name,
            rb.name,
            lacking.len(),
            lacking[..shown].join(", "),
            more(lacking.len() - shown)
        ));
    }
    if !other_rows.is_empty() {
        let shown: Vec<&str> = other_rows.iter().take(MAX_LISTED).copied().collect();
        notes.push(format!(
            "{} and {} used different annotation rows for {}{}: the fidelity columns leave these scenes out.",
            ra.name,
            rb.name,
            list(&shown),
            more(other_rows.len() - shown.len())
        ));
    }
    let bootstrap = Bootstrap::new(DEFAULT_RESAMPLES, level).unwrap_or_default();
    let mut scenes: Vec<SceneDifference> = Vec::new();
    let mut rows: Vec<PairedRow> = columns
        .iter()
        .map(|&column| {
            let fidelity = column.metric.fidelity().is_some();
            let items: Vec<SceneDifference> = both
                .iter()
                .filter(|(s, _, _)| !(fidelity && other_rows.contains(s)))
                .filter_map(|(s, x, y)| {
                    Some(SceneDifference {
                        scene: (*s).to_owned(),
                        column,
                        a: scene_values(x).value(column.name)?,
                        b: scene_values(y).value(column.name)?,
                    })
                })
                .collect();
            let (xs, ys): (Vec<f64>, Vec<f64>) = items.iter().map(|d| (d.a, d.b)).unzip();
            scenes.extend(items);
            paired_row(column, &xs, &ys, &bootstrap)
        })
        .collect();
    // Stable: equal sizes keep column order, then scene order.
    scenes.sort_by(|x, y| y.difference().abs().total_cmp(&x.difference().abs()));
    let adjusted = holm(&rows.iter().map(|r| r.p.ok()).collect::<Vec<_>>()).unwrap_or_default();
    for (row, p) in rows.iter_mut().zip(adjusted) {
        row.p_holm = p;
    }
    let mut verdicts = verdict_tests(&both, &other_rows, columns);
    let adjusted = holm(&verdicts.iter().map(|v| Some(v.test.p)).collect::<Vec<_>>()).unwrap_or_default();
    for (row, p) in verdicts.iter_mut().zip(adjusted) {
        row.p_holm = p;
    }
    PairComparison {
        a,
        b,
        rows,
        verdicts,
        notes,
        scenes,
    }
}

/// The statistics of one column from the paired values (`xs[i]`, `ys[i]` of the same scene).
pub(crate) fn paired_row(column: Column, xs: &[f64], ys: &[f64], bootstrap: &Bootstrap) -> PairedRow {
    match paired_stats(xs, ys, bootstrap) {
        Ok(p) => PairedRow {
            column,
            n: p.n,
            zeros: p.wilcoxon.zeros,
            mean_difference: p.mean_difference,
            interval: p.interval.bounds.ok(),
            p: p.wilcoxon.p.value(),
            method: p.wilcoxon.p.method(),
            p_holm: None,
        },
        // Values are finite percentages of equal counts; should one not be, the row says so.
        Err(e) => {
            tracing::warn!(column = column.name, error = %e, "paired statistics not computed");
            PairedRow {
                column,
                n: xs.len(),
                zeros: 0,
                mean_difference: None,
                interval: None,
                p: Err(Undefined::NoItems),
                method: "none",
                p_holm: None,
            }
        }
    }
}

/// McNemar's test per fidelity metric among `columns`, over the specs of the scenes both runs
/// evaluated with the same annotation row, matched by position and text.
fn verdict_tests(
    both: &[(&str, &SceneRecord, &SceneRecord)],
    other_rows: &[&str],
    columns: &[Column],
) -> Vec<VerdictRow> {
    let metrics: BTreeSet<Metric> = columns
        .iter()
        .map(|c| c.metric)
        .filter(|m| m.fidelity().is_some())
        .collect();
    metrics
        .into_iter()
        .map(|metric| {
            let mut pairs = Vec::new();
            for (scene, x, y) in both {
                if other_rows.contains(scene) {
                    continue;
                }
                let specs = |r: &SceneRecord| {
                    r.report()
                        .and_then(|r| r.fidelity.as_ref())
                        .map(|f| spec_verdicts(f, metric))
                        .unwrap_or_default()
                };
                for ((sa, va), (sb, vb)) in specs(x).into_iter().zip(specs(y)) {
                    let judged = |v: Verdict| match v {
                        Verdict::Satisfied => Some(true),
                        Verdict::NotSatisfied => Some(false),
                        Verdict::NotJudged => None,
                    };
                    if sa == sb
                        && let (Some(p), Some(q)) = (judged(va), judged(vb))
                    {
                        pairs.push((p, q));
                    }
                }
            }
            VerdictRow {
                metric,
                n: pairs.len(),
                test: McNemar::from_pairs(pairs),
                p_holm: None,
            }
        })
        .collect()
}

/// Warnings for what should be the same in two runs and is not: plans and presets (the
/// annotation rows are checked per scene by [`compare_pair`]).
fn pair_differences(a: &Run, b: &Run) -> Vec<String> {
    type Get = fn(&SceneRecord) -> Option<String>;
    let aspects: [(&str, Get); 2] = [
        ("plans (result digests)", |r| {
            r.fingerprint.as_ref().map(|f| f.plan.chars().take(16).collect())
        }),
        ("presets", |r| {
            r.fingerprint.as_ref()?.preset.map(|p| p.name().to_owned())
        }),
    ];
    let mut notes = Vec::new();
    for (what, get) in aspects {
        let of = |run: &Run| -> BTreeSet<String> { run.records.iter().filter_map(get).collect() };
        let (x, y) = (of(a), of(b));
        if x != y {
            let show = |s: &BTreeSet<String>| {
                if s.is_empty() {
                    "(not recorded)".to_owned()
                } else {
                    s.iter().map(String::as_str).collect::<Vec<_>>().join(" and ")
                }
            };
            notes.push(format!(
                "{} and {} used different {what}: {} {}, {} {}; their differences may not be comparable.",
                a.name,
                b.name,
                a.name,
                show(&x),
                b.name,
                show(&y)
            ));
        }
    }
    notes
}

/// " and N more" when N > 0.
fn more(n: usize) -> String {
    if n > 0 {
        format!(" and {n} more")
    } else {
        String::new()
    }
}
