//! Annotation generation, the paper's semi-automatic process (section "SceneEval-500",
//! appendix "Semi-Automatic Data Generation") as a tool: the SceneEval-500 annotations of a
//! given description ([`annotate`]) or of a list of them appended to an annotation file
//! ([`annotate_all`]), and new descriptions with their annotations appended to an annotation
//! file as they are accepted ([`generate`]).
//!
//! Every answer goes through the annotation validator ([`entry_checker`]: the entries parsed by
//! `sceneeval-annotation` and checked like `sceneeval annotations check` does): an answer with
//! findings is asked again once with the findings quoted ([`sceneeval_vlm::Session::ask`]); still
//! with findings, it is kept as a rejected candidate with them, never accepted and never
//! dropped. A generated description too similar to an existing one
//! ([`sceneeval_annotation::similarity`]: the examples and the rows already accepted) is rejected
//! with the description it is near to and the score, and the next request names the rejected
//! descriptions and asks for more variety. Refusals, truncated and unusable answers are
//! rejected candidates too. Rejected candidates go to the sidecar file `OUT.rejected.jsonl`
//! ([`rejected_path`], one [`RejectedCandidate`] per line). Both files are rewritten atomically
//! after each candidate, so an interrupted run loses at most the request in flight, and a
//! re-run with the same output continues: it counts the rows already there, compares with
//! them, and numbers on from their largest ID.
//!
//! # Example
//! ```
//! use sceneeval_annotate::{AnnotateOutcome, annotate};
//! use sceneeval_vlm::tasks::AnnotationLevel;
//! use sceneeval_vlm::{AnswerContent, Scripted, Session};
//! use serde_json::json;
//!
//! let vlm = Scripted::queue("m", [AnswerContent::Json { value: json!({
//!     "description": "A bedroom with a bed against the wall.", "difficulty": "easy",
//!     "obj_count": ["eq,1,bed"], "obj_attr": [], "oo_rel": [], "oa_rel": ["eq,1,against,bed,wall"]}) }]);
//! let session = Session::new(&vlm);
//! let outcome = pollster::block_on(annotate(
//!     &session, "A bedroom with a bed against the wall.", Some(AnnotationLevel::Easy), Vec::new(), "7",
//! )).unwrap();
//! let AnnotateOutcome::Accepted { row, .. } = outcome else { panic!("rejected") };
//! assert_eq!(row.id, "7");
//! assert_eq!(row.oa_rel[0].to_string(), "eq,1,against,bed,wall");
//! ```

pub mod review;

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;
use rand::seq::SliceRandom;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use sceneeval_annotation::similarity::{DEFAULT_THRESHOLD, DescriptionIndex};
use sceneeval_annotation::{
    AnnotationError, AnnotationRow, Annotations, Difficulty, Entry, EntryKind, Finding, FindingCode,
    parse_cell, validate_row,
};
use sceneeval_vlm::tasks::{AnnotatedDescription, AnnotationLevel, AnnotationTask, EntryChecker};
use sceneeval_vlm::{Outcome, Session, UnansweredKind, Vlm, VlmError};

/// Examples shown per request by default (the paper showed three to five).
pub const DEFAULT_EXAMPLES_PER_REQUEST: usize = 3;

/// How many of the last accepted descriptions, and of the last ones rejected as too similar, a
/// generation request names (to move away from them).
pub const NAMED_DESCRIPTIONS: usize = 5;

/// What the entry check of an answer leaves out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CheckScope {
    /// A description the user gave: findings about the text itself (`empty-description`,
    /// `description-semicolon`) and, when the user gave the difficulty,
    /// `difficulty-object-count` are not the model's to fix, so they are left out.
    UserDescription {
        /// Whether the user gave the difficulty.
        difficulty_given: bool,
    },
    /// A generated description: every finding counts.
    Generated,
}

/// One finding as a line of a problem list: code, column, entry, message, suggestion.
pub fn finding_line(f: &Finding) -> String {
    let mut line = format!("{} in {}", f.code, f.field);
    if let Some(entry) = &f.entry {
        line.push_str(&format!(" {entry:?}"));
    }
    line.push_str(&format!(": {}", f.message));
    if let Some(s) = &f.suggestion {
        line.push_str(&format!(" (suggestion: {s})"));
    }
    line
}

/// The annotation validator as the check of an answer's entries: the answer made a row
/// ([`row_of`]), its findings ([`validate_row`], errors and warnings alike, as
/// [`finding_line`]s) without those `scope` leaves out.
pub fn entry_checker(scope: CheckScope) -> Arc<EntryChecker> {
    Arc::new(move |answer: &AnnotatedDescription| {
        validate_row(&row_of(answer, "0"), 0)
            .iter()
            .filter(|f| match scope {
                CheckScope::Generated => true,
                CheckScope::UserDescription { difficulty_given } => match f.code {
                    FindingCode::EmptyDescription | FindingCode::DescriptionSemicolon => false,
                    FindingCode::DifficultyObjectCount => !difficulty_given,
                    _ => true,
                },
            })
            .map(finding_line)
            .collect()
    })
}

fn entries<T: EntryKind>(texts: &[String]) -> Vec<Entry<T>> {
    // An entry string holding several `;`-separated entries is split, as a CSV cell is.
    texts.iter().flat_map(|t| parse_cell(t)).collect()
}

/// The annotation row of an answer, with ID `id`.
pub fn row_of(answer: &AnnotatedDescription, id: &str) -> AnnotationRow {
    let mut row = AnnotationRow::new(
        id,
        Difficulty::parse(&answer.difficulty),
        answer.description.trim(),
    );
    row.obj_count = entries(&answer.obj_count);
    row.obj_attr = entries(&answer.obj_attr);
    row.oo_rel = entries(&answer.oo_rel);
    row.oa_rel = entries(&answer.oa_rel);
    row
}

