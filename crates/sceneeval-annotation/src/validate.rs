//! Validation: every problem of an annotation file as a [`Finding`].
//!
//! The checks are the failure modes the paper's authors fixed by hand in LLM-written
//! annotations (appendix "Semi-Automatic Data Generation Limitations") and the inputs that
//! make the reference implementation crash or silently mis-score (`reference-notes.md` §3, Q5,
//! Q6, Q18, Q21, Q24). See [`FindingCode`] for the list, with severities.

use std::collections::{HashMap, HashSet};
use std::fmt;

use serde::{Deserialize, Serialize};

use crate::Annotations;
use crate::entry::{ArchRef, Entry, EntryKind, EntryProblem, OaRel, ObjAttr, ObjCount, OoRel};
use crate::quantifier::{CountRange, CountSpec};
use crate::row::{AnnotationRow, Difficulty, Field};
use crate::vocab::{self, ArchSuggestion};

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
    /// The same entry appears twice in a field (the reference collapses them, Q21).
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
    /// The row's ID (empty for `missing-id`).
    pub row: String,
    /// The row's position among the data rows, 0-based (the header is not a row).
    pub row_index: usize,
    /// The column the problem is in.
    pub field: Field,
    /// The entry text, for problems in one entry.
    pub entry: Option<String>,
    /// The entry's position in its field, 0-based.
    pub entry_index: Option<usize>,
    /// What is wrong, in words.
    pub message: String,
    /// A likely fix, when one is known.
    pub suggestion: Option<String>,
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
        if let Some(s) = &self.suggestion {
            write!(f, " (suggestion: {s})")?;
        }
        Ok(())
    }
}

/// Counts of findings by severity.
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

/// Every finding of every row, in row order, then column order, then entry order.
///
/// Malformed entries are reported by their grammar problems only; the semantic checks run on
/// the parsed entries. A category counted by a malformed `ObjCount` entry whose last field is
/// readable still counts as defined, so one typo gives one finding, not a cascade.
///
/// The work is linear in the number of entries and references (hash lookups; a cell of
/// 100,000 entries validates in well under a second), apart from the findings' own text.
pub fn validate(annotations: &Annotations) -> Vec<Finding> {
    let mut out = Vec::new();
    let mut first_row_of: HashMap<&str, usize> = HashMap::new();
    for (index, row) in annotations.rows.iter().enumerate() {
        let mut ctx = RowCtx {
            row,
            index,
            out: &mut out,
        };
        if !row.id.is_empty() {
            match first_row_of.get(row.id.as_str()) {
                Some(&first) => ctx.push(
                    FindingCode::DuplicateId,
                    Field::Id,
                    None,
                    format!(
                        "ID {:?} is also used by record {}; lookups return that row",
                        row.id,
                        first + 1
                    ),
                    None,
                ),
                None => {
                    first_row_of.insert(&row.id, index);
                }
            }
        }
        check_row(&mut ctx);
    }
    out
}

/// The findings of one row alone (no `duplicate-id`, which needs the whole file);
/// `row_index` is set to `index`.
pub fn validate_row(row: &AnnotationRow, index: usize) -> Vec<Finding> {
    let mut out = Vec::new();
    check_row(&mut RowCtx {
        row,
        index,
        out: &mut out,
    });
    out
}

struct RowCtx<'a> {
    row: &'a AnnotationRow,
    index: usize,
    out: &'a mut Vec<Finding>,
}

impl RowCtx<'_> {
    fn push(
        &mut self,
        code: FindingCode,
        field: Field,
        entry: Option<(usize, String)>,
        message: String,
        suggestion: Option<String>,
    ) {
        let (entry_index, entry) = match entry {
            Some((i, text)) => (Some(i), Some(text)),
            None => (None, None),
        };
        self.out.push(Finding {
            code,
            severity: code.severity(),
            row: self.row.id.clone(),
            row_index: self.index,
            field,
            entry,
            entry_index,
            message,
            suggestion,
        });
    }
}

/// The per-entry context of the semantic checks.
struct EntryCtx<'c, 'a> {
    ctx: &'c mut RowCtx<'a>,
    field: Field,
    index: usize,
    text: String,
}

impl EntryCtx<'_, '_> {
    fn push(&mut self, code: FindingCode, message: String, suggestion: Option<String>) {
        let entry = Some((self.index, self.text.clone()));
        self.ctx.push(code, self.field, entry, message, suggestion);
    }
}

/// Counts the steps of the validator's loops in tests, so that a test can check that the
/// work grows linearly with the number of entries.
#[cfg(test)]
pub(crate) mod work {
    use std::cell::Cell;

    thread_local! {
        static STEPS: Cell<u64> = const { Cell::new(0) };
    }

    /// One step of a loop.
    pub(crate) fn tick() {
        STEPS.with(|s| s.set(s.get() + 1));
    }

