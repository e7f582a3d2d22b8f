//! The frame-to-frame runtime: papers/000's parallel collapses and papers/001's counter-checked
//! vertex splits on one mesh that is never rebuilt.
//!
//! ```text
//!   update(view), update_views(views):
//!     graded     on a first frame or a camera cut: collapse phases at τ / 2^k, k = K … 1
//!     classify   every live vertex: e(V) (papers/000 §3, on the current mesh), saturated
//!                over the records around it → pixels for this view → R if ≤ τc
//!     split      rounds over the front (records on top of all their faces, papers/001):
//!                split every record whose pixels > τs; records it uncovers join the next round
//!     collapse   papers/000 rounds on the vertices near what changed (boundaries, §5 flags);
//!                every collapse is recorded; ends with a fresh round that changes nothing
//!     rebalance  a bounded number of chain moves (papers/001 Figure 4, rebalance.rs)
//!     output     the stable index buffer takes the faces that changed
//!   τs = pixel error, τc = τs / hysteresis: a record is created below τc and split above τs
//!   several views: a record's pixels are the largest over them, every eye's planes hold
//! ```
//!
//! Files: `frame.rs` (one update in its phases), `grading.rs` (graded start, cuts), `charges.rs` (classify), `splits.rs` (split),
//! `collapses.rs` (collapse),
//! `../rebalance.rs` (rebalance), `budget.rs` (the triangle-budget mode), `memory.rs`
//! ([`Runtime::memory_report`]), `scratch.rs` (the lists a frame reuses), `view_order.rs`
//! (many views walked nearest first).
//!
//! **Errors are monotone along chains.** A record charges the error of u *and* of every record
//! it buries, and carries a radius around u that holds their vertices; its pixels are computed
//! on that sphere (nearest distance, frustum test on the sphere, no angle discount once the
//! radius is non-zero). So a buried record never needs a split its burier does not need, and
//! looking at the front alone is exact — the work follows the front, not the original mesh.
//!
//! **A static camera is a fixed point.** Classification is a pure function of the current
//! mesh and view, kept current after every edit; each record was made with pixels ≤ τc < τs;
//! and the collapse phase stops only after a round started from fresh flags over every live
//! vertex changed nothing — exactly what the next frame's first round would do. Once a frame
//! changed nothing at all, an update with the same view returns at once ([`Runtime::update`]).
//!
//! **Threads.** `update` runs on the current rayon pool: on the calling thread when it is one
//! of the pool's, else handed to the pool while the caller waits (one hand-off per frame
//! instead of one per pass: warm frames 0.31–0.36 → 0.27–0.29 ms on the bunny orbit, 2
//! cores). A pass over fewer than `PARALLEL_MIN` items runs on the thread running the frame.
//! A warm frame is small. On a 16-core machine a warm frame on the bunny took 0.29–0.30 ms
//! on 2 threads and 0.49–0.53 ms on 16 (docs/BENCHMARKS.md, "Many cores"; measured with a
//! hand-off per pass, before frames ran on the pool). So an engine with
//! many cores may do better running `update` inside a small pool of its own
//! (`rayon::ThreadPool::install`). The result does not depend on the pool's size.
//! `Runtime::new` runs on the calling thread, so that the runtime's large arrays come from
//! the caller's heap (glibc gives each thread its own arena: built on a pool thread, a
//! 120-frame bunny flight peaked at 17.7–18.5 MB resident instead of 16.3–16.6 MB; the heap
//! held at the end is about the same either way, 1.07–1.11× `memory_report` against 1.07×).
//!
//! **A warm frame allocates only to grow.** Every list a frame builds is kept for the next
//! (`scratch.rs`; selection uses each thread's own buffers), plans hold their faces inline,
//! and the hierarchy hands its edited faces over by swapping lists. So a frame allocates only
//! when a list outgrows its largest size yet, when a structure that follows the mesh's size
//! grows (the index buffer, the live list), or when rayon's job queue takes a new block (one
//! per 64 hand-offs): on the bunny orbit, 1 allocation in 120 frames after the first pass,
//! where each frame made 130–250 (`tests/allocations.rs`; docs/BENCHMARKS.md, "Warm frames
//! allocate only to grow"). The kept lists are `runtime.scratch` in the memory report.
//!
//! **The first update is the expensive one.** It coarsens from the full mesh: about 0.1 s
//! for the bunny, 0.7–1.1 s for igea (269k triangles) and 4.7 s for a million triangles on
//! 2 cores (docs/BENCHMARKS.md), where warm frames take a millisecond or two. A `Runtime` is
//! `Send` and `Sync`: build it and run its first `update` with the view the object will first
//! be seen from on a loading thread, then hand it to the render loop. (`max_rounds` does not
//! spread the first update over frames usefully: its first rounds are its largest, 25,000
//! collapses and 60 ms a round on igea.)

