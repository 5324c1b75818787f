//! A whole annotation file: [`Annotations`], read and written as CSV or JSON.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufReader, Read, Write};
use std::path::{Path, PathBuf};

use sceneeval_files::csv_cell;
use serde::de::{self, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::entry::{Entry, EntryKind};
use crate::row::{AnnotationRow, Difficulty, Field, OVERFLOW_KEY};
use crate::{AnnotationError, Finding, Stats};

/// The version written in, and accepted from, the JSON form.
pub const JSON_VERSION: u64 = 1;

/// The rows of an annotation file and its column order.
///
/// # Reading
/// CSV reading is tolerant the way published files need: a UTF-8 BOM, CRLF or LF line ends,
/// quoted cells with commas and line breaks, surrounding spaces in header cells and fields,
/// `; ` or `;` between entries, empty cells, a trailing `;`, extra columns in any order, and
/// rows shorter than the header (missing cells are empty). Only a file that cannot be read
/// at all is an error: not UTF-8 / broken quoting, a required column missing, a column named
/// twice. Everything else (malformed entries, cells beyond the header, empty IDs, ...) is kept
/// in the rows and reported by [`Annotations::validate`], so one run shows every problem.
///
/// # Writing and "without loss"
/// The writer emits the columns in [`Annotations::columns`] order, entries joined with `"; "`,
/// parsed entries in canonical form (no spaces) and malformed entries verbatim, LF line ends,
/// and quotes only where CSV needs them. Reading normalises spaces, separators, quoting, the
/// case of the difficulty and the BOM, and nothing else, so for every file `x` that reads:
/// `read(write(read(x))) == read(x)`, and `write` is a fixpoint after one round:
/// `write(read(write(read(x)))) == write(read(x))`. Cell values, descriptions (including any
/// `;`), extra columns and their order, row order and malformed entry texts are all kept.
/// An empty extra cell and a missing extra value are the same thing.
///
/// # Cells a spreadsheet would run
/// A cell a spreadsheet would run as a formula (a text starting with `=`, `+`, `-`, `@`, a tab
/// or a carriage return; numbers excepted) is written with a leading `'`, and the reader takes
/// that `'` off again, so the text reads back unchanged (the rule, which also keeps a text that
/// starts with `'=` as it is: `sceneeval_files::csv_cell`). Files written by other tools read as
/// before, except a cell that starts with `'` followed by such a character, which loses its
/// first `'`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Annotations {
    /// Column names in file order: the seven of [`Field::COLUMNS`] and any extra columns.
    pub columns: Vec<String>,
    /// The rows in file order.
    pub rows: Vec<AnnotationRow>,
}

impl Default for Annotations {
    fn default() -> Self {
        Annotations::new()
    }
}

impl Annotations {
    /// No rows, the canonical columns `ID, Difficulty, Description, ObjCount, ObjAttr, OORel,
    /// OARel`.
    pub fn new() -> Self {
        Annotations {
            columns: Field::COLUMNS.iter().map(|f| f.as_str().to_owned()).collect(),
            rows: Vec::new(),
        }
    }

    /// The canonical columns plus the extra columns the rows use (in order of first use).
    pub fn from_rows(rows: Vec<AnnotationRow>) -> Self {
        let mut a = Annotations {
            rows,
            ..Annotations::new()
        };
        a.columns = a.effective_columns();
        a
    }

    /// The first row whose ID is `id` (compared after trimming `id`). Lookup is by value,
    /// never by position; validation reports repeated IDs.
    pub fn get(&self, id: &str) -> Option<&AnnotationRow> {
        let id = id.trim();
        self.rows.iter().find(|r| r.id == id)
    }

    /// Mutable [`Annotations::get`].
    pub fn get_mut(&mut self, id: &str) -> Option<&mut AnnotationRow> {
        let id = id.trim();
        self.rows.iter_mut().find(|r| r.id == id)
    }

    /// An index from ID to row for many lookups (the first row of a repeated ID wins).
    pub fn index(&self) -> HashMap<&str, &AnnotationRow> {
        let mut map = HashMap::with_capacity(self.rows.len());
        for row in &self.rows {
            map.entry(row.id.as_str()).or_insert(row);
        }
        map
    }

