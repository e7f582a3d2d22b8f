//! Small helpers on sorted lists.

/// The two lists, each sorted by `key`, as one sorted list; on equal keys `a`'s element
/// comes first.
pub(crate) fn merge_by_key<T: Copy, K: Ord>(a: &[T], b: &[T], key: impl Fn(&T) -> K) -> Vec<T> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if key(&b[j]) < key(&a[i]) {
            out.push(b[j]);
            j += 1;
        } else {
            out.push(a[i]);
            i += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

#[cfg(test)]
mod tests {
    use super::merge_by_key;

    #[test]
    fn merges_in_key_order_with_the_first_list_first_on_ties() {
        let a = [(1, 'a'), (3, 'a'), (5, 'a')];
        let b = [(0, 'b'), (3, 'b'), (6, 'b')];
        let m = merge_by_key(&a, &b, |x| x.0);
        assert_eq!(m, [(0, 'b'), (1, 'a'), (3, 'a'), (3, 'b'), (5, 'a'), (6, 'b')]);
    }
}
