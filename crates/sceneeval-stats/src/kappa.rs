//! Agreement between raters beyond chance: Cohen's kappa of two raters ([`Confusion`]) and
//! Fleiss' kappa of several ([`FleissTable`]).
//!
//! Both are computed from exact integer sums and one division at the end, so that perfect
//! agreement is exactly 1, kappa never leaves [-1, 1] by rounding, and kappa is undefined
//! exactly when chance agreement is exactly 1 ([`Undefined::OneClass`]), never through a
//! rounded comparison.

use serde::{Deserialize, Serialize};

use crate::{StatsError, Undefined};

/// The confusion counts of two raters over the same items: `count(i, j)` items that the first
/// rater put in category `i` and the second in category `j`. Categories are indices
/// `0..categories`; for binary verdicts ([`Confusion::binary`]) category 0 is `false` and 1 is
/// `true`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Confusion {
    categories: usize,
    /// Row-major: `counts[i * categories + j]`.
    counts: Vec<u64>,
}

impl Confusion {
    /// An empty table of `categories` categories.
    #[must_use]
    pub fn new(categories: usize) -> Self {
        Self {
            categories,
            counts: vec![0; categories * categories],
        }
    }

    /// The table of items given as (first rater's category, second rater's category).
    ///
    /// # Errors
    /// [`StatsError::Category`] for a category index not below `categories`, naming the item.
    pub fn from_pairs(
        categories: usize,
        pairs: impl IntoIterator<Item = (usize, usize)>,
    ) -> Result<Self, StatsError> {
        let mut table = Self::new(categories);
        for (item, (a, b)) in pairs.into_iter().enumerate() {
            for category in [a, b] {
                if category >= categories {
                    return Err(StatsError::Category {
                        item,
                        category,
                        categories,
                    });
                }
            }
            table.counts[a * categories + b] += 1;
        }
        Ok(table)
    }

    /// The 2 x 2 table of binary verdicts (first rater's, second rater's): category 0 is
    /// `false`, 1 is `true`.
    #[must_use]
    pub fn binary(pairs: impl IntoIterator<Item = (bool, bool)>) -> Self {
        let mut table = Self::new(2);
        for (a, b) in pairs {
            table.counts[usize::from(a) * 2 + usize::from(b)] += 1;
        }
        table
    }

    /// The number of categories.
    #[must_use]
    pub fn categories(&self) -> usize {
        self.categories
    }

    /// Items the first rater put in category `a` and the second in `b` (0 past the table).
    #[must_use]
    pub fn count(&self, a: usize, b: usize) -> u64 {
        if a < self.categories && b < self.categories {
            self.counts[a * self.categories + b]
        } else {
            0
        }
    }

    /// The counts row by row (first rater's category), `categories` rows of `categories`.
    pub fn rows(&self) -> impl Iterator<Item = &[u64]> {
        self.counts.chunks(self.categories.max(1))
    }

