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

use rayon::prelude::*;

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
    let live: Vec<u32> =
        (0..t.vertex_count() as u32).into_par_iter().filter(|&v| t.vertex_he[v as usize] != INVALID).collect();
    if live.is_empty() {
        return vec![Vec::new(); 1 + o.layer_errors.len()];
    }
    // Minimum and maximum do not depend on the order they are taken in.
    let (lo, hi) = live.par_iter().map(|&v| (positions[v as usize], positions[v as usize])).reduce(
        || ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
        |(lo, hi), (l, h)| (std::array::from_fn(|k| lo[k].min(l[k])), std::array::from_fn(|k| hi[k].max(h[k]))),
    );
    let cells = if o.cells == 0 { ((live.len() as f64 / 128.0).sqrt().round() as u32).clamp(2, 64) } else { o.cells };
    (0..=o.layer_errors.len())
        .map(|layer| {
            let n = (cells as u64) << layer.min(20);
            let side: [f64; 3] = std::array::from_fn(|k| ((hi[k] - lo[k]) as f64 / n as f64).max(f64::MIN_POSITIVE));
            let l = side.iter().cloned().fold(0.0, f64::max);
            // (cell, m, distance, vertex) per vertex, computed in parallel.
            let scored: Vec<Scored> = live
                .par_iter()
                .map(|&v| {
                    let p = positions[v as usize];
                    let cell: [u64; 3] = std::array::from_fn(|k| (((p[k] - lo[k]) as f64 / side[k]) as u64).min(n - 1));
                    let centre: [f64; 3] = std::array::from_fn(|k| lo[k] as f64 + (cell[k] as f64 + 0.5) * side[k]);
                    let d = (0..3).map(|k| (p[k] as f64 - centre[k]).powi(2)).sum::<f64>().sqrt();
                    (cell, (l - d).powi(2) * errors[v as usize] as f64, d, v)
                })
                .collect();
            let dense = n.checked_pow(3).is_some_and(|c| c <= 4096.max(8 * live.len() as u64));
            let mut chosen = best_per_cell(scored, n, dense);
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

/// A vertex scored for a cell: (cell, m, distance to the centre, id).
type Scored = ([u64; 3], f64, f64, u32);

/// Best first within a cell: m descending, then the distance, then the id (a total order).
fn best_first(a: &Scored, b: &Scored) -> std::cmp::Ordering {
    b.1.total_cmp(&a.1).then(a.2.total_cmp(&b.2)).then(a.3.cmp(&b.3))
}

/// The best vertex of every occupied cell of an n³ grid (unordered). `dense`: one slot per
/// cell (few cells, the usual first layer); otherwise sort by cell, best first, and keep the
/// first of each cell (fine layers, where n³ slots would not fit). Both give the same set.
fn best_per_cell(mut scored: Vec<Scored>, n: u64, dense: bool) -> Vec<u32> {
    if dense {
        let mut best: Vec<Option<usize>> = vec![None; (n * n * n) as usize];
        for (i, s) in scored.iter().enumerate() {
            let slot = &mut best[((s.0[0] * n + s.0[1]) * n + s.0[2]) as usize];
            if slot.is_none_or(|j| best_first(s, &scored[j]).is_lt()) {
                *slot = Some(i);
            }
        }
        best.into_iter().flatten().map(|i| scored[i].3).collect()
    } else {
        scored.par_sort_unstable_by(|a, b| a.0.cmp(&b.0).then(best_first(a, b)));
        scored.dedup_by(|later, first| later.0 == first.0);
        scored.iter().map(|s| s.3).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense grid and the sort pick the same vertex in every cell, ties included.
    #[test]
    fn both_ways_of_picking_per_cell_agree() {
        let mut x = 12345u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let n = 5;
        let scored: Vec<Scored> = (0..2000u32)
            .map(|v| {
                let cell = [next() % n, next() % n, next() % n];
                // Few distinct m and distances, so ties reach the later keys.
                ((cell), (next() % 4) as f64, (next() % 3) as f64, v)
            })
            .collect();
        let mut a = best_per_cell(scored.clone(), n, true);
        let mut b = best_per_cell(scored, n, false);
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a.len(), 125);
        assert_eq!(a, b);
    }
}
