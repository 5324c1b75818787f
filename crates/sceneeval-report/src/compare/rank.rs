//! Ranks: competition ranking by value ("1224": runs with equal values share the best rank,
//! and the next rank skips as many places as runs tied), or ranks that respect uncertainty (a
//! run's rank is 1 + the number of runs better than it with a Holm-adjusted Wilcoxon p-value
//! below alpha).

use sceneeval_results::Better;
use sceneeval_stats::{holm, wilcoxon};

use super::Column;

/// How runs are ranked in a column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RankBy {
    /// 1 + the number of runs better on the column by a paired test: the two-sided Wilcoxon
    /// signed-rank test on the scenes both runs have a value for, Holm-adjusted across the
    /// columns of the pair, below alpha, with the mean difference in the better direction.
    /// Runs no test separates share a rank (`--rank tested`, the default).
    #[default]
    Tested,
    /// Competition ranks of the means as printed, whatever their uncertainty (`--rank mean`).
    Mean,
}

impl RankBy {
    /// `tested` or `mean`.
    pub const fn name(self) -> &'static str {
        match self {
            RankBy::Tested => "tested",
            RankBy::Mean => "mean",
        }
    }
}

/// Tested ranks: `values[column][run][scene]` (a scene's value, `None` without one) to
/// `ranks[column][run]` ([`RankBy::Tested`]); a run without any value gets `None`.
pub(crate) fn tested_ranks(
    values: &[Vec<Vec<Option<f64>>>],
    columns: &[Column],
    alpha: f64,
) -> Vec<Vec<Option<usize>>> {
    let runs = values.first().map_or(0, Vec::len);
    // beats[k][i][j]: run i is better than run j in column k.
    let mut beats = vec![vec![vec![false; runs]; runs]; columns.len()];
    for i in 0..runs {
        for j in i + 1..runs {
            let tests: Vec<(Option<f64>, f64)> = values
                .iter()
                .map(|column| pair_test(&column[i], &column[j]))
                .collect();
            let adjusted = holm(&tests.iter().map(|t| t.0).collect::<Vec<_>>()).unwrap_or_default();
            for (k, ((_, mean), p)) in tests.iter().zip(adjusted).enumerate() {
                if p.is_none_or(|p| p >= alpha) || *mean == 0.0 {
                    continue;
                }
                // `mean` is j - i.
                let j_better = match columns[k].better {
                    Better::Higher => *mean > 0.0,
                    Better::Lower => *mean < 0.0,
                };
                if j_better {
                    beats[k][j][i] = true;
                } else {
                    beats[k][i][j] = true;
                }
            }
        }
    }
    values
        .iter()
        .zip(&beats)
        .map(|(column, beats)| {
            (0..runs)
                .map(|i| {
                    column[i]
                        .iter()
                        .any(Option::is_some)
                        .then(|| 1 + (0..runs).filter(|&j| beats[j][i]).count())
                })
                .collect()
        })
        .collect()
}

/// The Wilcoxon p-value (when defined) and the mean difference `b - a` over the scenes both
/// have a value for.
fn pair_test(a: &[Option<f64>], b: &[Option<f64>]) -> (Option<f64>, f64) {
    let d: Vec<f64> = a.iter().zip(b).filter_map(|(x, y)| Some((*y)? - (*x)?)).collect();
    if d.is_empty() {
        return (None, 0.0);
    }
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let p = wilcoxon(&d).ok().and_then(|w| w.p.value().ok());
    (p, mean)
}

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
