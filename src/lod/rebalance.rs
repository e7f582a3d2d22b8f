//! Amortised rebalancing of dependency chains, papers/001 Figure 4.
//!
//! ```text
//!   chain depth of a front record R = the largest counter on its faces
//!   candidate: depth(R) ≥ 3, deepest first, at most `moves` per frame
//!   move:      split R (u comes back), then collapse u into another neighbour w whose
//!              collapse would sit at depth ≤ depth(R) − 2 ("more than two" shallower chains),
//!              is legal, keeps seams/borders, folds no face and stays under τc;
//!              if no neighbour qualifies, the original collapse is redone (always legal:
//!              the split restored its exact neighbourhood)
//! ```
//! A record that found no better neighbour is not tried again for [`RETRY_FRAMES`] frames,
//! and each frame makes at most `moves` attempts, so the cost per frame is bounded. On an
//! idle frame (a still camera: the views, the threshold and the mesh as the last frame left
//! them) only the attempts that get as far as a trial split count against `moves`, and up to
//! [`IDLE_LOOKS`] × `moves` records are looked at: most are turned away by `may_move` from
//! their counters alone, and spending the frame's attempts on those kept a still camera from
//! settling for hundreds of frames (docs/BENCHMARKS.md, "A still camera"). Nor is it
//! tried again before something changes: a failure remembers the count of changes (the view,
//! the threshold, an edit, a move) it saw, and a move's outcome depends on nothing else, so
//! under a still camera the attempts stop once every record has failed since the last change,
//! instead of coming round every [`RETRY_FRAMES`] frames for ever.
//! Most records cannot move at all: any collapse of u touches every face of u's fan, whose
//! counters drop by one at the split, so the new record lands at least as deep as the deepest
//! of those faces is now. Only the two faces across the wing edges carry depth a new target
//! need not inherit. `may_move` checks this from the counters before splitting anything (on
//! a bunny orbit it turns away ~98 % of the attempts, each a split, trial collapses and a
//! redone collapse).
//! The triangle count is unchanged by a move. Decision: a move must touch fewer than 16 faces,
//! so Φ = Σ_f 4^counter(f) strictly falls with every move (the deepest face loses 3·4^(d−1),
//! each new face gains at most 3·4^(d−3)); under a still camera rebalancing therefore stops.

use std::collections::VecDeque;

use bitvec::vec::BitVec;

use super::hierarchy::Hierarchy;
use super::runtime::{RebalanceScratch, Runtime};
use crate::mesh::constraints;
use crate::topology::{HalfEdgeCollapse, HalfEdges, Topology, INVALID};
use crate::view::Viewpoint;

/// Most faces a move may touch (see the module docs).
const MAX_TOUCHED: usize = 15;

/// Frames before a record that could not move is tried again.
pub const RETRY_FRAMES: u32 = 16;

/// On an idle frame, how many times the frame's attempts may be looked at (the module docs):
/// a check from the counters costs a small fraction of a trial split.
pub const IDLE_LOOKS: usize = 16;

/// Records whose move failed in the last [`RETRY_FRAMES`] frames, or since the last change:
/// a bit per vertex to ask, and the failures in the order they happened to expire them (a few
/// hundred; a frame stamp per vertex held 4 B per n for them), each with its frame and the
/// count of changes it saw.
#[derive(Debug, Clone)]
pub(super) struct RecentFailures {
    marked: BitVec,
    queue: VecDeque<(u32, u32, u32)>,
    /// Changes counted so far ([`RecentFailures::changed`]).
    changes: u32,
}

impl RecentFailures {
    pub(super) fn new(vertices: usize) -> Self {
        Self { marked: BitVec::repeat(false, vertices), queue: VecDeque::new(), changes: 0 }
    }

    /// Something a move is tested against changed: the mesh, the view or the threshold.
    pub(super) fn changed(&mut self) {
        self.changes = self.changes.wrapping_add(1);
    }

    /// Whether no failure can expire before the next change (all are since the last one): a
    /// run then tries only records it has not tried.
    fn settled(&self) -> bool {
        self.queue.front().is_none_or(|e| e.2 == self.changes)
    }

    /// Whether record `u` failed to move in the last [`RETRY_FRAMES`] frames.
    fn lately(&self, u: u32) -> bool {
        self.marked[u as usize]
    }

    /// Forgets the failures [`RETRY_FRAMES`] or more frames before `frame` that came before
    /// the last change. (The counts of changes in the queue never fall, so one since the last
    /// change is followed by no other kind.)
    fn expire(&mut self, frame: u32) {
        while let Some(&(u, at, changes)) = self.queue.front() {
            if frame.wrapping_sub(at) < RETRY_FRAMES || changes == self.changes {
                break;
            }
            self.marked.set(u as usize, false);
            self.queue.pop_front();
        }
    }

    /// Notes that `u` (not [`RecentFailures::lately`]) failed to move on `frame`.
    fn add(&mut self, u: u32, frame: u32) {
        debug_assert!(!self.marked[u as usize]);
        self.marked.set(u as usize, true);
        self.queue.push_back((u, frame, self.changes));
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        self.marked.capacity() / 8 + self.queue.capacity() * 12
    }
}

