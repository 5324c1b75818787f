//! `ObjCount`: the categories a row declares and the count range each allows ([`Counts`],
//! which the other entry kinds check against), and the checks of an `ObjCount` entry.

use std::collections::{HashMap, HashSet};

use super::checks::{check_names, check_satisfiable};
use super::{EntryCtx, FindingCode, work};
use crate::entry::{Entry, ObjCount};
use crate::quantifier::CountRange;
use crate::quote::{list, ticked};
use crate::row::AnnotationRow;
use crate::vocab;

/// Categories and their allowed count ranges, from `ObjCount`.
pub(super) struct Counts {
    /// Categories named by any ObjCount entry, parsed or (leniently) malformed.
    declared: HashSet<String>,
    /// Intersection of the ranges of the parsed entries per category.
    ranges: HashMap<String, CountRange>,
    /// The `contradictory-counts` message of the ObjCount entry (by index) that empties its
    /// category's range, if any: computed once for the field, not once per entry.
    contradictions: HashMap<usize, String>,
}

impl Counts {
    pub(super) fn of(row: &AnnotationRow) -> Counts {
        let mut declared = HashSet::new();
        let mut ranges: HashMap<String, CountRange> = HashMap::new();
        // Per category: the range so far and the entries that made it (indices), in order.
        let mut running: HashMap<&str, (CountRange, Vec<usize>)> = HashMap::new();
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
                        let earlier = list(before.iter(), ", ", |&k| ticked(&row.obj_count[k].to_string()));
                        contradictions.insert(
                            i,
                            format!(
                                "no count of {} satisfies both this entry and {earlier}",
                                ticked(&c.category),
                            ),
                        );
                        // The range stays empty from here on: later entries report nothing,
                        // so the texts are no longer needed.
                        before.clear();
                    } else if !range.is_empty() {
                        before.push(i);
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

    pub(super) fn is_declared(&self, category: &str) -> bool {
        self.declared.contains(category)
    }

    /// The largest count allowed (`None`: unbounded), or `Err` when the category has no
    /// usable range (undefined, only malformed entries, or contradictory).
    pub(super) fn max(&self, category: &str) -> Result<Option<u64>, ()> {
        match self.ranges.get(category) {
            Some(r) if !r.is_empty() => Ok(r.max),
            _ => Err(()),
        }
    }
}

pub(super) fn check_obj_count(e: &mut EntryCtx<'_, '_>, c: &ObjCount, counts: &Counts) {
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
#[cfg(test)]
mod tests {
    use super::super::test_support::{codes, row};
    use super::super::validate_row;
    use super::*;

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
}
