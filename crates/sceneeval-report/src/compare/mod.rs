//! Tables across runs: one row per run, one column per metric column the runs share, ranks and
//! rank points, written as Markdown, CSV, LaTeX or HTML.
//!
//! [`compare`] checks comparability before it puts numbers side by side: runs are compared only
//! on the scenes every run evaluated in full (not missing, failed or partial in any run: a
//! partial record lacks a shared geometry metric, or a shared fidelity metric although the scene
//! had an annotation row), with the same annotation row, and on the metrics every run ran; every difference (scenes left out and why, metrics not shared, different
//! plans, presets or tool versions) is a note printed under the table.
//!
//! **Ranks** are competition ranks ("1224": runs with equal values share the best rank, the
//! next rank skips the places they fill) per column, on the values as printed (two decimals),
//! among the runs with a value in that column; the direction is the metric's
//! ([`sceneeval_results::Metric::better`]). A run ranked `r` of the `N` runs with a value gets
//! `N - r + 1` points; a run's total is the sum over columns, its average rank the mean of its
//! ranks, and its places the number of columns where it is first, second and third. Best
//! values (rank 1) are bold, second (rank 2) italic.

mod rank;
#[cfg(test)]
mod tests;
mod text;

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use sceneeval_fidelity::FidelityReport;
use sceneeval_results::{Better, GroupSummary, Metric, Outcome, SceneName};
use sceneeval_stats::bootstrap::{Bootstrap, DEFAULT_RESAMPLES};

pub use rank::competition_ranks;
pub(crate) use text::{Emphasis, arrow as text_arrow, average, scenes, standing_order};

use crate::ReportError;
use crate::run::{Run, group_summary, groups, metrics_in, scene_order, scene_values, summary_columns};

/// How to compare.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CompareOptions {
    /// One table per difficulty after the table of every scene (`--by difficulty`).
    pub by_difficulty: bool,
    /// A bootstrap confidence interval per value at this level (`--ci 0.95`).
    pub ci: Option<f64>,
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
    /// The run's rank in the column, when it has a value.
    pub rank: Option<usize>,
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
/// (0, 1).
pub fn compare(runs: &[Run], options: &CompareOptions) -> Result<Comparison, ReportError> {
    if runs.is_empty() {
        return Err(ReportError::NoRuns);
    }
    if let Some(level) = options.ci
        && !(level > 0.0 && level < 1.0)
    {
        return Err(ReportError::ConfidenceLevel(level));
    }
    let mut notes = Vec::new();

    // Columns: the metrics every run ran; scenes: those every run evaluated in full.
    let metrics: Vec<Vec<Metric>> = runs.iter().map(Run::metrics).collect();
    let (shared, columns) = shared_columns(runs, &metrics, &mut notes);
    same_everywhere(runs, &mut notes);
    unreadable_records(runs, &mut notes);
    let scenes = common_scenes(runs, &metrics, &shared, &mut notes);
    let difficulty = difficulties(runs, &scenes, &mut notes);
    let names: Vec<&str> = scenes.iter().map(String::as_str).collect();
    let mut grouped = groups(&names, |s| difficulty.get(s).copied());
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
    let tables = grouped
        .into_iter()
        .map(|(group, members)| table(runs, &columns, &per_scene, group, &members, options.ci))
        .collect();

    let differences = differences(runs, &names, &shared);
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
    })
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
/// scene order; a note names the others and why.
fn common_scenes(
    runs: &[Run],
    metrics: &[Vec<Metric>],
    shared: &BTreeSet<Metric>,
    notes: &mut Vec<String>,
) -> Vec<String> {
    // Every scene of any run, read or not.
    let mut all_scenes: Vec<&SceneName> = runs
        .iter()
        .flat_map(|r| {
            r.records
                .iter()
                .map(|r| &r.scene)
                .chain(r.unreadable.iter().map(|u| &u.scene))
        })
        .collect();
    all_scenes.sort_by(|a, b| scene_order(a, b));
    all_scenes.dedup();
    let fidelity_shared = shared.iter().any(|m| m.fidelity().is_some());
    let mut left_out: Vec<String> = Vec::new();
    let mut scenes: Vec<String> = Vec::new();
    for name in all_scenes {
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
    if !left_out.is_empty() {
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

/// One group's table.
fn table(
    runs: &[Run],
    columns: &[Column],
    per_scene: &[BTreeMap<&str, GroupSummary>],
    group: String,
    members: &[&str],
    ci: Option<f64>,
) -> Table {
    let mut cells: Vec<Vec<Cell>> = runs
        .iter()
        .zip(per_scene)
        .map(|(run, scenes)| {
            let summary = group_summary(&group, members.iter().filter_map(|s| run.record(s)));
            columns
                .iter()
                .map(|c| {
                    let values: Vec<f64> = members
                        .iter()
                        .filter_map(|s| scenes.get(s)?.value(c.name))
                        .collect();
                    let value = summary.value(c.name);
                    Cell {
                        value,
                        n: values.len(),
                        rank: None,
                        points: 0,
                        ci: ci.and_then(|level| value.and(mean_interval(&values, level))),
                    }
                })
                .collect()
        })
        .collect();
    for (k, column) in columns.iter().enumerate() {
        let printed: Vec<Option<f64>> = cells
            .iter()
            .map(|row| row[k].value.map(rank::as_printed))
            .collect();
        let ranks = competition_ranks(&printed, column.better);
        let ranked = ranks.iter().flatten().count();
        for (row, rank) in cells.iter_mut().zip(ranks) {
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

/// Each spec of `metric` in `f` with its verdict, in the report's order.
pub(crate) fn spec_verdicts(f: &FidelityReport, metric: Metric) -> Vec<(String, Verdict)> {
    match metric {
        Metric::Cnt => f
            .cnt
            .iter()
            .flat_map(|m| &m.specs)
            .map(|s| (s.spec.clone(), Verdict::of(s.satisfied)))
            .collect(),
        Metric::Atr => f
            .atr
            .iter()
            .flat_map(|m| &m.specs)
            .map(|s| (s.spec.clone(), Verdict::of(s.satisfied)))
            .collect(),
        Metric::Oor => f
            .oor
            .iter()
            .flat_map(|m| &m.specs)
            .map(|s| (s.spec.clone(), Verdict::of(s.satisfied)))
            .collect(),
        Metric::Oar => f
            .oar
            .iter()
            .flat_map(|m| &m.specs)
            .map(|s| (s.spec.clone(), Verdict::of(s.satisfied)))
            .collect(),
        _ => Vec::new(),
    }
}

/// "A", "A and B", "A, B and C".
fn list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => (*one).to_owned(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}
