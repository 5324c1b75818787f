//! Validation: every problem of an annotation file as a [`Finding`].
//!
//! The checks are the failure modes the paper's authors fixed by hand in LLM-written
//! annotations (appendix "Semi-Automatic Data Generation Limitations") and the inputs that
//! make the reference implementation crash or silently mis-score (`reference-notes.md` §3, Q5,
//! Q6, Q18, Q21, Q24). See [`FindingCode`] for the list, with severities.
//!
//! One concept per file: `finding` (the finding types and codes), `row` (the checks of one row:
//! its own cells, then each field), `field` (checks shared by the entries of a field: repeats
//! and grammar), `checks` (checks shared by the entry kinds: names, satisfiable counts, defined
//! categories), then one file per entry kind with its semantic checks (`obj_count`, `obj_attr`,
//! `oo_rel`, `oa_rel`).

mod checks;
mod field;
mod finding;
mod oa_rel;
mod obj_attr;
mod obj_count;
mod oo_rel;
mod row;

#[cfg(test)]
mod test_support;

use std::collections::HashMap;

pub use finding::{Finding, FindingCode, Severity, Summary};
pub use oo_rel::binomial;

use crate::Annotations;
use crate::quote::excerpt;
use crate::row::{AnnotationRow, Field};
use row::check_row;

/// Every finding of every row, in row order, then column order, then entry order.
///
/// Malformed entries are reported by their grammar problems only; the semantic checks run on
/// the parsed entries. A category counted by a malformed `ObjCount` entry whose last field is
/// readable still counts as defined, so one typo gives one finding, not a cascade.
///
/// A problem repeated over the items of one entry (undefined references, unknown architecture
/// references, bad or empty references) is one finding with its number of
/// [`occurrences`](Finding::occurrences), and so is an entry repeated in one field. Each
/// finding quotes at most [`MAX_QUOTE_CHARS`](crate::MAX_QUOTE_CHARS) characters of any one
/// piece of input and lists at most [`MAX_QUOTED_ITEMS`](crate::MAX_QUOTED_ITEMS) items, so
/// the findings' size, like the work (hash lookups; a cell of 100,000 entries validates in
/// well under a second), is linear in the size of the file.
pub fn validate(annotations: &Annotations) -> Vec<Finding> {
    let mut out = Vec::new();
    let mut first_row_of: HashMap<&str, usize> = HashMap::new();
    for (index, row) in annotations.rows.iter().enumerate() {
        let mut ctx = RowCtx::new(row, index, &mut out);
        if !row.id.is_empty() {
            match first_row_of.get(row.id.as_str()) {
                Some(&first) => {
                    let message = format!(
                        "ID {:?} is also used by record {}; lookups return that row",
                        ctx.id,
                        first + 1
                    );
                    ctx.push(FindingCode::DuplicateId, Field::Id, None, message, None);
                }
                None => {
                    first_row_of.insert(&row.id, index);
                }
            }
        }
        check_row(&mut ctx);
    }
    out
}

