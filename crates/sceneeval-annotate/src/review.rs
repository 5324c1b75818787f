//! The review of generated candidates, the paper's manual step: a person reads each
//! candidate, edits it, accepts or rejects it; only accepted rows reach the annotation file
//! that `sceneeval evaluate --annotations` reads. [`ReviewStore`] is the files behind the
//! review page of `sceneeval annotations review`.
//!
//! The candidates are the rows of an annotation file (typically the output of [`generate`])
//! and the candidates of its rejected file ([`rejected_path`]) that have an answer: a rejected
//! candidate can be fixed by hand and accepted. Every decision is written at once, each file
//! atomically ([`sceneeval_files::write_atomic`]):
//!
//! - an edit rewrites the candidate where it lives (its row of the file, or its line of the
//!   rejected file, which then records the ID the review gave it);
//! - accept writes the row, with its final text, to the accepted file (by default the file's
//!   name with `.accepted` before the extension, [`accepted_path`]); a candidate accepted
//!   earlier and edited again is updated there in place (or goes back to pending when the
//!   edit has errors);
//! - reject records the candidate with the reviewer's note ([`RejectReason::Reviewer`]) in the
//!   rejected file of the accepted file.
//!
//! A candidate's state ([`ReviewState`]) is read from those files when the store opens: a
//! candidate whose ID is in the accepted file is accepted, in its rejected file rejected,
//! otherwise pending. A closed page, Ctrl-C or a killed process loses nothing, and a second
//! review continues where the first stopped.
//!
//! [`generate`]: crate::generate
//!
//! # Example
//! ```
//! use sceneeval_annotate::review::{ReviewState, ReviewStore};
//!
//! let dir = tempfile::tempdir().unwrap();
//! let file = dir.path().join("mine.csv");
//! std::fs::write(&file, "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
//!     7,easy,A bedroom with a bed.,\"eq,1,bed\",,,\n").unwrap();
//! let mut store = ReviewStore::open(&file, None).unwrap();
//! let mut content = store.candidate("7").unwrap().content.clone();
//! content.obj_attr.push("eq,1,bed,red".into());
//! content.description = "A bedroom with a red bed.".into();
//! store.accept("7", Some(content)).unwrap();
//! // The decision is on disk: a second store sees it.
//! let again = ReviewStore::open(&file, None).unwrap();
//! assert_eq!(again.candidate("7").unwrap().state, ReviewState::Accepted);
//! let accepted = std::fs::read_to_string(dir.path().join("mine.accepted.csv")).unwrap();
//! assert!(accepted.contains("A bedroom with a red bed.,\"eq,1,bed\",\"eq,1,bed,red\""));
//! ```

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::{
    GenerateError, RejectReason, RejectedCandidate, example_of, read_rejected, read_rows, rejected_path,
    row_of, write_rejected, write_rows,
};
use sceneeval_annotation::{AnnotationRow, Annotations, Finding, Severity, Stats, validate_row};
use sceneeval_vlm::tasks::AnnotatedDescription;

/// What went wrong in the review's files or decisions.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ReviewError {
    /// A file cannot be read or written (the error names it, and the line of a rejected file).
    #[error(transparent)]
    File(#[from] GenerateError),
    /// Two candidates have the same ID.
    #[error("{}: ID {id:?} is used twice (IDs must be unique to review a file)", path.display())]
    DuplicateId {
        /// The file of the second one.
        path: PathBuf,
        /// The ID.
        id: String,
    },
    /// No candidate has this ID.
    #[error("no candidate has ID {0:?}")]
    UnknownId(String),
    /// The candidate cannot be accepted: the validator finds errors in it.
    #[error("candidate {id} has {errors} error(s); fix them before accepting it")]
    HasErrors {
        /// The candidate's ID.
        id: String,
        /// How many errors.
        errors: usize,
    },
    /// The accepted file given is the reviewed file or its rejected file.
    #[error("the accepted rows cannot go to {} (the reviewed file or its rejected file)", .0.display())]
    SameFile(PathBuf),
    /// A rejection without a reason.
    #[error("a rejection needs a reason")]
    NoReason,
}

