//! Invariants of every statistic on random input (proptest), and the exact Wilcoxon and
//! McNemar p-values against brute-force enumeration.

use proptest::prelude::*;
use sceneeval_stats::{Bootstrap, Confusion, FleissTable, Majority, McNemar, WilcoxonP, holm, wilcoxon};

fn binary_pairs() -> impl Strategy<Value = Vec<(bool, bool)>> {
    proptest::collection::vec((any::<bool>(), any::<bool>()), 0..60)
}

/// Differences with ties and zeros likely: small integers scaled, some noise below 1e-9.
fn differences() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec((-6i32..=6, prop_oneof![Just(0.0), -4e-10..4e-10]), 0..70).prop_map(|v| {
        v.into_iter()
            .map(|(k, noise)| f64::from(k) * 0.25 + noise)
            .collect()
    })
}

proptest! {
    #[test]
    fn cohen_kappa_is_bounded_and_symmetric(pairs in binary_pairs()) {
        let table = Confusion::binary(pairs.iter().copied());
        let swapped = Confusion::binary(pairs.iter().map(|&(a, b)| (b, a)));
        prop_assert_eq!(table.kappa(), swapped.kappa());
        if let Ok(kappa) = table.kappa() {
            prop_assert!((-1.0..=1.0).contains(&kappa), "{}", kappa);
            // Defined kappa: p_e < 1, and kappa = 1 exactly when every item agrees.
            prop_assert_eq!(kappa == 1.0, table.agreement() == Some(1.0));
        }
    }

    #[test]
    fn nominal_kappa_is_bounded_and_symmetric(
        pairs in proptest::collection::vec((0usize..4, 0usize..4), 0..50)
    ) {
        let table = Confusion::from_pairs(4, pairs.iter().copied()).unwrap();
        let swapped = Confusion::from_pairs(4, pairs.iter().map(|&(a, b)| (b, a))).unwrap();
        prop_assert_eq!(table.kappa(), swapped.kappa());
        if let Ok(kappa) = table.kappa() {
            prop_assert!((-1.0..=1.0).contains(&kappa));
        }
        // Relabelling the categories changes nothing.
        let relabelled =
            Confusion::from_pairs(4, pairs.iter().map(|&(a, b)| (3 - a, 3 - b))).unwrap();
        prop_assert_eq!(table.kappa(), relabelled.kappa());
    }

    #[test]
    fn fleiss_kappa_is_at_most_one_and_order_free(
        rows in proptest::collection::vec(0u64..=5, 1..30)
    ) {
        // Five raters, two categories: row = true votes.
        let table: Vec<[u64; 2]> = rows.iter().map(|&t| [5 - t, t]).collect();
        let kappa = FleissTable::from_counts(&table).unwrap().kappa();
        let mut reversed: Vec<[u64; 2]> = table.iter().rev().map(|&[f, t]| [t, f]).collect();
        reversed.rotate_left(rows.len() / 2);
        prop_assert_eq!(kappa, FleissTable::from_counts(&reversed).unwrap().kappa());
        if let Ok(kappa) = kappa {
            prop_assert!((-1.0..=1.0).contains(&kappa), "{}", kappa);
        }
    }

    #[test]
    fn holm_is_monotone_above_raw_and_at_most_one(
        p in proptest::collection::vec(prop_oneof![Just(None), (0.0f64..=1.0).prop_map(Some)], 0..20)
    ) {
        let adjusted = holm(&p).unwrap();
        prop_assert_eq!(adjusted.len(), p.len());
        for (raw, adj) in p.iter().zip(&adjusted) {
            prop_assert_eq!(raw.is_some(), adj.is_some());
            if let (Some(raw), Some(adj)) = (raw, adj) {
                prop_assert!(*adj >= *raw && *adj <= 1.0);
            }
        }
        for (i, a) in p.iter().enumerate() {
            for (j, b) in p.iter().enumerate() {
                if let (Some(a), Some(b)) = (a, b)
                    && a <= b
                {
                    prop_assert!(adjusted[i] <= adjusted[j]);
                }
            }
        }
    }

    #[test]
    fn wilcoxon_is_symmetric_under_negation(d in differences()) {
        let w = wilcoxon(&d).unwrap();
        let negated: Vec<f64> = d.iter().map(|x| -x).collect();
        let v = wilcoxon(&negated).unwrap();
        prop_assert_eq!(w.statistic, v.statistic);
        prop_assert_eq!((w.r_plus, w.r_minus), (v.r_minus, v.r_plus));
        prop_assert_eq!((w.n, w.zeros, w.ties), (v.n, v.zeros, v.ties));
        prop_assert_eq!(w.p.value(), v.p.value());
        prop_assert_eq!(w.r_plus + w.r_minus, (w.n * (w.n + 1) / 2) as f64);
        match w.p {
            WilcoxonP::Exact { p } | WilcoxonP::Normal { p, .. } => {
                prop_assert!((0.0..=1.0).contains(&p), "{}", p);
                prop_assert!(w.n >= 2);
            }
            WilcoxonP::Undefined { .. } => prop_assert!(w.n < 2),
        }
        // Ties or more than 50 differences: the approximation; otherwise exact.
        if w.n >= 2 {
            let exact = matches!(w.p, WilcoxonP::Exact { .. });
            prop_assert_eq!(exact, w.n <= 50 && !w.ties);
        }
    }

    #[test]
    fn wilcoxon_exact_matches_enumeration(
        magnitudes in proptest::sample::subsequence((1..=40).collect::<Vec<u32>>(), 2..=12),
        signs in proptest::collection::vec(any::<bool>(), 12)
    ) {
        let d: Vec<f64> = magnitudes
            .iter()
            .zip(&signs)
            .map(|(&m, &s)| if s { f64::from(m) } else { -f64::from(m) })
            .collect();
        let w = wilcoxon(&d).unwrap();
        // Ranks of distinct magnitudes are 1..=n in sorted order.
        let n = d.len();
        let r_plus: usize = (1..=n).filter(|&rank| signs[rank - 1]).sum();
        prop_assert_eq!(w.r_plus, r_plus as f64);
        let sums: Vec<usize> = (0u32..1 << n)
            .map(|mask| (1..=n).filter(|&r| mask >> (r - 1) & 1 == 1).sum())
            .collect();
        let below = sums.iter().filter(|&&s| s <= r_plus).count();
        let above = sums.iter().filter(|&&s| s >= r_plus).count();
        let expected = (2.0 * below.min(above) as f64 / f64::from(1u32 << n)).min(1.0);
        prop_assert_eq!(w.p, WilcoxonP::Exact { p: expected });
    }

    #[test]
    fn mcnemar_matches_exact_sums(b in 0u64..60, c in 0u64..60) {
        let t = McNemar::exact(b, c);
        prop_assert_eq!(t.p, McNemar::exact(c, b).p);
        let n = b + c;
        // Exact binomial coefficients of n <= 118 in u128, summed, divided once.
        let mut coefficient = 1u128;
        let mut cumulative = 0u128;
        for i in 0..=b.min(c) {
            if i > 0 {
                coefficient = coefficient * u128::from(n - i + 1) / u128::from(i);
            }
            cumulative += coefficient;
        }
        let expected = (2.0 * (cumulative as f64 / 2f64.powi(n as i32))).min(1.0);
        prop_assert!((t.p - expected).abs() <= expected * 1e-13, "{} vs {}", t.p, expected);
        prop_assert!((0.0..=1.0).contains(&t.p));
    }

    #[test]
    fn bootstrap_intervals_are_ordered_inside_the_range_and_reproducible(
        values in proptest::collection::vec(-100.0f64..100.0, 1..40),
        level in 0.5f64..0.99
    ) {
        let b = Bootstrap::new(200, level).unwrap();
        let ci = b.mean(&values).unwrap();
        let [low, high] = ci.bounds.unwrap();
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        prop_assert!(low <= high);
        prop_assert!(min - 1e-9 <= low && high <= max + 1e-9);
        prop_assert_eq!(b.mean(&values).unwrap(), ci);
    }

    #[test]
    fn majority_is_the_larger_count(votes in proptest::collection::vec(proptest::option::of(any::<bool>()), 0..12)) {
        let m = Majority::of(votes.iter().copied());
        let yes = votes.iter().filter(|v| **v == Some(true)).count();
        let no = votes.iter().filter(|v| **v == Some(false)).count();
        prop_assert_eq!(m.verdict(), match yes.cmp(&no) {
            std::cmp::Ordering::Greater => Some(true),
            std::cmp::Ordering::Less => Some(false),
            std::cmp::Ordering::Equal => None,
        });
    }
}