    /// Steps so far on this thread.
    pub(crate) fn steps() -> u64 {
        STEPS.with(Cell::get)
    }
}

#[cfg(not(test))]
mod work {
    #[inline(always)]
    pub(crate) fn tick() {}
}

/// Categories and their allowed count ranges, from `ObjCount`.
struct Counts {
    /// Categories named by any ObjCount entry, parsed or (leniently) malformed.
    declared: HashSet<String>,
    /// Intersection of the ranges of the parsed entries per category.
    ranges: HashMap<String, CountRange>,
    /// The `contradictory-counts` message of the ObjCount entry (by index) that empties its
    /// category's range, if any: computed once for the field, not once per entry.
    contradictions: HashMap<usize, String>,
}

impl Counts {
    fn of(row: &AnnotationRow) -> Counts {
        let mut declared = HashSet::new();
        let mut ranges: HashMap<String, CountRange> = HashMap::new();
        // Per category: the range so far and the entries that made it, in order.
        let mut running: HashMap<&str, (CountRange, Vec<String>)> = HashMap::new();
        let mut contradictions = HashMap::new();
        for (i, entry) in row.obj_count.iter().enumerate() {
            work::tick();
            let name = match entry {
                Entry::Parsed(c) => {
                    let r = ranges.entry(c.category.clone()).or_insert(CountRange::ANY);
                    *r = r.intersect(&c.count.allowed());
                    let (range, before) = running
                        .entry(c.category.as_str())
                        .or_insert((CountRange::ANY, Vec::new()));
                    let next = range.intersect(&c.count.allowed());
                    if next.is_empty() && !range.is_empty() {
                        let list: Vec<String> = before.iter().map(|t| format!("`{t}`")).collect();
                        contradictions.insert(
                            i,
                            format!(
                                "no count of `{}` satisfies both this entry and {}",
                                c.category,
                                list.join(", ")
                            ),
                        );
                        // The range stays empty from here on: later entries report nothing,
                        // so the texts are no longer needed.
                        before.clear();
                    } else if !range.is_empty() {
                        before.push(c.to_string());
                    }
                    *range = next;
                    c.category.clone()
                }
                Entry::Malformed(m) => {
                    let parts: Vec<&str> = m.text().split(',').map(str::trim).collect();
                    parts
                        .get(2)
                        .or(parts.last())
                        .copied()
                        .unwrap_or_default()
                        .to_owned()
                }
            };
            if !name.is_empty() {
                declared.insert(name);
            }
        }
        Counts {
            declared,
            ranges,
            contradictions,
        }
    }

    fn is_declared(&self, category: &str) -> bool {
        self.declared.contains(category)
    }

    /// The largest count allowed (`None`: unbounded), or `Err` when the category has no
    /// usable range (undefined, only malformed entries, or contradictory).
    fn max(&self, category: &str) -> Result<Option<u64>, ()> {
        match self.ranges.get(category) {
            Some(r) if !r.is_empty() => Ok(r.max),
            _ => Err(()),
        }
    }
}

fn check_row(ctx: &mut RowCtx<'_>) {
    let row = ctx.row;
    if row.id.is_empty() {
        ctx.push(
            FindingCode::MissingId,
            Field::Id,
            None,
            "the ID cell is empty".into(),
            None,
        );
    } else if row.id.parse::<u64>().is_err() {
        ctx.push(
            FindingCode::NonIntegerId,
            Field::Id,
            None,
            format!(
                "ID {:?} is not a non-negative integer; scene files are named scene_<ID>.json",
                row.id
            ),
            None,
        );
    }
    if let Difficulty::Other(text) = &row.difficulty {
        ctx.push(
            FindingCode::UnknownDifficulty,
            Field::Difficulty,
            None,
            format!("difficulty {text:?} is not easy, medium or hard"),
            None,
        );
    }
    if row.description.is_empty() {
        ctx.push(
            FindingCode::EmptyDescription,
            Field::Description,
            None,
            "the description is empty".into(),
            None,
        );
    } else if row.description.contains(';') {
        ctx.push(
            FindingCode::DescriptionSemicolon,
            Field::Description,
            None,
            "the description contains `;`; it is kept whole here, but the reference implementation \
             truncates it at the first `;`"
                .into(),
            None,
        );
    }
    if !row.overflow.is_empty() {
        ctx.push(
            FindingCode::RaggedRow,
            Field::Row,
            None,
            format!(
                "the row has {} cell(s) beyond the header's last column ({:?}); an unquoted comma \
                 in a cell shifts every later column",
                row.overflow.len(),
                row.overflow
            ),
            Some("quote cells that contain commas".into()),
        );
    }

    let counts = Counts::of(row);
    check_field(ctx, &row.obj_count, |e, c| check_obj_count(e, c, &counts));
    check_field(ctx, &row.obj_attr, |e, c| check_obj_attr(e, c, &counts));
    check_field(ctx, &row.oo_rel, |e, c| check_oo_rel(e, c, &counts));
    check_field(ctx, &row.oa_rel, |e, c| check_oa_rel(e, c, &counts));
    check_difficulty(ctx);
}