/// Where a candidate lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum CandidateSource {
    /// A row of the reviewed file.
    File {
        /// The row's position, from 0.
        row: usize,
    },
    /// A line of the reviewed file's rejected file.
    Rejected {
        /// The line's position among the file's candidates, from 0.
        line: usize,
    },
}

/// A candidate's state, as the files say.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReviewState {
    /// Not decided yet.
    Pending,
    /// In the accepted file.
    Accepted,
    /// In the accepted file's rejected file.
    Rejected,
}

/// One candidate of the review.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Its row ID: the row's, or for a rejected candidate the one the review gave it.
    pub id: String,
    /// Where it lives.
    pub source: CandidateSource,
    /// Its state.
    pub state: ReviewState,
    /// Its text: description, difficulty and the four kinds' entries.
    pub content: AnnotatedDescription,
    /// Why `generate` rejected it (a candidate of the rejected file).
    pub generator_reason: Option<RejectReason>,
    /// The reviewer's reason, when rejected in the review.
    pub reviewer_note: Option<String>,
}

/// The accepted file of `file` by default: its name with `.accepted` before the extension
/// (`mine.csv` → `mine.accepted.csv`; `mine` → `mine.accepted`).
pub fn accepted_path(file: &Path) -> PathBuf {
    let stem = file.file_stem().map(|s| s.to_os_string()).unwrap_or_default();
    let mut name = stem;
    name.push(".accepted");
    if let Some(ext) = file.extension() {
        name.push(".");
        name.push(ext);
    }
    file.with_file_name(name)
}

/// The validator's findings of a candidate's text as the row with ID `id`
/// ([`validate_row`], the check of `sceneeval annotations check`).
pub fn findings(content: &AnnotatedDescription, id: &str) -> Vec<Finding> {
    validate_row(&row_of(content, id), 0)
}

/// The review's files and the state of every candidate; each decision writes the files at
/// once (module documentation).
#[derive(Debug)]
pub struct ReviewStore {
    file: PathBuf,
    rows: Annotations,
    rejected: Vec<RejectedCandidate>,
    accepted_file: PathBuf,
    accepted: Annotations,
    decisions: Vec<RejectedCandidate>,
    candidates: Vec<Candidate>,
}

impl ReviewStore {
    /// Opens the review of `file` (an annotation file; its rejected file is read when present)
    /// with the accepted rows in `accepted` (default [`accepted_path`]); neither the accepted
    /// file nor its rejected file need exist.
    ///
    /// # Errors
    /// [`ReviewError::File`] naming a file that cannot be read (and the line of a rejected
    /// file that is not a rejected candidate), [`ReviewError::DuplicateId`].
    pub fn open(file: &Path, accepted: Option<&Path>) -> Result<Self, ReviewError> {
        let rows = Annotations::read(file).map_err(|source| GenerateError::Read {
            path: file.to_owned(),
            source,
        })?;
        let rejected = read_rejected(&rejected_path(file))?;
        let accepted_file = accepted.map_or_else(|| accepted_path(file), Path::to_owned);
        if [file.to_owned(), rejected_path(file)].contains(&accepted_file) {
            return Err(ReviewError::SameFile(accepted_file));
        }
        let accepted_rows = read_rows(&accepted_file)?;
        let decisions = read_rejected(&rejected_path(&accepted_file))?;
        let mut store = ReviewStore {
            file: file.to_owned(),
            rows,
            rejected,
            accepted_file,
            accepted: accepted_rows,
            decisions,
            candidates: Vec::new(),
        };
        store.candidates = store.list()?;
        tracing::info!(
            file = %store.file.display(),
            candidates = store.candidates.len(),
            "review opened"
        );
        Ok(store)
    }

