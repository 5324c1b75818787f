use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use sceneeval_files::csv_cell;
use serde::{Deserialize, Serialize};

use sceneeval_annotation::{Annotations, Difficulty};
use sceneeval_fidelity::FidelitySummary;
use sceneeval_files::ErrorChain;
use sceneeval_plausibility::PlausibilitySummary;

use crate::error::write_atomic;
use crate::{Metric, Preset, ResultsError, SceneRecord};

/// The name of the CSV summary written into an output folder.
pub const SUMMARY_CSV: &str = "summary.csv";

/// The name of the Markdown summary written into an output folder.
pub const SUMMARY_MD: &str = "summary.md";

/// The name of the per-scene table written into an output folder.
pub const SUMMARY_SCENES_CSV: &str = "summary_scenes.csv";

/// The name of the group holding every scene.
pub const ALL_SCENES: &str = "all";
/// The group of scenes that have no annotation row when annotations were given.
pub const UNANNOTATED: &str = "unannotated";

/// `items` grouped as every table of a run groups its scenes: [`ALL_SCENES`] (every item), then
/// one group per difficulty `difficulty` gives, in the order of [`Difficulty`] (easy, medium,
/// hard, then others by name), then [`UNANNOTATED`] for the items without one when some have
/// one; each group with its items in the given order. The summaries, the report's overview and
/// `compare` group by it.
///
/// ```
/// use sceneeval_results::difficulty_groups;
/// let d = |s: &str| match s { "a" => Some("hard"), "b" => Some("easy"), "c" => Some("weird"), _ => None };
/// let groups = difficulty_groups(&["a", "b", "c", "x"], d);
/// let names: Vec<&str> = groups.iter().map(|(n, _)| n.as_str()).collect();
/// assert_eq!(names, ["all", "easy", "hard", "weird", "unannotated"]);
/// assert_eq!(groups[0].1, ["a", "b", "c", "x"]);
/// assert_eq!(groups[1].1, ["b"]);
/// // Without any difficulty, only the group of every item.
/// assert_eq!(difficulty_groups(&["x"], |_| None::<&str>).len(), 1);
/// ```
pub fn difficulty_groups<T: Copy, D: AsRef<str>>(
    items: &[T],
    difficulty: impl Fn(T) -> Option<D>,
) -> Vec<(String, Vec<T>)> {
    let mut out = vec![(ALL_SCENES.to_owned(), items.to_vec())];
    let mut by: BTreeMap<(Difficulty, String), Vec<T>> = BTreeMap::new();
    let mut none = Vec::new();
    for &item in items {
        match difficulty(item) {
            Some(d) => {
                let d = d.as_ref();
                by.entry((Difficulty::parse(d), d.to_owned()))
                    .or_default()
                    .push(item);
            }
            None => none.push(item),
        }
    }
    let any = !by.is_empty();
    out.extend(by.into_iter().map(|((_, d), items)| (d, items)));
    if any && !none.is_empty() {
        out.push((UNANNOTATED.to_owned(), none));
    }
    out
}

/// The paper's plausibility table (Table 2, and Table 6 by difficulty): one row per group of
/// scenes, each column the macro-average over the group's evaluated scenes, in percent.
///
/// | column | per scene | averaged over |
/// |---|---|---|
/// | `CNT` | satisfied ObjCount specs / specs | scenes with ObjCount specs (`CNT_n`) |
/// | `ATR` | satisfied ObjAttr specs / specs | scenes with ObjAttr specs judged by a VLM (`ATR_n`) |
/// | `OOR` | satisfied OORel specs / specs | scenes with OORel specs (`OOR_n`) |
/// | `OAR` | satisfied OARel specs / specs | scenes with OARel specs (`OAR_n`) |
/// | `COL_ob` | objects in collision / objects | scenes with objects |
/// | `COL_sc` | 1 if any collision, else 0 | evaluated scenes |
/// | `SUP` | supported objects / objects | scenes with objects |
/// | `NAV` | largest free component / free floor | evaluated scenes |
/// | `ACC` | mean best-side accessibility | scenes with an object with functional sides |
/// | `OOB` | objects out of bounds / objects | scenes with objects |
/// | `DOOR_blk` | blocked doors / doors | scenes with a door |
/// | `WIN_blk` | blocked windows / windows | scenes with a window |
/// | `STAB` | stable objects / objects free to move (stability metric) | scenes with an object free to move |
///
/// Higher is better for CNT, ATR, OOR, OAR, SUP, NAV, ACC and STAB; lower for the others. A column is empty when no scene
/// of the group has a value (the metric did not run, or never applies).
///
/// A `partial` scene (some metric could not be computed: a VLM request that got no answer,
/// another error of one metric; [`crate::SceneReport::incomplete`]) counts as evaluated, and
/// only its complete metrics are averaged. Besides, per group:
///
/// | column | what |
/// |---|---|
/// | `partial` | scenes evaluated partly |
/// | `CNT_unanswered` ... `OAR_unanswered` | specs without a verdict because an answer they need is missing (left out of the scores), summed over the scenes |
/// | `SUP_fallback`, `ACC_fallback` | objects whose support type, functional sides came from the category table (or no source) because the VLM's question failed or got no usable answer, summed over the scenes ([`crate::SceneReport::placement`]) |
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The groups: [`ALL_SCENES`] first, then easy, medium, hard, other difficulties in name
    /// order, then [`UNANNOTATED`].
    pub groups: Vec<GroupSummary>,
    /// The plan's preset, when known ([`Summary::with_plan`]).
    #[serde(default)]
    pub preset: Option<String>,
    /// The digest of the plan (`sceneeval_eval::EvaluationPlan::result_digest`), when known.
    #[serde(default)]
    pub plan_digest: Option<String>,
    /// One row per scene, in record order: the per-scene table (`summary_scenes.csv`).
    #[serde(default)]
    pub scenes: Vec<SceneRow>,
}

