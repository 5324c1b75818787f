//! A finished run: the records of an output folder of `sceneeval evaluate`, with the
//! difficulty of each scene, read without evaluating anything.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use sceneeval_annotation::Annotations;
use sceneeval_files::ErrorChain;
use sceneeval_results::{
    GroupSummary, Metric, RECORD_FILE, SUMMARY_SCENES_CSV, SceneName, SceneRecord, SceneReport, Summary,
    difficulty_groups,
};

use crate::ReportError;
use crate::within::{Inside, inside, is_file_name};

/// The records of one run folder and the difficulty of each scene.
#[derive(Debug, Clone)]
pub struct Run {
    /// The name shown in tables: `--names`, else the folder's name.
    pub name: String,
    /// The folder.
    pub dir: PathBuf,
    /// One record per scene, in scene order (benchmark id, then name).
    pub records: Vec<SceneRecord>,
    /// The records of the folder that could not be read, in scene order: listed by the report
    /// and the comparison as a missing scene is, with the reason.
    pub unreadable: Vec<Unreadable>,
    /// Scene name to difficulty (`easy`, `medium`, `hard`, ...), for scenes that have one.
    difficulty: BTreeMap<String, String>,
    /// Scene name to its annotation row's id and description, from the annotations given
    /// ([`Run::with_annotations`]); `None` when none were given.
    descriptions: Option<BTreeMap<String, (String, String)>>,
    /// The agreement of this run with people's labels, when the report shows them
    /// ([`Run::with_labels`]).
    pub(crate) labels: Option<Box<crate::agreement::Agreement>>,
}

/// What a scene page says about the scene's description ([`Run::description`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Description<'a> {
    /// The description of the scene's row in the annotations given to the report.
    Text {
        /// The row's id.
        id: &'a str,
        /// The description.
        text: &'a str,
        /// Whether the run's record says the run had an annotation row for the scene
        /// (`None`: the record has no fingerprint). `Some(false)`: the row shown is one the run
        /// did not use.
        run_had_row: Option<bool>,
    },
    /// The run's record says the run had no annotation row for the scene.
    NoRow,
    /// The report was given no annotations (and the record does not say the run had no row).
    NotGiven,
    /// The run had an annotation row, but the annotations given to the report have none for
    /// the scene.
    NotInGiven,
}

/// A record of a run folder that could not be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unreadable {
    /// The scene: the name of the folder the record is in.
    pub scene: SceneName,
    /// The record file (`<scene>/eval.json`).
    pub path: PathBuf,
    /// Why it could not be read: the parse error with its causes, a symbolic link out of the
    /// run folder, a record of another scene than its folder's.
    pub reason: String,
}

