//! Multiple-choice selection (papers/002 §3.3, after Wu & Kobbelt 2002): no priority queue.
//! Each step draws `d` vertices at random from the pool of vertices that still have an
//! allowed collapse, re-evaluates those marked dirty, and collapses the cheapest of the `d`.
//!
//! ```text
//!   pool: [v7 v2 v9 v4 ...]   draw d (with replacement) -> best of d -> collapse u -> v
//!   then: u leaves the pool; v and its neighbours become dirty and rejoin the pool
//! ```
//! A drawn vertex with no allowed collapse leaves the pool until a neighbour's collapse makes
//! it dirty again; the run ends at the target or when the pool is empty. The random numbers
//! come from a seeded xorshift generator, so a seed reproduces a result exactly.

use super::engine::{Best, Engine};
use super::Progress;

struct Pool {
    items: Vec<u32>,
    slot: Vec<u32>, // position in items, or u32::MAX when absent
}

impl Pool {
    fn insert(&mut self, v: u32) {
        if self.slot[v as usize] == u32::MAX {
            self.slot[v as usize] = self.items.len() as u32;
            self.items.push(v);
        }
    }

    fn remove(&mut self, v: u32) {
        let s = self.slot[v as usize];
        if s == u32::MAX {
            return;
        }
        let last = *self.items.last().unwrap();
        self.items[s as usize] = last;
        self.slot[last as usize] = s;
        self.items.pop();
        self.slot[v as usize] = u32::MAX;
    }
}

/// Collapses until `target_faces` remain or the pool is empty. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, candidates: usize, seed: u64, progress: &Progress) -> usize {
    let n = e.mesh.topology.vertex_count();
    let mut best: Vec<Option<Best>> = vec![None; n];
    let mut dirty = vec![false; n];
    let mut pool = Pool { items: Vec::with_capacity(n), slot: vec![u32::MAX; n] };
    for v in 0..n as u32 {
        best[v as usize] = e.evaluate(v);
        if best[v as usize].is_some() {
            pool.insert(v);
        }
    }
    progress.init_done();
    let mut rng = seed ^ 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let d = candidates.max(1);
    let mut collapses = 0;
    let mut changed = Vec::new();
    while e.live_faces > target_faces && !pool.items.is_empty() {
        let mut pick: Option<(u32, Best)> = None;
        for _ in 0..d {
            if pool.items.is_empty() {
                break;
            }
            let v = pool.items[(next() % pool.items.len() as u64) as usize];
            if dirty[v as usize] {
                best[v as usize] = e.evaluate(v);
                dirty[v as usize] = false;
            }
            match best[v as usize] {
                None => pool.remove(v),
                Some(b) => {
                    if pick.is_none_or(|(pv, pb)| b.cost < pb.cost || (b.cost == pb.cost && v < pv)) {
                        pick = Some((v, b));
                    }
                }
            }
        }
        let Some((u, b)) = pick else { continue };
        e.apply(b, &mut changed);
        collapses += 1;
        progress.tick(e.live_faces);
        pool.remove(u);
        best[u as usize] = None;
        for &w in &changed {
            dirty[w as usize] = true;
            pool.insert(w);
        }
    }
    collapses
}
