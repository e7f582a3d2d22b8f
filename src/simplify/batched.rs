//! Batched selection: passes of independent collapses, cheapest first, in the manner of
//! meshoptimizer's passes — but every collapse fully checked (link condition, wedges, flips),
//! and the checks, the costing and the reading half of every collapse spread over the threads.
//!
//! ```text
//!   pass:  list every vertex with a collapse in view by (key, id)   (key: checked cost or bound)
//!          keep those up to 1.5x the key at rank len/5 (or at the rank of the collapses still
//!            needed, if fewer) and sort them
//!          pick along the order: u goes when no vertex of its closed neighbourhood N[u] is
//!            locked yet, then locks N[u]; stop at the collapses still needed        (serial)
//!          check each pick on the pass's state                                  (parallel)
//!          work out every store of the picks that go, and what each touches,
//!            on the pass's state                                                (parallel)
//!          make the stores, in pick order                         (serial, no reads to wait on)
//!          run the bound rules for the touched vertices, in pick order           (serial)
//!          fresh bounds for the vertices the rules marked                         (parallel)
//! ```
//! Why no pick needs a re-check: two picks' closed neighbourhoods are disjoint, and a collapse
//! u → v writes only inside `N[u]` (u's faces, the twins of edges between vertices of `N[u]`,
//! `vertex_he` of v and the wings, v's quadric, u's corners), while a check of u2 reads only
//! u2's fan, its targets' and wings' fans (edges with an end in `N[u2]`) and their quadrics.
//! So each pick's check holds after the others are applied, and the pass equals applying its
//! picks one after another in any order. The same argument covers the collapse's own reads
//! ([`HalfEdges::collapse_writes`]): its stores are worked out on the pass's state and made
//! later. The bounds kept across a collapse follow the greedy queue's rules
//! ([`Engine::bound_rule`]), which read quadrics but no connectivity: run after the whole
//! pass in pick order, they decide what they would have decided after each collapse. Every
//! step is a pure function of the mesh or runs in a fixed order, so the result does not
//! depend on the thread count.

use rayon::prelude::*;

use super::attribute_quadric::AttributeQuadrics;
use super::engine::{Best, Bound, BoundUpdate, Change, Engine, Scratch, TargetCost};
use super::quadric::Quadric;
use super::Progress;
use crate::mesh::constraints::{self, MeshCollapseWrites};
use crate::mesh::Mesh;
use crate::topology::{HalfEdges, Topology, INVALID};

/// A pass considers the vertices whose key is at most this factor of the key at rank
/// `len / CONSIDERED_PART` (or at the rank of the collapses still needed, if fewer): without
/// a ceiling, vertices locked out by cheaper picks would be replaced by far costlier collapses
/// elsewhere (meshoptimizer's passes use the same factor).
pub(super) const CEILING_FACTOR: f64 = 1.5;

/// See [`CEILING_FACTOR`].
const CONSIDERED_PART: usize = 5;

/// Fewest elements a parallel step of a pass hands one task, so that a task holds some tens
/// of microseconds of work: a pass's steps are short (a fraction of a millisecond each on the
/// bunny), and split finer, waking the threads of a large pool costs more than the work
/// (measured on 16 cores: docs/BENCHMARKS.md). For a collapse check or a collapse's stores
/// (about a microsecond each, or cache misses; the touched sets go in chunks of
/// [`TOUCH_CHUNK`], as many)...
const CHECK_TASK: usize = 64;

/// ...for a ring or a fresh bound (a few tenths of a microsecond)...
const TASK: usize = 256;

/// ...and for a key read while listing (a few loads).
const LIST_TASK: usize = 4096;

/// A cost as bits whose unsigned order is `f64::total_cmp`'s (a plain integer compare sorts
/// several times faster than the float one).
pub(super) fn ordered_bits(k: f64) -> u64 {
    let b = k.to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | 1 << 63
    }
}

