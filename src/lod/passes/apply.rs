//! The application step of a papers/000 §4 round: the chosen collapses are made one after
//! another, each only if it is still legal after the ones before it, so that the round as a
//! whole keeps the mesh manifold (docs/ALGORITHM.md, "The round as a whole stays manifold").
//!
//! ```text
//!   local minima:  actors pairwise non-adjacent, each chose on the round's starting state
//!     parts side by side:  part k makes, in order, the collapses inside it   (topology/parts.rs)
//!     then the rest, in order, on the whole mesh
//!   per collapse:  still legal? (RoundTouches, mostly without a walk) → mark u's neighbours,
//!                  collapse, u leaves R
//! ```
//! Collapses inside different parts touch disjoint ids, so making the parts side by side
//! leaves the same mesh as making them part after part, and the order (part 0's, part 1's, …,
//! then the rest, each in vertex order) does not depend on the thread count.

use std::sync::atomic::AtomicU32;

use rayon::prelude::*;

use crate::mesh::{constraints, Mesh};
use crate::topology::INVALID;
use crate::topology::{HalfEdgeCollapse, HalfEdges, HalfEdgesMut, Parts, RoundTouches, RoundTouchesPart, TopologyPart};

/// Where a collapse is made: one part of the connectivity, or the whole mesh (with its
/// wedges).
pub(crate) trait Collapsible {
    /// The connectivity the legality checks read.
    type Topo: HalfEdges + ?Sized;
    /// The connectivity.
    fn topo(&self) -> &Self::Topo;
    /// Makes a collapse the caller has checked.
    fn make(&mut self, c: HalfEdgeCollapse);
}

impl<'a> Collapsible for TopologyPart<'a> {
    type Topo = TopologyPart<'a>;
    fn topo(&self) -> &Self::Topo {
        self
    }
    #[inline]
    fn make(&mut self, c: HalfEdgeCollapse) {
        self.collapse(c);
    }
}

impl Collapsible for Mesh {
    type Topo = crate::topology::Topology;
    fn topo(&self) -> &Self::Topo {
        &self.topology
    }
    #[inline]
    fn make(&mut self, c: HalfEdgeCollapse) {
        constraints::collapse_with_wedges(self, c);
    }
}

/// The per-vertex state the application writes, for the vertices from `first` on (a part's
/// range, or all of them), and what it did.
pub(crate) struct Applying<'a> {
    first: u32,
    /// Whether a vertex is in R (a removed vertex leaves it).
    in_r: &'a mut [bool],
    /// Whether a vertex was removed this round.
    removed_now: &'a mut [bool],
    /// The local-minima blocker, forgotten where a fan changes.
    blocker: &'a mut [AtomicU32],
    touches: RoundTouchesPart<'a>,
    /// Vertices touched for the first time this round, in the order met.
    pub dirtied: Vec<u32>,
    /// Every neighbour of a removed vertex, when asked for (the collapses outside the parts,
    /// whose vertices' parts are worked out again).
    pub seen: Option<Vec<u32>>,
    /// Collapses made.
    pub collapsed: usize,
    /// Collapses no longer legal, left for a later round.
    pub deferred: usize,
}

impl<'a> Applying<'a> {
    /// The state of all vertices.
    pub fn whole(
        in_r: &'a mut [bool],
        removed_now: &'a mut [bool],
        blocker: &'a mut [AtomicU32],
        touches: &'a mut RoundTouches,
    ) -> Self {
        Self::new(0, in_r, removed_now, blocker, touches.whole())
    }

    fn new(
        first: u32,
        in_r: &'a mut [bool],
        removed_now: &'a mut [bool],
        blocker: &'a mut [AtomicU32],
        touches: RoundTouchesPart<'a>,
    ) -> Self {
        Self { first, in_r, removed_now, blocker, touches, dirtied: Vec::new(), seen: None, collapsed: 0, deferred: 0 }
    }

