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

use std::sync::atomic::AtomicU32;
use std::sync::atomic::Ordering::Relaxed;

use rayon::prelude::*;

use super::passes::anchors::{apply_anchors, select_anchors, AnchorOptions};
use super::passes::apply::{apply_in_parts, Applied, Applying};
use super::passes::classify::{classify, screen_error_in, vertex_normals_and_errors, ClassifyOptions, TangentPlane};
use super::passes::select::{select_on_mesh_with, SelectScratch, Selection, NOBODY_ELSE};
use crate::lists::keep_and_pick;
use crate::mesh::{constraints, Mesh};
use crate::par::{filter_map_sized, map_sized};
use crate::topology::{Gained, HalfEdgeCollapse, HalfEdges, Parts, RoundTouches, Topology, INVALID};
use crate::view::{Frustum, View};

/// Below this many candidates (or vertices to reclassify) a round's pass runs on the calling
/// thread: the last dozen rounds of a run have a few hundred or fewer, and waking the pool
/// for them costs more than the work.
const PARALLEL_MIN: usize = 256;

/// Fewest of the vertices inside one part ([`Parts::inner_share`]) for a round's collapses to
/// be made in parts: below it (a mesh in file or scan order: the bunny's 61 % for two parts)
/// the collapses across the cuts, made afterwards on one thread, cost more than the parts
/// save; in spatial order 96 % (bunny) to 99 % (igea). docs/BENCHMARKS.md, session 20.
const MIN_INNER_SHARE: f64 = 0.9;

/// Fewest candidates a selection task takes (a selection is a microsecond or two)...
const SELECT_TASK: usize = 32;

/// ...and fewest vertices a reclassification task takes (a fan walk each).
const TASK: usize = 256;

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
    /// Which candidates act in a round. Default: [`Schedule::LocalMinima`].
    pub schedule: Schedule,
    /// Under [`Schedule::LocalMinima`] on a mesh without separate wedges, the parts a round's
    /// collapses are made in side by side ([`Parts`]); 1: all on the calling thread, in
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
            anchors: Some(AnchorOptions::default()),
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
    /// Whether a vertex has been stuck (no legal move even alone) in an earlier round.
    stuck_before: Vec<bool>,
    /// Live vertices in S (valid targets).
    stays: Vec<bool>,
    /// Vertices still in R, ascending (pruned every round: the work of a round follows R,
    /// not the mesh).
    pending: Vec<u32>,
    /// Whether a vertex has a neighbour in S. Kept up to date instead of recomputed: it never
    /// turns false (S only grows, and a collapse removes no edge between two survivors).
    near_s: Vec<bool>,
    /// Scratch flags, all false between rounds.
    cand: Vec<bool>,
    removed_now: Vec<bool>,
    /// What this round's collapses did to the fans around them, to tell which later ones
    /// need their link condition checked again, and which vertices gained one neighbour.
    touches: RoundTouches,
    /// §6's metric as last worked out per vertex, NaN when not yet or when a neighbour has
    /// joined S since (see [`Coarsener::round`]'s §6 pass). f32 bits, atomic as `blocker` is.
    stay_max: Vec<AtomicU32>,
    /// [`Schedule::LocalMinima`]: the neighbouring candidate that last made a vertex wait
    /// (`INVALID`: none, or the vertex's fan has changed since). While it is still a candidate
    /// and still comes first, the vertex waits again without walking its fan. Atomic so that
    /// the selection pass writes each candidate's own entry where it works it out (relaxed:
    /// no entry is read in the pass that writes it, except by its own candidate).
    blocker: Vec<AtomicU32>,
    /// Re-check every collapse at application (tests compare with the skipped re-checks).
    always_recheck: bool,
    /// Where the application is cut into parts ([`CoarsenOptions::apply_parts`]), if it is.
    parts: Option<Parts>,
}

