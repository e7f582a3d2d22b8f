//! Rounds of parallel half-edge collapses: papers/000 §2 (the loop), §4 (selection under the
//! boundaries), §5 (deadlock prevention) and §6 (reclassification).
//!
//! ```text
//!   classify once: R (remove) / S (stay), anchors in S          (§3, classify.rs, anchors.rs)
//!   round:  C = R \ ignored with a neighbour in S
//!           actors = C (the paper's schedule) or, by default, the c ∈ C that come before
//!             every neighbouring candidate in (error, scrambled id): the rest wait a round
//!           every actor selects a target from the same state, in parallel   (select.rs)
//!           apply in vertex order, re-checking the link condition, so the round as a whole
//!             keeps the mesh manifold (a choice that became illegal waits for the next round);
//!             on a mesh in spatial order, each part's collapses side by side, then the rest
//!             (passes/apply.rs, topology/parts.rs)
//!           §5: blocked even alone → c stays for good if all its neighbours are in S, else it
//!             waits (ignored) for a neighbour to change; blocked only by neighbours twice in a
//!             row with no neighbour removed → ignored, unless its error tops theirs
//!             (ties: the larger vertex id tops, so a flat deadlocked ring resolves)
//!           §6: R-neighbours of this round's removed vertices whose max tangent-plane
//!             distance to their S-neighbours exceeds the reclassification threshold move to S
//!   until C is empty, nothing changes, or the round cap
//! ```
//! Selection is a pure function per candidate and application runs in a fixed order (by
//! part, then vertex), so the result is the same for any thread count. Why local minima are the default, with the
//! measurements: docs/ALGORITHM.md ("Schedule"). The mesh is valid after every round (the paper's
//! "can be aborted after each iteration").
//!
//! Files: `round.rs` (the [`Coarsener`] and its round), `order.rs` (who goes first).

mod order;
mod round;

pub(crate) use order::{first_ahead, goes_first, outranks};
pub use round::Coarsener;

use super::passes::anchors::AnchorOptions;
use super::passes::classify::ClassifyOptions;
use super::InputError;
use crate::mesh::Mesh;
use crate::view::View;

/// Options of a coarsening run.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CoarsenOptions {
    /// Threshold u and view scales (§3). Default: u = 1 (pixel, or model unit without a view).
    pub classify: ClassifyOptions,
    /// Grid anchors (§3), with the structure's (`passes/structure_anchors.rs`). Default: L0
    /// only, √(n/128) cells per axis (16 on the bunny: denser than 4 cuts the rounds 2–4× at
    /// equal or lower error; see docs/BENCHMARKS.md), not nested: the rounds classify once
    /// and do not follow a removal's error along a chain of anchors, as the runtime's charges
    /// do, and nested, a 1 px cut of the bunny from 8 diagonals came out at 7.3 % of the
    /// diagonal off the input, against 1.4 % ([`AnchorOptions::nested`]).
    pub anchors: Option<AnchorOptions>,
    /// Reclassification threshold (§6), in the units of u. Default: 2 × u.
    pub reclassify_threshold: Option<f32>,
    /// Round cap. Default: 1000 (a far view, where nearly everything starts in R, can need
    /// a few hundred rounds with sparse anchors).
    pub max_rounds: usize,
    /// Which candidates act in a round. Default: [`Schedule::LocalMinima`].
    pub schedule: Schedule,
    /// Under [`Schedule::LocalMinima`] on a mesh without separate wedges, the parts a round's
    /// collapses are made in side by side ([`Parts`](crate::topology::Parts)); 1: all on the calling thread, in
    /// vertex order. The result depends on this number (the order the collapses are made
    /// in), never on the thread count. Default: 2.
    pub apply_parts: usize,
}

/// Which removal candidates select a collapse in a round.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Schedule {
    /// The paper's (§4): every candidate, every round. Tests 2 and 3 make simultaneous
    /// collapses of neighbouring candidates safe, but they refuse most moves: on the bunny
    /// about 60 % of evaluations end blocked by a neighbour and are redone next round.
    AllCandidates,
    /// A candidate acts only when no neighbouring candidate has a lower (error, id) — the
    /// same order as §5's tie-break, reversed: cheapest first. The others wait a round
    /// (treated as staying put, like §5's ignored vertices), so only test 1 applies and
    /// nearly every evaluation ends in a collapse. Same guarantees; on the bunny a third of
    /// the evaluations and a lower RMS error (docs/BENCHMARKS.md).
    #[default]
    LocalMinima,
}

impl Schedule {
    /// Both schedules, the default first.
    pub const ALL: [Schedule; 2] = [Schedule::LocalMinima, Schedule::AllCandidates];

    /// The command-line name (`local-minima` or `all`).
    pub fn name(self) -> &'static str {
        match self {
            Schedule::LocalMinima => "local-minima",
            Schedule::AllCandidates => "all",
        }
    }

    /// The schedule with this command-line name.
    pub fn from_name(name: &str) -> Option<Schedule> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

