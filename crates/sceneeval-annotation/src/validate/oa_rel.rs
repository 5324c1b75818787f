//! The checks of an `OARel` entry: architecture references (instance ids, misspellings, object
//! categories in their place), the object's category, and its count.

use super::checks::{check_defined, check_names, check_satisfiable};
use super::obj_count::Counts;
use super::{EntryCtx, FindingCode};
use crate::entry::{ArchRef, OaRel};
use crate::quote::{excerpt, ticked};
use crate::vocab::{self, ArchSuggestion};

pub(super) fn check_oa_rel(e: &mut EntryCtx<'_, '_>, rel: &OaRel, counts: &Counts) {
    let mut names: Vec<&str> = vec![rel.relationship.as_str(), rel.object.category.as_str()];
    names.extend(
        rel.arch
            .iter()
            .filter(|a| matches!(a, ArchRef::Unknown(_)))
            .map(ArchRef::as_str),
    );
    check_names(e, names);
    let satisfiable = check_satisfiable(e, &rel.count);
    // The parts of the OORel entry suggested for an object in an architecture reference's
    // place, quoted once for all of them.
    let relationship = excerpt(&rel.relationship);
    let object = rel.object.to_string();
    let object = excerpt(&object);
    for arch in &rel.arch {
        let ArchRef::Unknown(name) = arch else { continue };
        let quoted = ticked(name);
        let (message, suggestion) = if counts.is_declared(name) {
            (
                format!("{quoted} is an object category of this row, not architecture"),
                Some(
                    excerpt(&format!(
                        "{},{relationship},0,{},{object}",
                        rel.count,
                        excerpt(name)
                    ))
                    .into_owned(),
                ),
            )
        } else {
            match vocab::suggest_arch(name) {
                Some(ArchSuggestion::InstanceId(stem)) => (
                    format!("{quoted} names one instance; the authors' guidelines allow only types"),
                    Some(excerpt(&stem).into_owned()),
                ),
                Some(ArchSuggestion::Spelling(known)) => {
                    (format!("unknown architecture reference {quoted}"), Some(known))
                }
                None => (
                    format!(
                        "unknown architecture reference {quoted} (expected wall, floor, ceiling, \
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
                    "`{}` needs at least {need} {}, but ObjCount allows at most {max}",
                    rel.count,
                    ticked(cat)
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
}
