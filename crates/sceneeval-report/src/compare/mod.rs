//! Tables across runs: one row per run, one column per metric column the runs share, ranks and
//! rank points, written as Markdown, CSV, LaTeX or HTML.
//!
//! [`compare`] checks comparability before it puts numbers side by side: runs are compared only
//! on the scenes every run evaluated in full (not missing, failed or partial in any run: a
//! partial record lacks a shared geometry metric, or a shared fidelity metric although the scene
//! had an annotation row), with the same annotation row, and on the metrics every run ran; every difference (scenes left out and why, metrics not shared, different
//! plans, presets or tool versions) is a note printed under the table.
//!
//! Every table names, per run, the scenes it lacks or failed among every scene of any run
//! ([`Coverage`]); with [`FailedScenes::Worst`] the values are computed over every scene of any
//! run instead, a failed or missing scene at the column's worst value. A column no run has a
//! value in is left out, with a note.
//!
//! **Ranks** per column, among the runs with a value, in the metric's direction
//! ([`sceneeval_results::Metric::better`]): by default ([`RankBy::Tested`]) 1 + the number of
//! runs better by a paired Wilcoxon signed-rank test on the scenes both have, Holm-adjusted
//! across the pair's columns, below alpha, so runs no test separates share a rank;
//! [`RankBy::Mean`] gives competition ranks ("1224": runs with equal values, as printed with
//! two decimals, share the best rank). A run ranked `r` of the `N` runs with a value gets
//! `N - r + 1` points; a run's total is the sum over columns, its average rank the mean of its
//! ranks, and its places the number of columns where it is first, second and third. The best
//! value is bold, the second italic, whatever the ranking.
//!
//! **Paired comparisons** ([`CompareOptions::paired`]): per pair of runs and column, the
//! scenes both evaluated, the mean difference `b - a` with its paired bootstrap interval, the
//! Wilcoxon p-value and Holm's adjustment across the pair's columns, and McNemar's exact test
//! on the fidelity verdicts ([`PairComparison`]); every statistic from `sceneeval-stats`.

mod paired;
pub(crate) mod paired_text;
mod rank;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_paired;
mod text;

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use sceneeval_fidelity::FidelityReport;
use sceneeval_results::{Better, GroupSummary, Metric, Outcome, SceneName, difficulty_groups};
use sceneeval_stats::bootstrap::{Bootstrap, DEFAULT_RESAMPLES};

pub use paired::{PairComparison, PairedRow, Pairing, SceneDifference, VerdictRow};
pub use paired_text::{PAIRED_CSV_COLUMNS, PairedRecord};
pub use rank::{RankBy, competition_ranks};
pub(crate) use text::{Emphasis, arrow as text_arrow, average, scenes, standing_order};

use crate::ReportError;
use crate::run::{Run, group_summary, metrics_in, scene_order, scene_values, summary_columns};

/// How to compare.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareOptions {
    /// One table per difficulty after the table of every scene (`--by difficulty`).
    pub by_difficulty: bool,
    /// A bootstrap confidence interval per value at this level (`--ci 0.95`); also the level
    /// of the paired differences' intervals ([`DEFAULT_LEVEL`] when `None`).
    pub ci: Option<f64>,
    /// Paired comparisons of these pairs of runs (`--paired`, `--against-first`).
    pub paired: Option<Pairing>,
    /// How runs are ranked (`--rank`).
    pub rank: RankBy,
    /// The significance level of the tested ranks and the tables' marks (`--alpha`).
    pub alpha: f64,
    /// How a run's failed and missing scenes count in its means (`--failed`).
    pub failed: FailedScenes,
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self {
            by_difficulty: false,
            ci: None,
            paired: None,
            rank: RankBy::Tested,
            alpha: DEFAULT_ALPHA,
            failed: FailedScenes::Skip,
        }
    }
}

/// The significance level unless asked otherwise.
pub const DEFAULT_ALPHA: f64 = 0.05;

