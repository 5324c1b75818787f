//! The checks of an `OORel` entry: the anchor index, defined references, and the number of
//! distinct object groups the counts allow (binomials over the references' categories).

use std::collections::{HashMap, HashSet};

use super::checks::{check_defined, check_names, check_satisfiable};
use super::obj_count::Counts;
use super::{EntryCtx, FindingCode, work};
use crate::entry::OoRel;
use crate::quote::{excerpt, list};

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

pub(super) fn check_oo_rel(e: &mut EntryCtx<'_, '_>, rel: &OoRel, counts: &Counts) {
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
        let limits = list(
            reported
                .iter()
                .filter_map(|c| counts.max(c).ok().flatten().map(|m| (c, m))),
            ", ",
            |(c, m)| format!("{} at most {m}", excerpt(c)),
        );
        e.push(
            FindingCode::RelationshipExceedsCount,
            format!(
                "`{}` needs at least {need} distinct group(s) of objects, but the object counts \
                 allow at most {max} ({})",
                rel.count, limits
            ),
            None,
        );
    }
}
#[cfg(test)]
mod tests {
    use super::super::test_support::{codes, row};
    use super::*;

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
}