/// What [`run`] did.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Rebalanced {
    /// Records moved to a shallower chain.
    pub moves: usize,
    /// Records tried (moved or not).
    pub attempts: usize,
    /// A run right after this one, with nothing changed, would try nothing.
    pub settled: bool,
}

/// Makes up to `attempts` move attempts, deepest chains first; on an `idle` frame, up to
/// `attempts` trial splits among up to [`IDLE_LOOKS`] × `attempts` records (the module docs).
/// The caller counts the changes before it ([`RecentFailures::changed`]); each move counts
/// as one.
pub(super) fn run(rt: &mut Runtime, attempts: usize, idle: bool) -> Rebalanced {
    if attempts == 0 || rt.hierarchy.max_depth() < 3 {
        return Rebalanced { settled: true, ..Rebalanced::default() };
    }
    rt.with_scratch(|s| &mut s.rebalance, |rt, sc| run_with(rt, attempts, idle, sc))
}

/// [`run`] with its lists.
fn run_with(rt: &mut Runtime, attempts: usize, idle: bool, sc: &mut RebalanceScratch) -> Rebalanced {
    let h = &rt.hierarchy;
    let frame = rt.frame as u32;
    rt.rebalance_tried.expire(frame);
    let tried = &rt.rebalance_tried;
    let mut cands = std::mem::take(&mut sc.cands);
    cands.clear();
    cands.extend(h.front().map(|u| (h.depth(u), u)).filter(|&(d, u)| d >= 3 && !tried.lately(u)));
    // Deepest first, ties by id (a total order, so the outcome does not depend on the
    // algorithm): select the first `attempts` in linear time and sort only those. (The time
    // of a warm frame's rebalancing is in the trial splits and redone collapses, not here.)
    let order = |a: &(u16, u32), b: &(u16, u32)| b.0.cmp(&a.0).then(a.1.cmp(&b.1));
    let looks = if idle { attempts.saturating_mul(IDLE_LOOKS) } else { attempts };
    if cands.len() > looks {
        cands.select_nth_unstable_by(looks - 1, order);
        cands.truncate(looks);
    }
    cands.sort_unstable_by(order);
    let (mut done, mut counted) = (Rebalanced::default(), 0);
    for &(d, u) in &cands {
        if counted == attempts {
            break;
        }
        if !rt.hierarchy.is_splittable(u) {
            continue;
        }
        done.attempts += 1;
        let may = may_move(&rt.hierarchy, &rt.mesh.topology, u, d);
        counted += usize::from(may || !idle);
        if may && move_one_with(rt, u, sc) {
            done.moves += 1;
            rt.rebalance_tried.changed();
        } else {
            rt.rebalance_tried.add(u, frame);
        }
    }
    sc.cands = cands;
    // Tried nothing, and no failure can come back before a change: the next run tries nothing.
    done.settled = done.attempts == 0 && rt.rebalance_tried.settled();
    done
}

/// Whether front record `u` at chain depth `depth` could move at all: every face of u's fan
/// (all it touched but the two across its wing edges, `outer()[0]` and `outer()[3]`) must be at
/// least two shallower, since the fan comes back one shallower at the split and any new
/// target touches all of it. A necessary condition, so skipping the records that fail it
/// changes no move.
pub(super) fn may_move(h: &Hierarchy, t: &Topology, u: u32, depth: u16) -> bool {
    let outer = h.record(u).outer(t);
    let across = [outer[0], outer[3]].map(|g| if g == INVALID { INVALID } else { g / 3 });
    h.faces_on_top(t, u).filter(|f| !across.contains(f)).all(|f| h.counter(f) + 2 <= depth)
}

/// Tries to move record `u` to a shallower chain; returns whether it moved.
#[cfg(test)]
fn move_one(rt: &mut Runtime, u: u32) -> bool {
    rt.with_scratch(|s| &mut s.rebalance, |rt, sc| move_one_with(rt, u, sc))
}