    /// The row IDs in file order.
    pub fn ids(&self) -> impl Iterator<Item = &str> {
        self.rows.iter().map(|r| r.id.as_str())
    }

    /// Every validation finding (see [`crate::validate`]).
    pub fn validate(&self) -> Vec<Finding> {
        crate::validate(self)
    }

    /// The validation findings that concern the rows at `indices` (see
    /// [`crate::validate_rows`]).
    pub fn validate_rows(&self, indices: &std::collections::BTreeSet<usize>) -> Vec<Finding> {
        crate::validate_rows(self, indices)
    }

    /// The paper's Table 1 statistics (see [`Stats`]).
    pub fn stats(&self) -> Stats {
        Stats::of(self)
    }

    /// The columns the writer emits: [`Annotations::columns`] without repeats, then any of the
    /// seven required columns it lacks, then extra columns used by rows but not listed.
    pub fn effective_columns(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        let push = |name: &str, out: &mut Vec<String>| {
            if !out.iter().any(|c| c == name) {
                out.push(name.to_owned());
            }
        };
        for c in &self.columns {
            push(c, &mut out);
        }
        for f in Field::COLUMNS {
            push(f.as_str(), &mut out);
        }
        for row in &self.rows {
            for k in row.extra.keys() {
                push(k, &mut out);
            }
        }
        out
    }

    // ----------------------------------------------------------------------------- CSV

    /// Reads CSV from a reader (see the type docs for what is tolerated).
    pub fn from_csv_reader<R: Read>(reader: R) -> Result<Self, AnnotationError> {
        read_csv(reader, None)
    }

    /// Reads CSV from a string.
    pub fn from_csv_str(text: &str) -> Result<Self, AnnotationError> {
        read_csv(text.as_bytes(), None)
    }

    /// Reads a CSV file.
    pub fn read_csv(path: impl AsRef<Path>) -> Result<Self, AnnotationError> {
        let path = path.as_ref();
        let file = File::open(path).map_err(|source| AnnotationError::Io {
            path: path.to_owned(),
            source,
        })?;
        read_csv(BufReader::new(file), Some(path))
    }

    /// Writes CSV to a writer. Fails with [`AnnotationError::Unwritable`] before writing
    /// anything if a row would not read back unchanged (see [`Annotations::check_writable`]).
    pub fn write_csv_to<W: Write>(&self, writer: W) -> Result<(), AnnotationError> {
        self.check_writable()?;
        write_csv(self, writer).map_err(|source| AnnotationError::Csv {
            path: None,
            line: None,
            source,
        })
    }

    /// The CSV text.
    pub fn to_csv_string(&self) -> Result<String, AnnotationError> {
        let mut buf = Vec::new();
        self.write_csv_to(&mut buf)?;
        // The writer only copies `String`s and ASCII punctuation, so this is UTF-8.
        Ok(String::from_utf8_lossy(&buf).into_owned())
    }

    /// Writes a CSV file, atomically (`sceneeval_files::write_atomic`: a temporary file renamed
    /// over `path`; a replaced file keeps its permissions).
    pub fn write_csv(&self, path: impl AsRef<Path>) -> Result<(), AnnotationError> {
        let path = path.as_ref();
        let text = self.to_csv_string().map_err(|e| match e {
            AnnotationError::Csv { line, source, .. } => AnnotationError::Csv {
                path: Some(path.to_owned()),
                line,
                source,
            },
            other => other,
        })?;
        write_file(path, text.as_bytes())
    }

    // ---------------------------------------------------------------------------- JSON

    /// Reads the JSON form: `{"version": 1, "columns": [...], "rows": [...]}` or a bare array
    /// of row objects (see [`AnnotationRow`] for the row object).
    pub fn from_json_str(text: &str) -> Result<Self, AnnotationError> {
        parse_json(serde_json::from_str(text), None)
    }

    /// Reads the JSON form from a reader.
    pub fn from_json_reader<R: Read>(reader: R) -> Result<Self, AnnotationError> {
        parse_json(serde_json::from_reader(reader), None)
    }

