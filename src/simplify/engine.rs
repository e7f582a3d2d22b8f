//! What both selection strategies share: evaluating a vertex's best half-edge collapse and
//! applying one.
//!
//! A vertex u may collapse into a neighbour v when
//! * the connectivity allows it ([`HalfEdges::collapse_is_legal`]: link condition, borders),
//! * u is not a *corner*: counting u's constrained edges (border, UV/normal seam, or between
//!   two primitives), u is free with none, may slide along one of them with exactly two,
//!   moves along the others with exactly one (a seam's end), and stays put otherwise
//!   (seam/border junctions, corners where primitives meet);
//!   a border vertex where the border turns by more than 30° (85° under the quadric cost,
//!   whose border planes price the turn) stays too ([`crate::mesh::constraints`]);
//! * its attribute wedges carry over: each wedge of u maps to one wedge of v through the
//!   faces on edge (u, v);
//! * no surviving face turns over: its normal after · before must stay positive, and it may
//!   not turn more than about 78° from its normal in the input ([`MIN_NORMAL_DOT`]);
//! * the quadric error √(Q/W) stays within the error bound.
//!
//! Among the allowed targets the lowest cost wins (ties: the smaller vertex id), so results
//! do not depend on traversal order.

use glam::DVec3;

use super::attribute_quadric::AttributeQuadrics;
use super::dihedral_cost::{dihedral_cost_with, unit_normal};
use super::quadric::Quadric;
use super::Cost;
use crate::mesh::{constraints, Mesh};
use crate::topology::{vflag, HalfEdgeCollapse, HalfEdges, Topology, INVALID};

/// A face may turn at most this far from its input normal (cosine; 0.2 ≈ 78°). Zero would
/// allow slivers standing edge-on to the surface; small turns could otherwise add up.
pub const MIN_NORMAL_DOT: f64 = 0.2;

/// A vertex's chosen collapse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Best {
    pub collapse: HalfEdgeCollapse,
    pub target: u32,
    pub cost: f64,
    pub error: f64,
}

pub(crate) struct Engine<'m> {
    pub mesh: &'m mut Mesh,
    pub cost: Cost,
    pub quadrics: Vec<Quadric>,
    pub error_bound: f64,
    pub live_faces: usize,
    pub max_error: f64,
    /// Unit normal of each face slot in the input: no collapse may turn a face against it.
    pub(super) normal0: Vec<DVec3>,
    /// Interior vertices with no constrained edge (border, seam, between primitives) in the
    /// input: they may move along any edge, so [`constraints::movable_targets`] need not look
    /// at their edges. Stays true through every collapse but into it from a vertex that is
    /// not free (see [`free_vertices`]).
    pub(super) free: Vec<bool>,
    /// Per-wedge attribute quadrics, when attributes are weighted (quadric cost only): they
    /// add to every collapse's cost ([`AttributeQuadrics::cost`]).
    pub(super) attributes: Option<AttributeQuadrics>,
    scratch: Scratch,
}

/// Buffers reused by every evaluation (no allocation in the loop).
#[derive(Default)]
pub(crate) struct Scratch {
    fan: Vec<u32>,
    normals: Vec<[f64; 3]>,
    cands: Vec<(u32, u32)>,            // (half-edge, target) allowed by the constraints
    scored: Vec<(f64, u32, u32, f64)>, // (cost, target, half-edge, error)
}

impl<'m> Engine<'m> {
    /// An engine over `mesh`; `attributes` (built by the caller from the same mesh) add to
    /// the quadric cost.
    pub fn new(mesh: &'m mut Mesh, cost: Cost, error_bound: f64, attributes: Option<AttributeQuadrics>) -> Self {
        let live_faces = mesh.topology.live_face_count();
        // Three independent passes over the input, side by side (each is serial and
        // deterministic on its own, so the results do not depend on the threads).
        let m: &Mesh = mesh;
        let ((quadrics, normal0), free) =
            rayon::join(|| rayon::join(|| initial_quadrics(m), || input_normals(m)), || free_vertices(m));
        Self {
            mesh,
            cost,
            quadrics,
            error_bound,
            live_faces,
            max_error: 0.0,
            normal0,
            free,
            attributes: attributes.filter(|_| cost == Cost::Quadric),
            scratch: Scratch::default(),
        }
    }