    /// The candidates from the files: IDs checked, rejected candidates without one given the
    /// next free integer.
    fn list(&self) -> Result<Vec<Candidate>, ReviewError> {
        let mut used = HashSet::new();
        let mut out = Vec::new();
        for (i, row) in self.rows.rows.iter().enumerate() {
            if !used.insert(row.id.clone()) {
                return Err(ReviewError::DuplicateId {
                    path: self.file.clone(),
                    id: row.id.clone(),
                });
            }
            out.push(self.candidate_of(
                row.id.clone(),
                CandidateSource::File { row: i },
                example_of(row),
                None,
            ));
        }
        for line in &self.rejected {
            if let Some(id) = &line.id
                && !used.insert(id.clone())
            {
                return Err(ReviewError::DuplicateId {
                    path: rejected_path(&self.file),
                    id: id.clone(),
                });
            }
        }
        // Fresh IDs number on from the largest integer ID of every file.
        let all_ids = used
            .iter()
            .map(String::as_str)
            .chain(self.accepted.ids())
            .chain(self.decisions.iter().filter_map(|d| d.id.as_deref()));
        let mut next = all_ids
            .filter_map(|id| id.parse::<u64>().ok())
            .max()
            .map_or(0, |m| m + 1);
        for (i, line) in self.rejected.iter().enumerate() {
            let Some(content) = &line.candidate else {
                continue; // nothing to review: the model gave no usable answer
            };
            let id = match &line.id {
                Some(id) => id.clone(),
                None => {
                    // Above every integer ID of every file: never taken.
                    next += 1;
                    (next - 1).to_string()
                }
            };
            out.push(self.candidate_of(
                id,
                CandidateSource::Rejected { line: i },
                content.clone(),
                Some(line.reason.clone()),
            ));
        }
        Ok(out)
    }

    fn candidate_of(
        &self,
        id: String,
        source: CandidateSource,
        content: AnnotatedDescription,
        generator_reason: Option<RejectReason>,
    ) -> Candidate {
        let decision = self
            .decisions
            .iter()
            .find(|d| d.id.as_deref() == Some(id.as_str()));
        let (state, reviewer_note) = if self.accepted.get(&id).is_some() {
            (ReviewState::Accepted, None)
        } else if let Some(d) = decision {
            let note = match &d.reason {
                RejectReason::Reviewer { note } => Some(note.clone()),
                _ => None,
            };
            (ReviewState::Rejected, note)
        } else {
            (ReviewState::Pending, None)
        };
        Candidate {
            id,
            source,
            state,
            content,
            generator_reason,
            reviewer_note,
        }
    }

    /// The reviewed file.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// The accepted file.
    pub fn accepted_file(&self) -> &Path {
        &self.accepted_file
    }

    /// Every candidate: the file's rows in order, then the rejected file's candidates.
    pub fn candidates(&self) -> &[Candidate] {
        &self.candidates
    }

    /// The candidate with ID `id`.
    pub fn candidate(&self, id: &str) -> Option<&Candidate> {
        self.candidates.iter().find(|c| c.id == id)
    }

    /// The accepted rows (the accepted file).
    pub fn accepted(&self) -> &Annotations {
        &self.accepted
    }

    /// The accepted rows' statistics, the paper's Table 1 ([`Annotations::stats`]).
    pub fn stats(&self) -> Stats {
        self.accepted.stats()
    }

    fn position(&self, id: &str) -> Result<usize, ReviewError> {
        self.candidates
            .iter()
            .position(|c| c.id == id)
            .ok_or_else(|| ReviewError::UnknownId(id.to_owned()))
    }

    /// The row of candidate `index` with `content`: its ID, the text, and the extra columns
    /// of its row in the file.
    fn row(&self, index: usize, content: &AnnotatedDescription) -> AnnotationRow {
        let c = &self.candidates[index];
        let mut row = row_of(content, &c.id);
        if let CandidateSource::File { row: r } = c.source
            && let Some(old) = self.rows.rows.get(r)
        {
            row.extra = old.extra.clone();
        }
        row
    }

    /// Rewrites candidate `index` where it lives with `content` (a rejected candidate's line
    /// records its ID).
    fn write_source(&mut self, index: usize, content: &AnnotatedDescription) -> Result<(), ReviewError> {
        let row = self.row(index, content);
        let c = &mut self.candidates[index];
        match c.source {
            CandidateSource::File { row: r } => {
                if self.rows.rows.get(r) != Some(&row) {
                    let mut rows = self.rows.clone();
                    rows.rows[r] = row;
                    write_rows(&self.file, &rows)?;
                    self.rows = rows;
                }
            }
            CandidateSource::Rejected { line } => {
                let mut lines = self.rejected.clone();
                let l = &mut lines[line];
                if l.id.as_deref() != Some(c.id.as_str()) || l.candidate.as_ref() != Some(content) {
                    l.id = Some(c.id.clone());
                    l.candidate = Some(content.clone());
                    write_rejected(&rejected_path(&self.file), &lines)?;
                    self.rejected = lines;
                }
            }
        }
        c.content = content.clone();
        Ok(())
    }