    /// Reads a JSON file.
    pub fn read_json(path: impl AsRef<Path>) -> Result<Self, AnnotationError> {
        let path = path.as_ref();
        let file = File::open(path).map_err(|source| AnnotationError::Io {
            path: path.to_owned(),
            source,
        })?;
        parse_json(serde_json::from_reader(BufReader::new(file)), Some(path))
    }

    /// The JSON form, pretty-printed, with the same writability check as CSV.
    pub fn to_json_string(&self) -> Result<String, AnnotationError> {
        self.check_writable()?;
        serde_json::to_string_pretty(self).map_err(|source| AnnotationError::Json { path: None, source })
    }

    /// Writes a JSON file.
    pub fn write_json(&self, path: impl AsRef<Path>) -> Result<(), AnnotationError> {
        let path = path.as_ref();
        let mut text = self.to_json_string()?;
        text.push('\n');
        write_file(path, text.as_bytes())
    }

    /// Reads a file as JSON if its extension is `.json` (any case), as CSV otherwise.
    pub fn read(path: impl AsRef<Path>) -> Result<Self, AnnotationError> {
        let path = path.as_ref();
        if is_json_path(path) {
            Annotations::read_json(path)
        } else {
            Annotations::read_csv(path)
        }
    }

    /// Writes a file as JSON if its extension is `.json` (any case), as CSV otherwise.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), AnnotationError> {
        let path = path.as_ref();
        if is_json_path(path) {
            self.write_json(path)
        } else {
            self.write_csv(path)
        }
    }

    /// Checks that every row reads back unchanged after writing: IDs and descriptions without
    /// surrounding spaces, a difficulty that parses to itself, every entry's text re-parsing to
    /// the same entry and containing no `;` or line break (so names contain no `,` or `;`,
    /// reference categories no `:`, an `OORel` has at least two references ...), extra
    /// columns not named like a required column and not empty.
    pub fn check_writable(&self) -> Result<(), AnnotationError> {
        for row in &self.rows {
            check_row(row)?;
        }
        Ok(())
    }
}

/// Writes `bytes` to `path` atomically, the error naming the file.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), AnnotationError> {
    sceneeval_files::write_atomic(path, bytes).map_err(|source| AnnotationError::Io {
        path: path.to_owned(),
        source,
    })
}

fn is_json_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

fn unwritable(row: &AnnotationRow, field: Field, text: &str, reason: &str) -> AnnotationError {
    AnnotationError::Unwritable {
        row: row.id.clone(),
        field,
        text: text.to_owned(),
        reason: reason.to_owned(),
    }
}

fn check_entries<T: EntryKind + std::fmt::Debug>(
    row: &AnnotationRow,
    entries: &[Entry<T>],
) -> Result<(), AnnotationError> {
    for entry in entries {
        let text = entry.to_string();
        if text.contains([';', '\n', '\r']) {
            return Err(unwritable(
                row,
                T::FIELD,
                &text,
                "an entry cannot contain `;` or a line break",
            ));
        }
        if Entry::<T>::parse(&text) != *entry {
            let reason = match entry {
                Entry::Parsed(_) => {
                    "the entry text does not parse back to the same entry (a name with `,`, spaces \
                     around it, an empty name, a reference category with `:`, too few references \
                     or architecture references, or an ArchRef variant that does not match its text)"
                }
                Entry::Malformed(_) => "the malformed entry text was changed",
            };
            return Err(unwritable(row, T::FIELD, &text, reason));
        }
    }
    Ok(())
}

