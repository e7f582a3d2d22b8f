//! Which collapses of a round are still legal after the ones before them, mostly without
//! walking their fans again: the application step of papers/000 §4 under the local-minima
//! schedule, where the round's removed vertices are pairwise non-adjacent and each chose its
//! collapse on the round's starting state (docs/ALGORITHM.md, papers/000: "The round as a
//! whole stays manifold").
//!
//! ```text
//!   collapse u' → v' (wings a', b') touches N(u'):
//!     v'                    RESHAPED: gained u's other neighbours
//!     a', b'                WINGED: lost u', gained nothing (RESHAPED if touched otherwise too)
//!     any other x ∈ N(u')   lost u', gained v' (same number of neighbours); twice: TOUCHED_TWICE
//!   a later collapse u → v, legal on the starting state, is still legal if v is untouched,
//!   or was touched once as a plain neighbour and the v' it gained is not next to u;
//!   otherwise the whole condition is checked again
//! ```
//! Why this is exact:
//! * u is next to no u', so its neighbours, faces and wings are as they were. Of what
//!   [`HalfEdges::collapse_is_legal`] reads, only v's neighbours and the numbers of neighbours
//!   of v and of the wings can have changed.
//! * A plain neighbour x of u' was not next to v' (else it would be a wing of u' → v'), so it
//!   keeps its number of neighbours. As v, its one new neighbour v' adds a common neighbour
//!   of u and v only if v' is next to u; losing u' takes none away, as u' is not next to u.
//! * A wing loses one neighbour per removed neighbour at most, and the removed vertices
//!   around it are pairwise non-adjacent. Only a wing of valence 4 inside (3 on a border)
//!   can fall too low, and its fan has no room for a second removed vertex that is not next
//!   to v: the u' that lowered it also touched v, as v', as a wing, or as a plain neighbour
//!   whose v' is next to u, and v's rule checks everything.
//! * A v that was a wing (WINGED) is checked in full. It would not do to treat it as
//!   untouched: when u and v both have few neighbours, v's lost neighbour can leave the
//!   collapse a folded tetrahedron. (Treating it like a plain neighbour that gained v' would
//!   do, by the same counting; the tests cannot tell that from checking in full.)
//!
//! [`RoundTouches::gained`] also serves §6, whose metric reads each vertex's neighbours in S:
//! a vertex that gained nothing or one target keeps its metric or updates it from that one.

use super::{HalfEdgeCollapse, HalfEdges, Parts, Topology, INVALID};

/// No collapse of this round has touched the vertex's fan.
const UNTOUCHED: u32 = INVALID;
/// The vertex was the target of a collapse, or a wing of one and touched again.
const RESHAPED: u32 = INVALID - 1;
/// The vertex was a plain neighbour of two removed vertices. (A plain neighbour of one holds
/// the target it gained.)
const TOUCHED_TWICE: u32 = INVALID - 2;
/// The vertex was a wing of one or more collapses and touched no other way (it lost
/// neighbours, gained none).
const WINGED: u32 = INVALID - 3;

/// What a vertex gained as neighbours this round ([`RoundTouches::gained`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Gained {
    /// None: untouched, or only a wing (it lost the removed vertices, next to it already).
    Nothing,
    /// One vertex: it was a plain neighbour of one removed vertex, and gained its target.
    One(u32),
    /// Not recorded: it was a target, or touched more than once not only as a wing.
    Unknown,
}

/// Per vertex, what this round's collapses so far did to its fan. All untouched between
/// rounds: [`RoundTouches::clear`] the vertices marked.
#[derive(Debug, Clone, Default)]
pub struct RoundTouches {
    touch: Vec<u32>,
}

impl RoundTouches {
    /// For a mesh of `vertex_count` vertex slots (fewer than `u32::MAX - 3`: the largest ids
    /// are its marks).
    pub fn new(vertex_count: usize) -> Self {
        Self { touch: vec![UNTOUCHED; vertex_count] }
    }

    /// Records that `x`, a neighbour of a vertex about to collapse onto `target` with wings
    /// `wings`, is touched. Call it for every neighbour, before the collapse (or use
    /// [`RoundTouches::record`]).
    #[inline]
    pub fn mark(&mut self, x: u32, target: u32, wings: [u32; 2]) {
        let slot = &mut self.touch[x as usize];
        *slot = marked(*slot, x, target, wings);
    }