use std::time::Instant;

use bitvec::prelude::{BitSlice, BitVec};
use rayon::prelude::*;

use super::hierarchy::Hierarchy;
use super::index_buffer::IndexBuffer;
use super::lazy_list::LazyList;
use super::passes::classify::vertex_normals_and_errors;
use super::passes::select::Floors;
use super::passes::structure_anchors::mesh_anchors;
use super::rebalance;
use super::InputError;
use crate::mesh::Mesh;
use crate::topology::{vflag, Topology, INVALID};
use crate::view::{Frustum, View, Viewpoint};
pub(super) use budget::BudgetControl;

mod budget;
mod charges;
mod collapses;
mod cut;
mod frame;
mod frame_stats;
mod grading;
mod memory;
mod options;
mod scratch;
mod splits;
mod view_order;

pub(super) use budget::{Moved, Raising};
pub use cut::{Cut, CUT_FRAMES};
pub(super) use frame::Frame;
pub use frame_stats::{FrameStats, FrameStop};
pub(super) use grading::{across_a_cut, is_cut};
pub use memory::MemoryReport;
pub use options::RuntimeOptions;
pub(super) use scratch::{KthScratch, RebalanceScratch};

/// A mesh under view-dependent control. See the module docs.
///
/// A clone is the whole state, lists and all, and goes on frame for frame as the original
/// would: a warm start for a second runtime of the same mesh (`SceneRuntime`'s instance
/// groups start that way), at the original's memory.
#[derive(Clone)]
pub struct Runtime {
    pub(super) mesh: Mesh,
    pub(super) hierarchy: Hierarchy,
    pub(super) normals: Vec<[f32; 3]>,
    /// The anchors' error floors (papers/000 §3), by vertex id: only anchors have one (one per
    /// grid cell, infinite for those that always stay), read when a charge is worked out and
    /// when a removal picks its target (`select::Stays`).
    pub(super) floor: Floors,
    pub(super) options: RuntimeOptions,
    /// The views of the last update, as given (none: view-independent).
    views: Vec<View>,
    /// Their per-frame constants (classification runs per live vertex), a repeated view once.
    pub(super) frustums: Vec<Frustum>,
    /// Their eyes, for the boundary planes and facing checks, as `frustums`.
    pub(super) eyes: Vec<Viewpoint>,
    /// Many views in the order a record's pixels walk them (`view_order.rs`).
    view_order: view_order::ViewOrder,
    pub(super) tau: f32,
    budget: BudgetControl,
    pub(super) in_r: Vec<bool>,
    pub(super) stays: Vec<bool>,
    cand: Vec<bool>,
    /// Scratch marks for collecting vertices without repeats; all false between uses.
    seen: BitVec,
    ignored: BitVec,
    blocked_before: BitVec,
    flagged: Vec<u32>,
    /// The live vertices (and, until a pass clears them, some that were).
    live: LazyList,
    index: IndexBuffer,
    pub(super) frame: u64,
    /// The mesh's bounding sphere (centre, radius), for [`Runtime::tolerance`].
    sphere: ([f32; 3], f32),
    /// The last frame's [`Runtime::tolerance`] (0 before the first frame).
    last_tolerance: f32,
    /// Edits this frame may still make ([`RuntimeOptions::max_edits`]; `usize::MAX`: no cap).
    pub(super) edits_left: usize,
    /// The graded phase an edit cap stopped in, to go on with next frame (0: none).
    pending_grades: u32,
    /// Records whose rebalancing failed lately, or since the last change (not tried again
    /// for a while).
    pub(super) rebalance_tried: rebalance::RecentFailures,
    /// The threshold (bits) the last frame rebalanced at (`None`: the mesh changed since by
    /// hand); the views were that frame's. A frame at another threshold or other views, or
    /// with edits, counts a change for `rebalance_tried`.
    rebalanced_at: Option<u32>,
    /// The last frame's figures, when that frame changed nothing an update reads
    /// ([`Runtime::repeat`]): an update with the same view returns them at once.
    repeatable: Option<FrameStats>,
    /// Buffers reused from frame to frame (`scratch.rs`).
    pub(super) scratch: scratch::Scratch,
}

