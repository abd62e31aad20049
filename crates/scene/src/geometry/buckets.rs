//! Items grouped by a small integer key in one counting sort: two passes over the items, no
//! per-group allocation, each group keeping the items' order. Used where a map of vectors
//! (or lookups scattered over a big array) cost more than the work itself: the faces around
//! each position (`normals`), faces by hash shard (`dedup`).

/// Groups `items` (key, value) with keys below `keys`: group `k` is
/// `values[start[k]..start[k + 1]]`, in the order the items came.
pub(crate) fn group<T: Copy + Default>(
    keys: usize,
    items: impl Iterator<Item = (usize, T)> + Clone,
) -> (Vec<usize>, Vec<T>) {
    let mut start = vec![0usize; keys + 1];
    for (k, _) in items.clone() {
        start[k + 1] += 1;
    }
    for k in 1..=keys {
        start[k] += start[k - 1];
    }
    let mut fill = start.clone();
    let mut values = vec![T::default(); start[keys]];
    for (k, v) in items {
        values[fill[k]] = v;
        fill[k] += 1;
    }
    (start, values)
}

#[cfg(test)]
mod tests {
    #[test]
    fn groups_keep_the_items_order() {
        let items = [(2, 'a'), (0, 'b'), (2, 'c'), (1, 'd'), (0, 'e')];
        let (start, v) = crate::geometry::buckets::group(4, items.iter().copied());
        assert_eq!(start, vec![0, 2, 3, 5, 5]);
        assert_eq!(v, vec!['b', 'e', 'd', 'a', 'c']);
    }
}
