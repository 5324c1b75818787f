//! Writing a label file ([`crate::labels`]) as people judge: one JSON line appended per
//! verdict and synced to disk before the verdict counts as written, under an exclusive lock
//! of the file held for the whole session (`sceneeval judge`).
//!
//! - **Locked**: the file is locked with the operating system's advisory lock on open files
//!   (`flock` on Unix, `LockFileEx` on Windows; the lock `sceneeval evaluate` holds on its
//!   output folder), for as long as the [`LabelWriter`] lives. A second writer on the same
//!   file, in this process or another, is refused ([`LabelWriteError::Locked`]); the lock
//!   ends with the process, however it ends.
//! - **Durable**: a verdict is one `write` of its whole line, then `fsync` of the file
//!   ([`LabelWriter::append`] returns after both). A crash loses at most the verdict being
//!   written, and leaves at most one last line cut short, which the reader leaves out
//!   ([`crate::labels::LabelFile::torn`]) and the next writer removes before appending.
//! - **Resume**: the file's labels in force (a later line replaces an earlier one) are read
//!   when it is opened; [`LabelWriter::judged`] has the annotator's verdicts, so a session
//!   continues where the last one stopped.
//!
//! Only JSON Lines is written: a file whose name ends in `.csv` is refused.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::labels::{Item, Label, LabelError, LabelFile};

