//! The connectivity reads and writes every pass is written against, by global ids: on a whole
//! [`Topology`], or on one [`TopologyPart`](super::TopologyPart) of it (a range of vertices
//! and faces that one thread may edit while others edit theirs, papers/000 §4's application
//! step run in parallel: docs/ALGORITHM.md, "Applying a round in parts").
//!
//! ```text
//!   required   origin(h)  face(f)  twin_of(h)  vertex_he_of(v)  flags_of(v)  has_half_edge(h)
//!   provided   dest, outgoing, neighbors, is_boundary_vertex, … and the half-edge collapse:
//!              collapse_is_legal, collapse_writes (reads); write_collapse, collapse (writes)
//! ```
//! The walks and the collapse are written once, here and in `collapse.rs`, and compiled for
//! each storage; a part answers only for its own ids and panics on any other (a bug: the
//! caller promised the collapse stays inside the part).

use super::collapse::{self, CollapseWrites, HalfEdgeCollapse, Illegal};
use super::{vflag, Topology, INVALID};

/// Reads of half-edge connectivity (see the module docs).
pub trait HalfEdges {
    /// Start vertex of half-edge `h` (the corner `h % 3` of face `h / 3`).
    fn origin(&self, h: u32) -> u32;
    /// The corners of face `f` (`[INVALID; 3]` once removed).
    fn face(&self, f: u32) -> [u32; 3];
    /// The opposite half-edge of `h`, `INVALID` on a border.
    fn twin_of(&self, h: u32) -> u32;
    /// `v`'s stored outgoing half-edge (`INVALID` once removed).
    fn vertex_he_of(&self, v: u32) -> u32;
    /// `v`'s [`vflag`] bits.
    fn flags_of(&self, v: u32) -> u8;
    /// Whether `h` is a half-edge slot of this storage.
    fn has_half_edge(&self, h: u32) -> bool;
    /// Half-edge slots in this storage (a bound on any fan walk).
    fn half_edge_slots(&self) -> usize;

    /// End vertex of half-edge `h`.
    #[inline]
    fn dest(&self, h: u32) -> u32 {
        self.origin(Topology::next(h))
    }

    /// Whether face `f` is part of the mesh.
    #[inline]
    fn is_face_live(&self, f: u32) -> bool {
        self.face(f)[0] != INVALID
    }

    /// Whether `h` lies on a border.
    #[inline]
    fn is_border_he(&self, h: u32) -> bool {
        self.twin_of(h) == INVALID
    }

    /// Whether `v` is on a border.
    #[inline]
    fn is_boundary_vertex(&self, v: u32) -> bool {
        self.flags_of(v) & vflag::BOUNDARY != 0
    }

    /// Outgoing half-edges of `v`, counter-clockwise, starting at its stored one.
    #[inline]
    fn outgoing(&self, v: u32) -> Outgoing<'_, Self> {
        let start = self.vertex_he_of(v);
        Outgoing { topo: self, start, cur: start }
    }

    /// Neighbouring vertices of `v`, counter-clockwise (a border vertex's last neighbour is
    /// the far end of its incoming border half-edge).
    #[inline]
    fn neighbors(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let border = self.is_boundary_vertex(v);
        let mut last = INVALID;
        let ring = self.outgoing(v).map(move |h| self.dest(h));
        if border {
            // The last outgoing half-edge's face also holds the incoming border half-edge.
            if let Some(h) = self.outgoing(v).last() {
                last = self.origin(Topology::prev(h));
            }
        }
        ring.chain(std::iter::once(last).filter(|&x| x != INVALID))
    }

    /// Number of neighbours of `v` (its valence).
    fn valence(&self, v: u32) -> usize {
        self.outgoing(v).count() + usize::from(self.is_boundary_vertex(v))
    }

    /// Whether `v` has at least `k` neighbours; walks at most `k` half-edges of its fan.
    #[inline]
    fn valence_at_least(&self, v: u32, k: usize) -> bool {
        let border = usize::from(self.is_boundary_vertex(v));
        self.outgoing(v).take(k.saturating_sub(border)).count() + border >= k
    }

    /// Turns clockwise around the origin of outgoing half-edge `h` to the first half-edge of
    /// its fan (one whose twin is a border), or all the way round back to `h`
    /// ([`super::fan_start`] on this storage).
    fn fan_start_of(&self, h: u32) -> u32 {
        super::fan_start_by(|g| self.twin_of(g), h, self.half_edge_slots())
    }

    /// (u→v, v→u) half-edges of a collapse, each `INVALID` when that side is a border.
    #[inline]
    fn halves(&self, c: HalfEdgeCollapse) -> (u32, u32) {
        let t = self.twin_of(c.he);
        if self.origin(c.he) == c.remove {
            (c.he, t)
        } else {
            (t, c.he)
        }
    }

    /// The vertex that stays.
    #[inline]
    fn collapse_target(&self, c: HalfEdgeCollapse) -> u32 {
        let (a, b) = (self.origin(c.he), self.dest(c.he));
        if a == c.remove {
            b
        } else {
            a
        }
    }

    /// The one or two wing vertices of a collapse: (a, b) opposite the edge in the faces on
    /// u→v and v→u (`INVALID` for a missing side).
    #[inline]
    fn wings(&self, c: HalfEdgeCollapse) -> [u32; 2] {
        let (hu, hv) = self.halves(c);
        let wing = |g: u32| if g == INVALID { INVALID } else { self.origin(Topology::prev(g)) };
        [wing(hu), wing(hv)]
    }

    /// Checks the topological conditions for a collapse (`collapse.rs`).
    fn collapse_is_legal(&self, c: HalfEdgeCollapse) -> Result<(), Illegal> {
        collapse::is_legal(self, c)
    }

    /// Works out every store [`HalfEdgesMut::collapse`] makes, without making them
    /// (`collapse.rs`).
    fn collapse_writes(&self, c: HalfEdgeCollapse) -> CollapseWrites {
        collapse::writes(self, c)
    }
}