/// The cost whose [`ordered_bits`] are `b`.
pub(super) fn from_ordered_bits(b: u64) -> f64 {
    f64::from_bits(if b >> 63 == 1 { b & !(1 << 63) } else { !b })
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
    let mut going: Vec<Best> = Vec::new();
    let mut writes: Vec<(MeshCollapseWrites, Quadric)> = Vec::new();
    let mut touched: Vec<Vec<Touch>> = Vec::new();
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
        order.par_extend(
            listed
                .par_iter()
                .with_min_len(LIST_TASK)
                .map(|&v| (ordered_bits(key(v as usize).unwrap_or(f64::INFINITY)), v)),
        );
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
        rings.par_extend(order.par_iter().with_min_len(TASK).map(|&(_, u)| Ring::of(t, u)));
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
            .with_min_len(CHECK_TASK)
            .map_init(Scratch::default, |sc, &u| {
                checked[u as usize].or_else(|| engine.check_from_bound(u, bounds[u as usize], sc))
            })
            .collect();
        // The key of the last pick: a checked cost above it waits for a later pass.
        let last = picks.last().and_then(|&u| key(u as usize)).unwrap_or(f64::INFINITY);
        // The picks that go, in pick order, until the faces still to remove are gone.
        going.clear();
        let mut to_remove = e.live_faces - target_faces;
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
            going.push(b);
            bounds[u as usize] = None;
            checked[u as usize] = None;
            // Interior collapses remove two faces, border ones one.
            let faces = if t.twin[b.collapse.he as usize] == INVALID { 1 } else { 2 };
            if faces >= to_remove {
                break;
            }
            to_remove -= faces;
        }
        // Every store of every collapse, and what each touches, worked out on the pass's
        // state: no pick writes what another reads (module docs).
        let mesh: &Mesh = e.mesh;
        let quadrics = &e.quadrics;
        going
            .par_iter()
            .with_min_len(CHECK_TASK)
            .map(|b| {
                let mut q = quadrics[b.target as usize];
                q += quadrics[b.collapse.remove as usize];
                (constraints::collapse_writes(mesh, b.collapse), q)
            })
            .collect_into_vec(&mut writes);
        let engine: &Engine<'_> = e;
        going
            .par_chunks(TOUCH_CHUNK)
            .zip(writes.par_chunks(TOUCH_CHUNK))
            .map(|(bs, ws)| {
                let mut out = Vec::with_capacity(bs.len() * 16);
                bs.iter().zip(ws).for_each(|(b, (_, q_v))| touched_by(engine, b, q_v, &mut out));
                out
            })
            .collect_into_vec(&mut touched);
        // Attribute quadrics move with their wedges, on the pass's state like the stores.
        let merges: Vec<_> = match &e.attributes {
            Some(_) => going.iter().map(|b| AttributeQuadrics::merges(e.mesh, b.collapse, b.target)).collect(),
            None => Vec::new(),
        };
        for (i, (b, (w, q))) in going.iter().zip(&writes).enumerate() {
            // Test builds: the collapse, and every store it makes, are what they would be
            // after the picks written before it (the independence argument).
            #[cfg(test)]
            {
                let u = b.collapse.remove;
                let again = e.evaluate_with(u, &mut Scratch::default());
                assert_eq!(Some(*b), again, "pick {u}: an earlier pick of the pass changed its collapse");
                assert_eq!(*w, constraints::collapse_writes(e.mesh, b.collapse), "pick {u}: stores changed");
            }
            e.quadrics[b.target as usize] = *q;
            e.free[b.target as usize] &= e.free[b.collapse.remove as usize];
            if let Some(a) = &mut e.attributes {
                let (pairs, n) = merges[i];
                a.merge(&pairs[..n]);
            }
            let removed = constraints::write_collapse(e.mesh, w);
            e.live_faces -= removed.iter().filter(|&&f| f != INVALID).count();
            e.max_error = e.max_error.max(b.error);
            progress.tick(e.live_faces);
        }
        collapses += going.len();
        // The bound rules read no connectivity, only w's collapse into the target (`cost_v`,
        // from the target's quadric after its collapse and w's at the start of the pass), so
        // running them now, in pick order, decides what running them after each collapse
        // would. w's own quadric changes in the pass only if w is another pick's target, and
        // a target is always marked for a fresh bound, which ends its rules.
        for &Touch { vertex: w, change, removed, target, cost_v } in touched.iter().flatten() {
            let wu = w as usize;
            checked[wu] = None;
            if stale[wu] {
                continue;
            }
            // With attributes, `cost_v` (worked out ahead of the writes) lacks the merged
            // attribute quadrics: a fresh bound.
            let update = if e.attributes.is_some() {
                BoundUpdate::Fresh
            } else {
                e.bound_rule(w, change, bounds[wu], bounds[wu].is_some(), removed, target, || cost_v)
            };
            match update {
                BoundUpdate::Keep => {}
                BoundUpdate::New(b) => bounds[wu] = b,
                BoundUpdate::Fresh => {
                    stale[wu] = true;
                    marked.push(w);
                }
            }
        }
        let engine: &Engine<'_> = e;
        let fresh: Vec<Option<Bound>> =
            marked.par_iter().with_min_len(TASK).map_init(Scratch::default, |sc, &w| engine.bound(w, sc)).collect();
        for (&w, b) in marked.iter().zip(fresh) {
            bounds[w as usize] = b;
            stale[w as usize] = false;
        }
        // Test builds: every bound the rules kept or derived is what a fresh evaluation gives
        // on the state after the pass.
        #[cfg(test)]
        for &Touch { vertex: w, .. } in touched.iter().flatten() {
            let b = bounds[w as usize];
            e.assert_bound_update(w, BoundUpdate::New(b), b);
        }
        refreshed.append(&mut marked);
    }
    collapses
}

