//! How far to trust a judge: the agreement of runs (each made with one VLM judge) and people
//! (label files, [`crate::labels`]) on the same fidelity specs, as the paper's human check
//! measures it (`docs/judge.md`, `docs/formats.md` "Agreement tables").
//!
//! With reference label files, the reference verdict of an item (a spec of a scene) is the
//! majority of the reference annotators who judged it ([`sceneeval_stats::Majority`]; a tie is
//! left out and counted); every other source is a judge measured against it, per metric and
//! pooled over the metrics (`all`): n, agreement, Cohen's kappa
//! ([`sceneeval_stats::Confusion`]), a percentile bootstrap interval of kappa (items resampled;
//! [`sceneeval_stats::Bootstrap`]) and the confusion counts. The reference annotators get
//! Cohen's kappa of every pair and Fleiss' kappa ([`sceneeval_stats::FleissTable`]) over the
//! items all of them judged. Without a reference, every pair of sources is compared.
//!
//! A verdict `null` on either side (the person could not tell, the VLM gave no answer) leaves
//! the item out, counted. A kappa that does not exist (no item, one class only) is an empty
//! cell with its reason, never a number.

pub(crate) mod text;

pub use text::CSV_COLUMNS;

use std::collections::{BTreeMap, BTreeSet};

use sceneeval_fidelity::FidelityMetric;
use sceneeval_stats::{Bootstrap, BootstrapInterval, Confusion, Decision, FleissTable, Majority, Undefined};
use serde::Serialize;

use crate::Run;
use crate::labels::{Item, LabelError, LabelFile, SpecDiffers};

/// A source of verdicts: a run folder (its VLM judge) or a label file (its annotators).
#[derive(Debug, Clone)]
pub enum Source {
    /// A run: one judge named after the run.
    Run(Run),
    /// A label file: one rater per annotator.
    Labels(LabelFile),
}

impl Source {
    /// The source at `path`: a run when it is a folder ([`Run::open`]), else a label file
    /// ([`LabelFile::read`]).
    ///
    /// # Errors
    /// The run's or the label file's error.
    pub fn open(path: &std::path::Path) -> Result<Source, AgreementError> {
        if path.is_dir() {
            Ok(Source::Run(Run::open(path)?))
        } else {
            Ok(Source::Labels(LabelFile::read(path)?))
        }
    }
}

/// What kind of comparison a row is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RowKind {
    /// A judge (run or annotator of a non-reference label file) against the reference majority.
    Judge,
    /// Two reference annotators.
    Annotators,
    /// Fleiss' kappa of all reference annotators (`a` = `b` = `*`).
    Fleiss,
    /// Two sources, without a reference.
    Pair,
}

impl RowKind {
    /// The name in tables and CSV.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            RowKind::Judge => "judge",
            RowKind::Annotators => "annotators",
            RowKind::Fleiss => "fleiss",
            RowKind::Pair => "pair",
        }
    }
}

/// One row of the agreement table: two raters (or all annotators) on one metric or all.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AgreementRow {
    /// What is compared.
    pub kind: RowKind,
    /// The first rater: the judge, the first annotator or source; `*` for Fleiss.
    pub a: String,
    /// The second rater: `reference` for a judge; `*` for Fleiss.
    pub b: String,
    /// `cnt`, `atr`, `oor`, `oar` or `all` (the four pooled).
    pub metric: String,
    /// Items compared: both sides have a verdict (Fleiss: every annotator has one).
    pub n: u64,
    /// Share of the `n` items with equal verdicts; `None` without items and for Fleiss.
    pub agreement: Option<f64>,
    /// Cohen's kappa (Fleiss' kappa for [`RowKind::Fleiss`]); `None` when undefined.
    pub kappa: Option<f64>,
    /// The bootstrap interval's lower end, when there is one.
    pub kappa_low: Option<f64>,
    /// The bootstrap interval's upper end, when there is one.
    pub kappa_high: Option<f64>,
    /// Why `kappa` is empty.
    pub undefined: Option<String>,
    /// Why the interval is empty although kappa exists (every resample undefined).
    pub interval_undefined: Option<String>,
    /// Resamples on which kappa was undefined, left out of the interval.
    pub resamples_undefined: usize,
    /// Items `a` says satisfied and `b` says satisfied (not for Fleiss).
    pub tt: Option<u64>,
    /// `a` satisfied, `b` not.
    pub tf: Option<u64>,
    /// `a` not, `b` satisfied.
    pub ft: Option<u64>,
    /// Neither.
    pub ff: Option<u64>,
    /// Items both sides have but left out because a verdict is `null` (Fleiss: items some
    /// annotator did not judge or could not tell).
    pub left_out_null: u64,
    /// Items left out because the reference annotators tied.
    pub left_out_tie: u64,
}

