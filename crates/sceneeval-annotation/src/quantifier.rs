//! Quantifiers (`eq, lt, gt, le, ge`), the count an entry asks for, and the range of counts
//! that satisfies it.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::AnnotationError;

/// How an observed count is compared with an entry's quantity.
///
/// The five quantifiers of the paper's appendix "Annotation Schema": `eq` (=), `lt` (<),
/// `gt` (>), `le` (≤), `ge` (≥). The text form is lower case; anything else is an unknown
/// quantifier (the reference then silently reuses the previous entry's result, Q18; here it is
/// a validation finding).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantifier {
    /// Exactly `quantity`.
    Eq,
    /// Fewer than `quantity`.
    Lt,
    /// More than `quantity`.
    Gt,
    /// At most `quantity`.
    Le,
    /// At least `quantity`.
    Ge,
}

impl Quantifier {
    /// All quantifiers, in the paper's order.
    pub const ALL: [Quantifier; 5] = [
        Quantifier::Eq,
        Quantifier::Lt,
        Quantifier::Gt,
        Quantifier::Le,
        Quantifier::Ge,
    ];

    /// Does `count (op) quantity` hold? E.g. `Quantifier::Ge.holds(3, 2)` is `3 >= 2`.
    pub fn holds(self, count: u64, quantity: u64) -> bool {
        match self {
            Quantifier::Eq => count == quantity,
            Quantifier::Lt => count < quantity,
            Quantifier::Gt => count > quantity,
            Quantifier::Le => count <= quantity,
            Quantifier::Ge => count >= quantity,
        }
    }

    /// The text form: `eq`, `lt`, `gt`, `le` or `ge`.
    pub fn as_str(self) -> &'static str {
        match self {
            Quantifier::Eq => "eq",
            Quantifier::Lt => "lt",
            Quantifier::Gt => "gt",
            Quantifier::Le => "le",
            Quantifier::Ge => "ge",
        }
    }

    /// The quantifier meant by a common misspelling (`EQ`, `==`, `>=`, `gte`, ...), for
    /// suggestions in validation messages.
    pub fn suggest(text: &str) -> Option<Quantifier> {
        let t = text.trim().to_ascii_lowercase();
        match t.as_str() {
            "eq" | "=" | "==" | "equal" | "equals" | "exactly" => Some(Quantifier::Eq),
            "lt" | "<" | "less" | "less_than" | "fewer_than" => Some(Quantifier::Lt),
            "gt" | ">" | "more" | "more_than" | "greater_than" => Some(Quantifier::Gt),
            "le" | "<=" | "lte" | "at_most" => Some(Quantifier::Le),
            "ge" | ">=" | "gte" | "at_least" => Some(Quantifier::Ge),
            _ => None,
        }
    }
}

impl fmt::Display for Quantifier {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Quantifier {
    type Err = AnnotationError;

    /// Parses exactly `eq`, `lt`, `gt`, `le` or `ge` (after trimming spaces); no other
    /// spelling, so that a file the reference would misread is reported, not silently fixed.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "eq" => Ok(Quantifier::Eq),
            "lt" => Ok(Quantifier::Lt),
            "gt" => Ok(Quantifier::Gt),
            "le" => Ok(Quantifier::Le),
            "ge" => Ok(Quantifier::Ge),
            other => Err(AnnotationError::UnknownQuantifier {
                text: other.to_owned(),
            }),
        }
    }
}

/// The quantifier and quantity at the start of every entry: "how many".
///
/// For an object count entry it bounds the number of objects of the category; for the other
/// fields it bounds the number of objects (or object groups) that satisfy the attribute or
/// relationship.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct CountSpec {
    /// The comparison.
    pub quantifier: Quantifier,
    /// The non-negative integer compared against.
    pub quantity: u64,
}

impl CountSpec {
    /// A count spec from its parts.
    pub fn new(quantifier: Quantifier, quantity: u64) -> Self {
        CountSpec { quantifier, quantity }
    }

