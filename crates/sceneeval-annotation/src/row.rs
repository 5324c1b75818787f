//! One annotated scene: [`AnnotationRow`], its [`Difficulty`], and the [`Field`] names.

use std::collections::BTreeMap;
use std::fmt;

use serde::de::Error as _;
use serde::ser::{Error as _, SerializeMap};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::Value;

use crate::entry::{Entry, EntryKind, OaRel, ObjAttr, ObjCount, OoRel};
use crate::quantifier::CountRange;

/// A column of the annotation CSV (and key of the JSON row object).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Field {
    /// `ID`: the scene's identifier (`scene_<ID>.json`).
    Id,
    /// `Difficulty`: easy, medium or hard.
    Difficulty,
    /// `Description`: the scene description given to a generator.
    Description,
    /// `ObjCount`: object count entries.
    ObjCount,
    /// `ObjAttr`: object attribute entries.
    ObjAttr,
    /// `OORel`: object-object relationship entries.
    OoRel,
    /// `OARel`: object-architecture relationship entries.
    OaRel,
    /// The row as a whole (cells beyond the header).
    Row,
}

impl Field {
    /// The seven columns every annotation file has, in the canonical order.
    pub const COLUMNS: [Field; 7] = [
        Field::Id,
        Field::Difficulty,
        Field::Description,
        Field::ObjCount,
        Field::ObjAttr,
        Field::OoRel,
        Field::OaRel,
    ];

    /// The column name: `ID`, `Difficulty`, `Description`, `ObjCount`, `ObjAttr`, `OORel`,
    /// `OARel` (and `row` for [`Field::Row`]).
    pub fn as_str(self) -> &'static str {
        match self {
            Field::Id => "ID",
            Field::Difficulty => "Difficulty",
            Field::Description => "Description",
            Field::ObjCount => "ObjCount",
            Field::ObjAttr => "ObjAttr",
            Field::OoRel => "OORel",
            Field::OaRel => "OARel",
            Field::Row => "row",
        }
    }

    /// The field whose column name is `name`, if it is one of [`Field::COLUMNS`].
    pub fn from_column(name: &str) -> Option<Field> {
        Field::COLUMNS.into_iter().find(|f| f.as_str() == name)
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for Field {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Field {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        if text == Field::Row.as_str() {
            return Ok(Field::Row);
        }
        Field::from_column(&text).ok_or_else(|| D::Error::custom(format!("unknown field {text:?}")))
    }
}

/// The difficulty level of a scene description (paper, section "SceneEval-500").
///
/// Easy descriptions specify at most four large furniture objects, medium ones five to eight
/// objects (up to three small), hard ones at least nine. Parsing ignores case and surrounding
/// spaces; the canonical text is lower case. Any other text is kept in [`Difficulty::Other`]
/// (empty when the cell is empty) and reported by validation.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Difficulty {
    /// `easy`
    Easy,
    /// `medium`
    Medium,
    /// `hard`
    Hard,
    /// Anything else, verbatim (trimmed).
    Other(String),
}

impl Difficulty {
    /// The three levels of the paper.
    pub const LEVELS: [Difficulty; 3] = [Difficulty::Easy, Difficulty::Medium, Difficulty::Hard];

    /// Parses a difficulty cell (never fails).
    pub fn parse(text: &str) -> Difficulty {
        let text = text.trim();
        match text.to_ascii_lowercase().as_str() {
            "easy" => Difficulty::Easy,
            "medium" => Difficulty::Medium,
            "hard" => Difficulty::Hard,
            _ => Difficulty::Other(text.to_owned()),
        }
    }

    /// The text form.
    pub fn as_str(&self) -> &str {
        match self {
            Difficulty::Easy => "easy",
            Difficulty::Medium => "medium",
            Difficulty::Hard => "hard",
            Difficulty::Other(s) => s,
        }
    }
}

impl fmt::Display for Difficulty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for Difficulty {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Difficulty {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Ok(Difficulty::parse(&String::deserialize(deserializer)?))
    }
}

