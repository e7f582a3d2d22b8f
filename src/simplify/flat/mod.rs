//! Flat passes (`qem-flat`): greedy quadric collapses in passes over a triangle list, in
//! meshoptimizer's layout — per-vertex rows of face corners instead of half-edges, the costs
//! of a pass worked out in parallel, the collapses made in cost order, each locking only its
//! two ends, in several blocks of the mesh at once — under every rule of the half-edge
//! engines (rules.rs).
//!
//! ```text
//!   pass:  cost the cheapest allowed target of every vertex whose cost may have changed
//!            (its fan changed, or it neighbours a target of the last pass)       (parallel)
//!          keep the vertices up to 1.5x the cost at rank len/3 (or at the rank of the
//!            collapses still needed, if fewer); every vertex after a pass that made nothing;
//!          sort them by (cost, vertex)
//!          walk them (walk.rs): skip u → v if u or v is an end of a collapse made in this
//!            pass, check it on the mesh as it is, collapse: v takes u's faces, the faces on
//!            the edge die                                     (blocks in parallel, then serial)
//!          Q_v += Q_u for every collapse; rebuild the rows
//!   end:   write faces, twins, wedges and vertex links back into the mesh
//! ```
//! Why the costs a pass works out again are enough: u's cheapest target reads u's fan, Q_u
//! and, per target v, Q_v and v's position. A collapse x → y changes the fans of x's
//! neighbours (their corner x becomes y) and of y, and Q only at y. So only the vertices whose
//! fan changed and the neighbours of the targets need a fresh cost; the walk stamps x's and
//! y's neighbours as it collapses. Of y's neighbours, only those whose cheapest target was y,
//! when Q_y(y) does not come out lower once Q_y has gained Q_x (Q_x is nowhere negative, so
//! only a rounding error can lower it): then every other neighbour w's cost into y,
//! Q_w(y) + Q_y(y), does not fall either (floating-point addition is monotone), and its
//! cheapest target stays. Otherwise, and under an error bound (a larger weight can loosen
//! it), all of y's neighbours. A vertex that becomes y's neighbour later in the pass does
//! so through a collapse z → w with z next to y, and that collapse stamps w (z's neighbour).
//! The quadrics are summed after the walk, so every cost a walk reads is the pass's: a target
//! is locked for the rest of the pass, so nothing reads its new quadric before then anyway.
//!
//! With attributes weighted (simplify/attribute_quadric.rs), a cost adds W·ΣA over the edge's
//! wedge pairs, and the wedges' quadrics are summed after the walk like Q, from the wedge
//! maps the walk recorded before each collapse rewrote its corners. Since a target's wedge
//! quadrics grow, all of its neighbours go stale, as under an error bound.
//!
//! Every step is a pure function per vertex, runs in a fixed order, or runs on blocks that
//! touch disjoint state (walk.rs), so the result does not depend on the thread count. The
//! passes stop at the target, or after a pass that tried every vertex and made nothing (so
//! nothing is left that any rule allows).

mod attributes;
mod bounds;
mod faces;
mod rules;
mod walk;
mod write_back;

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;

use super::batched::{ordered_bits, CEILING_FACTOR};
use super::engine::Engine;
use super::Progress;
use crate::lists::keep_and_pick;
use crate::mesh::{constraints, Mesh};
use crate::par::for_each_sized;
use crate::topology::{vflag, INVALID};
use attributes::Attributes;
use bounds::Bounds;
use faces::FlatFaces;
use rules::{own_cost, own_costs, Rules, Scratch};
use walk::{curve_order, Blocks, Item, Scope, Walk, Walked};

/// A pass keeps the vertices whose cost is at most [`CEILING_FACTOR`] times the cost at rank
/// `len / CONSIDERED_PART` (or at the rank of the collapses still needed, if fewer).
const CONSIDERED_PART: usize = 3;

/// Fewest vertices a parallel task takes (a bound is a few tenths of a microsecond).
const TASK: usize = 256;

