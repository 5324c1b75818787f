//! The SceneEval-500 annotation schema: types, CSV and JSON reading and writing, validation
//! and dataset statistics, and the similarity of descriptions ([`similarity`]: the filter of
//! near duplicates in annotation generation).
//!
//! Each scene description of SceneEval-500 comes with four fields of expected properties
//! (paper, Table "Annotation schema" and appendix "Annotation Schema"):
//!
//! | column | entry | example | meaning |
//! |---|---|---|---|
//! | `ObjCount` | [`ObjCount`] `q,n,category` | `ge,2,bed` | at least two beds |
//! | `ObjAttr` | [`ObjAttr`] `q,n,category,attribute` | `eq,1,bed,king_size` | exactly one king-size bed |
//! | `OORel` | [`OoRel`] `q,n,relationship,anchor_index,ref_0,ref_1,...` | `eq,1,left,0,bed,lamp` | exactly one lamp left of a bed |
//! | `OARel` | [`OaRel`] `q,n,relationship,object,arch,...` | `gt,2,against,bookshelf,wall` | more than two bookshelves against a wall |
//!
//! `q` is a [`Quantifier`] (`eq, lt, gt, le, ge`) and `n` a non-negative integer; together a
//! [`CountSpec`], whose [`CountSpec::holds`] is the test the fidelity metrics apply to an
//! observed count. Categories, attributes and relationships are open vocabulary; relationships
//! are mapped to spatial predicates only at evaluation time, so this crate has no predicate
//! vocabulary. Architecture references are a closed set ([`ArchRef`], [`vocab`]).
//!
//! A file is [`Annotations`]: rows ([`AnnotationRow`]) in file order plus the column order,
//! with extra columns kept. Rows are looked up by ID ([`Annotations::get`]), never by position
//! (the reference indexes rows by position, Q24). Reading is tolerant and never drops data: an
//! entry that does not follow its grammar is kept as [`Entry::Malformed`], and
//! [`validate`] reports everything wrong with a file as [`Finding`]s in one run: each quotes
//! at most [`MAX_QUOTE_CHARS`] characters of any one piece of input, and a problem repeated
//! over many items of an entry is one finding with its [`Finding::occurrences`], so the
//! findings grow linearly with the file. Only a file that cannot be read at all is an
//! [`AnnotationError`]. CSV → types → CSV is lossless in the
//! sense documented on [`Annotations`].
//!
//! # Finding codes
//!
//! | code | severity | what |
//! |---|---|---|
//! | `missing-id` | error | the `ID` cell is empty |
//! | `duplicate-id` | error | another row already has this ID |
//! | `non-integer-id` | warning | the ID is not a non-negative integer |
//! | `unknown-difficulty` | error | not easy, medium or hard |
//! | `empty-description` | error | the description is empty |
//! | `description-semicolon` | warning | `;` in the description (the reference truncates it) |
//! | `ragged-row` | error | more cells than the header (an unquoted comma) |
//! | `unknown-quantifier` | error | not `eq, lt, gt, le, ge` |
//! | `bad-quantity` | error | not a non-negative integer |
//! | `wrong-field-count` | error | wrong number of `,` fields (two attributes in one entry, no anchor index, ...) |
//! | `empty-name` | error | an empty category, attribute, relationship or reference |
//! | `bad-anchor-index` | error | the anchor index is not an integer ≥ -1 |
//! | `bad-reference` | error | `category:k` with a non-integer `k` |
//! | `undefined-category` | error | a category used in ObjAttr/OORel/OARel without ObjCount entry |
//! | `arch-as-object` | error | wall, floor, ceiling, window, door or room used as an object |
//! | `anchor-out-of-range` | error | the anchor index does not index the references |
//! | `non-atomic-attribute` | warning | two known adjectives in one attribute ("round wooden"), heuristic |
//! | `attribute-category-swapped` | error | `eq,1,red,bed` |
//! | `duplicate-entry` | warning | the same entry twice in one field |
//! | `contradictory-counts` | error | `eq,0,x` with `ge,1,x`, or `lt,0` |
//! | `attribute-exceeds-count` | error | `eq,2,chair,red` with `eq,1,chair` |
//! | `relationship-exceeds-count` | error | `eq,2,next,0,table,chair` with `eq,1,chair` |
//! | `unknown-arch-reference` | error | not an element or room type (`wall_1`, `windw`), with a suggestion |
//! | `name-format` | warning | a space or hyphen in a name (the guidelines use `_`) |
//! | `difficulty-object-count` | warning | objects specified outside the level's range (easy ≤ 4, medium 5-8, hard ≥ 9) |
//!
//! "Needs more objects than the counts allow" uses the quantifier semantics: an entry needs
//! at least the smallest count its quantifier allows (`eq,n`/`ge,n`: n, `gt,n`: n+1,
//! `le`/`lt`: 0) and the `ObjCount` entries of a category allow at most the largest count in
//! the intersection of their ranges. For `OORel` the comparison is with the number of distinct
//! object groups (anchor times combinations of distinct other objects, see
//! `docs/formats.md`).
//!
//! # Example
//! ```
//! use sceneeval_annotation::{Annotations, FindingCode, Quantifier, Severity};
//!
//! let csv = "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel,Category\n\
//!     5,easy,\"A bedroom with a twin bed against the wall; a desk next to the window.\",\
//!     \"eq,1,bed; eq,1,desk\",\"eq,1,twin,bed\",,\"eq,1,against,bed,wall; eq,1,next_to,desk,windw\",demo\n";
//! let annotations = Annotations::from_csv_str(csv)?;
//!
//! // Lookup by ID; the `;` in the description does not truncate it.
//! let row = annotations.get("5").expect("row 5");
//! assert!(row.description.ends_with("next to the window."));
//! let bed = row.obj_counts().next().expect("an ObjCount entry");
//! assert!(bed.count.holds(1) && !bed.count.holds(2));
//! assert!(Quantifier::Ge.holds(3, 2));
//!
//! // Every problem at once.
//! let findings = annotations.validate();
//! let codes: Vec<FindingCode> = findings.iter().map(|f| f.code).collect();
//! assert_eq!(codes, [
//!     FindingCode::DescriptionSemicolon,
//!     FindingCode::AttributeCategorySwapped,
//!     FindingCode::UnknownArchReference,
//! ]);
//! assert_eq!(findings[1].suggestion.as_deref(), Some("eq,1,bed,twin"));
//! assert_eq!(findings[2].severity, Severity::Error);
//!
//! // Writing keeps the extra column and reads back unchanged.
//! let written = annotations.to_csv_string()?;
//! assert_eq!(Annotations::from_csv_str(&written)?, annotations);
//! # Ok::<(), sceneeval_annotation::AnnotationError>(())
//! ```

mod annotations;
mod entry;
mod error;
mod quantifier;
mod quote;
mod row;
pub mod similarity;
mod stats;
mod validate;
pub mod vocab;
pub mod words;

pub use annotations::{Annotations, JSON_VERSION};
pub use entry::{
    ArchElement, ArchRef, Entry, EntryKind, EntryProblem, MalformedEntry, OaRel, ObjAttr, ObjCount, ObjRef,
    OoRel,
};
pub use error::AnnotationError;
pub use quantifier::{CountRange, CountSpec, Quantifier};
pub use quote::{MAX_QUOTE_CHARS, MAX_QUOTED_ITEMS};
pub use row::{AnnotationRow, Difficulty, Field, format_cell, parse_cell, split_cell};
pub use stats::{GroupStats, Stats};
pub use validate::{
    Finding, FindingCode, Severity, Summary, binomial, validate, validate_row, validate_rows,
};
