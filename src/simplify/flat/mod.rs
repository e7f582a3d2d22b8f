//! Flat passes (`qem-flat`): greedy quadric collapses in passes over a triangle list, in
//! meshoptimizer's layout — per-vertex rows of face corners instead of half-edges, the costs
//! and checks of a pass worked out in parallel, the collapses made one after another, each
//! locking only its two ends — under every rule of the half-edge engines (rules.rs).
//!
//! ```text
//!   pass:  cost the cheapest allowed target of every vertex whose cost may have changed
//!            (its fan changed, or it neighbours a target of the last pass)       (parallel)
//!          keep the vertices up to 1.5x the cost at rank len/5 (or at the rank of the
//!            collapses still needed, if fewer); every vertex after a pass that made nothing;
//!            sort them by (cost, vertex)
//!          check each in full: its cheapest target passing every rule            (parallel)
//!          walk the order:                                                         (serial)
//!            skip u → v if u or v is an end of a collapse made in this pass
//!            check again if u, v or a wing had its fan changed in this pass
//!            collapse: v takes u's faces, the faces on the edge die, Q_v += Q_u
//!          rebuild the rows                                                        (serial)
//!   end:   write faces, twins, wedges and vertex links back into the mesh
//! ```
//! Why the walk needs no other re-check: a check of u → v reads u's fan (its faces, their
//! corners and wedges), v's neighbours, the wings' face counts and Q_u, Q_v. A collapse
//! x → y changes the faces of x's neighbours (their corner x becomes y) and of y (it gains
//! x's faces); every vertex whose fan changed is marked. Q changes only at y, and y is locked.
//! So a pick whose u, v and wings are unmarked reads exactly what it read when checked. A
//! locked target's row misses the faces it gained, but no check reads a locked vertex's row.
//! The same reads tell which costs a pass must work out again: u's cheapest target reads
//! u's fan, Q_u and, per target v, Q_v and v's position, so only the marked vertices and the
//! neighbours of the targets (whose Q grew) need a fresh one.
//!
//! Every step is a pure function per vertex, or runs in a fixed order, so the result does not
//! depend on the thread count. The passes stop at the target, or after a pass that checked
//! every vertex and made nothing (so nothing is left that any rule allows).

mod faces;
mod rules;
mod write_back;

use rayon::prelude::*;

use super::batched::{ordered_bits, CEILING_FACTOR};
use super::engine::Engine;
use super::Progress;
use crate::mesh::constraints;
use crate::par::map_sized;
use crate::sorted::merge_by_key;
use crate::topology::vflag;
use faces::FlatFaces;
use rules::{own_cost, own_costs, wedge_map, Rules, Scratch};

/// A pass keeps the vertices whose cost is at most [`CEILING_FACTOR`] times the cost at rank
/// `len / CONSIDERED_PART` (or at the rank of the collapses still needed, if fewer).
const CONSIDERED_PART: usize = 3;

/// Fewest vertices a parallel task takes (a bound or a check is a few tenths of a
/// microsecond to a microsecond).
const TASK: usize = 256;

