//! A seeded sample without replacement: which `k` of `n` items to look at (`sceneeval judge
//! --sample N --seed S` draws the scenes a person judges), the same on every run and machine.
//!
//! The rule: rand's Xoshiro256++ seeded with `seed_from_u64(seed)` (the generator of
//! [`crate::bootstrap`]) drives a partial Fisher–Yates shuffle of `0..n`: for `i` in `0..k`,
//! `j = i + r` with `r` drawn in `0..n - i` from one 64-bit output as the bootstrap draws (the
//! high half of its 128-bit product with `n - i`), and positions `i` and `j` are swapped. The
//! first `k` positions are the sample, returned in increasing order. `k >= n` is every item
//! (no number is drawn).

use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;

use crate::bootstrap::index;

/// `k` distinct indices of `0..n` drawn with `seed`, in increasing order (every index when
/// `k >= n`).
///
/// ```
/// use sceneeval_stats::sample::sample;
/// let a = sample(10, 3, 7);
/// assert_eq!(a, sample(10, 3, 7));
/// assert_eq!(a.len(), 3);
/// assert!(a.windows(2).all(|w| w[0] < w[1]) && a[2] < 10);
/// assert_eq!(sample(3, 5, 7), [0, 1, 2]);
/// ```
#[must_use]
pub fn sample(n: usize, k: usize, seed: u64) -> Vec<usize> {
    if k >= n {
        return (0..n).collect();
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut order: Vec<usize> = (0..n).collect();
    for i in 0..k {
        let j = i + index(&mut rng, n - i);
        order.swap(i, j);
    }
    let mut chosen = order[..k].to_vec();
    chosen.sort_unstable();
    chosen
}

#[cfg(test)]
mod tests {
    use rand::Rng;

    use super::*;

    #[test]
    fn the_rule_step_by_step() {
        // The rule written out with the generator's own outputs.
        let (n, k, seed) = (7usize, 3usize, 42u64);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut order: Vec<usize> = (0..n).collect();
        for i in 0..k {
            let r = ((u128::from(rng.next_u64()) * (n - i) as u128) >> 64) as usize;
            order.swap(i, i + r);
        }
        let mut expected = order[..k].to_vec();
        expected.sort_unstable();
        assert_eq!(sample(n, k, seed), expected);
    }

    #[test]
    fn same_seed_same_sample_other_seeds_differ_and_every_item_is_reachable() {
        assert_eq!(sample(100, 10, 1), sample(100, 10, 1));
        assert_ne!(sample(100, 10, 1), sample(100, 10, 2));
        assert_eq!(sample(5, 5, 9), [0, 1, 2, 3, 4]);
        assert_eq!(sample(5, 50, 9), [0, 1, 2, 3, 4]);
        assert!(sample(5, 0, 9).is_empty());
        assert!(sample(0, 3, 9).is_empty());
        // Over many seeds, each of 4 items is drawn (1 of 4) about a quarter of the time.
        let mut hits = [0usize; 4];
        for seed in 0..4000 {
            let s = sample(4, 1, seed);
            assert_eq!(s.len(), 1);
            hits[s[0]] += 1;
        }
        for h in hits {
            assert!((850..1150).contains(&h), "{hits:?}");
        }
    }

    proptest::proptest! {
        #[test]
        fn a_sample_is_k_distinct_sorted_indices(n in 0usize..60, k in 0usize..80, seed: u64) {
            let s = sample(n, k, seed);
            proptest::prop_assert_eq!(s.len(), k.min(n));
            proptest::prop_assert!(s.windows(2).all(|w| w[0] < w[1]));
            proptest::prop_assert!(s.iter().all(|&i| i < n));
        }
    }
}