    /// All vertices' state ([`Applying::whole`]) cut like `parts`' vertices, one piece per
    /// part.
    fn split(&mut self, parts: &Parts) -> Vec<Applying<'_>> {
        let pieces = parts
            .split_vertices(self.in_r)
            .into_iter()
            .zip(parts.split_vertices(self.removed_now))
            .zip(parts.split_vertices(self.blocker))
            .zip(self.touches.split(parts));
        pieces.map(|((((first, i), (_, r)), (_, b)), t)| Applying::new(first, i, r, b, t)).collect()
    }

    #[inline]
    fn at(&self, v: u32) -> usize {
        v.wrapping_sub(self.first) as usize
    }

    /// Whether collapse `c` of an actor, chosen on the round's starting state, is still legal
    /// after the collapses made so far (`full`: walk the whole condition; otherwise the
    /// [`RoundTouches`] rule, which says the same, mostly without walking).
    pub fn still_legal<T: HalfEdges + ?Sized>(&self, t: &T, c: HalfEdgeCollapse, full: bool) -> bool {
        if full {
            return t.collapse_is_legal(c).is_ok();
        }
        let legal = self.touches.still_legal(t, c);
        // Unit-test builds check the shortcut against the whole condition.
        #[cfg(test)]
        assert_eq!(legal, t.collapse_is_legal(c).is_ok(), "collapse of {}", c.remove);
        legal
    }

    /// Records collapse `c` (u → target) as about to be made: u's neighbours gain the target
    /// (their fans and the target's change; [`RoundTouches`]).
    pub fn touch<T: HalfEdges + ?Sized>(&mut self, t: &T, c: HalfEdgeCollapse) {
        let (target, wings) = (t.collapse_target(c), t.wings(c));
        for w in t.neighbors(c.remove) {
            if self.touches.untouched(w) {
                let i = self.at(w);
                *self.blocker[i].get_mut() = INVALID;
                self.dirtied.push(w);
            }
            self.touches.mark(w, target, wings);
            if let Some(seen) = &mut self.seen {
                seen.push(w);
            }
        }
    }

    /// Records that u has gone.
    pub fn removed(&mut self, u: u32) {
        let i = self.at(u);
        self.in_r[i] = false;
        self.removed_now[i] = true;
        self.collapsed += 1;
    }

    /// Makes the actors' collapses `list` (removed vertex, collapse) in order, each that is
    /// still legal.
    pub fn apply<E: Collapsible + ?Sized>(&mut self, e: &mut E, list: &[HalfEdgeCollapse], full: bool) {
        for &c in list {
            if !self.still_legal(e.topo(), c, full) {
                self.deferred += 1;
                continue;
            }
            self.touch(e.topo(), c);
            e.make(c);
            self.removed(c.remove);
        }
    }
}

/// Makes the actors' collapses `inner[k]` on part k, the parts side by side when there is
/// enough to share (the result is the same either way), then `rest` on the whole mesh with
/// `whole` (all vertices' state), and works out again which vertices the latter touched are
/// inner. Returns what each part did; what the rest did is in `whole`.
pub(crate) fn apply_in_parts(
    mesh: &mut Mesh,
    parts: &mut Parts,
    inner: &[Vec<HalfEdgeCollapse>],
    rest: &[HalfEdgeCollapse],
    full: bool,
    whole: &mut Applying<'_>,
    parallel_min: usize,
) -> Vec<Applied> {
    let done = {
        let work: Vec<_> = parts.split(&mut mesh.topology).into_iter().zip(whole.split(parts)).zip(inner).collect();
        let run = |((mut piece, mut state), list): ((TopologyPart<'_>, Applying<'_>), &Vec<HalfEdgeCollapse>)| {
            state.apply(&mut piece, list, full);
            Applied::from(state)
        };
        if inner.iter().map(Vec::len).sum::<usize>() >= parallel_min {
            work.into_par_iter().map(run).collect()
        } else {
            work.into_iter().map(run).collect()
        }
    };
    whole.seen = Some(Vec::new());
    whole.apply(mesh, rest, full);
    if let Some(seen) = whole.seen.take() {
        parts.refresh(&mesh.topology, &seen, parallel_min);
    }
    done
}

/// What one piece of the application did ([`Applying`]'s results).
pub(crate) struct Applied {
    /// [`Applying::dirtied`].
    pub dirtied: Vec<u32>,
    /// [`Applying::collapsed`].
    pub collapsed: usize,
    /// [`Applying::deferred`].
    pub deferred: usize,
}

impl From<Applying<'_>> for Applied {
    fn from(a: Applying<'_>) -> Self {
        Self { dirtied: a.dirtied, collapsed: a.collapsed, deferred: a.deferred }
    }
}