/// A row as an in-context example (its entries as text).
pub fn example_of(row: &AnnotationRow) -> AnnotatedDescription {
    fn texts<T: EntryKind>(entries: &[Entry<T>]) -> Vec<String> {
        entries.iter().map(ToString::to_string).collect()
    }
    AnnotatedDescription {
        description: row.description.clone(),
        difficulty: row.difficulty.as_str().to_owned(),
        obj_count: texts(&row.obj_count),
        obj_attr: texts(&row.obj_attr),
        oo_rel: texts(&row.oo_rel),
        oa_rel: texts(&row.oa_rel),
    }
}

/// `k` in-context examples drawn from `rows` with rand's Xoshiro256++ seeded with `seed`: rows
/// of `level` (all rows when `level` is `None` or no row has it), `k` of them (all when fewer)
/// in the order of a partial Fisher-Yates shuffle. The draw of both [`generate`] (seed
/// `S + n` for its n-th candidate) and `sceneeval annotations annotate --examples`.
pub fn draw_examples(
    rows: &[AnnotationRow],
    level: Option<AnnotationLevel>,
    k: usize,
    seed: u64,
) -> Vec<AnnotatedDescription> {
    let mut pool: Vec<&AnnotationRow> = rows
        .iter()
        .filter(|r| level.is_some() && level_of(&r.difficulty) == level)
        .collect();
    if pool.is_empty() {
        pool = rows.iter().collect();
    }
    let k = k.min(pool.len());
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let (drawn, _) = pool.partial_shuffle(&mut rng, k);
    drawn.iter().map(|r| example_of(r)).collect()
}

/// The level of a row's difficulty, if it is one of the three.
fn level_of(difficulty: &Difficulty) -> Option<AnnotationLevel> {
    match difficulty {
        Difficulty::Easy => Some(AnnotationLevel::Easy),
        Difficulty::Medium => Some(AnnotationLevel::Medium),
        Difficulty::Hard => Some(AnnotationLevel::Hard),
        Difficulty::Other(_) => None,
    }
}

/// Why a candidate was rejected (the `reason` of a line of the rejected file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum RejectReason {
    /// The answer still had findings (or other problems) after it was asked again once.
    Findings {
        /// The problems of the last answer and of the first, as the session recorded them.
        problems: String,
    },
    /// The description is too similar to an existing one.
    TooSimilar {
        /// The existing description's row ID.
        near_id: String,
        /// The existing description.
        near_description: String,
        /// The similarity (Jaccard of content words), at least the threshold.
        score: f64,
    },
    /// The model refused.
    Refused {
        /// The refusal.
        detail: String,
    },
    /// The answer stopped at the token limit.
    Truncated {
        /// What the session recorded.
        detail: String,
    },
    /// No answer followed the schema (not JSON, wrong fields), twice.
    Unusable {
        /// The problems.
        detail: String,
    },
    /// A person rejected it in the review ([`review`]).
    Reviewer {
        /// The reviewer's reason.
        note: String,
    },
}

/// A candidate that was not accepted: one line of the rejected file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RejectedCandidate {
    /// The row ID the candidate has: its description's ID ([`annotate_all`]), or given by the
    /// reviewer ([`review`]) to a candidate it edited or decided on, and on the lines of the
    /// review's own rejected file; `None` (left out of the line) for a candidate of `generate`
    /// no one touched.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<String>,
    /// The difficulty asked for (`None`: left to the model).
    pub difficulty: Option<String>,
    /// The model's last answer that followed the schema, if any.
    pub candidate: Option<AnnotatedDescription>,
    /// Why it was rejected.
    #[serde(flatten)]
    pub reason: RejectReason,
}

/// The outcome of one annotation request.
#[derive(Debug, Clone, PartialEq)]
pub enum AnnotateOutcome {
    /// A row without findings.
    Accepted {
        /// The row.
        row: AnnotationRow,
        /// 1, or 2 when the re-asked answer was the valid one.
        attempt: u8,
    },
    /// No acceptable row.
    Rejected(RejectedCandidate),
}

/// The candidate of an unanswered task: the reason, and the last answer that followed the
/// schema.
fn rejected(
    task: &AnnotationTask,
    difficulty: Option<AnnotationLevel>,
    kind: UnansweredKind,
    reason: String,
) -> RejectedCandidate {
    let candidate = task.answers().pop();
    let reason = match kind {
        UnansweredKind::Refused => RejectReason::Refused { detail: reason },
        UnansweredKind::Truncated => RejectReason::Truncated { detail: reason },
        _ if candidate.is_some() => RejectReason::Findings { problems: reason },
        _ => RejectReason::Unusable { detail: reason },
    };
    RejectedCandidate {
        id: None,
        difficulty: difficulty.map(|d| d.name().to_owned()),
        candidate,
        reason,
    }
}

/// Asks `task` and turns the outcome into a row with ID `id` or a rejected candidate.
async fn ask_row<V: Vlm>(
    session: &Session<V>,
    task: &AnnotationTask,
    difficulty: Option<AnnotationLevel>,
    id: &str,
) -> Result<AnnotateOutcome, VlmError> {
    let answers = session.ask(task).await?;
    Ok(match answers.into_single() {
        Some(Outcome::Answered { answer, attempt, .. }) => AnnotateOutcome::Accepted {
            row: row_of(&answer, id),
            attempt,
        },
        Some(Outcome::Unanswered(why)) => {
            AnnotateOutcome::Rejected(rejected(task, difficulty, why.kind, why.reason))
        }
        None => AnnotateOutcome::Rejected(rejected(
            task,
            difficulty,
            UnansweredKind::Invalid,
            "the task asked no question".to_owned(),
        )),
    })
}