    fn write_accepted(&mut self, accepted: Annotations) -> Result<(), ReviewError> {
        write_rows(&self.accepted_file, &accepted)?;
        self.accepted = accepted;
        Ok(())
    }

    fn write_decisions(&mut self, decisions: Vec<RejectedCandidate>) -> Result<(), ReviewError> {
        write_rejected(&rejected_path(&self.accepted_file), &decisions)?;
        self.decisions = decisions;
        Ok(())
    }

    /// Removes candidate `id` from the accepted file, if it is there.
    fn unaccept(&mut self, id: &str) -> Result<(), ReviewError> {
        if self.accepted.get(id).is_some() {
            let mut accepted = self.accepted.clone();
            accepted.rows.retain(|r| r.id != id);
            self.write_accepted(accepted)?;
        }
        Ok(())
    }

    /// Removes candidate `id` from the review's rejected file, if it is there.
    fn unreject(&mut self, id: &str) -> Result<(), ReviewError> {
        if self.decisions.iter().any(|d| d.id.as_deref() == Some(id)) {
            let mut decisions = self.decisions.clone();
            decisions.retain(|d| d.id.as_deref() != Some(id));
            self.write_decisions(decisions)?;
        }
        Ok(())
    }

    /// Saves an edit of candidate `id`: rewritten where it lives; an accepted candidate is
    /// updated in the accepted file in place, or goes back to pending (removed from it) when
    /// the edit has errors; a rejected one is updated in the review's rejected file.
    ///
    /// # Errors
    /// [`ReviewError::UnknownId`], or a file that cannot be written
    /// ([`GenerateError::Unwritable`] for text that would not read back unchanged).
    pub fn edit(&mut self, id: &str, content: AnnotatedDescription) -> Result<&Candidate, ReviewError> {
        let i = self.position(id)?;
        let row = self.row(i, &content);
        // Check before any write that the row can be written.
        Annotations::from_rows(vec![row.clone()])
            .check_writable()
            .map_err(|source| GenerateError::Unwritable {
                id: id.to_owned(),
                source,
            })?;
        self.write_source(i, &content)?;
        match self.candidates[i].state {
            ReviewState::Accepted if error_count(&row) > 0 => {
                self.unaccept(id)?;
                self.candidates[i].state = ReviewState::Pending;
                tracing::info!(id, "accepted candidate edited with errors: back to pending");
            }
            ReviewState::Accepted => {
                let mut accepted = self.accepted.clone();
                if let Some(r) = accepted.get_mut(id) {
                    *r = row;
                }
                if accepted != self.accepted {
                    self.write_accepted(accepted)?;
                }
            }
            ReviewState::Rejected => {
                let mut decisions = self.decisions.clone();
                for d in decisions.iter_mut().filter(|d| d.id.as_deref() == Some(id)) {
                    d.candidate = Some(content.clone());
                    d.difficulty = Some(content.difficulty.clone());
                }
                if decisions != self.decisions {
                    self.write_decisions(decisions)?;
                }
            }
            ReviewState::Pending => {}
        }
        Ok(&self.candidates[i])
    }

    /// Accepts candidate `id`, with `content` when given (saved as by [`ReviewStore::edit`]
    /// first): its row goes to the accepted file (replacing a row with its ID), and out of the
    /// review's rejected file. Warnings do not stop it: they are the reviewer's call.
    ///
    /// # Errors
    /// [`ReviewError::HasErrors`] when the validator finds errors (nothing is written then),
    /// [`ReviewError::UnknownId`], or a file that cannot be written.
    pub fn accept(
        &mut self,
        id: &str,
        content: Option<AnnotatedDescription>,
    ) -> Result<&Candidate, ReviewError> {
        let i = self.position(id)?;
        let content = content.unwrap_or_else(|| self.candidates[i].content.clone());
        let row = self.row(i, &content);
        let errors = error_count(&row);
        if errors > 0 {
            return Err(ReviewError::HasErrors {
                id: id.to_owned(),
                errors,
            });
        }
        self.edit(id, content)?;
        // Out of the rejected decisions first: a crash in between leaves it pending.
        self.unreject(id)?;
        let mut accepted = self.accepted.clone();
        match accepted.get_mut(id) {
            Some(r) => *r = row,
            None => accepted.rows.push(row),
        }
        if accepted != self.accepted {
            self.write_accepted(accepted)?;
        }
        let c = &mut self.candidates[i];
        c.state = ReviewState::Accepted;
        c.reviewer_note = None;
        tracing::info!(id, "candidate accepted");
        Ok(&self.candidates[i])
    }

