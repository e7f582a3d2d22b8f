//! One round of papers/000: candidates, the parallel selection (§4), the ordered application,
//! §5's ignore flags and §6's reclassification; the state a [`Coarsener`] carries between rounds.

use std::sync::atomic::AtomicU32;
use std::sync::atomic::Ordering::Relaxed;

use rayon::prelude::*;

use crate::lists::keep_and_pick;
use crate::lod::passes::apply::{apply_in_parts, Applied, Applying};
use crate::lod::passes::classify::{classify, screen_error_views, vertex_normals_and_errors, TangentPlane};
use crate::lod::passes::select::{select_on_mesh_with, Floors, SelectScratch, Selection, Stays, NOBODY_ELSE};
use crate::lod::passes::structure_anchors::mesh_anchors;
use crate::mesh::{constraints, Mesh};
use crate::par::{filter_map_sized, map_sized};
use crate::topology::{Gained, HalfEdgeCollapse, HalfEdges, Parts, RoundTouches, Topology, INVALID};
use crate::view::{Frustum, View, Viewpoint};

use super::{first_ahead, goes_first, outranks, CoarsenOptions, RoundStats, Schedule};

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

/// The state carried between rounds.
pub struct Coarsener {
    /// The views' per-pass constants (none: view-independent) and where each sees from.
    frustums: Vec<Frustum>,
    eyes: Vec<Viewpoint>,
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
    /// The anchors' floors by vertex id, when nested (else empty): an anchor also takes
    /// removals finer than itself (`select::Stays`).
    floors: Floors,
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
    pub(super) always_recheck: bool,
    /// Where the application is cut into parts ([`CoarsenOptions::apply_parts`]), if it is.
    parts: Option<Parts>,
}

impl Coarsener {
    /// Analyses and classifies `mesh` for every view of `views` at once (none:
    /// view-independent): a vertex is removed only where every view lets it go, and no
    /// triangle turns against any of them.
    pub fn new(mesh: &Mesh, views: &[View], options: CoarsenOptions) -> Self {
        let t = &mesh.topology;
        let (normals, mut errors) = vertex_normals_and_errors(t, &mesh.positions);
        let mut floors =
            options.anchors.as_ref().map_or_else(Vec::new, |a| mesh_anchors(mesh, &errors, a).floor_list(a));
        for &(v, f) in &floors {
            errors[v as usize] = errors[v as usize].max(f);
        }
        // Anchors take finer removals only when nested: elsewhere the paper's R → S alone.
        if options.anchors.as_ref().is_none_or(|a| a.nested.is_none()) {
            floors = Vec::new();
        }
        // A view repeated (instances at one place) counts once.
        let views: Vec<&View> = {
            let (mut order, mut keep) = (Vec::new(), Vec::new());
            crate::view::distinct_into(views, &mut order, &mut keep);
            keep.iter().map(|&k| &views[k as usize]).collect()
        };
        let frustums: Vec<Frustum> = views.iter().map(|v| Frustum::new(v)).collect();
        let in_r = classify(&frustums, t, &mesh.positions, &normals, &errors, &options.classify);
        let n = t.vertex_count();
        let live = |v: usize| t.vertex_he[v] != INVALID;
        let stays: Vec<bool> = (0..n).into_par_iter().map(|v| !in_r[v] && live(v)).collect();
        let pending: Vec<u32> =
            (0..n as u32).into_par_iter().filter(|&v| in_r[v as usize] && live(v as usize)).collect();
        // Only vertices in R ever read it.
        let floors = Floors::new(floors, n);
        let targets = Stays { class: &stays, floors: Some(&floors) };
        let near: Vec<u32> =
            pending.par_iter().copied().filter(|&v| t.neighbors(v).any(targets.taken_from(v))).collect();
        let mut near_s = vec![false; n];
        for v in near {
            near_s[v as usize] = true;
        }
        let in_parts =
            options.apply_parts > 1 && options.schedule == Schedule::LocalMinima && mesh.wedges.is_identity();
        let parts =
            in_parts.then(|| Parts::new(t, options.apply_parts)).filter(|p| p.inner_share(t) >= MIN_INNER_SHARE);
        Self {
            frustums,
            eyes: views.iter().map(|v| v.viewpoint()).collect(),
            options,
            normals,
            errors,
            in_r,
            ignored: vec![false; n],
            blocked_before: vec![false; n],
            stuck_before: vec![false; n],
            stays,
            floors,
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
        let eyes = &self.eyes[..];
        let m: &Mesh = mesh;
        let (cand, stays) = (&self.cand, Stays { class: &self.stays, floors: Some(&self.floors) });
        // `ids`: the actors, each with its selection; `all` keeps the candidates only where
        // they are more than the actors (to clear their flags at the end).
        let (ids, choices, all): (Vec<u32>, Vec<Selection>, Vec<u32>) = match self.options.schedule {
            Schedule::AllCandidates => {
                let choices = map_sized(&all, PARALLEL_MIN, SELECT_TASK, |sc: &mut SelectScratch, &v| {
                    select_on_mesh_with(sc, m, v, cand, stays, eyes)
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
                        (b == INVALID).then(|| (v, select_on_mesh_with(sc, m, v, NOBODY_ELSE, stays, eyes)))
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
        // (RoundTouches::gained; unless the target is in R): the same maximum over the same
        // neighbours as a walk. Any
        // other vertex walks its fan. (A vertex reclassified into S makes its neighbours
        // forget their metrics.)
        let threshold = self.options.reclassify_threshold.unwrap_or(2.0 * self.options.classify.threshold);
        let (in_r, normals, touches, stay_max) = (&self.in_r, &self.normals, &self.touches, &self.stay_max);
        // Each vertex's metric is kept where it is worked out (relaxed, as the blockers: each
        // vertex reads and writes only its own); the pass returns the vertices that go to S.
        let reclassified: Vec<u32> = filter_map_sized(&touched, PARALLEL_MIN, TASK, |_: &mut (), &w| {
            let u = w as usize;
            let known = f32::from_bits(stay_max[u].load(Relaxed));
            let e = match touches.gained(w) {
                Gained::Nothing if !known.is_nan() => known,
                // A target still in R (an anchor taking a finer removal, `select::Stays`) is
                // no stayer: the metric does not count it.
                Gained::One(v) if !known.is_nan() && in_r[v as usize] => known,
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
            let px = screen_error_views(&self.frustums, mesh.positions[u], normals[u], e, &self.options.classify);
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