/// The annotation row of `description` (kept word for word) with ID `id`, asked of the model
/// with `examples` as in-context examples; `difficulty` `None` leaves the level to the model.
///
/// # Errors
/// [`VlmError`] when no answer could be obtained (network, key, model).
pub async fn annotate<V: Vlm>(
    session: &Session<V>,
    description: &str,
    difficulty: Option<AnnotationLevel>,
    examples: Vec<AnnotatedDescription>,
    id: &str,
) -> Result<AnnotateOutcome, VlmError> {
    let scope = CheckScope::UserDescription {
        difficulty_given: difficulty.is_some(),
    };
    let task = AnnotationTask::annotate(description, difficulty)
        .with_examples(examples)
        .with_checker(entry_checker(scope));
    ask_row(session, &task, difficulty, id).await
}

/// What went wrong in [`generate`].
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum GenerateError {
    /// The examples or the output file cannot be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: AnnotationError,
    },
    /// The rejected file cannot be read.
    #[error("cannot read {}", path.display())]
    ReadRejected {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A list of descriptions cannot be read.
    #[error("cannot read the descriptions in {}", path.display())]
    ReadList {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The rejected file holds a line that is not a rejected candidate.
    #[error("{}: line {line} is not a rejected candidate", path.display())]
    RejectedFile {
        /// The file.
        path: PathBuf,
        /// The line, from 1.
        line: usize,
        /// Why.
        #[source]
        source: serde_json::Error,
    },
    /// An accepted row cannot be written as it would not read back unchanged.
    #[error("row {id} cannot be written")]
    Unwritable {
        /// The row's ID.
        id: String,
        /// Why.
        #[source]
        source: AnnotationError,
    },
    /// A file cannot be written.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// No answer could be obtained from the model (network, key, model); the rows accepted so
    /// far are saved.
    #[error("the model gave no answer")]
    Vlm(#[from] VlmError),
    /// The options are inconsistent.
    #[error("{0}")]
    Options(String),
    /// A rejected candidate cannot be written as JSON.
    #[error("a rejected candidate cannot be written as JSON")]
    Json(#[from] serde_json::Error),
}

/// The options of [`generate`].
#[derive(Debug, Clone)]
pub struct GenerateOptions {
    /// The annotation file the accepted rows are appended to (CSV, or JSON for `.json`),
    /// created if missing; the rejected candidates go to [`rejected_path`] of it.
    pub out: PathBuf,
    /// How many rows `out` should hold in the end (rows already there count).
    pub count: usize,
    /// The level of every description; `None` cycles through easy, medium and hard.
    pub difficulty: Option<AnnotationLevel>,
    /// The seed of the draw of in-context examples.
    pub seed: u64,
    /// In-context examples per request.
    pub examples_per_request: usize,
    /// The first ID when `out` has no rows (default: one more than the examples' largest
    /// integer ID, or 0).
    pub first_id: Option<u64>,
    /// Similarity at and above which a description is too similar
    /// ([`DEFAULT_THRESHOLD`]).
    pub threshold: f64,
    /// The most candidates this run asks for before it stops short of `count` (each is one
    /// request, or two when asked again).
    pub max_candidates: usize,
}

impl GenerateOptions {
    /// `count` rows in `out`, every other option at its default: all levels, seed 0,
    /// [`DEFAULT_EXAMPLES_PER_REQUEST`], [`DEFAULT_THRESHOLD`], at most three candidates per
    /// row to make.
    pub fn new(out: impl Into<PathBuf>, count: usize) -> Self {
        GenerateOptions {
            out: out.into(),
            count,
            difficulty: None,
            seed: 0,
            examples_per_request: DEFAULT_EXAMPLES_PER_REQUEST,
            first_id: None,
            threshold: DEFAULT_THRESHOLD,
            max_candidates: count.saturating_mul(3),
        }
    }
}

/// The rejected candidates' file of an output file: `OUT.rejected.jsonl` beside it.
pub fn rejected_path(out: &Path) -> PathBuf {
    let mut name = out.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(".rejected.jsonl");
    out.with_file_name(name)
}

/// What [`generate`] reports as it goes.
#[derive(Debug)]
pub enum GenerateEvent<'a> {
    /// The run starts: rows already in the output, rows wanted.
    Started {
        /// Rows already there.
        existing: usize,
        /// Rows wanted ([`GenerateOptions::count`]).
        target: usize,
    },
    /// A row was accepted and saved.
    Accepted(&'a AnnotationRow),
    /// A candidate was rejected and saved to the rejected file.
    Rejected(&'a RejectedCandidate),
}

/// What a [`generate`] run did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct GenerateSummary {
    /// Rows in the output before the run.
    pub existing: usize,
    /// Rows accepted by this run.
    pub accepted: usize,
    /// Candidates rejected by this run.
    pub rejected: usize,
    /// Rows in the output now.
    pub total: usize,
    /// Whether the run stopped at [`GenerateOptions::max_candidates`] short of the count.
    pub stopped_early: bool,
}

/// The state of a generation run: the output's rows, the rejected file's lines, what the
/// requests name.
struct Run<'o> {
    options: &'o GenerateOptions,
    rows: Annotations,
    rejected_lines: Vec<RejectedCandidate>,
    index: DescriptionIndex,
    /// The ID of each description of `index`, in order.
    index_ids: Vec<String>,
    recent: VecDeque<String>,
    too_similar: VecDeque<String>,
    next_id: u64,
}

fn push_bounded(list: &mut VecDeque<String>, text: String) {
    if list.len() == NAMED_DESCRIPTIONS {
        list.pop_front();
    }
    list.push_back(text);
}

fn max_id(rows: &[AnnotationRow]) -> Option<u64> {
    rows.iter().filter_map(|r| r.id.parse::<u64>().ok()).max()
}

impl<'o> Run<'o> {
    fn open(options: &'o GenerateOptions, examples: &Annotations) -> Result<Self, GenerateError> {
        let out = &options.out;
        let rows = read_rows(out)?;
        let rejected_lines = read_rejected(&rejected_path(out))?;
        let mut index = DescriptionIndex::new(options.threshold);
        let mut index_ids = Vec::new();
        for row in examples.rows.iter().chain(&rows.rows) {
            index.insert(&row.description);
            index_ids.push(row.id.clone());
        }
        let mut recent = VecDeque::new();
        for row in &rows.rows {
            push_bounded(&mut recent, row.description.clone());
        }
        // The descriptions an earlier run rejected as too similar: the next request still
        // asks for more variety than them.
        let mut too_similar = VecDeque::new();
        for line in &rejected_lines {
            if let (RejectReason::TooSimilar { .. }, Some(c)) = (&line.reason, &line.candidate) {
                push_bounded(&mut too_similar, c.description.clone());
            }
        }
        // IDs the review gave to rejected candidates are taken too.
        let rejected_ids = rejected_lines
            .iter()
            .filter_map(|l| l.id.as_deref()?.parse::<u64>().ok())
            .max();
        let next_id = match max_id(&rows.rows).max(rejected_ids) {
            Some(id) => id + 1,
            None if !rows.rows.is_empty() => rows.rows.len() as u64,
            None => options
                .first_id
                .unwrap_or_else(|| max_id(&examples.rows).map_or(0, |id| id + 1)),
        };
        Ok(Run {
            options,
            rows,
            rejected_lines,
            index,
            index_ids,
            recent,
            too_similar,
            next_id,
        })
    }

    /// Candidates made so far over every run: rows and rejected lines.
    fn candidates(&self) -> usize {
        self.rows.rows.len() + self.rejected_lines.len()
    }

    /// The user instruction of the next request: the descriptions to move away from.
    fn instruction(&self) -> String {
        let quote = |list: &VecDeque<String>| -> String {
            list.iter()
                .map(|d| format!("- {}", serde_json::to_string(d).unwrap_or_default()))
                .collect::<Vec<_>>()
                .join("\n")
        };
        let mut parts = Vec::new();
        if !self.too_similar.is_empty() {
            parts.push(format!(
                "These descriptions you wrote were rejected as too similar to existing ones. Have more variety: \
                 write a clearly different scene (another room type, other objects, another arrangement, \
                 other sentence structures):\n{}",
                quote(&self.too_similar)
            ));
        }
        if !self.recent.is_empty() {
            parts.push(format!(
                "These descriptions were already written; do not repeat them or their wording:\n{}",
                quote(&self.recent)
            ));
        }
        parts.join("\n")
    }

    fn save_rows(&self) -> Result<(), GenerateError> {
        write_rows(&self.options.out, &self.rows)
    }

    fn reject(&mut self, candidate: &RejectedCandidate) -> Result<(), GenerateError> {
        self.rejected_lines.push(candidate.clone());
        write_rejected(&rejected_path(&self.options.out), &self.rejected_lines)
    }
}

/// The rows of an annotation file ([`Annotations::read`]: JSON for `.json`, CSV otherwise);
/// none when the file does not exist.
///
/// # Errors
/// [`GenerateError::Read`] naming the file.
pub fn read_rows(path: &Path) -> Result<Annotations, GenerateError> {
    if !path.exists() {
        return Ok(Annotations::new());
    }
    Annotations::read(path).map_err(|source| GenerateError::Read {
        path: path.to_owned(),
        source,
    })
}

/// Writes `rows` to `path` atomically ([`sceneeval_files::write_atomic`]), in the JSON form for `.json`
/// and as CSV otherwise.
///
/// # Errors
/// [`GenerateError::Unwritable`] when a row would not read back unchanged (naming the last
/// row's ID), [`GenerateError::Write`] when the file cannot be written.
pub fn write_rows(path: &Path, rows: &Annotations) -> Result<(), GenerateError> {
    let is_json = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let unwritable = |source| GenerateError::Unwritable {
        id: rows.rows.last().map(|r| r.id.clone()).unwrap_or_default(),
        source,
    };
    let text = if is_json {
        rows.to_json_string().map_err(unwritable)? + "\n"
    } else {
        rows.to_csv_string().map_err(unwritable)?
    };
    write_atomic(path, text.as_bytes())
}

/// The lines of a rejected file (`OUT.rejected.jsonl`, [`rejected_path`]), blank lines
/// skipped; none when the file does not exist.
///
/// # Errors
/// [`GenerateError::ReadRejected`] when it cannot be read, [`GenerateError::RejectedFile`]
/// naming the file and the line that is not a [`RejectedCandidate`].
pub fn read_rejected(path: &Path) -> Result<Vec<RejectedCandidate>, GenerateError> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let text = std::fs::read_to_string(path).map_err(|source| GenerateError::ReadRejected {
        path: path.to_owned(),
        source,
    })?;
    let mut lines = Vec::new();
    for (i, line) in text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let candidate = serde_json::from_str::<RejectedCandidate>(line).map_err(|source| {
            GenerateError::RejectedFile {
                path: path.to_owned(),
                line: i + 1,
                source,
            }
        })?;
        lines.push(candidate);
    }
    Ok(lines)
}

