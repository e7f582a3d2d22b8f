//! [`RuntimeOptions`]: the thresholds, budget, anchors, schedule and switches of a [`Runtime`](super::Runtime).

use crate::lod::coarsen::Schedule;
#[cfg(doc)]
use crate::lod::hierarchy::Hierarchy;
use crate::lod::passes::anchors::AnchorOptions;
use crate::lod::passes::classify::ClassifyOptions;

/// Options of a [`Runtime`](super::Runtime).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct RuntimeOptions {
    /// Split threshold τs in pixels (model units without a view). Default: 1.
    pub pixel_error: f32,
    /// τs / τc: collapses need pixels ≤ τs / hysteresis. Default: 1.5.
    pub hysteresis: f32,
    /// Triangle budget: adapt the pixel error so the mesh stays at or below this many
    /// triangles (within a few frames after a jump). Default: none (pixel-error mode).
    pub budget: Option<usize>,
    /// View scales of the vertex analysis (the threshold inside is ignored).
    pub classify: ClassifyOptions,
    /// Grid anchors (papers/000 §3), with the structure's (`passes/structure_anchors.rs`).
    /// Default: L0, √(n/128) cells per axis, nested ([`AnchorOptions::nested`]).
    pub anchors: Option<AnchorOptions>,
    /// Graded cold start: the first frame coarsens at τ / 2^k for k = this, …, 1 before τ
    /// itself, so that what a lower threshold keeps serves as targets for what it removes,
    /// as it does for a camera that moves away frame by frame (R vertices collapse only into
    /// S). A camera cut (the model-space error the threshold allows at the mesh's centre
    /// grew 4× or more since the last frame: a jump away, a raised pixel error) is graded
    /// the same way, one phase per doubling and one more, at most this many. 0 turns both
    /// off. Default: 10 (docs/ALGORITHM.md, "Graded cold start").
    pub cold_grades: u32,
    /// Round cap per phase per frame. Default: 256.
    pub max_rounds: usize,
    /// Edit cap per frame: splits and collapses together. A frame that reaches it ends
    /// ([`FrameStop::EditCap`](super::FrameStop::EditCap)) and the next frame goes on from
    /// there, within a graded cut too. So a camera cut's hundred milliseconds spread over
    /// frames of bounded work, the mesh finer than asked (after a jump in, coarser) until it
    /// catches up. Splits go largest pixel error first; collapses, all below τc, in the
    /// rounds' order. A frame still classifies the live vertices and lists the candidates,
    /// so its cost does not fall below that. In budget mode the threshold is not moved on a
    /// frame that reaches the cap. Deterministic: which edits a frame makes does not depend
    /// on time or threads. Default: none (docs/ALGORITHM.md, "Edit cap").
    pub max_edits: Option<usize>,
    /// Rebalancing attempts per frame (papers/001 Figure 4); 0 turns it off. On an idle frame
    /// (a still camera) only attempts that get as far as a trial split count, among up to 16×
    /// as many records looked at (`lod/rebalance.rs`). Default: 64.
    pub rebalance_moves: usize,
    /// Which removal candidates select a collapse in a round (as in [`crate::lod::coarsen`]).
    /// Default: [`Schedule::LocalMinima`].
    pub schedule: Schedule,
    /// Whether the index buffer compacts itself when fewer than half its slots are live
    /// (faces from the tail move into free slots, reported as changed). Off: a live face never
    /// changes slot, and the buffer keeps its largest size. Default: on.
    pub compact_index_buffer: bool,
    /// Keep the face of every hierarchy stack entry (4 bytes per entry, about 30 bytes per
    /// input vertex on a coarsened scan) so that [`Hierarchy::check`] recounts buried
    /// records' stacks too, and [`Hierarchy::touched`] names a buried record's faces. For
    /// tests and `dynlod fly --verify`; nothing else reads it. Default: off.
    pub audit: bool,
    /// Whether an update whose view is the last one's, after a frame that changed nothing,
    /// returns at once ([`Runtime::update`](super::Runtime::update)): a still camera then
    /// costs nothing per frame. It gives the same figures, mesh and index buffer as the full
    /// frame would; off, every update classifies the live vertices and probes for collapses.
    /// Default: on.
    pub skip_unchanged_frames: bool,
}

impl Default for RuntimeOptions {
    fn default() -> Self {
        Self {
            pixel_error: 1.0,
            hysteresis: 1.5,
            budget: None,
            classify: ClassifyOptions::default(),
            anchors: Some(AnchorOptions::default()),
            cold_grades: 10,
            max_rounds: 256,
            max_edits: None,
            rebalance_moves: 64,
            schedule: Schedule::default(),
            compact_index_buffer: true,
            audit: false,
            skip_unchanged_frames: true,
        }
    }
}

impl RuntimeOptions {
    /// Sets the pixel error τs.
    pub fn pixel_error(mut self, px: f32) -> Self {
        self.pixel_error = px;
        self
    }
    /// Sets the hysteresis factor (≥ 1).
    pub fn hysteresis(mut self, h: f32) -> Self {
        self.hysteresis = h.max(1.0);
        self
    }
    /// Sets the triangle budget.
    pub fn budget(mut self, tris: Option<usize>) -> Self {
        self.budget = tris;
        self
    }
    /// Sets the anchors.
    pub fn anchors(mut self, a: Option<AnchorOptions>) -> Self {
        self.anchors = a;
        self
    }
    /// Sets the graded cold start's halvings (0: off).
    pub fn cold_grades(mut self, k: u32) -> Self {
        self.cold_grades = k;
        self
    }
    /// Sets the rebalancing moves per frame.
    pub fn rebalance_moves(mut self, n: usize) -> Self {
        self.rebalance_moves = n;
        self
    }
    /// Sets the round cap per phase.
    pub fn max_rounds(mut self, n: usize) -> Self {
        self.max_rounds = n.max(1);
        self
    }
    /// Sets the edit cap per frame (`None`: no cap; at least 1).
    pub fn max_edits(mut self, n: Option<usize>) -> Self {
        self.max_edits = n.map(|n| n.max(1));
        self
    }
    /// Sets the schedule of the collapse rounds.
    pub fn schedule(mut self, s: Schedule) -> Self {
        self.schedule = s;
        self
    }
    /// Turns hierarchy auditing on or off (see [`RuntimeOptions::audit`]).
    pub fn audit(mut self, on: bool) -> Self {
        self.audit = on;
        self
    }
    /// Turns skipping unchanged frames on or off (see [`RuntimeOptions::skip_unchanged_frames`]).
    pub fn skip_unchanged_frames(mut self, on: bool) -> Self {
        self.skip_unchanged_frames = on;
        self
    }
    /// Turns index-buffer compaction on or off.
    pub fn compact_index_buffer(mut self, on: bool) -> Self {
        self.compact_index_buffer = on;
        self
    }
}
