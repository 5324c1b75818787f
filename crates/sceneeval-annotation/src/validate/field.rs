//! The checks every field shares: the repeats of an entry are reported once, with their
//! number, a malformed entry by its grammar problems, and a parsed entry by its kind's semantic
//! checks.

use std::collections::HashMap;

use super::{EntryCtx, FindingCode, RowCtx, work};
use crate::entry::{Entry, EntryKind, EntryProblem};
use crate::quote::{excerpt, list};
use crate::row::Field;

/// Grammar problems of malformed entries, duplicates, then `check` on each parsed entry.
pub(super) fn check_field<T: EntryKind>(
    ctx: &mut RowCtx<'_>,
    entries: &[Entry<T>],
    mut check: impl FnMut(&mut EntryCtx<'_, '_>, &T),
) {
    let texts: Vec<String> = entries.iter().map(ToString::to_string).collect();
    let mut first_of: HashMap<&str, usize> = HashMap::with_capacity(texts.len());
    // The `duplicate-entry` finding of each repeated entry (by its first index), in the output.
    let mut repeats: HashMap<usize, usize> = HashMap::new();
    for (i, entry) in entries.iter().enumerate() {
        work::tick();
        let first = *first_of.entry(texts[i].as_str()).or_insert(i);
        if first < i
            && let Some(&k) = repeats.get(&first)
        {
            ctx.out[k].occurrences += 1;
            continue;
        }
        let mut e = EntryCtx::new(&mut *ctx, T::FIELD, i, &texts[i]);
        if first < i {
            repeats.insert(first, e.ctx.out.len());
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
            crate::Quantifier::suggest(q)
                .map(|s| excerpt(&text.replacen(q.as_str(), s.as_str(), 1)).into_owned()),
        ),
        EntryProblem::BadQuantity { .. } => (FindingCode::BadQuantity, None),
        EntryProblem::WrongFieldCount { found, .. } => {
            let parts: Vec<&str> = text.split(',').map(str::trim).collect();
            let suggestion = match field {
                Field::ObjAttr if *found > 4 => Some(list(&parts[3..], "; ", |a| {
                    excerpt(&format!("{},{},{},{a}", parts[0], parts[1], parts[2])).into_owned()
                })),
                Field::OoRel if *found == 5 && parts[3].parse::<i64>().is_err() => Some(
                    excerpt(&format!(
                        "{},{},{},0,{},{}",
                        parts[0], parts[1], parts[2], parts[3], parts[4]
                    ))
                    .into_owned(),
                ),
                _ => None,
            };
            (FindingCode::WrongFieldCount, suggestion)
        }
        EntryProblem::EmptyName { .. } => (FindingCode::EmptyName, None),
        EntryProblem::BadAnchorIndex { .. } => (FindingCode::BadAnchorIndex, None),
        EntryProblem::BadReference { .. } => (FindingCode::BadReference, None),
    }
}
#[cfg(test)]
mod tests {
    use super::super::test_support::{codes, row};
    use super::super::validate_row;
    use super::*;

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
