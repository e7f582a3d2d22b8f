//! What both selection strategies share: evaluating a vertex's best half-edge collapse and
//! applying one.
//!
//! A vertex u may collapse into a neighbour v when
//! * the connectivity allows it ([`Topology::collapse_is_legal`]: link condition, borders),
//! * u is not a *corner*: counting u's constrained edges (border, UV/normal seam, or between
//!   two primitives), u is free with none, may slide along one of them with exactly two, and
//!   stays put otherwise (seam ends, seam/border junctions, corners where primitives meet);
//!   a border vertex where the border turns by more than [`BORDER_CORNER_DEGREES`] stays too;
//! * its attribute wedges carry over: each wedge of u maps to one wedge of v through the
//!   faces on edge (u, v);
//! * no surviving face turns over: its normal after · before must stay positive, and it may
//!   not turn more than about 78° from its normal in the input ([`MIN_NORMAL_DOT`]);
//! * the quadric error √(Q/W) stays within the error bound.
//!
//! Among the allowed targets the lowest cost wins (ties: the smaller vertex id), so results
//! do not depend on traversal order.

use super::dihedral_cost::{dihedral_cost_with, unit_normal};
use super::quadric::Quadric;
use super::Cost;
use crate::mesh::Mesh;
use crate::topology::{vflag, HalfEdgeCollapse, Topology, INVALID};

/// A border vertex whose border turns by more than this many degrees is a corner and stays.
pub const BORDER_CORNER_DEGREES: f64 = 30.0;

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
    normal0: Vec<[f64; 3]>,
    scratch: Scratch,
}

/// Buffers reused by every evaluation (no allocation in the loop).
#[derive(Default)]
struct Scratch {
    fan: Vec<u32>,
    normals: Vec<[f64; 3]>,
    cands: Vec<(u32, u32, bool)>,      // (half-edge, target, constrained)
    scored: Vec<(f64, u32, u32, f64)>, // (cost, target, half-edge, error)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl<'m> Engine<'m> {
    pub fn new(mesh: &'m mut Mesh, cost: Cost, error_bound: f64) -> Self {
        let quadrics = initial_quadrics(mesh);
        let live_faces = mesh.topology.live_face_count();
        let normal0 = mesh
            .topology
            .faces
            .iter()
            .map(|f| {
                if f[0] == INVALID {
                    return [0.0; 3];
                }
                let [a, b, c] = f.map(|v| mesh.positions[v as usize].map(f64::from));
                let n = cross(sub(b, a), sub(c, a));
                let l = dot(n, n).sqrt();
                if l > 0.0 {
                    n.map(|x| x / l)
                } else {
                    [0.0; 3]
                }
            })
            .collect();
        Self { mesh, cost, quadrics, error_bound, live_faces, max_error: 0.0, normal0, scratch: Scratch::default() }
    }

    fn pos(&self, v: u32) -> [f64; 3] {
        self.mesh.positions[v as usize].map(f64::from)
    }

    /// Whether the edge of half-edge `g` is a border, a seam, or between two primitives.
    fn constrained(&self, g: u32) -> bool {
        let t = &self.mesh.topology;
        let o = t.twin[g as usize];
        if o == INVALID {
            return true;
        }
        let c = &self.mesh.wedges.corner;
        c[g as usize] != c[Topology::next(o) as usize]
            || c[Topology::next(g) as usize] != c[o as usize]
            || self.mesh.face_primitive[(g / 3) as usize] != self.mesh.face_primitive[(o / 3) as usize]
    }

    /// The best allowed collapse of `u`, if any.
    pub fn evaluate(&mut self, u: u32) -> Option<Best> {
        let mut sc = std::mem::take(&mut self.scratch);
        let best = self.evaluate_with(u, &mut sc);
        self.scratch = sc;
        best
    }