impl Runtime {
    /// Takes ownership of a full-resolution mesh. Nothing is collapsed until the first update.
    pub fn new(mesh: Mesh, options: RuntimeOptions) -> Self {
        let t = &mesh.topology;
        let n = t.vertex_count();
        // Without anchors the errors go unused; one pass over the fans either way.
        let (normals, errors) = vertex_normals_and_errors(t, &mesh.positions);
        // Every anchor's floor, also where its own error is higher: the floors also say which
        // anchor may take which removal (`select::Stays`).
        let floor = options.anchors.as_ref().map_or_else(Vec::new, |a| mesh_anchors(&mesh, &errors, a).floor_list(a));
        let floor = Floors::new(floor, n);
        // Sized once: a filtered collect grows by doubling (up to 2n slots for n vertices),
        // and the list never holds more than n.
        let live = {
            let (mut live, live_now) = (Vec::with_capacity(n), is_live(t));
            live.extend((0..n as u32).filter(|&v| live_now(v)));
            LazyList::new(n, live)
        };
        let hierarchy = Hierarchy::new(n, t.face_slots(), options.audit);
        let index = IndexBuffer::new(&mesh, options.compact_index_buffer);
        let tau = options.pixel_error;
        let (centre, diag) = crate::camera_path::frame_bounds(&mesh.positions);
        let mut rt = Self {
            mesh,
            hierarchy,
            normals,
            floor,
            options,
            views: Vec::new(),
            frustums: Vec::new(),
            eyes: Vec::new(),
            view_order: view_order::ViewOrder::default(),
            tau,
            budget: BudgetControl::default(),
            in_r: vec![false; n],
            stays: vec![false; n],
            cand: vec![false; n],
            seen: BitVec::repeat(false, n),
            ignored: BitVec::repeat(false, n),
            blocked_before: BitVec::repeat(false, n),
            flagged: Vec::new(),
            live,
            index,
            frame: 0,
            sphere: (centre, 0.5 * diag),
            last_tolerance: 0.0,
            edits_left: usize::MAX,
            pending_grades: 0,
            rebalance_tried: rebalance::RecentFailures::new(n),
            rebalanced_at: None,
            repeatable: None,
            scratch: scratch::Scratch::default(),
        };
        let charges: Vec<[f32; 2]> = rt.live.entries().par_iter().map(|&v| rt.charge(v).into()).collect();
        for (&v, c) in rt.live.entries().iter().zip(charges) {
            rt.hierarchy.set_charge(v, c);
        }
        rt
    }

    /// The current mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The dynamic vertex hierarchy.
    pub fn hierarchy(&self) -> &Hierarchy {
        &self.hierarchy
    }