/// Collapses until `target_faces` remain or nothing is allowed. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, progress: &Progress) -> usize {
    let mut p = Passes::new(e);
    progress.init_done();
    let mut collapses = 0;
    // After a pass that made nothing, one that tries every vertex; after that too, stop.
    while e.live_faces > target_faces {
        let Some(made) = p.pass(e, target_faces) else { break };
        progress.tick(e.live_faces);
        collapses += made.collapses();
        if made.collapses() == 0 && p.everything {
            break;
        }
        p.everything = made.collapses() == 0;
    }
    e.quadrics = std::mem::take(&mut p.quadrics);
    e.attributes = p.attributes.take().map(Attributes::into_quadrics);
    write_back::write_back(e.mesh, &p.flat);
    collapses
}

/// What one pass made, and where.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct PassStats {
    /// Blocks the walk was cut into (0: it ran serially alone).
    blocks: usize,
    /// Collapses made inside the blocks.
    in_blocks: usize,
    /// Picks the blocks deferred to the serial walk.
    deferred: usize,
    /// Collapses made by the serial walk.
    serial: usize,
}

impl PassStats {
    fn collapses(&self) -> usize {
        self.in_blocks + self.serial
    }
}

/// The state the passes carry from one to the next.
struct Passes {
    flat: FlatFaces,
    plain: bool,
    /// Live vertices the caller did not lock.
    active: Vec<u32>,
    quadrics: Vec<super::Quadric>,
    /// The wedges' attribute quadrics, when attributes are weighted ([`Rules::attributes`]).
    attributes: Option<Attributes>,
    /// Per vertex, Q_v(v) and the weight of Q_v ([`Rules::own`]).
    own: Vec<(f64, f64)>,
    /// The pass in which a vertex was last an end of a collapse (locked for the rest of it).
    locked: Vec<AtomicU32>,
    blocks: Blocks,
    /// Each vertex's bound as last worked out ([`Bounds`]), and the pass in
    /// which it last went stale (the walk stamps the vertices whose fan changed and the
    /// neighbours of every target, whose cost into it changed): the next pass works it out
    /// again.
    bound: Bounds,
    stale: Vec<AtomicU32>,
    sc: Scratch,
    /// Consider every vertex, not only the cheapest part (after a pass that made nothing).
    everything: bool,
    pass: u32,
}

impl Passes {
    fn new(e: &mut Engine<'_>) -> Self {
        let quadrics = std::mem::take(&mut e.quadrics);
        let mesh: &Mesh = e.mesh;
        let attributes = e.attributes.take().map(|a| Attributes::new(a, mesh));
        // The flat copy is serial; the Morton curve and the own costs go beside it.
        let (flat, (by_curve, own)) = rayon::join(
            || FlatFaces::new(mesh),
            || rayon::join(|| curve_order(&mesh.positions), || own_costs(mesh, &quadrics)),
        );
        let n = flat.vertex_count();
        let user_locked = |v: u32| mesh.topology.vflags[v as usize] & vflag::LOCKED != 0;
        let active: Vec<u32> = (0..n as u32).filter(|&v| flat.count(v) > 0 && !user_locked(v)).collect();
        Self {
            plain: constraints::plain_attributes(mesh),
            own,
            quadrics,
            attributes,
            locked: (0..n).map(|_| AtomicU32::new(0)).collect(),
            blocks: Blocks::along(by_curve, &flat),
            bound: Bounds::new(n),
            stale: (0..n).map(|_| AtomicU32::new(0)).collect(),
            active,
            flat,
            sc: Scratch::default(),
            everything: false,
            pass: 0,
        }
    }

