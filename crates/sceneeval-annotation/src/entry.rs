//! The four entry kinds, their text grammar, and the tolerant entry parser.
//!
//! | field | grammar | example |
//! |---|---|---|
//! | `ObjCount` | `q,n,category` | `eq,2,nightstand` |
//! | `ObjAttr` | `q,n,category,attribute` | `eq,1,bed,king_size` |
//! | `OORel` | `q,n,relationship,anchor_index,ref_0,ref_1[,ref_2...]` | `eq,1,left,0,bed,nightstand` |
//! | `OARel` | `q,n,relationship,object,arch[,arch...]` | `eq,1,against,bookshelf,wall` |
//!
//! `q` is a [`Quantifier`], `n` a non-negative integer. Fields are separated by `,` and
//! trimmed (the authors' data-generation prompt writes `, ` in places). A reference is
//! `category` or `category:k` ([`ObjRef`]); `anchor_index` indexes the references, `-1` meaning
//! unspecified. An architecture reference is an [`ArchRef`].
//!
//! [`Entry::parse`] never fails: an entry that does not follow its grammar becomes
//! [`Entry::Malformed`], keeping its text (so a file round-trips unchanged) and the
//! [`EntryProblem`]s that validation reports. `FromStr` on the entry types is the strict
//! version for code that builds entries from literals.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::quantifier::{CountSpec, Quantifier};
use crate::quote::excerpt;
use crate::vocab;
use crate::{AnnotationError, Field};

/// A reference to objects of a category inside a relationship: `category` or `category:k`.
///
/// The `:k` suffix tells apart several participants of one category in the same entry, e.g.
/// `surround,0,table,chair:0,chair:1,chair:2` needs three distinct chairs.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ObjRef {
    /// The category (must have an `ObjCount` entry).
    pub category: String,
    /// The participant number `k` of `category:k`, if given.
    pub instance: Option<u32>,
}

impl ObjRef {
    /// A plain `category` reference.
    pub fn new(category: impl Into<String>) -> Self {
        ObjRef {
            category: category.into(),
            instance: None,
        }
    }

    /// A `category:k` reference.
    pub fn instance(category: impl Into<String>, k: u32) -> Self {
        ObjRef {
            category: category.into(),
            instance: Some(k),
        }
    }

    fn parse(text: &str, problems: &mut Vec<EntryProblem>) -> Option<ObjRef> {
        let text = text.trim();
        let (category, instance) = match text.rsplit_once(':') {
            None => (text, None),
            Some((category, suffix)) => match suffix.trim().parse::<u32>() {
                Ok(k) => (category.trim(), Some(k)),
                Err(_) => {
                    problems.push(EntryProblem::BadReference {
                        text: text.to_owned(),
                    });
                    return None;
                }
            },
        };
        if category.is_empty() {
            problems.push(EntryProblem::EmptyName {
                what: "object reference",
            });
            return None;
        }
        Some(ObjRef {
            category: category.to_owned(),
            instance,
        })
    }
}

impl fmt::Display for ObjRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.instance {
            Some(k) => write!(f, "{}:{k}", self.category),
            None => f.write_str(&self.category),
        }
    }
}

/// The six architectural element types of the schema are the scene model's
/// [`ArchElement`](sceneeval_scene::ArchElement), with the same names.
pub use sceneeval_scene::ArchElement;

/// The architecture side of an object-architecture relationship.
///
/// Parsing is exact (lower case, `_` for spaces): `Wall` or `wall_1` become
/// [`ArchRef::Unknown`], which validation reports with a suggestion.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ArchRef {
    /// An architectural element type.
    Element(ArchElement),
    /// A room type from [`vocab::ROOM_TYPES`] (for scenes with several rooms).
    RoomType(String),
    /// Anything else, kept verbatim so the file round-trips; an `unknown-arch-reference`
    /// finding.
    Unknown(String),
}

impl ArchRef {
    /// Classifies an architecture reference (never fails).
    pub fn parse(text: &str) -> ArchRef {
        let text = text.trim();
        if let Some(e) = ArchElement::from_name(text) {
            ArchRef::Element(e)
        } else if vocab::is_room_type(text) {
            ArchRef::RoomType(text.to_owned())
        } else {
            ArchRef::Unknown(text.to_owned())
        }
    }

