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
//! [`HalfEdges::collapse_is_legal`] checks the topological conditions: the link condition
//! (the common neighbours of u and v are exactly the wing vertices a and b), a border vertex
//! only moves along its border, no wing vertex is left with too few neighbours, and the
//! component does not vanish. Geometry (face flips) and attributes (seams) are the caller's.

use super::{vflag, HalfEdges, HalfEdgesMut, Topology, INVALID};

/// Most neighbours the removed vertex may have for its collapse to be checked (the link
/// condition's buffer); a collapse of a vertex with more is refused.
pub(crate) const MAX_LINK_VALENCE: usize = 48;

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

/// Most of u's surviving corners a [`CollapseWrites`] lists (an interior u of valence 16 has
/// 14); with more, [`HalfEdgesMut::write_collapse`] finds them by walking u's fan.
pub const LISTED_CORNERS: usize = 14;

/// Every store a half-edge collapse makes ([`HalfEdges::collapse_writes`]), so that the reading
/// can happen apart from the writing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CollapseWrites {
    /// u, the vertex that goes.
    pub remove: u32,
    /// v, the vertex that stays.
    pub target: u32,
    /// The removed faces, `INVALID` for a missing second one.
    pub removed: [u32; 2],
    /// Half-edge pairs that become twins across each removed face (`INVALID` for none).
    links: [(u32, u32); 2],
    /// v's and the wings' outgoing half-edges after.
    relinks: [Relink; 3],
    /// u's corners on the surviving faces (its outgoing half-edges), to name v.
    corners: [u32; LISTED_CORNERS],
    /// How many; `u8::MAX` or over [`LISTED_CORNERS`]: not all listed.
    n_corners: u8,
}

impl CollapseWrites {
    /// u's corners on the surviving faces, or `None` when there were too many to list.
    pub fn corners(&self) -> Option<&[u32]> {
        self.corners.get(..usize::from(self.n_corners))
    }
}

/// A kept vertex's new outgoing half-edge: `start`, or for a border vertex the first half-edge
/// of its fan from `start` on the state after the collapse.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Relink {
    vertex: u32,
    start: u32,
    to_border: bool,
}

/// Checks the topological conditions for a collapse ([`HalfEdges::collapse_is_legal`]).
pub(super) fn is_legal<T: HalfEdges + ?Sized>(t: &T, c: HalfEdgeCollapse) -> Result<(), Illegal> {
    let h = c.he;
    if !t.has_half_edge(h) || !t.is_face_live(h / 3) {
        return Err(Illegal::Stale);
    }
    let (u, v) = (c.remove, t.collapse_target(c));
    if t.origin(h) != u && t.dest(h) != u {
        return Err(Illegal::Stale);
    }
    if t.flags_of(u) & vflag::LOCKED != 0 {
        return Err(Illegal::Locked);
    }
    let border_edge = t.twin_of(h) == INVALID;
    if t.is_boundary_vertex(u) != border_edge {
        // A border vertex moves only along its border; an interior vertex never sits on
        // a border edge.
        return Err(Illegal::Border);
    }
    let [a, b] = t.wings(c);
    // Link condition: the common neighbours of u and v are exactly the wings.
    let mut nu = [0u32; MAX_LINK_VALENCE];
    let mut len_u = 0;
    for w in t.neighbors(u) {
        if len_u == nu.len() {
            return Err(Illegal::Link); // valence over the cap: refuse rather than allocate
        }
        nu[len_u] = w;
        len_u += 1;
    }
    let nu = &nu[..len_u];
    let mut common = 0;
    let mut len_v = 0;
    for w in t.neighbors(v) {
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
        if w != INVALID && !t.valence_at_least(w, if t.is_boundary_vertex(w) { 3 } else { 4 }) {
            return Err(Illegal::Wing);
        }
    }
    // v keeps a proper fan: 3 neighbours after if interior, 2 on a border.
    let after = nu.len() + len_v - 2 - common;
    if after < if t.is_boundary_vertex(v) { 2 } else { 3 } {
        return Err(Illegal::Wing);
    }
    Ok(())
}