impl Run {
    /// Reads every `<scene>/eval.json` of `dir`, and each scene's difficulty from the run's
    /// `summary_scenes.csv` when it has one (the difficulty the annotations of the run gave;
    /// [`Run::with_annotations`] replaces them).
    ///
    /// Only what lies inside `dir` is read: a record (or its folder) that is a symbolic link
    /// leading out of `dir` is not read. A record that cannot be read (not JSON, another
    /// schema, a link out of the folder, not a regular file, or the record of another scene
    /// than the folder it is in) is listed in [`Run::unreadable`] with the reason, and the
    /// others are read.
    ///
    /// # Errors
    /// [`ReportError::File`] when the folder cannot be listed, [`ReportError::NoRecords`] when
    /// it holds no record, [`ReportError::NoReadableRecords`] when none can be read,
    /// [`ReportError::Csv`] for a malformed `summary_scenes.csv`.
    pub fn open(dir: &Path) -> Result<Run, ReportError> {
        let root = dir.canonicalize().map_err(|e| ReportError::file(dir, e))?;
        let entries = std::fs::read_dir(dir).map_err(|e| ReportError::file(dir, e))?;
        let mut records = Vec::new();
        let mut unreadable = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|e| ReportError::file(dir, e))?;
            let path = entry.path().join(RECORD_FILE);
            // A folder without a record (the report's own, a scratch folder) is not a scene.
            if path.symlink_metadata().is_err() {
                continue;
            }
            let scene = SceneName::new(entry.file_name().to_string_lossy());
            match read_record(&root, &scene, &path) {
                Ok(record) => records.push(record),
                Err(reason) => {
                    tracing::warn!(path = %path.display(), %reason, "record not read");
                    unreadable.push(Unreadable { scene, path, reason });
                }
            }
        }
        if records.is_empty() {
            return Err(
                match unreadable
                    .into_iter()
                    .min_by(|a, b| scene_order(&a.scene, &b.scene))
                {
                    None => ReportError::NoRecords { dir: dir.to_owned() },
                    Some(first) => ReportError::NoReadableRecords {
                        dir: dir.to_owned(),
                        first: Box::new(first),
                    },
                },
            );
        }
        unreadable.sort_by(|a, b| scene_order(&a.scene, &b.scene));
        let name = dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| dir.display().to_string());
        let difficulty = match inside(&root, &dir.join(SUMMARY_SCENES_CSV)) {
            Inside::Yes(path) => read_difficulties(&path)?,
            Inside::Missing => BTreeMap::new(),
            Inside::No => {
                tracing::warn!(dir = %dir.display(), "{SUMMARY_SCENES_CSV} leads out of the run folder: not read");
                BTreeMap::new()
            }
        };
        let mut run = Run::from_records(name, dir, records).with_difficulties(difficulty);
        run.unreadable = unreadable;
        Ok(run)
    }

    /// The folder of `scene`'s files in the run folder (`<dir>/<scene>`), when the name is one
    /// file name (not `..`, no separator): a record's name never builds a path out of the
    /// folder.
    pub fn scene_dir(&self, scene: &str) -> Option<PathBuf> {
        is_file_name(scene).then(|| self.dir.join(scene))
    }

    /// A run of `records` (put in scene order), named `name`, whose files are in `dir`.
    pub fn from_records(
        name: impl Into<String>,
        dir: impl Into<PathBuf>,
        mut records: Vec<SceneRecord>,
    ) -> Run {
        records.sort_by(|a, b| scene_order(&a.scene, &b.scene));
        Run {
            name: name.into(),
            dir: dir.into(),
            records,
            unreadable: Vec::new(),
            difficulty: BTreeMap::new(),
            descriptions: None,
            labels: None,
        }
    }

    /// The agreement of this run with the people's labels ([`Run::with_labels`]), if given.
    pub fn labels(&self) -> Option<&crate::agreement::Agreement> {
        self.labels.as_deref()
    }

    /// The run under another name.
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// The run with these difficulties (scene name to difficulty), replacing its own.
    pub fn with_difficulties(mut self, difficulty: BTreeMap<String, String>) -> Self {
        self.difficulty = difficulty;
        self
    }

    /// The run with each scene's difficulty and description from its row in `annotations`
    /// ([`sceneeval_results::SceneName::annotation_row`], the rule the run itself used).
    pub fn with_annotations(mut self, annotations: &Annotations) -> Self {
        let rows: Vec<(String, &sceneeval_annotation::AnnotationRow)> = self
            .records
            .iter()
            .filter_map(|r| Some((scene_of(r).to_owned(), r.scene.annotation_row(annotations)?)))
            .collect();
        self.difficulty = rows
            .iter()
            .map(|(s, row)| (s.clone(), row.difficulty.as_str().to_owned()))
            .collect();
        self.descriptions = Some(
            rows.into_iter()
                .map(|(s, row)| (s, (row.id.clone(), row.description.clone())))
                .collect(),
        );
        self
    }

    /// What the page of `scene` says about its description: the description of its row in
    /// the annotations given ([`Run::with_annotations`]), else why there is none. The run
    /// itself records only a digest of the row it used (`fingerprint.annotation`), so the
    /// text comes from the annotations given to the report; the digest says whether the run
    /// had a row at all.
    pub fn description(&self, scene: &str) -> Description<'_> {
        let run_had_row = self
            .record(scene)
            .and_then(|r| r.fingerprint.as_ref())
            .map(|f| f.annotation.is_some());
        match (self.descriptions.as_ref().map(|d| d.get(scene)), run_had_row) {
            (Some(Some((id, text))), _) => Description::Text {
                id,
                text,
                run_had_row,
            },
            (_, Some(false)) => Description::NoRow,
            (None, _) => Description::NotGiven,
            (Some(None), _) => Description::NotInGiven,
        }
    }

    /// The difficulty of `scene`, if known.
    pub fn difficulty(&self, scene: &str) -> Option<&str> {
        self.difficulty.get(scene).map(String::as_str)
    }

    /// Whether any scene has a difficulty.
    pub fn has_difficulties(&self) -> bool {
        !self.difficulty.is_empty()
    }

    /// The record of `scene`.
    pub fn record(&self, scene: &str) -> Option<&SceneRecord> {
        self.records.iter().find(|r| r.scene.as_str() == scene)
    }

    /// The metrics any evaluated scene of the run ran, in [`Metric::ALL`] order.
    pub fn metrics(&self) -> Vec<Metric> {
        let set: BTreeSet<Metric> = self
            .records
            .iter()
            .filter_map(SceneRecord::report)
            .flat_map(metrics_in)
            .collect();
        set.into_iter().collect()
    }

    /// The run's table: the group of every scene, then one per difficulty (easy, medium, hard,
    /// others by name, then scenes without one), each a [`GroupSummary`] as `summary.csv` has
    /// it.
    pub fn summary(&self) -> Vec<GroupSummary> {
        let names: Vec<&str> = self.records.iter().map(|r| r.scene.as_str()).collect();
        difficulty_groups(&names, |s| self.difficulty(s))
            .into_iter()
            .map(|(group, scenes)| {
                let records = scenes.iter().filter_map(|s| self.record(s));
                group_summary(&group, records)
            })
            .collect()
    }
}