    /// The kind of element the reference names: its element, [`ArchElement::Room`] for a room
    /// type (`bedroom` is a room), `None` for an unknown reference.
    ///
    /// ```
    /// use sceneeval_annotation::{ArchElement, ArchRef};
    /// assert_eq!(ArchRef::parse("window").element(), Some(ArchElement::Window));
    /// assert_eq!(ArchRef::parse("bedroom").element(), Some(ArchElement::Room));
    /// assert_eq!(ArchRef::parse("wall_1").element(), None);
    /// ```
    pub fn element(&self) -> Option<ArchElement> {
        match self {
            ArchRef::Element(e) => Some(*e),
            ArchRef::RoomType(_) => Some(ArchElement::Room),
            ArchRef::Unknown(_) => None,
        }
    }

    /// The text form.
    pub fn as_str(&self) -> &str {
        match self {
            ArchRef::Element(e) => e.name(),
            ArchRef::RoomType(s) | ArchRef::Unknown(s) => s,
        }
    }
}

impl fmt::Display for ArchRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// `q,n,category`: how many objects of a category the scene has.
///
/// `eq,0,category` states that the object is absent.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ObjCount {
    /// How many.
    pub count: CountSpec,
    /// Open-vocabulary category without attributes (`floor_lamp`, `fridge`).
    pub category: String,
}

impl ObjCount {
    /// An entry from its parts.
    pub fn new(count: CountSpec, category: impl Into<String>) -> Self {
        ObjCount {
            count,
            category: category.into(),
        }
    }
}

/// `q,n,category,attribute`: how many objects of a category have one attribute.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ObjAttr {
    /// How many objects of the category have the attribute.
    pub count: CountSpec,
    /// The category (must have an `ObjCount` entry).
    pub category: String,
    /// One atomic attribute: colour, material, shape, size, style or a specific type.
    pub attribute: String,
}

impl ObjAttr {
    /// An entry from its parts.
    pub fn new(count: CountSpec, category: impl Into<String>, attribute: impl Into<String>) -> Self {
        ObjAttr {
            count,
            category: category.into(),
            attribute: attribute.into(),
        }
    }
}

/// `q,n,relationship,anchor_index,ref_0,ref_1[,...]`: an object-object relationship.
///
/// Pairwise relations with several instances are written once with a quantity
/// (`eq,2,next,0,table,chair`: two chairs next to the table); `surround`-like relations list
/// every participant (`eq,1,surround,0,table,chair:0,chair:1,chair:2`).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct OoRel {
    /// How many groups of objects satisfy the relationship.
    pub count: CountSpec,
    /// Open-vocabulary relationship (`left`, `face`, `at_the_foot_of`, ...).
    pub relationship: String,
    /// Index into `refs` of the anchor object; `None` is written `-1` (unspecified).
    pub anchor: Option<usize>,
    /// The objects involved, at least two.
    pub refs: Vec<ObjRef>,
}

impl OoRel {
    /// An entry from its parts.
    pub fn new(
        count: CountSpec,
        relationship: impl Into<String>,
        anchor: Option<usize>,
        refs: Vec<ObjRef>,
    ) -> Self {
        OoRel {
            count,
            relationship: relationship.into(),
            anchor,
            refs,
        }
    }

    /// The anchor reference, when the anchor index is given and in range.
    pub fn anchor_ref(&self) -> Option<&ObjRef> {
        self.anchor.and_then(|i| self.refs.get(i))
    }
}

/// `q,n,relationship,object,arch[,arch...]`: an object-architecture relationship.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct OaRel {
    /// How many objects satisfy the relationship.
    pub count: CountSpec,
    /// Open-vocabulary relationship (`against`, `corner`, `hang`, ...).
    pub relationship: String,
    /// The object.
    pub object: ObjRef,
    /// The architecture side, at least one.
    pub arch: Vec<ArchRef>,
}

