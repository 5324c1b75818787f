//! Bootstrap confidence intervals of a mean over scenes: fixed seed, fixed number of
//! resamples, percentile method.

use rand::rngs::Xoshiro256PlusPlus;
use rand::{Rng, SeedableRng};

/// Resamples per interval.
pub const BOOTSTRAP_RESAMPLES: usize = 1000;

/// The generator's seed: every interval starts from it (rand's Xoshiro256++, whose output
/// for a seed is fixed by its definition), so a table is the same on every run and machine.
pub const BOOTSTRAP_SEED: u64 = 20_261_121;

/// The percentile bootstrap interval at `level` (e.g. 0.95) of the mean of `values` (one per
/// scene): [`BOOTSTRAP_RESAMPLES`] resamples of `values.len()` scenes drawn with replacement,
/// the resampled means sorted, and the `(1 - level) / 2` and `(1 + level) / 2` quantiles read
/// with linear interpolation. `None` without values.
///
/// ```
/// use sceneeval_report::compare::bootstrap_interval;
/// // Every scene has 40: every resample's mean is 40.
/// assert_eq!(bootstrap_interval(&[40.0, 40.0, 40.0], 0.95), Some([40.0, 40.0]));
/// assert_eq!(bootstrap_interval(&[], 0.95), None);
/// ```
pub fn bootstrap_interval(values: &[f64], level: f64) -> Option<[f64; 2]> {
    if values.is_empty() {
        return None;
    }
    let n = values.len();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(BOOTSTRAP_SEED);
    let mut means: Vec<f64> = (0..BOOTSTRAP_RESAMPLES)
        .map(|_| {
            let sum: f64 = (0..n).map(|_| values[index(&mut rng, n)]).sum();
            sum / n as f64
        })
        .collect();
    means.sort_by(f64::total_cmp);
    let tail = (1.0 - level) / 2.0;
    Some([quantile(&means, tail), quantile(&means, 1.0 - tail)])
}

/// A uniform index below `n` from one 64-bit draw (the high half of the 128-bit product; its
/// bias is below n / 2^64).
fn index(rng: &mut Xoshiro256PlusPlus, n: usize) -> usize {
    ((u128::from(rng.next_u64()) * n as u128) >> 64) as usize
}

/// The `q` quantile of sorted `values`, interpolated between the two nearest ranks.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let at = q.clamp(0.0, 1.0) * (sorted.len() - 1) as f64;
    let (lo, hi) = (at.floor() as usize, at.ceil() as usize);
    sorted[lo] + (sorted[hi] - sorted[lo]) * (at - lo as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_cover_the_mean_and_are_reproducible() {
        // Two scenes, 0 and 100: a resample's mean is 0, 50 or 100 with probabilities 1/4, 1/2,
        // 1/4, so about 250 of the 1000 sorted means are 0 and 250 are 100; the 2.5 % and
        // 97.5 % quantiles (positions 24.975 and 974.025) fall among them.
        assert_eq!(bootstrap_interval(&[0.0, 100.0], 0.95), Some([0.0, 100.0]));
        // A narrower level on many scenes: the interval holds the mean and is narrower.
        let values: Vec<f64> = (0..50).map(|k| f64::from(k % 5) * 25.0).collect();
        let mean = values.iter().sum::<f64>() / 50.0;
        let wide = bootstrap_interval(&values, 0.95).unwrap_or_default();
        let narrow = bootstrap_interval(&values, 0.5).unwrap_or_default();
        assert!(wide[0] < mean && mean < wide[1], "{wide:?} {mean}");
        assert!(wide[0] < narrow[0] && narrow[1] < wide[1], "{wide:?} {narrow:?}");
        // Fixed seed: the same interval every time.
        assert_eq!(bootstrap_interval(&values, 0.95), Some(wide));
        assert_eq!(quantile(&[0.0, 10.0], 0.25), 2.5);
    }
}