    /// [`RoundTouches::mark`] for every neighbour of the removed vertex of `c`, before it is
    /// made.
    pub fn record(&mut self, t: &Topology, c: HalfEdgeCollapse) {
        let (target, wings) = (t.collapse_target(c), t.wings(c));
        for x in t.neighbors(c.remove) {
            self.mark(x, target, wings);
        }
    }

    /// Whether `c`, legal on the round's starting state and with its removed vertex next to
    /// none of the round's earlier removed vertices, is still legal now.
    pub fn still_legal(&self, t: &Topology, c: HalfEdgeCollapse) -> bool {
        still_legal(self.touch[t.collapse_target(c) as usize], t, c)
    }

    /// Whether no collapse of this round has touched `x` yet.
    #[inline]
    pub fn untouched(&self, x: u32) -> bool {
        self.touch[x as usize] == UNTOUCHED
    }

    /// What `x` gained as neighbours this round, as far as the marks tell.
    pub fn gained(&self, x: u32) -> Gained {
        match self.touch[x as usize] {
            UNTOUCHED | WINGED => Gained::Nothing,
            RESHAPED | TOUCHED_TWICE => Gained::Unknown,
            v => Gained::One(v),
        }
    }

    /// Makes `vertices` untouched again (every vertex marked this round must be among them).
    pub fn clear(&mut self, vertices: &[u32]) {
        for &v in vertices {
            self.touch[v as usize] = UNTOUCHED;
        }
    }

    /// All the marks as one piece.
    pub fn whole(&mut self) -> RoundTouchesPart<'_> {
        RoundTouchesPart { first: 0, touch: &mut self.touch }
    }
}

/// The marks of a range of vertices (from `first`), for the collapses of one [`Parts`] part;
/// the same rules as [`RoundTouches`]. Asking about another vertex panics.
#[derive(Debug)]
pub struct RoundTouchesPart<'a> {
    first: u32,
    touch: &'a mut [u32],
}

impl RoundTouchesPart<'_> {
    /// All the marks ([`RoundTouches::whole`]) cut like the vertices of `parts`, one piece per
    /// part, for collapses made part by part ([`Parts`]).
    pub fn split(&mut self, parts: &Parts) -> Vec<RoundTouchesPart<'_>> {
        debug_assert_eq!(self.first, 0, "only all the marks are cut into parts");
        let pieces = parts.split_vertices(self.touch).into_iter();
        pieces.map(|(first, touch)| RoundTouchesPart { first, touch }).collect()
    }

    /// [`RoundTouches::mark`].
    #[inline]
    pub fn mark(&mut self, x: u32, target: u32, wings: [u32; 2]) {
        let slot = &mut self.touch[x.wrapping_sub(self.first) as usize];
        *slot = marked(*slot, x, target, wings);
    }

    /// [`RoundTouches::still_legal`], on the part's connectivity.
    pub fn still_legal<T: HalfEdges + ?Sized>(&self, t: &T, c: HalfEdgeCollapse) -> bool {
        still_legal(self.touch[t.collapse_target(c).wrapping_sub(self.first) as usize], t, c)
    }

    /// [`RoundTouches::untouched`].
    #[inline]
    pub fn untouched(&self, x: u32) -> bool {
        self.touch[x.wrapping_sub(self.first) as usize] == UNTOUCHED
    }
}

/// A vertex's mark after `x` is touched by a collapse onto `target` with `wings`.
#[inline]
fn marked(mark: u32, x: u32, target: u32, wings: [u32; 2]) -> u32 {
    match mark {
        _ if x == target => RESHAPED,
        UNTOUCHED | WINGED if wings.contains(&x) => WINGED,
        _ if wings.contains(&x) => RESHAPED,
        UNTOUCHED => target,
        RESHAPED | WINGED => RESHAPED,
        _ => TOUCHED_TWICE,
    }
}

/// Whether `c` is still legal, given its target's mark (the rule in the module docs).
#[inline]
fn still_legal<T: HalfEdges + ?Sized>(target_mark: u32, t: &T, c: HalfEdgeCollapse) -> bool {
    match target_mark {
        UNTOUCHED => true,
        RESHAPED | WINGED | TOUCHED_TWICE => t.collapse_is_legal(c).is_ok(),
        gained => !t.neighbors(c.remove).any(|x| x == gained) || t.collapse_is_legal(c).is_ok(),
    }
}
