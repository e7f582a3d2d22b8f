//! The rules every collapse of the flat passes obeys, read from the flat mesh: the same rules,
//! in the same order of cost, as the half-edge engines' (engine.rs): constraints (borders,
//! seams, primitives, corners, locked vertices), the link condition, wedges, no face turned
//! over or too far from its input normal, the error bound.

use glam::DVec3;

use super::attributes::Attributes;
use super::faces::{Corner, Fan, FlatFaces};
use crate::mesh::constraints::{is_border_corner, MAX_MOVABLE_VALENCE, QUADRIC_BORDER_CORNER_DEGREES};
use crate::mesh::Mesh;
use crate::simplify::engine::MIN_NORMAL_DOT;
use crate::simplify::Quadric;
use crate::topology::{vflag, INVALID, MAX_LINK_VALENCE};

/// Buffers one thread reuses.
#[derive(Debug, Default)]
pub(super) struct Scratch {
    pub fan: Fan,
    /// The target's neighbours, as the last [`Rules::passes`] that got as far as the link
    /// condition read them.
    pub target_ring: Vec<u32>,
    pub allowed: Vec<u32>,
    /// Allowed targets within the error bound, with their cost.
    scored: Vec<(f64, u32)>,
}

/// What the rules read: the mesh as it was handed in (positions, flags, primitives), the flat
/// faces as they are now, and the engine's quadrics and input normals.
pub(super) struct Rules<'a> {
    pub mesh: &'a Mesh,
    pub flat: &'a FlatFaces,
    pub quadrics: &'a [Quadric],
    /// Per vertex, Q_v(v) and the weight of Q_v ([`own_costs`]): (Q_u + Q_v)(v) is
    /// Q_u(v) + Q_v(v), so ranking u's targets reads only u's quadric.
    pub own: &'a [(f64, f64)],
    pub normal0: &'a [DVec3],
    pub free: &'a [bool],
    pub error_bound: f64,
    /// [`crate::mesh::constraints::plain_attributes`]: no edge is a seam or between primitives.
    pub plain: bool,
    /// The wedges' attribute quadrics, when attributes are weighted: a collapse u → v then
    /// costs (Q_u + Q_v)(v) + W·ΣA as in the half-edge engines (engine.rs), with ΣA over the
    /// wedge pairs of the faces on the edge (simplify/attribute_quadric.rs). They are summed
    /// after each pass's walk, as the quadrics are.
    pub attributes: Option<&'a Attributes>,
}