    /// The renderer's index buffer (wedge ids) and the ranges the last update changed.
    pub fn index_buffer(&self) -> &IndexBuffer {
        &self.index
    }

    /// Live triangles.
    pub fn triangles(&self) -> usize {
        self.index.live()
    }

    /// The options.
    pub fn options(&self) -> &RuntimeOptions {
        &self.options
    }

    /// Changes the pixel error from the next update on. (Setting the value in force changes
    /// nothing, so a renderer may set it every frame and still have still frames skipped.)
    pub fn set_pixel_error(&mut self, px: f32) {
        let bits = px.to_bits();
        if bits == self.options.pixel_error.to_bits() && (self.options.budget.is_some() || bits == self.tau.to_bits()) {
            return;
        }
        self.edited_by_hand();
        self.options.pixel_error = px;
        self.tau = px;
    }

    /// The largest screen-space error the mesh shows in the last update's views, in pixels:
    /// the largest pixel error of a collapsed vertex not split back (charges grow along
    /// chains, so the front holds the largest). After a frame that converged in pixel-error
    /// mode it is at most the pixel error; in budget mode it is what the budget allowed, the
    /// figure to compare controllers by at equal triangle counts. 0 when nothing is collapsed.
    /// Walks the front.
    pub fn screen_error(&self) -> f32 {
        crate::par::on_pool(|| self.front_max_pixels())
    }

    /// [`Runtime::screen_error`] in `view` alone, which need not be one the last update was
    /// given: what the mesh as it stands shows that camera (after [`Runtime::update_views`],
    /// at most the pixel error in each of its views once a frame converged in pixel-error
    /// mode). Walks the front. NaN for a view that fails [`View::check`]: it has no pixels.
    pub fn screen_error_in(&self, view: &View) -> f32 {
        if view.check().is_err() {
            return f32::NAN;
        }
        let frustum = Frustum::new(view);
        crate::par::on_pool(|| self.front_max_pixels_in(&frustum))
    }

    /// Changes the triangle budget from the next update on (`None`: back to the pixel error,
    /// which the budget mode had been adapting). The budget in force again changes nothing:
    /// the threshold's controller keeps its state.
    pub fn set_budget(&mut self, tris: Option<usize>) {
        if tris == self.options.budget {
            return;
        }
        self.edited_by_hand();
        if tris.is_none() {
            self.tau = self.options.pixel_error;
        }
        self.options.budget = tris;
        self.budget = BudgetControl::default();
    }

    /// Changes the edit cap per frame ([`RuntimeOptions::max_edits`]) from the next update
    /// on: for example none for the first update, on a loading thread, and a cap after it.
    pub fn set_max_edits(&mut self, n: Option<usize>) {
        let old = self.options.max_edits;
        self.options = std::mem::take(&mut self.options).max_edits(n);
        if self.options.max_edits != old {
            self.edited_by_hand();
        }
    }

    /// Turns rebalancing on or off (moves per frame).
    pub fn set_rebalance_moves(&mut self, n: usize) {
        if n != self.options.rebalance_moves {
            self.edited_by_hand();
            self.options.rebalance_moves = n;
        }
    }

    /// Something other than an update changed the options or the mesh: the next update is
    /// a full one, and rebalancing may try again the moves that failed before.
    pub(super) fn edited_by_hand(&mut self) {
        self.repeatable = None;
        self.rebalanced_at = None;
    }

    /// Gives the mesh back.
    pub fn into_mesh(self) -> Mesh {
        self.mesh
    }