/// The confidence level of the paired differences' intervals unless `--ci` gives one.
pub const DEFAULT_LEVEL: f64 = 0.95;

/// How a run's failed and missing scenes count in its per-run means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FailedScenes {
    /// The values are computed over the scenes every run evaluated in full; the others are
    /// named in the notes and under every table.
    #[default]
    Skip,
    /// Over every scene of any run: a scene a run failed or lacks counts at the column's worst
    /// value (0 % where higher is better, 100 % where lower is better) wherever another run has
    /// a value for it, so a method that crashes on hard prompts does not skip them.
    Worst,
}

/// The comparison of several runs: what every output format writes.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The runs, in the order given.
    pub runs: Vec<RunHead>,
    /// The columns every run has, in the summary's order.
    pub columns: Vec<Column>,
    /// The table of every common scene, then one per difficulty when asked.
    pub tables: Vec<Table>,
    /// The scenes the values are computed over: evaluated in full by every run.
    pub scenes: Vec<String>,
    /// What is not comparable and was left out, one sentence each; empty when the runs are
    /// comparable as they are.
    pub notes: Vec<String>,
    /// The confidence level of the intervals, when computed.
    pub ci: Option<f64>,
    /// Per common scene and fidelity spec, the verdicts when they differ between runs.
    pub differences: Vec<SpecDifference>,
    /// Per run, the scenes it lacks or failed among every scene of any run, one sentence each
    /// ("B: 2 of 20 scenes missing (scene_0, scene_1)"), printed under every table.
    pub coverage: Vec<Coverage>,
    /// The paired comparisons, when asked (`--paired`).
    pub pairs: Vec<PairComparison>,
    /// The confidence level of the paired differences' intervals.
    pub paired_level: f64,
    /// The significance level of the tested ranks and the marks.
    pub alpha: f64,
    /// How the ranks were made.
    pub rank: RankBy,
    /// How failed and missing scenes counted.
    pub failed: FailedScenes,
}

/// A run's scenes against every scene of any run.
#[derive(Debug, Clone, PartialEq)]
pub struct Coverage {
    /// The run's index.
    pub run: usize,
    /// Every scene of any run.
    pub total: usize,
    /// Scenes the run has no record of (or an unreadable one).
    pub missing: Vec<String>,
    /// Scenes the run failed.
    pub failed: Vec<String>,
}

impl Coverage {
    /// "B: 2 of 20 scenes missing (scene_0, scene_1), 1 failed (scene_3)" or "A: all 20 scenes".
    pub fn sentence(&self, name: &str) -> String {
        let names = |v: &[String]| {
            let shown: Vec<&str> = v.iter().take(MAX_LISTED).map(String::as_str).collect();
            let more = v.len() - shown.len();
            format!(
                "{}{}",
                shown.join(", "),
                if more > 0 {
                    format!(" and {more} more")
                } else {
                    String::new()
                }
            )
        };
        let mut parts = Vec::new();
        if !self.missing.is_empty() {
            parts.push(format!(
                "{} of {} missing ({})",
                self.missing.len(),
                scenes(self.total),
                names(&self.missing)
            ));
        }
        if !self.failed.is_empty() {
            let of = if parts.is_empty() {
                format!(" of {}", scenes(self.total))
            } else {
                String::new()
            };
            parts.push(format!(
                "{}{of} failed ({})",
                self.failed.len(),
                names(&self.failed)
            ));
        }
        if parts.is_empty() {
            format!("{name}: all {}", scenes(self.total))
        } else {
            format!("{name}: {}", parts.join(", "))
        }
    }
}

/// A run of a [`Comparison`].
#[derive(Debug, Clone, PartialEq)]
pub struct RunHead {
    /// Its name.
    pub name: String,
    /// Its folder.
    pub dir: PathBuf,
}

