//! The half-edge collapse u → v on [`Topology`] (papers/002 §3.1, Fig. 1; the atomic operator
//! of papers/000 §4 as well): u disappears, its faces are re-attached to v, and the one or two
//! faces on edge (u, v) are removed.
//!
//! ```text
//!          a                      a
//!        / | \                   / \
//!       /  |  \                 /   \
//!     .. f1|    ..            ..     ..
//!      u --h--> v     ==>         v
//!     .. f2|    ..            ..     ..
//!       \  |  /                 \   /
//!        \ | /                   \ /
//!          b                      b
//!   h = u→v in f1 = (u, v, a); its twin v→u in f2 = (v, u, b)
//! ```
//!
//! [`Topology::collapse_is_legal`] checks the topological conditions: the link condition
//! (the common neighbours of u and v are exactly the wing vertices a and b), a border vertex
//! only moves along its border, no wing vertex is left with too few neighbours, and the
//! component does not vanish. Geometry (face flips) and attributes (seams) are the caller's.

use super::{vflag, Topology, INVALID};

/// Why a collapse is not allowed topologically.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Illegal {
    /// u or v is removed, or the half-edge is in a removed face.
    Stale,
    /// u is locked.
    Locked,
    /// u is on a border but (u, v) is not a border edge, or u and v are both on borders
    /// joined by an interior edge.
    Border,
    /// u and v share a neighbour that is not a wing of the edge.
    Link,
    /// A wing vertex would be left with two faces over one edge (or none).
    Wing,
}

/// A half-edge collapse: `remove` merges into the other end of the edge of half-edge `he`.
/// `he` may run either way along the edge (on a border only one direction exists).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HalfEdgeCollapse {
    /// Any live half-edge of the edge.
    pub he: u32,
    /// The endpoint that disappears (u); the other endpoint (v) stays where it is.
    pub remove: u32,
}

/// Whether half-edge `g` lies on one of the faces a collapse removes, given its (u→v, v→u)
/// half-edges (either `INVALID` on a border side).
pub fn on_removed_face(g: u32, (hu, hv): (u32, u32)) -> bool {
    g != INVALID && ((hu != INVALID && g / 3 == hu / 3) || (hv != INVALID && g / 3 == hv / 3))
}

impl Topology {
    /// (u→v, v→u) half-edges of a collapse, each `INVALID` when that side is a border.
    fn halves(&self, c: HalfEdgeCollapse) -> (u32, u32) {
        let t = self.twin[c.he as usize];
        if self.origin(c.he) == c.remove {
            (c.he, t)
        } else {
            (t, c.he)
        }
    }

    /// The vertex that stays.
    pub fn collapse_target(&self, c: HalfEdgeCollapse) -> u32 {
        let (a, b) = (self.origin(c.he), self.dest(c.he));
        if a == c.remove {
            b
        } else {
            a
        }
    }

    /// The one or two wing vertices of a collapse: (a, b) opposite the edge in the faces on
    /// u→v and v→u (`INVALID` for a missing side).
    pub fn wings(&self, c: HalfEdgeCollapse) -> [u32; 2] {
        let (hu, hv) = self.halves(c);
        let wing = |g: u32| if g == INVALID { INVALID } else { self.origin(Self::prev(g)) };
        [wing(hu), wing(hv)]
    }

    /// Number of neighbours of `v` (its valence).
    pub fn valence(&self, v: u32) -> usize {
        self.outgoing(v).count() + usize::from(self.is_boundary_vertex(v))
    }

    /// Whether `v` has at least `k` neighbours; walks at most `k` half-edges of its fan.
    pub fn valence_at_least(&self, v: u32, k: usize) -> bool {
        let border = usize::from(self.is_boundary_vertex(v));
        self.outgoing(v).take(k.saturating_sub(border)).count() + border >= k
    }

    /// Checks the topological conditions for a collapse.
    pub fn collapse_is_legal(&self, c: HalfEdgeCollapse) -> Result<(), Illegal> {
        let h = c.he;
        if h as usize >= self.twin.len() || !self.is_face_live(h / 3) {
            return Err(Illegal::Stale);
        }
        let (u, v) = (c.remove, self.collapse_target(c));
        if self.origin(h) != u && self.dest(h) != u {
            return Err(Illegal::Stale);
        }
        if self.vflags[u as usize] & vflag::LOCKED != 0 {
            return Err(Illegal::Locked);
        }
        let border_edge = self.twin[h as usize] == INVALID;
        if self.is_boundary_vertex(u) != border_edge {
            // A border vertex moves only along its border; an interior vertex never sits on
            // a border edge.
            return Err(Illegal::Border);
        }
        let [a, b] = self.wings(c);
        // Link condition: the common neighbours of u and v are exactly the wings.
        let mut nu = [0u32; 48];
        let mut len_u = 0;
        for w in self.neighbors(u) {
            if len_u == nu.len() {
                return Err(Illegal::Link); // valence over 48: refuse rather than allocate
            }
            nu[len_u] = w;
            len_u += 1;
        }
        let nu = &nu[..len_u];
        let mut common = 0;
        let mut len_v = 0;
        for w in self.neighbors(v) {
            len_v += 1;
            if nu.contains(&w) {
                if w != a && w != b {
                    return Err(Illegal::Link);
                }
                common += 1;
            }
        }
        if common != [a, b].iter().filter(|&&w| w != INVALID).count() {
            return Err(Illegal::Link);
        }
        // Wings keep enough neighbours: an interior wing needs 4 (3 after), a border wing 3.
        for w in [a, b] {
            if w != INVALID && !self.valence_at_least(w, if self.is_boundary_vertex(w) { 3 } else { 4 }) {
                return Err(Illegal::Wing);
            }
        }
        // v keeps a proper fan: 3 neighbours after if interior, 2 on a border.
        let after = nu.len() + len_v - 2 - common;
        if after < if self.is_boundary_vertex(v) { 2 } else { 3 } {
            return Err(Illegal::Wing);
        }
        Ok(())
    }

