//! The offline simplifier: half-edge collapses chosen by a cost and a selection strategy,
//! kept apart so each can be compared on its own (as OpenMesh separates modules from engines).
//!
//! | method    | cost                                   | strategy                  |
//! |-----------|----------------------------------------|---------------------------|
//! | `mca`     | dihedral angles (papers/002 §3.2)      | multiple choice (§3.3)    |
//! | `qem`     | quadric error (Garland–Heckbert)       | greedy priority queue     |
//! | `mca-qem` | quadric error                          | multiple choice           |
//! | `qem-batch` | quadric error                        | passes of independent collapses |
//! | `qem-flat` | quadric error                         | passes over a triangle list, meshoptimizer's layout |
//!
//! Every collapse keeps the mesh manifold (link condition), rejects face flips, keeps borders
//! on borders, seams on seams, primitives apart and locked vertices in place (engine.rs). A
//! run stops at a triangle count, a ratio of the input, or an error bound, whichever comes
//! first, or when nothing more may collapse.

mod attribute_quadric;
mod batched;
mod dihedral_cost;
mod engine;
mod flat;
mod greedy;
mod indexed_heap;
mod mca;
mod quadric;
mod scene;

pub use crate::mesh::constraints::{BORDER_CORNER_DEGREES, QUADRIC_BORDER_CORNER_DEGREES};
pub use attribute_quadric::AttributeWeights;
pub use dihedral_cost::dihedral_cost;
pub use quadric::Quadric;
pub use scene::{
    lock_border, simplify_scene, Drawn, SceneEngine, SceneLod, SceneMeshReport, SceneOptions, SceneTarget,
};

use std::time::Instant;

use crate::mesh::Mesh;
use crate::topology::vflag;

/// The collapse cost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cost {
    /// Edge length × weighted dihedral angles (papers/002 equation 2).
    Dihedral,
    /// Quadric error of the target position.
    Quadric,
}

/// How the next collapse is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Always the cheapest (priority queue).
    Greedy,
    /// The cheapest of `candidates` random vertices (no queue).
    MultipleChoice,
    /// Passes of collapses with disjoint neighbourhoods, cheapest first, checked and costed
    /// in parallel (batched.rs).
    Batched,
    /// Passes over a flat triangle list with per-vertex face rows, each collapse locking
    /// only its two ends, in blocks of the mesh at once (flat/mod.rs). Ranks by the quadric
    /// cost whatever [`SimplifyOptions::cost`] says (the dihedral cost walks half-edges).
    Flat,
}

/// The named combinations of the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Dihedral cost, multiple choice: papers/002.
    Mca,
    /// Quadric cost, greedy.
    Qem,
    /// Quadric cost, multiple choice.
    McaQem,
    /// Quadric cost, batched passes.
    QemBatch,
    /// Quadric cost, flat passes.
    QemFlat,
}

impl Method {
    /// Every method, in the order of the command line's help.
    pub const ALL: [Method; 5] = [Method::Mca, Method::Qem, Method::McaQem, Method::QemBatch, Method::QemFlat];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Mca => "mca",
            Method::Qem => "qem",
            Method::McaQem => "mca-qem",
            Method::QemBatch => "qem-batch",
            Method::QemFlat => "qem-flat",
        }
    }

    /// The method with this command-line name.
    pub fn from_name(name: &str) -> Option<Method> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// (cost, strategy) of the method.
    pub fn parts(self) -> (Cost, Strategy) {
        match self {
            Method::Mca => (Cost::Dihedral, Strategy::MultipleChoice),
            Method::Qem => (Cost::Quadric, Strategy::Greedy),
            Method::McaQem => (Cost::Quadric, Strategy::MultipleChoice),
            Method::QemBatch => (Cost::Quadric, Strategy::Batched),
            Method::QemFlat => (Cost::Quadric, Strategy::Flat),
        }
    }
}

