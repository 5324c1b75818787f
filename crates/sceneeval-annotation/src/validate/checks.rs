//! Checks shared by the entry kinds: the format of names, counts that can never hold, and
//! categories used without an `ObjCount` entry (or architecture used as an object).

use std::collections::HashSet;

use super::obj_count::Counts;
use super::{EntryCtx, FindingCode, work};
use crate::quantifier::CountSpec;
use crate::quote::{excerpt, list, ticked};
use crate::row::Field;
use crate::vocab;

/// `name-format` for the names of one entry.
pub(super) fn check_names<'n>(e: &mut EntryCtx<'_, '_>, names: impl IntoIterator<Item = &'n str>) {
    let mut bad: Vec<&str> = Vec::new();
    let mut seen: HashSet<&str> = HashSet::new();
    for n in names {
        work::tick();
        if n.contains([' ', '-']) && seen.insert(n) {
            bad.push(n);
        }
    }
    if !bad.is_empty() {
        let names = list(&bad, ", ", |n| format!("{:?}", excerpt(n)));
        let fixed = list(&bad, ", ", |n| excerpt(&n.replace([' ', '-'], "_")).into_owned());
        e.push(
            FindingCode::NameFormat,
            format!("{names} contain(s) a space or hyphen; the authors' guidelines use `_` in all names"),
            Some(fixed),
        );
    }
}

/// `contradictory-counts` for an entry that can never hold (`lt,0`).
pub(super) fn check_satisfiable(e: &mut EntryCtx<'_, '_>, count: &CountSpec) -> bool {
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
pub(super) fn check_defined(e: &mut EntryCtx<'_, '_>, counts: &Counts, category: &str, role: &str) -> bool {
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
            format!("{role} {} has no ObjCount entry in this row", ticked(category)),
            Some(format!(
                "add an ObjCount entry such as ge,1,{}",
                excerpt(category)
            )),
        );
    }
    false
}
#[cfg(test)]
mod tests {
    use super::super::test_support::{codes, row};
    use super::super::validate_row;
    use super::*;

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
}