impl OaRel {
    /// An entry from its parts.
    pub fn new(
        count: CountSpec,
        relationship: impl Into<String>,
        object: ObjRef,
        arch: Vec<ArchRef>,
    ) -> Self {
        OaRel {
            count,
            relationship: relationship.into(),
            object,
            arch,
        }
    }
}

/// A problem that stops an entry from following its grammar. Its text (`Display`) quotes at
/// most [`MAX_QUOTE_CHARS`](crate::MAX_QUOTE_CHARS) characters of what was found.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum EntryProblem {
    /// The first field is not `eq, lt, gt, le, ge`.
    UnknownQuantifier {
        /// The text found.
        text: String,
    },
    /// The second field is not a non-negative integer.
    BadQuantity {
        /// The text found.
        text: String,
    },
    /// The entry has the wrong number of `,`-separated fields.
    WrongFieldCount {
        /// Fields found.
        found: usize,
        /// What the grammar asks for, e.g. `"exactly 3"`.
        expected: &'static str,
        /// A likely cause, when one is recognised.
        hint: Option<&'static str>,
    },
    /// A category, attribute, relationship or reference is empty.
    EmptyName {
        /// Which part.
        what: &'static str,
    },
    /// The anchor index is not an integer ≥ -1.
    BadAnchorIndex {
        /// The text found.
        text: String,
    },
    /// An object reference `category:k` whose `k` is not a non-negative integer.
    BadReference {
        /// The reference text.
        text: String,
    },
}

impl fmt::Display for EntryProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EntryProblem::UnknownQuantifier { text } => {
                write!(
                    f,
                    "unknown quantifier {:?} (expected eq, lt, gt, le or ge)",
                    excerpt(text)
                )?;
                if let Some(q) = Quantifier::suggest(text) {
                    write!(f, "; did you mean {q:?}?", q = q.as_str())?;
                }
                Ok(())
            }
            EntryProblem::BadQuantity { text } => {
                write!(f, "quantity {:?} is not a non-negative integer", excerpt(text))
            }
            EntryProblem::WrongFieldCount {
                found,
                expected,
                hint,
            } => {
                write!(f, "{found} comma-separated fields, expected {expected}")?;
                if let Some(hint) = hint {
                    write!(f, " ({hint})")?;
                }
                Ok(())
            }
            EntryProblem::EmptyName { what } => write!(f, "empty {what}"),
            EntryProblem::BadAnchorIndex { text } => {
                write!(
                    f,
                    "anchor index {:?} is not an integer >= -1 (-1 = unspecified)",
                    excerpt(text)
                )
            }
            EntryProblem::BadReference { text } => {
                write!(
                    f,
                    "object reference {:?} is not `category` or `category:k` with an integer k",
                    excerpt(text)
                )
            }
        }
    }
}

/// An entry that does not follow its grammar: its trimmed text and what is wrong with it.
///
/// Only [`Entry::parse`] creates these, so the text never contains `;` or a line break and
/// writes back unchanged.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct MalformedEntry {
    text: String,
    problems: Vec<EntryProblem>,
}

impl MalformedEntry {
    /// The entry text as found (trimmed).
    pub fn text(&self) -> &str {
        &self.text
    }

    /// What is wrong, at least one problem.
    pub fn problems(&self) -> &[EntryProblem] {
        &self.problems
    }
}

/// The entry kinds ([`ObjCount`], [`ObjAttr`], [`OoRel`], [`OaRel`]): their field and parser.
pub trait EntryKind: Sized + Clone + PartialEq + fmt::Display + private::Sealed {
    /// The CSV column holding entries of this kind.
    const FIELD: Field;

    /// Builds the entry from its trimmed `,`-separated parts, pushing every problem found.
    #[doc(hidden)]
    fn from_parts(parts: &[&str], problems: &mut Vec<EntryProblem>) -> Option<Self>;
}

mod private {
    pub trait Sealed {}
    impl Sealed for super::ObjCount {}
    impl Sealed for super::ObjAttr {}
    impl Sealed for super::OoRel {}
    impl Sealed for super::OaRel {}
}