    fn pos(&self, v: u32) -> DVec3 {
        DVec3::from(self.mesh.positions[v as usize].map(f64::from))
    }

    /// The border corner angle for this engine's cost (see [`constraints`]).
    fn corner_degrees(&self) -> f64 {
        match self.cost {
            Cost::Quadric => constraints::QUADRIC_BORDER_CORNER_DEGREES,
            Cost::Dihedral => constraints::BORDER_CORNER_DEGREES,
        }
    }

    /// The best allowed collapse of `u`, if any.
    pub fn evaluate(&mut self, u: u32) -> Option<Best> {
        let mut sc = std::mem::take(&mut self.scratch);
        let best = self.evaluate_with(u, &mut sc);
        self.scratch = sc;
        best
    }

    /// A lower bound on [`Engine::evaluate`]'s cost for `u`: the cheapest target its
    /// constraints and the error bound allow, before the (costlier) link, wedge and flip
    /// checks, with that target. `None` exactly when `evaluate` would find no target to check
    /// at all.
    pub fn bound(&self, u: u32, sc: &mut Scratch) -> Option<Bound> {
        self.scored(u, sc);
        // Ties as `evaluate` orders them (then by target id), so the bound's target is the
        // first target `evaluate` checks.
        sc.scored
            .iter()
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|s| Bound { cost: s.0, target: s.1 })
    }

    /// Whether a [`Change::TargetOnly`] vertex `w` needs a fresh bound after a collapse into
    /// `v`. Only its cost into v, and whether the error bound lets it into v, can have
    /// changed: v's quadric grew by u's.
    /// * Quadric cost: mathematically the cost into v only rises, so the bound stands unless v
    ///   was the cheapest target; in floating point the grown sum can come out a rounding
    ///   error lower (flat regions, costs near 0), so v's new cost, computed exactly as
    ///   [`Engine::bound`] does, must not undercut the bound either.
    /// * Dihedral cost: nothing it reads changed. Only an error bound can matter: the RMS
    ///   distance √(Q/W) into v can fall as well as rise (W grew too), so v may newly pass.
    ///
    /// With that, the bound kept is the one a fresh evaluation would give, bit for bit.
    pub fn target_only_needs_bound(&self, w: u32, bound: Option<Bound>, v: u32) -> bool {
        self.target_only_needs_bound_with(bound, v, || self.target_cost(w, v))
    }

    /// [`Engine::target_only_needs_bound`] with w's collapse into v given (worked out only if
    /// needed).
    fn target_only_needs_bound_with(&self, bound: Option<Bound>, v: u32, cost_v: impl FnOnce() -> TargetCost) -> bool {
        let Some(b) = bound else { return false };
        match self.cost {
            Cost::Quadric => b.target == v || Bound { cost: cost_v().cost, target: v }.before(&b),
            Cost::Dihedral => self.error_bound.is_finite() && (b.target == v || self.may_gain_target(cost_v)),
        }
    }

    /// The new bound of a [`Change::Faces`] vertex `w` other than the target, where it can be
    /// had without walking w's fan: under the quadric cost, for a free vertex (no constraint
    /// can have changed: [`free_vertices`]) whose cheapest target was neither u nor v. Its
    /// targets lost u and (unless a wing) gained v; every other target's cost reads Q_w and
    /// Q_x, unchanged; so the cheapest is the old bound or v's new cost, whichever is lower
    /// (the same sums [`Engine::bound`] does, so the same bits). `None`: recompute.
    pub fn faces_changed_bound(&self, w: u32, old: Option<Bound>, u: u32, v: u32) -> Option<Bound> {
        self.faces_changed_bound_with(w, old, u, v, || self.target_cost(w, v))
    }

    /// [`Engine::faces_changed_bound`] with w's collapse into v given (worked out only if
    /// needed).
    fn faces_changed_bound_with(
        &self,
        w: u32,
        old: Option<Bound>,
        u: u32,
        v: u32,
        cost_v: impl FnOnce() -> TargetCost,
    ) -> Option<Bound> {
        let b = old?;
        if self.cost != Cost::Quadric || !self.free[w as usize] || b.target == u || b.target == v {
            return None;
        }
        let c = cost_v();
        if self.error_bound.is_finite() && c.distance > self.error_bound {
            return Some(b);
        }
        let fresh = Bound { cost: c.cost, target: v };
        Some(if fresh.before(&b) { fresh } else { b })
    }

    /// Whether a [`Change::TargetOnly`] vertex w with no allowed collapse may have gained
    /// one into v (`cost_v`: w's collapse into v): only where the error bound kept it out of
    /// v, which the RMS distance into v may now pass. Otherwise nothing it could collapse along got any easier (see
    /// [`Change`]).
    fn may_gain_target(&self, cost_v: impl FnOnce() -> TargetCost) -> bool {
        self.error_bound.is_finite() && cost_v().distance <= self.error_bound
    }

    /// What the bound rules read of w's collapse into `v`: the cost and, under an error
    /// bound, the RMS distance, from Q_w + Q_v as [`Engine::bound`] sums them. Pure.
    pub(crate) fn target_cost(&self, w: u32, v: u32) -> TargetCost {
        self.target_cost_with(w, &self.quadrics[v as usize], v)
    }

    /// [`Engine::target_cost`] with `q_v` as v's quadric. With attributes weighted, the
    /// attribute part reads the wedges on edge (w, v) and v's attribute quadrics as they are
    /// now: call it on the state after the collapse (the batched passes, which cost ahead of
    /// their writes, take fresh bounds instead).
    pub(crate) fn target_cost_with(&self, w: u32, q_v: &Quadric, v: u32) -> TargetCost {
        let q = self.quadrics[w as usize] + *q_v;
        let pv = self.pos(v).to_array();
        let distance = if self.error_bound.is_finite() { q.distance(pv) } else { f64::NAN };
        // The edge is looked for only where the attribute part needs it.
        let edge = if self.attributes.is_some() { self.mesh.topology.find_edge(w, v) } else { None };
        let cost = match edge {
            Some(he) => self.quadric_cost(&q, pv, HalfEdgeCollapse { he, remove: w }, v),
            None => q.eval(pv),
        };
        TargetCost { cost, distance }
    }

    /// The quadric cost of collapse `c` into `v` at `pv` with `q` = Q_u + Q_v: Q(pv), plus
    /// W·ΣA with attributes weighted (simplify/attribute_quadric.rs). The one formula both
    /// [`Engine::bound`] and the bound rules use, so they agree bit for bit.
    #[inline]
    fn quadric_cost(&self, q: &Quadric, pv: [f64; 3], c: HalfEdgeCollapse, v: u32) -> f64 {
        match &self.attributes {
            Some(a) => q.eval(pv) + q.weight() * a.cost(self.mesh, c, v),
            None => q.eval(pv),
        }
    }

    /// What a vertex `w` touched by the collapse of `removed` into `target` needs, by the
    /// rules of [`Change`], given its bound, whether it is still in the running (has a
    /// collapse in view; one that is not has no allowed collapse) and its collapse into the
    /// target (`cost_v`: [`Engine::target_cost`], called only if needed). Shared by the greedy
    /// queue and the batched passes; test builds check each answer against a fresh
    /// evaluation (`Engine::assert_bound_update`). Past `cost_v` it reads only the `free`
    /// flags and the bound, never the connectivity, so it gives the same answer on any state
    /// in which w's and the target's quadrics are the same (simplify/batched.rs applies a
    /// whole pass first and then runs the rules in collapse order).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(crate) fn bound_rule(
        &self,
        w: u32,
        change: Change,
        bound: Option<Bound>,
        in_running: bool,
        removed: u32,
        target: u32,
        cost_v: impl FnOnce() -> TargetCost,
    ) -> BoundUpdate {
        match change {
            Change::Faces if w != target => self
                .faces_changed_bound_with(w, bound, removed, target, cost_v)
                .map_or(BoundUpdate::Fresh, |b| BoundUpdate::New(Some(b))),
            Change::Faces => BoundUpdate::Fresh,
            // Out of the running stays out: nothing w could collapse along got easier, unless
            // an error bound it may now pass into v. Its bound is not kept up to date: forget it.
            Change::TargetOnly if !in_running => {
                if self.may_gain_target(cost_v) {
                    BoundUpdate::Fresh
                } else {
                    BoundUpdate::New(None)
                }
            }
            Change::TargetOnly if self.target_only_needs_bound_with(bound, target, cost_v) => BoundUpdate::Fresh,
            Change::TargetOnly => BoundUpdate::Keep,
        }
    }

    /// Test builds: what [`Engine::bound_rule`] kept or derived for `w` is what a fresh
    /// evaluation gives on the current state.
    #[cfg(test)]
    pub(crate) fn assert_bound_update(&self, w: u32, update: BoundUpdate, bound: Option<Bound>) {
        let mut sc = Scratch::default();
        match update {
            BoundUpdate::New(Some(b)) => assert_same_bound(b, self.bound(w, &mut sc), w),
            BoundUpdate::New(None) => assert!(self.evaluate_with(w, &mut sc).is_none(), "vertex {w} gained a collapse"),
            BoundUpdate::Keep => assert_eq!(bound, self.bound(w, &mut sc), "vertex {w} kept a stale bound"),
            BoundUpdate::Fresh => {}
        }
    }

    /// Q_w + Q_v, summed as [`Engine::bound`] sums it.
    fn merged(&self, w: u32, v: u32) -> Quadric {
        self.quadrics[w as usize] + self.quadrics[v as usize]
    }

    /// Every vertex's [`Engine::bound`], computed in parallel (each is a pure function of the
    /// mesh, so the result does not depend on the thread count).
    pub fn initial_bounds(&self) -> Vec<Option<Bound>> {
        use rayon::prelude::*;
        let n = self.mesh.topology.vertex_count() as u32;
        (0..n).into_par_iter().map_init(Scratch::default, |sc, v| self.bound(v, sc)).collect()
    }

    /// Fills `sc.scored` with u's allowed targets and their costs, unsorted.
    fn scored(&self, u: u32, sc: &mut Scratch) {
        sc.scored.clear();
        let t = &self.mesh.topology;
        if t.vflags[u as usize] & (vflag::REMOVED | vflag::LOCKED) != 0 {
            return;
        }
        sc.fan.clear();
        sc.fan.extend(t.outgoing(u));
        if self.free[u as usize] && sc.fan.len() <= constraints::MAX_MOVABLE_VALENCE {
            sc.cands.clear();
            sc.cands.extend(sc.fan.iter().map(|&g| (g, t.dest(g))));
            #[cfg(test)]
            {
                let mut full = Vec::new();
                constraints::movable_targets(self.mesh, u, &sc.fan, self.corner_degrees(), &mut full);
                assert_eq!(full, sc.cands, "free vertex {u} is no longer free");
            }
        } else {
            constraints::movable_targets(self.mesh, u, &sc.fan, self.corner_degrees(), &mut sc.cands);
        }
        if sc.cands.is_empty() {
            return;
        }
        if self.cost == Cost::Dihedral {
            sc.normals.clear();
            sc.normals.extend(sc.fan.iter().map(|&g| unit_normal(&self.mesh.positions, t.faces[(g / 3) as usize])));
        }
        let qu = self.quadrics[u as usize];
        for &(g, v) in &sc.cands {
            let q = qu + self.quadrics[v as usize];
            let pv = self.pos(v).to_array();
            // The error is only needed against a bound here; the winner's is computed later.
            let error = if self.error_bound.is_finite() { q.distance(pv) } else { 0.0 };
            if error > self.error_bound {
                continue;
            }
            let cost = match self.cost {
                Cost::Quadric => self.quadric_cost(&q, pv, HalfEdgeCollapse { he: g, remove: u }, v),
                Cost::Dihedral => {
                    let (hu, hv) = constraints::halves(t, HalfEdgeCollapse { he: g, remove: u });
                    dihedral_cost_with(t, &self.mesh.positions, &sc.fan, &sc.normals, u, v, hu, hv)
                }
            };
            sc.scored.push((cost, v, g, error));
        }
    }

    pub(crate) fn evaluate_with(&self, u: u32, sc: &mut Scratch) -> Option<Best> {
        // Cost first (cheap), then the checks in order of cost until one passes: most
        // vertices need only one or two full checks.
        self.scored(u, sc);
        sc.scored.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for &(cost, v, g, error) in &sc.scored {
            let c = HalfEdgeCollapse { he: g, remove: u };
            if !self.allowed(&sc.fan, c, v) {
                continue;
            }
            let error =
                if self.error_bound.is_finite() { error } else { self.merged(u, v).distance(self.pos(v).to_array()) };
            return Some(Best { collapse: c, target: v, cost, error });
        }
        None
    }

    /// The checks after the cost, for collapse `c` of u (fan `fan`) into `v`: the link
    /// condition, the wedges, and no face turned over or too far.
    fn allowed(&self, fan: &[u32], c: HalfEdgeCollapse, v: u32) -> bool {
        let t = &self.mesh.topology;
        if t.collapse_is_legal(c).is_err() {
            return false;
        }
        let (hu, hv) = constraints::halves(t, c);
        constraints::wedges_carry_over(self.mesh, fan, hu, hv) && !self.flips(fan, c.remove, v, hu, hv)
    }

    /// [`Engine::evaluate`]'s answer, checking first the target of `u`'s current bound `b`
    /// alone — the common case: `b` is the first entry of `evaluate`'s order, so when that
    /// target passes (and only one half-edge leads to it) `evaluate` would return exactly it,
    /// without costing and sorting u's other targets. Otherwise (or without a bound) the full
    /// evaluation.
    pub fn evaluate_from_bound(&mut self, u: u32, b: Option<Bound>) -> Option<Best> {
        let mut sc = std::mem::take(&mut self.scratch);
        let best = self.check_from_bound(u, b, &mut sc);
        self.scratch = sc;
        best
    }

    /// [`Engine::evaluate_from_bound`] on a shared engine with the caller's buffers (the
    /// batched passes check their picks in parallel).
    pub(crate) fn check_from_bound(&self, u: u32, b: Option<Bound>, sc: &mut Scratch) -> Option<Best> {
        let quick = b.and_then(|b| self.evaluate_bound_with(u, b, sc));
        #[cfg(test)]
        if quick.is_some() {
            assert_eq!(quick, self.evaluate_with(u, sc), "vertex {u}: the bound's own check differs");
        }
        quick.or_else(|| self.evaluate_with(u, sc))
    }

    fn evaluate_bound_with(&self, u: u32, b: Bound, sc: &mut Scratch) -> Option<Best> {
        let t = &self.mesh.topology;
        sc.fan.clear();
        sc.fan.extend(t.outgoing(u));
        // The half-edge to the target, as `scored` lists it: outgoing, or on a border also
        // the incoming border half-edge.
        let mut to = sc.fan.iter().copied().filter(|&g| t.dest(g) == b.target);
        let mut g = to.next();
        let mut more = to.next().is_some();
        if t.is_boundary_vertex(u) {
            let inc = sc.fan.last().map(|&last| Topology::prev(last));
            if let Some(inc) = inc.filter(|&inc| t.origin(inc) == b.target) {
                more |= g.is_some();
                g = Some(inc);
            }
        }
        let c = HalfEdgeCollapse { he: g.filter(|_| !more)?, remove: u };
        if !self.allowed(&sc.fan, c, b.target) {
            return None;
        }
        let error = self.merged(u, b.target).distance(self.pos(b.target).to_array());
        Some(Best { collapse: c, target: b.target, cost: b.cost, error })
    }

    /// Whether moving u onto v turns any surviving face of u over (or flat), against its
    /// current normal or against its normal in the input (so small turns cannot add up).
    fn flips(&self, fan: &[u32], u: u32, v: u32, hu: u32, hv: u32) -> bool {
        constraints::moved_faces(self.mesh, fan, u, v, (hu, hv)).any(|m| {
            m.before.dot(m.after) <= 0.0
                || self.normal0[m.face as usize].dot(m.after) < MIN_NORMAL_DOT * m.after.length()
        })
    }

    /// Applies a collapse chosen by [`Engine::evaluate`]; fills `out` with the vertices whose
    /// best collapse may have changed (the target and its new neighbours), split by how much
    /// may have changed for them.
    pub fn apply(&mut self, b: Best, out: &mut Touched) {
        let u = b.collapse.remove;
        let v = b.target;
        out.removed = u;
        out.around_u.clear();
        out.around_u.extend(self.mesh.topology.neighbors(u));
        let q = self.quadrics[u as usize];
        self.quadrics[v as usize] += q;
        self.free[v as usize] &= self.free[u as usize];
        if let Some(a) = &mut self.attributes {
            let (pairs, n) = AttributeQuadrics::merges(self.mesh, b.collapse, v);
            a.merge(&pairs[..n]);
        }
        let removed = constraints::collapse_with_wedges(self.mesh, b.collapse);
        self.live_faces -= removed.iter().filter(|&&f| f != INVALID).count();
        self.max_error = self.max_error.max(b.error);
        out.vertices.clear();
        out.vertices.push((v, Change::Faces));
        for w in self.mesh.topology.neighbors(v) {
            let change = if out.around_u.contains(&w) { Change::Faces } else { Change::TargetOnly };
            out.vertices.push((w, change));
        }
    }
}