    /// Rejects candidate `id` with the reviewer's `note`, with `content` when given (saved as
    /// by [`ReviewStore::edit`] first): out of the accepted file, recorded in its rejected
    /// file ([`RejectReason::Reviewer`]).
    ///
    /// # Errors
    /// [`ReviewError::NoReason`] for an empty note, [`ReviewError::UnknownId`], or a file that
    /// cannot be written.
    pub fn reject(
        &mut self,
        id: &str,
        content: Option<AnnotatedDescription>,
        note: &str,
    ) -> Result<&Candidate, ReviewError> {
        let note = note.trim();
        if note.is_empty() {
            return Err(ReviewError::NoReason);
        }
        let i = self.position(id)?;
        // Saved first even unchanged: a rejected candidate's line records its ID.
        let content = content.unwrap_or_else(|| self.candidates[i].content.clone());
        self.edit(id, content)?;
        self.unaccept(id)?;
        let content = self.candidates[i].content.clone();
        let line = RejectedCandidate {
            id: Some(id.to_owned()),
            difficulty: Some(content.difficulty.clone()),
            candidate: Some(content),
            reason: RejectReason::Reviewer {
                note: note.to_owned(),
            },
        };
        let mut decisions = self.decisions.clone();
        match decisions.iter_mut().find(|d| d.id.as_deref() == Some(id)) {
            Some(d) => *d = line,
            None => decisions.push(line),
        }
        self.write_decisions(decisions)?;
        let c = &mut self.candidates[i];
        c.state = ReviewState::Rejected;
        c.reviewer_note = Some(note.to_owned());
        tracing::info!(id, "candidate rejected");
        Ok(&self.candidates[i])
    }
}

