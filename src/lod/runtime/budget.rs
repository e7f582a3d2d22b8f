//! The triangle-budget mode's controller: moves the split threshold τs so the mesh holds at
//! most the budget (a decision beyond papers/000 and papers/001, which fix τs).
//!
//! τs moves in log space by a step that halves at each change of direction (a bisection) and
//! grows ×1.5 up to e² while it keeps its direction, but is never more than the last lowering
//! moved (lowerings are held back below; a raise after one that overshot then halves the move
//! that overshot, not a step the lowerings never took, which collapsed far under where they
//! started and made moving cameras cycle). Over budget, the frame coarsens again at the
//! raised threshold, as often as it takes (`MAX_ATTEMPTS` in `mod.rs` only guards against a
//! bug). Under 85 % of the budget, the threshold is lowered for the next frame, where
//! nothing checks it within the frame, so less boldly:
//! by no more than a count model asks for (triangles ∝ τs⁻², so τs·√(tris / target), the
//! target the middle of the band), yet always to just below the front's largest pixel error
//! (the next split), and never below [`MIN_PIXEL_ERROR`]. Under [`FAR_BELOW`] of the budget
//! the model gives way to a count that is exact for the splits: a threshold splits back the
//! records answering more than it (charges only fall down a chain), so the k-th largest
//! pixel error of all collapsed vertices is where k splits, about 2k triangles, happen. That
//! lowering is exact, so it is not left for the next frame: the frame splits to it at once
//! ([`Moved::Filled`]; a cut away under a small budget emptied the mesh for a frame).
//! Lowering by the bisection's step alone (up to ×e⁻²) overshot on moving cameras and the
//! raise then collapsed it all again: 120-frame flights made 2–4× the edits they make now
//! (docs/BENCHMARKS.md, "Budget mode on moving cameras"). Across a camera cut the threshold
//! is not this controller's to find: `Runtime::carry_budget_over_a_cut` (grading.rs)
//! rescales it to the last frame's model-space tolerance and restarts the controller.
//! Raising is not capped by the model: capping a frame's first raise was tried (session 27)
//! and made more edits, the frame then raising twice, the second time by a grown step. Three
//! ways it could fail to settle, and what stops each:
//!
//! * **Wind-up over an unreachable budget.** The anchors (papers/000 §3) and the boundary
//!   planes (§4) keep a floor of triangles from every eye; raising on over it reached +∞
//!   within seven frames. A raise at the largest step that changes nothing marks the
//!   controller saturated, and it raises no more until the view splits something. First,
//!   once, the threshold goes straight to where the next live vertex becomes removable:
//!   close to the eye pixel errors are sparse, and a step can fall in a gap between them
//!   ([`BudgetControl::after_raise`]).
//! * **Sinking to zero.** Lowering stops at [`MIN_PIXEL_ERROR`]: from 0 no raise by a factor
//!   comes back.
//! * **A split-collapse cycle under a still camera.** The next split can carry its
//!   dependencies with it (papers/001: parents first), and on a coarse mesh they can jump from
//!   under 85 % to over the budget at once; the raise then collapses them again, and every frame
//!   split and collapsed the same ten vertices. So a lowering that ends over budget although
//!   it asked for the next split alone (the threshold just below the front's largest pixel
//!   error: a larger step that overshoots is the bisection's to correct) records the
//!   triangle count it started from and the pixel error of that split; the
//!   controller lowers again only from fewer triangles, or when the next split answers at least
//!   2 % less (the camera moved away). Both are kept as minimums over the overshoots, so each
//!   overshoot under a still camera tightens one of them and the camera settles. The memory is
//!   dropped once the mesh reaches the 85 % band. (Counts alone went stale on a moving camera:
//!   on the igea dolly, a count remembered from a near view kept a far view at 79 % of the
//!   budget for the last 25 frames.) A lowering that went past the next split (the count
//!   model's, or the bisection's step) and overshot is remembered the same way, but what it
//!   stops is only going past: from as many triangles or more, with the next split answering
//!   as much, the next lowering asks for the next split alone, and that one's overshoot, if
//!   it has one, the first memory holds. Without it a random walk under a budget of 30
//!   cycled for good: the model lowered 5 % past the next split, three splits with their
//!   dependencies took 25 triangles to 31, the raise collapsed back to 25, and no lowering
//!   had asked for the next split alone, so nothing was remembered (soak run, session 48).

/// The largest step of the threshold search, in log space (×e² per attempt).
const MAX_STEP: f32 = 2.0;

