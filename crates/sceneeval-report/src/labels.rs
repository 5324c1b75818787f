//! Human verdicts on a run's fidelity specs: the label file format (`docs/formats.md`, "Label
//! files").
//!
//! A label file is JSON Lines, one verdict a line:
//!
//! ```text
//! {"scene": "scene_3", "metric": "oor", "index": 0, "spec": "eq,2,next_to,0,bed,nightstand", "satisfied": true, "annotator": "alice"}
//! ```
//!
//! or CSV with the same column names (a file whose name ends in `.csv`). `scene` is the scene's
//! folder name in the run, `metric` one of `cnt`, `atr`, `oor`, `oar`, `index` the spec's
//! position in that metric's `specs` list of the scene's `eval.json`, `spec` its text (checked
//! against the run: [`LabelFile::check_run`]), `satisfied` `true`, `false` or `null` (the person
//! could not tell; an empty CSV cell), `annotator` a name. A later line for the same
//! (annotator, scene, metric, index) replaces an earlier one, so a changed mind is one appended
//! line. Every key is required and no other key is allowed: a misspelt key is an error naming
//! the line.
//!
//! A JSON Lines file whose last line has no line end and is not a label is a write cut short
//! (the program writing it stopped mid-line: a crash, a full disk): that line is left out and
//! [`LabelFile::torn`] names it; any other line that is not a label is an error. The writer
//! ([`crate::label_writer::LabelWriter`]) removes such a line before it appends.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use sceneeval_fidelity::FidelityMetric;
use sceneeval_results::SceneRecord;
use serde::{Deserialize, Deserializer, Serialize};

use crate::Run;

/// One verdict of one person on one spec: a line of a label file.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Label {
    /// The scene's folder name in the run.
    pub scene: String,
    /// The metric whose spec this is.
    pub metric: FidelityMetric,
    /// The spec's position in the metric's `specs` list of the scene's `eval.json`.
    pub index: usize,
    /// The spec's text, as `eval.json` has it.
    pub spec: String,
    /// The verdict: `None` when the person could not tell. The key is required (`null`
    /// written out).
    #[serde(deserialize_with = "required_option")]
    pub satisfied: Option<bool>,
    /// Who judged.
    pub annotator: String,
}

/// A required key whose value may be `null` (serde makes a missing `Option` key `None`
/// unless the field has its own deserializer).
fn required_option<'de, D: Deserializer<'de>>(d: D) -> Result<Option<bool>, D::Error> {
    Option::<bool>::deserialize(d)
}

/// A spec of a run: scene, metric and index, ordered by scene, metric, index.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Item {
    /// The scene's folder name.
    pub scene: String,
    /// The metric.
    pub metric: FidelityMetric,
    /// The spec's position in the metric's `specs`.
    pub index: usize,
}

impl Label {
    /// The item this label judges.
    #[must_use]
    pub fn item(&self) -> Item {
        Item {
            scene: self.scene.clone(),
            metric: self.metric,
            index: self.index,
        }
    }

    /// The label as one JSON line (without the line end).
    #[must_use]
    pub fn to_json_line(&self) -> String {
        // A struct of strings, numbers and booleans always serialises.
        serde_json::to_string(self).unwrap_or_default()
    }
}

/// A label and the line of its file it was read from (1-based; a CSV file's header is line 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LabelLine {
    /// The label.
    pub label: Label,
    /// Its line.
    pub line: u64,
}

/// A label file, read: the labels in force (a later line for the same annotator and item
/// replaced the earlier), in the order of their first line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LabelFile {
    /// The file.
    pub path: PathBuf,
    /// The labels in force.
    pub labels: Vec<LabelLine>,
    /// Lines replaced by a later line for the same annotator and item.
    pub replaced: usize,
    /// A last line cut short (no line end, not a label: its writer stopped mid-line), left
    /// out: its line number and the byte offset where it starts.
    pub torn: Option<TornLine>,
}

/// The last line of a JSON Lines label file, cut short by a writer that stopped mid-line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TornLine {
    /// Its line number (1-based).
    pub line: u64,
    /// The byte offset in the file where it starts (the file's length without it).
    pub offset: u64,
}

