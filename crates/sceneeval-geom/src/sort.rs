//! Sorting helpers for the mesh tables.

use std::cmp::Ordering;

/// Sorts `items` by their bucket (each below `buckets`), then within a bucket by `within`: a
/// counting sort followed by a sort of each bucket, linear in the items when buckets hold few
/// of them (the edges at one vertex). Deterministic: equal items keep an order that depends
/// only on the input.
pub(crate) fn bucket_sort<T: Copy>(
    items: &mut [T],
    buckets: usize,
    bucket: impl Fn(&T) -> usize,
    mut within: impl FnMut(&T, &T) -> Ordering,
) {
    let mut start = vec![0usize; buckets + 1];
    for item in items.iter() {
        start[bucket(item) + 1] += 1;
    }
    for k in 0..buckets {
        start[k + 1] += start[k];
    }
    let mut next = start.clone();
    let unsorted = items.to_vec();
    for item in &unsorted {
        let b = bucket(item);
        items[next[b]] = *item;
        next[b] += 1;
    }
    for k in 0..buckets {
        items[start[k]..start[k + 1]].sort_unstable_by(&mut within);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The bucket sort orders like a full sort by (bucket, key).
        #[test]
        fn bucket_sort_orders_like_a_full_sort(
            items in proptest::collection::vec((0u32..12, 0u32..50, 0u32..1000), 0..300)
        ) {
            let mut ours = items.clone();
            bucket_sort(&mut ours, 12, |e| e.0 as usize, |a, b| (a.1, a.2).cmp(&(b.1, b.2)));
            let mut full = items;
            full.sort();
            prop_assert_eq!(ours, full);
        }
    }
}