/// The threshold goes no lower: splits answering less than a thousandth of a pixel change
/// nothing on screen, and a threshold at 0 could never be raised again.
pub(in crate::lod) const MIN_PIXEL_ERROR: f32 = 1e-3;

/// The share of the budget under which the threshold is lowered.
const LOWER_BELOW: f64 = 0.85;

/// The share of the budget under which a lowering asks which splits would fill the gap
/// instead of trusting the count model.
const FAR_BELOW: f64 = 0.5;

/// What moves τs. See the module docs.
#[derive(Clone, Debug, PartialEq)]
pub(in crate::lod) struct BudgetControl {
    step: f32,
    /// The last change's direction (+1 raised, −1 lowered, 0 none yet).
    dir: i8,
    /// The last raise at the largest step changed nothing: no raising until the view splits.
    saturated: bool,
    /// A raise at the largest step changed nothing, and the threshold went straight to the
    /// next removable vertex's ([`BudgetControl::after_raise`]).
    jumped: bool,
    /// The smallest triangle count a lowering that overshot started from (`usize::MAX`: no
    /// overshoot remembered).
    overshot_from: usize,
    /// The smallest front pixel error a lowering that overshot aimed below.
    overshot_px: f32,
    /// The smallest triangle count a lowering past the next split (the count model's or the
    /// bisection's) started from and overshot: from there on, lowerings go to the next split
    /// alone (`usize::MAX`: none remembered).
    overreached_from: usize,
    /// The smallest front pixel error such a lowering went past.
    overreached_px: f32,
    /// The triangle count and the front's largest pixel error at the last lowering, and
    /// whether it asked for the next split alone.
    lowered_at: Option<(usize, f32, bool)>,
}

impl Default for BudgetControl {
    fn default() -> Self {
        Self {
            step: 0.5,
            dir: 0,
            saturated: false,
            jumped: false,
            overshot_from: usize::MAX,
            overshot_px: f32::INFINITY,
            overreached_from: usize::MAX,
            overreached_px: f32::INFINITY,
            lowered_at: None,
        }
    }
}

impl BudgetControl {
    /// Called after a frame's attempt that raised the threshold: `changed` says whether the
    /// attempt split or collapsed anything, `next_removal()` gives the threshold at which the
    /// next live vertex becomes removable (infinite where none can). Says whether the frame
    /// goes on raising, and whether `tau` was moved here already.
    pub(in crate::lod) fn after_raise(
        &mut self,
        changed: bool,
        tau: &mut f32,
        next_removal: impl FnOnce() -> f32,
    ) -> Raising {
        if changed {
            (self.saturated, self.jumped) = (false, false);
            return Raising::Go;
        }
        if self.step < MAX_STEP {
            return Raising::Go;
        }
        // Nothing changed at the largest step. Either what is left cannot go (the anchors
        // that always stay, and the boundary planes forbid the rest from this eye), or the
        // next removable vertex answers more than the step reached: close to the eye pixel
        // errors are sparse (a sphere that holds the eye answers at the near limit), and the
        // step stopped short of a gap in them. So once, try that vertex's threshold itself.
        if !self.jumped {
            let next = next_removal();
            if next.is_finite() && next > *tau {
                // The step restarts: it had grown to cross the scales the jump crossed.
                *tau = (next * 1.001).min(1e30);
                (self.jumped, self.step) = (true, 0.5);
                return Raising::Jumped;
            }
        }
        // Raising on would only wind the threshold up.
        (self.saturated, self.jumped) = (true, false);
        Raising::Stop
    }

