//! One update in its phases: [`Runtime::begin_frame`] takes the views, [`Runtime::start_frame`]
//! runs the graded phases of a first frame or a cut, [`Runtime::attempt`] classifies, splits
//! and collapses at the threshold (once in pixel-error mode; again after each raise in budget
//! mode), and [`Runtime::end_frame`] rebalances, updates the index buffer and says what the
//! frame did. [`Runtime::update`] runs them in that order with its own budget controller
//! (`budget.rs`); a [`SceneRuntime`](crate::lod::SceneRuntime) under one budget runs the same
//! phases on every mesh, with one controller for the whole scene between the attempts
//! (`../scene_budget.rs`).

use std::time::Instant;

use super::budget::{BudgetControl, Moved, Raising};
use super::{ms, rebalance, same_views, scratch, FrameStats, FrameStop, Runtime, MAX_ATTEMPTS};
use crate::view::{Frustum, View};

/// A frame under way: what its phases counted so far, and what its end compares with.
pub(in crate::lod) struct Frame {
    /// The figures so far.
    pub(in crate::lod) s: FrameStats,
    /// The last attempt's split or collapse phase hit the round cap.
    capped: bool,
    /// A graded phase hit the round cap.
    graded_cap: bool,
    /// The views are the last frame's.
    same_views: bool,
    /// The threshold and the budget's controller when the frame began.
    tau_before: f32,
    budget_before: BudgetControl,
    /// The frame ran out of attempts over its budget.
    pub(in crate::lod) out_of_attempts: bool,
}

impl Runtime {
    /// [`Runtime::update`] on the calling thread; `start` is when the caller asked.
    pub(super) fn update_here(&mut self, views: &[View], start: Instant) -> FrameStats {
        let mut f = self.begin_frame(views);
        self.carry_budget_over_a_cut();
        self.start_frame(&mut f);
        // The last attempt raised the threshold; a lowering to the exact count ran already.
        let (mut raised, mut filled) = (false, false);
        while (f.s.attempts as usize) < MAX_ATTEMPTS {
            // The edit cap ends the frame; the budget is not adjusted on a mesh still catching up.
            let Some(changed) = self.attempt(&mut f) else { break };
            if raised {
                let (mut control, mut tau) = (std::mem::take(&mut self.budget), self.tau);
                let go = control.after_raise(changed, &mut tau, || self.removal_threshold());
                (self.budget, self.tau) = (control, tau);
                match go {
                    Raising::Stop => break,
                    Raising::Jumped => continue,
                    Raising::Go => {}
                }
            }
            if f.s.attempts as usize == MAX_ATTEMPTS {
                f.out_of_attempts = self.options.budget.is_some_and(|b| self.live_faces() > b);
                break;
            }
            match self.adjust_budget(f.s.splits > 0) {
                Moved::Raised => raised = true,
                // Far under the budget (a cut away, a raised budget): split to the count now
                // rather than show the emptied mesh for a frame. Once a frame, as the count
                // is exact.
                Moved::Filled if !filled => (raised, filled) = (false, true),
                _ => break,
            }
        }
        self.end_frame(f, start)
    }

    /// Starts a frame with `views`: counts it, makes them the current views and opens the
    /// frame's edit allowance. The threshold may still be moved before [`Runtime::start_frame`]
    /// (a budget carried over a cut).
    pub(in crate::lod) fn begin_frame(&mut self, views: &[View]) -> Frame {
        self.frame += 1;
        self.repeatable = None;
        let (tau_before, budget_before) = (self.tau, self.budget.clone());
        let same_views = self.take_views(views);
        self.edits_left = self.options.max_edits.unwrap_or(usize::MAX);
        Frame {
            s: FrameStats { frame: self.frame, ..Default::default() },
            capped: false,
            graded_cap: false,
            same_views,
            tau_before,
            budget_before,
            out_of_attempts: false,
        }
    }

    /// The graded phases of a first frame or a camera cut (`grading.rs`), at the threshold
    /// in force.
    pub(in crate::lod) fn start_frame(&mut self, f: &mut Frame) {
        let grades = self.grades().max(std::mem::take(&mut self.pending_grades));
        f.graded_cap = self.graded_start(grades, &mut f.s);
    }

    /// One attempt at the threshold in force: classify, split, collapse. Returns whether it
    /// split or collapsed anything, or `None` where the edit cap is reached (the frame ends).
    pub(in crate::lod) fn attempt(&mut self, f: &mut Frame) -> Option<bool> {
        if self.edits_left == 0 {
            return None;
        }
        let before = f.s.splits + f.s.collapses;
        f.s.attempts += 1;
        self.timed_classify(&mut f.s);
        let t = Instant::now();
        let (splits, rounds, cap) = self.split_phase();
        f.s.splits += splits;
        f.s.split_rounds += rounds;
        f.s.split_ms += ms(t);
        f.capped = self.timed_collapses(&mut f.s) || cap;
        if self.edits_left == 0 {
            return None;
        }
        Some(f.s.splits + f.s.collapses != before)
    }