impl Engine<'_> {
    /// Why each live vertex can or cannot collapse now (see [`super::Remaining`]).
    pub fn remaining(&mut self) -> super::Remaining {
        let bound = self.error_bound;
        let mut sc = Scratch::default();
        let mut r = super::Remaining::default();
        for v in 0..self.mesh.topology.vertex_count() as u32 {
            let flags = self.mesh.topology.vflags[v as usize];
            if flags & vflag::REMOVED != 0 || self.mesh.topology.vertex_he[v as usize] == INVALID {
                continue;
            }
            r.vertices += 1;
            self.error_bound = f64::INFINITY;
            if flags & vflag::LOCKED != 0 {
                r.locked += 1;
            } else if self.bound(v, &mut sc).is_none() {
                r.fixed += 1;
            } else if self.evaluate(v).is_none() {
                r.blocked += 1;
            } else {
                self.error_bound = bound;
                if self.evaluate(v).is_none() {
                    r.over_error += 1;
                } else {
                    r.movable += 1;
                }
            }
        }
        self.error_bound = bound;
        r
    }
}

/// Test builds: a bound worked out without the fan walk is the one a fresh evaluation gives.
#[cfg(test)]
pub(crate) fn assert_same_bound(quick: Bound, fresh: Option<Bound>, w: u32) {
    assert_eq!(Some(quick), fresh, "vertex {w}: quick bound differs");
}

