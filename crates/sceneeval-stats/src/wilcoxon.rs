//! The two-sided Wilcoxon signed-rank test on paired differences.
//!
//! The rule (issue 37):
//!
//! 1. Each difference is rounded to 1e-9 ([`round_difference`]: `rint(d * 1e9) / 1e9`, ties to
//!    even, as NumPy's `np.round(d, 9)`), so that differences equal up to floating-point noise
//!    tie and differences that are zero up to noise are zero.
//! 2. Zero differences are dropped and counted (Wilcoxon's own treatment, SciPy's
//!    `zero_method='wilcox'`).
//! 3. The absolute values of the `n` others are ranked, ties sharing their average rank;
//!    `R+` and `R-` are the rank sums of the positive and negative differences, and the
//!    statistic is `min(R+, R-)`.
//! 4. With fewer than two of them there is no p-value ([`Undefined::TooFewDifferences`]).
//! 5. With at most 50 and no ties among their absolute values, the p-value is exact:
//!    `min(1, 2 min(P(T <= R+), P(T >= R+)))` under the null distribution of `T = R+` (every
//!    sign equally likely), whose counts are exact integers below 2^50, so the p-value is the
//!    exact dyadic rational (the one SciPy computes in floating point without rounding).
//! 6. Otherwise the normal approximation with tie and continuity correction:
//!    `z = (R+ - n(n+1)/4) / σ`, `σ = sqrt((n(n+1)(2n+1) - Σ(t³ - t)/2) / 24)` over groups of
//!    `t` tied absolute values, then `z -= sign(z) 0.5 / σ` and `p = 2 Φ(-|z|)`.
//!
//! This is SciPy's `scipy.stats.wilcoxon(np.round(d, 9), zero_method='wilcox',
//! correction=True, alternative='two-sided', method=M)` with `M = 'exact'` when the rule picks
//! the exact distribution and `M = 'asymptotic'` (formerly `'approx'`) otherwise, operation for
//! operation: the exact p-value and the statistic are bit-identical, the approximate p-value
//! differs only through `erfc` (musl's here, Cephes' there): bit-identical or a few units in
//! the last place apart. SciPy's `method='auto'` is a different rule (a
//! permutation test for small samples with ties or zeros).

use serde::{Deserialize, Serialize};

use crate::bootstrap::check_finite;
use crate::special::normal_cdf;
use crate::{StatsError, Undefined};

/// The largest number of non-zero differences for which the exact distribution is used.
pub const EXACT_MAX: usize = 50;

/// The p-value of a Wilcoxon test and the method that gave it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "method", rename_all = "snake_case")]
pub enum WilcoxonP {
    /// The exact null distribution (at most [`EXACT_MAX`] non-zero differences, no ties).
    Exact {
        /// The two-sided p-value.
        p: f64,
    },
    /// The normal approximation with tie and continuity correction.
    Normal {
        /// The corrected z statistic (its sign is that of `R+ - n(n+1)/4`).
        z: f64,
        /// The two-sided p-value.
        p: f64,
    },
    /// No p-value.
    Undefined {
        /// Why.
        reason: Undefined,
    },
}

impl WilcoxonP {
    /// The p-value, or why there is none.
    ///
    /// # Errors
    /// The reason when there is no p-value.
    pub fn value(&self) -> Result<f64, Undefined> {
        match *self {
            Self::Exact { p } | Self::Normal { p, .. } => Ok(p),
            Self::Undefined { reason } => Err(reason),
        }
    }

    /// The method's name: `exact`, `normal` or `none`.
    #[must_use]
    pub fn method(&self) -> &'static str {
        match self {
            Self::Exact { .. } => "exact",
            Self::Normal { .. } => "normal",
            Self::Undefined { .. } => "none",
        }
    }
}

/// The result of [`wilcoxon`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Wilcoxon {
    /// `min(R+, R-)` (SciPy's two-sided statistic); 0 without non-zero differences.
    pub statistic: f64,
    /// Rank sum of the positive differences.
    pub r_plus: f64,
    /// Rank sum of the negative differences.
    pub r_minus: f64,
    /// Non-zero differences used (after rounding).
    pub n: usize,
    /// Differences dropped as zero (after rounding).
    pub zeros: usize,
    /// Whether some non-zero absolute differences tie (after rounding).
    pub ties: bool,
    /// The p-value and its method.
    pub p: WilcoxonP,
}