    /// The number of items.
    #[must_use]
    pub fn n(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// Items both raters put in the same category.
    #[must_use]
    pub fn agreed(&self) -> u64 {
        (0..self.categories).map(|i| self.count(i, i)).sum()
    }

    /// Observed agreement `p_o`: the fraction of items both raters put in the same category.
    /// `None` without items.
    #[must_use]
    pub fn agreement(&self) -> Option<f64> {
        let n = self.n();
        (n > 0).then(|| self.agreed() as f64 / n as f64)
    }

    /// Chance agreement `p_e = sum_i (row_i / n) (column_i / n)`: the agreement of two raters
    /// who keep their own class frequencies but rate independently. `None` without items.
    #[must_use]
    pub fn expected_agreement(&self) -> Option<f64> {
        let n = u128::from(self.n());
        (n > 0).then(|| self.chance_numerator() as f64 / (n * n) as f64)
    }

    /// `sum_i row_i * column_i` (chance agreement times n²).
    fn chance_numerator(&self) -> u128 {
        (0..self.categories)
            .map(|i| {
                let row: u64 = (0..self.categories).map(|j| self.count(i, j)).sum();
                let column: u64 = (0..self.categories).map(|j| self.count(j, i)).sum();
                u128::from(row) * u128::from(column)
            })
            .sum()
    }

    /// Cohen's kappa, `(p_o - p_e) / (1 - p_e)`, computed as
    /// `(n * agreed - sum_i row_i column_i) / (n² - sum_i row_i column_i)` in exact integers and
    /// one division (so perfect agreement is exactly 1). Equal to scikit-learn's
    /// `cohen_kappa_score(a, b)` (unweighted) wherever that is defined; two raters who always
    /// disagree with one class each (one all `true`, the other all `false`) have `p_o = p_e = 0`
    /// and kappa 0.
    ///
    /// # Errors
    /// [`Undefined::NoItems`] without items; [`Undefined::OneClass`] when `p_e` is 1, i.e. both
    /// raters used one and the same class for every item (scikit-learn returns NaN there).
    ///
    /// ```
    /// use sceneeval_stats::{Confusion, Undefined};
    /// // 4 items: agree on 3 (2 true, 1 false), disagree on 1.
    /// let t = Confusion::binary([(true, true), (true, true), (false, false), (true, false)]);
    /// // p_o = 3/4; rows (first rater) false 1, true 3; columns false 2, true 2;
    /// // p_e = (1*2 + 3*2) / 16 = 1/2; kappa = (3/4 - 1/2) / (1 - 1/2) = 1/2.
    /// assert_eq!(t.kappa(), Ok(0.5));
    /// assert_eq!(Confusion::binary([(true, true); 5]).kappa(), Err(Undefined::OneClass));
    /// ```
    pub fn kappa(&self) -> Result<f64, Undefined> {
        let n = u128::from(self.n());
        if n == 0 {
            return Err(Undefined::NoItems);
        }
        let chance = self.chance_numerator();
        let denominator = n * n - chance;
        if denominator == 0 {
            return Err(Undefined::OneClass);
        }
        // n * agreed and chance are both at most n² < 2^128; their difference has either sign.
        let agreed = n * u128::from(self.agreed());
        let numerator = if agreed >= chance {
            (agreed - chance) as f64
        } else {
            -((chance - agreed) as f64)
        };
        Ok(numerator / denominator as f64)
    }
}

/// The ratings of several raters on the same items, for Fleiss' kappa: per item the number of
/// raters who chose each category. Every item has the same number of ratings (the raters who
/// judged every item). Only the sums Fleiss' kappa needs are kept.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FleissTable {
    items: u64,
    raters: u64,
    /// Ratings per category over all items.
    totals: Vec<u64>,
    /// `sum over items and categories of n_ij (n_ij - 1)`: agreeing ordered pairs of ratings.
    agreeing_pairs: u64,
}

/// Ratings beyond which the exact arithmetic of [`FleissTable`] could overflow `i128`.
const FLEISS_MAX_RATINGS: u64 = 1 << 31;

impl FleissTable {
    /// The table from per-item category counts (items x categories, as statsmodels'
    /// `fleiss_kappa(table)` takes it).
    ///
    /// # Errors
    /// [`StatsError::UnequalCategories`] or [`StatsError::UnequalRaters`] naming the first item
    /// whose row differs from item 0 in length or sum; [`StatsError::TooLarge`] beyond 2^31
    /// ratings in all.
    pub fn from_counts<R: AsRef<[u64]>>(rows: &[R]) -> Result<Self, StatsError> {
        let categories = rows.first().map_or(0, |r| r.as_ref().len());
        let raters: u64 = rows.first().map_or(0, |r| r.as_ref().iter().sum());
        let mut totals = vec![0u64; categories];
        let mut agreeing_pairs = 0u64;
        let mut all = 0u64;
        let too_large = StatsError::TooLarge {
            what: "Fleiss' kappa",
        };
        for (item, row) in rows.iter().enumerate() {
            let row = row.as_ref();
            if row.len() != categories {
                return Err(StatsError::UnequalCategories {
                    item,
                    found: row.len(),
                    expected: categories,
                });
            }
            let ratings = row
                .iter()
                .try_fold(0u64, |sum, &c| sum.checked_add(c))
                .ok_or(too_large.clone())?;
            if ratings != raters {
                return Err(StatsError::UnequalRaters {
                    item,
                    ratings,
                    expected: raters,
                });
            }
            all += ratings;
            if all > FLEISS_MAX_RATINGS {
                return Err(too_large);
            }
            // Every count is at most 2^31, so these sums stay below 2^62.
            for (total, &c) in totals.iter_mut().zip(row) {
                *total += c;
                agreeing_pairs += c * c.saturating_sub(1);
            }
        }
        Ok(Self {
            items: rows.len() as u64,
            raters,
            totals,
            agreeing_pairs,
        })
    }

    /// The table of items rated with category indices: `ratings[item]` lists each rater's
    /// category for that item (the same number of raters on every item).
    ///
    /// # Errors
    /// [`StatsError::Category`] for an index not below `categories`, otherwise as
    /// [`FleissTable::from_counts`].
    pub fn from_ratings<R: AsRef<[usize]>>(categories: usize, ratings: &[R]) -> Result<Self, StatsError> {
        let rows = ratings
            .iter()
            .enumerate()
            .map(|(item, r)| {
                let mut row = vec![0u64; categories];
                for &category in r.as_ref() {
                    *row.get_mut(category).ok_or(StatsError::Category {
                        item,
                        category,
                        categories,
                    })? += 1;
                }
                Ok(row)
            })
            .collect::<Result<Vec<_>, StatsError>>()?;
        Self::from_counts(&rows)
    }