/// One scene of the per-scene table: its numbers (the group table's columns, for this scene
/// alone) or why it has none.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneRow {
    /// The scene's name.
    pub scene: String,
    /// Its benchmark id.
    pub scene_id: Option<String>,
    /// Its difficulty, when it has an annotation row.
    pub difficulty: Option<String>,
    /// `ok`, `partial` or `failed`.
    pub status: String,
    /// Why it failed (the stage and the error with its causes on one line), or which metrics
    /// of a partial scene could not be computed and why.
    pub error: Option<String>,
    /// The scene's numbers (a group of one).
    pub values: GroupSummary,
}

/// The columns of the per-scene table: the scene, then the group table's numbers for the
/// scene alone ([`GroupSummary::cell`]), then why it failed or is partial.
fn scene_columns() -> Vec<&'static str> {
    let mut columns = vec!["scene", "scene_id", "difficulty", "status"];
    columns.extend(Metric::summary_columns().into_iter().map(|(c, _)| c));
    columns.extend(VLM_COLUMNS);
    columns.push("error");
    columns
}

/// The columns of both tables after the metrics': the VLM questions without an answer and the
/// category-table fallbacks.
const VLM_COLUMNS: [&str; 6] = [
    "CNT_unanswered",
    "ATR_unanswered",
    "OOR_unanswered",
    "OAR_unanswered",
    "SUP_fallback",
    "ACC_fallback",
];

/// One row of the [`Summary`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroupSummary {
    /// The group's name.
    pub group: String,
    /// Scenes in the group.
    pub scenes: usize,
    /// Scenes evaluated.
    pub evaluated: usize,
    /// Scenes that failed to load or evaluate.
    pub failed: usize,
    /// Scenes evaluated partly (counted in `evaluated`): their incomplete metrics are left out
    /// of the averages.
    #[serde(default)]
    pub partial: usize,
    /// Mean CNT, percent.
    #[serde(default)]
    pub cnt: Option<f64>,
    /// Mean ATR, percent.
    #[serde(default)]
    pub atr: Option<f64>,
    /// Mean OOR, percent.
    #[serde(default)]
    pub oor: Option<f64>,
    /// Mean OAR, percent.
    #[serde(default)]
    pub oar: Option<f64>,
    /// Scenes behind `cnt`, `atr`, `oor`, `oar`.
    #[serde(default)]
    pub fidelity_n: [usize; 4],
    /// Specs of CNT, ATR, OOR, OAR without a verdict (an answer they need is missing; left out
    /// of the scores), summed over the group's scenes.
    #[serde(default)]
    pub fidelity_unanswered: [usize; 4],
    /// Mean share of objects in collision, percent.
    pub col_ob: Option<f64>,
    /// Share of scenes with a collision, percent.
    pub col_sc: Option<f64>,
    /// Mean share of supported objects, percent.
    pub sup: Option<f64>,
    /// Mean navigability, percent.
    pub nav: Option<f64>,
    /// Mean accessibility, percent.
    pub acc: Option<f64>,
    /// Mean share of objects out of bounds, percent.
    pub oob: Option<f64>,
    /// Mean share of doors blocked, percent.
    pub door_blocked: Option<f64>,
    /// Mean share of windows blocked, percent.
    pub window_blocked: Option<f64>,
    /// Mean share of the objects free to move that stayed put under the stability metric,
    /// percent.
    #[serde(default)]
    pub stab: Option<f64>,
    /// Objects whose support type is a fallback (the category table, or no source) because
    /// the VLM's question failed or got no usable answer, summed over the group's scenes.
    #[serde(default)]
    pub support_fallbacks: usize,
    /// Objects whose functional sides are a fallback, likewise.
    #[serde(default)]
    pub sides_fallbacks: usize,
}

