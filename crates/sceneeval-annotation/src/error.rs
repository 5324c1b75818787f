use std::path::PathBuf;

use thiserror::Error;

use crate::Field;

/// What went wrong reading, parsing or writing annotations.
///
/// Only problems that stop a file from being read at all are errors (it cannot be opened, it
/// is not CSV or JSON, a required column is missing). Problems inside rows and entries are
/// kept with the row and reported by [`crate::validate`] as [`crate::Finding`]s, so a dataset
/// tool sees every problem of a file in one run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum AnnotationError {
    /// The file could not be opened, read or written.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// The CSV layer failed: invalid UTF-8, an unterminated quote, or an IO error while
    /// streaming.
    #[error("{}CSV{}: {source}", at(.path), at_line(.line))]
    Csv {
        /// The file, when reading from a file.
        path: Option<PathBuf>,
        /// The 1-based line where the CSV reader stopped, when known.
        line: Option<u64>,
        /// The CSV error.
        #[source]
        source: csv::Error,
    },
    /// A quoted cell is still open at the end of the file (its closing `"` is missing): the
    /// rest of the file would silently become part of that cell.
    #[error("{}CSV line {line}: the quoted cell that starts here is never closed (a `\"` is missing)", at(.path))]
    UnterminatedQuote {
        /// The file, when reading from a file.
        path: Option<PathBuf>,
        /// The 1-based line where the quoted cell starts.
        line: u64,
    },
    /// The header lacks one of `ID, Difficulty, Description, ObjCount, ObjAttr, OORel, OARel`.
    #[error("{}missing required column {column:?}; the header has {found:?}", at(.path))]
    MissingColumn {
        /// The file, when reading from a file.
        path: Option<PathBuf>,
        /// The missing column.
        column: &'static str,
        /// The header cells found.
        found: Vec<String>,
    },
    /// Two header cells have the same name.
    #[error("{}column {column:?} appears twice in the header", at(.path))]
    DuplicateColumn {
        /// The file, when reading from a file.
        path: Option<PathBuf>,
        /// The repeated name.
        column: String,
    },
    /// The JSON form could not be parsed (the message has the line and column).
    #[error("{}JSON: {source}", at(.path))]
    Json {
        /// The file, when reading from a file.
        path: Option<PathBuf>,
        /// The JSON error.
        #[source]
        source: serde_json::Error,
    },
    /// A JSON annotation file declares a format version this crate does not know.
    #[error("{}unsupported annotation JSON version {version} (this crate reads version 1)", at(.path))]
    UnsupportedVersion {
        /// The file, when reading from a file.
        path: Option<PathBuf>,
        /// The declared version.
        version: u64,
    },
    /// A quantifier string is not one of `eq, lt, gt, le, ge`.
    #[error("unknown quantifier {text:?} (expected eq, lt, gt, le or ge)")]
    UnknownQuantifier {
        /// The text given.
        text: String,
    },
    /// A single entry parsed on its own (`"eq,1,bed".parse::<ObjCount>()`) is malformed.
    #[error("{field} entry {text:?}: {reason}")]
    InvalidEntry {
        /// The field the entry was parsed as.
        field: Field,
        /// The entry text.
        text: String,
        /// What is wrong, as in the validation finding.
        reason: String,
    },
    /// A row built in code cannot be written: its text would not read back as the same row
    /// (a name containing `,` or `;`, a reference category containing `:`, ...).
    #[error("row {row:?} {field}: cannot write {text:?}: {reason}")]
    Unwritable {
        /// The row ID.
        row: String,
        /// The field.
        field: Field,
        /// The offending text.
        text: String,
        /// Why it would not survive a round trip.
        reason: String,
    },
}

fn at(path: &Option<PathBuf>) -> String {
    match path {
        Some(p) => format!("{}: ", p.display()),
        None => String::new(),
    }
}

fn at_line(line: &Option<u64>) -> String {
    match line {
        Some(l) => format!(" line {l}"),
        None => String::new(),
    }
}
