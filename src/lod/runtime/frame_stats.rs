//! What one [`Runtime::update`](super::Runtime::update) did: [`FrameStats`] and [`FrameStop`].

/// Why a frame's update ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrameStop {
    /// Nothing more to split or collapse for this view: the next update with it changes nothing.
    #[default]
    Converged,
    /// A phase hit the round cap; the next frame continues.
    RoundCap,
    /// The frame made [`RuntimeOptions::max_edits`](super::RuntimeOptions::max_edits) edits;
    /// the next frame continues.
    EditCap,
    /// Budget mode: the frame made its most classify-split-collapse attempts and is still over
    /// the budget; the next frame raises on. (No walk on the shared meshes reaches it.)
    AttemptCap,
    /// The update did nothing: a view, the pixel error or the hysteresis cannot be used
    /// ([`InputError`](crate::lod::InputError)). The mesh, the index buffer (no changed
    /// ranges), the threshold and the frame count are the last frame's
    /// ([`FrameStats::frame`] is its number): the next update goes on as if this one had not
    /// been made.
    Refused(crate::lod::InputError),
}

/// What one [`Runtime::update`](super::Runtime::update) did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FrameStats {
    /// Frame number, from 1 (a refused update, [`FrameStop::Refused`], is not a frame: it
    /// gives the last frame's number, 0 before the first).
    pub frame: u64,
    /// Collapses performed (rebalancing excluded).
    pub collapses: usize,
    /// Splits performed (rebalancing excluded).
    pub splits: usize,
    /// Split rounds.
    pub split_rounds: usize,
    /// Collapse rounds.
    pub collapse_rounds: usize,
    /// Graded collapse phases run before the frame's own, at falling fractions of the
    /// threshold: on the first frame, and on a camera cut that raised the tolerance 4× or
    /// more ([`RuntimeOptions::cold_grades`](super::RuntimeOptions::cold_grades)).
    pub graded_phases: u32,
    /// Classify-split-collapse attempts after the graded phases: one in pixel-error mode; in
    /// budget mode one more per raise of the threshold within the frame, and one after a
    /// lowering far under the budget; none where the graded phases reached the edit cap.
    pub attempts: u32,
    /// Chain moves made by rebalancing.
    pub rebalanced: usize,
    /// Records rebalancing tried to move, moved or not: most are turned away by their faces'
    /// counters before any split; the others are split and collapsed again, into a shallower
    /// chain or where they were. At most
    /// [`RuntimeOptions::rebalance_moves`](super::RuntimeOptions::rebalance_moves) a frame; on an
    /// idle frame (a still camera) that many trial splits among up to 16 times as many
    /// records.
    pub rebalance_attempts: usize,
    /// Live triangles after the frame.
    pub triangles: usize,
    /// Live vertices after the frame.
    pub vertices: usize,
    /// Longest dependency chain (largest face counter).
    pub max_chain_depth: u16,
    /// Mean counter over faces with one.
    pub mean_chain_depth: f64,
    /// The split threshold used (changes in budget mode).
    pub pixel_error: f32,
    /// Time classifying, ms.
    pub classify_ms: f64,
    /// Time splitting, ms.
    pub split_ms: f64,
    /// Time collapsing, ms.
    pub collapse_ms: f64,
    /// Time rebalancing, ms.
    pub rebalance_ms: f64,
    /// Time updating the index buffer, ms.
    pub output_ms: f64,
    /// Whole update, ms.
    pub total_ms: f64,
    /// Index-buffer triangle slots rewritten.
    pub changed_triangles: usize,
    /// Ranges they form.
    pub changed_ranges: usize,
    /// Why it ended.
    pub stop: FrameStop,
    /// The frame repeated the last one's view after a frame that changed nothing, and
    /// returned that frame's figures without doing any work
    /// ([`RuntimeOptions::skip_unchanged_frames`](super::RuntimeOptions::skip_unchanged_frames)).
    pub skipped: bool,
}