    /// `eq,n`: exactly `n`.
    pub fn exactly(n: u64) -> Self {
        CountSpec::new(Quantifier::Eq, n)
    }

    /// `ge,n`: at least `n`.
    pub fn at_least(n: u64) -> Self {
        CountSpec::new(Quantifier::Ge, n)
    }

    /// `gt,n`: more than `n`.
    pub fn more_than(n: u64) -> Self {
        CountSpec::new(Quantifier::Gt, n)
    }

    /// `le,n`: at most `n`.
    pub fn at_most(n: u64) -> Self {
        CountSpec::new(Quantifier::Le, n)
    }

    /// `lt,n`: fewer than `n`.
    pub fn fewer_than(n: u64) -> Self {
        CountSpec::new(Quantifier::Lt, n)
    }

    /// Does an observed `count` satisfy this spec?
    pub fn holds(&self, count: u64) -> bool {
        self.quantifier.holds(count, self.quantity)
    }

    /// The counts that satisfy this spec, as an inclusive range (empty for `lt,0`).
    pub fn allowed(&self) -> CountRange {
        let n = self.quantity;
        match self.quantifier {
            Quantifier::Eq => CountRange::between(n, n),
            Quantifier::Le => CountRange::between(0, n),
            Quantifier::Lt => match n.checked_sub(1) {
                Some(max) => CountRange::between(0, max),
                None => CountRange::EMPTY,
            },
            Quantifier::Ge => CountRange::at_least(n),
            Quantifier::Gt => match n.checked_add(1) {
                Some(min) => CountRange::at_least(min),
                None => CountRange::EMPTY,
            },
        }
    }

    /// The count a description "names" with this spec, used for the "objects specified"
    /// statistic: the allowed count closest to the quantity (`eq`/`le`/`ge` n give n, `gt` n
    /// gives n+1, `lt` n gives n-1, and `lt,0`, which nothing satisfies, gives 0).
    pub fn nominal(&self) -> u64 {
        match self.quantifier {
            Quantifier::Eq | Quantifier::Le | Quantifier::Ge => self.quantity,
            Quantifier::Gt => self.quantity.saturating_add(1),
            Quantifier::Lt => self.quantity.saturating_sub(1),
        }
    }
}

impl fmt::Display for CountSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.quantifier, self.quantity)
    }
}

/// An inclusive range of counts `min..=max` (`max` `None`: unbounded). Empty when
/// `min > max`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct CountRange {
    /// The smallest allowed count.
    pub min: u64,
    /// The largest allowed count, `None` for no upper bound.
    pub max: Option<u64>,
}

impl CountRange {
    /// The empty range (no count allowed).
    pub const EMPTY: CountRange = CountRange { min: 1, max: Some(0) };
    /// Every count.
    pub const ANY: CountRange = CountRange { min: 0, max: None };

    /// `min..=max`.
    pub fn between(min: u64, max: u64) -> Self {
        CountRange { min, max: Some(max) }
    }

    /// `min..`.
    pub fn at_least(min: u64) -> Self {
        CountRange { min, max: None }
    }

    /// Does the range contain no count?
    pub fn is_empty(&self) -> bool {
        self.max.is_some_and(|max| self.min > max)
    }

    /// Is `count` in the range?
    pub fn contains(&self, count: u64) -> bool {
        count >= self.min && self.max.is_none_or(|max| count <= max)
    }