    /// Ends the frame: rebalancing, the index buffer, the figures; and, where the frame
    /// changed nothing an update reads, makes the next update with these views a repeat.
    pub(in crate::lod) fn end_frame(&mut self, f: Frame, start: Instant) -> FrameStats {
        let Frame { mut s, capped, graded_cap, same_views, tau_before, budget_before, out_of_attempts } = f;
        let rebalance_settled = self.timed_rebalance(&mut s, same_views);
        let t4 = Instant::now();
        self.live.shrink();
        self.sync_index();
        if self.frame % scratch::TRIM_EVERY == 1 {
            self.scratch.trim(self.live.entries().len(), self.live.len());
            let keep = self.live.len() / 16;
            for v in std::iter::once(&mut self.flagged).chain(self.hierarchy.swapped_lists()) {
                scratch::trim(v, keep);
            }
        }
        s.output_ms = ms(t4);
        s.changed_triangles = self.index.changed_triangles();
        s.changed_ranges = self.index.changed_range_count();
        s.triangles = self.index.live();
        s.vertices = self.live.len();
        s.max_chain_depth = self.hierarchy.max_depth();
        s.mean_chain_depth = self.hierarchy.mean_depth();
        s.pixel_error = self.tau;
        self.last_tolerance = self.tolerance();
        s.stop = if self.edits_left == 0 {
            FrameStop::EditCap
        } else if capped || graded_cap {
            FrameStop::RoundCap
        } else if out_of_attempts {
            FrameStop::AttemptCap
        } else {
            FrameStop::Converged
        };
        // Nothing an update reads has changed, and no failed move can come back before
        // something does (a settled rebalancing tried nothing): the next update with this
        // view would do the same nothing.
        let unchanged = s.splits + s.collapses + s.changed_triangles == 0
            && rebalance_settled
            && s.graded_phases == 0
            && self.pending_grades == 0
            && s.stop == FrameStop::Converged
            && self.tau.to_bits() == tau_before.to_bits()
            && self.budget == budget_before;
        if unchanged && self.options.skip_unchanged_frames {
            self.repeatable = Some(s);
        }
        s.total_ms = ms(start);
        s
    }

    /// Live faces now (the index buffer counts them only at the end of a frame).
    pub(in crate::lod) fn live_faces(&self) -> usize {
        self.mesh.topology.live_face_count()
    }

    /// Makes `views` the current views; returns whether they are the last frame's (as a set,
    /// [`same_views`]). Allocates only when more views come than ever before.
    fn take_views(&mut self, views: &[View]) -> bool {
        let same = same_views(views, &self.views);
        self.views.clear();
        self.views.extend_from_slice(views);
        self.frustums.clear();
        self.eyes.clear();
        let (order, keep) = &mut self.scratch.views;
        crate::view::distinct_into(views, order, keep);
        for &k in keep.iter() {
            let v = &views[k as usize];
            self.frustums.push(Frustum::new(v));
            self.eyes.push(v.viewpoint());
        }
        self.view_order.set(&self.frustums, self.sphere);
        same
    }

    /// [`Runtime::classify_all`], its time counted in `s`.
    pub(super) fn timed_classify(&mut self, s: &mut FrameStats) {
        let t = Instant::now();
        self.classify_all();
        s.classify_ms += ms(t);
    }

    /// [`Runtime::collapse_phase`], counted in `s`; returns whether it hit the round cap.
    pub(super) fn timed_collapses(&mut self, s: &mut FrameStats) -> bool {
        let t = Instant::now();
        let (collapses, rounds, cap) = self.collapse_phase();
        s.collapses += collapses;
        s.collapse_rounds += rounds;
        s.collapse_ms += ms(t);
        cap
    }

    /// Rebalancing (`rebalance.rs`), counted in `s`; returns whether a run right after it
    /// with nothing changed would try nothing. A change since the last frame's run (other
    /// views (`same_views` false) or another threshold, an edit, a hand edit) lets the moves
    /// that failed before it be tried again; without one the frame is idle, and rebalancing
    /// looks further.
    fn timed_rebalance(&mut self, s: &mut FrameStats, same_views: bool) -> bool {
        let t = Instant::now();
        let tau = self.tau.to_bits();
        let same = same_views && s.splits + s.collapses == 0 && self.rebalanced_at == Some(tau);
        if !same {
            self.rebalance_tried.changed();
        }
        self.rebalanced_at = Some(tau);
        let r = rebalance::run(self, self.options.rebalance_moves, same);
        (s.rebalanced, s.rebalance_attempts) = (r.moves, r.attempts);
        s.rebalance_ms = ms(t);
        r.settled
    }

    /// Budget mode (`budget.rs`): moves the threshold and says how.
    fn adjust_budget(&mut self, frame_split: bool) -> Moved {
        let Some(budget) = self.options.budget else { return Moved::Held };
        let tris = self.live_faces();
        let (mut control, mut tau) = (std::mem::take(&mut self.budget), self.tau);
        let moved = self.with_scratch(
            |s| &mut s.kth,
            |rt, sc| {
                let kth = |k| rt.kth_record_pixels(k, sc);
                control.adjust(&mut tau, tris, budget, || rt.front_max_pixels(), kth, frame_split)
            },
        );
        (self.budget, self.tau) = (control, tau);
        moved
    }
}