/// When to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct SimplifyOptions {
    /// The collapse cost. Default: quadric. (The dihedral cost of papers/002, `Method::Mca`,
    /// leaves 1.6–2.6× meshoptimizer's RMS error at equal triangle counts; the quadric cost
    /// 0.9–1.04×: docs/BENCHMARKS.md, "quality beside meshopt".)
    pub cost: Cost,
    /// The selection strategy. Default: flat passes (`Method::QemFlat`, the fastest, with
    /// the quadric cost's quality).
    pub strategy: Strategy,
    /// Candidates drawn per multiple-choice step. Default: 6 (papers/002, after Wu & Kobbelt).
    pub candidates: usize,
    /// Seed of the multiple-choice draws. Default: 1.
    pub seed: u64,
    /// Stop when this many triangles remain. Default: 0 (as far as possible).
    pub target_triangles: usize,
    /// Never let a collapse's quadric error √(Q/W) exceed this (model units). Default: ∞.
    pub max_error: f64,
    /// Show a progress bar on stderr (hidden when stderr is not a terminal). Default: false.
    pub progress: bool,
    /// When the run stops short of `target_triangles`, count why the vertices left stay
    /// ([`SimplifyStats::remaining`]; one more evaluation of each). Default: false.
    pub explain_shortfall: bool,
    /// How much normals, texture coordinates, colours and tangents count in the quadric
    /// cost beside the geometric error (Hoppe 1999, as meshoptimizer's
    /// `simplifyWithAttributes`). Default: none. Read by the quadric cost under every
    /// strategy; the dihedral cost leaves them out, and
    /// [`SimplifyStats::weighted_attributes`] then stays empty.
    pub attribute_weights: AttributeWeights,
}

impl Default for SimplifyOptions {
    fn default() -> Self {
        Self {
            cost: Cost::Quadric,
            strategy: Strategy::Flat,
            candidates: 6,
            seed: 1,
            target_triangles: 0,
            max_error: f64::INFINITY,
            progress: false,
            explain_shortfall: false,
            attribute_weights: AttributeWeights::default(),
        }
    }
}

impl SimplifyOptions {
    /// Cost and strategy of a named method.
    pub fn method(mut self, m: Method) -> Self {
        (self.cost, self.strategy) = m.parts();
        self
    }
    /// Sets [`SimplifyOptions::target_triangles`].
    pub fn target_triangles(mut self, n: usize) -> Self {
        self.target_triangles = n;
        self
    }
    /// Sets [`SimplifyOptions::max_error`].
    pub fn max_error(mut self, e: f64) -> Self {
        self.max_error = e;
        self
    }
    /// Sets [`SimplifyOptions::candidates`].
    pub fn candidates(mut self, d: usize) -> Self {
        self.candidates = d;
        self
    }
    /// Sets [`SimplifyOptions::seed`].
    pub fn seed(mut self, s: u64) -> Self {
        self.seed = s;
        self
    }
    /// Sets [`SimplifyOptions::progress`].
    pub fn progress(mut self, on: bool) -> Self {
        self.progress = on;
        self
    }

    /// See [`SimplifyOptions::explain_shortfall`].
    pub fn explain_shortfall(mut self, on: bool) -> Self {
        self.explain_shortfall = on;
        self
    }

    /// Sets [`SimplifyOptions::attribute_weights`].
    pub fn attribute_weights(mut self, w: AttributeWeights) -> Self {
        self.attribute_weights = w;
        self
    }

    /// Whether these options read [`SimplifyOptions::attribute_weights`] (the quadric
    /// cost).
    pub fn weighs_attributes(&self) -> bool {
        self.cost == Cost::Quadric
    }
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The triangle target was reached.
    Target,
    /// No allowed collapse is left (or none within the error bound).
    NothingAllowed,
}

/// What a run did and how long it took.
#[derive(Debug, Clone, PartialEq)]
pub struct SimplifyStats {
    /// Live triangles before.
    pub input_triangles: usize,
    /// Live triangles after.
    pub output_triangles: usize,
    /// Collapses performed.
    pub collapses: usize,
    /// Largest quadric error √(Q/W) of any collapse made.
    pub max_error: f64,
    /// Time to compute the initial costs.
    pub init_ms: f64,
    /// Time for the collapses.
    pub simplify_ms: f64,
    /// Why it stopped.
    pub stop: StopReason,
    /// Why the vertices left stay, when asked for and the run stopped short of its target.
    pub remaining: Option<Remaining>,
    /// The attributes that counted in the cost ([`SimplifyOptions::attribute_weights`]), by
    /// semantic (`NORMAL`, `TEXCOORD_0`, `COLOR_0`, ...): empty when none did.
    pub weighted_attributes: Vec<String>,
}

/// Progress reporting (a no-op unless asked for).
pub(crate) struct Progress {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    init: std::cell::Cell<Option<Instant>>,
    total: usize,
}

