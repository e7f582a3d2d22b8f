//! The walk of a pass: the picks in cost order, each checked on the mesh as it is at its turn
//! and collapsed if it passes every rule, each collapse locking its two ends for the rest of
//! the pass (meshoptimizer's rule). Several blocks of the mesh are walked at once.
//!
//! ```text
//!   blocks:  the live vertices along a Morton curve, cut into runs of up to BLOCK
//!   walk B:  its picks (u in B) in order; a pick whose u has a neighbour outside B
//!            is deferred                                                   (blocks in parallel)
//!   walk:    the deferred picks, in order, anywhere                         (serial)
//! ```
//!
//! **Why blocks can be walked at once.** Call a pick *interior* to block B when u and every
//! neighbour of u are in B; only interior picks are collapsed in the block walks.
//! * An interior collapse u → v writes only the faces of u's fan (whose corners are u and
//!   its neighbours: all in B), the face counts of those corners, and the locks of u and v.
//!   (It also stamps v's neighbours stale, some of them perhaps in another block; but every
//!   stamp of a pass is the pass's number, and nothing reads them until the next pass.
//!   Which of them it stamps depends on their bounds and the quadrics, which no walk
//!   writes.)
//! * Checking u → v reads u's fan (faces around u), v's fan (faces around v, a neighbour of
//!   u), the face counts of the wings (neighbours of u), the locks of u and v, and what no
//!   pass writes (positions, flags, input normals, wedges' sources, the quadrics: a pass
//!   adds them up after its walk; the bounds: worked out before it); evaluating u again
//!   reads the same for each of u's targets. So a check in B reads only faces with a corner
//!   in B and vertices of B.
//!   Deciding that a pick is interior reads u's fan alone.
//! * A face another block B' writes has all its corners in B', so no face around a vertex of
//!   B; a count or lock B' writes is of a vertex of B'. And interior collapses keep it so:
//!   u's faces pass to v and its neighbours gain v, all within B.
//!
//! So the blocks touch disjoint cells and each block's walk reads exactly what a walk of its
//! picks alone would: the result is the same whatever runs when, on any number of threads.
//! The cells are atomic (relaxed) so that this argument is about determinism, not memory
//! safety. A walk that could overshoot the target (more than half the faces to remove in
//! picks) runs serially, one pick at a time, stopping at the target.
//!
//! The runtime's papers/000 rounds cut their work the same way (`topology/parts.rs`), but as
//! ranges of vertex and face ids handed out as disjoint slices: that needs ids in spatial
//! order and the half-edge arrays. Here the blocks follow the curve whatever the ids, and the
//! flat arrays are shared as atomics instead of sliced.
//!
//! A pick whose checked target fails is evaluated again on the spot: its cheapest target that
//! passes, if within the pass's ceiling, joins the walk at its own cost (once per walk: a
//! second failure drops it until the next walk).

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use super::bounds::Bounds;
use super::faces::FlatFaces;
use super::rules::{wedge_map, Rules, Scratch};
use crate::mesh::spatial_order::morton_codes;
use crate::simplify::batched::{from_ordered_bits, ordered_bits};

/// Most live vertices per block. Smaller blocks defer more picks (the band along their
/// edges is a larger part of them).
const BLOCK: usize = 2048;

/// Fewest live vertices per block, and the fewest blocks a mesh is cut into while its blocks
/// can be that large: small meshes are cut too, so every mesh takes the same path (and the
/// tests' small meshes exercise the blocks). Unit-test builds allow blocks of 4, so their
/// meshes of a few hundred vertices are cut into 16 (flat/mod.rs tests).
const MIN_BLOCK: usize = if cfg!(test) { 4 } else { 32 };
const MIN_BLOCKS: usize = 16;

/// A collapse the walk is to try: u into v, at the cost whose ordered bits are `key`. The
/// walk's order is (key, u); 16 bytes, so that sorting a pass's picks stays cheap.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Item {
    pub key: u64,
    pub u: u32,
    pub v: u32,
}

impl Item {
    pub fn new(cost: f64, u: u32, v: u32) -> Self {
        Self { key: ordered_bits(cost), u, v }
    }

    /// The cost, back from its ordered bits.
    pub fn cost(&self) -> f64 {
        from_ordered_bits(self.key)
    }
}

/// The vertices along a Morton curve, and each live vertex's block.
pub(super) struct Blocks {
    by_curve: Vec<u32>,
    of: Vec<u32>,
    /// Live vertices per block, set from the input's live vertices (so a pass's blocks
    /// shrink in area as the mesh coarsens, and small meshes are cut too).
    size: usize,
}

/// The vertex ids along a Morton curve over `positions` (ties: the smaller id): what
/// [`Blocks::along`] cuts. Needs only the positions, so it can be worked out beside the flat
/// faces.
pub(super) fn curve_order(positions: &[[f32; 3]]) -> Vec<u32> {
    let codes = morton_codes(positions);
    let mut by_curve: Vec<u32> = (0..positions.len() as u32).collect();
    // Meshes built in spatial order are already sorted.
    if !codes.windows(2).all(|w| w[0] <= w[1]) {
        by_curve.sort_unstable_by_key(|&v| (codes[v as usize], v));
    }
    by_curve
}

impl Blocks {
    /// Blocks along `by_curve` ([`curve_order`]), sized from the live vertices of `flat`.
    pub fn along(by_curve: Vec<u32>, flat: &FlatFaces) -> Self {
        let live = by_curve.iter().filter(|&&v| flat.count(v) > 0).count();
        let size = (live / MIN_BLOCKS).clamp(MIN_BLOCK, BLOCK);
        let of = vec![u32::MAX; by_curve.len()];
        Self { by_curve, of, size }
    }