    /// Moves `tau` for a mesh of `tris` triangles under `budget`; `front_max_px` gives the
    /// front's largest pixel error now (0 when nothing can be refined; asked for only under
    /// the band, as it costs a pass over the front), `kth_px(k)` the k-th largest pixel error
    /// of any collapsed vertex (asked for only under [`FAR_BELOW`] of the budget, as it costs
    /// a pass over all of them), and `frame_split` says whether this frame split anything.
    /// Says how the threshold moved ([`Moved`]).
    pub(in crate::lod) fn adjust(
        &mut self,
        tau: &mut f32,
        tris: usize,
        budget: usize,
        front_max_px: impl FnOnce() -> f32,
        kth_px: impl FnOnce(usize) -> f32,
        frame_split: bool,
    ) -> Moved {
        let in_band = tris as f64 >= LOWER_BELOW * budget as f64;
        let mut front_max = 0.0;
        let dir: i8 = if tris > budget {
            if self.saturated && !frame_split {
                return Moved::Held;
            }
            match (self.dir, self.lowered_at) {
                (-1, Some((from, px, true))) => {
                    // The smallest lowering overshot: not again from there.
                    self.overshot_from = self.overshot_from.min(from);
                    self.overshot_px = self.overshot_px.min(px);
                }
                (-1, Some((from, px, false))) => {
                    // A lowering past the next split overshot: from there, the next split alone.
                    self.overreached_from = self.overreached_from.min(from);
                    self.overreached_px = self.overreached_px.min(px);
                }
                _ => {}
            }
            1
        } else if in_band {
            (self.overshot_from, self.overshot_px) = (usize::MAX, f32::INFINITY);
            (self.overreached_from, self.overreached_px) = (usize::MAX, f32::INFINITY);
            return Moved::Held;
        } else {
            front_max = front_max_px();
            if tris >= self.overshot_from && front_max >= 0.98 * self.overshot_px {
                // The smallest lowering from here overshot before.
                return Moved::Held;
            }
            if front_max.is_nan() || front_max * 0.999 < MIN_PIXEL_ERROR {
                self.step = 0.5;
                return Moved::Held;
            }
            -1
        };
        if self.dir != 0 && dir != self.dir {
            self.step = (self.step * 0.5).max(0.01);
        } else if self.dir == dir {
            self.step = (self.step * 1.5).min(MAX_STEP);
        }
        self.dir = dir;
        let mut moved = *tau * (f32::from(dir) * self.step).exp();
        let mut filled = false;
        if dir < 0 {
            // No further than the count model asks for: the middle of the band.
            let target = 0.5 * (LOWER_BELOW + 1.0) * budget as f64;
            moved = moved.max(*tau * (tris as f64 / target).sqrt() as f32);
            if (tris as f64) < FAR_BELOW * budget as f64 {
                // Far under: the splits a threshold makes are known, all records answering
                // more (module docs), about two triangles each; ask for those that fill the gap.
                let wanted = kth_px(((target - tris as f64) / 2.0) as usize);
                if wanted > 0.0 && wanted < moved {
                    moved = wanted * 0.999;
                    filled = true;
                }
            }
            let next_split = front_max * 0.999;
            if tris >= self.overreached_from && front_max >= 0.98 * self.overreached_px {
                // A lowering past the next split overshot from here before.
                (moved, filled) = (moved.max(next_split), false);
            }
            self.lowered_at = Some((tris, front_max, moved >= next_split));
            let from = *tau;
            *tau = moved.min(next_split).max(MIN_PIXEL_ERROR);
            // The step is what the threshold moved, where the model or the next split held
            // it back: a raise after an overshoot then halves the move that overshot, not
            // a step grown over lowerings that were never taken.
            let moved_by = (from / *tau).ln();
            if moved_by > 0.0 {
                self.step = self.step.min(moved_by).max(0.01);
            }
            if filled && moved <= next_split {
                Moved::Filled
            } else {
                Moved::Lowered
            }
        } else {
            *tau = moved.min(1e30);
            Moved::Raised
        }
    }
}

/// What [`BudgetControl::after_raise`] tells the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::lod) enum Raising {
    /// Stop raising.
    Stop,
    /// Go on: adjust the threshold again.
    Go,
    /// The threshold moved already: coarsen at it.
    Jumped,
}

