//! Batched selection: passes of independent collapses, cheapest first, in the manner of
//! meshoptimizer's passes — but every collapse fully checked (link condition, wedges, flips),
//! and the checks and the costing spread over the threads.
//!
//! ```text
//!   pass:  list every vertex with a collapse in view by (key, id)   (key: checked cost or bound)
//!          keep those up to 1.5x the key at rank len/5 (or at the rank of the collapses still
//!            needed, if fewer) and sort them
//!          pick along the order: u goes when no vertex of its closed neighbourhood N[u] is
//!            locked yet, then locks N[u]; stop at the collapses still needed        (serial)
//!          check each pick on the pass's state                                  (parallel)
//!          apply the picks that pass, in pick order; keep or mark their neighbours' bounds
//!                                                                                 (serial)
//!          fresh bounds for the marked vertices                                  (parallel)
//! ```
//! Why no pick needs a re-check: two picks' closed neighbourhoods are disjoint, and a collapse
//! u → v writes only inside N[u] (u's faces, the twins of edges between vertices of N[u],
//! `vertex_he` of v and the wings, v's quadric, u's corners), while a check of u2 reads only
//! u2's fan, its targets' and wings' fans (edges with an end in N[u2]) and their quadrics.
//! So each pick's check holds after the others are applied, and the pass equals applying its
//! picks one after another in any order. The bounds kept across a collapse follow the greedy
//! queue's rules ([`Engine::bound_update`]). Every step is a pure function of the mesh or runs in a fixed
//! order, so the result does not depend on the thread count.

use rayon::prelude::*;

use super::engine::{Best, Bound, BoundUpdate, Engine, Scratch, Touched};
use super::Progress;
use crate::topology::Topology;

/// A pass considers the vertices whose key is at most this factor of the key at rank
/// `len / CONSIDERED_PART` (or at the rank of the collapses still needed, if fewer): without
/// a ceiling, vertices locked out by cheaper picks would be replaced by far costlier collapses
/// elsewhere (meshoptimizer's passes use the same factor).
const CEILING_FACTOR: f64 = 1.5;

/// See [`CEILING_FACTOR`].
const CONSIDERED_PART: usize = 5;

/// A cost as bits whose unsigned order is `f64::total_cmp`'s (a plain integer compare sorts
/// several times faster than the float one).
fn ordered_bits(k: f64) -> u64 {
    let b = k.to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | 1 << 63
    }
}