impl Default for CoarsenOptions {
    fn default() -> Self {
        Self {
            classify: ClassifyOptions::default(),
            anchors: Some(AnchorOptions::default().nested(None)),
            reclassify_threshold: None,
            max_rounds: 1000,
            schedule: Schedule::default(),
            apply_parts: 2,
        }
    }
}

impl CoarsenOptions {
    /// Sets the threshold u.
    pub fn threshold(mut self, u: f32) -> Self {
        self.classify.threshold = u;
        self
    }
    /// Sets the anchors (`None`: no anchors).
    pub fn anchors(mut self, a: Option<AnchorOptions>) -> Self {
        self.anchors = a;
        self
    }
    /// Sets the round cap.
    pub fn max_rounds(mut self, n: usize) -> Self {
        self.max_rounds = n;
        self
    }
    /// Sets the schedule.
    pub fn schedule(mut self, s: Schedule) -> Self {
        self.schedule = s;
        self
    }
    /// Sets [`CoarsenOptions::apply_parts`].
    pub fn apply_parts(mut self, parts: usize) -> Self {
        self.apply_parts = parts;
        self
    }
}

/// What one round did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RoundStats {
    /// Removal candidates this round.
    pub candidates: usize,
    /// Candidates that waited for a neighbouring candidate ([`Schedule::LocalMinima`]).
    pub waiting: usize,
    /// Collapses applied.
    pub collapsed: usize,
    /// Selections dropped at application (link condition no longer held).
    pub deferred: usize,
    /// Of the collapses applied, those made inside a part, side by side with the other
    /// parts' ([`CoarsenOptions::apply_parts`]); the rest were made on one thread.
    pub collapsed_in_parts: usize,
    /// Candidates blocked by their neighbours' boundaries only.
    pub blocked: usize,
    /// Candidates with no legal target even alone (kept, or waiting for a neighbour).
    pub stuck: usize,
    /// Vertices newly marked "ignored" (§5).
    pub ignored: usize,
    /// Vertices moved from R to S by §6.
    pub reclassified: usize,
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoarsenStop {
    /// No removal candidate left.
    Done,
    /// A round changed nothing.
    NoChange,
    /// The round cap was reached.
    RoundCap,
    /// Nothing was done: a view fails [`View::check`], or the threshold is negative or NaN
    /// ([`InputError`]).
    Refused(InputError),
}

/// What a whole run did.
#[derive(Debug, Clone, PartialEq)]
pub struct CoarsenStats {
    /// Live triangles before.
    pub input_triangles: usize,
    /// Live triangles after.
    pub output_triangles: usize,
    /// Per round.
    pub rounds: Vec<RoundStats>,
    /// Why it stopped.
    pub stop: CoarsenStop,
    /// Wall time.
    pub milliseconds: f64,
}

/// Coarsens `mesh` in place for `view` (None: view-independent, u in model units) until no
/// candidate is left, a round changes nothing, or the round cap. Runs on the current rayon
/// pool: on the calling thread when it is one of the pool's, else handed to the pool while
/// the caller waits (the rounds' many short passes then fork and join on threads that are
/// already awake).
pub fn coarsen(mesh: &mut Mesh, view: Option<View>, options: CoarsenOptions) -> CoarsenStats {
    coarsen_views(mesh, view.as_slice(), options)
}

/// [`coarsen`] for several views at once: a vertex goes only where every view lets it (its
/// pixel error is the largest any view gives it), and a collapse must pass every view's
/// boundary planes, so no triangle turns against any of them. For one mesh drawn by several
/// cameras (split screen, a set of viewpoints), or drawn several times under one camera (a
/// glTF mesh that several nodes draw: each node's view carried into the mesh's space by
/// [`View::in_model_space`]). No views: view-independent; one view: [`coarsen`]'s result.
/// A view that fails [`View::check`], or a negative or NaN threshold, is refused before the
/// mesh is touched ([`CoarsenStop::Refused`]).
pub fn coarsen_views(mesh: &mut Mesh, views: &[View], options: CoarsenOptions) -> CoarsenStats {
    crate::par::on_pool(|| coarsen_here(mesh, views, options))
}

/// [`coarsen_views`] on the calling thread.
fn coarsen_here(mesh: &mut Mesh, views: &[View], options: CoarsenOptions) -> CoarsenStats {
    let start = std::time::Instant::now();
    let input = mesh.topology.live_face_count();
    if let Err(e) = crate::lod::input_error::check(views, options.classify.threshold) {
        let (rounds, stop) = (Vec::new(), CoarsenStop::Refused(e));
        return CoarsenStats { input_triangles: input, output_triangles: input, rounds, stop, milliseconds: 0.0 };
    }
    let cap = options.max_rounds;
    let mut c = Coarsener::new(mesh, views, options);
    let mut rounds = Vec::new();
    let stop = loop {
        if rounds.len() >= cap {
            break CoarsenStop::RoundCap;
        }
        let r = c.round(mesh);
        rounds.push(r);
        if r.candidates == 0 {
            break CoarsenStop::Done;
        }
        if r.collapsed == 0 && r.reclassified == 0 && r.ignored == 0 && r.stuck == 0 {
            break CoarsenStop::NoChange;
        }
    };
    CoarsenStats {
        input_triangles: input,
        output_triangles: mesh.topology.live_face_count(),
        rounds,
        stop,
        milliseconds: start.elapsed().as_secs_f64() * 1e3,
    }
}