/// A column of a [`Comparison`]: a summary column and which way it improves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Column {
    /// The summary column (`CNT`, `COL_ob`, ...).
    pub name: &'static str,
    /// Its metric.
    pub metric: Metric,
    /// Which way it improves.
    pub better: Better,
}

/// One table: a group of the common scenes (every scene, or one difficulty).
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// `all` or the difficulty.
    pub group: String,
    /// Common scenes in the group.
    pub scenes: usize,
    /// `cells[run][column]`.
    pub cells: Vec<Vec<Cell>>,
    /// Each run's ranking over the columns, in run order.
    pub standings: Vec<Standing>,
}

/// One value of a [`Table`].
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// The macro average in percent, as `summary.csv` computes it over the group's common
    /// scenes; `None` when no scene has a value.
    pub value: Option<f64>,
    /// The scenes behind the value (those with a value for the column).
    pub n: usize,
    /// The run's rank in the column, when it has a value ([`RankBy`]).
    pub rank: Option<usize>,
    /// The competition rank of the value as printed, which the emphasis follows (bold: best
    /// value, italic: second), whatever the ranking.
    pub value_rank: Option<usize>,
    /// Its points, `N - rank + 1` (0 without a value).
    pub points: usize,
    /// The bootstrap interval, when asked and there is a value.
    pub ci: Option<[f64; 2]>,
}

/// A run's ranking over a [`Table`]'s columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Standing {
    /// Total points.
    pub points: usize,
    /// Mean rank over the columns where the run is ranked.
    pub average_rank: Option<f64>,
    /// Columns where the run is first, second, third.
    pub places: [usize; 3],
    /// Its place by total points (competition ranking, higher points first).
    pub place: usize,
}

/// A fidelity spec of a common scene whose verdict differs between runs.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecDifference {
    /// The scene.
    pub scene: String,
    /// The metric (CNT, ATR, OOR, OAR).
    pub metric: Metric,
    /// The spec as written in the annotation row.
    pub spec: String,
    /// Per run, in run order.
    pub verdicts: Vec<Verdict>,
}

/// A fidelity spec's verdict in one run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Satisfied.
    Satisfied,
    /// Not satisfied.
    NotSatisfied,
    /// Not judged (an attribute without a VLM, an unanswered question).
    NotJudged,
}

impl Verdict {
    /// `satisfied`, `not satisfied`, `not judged`.
    pub const fn name(self) -> &'static str {
        match self {
            Verdict::Satisfied => "satisfied",
            Verdict::NotSatisfied => "not satisfied",
            Verdict::NotJudged => "not judged",
        }
    }

    fn of(satisfied: Option<bool>) -> Verdict {
        match satisfied {
            Some(true) => Verdict::Satisfied,
            Some(false) => Verdict::NotSatisfied,
            None => Verdict::NotJudged,
        }
    }
}

/// The most scenes a note names before it counts the rest.
const MAX_LISTED: usize = 12;