fn check_row(row: &AnnotationRow) -> Result<(), AnnotationError> {
    if row.id.trim() != row.id {
        return Err(unwritable(
            row,
            Field::Id,
            &row.id,
            "the ID has surrounding spaces",
        ));
    }
    if Difficulty::parse(row.difficulty.as_str()) != row.difficulty {
        return Err(unwritable(
            row,
            Field::Difficulty,
            row.difficulty.as_str(),
            "Difficulty::Other holds a text that reads as another difficulty or has surrounding spaces",
        ));
    }
    if row.description.trim() != row.description {
        return Err(unwritable(
            row,
            Field::Description,
            &row.description,
            "the description has surrounding spaces",
        ));
    }
    check_entries(row, &row.obj_count)?;
    check_entries(row, &row.obj_attr)?;
    check_entries(row, &row.oo_rel)?;
    check_entries(row, &row.oa_rel)?;
    for (k, v) in &row.extra {
        if Field::from_column(k).is_some() || k == OVERFLOW_KEY {
            return Err(unwritable(
                row,
                Field::Row,
                k,
                "an extra column cannot be named like a required column",
            ));
        }
        if v.is_empty() {
            return Err(unwritable(
                row,
                Field::Row,
                k,
                "an empty extra value reads back as no value; remove it",
            ));
        }
    }
    Ok(())
}

fn csv_error(source: csv::Error, path: Option<&Path>) -> AnnotationError {
    let line = source.position().map(|p| p.line());
    AnnotationError::Csv {
        path: path.map(Path::to_path_buf),
        line,
        source,
    }
}

/// The 1-based line where a quoted cell opens that is still open at the end of the input, as
/// the `csv` reader splits cells (a `"` opens a quoted cell only at the start of a cell; `""`
/// inside is an escaped quote; after the closing quote the cell goes on unquoted). The `csv`
/// crate silently ends such a cell at the end of the file, swallowing every later row.
fn unterminated_quote(bytes: &[u8]) -> Option<u64> {
    #[derive(Clone, Copy, PartialEq)]
    enum State {
        CellStart,
        Unquoted,
        Quoted,
        QuoteInQuoted,
    }
    let mut state = State::CellStart;
    let mut line = 1u64;
    let mut opened_at = 0u64;
    for &b in bytes {
        state = match (state, b) {
            (State::CellStart, b'"') => {
                opened_at = line;
                State::Quoted
            }
            (State::CellStart | State::Unquoted | State::QuoteInQuoted, b',' | b'\n' | b'\r') => {
                State::CellStart
            }
            (State::CellStart | State::Unquoted, _) => State::Unquoted,
            (State::Quoted, b'"') => State::QuoteInQuoted,
            (State::Quoted, _) => State::Quoted,
            (State::QuoteInQuoted, b'"') => State::Quoted,
            (State::QuoteInQuoted, _) => State::Unquoted,
        };
        if b == b'\n' {
            line += 1;
        }
    }
    (state == State::Quoted).then_some(opened_at)
}

fn read_csv<R: Read>(mut reader: R, path: Option<&Path>) -> Result<Annotations, AnnotationError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| csv_error(csv::Error::from(e), path))?;
    if let Some(line) = unterminated_quote(&bytes) {
        return Err(AnnotationError::UnterminatedQuote {
            path: path.map(Path::to_path_buf),
            line,
        });
    }
    let mut rdr = csv::ReaderBuilder::new()
        .flexible(true)
        .has_headers(true)
        .from_reader(bytes.as_slice());
    let header: Vec<String> = rdr
        .headers()
        .map_err(|e| csv_error(e, path))?
        .iter()
        .map(|h| csv_cell::unescape(h.trim_start_matches('\u{feff}').trim()).to_owned())
        .collect();
    for (i, h) in header.iter().enumerate() {
        if header[..i].contains(h) {
            return Err(AnnotationError::DuplicateColumn {
                path: path.map(PathBuf::from),
                column: h.clone(),
            });
        }
    }
    for f in Field::COLUMNS {
        if !header.iter().any(|h| h == f.as_str()) {
            return Err(AnnotationError::MissingColumn {
                path: path.map(PathBuf::from),
                column: f.as_str(),
                found: header.clone(),
            });
        }
    }
    let mut rows = Vec::new();
    let mut record = csv::StringRecord::new();
    while rdr.read_record(&mut record).map_err(|e| csv_error(e, path))? {
        let mut row = AnnotationRow::default();
        for (i, cell) in record.iter().enumerate() {
            // Cells a spreadsheet would run were written with a leading `'`.
            let cell = csv_cell::unescape(cell);
            match header.get(i) {
                Some(column) => row.set_cell(column, cell),
                None => row.overflow.push(cell.to_owned()),
            }
        }
        rows.push(row);
    }
    tracing::debug!(rows = rows.len(), columns = header.len(), "read annotation CSV");
    Ok(Annotations {
        columns: header,
        rows,
    })
}