/// Grammar problems of malformed entries, duplicates, then `check` on each parsed entry.
fn check_field<T: EntryKind>(
    ctx: &mut RowCtx<'_>,
    entries: &[Entry<T>],
    mut check: impl FnMut(&mut EntryCtx<'_, '_>, &T),
) {
    let texts: Vec<String> = entries.iter().map(ToString::to_string).collect();
    let mut first_of: HashMap<&str, usize> = HashMap::with_capacity(texts.len());
    for (i, entry) in entries.iter().enumerate() {
        work::tick();
        let first = *first_of.entry(texts[i].as_str()).or_insert(i);
        let mut e = EntryCtx {
            ctx: &mut *ctx,
            field: T::FIELD,
            index: i,
            text: texts[i].clone(),
        };
        if first < i {
            e.push(
                FindingCode::DuplicateEntry,
                format!(
                    "the same entry is entry {} of this field; the reference counts it once",
                    first + 1
                ),
                Some("remove the repeated entry".into()),
            );
            continue;
        }
        match entry {
            Entry::Malformed(m) => {
                for p in m.problems() {
                    let (code, suggestion) = problem_code(p, m.text(), T::FIELD);
                    e.push(code, p.to_string(), suggestion);
                }
            }
            Entry::Parsed(v) => check(&mut e, v),
        }
    }
}

fn problem_code(p: &EntryProblem, text: &str, field: Field) -> (FindingCode, Option<String>) {
    match p {
        EntryProblem::UnknownQuantifier { text: q } => (
            FindingCode::UnknownQuantifier,
            crate::Quantifier::suggest(q).map(|s| text.replacen(q.as_str(), s.as_str(), 1)),
        ),
        EntryProblem::BadQuantity { .. } => (FindingCode::BadQuantity, None),
        EntryProblem::WrongFieldCount { found, .. } => {
            let parts: Vec<&str> = text.split(',').map(str::trim).collect();
            let suggestion = match field {
                Field::ObjAttr if *found > 4 => Some(
                    parts[3..]
                        .iter()
                        .map(|a| format!("{},{},{},{a}", parts[0], parts[1], parts[2]))
                        .collect::<Vec<_>>()
                        .join("; "),
                ),
                Field::OoRel if *found == 5 && parts[3].parse::<i64>().is_err() => Some(format!(
                    "{},{},{},0,{},{}",
                    parts[0], parts[1], parts[2], parts[3], parts[4]
                )),
                _ => None,
            };
            (FindingCode::WrongFieldCount, suggestion)
        }
        EntryProblem::EmptyName { .. } => (FindingCode::EmptyName, None),
        EntryProblem::BadAnchorIndex { .. } => (FindingCode::BadAnchorIndex, None),
        EntryProblem::BadReference { .. } => (FindingCode::BadReference, None),
    }
}

/// `name-format` for the names of one entry.
fn check_names<'n>(e: &mut EntryCtx<'_, '_>, names: impl IntoIterator<Item = &'n str>) {
    let mut bad: Vec<&str> = Vec::new();
    let mut seen: HashSet<&str> = HashSet::new();
    for n in names {
        work::tick();
        if n.contains([' ', '-']) && seen.insert(n) {
            bad.push(n);
        }
    }
    if !bad.is_empty() {
        let fixed: Vec<String> = bad.iter().map(|n| n.replace([' ', '-'], "_")).collect();
        e.push(
            FindingCode::NameFormat,
            format!("{bad:?} contain(s) a space or hyphen; the authors' guidelines use `_` in all names"),
            Some(fixed.join(", ")),
        );
    }
}

/// `contradictory-counts` for an entry that can never hold (`lt,0`).
fn check_satisfiable(e: &mut EntryCtx<'_, '_>, count: &CountSpec) -> bool {
    if count.allowed().is_empty() {
        e.push(
            FindingCode::ContradictoryCounts,
            format!("`{count}` can never hold: no count satisfies it"),
            None,
        );
        return false;
    }
    true
}

/// Reports a category used by a non-count entry that `ObjCount` does not define. Returns
/// whether the category is defined.
fn check_defined(e: &mut EntryCtx<'_, '_>, counts: &Counts, category: &str, role: &str) -> bool {
    if counts.is_declared(category) {
        return true;
    }
    if vocab::is_arch_element(category) {
        let hint = if e.field == Field::OoRel {
            " relationships with architecture belong in OARel"
        } else {
            " it cannot be an object"
        };
        e.push(
            FindingCode::ArchAsObject,
            format!("{role} `{category}` is an architectural element;{hint}"),
            None,
        );
    } else {
        e.push(
            FindingCode::UndefinedCategory,
            format!("{role} `{category}` has no ObjCount entry in this row"),
            Some(format!("add an ObjCount entry such as ge,1,{category}")),
        );
    }
    false
}