/// One entry of a field as read from a file: parsed, or kept verbatim with its problems.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Entry<T> {
    /// The entry follows its grammar (semantic checks are up to [`crate::validate`]).
    Parsed(T),
    /// The entry does not follow its grammar.
    Malformed(MalformedEntry),
}

impl<T: EntryKind> Entry<T> {
    /// Parses one entry (never fails; see [`Entry::Malformed`]).
    pub fn parse(text: &str) -> Self {
        let text = text.trim();
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        let mut problems = Vec::new();
        match T::from_parts(&parts, &mut problems) {
            Some(value) if problems.is_empty() => Entry::Parsed(value),
            _ => {
                if problems.is_empty() {
                    // from_parts returns None only after pushing a problem; keep the
                    // invariant "at least one problem" even if a parser forgets.
                    problems.push(EntryProblem::EmptyName { what: "entry" });
                }
                Entry::Malformed(MalformedEntry {
                    text: text.to_owned(),
                    problems,
                })
            }
        }
    }

    /// The parsed entry, if it follows its grammar.
    pub fn parsed(&self) -> Option<&T> {
        match self {
            Entry::Parsed(v) => Some(v),
            Entry::Malformed(_) => None,
        }
    }

    /// The malformed entry, if it does not follow its grammar.
    pub fn malformed(&self) -> Option<&MalformedEntry> {
        match self {
            Entry::Parsed(_) => None,
            Entry::Malformed(m) => Some(m),
        }
    }

    /// The text written to a file: the canonical form of a parsed entry (no spaces), or the
    /// malformed text verbatim.
    pub fn text(&self) -> String {
        self.to_string()
    }
}

impl<T: EntryKind> From<T> for Entry<T> {
    fn from(value: T) -> Self {
        Entry::Parsed(value)
    }
}

impl<T: fmt::Display> fmt::Display for Entry<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Entry::Parsed(v) => v.fmt(f),
            Entry::Malformed(m) => f.write_str(&m.text),
        }
    }
}

impl<T: fmt::Display> Serialize for Entry<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de, T: EntryKind> Deserialize<'de> for Entry<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        Ok(Entry::parse(&text))
    }
}

/// Parses `q,n` from the first two parts, pushing problems.
fn parse_count(parts: &[&str], problems: &mut Vec<EntryProblem>) -> Option<CountSpec> {
    let quantifier = match parts.first().map(|q| q.parse::<Quantifier>()) {
        Some(Ok(q)) => Some(q),
        Some(Err(_)) => {
            let text = parts.first().copied().unwrap_or_default();
            problems.push(EntryProblem::UnknownQuantifier {
                text: text.to_owned(),
            });
            None
        }
        None => None,
    };
    let quantity = match parts.get(1) {
        Some(text) => match text.parse::<u64>() {
            Ok(n) => Some(n),
            Err(_) => {
                problems.push(EntryProblem::BadQuantity {
                    text: (*text).to_owned(),
                });
                None
            }
        },
        None => None,
    };
    Some(CountSpec::new(quantifier?, quantity?))
}

fn name(part: Option<&&str>, what: &'static str, problems: &mut Vec<EntryProblem>) -> Option<String> {
    match part {
        Some(s) if !s.is_empty() => Some((*s).to_owned()),
        Some(_) => {
            problems.push(EntryProblem::EmptyName { what });
            None
        }
        None => None,
    }
}

fn field_count(
    parts: &[&str],
    ok: bool,
    expected: &'static str,
    hint: Option<&'static str>,
    problems: &mut Vec<EntryProblem>,
) {
    if !ok {
        problems.push(EntryProblem::WrongFieldCount {
            found: parts.len(),
            expected,
            hint,
        });
    }
}

impl EntryKind for ObjCount {
    const FIELD: Field = Field::ObjCount;

    fn from_parts(parts: &[&str], problems: &mut Vec<EntryProblem>) -> Option<Self> {
        let count = parse_count(parts, problems);
        let hint = (parts.len() == 4).then_some("an attribute belongs in ObjAttr, not in ObjCount");
        field_count(
            parts,
            parts.len() == 3,
            "exactly 3 (q,n,category)",
            hint,
            problems,
        );
        let category = name(parts.get(2), "category", problems);
        Some(ObjCount {
            count: count?,
            category: category?,
        })
    }
}