    fn evaluate_with(&self, u: u32, sc: &mut Scratch) -> Option<Best> {
        let t = &self.mesh.topology;
        if t.vflags[u as usize] & (vflag::REMOVED | vflag::LOCKED) != 0 {
            return None;
        }
        sc.fan.clear();
        sc.fan.extend(t.outgoing(u));
        // Candidate edges: every outgoing half-edge, and on a border the incoming border one.
        sc.cands.clear();
        sc.cands.extend(sc.fan.iter().map(|&g| (g, t.dest(g), self.constrained(g))));
        let border = t.is_boundary_vertex(u);
        if border {
            let inc = Topology::prev(*sc.fan.last()?);
            sc.cands.push((inc, t.origin(inc), true));
        }
        let n_constrained = sc.cands.iter().filter(|c| c.2).count();
        if (n_constrained != 0 && n_constrained != 2) || (border && self.is_border_corner(u, &sc.cands)) {
            return None;
        }
        if self.cost == Cost::Dihedral {
            sc.normals.clear();
            sc.normals.extend(sc.fan.iter().map(|&g| unit_normal(&self.mesh.positions, t.faces[(g / 3) as usize])));
        }
        // Cost first (cheap), then the checks in order of cost until one passes: most
        // vertices need only one or two full checks.
        sc.scored.clear();
        let qu = self.quadrics[u as usize];
        for &(g, v, constrained) in &sc.cands {
            if n_constrained == 2 && !constrained {
                continue;
            }
            let q = qu + self.quadrics[v as usize];
            let pv = self.pos(v);
            // The error is only needed against a bound here; the winner's is computed below.
            let error = if self.error_bound.is_finite() { q.distance(pv) } else { 0.0 };
            if error > self.error_bound {
                continue;
            }
            let cost = match self.cost {
                Cost::Quadric => q.eval(pv),
                Cost::Dihedral => {
                    let (hu, hv) = self.halves(HalfEdgeCollapse { he: g, remove: u });
                    dihedral_cost_with(t, &self.mesh.positions, &sc.fan, &sc.normals, u, v, hu, hv)
                }
            };
            sc.scored.push((cost, v, g, error));
        }
        sc.scored.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for &(cost, v, g, error) in &sc.scored {
            let c = HalfEdgeCollapse { he: g, remove: u };
            if t.collapse_is_legal(c).is_err() {
                continue;
            }
            let (hu, hv) = self.halves(c);
            if !self.wedges_carry_over(&sc.fan, hu, hv) || self.flips(&sc.fan, u, v, hu, hv) {
                continue;
            }
            let error = if self.error_bound.is_finite() {
                error
            } else {
                (self.quadrics[u as usize] + self.quadrics[v as usize]).distance(self.pos(v))
            };
            return Some(Best { collapse: c, target: v, cost, error });
        }
        None
    }

    /// Whether border vertex `u` is a corner: its border turns by more than
    /// [`BORDER_CORNER_DEGREES`]. `cands` holds u's outgoing edges, then its incoming border one.
    fn is_border_corner(&self, u: u32, cands: &[(u32, u32, bool)]) -> bool {
        let (Some(&(_, next, _)), Some(&(_, prev, _))) = (cands.first(), cands.last()) else { return true };
        let (pu, pn, pp) = (self.pos(u), self.pos(next), self.pos(prev));
        let (a, b) = (sub(pu, pp), sub(pn, pu));
        let (la, lb) = (dot(a, a).sqrt(), dot(b, b).sqrt());
        if la == 0.0 || lb == 0.0 {
            return true;
        }
        dot(a, b) / (la * lb) < BORDER_CORNER_DEGREES.to_radians().cos()
    }

    /// (u→v, v→u) of a collapse, `INVALID` for a missing side.
    fn halves(&self, c: HalfEdgeCollapse) -> (u32, u32) {
        let t = &self.mesh.topology;
        let o = t.twin[c.he as usize];
        if t.origin(c.he) == c.remove {
            (c.he, o)
        } else {
            (o, c.he)
        }
    }

    /// The wedge map u → v through the faces on the edge: (u's wedge, v's wedge) per side.
    fn wedge_map(&self, hu: u32, hv: u32) -> [(u32, u32); 2] {
        let c = &self.mesh.wedges.corner;
        let side1 = if hu != INVALID { (c[hu as usize], c[Topology::next(hu) as usize]) } else { (INVALID, INVALID) };
        let side2 = if hv != INVALID { (c[Topology::next(hv) as usize], c[hv as usize]) } else { (INVALID, INVALID) };
        [side1, side2]
    }

