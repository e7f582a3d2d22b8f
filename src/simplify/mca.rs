//! Multiple-choice selection (papers/002 §3.3, after Wu & Kobbelt 2002): no priority queue.
//! Each step draws `d` vertices at random from the pool of vertices that still have an
//! allowed collapse, and collapses the cheapest of the `d`. Lazily checked, as the greedy
//! queue: a drawn vertex carries its [`Engine::bound`] until it is the cheapest of the draw,
//! and only then gets the full link, wedge and flip checks (bound ≤ checked cost, so the
//! result is the cheapest allowed collapse of the `d`, with a fraction of the checks).
//!
//! ```text
//!   pool: [v7 v2 v9 v4 ...]   draw d (with replacement) -> best of d -> collapse u -> v
//!   then: u leaves the pool; v and its neighbours become dirty and rejoin the pool
//! ```
//! A drawn vertex with no allowed collapse leaves the pool until a neighbour's collapse makes
//! it dirty again; the run ends at the target or when the pool is empty. The random numbers
//! come from a seeded xorshift generator, so a seed reproduces a result exactly.

use super::engine::{Best, Bound, Change, Engine, Scratch, Touched};
use super::Progress;
use crate::topology::INVALID;

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

/// One vertex's draw state in 24 bytes, so that drawing and comparing a vertex reads one
/// cache line: its bound (valid unless `dirty`; `target == INVALID`: none) and its key — the
/// cost of its checked collapse while the run holds one, else the bound's cost.
#[derive(Clone, Copy)]
struct Slot {
    key: f64,
    cost: f64,
    target: u32,
    dirty: bool,
}

impl Slot {
    fn new(b: Option<Bound>) -> Self {
        let mut s = Slot { key: 0.0, cost: 0.0, target: INVALID, dirty: false };
        s.set_bound(b);
        s
    }

    fn bound(&self) -> Option<Bound> {
        (self.target != INVALID).then_some(Bound { cost: self.cost, target: self.target })
    }

    /// A new bound: nothing is checked against it yet, so it is also the key.
    fn set_bound(&mut self, b: Option<Bound>) {
        (self.cost, self.target) = b.map_or((f64::INFINITY, INVALID), |b| (b.cost, b.target));
        self.key = self.cost;
    }

    /// Forgets the checked collapse (the caller clears it in `checked`): the key is the
    /// bound's cost again.
    fn uncheck(&mut self) {
        self.key = self.cost;
    }
}

/// Collapses until `target_faces` remain or the pool is empty. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, candidates: usize, seed: u64, progress: &Progress) -> usize {
    let n = e.mesh.topology.vertex_count();
    let mut slots: Vec<Slot> = e.initial_bounds().into_iter().map(Slot::new).collect();
    // The fully checked collapse of a vertex whose key is its checked cost (read at the pick).
    let mut checked: Vec<Option<Best>> = vec![None; n];
    let mut pool = Pool { items: Vec::with_capacity(n), slot: vec![u32::MAX; n] };
    for (v, s) in slots.iter().enumerate() {
        if s.target != INVALID {
            pool.insert(v as u32);
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
    let mut sc = Scratch::default();
    let mut collapses = 0;
    let mut touched = Touched::default();
    let mut drawn: Vec<u32> = Vec::with_capacity(d);
    while e.live_faces > target_faces && !pool.items.is_empty() {
        drawn.clear();
        for _ in 0..d {
            if pool.items.is_empty() {
                break;
            }
            let v = pool.items[(next() % pool.items.len() as u64) as usize];
            let s = &mut slots[v as usize];
            if s.dirty {
                s.dirty = false;
                s.set_bound(e.bound(v, &mut sc));
                if s.target == INVALID {
                    pool.remove(v);
                    continue;
                }
            }
            #[cfg(test)]
            assert_eq!(slots[v as usize].bound(), e.bound(v, &mut sc), "vertex {v} kept a stale bound");
            drawn.push(v);
        }
        // The cheapest drawn by key; check it; until the cheapest is checked.
        let pick = loop {
            let Some(&v) =
                drawn.iter().min_by(|&&a, &&b| slots[a as usize].key.total_cmp(&slots[b as usize].key).then(a.cmp(&b)))
            else {
                break None;
            };
            if let Some(b) = checked[v as usize] {
                break Some((v, b));
            }
            let s = &mut slots[v as usize];
            match e.evaluate_from_bound(v, s.bound()) {
                None => {
                    pool.remove(v);
                    drawn.retain(|&w| w != v);
                }
                Some(b) => {
                    checked[v as usize] = Some(b);
                    s.key = b.cost;
                }
            }
        };
        let Some((u, b)) = pick else { continue };
        e.apply(b, &mut touched);
        collapses += 1;
        progress.tick(e.live_faces);
        pool.remove(u);
        checked[u as usize] = None;
        for &(w, change) in &touched.vertices {
            // Back into the pool in the same order (the draws stay the same); a fresh bound only
            // where it can have changed, or where there was none (so the draw drops it as before).
            let s = &mut slots[w as usize];
            if change == Change::Faces && !s.dirty && w != b.target {
                // A clean bound updated without the fan walk where that is exact.
                match e.faces_changed_bound(w, s.bound(), touched.removed, b.target) {
                    Some(nb) => {
                        #[cfg(test)]
                        super::engine::assert_same_bound(nb, e.bound(w, &mut sc), w);
                        s.set_bound(Some(nb));
                    }
                    None => s.dirty = true,
                }
            } else if change == Change::Faces
                || s.dirty
                || s.target == INVALID
                || e.target_only_needs_bound(w, s.bound(), b.target)
            {
                s.dirty = true;
            }
            s.uncheck();
            checked[w as usize] = None;
            pool.insert(w);
        }
    }
    collapses
}