    /// The number of items.
    #[must_use]
    pub fn items(&self) -> u64 {
        self.items
    }

    /// Ratings per item.
    #[must_use]
    pub fn raters(&self) -> u64 {
        self.raters
    }

    /// Ratings per category over all items.
    #[must_use]
    pub fn totals(&self) -> &[u64] {
        &self.totals
    }

    /// Mean observed agreement `P̄`: over items, the fraction of pairs of ratings of the item
    /// that agree. `None` without items or with fewer than two raters.
    #[must_use]
    pub fn agreement(&self) -> Option<f64> {
        let pairs = self.items * self.raters * self.raters.saturating_sub(1);
        (pairs > 0).then(|| self.agreeing_pairs as f64 / pairs as f64)
    }

    /// Chance agreement `P_e = sum_j p_j²`, `p_j` the share of all ratings in category `j`.
    /// `None` without ratings.
    #[must_use]
    pub fn expected_agreement(&self) -> Option<f64> {
        let ratings = u128::from(self.items * self.raters);
        (ratings > 0).then(|| self.sum_squared_totals() as f64 / (ratings * ratings) as f64)
    }

    fn sum_squared_totals(&self) -> u128 {
        self.totals.iter().map(|&t| u128::from(t) * u128::from(t)).sum()
    }

