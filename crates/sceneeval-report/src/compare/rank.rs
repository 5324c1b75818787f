//! Competition ranking ("1224"): runs with equal values share the best rank, and the next rank
//! skips as many places as runs tied.

use sceneeval_results::Better;

/// The rank of each value (1 = best) among the values present, by competition ranking: a
/// value's rank is one more than the number of values strictly better than it. `None` where
/// the value is missing (not ranked).
///
/// ```
/// use sceneeval_results::Better;
/// use sceneeval_report::compare::competition_ranks;
/// // Higher is better: 90 first, the two 80s share second, 70 is fourth.
/// let ranks = competition_ranks(&[Some(80.0), Some(90.0), None, Some(80.0), Some(70.0)], Better::Higher);
/// assert_eq!(ranks, [Some(2), Some(1), None, Some(2), Some(4)]);
/// ```
pub fn competition_ranks(values: &[Option<f64>], better: Better) -> Vec<Option<usize>> {
    values
        .iter()
        .map(|v| {
            let v = (*v)?;
            let ahead = values.iter().flatten().filter(|&&w| better.prefers(w, v)).count();
            Some(ahead + 1)
        })
        .collect()
}

/// A value as it is printed, two decimals, read back: ranks compare what a reader sees, so two
/// values printed alike tie.
pub(crate) fn as_printed(v: f64) -> f64 {
    format!("{v:.2}").parse().unwrap_or(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ties_share_the_best_rank_and_lower_can_be_better() {
        // Lower is better: 0 first, the two 5s share second, 10 is fourth.
        let r = competition_ranks(&[Some(5.0), Some(10.0), Some(0.0), Some(5.0)], Better::Lower);
        assert_eq!(r, [Some(2), Some(4), Some(1), Some(2)]);
        // Everyone tied: everyone first.
        let r = competition_ranks(&[Some(1.0), Some(1.0)], Better::Higher);
        assert_eq!(r, [Some(1), Some(1)]);
        assert_eq!(competition_ranks(&[None, None], Better::Higher), [None, None]);
        // Printed alike, tied: 50.001 and 50.004 both print 50.00.
        assert_eq!(as_printed(50.001), as_printed(50.004));
        assert!(as_printed(50.004) < as_printed(50.006));
    }
}
