//! Rounds of parallel half-edge collapses: papers/000 §2 (the loop), §4 (selection under the
//! boundaries), §5 (deadlock prevention) and §6 (reclassification).
//!
//! ```text
//!   classify once: R (remove) / S (stay), anchors in S          (§3, classify.rs, anchors.rs)
//!   round:  C = R \ ignored with a neighbour in S
//!           every c ∈ C selects a target from the same state, in parallel   (select.rs)
//!           apply in vertex order, re-checking the link condition, so the round as a whole
//!             keeps the mesh manifold (a choice that became illegal waits for the next round)
//!           §5: blocked even alone → c stays for good if all its neighbours are in S, else it
//!             waits (ignored) for a neighbour to change; blocked only by neighbours twice in a
//!             row with no neighbour removed → ignored, unless its error tops theirs
//!             (ties: the larger vertex id tops, so a flat deadlocked ring resolves)
//!           §6: R-neighbours of this round's targets whose max tangent-plane distance to
//!             their S-neighbours exceeds the reclassification threshold move to S
//!   until C is empty, nothing changes, or the round cap
//! ```
//! Selection is a pure function per candidate and application runs in vertex order, so the
//! result is the same for any thread count. The mesh is valid after every round (the paper's
//! "can be aborted after each iteration").

use rayon::prelude::*;

use super::passes::anchors::{apply_anchors, select_anchors, AnchorOptions};
use super::passes::classify::{classify, screen_error, vertex_errors, vertex_normals, ClassifyOptions};
use super::passes::select::{select_on_mesh, Selection};
use crate::mesh::{constraints, Mesh};
use crate::topology::{HalfEdgeCollapse, Topology, INVALID};
use crate::view::View;

/// Options of a coarsening run.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CoarsenOptions {
    /// Threshold u and view scales (§3). Default: u = 1 (pixel, or model unit without a view).
    pub classify: ClassifyOptions,
    /// Grid anchors (§3). Default: L0 only, √(n/128) cells per axis (16 on the bunny: denser
    /// than 4 cuts the rounds 2–4× at equal or lower error; see docs/BENCHMARKS.md).
    pub anchors: Option<AnchorOptions>,
    /// Reclassification threshold (§6), in the units of u. Default: 2 × u.
    pub reclassify_threshold: Option<f32>,
    /// Round cap. Default: 1000 (a far view, where nearly everything starts in R, can need
    /// a few hundred rounds with sparse anchors).
    pub max_rounds: usize,
}

impl Default for CoarsenOptions {
    fn default() -> Self {
        Self {
            classify: ClassifyOptions::default(),
            anchors: Some(AnchorOptions::default()),
            reclassify_threshold: None,
            max_rounds: 1000,
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
}

/// What one round did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RoundStats {
    /// Removal candidates this round.
    pub candidates: usize,
    /// Collapses applied.
    pub collapsed: usize,
    /// Selections dropped at application (link condition no longer held).
    pub deferred: usize,
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
}

/// The state carried between rounds.
pub struct Coarsener {
    view: Option<View>,
    options: CoarsenOptions,
    normals: Vec<[f32; 3]>,
    errors: Vec<f32>,
    in_r: Vec<bool>,
    ignored: Vec<bool>,
    blocked_before: Vec<bool>,
}

impl Coarsener {
    /// Analyses and classifies `mesh` for `view` (None: view-independent).
    pub fn new(mesh: &Mesh, view: Option<View>, options: CoarsenOptions) -> Self {
        let t = &mesh.topology;
        let normals = vertex_normals(t, &mesh.positions);
        let mut errors = vertex_errors(t, &mesh.positions, &normals);
        if let Some(a) = &options.anchors {
            let anchors = select_anchors(t, &mesh.positions, &errors, a);
            apply_anchors(&mut errors, &anchors, a);
        }
        let in_r = classify(view.as_ref(), t, &mesh.positions, &normals, &errors, &options.classify);
        let n = t.vertex_count();
        Self { view, options, normals, errors, in_r, ignored: vec![false; n], blocked_before: vec![false; n] }
    }

    /// Vertices currently in R.
    pub fn remove_set(&self) -> &[bool] {
        &self.in_r
    }