/// The legend printed below the Markdown table.
pub const LEGEND: &str = "Values are percentages, macro-averaged over the group's evaluated scenes \
(`-`: no scene of the group has a value). Lower is better for COL_ob (objects in collision), \
COL_sc (scenes with a collision), OOB (objects out of bounds), DOOR_blk and WIN_blk (blocked \
doors and windows); higher is better for SUP (supported objects), NAV (navigable floor), ACC \
(accessible functional sides) and STAB (objects free to move that stay put under physics), and for \
CNT, ATR, OOR, OAR (satisfied object-count, attribute, object-object and object-architecture specs; \
`*_n`: scenes with such specs; `*_unanswered`: specs without a verdict because an answer they need \
is missing, left out of the scores). `failed` scenes are counted but not averaged; `partial` scenes \
(some metric could not be computed, listed below) are averaged on their complete metrics only. \
`SUP_fallback`, `ACC_fallback`: objects whose support type or functional sides came from the \
category table because the VLM's question failed or got no usable answer.\n";

/// The group table's columns: the group and its counts, each metric's columns
/// ([`Metric::summary_columns`]), the text-fidelity metrics' scored counts, then
/// [`VLM_COLUMNS`].
fn columns() -> Vec<&'static str> {
    let mut columns = vec!["group", "scenes", "evaluated", "failed", "partial"];
    columns.extend(Metric::summary_columns().into_iter().map(|(c, _)| c));
    columns.extend(["CNT_n", "ATR_n", "OOR_n", "OAR_n"]);
    columns.extend(VLM_COLUMNS);
    columns
}