/// What [`Engine::bound_rule`] found for a touched vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum BoundUpdate {
    /// Its bound stands.
    Keep,
    /// Its bound is this, found without a fan walk (`None`: it has no allowed collapse).
    New(Option<Bound>),
    /// It needs a fresh [`Engine::bound`].
    Fresh,
}

/// A vertex w's collapse into a target v as the bound rules read it ([`Engine::target_cost`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TargetCost {
    /// The quadric cost Q(v) with Q = Q_w + Q_v.
    pub cost: f64,
    /// The RMS distance √(Q/W) at v; NaN (never read) without an error bound.
    pub distance: f64,
}

/// A vertex's [`Engine::bound`]: the cheapest cost before the full checks, and its target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bound {
    pub cost: f64,
    pub target: u32,
}

impl Bound {
    /// Whether `self` comes before `o` in `evaluate`'s order (cost, then target id).
    pub fn before(&self, o: &Bound) -> bool {
        self.cost.total_cmp(&o.cost).then(self.target.cmp(&o.target)).is_lt()
    }
}

/// The vertices a collapse u → v touched ([`Engine::apply`]): v, then its neighbours in fan
/// order, each with what may have changed for it.
#[derive(Default)]
pub(crate) struct Touched {
    pub vertices: Vec<(u32, Change)>,
    /// The removed vertex u.
    pub removed: u32,
    around_u: Vec<u32>,
}

