//! What can go wrong: input that is not valid ([`StatsError`]) and a statistic that does not
//! exist for valid input ([`Undefined`]).

use serde::{Deserialize, Serialize};

/// Input a statistic cannot be computed from: the caller's data or arguments are wrong. Each
/// variant names the offending position.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StatsError {
    /// A value is NaN or infinite.
    #[error("value {index} is not a finite number ({value})")]
    NotFinite {
        /// Its position in the input.
        index: usize,
        /// The value.
        value: f64,
    },
    /// Paired samples of different lengths.
    #[error("the paired samples differ in length ({a} and {b}): pairs need one value on each side")]
    LengthMismatch {
        /// Length of the first sample.
        a: usize,
        /// Length of the second sample.
        b: usize,
    },
    /// A category index past the number of categories.
    #[error("item {item} has category {category}, but there are only {categories} categories")]
    Category {
        /// The item's position.
        item: usize,
        /// Its category index.
        category: usize,
        /// The number of categories.
        categories: usize,
    },
    /// Fleiss' kappa needs the same number of ratings on every item.
    #[error(
        "item {item} has {ratings} ratings but item 0 has {expected}: Fleiss' kappa needs the same \
         number of raters on every item"
    )]
    UnequalRaters {
        /// The item's position.
        item: usize,
        /// Its number of ratings.
        ratings: u64,
        /// The first item's number of ratings.
        expected: u64,
    },
    /// Rows of a table with different numbers of categories.
    #[error("item {item} has {found} categories but item 0 has {expected}")]
    UnequalCategories {
        /// The item's position.
        item: usize,
        /// Its number of categories.
        found: usize,
        /// The first item's number of categories.
        expected: usize,
    },
    /// Counts too large for the exact integer arithmetic (more than 2^31 ratings in all).
    #[error("{what}: counts too large for exact arithmetic")]
    TooLarge {
        /// Which statistic.
        what: &'static str,
    },
    /// A confidence level outside (0, 1).
    #[error("confidence level {0} is not between 0 and 1 (exclusive)")]
    Level(f64),
    /// A bootstrap without resamples.
    #[error("a bootstrap needs at least one resample")]
    NoResamples,
    /// A p-value outside [0, 1] (or NaN).
    #[error("p-value {index} is {value}, not a probability in [0, 1]")]
    PValue {
        /// Its position in the input.
        index: usize,
        /// The value.
        value: f64,
    },
}

/// Why a statistic does not exist for valid input. A table shows it as an empty cell with this
/// reason; it is never replaced by a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, thiserror::Error)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Undefined {
    /// There is no item to compute it over.
    #[error("no items")]
    NoItems,
    /// Chance agreement is 1: both raters (Cohen) or all ratings (Fleiss) use one and the same
    /// class only, so agreement beyond chance is 0 / 0.
    #[error("one class only: every rating is the same class, so chance agreement is 1")]
    OneClass,
    /// Fewer than two ratings per item (Fleiss).
    #[error("fewer than two raters per item")]
    TooFewRaters,
    /// Fewer than two non-zero paired differences (Wilcoxon).
    #[error("fewer than two non-zero differences")]
    TooFewDifferences,
    /// Every bootstrap resample's statistic was undefined.
    #[error("the statistic is undefined on every bootstrap resample")]
    EveryResample,
}