    /// Cuts the live vertices into runs along the curve. Returns each vertex's block
    /// (meaningless for dead vertices) and the number of blocks.
    pub fn assign(&mut self, flat: &FlatFaces) -> (&[u32], usize) {
        let mut k = 0;
        for &v in &self.by_curve {
            if flat.count(v) > 0 {
                self.of[v as usize] = (k / self.size) as u32;
                k += 1;
            }
        }
        (&self.of, k.div_ceil(self.size))
    }
}

/// Where a walk may collapse: around the vertices of one block, or anywhere.
#[derive(Debug, Clone, Copy)]
pub(super) enum Scope<'a> {
    Block { of: &'a [u32], id: u32 },
    All,
}

/// What a walk reads and locks.
pub(super) struct Walk<'a> {
    pub rules: &'a Rules<'a>,
    /// Per vertex, the pass in which it last was an end of a collapse.
    pub locked: &'a [AtomicU32],
    /// Per vertex, the pass in which its bound last went stale.
    pub stale: &'a [AtomicU32],
    /// Per vertex, its bound as the pass began (flat/mod.rs): read to stamp only the
    /// target's neighbours whose cheapest target it was.
    pub bound: &'a Bounds,
    pub pass: u32,
    /// Re-evaluated picks costlier than this wait for the next pass.
    pub ceiling: u64,
}

/// What one walk did.
#[derive(Debug, Default)]
pub(super) struct Walked {
    /// (u, v) of each collapse, in the order made.
    pub made: Vec<(u32, u32)>,
    /// Faces removed.
    pub removed: usize,
    pub max_error: f64,
    /// With attributes weighted, each collapse's wedge map (as `made`), read before the
    /// collapse rewrote the corners: what the pass adds to which wedge's attribute quadric.
    pub wedge_maps: Vec<[(u32, u32); 2]>,
    /// Picks that were not interior to the block, for the walk over all.
    pub deferred: Vec<Item>,
}

impl Walk<'_> {
    /// Walks `items` (in order) within `scope` until `budget` faces are removed. Picks found
    /// by evaluating a vertex again join in order from a heap, and are not evaluated again
    /// in this walk.
    pub fn run(&self, items: &[Item], scope: Scope<'_>, budget: usize, sc: &mut Scratch) -> Walked {
        let mut out = Walked::default();
        let mut late: BinaryHeap<Reverse<Item>> = BinaryHeap::new();
        let mut next = items.iter().copied().peekable();
        while out.removed < budget {
            let (item, is_late) = match (next.peek(), late.peek()) {
                (Some(a), Some(Reverse(b))) if b < a => (late.pop().map(|r| r.0), true),
                (Some(_), _) => (next.next(), false),
                (None, _) => (late.pop().map(|r| r.0), true),
            };
            let Some(item) = item else { break };
            let again = if is_late { None } else { Some(&mut late) };
            self.try_item(item, scope, &mut out, again, sc);
        }
        out
    }

    fn is_locked(&self, v: u32) -> bool {
        self.locked[v as usize].load(Relaxed) == self.pass
    }

    fn try_item(
        &self,
        item: Item,
        scope: Scope<'_>,
        out: &mut Walked,
        late: Option<&mut BinaryHeap<Reverse<Item>>>,
        sc: &mut Scratch,
    ) {
        let (rules, u, v) = (self.rules, item.u, item.v);
        if self.is_locked(u) {
            return;
        }
        // Before reading u's fan: a target outside the block makes the pick not interior (or
        // it is no longer u's neighbour, which the walk over all finds as well), and a locked
        // target fails it (v in the block: its lock is this walk's to write).
        if let Scope::Block { of, id } = scope {
            if of[v as usize] != id {
                out.deferred.push(item);
                return;
            }
        }
        if self.is_locked(v) {
            return;
        }
        rules.targets(u, sc);
        if let Scope::Block { of, id } = scope {
            if sc.fan.ring.iter().any(|&x| of[x as usize] != id) {
                out.deferred.push(item);
                return;
            }
        }
        // v left u's fan (it was collapsed) or is no longer allowed (u's fan changed): u's
        // cost is worked out again next pass.
        if !sc.allowed.contains(&v) {
            return;
        }
        if !rules.passes(u, v, sc) {
            // u's fan and targets are still in `sc` (the checks read only v's ring into it).
            if let Some(late) = late {
                if let Some((cost, v)) = rules.evaluate(u, sc, |t| !self.is_locked(t)) {
                    let next = Item::new(cost, u, v);
                    if next.key <= self.ceiling {
                        late.push(Reverse(next));
                    }
                }
            }
            return;
        }
        let (forward, backward) = sc.fan.edge(v);
        let map = wedge_map(rules.flat, forward, backward);
        // Stale: u's neighbours (their fans changed) and those of v's whose cheapest target
        // was v; all of v's where their cost into v may not have risen (flat/mod.rs), or
        // reads v's attribute quadrics, which gain u's.
        let rises = !rules.error_bound.is_finite()
            && rules.attributes.is_none()
            && rules.own_cost_after(u, v) >= rules.own[v as usize].0;
        for &x in sc.fan.ring.iter().chain([&u]) {
            self.stale[x as usize].store(self.pass, Relaxed);
        }
        for &x in &sc.target_ring {
            if !rises || self.bound.target(x) == v {
                self.stale[x as usize].store(self.pass, Relaxed);
            }
        }
        out.removed += rules.flat.collapse(u, v, &sc.fan, map);
        self.locked[u as usize].store(self.pass, Relaxed);
        self.locked[v as usize].store(self.pass, Relaxed);
        out.made.push((u, v));
        if rules.attributes.is_some() {
            out.wedge_maps.push(map);
        }
        out.max_error = out.max_error.max(rules.error(u, v, item.cost()));
    }
}
