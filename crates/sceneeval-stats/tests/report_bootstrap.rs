//! The bootstrap moved here from `sceneeval-report` (its `compare::bootstrap_interval`), whose
//! tables must not change: the same seed, the same draws in the same order, the same
//! quantiles. The report's former function is kept below, verbatim, as the oracle.

use proptest::prelude::*;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{Rng, SeedableRng};
use sceneeval_stats::Bootstrap;

/// `sceneeval_report::compare::bootstrap_interval` before the move.
fn former_bootstrap_interval(values: &[f64], level: f64) -> Option<[f64; 2]> {
    if values.is_empty() {
        return None;
    }
    let n = values.len();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(20_261_121);
    let mut means: Vec<f64> = (0..1000)
        .map(|_| {
            let sum: f64 = (0..n)
                .map(|_| values[((u128::from(rng.next_u64()) * n as u128) >> 64) as usize])
                .sum();
            sum / n as f64
        })
        .collect();
    means.sort_by(f64::total_cmp);
    let tail = (1.0 - level) / 2.0;
    let quantile = |q: f64| {
        let at = q.clamp(0.0, 1.0) * (means.len() - 1) as f64;
        let (lo, hi) = (at.floor() as usize, at.ceil() as usize);
        means[lo] + (means[hi] - means[lo]) * (at - lo as f64)
    };
    Some([quantile(tail), quantile(1.0 - tail)])
}

proptest! {
    #[test]
    fn same_bits_as_the_reports_former_bootstrap(
        values in proptest::collection::vec(-1000.0f64..1000.0, 0..80),
        level in 0.01f64..0.999
    ) {
        let new = Bootstrap::new(1000, level).unwrap().mean(&values).unwrap().bounds.ok();
        let old = former_bootstrap_interval(&values, level);
        prop_assert_eq!(
            new.map(|b| b.map(f64::to_bits)),
            old.map(|b| b.map(f64::to_bits))
        );
    }
}