/// An item a judge got wrong.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct WrongItem {
    /// The judge.
    pub judge: String,
    /// The item.
    pub scene: String,
    /// Its metric.
    pub metric: FidelityMetric,
    /// Its index.
    pub index: usize,
    /// The spec's text.
    pub spec: String,
    /// The judge's verdict.
    pub verdict: bool,
    /// The reference's verdict.
    pub reference: bool,
}

/// The agreement of the sources: rows, the items each judge got wrong, notes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Agreement {
    /// The reference annotators, when there is a reference.
    pub reference: Vec<String>,
    /// The metrics any item has, in the paper's order.
    pub metrics: Vec<FidelityMetric>,
    /// Every row: judges (or pairs), then annotator pairs, then Fleiss.
    pub rows: Vec<AgreementRow>,
    /// Per judge, the items where its verdict differs from the reference's.
    pub wrong: Vec<WrongItem>,
    /// Items left out of the reference because its annotators tied.
    pub reference_ties: usize,
    /// Resamples per interval, when intervals were computed.
    pub resamples: Option<usize>,
    /// The seed of the intervals.
    pub seed: Option<u64>,
    /// The confidence level of the intervals.
    pub level: Option<f64>,
    /// Everything worth knowing: labels for scenes not in a run, lines replaced.
    pub notes: Vec<String>,
}

/// How to compute the table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AgreementOptions {
    /// The bootstrap of kappa's interval; `None`: no intervals.
    pub bootstrap: Option<Bootstrap>,
}

impl Default for AgreementOptions {
    /// 1000 resamples, seed 20261121, level 0.95.
    fn default() -> Self {
        Self {
            bootstrap: Some(Bootstrap::default()),
        }
    }
}

/// Why the agreement cannot be computed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AgreementError {
    /// A label file is malformed or does not fit a run.
    #[error(transparent)]
    Labels(#[from] LabelError),
    /// A run folder could not be read.
    #[error(transparent)]
    Run(#[from] crate::ReportError),
    /// Two raters have one name.
    #[error(
        "two raters are named {name:?}: {first} and {second} (rename an annotator, or give the runs other folder names)"
    )]
    DuplicateName {
        /// The name.
        name: String,
        /// Where the first is.
        first: String,
        /// Where the second is.
        second: String,
    },
    /// Two runs have different spec texts at one item (other annotations).
    #[error(transparent)]
    RunsDiffer(Box<RunsDiffer>),
    /// Nothing to compare.
    #[error("{0}")]
    Nothing(String),
}

/// Two runs with different spec texts at one item: they used other annotations.
#[derive(Debug, thiserror::Error)]
#[error(
    "{metric} spec {index} of {scene} is {a_text:?} in {a} but {b_text:?} in {b}: the runs used other annotations"
)]
pub struct RunsDiffer {
    /// The first run.
    pub a: String,
    /// The second run.
    pub b: String,
    /// The scene.
    pub scene: String,
    /// The metric.
    pub metric: FidelityMetric,
    /// The index.
    pub index: usize,
    /// The first run's text.
    pub a_text: String,
    /// The second run's text.
    pub b_text: String,
}

