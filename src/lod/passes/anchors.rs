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

/// [`AnchorOptions::nested`]'s default: an anchor that only a grid of side s holds stays while
/// s / 4 is an error the view shows (its floor is (s / 4)²).
pub const NESTED_SCALE: f32 = 0.25;

/// How many anchor layers, how dense, and their minimum errors.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct AnchorOptions {
    /// Cells along each axis of the bounding box for L0; 0 picks √(n / 128) for n vertices
    /// (16 for the bunny), so the anchors stay a few percent of any mesh. Default: 0.
    pub cells: u32,
    /// e(L_i) for layers 1, 2, …; L0 is infinite unless nested. Default: none (L0 only).
    pub layer_errors: Vec<f32>,
    /// Nesting L0 (not in the paper): `Some(κ)` picks coarser grids of half as many cells per
    /// axis, down to 2, each among the anchors of the one below ([`nested_floors`]). Only the
    /// coarsest grid's anchors always stay; an anchor whose coarsest grid has cells of side s
    /// gets the floor (κ · s)², so it stays while the view shows an error of κ · s, and a far
    /// view can coarsen below the finest grid. `None`: the paper's L0, every anchor infinite.
    /// Default: `Some(NESTED_SCALE)`; the runtime keeps it, the one-shot rounds of
    /// `lod::coarsen` turn it off (their default options say why).
    pub nested: Option<f32>,
}

impl Default for AnchorOptions {
    fn default() -> Self {
        Self { cells: 0, layer_errors: Vec::new(), nested: Some(NESTED_SCALE) }
    }
}

impl AnchorOptions {
    /// Sets [`AnchorOptions::nested`].
    pub fn nested(mut self, scale: Option<f32>) -> Self {
        self.nested = scale;
        self
    }
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

/// The live vertices, their bounding box and L0's cells per axis.
struct Frame {
    live: Vec<u32>,
    lo: [f32; 3],
    hi: [f32; 3],
    cells: u32,
}

impl Frame {
    fn new(t: &Topology, positions: &[[f32; 3]], o: &AnchorOptions) -> Option<Self> {
        let live: Vec<u32> =
            (0..t.vertex_count() as u32).into_par_iter().filter(|&v| t.vertex_he[v as usize] != INVALID).collect();
        if live.is_empty() {
            return None;
        }
        // Minimum and maximum do not depend on the order they are taken in.
        let (lo, hi) = live.par_iter().map(|&v| (positions[v as usize], positions[v as usize])).reduce(
            || ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
            |(lo, hi), (l, h)| (std::array::from_fn(|k| lo[k].min(l[k])), std::array::from_fn(|k| hi[k].max(h[k]))),
        );
        let cells =
            if o.cells == 0 { ((live.len() as f64 / 128.0).sqrt().round() as u32).clamp(2, 64) } else { o.cells };
        Some(Self { live, lo, hi, cells })
    }

    /// The cell sides of an n³ grid over the box, and the longest.
    fn sides(&self, n: u64) -> ([f64; 3], f64) {
        let side: [f64; 3] =
            std::array::from_fn(|k| ((self.hi[k] - self.lo[k]) as f64 / n as f64).max(f64::MIN_POSITIVE));
        (side, side.iter().cloned().fold(0.0, f64::max))
    }

    /// The best of `among` in every occupied cell of an n³ grid (ascending ids).
    fn best(&self, positions: &[[f32; 3]], errors: &[f32], among: &[u32], n: u64) -> Vec<u32> {
        let (side, l) = self.sides(n);
        let lo = self.lo;
        // (cell, m, distance, vertex) per vertex, computed in parallel.
        let scored: Vec<Scored> = among
            .par_iter()
            .map(|&v| {
                let p = positions[v as usize];
                let cell: [u64; 3] = std::array::from_fn(|k| (((p[k] - lo[k]) as f64 / side[k]) as u64).min(n - 1));
                let centre: [f64; 3] = std::array::from_fn(|k| lo[k] as f64 + (cell[k] as f64 + 0.5) * side[k]);
                let d = (0..3).map(|k| (p[k] as f64 - centre[k]).powi(2)).sum::<f64>().sqrt();
                (cell, (l - d).powi(2) * errors[v as usize] as f64, d, v)
            })
            .collect();
        let dense = n.checked_pow(3).is_some_and(|c| c <= 4096.max(8 * among.len() as u64));
        let mut chosen = best_per_cell(scored, n, dense);
        chosen.sort_unstable();
        chosen
    }
}

/// The anchors of each layer (vertex ids, ascending).
pub fn select_anchors(t: &Topology, positions: &[[f32; 3]], errors: &[f32], o: &AnchorOptions) -> Vec<Vec<u32>> {
    let Some(f) = Frame::new(t, positions, o) else {
        return vec![Vec::new(); 1 + o.layer_errors.len()];
    };
    (0..=o.layer_errors.len())
        .map(|layer| f.best(positions, errors, &f.live, (f.cells as u64) << layer.min(20)))
        .collect()
}

/// The floor of each of `l0`'s anchors (L0 of [`select_anchors`] with the same options) under
/// [`AnchorOptions::nested`] `Some(κ)`, in `l0`'s order: grids of half as many cells per axis
/// (clamped at 2, down to 2) each pick the best of the previous grid's anchors per cell, as
/// the grid picks among vertices; an anchor in the coarsest grid gets +∞, any other
/// (κ · s)², s the longest cell side of the coarsest grid it is in. With `None`, all +∞.
///
/// ```text
///   16 cells: every anchor        8: the best of those per cell     …     2: always stay
///   floor (κ·s16)²                floor (κ·s8)²                           +∞
/// ```
pub fn nested_floors(t: &Topology, positions: &[[f32; 3]], errors: &[f32], l0: &[u32], o: &AnchorOptions) -> Vec<f32> {
    let (Some(kappa), Some(f)) = (o.nested, Frame::new(t, positions, o)) else {
        return vec![f32::INFINITY; l0.len()];
    };
    let mut among = l0.to_vec();
    let mut floors = vec![f32::INFINITY; l0.len()];
    let mut n = f.cells as u64;
    while n > 2 {
        let coarser = f.best(positions, errors, &among, (n / 2).max(2));
        let floor = ((kappa as f64 * f.sides(n).1).powi(2)) as f32;
        // `among` and `coarser` are ascending: the ones left out stop at this grid.
        let mut k = 0;
        for &v in &among {
            if coarser.get(k) == Some(&v) {
                k += 1;
            } else {
                floors[l0.binary_search(&v).expect("among L0")] = floor;
            }
        }
        among = coarser;
        n = (n / 2).max(2);
    }
    floors
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
pub(super) type Scored = ([u64; 3], f64, f64, u32);

/// Best first within a cell: m descending, then the distance, then the id (a total order).
fn best_first(a: &Scored, b: &Scored) -> std::cmp::Ordering {
    b.1.total_cmp(&a.1).then(a.2.total_cmp(&b.2)).then(a.3.cmp(&b.3))
}

/// The best vertex of every occupied cell of an n³ grid (unordered). `dense`: one slot per
/// cell (few cells, the usual first layer); otherwise sort by cell, best first, and keep the
/// first of each cell (fine layers, where n³ slots would not fit). Both give the same set.
/// The sort does not read `n`, so its cells may be any ids (structure_anchors.rs's groups).
pub(super) fn best_per_cell(mut scored: Vec<Scored>, n: u64, dense: bool) -> Vec<u32> {
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