/// Writes of half-edge connectivity, and the collapse made with them.
pub trait HalfEdgesMut: HalfEdges {
    /// Sets the start vertex of half-edge `h`.
    fn set_origin(&mut self, h: u32, v: u32);
    /// Sets the corners of face `f`.
    fn set_face(&mut self, f: u32, corners: [u32; 3]);
    /// Sets the twin of `h`.
    fn set_twin(&mut self, h: u32, t: u32);
    /// Sets `v`'s stored outgoing half-edge.
    fn set_vertex_he(&mut self, v: u32, h: u32);
    /// Sets `v`'s [`vflag`] bits.
    fn set_flags(&mut self, v: u32, flags: u8);

    /// Makes the stores of [`HalfEdges::collapse_writes`] (`collapse.rs`). Returns the
    /// removed faces.
    fn write_collapse(&mut self, w: &CollapseWrites) -> [u32; 2] {
        collapse::write(self, w)
    }

    /// Performs a collapse the caller has checked with [`HalfEdges::collapse_is_legal`].
    /// Returns the removed faces (`INVALID` for a missing second face). u is flagged REMOVED
    /// and its surviving faces now name v.
    fn collapse(&mut self, c: HalfEdgeCollapse) -> [u32; 2] {
        let w = self.collapse_writes(c);
        self.write_collapse(&w)
    }
}

impl HalfEdges for Topology {
    #[inline]
    fn origin(&self, h: u32) -> u32 {
        self.faces.as_flattened()[h as usize]
    }
    #[inline]
    fn face(&self, f: u32) -> [u32; 3] {
        self.faces[f as usize]
    }
    #[inline]
    fn twin_of(&self, h: u32) -> u32 {
        self.twin[h as usize]
    }
    #[inline]
    fn vertex_he_of(&self, v: u32) -> u32 {
        self.vertex_he[v as usize]
    }
    #[inline]
    fn flags_of(&self, v: u32) -> u8 {
        self.vflags[v as usize]
    }
    #[inline]
    fn has_half_edge(&self, h: u32) -> bool {
        (h as usize) < self.twin.len()
    }
    #[inline]
    fn half_edge_slots(&self) -> usize {
        self.twin.len()
    }
}

impl HalfEdgesMut for Topology {
    #[inline]
    fn set_origin(&mut self, h: u32, v: u32) {
        self.faces.as_flattened_mut()[h as usize] = v;
    }
    #[inline]
    fn set_face(&mut self, f: u32, corners: [u32; 3]) {
        self.faces[f as usize] = corners;
    }
    #[inline]
    fn set_twin(&mut self, h: u32, t: u32) {
        self.twin[h as usize] = t;
    }
    #[inline]
    fn set_vertex_he(&mut self, v: u32, h: u32) {
        self.vertex_he[v as usize] = h;
    }
    #[inline]
    fn set_flags(&mut self, v: u32, flags: u8) {
        self.vflags[v as usize] = flags;
    }
}

/// Iterator over the outgoing half-edges of a vertex (see [`HalfEdges::outgoing`]).
pub struct Outgoing<'a, T: ?Sized = Topology> {
    topo: &'a T,
    start: u32,
    cur: u32,
}

impl<T: HalfEdges + ?Sized> Iterator for Outgoing<'_, T> {
    type Item = u32;
    #[inline]
    fn next(&mut self) -> Option<u32> {
        if self.cur == INVALID {
            return None;
        }
        let h = self.cur;
        let n = self.topo.twin_of(Topology::prev(h));
        self.cur = if n == self.start { INVALID } else { n };
        Some(h)
    }
}