/// What a collapse u → v may have changed for a vertex it touched.
///
/// ```text
///   Faces:       v and u's former neighbours — their faces changed, so may any cost
///   TargetOnly:  v's other neighbours — faces, positions, corners and targets as before;
///                only v's quadric grew (their cost into v), and a link with v may now fail
/// ```
/// A target-only vertex cannot gain a collapse except past an error bound (its targets,
/// faces, corners and normals are the same, its cost into v does not fall, and a link
/// condition can only start failing: v gained neighbours and lost only u, which was not one of
/// theirs; [`Engine::may_gain_target`]), and its bound stands unless v was its cheapest target
/// or v's new cost undercuts it ([`Engine::target_only_needs_bound`]); only a collapse
/// already checked is stale. In test builds the loops assert both for every vertex they skip.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Change {
    Faces,
    TargetOnly,
}

/// Unit normal of each face slot (zero for a dead or degenerate one).
fn input_normals(mesh: &Mesh) -> Vec<DVec3> {
    let p = |v: u32| DVec3::from(mesh.positions[v as usize].map(f64::from));
    let normal = |f: &[u32; 3]| {
        if f[0] == INVALID {
            return DVec3::ZERO;
        }
        let [a, b, c] = f.map(p);
        (b - a).cross(c - a).normalize_or_zero()
    };
    mesh.topology.faces.iter().map(normal).collect()
}