/// A difference rounded to 1e-9 as NumPy's `np.round(d, 9)` rounds it: `rint(d * 1e9) / 1e9`
/// (ties to even). A difference so large that `d * 1e9` overflows is kept as it is.
#[must_use]
pub fn round_difference(d: f64) -> f64 {
    let scaled = d * 1e9;
    if scaled.is_finite() {
        scaled.round_ties_even() / 1e9
    } else {
        d
    }
}

/// The two-sided Wilcoxon signed-rank test of paired differences (`b - a` per item; the
/// module documentation states the rule).
///
/// # Errors
/// [`StatsError::NotFinite`] for a NaN or infinite difference.
///
/// ```
/// use sceneeval_stats::wilcoxon::{wilcoxon, WilcoxonP};
/// // Ranks of |d| = 1, 2, 3, 4; R+ = 2 + 3 + 4 = 9, R- = 1. Of the 16 sign patterns, R+ >= 9
/// // in 2 (9 and 10): p = 2 * 2/16 = 0.25.
/// let w = wilcoxon(&[-1.0, 2.0, 3.0, 4.0, 0.0]).unwrap();
/// assert_eq!((w.statistic, w.n, w.zeros), (1.0, 4, 1));
/// assert_eq!(w.p, WilcoxonP::Exact { p: 0.25 });
/// ```
pub fn wilcoxon(differences: &[f64]) -> Result<Wilcoxon, StatsError> {
    check_finite(differences)?;
    let rounded: Vec<f64> = differences.iter().map(|&d| round_difference(d)).collect();
    let nonzero: Vec<f64> = rounded.iter().copied().filter(|&d| d != 0.0).collect();
    let zeros = rounded.len() - nonzero.len();
    let n = nonzero.len();
    let ranked = Ranked::new(&nonzero);
    let statistic = ranked.r_plus.min(ranked.r_minus);
    let p = if n < 2 {
        WilcoxonP::Undefined {
            reason: Undefined::TooFewDifferences,
        }
    } else if n <= EXACT_MAX && ranked.tie_sum == 0.0 {
        WilcoxonP::Exact {
            p: exact_p(n, ranked.r_plus),
        }
    } else {
        normal_p(n, ranked.r_plus, ranked.tie_sum)
    };
    Ok(Wilcoxon {
        statistic,
        r_plus: ranked.r_plus,
        r_minus: ranked.r_minus,
        n,
        zeros,
        ties: ranked.tie_sum > 0.0,
        p,
    })
}

/// Average ranks of the absolute differences, summed by sign, and the tie term.
struct Ranked {
    r_plus: f64,
    r_minus: f64,
    /// `Σ (t³ - t)` over groups of `t` tied absolute values (0 without ties).
    tie_sum: f64,
}

impl Ranked {
    fn new(nonzero: &[f64]) -> Self {
        let mut order: Vec<(f64, bool)> = nonzero.iter().map(|&d| (d.abs(), d > 0.0)).collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut ranked = Self {
            r_plus: 0.0,
            r_minus: 0.0,
            tie_sum: 0.0,
        };
        let mut start = 0;
        while start < order.len() {
            let end = start + order[start..].partition_point(|x| x.0 == order[start].0);
            let t = (end - start) as f64;
            // Positions start+1 ..= end share their mean; ranks are halves, so sums are exact.
            let rank = (start + 1) as f64 + (t - 1.0) / 2.0;
            for &(_, positive) in &order[start..end] {
                if positive {
                    ranked.r_plus += rank;
                } else {
                    ranked.r_minus += rank;
                }
            }
            ranked.tie_sum += t * t * t - t;
            start = end;
        }
        ranked
    }
}

/// The null distribution of `R+` among `n` untied ranks as counts: `counts[s]` sign patterns
/// of the ranks 1..=n whose positive ranks sum to `s` (`2^n` patterns in all, so exact in `u64`
/// up to n = 63).
fn null_counts(n: usize) -> Vec<u64> {
    let mut counts = vec![0u64; n * (n + 1) / 2 + 1];
    counts[0] = 1;
    for k in 1..=n {
        for s in (k..=k * (k + 1) / 2).rev() {
            counts[s] += counts[s - k];
        }
    }
    counts
}