impl Coarsener {
    /// Analyses and classifies `mesh` for `view` (None: view-independent).
    pub fn new(mesh: &Mesh, view: Option<View>, options: CoarsenOptions) -> Self {
        let t = &mesh.topology;
        let (normals, mut errors) = vertex_normals_and_errors(t, &mesh.positions);
        if let Some(a) = &options.anchors {
            let anchors = select_anchors(t, &mesh.positions, &errors, a);
            apply_anchors(&mut errors, &anchors, a);
        }
        let in_r = classify(view.as_ref(), t, &mesh.positions, &normals, &errors, &options.classify);
        let n = t.vertex_count();
        let live = |v: usize| t.vertex_he[v] != INVALID;
        let stays: Vec<bool> = (0..n).into_par_iter().map(|v| !in_r[v] && live(v)).collect();
        let pending: Vec<u32> =
            (0..n as u32).into_par_iter().filter(|&v| in_r[v as usize] && live(v as usize)).collect();
        // Only vertices in R ever read it.
        let near: Vec<u32> =
            pending.par_iter().copied().filter(|&v| t.neighbors(v).any(|w| stays[w as usize])).collect();
        let mut near_s = vec![false; n];
        for v in near {
            near_s[v as usize] = true;
        }
        let in_parts =
            options.apply_parts > 1 && options.schedule == Schedule::LocalMinima && mesh.wedges.is_identity();
        let parts =
            in_parts.then(|| Parts::new(t, options.apply_parts)).filter(|p| p.inner_share(t) >= MIN_INNER_SHARE);
        Self {
            view,
            options,
            normals,
            errors,
            in_r,
            ignored: vec![false; n],
            blocked_before: vec![false; n],
            stuck_before: vec![false; n],
            stays,
            pending,
            near_s,
            cand: vec![false; n],
            removed_now: vec![false; n],
            touches: RoundTouches::new(n),
            stay_max: (0..n).map(|_| AtomicU32::new(f32::NAN.to_bits())).collect(),
            blocker: (0..n).map(|_| AtomicU32::new(INVALID)).collect(),
            always_recheck: false,
            parts,
        }
    }

    /// Vertices currently in R.
    pub fn remove_set(&self) -> &[bool] {
        &self.in_r
    }