impl Run {
    /// The run with its agreement with the annotators of `reference` (their majority per spec),
    /// shown by its report ([`crate::write_report`]: the table on the overview page, the specs
    /// where the run and the people disagree marked on each scene page): the table
    /// [`agreement`] computes for `reference` and this run alone, the numbers `sceneeval
    /// agreement --reference LABELS RUN` prints with the same options. Give the run its final
    /// name ([`Run::with_name`]) first: the table names it.
    ///
    /// # Errors
    /// As [`agreement`]: a label that does not fit the run, nothing to compare.
    pub fn with_labels(
        mut self,
        reference: &[LabelFile],
        options: &AgreementOptions,
    ) -> Result<Run, AgreementError> {
        let table = agreement(reference, &[Source::Run(self.clone())], options)?;
        self.labels = Some(Box::new(table));
        Ok(self)
    }
}

/// One rater: a name, where it comes from, and its verdict on each item it judged.
#[derive(Debug, Clone)]
struct Rater {
    name: String,
    origin: String,
    verdicts: BTreeMap<Item, Option<bool>>,
}

/// The agreement of `sources` with the majority of `reference`'s annotators (or, without
/// reference files, of every pair of sources).
///
/// # Errors
/// A label that does not fit a run ([`AgreementError::Labels`]), two raters with one name,
/// two runs with other spec texts, or nothing to compare ([`AgreementError::Nothing`]: no
/// judge for a reference, fewer than two raters without one).
pub fn agreement(
    reference: &[LabelFile],
    sources: &[Source],
    options: &AgreementOptions,
) -> Result<Agreement, AgreementError> {
    let mut notes = Vec::new();
    let texts = spec_texts(reference, sources, &mut notes)?;
    let reference_raters = merge_annotators(reference.iter());
    let mut judges = Vec::new();
    let label_sources: Vec<&LabelFile> = sources
        .iter()
        .filter_map(|s| match s {
            Source::Labels(f) => Some(f),
            Source::Run(_) => None,
        })
        .collect();
    for source in sources {
        if let Source::Run(run) = source {
            judges.push(run_rater(run));
        }
    }
    judges.extend(merge_annotators(label_sources.into_iter()));
    check_names(reference_raters.iter().chain(&judges))?;
    // The metrics with something to compare: those the reference judged, or, without one,
    // those at least two raters judged (a run's ATR specs that nobody labelled make no row).
    let judged = |r: &Rater, m: FidelityMetric| r.verdicts.keys().any(|i| i.metric == m);
    let metrics: Vec<FidelityMetric> = FidelityMetric::ALL
        .into_iter()
        .filter(|&m| {
            if reference.is_empty() {
                judges.iter().filter(|r| judged(r, m)).count() >= 2
            } else {
                reference_raters.iter().any(|r| judged(r, m))
            }
        })
        .collect();
    let mut table = Agreement {
        reference: reference_raters.iter().map(|r| r.name.clone()).collect(),
        metrics: metrics.clone(),
        rows: Vec::new(),
        wrong: Vec::new(),
        reference_ties: 0,
        resamples: options.bootstrap.map(|b| b.resamples()),
        seed: options.bootstrap.map(|b| b.seed()),
        level: options.bootstrap.map(|b| b.level()),
        notes,
    };
    let scopes: Vec<Option<FidelityMetric>> = metrics.iter().copied().map(Some).chain([None]).collect();
    if reference.is_empty() {
        if judges.len() < 2 {
            return Err(AgreementError::Nothing(format!(
                "{} rater(s) in the sources: without --reference, agreement needs at least two (runs or annotators)",
                judges.len()
            )));
        }
        for (i, a) in judges.iter().enumerate() {
            for b in &judges[i + 1..] {
                let votes = as_decisions(b);
                for &scope in &scopes {
                    table.rows.push(pair_row(
                        RowKind::Pair,
                        a,
                        &b.name,
                        &votes,
                        scope,
                        &metrics,
                        options,
                    ));
                }
            }
        }
        return Ok(table);
    }
    if reference_raters.is_empty() {
        return Err(AgreementError::Nothing(
            "the reference label files hold no label".into(),
        ));
    }
    if judges.is_empty() {
        return Err(AgreementError::Nothing(
            "no judge to measure against the reference: give a run folder or a label file besides --reference".into(),
        ));
    }
    let majority = majority_of(&reference_raters);
    table.reference_ties = majority.values().filter(|d| **d == Decision::Tie).count();
    for judge in &judges {
        for &scope in &scopes {
            table.rows.push(pair_row(
                RowKind::Judge,
                judge,
                "reference",
                &majority,
                scope,
                &metrics,
                options,
            ));
        }
        for (item, verdict) in &judge.verdicts {
            if let (Some(v), Some(Decision::Verdict(r))) = (verdict, majority.get(item))
                && v != r
                && metrics.contains(&item.metric)
            {
                table.wrong.push(WrongItem {
                    judge: judge.name.clone(),
                    scene: item.scene.clone(),
                    metric: item.metric,
                    index: item.index,
                    spec: texts.get(item).cloned().unwrap_or_default(),
                    verdict: *v,
                    reference: *r,
                });
            }
        }
    }
    for (i, a) in reference_raters.iter().enumerate() {
        for b in &reference_raters[i + 1..] {
            let votes = as_decisions(b);
            for &scope in &scopes {
                table.rows.push(pair_row(
                    RowKind::Annotators,
                    a,
                    &b.name,
                    &votes,
                    scope,
                    &metrics,
                    options,
                ));
            }
        }
    }
    if reference_raters.len() >= 2 {
        for &scope in &scopes {
            table
                .rows
                .push(fleiss_row(&reference_raters, scope, &metrics, options));
        }
    }
    Ok(table)
}