impl EntryKind for ObjAttr {
    const FIELD: Field = Field::ObjAttr;

    fn from_parts(parts: &[&str], problems: &mut Vec<EntryProblem>) -> Option<Self> {
        let count = parse_count(parts, problems);
        let hint = (parts.len() > 4).then_some("one attribute per entry: write one entry for each attribute");
        field_count(
            parts,
            parts.len() == 4,
            "exactly 4 (q,n,category,attribute)",
            hint,
            problems,
        );
        let category = name(parts.get(2), "category", problems);
        let attribute = name(parts.get(3), "attribute", problems);
        Some(ObjAttr {
            count: count?,
            category: category?,
            attribute: attribute?,
        })
    }
}

fn is_anchor_like(text: &str) -> bool {
    text.parse::<i64>().is_ok()
}

impl EntryKind for OoRel {
    const FIELD: Field = Field::OoRel;

    fn from_parts(parts: &[&str], problems: &mut Vec<EntryProblem>) -> Option<Self> {
        let count = parse_count(parts, problems);
        let missing_anchor = parts.len() >= 5 && !parts.get(3).is_some_and(|a| is_anchor_like(a));
        let hint = if missing_anchor {
            Some(
                "the anchor index is missing: write q,n,relationship,0,anchor,other (the paper's schema table omits it)",
            )
        } else if parts.len() == 5 {
            Some("a relationship needs at least two object references")
        } else {
            None
        };
        let ok = parts.len() >= 6;
        field_count(
            parts,
            ok,
            "at least 6 (q,n,relationship,anchor_index,ref_0,ref_1,...)",
            hint,
            problems,
        );
        let relationship = name(parts.get(2), "relationship", problems);
        // With the anchor missing the remaining parts are references; do not report them
        // a second time as a bad anchor.
        let anchor = match parts.get(3) {
            Some(text) if ok || !missing_anchor => {
                // -1 is "unspecified"; other negative values and non-integers are errors.
                let index = match text.parse::<i64>() {
                    Ok(-1) => Some(None),
                    Ok(i) => usize::try_from(i).ok().map(Some),
                    Err(_) => None,
                };
                if index.is_none() {
                    problems.push(EntryProblem::BadAnchorIndex {
                        text: (*text).to_owned(),
                    });
                }
                index
            }
            _ => None,
        };
        let mut refs = Vec::new();
        let mut refs_ok = true;
        if ok {
            for part in &parts[4..] {
                match ObjRef::parse(part, problems) {
                    Some(r) => refs.push(r),
                    None => refs_ok = false,
                }
            }
        }
        if !(ok && refs_ok) {
            return None;
        }
        Some(OoRel {
            count: count?,
            relationship: relationship?,
            anchor: anchor?,
            refs,
        })
    }
}

impl EntryKind for OaRel {
    const FIELD: Field = Field::OaRel;

    fn from_parts(parts: &[&str], problems: &mut Vec<EntryProblem>) -> Option<Self> {
        let count = parse_count(parts, problems);
        let ok = parts.len() >= 5;
        let hint = (parts.len() == 4).then_some("an architecture reference (wall, floor, ...) is missing");
        field_count(
            parts,
            ok,
            "at least 5 (q,n,relationship,object,arch,...)",
            hint,
            problems,
        );
        let relationship = name(parts.get(2), "relationship", problems);
        let object = match parts.get(3) {
            Some(text) => ObjRef::parse(text, problems),
            None => None,
        };
        let mut arch = Vec::new();
        if ok {
            for part in &parts[4..] {
                if part.is_empty() {
                    problems.push(EntryProblem::EmptyName {
                        what: "architecture reference",
                    });
                } else {
                    arch.push(ArchRef::parse(part));
                }
            }
        }
        if !ok || arch.len() != parts.len().saturating_sub(4) {
            return None;
        }
        Some(OaRel {
            count: count?,
            relationship: relationship?,
            object: object?,
            arch,
        })
    }
}

impl fmt::Display for ObjCount {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.count, self.category)
    }
}