/// The scene of a record, as the report's pages and tables name it.
pub(crate) fn scene_of(record: &SceneRecord) -> &str {
    record.scene.as_str()
}

/// Scenes in order: benchmark id, then name.
pub(crate) fn scene_order(a: &SceneName, b: &SceneName) -> std::cmp::Ordering {
    let key = |s: &SceneName| (s.number().unwrap_or(u64::MAX), s.as_str().to_owned());
    key(a).cmp(&key(b))
}

/// The record `path` of the folder of `scene`, or why it cannot be read.
fn read_record(root: &Path, scene: &SceneName, path: &Path) -> Result<SceneRecord, String> {
    let file = match inside(root, path) {
        Inside::Yes(file) => file,
        Inside::No => return Err("a symbolic link that leads out of the run folder (not read)".to_owned()),
        Inside::Missing => return Err("a symbolic link to nothing".to_owned()),
    };
    sceneeval_files::check_regular(&file).map_err(|e| e.to_string())?;
    let record = SceneRecord::read(&file).map_err(|e| format!("{}", ErrorChain::new(&e)))?;
    if record.scene != *scene {
        return Err(format!(
            "the record is of scene {:?}, not of the folder {:?} it is in",
            record.scene.as_str(),
            scene.as_str()
        ));
    }
    Ok(record)
}

/// The metrics that ran on a scene, in [`Metric::ALL`] order: its geometry metrics and the
/// fidelity metrics that have a section, without those the scene could not compute
/// ([`SceneReport::incomplete`], status partial).
pub fn metrics_in(report: &SceneReport) -> Vec<Metric> {
    let mut metrics: Vec<Metric> = report.metrics.iter().map(|&m| Metric::from(m)).collect();
    if let Some(f) = &report.fidelity {
        for (present, m) in [
            (f.cnt.is_some(), Metric::Cnt),
            (f.atr.is_some(), Metric::Atr),
            (f.oor.is_some(), Metric::Oor),
            (f.oar.is_some(), Metric::Oar),
        ] {
            if present {
                metrics.push(m);
            }
        }
    }
    if report.summary.stab.is_some() {
        metrics.push(Metric::Stability);
    }
    // A metric the scene could not compute (status partial) has no value to compare.
    metrics.retain(|m| !report.incomplete.iter().any(|i| i.metric == *m));
    metrics.sort();
    metrics.dedup();
    metrics
}

/// The summary's metric columns in the summary's order (`summary.csv`: CNT, ATR, OOR, OAR, then
/// COL_ob ... WIN_blk, STAB), each with its metric.
pub fn summary_columns() -> Vec<(&'static str, Metric)> {
    Metric::summary_columns()
}

/// The table row of `records` as `summary.csv` computes it, named `group`.
pub(crate) fn group_summary<'a>(
    group: &str,
    records: impl IntoIterator<Item = &'a SceneRecord>,
) -> GroupSummary {
    let mut summary = Summary::from_records(records, None);
    let mut row = summary.groups.swap_remove(0);
    row.group = group.to_owned();
    row
}

/// A scene's own numbers (a group of one), as `summary_scenes.csv` has them.
pub fn scene_values(record: &SceneRecord) -> GroupSummary {
    group_summary(record.scene.as_str(), std::iter::once(record))
}

/// Scene name to difficulty from a run's `summary_scenes.csv` (columns `scene` and
/// `difficulty`).
fn read_difficulties(path: &Path) -> Result<BTreeMap<String, String>, ReportError> {
    let csv_error = |source| ReportError::Csv {
        path: path.to_owned(),
        source,
    };
    let file = sceneeval_files::open_regular(path).map_err(|e| ReportError::file(path, e))?;
    let mut reader = csv::Reader::from_reader(file);
    // Cells a spreadsheet would run were written with a leading `'` (`Summary::scenes_csv`).
    let cell = sceneeval_files::csv_cell::unescape;
    let headers = reader.headers().map_err(csv_error)?.clone();
    let column = |name: &str| headers.iter().position(|h| h == name);
    let (Some(scene), Some(difficulty)) = (column("scene"), column("difficulty")) else {
        return Ok(BTreeMap::new());
    };
    let mut out = BTreeMap::new();
    for row in reader.records() {
        let row = row.map_err(csv_error)?;
        if let (Some(s), Some(d)) = (row.get(scene), row.get(difficulty))
            && !d.is_empty()
        {
            out.insert(cell(s).to_owned(), cell(d).to_owned());
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_columns_are_the_summary_s_in_its_order() {
        let csv = Summary::from_records(std::iter::empty::<&SceneRecord>(), None)
            .to_csv()
            .unwrap_or_default();
        let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
        let columns: Vec<&str> = summary_columns().into_iter().map(|(c, _)| c).collect();
        let first = header.iter().position(|c| *c == columns[0]).unwrap_or_default();
        assert_eq!(columns, header[first..first + columns.len()]);
    }
}