/// What went wrong reading a label file or checking it against a run; every error names the
/// file, and the line where there is one.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LabelError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A line is not a label: malformed JSON, a missing or unknown key, an unknown metric.
    #[error("{}:{line}: not a label: {source}", path.display())]
    Json {
        /// The file.
        path: PathBuf,
        /// The line.
        line: u64,
        /// The parse error.
        #[source]
        source: serde_json::Error,
    },
    /// A CSV row could not be read.
    #[error("{}:{line}: {source}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// The line.
        line: u64,
        /// The CSV error.
        #[source]
        source: csv::Error,
    },
    /// A value is wrong: an empty annotator or scene, an unknown metric, a `satisfied` that is
    /// not `true`, `false` or empty, a missing column.
    #[error("{}:{line}: {message}", path.display())]
    Value {
        /// The file.
        path: PathBuf,
        /// The line.
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// The index is past the metric's specs in the run's record of the scene.
    #[error(transparent)]
    IndexPastSpecs(Box<IndexPastSpecs>),
    /// The spec text differs from the run's at that index (or from another label file's).
    #[error(transparent)]
    SpecDiffers(Box<SpecDiffers>),
}

/// A label whose index is past the metric's specs in a run's record of the scene.
#[derive(Debug, thiserror::Error)]
#[error(
    "{}:{line}: {metric} spec {index} of {scene}: {run} has {count} {metric} specs for this scene \
     (were the labels made for other annotations?)",
    path.display()
)]
pub struct IndexPastSpecs {
    /// The label file.
    pub path: PathBuf,
    /// The line.
    pub line: u64,
    /// The run folder.
    pub run: String,
    /// The scene.
    pub scene: String,
    /// The metric.
    pub metric: FidelityMetric,
    /// The label's index.
    pub index: usize,
    /// The specs the run has.
    pub count: usize,
}

/// A label whose spec text differs from a run's at that index (or from another label file's).
#[derive(Debug, thiserror::Error)]
#[error(
    "{}:{line}: {metric} spec {index} of {scene} is {found:?} here but {expected:?} in {source_name} \
     (the labels were made for other annotations)",
    path.display()
)]
pub struct SpecDiffers {
    /// The label file.
    pub path: PathBuf,
    /// The line.
    pub line: u64,
    /// The run folder or label file (with its line) that has the other text.
    pub source_name: String,
    /// The scene.
    pub scene: String,
    /// The metric.
    pub metric: FidelityMetric,
    /// The index.
    pub index: usize,
    /// The text there.
    pub expected: String,
    /// The label's text.
    pub found: String,
}

impl LabelFile {
    /// Reads a label file: CSV when its name ends in `.csv` (any case), else JSON Lines.
    ///
    /// # Errors
    /// [`LabelError::Read`] when it cannot be read (only a regular file is opened); a
    /// [`LabelError`] naming the line for the first line that is not a label.
    pub fn read(path: &Path) -> Result<LabelFile, LabelError> {
        let read_error = |source| LabelError::Read {
            path: path.to_owned(),
            source,
        };
        let mut file = sceneeval_files::open_regular(path).map_err(read_error)?;
        let mut text = String::new();
        std::io::Read::read_to_string(&mut file, &mut text).map_err(read_error)?;
        let is_csv = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        if is_csv {
            LabelFile::from_csv_str(path, &text)
        } else {
            LabelFile::from_jsonl_str(path, &text)
        }
    }

    /// Parses JSON Lines; `path` names the file in errors. Blank lines are skipped; a last
    /// line without a line end that is not a label is a torn write, left out
    /// ([`LabelFile::torn`]).
    ///
    /// # Errors
    /// A [`LabelError`] naming the first line that is not a label.
    pub fn from_jsonl_str(path: &Path, text: &str) -> Result<LabelFile, LabelError> {
        let mut lines = Vec::new();
        let mut torn = None;
        let mut offset = 0u64;
        for (k, raw) in text.split_inclusive('\n').enumerate() {
            let line = k as u64 + 1;
            let start = offset;
            offset += raw.len() as u64;
            let ended = raw.ends_with('\n');
            let raw = raw.trim_end_matches('\n').trim_end_matches('\r');
            if raw.trim().is_empty() {
                continue;
            }
            let label: Label = match serde_json::from_str(raw) {
                Ok(label) => label,
                Err(_) if !ended => {
                    tracing::warn!(
                        path = %path.display(),
                        line,
                        "the last line has no line end and is not a label (a write cut short): left out"
                    );
                    torn = Some(TornLine { line, offset: start });
                    continue;
                }
                Err(source) => {
                    return Err(LabelError::Json {
                        path: path.to_owned(),
                        line,
                        source,
                    });
                }
            };
            lines.push(checked(path, line, label)?);
        }
        let mut file = LabelFile::from_lines(path, lines);
        file.torn = torn;
        Ok(file)
    }