/// What went wrong opening a label file for writing or appending to it; every error names the
/// file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LabelWriteError {
    /// Another writer holds the file's lock.
    #[error(
        "{}: another sceneeval judge is writing this label file (it is locked); stop that one first, or give another --out",
        path.display()
    )]
    Locked {
        /// The file.
        path: PathBuf,
    },
    /// The file is CSV; verdicts are written as JSON Lines only.
    #[error(
        "{}: verdicts are written as JSON Lines; give a file whose name does not end in .csv (e.g. labels.jsonl)",
        path.display()
    )]
    Csv {
        /// The file.
        path: PathBuf,
    },
    /// A label to append is not this writer's annotator's, or its names are empty.
    #[error("{}: cannot append {what}", path.display())]
    BadLabel {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
    /// The file could not be opened, locked, read, written or synced.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// What the file holds is not a label file.
    #[error(transparent)]
    Read(#[from] LabelError),
}

/// A label file open for appending one annotator's verdicts, locked until dropped.
#[derive(Debug)]
pub struct LabelWriter {
    path: PathBuf,
    file: File,
    annotator: String,
    judged: BTreeMap<Item, Label>,
    appended: usize,
}

impl LabelWriter {
    /// Opens (or creates) the label file at `path` for `annotator`'s verdicts: locks it,
    /// reads the labels it has, removes a last line cut short by an earlier writer (and ends a
    /// complete last line that lacks its line end), so that appended lines are whole lines.
    ///
    /// # Errors
    /// [`LabelWriteError::Locked`] when another writer holds it, [`LabelWriteError::Csv`] for a
    /// `.csv` name, [`LabelWriteError::Read`] when a line of it is not a label,
    /// [`LabelWriteError::Io`] when it cannot be opened, locked, read or written (not a
    /// regular file, no permission).
    pub fn open(path: &Path, annotator: &str) -> Result<LabelWriter, LabelWriteError> {
        let io = |source| LabelWriteError::Io {
            path: path.to_owned(),
            source,
        };
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")) {
            return Err(LabelWriteError::Csv {
                path: path.to_owned(),
            });
        }
        if annotator.trim().is_empty() {
            return Err(LabelWriteError::BadLabel {
                path: path.to_owned(),
                what: "verdicts without an annotator's name".to_owned(),
            });
        }
        if path.exists() {
            // Never open a named pipe or a device (which could block) as a label file.
            sceneeval_files::check_regular(path).map_err(io)?;
        }
        let mut file = OpenOptions::new()
            .read(true)
            .append(true)
            .create(true)
            .open(path)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                return Err(LabelWriteError::Locked {
                    path: path.to_owned(),
                });
            }
            Err(TryLockError::Error(e)) => return Err(io(e)),
        }
        let mut text = String::new();
        file.seek(SeekFrom::Start(0)).map_err(io)?;
        file.read_to_string(&mut text).map_err(io)?;
        let read = LabelFile::from_jsonl_str(path, &text)?;
        if let Some(torn) = read.torn {
            tracing::warn!(
                path = %path.display(),
                line = torn.line,
                "removing the last line, cut short by an earlier writer (its verdict was never saved)"
            );
            file.set_len(torn.offset).map_err(io)?;
            file.sync_data().map_err(io)?;
        } else if !text.is_empty() && !text.ends_with('\n') {
            file.write_all(b"\n").map_err(io)?;
            file.sync_data().map_err(io)?;
        }
        let judged = read
            .labels
            .into_iter()
            .filter(|l| l.label.annotator == annotator)
            .map(|l| (l.label.item(), l.label))
            .collect();
        Ok(LabelWriter {
            path: path.to_owned(),
            file,
            annotator: annotator.to_owned(),
            judged,
            appended: 0,
        })
    }

    /// The file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The annotator whose verdicts this writer appends.
    #[must_use]
    pub fn annotator(&self) -> &str {
        &self.annotator
    }

    /// The annotator's verdicts in force (the file's, then those appended), by item.
    #[must_use]
    pub fn judged(&self) -> &BTreeMap<Item, Label> {
        &self.judged
    }

    /// How many lines this writer appended.
    #[must_use]
    pub fn appended(&self) -> usize {
        self.appended
    }

    /// Appends `label` as one line and syncs the file: when this returns `Ok`, the verdict is
    /// on disk. A later label for the same item replaces the earlier (in [`Self::judged`] and
    /// for every reader).
    ///
    /// # Errors
    /// [`LabelWriteError::BadLabel`] when the label is another annotator's or names no scene;
    /// [`LabelWriteError::Io`] when it cannot be written or synced (the verdict is then not
    /// recorded as judged).
    pub fn append(&mut self, label: Label) -> Result<(), LabelWriteError> {
        if label.annotator != self.annotator {
            return Err(LabelWriteError::BadLabel {
                path: self.path.clone(),
                what: format!(
                    "a verdict of {:?} with the writer of {:?}",
                    label.annotator, self.annotator
                ),
            });
        }
        if label.scene.trim().is_empty() {
            return Err(LabelWriteError::BadLabel {
                path: self.path.clone(),
                what: "a verdict without a scene".to_owned(),
            });
        }
        let mut line = label.to_json_line();
        line.push('\n');
        let io = |source| LabelWriteError::Io {
            path: self.path.clone(),
            source,
        };
        // One write of the whole line (O_APPEND: at the end, never interleaved), then synced.
        self.file.write_all(line.as_bytes()).map_err(io)?;
        self.file.sync_data().map_err(io)?;
        self.appended += 1;
        self.judged.insert(label.item(), label);
        Ok(())
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::panic)]
mod tests {
    use sceneeval_fidelity::FidelityMetric;

    use super::*;

    fn label(annotator: &str, index: usize, satisfied: Option<bool>) -> Label {
        Label {
            scene: "scene_3".to_owned(),
            metric: FidelityMetric::Oor,
            index,
            spec: format!("eq,1,next_to,0,bed,nightstand:{index}"),
            satisfied,
            annotator: annotator.to_owned(),
        }
    }