    /// Runs one round on `mesh` (the mesh this coarsener was made for).
    pub fn round(&mut self, mesh: &mut Mesh) -> RoundStats {
        let t = &mesh.topology;
        let (in_r, near_s, ignored) = (&self.in_r, &self.near_s, &self.ignored);
        // Serial: a flag read or two per vertex is cheaper here than splitting the list over
        // the pool and joining the pieces (bunny, 17,565-triangle case: 2.7 → 1.6 ms a run).
        // One pass without a branch on the flags (crate::lists), raising the candidates' flags.
        let cand = &mut self.cand;
        let all = keep_and_pick(&mut self.pending, |v| {
            let u = v as usize;
            let keep = in_r[u] & (t.vertex_he[u] != INVALID);
            let candidate = keep & !ignored[u] & near_s[u];
            cand[u] |= candidate;
            (keep, candidate)
        });
        let count = all.len();
        let eye = self.view.map(|v| v.eye);
        let m: &Mesh = mesh;
        let (cand, stays) = (&self.cand, &self.stays);
        // `ids`: the actors, each with its selection; `all` keeps the candidates only where
        // they are more than the actors (to clear their flags at the end).
        let (ids, choices, all): (Vec<u32>, Vec<Selection>, Vec<u32>) = match self.options.schedule {
            Schedule::AllCandidates => {
                let choices = map_sized(&all, PARALLEL_MIN, SELECT_TASK, |sc: &mut SelectScratch, &v| {
                    select_on_mesh_with(sc, m, v, cand, stays, eye)
                });
                (all, choices, Vec::new())
            }
            Schedule::LocalMinima => {
                // One pass: a candidate that comes first among its neighbouring candidates
                // acts; the others wait and, to the actors, stay put. No neighbour of an actor
                // acts, so an actor selects as if it were the only one moving.
                let (errors, stuck, blocker) = (&self.errors, &self.stuck_before, &self.blocker);
                let key = |v: u32| (stuck[v as usize], errors[v as usize], v);
                // The neighbouring candidate that goes before v (INVALID: v acts). The last
                // one found is tried first: still a neighbour unless v's fan changed (which
                // forgets it), so only whether it is still a candidate and still comes first
                // needs checking.
                let behind = |v: u32| {
                    let b = blocker[v as usize].load(Relaxed);
                    if b != INVALID && cand[b as usize] && goes_first(key(b), key(v)) {
                        return b;
                    }
                    first_ahead(t, v, cand, key).unwrap_or(INVALID)
                };
                // The actors with their selections, in `all`'s order; every candidate's
                // blocker is written as it is worked out (three in four wait, and a serial
                // pass over all of them cost more than the wait checks on two threads).
                let actors: Vec<(u32, Selection)> =
                    filter_map_sized(&all, PARALLEL_MIN, SELECT_TASK, |sc: &mut SelectScratch, &v| {
                        let b = behind(v);
                        // Unit-test builds check the remembered blocker against the full walk.
                        #[cfg(test)]
                        assert_eq!(
                            b == INVALID,
                            t.neighbors(v).filter(|&w| cand[w as usize]).all(|w| goes_first(key(v), key(w))),
                            "vertex {v}: the remembered blocker {b} disagrees with its fan"
                        );
                        blocker[v as usize].store(b, Relaxed);
                        (b == INVALID).then(|| (v, select_on_mesh_with(sc, m, v, NOBODY_ELSE, stays, eye)))
                    });
                let (ids, choices) = actors.into_iter().unzip();
                (ids, choices, all)
            }
        };
        let mut s = RoundStats { candidates: count, waiting: count - ids.len(), ..Default::default() };
        let mut settled = Vec::new();
        let dirtied = match self.options.schedule {
            Schedule::AllCandidates => self.apply_in_order(mesh, &ids, &choices, &mut settled, &mut s),
            Schedule::LocalMinima => {
                for (&v, choice) in ids.iter().zip(&choices) {
                    if let Selection::Blocked { alone } = *choice {
                        self.blocked(&mesh.topology, v, alone, &mut settled, &mut s);
                    }
                }
                self.apply_actors(mesh, &ids, &choices, &mut s)
            }
        };
        // §6 re-checks the removed vertices' neighbours still in R, in the order the round
        // first touched them (targets are in S, so not among them).
        let touched: Vec<u32> = dirtied.iter().copied().filter(|&w| self.in_r[w as usize]).collect();
        let t = &mesh.topology;
        // (A settled vertex has only neighbours in S, so no §6 metric below counts it.)
        for &v in &settled {
            self.stays[v as usize] = true;
        }
        // §5: a candidate blocked by neighbours in two rounds running, none of whose
        // neighbouring candidates went away, is ignored unless its error is the largest.
        for (&v, choice) in ids.iter().zip(&choices) {
            let u = v as usize;
            let blocked = matches!(choice, Selection::Blocked { alone: true });
            if blocked && self.blocked_before[u] && t.vertex_he[u] != INVALID {
                let neighbours_moved = t.neighbors(v).any(|w| self.removed_now[w as usize]);
                let tops = t
                    .neighbors(v)
                    .filter(|&w| self.cand[w as usize])
                    .all(|w| outranks((self.errors[u], v), (self.errors[w as usize], w)));
                if !neighbours_moved && !tops {
                    self.ignored[u] = true;
                    s.ignored += 1;
                }
            }
            self.blocked_before[u] = blocked;
        }
        // §6: re-check the R-neighbours of this round's removed vertices with the max-distance
        // metric, all against the state after the collapses (the order does not matter). A
        // vertex's neighbours in S only ever grow: S vertices are never removed, and a
        // collapse u → v hands u's neighbours the target v. So a vertex whose metric is known
        // keeps it if it gained no neighbour this round (it was only a wing), or takes the
        // larger of it and the target's distance if it gained exactly that one
        // (RoundTouches::gained): the same maximum over the same neighbours as a walk. Any
        // other vertex walks its fan. (A vertex reclassified into S makes its neighbours
        // forget their metrics.)
        let threshold = self.options.reclassify_threshold.unwrap_or(2.0 * self.options.classify.threshold);
        let (in_r, normals, touches, stay_max) = (&self.in_r, &self.normals, &self.touches, &self.stay_max);
        let frustum = self.view.as_ref().map(Frustum::new);
        // Each vertex's metric is kept where it is worked out (relaxed, as the blockers: each
        // vertex reads and writes only its own); the pass returns the vertices that go to S.
        let reclassified: Vec<u32> = filter_map_sized(&touched, PARALLEL_MIN, TASK, |_: &mut (), &w| {
            let u = w as usize;
            let known = f32::from_bits(stay_max[u].load(Relaxed));
            let e = match touches.gained(w) {
                Gained::Nothing if !known.is_nan() => known,
                Gained::One(v) if !known.is_nan() => known
                    .max(squared_f32(&TangentPlane::new(&mesh.positions, normals[u], w), mesh.positions[v as usize])),
                _ => max_distance_to_stayers(t, &mesh.positions, normals[u], w, in_r),
            };
            // Unit-test builds check the update against the walk.
            #[cfg(test)]
            assert_eq!(
                e.to_bits(),
                max_distance_to_stayers(t, &mesh.positions, normals[u], w, in_r).to_bits(),
                "vertex {w}"
            );
            stay_max[u].store(e.to_bits(), Relaxed);
            let px = screen_error_in(frustum.as_ref(), mesh.positions[u], normals[u], e, &self.options.classify);
            (px > threshold).then_some(w)
        });
        self.touches.clear(&dirtied);
        for &w in &reclassified {
            self.in_r[w as usize] = false;
            self.stays[w as usize] = true;
            forget_stay_max(&mut self.stay_max, t, w);
        }
        s.reclassified = reclassified.len();
        for &v in &ids {
            self.removed_now[v as usize] = false;
        }
        // A neighbour removed or reclassified lifts the ignore flag: the removed vertex's
        // neighbours (`touched`) are the vertices whose fans the round changed. (Not every
        // neighbour of a target: on CAD models a target can have a hundred neighbours, all
        // stuck for good, and waking them after every collapse kept runs going for hundreds
        // of rounds.) Every vertex next to a target, a reclassified or a settled vertex is
        // next to S.
        for &x in &touched {
            self.ignored[x as usize] = false;
        }
        for &w in &reclassified {
            for x in t.neighbors(w) {
                self.ignored[x as usize] = false;
            }
        }
        // New neighbours of S: a target's are the removed vertex's (`dirtied`).
        for &x in &dirtied {
            self.near_s[x as usize] = true;
        }
        for &w in reclassified.iter().chain(&settled) {
            for x in t.neighbors(w) {
                self.near_s[x as usize] = true;
            }
        }
        for &v in ids.iter().chain(&all) {
            self.cand[v as usize] = false;
        }
        s
    }
}