    /// Adapts the level of detail to `view` (None: view-independent, errors in model units),
    /// starting from the previous frame's state. Runs on the current rayon pool (the calling
    /// thread waits when it is not one of the pool's).
    ///
    /// A frame whose view is the last frame's, bit for bit, after a frame that changed
    /// nothing an update reads (no split, collapse or rebalancing attempt, the threshold and
    /// the budget's controller where they were, converged) returns the last frame's figures
    /// at once, with its own frame number and time and [`FrameStats::skipped`] set: the
    /// full frame would classify the same, split and collapse nothing and try no move
    /// (`rebalance.rs`: a failed move is not tried again before something changes).
    /// [`RuntimeOptions::skip_unchanged_frames`] turns this off.
    pub fn update(&mut self, view: Option<&View>) -> FrameStats {
        self.update_views(view.map_or(&[], std::slice::from_ref))
    }

    /// [`Runtime::update`] for a mesh seen by several views at once: a split screen, one
    /// mesh drawn by several instances (each instance's view carried into the mesh's space
    /// by [`View::in_model_space`]), the eyes of a stereo camera. The level of detail serves
    /// every view: a vertex stays collapsed only while every view finds its error within the
    /// threshold (the largest of the views' pixel errors counts), and no collapse turns a
    /// triangle against any of the eyes (docs/ALGORITHM.md, "Several views in one runtime"). No
    /// views: view-independent; one view: exactly [`Runtime::update`]. The order of the
    /// views and a view repeated change nothing; a frame is skipped when its views are the
    /// last frame's (bit for bit, in any order) and that frame changed nothing.
    ///
    /// In budget mode the one threshold is adapted for all views together, so the budget
    /// covers the mesh once, however many views see it.
    ///
    /// A view that fails [`View::check`] (a NaN eye, the eye on its target, a field of view
    /// outside (0°, 180°), an empty viewport), a negative or NaN pixel error, or a hysteresis
    /// below 1 makes the update do nothing and say so ([`FrameStop::Refused`]): the mesh, the
    /// index buffer and the threshold stay the last frame's.
    pub fn update_views(&mut self, views: &[View]) -> FrameStats {
        let start = Instant::now();
        // A repeat's views and options are those of a frame that ran, so they were checked.
        if let Some(s) = self.repeat(views, start) {
            return s;
        }
        if let Err(e) = self.check_input(views) {
            return self.refuse(e, start);
        }
        crate::par::on_pool(|| self.update_here(views, start))
    }

    /// Whether `views` and the options in force can be used for an update
    /// ([`Runtime::update_views`]).
    pub fn check_input(&self, views: &[View]) -> Result<(), InputError> {
        crate::lod::input_error::check(views, self.options.pixel_error)?;
        if self.options.hysteresis.is_nan() || self.options.hysteresis < 1.0 {
            return Err(InputError::Hysteresis);
        }
        Ok(())
    }

    /// An update refused for `error`: nothing changed, not even the frame count (so what
    /// follows is what would have followed without it), the figures of the mesh as it stands,
    /// no changed ranges.
    pub(in crate::lod) fn refuse(&mut self, error: InputError, start: Instant) -> FrameStats {
        // Nothing was edited since the last frame's sync, unless by hand: either way the
        // index buffer's changed ranges are now those since the last update.
        self.sync_index();
        FrameStats {
            frame: self.frame,
            triangles: self.index.live(),
            vertices: self.live.len(),
            max_chain_depth: self.hierarchy.max_depth(),
            mean_chain_depth: self.hierarchy.mean_depth(),
            pixel_error: self.tau,
            changed_triangles: self.index.changed_triangles(),
            changed_ranges: self.index.changed_range_count(),
            stop: FrameStop::Refused(error),
            total_ms: ms(start),
            ..FrameStats::default()
        }
    }

    /// Whether an update with `views` now would return at once, repeating the last frame
    /// (see [`Runtime::update`]).
    pub(crate) fn repeats(&self, views: &[View]) -> bool {
        self.repeatable.is_some() && same_views(views, &self.views)
    }