    /// One pass (module docs). `None` when no vertex has an allowed target.
    fn pass(&mut self, e: &mut Engine<'_>, target_faces: usize) -> Option<PassStats> {
        self.pass += 1;
        let rules = rules_of(e, &self.flat, &self.quadrics, self.attributes.as_ref(), &self.own, self.plain);
        let flat = rules.flat;
        // The live vertices, and those of them stamped stale last pass: one pass without a
        // branch on the flags (crate::lists).
        let (was_stamped, last) = (&self.stale, self.pass - 1);
        let stale =
            keep_and_pick(&mut self.active, |v| (flat.count(v) > 0, was_stamped[v as usize].load(Relaxed) == last));
        let bound = &self.bound;
        for_each_sized(&stale, TASK, TASK, |sc: &mut Scratch, &u| bound.set(u, rules.bound(u, sc)));
        // Test builds: every bound the walk left unstamped is what a fresh one gives.
        #[cfg(test)]
        for &v in &self.active {
            assert_eq!(self.bound.get(v), rules.bound(v, &mut self.sc), "vertex {v}: a kept bound is stale");
        }
        let budget = e.live_faces - target_faces;
        let (order, ceiling) = self.order(budget)?;
        let walk = Walk {
            rules: &rules,
            locked: &self.locked,
            stale: &self.stale,
            bound: &self.bound,
            pass: self.pass,
            ceiling,
        };
        let (walked, stats) = walk_pass(&walk, order, &mut self.blocks, budget, &mut self.sc);
        for w in &walked {
            e.live_faces -= w.removed;
            e.max_error = e.max_error.max(w.max_error);
        }
        let made = || walked.iter().flat_map(|w| w.made.iter().copied());
        // A seam end hands its target its seam edge (engine.rs, `free_vertices`); the target
        // is locked for the rest of the pass, so nothing read its flag since.
        for (u, v) in made() {
            e.free[v as usize] &= e.free[u as usize];
        }
        let (quadrics, own, mesh) = (&mut self.quadrics, &mut self.own, &*e.mesh);
        let attributes = &mut self.attributes;
        rayon::join(
            || {
                for (u, v) in made() {
                    let q = quadrics[u as usize];
                    quadrics[v as usize] += q;
                    own[v as usize] = own_cost(mesh, &quadrics[v as usize], v);
                }
                if let Some(a) = attributes {
                    for &map in walked.iter().flat_map(|w| &w.wedge_maps) {
                        a.merge(map, mesh);
                    }
                }
            },
            || self.flat.rebuild_rows(made()),
        );
        Some(stats)
    }

    /// The picks of a pass (unsorted: the walk sorts them), and the ceiling on their costs: the
    /// vertices up to [`CEILING_FACTOR`] times the cost at rank len / [`CONSIDERED_PART`] (or
    /// at the rank of the collapses still needed, if fewer), or every vertex. `None` when no
    /// vertex has an allowed target.
    fn order(&self, budget: usize) -> Option<(Vec<Item>, u64)> {
        // Without a branch on whether a vertex has a bound (as crate::lists).
        let mut order = vec![Item::new(0.0, 0, 0); self.active.len()];
        let mut len = 0;
        for &u in &self.active {
            let (cost, v) = self.bound.get_or_none(u);
            order[len] = Item::new(cost, u, v);
            len += usize::from(v != INVALID);
        }
        order.truncate(len);
        if order.is_empty() {
            return None;
        }
        // Interior collapses remove two faces, border ones one.
        let mut ceiling = u64::MAX;
        let consider = budget.div_ceil(2).min(order.len() / CONSIDERED_PART).max(1);
        if !self.everything && consider < order.len() {
            let (_, at, _) = order.select_nth_unstable(consider);
            // Never below the cost at that rank: costs can come out a rounding error below
            // zero (flat regions), where 1.5x is lower.
            ceiling = at.key.max(ordered_bits(CEILING_FACTOR * at.cost()));
            order.retain(|p| p.key <= ceiling);
        }
        Some((order, ceiling))
    }
}

/// One pass's walk (walk.rs) over `order`: in blocks, in parallel, when the picks cannot
/// overshoot `budget` faces removed; then the picks the blocks deferred (or all of them)
/// serially.
fn walk_pass(
    walk: &Walk<'_>,
    order: Vec<Item>,
    blocks: &mut Blocks,
    budget: usize,
    sc: &mut Scratch,
) -> (Vec<Walked>, PassStats) {
    let mut stats = PassStats::default();
    let mut walked = Vec::new();
    let mut rest = order;
    if 2 * rest.len() <= budget {
        let (of, count) = blocks.assign(walk.rules.flat);
        let mut per_block: Vec<Vec<Item>> = vec![Vec::new(); count];
        for p in rest {
            per_block[of[p.u as usize] as usize].push(p);
        }
        // Each block sorts its own picks: smaller sorts, and in parallel.
        walked = per_block
            .par_iter_mut()
            .enumerate()
            .map_init(Scratch::default, |sc, (id, items)| {
                items.sort_unstable();
                walk.run(items, Scope::Block { of, id: id as u32 }, usize::MAX, sc)
            })
            .collect();
        rest = walked.iter_mut().flat_map(|w| std::mem::take(&mut w.deferred)).collect();
        rest.sort_unstable();
        stats.blocks = count;
        stats.in_blocks = walked.iter().map(|w| w.made.len()).sum();
        stats.deferred = rest.len();
    } else {
        rest.par_sort_unstable();
    }
    let removed: usize = walked.iter().map(|w| w.removed).sum();
    walked.push(walk.run(&rest, Scope::All, budget - removed, sc));
    stats.serial = walked.last().map_or(0, |w| w.made.len());
    (walked, stats)
}

