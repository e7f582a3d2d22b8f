//! Parallel maps sized to their work. A coarsening round or a pass ends with a few hundred
//! items or fewer, and waking a pool for those costs more than the work, the more so the
//! larger the pool (measured on 16 cores: docs/BENCHMARKS.md, "Many cores").

use rayon::prelude::*;

/// `f` over `items`, results in order, with one scratch `S` per task: on the pool when there
/// are at least `serial_below` items, each task taking at least `min_len`; else on the
/// calling thread. The result does not depend on which.
pub(crate) fn map_sized<T, S, R>(
    items: &[T],
    serial_below: usize,
    min_len: usize,
    f: impl Fn(&mut S, &T) -> R + Sync + Send,
) -> Vec<R>
where
    T: Sync,
    S: Default,
    R: Send,
{
    if items.len() < serial_below {
        let mut scratch = S::default();
        items.iter().map(|x| f(&mut scratch, x)).collect()
    } else {
        items.par_iter().with_min_len(min_len).map_init(S::default, |s, x| f(s, x)).collect()
    }
}

/// The `items` that `keep` holds for, in order, sized as [`map_sized`] sizes its work.
pub(crate) fn filter_sized<T>(
    items: &[T],
    serial_below: usize,
    min_len: usize,
    keep: impl Fn(&T) -> bool + Sync + Send,
) -> Vec<T>
where
    T: Copy + Send + Sync,
{
    if items.len() < serial_below {
        items.iter().copied().filter(|x| keep(x)).collect()
    } else {
        items.par_iter().with_min_len(min_len).copied().filter(|x| keep(x)).collect()
    }
}
