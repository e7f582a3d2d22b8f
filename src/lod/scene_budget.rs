//! One triangle budget for a whole [`SceneRuntime`]: the triangles the scene draws (each
//! mesh's live triangles times its placements) held at or under the budget by one split
//! threshold τs shared by every mesh (a decision beyond papers/000 and papers/001, which fix
//! τs for one mesh).
//!
//! One threshold for all is what spends a budget where it shows: a vertex of any mesh stays
//! collapsed while its error in pixels (the largest over the instances that draw it) is
//! within τs, so the scene's screen error is even, the nearest objects get the triangles and
//! the far ones give them up. The threshold's controller is the single runtime's
//! (`runtime/budget.rs`), fed with the scene's figures: the drawn count, the front's largest
//! pixel error over the meshes, the next removable vertex over the meshes, and for the exact
//! lowering the k-th largest pixel error over all collapsed vertices with each counted once per
//! placement (a split in a mesh drawn five times adds five times its triangles).
//!
//! A frame runs every drawn mesh through the phases of `runtime/frame.rs` in step: the meshes
//! begin their frames side by side on the pool, run the graded phases of a first frame or a
//! cut, then attempt (classify, split, collapse) at the threshold side by side; between
//! attempts the controller reads the scene and raises the threshold while it is over the
//! budget, as one runtime does. Each runtime is updated once per frame, so its index buffer's
//! changed ranges are the whole frame's. A camera cut is judged by the tolerance growth of the
//! mesh at the drawn-triangle-weighted median: the threshold is rescaled as a single runtime
//! rescales its own (`runtime/grading.rs`).
//!
//! With one mesh and one placement this is the single runtime's budget mode, frame for frame
//! (`tests/scene_runtime.rs`). What it gives up: a mesh whose views repeat is not skipped
//! alone in budget mode (the threshold may rise within the frame, and every mesh must answer
//! at it); a frame every mesh would skip, under a settled controller, is still skipped whole.

use std::time::Instant;

use rayon::prelude::*;

use super::runtime::{across_a_cut, is_cut, BudgetControl, Frame, KthScratch, Moved, Raising};
use super::scene_runtime::SceneMeshRuntime;
use super::{FrameStats, SceneRuntime};

/// The budget mode's state, kept between frames (and its lists, kept for reuse).
#[derive(Default)]
pub(super) struct SceneBudget {
    /// The scene's triangle budget (drawn triangles); `None`: pixel-error mode.
    pub(super) tris: Option<usize>,
    /// The controller of the one threshold.
    control: BudgetControl,
    /// The last frame moved neither the threshold nor the controller (a frame every mesh
    /// repeats may then be skipped).
    pub(super) settled: bool,
    /// Each mesh's frame under way.
    frames: Vec<Option<Frame>>,
    /// The exact lowering's lists.
    kth: KthScratch,
    weighted: Vec<(f32, u32)>,
    /// The cut's growths and weights.
    growths: Vec<(f32, usize)>,
}

impl SceneBudget {
    pub(super) fn new(tris: Option<usize>) -> Self {
        Self { tris, ..Default::default() }
    }

    /// A new budget: the controller starts afresh.
    pub(super) fn restart(&mut self, tris: Option<usize>) {
        (self.tris, self.control, self.settled) = (tris, BudgetControl::default(), false);
    }
}

/// Whether a mesh is drawn (has placements) and so takes part in the frame.
fn drawn(m: &SceneMeshRuntime) -> bool {
    !m.placements.is_empty()
}

/// Triangles a mesh draws now: its live faces (mid-frame) times its placements.
fn drawn_now(m: &SceneMeshRuntime) -> usize {
    m.runtime.live_faces() * m.placements.len()
}

impl SceneRuntime {
    /// One frame under the scene's budget (the module docs); the views are in `meshes` already.
    pub(super) fn update_in_budget(&mut self, budget: usize) {
        let start = Instant::now();
        let Self { meshes, stats, tau, budget: b, .. } = self;
        let (tau_before, control_before) = (*tau, b.control.clone());
        b.frames.clear();
        b.frames.resize_with(meshes.len(), || None);
        crate::par::on_pool(|| {
            let each = |(m, f): (&mut SceneMeshRuntime, &mut Option<Frame>)| {
                if drawn(m) {
                    m.runtime.tau = *tau;
                    *f = Some(m.runtime.begin_frame(&m.views));
                }
            };
            meshes.par_iter_mut().zip(&mut b.frames).for_each(each);
            if let Some(growth) = cut_growth(meshes, &mut b.growths).filter(|&g| is_cut(g)) {
                *tau = across_a_cut(*tau, growth);
                b.control = BudgetControl::default();
            }
            let each = |(m, f): (&mut SceneMeshRuntime, &mut Option<Frame>)| {
                if let Some(f) = f {
                    m.runtime.tau = *tau;
                    m.runtime.start_frame(f);
                }
            };
            meshes.par_iter_mut().zip(&mut b.frames).for_each(each);
            attempts(meshes, b, tau, budget);
            let each = |((m, f), s): ((&mut SceneMeshRuntime, &mut Option<Frame>), &mut FrameStats)| {
                *s = match f.take() {
                    Some(f) => {
                        m.runtime.tau = *tau;
                        m.runtime.end_frame(f, start)
                    }
                    None => FrameStats { skipped: true, ..FrameStats::default() },
                };
            };
            meshes.par_iter_mut().zip(&mut b.frames).zip(stats.par_iter_mut()).for_each(each);
        });
        b.settled = tau.to_bits() == tau_before.to_bits() && b.control == control_before;
    }
}

