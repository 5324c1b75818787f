//! Percentile bootstrap intervals: items resampled with replacement from a fixed seed, so an
//! interval is the same on every run and machine.
//!
//! One resample draws `n` item indices, each from one 64-bit output of rand's Xoshiro256++
//! (the high half of the 128-bit product with `n`; bias below `n / 2^64`), then computes the
//! statistic on the drawn items. The resampled statistics are sorted and the `(1 - level) / 2`
//! and `(1 + level) / 2` quantiles read with linear interpolation between the two nearest
//! ranks. Every interval starts from the seed, so intervals of different columns do not depend
//! on each other or on the order they are computed in.
//!
//! **Undefined resamples.** A statistic can be undefined on some resamples although it is
//! defined on the data (Cohen's kappa on a resample that drew only items both raters put in
//! the same one class). Such resamples are left out of the quantiles and counted
//! ([`BootstrapInterval::undefined`]): the interval is that of the statistic where it exists;
//! a caller who shows the interval should show the count when it is not 0. When every
//! resample is undefined there is no interval ([`Undefined::EveryResample`]).

use rand::rngs::Xoshiro256PlusPlus;
use rand::{Rng, SeedableRng};

use crate::{Confusion, StatsError, Undefined};

/// Resamples per interval unless asked otherwise.
pub const DEFAULT_RESAMPLES: usize = 1000;

/// The generator's seed unless asked otherwise (rand's Xoshiro256++, whose output for a seed is
/// fixed by its definition).
pub const DEFAULT_SEED: u64 = 20_261_121;

/// How to bootstrap: resamples, seed and confidence level. Built valid
/// ([`Bootstrap::new`]); [`Bootstrap::default`] is 1000 resamples, seed 20261121, level 0.95.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bootstrap {
    resamples: usize,
    seed: u64,
    level: f64,
}

impl Default for Bootstrap {
    fn default() -> Self {
        Self {
            resamples: DEFAULT_RESAMPLES,
            seed: DEFAULT_SEED,
            level: 0.95,
        }
    }
}

/// A percentile bootstrap interval and how it was obtained.
#[derive(Debug, Clone, PartialEq)]
pub struct BootstrapInterval {
    /// `[low, high]`, or why there is none.
    pub bounds: Result<[f64; 2], Undefined>,
    /// The confidence level.
    pub level: f64,
    /// Resamples drawn.
    pub resamples: usize,
    /// Resamples on which the statistic was undefined, left out of the quantiles.
    pub undefined: usize,
}

impl Bootstrap {
    /// `resamples` resamples at confidence `level`, from [`DEFAULT_SEED`].
    ///
    /// # Errors
    /// [`StatsError::NoResamples`] for 0 resamples; [`StatsError::Level`] for a level outside
    /// (0, 1).
    pub fn new(resamples: usize, level: f64) -> Result<Self, StatsError> {
        if resamples == 0 {
            return Err(StatsError::NoResamples);
        }
        if !(level > 0.0 && level < 1.0) {
            return Err(StatsError::Level(level));
        }
        Ok(Self {
            resamples,
            seed: DEFAULT_SEED,
            level,
        })
    }

    /// The same with another seed.
    #[must_use]
    pub fn with_seed(self, seed: u64) -> Self {
        Self { seed, ..self }
    }

    /// Resamples per interval.
    #[must_use]
    pub fn resamples(&self) -> usize {
        self.resamples
    }

    /// The generator's seed.
    #[must_use]
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The confidence level.
    #[must_use]
    pub fn level(&self) -> f64 {
        self.level
    }