    /// Performs a collapse the caller has checked with [`Topology::collapse_is_legal`].
    /// Returns the removed faces (`INVALID` for a missing second face). u is flagged REMOVED
    /// and its surviving faces now name v.
    pub fn collapse(&mut self, c: HalfEdgeCollapse) -> [u32; 2] {
        let (u, v) = (c.remove, self.collapse_target(c));
        let (hu, hv) = self.halves(c);
        let [a, b] = self.wings(c);
        let twin_of = |topo: &Self, g: u32| if g == INVALID { INVALID } else { topo.twin[g as usize] };
        let next = |g: u32| if g == INVALID { INVALID } else { Self::next(g) };
        let prev = |g: u32| if g == INVALID { INVALID } else { Self::prev(g) };
        // f1 = (u, v, a) on hu: outside x1 = a→v, y1 = u→a (to become v→a).
        let (x1, y1) = (twin_of(self, next(hu)), twin_of(self, prev(hu)));
        // f2 = (v, u, b) on hv: outside x2 = b→u (to become b→v), y2 = v→b.
        let (x2, y2) = (twin_of(self, next(hv)), twin_of(self, prev(hv)));
        // A surviving outgoing half-edge for each vertex whose stored one may vanish.
        let first_valid = |gs: [u32; 3]| gs.into_iter().find(|&g| g != INVALID).unwrap_or(INVALID);
        let hint_a = first_valid([x1, next(y1), INVALID]);
        let hint_b = first_valid([x2, next(y2), INVALID]);
        // u's surviving faces name v instead: each is found at its corner (half-edge) at u.
        // The walk reads only twins, which do not change until the links below.
        let mut first_corner = INVALID;
        let mut g = self.vertex_he[u as usize];
        let start = g;
        while g != INVALID {
            if !on_removed_face(g, (hu, hv)) {
                first_corner = if first_corner == INVALID { g } else { first_corner };
                self.faces[(g / 3) as usize][(g % 3) as usize] = v;
            }
            let n = self.twin[Self::prev(g) as usize];
            g = if n == start { INVALID } else { n };
        }
        let hint_v = first_valid([y1, y2, first_corner]);
        if hu != INVALID {
            self.link(x1, y1);
        }
        if hv != INVALID {
            self.link(y2, x2);
        }
        let removed = [hu, hv].map(|g| if g == INVALID { INVALID } else { g / 3 });
        // A removed face keeps its twin entries (nothing follows a dead face's twins): the
        // runtime's split reads the outside half-edges back from them (lod/hierarchy.rs).
        for f in removed.into_iter().filter(|&f| f != INVALID) {
            self.faces[f as usize] = [INVALID; 3];
        }
        self.vertex_he[u as usize] = INVALID;
        self.vflags[u as usize] |= vflag::REMOVED;
        for (w, hint) in [(v, hint_v), (a, hint_a), (b, hint_b)] {
            if w != INVALID {
                self.relink_vertex(w, hint);
            }
        }
        removed
    }

    /// After a collapse: makes `p` and `q` twins (either may be `INVALID`).
    fn link(&mut self, p: u32, q: u32) {
        if p != INVALID {
            self.twin[p as usize] = q;
        }
        if q != INVALID {
            self.twin[q as usize] = p;
        }
    }

    /// Resets `vertex_he[w]` to a live outgoing half-edge, the border one if w is on a border.
    /// `hint` is a live outgoing half-edge of w, used when the stored one was removed. An
    /// interior vertex (no BOUNDARY flag: collapses and splits never change it) has no first
    /// half-edge, so a live stored one is kept as it is and no fan is walked.
    pub(crate) fn relink_vertex(&mut self, w: u32, hint: u32) {
        let stored = self.vertex_he[w as usize];
        let stored_live = stored != INVALID && self.is_face_live(stored / 3) && self.origin(stored) == w;
        let start = if stored_live { stored } else { hint };
        debug_assert!(start != INVALID && self.origin(start) == w, "no live outgoing half-edge for {w}");
        self.vertex_he[w as usize] =
            if self.is_boundary_vertex(w) { super::fan_start(&self.twin, start, self.twin.len()) } else { start };
    }
}
