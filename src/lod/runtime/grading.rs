//! Graded collapse phases (docs/ALGORITHM.md, "Graded cold start", "Camera cuts are graded
//! too"): on a first frame, and on a frame whose tolerance grew 4× or more since the last
//! (a camera cut), collapse phases at τ / 2^k run before τ itself, so that what a lower
//! threshold keeps serves as targets for what it removes (papers/000 §4: R vertices collapse
//! only into S), as when a camera moves away frame by frame.

use super::budget::{BudgetControl, MIN_PIXEL_ERROR};
#[cfg(doc)]
use super::RuntimeOptions;
use super::{FrameStats, Runtime};
use crate::view::Frustum;

impl Runtime {
    /// The graded start of a first frame or a cut ([`RuntimeOptions::cold_grades`],
    /// [`Runtime::grades`]): collapse phases at τ / 2^k, k from `grades` down to 1, each from
    /// a fresh classification. Every record made answers at most τc / 2, so the frame's own
    /// phases split none of them. Returns whether a phase hit the round cap. A phase that
    /// reaches the edit cap stops the frame's grading, and the next frame takes it up again
    /// at that phase.
    pub(super) fn graded_start(&mut self, grades: u32, s: &mut FrameStats) -> bool {
        let (tau, mut capped) = (self.tau, false);
        for k in (1..=grades.min(30)).rev() {
            self.tau = tau / (1u32 << k) as f32;
            self.timed_classify(s);
            capped |= self.timed_collapses(s);
            s.graded_phases += 1;
            if self.edits_left == 0 {
                self.pending_grades = k;
                break;
            }
        }
        self.tau = tau;
        capped
    }

    /// How many graded phases this frame runs: all of [`RuntimeOptions::cold_grades`] on the
    /// first frame; on a later one, where the tolerance grew [`CUT_DOUBLINGS`] times or more
    /// since the last frame (a camera cut, a raised pixel error), one per doubling and
    /// [`CUT_MARGIN`] more, up to the option.
    pub(super) fn grades(&self) -> u32 {
        let most = self.options.cold_grades;
        let Some(growth) = self.tolerance_growth() else { return most };
        let doublings = growth.log2().floor();
        // An undefined growth (∞ / ∞, from a degenerate view) is no cut.
        if doublings.is_nan() || doublings < CUT_DOUBLINGS as f32 {
            return 0;
        }
        (doublings.min(30.0) as u32 + CUT_MARGIN).min(most)
    }

    /// Budget mode across a camera cut (the tolerance at the current threshold moved 4× or
    /// more either way since the last frame): the threshold is rescaled to allow the last
    /// frame's tolerance again, and the controller starts afresh. The mesh then needs few
    /// edits to serve the new view at about the triangle count it had, where the old
    /// threshold would have collapsed nearly everything (a jump away) or split back tens of
    /// thousands of vertices to collapse them again within the frame (a jump in); the
    /// controller corrects the rest over the next frames.
    pub(super) fn carry_budget_over_a_cut(&mut self) {
        if self.options.budget.is_none() {
            return;
        }
        if let Some(growth) = self.tolerance_growth().filter(|&g| is_cut(g)) {
            self.tau = across_a_cut(self.tau, growth);
            self.budget = BudgetControl::default();
        }
    }

    /// How many times the tolerance at the current threshold and views exceeds the last
    /// frame's (`None` before the first frame; NaN or ∞ where a view is degenerate).
    pub(in crate::lod) fn tolerance_growth(&self) -> Option<f32> {
        (self.last_tolerance > 0.0).then(|| self.tolerance() / self.last_tolerance)
    }

    /// The model-space error the current threshold allows at the mesh's bounding sphere's
    /// centre (an eye inside the sphere counts as on it): τ over the pixels per unit there,
    /// the least over the views (the one that sees the mesh largest decides), or τ itself
    /// without a view.
    pub(super) fn tolerance(&self) -> f32 {
        let (c, r) = self.sphere;
        let at = |f: &Frustum| {
            let d = glam::Vec3::from(f.eye()).distance(glam::Vec3::from(c));
            self.tau / f.pixels_per_unit_at(d.max(r))
        };
        self.frustums.iter().map(at).reduce(f32::min).unwrap_or(self.tau)
    }
}

/// Whether the tolerance growing `growth` times from one frame to the next is a camera cut
/// for the budget ([`Runtime::carry_budget_over_a_cut`]): [`CUT_DOUBLINGS`] either way.
pub(in crate::lod) fn is_cut(growth: f32) -> bool {
    let cut = (CUT_DOUBLINGS as f32).exp2();
    growth.is_finite() && growth > 0.0 && (growth >= cut || growth <= 1.0 / cut)
}

/// The threshold that allows the last frame's tolerance again after it grew `growth` times.
pub(in crate::lod) fn across_a_cut(tau: f32, growth: f32) -> f32 {
    (tau / growth).clamp(MIN_PIXEL_ERROR, 1e30)
}

/// The doublings of the tolerance from one frame to the next that make a cut, graded like a
/// first frame. A camera moving on a path stays far under it; at 2× (one doubling) grading
/// changed the bunny's and igea's counts by under 1 %, up or down (docs/BENCHMARKS.md,
/// "Camera cuts").
const CUT_DOUBLINGS: u32 = 2;

/// Graded phases a cut runs beyond one per doubling of the tolerance: the tolerance is read
/// at the mesh's centre, and the parts of the mesh nearest the old eye saw it grow more
/// (igea from 0.6 to 40 diagonals: 444 triangles with no margin, 428 with one, as with two).
const CUT_MARGIN: u32 = 1;