/// Compares `runs`.
///
/// # Errors
/// [`ReportError::NoRuns`] without runs; [`ReportError::ConfidenceLevel`] for a level outside
/// (0, 1); [`ReportError::Alpha`] for a significance level outside (0, 1).
pub fn compare(runs: &[Run], options: &CompareOptions) -> Result<Comparison, ReportError> {
    if runs.is_empty() {
        return Err(ReportError::NoRuns);
    }
    if let Some(level) = options.ci
        && !(level > 0.0 && level < 1.0)
    {
        return Err(ReportError::ConfidenceLevel(level));
    }
    if !(options.alpha > 0.0 && options.alpha < 1.0) {
        return Err(ReportError::Alpha(options.alpha));
    }
    let mut notes = Vec::new();

    // Columns: the metrics every run ran; scenes: those every run evaluated in full.
    let metrics: Vec<Vec<Metric>> = runs.iter().map(Run::metrics).collect();
    let (shared, mut columns) = shared_columns(runs, &metrics, &mut notes);
    same_everywhere(runs, &mut notes);
    unreadable_records(runs, &mut notes);
    let all_scenes = every_scene(runs);
    let coverage = coverage(runs, &all_scenes);
    let common = common_scenes(runs, &metrics, &shared, &all_scenes, options.failed, &mut notes);
    // The scenes of the tables: the common ones, or every scene when failures count as worst.
    let scenes: Vec<String> = match options.failed {
        FailedScenes::Skip => common,
        FailedScenes::Worst => all_scenes.iter().map(|s| s.as_str().to_owned()).collect(),
    };
    let difficulty = difficulties(runs, &scenes, &mut notes);
    let names: Vec<&str> = scenes.iter().map(String::as_str).collect();
    let mut grouped = difficulty_groups(&names, |s| difficulty.get(s).copied());
    if !options.by_difficulty {
        grouped.truncate(1);
    } else if grouped.len() == 1 {
        notes.push(
            "No run has difficulties (neither in its summary_scenes.csv nor from the annotations given): only the table \
             of every scene."
                .to_owned(),
        );
    }

    // Per run and scene, the scene's own numbers (for the number of scenes and intervals).
    let per_scene: Vec<BTreeMap<&str, GroupSummary>> = runs
        .iter()
        .map(|run| {
            names
                .iter()
                .filter_map(|s| Some((*s, scene_values(run.record(s)?))))
                .collect()
        })
        .collect();
    let mut tables: Vec<Table> = grouped
        .into_iter()
        .map(|(group, members)| {
            let values = TableValues {
                runs,
                columns: &columns,
                per_scene: &per_scene,
                members: &members,
                failed: options.failed,
            };
            table(&values, group, options)
        })
        .collect();
    drop_empty_columns(&mut columns, &mut tables, &mut notes);

    let differences = differences(runs, &names, &shared);
    let paired_level = options.ci.unwrap_or(DEFAULT_LEVEL);
    let pairs = options.paired.map_or_else(Vec::new, |pairing| {
        pairing
            .pairs(runs.len())
            .into_iter()
            .map(|(a, b)| paired::compare_pair(runs, a, b, &columns, paired_level))
            .collect()
    });
    Ok(Comparison {
        runs: runs
            .iter()
            .map(|r| RunHead {
                name: r.name.clone(),
                dir: r.dir.clone(),
            })
            .collect(),
        columns,
        tables,
        scenes,
        notes,
        ci: options.ci,
        differences,
        coverage,
        pairs,
        paired_level,
        alpha: options.alpha,
        rank: options.rank,
        failed: options.failed,
    })
}

/// Every scene of any run, read or not, in scene order.
fn every_scene(runs: &[Run]) -> Vec<&SceneName> {
    let mut all: Vec<&SceneName> = runs
        .iter()
        .flat_map(|r| {
            r.records
                .iter()
                .map(|r| &r.scene)
                .chain(r.unreadable.iter().map(|u| &u.scene))
        })
        .collect();
    all.sort_by(|a, b| scene_order(a, b));
    all.dedup();
    all
}

/// Each run's missing and failed scenes among `all`.
fn coverage(runs: &[Run], all: &[&SceneName]) -> Vec<Coverage> {
    runs.iter()
        .enumerate()
        .map(|(k, run)| {
            let mut missing = Vec::new();
            let mut failed = Vec::new();
            for scene in all {
                match run.record(scene.as_str()) {
                    None => missing.push(scene.as_str().to_owned()),
                    Some(r) if matches!(r.outcome, Outcome::Failed { .. }) => {
                        failed.push(scene.as_str().to_owned());
                    }
                    Some(_) => {}
                }
            }
            Coverage {
                run: k,
                total: all.len(),
                missing,
                failed,
            }
        })
        .collect()
}