/// Which vertices are free: interior, with no constrained edge. A collapse u → v keeps a
/// free vertex free, except v when u was not free (a seam end moving in hands v its seam
/// edge: [`Engine::apply`] clears v's flag then): it makes no border edge (link condition),
/// and an edge it rewires or merges joins faces whose corners at each end were equal (both
/// edges unconstrained) and map to one wedge (the wedge map is a function), in one
/// primitive. Test builds check every use.
fn free_vertices(mesh: &Mesh) -> Vec<bool> {
    let t = &mesh.topology;
    let mut free: Vec<bool> = (0..t.vertex_count() as u32).map(|v| !t.is_boundary_vertex(v)).collect();
    for (fi, f) in t.faces.iter().enumerate() {
        if f[0] == INVALID {
            continue;
        }
        for k in 0..3 {
            let h = (3 * fi + k) as u32;
            if constraints::edge_constrained(mesh, h) {
                free[t.origin(h) as usize] = false;
                free[t.dest(h) as usize] = false;
            }
        }
    }
    free
}

/// How much a seam edge's perpendicular plane weighs on each of its two sides, against 1
/// for a border edge's one (so a seam edge weighs as much as a border edge in all). The
/// planes keep a seam's line where it was, and with it the texture layout along it, as
/// meshoptimizer's seam edge quadrics do. On Duck.glb (`qem`, `compare`'s TEXCOORD_0 RMS at
/// 50 / 25 / 10 %): 0.022 / 0.050 / 0.109 without them, 0.0059 / 0.021 / 0.069 with them
/// (meshopt 0.0065 / 0.034 / 0.076), for 2–8 % more geometric RMS; 0.25 kept the
/// geometry closer (0–3 %) and the UVs less (0.0059 / 0.023 / 0.082), 1 the reverse.
pub(crate) const SEAM_PLANE_WEIGHT: f64 = 0.5;

