//! Verdicts when an answer is missing: a spec whose verdict a missing answer could change has
//! no verdict (it is unanswered, left out of the score), never a silent "not satisfied".
//!
//! A missing answer widens what a count could be: objects without a matching answer could be
//! of any category (adding up to that many objects, instances or candidates), attributes
//! without a verdict could hold or not. The spec keeps its verdict when the quantifier gives
//! the same verdict for every count it could be ([`verdict_over`]).

use sceneeval_annotation::{CountRange, CountSpec};

/// The objects without a matching answer (the VLM gave no valid answer for them): any of them
/// could be of any annotated category.
#[derive(Debug, Clone, Copy)]
pub(super) struct Unknown<'a> {
    /// Their ids, sorted.
    pub ids: &'a [String],
}

impl Unknown<'_> {
    /// How many.
    pub fn count(&self) -> u64 {
        self.ids.len() as u64
    }

    /// Why a spec they could change has no verdict.
    pub fn reason(&self) -> String {
        format!(
            "{} object(s) without a matching answer ({}) could be of the spec's categories",
            self.ids.len(),
            self.ids.join(", ")
        )
    }
}

/// The verdict of `count` when the counted number can be anything in `possible`: `Some` when
/// every such number gives the same verdict.
///
/// ```text
/// eq,2 over 1..=3 -> None (2 holds, 1 and 3 do not); ge,2 over 2.. -> Some(true);
/// lt,1 over 1..=4 -> Some(false)
/// ```
pub(super) fn verdict_over(count: &CountSpec, possible: CountRange) -> Option<bool> {
    let both = count.allowed().intersect(&possible);
    if both.is_empty() {
        Some(false)
    } else if both == possible {
        Some(true)
    } else {
        None
    }
}

/// `Some(v)` when both verdicts are `Some(v)`: the verdict of a spec that could be in either
/// case.
pub(super) fn agree(a: Option<bool>, b: Option<bool>) -> Option<bool> {
    match (a, b) {
        (Some(x), Some(y)) if x == y => Some(x),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_annotation::Quantifier;

    #[test]
    fn verdicts_over_ranges() {
        let spec = |q, n| CountSpec::new(q, n);
        let between = CountRange::between;
        // eq,2: holds only at 2.
        assert_eq!(verdict_over(&spec(Quantifier::Eq, 2), between(2, 2)), Some(true));
        assert_eq!(verdict_over(&spec(Quantifier::Eq, 2), between(1, 3)), None);
        assert_eq!(verdict_over(&spec(Quantifier::Eq, 2), between(3, 5)), Some(false));
        assert_eq!(
            verdict_over(&spec(Quantifier::Eq, 2), CountRange::at_least(3)),
            Some(false)
        );
        assert_eq!(
            verdict_over(&spec(Quantifier::Eq, 2), CountRange::at_least(2)),
            None
        );
        // ge,2 over 2.. always holds; over 1.. it may not.
        assert_eq!(
            verdict_over(&spec(Quantifier::Ge, 2), CountRange::at_least(2)),
            Some(true)
        );
        assert_eq!(
            verdict_over(&spec(Quantifier::Ge, 2), CountRange::at_least(1)),
            None
        );
        // lt,1 (only 0) over 1..=4 never holds; eq,0 over 0..=0 holds.
        assert_eq!(verdict_over(&spec(Quantifier::Lt, 1), between(1, 4)), Some(false));
        assert_eq!(verdict_over(&spec(Quantifier::Eq, 0), between(0, 0)), Some(true));
        // lt,0 holds for nothing.
        assert_eq!(
            verdict_over(&spec(Quantifier::Lt, 0), CountRange::ANY),
            Some(false)
        );
        assert_eq!(agree(Some(true), Some(true)), Some(true));
        assert_eq!(agree(Some(true), Some(false)), None);
        assert_eq!(agree(None, Some(false)), None);
    }
}