fn check_obj_count(e: &mut EntryCtx<'_, '_>, c: &ObjCount, counts: &Counts) {
    check_names(e, [c.category.as_str()]);
    if vocab::is_arch_element(&c.category) {
        e.push(
            FindingCode::ArchAsObject,
            format!(
                "`{}` is an architectural element, not an object to count",
                c.category
            ),
            Some("state it in an OARel entry instead".into()),
        );
    }
    if !check_satisfiable(e, &c.count) {
        return;
    }
    // Reported once per category, at the entry that empties the range.
    if let Some(message) = counts.contradictions.get(&e.index) {
        e.push(FindingCode::ContradictoryCounts, message.clone(), None);
    }
}

fn check_obj_attr(e: &mut EntryCtx<'_, '_>, a: &ObjAttr, counts: &Counts) {
    check_names(e, [a.category.as_str(), a.attribute.as_str()]);
    let satisfiable = check_satisfiable(e, &a.count);
    if !counts.is_declared(&a.category) {
        let swapped = counts.is_declared(&a.attribute)
            || (vocab::is_known_adjective(&a.category) && !vocab::is_known_adjective(&a.attribute));
        if swapped {
            e.push(
                FindingCode::AttributeCategorySwapped,
                format!(
                    "`{}` looks like the attribute and `{}` like the category (the schema is \
                     q,n,category,attribute)",
                    a.category, a.attribute
                ),
                Some(format!("{},{},{}", a.count, a.attribute, a.category)),
            );
        } else {
            check_defined(e, counts, &a.category, "category");
        }
        return;
    }
    let adjectives = vocab::known_adjective_words(&a.attribute);
    if adjectives.len() >= 2 {
        e.push(
            FindingCode::NonAtomicAttribute,
            format!(
                "attribute `{}` combines {} attributes {adjectives:?}; use one entry per attribute",
                a.attribute,
                adjectives.len()
            ),
            Some(
                adjectives
                    .iter()
                    .map(|w| format!("{},{},{w}", a.count, a.category))
                    .collect::<Vec<_>>()
                    .join("; "),
            ),
        );
    }
    if satisfiable && let Ok(Some(max)) = counts.max(&a.category) {
        let need = a.count.allowed().min;
        if need > max {
            e.push(
                FindingCode::AttributeExceedsCount,
                format!(
                    "`{}` needs at least {need} `{}` with the attribute, but ObjCount allows at most {max}",
                    a.count, a.category
                ),
                None,
            );
        }
    }
}

/// C(n, k), saturating at `u128::MAX`.
pub fn binomial(n: u64, k: u64) -> u128 {
    if k > n {
        return 0;
    }
    let k = k.min(n - k);
    let mut r: u128 = 1;
    for i in 0..k {
        // r = C(n, i) here, and C(n, i) * (n - i) = C(n, i + 1) * (i + 1): exact division.
        r = match r.checked_mul(u128::from(n - i)) {
            Some(v) => v / u128::from(i + 1),
            None => return u128::MAX,
        };
    }
    r
}

/// An upper bound on a count: `None` unbounded.
type Bound = Option<u128>;

fn product(factors: &[Bound]) -> Bound {
    if factors.contains(&Some(0)) {
        return Some(0);
    }
    let mut p: u128 = 1;
    for f in factors {
        p = p.saturating_mul((*f)?);
    }
    Some(p)
}

/// The largest number of distinct object groups an `OORel` entry can have under the
/// `ObjCount` entries, or `None` when unbounded or not computable (a category without a usable
/// count range, reported elsewhere).
///
/// A group is one anchor object plus, for every other reference, a distinct object of its
/// category (the references of one category are distinct objects, so `chair:0,chair:1` needs
/// two chairs). With anchor index `a` in range the bound is
/// `max(A) · Π_c C(max(c) - [c = A], k_c)`, where A is the anchor's category and `k_c` the
/// number of non-anchor references of category c; without an anchor (or out of range),
/// groups are unordered: `Π_c C(max(c), t_c)` with `t_c` all references of c.
fn max_groups(rel: &OoRel, counts: &Counts) -> Result<Bound, ()> {
    let mut mentions: Vec<(&str, u64)> = Vec::new();
    let mut slot: HashMap<&str, usize> = HashMap::new();
    for r in &rel.refs {
        work::tick();
        match slot.get(r.category.as_str()) {
            Some(&k) => mentions[k].1 += 1,
            None => {
                slot.insert(&r.category, mentions.len());
                mentions.push((&r.category, 1));
            }
        }
    }
    let mut factors: Vec<Bound> = Vec::new();
    let anchor = rel.anchor_ref().map(|r| r.category.as_str());
    if let Some(a) = anchor {
        factors.push(counts.max(a)?.map(u128::from));
    }
    for (c, t) in mentions {
        let max = counts.max(c)?;
        let (avail, k) = match anchor {
            Some(a) if a == c => (max.map(|m| m.checked_sub(1)), t - 1),
            _ => (max.map(Some), t),
        };
        let factor = match avail {
            None => {
                if k == 0 {
                    Some(1)
                } else {
                    None
                }
            }
            // The anchor's category has no object left for the others (max 0).
            Some(None) => Some(0),
            Some(Some(n)) => Some(binomial(n, k)),
        };
        factors.push(factor);
    }
    Ok(product(&factors))
}

