//! Holm's step-down adjustment of p-values for multiple tests.

use crate::StatsError;

/// Holm-adjusted p-values, in the input's order: sorted ascending, the `i`-th smallest
/// (from 0) of the `m` p-values becomes `min(1, max_{j <= i} (m - j) p_(j))`. Equal to
/// statsmodels' `multipletests(p, method='holm')[1]` (same products, same running maximum, so
/// the same bits). `None` entries (tests without a p-value) stay `None` and are not counted in
/// `m`: a test that could not be run does not make the others' adjustment stricter.
///
/// # Errors
/// [`StatsError::PValue`] for a value outside [0, 1] or NaN.
///
/// ```
/// use sceneeval_stats::holm;
/// // Sorted 0.01, 0.03, 0.04 (m = 3): 0.03, max(0.03, 0.06), max(0.06, 0.04) = 0.06.
/// let adjusted = holm(&[Some(0.04), None, Some(0.01), Some(0.03)]).unwrap();
/// assert_eq!(adjusted, vec![Some(0.06), None, Some(0.03), Some(0.06)]);
/// ```
pub fn holm(p_values: &[Option<f64>]) -> Result<Vec<Option<f64>>, StatsError> {
    let mut present: Vec<(usize, f64)> = Vec::with_capacity(p_values.len());
    for (index, p) in p_values.iter().enumerate() {
        if let Some(value) = *p {
            if !(0.0..=1.0).contains(&value) {
                return Err(StatsError::PValue { index, value });
            }
            present.push((index, value));
        }
    }
    present.sort_by(|a, b| a.1.total_cmp(&b.1));
    let m = present.len();
    let mut adjusted = vec![None; p_values.len()];
    let mut running = 0.0f64;
    for (rank, &(index, p)) in present.iter().enumerate() {
        running = running.max(p * (m - rank) as f64);
        adjusted[index] = Some(running.min(1.0));
    }
    Ok(adjusted)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holm_by_hand() {
        // m = 4: 0.01*4 = 0.04, 0.02*3 = 0.06, 0.03*2 = 0.06, 0.5*1 = 0.5.
        let p = [Some(0.5), Some(0.03), Some(0.01), Some(0.02)];
        let adjusted = holm(&p).unwrap();
        let expected = [0.5, 0.06, 0.04, 0.06];
        for (got, want) in adjusted.iter().zip(expected) {
            assert!((got.unwrap() - want).abs() < 1e-15, "{adjusted:?}");
        }
        // The running maximum lifts a later, smaller product: 0.01*3 = 0.03 then 0.012*2.
        assert_eq!(
            holm(&[Some(0.012), Some(0.01), Some(0.9)]).unwrap(),
            vec![Some(0.03), Some(0.03), Some(0.9)]
        );
        // Capped at 1; ties share their value whatever their order.
        assert_eq!(holm(&[Some(0.6), Some(0.6)]).unwrap(), vec![Some(1.0), Some(1.0)]);
        // One test: unchanged. None: kept, not counted.
        assert_eq!(holm(&[Some(0.03)]).unwrap(), vec![Some(0.03)]);
        assert_eq!(
            holm(&[None, Some(0.03), None]).unwrap(),
            vec![None, Some(0.03), None]
        );
        assert_eq!(holm(&[]).unwrap(), vec![]);
        let err = holm(&[Some(0.2), Some(1.5)]).unwrap_err();
        assert_eq!(err.to_string(), "p-value 1 is 1.5, not a probability in [0, 1]");
        assert!(holm(&[Some(f64::NAN)]).is_err());
    }
}