/// Writes `lines` to the rejected file `path` atomically ([`sceneeval_files::write_atomic`]), one JSON
/// object per line.
///
/// # Errors
/// [`GenerateError::Json`] or [`GenerateError::Write`].
pub fn write_rejected(path: &Path, lines: &[RejectedCandidate]) -> Result<(), GenerateError> {
    let mut text = String::new();
    for line in lines {
        text.push_str(&serde_json::to_string(line)?);
        text.push('\n');
    }
    write_atomic(path, text.as_bytes())
}

/// Writes `bytes` to `path` atomically, the error naming the file.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), GenerateError> {
    sceneeval_files::write_atomic(path, bytes).map_err(|source| GenerateError::Write {
        path: path.to_owned(),
        source,
    })
}

/// Whether two texts have the same words (runs of whitespace made one).
fn same_words(a: &str, b: &str) -> bool {
    a.split_whitespace().eq(b.split_whitespace())
}

/// In-context examples are shown when there are any: at least one per request then.
fn check_examples_per_request(k: usize, examples: &Annotations) -> Result<(), GenerateError> {
    if k == 0 && !examples.rows.is_empty() {
        return Err(GenerateError::Options(
            "examples per request must be at least 1".to_owned(),
        ));
    }
    Ok(())
}

/// New descriptions with their annotations, the paper's process: each request shows
/// [`GenerateOptions::examples_per_request`] rows of `examples` (drawn with the seed, of the
/// requested level when the file has such rows) and names the last accepted descriptions and
/// those rejected as too similar; each answer is checked ([`entry_checker`], asked again once
/// with the findings), compared with the examples and the accepted rows, and appended to
/// [`GenerateOptions::out`] (accepted) or to its [`rejected_path`] (rejected), each file
/// rewritten atomically. Stops when the output holds [`GenerateOptions::count`] rows or after
/// [`GenerateOptions::max_candidates`] candidates.
///
/// # Errors
/// [`GenerateError`]: a file that cannot be read or written, or a request without an answer
/// (the rows accepted so far are saved; a re-run continues).
pub fn generate<V: Vlm>(
    session: &Session<V>,
    examples: &Annotations,
    options: &GenerateOptions,
    on_event: &dyn Fn(&GenerateEvent<'_>),
) -> Result<GenerateSummary, GenerateError> {
    check_examples_per_request(options.examples_per_request, examples)?;
    let mut run = Run::open(options, examples)?;
    let existing = run.rows.rows.len();
    on_event(&GenerateEvent::Started {
        existing,
        target: options.count,
    });
    let (mut accepted, mut rejected_now, mut asked) = (0, 0, 0);
    while run.rows.rows.len() < options.count && asked < options.max_candidates {
        asked += 1;
        let n = run.candidates() as u64;
        let level = options
            .difficulty
            .unwrap_or(AnnotationLevel::ALL[(n % 3) as usize]);
        let shown = draw_examples(
            &examples.rows,
            Some(level),
            options.examples_per_request,
            options.seed.wrapping_add(n),
        );
        let task = AnnotationTask::generate(level, run.instruction())
            .with_examples(shown)
            .with_checker(entry_checker(CheckScope::Generated));
        let id = run.next_id.to_string();
        let outcome = pollster::block_on(ask_row(session, &task, Some(level), &id))?;
        match outcome {
            AnnotateOutcome::Accepted { row, attempt } => {
                if let Some(near) = run.index.too_similar(&row.description) {
                    let candidate = RejectedCandidate {
                        id: None,
                        difficulty: Some(level.name().to_owned()),
                        candidate: Some(example_of(&row)),
                        reason: RejectReason::TooSimilar {
                            near_id: run.index_ids.get(near.index).cloned().unwrap_or_default(),
                            near_description: near.description,
                            score: near.score,
                        },
                    };
                    tracing::info!(score = near.score, "generated description too similar; rejected");
                    push_bounded(&mut run.too_similar, row.description.clone());
                    run.reject(&candidate)?;
                    rejected_now += 1;
                    on_event(&GenerateEvent::Rejected(&candidate));
                    continue;
                }
                tracing::info!(id = %row.id, attempt, "generated row accepted");
                run.index.insert(&row.description);
                run.index_ids.push(row.id.clone());
                push_bounded(&mut run.recent, row.description.clone());
                run.rows.rows.push(row);
                run.next_id += 1;
                run.save_rows()?;
                accepted += 1;
                if let Some(row) = run.rows.rows.last() {
                    on_event(&GenerateEvent::Accepted(row));
                }
            }
            AnnotateOutcome::Rejected(candidate) => {
                tracing::info!(reason = ?candidate.reason, "generated candidate rejected");
                run.reject(&candidate)?;
                rejected_now += 1;
                on_event(&GenerateEvent::Rejected(&candidate));
            }
        }
    }
    let total = run.rows.rows.len();
    Ok(GenerateSummary {
        existing,
        accepted,
        rejected: rejected_now,
        total,
        stopped_early: total < options.count,
    })
}

/// The options of [`annotate_all`].
#[derive(Debug, Clone)]
pub struct AnnotateAllOptions {
    /// The annotation file the accepted rows are appended to (CSV, or JSON for `.json`),
    /// created if missing; the rejected candidates go to [`rejected_path`] of it.
    pub out: PathBuf,
    /// The level of every description; `None` leaves it to the model.
    pub difficulty: Option<AnnotationLevel>,
    /// The ID of the first description; the n-th (from 0) has `first_id + n`.
    pub first_id: u64,
    /// The seed of the draw of in-context examples (description n draws with `seed + n`).
    pub seed: u64,
    /// In-context examples per request.
    pub examples_per_request: usize,
}

impl AnnotateAllOptions {
    /// Rows to `out`, IDs from 0, every other option at its default: the level left to the
    /// model, seed 0, [`DEFAULT_EXAMPLES_PER_REQUEST`].
    pub fn new(out: impl Into<PathBuf>) -> Self {
        AnnotateAllOptions {
            out: out.into(),
            difficulty: None,
            first_id: 0,
            seed: 0,
            examples_per_request: DEFAULT_EXAMPLES_PER_REQUEST,
        }
    }
}

/// The descriptions of a list: one per line, in order, each trimmed; empty lines are left
/// out (and not numbered).
pub fn description_lines(text: &str) -> Vec<String> {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .map(str::to_owned)
        .collect()
}

/// The descriptions of a list file ([`description_lines`]; a regular UTF-8 file).
///
/// # Errors
/// [`GenerateError::ReadList`] naming the file.
pub fn read_descriptions(path: &Path) -> Result<Vec<String>, GenerateError> {
    let read = || -> std::io::Result<String> {
        let mut text = String::new();
        std::io::Read::read_to_string(&mut sceneeval_files::open_regular(path)?, &mut text)?;
        Ok(text)
    };
    read()
        .map(|text| description_lines(&text))
        .map_err(|source| GenerateError::ReadList {
            path: path.to_owned(),
            source,
        })
}

/// The annotation rows of a list of the user's own descriptions: description `n` (from 0) is
/// annotated as [`annotate`] does (word for word, the level given or left to the model, the
/// answer checked and asked again once) with the ID `first_id + n`, and its row appended to
/// [`AnnotateAllOptions::out`], or its rejected candidate (with that ID, so that the review
/// keeps it: [`review`]) to the [`rejected_path`] of it, each file rewritten atomically after
/// each description. A re-run continues: a description with a row, or with a rejected
/// candidate that holds an answer (to fix in the review), is not asked again; one rejected
/// without an answer (a refusal, an answer cut off at the token limit or off the schema) is
/// asked again and its old line replaced. The list must keep its order (new descriptions go
/// at its end). The summary's `existing` counts the descriptions done before the run,
/// `stopped_early` is always false.
///
/// # Errors
/// [`GenerateError`]: a file that cannot be read or written, an ID of `out` used twice, or a
/// request without an answer (what was done so far is saved; a re-run continues).
pub fn annotate_all<V: Vlm>(
    session: &Session<V>,
    descriptions: &[String],
    examples: &Annotations,
    options: &AnnotateAllOptions,
    on_event: &dyn Fn(&GenerateEvent<'_>),
) -> Result<GenerateSummary, GenerateError> {
    check_examples_per_request(options.examples_per_request, examples)?;
    let out = &options.out;
    let mut rows = read_rows(out)?;
    let mut rejected_lines = read_rejected(&rejected_path(out))?;
    // Done: a row, or a rejected candidate with an answer to review. A rejection without one
    // (a refusal, an answer cut off or off the schema) is asked again.
    let done = |id: &str, rows: &Annotations, rejected: &[RejectedCandidate]| {
        rows.get(id).is_some()
            || rejected
                .iter()
                .any(|l| l.id.as_deref() == Some(id) && l.candidate.is_some())
    };
    let existing = (0..descriptions.len() as u64)
        .filter(|n| done(&(options.first_id + n).to_string(), &rows, &rejected_lines))
        .count();
    on_event(&GenerateEvent::Started {
        existing,
        target: descriptions.len(),
    });
    let (mut accepted, mut rejected_now) = (0, 0);
    for (n, description) in (0u64..).zip(descriptions) {
        let id = options.first_id.saturating_add(n).to_string();
        if let Some(row) = rows.get(&id)
            && !same_words(&row.description, description)
        {
            return Err(GenerateError::Options(format!(
                "{}: row {id} describes {:?}, but description {} of the list (ID {id}) is {:?}: \
                 the list changed order or --id changed since the earlier run (keep its order, add \
                 new descriptions at its end)",
                out.display(),
                row.description,
                n + 1,
                description
            )));
        }
        if done(&id, &rows, &rejected_lines) {
            continue;
        }
        let shown = draw_examples(
            &examples.rows,
            options.difficulty,
            options.examples_per_request,
            options.seed.wrapping_add(n),
        );
        let outcome = pollster::block_on(annotate(session, description, options.difficulty, shown, &id))?;
        // An earlier rejection without an answer is replaced by this outcome.
        if rejected_lines
            .iter()
            .any(|l| l.id.as_deref() == Some(id.as_str()))
        {
            rejected_lines.retain(|l| l.id.as_deref() != Some(id.as_str()));
            write_rejected(&rejected_path(out), &rejected_lines)?;
        }
        match outcome {
            AnnotateOutcome::Accepted { row, attempt } => {
                tracing::info!(id = %row.id, attempt, "description annotated");
                rows.rows.push(row);
                write_rows(out, &rows)?;
                accepted += 1;
                if let Some(row) = rows.rows.last() {
                    on_event(&GenerateEvent::Accepted(row));
                }
            }
            AnnotateOutcome::Rejected(mut candidate) => {
                tracing::info!(%id, reason = ?candidate.reason, "description not annotated");
                candidate.id = Some(id);
                rejected_lines.push(candidate);
                write_rejected(&rejected_path(out), &rejected_lines)?;
                rejected_now += 1;
                if let Some(candidate) = rejected_lines.last() {
                    on_event(&GenerateEvent::Rejected(candidate));
                }
            }
        }
    }
    Ok(GenerateSummary {
        existing,
        accepted,
        rejected: rejected_now,
        total: rows.rows.len(),
        stopped_early: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_vlm::{AnswerContent, Scripted};
    use serde_json::json;

    fn answer(description: &str, difficulty: &str, counts: &[&str], attrs: &[&str]) -> AnswerContent {
        AnswerContent::Json {
            value: json!({"description": description, "difficulty": difficulty, "obj_count": counts,
                          "obj_attr": attrs, "oo_rel": [], "oa_rel": []}),
        }
    }

    /// An answer the validator accepts.
    fn study() -> AnswerContent {
        answer(
            "A study with a desk and a chair.",
            "easy",
            &["eq,1,desk", "eq,1,chair"],
            &[],
        )
    }

    /// An answer with a finding (`attribute-category-swapped`).
    fn hall_with_swapped_attribute() -> AnswerContent {
        answer(
            "A hall with a bench.",
            "easy",
            &["eq,1,bench"],
            &["eq,1,red,bench"],
        )
    }

    fn examples() -> Annotations {
        Annotations::from_csv_str(
            "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
             10,easy,A bedroom with a bed and a wardrobe.,\"eq,1,bed; eq,1,wardrobe\",,,\n\
             11,easy,A kitchen with a fridge and a stove.,\"eq,1,fridge; eq,1,stove\",,,\n\
             12,medium,\"A den with a sofa, a rug, a lamp, a table and two chairs.\",\
             \"eq,1,sofa; eq,1,rug; eq,1,lamp; eq,1,table; eq,2,chair\",,,\n",
        )
        .unwrap()
    }

    #[test]
    fn the_checker_is_the_validator() {
        let a = AnnotatedDescription {
            description: "A bedroom; a bed.".into(),
            difficulty: "easy".into(),
            obj_count: vec!["eq,1,bed".into()],
            obj_attr: vec!["eq,1,red,bed".into()],
            oo_rel: vec![],
            oa_rel: vec!["eq,1,against,bed,wal".into()],
        };
        let generated = entry_checker(CheckScope::Generated)(&a);
        let codes: Vec<&str> = generated.iter().map(|l| l.split(' ').next().unwrap()).collect();
        assert_eq!(
            codes,
            [
                "description-semicolon",
                "attribute-category-swapped",
                "unknown-arch-reference"
            ]
        );
        assert!(
            generated[1].contains("(suggestion: eq,1,bed,red)"),
            "{}",
            generated[1]
        );
        let user = entry_checker(CheckScope::UserDescription {
            difficulty_given: true,
        })(&a);
        assert_eq!(user.len(), 2, "the user's semicolon is not the model's to fix");
        // `;`-joined entries in one string are split like a CSV cell.
        let mut b = a.clone();
        b.obj_count = vec!["eq,1,bed; eq,1,desk".into()];
        assert_eq!(row_of(&b, "3").obj_count.len(), 2);
        assert_eq!(example_of(&row_of(&b, "3")).obj_count, ["eq,1,bed", "eq,1,desk"]);
    }

    #[test]
    fn a_list_of_descriptions_is_annotated_in_order_and_resumed() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("mine.csv");
        let list = dir.path().join("list.txt");
        std::fs::write(
            &list,
            "A study with a desk and a chair.\n\n  A hall with a bench.  \nA garage with a workbench.\n",
        )
        .unwrap();
        let descriptions = read_descriptions(&list).unwrap();
        assert_eq!(
            descriptions,
            [
                "A study with a desk and a chair.",
                "A hall with a bench.",
                "A garage with a workbench."
            ]
        );
        let vlm = Scripted::queue(
            "m",
            [
                // Description 0: accepted as ID 5.
                study(),
                // Description 1 and its re-ask: findings twice: rejected, with ID 6.
                hall_with_swapped_attribute(),
                hall_with_swapped_attribute(),
            ],
        );
        let session = Session::new(&vlm);
        let mut options = AnnotateAllOptions::new(&out);
        options.difficulty = Some(AnnotationLevel::Easy);
        options.first_id = 5;
        // Only the first two: the third comes in the second run.
        let summary = annotate_all(&session, &descriptions[..2], &examples(), &options, &|_| {}).unwrap();
        assert_eq!(
            summary,
            GenerateSummary {
                existing: 0,
                accepted: 1,
                rejected: 1,
                total: 1,
                stopped_early: false
            }
        );
        let rows = Annotations::read(&out).unwrap();
        assert_eq!(rows.rows.len(), 1);
        assert_eq!(rows.rows[0].id, "5");
        assert_eq!(rows.rows[0].description, "A study with a desk and a chair.");
        let lines = read_rejected(&rejected_path(&out)).unwrap();
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].id.as_deref(), Some("6"));
        assert!(
            matches!(&lines[0].reason, RejectReason::Findings { problems } if problems.contains("attribute-category-swapped"))
        );
        // The user's description with the in-context examples of its level.
        let requests = vlm.requests();
        assert_eq!(requests.len(), 3);
        assert!(requests[0].user_text.contains("A study with a desk and a chair."));
        assert!(
            requests[0]
                .user_text
                .contains("A bedroom with a bed and a wardrobe.")
        );

        // A re-run of the whole list asks only for description 2 (ID 7).
        let vlm = Scripted::queue(
            "m",
            [answer(
                "A garage with a workbench.",
                "easy",
                &["eq,1,workbench"],
                &[],
            )],
        );
        let session = Session::new(&vlm);
        let events = std::cell::RefCell::new(Vec::new());
        let summary = annotate_all(&session, &descriptions, &examples(), &options, &|e| {
            events.borrow_mut().push(match e {
                GenerateEvent::Started { existing, target } => format!("started {existing}/{target}"),
                GenerateEvent::Accepted(row) => format!("accepted {}", row.id),
                GenerateEvent::Rejected(c) => format!("rejected {:?}", c.id),
            });
        })
        .unwrap();
        assert_eq!(events.into_inner(), ["started 2/3", "accepted 7"]);
        assert_eq!(
            (
                summary.existing,
                summary.accepted,
                summary.rejected,
                summary.total
            ),
            (2, 1, 0, 2)
        );
        assert_eq!(vlm.requests().len(), 1);
        let ids: Vec<String> = Annotations::read(&out)
            .unwrap()
            .rows
            .into_iter()
            .map(|r| r.id)
            .collect();
        assert_eq!(ids, ["5", "7"]);

        // A list whose order changed is refused before any request.
        let reordered = [descriptions[2].clone(), descriptions[0].clone()];
        let vlm = Scripted::queue("m", [study()]);
        let err = annotate_all(&Session::new(&vlm), &reordered, &examples(), &options, &|_| {}).unwrap_err();
        assert!(err.to_string().contains("row 5 describes"), "{err}");
        assert!(vlm.requests().is_empty());

        // The review lists the rejected description with its ID, to be fixed by hand.
        let store = review::ReviewStore::open(&out, None).unwrap();
        let ids: Vec<&str> = store.candidates().iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["5", "7", "6"]);
    }

    #[test]
    fn an_empty_or_unreadable_list_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let list = dir.path().join("list.txt");
        std::fs::write(&list, "\n  \n").unwrap();
        assert!(read_descriptions(&list).unwrap().is_empty());
        let missing = dir.path().join("missing.txt");
        let err = read_descriptions(&missing).unwrap_err();
        assert!(err.to_string().contains("missing.txt"), "{err}");
    }

    #[test]
    fn generation_accepts_rejects_and_resumes() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("new.csv");
        let vlm = Scripted::queue(
            "m",
            [
                // 1: accepted as ID 13 (the examples' largest ID is 12).
                study(),
                // 2: a near copy of example 10: rejected; the next request names it.
                answer(
                    "A bedroom with beds and a wardrobe.",
                    "easy",
                    &["eq,2,bed", "eq,1,wardrobe"],
                    &[],
                ),
                // 3 and its re-ask: findings twice: a rejected candidate.
                hall_with_swapped_attribute(),
                hall_with_swapped_attribute(),
            ],
        );
        let session = Session::new(&vlm);
        let mut options = GenerateOptions::new(&out, 2);
        options.difficulty = Some(AnnotationLevel::Easy);
        options.max_candidates = 3;
        let summary = generate(&session, &examples(), &options, &|_| {}).unwrap();
        assert_eq!(
            summary,
            GenerateSummary {
                existing: 0,
                accepted: 1,
                rejected: 2,
                total: 1,
                stopped_early: true
            }
        );
        let rows = Annotations::read(&out).unwrap();
        assert_eq!(rows.ids().collect::<Vec<_>>(), ["13"]);
        let rejected = std::fs::read_to_string(rejected_path(&out)).unwrap();
        let lines: Vec<RejectedCandidate> = rejected
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert!(
            matches!(&lines[0].reason, RejectReason::TooSimilar { near_id, score, .. } if near_id == "10" && *score == 1.0)
        );
        assert!(
            matches!(&lines[1].reason, RejectReason::Findings { problems } if problems.contains("attribute-category-swapped"))
        );
        assert_eq!(lines[1].candidate.as_ref().unwrap().obj_attr, ["eq,1,red,bench"]);
        let requests = vlm.requests();
        assert_eq!(requests.len(), 4);
        // The request after the near copy names it.
        assert!(
            requests[0]
                .user_text
                .ends_with("generate a easy scene description and its annotations.")
        );
        assert!(requests[2].user_text.contains("rejected as too similar"));
        assert!(
            requests[2]
                .user_text
                .contains("\"A bedroom with beds and a wardrobe.\"")
        );
        assert!(
            requests[2]
                .user_text
                .contains("\"A study with a desk and a chair.\"")
        );
        assert!(requests[3].user_text.contains("attribute-category-swapped"));

        // A second run continues: one more row, ID 14, the first row not asked again.
        let vlm = Scripted::queue(
            "m",
            [answer(
                "A garage with a workbench.",
                "easy",
                &["eq,1,workbench"],
                &[],
            )],
        );
        let summary = generate(&Session::new(&vlm), &examples(), &options, &|_| {}).unwrap();
        assert_eq!((summary.existing, summary.accepted, summary.total), (1, 1, 2));
        let rows = Annotations::read(&out).unwrap();
        assert_eq!(rows.ids().collect::<Vec<_>>(), ["13", "14"]);
        assert!(rows.validate().is_empty());
        // Its request named the first row, and still asked for more variety than the
        // description the first run rejected as too similar (read back from the rejected file).
        let text = &vlm.requests()[0].user_text;
        assert!(text.contains("\"A study with a desk and a chair.\""));
        assert!(text.contains("rejected as too similar"), "{text}");
        assert!(text.contains("\"A bedroom with beds and a wardrobe.\""), "{text}");
        assert_eq!(
            std::fs::read_to_string(rejected_path(&out))
                .unwrap()
                .lines()
                .count(),
            2
        );
    }

    #[test]
    fn the_draw_without_a_level_takes_every_row() {
        let rows = examples().rows;
        let all = draw_examples(&rows, None, 5, 0);
        assert_eq!(all.len(), 3);
        let medium = draw_examples(&rows, Some(AnnotationLevel::Medium), 5, 0);
        assert_eq!(medium.len(), 1);
        assert!(medium[0].description.starts_with("A den"));
        // No hard row: every row is a candidate.
        assert_eq!(draw_examples(&rows, Some(AnnotationLevel::Hard), 2, 9).len(), 2);
        assert_eq!(draw_examples(&rows, None, 2, 4), draw_examples(&rows, None, 2, 4));
    }

    #[test]
    fn examples_are_drawn_from_the_level_with_the_seed() {
        let dir = tempfile::tempdir().unwrap();
        let mut options = GenerateOptions::new(dir.path().join("x.json"), 1);
        options.difficulty = Some(AnnotationLevel::Easy);
        options.examples_per_request = 1;
        options.first_id = Some(500);
        let ask = |options: &GenerateOptions| {
            let vlm = Scripted::queue(
                "m",
                [answer("A loft with a hammock.", "easy", &["eq,1,hammock"], &[])],
            );
            let _ = std::fs::remove_file(&options.out);
            generate(&Session::new(&vlm), &examples(), options, &|_| {}).unwrap();
            vlm.requests()[0].user_text.clone()
        };
        let first = ask(&options);
        assert!(first.contains("Here are 1 manually annotated examples"));
        assert!(!first.contains("A den with"), "only easy examples");
        assert_eq!(ask(&options), first, "the same seed draws the same examples");
        let rows = Annotations::read(&options.out).unwrap();
        assert_eq!(rows.ids().collect::<Vec<_>>(), ["500"]);
        let drawn: Vec<bool> = (0..8)
            .map(|seed| {
                options.seed = seed;
                ask(&options).contains("A bedroom with a bed")
            })
            .collect();
        assert!(drawn.contains(&true) && drawn.contains(&false), "{drawn:?}");
    }
}