fn check_oo_rel(e: &mut EntryCtx<'_, '_>, rel: &OoRel, counts: &Counts) {
    let mut names: Vec<&str> = vec![rel.relationship.as_str()];
    names.extend(rel.refs.iter().map(|r| r.category.as_str()));
    check_names(e, names);
    let satisfiable = check_satisfiable(e, &rel.count);
    if let Some(a) = rel.anchor
        && a >= rel.refs.len()
    {
        e.push(
            FindingCode::AnchorOutOfRange,
            format!(
                "anchor index {a} but the entry has {} object references (valid: 0-{})",
                rel.refs.len(),
                rel.refs.len() - 1
            ),
            Some("the authors' guidelines fix the anchor index at 0 and put the anchor first".into()),
        );
    }
    let mut all_defined = true;
    let mut reported: Vec<&str> = Vec::new();
    let mut seen: HashSet<&str> = HashSet::new();
    for (i, r) in rel.refs.iter().enumerate() {
        work::tick();
        if !seen.insert(r.category.as_str()) {
            continue;
        }
        reported.push(&r.category);
        all_defined &= check_defined(e, counts, &r.category, &format!("reference {i}"));
    }
    if !(satisfiable && all_defined) {
        return;
    }
    let need = u128::from(rel.count.allowed().min);
    if let Ok(Some(max)) = max_groups(rel, counts)
        && max < need
    {
        let limits: Vec<String> = reported
            .iter()
            .filter_map(|c| counts.max(c).ok().flatten().map(|m| format!("{c} at most {m}")))
            .collect();
        e.push(
            FindingCode::RelationshipExceedsCount,
            format!(
                "`{}` needs at least {need} distinct group(s) of objects, but the object counts \
                 allow at most {max} ({})",
                rel.count,
                limits.join(", ")
            ),
            None,
        );
    }
}

fn check_oa_rel(e: &mut EntryCtx<'_, '_>, rel: &OaRel, counts: &Counts) {
    let mut names: Vec<&str> = vec![rel.relationship.as_str(), rel.object.category.as_str()];
    names.extend(
        rel.arch
            .iter()
            .filter(|a| matches!(a, ArchRef::Unknown(_)))
            .map(ArchRef::as_str),
    );
    check_names(e, names);
    let satisfiable = check_satisfiable(e, &rel.count);
    for arch in &rel.arch {
        let ArchRef::Unknown(name) = arch else { continue };
        let (message, suggestion) = if counts.is_declared(name) {
            (
                format!("`{name}` is an object category of this row, not architecture"),
                Some(format!(
                    "{},{},0,{name},{}",
                    rel.count, rel.relationship, rel.object
                )),
            )
        } else {
            match vocab::suggest_arch(name) {
                Some(ArchSuggestion::InstanceId(stem)) => (
                    format!("`{name}` names one instance; the authors' guidelines allow only types"),
                    Some(stem),
                ),
                Some(ArchSuggestion::Spelling(known)) => {
                    (format!("unknown architecture reference `{name}`"), Some(known))
                }
                None => (
                    format!(
                        "unknown architecture reference `{name}` (expected wall, floor, ceiling, \
                         window, door, room or a room type)"
                    ),
                    None,
                ),
            }
        };
        e.push(FindingCode::UnknownArchReference, message, suggestion);
    }
    let cat = rel.object.category.as_str();
    if !check_defined(e, counts, cat, "object") || !satisfiable {
        return;
    }
    if let Ok(Some(max)) = counts.max(cat) {
        let need = rel.count.allowed().min;
        if need > max {
            e.push(
                FindingCode::RelationshipExceedsCount,
                format!(
                    "`{}` needs at least {need} `{cat}`, but ObjCount allows at most {max}",
                    rel.count
                ),
                None,
            );
        }
    }
}

/// Object-count bounds of the difficulty levels (paper, section "SceneEval-500").
fn difficulty_bounds(d: &Difficulty) -> Option<(u64, Option<u64>)> {
    match d {
        Difficulty::Easy => Some((0, Some(4))),
        Difficulty::Medium => Some((5, Some(8))),
        Difficulty::Hard => Some((9, None)),
        Difficulty::Other(_) => None,
    }
}

