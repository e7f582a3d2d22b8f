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
    let mut out = Vec::new();
    map_sized_into(items, serial_below, min_len, &mut S::default(), &mut out, f);
    out
}

/// [`map_sized`] into `out` (cleared first), reusing its capacity; the serial path uses
/// `scratch`, the parallel one a scratch per task. Allocates nothing on the serial path once
/// `out` and `scratch` have grown, nor on the parallel path beyond the tasks' scratch.
pub(crate) fn map_sized_into<T, S, R>(
    items: &[T],
    serial_below: usize,
    min_len: usize,
    scratch: &mut S,
    out: &mut Vec<R>,
    f: impl Fn(&mut S, &T) -> R + Sync + Send,
) where
    T: Sync,
    S: Default,
    R: Send,
{
    if items.len() < serial_below {
        out.clear();
        out.extend(items.iter().map(|x| f(scratch, x)));
    } else {
        items.par_iter().with_min_len(min_len).map_init(S::default, |s, x| f(s, x)).collect_into_vec(out);
    }
}

/// The `Some` results of `f` over the indices `0..len`, in order, into `out` (cleared
/// first), a chunk of `chunk` indices per task with a list of its own (`parts`, kept for
/// reuse): one tight loop per chunk instead of rayon's shared list folder item by item.
/// Allocates nothing once `out` and `parts` have grown.
pub(crate) fn filter_map_chunks_into<R: Send>(
    len: usize,
    chunk: usize,
    parts: &mut Vec<Vec<R>>,
    out: &mut Vec<R>,
    f: impl Fn(usize) -> Option<R> + Sync + Send,
) {
    out.clear();
    if len <= chunk {
        out.extend((0..len).filter_map(f));
        return;
    }
    let n = len.div_ceil(chunk);
    if parts.len() < n {
        parts.resize_with(n, Vec::new);
    }
    parts[..n].par_iter_mut().enumerate().for_each(|(k, part)| {
        part.clear();
        part.extend((k * chunk..len.min((k + 1) * chunk)).filter_map(&f));
    });
    for part in &mut parts[..n] {
        out.append(part);
    }
}

/// The `items` that `keep` holds for, in order, into `out`, as [`filter_map_chunks_into`].
pub(crate) fn filter_chunks_into<T>(
    items: &[T],
    chunk: usize,
    parts: &mut Vec<Vec<T>>,
    out: &mut Vec<T>,
    keep: impl Fn(&T) -> bool + Sync + Send,
) where
    T: Copy + Send + Sync,
{
    filter_map_chunks_into(items.len(), chunk, parts, out, |i| keep(&items[i]).then_some(items[i]));
}

/// Keeps the `items` that `keep` holds for, in order, sized as [`map_sized`] sizes its work;
/// `flags` is kept for reuse. Allocates nothing once `flags` has grown.
pub(crate) fn retain_sized<T>(
    items: &mut Vec<T>,
    serial_below: usize,
    min_len: usize,
    flags: &mut Vec<bool>,
    keep: impl Fn(&T) -> bool + Sync + Send,
) where
    T: Copy + Send + Sync,
{
    if items.len() < serial_below {
        items.retain(|x| keep(x));
    } else {
        items.par_iter().with_min_len(min_len).map(&keep).collect_into_vec(flags);
        let mut k = 0;
        items.retain(|_| {
            k += 1;
            flags[k - 1]
        });
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The reusing forms give what a plain serial filter or map gives, across chunk and
        /// serial-parallel boundaries, with buffers left over from a longer or shorter run.
        #[test]
        fn reusing_forms_match_a_serial_pass(
            items in prop::collection::vec(0u32..1000, 0..700),
            chunk in 1usize..64,
            serial_below in 0usize..300,
            before in prop::collection::vec(0u32..1000, 0..300),
        ) {
            let keep = |x: &u32| x % 3 != 0;
            let plain: Vec<u32> = items.iter().copied().filter(keep).collect();
            let (mut parts, mut out) = (Vec::new(), Vec::new());
            filter_chunks_into(&before, chunk, &mut parts, &mut out, keep);
            filter_chunks_into(&items, chunk, &mut parts, &mut out, keep);
            prop_assert_eq!(&out, &plain);
            let mut kept = before.clone();
            let mut flags = vec![true; 5];
            retain_sized(&mut kept, serial_below, 1, &mut flags, keep);
            kept.clone_from(&items);
            retain_sized(&mut kept, serial_below, 1, &mut flags, keep);
            prop_assert_eq!(&kept, &plain);
            let mut mapped = before.clone();
            map_sized_into(&items, serial_below, 1, &mut (), &mut mapped, |_: &mut (), &x| x * 2);
            prop_assert_eq!(mapped, items.iter().map(|&x| x * 2).collect::<Vec<_>>());
        }
    }
}