    /// Runs one round on `mesh` (the mesh this coarsener was made for).
    pub fn round(&mut self, mesh: &mut Mesh) -> RoundStats {
        let n = mesh.topology.vertex_count();
        let stays: Vec<bool> = (0..n).map(|v| !self.in_r[v] && mesh.topology.vertex_he[v] != INVALID).collect();
        let t = &mesh.topology;
        let cand: Vec<bool> = (0..n as u32)
            .into_par_iter()
            .map(|v| {
                let u = v as usize;
                self.in_r[u]
                    && !self.ignored[u]
                    && t.vertex_he[u] != INVALID
                    && t.neighbors(v).any(|w| stays[w as usize])
            })
            .collect();
        let ids: Vec<u32> = (0..n as u32).filter(|&v| cand[v as usize]).collect();
        let eye = self.view.map(|v| v.eye);
        let m: &Mesh = mesh;
        let choices: Vec<Selection> = ids.par_iter().map(|&v| select_on_mesh(m, v, &cand, &stays, eye)).collect();
        let mut s = RoundStats { candidates: ids.len(), ..Default::default() };
        let mut removed_now = vec![false; n];
        let mut targets = Vec::new();
        for (&v, choice) in ids.iter().zip(&choices) {
            match *choice {
                Selection::Collapse { target, .. } => {
                    let Some(he) = mesh.topology.find_edge(v, target) else {
                        s.deferred += 1;
                        continue;
                    };
                    let c = HalfEdgeCollapse { he, remove: v };
                    let (hu, hv) = constraints::halves(&mesh.topology, c);
                    let fan: Vec<u32> = mesh.topology.outgoing(v).collect();
                    if mesh.topology.collapse_is_legal(c).is_err()
                        || !constraints::wedges_carry_over(mesh, &fan, hu, hv)
                    {
                        s.deferred += 1;
                        continue;
                    }
                    constraints::collapse_with_wedges(mesh, c);
                    self.in_r[v as usize] = false;
                    removed_now[v as usize] = true;
                    targets.push(target);
                    s.collapsed += 1;
                }
                Selection::Blocked { alone: false } => {
                    // Cannot go now even alone. With only S around it nothing will change:
                    // it is part of the result. Otherwise it waits (like an ignored vertex)
                    // until a neighbour is removed or reclassified.
                    if mesh.topology.neighbors(v).all(|w| stays[w as usize]) {
                        self.in_r[v as usize] = false;
                    } else {
                        self.ignored[v as usize] = true;
                    }
                    s.stuck += 1;
                }
                Selection::Blocked { alone: true } => s.blocked += 1,
            }
        }
        let t = &mesh.topology;
        // §5: a candidate blocked by neighbours in two rounds running, none of whose
        // neighbouring candidates went away, is ignored unless its error is the largest.
        for (&v, choice) in ids.iter().zip(&choices) {
            let u = v as usize;
            let blocked = matches!(choice, Selection::Blocked { alone: true });
            if blocked && self.blocked_before[u] && t.vertex_he[u] != INVALID {
                let neighbours_moved = t.neighbors(v).any(|w| removed_now[w as usize]);
                let tops = t
                    .neighbors(v)
                    .filter(|&w| cand[w as usize])
                    .all(|w| outranks((self.errors[u], v), (self.errors[w as usize], w)));
                if !neighbours_moved && !tops {
                    self.ignored[u] = true;
                    s.ignored += 1;
                }
            }
            self.blocked_before[u] = blocked;
        }
        // §6: re-check the R-neighbours of this round's targets with the max-distance metric.
        let threshold = self.options.reclassify_threshold.unwrap_or(2.0 * self.options.classify.threshold);
        targets.sort_unstable();
        targets.dedup();
        let mut touched: Vec<u32> = targets.iter().flat_map(|&x| t.neighbors(x).chain(std::iter::once(x))).collect();
        touched.sort_unstable();
        touched.dedup();
        let mut reclassified = Vec::new();
        for &w in &touched {
            let u = w as usize;
            if !self.in_r[u] || t.vertex_he[u] == INVALID {
                continue;
            }
            let e = max_distance_to_stayers(t, &mesh.positions, self.normals[u], w, &self.in_r);
            let px = screen_error(self.view.as_ref(), mesh.positions[u], self.normals[u], e, &self.options.classify);
            if px > threshold {
                self.in_r[u] = false;
                reclassified.push(w);
            }
        }
        s.reclassified = reclassified.len();
        // A neighbour reclassified or removed lifts the ignore flag.
        for &w in targets.iter().chain(&reclassified) {
            for x in t.neighbors(w) {
                self.ignored[x as usize] = false;
            }
        }
        s
    }
}

/// §5's "e(VR) is greater than the error of every neighbouring candidate", with ties broken
/// by the larger vertex id. Without the tie-break a ring of equal errors (any flat region:
/// e(V) = 0 there) would be ignored as a whole and never resolved.
pub(crate) fn outranks((e, v): (f32, u32), (f, w): (f32, u32)) -> bool {
    e > f || (e == f && v > w)
}

/// §6's metric: the largest squared distance from V's (stored) tangent plane to a neighbour
/// that stays (neighbours in R are left out: they may go).
fn max_distance_to_stayers(t: &Topology, positions: &[[f32; 3]], normal: [f32; 3], v: u32, in_r: &[bool]) -> f32 {
    let p = positions[v as usize].map(f64::from);
    let n = normal.map(f64::from);
    let d = -(n[0] * p[0] + n[1] * p[1] + n[2] * p[2]);
    t.neighbors(v)
        .filter(|&w| !in_r[w as usize])
        .map(|w| {
            let q = positions[w as usize].map(f64::from);
            let dist = n[0] * q[0] + n[1] * q[1] + n[2] * q[2] + d;
            (dist * dist) as f32
        })
        .fold(0.0, f32::max)
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
/// candidate is left, a round changes nothing, or the round cap.
pub fn coarsen(mesh: &mut Mesh, view: Option<View>, options: CoarsenOptions) -> CoarsenStats {
    let start = std::time::Instant::now();
    let input = mesh.topology.live_face_count();
    let cap = options.max_rounds;
    let mut c = Coarsener::new(mesh, view, options);
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
/// (else the smallest reached), its stats and its u.
pub fn coarsen_to_triangles(
    mesh: &Mesh,
    view: Option<View>,
    options: &CoarsenOptions,
    target: usize,
    lo: f32,
    hi: f32,
) -> (Mesh, CoarsenStats, f32) {
    let run = |u: f32| {
        let mut m = mesh.clone();
        let s = coarsen(&mut m, view, options.clone().threshold(u));
        (m, s, u)
    };
    let (mut lo, mut hi) = (lo.max(f32::MIN_POSITIVE).ln(), hi.max(lo * 2.0).ln());
    let mut best = run(hi.exp());
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