    fn wedges_carry_over(&self, fan: &[u32], hu: u32, hv: u32) -> bool {
        let map = self.wedge_map(hu, hv);
        if map[0].0 == map[1].0 && map[0].1 != map[1].1 && map[0].0 != INVALID {
            return false; // one wedge of u would need two wedges of v
        }
        let c = &self.mesh.wedges.corner;
        fan.iter().all(|&g| map.iter().any(|&(from, _)| from == c[g as usize]))
    }

    /// Whether moving u onto v turns any surviving face of u over (or flat), against its
    /// current normal or against its normal in the input (so small turns cannot add up).
    fn flips(&self, fan: &[u32], u: u32, v: u32, hu: u32, hv: u32) -> bool {
        let t = &self.mesh.topology;
        let pv = self.pos(v);
        for &g in fan {
            if (hu != INVALID && g / 3 == hu / 3) || (hv != INVALID && g / 3 == hv / 3) {
                continue;
            }
            let f = t.faces[(g / 3) as usize];
            let [a, b, c] = f.map(|x| self.pos(x));
            let before = cross(sub(b, a), sub(c, a));
            let [a2, b2, c2] = f.map(|x| if x == u { pv } else { self.pos(x) });
            let after = cross(sub(b2, a2), sub(c2, a2));
            let la = dot(after, after).sqrt();
            if dot(before, after) <= 0.0 || dot(self.normal0[(g / 3) as usize], after) < MIN_NORMAL_DOT * la {
                return true;
            }
        }
        false
    }

    /// Applies a collapse chosen by [`Engine::evaluate`]; returns the vertices whose best
    /// collapse may have changed (the target and its new neighbours).
    pub fn apply(&mut self, b: Best, out_dirty: &mut Vec<u32>) {
        let u = b.collapse.remove;
        let v = b.target;
        let (hu, hv) = self.halves(b.collapse);
        let map = self.wedge_map(hu, hv);
        let fan: Vec<u32> = self.mesh.topology.outgoing(u).collect();
        for g in fan {
            let w = &mut self.mesh.wedges.corner[g as usize];
            if let Some(&(_, to)) = map.iter().find(|&&(from, _)| from == *w) {
                *w = to;
            }
        }
        let q = self.quadrics[u as usize];
        self.quadrics[v as usize] += q;
        let removed = self.mesh.topology.collapse(b.collapse);
        self.live_faces -= removed.iter().filter(|&&f| f != INVALID).count();
        self.max_error = self.max_error.max(b.error);
        out_dirty.clear();
        out_dirty.push(v);
        out_dirty.extend(self.mesh.topology.neighbors(v));
    }
}

/// Area-weighted face-plane quadrics per vertex, plus perpendicular planes along borders.
fn initial_quadrics(mesh: &Mesh) -> Vec<Quadric> {
    let t = &mesh.topology;
    let p = |v: u32| mesh.positions[v as usize].map(f64::from);
    let mut q = vec![Quadric::default(); t.vertex_count()];
    for (fi, f) in t.faces.iter().enumerate() {
        if f[0] == INVALID {
            continue;
        }
        let [a, b, c] = f.map(p);
        let n = cross(sub(b, a), sub(c, a));
        let len = dot(n, n).sqrt();
        if len == 0.0 {
            continue;
        }
        let unit = n.map(|x| x / len);
        let plane = Quadric::plane(unit, -dot(unit, a), 0.5 * len);
        for &v in f {
            q[v as usize] += plane;
        }
        for k in 0..3 {
            let h = (3 * fi + k) as u32;
            if t.twin[h as usize] != INVALID {
                continue;
            }
            // Border edge: a plane through it, perpendicular to the face, weighted by length².
            let (e0, e1) = (p(t.origin(h)), p(t.dest(h)));
            let e = sub(e1, e0);
            let m = cross(e, unit);
            let ml = dot(m, m).sqrt();
            if ml == 0.0 {
                continue;
            }
            let mu = m.map(|x| x / ml);
            let bp = Quadric::plane(mu, -dot(mu, e0), dot(e, e));
            q[t.origin(h) as usize] += bp;
            q[t.dest(h) as usize] += bp;
        }
    }
    q
}