/// The order of (cost, target) candidates: the lower cost, ties to the smaller vertex id.
/// [`Rules::bound`] and [`Rules::evaluate`] rank by it alike.
fn cheaper(a: &(f64, u32), b: &(f64, u32)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

impl Rules<'_> {
    fn border(&self, v: u32) -> bool {
        self.mesh.topology.vflags[v as usize] & vflag::BOUNDARY != 0
    }

    fn pos(&self, v: u32) -> DVec3 {
        DVec3::from(self.mesh.positions[v as usize].map(f64::from))
    }

    /// Whether u may move at all: not locked, not removed.
    fn movable(&self, u: u32) -> bool {
        self.mesh.topology.vflags[u as usize] & vflag::LOCKED == 0 && self.flat.count(u) > 0
    }

    /// Reads u's fan into `sc.fan` and its allowed targets into `sc.allowed`, as
    /// [`crate::mesh::constraints::movable_targets`] allows them (none for a locked or
    /// removed vertex).
    pub fn targets(&self, u: u32, sc: &mut Scratch) {
        sc.allowed.clear();
        sc.fan.corners.clear();
        sc.fan.ring.clear();
        if !self.movable(u) {
            return;
        }
        let border = self.border(u);
        self.flat.fan(u, border, &mut sc.fan);
        let ring = &sc.fan.ring;
        if ring.len() > MAX_MOVABLE_VALENCE {
            return;
        }
        if self.free[u as usize] {
            sc.allowed.extend_from_slice(ring);
            // Test builds: a free vertex has no constrained edge (its flag is kept up to date
            // across collapses into it, flat/mod.rs).
            #[cfg(test)]
            for &x in ring {
                let constrained = match sc.fan.edge(x) {
                    (Some(f1), Some(f2)) => !self.plain && self.differ(f1, f2),
                    _ => true,
                };
                assert!(!constrained, "free vertex {u} has a constrained edge to {x}");
            }
            return;
        }
        let (mut along, mut n) = ([INVALID; 2], 0);
        let (mut next, mut prev) = (INVALID, INVALID);
        for &x in ring {
            let (forward, backward) = sc.fan.edge(x);
            let constrained = match (forward, backward) {
                (Some(f1), Some(f2)) => !self.plain && self.differ(f1, f2),
                (Some(_), None) => {
                    next = x;
                    true
                }
                (None, Some(_)) => {
                    prev = x;
                    true
                }
                (None, None) => unreachable!("a neighbour off every face"),
            };
            if constrained {
                if n < 2 {
                    along[n] = x;
                }
                n += 1;
            }
        }
        // One constrained edge: a seam's end (a border vertex has two), which moves along
        // its other edges (crate::mesh::constraints).
        if n > 2 || (border && is_border_corner(self.mesh, u, next, prev, QUADRIC_BORDER_CORNER_DEGREES)) {
            return;
        }
        match n {
            2 => sc.allowed.extend_from_slice(&along),
            1 => sc.allowed.extend(ring.iter().filter(|&&x| x != along[0])),
            _ => sc.allowed.extend_from_slice(ring),
        }
    }

    /// Whether edge (u, x) is a seam or between primitives: f1 holds u → x, f2 holds x → u.
    fn differ(&self, f1: Corner, f2: Corner) -> bool {
        let w = |c: Corner, k: u8| self.flat.wedge(c.face, (c.at + k) % 3);
        w(f1, 0) != w(f2, 0)
            || w(f1, 1) != w(f2, 2)
            || self.mesh.primitive_of(f1.face as usize) != self.mesh.primitive_of(f2.face as usize)
    }

    /// u's cost (Q_u + Q_v)(v) into `v`, plus W times the attribute part `attribute` gives
    /// where attributes are weighted, with `v`, if within the error bound (geometric; its
    /// error is worked out only under one: otherwise only the winner's is needed,
    /// [`Rules::error`]).
    #[inline]
    fn scored(&self, qu: &Quadric, v: u32, attribute: impl FnOnce(DVec3) -> f64) -> Option<(f64, u32)> {
        let (own, weight) = self.own[v as usize];
        let pv = self.pos(v);
        let geometric = qu.eval(pv.to_array()) + own;
        // An error that is not a number does not exceed the bound either.
        let over = self.error_bound.is_finite()
            && Quadric::distance_of(geometric, qu.weight() + weight).partial_cmp(&self.error_bound)
                == Some(std::cmp::Ordering::Greater);
        if over {
            return None;
        }
        let cost = match self.attributes {
            Some(_) => geometric + (qu.weight() + weight) * attribute(pv),
            None => geometric,
        };
        Some((cost, v))
    }

    /// The attribute part of u → v, u's fan in `fan` (0 without weighted attributes).
    fn attribute_cost(&self, fan: &Fan, v: u32, pv: DVec3) -> f64 {
        let Some(a) = self.attributes else { return 0.0 };
        let (forward, backward) = fan.edge(v);
        a.cost(wedge_map(self.flat, forward, backward), pv)
    }

    /// Q_v(v) once u has collapsed into v, bit for bit as the pass will work it out
    /// ([`own_cost`] of Q_v + Q_u).
    pub fn own_cost_after(&self, u: u32, v: u32) -> f64 {
        own_cost(self.mesh, &(self.quadrics[v as usize] + self.quadrics[u as usize]), v).0
    }

    /// The error of u's collapse into v at `cost`, as [`Rules::scored`] works it out under a
    /// bound.
    pub fn error(&self, u: u32, v: u32, cost: f64) -> f64 {
        let qu = &self.quadrics[u as usize];
        let (own, weight) = self.own[v as usize];
        // With attributes weighted, the cost holds them too; the error is geometric.
        let geometric = if self.attributes.is_some() { qu.eval(self.pos(v).to_array()) + own } else { cost };
        Quadric::distance_of(geometric, qu.weight() + weight)
    }

    /// The cheapest allowed target (ties: the smaller id) and its cost, before the link, wedge
    /// and flip checks: what the passes rank by, and the target the walk checks first.
    pub fn bound(&self, u: u32, sc: &mut Scratch) -> Option<(f64, u32)> {
        let qu = &self.quadrics[u as usize];
        let cheapest = |a: (f64, u32), b: (f64, u32)| if cheaper(&b, &a).is_lt() { b } else { a };
        if self.free[u as usize] {
            // A free vertex (interior, no constrained edge): every neighbour is a target, the
            // vertex after it in one of its faces, read off its row without building its fan
            // (most vertices, most passes: this is the passes' costing).
            if !self.movable(u) || self.flat.count(u) as usize > MAX_MOVABLE_VALENCE {
                return None;
            }
            // Its edges are no seams, so u has one wedge and each edge one pair.
            return match self.attributes {
                None => self.flat.followers(u).filter_map(|v| self.scored(qu, v, |_| 0.0)).reduce(cheapest),
                Some(a) => self
                    .flat
                    .follower_wedges(u)
                    .filter_map(|(v, wu, wv)| self.scored(qu, v, |pv| a.cost_of_pair((wu, wv), pv)))
                    .reduce(cheapest),
            };
        }
        self.targets(u, sc);
        let fan = &sc.fan;
        sc.allowed.iter().filter_map(|&v| self.scored(qu, v, |pv| self.attribute_cost(fan, v, pv))).reduce(cheapest)
    }

    /// u's cheapest target among the `usable` ones that passes every rule (ties: the smaller
    /// vertex id), with its cost; u's fan and targets in `sc`, as [`Rules::targets`] reads
    /// them (the walk has just read them to check u's pick).
    pub fn evaluate(&self, u: u32, sc: &mut Scratch, usable: impl Fn(u32) -> bool) -> Option<(f64, u32)> {
        let qu = &self.quadrics[u as usize];
        let mut scored = std::mem::take(&mut sc.scored);
        scored.clear();
        let fan = &sc.fan;
        scored.extend(
            sc.allowed
                .iter()
                .filter(|&&v| usable(v))
                .filter_map(|&v| self.scored(qu, v, |pv| self.attribute_cost(fan, v, pv))),
        );
        scored.sort_unstable_by(cheaper);
        let pick = scored.iter().copied().find(|&(_, v)| self.passes(u, v, sc));
        sc.scored = scored;
        pick
    }

    /// The checks after the cost for u → v, u's fan in `sc.fan`: the link condition, the
    /// wedges, the faces' turns.
    pub fn passes(&self, u: u32, v: u32, sc: &mut Scratch) -> bool {
        let (forward, backward) = sc.fan.edge(v);
        if forward.is_none() && backward.is_none() {
            return false;
        }
        let border_edge = forward.is_none() || backward.is_none();
        if self.border(u) != border_edge {
            return false;
        }
        let wings = [forward.map_or(INVALID, |c| c.b), backward.map_or(INVALID, |c| c.a)];
        self.link_holds(v, wings, sc)
            && (self.plain || self.wedges_carry_over(&sc.fan, forward, backward))
            && !self.turns(&sc.fan, v)
    }

    /// The link condition ([`crate::topology::HalfEdges::collapse_is_legal`]'s, on the flat
    /// fans): the common neighbours of u and v are exactly the wings, the wings keep enough
    /// neighbours, and v keeps a proper fan.
    fn link_holds(&self, v: u32, wings: [u32; 2], sc: &mut Scratch) -> bool {
        let nu = &sc.fan.ring;
        if nu.len() > MAX_LINK_VALENCE {
            return false;
        }
        self.flat.ring(v, self.border(v), &mut sc.target_ring);
        let mut common = 0;
        for &w in &sc.target_ring {
            if nu.contains(&w) {
                if !wings.contains(&w) {
                    return false;
                }
                common += 1;
            }
        }
        if common != wings.iter().filter(|&&w| w != INVALID).count() {
            return false;
        }
        for w in wings.into_iter().filter(|&w| w != INVALID) {
            let border = self.border(w);
            let valence = self.flat.count(w) as usize + usize::from(border);
            if valence < if border { 3 } else { 4 } {
                return false;
            }
        }
        let after = nu.len() + sc.target_ring.len() - 2 - common;
        after >= if self.border(v) { 2 } else { 3 }
    }

    /// [`crate::mesh::constraints::wedges_carry_over`] on the flat fan.
    fn wedges_carry_over(&self, fan: &Fan, forward: Option<Corner>, backward: Option<Corner>) -> bool {
        let map = wedge_map(self.flat, forward, backward);
        if map[0].0 == map[1].0 && map[0].1 != map[1].1 && map[0].0 != INVALID {
            return false;
        }
        fan.corners.iter().all(|c| {
            let w = self.flat.wedge(c.face, c.at);
            map.iter().any(|&(from, _)| from == w)
        })
    }

    /// Whether moving u onto v turns a surviving face of u over (or flat), against its
    /// current normal or against its input normal ([`MIN_NORMAL_DOT`]), as the half-edge
    /// engines' flip test does.
    fn turns(&self, fan: &Fan, v: u32) -> bool {
        let pv = self.pos(v);
        fan.corners.iter().filter(|c| c.a != v && c.b != v).any(|c| {
            let f = self.flat.tri(c.face);
            let [a, b, d] = f.map(|x| self.pos(x));
            let mut moved = [a, b, d];
            moved[c.at as usize] = pv;
            let before = (b - a).cross(d - a);
            let after = (moved[1] - moved[0]).cross(moved[2] - moved[0]);
            before.dot(after) <= 0.0 || self.normal0[c.face as usize].dot(after) < MIN_NORMAL_DOT * after.length()
        })
    }
}

/// Q_v(v) and the weight of Q_v for every vertex (in parallel).
pub(super) fn own_costs(mesh: &Mesh, quadrics: &[Quadric]) -> Vec<(f64, f64)> {
    use rayon::prelude::*;
    quadrics.par_iter().with_min_len(4096).enumerate().map(|(v, q)| own_cost(mesh, q, v as u32)).collect()
}

/// Q_v(v) and the weight of `q` = Q_v.
pub(super) fn own_cost(mesh: &Mesh, q: &Quadric, v: u32) -> (f64, f64) {
    (q.eval(mesh.positions[v as usize].map(f64::from)), q.weight())
}

/// The wedge map u → v through the faces on the edge ([`crate::mesh::constraints::wedge_map`]): (u's
/// wedge, v's wedge) in the face holding u → v, then in the one holding v → u.
pub(super) fn wedge_map(flat: &FlatFaces, forward: Option<Corner>, backward: Option<Corner>) -> [(u32, u32); 2] {
    let side = |c: Option<Corner>, k: u8| {
        c.map_or((INVALID, INVALID), |c| (flat.wedge(c.face, c.at), flat.wedge(c.face, (c.at + k) % 3)))
    };
    [side(forward, 1), side(backward, 2)]
}