/// `move_one` with its lists.
fn move_one_with(rt: &mut Runtime, u: u32, sc: &mut RebalanceScratch) -> bool {
    let RebalanceScratch { faces: touched, neighbours, fan, allowed, changed, .. } = sc;
    let depth = rt.hierarchy.depth(u);
    let old = rt.hierarchy.record(u).target;
    // Only split if some other neighbour can take u: check on a trial basis after the split,
    // and redo the original collapse otherwise.
    touched.clear();
    rt.split_vertex(u, touched).expect("front records are splittable");
    let tau_c = rt.collapse_threshold();
    let mut best: Option<(u16, u32)> = None;
    neighbours.clear();
    neighbours.extend(rt.mesh.topology.neighbors(u));
    fan.clear();
    fan.extend(rt.mesh.topology.outgoing(u));
    constraints::movable_targets(&rt.mesh, u, fan, constraints::BORDER_CORNER_DEGREES, allowed);
    for &w in neighbours.iter() {
        if w == old || !allowed.iter().any(|&(_, x)| x == w) {
            continue;
        }
        let Some(he) = rt.mesh.topology.find_edge(u, w) else { continue };
        let c = HalfEdgeCollapse { he, remove: u };
        let (hu, hv) = constraints::halves(&rt.mesh.topology, c);
        if rt.mesh.topology.collapse_is_legal(c).is_err()
            || !constraints::wedges_carry_over(&rt.mesh, fan.iter().copied(), hu, hv)
            || folds(rt, u, w, fan, hu, hv)
        {
            continue;
        }
        let Ok(plan) = rt.hierarchy.plan(&rt.mesh, c) else { continue };
        let d = plan.depth_after(&rt.hierarchy);
        if plan.touched().len() > MAX_TOUCHED || d + 2 > depth {
            continue;
        }
        let (e, r) = rt.plan_charge(u, &plan);
        if rt.pixels(u, e, r) > tau_c {
            continue;
        }
        if best.is_none_or(|(bd, bw)| (d, w) < (bd, bw)) {
            best = Some((d, w));
        }
    }
    let moved = match best {
        Some((_, w)) => rt.try_collapse(u, w, tau_c, touched),
        None => false,
    };
    if !moved {
        let redone = rt.try_collapse(u, old, f32::INFINITY, touched);
        debug_assert!(redone, "the original collapse of {u} into {old} must be redoable");
    }
    rt.reclassify_faces(touched, changed);
    moved
}

/// Whether moving u onto w turns a surviving face of u over, or turns a face that faces an
/// eye away from it.
fn folds(rt: &Runtime, u: u32, w: u32, fan: &[u32], hu: u32, hv: u32) -> bool {
    let seen_from = |e: Viewpoint, x: glam::DVec3| glam::DVec3::from(e.seen_from(x.to_array()));
    constraints::moved_faces(&rt.mesh, fan, u, w, (hu, hv)).any(|m| {
        m.before.dot(m.after) <= 0.0
            || rt.eyes.iter().any(|&e| {
                m.before.dot(seen_from(e, m.corner_before)) > 0.0 && m.after.dot(seen_from(e, m.corner_after)) <= 0.0
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lod::RuntimeOptions;

    /// Every front record that [`may_move`] turns away really cannot move ([`move_one`]
    /// fails, leaving the mesh as it was), and it does not turn away every record that can.
    #[test]
    fn records_turned_away_before_the_split_could_not_have_moved() {
        let mut rt = crate::test_bunny_runtime(RuntimeOptions::default().rebalance_moves(0), 0, (1920, 1080));
        let mut deep: Vec<(u16, u32)> =
            rt.hierarchy.front().map(|u| (rt.hierarchy.depth(u), u)).filter(|&(d, _)| d >= 3).collect();
        deep.sort_unstable();
        let (mut refused, mut passed, mut moved) = (0, 0, 0);
        for (d, u) in deep {
            if !rt.hierarchy.is_splittable(u) || rt.hierarchy.depth(u) != d {
                continue; // an earlier move changed its neighbourhood
            }
            if may_move(&rt.hierarchy, &rt.mesh.topology, u, d) {
                passed += 1;
                moved += usize::from(move_one(&mut rt, u));
            } else {
                refused += 1;
                let faces = rt.mesh.topology.live_face_count();
                assert!(!move_one(&mut rt, u), "record {u} at depth {d} moved after all");
                assert_eq!(rt.mesh.topology.live_face_count(), faces);
            }
        }
        rt.mesh.topology.validate().unwrap();
        rt.hierarchy.check(&rt.mesh.topology).unwrap();
        assert!(refused > 100 && passed > 10 && moved > 0, "refused {refused}, passed {passed}, moved {moved}");
    }

    /// Under a still camera, once updates are skipped (no failed move comes back before a
    /// change), no front record could move: every one that failed did so after the last
    /// change, so none was given up on too early.
    #[test]
    fn a_settled_still_camera_leaves_no_record_that_could_move() {
        let m = crate::test_bunny();
        let (centre, diag) = crate::camera_path::frame_bounds(&m.positions);
        let view = crate::camera_path::CameraPath::Dolly.view(0, 100, centre, diag, (1920, 1080));
        let mut rt = Runtime::new(m, RuntimeOptions::default());
        let (mut moves, mut settled) = (0, false);
        for _ in 0..200 {
            let s = rt.update(Some(&view));
            moves += s.rebalanced;
            if s.skipped {
                settled = true;
                break;
            }
        }
        assert!(settled && moves > 50, "settled {settled} after {moves} moves");
        let deep: Vec<u32> = rt.hierarchy.front().filter(|&u| rt.hierarchy.depth(u) >= 3).collect();
        assert!(deep.len() > 300, "{} deep records", deep.len());
        for u in deep {
            assert!(!rt.hierarchy.is_splittable(u) || !move_one(&mut rt, u), "record {u} could still move");
        }
    }
}