fn write_csv<W: Write>(a: &Annotations, writer: W) -> Result<(), csv::Error> {
    let columns = a.effective_columns();
    let mut w = csv::WriterBuilder::new().flexible(true).from_writer(writer);
    // Every cell through `csv_cell::escape`: a description or entry a spreadsheet would run
    // as a formula gets a leading `'`, which `read_csv` takes off again.
    w.write_record(columns.iter().map(|c| csv_cell::escape(c).into_owned()))?;
    for row in &a.rows {
        let cells = columns.iter().map(|c| row.cell(c).unwrap_or_default());
        let record: Vec<String> = cells
            .chain(row.overflow.iter().cloned())
            .map(|c| csv_cell::escape(&c).into_owned())
            .collect();
        w.write_record(&record)?;
    }
    w.flush().map_err(csv::Error::from)
}

impl Serialize for Annotations {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(3))?;
        map.serialize_entry("version", &JSON_VERSION)?;
        map.serialize_entry("columns", &self.effective_columns())?;
        map.serialize_entry("rows", &self.rows)?;
        map.end()
    }
}

/// What the JSON top level holds before normalisation.
struct JsonFile {
    version: Option<u64>,
    columns: Option<Vec<String>>,
    rows: Vec<AnnotationRow>,
}

impl<'de> Deserialize<'de> for JsonFile {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct FileVisitor;
        impl<'de> Visitor<'de> for FileVisitor {
            type Value = JsonFile;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an object with \"rows\" or an array of row objects")
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<JsonFile, A::Error> {
                let mut rows = Vec::new();
                while let Some(row) = seq.next_element::<AnnotationRow>()? {
                    rows.push(row);
                }
                Ok(JsonFile {
                    version: None,
                    columns: None,
                    rows,
                })
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<JsonFile, A::Error> {
                let mut file = JsonFile {
                    version: None,
                    columns: None,
                    rows: Vec::new(),
                };
                let mut saw_rows = false;
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "version" => file.version = Some(map.next_value()?),
                        "columns" => file.columns = Some(map.next_value()?),
                        "rows" => {
                            file.rows = map.next_value()?;
                            saw_rows = true;
                        }
                        other => {
                            tracing::debug!(key = other, "ignoring unknown top-level key in annotation JSON");
                            map.next_value::<IgnoredAny>()?;
                        }
                    }
                }
                if !saw_rows {
                    return Err(de::Error::missing_field("rows"));
                }
                Ok(file)
            }
        }
        deserializer.deserialize_any(FileVisitor)
    }
}

impl<'de> Deserialize<'de> for Annotations {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let file = JsonFile::deserialize(deserializer)?;
        if let Some(v) = file.version.filter(|&v| v != JSON_VERSION) {
            return Err(de::Error::custom(format!(
                "unsupported annotation JSON version {v}"
            )));
        }
        Ok(from_json_file(file))
    }
}

fn from_json_file(file: JsonFile) -> Annotations {
    let mut a = Annotations {
        columns: file.columns.unwrap_or_default(),
        rows: file.rows,
    };
    if a.columns.is_empty() {
        a.columns = Annotations::new().columns;
    }
    a.columns = a.effective_columns();
    a
}