/// Appends the vertices the collapse `b` touches, read on the state before it: v and u's
/// other neighbours (their faces change), then v's neighbours that were not u's (only v's
/// quadric changes for them). After the collapse these are v and its neighbours. Each comes
/// with its collapse into v as the bound rules read it, from v's quadric after the collapse
/// (`q_v`).
fn touched_by(e: &Engine<'_>, b: &Best, q_v: &Quadric, out: &mut Vec<Touch>) {
    let t = &e.mesh.topology;
    let (u, v) = (b.collapse.remove, b.target);
    let from = out.len();
    let touch = |w: u32, change: Change| Touch {
        vertex: w,
        change,
        removed: u,
        target: v,
        cost_v: e.target_cost_with(w, q_v, v),
    };
    // The target's rule is always a fresh bound: it reads no cost.
    out.push(Touch {
        vertex: v,
        change: Change::Faces,
        removed: u,
        target: v,
        cost_v: TargetCost { cost: f64::NAN, distance: f64::NAN },
    });
    out.extend(t.neighbors(u).filter(|&w| w != v).map(|w| touch(w, Change::Faces)));
    for w in t.neighbors(v) {
        if w != u && !out[from..].iter().any(|x| x.vertex == w) {
            out.push(touch(w, Change::TargetOnly));
        }
    }
}

/// A vertex touched by a collapse, with what may have changed for it ([`Change`]), the
/// collapse's removed vertex and target, and its own collapse into the target.
#[derive(Clone, Copy)]
struct Touch {
    vertex: u32,
    change: Change,
    removed: u32,
    target: u32,
    cost_v: TargetCost,
}

/// Picks per task when listing what they touch (one buffer per task).
const TOUCH_CHUNK: usize = 64;

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

#[cfg(test)]
mod ordered_bits_tests {
    use super::{from_ordered_bits, ordered_bits};

    /// The bits sort as `total_cmp` does, and give the cost back bit for bit.
    #[test]
    fn ordered_bits_sort_like_total_cmp_and_invert() {
        let costs = [f64::NEG_INFINITY, -2.5, -1e-300, -0.0, 0.0, 1e-300, 3.0, f64::INFINITY];
        for w in costs.windows(2) {
            assert!(ordered_bits(w[0]) < ordered_bits(w[1]), "{} < {}", w[0], w[1]);
        }
        for c in costs {
            assert_eq!(from_ordered_bits(ordered_bits(c)).to_bits(), c.to_bits());
        }
    }
}
