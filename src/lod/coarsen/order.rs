//! The order candidates act in: [`Schedule::LocalMinima`](super::Schedule::LocalMinima)'s local minima and §5's "outranks" (papers/000).

use crate::topology::{HalfEdges, Topology};

/// [`Schedule::LocalMinima`](super::Schedule::LocalMinima)'s order. Vertices that have been stuck (no legal move even
/// alone) go after the others: they are woken whenever a neighbour changes and are usually
/// stuck again, and in front they would hold their waiting neighbours back a round each time
/// (on CAD models, with many seam and corner vertices, the run hit the round cap). Then the
/// lower error first; ties (flat regions, where every e(V) is 0) by a scrambled id, so that a
/// row of tied vertices numbered in order does not go one per round (with plain ids only the
/// row's first vertex would be a local minimum). A total order: `scramble` is a bijection.
pub(crate) fn goes_first((s, e, v): (bool, f32, u32), (t, f, w): (bool, f32, u32)) -> bool {
    s.cmp(&t).then(e.total_cmp(&f)).then(scramble(v).cmp(&scramble(w))).is_lt()
}

/// The first neighbouring candidate of `v` (fan order) that goes before it in `key`'s
/// [`goes_first`] order; `None` when v is a local minimum and acts this round.
pub(crate) fn first_ahead(t: &Topology, v: u32, cand: &[bool], key: impl Fn(u32) -> (bool, f32, u32)) -> Option<u32> {
    let kv = key(v);
    t.neighbors(v).find(|&w| cand[w as usize] && goes_first(key(w), kv))
}

/// A bijection on u32 that scatters consecutive ids (a multiply-xorshift mixer; each step is
/// invertible).
fn scramble(v: u32) -> u32 {
    let mut x = v.wrapping_mul(0x9E37_79B1);
    x ^= x >> 16;
    x = x.wrapping_mul(0x85EB_CA6B);
    x ^ (x >> 13)
}

/// §5's "e(VR) is greater than the error of every neighbouring candidate", with ties broken
/// by the larger vertex id. Without the tie-break a ring of equal errors (any flat region:
/// e(V) = 0 there) would be ignored as a whole and never resolved.
pub(crate) fn outranks((e, v): (f32, u32), (f, w): (f32, u32)) -> bool {
    e > f || (e == f && v > w)
}