impl fmt::Display for ObjAttr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.count, self.category, self.attribute)
    }
}

impl fmt::Display for OoRel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},", self.count, self.relationship)?;
        match self.anchor {
            Some(i) => write!(f, "{i}")?,
            None => f.write_str("-1")?,
        }
        for r in &self.refs {
            write!(f, ",{r}")?;
        }
        Ok(())
    }
}

impl fmt::Display for OaRel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.count, self.relationship, self.object)?;
        for a in &self.arch {
            write!(f, ",{a}")?;
        }
        Ok(())
    }
}

/// Strict parsing and string serde for the four entry kinds.
macro_rules! strict_entry {
    ($ty:ty) => {
        impl FromStr for $ty {
            type Err = AnnotationError;

            /// Parses one entry; a malformed entry is an [`AnnotationError::InvalidEntry`]
            /// naming every problem.
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                match Entry::<$ty>::parse(s) {
                    Entry::Parsed(v) => Ok(v),
                    Entry::Malformed(m) => Err(AnnotationError::InvalidEntry {
                        field: <$ty as EntryKind>::FIELD,
                        text: m.text.clone(),
                        reason: m
                            .problems
                            .iter()
                            .map(ToString::to_string)
                            .collect::<Vec<_>>()
                            .join("; "),
                    }),
                }
            }
        }

        impl Serialize for $ty {
            fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.collect_str(self)
            }
        }

        impl<'de> Deserialize<'de> for $ty {
            fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                let text = String::deserialize(deserializer)?;
                text.parse().map_err(serde::de::Error::custom)
            }
        }
    };
}

strict_entry!(ObjCount);
strict_entry!(ObjAttr);
strict_entry!(OoRel);
strict_entry!(OaRel);

#[cfg(test)]
mod tests {
    use super::*;

    fn problems<T: EntryKind + fmt::Debug>(text: &str) -> Vec<EntryProblem> {
        match Entry::<T>::parse(text) {
            Entry::Parsed(v) => panic!("{text:?} parsed as {v:?}"),
            Entry::Malformed(m) => {
                assert_eq!(m.text(), text.trim());
                m.problems().to_vec()
            }
        }
    }

    #[test]
    fn parses_the_four_kinds() {
        let c: ObjCount = "eq,2,nightstand".parse().unwrap();
        assert_eq!(c, ObjCount::new(CountSpec::exactly(2), "nightstand"));
        let a: ObjAttr = "ge, 1, bed , king_size".parse().unwrap();
        assert_eq!(a, ObjAttr::new(CountSpec::at_least(1), "bed", "king_size"));
        assert_eq!(a.to_string(), "ge,1,bed,king_size");
        let o: OoRel = "eq,1,surround,0,table,chair:0,chair:1,chair:2".parse().unwrap();
        assert_eq!(o.refs.len(), 4);
        assert_eq!(o.refs[3], ObjRef::instance("chair", 2));
        assert_eq!(o.anchor_ref(), Some(&ObjRef::new("table")));
        assert_eq!(o.to_string(), "eq,1,surround,0,table,chair:0,chair:1,chair:2");
        let u: OoRel = "gt,0,near,-1,sofa,lamp".parse().unwrap();
        assert_eq!(u.anchor, None);
        assert_eq!(u.anchor_ref(), None);
        assert_eq!(u.to_string(), "gt,0,near,-1,sofa,lamp");
        let r: OaRel = "eq,1,between,sofa,window,door".parse().unwrap();
        assert_eq!(
            r.arch,
            vec![
                ArchRef::Element(ArchElement::Window),
                ArchRef::Element(ArchElement::Door)
            ]
        );
        let r: OaRel = "eq,1,in,bed,master_bedroom".parse().unwrap();
        assert_eq!(r.arch, vec![ArchRef::RoomType("master_bedroom".into())]);
        let r: OaRel = "eq,1,on,painting,wall_1".parse().unwrap();
        assert_eq!(r.arch, vec![ArchRef::Unknown("wall_1".into())]);
    }