/// Meets a triangle target by searching over the threshold u (never by truncating): a
/// bisection in log space between `lo` and `hi` (units of u), coarsening a copy of `mesh` at
/// each step. Returns the coarsened mesh closest to `target` from below when one is reachable
/// (else the smallest reached), its stats and its u. `views` as for [`coarsen_views`] (one
/// view: `view.as_slice()`, none: view-independent). A view [`coarsen_views`] refuses is
/// refused at once ([`CoarsenStop::Refused`], the mesh as it was).
pub fn coarsen_to_triangles(
    mesh: &Mesh,
    views: &[View],
    options: &CoarsenOptions,
    target: usize,
    lo: f32,
    hi: f32,
) -> (Mesh, CoarsenStats, f32) {
    let run = |u: f32| {
        let mut m = mesh.clone();
        let s = coarsen_views(&mut m, views, options.clone().threshold(u));
        (m, s, u)
    };
    let (mut lo, mut hi) = (lo.max(f32::MIN_POSITIVE).ln(), hi.max(lo * 2.0).ln());
    let mut best = run(hi.exp());
    if matches!(best.1.stop, CoarsenStop::Refused(_)) {
        return best;
    }
    for _ in 0..14 {
        let mid = 0.5 * (lo + hi);
        let r = run(mid.exp());
        let tris = r.1.output_triangles;
        let better = match (tris <= target, best.1.output_triangles <= target) {
            (true, false) => true,
            (true, true) => tris > best.1.output_triangles,
            (false, false) => tris < best.1.output_triangles,
            (false, true) => false,
        };
        if tris > target {
            lo = mid;
        } else {
            hi = mid;
        }
        if better {
            best = r;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{procedural, BuildOptions};

    /// `coarsen` hands itself to the pool from a plain thread and runs in place on a pool
    /// thread: both give the same mesh, and from a plain thread the rounds do run on the pool.
    #[test]
    fn runs_on_the_pool_from_any_thread() {
        let mesh = crate::test_bunny();
        let (_, diag) = crate::camera_path::frame_bounds(&mesh.positions);
        let options = CoarsenOptions::default().threshold(1e-2 * diag);
        let mut outside = mesh.clone();
        assert!(rayon::current_thread_index().is_none(), "the test thread is not a pool thread");
        let stats = coarsen(&mut outside, None, options.clone());
        assert!(stats.output_triangles < stats.input_triangles / 2, "{stats:?}");
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let mut inside = mesh.clone();
        pool.install(|| coarsen(&mut inside, None, options.clone()));
        assert!(outside == inside);
        assert!(crate::par::on_pool(|| rayon::current_thread_index().is_some()));
    }

    /// Deciding from [`RoundTouches`] which collapses need their link condition checked again
    /// at application gives exactly the mesh that re-checking everything gives.
    #[test]
    fn skipped_rechecks_change_nothing() {
        let bunny = crate::test_bunny();
        let meshes = [
            // In spatial order: its collapses are made in parts (asserted below).
            Mesh::build(&bunny.to_indexed(), BuildOptions::default().spatial_order(true)).unwrap(),
            bunny,
            Mesh::build(&procedural::torus(40, 20), BuildOptions::default()).unwrap(),
            Mesh::build(&procedural::grid(30, 20, |i, j| (i * j) % 3 == 0), BuildOptions::default()).unwrap(),
        ];
        let mut coarsened = 0;
        for (i, mesh) in meshes.into_iter().enumerate() {
            let (_, diag) = crate::camera_path::frame_bounds(&mesh.positions);
            for u in [1e-3, 1e-2, 5e-2] {
                let run = |recheck: bool| {
                    let mut m = mesh.clone();
                    let mut c = Coarsener::new(&m, &[], CoarsenOptions::default().threshold(u * diag));
                    c.always_recheck = recheck;
                    let (mut collapsed, mut in_parts) = (0, 0);
                    for _ in 0..300 {
                        let r = c.round(&mut m);
                        (collapsed, in_parts) = (collapsed + r.collapsed, in_parts + r.collapsed_in_parts);
                        if r.candidates == 0 {
                            break;
                        }
                    }
                    (m, collapsed, in_parts)
                };
                let ((fast, collapsed, in_parts), (slow, _, _)) = (run(false), run(true));
                let faces = fast.topology.live_face_count();
                assert!(fast == slow, "u = {u}: {faces} vs {} faces", slow.topology.live_face_count());
                if i == 0 {
                    assert!(in_parts * 10 >= collapsed * 8, "u = {u}: {in_parts} of {collapsed} collapses in parts");
                }
                coarsened += usize::from(faces < mesh.topology.live_face_count());
            }
        }
        assert!(coarsened >= 10, "only {coarsened} of 12 runs removed anything");
    }
}
