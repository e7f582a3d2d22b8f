//! List passes over vertex ids without a branch on per-vertex flags. The flags follow the
//! mesh, not the ids, so a branch on them mispredicts about as often as it goes either way;
//! writing every entry and advancing a list's end by the answer costs a few more stores and
//! no mispredictions (docs/BENCHMARKS.md, session 24).

/// Keeps the entries of `xs` for which `f` answers `(true, _)`, in order, and returns those
/// for which it answers `(true, true)`, in order. `f` sees every entry once, in order.
pub(crate) fn keep_and_pick(xs: &mut Vec<u32>, mut f: impl FnMut(u32) -> (bool, bool)) -> Vec<u32> {
    let mut picked = vec![0; xs.len()];
    let (mut kept, mut listed) = (0, 0);
    for i in 0..xs.len() {
        let x = xs[i];
        let (keep, pick) = f(x);
        xs[kept] = x;
        kept += usize::from(keep);
        picked[listed] = x;
        listed += usize::from(keep & pick);
    }
    xs.truncate(kept);
    picked.truncate(listed);
    picked
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_and_picks_in_order() {
        let mut xs: Vec<u32> = (0..20).collect();
        let picked = keep_and_pick(&mut xs, |x| (x % 2 == 0, x % 3 == 0 || x == 7));
        assert_eq!(xs, [0, 2, 4, 6, 8, 10, 12, 14, 16, 18]);
        // 7 and 9 are not kept, so not picked.
        assert_eq!(picked, [0, 6, 12, 18]);
        let mut none: Vec<u32> = Vec::new();
        assert!(keep_and_pick(&mut none, |_| (true, true)).is_empty());
    }
}
