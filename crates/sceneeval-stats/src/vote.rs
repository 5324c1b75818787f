//! Majority votes over binary verdicts, with ties and missing votes kept apart.

use serde::{Deserialize, Serialize};

/// The votes on one item: each voter's `Option<bool>`, `None` (no verdict) ignored.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Majority {
    /// `true` votes.
    pub yes: usize,
    /// `false` votes.
    pub no: usize,
    /// Voters without a verdict.
    pub abstained: usize,
}

/// What a majority vote decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Decision {
    /// More votes for this verdict than for the other.
    Verdict(bool),
    /// As many `true` as `false` votes (at least one each).
    Tie,
    /// No verdict at all.
    NoVotes,
}

impl Majority {
    /// Counts the votes.
    ///
    /// ```
    /// use sceneeval_stats::{Decision, Majority};
    /// let votes = Majority::of([Some(true), None, Some(false), Some(true)]);
    /// assert_eq!(votes.decision(), Decision::Verdict(true));
    /// assert_eq!(Majority::of([Some(true), Some(false)]).verdict(), None); // a tie
    /// assert_eq!(Majority::of([Some(true), Some(false)]).decision(), Decision::Tie);
    /// assert_eq!(Majority::of([None, None]).decision(), Decision::NoVotes);
    /// ```
    pub fn of(votes: impl IntoIterator<Item = Option<bool>>) -> Self {
        let mut counts = Self::default();
        for vote in votes {
            match vote {
                Some(true) => counts.yes += 1,
                Some(false) => counts.no += 1,
                None => counts.abstained += 1,
            }
        }
        counts
    }

    /// The decision: the verdict with more votes, a tie, or no votes.
    #[must_use]
    pub fn decision(&self) -> Decision {
        match self.yes.cmp(&self.no) {
            std::cmp::Ordering::Greater => Decision::Verdict(true),
            std::cmp::Ordering::Less => Decision::Verdict(false),
            std::cmp::Ordering::Equal if self.yes == 0 => Decision::NoVotes,
            std::cmp::Ordering::Equal => Decision::Tie,
        }
    }

    /// The majority verdict; `None` for a tie or without votes ([`Majority::decision`] tells
    /// which).
    #[must_use]
    pub fn verdict(&self) -> Option<bool> {
        match self.decision() {
            Decision::Verdict(v) => Some(v),
            Decision::Tie | Decision::NoVotes => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn majorities() {
        let m = Majority::of([Some(false), Some(false), Some(true), None]);
        assert_eq!(
            m,
            Majority {
                yes: 1,
                no: 2,
                abstained: 1
            }
        );
        assert_eq!(m.verdict(), Some(false));
        assert_eq!(Majority::of([Some(true)]).verdict(), Some(true));
        let tie = Majority::of([Some(true), None, Some(false), Some(false), Some(true)]);
        assert_eq!(tie.decision(), Decision::Tie);
        assert_eq!(tie.verdict(), None);
        assert_eq!(Majority::of([]).decision(), Decision::NoVotes);
        assert_eq!(Majority::of([None]).verdict(), None);
    }
}