impl Coarsener {
    /// §5 for an actor that found no valid target. Cannot go even alone: with only S around
    /// it nothing will change, so it is part of the result; otherwise it waits (like an
    /// ignored vertex) until a neighbour is removed or reclassified.
    fn blocked(&mut self, t: &Topology, v: u32, alone: bool, settled: &mut Vec<u32>, s: &mut RoundStats) {
        if alone {
            s.blocked += 1;
            return;
        }
        if t.neighbors(v).all(|w| self.stays[w as usize]) {
            self.in_r[v as usize] = false;
            settled.push(v);
        } else {
            self.ignored[v as usize] = true;
        }
        self.stuck_before[v as usize] = true;
        s.stuck += 1;
    }

    /// [`Schedule::AllCandidates`]: neighbouring actors may both have chosen, so each choice
    /// is checked again in full, in vertex order, after the ones before it (blocked actors
    /// are settled in the same order: a neighbour's collapse can change what they see).
    /// Returns the vertices touched, in the order met.
    fn apply_in_order(
        &mut self,
        mesh: &mut Mesh,
        ids: &[u32],
        choices: &[Selection],
        settled: &mut Vec<u32>,
        s: &mut RoundStats,
    ) -> Vec<u32> {
        let mut fan = Vec::new();
        let mut dirtied = Vec::new();
        for (&v, choice) in ids.iter().zip(choices) {
            let (c, target) = match *choice {
                Selection::Collapse { target, .. } => match mesh.topology.find_edge(v, target) {
                    Some(he) => (HalfEdgeCollapse { he, remove: v }, target),
                    None => {
                        s.deferred += 1;
                        continue;
                    }
                },
                Selection::Blocked { alone } => {
                    self.blocked(&mesh.topology, v, alone, settled, s);
                    continue;
                }
            };
            let (hu, hv) = constraints::halves(&mesh.topology, c);
            fan.clear();
            fan.extend(mesh.topology.outgoing(v));
            if mesh.topology.collapse_is_legal(c).is_err() || !constraints::wedges_carry_over(mesh, &fan, hu, hv) {
                s.deferred += 1;
                continue;
            }
            let mut state =
                Applying::whole(&mut self.in_r, &mut self.removed_now, &mut self.blocker, &mut self.touches);
            state.touch(&mesh.topology, c);
            debug_assert_eq!(mesh.topology.collapse_target(c), target);
            constraints::collapse_with_wedges(mesh, c);
            state.removed(v);
            dirtied.append(&mut state.dirtied);
            s.collapsed += 1;
        }
        dirtied
    }