    /// The interval of any statistic of `n` items: `statistic` gets the indices (`< n`) of
    /// one resample, in the order drawn, and returns its value or `None` where it is
    /// undefined. Without items there is no interval ([`Undefined::NoItems`]; `statistic` is
    /// not called).
    pub fn interval(
        &self,
        n: usize,
        mut statistic: impl FnMut(&[usize]) -> Option<f64>,
    ) -> BootstrapInterval {
        let mut result = BootstrapInterval {
            bounds: Err(Undefined::NoItems),
            level: self.level,
            resamples: self.resamples,
            undefined: 0,
        };
        if n == 0 {
            result.undefined = self.resamples;
            return result;
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(self.seed);
        let mut indices = vec![0usize; n];
        let mut values = Vec::with_capacity(self.resamples);
        for _ in 0..self.resamples {
            for slot in &mut indices {
                *slot = index(&mut rng, n);
            }
            match statistic(&indices) {
                Some(value) => values.push(value),
                None => result.undefined += 1,
            }
        }
        if values.is_empty() {
            result.bounds = Err(Undefined::EveryResample);
            return result;
        }
        values.sort_by(f64::total_cmp);
        let tail = (1.0 - self.level) / 2.0;
        result.bounds = Ok([quantile(&values, tail), quantile(&values, 1.0 - tail)]);
        result
    }

    /// The interval of the mean of `values` (one per item), the resampled values summed in
    /// the order drawn.
    ///
    /// # Errors
    /// [`StatsError::NotFinite`] for a NaN or infinite value.
    ///
    /// ```
    /// use sceneeval_stats::Bootstrap;
    /// // Every item has 40: every resample's mean is 40.
    /// let ci = Bootstrap::default().mean(&[40.0, 40.0, 40.0]).unwrap();
    /// assert_eq!(ci.bounds, Ok([40.0, 40.0]));
    /// ```
    pub fn mean(&self, values: &[f64]) -> Result<BootstrapInterval, StatsError> {
        check_finite(values)?;
        let n = values.len();
        Ok(self.interval(n, |drawn| {
            let sum: f64 = drawn.iter().map(|&i| values[i]).sum();
            Some(sum / n as f64)
        }))
    }

    /// The interval of Cohen's kappa of two raters, items resampled: `pairs` holds each
    /// item's (first rater's, second rater's) category below `categories`. Resamples on which
    /// kappa is undefined (one class only) are left out and counted.
    ///
    /// # Errors
    /// [`StatsError::Category`] for a category not below `categories`.
    pub fn cohen_kappa(
        &self,
        categories: usize,
        pairs: &[(usize, usize)],
    ) -> Result<BootstrapInterval, StatsError> {
        // Checks the categories once; each resample then builds its table from valid pairs.
        Confusion::from_pairs(categories, pairs.iter().copied())?;
        Ok(self.interval(pairs.len(), |drawn| {
            Confusion::from_pairs(categories, drawn.iter().map(|&i| pairs[i]))
                .ok()?
                .kappa()
                .ok()
        }))
    }

    /// [`Bootstrap::cohen_kappa`] for binary verdicts (first rater's, second rater's).
    #[must_use]
    pub fn cohen_kappa_binary(&self, pairs: &[(bool, bool)]) -> BootstrapInterval {
        self.interval(pairs.len(), |drawn| {
            Confusion::binary(drawn.iter().map(|&i| pairs[i])).kappa().ok()
        })
    }
}

/// An error naming the first value that is NaN or infinite.
pub(crate) fn check_finite(values: &[f64]) -> Result<(), StatsError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(StatsError::NotFinite {
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

/// A uniform index below `n` from one 64-bit draw (the high half of the 128-bit product; its
/// bias is below n / 2^64).
pub(crate) fn index(rng: &mut Xoshiro256PlusPlus, n: usize) -> usize {
    ((u128::from(rng.next_u64()) * n as u128) >> 64) as usize
}

/// The `q` quantile of sorted `values` (not empty), interpolated between the two nearest ranks.
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
        // Two items, 0 and 100: a resample's mean is 0, 50 or 100 with probabilities 1/4, 1/2,
        // 1/4, so about 250 of the 1000 sorted means are 0 and 250 are 100; the 2.5 % and
        // 97.5 % quantiles (positions 24.975 and 974.025) fall among them.
        let b = Bootstrap::default();
        assert_eq!(b.mean(&[0.0, 100.0]).unwrap().bounds, Ok([0.0, 100.0]));
        // A narrower level on many items: the interval holds the mean and is narrower.
        let values: Vec<f64> = (0..50).map(|k| f64::from(k % 5) * 25.0).collect();
        let mean = values.iter().sum::<f64>() / 50.0;
        let wide = b.mean(&values).unwrap().bounds.unwrap();
        let narrow = Bootstrap::new(1000, 0.5).unwrap().mean(&values).unwrap();
        let narrow = narrow.bounds.unwrap();
        assert!(wide[0] < mean && mean < wide[1], "{wide:?} {mean}");
        assert!(wide[0] < narrow[0] && narrow[1] < wide[1], "{wide:?} {narrow:?}");
        // Fixed seed: the same interval every time; another seed, another interval.
        assert_eq!(b.mean(&values).unwrap().bounds, Ok(wide));
        let other = b.with_seed(7).mean(&values).unwrap().bounds.unwrap();
        assert_ne!(other, wide);
        assert_eq!(quantile(&[0.0, 10.0], 0.25), 2.5);
        assert_eq!(quantile(&[3.0], 0.975), 3.0);
    }

    #[test]
    fn nothing_to_resample() {
        let b = Bootstrap::default();
        let none = b.mean(&[]).unwrap();
        assert_eq!(none.bounds, Err(Undefined::NoItems));
        assert_eq!(none.undefined, 1000);
        let err = b.mean(&[1.0, f64::NAN]).unwrap_err();
        assert_eq!(err.to_string(), "value 1 is not a finite number (NaN)");
        assert_eq!(Bootstrap::new(0, 0.9), Err(StatsError::NoResamples));
        assert_eq!(Bootstrap::new(10, 1.0), Err(StatsError::Level(1.0)));
        assert!(Bootstrap::new(10, f64::NAN).is_err());
    }

    #[test]
    fn kappa_resamples_where_it_is_undefined_are_counted() {
        // 2 items, both agree, one true and one false: kappa 1 on the data. A resample draws
        // both items twice the same with probability 1/2 (one class: undefined), else kappa 1.
        let b = Bootstrap::default();
        let ci = b.cohen_kappa_binary(&[(true, true), (false, false)]);
        assert_eq!(ci.bounds, Ok([1.0, 1.0]));
        assert!(
            (400..600).contains(&ci.undefined),
            "about half of 1000: {}",
            ci.undefined
        );
        // One class everywhere: undefined on every resample.
        let ci = b.cohen_kappa_binary(&[(true, true); 4]);
        assert_eq!(ci.bounds, Err(Undefined::EveryResample));
        assert_eq!(ci.undefined, 1000);
        // The nominal form gives the same resamples as the binary one.
        let pairs = [
            (true, true),
            (true, false),
            (false, false),
            (false, true),
            (true, true),
        ];
        let nominal: Vec<(usize, usize)> = pairs
            .iter()
            .map(|&(a, b)| (usize::from(a), usize::from(b)))
            .collect();
        assert_eq!(b.cohen_kappa(2, &nominal).unwrap(), b.cohen_kappa_binary(&pairs));
        assert!(b.cohen_kappa(2, &[(0, 3)]).is_err());
    }
}
