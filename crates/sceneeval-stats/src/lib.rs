//! The statistics SceneEval's comparisons rest on, each equal to the implementation reviewers
//! know (scikit-learn, statsmodels, SciPy) and tested against it:
//!
//! | what | here | equal to |
//! |---|---|---|
//! | Cohen's kappa of two raters | [`Confusion::kappa`] | scikit-learn `cohen_kappa_score(a, b)` |
//! | Fleiss' kappa of several raters | [`FleissTable::kappa`] | statsmodels `fleiss_kappa(table, method='fleiss')` |
//! | percentile bootstrap interval (seeded) | [`Bootstrap`] | — (the rule is stated in [`bootstrap`]) |
//! | paired mean difference, its interval, Wilcoxon | [`paired()`] | — / SciPy `wilcoxon` |
//! | two-sided Wilcoxon signed-rank test | [`wilcoxon()`] | SciPy `wilcoxon(np.round(d, 9), zero_method='wilcox', correction=True, method='exact' or 'asymptotic')` |
//! | Holm's step-down adjustment | [`holm()`] | statsmodels `multipletests(p, method='holm')[1]` |
//! | McNemar's exact test | [`McNemar`] | statsmodels `mcnemar(table, exact=True).pvalue` |
//! | majority vote with ties | [`Majority`] | — |
//! | seeded sample without replacement | [`sample::sample`] | — (the rule is stated in [`sample`]) |
//!
//! **Missing is not a number.** Input a statistic cannot be computed from (NaN, paired samples
//! of different lengths, uneven rater counts, a level outside (0, 1)) is a [`StatsError`]
//! naming the position. A statistic that does not exist for valid input is an [`Undefined`]
//! reason (no items, one class only, fewer than two non-zero differences, every bootstrap
//! resample undefined): callers show an empty cell with the reason, never a made-up value.
//!
//! **Numerical accuracy.**
//! - Kappas are exact integer sums (Cohen's in `u128`, Fleiss' in `i128`, checked against
//!   overflow) and one division: perfect agreement is exactly 1, a kappa never leaves [-1, 1]
//!   by rounding, and "chance agreement is 1" is decided exactly. The division's operands are
//!   exact below 2^53, so the result is then correctly rounded.
//! - The Wilcoxon exact p-value is an exact dyadic rational (counts of sign patterns in
//!   `u64`); the rank sums, the tie term and the normal approximation's `z` are computed with
//!   SciPy's operations in SciPy's order, so they are bit-identical to SciPy's.
//! - The normal tail `Φ(-|z|)` uses musl's `erf`/`erfc` (through `libm`, error below 1 ulp) in
//!   Cephes' `ndtr` branches: relative error about 1e-15, and no cancellation in the far tail
//!   (SciPy's Cephes `erfc` is off by up to about 1e-14 relative beyond `|z| = 5`). The
//!   approximate Wilcoxon p-values are bit-identical to SciPy's or within 1e-14 relative on
//!   the Python tests' random cases.
//! - McNemar's binomial tail is a running product with its exponent kept apart, then a sum of
//!   ratios: within 1e-14 relative of the exact fraction down to 1e-300 on the Python tests'
//!   cases (the bound is `2 min(b, c) + 4` ulps), where SciPy's `binom.cdf`, which statsmodels
//!   uses, gives 0 below about 1e-267.
//! - Holm's products and running maximum are statsmodels' operations: the same bits.
//! - Bootstrap quantiles interpolate linearly between the two nearest sorted resampled values.
//!
//! `crates/sceneeval-py/tests/test_stats.py` checks all of this against scikit-learn,
//! statsmodels and SciPy on seeded random cases and the edge cases.
//!
//! ```
//! use sceneeval_stats::{Bootstrap, Confusion, Majority, holm, paired};
//!
//! // A judge against people on 6 specs (judge's verdict, people's majority).
//! let people = [
//!     [Some(true), Some(true), None],
//!     [Some(false), Some(false), Some(true)],
//!     [Some(true), Some(false), None], // a tie: left out
//!     [Some(true), Some(true), Some(true)],
//!     [Some(false), None, None],
//!     [Some(true), Some(true), Some(false)],
//! ];
//! let judge = [true, false, true, false, false, true];
//! let pairs: Vec<(bool, bool)> = judge
//!     .iter()
//!     .zip(&people)
//!     .filter_map(|(&j, votes)| Some((j, Majority::of(votes.iter().copied()).verdict()?)))
//!     .collect();
//! assert_eq!(pairs.len(), 5);
//! let table = Confusion::binary(pairs.iter().copied());
//! assert_eq!(table.agreement(), Some(0.8));
//! // Rows (judge) false 3, true 2; columns (people) false 2, true 3: p_e = 12/25;
//! // kappa = (5 * 4 - 12) / (25 - 12) = 8/13.
//! assert_eq!(table.kappa(), Ok(8.0 / 13.0));
//! let interval = Bootstrap::default().cohen_kappa_binary(&pairs);
//! assert_eq!(interval.resamples, 1000);
//!
//! // Two methods on the same five scenes, then Holm across two metrics.
//! let a = [0.91, 0.85, 0.78, 0.88, 0.95];
//! let b = [0.93, 0.90, 0.80, 0.87, 0.99];
//! let collision = paired(&a, &b, &Bootstrap::default()).unwrap();
//! let p = collision.wilcoxon.p.value().ok();
//! let adjusted = holm(&[p, Some(0.01)]).unwrap();
//! assert!(adjusted[0] >= p);
//! ```

pub mod bootstrap;
mod error;
pub mod holm;
pub mod kappa;
pub mod mcnemar;
pub mod paired;
pub mod sample;
pub mod special;
pub mod vote;
pub mod wilcoxon;

pub use bootstrap::{Bootstrap, BootstrapInterval};
pub use error::{StatsError, Undefined};
pub use holm::holm;
pub use kappa::{Confusion, FleissTable};
pub use mcnemar::McNemar;
pub use paired::{Paired, paired};
pub use vote::{Decision, Majority};
pub use wilcoxon::{Wilcoxon, WilcoxonP, wilcoxon};