/// Area-weighted face-plane quadrics per vertex, plus perpendicular planes along borders and
/// seams.
fn initial_quadrics(mesh: &Mesh) -> Vec<Quadric> {
    let t = &mesh.topology;
    let p = |v: u32| DVec3::from(mesh.positions[v as usize].map(f64::from));
    let mut q = vec![Quadric::default(); t.vertex_count()];
    for (fi, f) in t.faces.iter().enumerate() {
        if f[0] == INVALID {
            continue;
        }
        let [a, b, c] = f.map(p);
        let n = (b - a).cross(c - a);
        let len = n.length();
        if len == 0.0 {
            continue;
        }
        let unit = n / len;
        let plane = Quadric::plane(unit.to_array(), -unit.dot(a), 0.5 * len);
        for &v in f {
            q[v as usize] += plane;
        }
        for k in 0..3 {
            let h = (3 * fi + k) as u32;
            let border = t.twin[h as usize] == INVALID;
            if !border && !constraints::edge_constrained(mesh, h) {
                continue;
            }
            // Border or seam edge: a plane through it, perpendicular to the face, weighted by
            // length² (a seam's two sides by SEAM_PLANE_WEIGHT each).
            let (e0, e1) = (p(t.origin(h)), p(t.dest(h)));
            let e = e1 - e0;
            let m = e.cross(unit);
            let ml = m.length();
            if ml == 0.0 {
                continue;
            }
            let mu = m / ml;
            let bp =
                Quadric::plane(mu.to_array(), -mu.dot(e0), e.dot(e) * if border { 1.0 } else { SEAM_PLANE_WEIGHT });
            q[t.origin(h) as usize] += bp;
            q[t.dest(h) as usize] += bp;
        }
    }
    q
}