/// Splits a field cell into entry texts the way real files need: entries are separated by
/// `;` (a line break also separates, since no entry can contain one), each piece is trimmed,
/// and empty pieces (`;;`, a trailing `;`, an empty cell) are dropped.
pub fn split_cell(cell: &str) -> impl Iterator<Item = &str> {
    cell.split([';', '\n', '\r'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
}

/// Parses a field cell into entries (see [`split_cell`] and [`Entry::parse`]).
pub fn parse_cell<T: EntryKind>(cell: &str) -> Vec<Entry<T>> {
    split_cell(cell).map(Entry::parse).collect()
}

/// Writes entries as one cell: texts joined with `"; "` (the published file's separator).
pub fn format_cell<T: EntryKind>(entries: &[Entry<T>]) -> String {
    entries
        .iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join("; ")
}

/// One annotated scene description.
///
/// The JSON form (serde) is one object whose keys are the CSV column names, with each entry
/// field a list of entry strings, and extra columns as further string-valued keys:
///
/// ```json
/// {"ID": "5", "Difficulty": "easy", "Description": "A bedroom with a bed.",
///  "ObjCount": ["eq,1,bed"], "ObjAttr": [], "OORel": [], "OARel": [],
///  "Category": "SceneEval-100"}
/// ```
///
/// Reading is lenient: `ID` may be a number, an entry field may be one `;`-separated string
/// like a CSV cell, missing keys are empty, and the keys of the authors' data-generation
/// prompt (`scene_description`, `obj_counts`, `obj_attributes`, `obj_obj_relationships`,
/// `obj_arch_relationships`) are accepted for the corresponding fields.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct AnnotationRow {
    /// The scene ID, trimmed (integers 0-499 in SceneEval-500). Rows are looked up by this
    /// value, never by position.
    pub id: String,
    /// The difficulty level.
    pub difficulty: Difficulty,
    /// The scene description, trimmed, complete (a `;` inside does not truncate it).
    pub description: String,
    /// `ObjCount` entries in file order.
    pub obj_count: Vec<Entry<ObjCount>>,
    /// `ObjAttr` entries in file order.
    pub obj_attr: Vec<Entry<ObjAttr>>,
    /// `OORel` entries in file order.
    pub oo_rel: Vec<Entry<OoRel>>,
    /// `OARel` entries in file order.
    pub oa_rel: Vec<Entry<OaRel>>,
    /// Values of the extra columns (e.g. `Category`, `SceneEvalID`), verbatim, keyed by column
    /// name. An empty cell is stored as no value.
    pub extra: BTreeMap<String, String>,
    /// Cells beyond the header's last column (a `ragged-row` finding), kept so that the row
    /// writes back as it was read.
    pub overflow: Vec<String>,
}

impl Default for Difficulty {
    fn default() -> Self {
        Difficulty::Other(String::new())
    }
}

impl AnnotationRow {
    /// A row with no entries.
    pub fn new(id: impl Into<String>, difficulty: Difficulty, description: impl Into<String>) -> Self {
        AnnotationRow {
            id: id.into(),
            difficulty,
            description: description.into(),
            ..AnnotationRow::default()
        }
    }

    /// The parsed `ObjCount` entries (malformed ones skipped).
    pub fn obj_counts(&self) -> impl Iterator<Item = &ObjCount> {
        self.obj_count.iter().filter_map(Entry::parsed)
    }

    /// The parsed `ObjAttr` entries (malformed ones skipped).
    pub fn obj_attrs(&self) -> impl Iterator<Item = &ObjAttr> {
        self.obj_attr.iter().filter_map(Entry::parsed)
    }

    /// The parsed `OORel` entries (malformed ones skipped).
    pub fn oo_rels(&self) -> impl Iterator<Item = &OoRel> {
        self.oo_rel.iter().filter_map(Entry::parsed)
    }

    /// The parsed `OARel` entries (malformed ones skipped).
    pub fn oa_rels(&self) -> impl Iterator<Item = &OaRel> {
        self.oa_rel.iter().filter_map(Entry::parsed)
    }

    /// The categories of the `ObjCount` entries, de-duplicated, in file order: the target
    /// categories of object matching.
    pub fn categories(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for c in self.obj_counts() {
            if seen.insert(c.category.as_str()) {
                out.push(&c.category);
            }
        }
        out
    }

    /// The counts of `category` allowed by all its `ObjCount` entries together, `None` if it
    /// has none (empty if they contradict each other).
    pub fn count_range(&self, category: &str) -> Option<CountRange> {
        self.obj_counts()
            .filter(|c| c.category == category)
            .map(|c| c.count.allowed())
            .reduce(|a, b| a.intersect(&b))
    }

    /// Words in the description (runs of non-whitespace).
    pub fn word_count(&self) -> usize {
        self.description.split_whitespace().count()
    }

    /// Objects specified by the description: the sum over parsed `ObjCount` entries of
    /// [`crate::CountSpec::nominal`] (`eq,n`, `ge,n`, `le,n` count n; `gt,n` counts n+1;
    /// `lt,n` counts n-1; so `eq,0` counts 0).
    pub fn objects_specified(&self) -> u64 {
        self.obj_counts()
            .map(|c| c.count.nominal())
            .fold(0, u64::saturating_add)
    }

    /// The entry texts of an entry field (`None` for ID, Difficulty, Description and Row).
    pub fn entry_texts(&self, field: Field) -> Option<Vec<String>> {
        fn texts<T: EntryKind>(entries: &[Entry<T>]) -> Vec<String> {
            entries.iter().map(|e| e.to_string()).collect()
        }
        match field {
            Field::ObjCount => Some(texts(&self.obj_count)),
            Field::ObjAttr => Some(texts(&self.obj_attr)),
            Field::OoRel => Some(texts(&self.oo_rel)),
            Field::OaRel => Some(texts(&self.oa_rel)),
            Field::Id | Field::Difficulty | Field::Description | Field::Row => None,
        }
    }

    /// The CSV cell text of a column (`None` for an extra column the row has no value for).
    pub fn cell(&self, column: &str) -> Option<String> {
        match Field::from_column(column) {
            Some(Field::Id) => Some(self.id.clone()),
            Some(Field::Difficulty) => Some(self.difficulty.to_string()),
            Some(Field::Description) => Some(self.description.clone()),
            Some(Field::ObjCount) => Some(format_cell(&self.obj_count)),
            Some(Field::ObjAttr) => Some(format_cell(&self.obj_attr)),
            Some(Field::OoRel) => Some(format_cell(&self.oo_rel)),
            Some(Field::OaRel) => Some(format_cell(&self.oa_rel)),
            Some(Field::Row) | None => self.extra.get(column).cloned(),
        }
    }

    /// Sets a column from its CSV cell text (parsing entry fields; an empty extra cell removes
    /// the value).
    pub fn set_cell(&mut self, column: &str, cell: &str) {
        match Field::from_column(column) {
            Some(Field::Id) => self.id = cell.trim().to_owned(),
            Some(Field::Difficulty) => self.difficulty = Difficulty::parse(cell),
            Some(Field::Description) => self.description = cell.trim().to_owned(),
            Some(Field::ObjCount) => self.obj_count = parse_cell(cell),
            Some(Field::ObjAttr) => self.obj_attr = parse_cell(cell),
            Some(Field::OoRel) => self.oo_rel = parse_cell(cell),
            Some(Field::OaRel) => self.oa_rel = parse_cell(cell),
            Some(Field::Row) | None => {
                if cell.is_empty() {
                    self.extra.remove(column);
                } else {
                    self.extra.insert(column.to_owned(), cell.to_owned());
                }
            }
        }
    }
}

/// JSON key of [`AnnotationRow::overflow`].
pub(crate) const OVERFLOW_KEY: &str = "#overflow";

/// Alternative JSON keys (the authors' data-generation response schema).
const ALIASES: [(&str, Field); 5] = [
    ("scene_description", Field::Description),
    ("obj_counts", Field::ObjCount),
    ("obj_attributes", Field::ObjAttr),
    ("obj_obj_relationships", Field::OoRel),
    ("obj_arch_relationships", Field::OaRel),
];

impl Serialize for AnnotationRow {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        fn texts<T: EntryKind>(entries: &[Entry<T>]) -> Vec<String> {
            entries.iter().map(|e| e.to_string()).collect()
        }
        let mut map = serializer.serialize_map(None)?;
        map.serialize_entry("ID", &self.id)?;
        map.serialize_entry("Difficulty", &self.difficulty)?;
        map.serialize_entry("Description", &self.description)?;
        map.serialize_entry("ObjCount", &texts(&self.obj_count))?;
        map.serialize_entry("ObjAttr", &texts(&self.obj_attr))?;
        map.serialize_entry("OORel", &texts(&self.oo_rel))?;
        map.serialize_entry("OARel", &texts(&self.oa_rel))?;
        for (k, v) in &self.extra {
            if Field::from_column(k).is_some() || k == OVERFLOW_KEY {
                return Err(S::Error::custom(format!(
                    "row {:?}: extra column {k:?} is a reserved name",
                    self.id
                )));
            }
            map.serialize_entry(k, v)?;
        }
        if !self.overflow.is_empty() {
            map.serialize_entry(OVERFLOW_KEY, &self.overflow)?;
        }
        map.end()
    }
}

