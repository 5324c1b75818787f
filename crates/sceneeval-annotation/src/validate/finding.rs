//! What validation reports: [`Finding`]s, their [`FindingCode`]s and [`Severity`], and the
//! [`Summary`] of a list of findings.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::row::Field;

/// How serious a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// The row is wrong: the reference would crash, mis-score, or the annotation contradicts
    /// itself. `sceneeval annotations check` exits non-zero.
    Error,
    /// Probably wrong or against the authors' guidelines, but evaluable as written.
    Warning,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        })
    }
}

macro_rules! finding_codes {
    ($( $(#[$doc:meta])* $variant:ident = $code:literal, $severity:ident; )*) => {
        /// What a finding is about. The text code (kebab case) is stable and is what the
        /// CLI and the JSON output show.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
        #[serde(rename_all = "kebab-case")]
        pub enum FindingCode {
            $( $(#[$doc])* $variant, )*
        }

        impl FindingCode {
            /// Every code, in documentation order.
            pub const ALL: &'static [FindingCode] = &[ $( FindingCode::$variant, )* ];

            /// The stable text code, e.g. `undefined-category`.
            pub fn as_str(self) -> &'static str {
                match self { $( FindingCode::$variant => $code, )* }
            }

            /// The severity findings of this code have.
            pub fn severity(self) -> Severity {
                match self { $( FindingCode::$variant => Severity::$severity, )* }
            }
        }
    };
}

finding_codes! {
    /// The `ID` cell is empty.
    MissingId = "missing-id", Error;
    /// Another row already has this ID (lookups return the first).
    DuplicateId = "duplicate-id", Error;
    /// The ID is not a non-negative integer (the reference and `scene_<ID>.json` expect one).
    NonIntegerId = "non-integer-id", Warning;
    /// The difficulty is not easy, medium or hard.
    UnknownDifficulty = "unknown-difficulty", Error;
    /// The description is empty (the reference crashes).
    EmptyDescription = "empty-description", Error;
    /// The description contains `;` (kept whole here; the reference truncates it, Q24).
    DescriptionSemicolon = "description-semicolon", Warning;
    /// The row has more cells than the header (usually an unquoted comma).
    RaggedRow = "ragged-row", Error;
    /// An entry's quantifier is not `eq, lt, gt, le, ge` (the reference reuses a stale
    /// result, Q18).
    UnknownQuantifier = "unknown-quantifier", Error;
    /// An entry's quantity is not a non-negative integer.
    BadQuantity = "bad-quantity", Error;
    /// An entry has the wrong number of `,`-separated fields (including several attributes in
    /// one `ObjAttr` entry, Q6, and an `OORel` entry without anchor index).
    WrongFieldCount = "wrong-field-count", Error;
    /// A category, attribute, relationship or reference is empty.
    EmptyName = "empty-name", Error;
    /// An `OORel` anchor index is not an integer ≥ -1.
    BadAnchorIndex = "bad-anchor-index", Error;
    /// An object reference `category:k` has a `k` that is not a non-negative integer.
    BadReference = "bad-reference", Error;
    /// A category used in `ObjAttr`, `OORel` or `OARel` has no `ObjCount` entry (the
    /// reference crashes on it).
    UndefinedCategory = "undefined-category", Error;
    /// An architectural element (wall, floor, ceiling, window, door, room) is used as an
    /// object: counted in `ObjCount`, given an attribute, or related in `OORel`.
    ArchAsObject = "arch-as-object", Error;
    /// An `OORel` anchor index does not index its references.
    AnchorOutOfRange = "anchor-out-of-range", Error;
    /// An attribute combines two or more known adjectives ("round wooden"); heuristic.
    NonAtomicAttribute = "non-atomic-attribute", Warning;
    /// An `ObjAttr` entry has attribute and category swapped (`eq,1,red,bed`).
    AttributeCategorySwapped = "attribute-category-swapped", Error;
    /// The same entry appears twice in a field (the reference collapses them, Q21); reported
    /// once, at the first repeat, with the number of repeats as its occurrences.
    DuplicateEntry = "duplicate-entry", Warning;
    /// `ObjCount` entries of one category allow no common count (`eq,0,x` with `ge,1,x`), or
    /// an entry can never hold (`lt,0`).
    ContradictoryCounts = "contradictory-counts", Error;
    /// An `ObjAttr` entry needs more objects of its category than `ObjCount` allows.
    AttributeExceedsCount = "attribute-exceeds-count", Error;
    /// An `OORel` or `OARel` entry needs more objects than `ObjCount` allows.
    RelationshipExceedsCount = "relationship-exceeds-count", Error;
    /// An architecture reference is not wall, floor, ceiling, window, door, room or a known
    /// room type (instance ids like `wall_1` are forbidden by the authors' guidelines).
    UnknownArchReference = "unknown-arch-reference", Error;
    /// A name contains a space or hyphen (the authors' guidelines use `_`).
    NameFormat = "name-format", Warning;
    /// The number of objects specified does not fit the difficulty level (easy ≤ 4,
    /// medium 5-8, hard ≥ 9).
    DifficultyObjectCount = "difficulty-object-count", Warning;
}

impl fmt::Display for FindingCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One problem found in an annotation file.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Finding {
    /// What kind of problem.
    pub code: FindingCode,
    /// How serious (fixed per code, see [`FindingCode::severity`]).
    pub severity: Severity,
    /// The row's ID (empty for `missing-id`), cut to [`MAX_QUOTE_CHARS`](crate::MAX_QUOTE_CHARS)
    /// characters like every quote of input text.
    pub row: String,
    /// The row's position among the data rows, 0-based (the header is not a row).
    pub row_index: usize,
    /// The column the problem is in.
    pub field: Field,
    /// The entry text, for problems in one entry, cut to
    /// [`MAX_QUOTE_CHARS`](crate::MAX_QUOTE_CHARS) characters (`entry_index` locates it).
    pub entry: Option<String>,
    /// The entry's position in its field, 0-based.
    pub entry_index: Option<usize>,
    /// What is wrong, in words. Names, cells and entries in it are cut to
    /// [`MAX_QUOTE_CHARS`](crate::MAX_QUOTE_CHARS) characters and lists to
    /// [`MAX_QUOTED_ITEMS`](crate::MAX_QUOTED_ITEMS) items.
    pub message: String,
    /// A likely fix, when one is known (quoted with the same bounds as `message`).
    pub suggestion: Option<String>,
    /// How many times the problem occurs where the finding points: 1, or for a problem
    /// repeated over the items of one entry (references, architecture references, names) or
    /// an entry repeated in one field, their number. The finding describes the first of them.
    #[serde(default = "one")]
    pub occurrences: usize,
}

fn one() -> usize {
    1
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}[{}] row {:?} (record {}) {}",
            self.severity,
            self.code,
            self.row,
            self.row_index + 1,
            self.field
        )?;
        if let Some(entry) = &self.entry {
            write!(f, " {entry:?}")?;
        }
        write!(f, ": {}", self.message)?;
        if self.occurrences > 1 {
            write!(f, " (and {} more like it)", self.occurrences - 1)?;
        }
        if let Some(s) = &self.suggestion {
            write!(f, " (suggestion: {s})")?;
        }
        Ok(())
    }
}

/// Counts of findings by severity (a finding of several occurrences counts once).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Summary {
    /// Findings with [`Severity::Error`].
    pub errors: usize,
    /// Findings with [`Severity::Warning`].
    pub warnings: usize,
}

impl Summary {
    /// Counts `findings`.
    pub fn of(findings: &[Finding]) -> Summary {
        let errors = findings.iter().filter(|f| f.severity == Severity::Error).count();
        Summary {
            errors,
            warnings: findings.len() - errors,
        }
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_has_a_distinct_text() {
        let mut texts: Vec<&str> = FindingCode::ALL.iter().map(|c| c.as_str()).collect();
        texts.sort_unstable();
        texts.dedup();
        assert_eq!(texts.len(), FindingCode::ALL.len());
        for c in FindingCode::ALL {
            let json = serde_json::to_string(c).unwrap();
            assert_eq!(json, format!("\"{}\"", c.as_str()));
        }
    }
}