/// The attempts of a budget frame: every drawn mesh classifies, splits and collapses at the
/// threshold, side by side, and the controller moves the threshold between attempts, as
/// `Runtime::update_here` does for one mesh.
fn attempts(meshes: &mut [SceneMeshRuntime], b: &mut SceneBudget, tau: &mut f32, budget: usize) {
    // The last attempt raised the threshold; a lowering to the exact count ran already.
    let (mut raised, mut filled, mut made) = (false, false, 0);
    while made < super::runtime::MAX_ATTEMPTS {
        made += 1;
        let one = |(m, f): (&mut SceneMeshRuntime, &mut Option<Frame>)| match f {
            Some(f) => {
                m.runtime.tau = *tau;
                // (edit cap reached, changed)
                m.runtime.attempt(f).map_or((true, false), |changed| (false, changed))
            }
            None => (false, false),
        };
        let or = |x: (bool, bool), y: (bool, bool)| (x.0 || y.0, x.1 || y.1);
        let (capped, changed) = meshes.par_iter_mut().zip(&mut b.frames).map(one).reduce(|| (false, false), or);
        // A mesh's edit cap ends the frame; the budget is not adjusted on a scene catching up.
        if capped {
            break;
        }
        let meshes = &*meshes;
        if raised {
            let next_removal = || {
                meshes.iter().filter(|m| drawn(m)).map(|m| m.runtime.removal_threshold()).fold(f32::INFINITY, f32::min)
            };
            match b.control.after_raise(changed, tau, next_removal) {
                Raising::Stop => break,
                Raising::Jumped => continue,
                Raising::Go => {}
            }
        }
        let count: usize = meshes.iter().map(drawn_now).sum();
        if made == super::runtime::MAX_ATTEMPTS {
            for f in b.frames.iter_mut().flatten() {
                f.out_of_attempts = count > budget;
            }
            break;
        }
        let split = b.frames.iter().flatten().any(|f| f.s.splits > 0);
        let front_max = || meshes.iter().filter(|m| drawn(m)).map(|m| m.runtime.front_max_pixels()).fold(0.0, f32::max);
        let (kth, weighted) = (&mut b.kth, &mut b.weighted);
        let kth_px = |k| weighted_kth(meshes, kth, weighted, k);
        match b.control.adjust(tau, count, budget, front_max, kth_px, split) {
            Moved::Raised => raised = true,
            // Far under the budget: split to the count now (once a frame; the count is exact).
            Moved::Filled if !filled => (raised, filled) = (false, true),
            _ => break,
        }
    }
}

/// The tolerance growth since the last frame of the drawn mesh at the median of the drawn
/// triangles (the last frame's, one at least per mesh), or `None` before any mesh's first
/// frame. With one mesh, its own growth.
fn cut_growth(meshes: &[SceneMeshRuntime], growths: &mut Vec<(f32, usize)>) -> Option<f32> {
    growths.clear();
    let weighed = |m: &SceneMeshRuntime| {
        Some((m.runtime.tolerance_growth()?, (m.runtime.triangles() * m.placements.len()).max(1)))
    };
    growths.extend(meshes.iter().filter(|m| drawn(m)).filter_map(weighed));
    growths.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = growths.iter().map(|g| g.1).sum::<usize>().div_ceil(2);
    let mut seen = 0;
    growths
        .iter()
        .copied()
        .find(|&(_, w)| {
            seen += w;
            seen >= half
        })
        .map(|(g, _)| g)
}

/// The pixel error at which the splits of the drawn meshes' collapsed vertices, each counted
/// once per placement of its mesh, first number `k` (0 where they number fewer, or `k` is 0):
/// for one placement, the k-th largest pixel error (`Runtime::kth_record_pixels`).
fn weighted_kth(meshes: &[SceneMeshRuntime], sc: &mut KthScratch, out: &mut Vec<(f32, u32)>, k: usize) -> f32 {
    out.clear();
    for m in meshes.iter().filter(|m| drawn(m)) {
        m.runtime.collapsed_pixels_into(sc);
        let w = m.placements.len() as u32;
        out.extend(sc.pixels.iter().map(|&px| (px, w)));
    }
    if k == 0 {
        return 0.0;
    }
    out.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
    let mut seen = 0usize;
    out.iter()
        .find(|&&(_, w)| {
            seen += w as usize;
            seen >= k
        })
        .map_or(0.0, |&(px, _)| px)
}
