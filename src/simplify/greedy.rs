//! Greedy selection (Garland & Heckbert 1997): always the cheapest allowed collapse first.
//!
//! Lazily checked: the queue holds each vertex's [`Engine::bound`] (its cheapest target
//! before the link, wedge and flip checks) until it reaches the top; only then is the vertex
//! fully evaluated. If the checked cost equals the bound the collapse is made at once,
//! otherwise the vertex goes back with its checked cost. A bound never exceeds the checked
//! cost, so what comes off the top checked is the cheapest allowed collapse of all — the same
//! choice (ties: the smaller vertex id) as evaluating every vertex fully after every collapse,
//! at a fraction of the checks. After a collapse the target and the vertices whose faces
//! changed get fresh bounds, updated in place in an indexed heap (one slot per vertex); the
//! target's other neighbours keep theirs unless their cost into the target can have changed
//! it ([`super::engine::Change`]).

use super::engine::{Best, Bound, BoundUpdate, Engine, Scratch, Touched};
use super::indexed_heap::IndexedHeap;
use super::Progress;

/// Collapses until `target_faces` remain or nothing is allowed. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, progress: &Progress) -> usize {
    let n = e.mesh.topology.vertex_count();
    let mut bounds = e.initial_bounds();
    let items = bounds.iter().enumerate().filter_map(|(v, b)| b.map(|b| (b.cost, v as u32))).collect();
    let mut heap = IndexedHeap::from_items(n, items);
    // The fully checked collapse of a vertex whose key is its checked cost (else its bound).
    let mut checked: Vec<Option<Best>> = vec![None; n];
    progress.init_done();
    let mut sc = Scratch::default();
    let mut collapses = 0;
    let mut touched = Touched::default();
    while e.live_faces > target_faces {
        let Some((cost, v)) = heap.peek() else { break };
        let b = match checked[v as usize] {
            Some(b) => b,
            None => match e.evaluate_from_bound(v, bounds[v as usize]) {
                None => {
                    heap.remove(v); // nothing allowed until a neighbour's faces change
                    continue;
                }
                Some(b) if b.cost == cost => b,
                Some(b) => {
                    checked[v as usize] = Some(b);
                    heap.set(v, b.cost);
                    continue;
                }
            },
        };
        e.apply(b, &mut touched);
        collapses += 1;
        progress.tick(e.live_faces);
        heap.remove(v);
        checked[v as usize] = None;
        for &(w, change) in &touched.vertices {
            let wu = w as usize;
            let in_running = heap.contains(w);
            let update = e.bound_rule(w, change, bounds[wu], in_running, touched.removed, b.target, || {
                e.target_cost(w, b.target)
            });
            #[cfg(test)]
            e.assert_bound_update(w, update, bounds[wu]);
            match update {
                BoundUpdate::Fresh => fresh_bound(e, w, &mut sc, &mut heap, &mut bounds, &mut checked),
                BoundUpdate::New(nb) => {
                    checked[wu] = None;
                    bounds[wu] = nb;
                    if let Some(nb) = nb {
                        heap.set(w, nb.cost);
                    }
                }
                // A checked collapse is stale: back to the bound's key.
                BoundUpdate::Keep => {
                    if checked[wu].take().is_some() {
                        heap.set(w, bounds[wu].map_or(f64::INFINITY, |b| b.cost));
                    }
                }
            }
        }
    }
    collapses
}

/// Recomputes `w`'s bound and re-keys it (or takes it out when it has no target left).
fn fresh_bound(
    e: &Engine<'_>,
    w: u32,
    sc: &mut Scratch,
    heap: &mut IndexedHeap,
    bounds: &mut [Option<Bound>],
    checked: &mut [Option<Best>],
) {
    checked[w as usize] = None;
    bounds[w as usize] = e.bound(w, sc);
    match bounds[w as usize] {
        Some(b) => heap.set(w, b.cost),
        None => heap.remove(w),
    }
}