/// The findings of [`validate`] (the whole file's validation, so exactly what it reports)
/// that concern the rows at `indices` (positions in [`Annotations::rows`]): each row's own
/// findings, and the `duplicate-id` findings of the other rows with its ID (another row with
/// the ID makes a lookup of it ambiguous). What a run that uses only these rows checks before
/// it starts.
///
/// ```
/// use std::collections::BTreeSet;
/// use sceneeval_annotation::{Annotations, FindingCode, validate_rows};
/// let a = Annotations::from_csv_str(
///     "ID,Difficulty,Description,ObjCount,ObjAttr,OORel,OARel\n\
///      1,easy,a bed,\"eq,1,bed\",\"eq,1,chair,red\",,\n\
///      2,easy,a desk,\"eq,1,desk\",,,\n\
///      2,easy,two desks,\"eq,2,desk\",,,\n",
/// ).unwrap();
/// // Row 2 (index 1) is fine on its own, but its ID is used again by the last row.
/// let codes: Vec<_> = validate_rows(&a, &BTreeSet::from([1])).iter().map(|f| f.code).collect();
/// assert_eq!(codes, [FindingCode::DuplicateId]);
/// // Row 1 counts no chair but gives one an attribute.
/// assert_eq!(validate_rows(&a, &BTreeSet::from([0]))[0].code, FindingCode::UndefinedCategory);
/// ```
pub fn validate_rows(annotations: &Annotations, indices: &std::collections::BTreeSet<usize>) -> Vec<Finding> {
    let ids: std::collections::HashSet<&str> = indices
        .iter()
        .filter_map(|&i| annotations.rows.get(i))
        .map(|r| r.id.as_str())
        .filter(|id| !id.is_empty())
        .collect();
    validate(annotations)
        .into_iter()
        .filter(|f| {
            indices.contains(&f.row_index)
                || (f.code == FindingCode::DuplicateId
                    && annotations
                        .rows
                        .get(f.row_index)
                        .is_some_and(|r| ids.contains(r.id.as_str())))
        })
        .collect()
}

/// The findings of one row alone (no `duplicate-id`, which needs the whole file);
/// `row_index` is set to `index`.
pub fn validate_row(row: &AnnotationRow, index: usize) -> Vec<Finding> {
    let mut out = Vec::new();
    check_row(&mut RowCtx::new(row, index, &mut out));
    out
}

struct RowCtx<'a> {
    row: &'a AnnotationRow,
    /// The row's ID as findings quote it.
    id: String,
    index: usize,
    out: &'a mut Vec<Finding>,
}

impl<'a> RowCtx<'a> {
    fn new(row: &'a AnnotationRow, index: usize, out: &'a mut Vec<Finding>) -> Self {
        RowCtx {
            row,
            id: excerpt(&row.id).into_owned(),
            index,
            out,
        }
    }

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
            row: self.id.clone(),
            row_index: self.index,
            field,
            entry,
            entry_index,
            message,
            suggestion,
            occurrences: 1,
        });
    }
}

/// The per-entry context of the semantic checks.
struct EntryCtx<'c, 'a> {
    ctx: &'c mut RowCtx<'a>,
    field: Field,
    index: usize,
    /// The entry as findings quote it.
    text: String,
    /// Where the entry's findings start in the row's output.
    start: usize,
}

impl<'c, 'a> EntryCtx<'c, 'a> {
    fn new(ctx: &'c mut RowCtx<'a>, field: Field, index: usize, text: &str) -> Self {
        let start = ctx.out.len();
        EntryCtx {
            ctx,
            field,
            index,
            text: excerpt(text).into_owned(),
            start,
        }
    }

    /// Reports a problem of the entry; a second problem of the same code counts as another
    /// occurrence of the first finding (an entry has at most one finding per code, so the
    /// search is short).
    fn push(&mut self, code: FindingCode, message: String, suggestion: Option<String>) {
        if let Some(found) = self.ctx.out[self.start..].iter_mut().find(|f| f.code == code) {
            found.occurrences += 1;
            return;
        }
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
#[cfg(test)]
mod tests {
    use super::test_support::row;
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
        // The n - 1 repeats of one entry are one finding of n - 1 occurrences.
        let repeats: Vec<&Finding> = findings
            .iter()
            .filter(|f| f.code == FindingCode::DuplicateEntry)
            .collect();
        assert_eq!(repeats.len(), 1);
        assert_eq!(repeats[0].occurrences, n - 1);
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
        // The issue's case: one cell of 100,000 ObjCount entries.
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
    fn duplicate_ids_across_rows() {
        let a = Annotations::from_rows(vec![row("eq,1,bed", "", "", ""), row("eq,1,bed", "", "", "")]);
        let f = validate(&a);
        assert_eq!(f.len(), 1);
        assert_eq!((f[0].code, f[0].row_index), (FindingCode::DuplicateId, 1));
    }
}