impl Progress {
    fn new(on: bool, total: usize, target: usize) -> Self {
        let bar = on.then(|| {
            let b = indicatif::ProgressBar::new((total - target.min(total)) as u64);
            b.set_style(
                indicatif::ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} triangles removed [{elapsed}]")
                    .unwrap(),
            );
            b.set_message("simplifying");
            b
        });
        Self { bar, start: Instant::now(), init: std::cell::Cell::new(None), total }
    }

    pub(crate) fn init_done(&self) {
        self.init.set(Some(Instant::now()));
    }

    pub(crate) fn tick(&self, live: usize) {
        if let Some(b) = &self.bar {
            if live % 1024 < 2 {
                b.set_position((self.total - live) as u64);
            }
        }
    }
}

/// Simplifies `mesh` in place; [`Mesh::to_indexed`] then gives the result with its wedges
/// and primitives. Vertices flagged [`vflag::LOCKED`] in `mesh.topology.vflags` never move.
pub fn simplify(mesh: &mut Mesh, options: SimplifyOptions) -> SimplifyStats {
    // On a pool thread: the parallel steps then fork and join on threads already awake
    // ([`crate::par::on_pool`]).
    crate::par::on_pool(|| simplify_here(mesh, options))
}

fn simplify_here(mesh: &mut Mesh, options: SimplifyOptions) -> SimplifyStats {
    let input = mesh.topology.live_face_count();
    let target = options.target_triangles.min(input);
    let progress = Progress::new(options.progress, input, target);
    let weights = if options.weighs_attributes() { options.attribute_weights } else { AttributeWeights::default() };
    let weighted_attributes = weights.weighted(mesh);
    let attributes = attribute_quadric::AttributeQuadrics::new(mesh, &weights);
    let mut engine = engine::Engine::new(mesh, options.cost, options.max_error, attributes);
    let collapses = match options.strategy {
        Strategy::Greedy => greedy::run(&mut engine, target, &progress),
        Strategy::MultipleChoice => mca::run(&mut engine, target, options.candidates, options.seed, &progress),
        Strategy::Batched => batched::run(&mut engine, target, &progress),
        Strategy::Flat => flat::run(&mut engine, target, &progress),
    };
    let end = Instant::now();
    let init = progress.init.get().unwrap_or(end);
    if let Some(b) = &progress.bar {
        b.finish_and_clear();
    }
    let output = engine.live_faces;
    SimplifyStats {
        input_triangles: input,
        output_triangles: output,
        collapses,
        max_error: engine.max_error,
        init_ms: (init - progress.start).as_secs_f64() * 1e3,
        simplify_ms: (end - init).as_secs_f64() * 1e3,
        stop: if output <= target { StopReason::Target } else { StopReason::NothingAllowed },
        remaining: (options.explain_shortfall && output > target).then(|| engine.remaining()),
        weighted_attributes,
    }
}

/// Why the vertices a run left cannot collapse any further, counted per live vertex by the
/// run's own engine (its quadrics, input normals and error bound) when it stopped short of
/// its target ([`SimplifyOptions::explain_shortfall`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Remaining {
    /// Live vertices.
    pub vertices: usize,
    /// Locked by the caller (`--lock-border`, [`lock_vertices`]).
    pub locked: usize,
    /// Fixed by the constraints: corners (borders turning too sharply), seam junctions, vertices
    /// where primitives meet or seams cross, valence over 128.
    pub fixed: usize,
    /// With somewhere to go, but every such collapse would break the manifold (link
    /// condition), split an attribute wedge, or turn a face over or too far from its input
    /// normal.
    pub blocked: usize,
    /// With an allowed collapse, but none within the error bound.
    pub over_error: usize,
    /// Still with an allowed collapse within the bound (0 after a run that ran out of
    /// collapses; the tests hold it to that).
    pub movable: usize,
}

/// Marks vertices that must never move or disappear.
pub fn lock_vertices(mesh: &mut Mesh, vertices: impl IntoIterator<Item = u32>) {
    for v in vertices {
        if let Some(f) = mesh.topology.vflags.get_mut(v as usize) {
            *f |= vflag::LOCKED;
        }
    }
}

#[cfg(test)]
mod tests {
    //! The bounds kept across a collapse ([`engine::Change::TargetOnly`]) against fresh ones:
    //! in test builds the greedy and multiple-choice loops assert, for every bound they keep,
    //! that a fresh evaluation gives the same bits, and that a vertex left out of the queue
    //! has no collapse. These runs drive those assertions over borders, seams, seam ends,
    //! primitives, flat regions (costs at rounding level) and both costs, with and without an
    //! error bound, with and without attributes weighed.
    use super::*;
    use crate::{procedural, BuildOptions};