/// Collapses until `target_faces` remain or nothing is allowed. Returns the collapse count.
pub(crate) fn run(e: &mut Engine<'_>, target_faces: usize, progress: &Progress) -> usize {
    let mut flat = FlatFaces::new(e.mesh);
    let n = flat.count.len();
    let plain = constraints::plain_attributes(e.mesh);
    let user_locked = |v: usize| e.mesh.topology.vflags[v] & vflag::LOCKED != 0;
    let mut active: Vec<u32> =
        (0..n as u32).filter(|&v| flat.count[v as usize] > 0 && !user_locked(v as usize)).collect();
    let mut quadrics = std::mem::take(&mut e.quadrics);
    let mut own = own_costs(e.mesh, &quadrics);
    // The pass in which a vertex was last an end of a collapse (locked for the rest of that
    // pass), and in which its fan last changed.
    let mut locked = vec![0u32; n];
    let mut marked = vec![0u32; n];
    // Each vertex's bound as last worked out (`None`: no allowed target), and the vertices
    // whose bound may have changed since: those whose fan changed, and the neighbours of
    // every target (their cost into it changed).
    let mut bound: Vec<Option<(f64, u32)>> = vec![None; n];
    let mut stale = active.clone();
    let mut is_stale = vec![true; n];
    let mut targets: Vec<u32> = Vec::new();
    let mut sc = Scratch::default();
    let mut everything = false;
    let mut collapses = 0;
    progress.init_done();
    let mut pass = 0u32;
    while e.live_faces > target_faces {
        pass += 1;
        let rules = rules_of(e, &flat, &quadrics, &own, plain);
        stale.retain(|&v| flat.count[v as usize] > 0);
        let fresh = map_sized(&stale, TASK, TASK, |sc: &mut Scratch, &u| rules.bound(u, sc));
        for (&v, b) in stale.iter().zip(fresh) {
            bound[v as usize] = b;
            is_stale[v as usize] = false;
        }
        stale.clear();
        active.retain(|&v| flat.count[v as usize] > 0);
        let mut order: Vec<(u64, u32)> =
            active.iter().filter_map(|&u| Some((ordered_bits(bound[u as usize]?.0), u))).collect();
        if order.is_empty() {
            break;
        }
        // Interior collapses remove two faces, border ones one.
        let goal = (e.live_faces - target_faces).div_ceil(2);
        let mut ceiling = u64::MAX;
        let consider = goal.min(order.len() / CONSIDERED_PART).max(1);
        if !everything && consider < order.len() {
            let (_, &mut (bits, u), _) = order.select_nth_unstable(consider);
            let cost = bound[u as usize].map_or(f64::INFINITY, |b| b.0);
            // Never below the cost at that rank: costs can come out a rounding error below
            // zero (flat regions), where 1.5x is lower.
            ceiling = bits.max(ordered_bits(CEILING_FACTOR * cost));
            order.retain(|&(k, _)| k <= ceiling);
        }
        // In (bound, vertex) order, sorted before the checks: a 12-byte key sorts far faster
        // than the checked picks would. The few picks whose target is not their bound's (it
        // failed a rule) cost more than their bound and are merged in at their own cost.
        order.par_sort_unstable();
        let checked =
            map_sized(&order, TASK, TASK, |sc: &mut Scratch, &(_, u)| rules.evaluate(u, bound[u as usize], sc));
        let (mut picks, mut late) = (Vec::with_capacity(checked.len()), Vec::new());
        for (p, &(key, _)) in checked.into_iter().zip(&order) {
            match p {
                Some(p) if ordered_bits(p.cost) == key => picks.push(p),
                Some(p) if ordered_bits(p.cost) <= ceiling => late.push(p),
                _ => {}
            }
        }
        if !late.is_empty() {
            late.sort_unstable_by_key(|p| (ordered_bits(p.cost), p.u));
            picks = merge_by_key(&picks, &late, |p| (ordered_bits(p.cost), p.u));
        }
        let made = collapses;
        for p in &picks {
            if e.live_faces <= target_faces {
                break;
            }
            let (u, v) = (p.u as usize, p.v as usize);
            if locked[u] == pass || locked[v] == pass {
                continue;
            }
            let rules = rules_of(e, &flat, &quadrics, &own, plain);
            let changed = marked[u] == pass
                || marked[v] == pass
                || p.wings.iter().any(|&w| w != u32::MAX && marked[w as usize] == pass);
            if changed {
                if !rules.still_passes(p, &mut sc) {
                    continue;
                }
            } else {
                flat.fan(p.u, e.mesh.topology.vflags[u] & vflag::BOUNDARY != 0, &mut sc.fan);
            }
            #[cfg(test)]
            assert!(rules.still_passes(p, &mut Scratch::default()), "pick {u} → {v} no longer passes");
            let (forward, backward) = sc.fan.edge(p.v);
            let map = wedge_map(&flat, forward, backward);
            for &x in sc.fan.ring.iter().chain([&p.u, &p.v]) {
                marked[x as usize] = pass;
                mark_stale(&mut stale, &mut is_stale, x);
            }
            targets.push(p.v);
            let q = quadrics[u];
            quadrics[v] += q;
            own[v] = own_cost(e.mesh, &quadrics[v], p.v);
            e.live_faces -= flat.collapse(p.u, p.v, &sc.fan, map);
            e.max_error = e.max_error.max(p.error);
            locked[u] = pass;
            locked[v] = pass;
            collapses += 1;
            progress.tick(e.live_faces);
        }
        flat.rebuild_rows();
        for &y in &targets {
            for f in flat.row(y) {
                for x in flat.tris[f as usize] {
                    mark_stale(&mut stale, &mut is_stale, x);
                }
            }
        }
        targets.clear();
        if collapses == made {
            if everything {
                break;
            }
            everything = true;
        } else {
            everything = false;
        }
    }
    e.quadrics = quadrics;
    write_back::write_back(e.mesh, &flat);
    collapses
}

/// The rules on the engine's mesh as handed in, with the flat faces and quadrics as they are
/// now.
fn rules_of<'a>(
    e: &'a Engine<'_>,
    flat: &'a FlatFaces,
    quadrics: &'a [super::Quadric],
    own: &'a [(f64, f64)],
    plain: bool,
) -> Rules<'a> {
    Rules { mesh: e.mesh, flat, quadrics, own, normal0: &e.normal0, free: &e.free, error_bound: e.error_bound, plain }
}

/// Lists `x` among the vertices whose bound is worked out again next pass, once.
fn mark_stale(stale: &mut Vec<u32>, is_stale: &mut [bool], x: u32) {
    if !is_stale[x as usize] {
        is_stale[x as usize] = true;
        stale.push(x);
    }
}