fn json_text(key: &str, value: &Value) -> Result<Option<String>, String> {
    match value {
        Value::Null => Ok(None),
        Value::String(s) => Ok(Some(s.clone())),
        Value::Number(n) => Ok(Some(n.to_string())),
        Value::Bool(b) => Ok(Some(b.to_string())),
        Value::Array(_) | Value::Object(_) => Err(format!("{key:?} must be a string")),
    }
}

fn json_entries<T: EntryKind>(key: &str, value: &Value) -> Result<Vec<Entry<T>>, String> {
    match value {
        Value::Null => Ok(Vec::new()),
        Value::String(cell) => Ok(parse_cell(cell)),
        Value::Array(items) => {
            let mut out = Vec::new();
            for item in items {
                match item {
                    // An item is one entry, but tolerate "a; b" inside an item like a cell.
                    Value::String(s) => out.extend(parse_cell::<T>(s)),
                    _ => return Err(format!("{key:?} must be a list of entry strings")),
                }
            }
            Ok(out)
        }
        _ => Err(format!(
            "{key:?} must be a list of entry strings or one `;`-separated string"
        )),
    }
}

impl<'de> Deserialize<'de> for AnnotationRow {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let map = serde_json::Map::<String, Value>::deserialize(deserializer)?;
        let mut row = AnnotationRow::default();
        let mut seen: Vec<Field> = Vec::new();
        for (key, value) in &map {
            let field = Field::from_column(key)
                .or_else(|| ALIASES.iter().find(|(alias, _)| alias == key).map(|&(_, f)| f));
            if let Some(f) = field {
                if seen.contains(&f) {
                    return Err(D::Error::custom(format!(
                        "field {f} is given twice (under an alias)"
                    )));
                }
                seen.push(f);
            }
            let text = || {
                json_text(key, value)
                    .map(Option::unwrap_or_default)
                    .map_err(D::Error::custom)
            };
            match field {
                Some(Field::Id) => row.id = text()?.trim().to_owned(),
                Some(Field::Difficulty) => row.difficulty = Difficulty::parse(&text()?),
                Some(Field::Description) => row.description = text()?.trim().to_owned(),
                Some(Field::ObjCount) => {
                    row.obj_count = json_entries(key, value).map_err(D::Error::custom)?
                }
                Some(Field::ObjAttr) => row.obj_attr = json_entries(key, value).map_err(D::Error::custom)?,
                Some(Field::OoRel) => row.oo_rel = json_entries(key, value).map_err(D::Error::custom)?,
                Some(Field::OaRel) => row.oa_rel = json_entries(key, value).map_err(D::Error::custom)?,
                Some(Field::Row) => {}
                None if key == OVERFLOW_KEY => {
                    row.overflow = serde_json::from_value(value.clone()).map_err(D::Error::custom)?;
                }
                None => {
                    let value = match value {
                        Value::Array(_) | Value::Object(_) => Some(value.to_string()),
                        _ => json_text(key, value).map_err(D::Error::custom)?,
                    };
                    if let Some(v) = value.filter(|v| !v.is_empty()) {
                        row.extra.insert(key.clone(), v);
                    }
                }
            }
        }
        Ok(row)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantifier::CountSpec;