/// Leaves out the columns no run has a value in, in any table, with a note.
fn drop_empty_columns(columns: &mut Vec<Column>, tables: &mut [Table], notes: &mut Vec<String>) {
    let empty: Vec<usize> = (0..columns.len())
        .filter(|&k| {
            tables
                .iter()
                .all(|t| t.cells.iter().all(|row| row[k].value.is_none()))
        })
        .collect();
    if empty.is_empty() {
        return;
    }
    let names: Vec<&str> = empty.iter().map(|&k| columns[k].name).collect();
    notes.push(format!(
        "{} left out: no run has a value in {}.",
        list(&names),
        if names.len() == 1 { "it" } else { "them" }
    ));
    for &k in empty.iter().rev() {
        columns.remove(k);
        for t in tables.iter_mut() {
            for row in &mut t.cells {
                row.remove(k);
            }
        }
    }
}
/// The metrics every run ran (a note for each one some runs lack) and their summary columns.
fn shared_columns(
    runs: &[Run],
    metrics: &[Vec<Metric>],
    notes: &mut Vec<String>,
) -> (BTreeSet<Metric>, Vec<Column>) {
    let shared: BTreeSet<Metric> = Metric::ALL
        .into_iter()
        .filter(|m| metrics.iter().all(|ms| ms.contains(m)))
        .collect();
    for m in Metric::ALL {
        let missing: Vec<&str> = runs
            .iter()
            .zip(metrics)
            .filter(|(_, ms)| !ms.contains(&m))
            .map(|(r, _)| r.name.as_str())
            .collect();
        if !missing.is_empty() && missing.len() < runs.len() {
            notes.push(format!(
                "{} ({}) left out: not evaluated by {}.",
                m.columns().join(", "),
                m.name(),
                list(&missing)
            ));
        }
    }
    let columns: Vec<Column> = summary_columns()
        .into_iter()
        .filter(|(_, m)| shared.contains(m))
        .map(|(name, metric)| Column {
            name,
            metric,
            better: metric.better(),
        })
        .collect();
    (shared, columns)
}

