//! Greedy selection (Garland & Heckbert 1997): every vertex's best collapse in a priority
//! queue, always the cheapest first; after each collapse the target and its neighbours are
//! re-evaluated and pushed again (stale entries are skipped by a per-vertex stamp).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::engine::{Best, Engine};
use super::Progress;

#[derive(PartialEq)]
struct Entry {
    cost: f64,
    vertex: u32,
    stamp: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on cost, then on vertex id for determinism.
        o.cost.total_cmp(&self.cost).then_with(|| o.vertex.cmp(&self.vertex))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Collapses until `target_faces` remain or nothing is allowed. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, progress: &Progress) -> usize {
    let n = e.mesh.topology.vertex_count();
    let mut best: Vec<Option<Best>> = vec![None; n];
    let mut stamp = vec![0u32; n];
    let mut heap = BinaryHeap::with_capacity(n);
    for v in 0..n as u32 {
        best[v as usize] = e.evaluate(v);
        if let Some(b) = best[v as usize] {
            heap.push(Entry { cost: b.cost, vertex: v, stamp: 0 });
        }
    }
    progress.init_done();
    let mut collapses = 0;
    let mut dirty = Vec::new();
    while e.live_faces > target_faces {
        let Some(top) = heap.pop() else { break };
        let v = top.vertex as usize;
        if top.stamp != stamp[v] {
            continue;
        }
        let Some(b) = best[v] else { continue };
        e.apply(b, &mut dirty);
        collapses += 1;
        progress.tick(e.live_faces);
        best[v] = None;
        stamp[v] += 1;
        for &w in &dirty {
            let w = w as usize;
            let fresh = e.evaluate(w as u32);
            if fresh == best[w] {
                continue; // its queue entry is still right
            }
            stamp[w] += 1;
            best[w] = fresh;
            if let Some(b) = fresh {
                heap.push(Entry { cost: b.cost, vertex: w as u32, stamp: stamp[w] });
            }
        }
    }
    collapses
}