    #[test]
    fn cell_splitting_is_tolerant() {
        let cells = [
            "eq,1,bed; eq,2,nightstand",
            " eq,1,bed;eq,2,nightstand ;",
            "eq,1,bed;;\r\n eq,2,nightstand  ",
        ];
        for cell in cells {
            assert_eq!(
                split_cell(cell).collect::<Vec<_>>(),
                vec!["eq,1,bed", "eq,2,nightstand"],
                "{cell:?}"
            );
        }
        assert_eq!(split_cell("").count(), 0);
        assert_eq!(split_cell(" ; ").count(), 0);
    }

    #[test]
    fn difficulty_parsing() {
        assert_eq!(Difficulty::parse(" Easy "), Difficulty::Easy);
        assert_eq!(Difficulty::parse("HARD"), Difficulty::Hard);
        assert_eq!(Difficulty::parse("expert"), Difficulty::Other("expert".into()));
        assert_eq!(Difficulty::parse(""), Difficulty::Other(String::new()));
    }

    #[test]
    fn derived_quantities() {
        let mut row = AnnotationRow::new(
            "7",
            Difficulty::Easy,
            "A living room with a TV, sofa and bookshelf.",
        );
        row.set_cell(
            "ObjCount",
            "eq,1,TV; eq,1,sofa; gt,1,book; eq,0,coffee_table; eq,1,sofa",
        );
        // 1 + 1 + (1+1) + 0 + 1 = 5.
        assert_eq!(row.objects_specified(), 5);
        assert_eq!(row.categories(), vec!["TV", "sofa", "book", "coffee_table"]);
        assert_eq!(row.word_count(), 9);
        assert_eq!(row.count_range("book"), Some(CountSpec::at_least(2).allowed()));
        assert_eq!(row.count_range("lamp"), None);
    }