    /// [`Schedule::LocalMinima`]: the actors are pairwise non-adjacent, so no earlier collapse
    /// of this round touched an actor's fan (its faces, their corners and wedges), and the
    /// collapse it chose on the round's state is still the same half-edge with the same
    /// wedges. What earlier collapses did around the target tells whether the link condition
    /// checked at selection still holds, mostly without walking a fan ([`RoundTouches`]).
    /// Made in parts side by side where the mesh is cut ([`Parts`]), else in vertex order.
    /// Returns the vertices touched.
    fn apply_actors(&mut self, mesh: &mut Mesh, ids: &[u32], choices: &[Selection], s: &mut RoundStats) -> Vec<u32> {
        let chosen = ids.iter().zip(choices).filter_map(|(&v, choice)| match *choice {
            Selection::Collapse { collapse, .. } => {
                debug_assert_eq!(collapse.remove, v);
                Some(collapse)
            }
            Selection::Blocked { .. } => None,
        });
        let full = self.always_recheck;
        let mut whole = Applying::whole(&mut self.in_r, &mut self.removed_now, &mut self.blocker, &mut self.touches);
        let mut done = match &mut self.parts {
            Some(parts) => {
                let mut inner = vec![Vec::new(); parts.count()];
                let mut rest = Vec::new();
                for c in chosen {
                    match parts.part_of(&mesh.topology, c) {
                        Some(k) => inner[k].push(c),
                        None => rest.push(c),
                    }
                }
                let done = apply_in_parts(mesh, parts, &inner, &rest, full, &mut whole, PARALLEL_MIN);
                s.collapsed_in_parts = done.iter().map(|d| d.collapsed).sum();
                done
            }
            None => {
                let list: Vec<HalfEdgeCollapse> = chosen.collect();
                whole.apply(mesh, &list, full);
                Vec::new()
            }
        };
        done.push(Applied::from(whole));
        let mut dirtied = Vec::new();
        for mut d in done {
            s.collapsed += d.collapsed;
            s.deferred += d.deferred;
            dirtied.append(&mut d.dirtied);
        }
        dirtied
    }
}

/// [`Schedule::LocalMinima`]'s order. Vertices that have been stuck (no legal move even
/// alone) go after the others: they are woken whenever a neighbour changes and are usually
/// stuck again, and in front they would hold their waiting neighbours back a round each time
/// (on CAD models, with many seam and corner vertices, the run hit the round cap). Then the
/// lower error first; ties (flat regions, where every e(V) is 0) by a scrambled id, so that a
/// row of tied vertices numbered in order does not go one per round (with plain ids only the
/// row's first vertex would be a local minimum). A total order: `scramble` is a bijection.
pub(crate) fn goes_first((s, e, v): (bool, f32, u32), (t, f, w): (bool, f32, u32)) -> bool {
    s.cmp(&t).then(e.total_cmp(&f)).then(scramble(v).cmp(&scramble(w))).is_lt()
}

/// The first neighbouring candidate of `v` (fan order) that goes before it in `key`'s
/// [`goes_first`] order; `None` when v is a local minimum and acts this round.
pub(crate) fn first_ahead(t: &Topology, v: u32, cand: &[bool], key: impl Fn(u32) -> (bool, f32, u32)) -> Option<u32> {
    let kv = key(v);
    t.neighbors(v).find(|&w| cand[w as usize] && goes_first(key(w), kv))
}

/// A bijection on u32 that scatters consecutive ids (a multiply-xorshift mixer; each step is
/// invertible).
fn scramble(v: u32) -> u32 {
    let mut x = v.wrapping_mul(0x9E37_79B1);
    x ^= x >> 16;
    x = x.wrapping_mul(0x85EB_CA6B);
    x ^ (x >> 13)
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
    let plane = TangentPlane::new(positions, normal, v);
    t.neighbors(v)
        .filter(|&w| !in_r[w as usize])
        .map(|w| squared_f32(&plane, positions[w as usize]))
        .fold(0.0, f32::max)
}

/// §6's squared distance from a tangent plane, rounded to f32.
#[inline]
fn squared_f32(plane: &TangentPlane, q: [f32; 3]) -> f32 {
    let dist = plane.distance(q);
    (dist * dist) as f32
}

/// A vertex joined S: its neighbours' §6 metrics no longer cover all their neighbours in S.
fn forget_stay_max(stay_max: &mut [AtomicU32], t: &Topology, v: u32) {
    for x in t.neighbors(v) {
        *stay_max[x as usize].get_mut() = f32::NAN.to_bits();
    }
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
    crate::par::on_pool(|| coarsen_here(mesh, view, options))
}

/// [`coarsen`] on the calling thread.
fn coarsen_here(mesh: &mut Mesh, view: Option<View>, options: CoarsenOptions) -> CoarsenStats {
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
                    let mut c = Coarsener::new(&m, None, CoarsenOptions::default().threshold(u * diag));
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