/// Every spec's text, checked: each label file against each run, the runs against each
/// other, and label files against each other. Labels for scenes a run has no verdicts for are
/// noted.
fn spec_texts(
    reference: &[LabelFile],
    sources: &[Source],
    notes: &mut Vec<String>,
) -> Result<BTreeMap<Item, String>, AgreementError> {
    let runs: Vec<&Run> = sources
        .iter()
        .filter_map(|s| match s {
            Source::Run(r) => Some(r),
            Source::Labels(_) => None,
        })
        .collect();
    let files: Vec<&LabelFile> = reference
        .iter()
        .chain(sources.iter().filter_map(|s| match s {
            Source::Labels(f) => Some(f),
            Source::Run(_) => None,
        }))
        .collect();
    let mut texts: BTreeMap<Item, (String, String)> = BTreeMap::new();
    for run in &runs {
        for (item, (text, _)) in run_items(run) {
            match texts.get(&item) {
                Some((other, origin)) if *other != text => {
                    return Err(AgreementError::RunsDiffer(Box::new(RunsDiffer {
                        a: origin.clone(),
                        b: run.dir.display().to_string(),
                        scene: item.scene,
                        metric: item.metric,
                        index: item.index,
                        a_text: other.clone(),
                        b_text: text,
                    })));
                }
                Some(_) => {}
                None => {
                    texts.insert(item, (text, run.dir.display().to_string()));
                }
            }
        }
    }
    for file in &files {
        for run in &runs {
            let outside = file.check_run(run)?;
            if !outside.is_empty() {
                notes.push(format!(
                    "{}: labels for {} scene(s) without fidelity verdicts in {} (not in the run, failed, or the metric not run), left out of its rows: {}",
                    file.path.display(),
                    outside.len(),
                    run.name,
                    outside.join(", ")
                ));
            }
        }
        if file.replaced > 0 {
            notes.push(format!(
                "{}: {} line(s) replaced by a later line for the same annotator and spec",
                file.path.display(),
                file.replaced
            ));
        }
        for line in &file.labels {
            let label = &line.label;
            match texts.get(&label.item()) {
                Some((other, origin)) if *other != label.spec => {
                    return Err(LabelError::SpecDiffers(Box::new(SpecDiffers {
                        path: file.path.clone(),
                        line: line.line,
                        source_name: origin.clone(),
                        scene: label.scene.clone(),
                        metric: label.metric,
                        index: label.index,
                        expected: other.clone(),
                        found: label.spec.clone(),
                    }))
                    .into());
                }
                Some(_) => {}
                None => {
                    texts.insert(
                        label.item(),
                        (
                            label.spec.clone(),
                            format!("{}:{}", file.path.display(), line.line),
                        ),
                    );
                }
            }
        }
    }
    Ok(texts.into_iter().map(|(k, (t, _))| (k, t)).collect())
}