/// A note per run with records that could not be read: each file and why (the first
/// [`MAX_LISTED`]).
fn unreadable_records(runs: &[Run], notes: &mut Vec<String>) {
    for run in runs.iter().filter(|r| !r.unreadable.is_empty()) {
        let listed: Vec<String> = run
            .unreadable
            .iter()
            .take(MAX_LISTED)
            .map(|u| format!("{} ({})", u.path.display(), u.reason))
            .collect();
        let more = run.unreadable.len() - listed.len();
        notes.push(format!(
            "{}: {} record(s) could not be read, their scenes are left out: {}{}.",
            run.name,
            run.unreadable.len(),
            listed.join("; "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ));
    }
}

/// The scenes every run evaluated in full (every shared metric) with one annotation row, in
/// scene order; a note names the others and why (with `--failed worst`, a note says how they
/// count instead).
fn common_scenes(
    runs: &[Run],
    metrics: &[Vec<Metric>],
    shared: &BTreeSet<Metric>,
    all_scenes: &[&SceneName],
    failed: FailedScenes,
    notes: &mut Vec<String>,
) -> Vec<String> {
    let fidelity_shared = shared.iter().any(|m| m.fidelity().is_some());
    let mut left_out: Vec<String> = Vec::new();
    let mut scenes: Vec<String> = Vec::new();
    for &name in all_scenes {
        let scene = name.as_str();
        let mut why = Vec::new();
        let mut digests = BTreeSet::new();
        for (run, run_metrics) in runs.iter().zip(metrics) {
            match run.record(scene).map(|r| (&r.outcome, r)) {
                None if run.unreadable.iter().any(|u| u.scene == *name) => {
                    why.push(format!("unreadable in {}", run.name));
                }
                None => why.push(format!("not in {}", run.name)),
                Some((Outcome::Failed { .. }, _)) => why.push(format!("failed in {}", run.name)),
                Some((Outcome::Ok { report } | Outcome::Partial { report }, r)) => {
                    let have = metrics_in(report);
                    // A scene without an annotation row has no fidelity specs, hence no
                    // fidelity section: that is not a partial result.
                    let row = r.fingerprint.as_ref().is_some_and(|f| f.annotation.is_some());
                    let lacking: Vec<&str> = run_metrics
                        .iter()
                        .filter(|m| {
                            shared.contains(m) && !have.contains(m) && (m.fidelity().is_none() || row)
                        })
                        .map(|m| m.name())
                        .collect();
                    if !lacking.is_empty() {
                        why.push(format!("partial in {}: no {}", run.name, lacking.join(", ")));
                    }
                    if let Some(d) = r.fingerprint.as_ref().and_then(|f| f.annotation.as_deref()) {
                        digests.insert(d);
                    }
                }
            }
        }
        if fidelity_shared && digests.len() > 1 {
            why.push("its annotation row differs between the runs".to_owned());
        }
        if why.is_empty() {
            scenes.push(scene.to_owned());
        } else {
            left_out.push(format!("{scene} ({})", why.join("; ")));
        }
    }
    if !left_out.is_empty() && failed == FailedScenes::Worst {
        notes.push(format!(
            "Values over every scene of any run ({}): a scene a run failed or lacks counts at the column's worst value \
             (0 where higher is better, 100 where lower is better) wherever another run has a value; a metric a \
             scene could not compute (partial) is left out of that run's mean.",
            all_scenes.len()
        ));
    } else if !left_out.is_empty() {
        let total = scenes.len() + left_out.len();
        let shown = left_out.len().min(MAX_LISTED);
        let more = left_out.len() - shown;
        notes.push(format!(
            "Compared on the {} of {total} scenes every run evaluated in full; left out: {}{}.",
            scenes.len(),
            left_out[..shown].join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ));
    }
    scenes
}

/// Each scene's difficulty (the first run's that has one); a note names the scenes the runs
/// disagree on.
fn difficulties<'r>(
    runs: &'r [Run],
    scenes: &'r [String],
    notes: &mut Vec<String>,
) -> BTreeMap<&'r str, &'r str> {
    let mut difficulty: BTreeMap<&str, &str> = BTreeMap::new();
    let mut disagree = Vec::new();
    for scene in scenes {
        let said: BTreeSet<&str> = runs.iter().filter_map(|r| r.difficulty(scene)).collect();
        if let Some(d) = runs.iter().find_map(|r| r.difficulty(scene)) {
            difficulty.insert(scene, d);
        }
        if said.len() > 1 {
            disagree.push(scene.as_str());
        }
    }
    if !disagree.is_empty() {
        notes.push(format!(
            "The runs give different difficulties to {}; the first run's is used.",
            list(&disagree)
        ));
    }
    difficulty
}

/// The percentile bootstrap interval at `level` of the mean of a cell's per-scene values:
/// `sceneeval-stats`' seeded bootstrap ([`Bootstrap::mean`], 1000 resamples, seed 20261121).
/// `None` without values.
fn mean_interval(values: &[f64], level: f64) -> Option<[f64; 2]> {
    let bootstrap = Bootstrap::new(DEFAULT_RESAMPLES, level).ok()?;
    bootstrap.mean(values).ok()?.bounds.ok()
}

/// What a table is computed from.
struct TableValues<'a> {
    runs: &'a [Run],
    columns: &'a [Column],
    per_scene: &'a [BTreeMap<&'a str, GroupSummary>],
    members: &'a [&'a str],
    failed: FailedScenes,
}