    #[test]
    fn out_of_range_anchor_parses() {
        // Out of range is a semantic problem (validation), not a grammar problem.
        let o: OoRel = "eq,1,left,14,bed,nightstand".parse().unwrap();
        assert_eq!(o.anchor, Some(14));
        assert_eq!(o.anchor_ref(), None);
    }

    #[test]
    fn grammar_problems() {
        assert_eq!(
            problems::<ObjCount>("EQ,1,bed"),
            vec![EntryProblem::UnknownQuantifier { text: "EQ".into() }]
        );
        assert_eq!(
            problems::<ObjCount>("eq,two,bed"),
            vec![EntryProblem::BadQuantity { text: "two".into() }]
        );
        assert_eq!(
            problems::<ObjCount>("eq,-1,bed"),
            vec![EntryProblem::BadQuantity { text: "-1".into() }]
        );
        assert_eq!(
            problems::<ObjCount>("eq,1.5,bed"),
            vec![EntryProblem::BadQuantity { text: "1.5".into() }]
        );
        assert!(matches!(
            problems::<ObjCount>("eq,1,bed,red")[..],
            [EntryProblem::WrongFieldCount {
                found: 4,
                hint: Some(_),
                ..
            }]
        ));
        assert_eq!(
            problems::<ObjCount>("eq,1,"),
            vec![EntryProblem::EmptyName { what: "category" }]
        );
        assert!(matches!(
            problems::<ObjAttr>("eq,1,table,round,wooden")[..],
            [EntryProblem::WrongFieldCount {
                found: 5,
                hint: Some(_),
                ..
            }]
        ));
        // The paper's schema-table form without the anchor index.
        let p = problems::<OoRel>("eq,1,left,bed,lamp");
        assert!(
            matches!(p[..], [EntryProblem::WrongFieldCount { found: 5, hint: Some(h), .. }] if h.contains("anchor"))
        );
        assert_eq!(
            problems::<OoRel>("eq,1,left,x,bed,lamp"),
            vec![EntryProblem::BadAnchorIndex { text: "x".into() }]
        );
        assert_eq!(
            problems::<OoRel>("eq,1,left,-2,bed,lamp"),
            vec![EntryProblem::BadAnchorIndex { text: "-2".into() }]
        );
        assert_eq!(
            problems::<OoRel>("eq,1,left,0,bed,lamp:x"),
            vec![EntryProblem::BadReference {
                text: "lamp:x".into()
            }]
        );
        assert_eq!(
            problems::<OoRel>("eq,1,left,0,bed,:1"),
            vec![EntryProblem::EmptyName {
                what: "object reference"
            }]
        );
        assert!(matches!(
            problems::<OaRel>("eq,1,against,bed")[..],
            [EntryProblem::WrongFieldCount { found: 4, .. }]
        ));
        assert_eq!(
            problems::<OaRel>("eq,1,against,bed,wall,"),
            vec![EntryProblem::EmptyName {
                what: "architecture reference"
            }]
        );
        // Several problems at once are all kept.
        let p = problems::<ObjCount>("foo,x");
        assert_eq!(p.len(), 3, "{p:?}");
    }

    #[test]
    fn strict_parse_error_names_field_and_text() {
        let err = "eq,x,bed".parse::<ObjCount>().unwrap_err().to_string();
        assert!(
            err.contains("ObjCount") && err.contains("eq,x,bed") && err.contains("quantity"),
            "{err}"
        );
    }

    #[test]
    fn entry_serde_is_the_text_form() {
        let e: Entry<ObjCount> = serde_json::from_str("\"eq,1,bed\"").unwrap();
        assert_eq!(e, Entry::Parsed(ObjCount::new(CountSpec::exactly(1), "bed")));
        let m: Entry<ObjCount> = serde_json::from_str("\"eq,x,bed\"").unwrap();
        assert!(m.malformed().is_some());
        assert_eq!(serde_json::to_string(&m).unwrap(), "\"eq,x,bed\"");
        assert!(serde_json::from_str::<ObjCount>("\"eq,x,bed\"").is_err());
        let c: ObjCount = serde_json::from_str("\"le,3,chair\"").unwrap();
        assert_eq!(serde_json::to_string(&c).unwrap(), "\"le,3,chair\"");
    }
}
