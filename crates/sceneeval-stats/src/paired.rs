//! Paired comparisons of two methods on the same items: the mean difference, its bootstrap
//! interval and the Wilcoxon signed-rank test, from one set of differences.

use crate::StatsError;
use crate::bootstrap::{Bootstrap, BootstrapInterval, check_finite};
use crate::wilcoxon::{Wilcoxon, wilcoxon};

/// What [`paired`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Paired {
    /// Pairs (items with a value on both sides).
    pub n: usize,
    /// The mean of `b - a` over the pairs; `None` without pairs.
    pub mean_difference: Option<f64>,
    /// The percentile bootstrap interval of that mean, items (pairs) resampled.
    pub interval: BootstrapInterval,
    /// The Wilcoxon signed-rank test of the differences.
    pub wilcoxon: Wilcoxon,
}

/// Compares `b` with `a` item by item (`a[i]` and `b[i]` are the same item): the differences
/// `b[i] - a[i]` (positive where `b` is higher), their mean (summed in item order), the
/// bootstrap interval of the mean ([`Bootstrap::mean`] of the differences: resampling pairs
/// is resampling their differences) and [`wilcoxon`] on them.
///
/// # Errors
/// [`StatsError::LengthMismatch`] when `a` and `b` differ in length; [`StatsError::NotFinite`]
/// for a NaN or infinite value (its index in `a`, or in `b` when `a`'s is finite).
///
/// ```
/// use sceneeval_stats::{Bootstrap, paired};
/// let a = [0.50, 0.40, 0.70, 0.20];
/// let b = [0.60, 0.55, 0.90, 0.25];
/// let r = paired(&a, &b, &Bootstrap::default()).unwrap();
/// assert_eq!(r.n, 4);
/// assert!((r.mean_difference.unwrap() - 0.125).abs() < 1e-12);
/// // All four differences positive and untied: exact p = 2 / 16.
/// assert_eq!(r.wilcoxon.p.value(), Ok(0.125));
/// ```
pub fn paired(a: &[f64], b: &[f64], bootstrap: &Bootstrap) -> Result<Paired, StatsError> {
    if a.len() != b.len() {
        return Err(StatsError::LengthMismatch {
            a: a.len(),
            b: b.len(),
        });
    }
    check_finite(a)?;
    check_finite(b)?;
    let differences: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let n = differences.len();
    let mean_difference = (n > 0).then(|| differences.iter().sum::<f64>() / n as f64);
    Ok(Paired {
        n,
        mean_difference,
        interval: bootstrap.mean(&differences)?,
        wilcoxon: wilcoxon(&differences)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Undefined;

    #[test]
    fn paired_by_hand() {
        let b = Bootstrap::default();
        // Identical runs: mean 0, interval [0, 0], no p-value (every difference is 0).
        let same = paired(&[0.3, 0.6], &[0.3, 0.6], &b).unwrap();
        assert_eq!(same.mean_difference, Some(0.0));
        assert_eq!(same.interval.bounds, Ok([0.0, 0.0]));
        assert_eq!(same.wilcoxon.zeros, 2);
        assert_eq!(same.wilcoxon.p.value(), Err(Undefined::TooFewDifferences));
        // Without pairs: nothing.
        let none = paired(&[], &[], &b).unwrap();
        assert_eq!((none.n, none.mean_difference), (0, None));
        assert_eq!(none.interval.bounds, Err(Undefined::NoItems));
        assert_eq!(
            paired(&[1.0], &[1.0, 2.0], &b).unwrap_err(),
            StatsError::LengthMismatch { a: 1, b: 2 }
        );
        assert!(matches!(
            paired(&[1.0, 2.0], &[1.0, f64::NAN], &b),
            Err(StatsError::NotFinite { index: 1, .. })
        ));
    }
}