impl TableValues<'_> {
    /// Per run, the values of column `k` on the members (`None`: no value), failed and missing
    /// scenes at the worst value with [`FailedScenes::Worst`] where another run has a value.
    fn column(&self, k: usize) -> Vec<Vec<Option<f64>>> {
        let name = self.columns[k].name;
        let mut values: Vec<Vec<Option<f64>>> = self
            .per_scene
            .iter()
            .map(|scenes| {
                self.members
                    .iter()
                    .map(|s| scenes.get(s).and_then(|v| v.value(name)))
                    .collect()
            })
            .collect();
        if self.failed == FailedScenes::Worst {
            let worst = match self.columns[k].better {
                Better::Higher => 0.0,
                Better::Lower => 100.0,
            };
            for (i, scene) in self.members.iter().enumerate() {
                if !values.iter().any(|v| v[i].is_some()) {
                    continue;
                }
                for (run, v) in self.runs.iter().zip(values.iter_mut()) {
                    let lacks = run
                        .record(scene)
                        .is_none_or(|r| matches!(r.outcome, Outcome::Failed { .. }));
                    if lacks {
                        v[i] = Some(worst);
                    }
                }
            }
        }
        values
    }
}

/// One group's table.
fn table(values: &TableValues<'_>, group: String, options: &CompareOptions) -> Table {
    let (runs, columns, members) = (values.runs, values.columns, values.members);
    let per_column: Vec<Vec<Vec<Option<f64>>>> = (0..columns.len()).map(|k| values.column(k)).collect();
    let mut cells: Vec<Vec<Cell>> = runs
        .iter()
        .enumerate()
        .map(|(r, run)| {
            let summary = group_summary(&group, members.iter().filter_map(|s| run.record(s)));
            columns
                .iter()
                .enumerate()
                .map(|(k, c)| {
                    let scene_values: Vec<f64> = per_column[k][r].iter().flatten().copied().collect();
                    let value = match options.failed {
                        FailedScenes::Skip => summary.value(c.name),
                        FailedScenes::Worst => (!scene_values.is_empty())
                            .then(|| scene_values.iter().sum::<f64>() / scene_values.len() as f64),
                    };
                    Cell {
                        value,
                        n: scene_values.len(),
                        rank: None,
                        value_rank: None,
                        points: 0,
                        ci: options
                            .ci
                            .and_then(|level| value.and(mean_interval(&scene_values, level))),
                    }
                })
                .collect()
        })
        .collect();
    let tested =
        (options.rank == RankBy::Tested).then(|| rank::tested_ranks(&per_column, columns, options.alpha));
    for (k, column) in columns.iter().enumerate() {
        let printed: Vec<Option<f64>> = cells
            .iter()
            .map(|row| row[k].value.map(rank::as_printed))
            .collect();
        let by_value = competition_ranks(&printed, column.better);
        let ranked = by_value.iter().flatten().count();
        for (r, (row, value_rank)) in cells.iter_mut().zip(by_value).enumerate() {
            let rank = match &tested {
                Some(t) => value_rank.and(t[k][r]),
                None => value_rank,
            };
            row[k].value_rank = value_rank;
            row[k].rank = rank;
            row[k].points = rank.map_or(0, |r| ranked + 1 - r);
        }
    }
    let mut standings: Vec<Standing> = cells
        .iter()
        .map(|row| {
            let ranks: Vec<usize> = row.iter().filter_map(|c| c.rank).collect();
            let mut places = [0; 3];
            for &r in &ranks {
                if (1..=3).contains(&r) {
                    places[r - 1] += 1;
                }
            }
            Standing {
                points: row.iter().map(|c| c.points).sum(),
                average_rank: (!ranks.is_empty())
                    .then(|| ranks.iter().sum::<usize>() as f64 / ranks.len() as f64),
                places,
                place: 0,
            }
        })
        .collect();
    let points: Vec<Option<f64>> = standings.iter().map(|s| Some(s.points as f64)).collect();
    for (s, place) in standings
        .iter_mut()
        .zip(competition_ranks(&points, Better::Higher))
    {
        s.place = place.unwrap_or(0);
    }
    Table {
        group,
        scenes: members.len(),
        cells,
        standings,
    }
}

