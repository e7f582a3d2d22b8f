//! A level of detail made once, offline, for fixed views: the runtime's frames from the full
//! mesh until one changes nothing (`dynlod simplify --method runtime`).
//!
//! papers/000's rounds alone (`coarsen_views`) classify the input once, and R vertices
//! collapse only into S: from far away nearly everything is in R, the few anchors are the only
//! targets, and the boundary planes of faces seen edge-on stop the rounds early, so a farther
//! eye can leave *more* triangles (the 2CylinderEngine from 2, 8 and 32 diagonals: 49,427,
//! 53,291 and 58,223). The runtime's first frame runs graded phases at τ / 2^k first
//! (docs/ALGORITHM.md, "Graded cold start"), so what a finer phase keeps serves as targets
//! for the next, as when a camera moves away frame by frame, and each record's charge
//! carries the errors of the records it buries (papers/001's chains; "Errors are monotone
//! along chains"): every removed vertex, with everything collapsed into it, is within the
//! threshold in every view, and no triangle turns against any eye. Rebalancing is off (it
//! moves chains for later splits, which an offline cut never makes).

use std::time::Instant;

use super::budget::MIN_PIXEL_ERROR;
use super::{FrameStats, Runtime, RuntimeOptions};
use crate::lod::{input_error, InputError};
use crate::mesh::Mesh;
use crate::view::View;

/// Updates a cut may take at one threshold to reach a frame that changes nothing (two or
/// three in practice: the cut, a repeat that changes nothing, and the skipped one).
pub const CUT_FRAMES: usize = 16;

/// What [`Runtime::cut`] made.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Cut {
    /// The mesh as the runtime left it (collapsed vertices removed, faces in place).
    pub mesh: Mesh,
    /// The threshold the cut ended at (pixels, or model units without a view).
    pub threshold: f32,
    /// The last frame that did something.
    pub last: FrameStats,
    /// Updates made, over every threshold tried.
    pub frames: usize,
    /// Whether the last threshold's updates reached one that changed nothing within
    /// [`CUT_FRAMES`].
    pub settled: bool,
    /// Collapses over every frame.
    pub collapses: usize,
    /// Splits over every frame (a count's threshold search splits back some of what it
    /// collapsed on the way).
    pub splits: usize,
    /// Wall time of the updates.
    pub milliseconds: f64,
}

impl Runtime {
    /// The level of detail the runtime keeps for `views` (none: view-independent, the pixel
    /// error in model units), made from the full `mesh` and served until an update changes
    /// nothing, at `options`' pixel error (its budget, if any, is left out: for a count use
    /// [`Runtime::cut_to_triangles`]). See the module docs.
    ///
    /// A view that fails [`View::check`], or a negative or NaN pixel error, is refused
    /// before anything is done ([`InputError`]).
    pub fn cut(mesh: Mesh, views: &[View], options: RuntimeOptions) -> Result<Cut, InputError> {
        let start = Instant::now();
        input_error::check(views, options.pixel_error)?;
        let mut c = Cutting::new(mesh, options);
        c.settle(views);
        Ok(c.done(start))
    }