/// The rules on the engine's mesh as handed in, with the flat faces and quadrics as they are
/// now.
fn rules_of<'a>(
    e: &'a Engine<'_>,
    flat: &'a FlatFaces,
    quadrics: &'a [super::Quadric],
    attributes: Option<&'a Attributes>,
    own: &'a [(f64, f64)],
    plain: bool,
) -> Rules<'a> {
    Rules {
        mesh: e.mesh,
        flat,
        quadrics,
        own,
        normal0: &e.normal0,
        free: &e.free,
        error_bound: e.error_bound,
        plain,
        attributes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simplify::{simplify, Cost, Method, SimplifyOptions};
    use crate::{procedural, BuildOptions, Mesh};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// The blocks' walks touch disjoint state (walk.rs): on surfaces cut into 16 blocks
        /// (unit-test builds allow blocks of 4 vertices), one thread and two give the same
        /// mesh, a valid one with the input's Euler characteristic and border loops.
        #[test]
        fn blocks_give_the_same_mesh_on_one_thread_and_two(
            kind in 0u8..3,
            a in 4usize..18,
            b in 4usize..18,
            bits in any::<u64>(),
            keep in 0.0f64..0.8,
        ) {
            let input = match kind {
                0 => procedural::torus(a + 2, b),
                1 => procedural::uv_sphere(a, b + 2),
                _ => procedural::grid(a, b, move |i, j| bits >> ((i * 7 + j) % 64) & 1 == 1),
            };
            let src = Mesh::build(&input, BuildOptions::default()).unwrap();
            let before = src.topology.stats();
            let target = (src.topology.live_face_count() as f64 * keep) as usize;
            let run = |threads| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let mut mesh = src.clone();
                let opts = SimplifyOptions::default().method(Method::QemFlat).target_triangles(target);
                pool.install(|| simplify(&mut mesh, opts));
                mesh
            };
            let one = run(1);
            prop_assert_eq!(one.topology.validate(), Ok(()));
            let after = one.topology.stats();
            prop_assert_eq!((after.euler, after.boundary_loops), (before.euler, before.boundary_loops));
            prop_assert!(one == run(2), "one and two threads differ");
        }
    }

    /// On the bunny, the first pass cuts the mesh into blocks and makes most of its collapses
    /// inside them (in parallel); the picks on the blocks' edges go to the serial walk, which
    /// makes some of them; and the mesh is a valid one after the pass.
    #[test]
    fn the_first_pass_collapses_mostly_inside_blocks() {
        let mut mesh = crate::test_bunny();
        let mut e = Engine::new(&mut mesh, Cost::Quadric, f64::INFINITY, None);
        let (input, target) = (e.live_faces, e.live_faces / 10);
        let mut p = Passes::new(&mut e);
        let stats = p.pass(&mut e, target).expect("the bunny has collapses");
        assert!(stats.blocks >= 16, "{stats:?}");
        assert!(stats.in_blocks > 4 * stats.serial && stats.serial > 0, "{stats:?}");
        assert!(stats.deferred >= stats.serial, "{stats:?}");
        assert!(e.live_faces < input - stats.collapses(), "each collapse removes one or two faces");
        write_back::write_back(e.mesh, &p.flat);
        e.mesh.topology.validate().unwrap();
        assert_eq!(e.mesh.topology.live_face_count(), e.live_faces);
    }
}