    #[test]
    fn appended_verdicts_read_back_and_a_later_one_replaces_an_earlier() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("labels.jsonl");
        {
            let mut w = LabelWriter::open(&path, "alice").unwrap();
            assert!(w.judged().is_empty());
            w.append(label("alice", 0, Some(true))).unwrap();
            w.append(label("alice", 1, None)).unwrap();
            w.append(label("alice", 0, Some(false))).unwrap();
            assert_eq!(w.appended(), 3);
            assert_eq!(w.judged().len(), 2);
            // Every line is on disk at once, while the writer is open.
            let read = LabelFile::read(&path).unwrap();
            assert_eq!(read.labels.len(), 2);
            assert_eq!(read.replaced, 1);
            assert_eq!(read.labels[0].label, label("alice", 0, Some(false)));
            assert_eq!(read.labels[0].line, 3);
            assert_eq!(read.labels[1].label, label("alice", 1, None));
        }
        // Bob's lines are there for the next session, Alice's are resumed.
        std::fs::write(
            &path,
            std::fs::read_to_string(&path).unwrap() + &label("bob", 2, Some(true)).to_json_line() + "\n",
        )
        .unwrap();
        let mut w = LabelWriter::open(&path, "alice").unwrap();
        let judged: Vec<(usize, Option<bool>)> =
            w.judged().values().map(|l| (l.index, l.satisfied)).collect();
        assert_eq!(judged, [(0, Some(false)), (1, None)]);
        // Another annotator's verdict is not this writer's.
        let err = w.append(label("bob", 3, Some(true))).unwrap_err().to_string();
        assert!(
            err.contains("a verdict of \"bob\" with the writer of \"alice\""),
            "{err}"
        );
        w.append(label("alice", 1, Some(true))).unwrap();
        drop(w);
        let read = LabelFile::read(&path).unwrap();
        assert_eq!(read.labels.len(), 3);
        assert_eq!(read.annotators(), ["alice", "bob"]);
        assert_eq!(read.labels[1].label.satisfied, Some(true));
    }

    #[test]
    fn a_second_writer_on_the_same_file_is_refused_until_the_first_ends() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("labels.jsonl");
        let first = LabelWriter::open(&path, "alice").unwrap();
        let err = LabelWriter::open(&path, "bob").unwrap_err();
        assert!(matches!(err, LabelWriteError::Locked { .. }), "{err}");
        let text = err.to_string();
        assert!(text.starts_with(&path.display().to_string()), "{text}");
        assert!(
            text.contains("another sceneeval judge is writing this label file"),
            "{text}"
        );
        drop(first);
        LabelWriter::open(&path, "bob").unwrap();
    }

    #[test]
    fn a_line_cut_short_is_removed_before_appending() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("labels.jsonl");
        let whole = label("alice", 0, Some(true)).to_json_line();
        let cut = label("alice", 1, Some(false)).to_json_line();
        // A crash in the middle of the second line.
        std::fs::write(&path, format!("{whole}\n{}", &cut[..cut.len() / 2])).unwrap();
        let mut w = LabelWriter::open(&path, "alice").unwrap();
        assert_eq!(w.judged().len(), 1);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), format!("{whole}\n"));
        w.append(label("alice", 1, Some(false))).unwrap();
        drop(w);
        let read = LabelFile::read(&path).unwrap();
        assert_eq!(read.labels.len(), 2);
        assert_eq!(read.torn, None);
        // A whole last line without its line end is kept and ended.
        std::fs::write(&path, &whole).unwrap();
        let mut w = LabelWriter::open(&path, "alice").unwrap();
        w.append(label("alice", 1, None)).unwrap();
        drop(w);
        assert_eq!(LabelFile::read(&path).unwrap().labels.len(), 2);
    }

    #[test]
    fn csv_files_bad_files_and_empty_names_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let err = LabelWriter::open(&dir.path().join("l.csv"), "alice").unwrap_err();
        assert!(matches!(err, LabelWriteError::Csv { .. }), "{err}");
        let err = LabelWriter::open(&dir.path().join("l.jsonl"), " ").unwrap_err();
        assert!(err.to_string().contains("without an annotator"), "{err}");
        // A folder is not a label file.
        let err = LabelWriter::open(dir.path(), "alice").unwrap_err();
        assert!(matches!(err, LabelWriteError::Io { .. }), "{err}");
        // A malformed line (not the last) is the reader's error, naming the line.
        let path = dir.path().join("bad.jsonl");
        std::fs::write(&path, "{\"scene\": 1}\n").unwrap();
        let err = LabelWriter::open(&path, "alice").unwrap_err().to_string();
        assert!(err.contains("bad.jsonl:1: not a label"), "{err}");
    }
}