fn error_count(row: &AnnotationRow) -> usize {
    validate_row(row, 0)
        .iter()
        .filter(|f| f.severity == Severity::Error)
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
        20,easy,A bedroom with a bed and a wardrobe.,\"eq,1,bed; eq,1,wardrobe\",,,\n\
        21,easy,A kitchen with a fridge.,\"eq,1,fridge\",,,\n";

    /// Two lines: a near copy (with an answer) and a refusal (without).
    const REJECTED: &str = concat!(
        r#"{"difficulty":"easy","candidate":{"description":"A hall with a bench.","difficulty":"easy","obj_count":["eq,1,bench"],"obj_attr":["eq,1,red,bench"],"oo_rel":[],"oa_rel":[]},"reason":"findings","problems":"attribute-category-swapped"}"#,
        "\n",
        r#"{"difficulty":"easy","candidate":null,"reason":"refused","detail":"no"}"#,
        "\n"
    );

    fn setup() -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("mine.csv");
        std::fs::write(&file, FILE).unwrap();
        std::fs::write(rejected_path(&file), REJECTED).unwrap();
        (dir, file)
    }

    #[test]
    fn accepted_path_puts_accepted_before_the_extension() {
        assert_eq!(
            accepted_path(Path::new("a/mine.csv")),
            Path::new("a/mine.accepted.csv")
        );
        assert_eq!(accepted_path(Path::new("m.json")), Path::new("m.accepted.json"));
        assert_eq!(accepted_path(Path::new("mine")), Path::new("mine.accepted"));
    }

    #[test]
    fn candidates_are_the_rows_and_the_rejected_answers() {
        let (_dir, file) = setup();
        let store = ReviewStore::open(&file, None).unwrap();
        let ids: Vec<&str> = store.candidates().iter().map(|c| c.id.as_str()).collect();
        // The rejected candidate gets the next integer after 21; the refusal has no answer.
        assert_eq!(ids, ["20", "21", "22"]);
        let c = store.candidate("22").unwrap();
        assert_eq!(c.source, CandidateSource::Rejected { line: 0 });
        assert_eq!(c.state, ReviewState::Pending);
        assert!(matches!(c.generator_reason, Some(RejectReason::Findings { .. })));
        // The swapped attribute is an error of the validator.
        let f = findings(&c.content, &c.id);
        assert_eq!(f[0].code.to_string(), "attribute-category-swapped");
    }

    #[test]
    fn decisions_are_files_and_survive_a_restart() {
        let (dir, file) = setup();
        let mut store = ReviewStore::open(&file, None).unwrap();
        // Accepting the swapped attribute is refused, nothing written.
        let bad = store.candidate("22").unwrap().content.clone();
        let err = store.accept("22", Some(bad.clone())).unwrap_err();
        assert!(matches!(err, ReviewError::HasErrors { errors: 1, .. }), "{err}");
        assert!(!accepted_path(&file).exists());
        // Fixed by hand and accepted: the line records its ID, the row goes to the accepted file.
        let mut fixed = bad;
        fixed.obj_attr = vec!["eq,1,bench,red".into()];
        store.accept("22", Some(fixed)).unwrap();
        store.reject("21", None, "  too plain ").unwrap();
        assert_eq!(
            store.reject("20", None, " ").unwrap_err().to_string(),
            "a rejection needs a reason"
        );
        let rejected = std::fs::read_to_string(rejected_path(&file)).unwrap();
        assert!(rejected.starts_with(r#"{"id":"22","difficulty":"easy","candidate":{"description":"A hall with a bench.","difficulty":"easy","obj_count":["eq,1,bench"],"obj_attr":["eq,1,bench,red"]"#), "{rejected}");
        let accepted = Annotations::read(accepted_path(&file)).unwrap();
        assert_eq!(accepted.ids().collect::<Vec<_>>(), ["22"]);
        let decisions = read_rejected(&rejected_path(&accepted_path(&file))).unwrap();
        assert_eq!(decisions.len(), 1);
        assert_eq!(decisions[0].id.as_deref(), Some("21"));
        assert_eq!(
            decisions[0].reason,
            RejectReason::Reviewer {
                note: "too plain".into()
            }
        );
        // Every write was atomic: no temporary file is left.
        assert_eq!(
            sceneeval_test_support::file_names(dir.path()),
            [
                "mine.accepted.csv",
                "mine.accepted.csv.rejected.jsonl",
                "mine.csv",
                "mine.csv.rejected.jsonl"
            ]
        );

        // A second store sees the same states.
        let mut again = ReviewStore::open(&file, None).unwrap();
        let states: Vec<(&str, ReviewState)> = again
            .candidates()
            .iter()
            .map(|c| (c.id.as_str(), c.state))
            .collect();
        assert_eq!(
            states,
            [
                ("20", ReviewState::Pending),
                ("21", ReviewState::Rejected),
                ("22", ReviewState::Accepted)
            ]
        );
        assert_eq!(
            again.candidate("21").unwrap().reviewer_note.as_deref(),
            Some("too plain")
        );

        // Accepting the rejected one moves it; editing an accepted one updates it in place.
        again.accept("21", None).unwrap();
        let mut edit = again.candidate("21").unwrap().content.clone();
        edit.description = "A kitchen with a white fridge.".into();
        edit.obj_attr = vec!["eq,1,fridge,white".into()];
        again.edit("21", edit).unwrap();
        let accepted = Annotations::read(accepted_path(&file)).unwrap();
        assert_eq!(accepted.ids().collect::<Vec<_>>(), ["22", "21"]);
        assert_eq!(
            accepted.get("21").unwrap().description,
            "A kitchen with a white fridge."
        );
        assert!(
            read_rejected(&rejected_path(&accepted_path(&file)))
                .unwrap()
                .is_empty()
        );
        // The edit rewrote the row of the reviewed file too.
        assert_eq!(
            Annotations::read(&file).unwrap().get("21").unwrap().description,
            "A kitchen with a white fridge."
        );
        // An edit with errors sends an accepted candidate back to pending.
        let mut broken = again.candidate("21").unwrap().content.clone();
        broken.obj_attr = vec!["eq,1,white,fridge".into()];
        assert_eq!(again.edit("21", broken).unwrap().state, ReviewState::Pending);
        let accepted = Annotations::read(accepted_path(&file)).unwrap();
        assert_eq!(accepted.ids().collect::<Vec<_>>(), ["22"]);
        let third = ReviewStore::open(&file, None).unwrap();
        assert_eq!(third.candidate("21").unwrap().state, ReviewState::Pending);
        assert_eq!(third.candidate("22").unwrap().id, "22", "a recorded ID stays");
        assert_eq!(third.stats().groups[0].scenes, 1);
    }

    #[test]
    fn bad_files_name_the_file_and_line() {
        let (_dir, file) = setup();
        std::fs::write(rejected_path(&file), "{\"difficulty\":\"easy\"}\n\nnot json\n").unwrap();
        let err = ReviewStore::open(&file, None).unwrap_err();
        let text = sceneeval_files::ErrorChain::new(&err).to_string();
        assert!(
            text.contains("mine.csv.rejected.jsonl: line 1 is not a rejected candidate"),
            "{text}"
        );
        std::fs::write(rejected_path(&file), "").unwrap();
        let dup = FILE.to_owned() + "21,easy,Again.,\"eq,1,sofa\",,,\n";
        std::fs::write(&file, dup).unwrap();
        let err = ReviewStore::open(&file, None).unwrap_err().to_string();
        assert!(
            err.ends_with("mine.csv: ID \"21\" is used twice (IDs must be unique to review a file)"),
            "{err}"
        );
        std::fs::write(&file, "ID,Difficulty\n1,easy\n").unwrap();
        let err = ReviewStore::open(&file, None).unwrap_err();
        let text = sceneeval_files::ErrorChain::new(&err).to_string();
        assert!(
            text.contains("cannot read")
                && text.contains("mine.csv")
                && text.contains("missing required column"),
            "{text}"
        );
        let err = ReviewStore::open(&file.with_file_name("none.csv"), None).unwrap_err();
        assert!(
            sceneeval_files::ErrorChain::new(&err)
                .to_string()
                .contains("none.csv")
        );
    }

    #[test]
    fn a_rejected_candidate_keeps_the_id_it_was_rejected_with() {
        let (_dir, file) = setup();
        let mut store = ReviewStore::open(&file, None).unwrap();
        store.reject("22", None, "not a hall").unwrap();
        // A row added to the file later (by generate) with the next ID does not take it.
        let mut rows = Annotations::read(&file).unwrap();
        rows.rows.push(AnnotationRow::new(
            "23",
            sceneeval_annotation::Difficulty::Easy,
            "A loft.",
        ));
        write_rows(&file, &rows).unwrap();
        let store = ReviewStore::open(&file, None).unwrap();
        let c = store.candidate("22").unwrap();
        assert_eq!(
            (c.state, c.source),
            (ReviewState::Rejected, CandidateSource::Rejected { line: 0 })
        );
        assert_eq!(store.candidate("23").unwrap().state, ReviewState::Pending);
        // The accepted rows cannot go to the reviewed file.
        let err = ReviewStore::open(&file, Some(&file)).unwrap_err();
        assert!(matches!(err, ReviewError::SameFile(_)), "{err}");
    }

    #[test]
    fn unknown_ids_are_errors_and_write_nothing() {
        let (dir, file) = setup();
        let before = sceneeval_test_support::file_names(dir.path());
        let mut store = ReviewStore::open(&file, None).unwrap();
        assert!(matches!(store.accept("99", None), Err(ReviewError::UnknownId(_))));
        let c = store.candidate("20").unwrap().content.clone();
        assert!(matches!(store.edit("x", c), Err(ReviewError::UnknownId(_))));
        assert!(matches!(
            store.reject("x", None, "no"),
            Err(ReviewError::UnknownId(_))
        ));
        assert_eq!(sceneeval_test_support::file_names(dir.path()), before);
        assert_eq!(std::fs::read_to_string(&file).unwrap(), FILE);
    }
}