/// Every spec of a run's evaluated scenes with its text and verdict.
fn run_items(run: &Run) -> Vec<(Item, (String, Option<bool>))> {
    let mut out = Vec::new();
    for record in &run.records {
        let Some(fidelity) = record.report().and_then(|r| r.fidelity.as_ref()) else {
            continue;
        };
        for metric in FidelityMetric::ALL {
            for (index, (text, verdict)) in fidelity.verdicts(metric).into_iter().enumerate() {
                let item = Item {
                    scene: record.scene.as_str().to_owned(),
                    metric,
                    index,
                };
                out.push((item, (text.to_owned(), verdict)));
            }
        }
    }
    out
}

/// A run as a rater.
fn run_rater(run: &Run) -> Rater {
    Rater {
        name: run.name.clone(),
        origin: run.dir.display().to_string(),
        verdicts: run_items(run).into_iter().map(|(i, (_, v))| (i, v)).collect(),
    }
}

/// The annotators of `files`, one rater each, in the order of their first label; a later
/// file's label for the same annotator and item replaces an earlier file's.
fn merge_annotators<'f>(files: impl Iterator<Item = &'f LabelFile>) -> Vec<Rater> {
    let mut raters: Vec<Rater> = Vec::new();
    for file in files {
        for line in &file.labels {
            let label = &line.label;
            let k = match raters.iter().position(|r| r.name == label.annotator) {
                Some(k) => k,
                None => {
                    raters.push(Rater {
                        name: label.annotator.clone(),
                        origin: file.path.display().to_string(),
                        verdicts: BTreeMap::new(),
                    });
                    raters.len() - 1
                }
            };
            raters[k].verdicts.insert(label.item(), label.satisfied);
        }
    }
    raters
}

/// Refuses two raters with one name (and the names the table reserves).
fn check_names<'r>(raters: impl Iterator<Item = &'r Rater>) -> Result<(), AgreementError> {
    let mut seen: BTreeMap<&str, &str> = BTreeMap::new();
    for r in raters {
        if r.name == "reference" || r.name == "*" {
            return Err(AgreementError::Nothing(format!(
                "{}: the name {:?} is reserved for the table; rename the annotator",
                r.origin, r.name
            )));
        }
        if let Some(first) = seen.insert(&r.name, &r.origin) {
            return Err(AgreementError::DuplicateName {
                name: r.name.clone(),
                first: first.to_owned(),
                second: r.origin.clone(),
            });
        }
    }
    Ok(())
}

/// The majority of `raters` on every item any of them judged.
fn majority_of(raters: &[Rater]) -> BTreeMap<Item, Decision> {
    let items: BTreeSet<&Item> = raters.iter().flat_map(|r| r.verdicts.keys()).collect();
    items
        .into_iter()
        .map(|item| {
            let votes = raters.iter().filter_map(|r| r.verdicts.get(item).copied());
            (item.clone(), Majority::of(votes).decision())
        })
        .collect()
}

/// A rater's verdicts as decisions (no verdict: no votes).
fn as_decisions(r: &Rater) -> BTreeMap<Item, Decision> {
    r.verdicts
        .iter()
        .map(|(i, v)| (i.clone(), v.map_or(Decision::NoVotes, Decision::Verdict)))
        .collect()
}

/// The metric's name, or `all`.
fn scope_name(scope: Option<FidelityMetric>) -> String {
    scope.map_or_else(|| "all".to_owned(), |m| m.name().to_owned())
}

/// Whether an item of `metric` counts in a row of `scope` (`None`: all of the table's
/// `metrics`).
fn in_scope(scope: Option<FidelityMetric>, metrics: &[FidelityMetric], metric: FidelityMetric) -> bool {
    scope.map_or_else(|| metrics.contains(&metric), |m| m == metric)
}