impl Summary {
    /// Summarises scene records, grouped by the difficulty of each scene's row in
    /// `annotations` ([`crate::SceneName::annotation_row`]); without annotations only the
    /// [`ALL_SCENES`] row is produced.
    pub fn from_records<'a>(
        records: impl IntoIterator<Item = &'a SceneRecord>,
        annotations: Option<&Annotations>,
    ) -> Self {
        let records: Vec<&SceneRecord> = records.into_iter().collect();
        let labels: Vec<Option<String>> = records
            .iter()
            .map(|r| {
                let row = r.scene.annotation_row(annotations?)?;
                Some(row.difficulty.as_str().to_owned())
            })
            .collect();
        let indices: Vec<usize> = (0..records.len()).collect();
        let groups = difficulty_groups(&indices, |i| labels[i].as_deref())
            .into_iter()
            .map(|(name, members)| GroupSummary::of(&name, members.into_iter().map(|i| records[i])))
            .collect();
        let scenes = records
            .iter()
            .zip(&labels)
            .map(|(r, difficulty)| SceneRow {
                scene: r.scene.to_string(),
                scene_id: r.scene.id().map(str::to_owned),
                difficulty: difficulty.clone(),
                status: r.status().to_owned(),
                error: match &r.outcome {
                    crate::Outcome::Failed { stage, error, causes } => Some(format!(
                        "{} stage: {}",
                        match stage {
                            crate::Stage::Load => "load",
                            crate::Stage::Evaluate => "evaluate",
                        },
                        ErrorChain::from_parts(error.as_str(), causes)
                    )),
                    crate::Outcome::Partial { report } => {
                        let parts: Vec<String> = report
                            .incomplete
                            .iter()
                            .map(|m| {
                                format!(
                                    "{}: {}",
                                    m.metric.name(),
                                    ErrorChain::from_parts(m.error.as_str(), &m.causes)
                                )
                            })
                            .collect();
                        Some(format!("incomplete: {}", parts.join("; ")))
                    }
                    crate::Outcome::Ok { .. } => None,
                },
                values: GroupSummary::of(r.scene.as_str(), std::iter::once(*r)),
            })
            .collect();
        // The plan behind the records, when they all record the same one (a run sets its own
        // with `with_plan`; `sceneeval summarize` has only the records).
        let fingerprints: Vec<_> = records.iter().filter_map(|r| r.fingerprint.as_ref()).collect();
        let same = |f: &dyn Fn(&crate::Fingerprint) -> Option<String>| {
            let first = f(fingerprints.first()?)?;
            fingerprints
                .iter()
                .all(|x| f(x).as_ref() == Some(&first))
                .then_some(first)
        };
        Summary {
            groups,
            preset: same(&|f| f.preset.map(|p| p.name().to_owned())),
            plan_digest: same(&|f| Some(f.plan.clone())),
            scenes,
        }
    }

    /// The summary with the plan that produced it (its preset and result digest), shown below
    /// the Markdown table.
    pub fn with_plan(mut self, preset: Preset, plan_digest: impl Into<String>) -> Self {
        self.preset = Some(preset.name().to_owned());
        self.plan_digest = Some(plan_digest.into());
        self
    }

    /// Writes the table into `dir` as [`SUMMARY_CSV`] and [`SUMMARY_MD`], each replaced
    /// atomically.
    ///
    /// # Errors
    /// [`ResultsError::File`] when a file cannot be written; [`ResultsError::Csv`] as [`Self::to_csv`].
    pub fn write_to(&self, dir: &Path) -> Result<(), ResultsError> {
        write_atomic(&dir.join(SUMMARY_CSV), self.to_csv()?.as_bytes())?;
        write_atomic(&dir.join(SUMMARY_SCENES_CSV), self.scenes_csv()?.as_bytes())?;
        write_atomic(&dir.join(SUMMARY_MD), self.to_markdown().as_bytes())
    }

    /// The per-scene table as CSV: scene, benchmark id, difficulty, status, the scene's numbers
    /// (the group table's columns, in percent with four decimals; empty where the scene has
    /// no value), and for a failed scene its stage and error with causes, for a partial one
    /// its incomplete metrics and why.
    pub fn scenes_csv(&self) -> Result<String, ResultsError> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let columns = scene_columns();
        w.write_record(&columns)?;
        for row in &self.scenes {
            let cells = columns.iter().map(|&column| match column {
                "scene" => row.scene.clone(),
                "scene_id" => row.scene_id.clone().unwrap_or_default(),
                "difficulty" => row.difficulty.clone().unwrap_or_default(),
                "status" => row.status.clone(),
                "error" => row.error.clone().unwrap_or_default(),
                number => row.values.cell(number, 4),
            });
            // A scene name or error a spreadsheet would run gets a leading `'`; numbers stay.
            w.write_record(cells.map(csv_cell::escape_owned))?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| ResultsError::Csv(e.into_error().into()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The table as CSV (header row, numbers with four decimals, empty cells for missing values).
    pub fn to_csv(&self) -> Result<String, ResultsError> {
        let mut w = csv::Writer::from_writer(Vec::new());
        let columns = columns();
        w.write_record(&columns)?;
        for g in &self.groups {
            w.write_record(columns.iter().map(|c| csv_cell::escape_owned(g.cell(c, 4))))?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| ResultsError::Csv(e.into_error().into()))?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// The table as GitHub Markdown (numbers with two decimals, `-` for missing values),
    /// followed by the preset and plan digest (when known) and a legend.
    pub fn to_markdown(&self) -> String {
        let mut out = String::new();
        let columns = columns();
        let _ = writeln!(out, "| {} |", columns.join(" | "));
        let _ = writeln!(out, "|{}", "---|".repeat(columns.len()));
        for g in &self.groups {
            let cells: Vec<String> = columns
                .iter()
                .map(|c| g.cell(c, 2))
                .map(|c| if c.is_empty() { "-".to_owned() } else { c })
                .collect();
            let _ = writeln!(out, "| {} |", cells.join(" | "));
        }
        out.push('\n');
        if self.preset.is_some() || self.plan_digest.is_some() {
            let preset = self.preset.as_deref().unwrap_or("not recorded");
            let digest = self.plan_digest.as_deref().unwrap_or("-");
            let _ = writeln!(
                out,
                "Preset: `{preset}`; plan digest `{}`.",
                &digest[..digest.len().min(16)]
            );
        }
        out.push_str(LEGEND);
        for (status, title) in [("partial", "Partial scenes"), ("failed", "Failed scenes")] {
            let rows: Vec<&SceneRow> = self.scenes.iter().filter(|r| r.status == status).collect();
            if rows.is_empty() {
                continue;
            }
            let _ = writeln!(out, "\n{title} ({}):\n", rows.len());
            for row in rows {
                let _ = writeln!(
                    out,
                    "- `{}`: {}",
                    row.scene,
                    row.error.as_deref().unwrap_or_default()
                );
            }
        }
        out
    }
}

impl GroupSummary {
    fn of<'a>(group: &str, records: impl Iterator<Item = &'a SceneRecord>) -> Self {
        let (mut scenes, mut partial) = (0, 0);
        let mut summaries: Vec<PlausibilitySummary> = Vec::new();
        let mut fidelity: Vec<FidelitySummary> = Vec::new();
        let mut unanswered = [0usize; 4];
        let (mut support_fallbacks, mut sides_fallbacks) = (0, 0);
        let mut stab: Vec<f64> = Vec::new();
        for r in records {
            scenes += 1;
            let Some(report) = r.report() else { continue };
            partial += usize::from(!report.incomplete.is_empty());
            // Incomplete metrics are left out of the averages.
            let mut geometry = report.summary.geometry.clone();
            let mut scores = report.summary.fidelity;
            let mut stable = report.summary.stab.flatten();
            for m in &report.incomplete {
                leave_out(&mut geometry, scores.as_mut(), &mut stable, m.metric);
            }
            summaries.push(geometry);
            fidelity.extend(scores);
            stab.extend(stable);
            if let Some(f) = &report.fidelity {
                let counts = [
                    f.cnt.as_ref().map(|r| r.unanswered),
                    f.atr.as_ref().map(|r| r.unanswered),
                    f.oor.as_ref().map(|r| r.unanswered),
                    f.oar.as_ref().map(|r| r.unanswered),
                ];
                for (total, n) in unanswered.iter_mut().zip(counts) {
                    *total += n.unwrap_or(0);
                }
            }
            for o in report.placement.iter().flatten() {
                support_fallbacks +=
                    usize::from(o.support_type.as_ref().is_some_and(|p| p.source.is_fallback()));
                sides_fallbacks += usize::from(
                    o.functional_sides
                        .as_ref()
                        .is_some_and(|p| p.source.is_fallback()),
                );
            }
        }
        let fmean = |f: &dyn Fn(&FidelitySummary) -> Option<f64>| -> (Option<f64>, usize) {
            let values: Vec<f64> = fidelity.iter().filter_map(f).collect();
            let n = values.len();
            ((n > 0).then(|| 100.0 * values.iter().sum::<f64>() / n as f64), n)
        };
        let (cnt, cnt_n) = fmean(&|s| s.cnt);
        let (atr, atr_n) = fmean(&|s| s.atr);
        let (oor, oor_n) = fmean(&|s| s.oor);
        let (oar, oar_n) = fmean(&|s| s.oar);
        let mean = |f: &dyn Fn(&PlausibilitySummary) -> Option<f64>| -> Option<f64> {
            let values: Vec<f64> = summaries.iter().filter_map(f).collect();
            (!values.is_empty()).then(|| 100.0 * values.iter().sum::<f64>() / values.len() as f64)
        };
        let share = |blocked: Option<usize>, total: Option<usize>| match (blocked, total) {
            (Some(b), Some(t)) if t > 0 => Some(b as f64 / t as f64),
            _ => None,
        };
        GroupSummary {
            group: group.to_owned(),
            scenes,
            evaluated: summaries.len(),
            failed: scenes - summaries.len(),
            partial,
            cnt,
            atr,
            oor,
            oar,
            fidelity_n: [cnt_n, atr_n, oor_n, oar_n],
            fidelity_unanswered: unanswered,
            col_ob: mean(&|s| s.col_ob),
            col_sc: mean(&|s| s.col_sc.map(|c| if c { 1.0 } else { 0.0 })),
            sup: mean(&|s| s.sup),
            nav: mean(&|s| s.nav),
            acc: mean(&|s| s.acc),
            oob: mean(&|s| s.oob),
            door_blocked: mean(&|s| share(s.doors_blocked, s.num_doors)),
            window_blocked: mean(&|s| share(s.windows_blocked, s.num_windows)),
            stab: (!stab.is_empty()).then(|| 100.0 * stab.iter().sum::<f64>() / stab.len() as f64),
            support_fallbacks,
            sides_fallbacks,
        }
    }

    /// The value of the summary column named `column` (`CNT`, `COL_ob`, ... as in
    /// [`Metric::columns`](crate::Metric::columns), exact case), in percent; `None` when the
    /// group has no value there or there is no such column.
    pub fn value(&self, column: &str) -> Option<f64> {
        match column {
            "CNT" => self.cnt,
            "ATR" => self.atr,
            "OOR" => self.oor,
            "OAR" => self.oar,
            "COL_ob" => self.col_ob,
            "COL_sc" => self.col_sc,
            "SUP" => self.sup,
            "NAV" => self.nav,
            "ACC" => self.acc,
            "OOB" => self.oob,
            "DOOR_blk" => self.door_blocked,
            "WIN_blk" => self.window_blocked,
            "STAB" => self.stab,
            _ => None,
        }
    }

    /// The cell of `column` (one of the group table's columns), numbers with `decimals`
    /// decimals, empty for a missing value or an unknown column.
    pub fn cell(&self, column: &str, decimals: usize) -> String {
        let num = |v: Option<f64>| v.map(|v| format!("{v:.decimals$}")).unwrap_or_default();
        match column {
            "group" => self.group.clone(),
            "scenes" => self.scenes.to_string(),
            "evaluated" => self.evaluated.to_string(),
            "failed" => self.failed.to_string(),
            "partial" => self.partial.to_string(),
            "CNT_n" => self.fidelity_n[0].to_string(),
            "ATR_n" => self.fidelity_n[1].to_string(),
            "OOR_n" => self.fidelity_n[2].to_string(),
            "OAR_n" => self.fidelity_n[3].to_string(),
            "CNT_unanswered" => self.fidelity_unanswered[0].to_string(),
            "ATR_unanswered" => self.fidelity_unanswered[1].to_string(),
            "OOR_unanswered" => self.fidelity_unanswered[2].to_string(),
            "OAR_unanswered" => self.fidelity_unanswered[3].to_string(),
            "SUP_fallback" => self.support_fallbacks.to_string(),
            "ACC_fallback" => self.sides_fallbacks.to_string(),
            percent => num(self.value(percent)),
        }
    }
}

/// Leaves `metric`'s numbers out of a scene's summary (it is incomplete): its geometry
/// numbers, fidelity score or share of stable objects (`stab`).
fn leave_out(
    geometry: &mut PlausibilitySummary,
    fidelity: Option<&mut FidelitySummary>,
    stab: &mut Option<f64>,
    metric: Metric,
) {
    match metric {
        Metric::Collision => (geometry.col_ob, geometry.col_sc) = (None, None),
        Metric::Support => geometry.sup = None,
        Metric::Navigability => (geometry.nav, geometry.all_rooms_reachable) = (None, None),
        Metric::Accessibility => geometry.acc = None,
        Metric::OutOfBounds => geometry.oob = None,
        Metric::OpeningClearance => {
            (geometry.num_doors, geometry.doors_blocked) = (None, None);
            (geometry.num_windows, geometry.windows_blocked) = (None, None);
        }
        Metric::Stability => *stab = None,
        Metric::Cnt | Metric::Atr | Metric::Oor | Metric::Oar => {
            if let Some(f) = fidelity {
                match metric {
                    Metric::Cnt => f.cnt = None,
                    Metric::Atr => f.atr = None,
                    Metric::Oor => f.oor = None,
                    _ => f.oar = None,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_plausibility::{self as plausibility, PlausibilityReport};

    use crate::{SceneName, SceneReport, Stage};

    type SceneSummary = PlausibilitySummary;

    fn record(name: &str, summary: SceneSummary) -> SceneRecord {
        let geometry =
            PlausibilityReport::of_summary(Some(name.into()), plausibility::Metric::ALL.to_vec(), summary);
        SceneRecord::ok(
            SceneName::new(name),
            SceneReport::new(Some(name.into()), geometry, None),
        )
    }

    fn records() -> Vec<SceneRecord> {
        let a = SceneSummary {
            col_ob: Some(0.5),
            col_sc: Some(true),
            sup: Some(1.0),
            nav: Some(0.8),
            acc: None,
            oob: Some(0.0),
            num_doors: Some(2),
            doors_blocked: Some(1),
            num_windows: Some(0),
            windows_blocked: Some(0),
            ..SceneSummary::default()
        };
        let b = SceneSummary {
            col_ob: Some(0.0),
            col_sc: Some(false),
            sup: Some(0.5),
            nav: Some(1.0),
            acc: Some(0.25),
            oob: Some(0.25),
            num_doors: Some(1),
            doors_blocked: Some(0),
            ..SceneSummary::default()
        };
        let err = std::io::Error::other("broken");
        vec![
            record("scene_0", a),
            record("scene_1", b),
            SceneRecord::failed(SceneName::new("scene_2"), Stage::Load, &err),
        ]
    }

    #[test]
    fn macro_averages_by_hand() {
        let s = Summary::from_records(&records(), None);
        assert_eq!(s.groups.len(), 1);
        let all = &s.groups[0];
        assert_eq!((all.scenes, all.evaluated, all.failed), (3, 2, 1));
        // COL_ob (0.5 + 0) / 2 = 25 %; COL_sc 1 of 2 = 50 %; SUP (1 + 0.5) / 2 = 75 %;
        // NAV (0.8 + 1) / 2 = 90 %; ACC only scene_1: 25 %; OOB (0 + 0.25) / 2 = 12.5 %;
        // doors (1/2 + 0/1) / 2 = 25 %; windows: no scene has one.
        assert_eq!(all.col_ob, Some(25.0));
        assert_eq!(all.col_sc, Some(50.0));
        assert_eq!(all.sup, Some(75.0));
        assert_eq!(all.nav, Some(90.0));
        assert_eq!(all.acc, Some(25.0));
        assert_eq!(all.oob, Some(12.5));
        assert_eq!(all.door_blocked, Some(25.0));
        assert_eq!(all.window_blocked, None);
        let csv = s.to_csv().unwrap();
        // The header, written out: the columns made from the Metric table are the paper's.
        assert_eq!(
            csv.lines().next().unwrap(),
            "group,scenes,evaluated,failed,partial,CNT,ATR,OOR,OAR,COL_ob,COL_sc,SUP,NAV,ACC,OOB,DOOR_blk,\
             WIN_blk,STAB,CNT_n,ATR_n,OOR_n,OAR_n,CNT_unanswered,ATR_unanswered,OOR_unanswered,\
             OAR_unanswered,SUP_fallback,ACC_fallback"
        );
        assert_eq!(
            csv.lines().nth(1).unwrap(),
            "all,3,2,1,0,,,,,25.0000,50.0000,75.0000,90.0000,25.0000,12.5000,25.0000,,,0,0,0,0,0,0,0,0,0,0"
        );
        let md = s.to_markdown();
        assert!(
            md.contains("| all | 3 | 2 | 1 | 0 | - | - | - | - | 25.00 | 50.00 | 75.00 | 90.00 | 25.00 | 12.50 | 25.00 | - | - | 0 | 0 | 0 | 0 | 0 | 0 | 0 | 0 | 0 | 0 |"),
            "{md}"
        );
        assert!(md.contains("Lower is better for COL_ob"), "{md}");
        assert!(!md.contains("Preset:"), "no plan given");
        let md = s
            .clone()
            .with_plan(Preset::Reference, "0123456789abcdef0123")
            .to_markdown();
        assert!(
            md.contains("Preset: `reference`; plan digest `0123456789abcdef`."),
            "{md}"
        );
        // The failed scene is listed with its stage and cause below the legend.
        assert!(
            md.ends_with("\nFailed scenes (1):\n\n- `scene_2`: load stage: broken\n"),
            "{md}"
        );
        // The per-scene table: each scene's own numbers, and the failure with its cause.
        let scenes = s.scenes_csv().unwrap();
        let lines: Vec<&str> = scenes.lines().collect();
        assert_eq!(
            lines[0],
            "scene,scene_id,difficulty,status,CNT,ATR,OOR,OAR,COL_ob,COL_sc,SUP,NAV,ACC,OOB,DOOR_blk,\
             WIN_blk,STAB,CNT_unanswered,ATR_unanswered,OOR_unanswered,OAR_unanswered,SUP_fallback,\
             ACC_fallback,error"
        );
        // scene_0: COL_ob 50 %, COL_sc 100 %, SUP 100 %, NAV 80 %, OOB 0 %, doors 1/2 = 50 %,
        // windows: 0 of 0 is no value.
        assert_eq!(
            lines[1],
            "scene_0,0,,ok,,,,,50.0000,100.0000,100.0000,80.0000,,0.0000,50.0000,,,0,0,0,0,0,0,"
        );
        assert_eq!(
            lines[3],
            "scene_2,2,,failed,,,,,,,,,,,,,,0,0,0,0,0,0,load stage: broken"
        );
    }

    #[test]
    fn text_cells_a_spreadsheet_would_run_are_escaped_and_numbers_are_not() {
        // A scene named like a formula (the error cell starts with its stage: plain text).
        let err = std::io::Error::other("-1 objects: broken");
        let mut recs = records();
        recs.push(SceneRecord::failed(
            SceneName::new("=cmd|calc!A1"),
            Stage::Load,
            &err,
        ));
        let s = Summary::from_records(&recs, None);
        let scenes = s.scenes_csv().unwrap();
        assert_eq!(
            scenes.lines().last().unwrap(),
            "'=cmd|calc!A1,,,failed,,,,,,,,,,,,,,0,0,0,0,0,0,load stage: -1 objects: broken"
        );
        // The numbers of the other scenes stay numbers.
        assert!(scenes.contains(",50.0000,100.0000,"), "{scenes}");
    }

    #[test]
    fn partial_scenes_are_averaged_on_their_complete_metrics_only() {
        use crate::{IncompleteMetric, Metric, ObjectPlacement, PlacementSource, Provenance};
        let mut recs = records();
        // scene_1's support question failed (the endpoint was down): its SUP (50 %) is left
        // out; its other numbers stay. One object took the category table's support type.
        let Some(SceneRecord {
            outcome: crate::Outcome::Ok { report },
            ..
        }) = recs.get_mut(1)
        else {
            panic!("scene_1 is ok")
        };
        let mut report = (**report).clone();
        report.placement = Some(vec![ObjectPlacement {
            object: "bed".into(),
            support_type: Some(Provenance {
                value: Some(sceneeval_scene::SupportType::Ground),
                source: PlacementSource::CategoryPrior,
                reason: "the VLM request failed: 503".into(),
            }),
            functional_sides: None,
        }]);
        let err = std::io::Error::other("503 Service Unavailable");
        let report = report.with_incomplete(vec![IncompleteMetric::new(Metric::Support, true, &err)]);
        recs[1] = SceneRecord::ok(SceneName::new("scene_1"), report);
        assert_eq!(recs[1].status(), "partial");
        let s = Summary::from_records(&recs, None);
        let all = &s.groups[0];
        assert_eq!((all.scenes, all.evaluated, all.failed, all.partial), (3, 2, 1, 1));
        // SUP: scene_0's 100 % alone; NAV still (0.8 + 1) / 2 = 90 %.
        assert_eq!((all.sup, all.nav), (Some(100.0), Some(90.0)));
        assert_eq!((all.support_fallbacks, all.sides_fallbacks), (1, 0));
        let md = s.to_markdown();
        assert!(
            md.contains(
                "\nPartial scenes (1):\n\n- `scene_1`: incomplete: support: 503 Service Unavailable\n"
            ),
            "{md}"
        );
        let scenes = s.scenes_csv().unwrap();
        let line = scenes.lines().nth(2).unwrap();
        assert!(line.starts_with("scene_1,1,,partial,"), "{line}");
        assert!(
            line.ends_with(",1,0,incomplete: support: 503 Service Unavailable"),
            "{line}"
        );
    }

    #[test]
    fn stab_averages_the_scenes_with_an_object_free_to_move() {
        let mut recs = records();
        // scene_0: 3 of 4 free objects stayed (0.75); scene_1: stability ran but every
        // object was welded (no value). STAB: 75 % over one scene.
        for (r, stab) in recs.iter_mut().zip([Some(0.75), None]) {
            if let crate::Outcome::Ok { report } = &mut r.outcome {
                report.summary.stab = Some(stab);
            }
        }
        let s = Summary::from_records(&recs, None);
        assert_eq!(s.groups[0].stab, Some(75.0));
        assert_eq!(s.scenes[0].values.stab, Some(75.0));
        assert_eq!(s.scenes[1].values.stab, None);
        let csv = s.to_csv().unwrap();
        assert!(csv.contains(",25.0000,,75.0000,0,0,0,0,0,0,0,0,0,0\n"), "{csv}");
        let scenes = s.scenes_csv().unwrap();
        assert!(
            scenes
                .lines()
                .nth(1)
                .unwrap()
                .ends_with(",50.0000,,75.0000,0,0,0,0,0,0,"),
            "{scenes}"
        );
        assert!(s.to_markdown().contains("STAB (objects free to move"));
    }

    #[test]
    fn every_metric_column_has_a_value_accessor() {
        let s = Summary::from_records(&records(), None);
        let all = &s.groups[0];
        // The accessor gives the CSV's cells of every metric column (CNT .. STAB).
        let metric_columns: Vec<&str> = columns()
            .iter()
            .copied()
            .filter(|c| crate::Metric::from_name(c).is_some())
            .collect();
        assert_eq!(metric_columns.len(), 13);
        for column in metric_columns {
            let v = all.value(column).map(|v| format!("{v:.4}")).unwrap_or_default();
            assert_eq!(v, all.cell(column, 4), "{column}");
        }
        assert_eq!(all.value("SUP"), Some(75.0));
        assert_eq!(all.value("nope"), None);
    }

    #[test]
    fn groups_by_difficulty() {
        let recs = records();
        let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n0,hard,A.,,,,\n1,easy,B.,,,,\n";
        let annotations = Annotations::from_csv_str(csv).unwrap();
        let s = Summary::from_records(&recs, Some(&annotations));
        let names: Vec<&str> = s.groups.iter().map(|g| g.group.as_str()).collect();
        assert_eq!(names, vec!["all", "easy", "hard", UNANNOTATED]);
        assert_eq!(s.groups[1].sup, Some(50.0));
        assert_eq!(s.groups[2].sup, Some(100.0));
        assert_eq!(s.groups[3].evaluated, 0);
        assert_eq!(s.groups[3].sup, None);
    }
}
