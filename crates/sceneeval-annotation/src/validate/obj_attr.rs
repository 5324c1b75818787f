//! The checks of an `ObjAttr` entry: swapped attribute and category, attributes that combine
//! several adjectives, and more objects with the attribute than `ObjCount` allows.

use super::checks::{check_defined, check_names, check_satisfiable};
use super::obj_count::Counts;
use super::{EntryCtx, FindingCode};
use crate::entry::ObjAttr;
use crate::quote::{excerpt, list, ticked};
use crate::vocab;

pub(super) fn check_obj_attr(e: &mut EntryCtx<'_, '_>, a: &ObjAttr, counts: &Counts) {
    check_names(e, [a.category.as_str(), a.attribute.as_str()]);
    let satisfiable = check_satisfiable(e, &a.count);
    if !counts.is_declared(&a.category) {
        let swapped = counts.is_declared(&a.attribute)
            || (vocab::is_known_adjective(&a.category) && !vocab::is_known_adjective(&a.attribute));
        if swapped {
            e.push(
                FindingCode::AttributeCategorySwapped,
                format!(
                    "{} looks like the attribute and {} like the category (the schema is \
                     q,n,category,attribute)",
                    ticked(&a.category),
                    ticked(&a.attribute)
                ),
                Some(excerpt(&format!("{},{},{}", a.count, a.attribute, a.category)).into_owned()),
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
                "attribute {} combines {} attributes ({}); use one entry per attribute",
                ticked(&a.attribute),
                adjectives.len(),
                list(&adjectives, ", ", |w| format!("{:?}", excerpt(w)))
            ),
            Some(list(&adjectives, "; ", |w| {
                excerpt(&format!("{},{},{w}", a.count, a.category)).into_owned()
            })),
        );
    }
    if satisfiable && let Ok(Some(max)) = counts.max(&a.category) {
        let need = a.count.allowed().min;
        if need > max {
            e.push(
                FindingCode::AttributeExceedsCount,
                format!(
                    "`{}` needs at least {need} {} with the attribute, but ObjCount allows at most {max}",
                    a.count,
                    ticked(&a.category)
                ),
                None,
            );
        }
    }
}
#[cfg(test)]
mod tests {
    use super::super::test_support::row;
    use super::super::validate_row;
    use super::*;

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
}