fn parse_json(
    parsed: Result<JsonFile, serde_json::Error>,
    path: Option<&Path>,
) -> Result<Annotations, AnnotationError> {
    let file = parsed.map_err(|source| AnnotationError::Json {
        path: path.map(PathBuf::from),
        source,
    })?;
    if let Some(version) = file.version.filter(|&v| v != JSON_VERSION) {
        return Err(AnnotationError::UnsupportedVersion {
            path: path.map(PathBuf::from),
            version,
        });
    }
    let a = from_json_file(file);
    tracing::debug!(rows = a.rows.len(), "read annotation JSON");
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::entry::{ObjCount, OoRel};
    use crate::quantifier::CountSpec;

    const MESSY: &str = "\u{feff} ID ,Description,ObjCount,ObjAttr,OORel,OARel,Difficulty,Category\r\n\
        3,\"A bed, a desk; and a lamp.\",\"eq,1,bed; eq,1,desk ;eq,1,lamp;\",,\"eq,1,near,0,bed,lamp \",\"eq,1,against,bed,wall\",Easy,SceneEval-100\r\n\
        1,\"Two lines\r\nof text.\",\"eq,2,chair\",\"eq,1,chair , red\",,,medium,\r\n";

    #[test]
    fn reads_a_messy_file() {
        let a = Annotations::from_csv_str(MESSY).unwrap();
        assert_eq!(
            a.columns,
            vec![
                "ID",
                "Description",
                "ObjCount",
                "ObjAttr",
                "OORel",
                "OARel",
                "Difficulty",
                "Category"
            ]
        );
        assert_eq!(a.rows.len(), 2);
        let r = a.get("3").unwrap();
        assert_eq!(r.description, "A bed, a desk; and a lamp.");
        assert_eq!(r.difficulty, Difficulty::Easy);
        assert_eq!(r.obj_count.len(), 3);
        assert_eq!(
            r.obj_count[1],
            Entry::Parsed(ObjCount::new(CountSpec::exactly(1), "desk"))
        );
        assert_eq!(r.oo_rel[0].parsed().map(|o: &OoRel| o.refs.len()), Some(2));
        assert_eq!(r.extra.get("Category").map(String::as_str), Some("SceneEval-100"));
        // Lookup by value, not position: ID 1 is the second row.
        let r1 = a.get(" 1").unwrap();
        assert_eq!(r1.description, "Two lines\r\nof text.");
        assert_eq!(r1.obj_attr[0].to_string(), "eq,1,chair,red");
        assert!(r1.extra.is_empty());
        assert!(a.get("0").is_none());
    }

    #[test]
    fn round_trip_is_a_fixpoint_after_one_write() {
        let a = Annotations::from_csv_str(MESSY).unwrap();
        let w1 = a.to_csv_string().unwrap();
        let b = Annotations::from_csv_str(&w1).unwrap();
        assert_eq!(a, b);
        assert_eq!(b.to_csv_string().unwrap(), w1);
        assert!(w1.starts_with("ID,Description,ObjCount,ObjAttr,OORel,OARel,Difficulty,Category\n"));
        assert!(w1.contains("\"eq,1,bed; eq,1,desk; eq,1,lamp\""), "{w1}");
        // JSON carries the same information.
        let j = a.to_json_string().unwrap();
        assert_eq!(Annotations::from_json_str(&j).unwrap(), a);
    }

    #[test]
    fn ragged_rows_keep_their_cells() {
        let text = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
                    0,easy,A bed, with a comma,eq,1,bed,,,\n1,easy\n";
        let a = Annotations::from_csv_str(text).unwrap();
        assert_eq!(a.rows[0].description, "A bed");
        assert_eq!(a.rows[0].overflow, vec!["", "", ""]);
        assert_eq!(a.rows[1].id, "1");
        assert!(a.rows[1].obj_count.is_empty());
        let b = Annotations::from_csv_str(&a.to_csv_string().unwrap()).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn file_level_errors() {
        let e = Annotations::from_csv_str("ID,Description\n0,x\n").unwrap_err();
        assert!(
            matches!(
                e,
                AnnotationError::MissingColumn {
                    column: "Difficulty",
                    ..
                }
            ),
            "{e}"
        );
        let e = Annotations::from_csv_str("ID,ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n")
            .unwrap_err();
        assert!(matches!(e, AnnotationError::DuplicateColumn { .. }), "{e}");
        let bad_utf8 = b"ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n0,easy,\xff\xfe,,,,\n";
        let e = Annotations::from_csv_reader(&bad_utf8[..]).unwrap_err();
        assert!(matches!(e, AnnotationError::Csv { line: Some(2), .. }), "{e}");
        let e = Annotations::from_json_str("{\"version\": 2, \"rows\": []}").unwrap_err();
        assert!(
            matches!(e, AnnotationError::UnsupportedVersion { version: 2, .. }),
            "{e}"
        );
        let e = Annotations::from_json_str("{\"rows\": [{\"ObjCount\": 1}]}").unwrap_err();
        assert!(e.to_string().contains("line 1"), "{e}");
        let e = Annotations::read_csv("/nonexistent/annotations.csv").unwrap_err();
        assert!(e.to_string().contains("/nonexistent/annotations.csv"), "{e}");
    }

    #[test]
    fn a_quote_that_is_never_closed_is_an_error() {
        let header = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n";
        // Row 2's description opens a quote on line 3 that the file never closes: without the
        // check, row 3 would vanish into that cell.
        let text = format!("{header}0,easy,fine,,,,\n1,easy,\"A room, with a bed,,,,\n2,hard,x,,,,\n");
        let e = Annotations::from_csv_str(&text).unwrap_err();
        assert!(
            matches!(e, AnnotationError::UnterminatedQuote { line: 3, .. }),
            "{e}"
        );
        assert!(
            e.to_string().contains("line 3") && e.to_string().contains("never closed"),
            "{e}"
        );
        // Closed quotes, escaped quotes, quotes inside unquoted cells and line breaks inside
        // quoted cells are fine.
        let ok = format!(
            "{header}0,easy,\"A \"\"quoted\"\" word\",,,,\n1,easy,6\" tall,,,,\n2,hard,\"two\nlines\",,,,\n"
        );
        let a = Annotations::from_csv_str(&ok).unwrap();
        assert_eq!(a.rows.len(), 3);
        assert_eq!(a.rows[0].description, "A \"quoted\" word");
        assert_eq!(a.rows[1].description, "6\" tall");
        assert_eq!(
            unterminated_quote(b"\"a\"b\"c"),
            None,
            "after the closing quote the cell is unquoted"
        );
        assert_eq!(unterminated_quote(b"x\n\r\n\"open"), Some(3));
    }

    #[test]
    fn writer_refuses_rows_that_would_not_read_back() {
        let mut a = Annotations::new();
        let mut row = AnnotationRow::new("0", Difficulty::Easy, "A bed.");
        row.obj_count
            .push(Entry::Parsed(ObjCount::new(CountSpec::exactly(1), "bed, king")));
        a.rows.push(row);
        let e = a.to_csv_string().unwrap_err();
        assert!(
            matches!(
                e,
                AnnotationError::Unwritable {
                    field: Field::ObjCount,
                    ..
                }
            ),
            "{e}"
        );
        a.rows[0].obj_count.clear();
        a.rows[0].extra.insert("ID".into(), "x".into());
        assert!(a.to_csv_string().is_err());
        a.rows[0].extra.clear();
        a.rows[0].description = " padded".into();
        assert!(a.to_json_string().is_err());
    }

    #[test]
    fn json_forms() {
        let a = Annotations::from_json_str(
            r#"[{"ID": 4, "Difficulty": "hard", "Description": "x", "Room": "den"}]"#,
        )
        .unwrap();
        assert_eq!(a.columns.last().map(String::as_str), Some("Room"));
        assert_eq!(a.get("4").unwrap().difficulty, Difficulty::Hard);
        let a = Annotations::from_json_str(r#"{"columns": ["Description", "ID"], "rows": [], "note": 1}"#)
            .unwrap();
        assert_eq!(a.columns[..3], ["Description", "ID", "Difficulty"]);
        assert!(Annotations::from_json_str("{\"columns\": []}").is_err());
        assert!(Annotations::from_json_str("3").is_err());
    }

    #[test]
    fn files_by_extension() {
        let dir = tempfile::tempdir().unwrap();
        let a = Annotations::from_csv_str(MESSY).unwrap();
        for name in ["a.csv", "a.JSON"] {
            let p = dir.path().join(name);
            a.write(&p).unwrap();
            assert_eq!(Annotations::read(&p).unwrap(), a, "{name}");
        }
        let json = std::fs::read_to_string(dir.path().join("a.JSON")).unwrap();
        assert!(json.starts_with("{\n  \"version\": 1,"), "{json}");
    }
}