/// Collapses until `target_faces` remain or nothing is allowed. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, progress: &Progress) -> usize {
    let n = e.mesh.topology.vertex_count();
    let mut bounds = e.initial_bounds();
    // The fully checked collapse of a vertex, while nothing around it has changed since.
    let mut checked: Vec<Option<Best>> = vec![None; n];
    let mut stale = vec![false; n];
    let mut locked = vec![false; n];
    progress.init_done();
    let mut touched = Touched::default();
    let mut collapses = 0;
    let mut order: Vec<(u64, u32)> = Vec::new();
    let mut rings: Vec<Ring> = Vec::new();
    let mut picks: Vec<u32> = Vec::new();
    // Where each pick's ring is in `rings`.
    let mut picked: Vec<usize> = Vec::new();
    let mut marked: Vec<u32> = Vec::new();
    let mut refreshed: Vec<u32> = Vec::new();
    let mut listed: Vec<u32> = (0..n as u32).collect();
    let mut in_list = vec![true; n];
    while e.live_faces > target_faces {
        let key = |v: usize| checked[v].map(|b| b.cost).or(bounds[v].map(|b| b.cost));
        // The vertices with a collapse in view: those of the last pass that still have one,
        // and those that got one back from a fresh bound.
        listed.retain(|&v| {
            let keep = key(v as usize).is_some();
            in_list[v as usize] = keep;
            keep
        });
        for &w in &refreshed {
            if !in_list[w as usize] && key(w as usize).is_some() {
                in_list[w as usize] = true;
                listed.push(w);
            }
        }
        refreshed.clear();
        if listed.is_empty() {
            break;
        }
        // Interior collapses remove two faces, border ones one.
        let goal = (e.live_faces - target_faces).div_ceil(2);
        // Only the cheapest part of the list is sorted and walked: up to CEILING_FACTOR times
        // the key at rank `consider` (a fifth of the list, or the collapses still needed).
        order.clear();
        order.par_extend(listed.par_iter().map(|&v| (ordered_bits(key(v as usize).unwrap_or(f64::INFINITY)), v)));
        let consider = goal.min(order.len() / CONSIDERED_PART).max(1);
        if consider < order.len() {
            let (_, &mut (bits, v), _) = order.select_nth_unstable(consider);
            // Never below the key at that rank: costs can come out a rounding error below
            // zero (flat regions), where 1.5x is lower, and the pass would keep nothing.
            let ceiling = bits.max(ordered_bits(CEILING_FACTOR * key(v as usize).unwrap_or(f64::INFINITY)));
            order.retain(|&(k, _)| k <= ceiling);
        }
        order.par_sort_unstable();
        let t = &e.mesh.topology;
        // The neighbours of every vertex in view, listed in parallel so the serial walk below
        // reads them from one array.
        rings.clear();
        rings.par_extend(order.par_iter().map(|&(_, u)| Ring::of(t, u)));
        picks.clear();
        picked.clear();
        for (i, (&(_, u), ring)) in order.iter().zip(&rings).enumerate() {
            if picks.len() >= goal {
                break;
            }
            if locked[u as usize] || ring.any(t, u, |w| locked[w as usize]) {
                continue;
            }
            locked[u as usize] = true;
            ring.for_each(t, u, |w| locked[w as usize] = true);
            picks.push(u);
            picked.push(i);
        }
        // The cheapest listed vertex is always picked: nothing is locked before it.
        debug_assert!(!picks.is_empty(), "a pass with nothing picked would repeat forever");
        for (&u, &i) in picks.iter().zip(&picked) {
            locked[u as usize] = false;
            rings[i].for_each(t, u, |w| locked[w as usize] = false);
        }
        let engine: &Engine<'_> = e;
        let results: Vec<Option<Best>> = picks
            .par_iter()
            .map_init(Scratch::default, |sc, &u| {
                checked[u as usize].or_else(|| engine.check_from_bound(u, bounds[u as usize], sc))
            })
            .collect();
        // The key of the last pick: a checked cost above it waits for a later pass.
        let last = picks.last().and_then(|&u| key(u as usize)).unwrap_or(f64::INFINITY);
        for (&u, result) in picks.iter().zip(results) {
            #[cfg(test)]
            if result.is_none() {
                assert!(e.evaluate_with(u, &mut Scratch::default()).is_none(), "pick {u} gained a collapse");
            }
            let Some(b) = result else {
                // Nothing allowed until a neighbour's faces change.
                bounds[u as usize] = None;
                checked[u as usize] = None;
                continue;
            };
            if b.cost > last {
                checked[u as usize] = Some(b);
                continue;
            }
            // Test builds: the check made on the pass's state still holds after the picks
            // applied before this one (the independence argument in the module docs).
            #[cfg(test)]
            assert_eq!(
                Some(b),
                e.evaluate_with(u, &mut Scratch::default()),
                "pick {u}: an earlier pick of the pass changed its collapse"
            );
            e.apply(b, &mut touched);
            collapses += 1;
            progress.tick(e.live_faces);
            bounds[u as usize] = None;
            checked[u as usize] = None;
            keep_or_mark(e, &touched, b.target, &mut bounds, &mut checked, &mut stale, &mut marked);
            if e.live_faces <= target_faces {
                break;
            }
        }
        let engine: &Engine<'_> = e;
        let fresh: Vec<Option<Bound>> =
            marked.par_iter().map_init(Scratch::default, |sc, &w| engine.bound(w, sc)).collect();
        for (&w, b) in marked.iter().zip(fresh) {
            bounds[w as usize] = b;
            stale[w as usize] = false;
        }
        refreshed.append(&mut marked);
    }
    collapses
}

/// After a collapse into `target`: each touched vertex keeps (or gets without a fan walk) the
/// bound a fresh evaluation would give ([`Engine::bound_update`]), or is marked for a fresh
/// one after the pass. A vertex already marked stays marked: its fresh bound will read the
/// final state. A vertex with no bound is out of the running.
fn keep_or_mark(
    e: &Engine<'_>,
    touched: &Touched,
    target: u32,
    bounds: &mut [Option<Bound>],
    checked: &mut [Option<Best>],
    stale: &mut [bool],
    marked: &mut Vec<u32>,
) {
    for &(w, change) in &touched.vertices {
        let wu = w as usize;
        checked[wu] = None;
        if stale[wu] {
            continue;
        }
        match e.bound_update(w, change, bounds[wu], bounds[wu].is_some(), touched.removed, target) {
            BoundUpdate::Keep => {}
            BoundUpdate::New(b) => bounds[wu] = b,
            BoundUpdate::Fresh => {
                stale[wu] = true;
                marked.push(w);
            }
        }
    }
}

/// A vertex's neighbours, or `len == u8::MAX` when there are more than fit (then walked).
#[derive(Clone, Copy)]
struct Ring {
    len: u8,
    ids: [u32; 15],
}

impl Ring {
    fn of(t: &Topology, u: u32) -> Ring {
        let mut r = Ring { len: 0, ids: [0; 15] };
        for w in t.neighbors(u) {
            if r.len as usize == r.ids.len() {
                return Ring { len: u8::MAX, ..r };
            }
            r.ids[r.len as usize] = w;
            r.len += 1;
        }
        r
    }

    /// Calls `f` on every neighbour of `u`.
    fn for_each(&self, t: &Topology, u: u32, mut f: impl FnMut(u32)) {
        self.any(t, u, |w| {
            f(w);
            false
        });
    }

    /// Whether `f` holds for a neighbour of `u` (calls it in order until it does).
    fn any(&self, t: &Topology, u: u32, mut f: impl FnMut(u32) -> bool) -> bool {
        if self.len == u8::MAX {
            t.neighbors(u).any(f)
        } else {
            self.ids[..self.len as usize].iter().any(|&w| f(w))
        }
    }
}