/// Notes for what should be the same in every run and is not: the plan, the preset, the tool.
fn same_everywhere(runs: &[Run], notes: &mut Vec<String>) {
    type Get = fn(&sceneeval_results::Fingerprint) -> Option<String>;
    let aspects: [(&str, Get); 3] = [
        ("plans (result digests: metrics or parameters differ)", |f| {
            // The digest's first 16 characters (a record is input: not cut inside a character).
            Some(f.plan.chars().take(16).collect())
        }),
        ("presets", |f| f.preset.map(|p| p.name().to_owned())),
        ("tool versions", |f| Some(f.tool.clone())),
    ];
    for (what, get) in aspects {
        let per_run: Vec<BTreeSet<String>> = runs
            .iter()
            .map(|r| {
                r.records
                    .iter()
                    .filter_map(|rec| rec.fingerprint.as_ref().and_then(get))
                    .collect()
            })
            .collect();
        let distinct: BTreeSet<&BTreeSet<String>> = per_run.iter().filter(|s| !s.is_empty()).collect();
        if distinct.len() > 1 || per_run.iter().any(|s| s.len() > 1) {
            let parts: Vec<String> = runs
                .iter()
                .zip(&per_run)
                .map(|(r, s)| {
                    let values: Vec<&str> = s.iter().map(String::as_str).collect();
                    format!(
                        "{} {}",
                        r.name,
                        if values.is_empty() {
                            "(not recorded)".to_owned()
                        } else {
                            values.join(" and ")
                        }
                    )
                })
                .collect();
            notes.push(format!(
                "The runs used different {what}: {}; their numbers may not be comparable.",
                parts.join(", ")
            ));
        }
    }
}

/// The fidelity specs of the common scenes whose verdicts differ between runs.
fn differences(runs: &[Run], scenes: &[&str], shared: &BTreeSet<Metric>) -> Vec<SpecDifference> {
    let mut out = Vec::new();
    for &scene in scenes {
        let reports: Vec<Option<&FidelityReport>> = runs
            .iter()
            .map(|r| r.record(scene)?.report()?.fidelity.as_ref())
            .collect();
        for metric in [Metric::Cnt, Metric::Atr, Metric::Oor, Metric::Oar] {
            if !shared.contains(&metric) {
                continue;
            }
            let specs: Vec<Vec<(String, Verdict)>> = reports
                .iter()
                .map(|f| f.map(|f| spec_verdicts(f, metric)).unwrap_or_default())
                .collect();
            let count = specs.iter().map(Vec::len).max().unwrap_or(0);
            for k in 0..count {
                let Some((spec, _)) = specs.iter().find_map(|s| s.get(k)) else {
                    continue;
                };
                // A spec every run has (the rows are the same), else it is not comparable.
                let verdicts: Option<Vec<Verdict>> = specs
                    .iter()
                    .map(|s| s.get(k).filter(|(t, _)| t == spec).map(|(_, v)| *v))
                    .collect();
                if let Some(verdicts) = verdicts
                    && verdicts.iter().any(|v| *v != verdicts[0])
                {
                    out.push(SpecDifference {
                        scene: scene.to_owned(),
                        metric,
                        spec: spec.clone(),
                        verdicts,
                    });
                }
            }
        }
    }
    out
}

/// Each spec of `metric` in `f` with its verdict, in the report's order (the fidelity crate's
/// [`FidelityReport::verdicts`]; nothing for a metric that is not a fidelity metric).
pub(crate) fn spec_verdicts(f: &FidelityReport, metric: Metric) -> Vec<(String, Verdict)> {
    metric
        .fidelity()
        .map(|m| {
            f.verdicts(m)
                .into_iter()
                .map(|(spec, satisfied)| (spec.to_owned(), Verdict::of(satisfied)))
                .collect()
        })
        .unwrap_or_default()
}

/// "A", "A and B", "A, B and C".
fn list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => (*one).to_owned(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}