    /// Parses CSV with the columns `scene,metric,index,spec,satisfied,annotator` (any order;
    /// `satisfied` is `true`, `false` or empty for `null`); `path` names the file in errors.
    /// Cells a spreadsheet would run as formulas may carry the leading `'` that
    /// [`sceneeval_files::csv_cell`] adds; it is removed.
    ///
    /// # Errors
    /// A [`LabelError`] naming the first row that is not a label.
    pub fn from_csv_str(path: &Path, text: &str) -> Result<LabelFile, LabelError> {
        const COLUMNS: [&str; 6] = ["scene", "metric", "index", "spec", "satisfied", "annotator"];
        let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
        let csv_error = |line: u64, source| LabelError::Csv {
            path: path.to_owned(),
            line,
            source,
        };
        let headers = reader.headers().map_err(|e| csv_error(1, e))?.clone();
        let mut at = [0usize; 6];
        for (slot, name) in at.iter_mut().zip(COLUMNS) {
            *slot = headers
                .iter()
                .position(|h| h.trim() == name)
                .ok_or_else(|| LabelError::Value {
                    path: path.to_owned(),
                    line: 1,
                    message: format!("no column {name:?} (the columns are {})", COLUMNS.join(",")),
                })?;
        }
        if let Some(extra) = headers.iter().find(|h| !COLUMNS.contains(&h.trim())) {
            return Err(LabelError::Value {
                path: path.to_owned(),
                line: 1,
                message: format!("unknown column {extra:?} (the columns are {})", COLUMNS.join(",")),
            });
        }
        let mut lines = Vec::new();
        for record in reader.records() {
            let record = record.map_err(|e| {
                let line = e.position().map_or(0, csv::Position::line);
                csv_error(line, e)
            })?;
            let line = record.position().map_or(0, csv::Position::line);
            let cell = |k: usize| sceneeval_files::csv_cell::unescape(record.get(at[k]).unwrap_or(""));
            let value_error = |message: String| LabelError::Value {
                path: path.to_owned(),
                line,
                message,
            };
            let metric = cell(1)
                .trim()
                .parse::<FidelityMetric>()
                .map_err(|_| value_error(format!("unknown metric {:?} (cnt, atr, oor or oar)", cell(1))))?;
            let index = cell(2)
                .trim()
                .parse::<usize>()
                .map_err(|_| value_error(format!("index {:?} is not a whole number >= 0", cell(2))))?;
            let satisfied = match cell(4).trim() {
                "true" => Some(true),
                "false" => Some(false),
                "" | "null" => None,
                other => {
                    return Err(value_error(format!(
                        "satisfied {other:?} is not true, false or empty (could not tell)"
                    )));
                }
            };
            let label = Label {
                scene: cell(0).to_owned(),
                metric,
                index,
                spec: cell(3).to_owned(),
                satisfied,
                annotator: cell(5).to_owned(),
            };
            lines.push(checked(path, line, label)?);
        }
        Ok(LabelFile::from_lines(path, lines))
    }

    /// The labels in force of `lines` (in file order): a later line for the same annotator and
    /// item replaces the earlier one in its place.
    fn from_lines(path: &Path, lines: Vec<LabelLine>) -> LabelFile {
        let mut at: BTreeMap<(String, Item), usize> = BTreeMap::new();
        let mut labels: Vec<LabelLine> = Vec::with_capacity(lines.len());
        let mut replaced = 0;
        for line in lines {
            let key = (line.label.annotator.clone(), line.label.item());
            match at.get(&key) {
                Some(&k) => {
                    labels[k] = line;
                    replaced += 1;
                }
                None => {
                    at.insert(key, labels.len());
                    labels.push(line);
                }
            }
        }
        LabelFile {
            path: path.to_owned(),
            labels,
            replaced,
            torn: None,
        }
    }