    #[test]
    fn json_row_accepts_the_generation_schema() {
        let json = r#"{"ID": 12, "Difficulty": "Easy",
            "scene_description": "a bedroom with a red bed",
            "obj_counts": ["eq,1,bed", "eq,1,nightstand"],
            "obj_attributes": "eq,1,bed,red",
            "obj_obj_relationships": ["eq,1,left,0,bed,nightstand"],
            "obj_arch_relationships": ["eq,1,corner,wardrobe,room"],
            "reason": "because", "total_num_objects": 3, "note": null}"#;
        let row: AnnotationRow = serde_json::from_str(json).unwrap();
        assert_eq!(row.id, "12");
        assert_eq!(row.difficulty, Difficulty::Easy);
        assert_eq!(row.obj_count.len(), 2);
        assert_eq!(row.obj_attr.len(), 1);
        assert_eq!(row.extra.get("total_num_objects").map(String::as_str), Some("3"));
        assert!(!row.extra.contains_key("note"));
        let back: AnnotationRow = serde_json::from_str(&serde_json::to_string(&row).unwrap()).unwrap();
        assert_eq!(back, row);
        let twice = r#"{"ObjCount": [], "obj_counts": []}"#;
        assert!(serde_json::from_str::<AnnotationRow>(twice).is_err());
        assert!(serde_json::from_str::<AnnotationRow>(r#"{"ObjCount": 3}"#).is_err());
    }
}