    /// [`Runtime::cut`] with the threshold searched so that the cut keeps at most `target`
    /// triangles, as many as it can: the cut at `options`' pixel error first, then the
    /// threshold moved by ×4 until the target is bracketed and bisected (in log space, to
    /// 0.1 %), each step an update from the last state (raised 4× or more, the collapses are
    /// graded like a camera cut), within 10⁻³ to 10³⁰ px, or without a view 10⁻⁷ to 10³ of the
    /// mesh's bounding-box diagonal. Where no threshold gets under the target (the anchors
    /// and the boundary planes keep a floor), the cut at the largest threshold tried. The
    /// state a threshold reaches depends on the way there (collapses from a finer state can
    /// stop short of what splits from a coarser one reach), so where the search ends over the
    /// target although it passed a state under it, it gives the largest such state (a copy
    /// of the mesh is kept whenever one is found). Refuses what [`Runtime::cut`] refuses.
    pub fn cut_to_triangles(
        mesh: Mesh,
        views: &[View],
        options: RuntimeOptions,
        target: usize,
    ) -> Result<Cut, InputError> {
        let start = Instant::now();
        input_error::check(views, options.pixel_error)?;
        // Without a view the threshold is in model units: the search spans the model's size.
        let (lowest, highest) = if views.is_empty() {
            let (_, diag) = crate::camera_path::frame_bounds(&mesh.positions);
            (diag * 1e-7, diag.max(f32::MIN_POSITIVE) * 1e3)
        } else {
            (MIN_PIXEL_ERROR, MAX_THRESHOLD)
        };
        let mut c = Cutting::new(mesh, options);
        let mut tau = c.rt.options.pixel_error.clamp(lowest, highest);
        let at = |c: &mut Cutting, tau: f32| {
            c.rt.set_pixel_error(tau);
            c.settle(views);
            c.keep_if_best(target);
            c.rt.triangles()
        };
        // `over`: a threshold that keeps more than the target; `under`: one that keeps at most.
        let (mut over, mut under) = (None, None);
        let mut count = at(&mut c, tau);
        for _ in 0..SEARCH_STEPS {
            if count > target {
                over = Some(tau);
            } else {
                under = Some(tau);
            }
            let next = match (over, under) {
                (Some(_), Some(_)) => break,
                (None, _) => tau / 4.0,
                (Some(_), None) => tau * 4.0,
            };
            if !(lowest..=highest).contains(&next) {
                break;
            }
            tau = next;
            count = at(&mut c, tau);
        }
        if let (Some(mut lo), Some(mut hi)) = (over, under) {
            for _ in 0..SEARCH_STEPS {
                if hi / lo < 1.001 {
                    break;
                }
                let mid = (lo * hi).sqrt();
                if at(&mut c, mid) > target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            under = Some(hi);
        }
        // End on the threshold that kept the target (the state reached may differ by a few
        // triangles from when it was first visited: raise on until the count holds).
        if let Some(mut tau) = under {
            for _ in 0..SEARCH_STEPS {
                if at(&mut c, tau) <= target || tau >= highest {
                    break;
                }
                tau *= 1.01;
            }
        }
        // Where it does not hold (collapses from a finer state can stop short of what splits
        // from a coarser one reached at the same threshold), the largest state at most the
        // target that the search passed.
        if c.rt.triangles() <= target {
            c.kept = None;
        }
        Ok(c.done(start))
    }
}

/// A state of a count's search kept for its end ([`Cutting::keep_if_best`]).
struct Kept {
    mesh: Mesh,
    threshold: f32,
    triangles: usize,
    last: Option<FrameStats>,
    settled: bool,
}

/// Steps of each stage of the threshold search (bracketing by ×4, bisection, the final hold).
const SEARCH_STEPS: usize = 64;

/// The largest threshold in pixels the search tries (the budget controller's bound too).
const MAX_THRESHOLD: f32 = 1e30;

/// A cut under way: the runtime and what its updates did.
struct Cutting {
    rt: Runtime,
    last: Option<FrameStats>,
    frames: usize,
    settled: bool,
    collapses: usize,
    splits: usize,
    /// A count's search: the state with the most triangles at most the target so far.
    kept: Option<Kept>,
}

impl Cutting {
    fn new(mesh: Mesh, options: RuntimeOptions) -> Self {
        // No hysteresis: a cut is made once, so nothing can flicker, and a threshold of τ
        // collapses what is within τ. Rebalancing moves chains for later splits, which a cut
        // never makes.
        let options =
            options.budget(None).hysteresis(1.0).rebalance_moves(0).skip_unchanged_frames(true).max_edits(None);
        let rt = Runtime::new(mesh, options);
        Self { rt, last: None, frames: 0, settled: false, collapses: 0, splits: 0, kept: None }
    }

    /// Keeps a copy of the mesh as it stands if it holds at most `target` triangles and more
    /// than the state kept: the state a threshold reaches depends on the way there, so the
    /// search's last state can hold more than the target where one it passed did not.
    fn keep_if_best(&mut self, target: usize) {
        let n = self.rt.triangles();
        if n <= target && self.kept.as_ref().is_none_or(|k| n > k.triangles) {
            let (mesh, threshold) = (self.rt.mesh().clone(), self.rt.options.pixel_error);
            self.kept = Some(Kept { mesh, threshold, triangles: n, last: self.last, settled: self.settled });
        }
    }

    /// Updates with `views` until one changes nothing (at most [`CUT_FRAMES`]).
    fn settle(&mut self, views: &[View]) {
        self.settled = false;
        for _ in 0..CUT_FRAMES {
            let s = self.rt.update_views(views);
            self.frames += 1;
            if s.skipped {
                self.settled = true;
                return;
            }
            (self.collapses, self.splits) = (self.collapses + s.collapses, self.splits + s.splits);
            if s.collapses + s.splits > 0 || self.last.is_none() {
                self.last = Some(s);
            }
        }
    }

    /// The cut: the state kept by a count's search where there is one (`cut_to_triangles`
    /// keeps it only where the runtime's last state holds more than the target), else the
    /// runtime's.
    fn done(self, start: Instant) -> Cut {
        let Self { rt, last, frames, settled, collapses, splits, kept } = self;
        let Kept { mesh, threshold, last, settled, .. } = kept.unwrap_or_else(|| Kept {
            threshold: rt.options.pixel_error,
            triangles: rt.triangles(),
            last,
            settled,
            mesh: rt.into_mesh(),
        });
        let last = last.expect("a cut makes at least one update");
        let milliseconds = start.elapsed().as_secs_f64() * 1e3;
        Cut { mesh, threshold, last, frames, settled, collapses, splits, milliseconds }
    }
}