    /// The annotators of the file, in the order of their first label.
    #[must_use]
    pub fn annotators(&self) -> Vec<&str> {
        let mut seen = BTreeSet::new();
        self.labels
            .iter()
            .map(|l| l.label.annotator.as_str())
            .filter(|a| seen.insert(*a))
            .collect()
    }

    /// Checks every label against `run`: a label for a scene the run evaluated must name a
    /// spec the run's record has, with the same text. Labels for scenes the run has no
    /// fidelity verdicts for (not in the run, failed, the metric not run) are not an error:
    /// their scenes are returned, sorted.
    ///
    /// # Errors
    /// [`LabelError::IndexPastSpecs`] or [`LabelError::SpecDiffers`] for the first label that
    /// does not fit.
    pub fn check_run(&self, run: &Run) -> Result<Vec<String>, LabelError> {
        let mut outside = BTreeSet::new();
        for LabelLine { label, line } in &self.labels {
            let fidelity = run
                .record(&label.scene)
                .and_then(SceneRecord::report)
                .and_then(|r| r.fidelity.as_ref());
            let specs = fidelity.map(|f| f.verdicts(label.metric)).unwrap_or_default();
            let ran = fidelity.is_some_and(|f| metric_ran(f, label.metric));
            if !ran {
                outside.insert(label.scene.clone());
                continue;
            }
            match specs.get(label.index) {
                None => {
                    return Err(LabelError::IndexPastSpecs(Box::new(IndexPastSpecs {
                        path: self.path.clone(),
                        line: *line,
                        run: run.dir.display().to_string(),
                        scene: label.scene.clone(),
                        metric: label.metric,
                        index: label.index,
                        count: specs.len(),
                    })));
                }
                Some((text, _)) if *text != label.spec => {
                    return Err(LabelError::SpecDiffers(Box::new(SpecDiffers {
                        path: self.path.clone(),
                        line: *line,
                        source_name: run.dir.display().to_string(),
                        scene: label.scene.clone(),
                        metric: label.metric,
                        index: label.index,
                        expected: (*text).to_owned(),
                        found: label.spec.clone(),
                    })));
                }
                Some(_) => {}
            }
        }
        Ok(outside.into_iter().collect())
    }
}

/// Whether the report has the metric's section.
pub(crate) fn metric_ran(f: &sceneeval_fidelity::FidelityReport, metric: FidelityMetric) -> bool {
    match metric {
        FidelityMetric::Cnt => f.cnt.is_some(),
        FidelityMetric::Atr => f.atr.is_some(),
        FidelityMetric::Oor => f.oor.is_some(),
        FidelityMetric::Oar => f.oar.is_some(),
    }
}

/// The label with its line, after the checks serde does not make: names not empty.
fn checked(path: &Path, line: u64, label: Label) -> Result<LabelLine, LabelError> {
    let empty = |what: &str| LabelError::Value {
        path: path.to_owned(),
        line,
        message: format!("{what} is empty"),
    };
    if label.annotator.trim().is_empty() {
        return Err(empty("annotator"));
    }
    if label.scene.trim().is_empty() {
        return Err(empty("scene"));
    }
    Ok(LabelLine { label, line })
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::panic)]
mod tests {
    use super::*;

    fn jsonl(text: &str) -> Result<LabelFile, LabelError> {
        LabelFile::from_jsonl_str(Path::new("labels.jsonl"), text)
    }

    const LINE: &str = r#"{"scene": "scene_3", "metric": "oor", "index": 0, "spec": "eq,2,next_to,0,bed,nightstand", "satisfied": true, "annotator": "alice"}"#;