    /// The figures of a frame that repeats the last one, if it does (see [`Runtime::update`]).
    fn repeat(&mut self, views: &[View], start: Instant) -> Option<FrameStats> {
        let last = self.repeatable?;
        if !same_views(views, &self.views) {
            return None;
        }
        self.frame += 1;
        Some(FrameStats {
            frame: self.frame,
            skipped: true,
            classify_ms: 0.0,
            split_ms: 0.0,
            collapse_ms: 0.0,
            rebalance_ms: 0.0,
            output_ms: 0.0,
            total_ms: ms(start),
            ..last
        })
    }

    /// Runs up to `attempts` rebalancing attempts now (also part of every update); returns
    /// the moves made.
    pub fn rebalance(&mut self, attempts: usize) -> usize {
        self.edited_by_hand();
        let n = rebalance::run(self, attempts, false).moves;
        self.sync_index();
        n
    }

    fn sync_index(&mut self) {
        self.with_scratch(
            |s| &mut s.changed_faces,
            |rt, changed| {
                rt.hierarchy.swap_changed(changed);
                rt.index.sync(&rt.mesh, changed);
            },
        );
    }
}

// A runtime can be built and warmed on a loading thread, then handed over (module docs).
const _: () = {
    const fn send_and_sync<T: Send + Sync>() {}
    send_and_sync::<Runtime>();
};

/// The most classify-split-collapse attempts a frame makes after its graded phases: one in
/// pixel-error mode; in budget mode, one more per raise of the threshold and one for a
/// lowering to the exact count (`budget.rs`). A frame over its budget raises until it is
/// under it or the raises change nothing (saturated), and this cap is not meant to end any
/// frame: raises grow to ×e² an attempt, so it covers the threshold's whole range
/// ([`MIN_PIXEL_ERROR`](budget::MIN_PIXEL_ERROR) to 10³⁰, 76 in log space) at the largest
/// step, one lowering to the exact count, and the smaller steps after it. A fixed cap of 12
/// (8 before) ended first frames close to the eye over the budget: at 0.6 diagonals, 2,197
/// bunny triangles under a budget of 2,000 and 668 armadillo triangles under 300; they take
/// up to 16 attempts (docs/BENCHMARKS.md, "Session 40"). Each raise costs a pass over the
/// live vertices of an ever smaller mesh.
pub(in crate::lod) const MAX_ATTEMPTS: usize = 64;

/// Below this many items a pass runs on the calling thread: a warm frame runs several small
/// rounds, and waking the thread pool for a few hundred items costs more than the work.
const PARALLEL_MIN: usize = 1024;

/// Whether vertex `v` of `t` is live (has faces, and is not collapsed): who belongs in
/// [`Runtime`]'s live list.
fn is_live(t: &Topology) -> impl Fn(u32) -> bool + '_ {
    |v| t.vertex_he[v as usize] != INVALID && t.vflags[v as usize] & vflag::REMOVED == 0
}

/// Appends `v` to `out` and raises its mark, unless the mark is up already; returns whether it
/// was appended. The caller lowers the marks of what it listed ([`unmark`]) before the next use.
fn list_once(marks: &mut BitSlice, out: &mut Vec<u32>, v: u32) -> bool {
    let fresh = !marks.replace(v as usize, true);
    if fresh {
        out.push(v);
    }
    fresh
}

/// Lowers the marks [`list_once`] raised for `listed`.
fn unmark(marks: &mut BitSlice, listed: &[u32]) {
    for &v in listed {
        marks.set(v as usize, false);
    }
}

/// Whether two lists hold the same views, bit for bit, in any order and however often each
/// (what an update does depends on the set alone: the largest error, every eye's planes).
fn same_views(a: &[View], b: &[View]) -> bool {
    // The same list again (a still camera, a still scene) in one pass.
    if a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.is_identical(y)) {
        return true;
    }
    let within = |a: &[View], b: &[View]| a.iter().all(|x| b.iter().any(|y| x.is_identical(y)));
    within(a, b) && within(b, a)
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