/// The exact two-sided p-value for `R+ = r_plus` among `n <= 50` untied ranks.
fn exact_p(n: usize, r_plus: f64) -> f64 {
    let counts = null_counts(n);
    // Without ties R+ is an integer in 0..=n(n+1)/2.
    let r = r_plus as usize;
    let below: u64 = counts[..=r].iter().sum();
    let above: u64 = counts[r..].iter().sum();
    let total = 2f64.powi(n as i32);
    (2.0 * (below.min(above) as f64 / total)).min(1.0)
}

/// The normal approximation with tie and continuity correction, as SciPy computes it.
fn normal_p(n: usize, r_plus: f64, tie_sum: f64) -> WilcoxonP {
    let count = n as f64;
    let mean = count * (count + 1.0) * 0.25;
    let variance = count * (count + 1.0) * (2.0 * count + 1.0);
    let se = ((variance - tie_sum / 2.0) / 24.0).sqrt();
    let z = (r_plus - mean) / se;
    // NumPy's sign: 0 at 0 (f64::signum would give 1).
    let sign = if z == 0.0 { 0.0 } else { z.signum() };
    let z = z - sign * 0.5 / se;
    WilcoxonP::Normal {
        z,
        p: 2.0 * normal_cdf(-z.abs()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_small_n_by_hand() {
        // n = 3, ranks 1, 2, 3: R+ takes 0,1,2,3,3,4,5,6 over the 8 sign patterns.
        // All positive: R+ = 6, P(T >= 6) = 1/8, p = 2/8.
        let w = wilcoxon(&[0.1, 0.2, 0.3]).unwrap();
        assert_eq!((w.r_plus, w.r_minus, w.statistic), (6.0, 0.0, 0.0));
        assert_eq!(w.p, WilcoxonP::Exact { p: 0.25 });
        // d = [-0.1, 0.2, 0.3]: R+ = 5, P(T >= 5) = 2/8 (5, 6), P(T <= 5) = 7/8: p = 0.5.
        let w = wilcoxon(&[-0.1, 0.2, 0.3]).unwrap();
        assert_eq!(w.p.value(), Ok(0.5));
        assert_eq!(w.statistic, 1.0);
        // R+ = 3 = the mean: P(T <= 3) = 5/8, P(T >= 3) = 5/8, 2 * 5/8 > 1: p = 1.
        let w = wilcoxon(&[-0.3, 0.1, 0.2]).unwrap();
        assert_eq!(w.r_plus, 3.0);
        assert_eq!(w.p.value(), Ok(1.0));
        // n = 2, both positive: P(T >= 3) = 1/4, p = 0.5.
        assert_eq!(wilcoxon(&[1.0, 2.0]).unwrap().p.value(), Ok(0.5));
        // n = 10, all positive: P(T = 55) = 2^-10, p = 2^-9.
        let d: Vec<f64> = (1..=10).map(f64::from).collect();
        assert_eq!(wilcoxon(&d).unwrap().p.value(), Ok(1.0 / 512.0));
    }

    #[test]
    fn distribution_counts_are_exact() {
        // The counts of n = 50 sum to 2^50 and are symmetric.
        let counts = null_counts(50);
        let max = 50 * 51 / 2;
        assert_eq!(counts.len(), max + 1);
        assert_eq!(counts.iter().sum::<u64>(), 1 << 50);
        assert!((0..=max).all(|s| counts[s] == counts[max - s]));
        // n = 3 by hand: R+ = 0, 1, 2, 3, 3, 4, 5, 6 over the 8 patterns.
        assert_eq!(null_counts(3), vec![1, 1, 1, 2, 1, 1, 1]);
        // All 50 positive: p = 2 / 2^50.
        let d: Vec<f64> = (1..=50).map(f64::from).collect();
        assert_eq!(wilcoxon(&d).unwrap().p.value(), Ok(2f64.powi(-49)));
    }

    #[test]
    fn ties_use_the_normal_approximation_by_hand() {
        // d = [1, 1, -2, 3]: |d| ranks 1.5, 1.5, 3, 4; R+ = 7, R- = 3; one tie group of 2.
        // mean = 4*5/4 = 5; σ² = (4*5*9 - (8 - 2)/2) / 24 = 177/24; z = 2/σ - 0.5/σ = 1.5/σ.
        let w = wilcoxon(&[1.0, 1.0, -2.0, 3.0]).unwrap();
        assert_eq!((w.r_plus, w.r_minus, w.statistic), (7.0, 3.0, 3.0));
        assert!(w.ties);
        let se = (177.0f64 / 24.0).sqrt();
        let WilcoxonP::Normal { z, p } = w.p else {
            panic!("ties must use the normal approximation: {:?}", w.p);
        };
        assert!((z - 1.5 / se).abs() < 1e-15);
        // z = 0.55234...; 2 Φ(-z) = 0.580712... (SciPy: 0.5807121621890252).
        assert!((p - 2.0 * normal_cdf(-1.5 / se)).abs() < 1e-15);
        assert!((p - 0.580_712_162_189_025_2).abs() < 1e-15, "{p}");
    }

    #[test]
    fn zeros_rounding_and_too_few() {
        // Differences that are zero up to noise are zeros; noise does not break ties.
        let noisy = [0.1 + 0.2 - 0.3, 1e-12, 0.5, 0.5 + 1e-13, -0.25];
        let w = wilcoxon(&noisy).unwrap();
        assert_eq!((w.n, w.zeros), (3, 2));
        assert!(w.ties, "0.5 and 0.5 + 1e-13 tie after rounding");
        // n = 1 and all zero: no p-value, with the reason.
        let one = wilcoxon(&[0.0, 3.0, 0.0]).unwrap();
        assert_eq!((one.n, one.zeros), (1, 2));
        assert_eq!(one.p.value(), Err(Undefined::TooFewDifferences));
        assert_eq!(one.p.method(), "none");
        let none = wilcoxon(&[0.0; 4]).unwrap();
        assert_eq!((none.n, none.zeros, none.statistic), (0, 4, 0.0));
        assert!(none.p.value().is_err());
        assert!(wilcoxon(&[]).unwrap().p.value().is_err());
        let err = wilcoxon(&[1.0, f64::INFINITY]).unwrap_err();
        assert!(matches!(err, StatsError::NotFinite { index: 1, .. }));
    }

    #[test]
    fn all_equal_differences() {
        // Five equal differences: all tie (rank 3 each), R+ = 15, mean 7.5,
        // σ² = (5*6*11 - (125 - 5)/2)/24 = 270/24; z = 7.5/σ - 0.5/σ.
        let w = wilcoxon(&[0.2; 5]).unwrap();
        assert_eq!((w.r_plus, w.statistic), (15.0, 0.0));
        let se = (270.0f64 / 24.0).sqrt();
        let z = 7.5 / se - 0.5 / se;
        let p = 2.0 * normal_cdf(-z);
        assert_eq!(w.p, WilcoxonP::Normal { z, p });
        assert_eq!(w.p.method(), "normal");
    }

    #[test]
    fn more_than_fifty_use_the_normal_approximation() {
        // 51 untied differences, all positive: R+ = 51*52/2 = 1326, mean 663,
        // σ² = 51*52*103/24, z = (663 - 0.5)/σ.
        let d: Vec<f64> = (1..=51).map(f64::from).collect();
        let w = wilcoxon(&d).unwrap();
        let se = (51.0f64 * 52.0 * 103.0 / 24.0).sqrt();
        assert_eq!(
            w.p,
            WilcoxonP::Normal {
                z: 663.0 / se - 0.5 / se,
                p: 2.0 * normal_cdf(-(663.0 / se - 0.5 / se))
            }
        );
    }

    #[test]
    fn rounding_is_numpys() {
        assert_eq!(round_difference(0.1 + 0.2 - 0.3), 0.0);
        assert_eq!(round_difference(2.5e-9), 2e-9); // ties to even
        assert_eq!(round_difference(-3.5e-9), -4e-9);
        assert_eq!(round_difference(1e300), 1e300);
    }
}