    /// The counts allowed by both ranges.
    pub fn intersect(&self, other: &CountRange) -> CountRange {
        let min = self.min.max(other.min);
        let max = match (self.max, other.max) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, None) => a,
            (None, b) => b,
        };
        CountRange { min, max }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every quantifier at n-1, n, n+1 for n = 3 (and at the 0 boundary).
    #[test]
    fn holds_at_the_boundaries() {
        let n = 3;
        let table = [
            // (quantifier, [count n-1, n, n+1])
            (Quantifier::Eq, [false, true, false]),
            (Quantifier::Lt, [true, false, false]),
            (Quantifier::Gt, [false, false, true]),
            (Quantifier::Le, [true, true, false]),
            (Quantifier::Ge, [false, true, true]),
        ];
        for (q, expected) in table {
            for (count, want) in [n - 1, n, n + 1].into_iter().zip(expected) {
                assert_eq!(q.holds(count, n), want, "{q} count {count} quantity {n}");
                assert_eq!(CountSpec::new(q, n).holds(count), want);
                assert_eq!(CountSpec::new(q, n).allowed().contains(count), want);
            }
        }
        // Quantity 0: eq,0 holds only for 0 (an explicitly absent object); lt,0 never holds.
        assert!(Quantifier::Eq.holds(0, 0));
        assert!(!Quantifier::Eq.holds(1, 0));
        assert!(!Quantifier::Lt.holds(0, 0));
        assert!(Quantifier::Le.holds(0, 0));
        assert!(Quantifier::Ge.holds(0, 0));
        assert!(!Quantifier::Gt.holds(0, 0));
    }

    #[test]
    fn allowed_ranges() {
        assert_eq!(CountSpec::exactly(2).allowed(), CountRange::between(2, 2));
        assert_eq!(CountSpec::fewer_than(2).allowed(), CountRange::between(0, 1));
        assert_eq!(CountSpec::at_most(2).allowed(), CountRange::between(0, 2));
        assert_eq!(CountSpec::more_than(2).allowed(), CountRange::at_least(3));
        assert_eq!(CountSpec::at_least(2).allowed(), CountRange::at_least(2));
        assert!(CountSpec::fewer_than(0).allowed().is_empty());
        assert!(CountSpec::more_than(u64::MAX).allowed().is_empty());
        assert!(!CountRange::ANY.is_empty());
    }

    #[test]
    fn intersections() {
        // eq,0 and ge,1 contradict: [0,0] ∩ [1,∞) = empty.
        let r = CountSpec::exactly(0)
            .allowed()
            .intersect(&CountSpec::at_least(1).allowed());
        assert!(r.is_empty());
        // ge,1 and le,3: [1,3].
        let r = CountSpec::at_least(1)
            .allowed()
            .intersect(&CountSpec::at_most(3).allowed());
        assert_eq!(r, CountRange::between(1, 3));
        // gt,1 and ge,4: [4,∞).
        let r = CountSpec::more_than(1)
            .allowed()
            .intersect(&CountSpec::at_least(4).allowed());
        assert_eq!(r, CountRange::at_least(4));
    }

    #[test]
    fn nominal_counts() {
        assert_eq!(CountSpec::exactly(2).nominal(), 2);
        assert_eq!(CountSpec::exactly(0).nominal(), 0);
        assert_eq!(CountSpec::at_least(2).nominal(), 2);
        assert_eq!(CountSpec::more_than(1).nominal(), 2);
        assert_eq!(CountSpec::at_most(3).nominal(), 3);
        assert_eq!(CountSpec::fewer_than(3).nominal(), 2);
        assert_eq!(CountSpec::fewer_than(0).nominal(), 0);
    }

    #[test]
    fn text_forms() {
        for q in Quantifier::ALL {
            assert_eq!(q.as_str().parse::<Quantifier>().unwrap(), q);
            assert_eq!(Quantifier::suggest(&q.as_str().to_uppercase()), Some(q));
        }
        assert!("EQ".parse::<Quantifier>().is_err());
        assert!("=".parse::<Quantifier>().is_err());
        assert_eq!(Quantifier::suggest(">="), Some(Quantifier::Ge));
        assert_eq!(Quantifier::suggest("about"), None);
        assert_eq!(CountSpec::more_than(2).to_string(), "gt,2");
    }
}
