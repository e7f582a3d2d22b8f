//! Greedy selection (Garland & Heckbert 1997): always the cheapest allowed collapse first.
//!
//! Lazily checked: the queue holds each vertex's [`Engine::bound`] (its cheapest target
//! before the link, wedge and flip checks) until it reaches the top; only then is the vertex
//! fully evaluated. If the checked cost equals the bound the collapse is made at once,
//! otherwise the vertex goes back with its checked cost. A bound never exceeds the checked
//! cost, so what comes off the top checked is the cheapest allowed collapse of all — the same
//! choice (ties: the smaller vertex id) as evaluating every vertex fully after every collapse,
//! at a fraction of the checks. After a collapse the target and its neighbours get fresh
//! bounds, updated in place in an indexed heap (one slot per vertex).

use super::engine::{Best, Engine, Scratch};
use super::indexed_heap::IndexedHeap;
use super::Progress;

/// Collapses until `target_faces` remain or nothing is allowed. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, progress: &Progress) -> usize {
    let n = e.mesh.topology.vertex_count();
    let bounds = e.initial_bounds();
    let items = bounds.iter().enumerate().filter_map(|(v, b)| b.map(|cost| (cost, v as u32))).collect();
    let mut heap = IndexedHeap::from_items(n, items);
    // The fully checked collapse of a vertex whose key is its checked cost (else a bound).
    let mut checked: Vec<Option<Best>> = vec![None; n];
    progress.init_done();
    let mut sc = Scratch::default();
    let mut collapses = 0;
    let mut dirty = Vec::new();
    while e.live_faces > target_faces {
        let Some((cost, v)) = heap.peek() else { break };
        let b = match checked[v as usize] {
            Some(b) => b,
            None => match e.evaluate(v) {
                None => {
                    heap.remove(v); // nothing allowed until a neighbour changes
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
        e.apply(b, &mut dirty);
        collapses += 1;
        progress.tick(e.live_faces);
        heap.remove(v);
        checked[v as usize] = None;
        for &w in &dirty {
            checked[w as usize] = None;
            match e.bound(w, &mut sc) {
                Some(c) => heap.set(w, c),
                None => heap.remove(w),
            }
        }
    }
    collapses
}
