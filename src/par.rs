//! Parallel maps sized to their work. A coarsening round or a pass ends with a few hundred
//! items or fewer, and waking a pool for those costs more than the work, the more so the
//! larger the pool (measured on 16 cores: docs/BENCHMARKS.md, "Many cores").

use rayon::prelude::*;

/// Runs `f` on a thread of the current rayon pool: directly when the caller is one, else
/// handed to the pool (the caller waits). A pass that starts from outside the pool hands its
/// job over and puts the caller to sleep until the pool is done, then wakes it: a round of
/// coarsening has several passes, a run has dozens of rounds, and on two cores these hand-offs
/// and the pool's threads spinning beside the sleeping caller cost more than a tenth of the run
/// and most of its spread (docs/BENCHMARKS.md). From inside, a pass forks and joins on
/// threads that are already awake, and the serial steps between passes run on one of them.
pub(crate) fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() {
        f()
    } else {
        rayon::scope(|_| f())
    }
}

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

/// `f` over `items` for its effects, sized and with scratch as [`map_sized`].
pub(crate) fn for_each_sized<T, S>(
    items: &[T],
    serial_below: usize,
    min_len: usize,
    f: impl Fn(&mut S, &T) + Sync + Send,
) where
    T: Sync,
    S: Default,
{
    if items.len() < serial_below {
        let mut scratch = S::default();
        items.iter().for_each(|x| f(&mut scratch, x));
    } else {
        items.par_iter().with_min_len(min_len).for_each_init(S::default, |s, x| f(s, x));
    }
}

/// The `Some` results of `f` over `items`, in order, sized and with scratch as [`map_sized`]:
/// for a pass whose results are mostly `None`, without a list of them all.
pub(crate) fn filter_map_sized<T, S, R>(
    items: &[T],
    serial_below: usize,
    min_len: usize,
    f: impl Fn(&mut S, &T) -> Option<R> + Sync + Send,
) -> Vec<R>
where
    T: Sync,
    S: Default,
    R: Send,
{
    if items.len() < serial_below {
        let mut scratch = S::default();
        items.iter().filter_map(|x| f(&mut scratch, x)).collect()
    } else {
        items.par_iter().with_min_len(min_len).map_init(S::default, |s, x| f(s, x)).flatten_iter().collect()
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