fn check_difficulty(ctx: &mut RowCtx<'_>) {
    let row = ctx.row;
    let Some((min, max)) = difficulty_bounds(&row.difficulty) else {
        return;
    };
    if row.obj_count.iter().any(|e| e.malformed().is_some()) {
        return;
    }
    let n = row.objects_specified();
    if n < min || max.is_some_and(|m| n > m) {
        let range = match max {
            Some(m) => format!("{min}-{m}"),
            None => format!("at least {min}"),
        };
        ctx.push(
            FindingCode::DifficultyObjectCount,
            Field::Difficulty,
            None,
            format!(
                "ObjCount specifies {n} objects; {} descriptions specify {range}",
                row.difficulty
            ),
            None,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Validation steps for a row with `n` entries in every field: `n` distinct categories
    /// counted, `n` attributes, `n` relationships (one of them with `n` references), `n`
    /// architecture relationships, and `n` repeats of one entry.
    fn steps_for(n: usize) -> u64 {
        let counts: Vec<String> = (0..n).map(|i| format!("eq,1,c{i}")).collect();
        let attrs: Vec<String> = (0..n).map(|i| format!("eq,1,c{i},red")).collect();
        let mut rels: Vec<String> = (1..n).map(|i| format!("eq,1,next_to,0,c0,c{i}")).collect();
        let refs: Vec<String> = (0..n).map(|i| format!("c{i}")).collect();
        rels.push(format!("ge,1,surround,0,{}", refs.join(",")));
        let arch: Vec<String> = (0..n).map(|i| format!("eq,1,against,c{i},wall")).collect();
        let repeats = vec!["eq,1,c0,blue"; n].join("; ");
        let text = format!(
            "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n0,hard,x,\"{}\",\"{}; {repeats}\",\"{}\",\"{}\"\n",
            counts.join("; "),
            attrs.join("; "),
            rels.join("; "),
            arch.join("; ")
        );
        let a = Annotations::from_csv_str(&text).unwrap();
        let before = work::steps();
        let findings = validate(&a);
        // The n - 1 repeats are each reported.
        assert!(
            findings
                .iter()
                .filter(|f| f.code == FindingCode::DuplicateEntry)
                .count()
                >= n - 1
        );
        work::steps() - before
    }

    #[test]
    fn validation_work_is_linear_in_the_number_of_entries() {
        // Every loop of the validator counts a step. With hash lookups each entry and reference
        // costs a constant number of steps; the earlier pairwise comparisons cost n^2 / 2
        // (5e9 for a cell of 100,000 entries, over 20 s).
        let small = steps_for(2_000);
        let large = steps_for(8_000);
        assert!(
            large <= 4 * small + 100,
            "{small} steps for 2,000, {large} for 8,000"
        );
        // About 6n entries and n references in all: a few steps each.
        assert!(large <= 30 * 8_000, "{large} steps for 8,000 entries per field");
        // The case: one cell of 100,000 ObjCount entries.
        let cell: Vec<String> = (0..100_000).map(|i| format!("eq,1,c{i}")).collect();
        let text = format!(
            "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n0,hard,x,\"{}\",,,\n",
            cell.join("; ")
        );
        let a = Annotations::from_csv_str(&text).unwrap();
        let before = work::steps();
        let findings = validate(&a);
        let steps = work::steps() - before;
        assert!(steps <= 3 * 100_000, "{steps} steps");
        assert!(findings.iter().all(|f| f.code != FindingCode::DuplicateEntry));
    }

    fn row(obj_count: &str, obj_attr: &str, oo_rel: &str, oa_rel: &str) -> AnnotationRow {
        let mut r = AnnotationRow::new("0", Difficulty::Easy, "A room.");
        r.set_cell("ObjCount", obj_count);
        r.set_cell("ObjAttr", obj_attr);
        r.set_cell("OORel", oo_rel);
        r.set_cell("OARel", oa_rel);
        r
    }

    /// The codes found, without `difficulty-object-count` (the test rows are all "easy").
    fn codes(r: &AnnotationRow) -> Vec<FindingCode> {
        validate_row(r, 0)
            .into_iter()
            .map(|f| f.code)
            .filter(|&c| c != FindingCode::DifficultyObjectCount)
            .collect()
    }

    #[test]
    fn a_clean_row_has_no_findings() {
        let r = row(
            "eq,1,bed; eq,2,nightstand; eq,1,wardrobe",
            "eq,1,bed,king_size",
            "eq,1,left,0,bed,nightstand; eq,1,right,0,bed,nightstand",
            "eq,1,corner,wardrobe,room; eq,1,against,bed,wall",
        );
        assert_eq!(validate_row(&r, 0), vec![]);
    }

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

    #[test]
    fn undefined_and_swapped_and_arch() {
        assert_eq!(
            codes(&row("eq,1,bed", "eq,1,sofa,red", "", "")),
            vec![FindingCode::UndefinedCategory]
        );
        // The data-generation prompt's own example: eq,1,red,bed.
        let r = row("eq,1,bed", "eq,1,red,bed", "", "");
        let f = validate_row(&r, 0);
        assert_eq!(f.len(), 1);
        assert_eq!(f[0].code, FindingCode::AttributeCategorySwapped);
        assert_eq!(f[0].suggestion.as_deref(), Some("eq,1,bed,red"));
        // Swapped even when the category is not counted, because "red" is a colour.
        assert_eq!(
            codes(&row("eq,1,lamp", "eq,1,red,sofa", "", "")),
            vec![FindingCode::AttributeCategorySwapped]
        );
        assert_eq!(
            codes(&row("eq,1,bed; eq,1,window", "", "eq,1,near,0,bed,door", "")),
            vec![FindingCode::ArchAsObject, FindingCode::ArchAsObject]
        );
    }

    #[test]
    fn anchors() {
        // The hallucinated anchor of the paper's limitations section: 14 with two objects.
        let r = row("eq,1,bed; eq,1,nightstand", "", "eq,1,left,14,bed,nightstand", "");
        assert_eq!(codes(&r), vec![FindingCode::AnchorOutOfRange]);
        let r = row(
            "eq,1,bed; eq,1,nightstand",
            "",
            "eq,1,left,1,bed,nightstand; eq,1,near,-1,bed,nightstand",
            "",
        );
        assert_eq!(codes(&r), vec![]);
    }

    #[test]
    fn non_atomic_attributes() {
        let r = row(
            "eq,1,table",
            "eq,1,table,round_wooden; eq,1,table,stainless_steel",
            "",
            "",
        );
        let f = validate_row(&r, 0);
        assert_eq!(
            f.iter().map(|f| f.code).collect::<Vec<_>>(),
            vec![FindingCode::NonAtomicAttribute]
        );
        assert_eq!(
            f[0].suggestion.as_deref(),
            Some("eq,1,table,round; eq,1,table,wooden")
        );
    }

    #[test]
    fn duplicates_and_contradictions() {
        let r = row("eq,1,bed; eq,1,bed", "", "", "");
        assert_eq!(codes(&r), vec![FindingCode::DuplicateEntry]);
        let r = row("eq,0,chair; ge,1,chair; le,3,chair", "", "", "");
        let f = validate_row(&r, 0);
        assert_eq!(
            f.iter().map(|f| f.code).collect::<Vec<_>>(),
            vec![FindingCode::ContradictoryCounts]
        );
        assert_eq!(f[0].entry_index, Some(1));
        // ge,1 and le,3 agree: no finding.
        assert_eq!(codes(&row("ge,1,chair; le,3,chair", "", "", "")), vec![]);
        assert_eq!(
            codes(&row("lt,0,chair", "", "", "")),
            vec![FindingCode::ContradictoryCounts]
        );
    }

    #[test]
    fn counts_exceeded() {
        // Two chairs next to the table but only one chair: 1 table x C(1,1) = 1 group < 2.
        let r = row("eq,1,table; eq,1,chair", "", "eq,2,next,0,table,chair", "");
        assert_eq!(codes(&r), vec![FindingCode::RelationshipExceedsCount]);
        // Surround needing three chairs with one chair: C(1,3) = 0 < 1.
        let r = row(
            "eq,1,table; eq,1,chair",
            "",
            "eq,1,surround,0,table,chair:0,chair:1,chair:2",
            "",
        );
        assert_eq!(codes(&r), vec![FindingCode::RelationshipExceedsCount]);
        // Four chairs: C(4,3) = 4 >= 1.
        let r = row(
            "eq,1,table; eq,4,chair",
            "",
            "eq,1,surround,0,table,chair:0,chair:1,chair:2",
            "",
        );
        assert_eq!(codes(&r), vec![]);
        // Unbounded chairs (ge) but zero tables: 0 x inf = 0 < 1.
        let r = row("eq,0,table; ge,1,chair", "", "ge,1,next,0,table,chair", "");
        assert_eq!(codes(&r), vec![FindingCode::RelationshipExceedsCount]);
        // le/lt need no group at all.
        let r = row("eq,0,table; eq,0,chair", "", "le,2,next,0,table,chair", "");
        assert_eq!(codes(&r), vec![]);
        // A chair next to a chair needs two chairs: 1 x C(1-1, 1) = 0.
        let r = row("eq,1,chair", "", "eq,1,next,0,chair,chair", "");
        assert_eq!(codes(&r), vec![FindingCode::RelationshipExceedsCount]);
        let r = row("eq,2,chair", "", "eq,1,next,0,chair,chair", "");
        assert_eq!(codes(&r), vec![]);
        // Unspecified anchor: unordered groups, C(1, 2) = 0 with one chair, C(2, 2) = 1 with two.
        let r = row("eq,1,chair", "", "eq,1,near,-1,chair,chair", "");
        assert_eq!(codes(&r), vec![FindingCode::RelationshipExceedsCount]);
        let r = row("eq,2,chair", "", "eq,1,near,-1,chair,chair", "");
        assert_eq!(codes(&r), vec![]);
        // gt,1 needs 2 groups: 1 table x C(3, 2) = 3 pairs of chairs is enough.
        let r = row(
            "eq,1,table; eq,3,chair",
            "",
            "gt,1,between,0,table,chair:0,chair:1",
            "",
        );
        assert_eq!(codes(&r), vec![]);
        // ... but gt,3 needs 4 > 3.
        let r = row(
            "eq,1,table; eq,3,chair",
            "",
            "gt,3,between,0,table,chair:0,chair:1",
            "",
        );
        assert_eq!(codes(&r), vec![FindingCode::RelationshipExceedsCount]);
        let r = row(
            "eq,1,armchair",
            "eq,2,armchair,blue",
            "",
            "eq,2,against,armchair,wall",
        );
        assert_eq!(
            codes(&r),
            vec![
                FindingCode::AttributeExceedsCount,
                FindingCode::RelationshipExceedsCount
            ]
        );
    }

    #[test]
    fn binomials() {
        assert_eq!(binomial(4, 3), 4);
        assert_eq!(binomial(5, 2), 10);
        assert_eq!(binomial(1, 3), 0);
        assert_eq!(binomial(0, 0), 1);
        // C(60, 30) = 118264581564861424.
        assert_eq!(binomial(60, 30), 118_264_581_564_861_424);
        assert_eq!(binomial(u64::MAX, 5), u128::MAX);
    }

    #[test]
    fn arch_references() {
        let r = row(
            "eq,1,painting; eq,1,lamp",
            "",
            "",
            "eq,1,on,painting,wall_1; eq,1,near,lamp,windw; eq,1,on,lamp,painting",
        );
        let f = validate_row(&r, 0);
        let got: Vec<(FindingCode, Option<&str>)> =
            f.iter().map(|f| (f.code, f.suggestion.as_deref())).collect();
        assert_eq!(
            got,
            vec![
                (FindingCode::UnknownArchReference, Some("wall")),
                (FindingCode::UnknownArchReference, Some("window")),
                (FindingCode::UnknownArchReference, Some("eq,1,on,0,painting,lamp")),
            ]
        );
    }

    #[test]
    fn row_level_findings() {
        let mut r = row("eq,1,bed", "", "", "");
        r.id = "x1".into();
        r.difficulty = Difficulty::Other("expert".into());
        r.description = "A bed; nothing else.".into();
        r.overflow = vec!["extra".into()];
        assert_eq!(
            codes(&r),
            vec![
                FindingCode::NonIntegerId,
                FindingCode::UnknownDifficulty,
                FindingCode::DescriptionSemicolon,
                FindingCode::RaggedRow
            ]
        );
        r.id.clear();
        r.description.clear();
        let c = codes(&r);
        assert!(c.contains(&FindingCode::MissingId) && c.contains(&FindingCode::EmptyDescription));
    }

    #[test]
    fn duplicate_ids_across_rows() {
        let a = Annotations::from_rows(vec![row("eq,1,bed", "", "", ""), row("eq,1,bed", "", "", "")]);
        let f = validate(&a);
        assert_eq!(f.len(), 1);
        assert_eq!((f[0].code, f[0].row_index), (FindingCode::DuplicateId, 1));
    }

    #[test]
    fn difficulty_object_counts() {
        let all = |r: &AnnotationRow| validate_row(r, 0).into_iter().map(|f| f.code).collect::<Vec<_>>();
        // eq,5 + gt,1 (counts 2) + eq,0 = 7 objects.
        let mut r = row("eq,5,chair; gt,1,cup; eq,0,table", "", "", "");
        assert_eq!(all(&r), vec![FindingCode::DifficultyObjectCount]);
        r.difficulty = Difficulty::Medium;
        assert_eq!(all(&r), vec![]);
        r.difficulty = Difficulty::Hard;
        assert_eq!(all(&r), vec![FindingCode::DifficultyObjectCount]);
    }

    #[test]
    fn malformed_entries_do_not_cascade() {
        // The malformed ObjCount entry still declares "bed"; only the grammar is reported.
        let r = row("eq,x,bed", "eq,1,bed,large", "", "");
        assert_eq!(codes(&r), vec![FindingCode::BadQuantity]);
        let f = validate_row(&row("EQ,1,bed", "", "", ""), 0);
        assert_eq!(f[0].suggestion.as_deref(), Some("eq,1,bed"));
        let f = validate_row(&row("eq,1,bed; eq,1,lamp", "", "eq,1,left,bed,lamp", ""), 0);
        assert_eq!(f[0].code, FindingCode::WrongFieldCount);
        assert_eq!(f[0].suggestion.as_deref(), Some("eq,1,left,0,bed,lamp"));
    }
}