    fn runs(mesh: &Mesh) {
        let bb = mesh.positions.iter().fold([f32::MAX, f32::MIN], |a, p| [a[0].min(p[0]), a[1].max(p[0])]);
        for m in Method::ALL {
            let weighted = SimplifyOptions::default().method(m).attribute_weights(AttributeWeights::all(1.0));
            for opts in [
                SimplifyOptions::default().method(m).target_triangles(0),
                SimplifyOptions::default().method(m).max_error(f64::from(bb[1] - bb[0]) * 0.01),
                weighted.target_triangles(0),
                weighted.max_error(f64::from(bb[1] - bb[0]) * 0.01),
            ] {
                let mut out = mesh.clone();
                let s = simplify(&mut out, opts);
                assert!(s.collapses > 0, "{m:?}: nothing collapsed");
                let weighs = opts.weighs_attributes() && opts.attribute_weights.any();
                assert_eq!(!s.weighted_attributes.is_empty(), weighs && !mesh.wedges.uvs.is_empty(), "{m:?}");
                out.topology.validate().unwrap();
            }
        }
    }

    #[test]
    fn kept_bounds_match_fresh_ones_on_the_bunny() {
        runs(&crate::test_bunny());
    }

    #[test]
    fn kept_bounds_match_fresh_ones_on_seams_flats_and_primitives() {
        runs(&Mesh::build(&procedural::uv_sphere(24, 32), BuildOptions::default()).unwrap());
        runs(&Mesh::build(&procedural::cut_grid(12, 10, 7, |x, y| (x * y) % 4 == 1), BuildOptions::default()).unwrap());
        let mut g = procedural::grid(12, 8, |x, y| (x + y) % 3 == 0);
        g.triangle_primitive = (0..g.triangles.len()).map(|t| u32::from((t / 2) % 12 >= 6)).collect();
        g.primitives = vec![Default::default(), Default::default()];
        runs(&Mesh::build(&g, BuildOptions::default()).unwrap());
    }
}

#[cfg(test)]
mod remaining_tests {
    use super::*;
    use crate::{procedural, BuildOptions};

    /// A grid run to nothing keeps its four outline corners (fixed), the locked vertex, and
    /// nothing movable; with an error bound, vertices are left over it.
    #[test]
    fn a_run_that_stops_short_says_why_each_vertex_stays() {
        let mut mesh = Mesh::build(&procedural::grid(6, 6, |_, _| false), BuildOptions::default()).unwrap();
        lock_vertices(&mut mesh, [24]);
        for m in Method::ALL {
            let mut work = mesh.clone();
            let s = simplify(&mut work, SimplifyOptions::default().method(m).explain_shortfall(true));
            assert_eq!(s.stop, StopReason::NothingAllowed);
            let r = s.remaining.unwrap();
            assert_eq!((r.locked, r.fixed, r.movable, r.over_error), (1, 4, 0, 0), "{m:?}: {r:?}");
            assert_eq!(r.vertices, r.locked + r.fixed + r.blocked, "{m:?}: {r:?}");
        }
        let mut work = Mesh::build(&procedural::uv_sphere(12, 16), BuildOptions::default()).unwrap();
        let s =
            simplify(&mut work, SimplifyOptions::default().method(Method::Qem).max_error(1e-3).explain_shortfall(true));
        let r = s.remaining.unwrap();
        assert!(r.over_error > 0 && r.movable == 0, "{r:?}");
        let s = simplify(&mut work, SimplifyOptions::default().target_triangles(usize::MAX));
        assert_eq!(s.remaining, None, "not asked for, or nothing short");
    }

    /// The library's default is the command line's: the flat quadric passes.
    #[test]
    fn the_default_method_is_qem_flat() {
        assert_eq!(SimplifyOptions::default(), SimplifyOptions::default().method(Method::QemFlat));
        assert_ne!(SimplifyOptions::default(), SimplifyOptions::default().method(Method::Mca));
    }

    /// After a run that ran out of collapses, the run's own engine finds nothing movable left
    /// (on the bunny, for every method): the count reads the state the run stopped in.
    #[test]
    fn nothing_is_movable_after_a_run_that_ran_out() {
        let mesh = crate::test_bunny();
        for m in Method::ALL {
            let mut work = mesh.clone();
            let s = simplify(&mut work, SimplifyOptions::default().method(m).explain_shortfall(true));
            let r = s.remaining.unwrap();
            assert_eq!(r.movable, 0, "{m:?}: {r:?}");
            assert!(r.fixed > 0 && r.vertices == r.fixed + r.blocked, "{m:?}: {r:?}");
        }
    }
}