/// Works out every store [`HalfEdgesMut::collapse`] makes, reading only u's fan (faces and
/// twins), the removed faces' twins, and the stored half-edge (with its face) and border
/// flag of v and the wings. Collapses whose closed neighbourhoods N\[u\] are disjoint read and write disjoint
/// entries, so theirs can be worked out in parallel on one state and written after one
/// another in any order (simplify/batched.rs).
pub(super) fn writes<T: HalfEdges + ?Sized>(t: &T, c: HalfEdgeCollapse) -> CollapseWrites {
    let (u, v) = (c.remove, t.collapse_target(c));
    let (hu, hv) = t.halves(c);
    let twin_of = |g: u32| if g == INVALID { INVALID } else { t.twin_of(g) };
    let next = |g: u32| if g == INVALID { INVALID } else { Topology::next(g) };
    let prev = |g: u32| if g == INVALID { INVALID } else { Topology::prev(g) };
    // The wings (as `wings`): a = origin(prev(hu)), b = origin(prev(hv)).
    let wing = |g: u32| if g == INVALID { INVALID } else { t.origin(prev(g)) };
    let (a, b) = (wing(hu), wing(hv));
    let removed = [hu, hv].map(|g| if g == INVALID { INVALID } else { g / 3 });
    // Whether a half-edge's face is one of the removed ones (a live face is never INVALID).
    let on_removed = |g: u32| removed.contains(&(g / 3));
    // f1 = (u, v, a) on hu: outside x1 = a→v, y1 = u→a (to become v→a).
    let (x1, y1) = (twin_of(next(hu)), twin_of(prev(hu)));
    // f2 = (v, u, b) on hv: outside x2 = b→u (to become b→v), y2 = v→b.
    let (x2, y2) = (twin_of(next(hv)), twin_of(prev(hv)));
    // A surviving outgoing half-edge for each vertex whose stored one may vanish.
    let first_valid = |gs: [u32; 3]| gs.into_iter().find(|&g| g != INVALID).unwrap_or(INVALID);
    let hint_a = first_valid([x1, next(y1), INVALID]);
    let hint_b = first_valid([x2, next(y2), INVALID]);
    // u's surviving faces will name v: each is found at its corner (half-edge) at u.
    let mut corners = [INVALID; LISTED_CORNERS];
    let mut n_corners = 0usize;
    let mut first_corner = INVALID;
    for g in t.outgoing(u).filter(|&g| !on_removed(g)) {
        first_corner = if first_corner == INVALID { g } else { first_corner };
        if n_corners < LISTED_CORNERS {
            corners[n_corners] = g;
        }
        n_corners += 1;
    }
    let hint_v = first_valid([y1, y2, first_corner]);
    // Each kept vertex's outgoing half-edge after the collapse: its stored one if that
    // survives (no half-edge out of v or a wing is renamed), else the hint; a border
    // vertex then turns to its border half-edge, on the state after (see `relink`).
    let relink = |w: u32, hint: u32| {
        if w == INVALID {
            return Relink { vertex: INVALID, start: INVALID, to_border: false };
        }
        let stored = t.vertex_he_of(w);
        let survives = stored != INVALID && t.is_face_live(stored / 3) && !on_removed(stored) && t.origin(stored) == w;
        Relink { vertex: w, start: if survives { stored } else { hint }, to_border: t.is_boundary_vertex(w) }
    };
    CollapseWrites {
        remove: u,
        target: v,
        // A missing side links nothing.
        links: [
            if hu != INVALID { (x1, y1) } else { (INVALID, INVALID) },
            if hv != INVALID { (y2, x2) } else { (INVALID, INVALID) },
        ],
        removed,
        relinks: [relink(v, hint_v), relink(a, hint_a), relink(b, hint_b)],
        corners,
        n_corners: u8::try_from(n_corners).unwrap_or(u8::MAX),
    }
}

/// Makes the stores of [`HalfEdges::collapse_writes`], worked out on this state or on one
/// that differs only outside the collapse's closed neighbourhood. Returns the removed
/// faces.
pub(super) fn write<T: HalfEdgesMut + ?Sized>(t: &mut T, w: &CollapseWrites) -> [u32; 2] {
    let (u, v) = (w.remove, w.target);
    match w.corners() {
        Some(corners) => {
            for &g in corners {
                t.set_origin(g, v);
            }
        }
        // Too many to list (a rare pole): u's fan is still as it was (nothing below has
        // run yet), so list its corners now.
        None => {
            let corners: Vec<u32> = t.outgoing(u).filter(|&g| !w.removed.contains(&(g / 3))).collect();
            for g in corners {
                t.set_origin(g, v);
            }
        }
    }
    // After a collapse, makes `p` and `q` twins (either may be `INVALID`).
    for (p, q) in w.links {
        if p != INVALID {
            t.set_twin(p, q);
        }
        if q != INVALID {
            t.set_twin(q, p);
        }
    }
    // A removed face keeps its twin entries (nothing follows a dead face's twins): the
    // runtime's split reads the outside half-edges back from them (lod/hierarchy.rs).
    for f in w.removed.into_iter().filter(|&f| f != INVALID) {
        t.set_face(f, [INVALID; 3]);
    }
    t.set_vertex_he(u, INVALID);
    t.set_flags(u, t.flags_of(u) | vflag::REMOVED);
    for r in w.relinks.iter().filter(|r| r.vertex != INVALID) {
        debug_assert!(r.start != INVALID && t.origin(r.start) == r.vertex, "no outgoing half-edge for {}", r.vertex);
        t.set_vertex_he(r.vertex, if r.to_border { t.fan_start_of(r.start) } else { r.start });
    }
    w.removed
}

impl Topology {
    /// Resets `vertex_he[w]` to a live outgoing half-edge, the border one if w is on a border.
    /// `hint` is a live outgoing half-edge of w, used when the stored one was removed. An
    /// interior vertex (no BOUNDARY flag: collapses and splits never change it) has no first
    /// half-edge, so a live stored one is kept as it is and no fan is walked.
    pub(crate) fn relink_vertex(&mut self, w: u32, hint: u32) {
        let stored = self.vertex_he[w as usize];
        let stored_live = stored != INVALID && self.is_face_live(stored / 3) && self.origin(stored) == w;
        let start = if stored_live { stored } else { hint };
        debug_assert!(start != INVALID && self.origin(start) == w, "no live outgoing half-edge for {w}");
        self.vertex_he[w as usize] = if self.is_boundary_vertex(w) { self.fan_start_of(start) } else { start };
    }
}
