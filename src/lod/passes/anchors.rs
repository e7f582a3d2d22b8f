//! The layered grid anchors of papers/000 §3 (equation 2): vertices given an artificially high
//! error so that they stay in S, which guarantees every region has collapse targets and
//! raises parallelism.
//!
//! ```text
//!   L0: bbox split into k cells per axis     L1: cells of half the side     ...
//!   +-----+-----+                            +--+--+--+--+
//!   |  .  |  .  |   one vertex per cell:     |. |. |. |. |   m(V, P) = (l − d(V, P))² · e(V)
//!   +-----+-----+   the largest m(V, P)      +--+--+--+--+   l = longest side of the cell,
//!   |  .  |  .  |                            |. |. |. |. |   d = distance from V to the centre P
//!   +-----+-----+                            +--+--+--+--+
//! ```
//! Layer L0's chosen vertices get an infinite error (e_m > u for any u); layer L_i's get at
//! least the user's e(L_i). Decision (the paper's "halfway points" are ambiguous): layer i's
//! points are the centres of the cells of side s_0 / 2^i, and each cell is the point's volume.
//! Ties in m (e.g. flat regions, where every e is 0) go to the vertex nearest the centre, then
//! to the smaller id, so the choice is deterministic.

use rustc_hash::FxHashMap;

use crate::topology::{Topology, INVALID};

/// How many anchor layers, how dense, and their minimum errors.
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct AnchorOptions {
    /// Cells along each axis of the bounding box for L0; 0 picks √(n / 128) for n vertices
    /// (16 for the bunny), so the anchors stay a few percent of any mesh. Default: 0.
    pub cells: u32,
    /// e(L_i) for layers 1, 2, …; L0 is always infinite. Default: none (L0 only).
    pub layer_errors: Vec<f32>,
}

impl AnchorOptions {
    /// Sets [`AnchorOptions::cells`] (0: automatic).
    pub fn cells(mut self, k: u32) -> Self {
        self.cells = k;
        self
    }
    /// Sets [`AnchorOptions::layer_errors`].
    pub fn layer_errors(mut self, e: Vec<f32>) -> Self {
        self.layer_errors = e;
        self
    }
}

/// The anchors of each layer (vertex ids, ascending).
pub fn select_anchors(t: &Topology, positions: &[[f32; 3]], errors: &[f32], o: &AnchorOptions) -> Vec<Vec<u32>> {
    let live: Vec<u32> = (0..t.vertex_count() as u32).filter(|&v| t.vertex_he[v as usize] != INVALID).collect();
    if live.is_empty() {
        return vec![Vec::new(); 1 + o.layer_errors.len()];
    }
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for &v in &live {
        for k in 0..3 {
            lo[k] = lo[k].min(positions[v as usize][k]);
            hi[k] = hi[k].max(positions[v as usize][k]);
        }
    }
    let cells = if o.cells == 0 { ((live.len() as f64 / 128.0).sqrt().round() as u32).clamp(2, 64) } else { o.cells };
    (0..=o.layer_errors.len())
        .map(|layer| {
            let n = (cells as u64) << layer.min(20);
            let side: [f64; 3] = std::array::from_fn(|k| ((hi[k] - lo[k]) as f64 / n as f64).max(f64::MIN_POSITIVE));
            let l = side.iter().cloned().fold(0.0, f64::max);
            // cell -> (m, distance, vertex) of the best vertex so far
            let mut best: FxHashMap<[u64; 3], (f64, f64, u32)> = FxHashMap::default();
            for &v in &live {
                let p = positions[v as usize];
                let cell: [u64; 3] = std::array::from_fn(|k| (((p[k] - lo[k]) as f64 / side[k]) as u64).min(n - 1));
                let centre: [f64; 3] = std::array::from_fn(|k| lo[k] as f64 + (cell[k] as f64 + 0.5) * side[k]);
                let d = (0..3).map(|k| (p[k] as f64 - centre[k]).powi(2)).sum::<f64>().sqrt();
                let m = (l - d).powi(2) * errors[v as usize] as f64;
                let better =
                    |old: &(f64, f64, u32)| m > old.0 || (m == old.0 && (d < old.1 || (d == old.1 && v < old.2)));
                best.entry(cell)
                    .and_modify(|old| {
                        if better(old) {
                            *old = (m, d, v)
                        }
                    })
                    .or_insert((m, d, v));
            }
            let mut chosen: Vec<u32> = best.values().map(|b| b.2).collect();
            chosen.sort_unstable();
            chosen
        })
        .collect()
}

/// Raises the errors of the anchors in place: L0 to infinity, L_i to at least e(L_i).
pub fn apply_anchors(errors: &mut [f32], anchors: &[Vec<u32>], o: &AnchorOptions) {
    for (layer, vs) in anchors.iter().enumerate() {
        let e = if layer == 0 { f32::INFINITY } else { o.layer_errors[layer - 1] };
        for &v in vs {
            errors[v as usize] = errors[v as usize].max(e);
        }
    }
}
