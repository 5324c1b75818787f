//! McNemar's exact test of paired binary outcomes.

use serde::{Deserialize, Serialize};

use crate::special::binomial_half_cdf;

/// McNemar's exact test on a paired 2 x 2 table `[[a, b], [c, d]]` (rows: the first run's
/// verdict true, false; columns: the second run's): only the discordant counts `b` (true, then
/// false) and `c` (false, then true) matter. Under the null hypothesis each discordant item
/// goes either way with probability 1/2, so the two-sided p-value is
/// `min(1, 2 P(X <= min(b, c)))` for `X ~ Binomial(b + c, 1/2)`, equal to statsmodels'
/// `mcnemar([[a, b], [c, d]], exact=True).pvalue` (SciPy's `binom.cdf` there, this crate's
/// [`crate::special::binomial_half_cdf`] here: within 1e-12 relative down to about 1e-250, below
/// which SciPy's loses its digits and gives 0 under about 1e-267, while this one stays within
/// 1e-14 of the exact value down to 1e-300). Without discordant items the p-value is 1
/// (nothing speaks against the null), as statsmodels gives.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct McNemar {
    /// Items true in both.
    pub both: u64,
    /// Items true in the first, false in the second.
    pub b: u64,
    /// Items false in the first, true in the second.
    pub c: u64,
    /// Items false in both.
    pub neither: u64,
    /// `min(b, c)`, statsmodels' statistic.
    pub statistic: u64,
    /// The two-sided exact p-value.
    pub p: f64,
}

impl McNemar {
    /// The test from the discordant counts alone (`both` and `neither` are 0).
    ///
    /// ```
    /// use sceneeval_stats::McNemar;
    /// // b = 1, c = 5: P(X <= 1) = (1 + 6) / 64; p = 14 / 64.
    /// assert_eq!(McNemar::exact(1, 5).p, 14.0 / 64.0);
    /// ```
    #[must_use]
    pub fn exact(b: u64, c: u64) -> Self {
        Self::from_table([[0, b], [c, 0]])
    }

    /// The test on the table `[[a, b], [c, d]]`.
    #[must_use]
    pub fn from_table(table: [[u64; 2]; 2]) -> Self {
        let [[both, b], [c, neither]] = table;
        let statistic = b.min(c);
        let p = (2.0 * binomial_half_cdf(statistic, b.saturating_add(c))).min(1.0);
        Self {
            both,
            b,
            c,
            neither,
            statistic,
            p,
        }
    }

    /// The test on paired verdicts (first, second).
    #[must_use]
    pub fn from_pairs(pairs: impl IntoIterator<Item = (bool, bool)>) -> Self {
        let mut table = [[0u64; 2]; 2];
        for (first, second) in pairs {
            table[usize::from(!first)][usize::from(!second)] += 1;
        }
        Self::from_table(table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mcnemar_by_hand() {
        // b = 0, c = 6: P(X <= 0) = 1/64, p = 1/32.
        assert_eq!(McNemar::exact(0, 6).p, 1.0 / 32.0);
        assert_eq!(McNemar::exact(6, 0).p, 1.0 / 32.0);
        // b = 2, c = 8 (n = 10): P(X <= 2) = 56/1024, p = 112/1024.
        assert_eq!(McNemar::exact(2, 8).p, 112.0 / 1024.0);
        // Balanced and empty: 1.
        assert_eq!(McNemar::exact(4, 4).p, 1.0);
        assert_eq!(McNemar::exact(0, 0).p, 1.0);
        // From verdicts: 3 true/true, 1 true/false, 4 false/true, 2 false/false.
        let mut pairs = vec![(true, true); 3];
        pairs.push((true, false));
        pairs.extend([(false, true); 4]);
        pairs.extend([(false, false); 2]);
        let t = McNemar::from_pairs(pairs);
        assert_eq!((t.both, t.b, t.c, t.neither, t.statistic), (3, 1, 4, 2, 1));
        // n = 5: P(X <= 1) = 6/32, p = 12/32.
        assert_eq!(t.p, 12.0 / 32.0);
    }
}