    #[test]
    fn reads_the_issue_line_and_a_later_line_replaces_an_earlier() {
        let changed = LINE.replace("true", "false");
        let bob = LINE.replace("alice", "bob").replace("true", "null");
        let file = jsonl(&format!("{LINE}\n\n{bob}\n{changed}\n")).unwrap();
        assert_eq!(file.replaced, 1);
        assert_eq!(file.labels.len(), 2);
        // Alice's changed mind (line 4) in the place of her first verdict.
        assert_eq!(file.labels[0].line, 4);
        assert_eq!(file.labels[0].label.satisfied, Some(false));
        assert_eq!(file.labels[0].label.metric, FidelityMetric::Oor);
        assert_eq!(file.labels[1].label.satisfied, None);
        assert_eq!(file.annotators(), ["alice", "bob"]);
        // A label written back is the same line.
        let again = jsonl(&file.labels[1].label.to_json_line()).unwrap();
        assert_eq!(again.labels[0].label, file.labels[1].label);
    }

    #[test]
    fn a_last_line_cut_short_is_left_out_and_named() {
        let bob = LINE.replace("alice", "bob");
        // Bob's line cut after 40 bytes, no line end: a torn write.
        let text = format!("{LINE}\n{}", &bob[..40]);
        let file = jsonl(&text).unwrap();
        assert_eq!(file.labels.len(), 1);
        assert_eq!(
            file.torn,
            Some(TornLine {
                line: 2,
                offset: LINE.len() as u64 + 1
            })
        );
        // A complete last line without its line end is a label; a file that ends well has
        // nothing torn.
        let whole = jsonl(&format!("{LINE}\n{bob}")).unwrap();
        assert_eq!((whole.labels.len(), whole.torn), (2, None));
        // The same cut line with its line end (not the last write) is an error naming it.
        let err = jsonl(&format!("{}\n{LINE}\n", &bob[..40]))
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("labels.jsonl:1: not a label"), "{err}");
        // CRLF line ends read as LF.
        let crlf = jsonl(&format!("{LINE}\r\n{bob}\r\n")).unwrap();
        assert_eq!((crlf.labels.len(), crlf.torn), (2, None));
    }

    #[test]
    fn bad_lines_are_errors_naming_the_line() {
        let cases = [
            ("{\"scene\": ", "labels.jsonl:2: not a label"),
            (
                &LINE.replace("\"oor\"", "\"xyz\"") as &str,
                "unknown variant `xyz`",
            ),
            (
                &LINE.replace(", \"satisfied\": true", ""),
                "missing field `satisfied`",
            ),
            (
                &LINE.replace("\"satisfied\"", "\"satisifed\""),
                "unknown field `satisifed`",
            ),
            (&LINE.replace("\"index\": 0", "\"index\": -1"), "labels.jsonl:2"),
            (
                &LINE.replace("\"alice\"", "\"  \""),
                "labels.jsonl:2: annotator is empty",
            ),
        ];
        for (bad, expected) in cases {
            let err = jsonl(&format!("{LINE}\n{bad}\n")).unwrap_err().to_string();
            assert!(err.contains(expected), "{bad}: {err}");
            assert!(err.starts_with("labels.jsonl:2:"), "{err}");
        }
    }

    #[test]
    fn csv_has_the_same_columns() {
        let text = "annotator,scene,metric,index,spec,satisfied\n\
                    alice,scene_3,oor,0,\"eq,2,next_to,0,bed,nightstand\",true\n\
                    bob,scene_3,OOR,0,\"eq,2,next_to,0,bed,nightstand\",\n";
        let file = LabelFile::from_csv_str(Path::new("l.csv"), text).unwrap();
        let from_json = jsonl(LINE).unwrap();
        assert_eq!(file.labels[0].label, from_json.labels[0].label);
        assert_eq!(file.labels[0].line, 2);
        assert_eq!(file.labels[1].label.satisfied, None);
        let bad = text.replace(",true", ",yes");
        let err = LabelFile::from_csv_str(Path::new("l.csv"), &bad)
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("l.csv:2: satisfied \"yes\""), "{err}");
        let bad = text.replace("metric", "metrik");
        let err = LabelFile::from_csv_str(Path::new("l.csv"), &bad)
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("l.csv:1: no column \"metric\""), "{err}");
        let bad = text.replace(",oor,", ",size,");
        let err = LabelFile::from_csv_str(Path::new("l.csv"), &bad)
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("l.csv:2: unknown metric \"size\""), "{err}");
    }
}