/// How [`BudgetControl::adjust`] moved the threshold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::lod) enum Moved {
    /// It stays.
    Held,
    /// Up: the frame coarsens again.
    Raised,
    /// Down, for the next frame.
    Lowered,
    /// Down, far under the budget, to where the splits fill the gap to the band's middle.
    /// That count is exact (module docs), so the frame splits again at once.
    Filled,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A toy mesh whose next split (with its dependencies) jumps from 41 to 55 triangles
    /// under a budget of 53: the old controller split and collapsed every frame.
    fn step(c: &mut BudgetControl, tau: &mut f32, tris: &mut usize) -> bool {
        // The next split answers 10 px; below that threshold the mesh holds 55 triangles.
        let front_max = if *tris == 41 { 10.0 } else { 0.0 };
        let raised = c.adjust(tau, *tris, 53, || front_max, |_| 0.0, false) == Moved::Raised;
        *tris = if *tau < 10.0 { 55 } else { 41 };
        raised
    }

    #[test]
    fn an_overshooting_lowering_is_not_repeated() {
        let mut c = BudgetControl::default();
        let (mut tau, mut tris) = (12.0f32, 41usize);
        let mut changes = Vec::new();
        for _ in 0..20 {
            let before = tris;
            // One frame: adjust until the controller stops raising.
            for _ in 0..8 {
                if !step(&mut c, &mut tau, &mut tris) {
                    break;
                }
            }
            changes.push(before != tris);
        }
        assert_eq!(tris, 41);
        assert!(changes[10..].iter().all(|c| !c), "still cycling: {changes:?}");
    }

    #[test]
    fn a_raise_after_an_overshooting_lowering_halves_the_move_that_was_made() {
        // Lowering for the third time in a row (the step has grown to e²), but only as far
        // as the next split: from 10 to 8.99 px.
        let mut c = BudgetControl { step: 2.0, dir: -1, ..Default::default() };
        let mut tau = 10.0f32;
        assert_eq!(c.adjust(&mut tau, 40, 53, || 9.0, |_| 0.0, false), Moved::Lowered);
        assert_eq!(tau, 9.0 * 0.999);
        // Its dependencies took the mesh over the budget: the raise halves that move, and
        // does not jump by half the grown step (×e, to 24 px, collapsing all it split and more).
        assert_eq!(c.adjust(&mut tau, 60, 53, || 9.0, |_| 0.0, false), Moved::Raised);
        let half_way = (10.0f32 * 9.0 * 0.999).sqrt();
        assert!((tau - half_way).abs() < 1e-3, "{tau} against {half_way}");
    }

    /// The cycle a random walk found (budget 30): from 25 triangles the count model lowers
    /// past the next split (10 px) to where three splits and their dependencies take the
    /// mesh to 31; the raise collapses back to 25. Once that has overshot, lowerings from 25
    /// go to the next split alone, whose own overshoot the memory then holds.
    #[test]
    fn a_lowering_past_the_next_split_that_overshot_goes_to_the_next_split_alone() {
        // Below 9 px three splits (31 triangles); between 9 and 10 px one (27).
        let count = |tau: f32| {
            if tau < 9.0 {
                31
            } else if tau < 10.0 {
                27
            } else {
                25
            }
        };
        let mut c = BudgetControl::default();
        let (mut tau, mut tris) = (10.5f32, 25usize);
        // The model's lowering (×√(25 / 27.75)) goes past the next split, to about 9.97 px…
        assert_eq!(c.adjust(&mut tau, tris, 30, || 10.0, |_| 0.0, false), Moved::Lowered);
        assert!(tau < 10.0 * 0.999 && tau > 9.0, "{tau}");
        // …and with its neighbours' dependencies it overshoots: the raise remembers it.
        tris = 31;
        assert_eq!(c.adjust(&mut tau, tris, 30, || 10.0, |_| 0.0, false), Moved::Raised);
        assert_eq!((c.overreached_from, c.overreached_px), (25, 10.0));
        assert_eq!(c.overshot_from, usize::MAX, "not the next split's own overshoot");
        // Back at 25 triangles, the next lowering asks for the next split alone.
        (tau, tris) = (10.5, 25);
        c.dir = 1;
        assert_eq!(c.adjust(&mut tau, tris, 30, || 10.0, |_| 0.0, false), Moved::Lowered);
        assert_eq!(tau, 10.0 * 0.999);
        assert_eq!(count(tau), 27, "one split: in the band, no raise");
        // A camera that moved away (the next split answers 3 % less) lowers past it again,
        // where the model asks for that.
        let model = 10.2 * (25.0f32 / 27.75).sqrt();
        let mut tau = 10.2f32;
        (c.dir, c.step) = (1, MAX_STEP);
        assert_eq!(c.adjust(&mut tau, 25, 30, || 9.7, |_| 0.0, false), Moved::Lowered);
        assert!((tau - model).abs() < 1e-4 && tau < 9.7 * 0.999, "{tau}");
        // 1.5 % less: still the next split alone.
        let mut tau = 10.2f32;
        (c.dir, c.step) = (1, MAX_STEP);
        assert_eq!(c.adjust(&mut tau, 25, 30, || 9.85, |_| 0.0, false), Moved::Lowered);
        assert_eq!(tau, 9.85 * 0.999);
    }

    fn remembering(from: usize, px: f32) -> BudgetControl {
        BudgetControl { overshot_from: from, overshot_px: px, ..Default::default() }
    }

    #[test]
    fn the_memory_clears_in_the_band() {
        let mut c = remembering(41, 4.0);
        let mut tau = 5.0;
        assert_eq!(c.adjust(&mut tau, 42, 53, || 4.0, |_| 0.0, false), Moved::Held);
        assert_eq!((c.overshot_from, tau), (41, 5.0), "lowered from more triangles than the memory");
        assert_eq!(c.adjust(&mut tau, 50, 53, || 4.0, |_| 0.0, false), Moved::Held);
        assert_eq!(c.overshot_from, usize::MAX);
        // And lowering works again below the band.
        assert_eq!(c.adjust(&mut tau, 42, 53, || 4.0, |_| 0.0, false), Moved::Lowered);
        assert!(tau < 4.0);
    }

    #[test]
    fn a_lowering_goes_no_further_than_the_count_model_asks() {
        // Lowering for the third time in a row: the bisection's step is at e^-2 by now.
        let mut c = BudgetControl { step: 2.0, dir: -1, ..Default::default() };
        let mut tau = 10.0;
        assert_eq!(c.adjust(&mut tau, 26, 53, || 9.0, |_| 0.0, false), Moved::Lowered);
        let model = 10.0 * (26.0f32 / (0.925 * 53.0)).sqrt();
        assert!((tau - model).abs() < 1e-3, "{tau} against the model's {model}");
        // But always as far as the next split.
        let mut c = BudgetControl::default();
        let mut tau = 10.0;
        assert_eq!(c.adjust(&mut tau, 26, 53, || 5.0, |_| 0.0, false), Moved::Lowered);
        assert_eq!(tau, 5.0 * 0.999);
    }

    #[test]
    fn the_memory_yields_when_the_view_moves_away() {
        let mut tau = 5.0;
        // The next split answers 1 % less than the one that overshot: still blocked.
        let mut c = remembering(30, 4.0);
        assert_eq!(c.adjust(&mut tau, 42, 53, || 3.96, |_| 0.0, false), Moved::Held);
        assert_eq!(tau, 5.0);
        // 3 % less: the camera moved away, lower again.
        assert_eq!(c.adjust(&mut tau, 42, 53, || 3.88, |_| 0.0, false), Moved::Lowered);
        assert!(tau < 3.88, "{tau}");
    }

    #[test]
    fn far_under_the_budget_the_count_of_splits_fills_the_gap_at_once() {
        // 10 of 53 triangles: the gap to the band's middle (49) is about 19 splits.
        let mut c = BudgetControl::default();
        let (mut tau, mut asked) = (10.0, 0);
        let kth = |k| {
            asked = k;
            3.0
        };
        assert_eq!(c.adjust(&mut tau, 10, 53, || 9.0, kth, false), Moved::Filled);
        assert_eq!((asked, tau), (19, 3.0 * 0.999));
        // Where the bisection's step goes further than the count, the step's lowering is
        // not exact: it waits for the next frame.
        let mut c = BudgetControl::default();
        let mut tau = 10.0;
        assert_eq!(c.adjust(&mut tau, 10, 53, || 9.0, |_| 8.0, false), Moved::Lowered);
        // And under half the budget with nothing collapsed to split, the same.
        let mut tau = 10.0;
        assert_eq!(c.adjust(&mut tau, 10, 53, || 9.0, |_| 0.0, false), Moved::Lowered);
    }

    #[test]
    fn a_raise_that_changes_nothing_tries_the_next_removal_once() {
        let at_the_largest_step = || BudgetControl { step: MAX_STEP, dir: 1, ..Default::default() };
        // The next removable vertex answers 50 px over a threshold of 10: go straight there,
        // and the step restarts.
        let (mut c, mut tau) = (at_the_largest_step(), 10.0f32);
        assert_eq!(c.after_raise(false, &mut tau, || 50.0), Raising::Jumped);
        assert_eq!((tau, c.step, c.saturated), (50.0 * 1.001, 0.5, false));
        // That changed nothing either (at the largest step again): the floor.
        c.step = MAX_STEP;
        assert_eq!(c.after_raise(false, &mut tau, || 80.0), Raising::Stop);
        assert!(c.saturated && tau == 50.0 * 1.001);
        // Nothing removable at any threshold: the floor at once.
        let (mut c, mut tau) = (at_the_largest_step(), 10.0f32);
        assert_eq!(c.after_raise(false, &mut tau, || f32::INFINITY), Raising::Stop);
        assert!(c.saturated && tau == 10.0);
        // A raise that changed something, or a small step: raise on as usual.
        let (mut c, mut tau) = (at_the_largest_step(), 10.0f32);
        assert_eq!(c.after_raise(true, &mut tau, || unreachable!()), Raising::Go);
        c.step = 1.0;
        assert_eq!(c.after_raise(false, &mut tau, || unreachable!()), Raising::Go);
        assert_eq!(tau, 10.0);
    }
}