    /// Fleiss' kappa, `(P̄ - P_e) / (1 - P_e)`, equal to statsmodels'
    /// `fleiss_kappa(table, method='fleiss')`. With `M = items * raters`, `A` the agreeing
    /// pairs and `C = sum_j total_j²` it is `(A M - C (r - 1)) / ((r - 1)(M² - C))`, evaluated
    /// in exact integers and one division.
    ///
    /// # Errors
    /// [`Undefined::NoItems`] without items; [`Undefined::TooFewRaters`] with fewer than two
    /// ratings per item; [`Undefined::OneClass`] when every rating is the same category
    /// (`P_e` = 1).
    ///
    /// ```
    /// use sceneeval_stats::FleissTable;
    /// // 2 items, 3 raters: [3, 0] and [1, 2] (ratings per category).
    /// let t = FleissTable::from_counts(&[[3u64, 0], [1, 2]]).unwrap();
    /// // P̄ = (6/6 + 2/6) / 2 = 2/3; p = (4/6, 2/6), P_e = 5/9; kappa = (2/3 - 5/9) / (4/9) = 1/4.
    /// assert_eq!(t.kappa(), Ok(0.25));
    /// ```
    pub fn kappa(&self) -> Result<f64, Undefined> {
        if self.items == 0 {
            return Err(Undefined::NoItems);
        }
        if self.raters < 2 {
            return Err(Undefined::TooFewRaters);
        }
        // Below 2^31 ratings in all (checked when built): M² < 2^62, A M < 2^93, C (r-1) < 2^93.
        let m = i128::from(self.items * self.raters);
        let r1 = i128::from(self.raters - 1);
        let c = self.sum_squared_totals() as i128;
        let denominator = r1 * (m * m - c);
        if denominator == 0 {
            return Err(Undefined::OneClass);
        }
        let numerator = i128::from(self.agreeing_pairs) * m - c * r1;
        Ok(numerator as f64 / denominator as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cohen_by_hand() {
        // Perfect agreement with both classes: 1.
        let perfect = Confusion::binary([(true, true), (false, false), (true, true)]);
        assert_eq!(perfect.kappa(), Ok(1.0));
        assert_eq!(perfect.agreement(), Some(1.0));
        // Chance: rows (6 true, 4 false), columns (5, 5), agreed 3 + 2 = 5 of 10:
        // p_o = 0.5, p_e = (6*5 + 4*5)/100 = 0.5, kappa 0.
        let mut pairs = vec![(true, true); 3];
        pairs.extend([(true, false); 3]);
        pairs.extend([(false, true); 2]);
        pairs.extend([(false, false); 2]);
        let chance = Confusion::binary(pairs);
        assert_eq!(chance.agreement(), Some(0.5));
        assert_eq!(chance.expected_agreement(), Some(0.5));
        assert_eq!(chance.kappa(), Ok(0.0));
        // Complete disagreement, balanced: p_o 0, p_e 0.5, kappa -1.
        let opposite = Confusion::binary([(true, false), (false, true)]);
        assert_eq!(opposite.kappa(), Ok(-1.0));
        // One rater all true, the other all false: p_o = p_e = 0, kappa 0 (scikit-learn's 0).
        let split = Confusion::binary([(true, false); 4]);
        assert_eq!(split.expected_agreement(), Some(0.0));
        assert_eq!(split.kappa(), Ok(0.0));
        // One class on both sides: undefined; no items: undefined.
        assert_eq!(
            Confusion::binary([(false, false); 3]).kappa(),
            Err(Undefined::OneClass)
        );
        assert_eq!(Confusion::binary([]).kappa(), Err(Undefined::NoItems));
        assert_eq!(Confusion::binary([]).agreement(), None);
        // The paper's kind of case: 20 items, 12 agree true, 4 agree false, 3 true/false,
        // 1 false/true. Rows 15, 5; columns 13, 7; p_o = 16/20; p_e = (15*13 + 5*7)/400 =
        // 230/400; kappa = (320 - 230) / (400 - 230) = 90/170.
        let mut pairs = vec![(true, true); 12];
        pairs.extend([(false, false); 4]);
        pairs.extend([(true, false); 3]);
        pairs.push((false, true));
        assert_eq!(Confusion::binary(pairs).kappa(), Ok(90.0 / 170.0));
    }

    #[test]
    fn cohen_nominal_and_errors() {
        // Three categories: a = [0,1,2,0], b = [0,1,1,2]; agreed 2 of 4; rows (2,1,1),
        // columns (1,2,1); chance numerator 2*1 + 1*2 + 1*1 = 5; kappa = (4*2 - 5)/(16 - 5).
        let t = Confusion::from_pairs(3, [(0, 0), (1, 1), (2, 1), (0, 2)]).unwrap();
        assert_eq!(t.kappa(), Ok(3.0 / 11.0));
        assert_eq!(t.count(2, 1), 1);
        assert_eq!(t.count(5, 1), 0);
        assert_eq!(
            t.rows().map(<[u64]>::to_vec).collect::<Vec<_>>()[0],
            vec![1, 0, 1]
        );
        let err = Confusion::from_pairs(2, [(0, 0), (0, 2)]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "item 1 has category 2, but there are only 2 categories"
        );
    }

    #[test]
    fn fleiss_by_hand() {
        // 3 items x 2 categories, 4 raters: [4,0], [2,2], [1,3].
        // Agreeing ordered pairs: 12 + (2+2) + (0+6) = 22 of 3 * 4 * 3 = 36: P̄ = 22/36.
        // Totals 7, 5 of 12: P_e = (49 + 25)/144 = 74/144.
        // kappa = (22/36 - 74/144) / (70/144) = (88 - 74) / 70 = 0.2.
        let t = FleissTable::from_counts(&[[4u64, 0], [2, 2], [1, 3]]).unwrap();
        assert_eq!(t.agreement(), Some(22.0 / 36.0));
        assert_eq!(t.expected_agreement(), Some(74.0 / 144.0));
        assert_eq!(t.kappa(), Ok(14.0 / 70.0));
        assert_eq!(t.totals(), &[7, 5]);
        // The same from each rater's labels.
        let by_labels = FleissTable::from_ratings(2, &[[0, 0, 0, 0], [0, 1, 0, 1], [1, 1, 0, 1]]).unwrap();
        assert_eq!(by_labels, t);
        // Perfect agreement on both classes: 1. One category only: undefined.
        assert_eq!(
            FleissTable::from_counts(&[[3u64, 0], [0, 3]]).unwrap().kappa(),
            Ok(1.0)
        );
        assert_eq!(
            FleissTable::from_counts(&[[3u64, 0], [3, 0]]).unwrap().kappa(),
            Err(Undefined::OneClass)
        );
        assert_eq!(
            FleissTable::from_counts(&[[1u64, 0], [0, 1]]).unwrap().kappa(),
            Err(Undefined::TooFewRaters)
        );
        let empty: [[u64; 2]; 0] = [];
        assert_eq!(
            FleissTable::from_counts(&empty).unwrap().kappa(),
            Err(Undefined::NoItems)
        );
    }

    #[test]
    fn fleiss_rejects_uneven_tables() {
        let err = FleissTable::from_counts(&[vec![2u64, 1], vec![1, 1]]).unwrap_err();
        assert_eq!(
            err,
            StatsError::UnequalRaters {
                item: 1,
                ratings: 2,
                expected: 3
            }
        );
        assert!(err.to_string().contains("item 1 has 2 ratings but item 0 has 3"));
        let err = FleissTable::from_counts(&[vec![2u64, 1], vec![1, 1, 1]]).unwrap_err();
        assert!(matches!(err, StatsError::UnequalCategories { item: 1, .. }));
        let err = FleissTable::from_ratings(2, &[[0, 2]]).unwrap_err();
        assert!(matches!(err, StatsError::Category { category: 2, .. }));
        let err = FleissTable::from_counts(&[[1u64 << 30, 1 << 30], [1 << 30, 1 << 30]]);
        assert!(matches!(err, Err(StatsError::TooLarge { .. })));
    }
}