/// Cohen's kappa of `a` against `b`'s decisions on the items of `scope` both have.
fn pair_row(
    kind: RowKind,
    a: &Rater,
    b_name: &str,
    b: &BTreeMap<Item, Decision>,
    scope: Option<FidelityMetric>,
    metrics: &[FidelityMetric],
    options: &AgreementOptions,
) -> AgreementRow {
    let mut pairs = Vec::new();
    let (mut null, mut tie) = (0, 0);
    for (item, verdict) in &a.verdicts {
        if !in_scope(scope, metrics, item.metric) {
            continue;
        }
        match (verdict, b.get(item)) {
            (_, None) => {}
            (_, Some(Decision::Tie)) => tie += 1,
            (None, Some(_)) | (Some(_), Some(Decision::NoVotes)) => null += 1,
            (Some(x), Some(Decision::Verdict(y))) => pairs.push((*x, *y)),
        }
    }
    let table = Confusion::binary(pairs.iter().copied());
    let interval = options.bootstrap.map(|b| b.cohen_kappa_binary(&pairs));
    let mut row = row_of(kind, &a.name, b_name, scope, table.n(), table.kappa(), interval);
    row.agreement = table.agreement();
    // Binary categories: 0 = false, 1 = true; `count(a, b)`.
    row.tt = Some(table.count(1, 1));
    row.tf = Some(table.count(1, 0));
    row.ft = Some(table.count(0, 1));
    row.ff = Some(table.count(0, 0));
    row.left_out_null = null;
    row.left_out_tie = tie;
    row
}

/// Fleiss' kappa of `raters` over the items of `scope` every one of them judged (not null).
fn fleiss_row(
    raters: &[Rater],
    scope: Option<FidelityMetric>,
    metrics: &[FidelityMetric],
    options: &AgreementOptions,
) -> AgreementRow {
    let items: BTreeSet<&Item> = raters
        .iter()
        .flat_map(|r| r.verdicts.keys())
        .filter(|i| in_scope(scope, metrics, i.metric))
        .collect();
    let mut counts: Vec<[u64; 2]> = Vec::new();
    let mut left_out = 0;
    for item in items {
        let votes: Option<Vec<bool>> = raters
            .iter()
            .map(|r| r.verdicts.get(item).copied().flatten())
            .collect();
        match votes {
            Some(votes) => {
                let yes = votes.iter().filter(|v| **v).count() as u64;
                counts.push([votes.len() as u64 - yes, yes]);
            }
            None => left_out += 1,
        }
    }
    let kappa = |rows: &[[u64; 2]]| -> Result<f64, Undefined> {
        if rows.is_empty() {
            return Err(Undefined::NoItems);
        }
        // Every row sums to the number of raters: the table always builds.
        FleissTable::from_counts(rows).map_or(Err(Undefined::NoItems), |t| t.kappa())
    };
    let interval = options.bootstrap.map(|b| {
        b.interval(counts.len(), |drawn| {
            let rows: Vec<[u64; 2]> = drawn.iter().map(|&i| counts[i]).collect();
            kappa(&rows).ok()
        })
    });
    let mut row = row_of(
        RowKind::Fleiss,
        "*",
        "*",
        scope,
        counts.len() as u64,
        kappa(&counts),
        interval,
    );
    row.left_out_null = left_out;
    row
}

/// A row with its kappa and interval; counts empty.
fn row_of(
    kind: RowKind,
    a: &str,
    b: &str,
    scope: Option<FidelityMetric>,
    n: u64,
    kappa: Result<f64, Undefined>,
    interval: Option<BootstrapInterval>,
) -> AgreementRow {
    let (low, high, interval_undefined, resamples_undefined) = match (&kappa, interval) {
        (Ok(_), Some(i)) => match i.bounds {
            Ok([l, h]) => (Some(l), Some(h), None, i.undefined),
            Err(why) => (None, None, Some(why.to_string()), i.undefined),
        },
        (_, Some(i)) => (None, None, None, i.undefined),
        (_, None) => (None, None, None, 0),
    };
    AgreementRow {
        kind,
        a: a.to_owned(),
        b: b.to_owned(),
        metric: scope_name(scope),
        n,
        agreement: None,
        kappa: kappa.ok(),
        kappa_low: low,
        kappa_high: high,
        undefined: kappa.err().map(|e| e.to_string()),
        interval_undefined,
        resamples_undefined,
        tt: None,
        tf: None,
        ft: None,
        ff: None,
        left_out_null: 0,
        left_out_tie: 0,
    }
}

#[cfg(test)]
mod tests;
