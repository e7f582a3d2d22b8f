//! A collapse record of the dynamic vertex hierarchy (papers/001 `consumedBy`), the plan a
//! collapse is recorded from, and the faces a record touches.

use super::Hierarchy;
use crate::topology::{HalfEdgeCollapse, Topology, INVALID};

/// Why a collapse cannot be recorded (so it is not performed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unrecordable {
    /// The removed vertex's corners do not fall into two runs of wedges, one per side of the
    /// edge, so the split could not give each corner its wedge back.
    Wedges,
    /// A face's chain is already 65,535 deep.
    Depth,
    /// The removed vertex has more than [`MAX_ARC`] faces besides the edge's: its record
    /// could not count them.
    Degree,
}

/// Most surviving faces a recorded collapse's removed vertex may have (15 bits of
/// [`CollapseRecord`]; the sixteenth says which side of the edge the record names).
pub const MAX_ARC: usize = (1 << 15) - 1;

/// The top bit of `CollapseRecord::arc`: the u→v side is a border, `edge` is v→u.
pub(super) const EDGE_IS_VU: u16 = 1 << 15;

/// Why a split cannot happen now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unsplittable {
    /// The vertex is not collapsed.
    NotCollapsed,
    /// A later collapse still holds one of the record's faces.
    Buried,
}

/// Everything needed to put a collapsed vertex back. Fixed size; the stack entries of its
/// touched faces live in the hierarchy's arena.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollapseRecord {
    /// consumedBy: the vertex u merged into (`INVALID` when u is not collapsed).
    pub target: u32,
    /// The u→v half-edge before the collapse, or v→u where u→v is a border side (then the
    /// top bit of `arc` is set). The other half is its twin, which the removed face keeps
    /// (see [`CollapseRecord::halves`]): one half-edge stored, not two.
    pub(super) edge: u32,
    /// First of u's surviving outgoing half-edges, counter-clockwise after u→v.
    pub arc_start: u32,
    /// How many surviving faces u had (low 15 bits), and `EDGE_IS_VU`.
    pub(super) arc: u16,
    /// The first `wedge_switch` arc corners had u's wedge on the u→v side, the rest the other.
    pub wedge_switch: u16,
    pub(super) slab: u32,
    pub(super) touched: u16,
    /// The largest counter among its faces right after the collapse. Only a push (which
    /// buries the record) or its own split's pop changes those counters, and a record buried
    /// and uncovered again finds them as they were: so it is the chain depth whenever the
    /// record is on top. (The record is 24 bytes: checked below.)
    pub(super) depth: u16,
}

const _: () = assert!(std::mem::size_of::<CollapseRecord>() == 24);

impl Default for CollapseRecord {
    fn default() -> Self {
        Self {
            target: INVALID,
            edge: INVALID,
            arc_start: INVALID,
            arc: 0,
            wedge_switch: 0,
            slab: 0,
            touched: 0,
            depth: 0,
        }
    }
}

impl CollapseRecord {
    /// The outside half-edges of the removed faces as they were before the collapse: x1 (a→v),
    /// y1 (u→a), x2 (b→u), y2 (v→b); `INVALID` on borders. Read from the removed faces'
    /// twin entries, which the collapse leaves as they were and nothing writes while the
    /// faces are removed, so it holds for any active record.
    pub fn outer(&self, t: &Topology) -> [u32; 4] {
        let (hu, hv) = self.halves(t);
        outer_half_edges(t, hu, hv)
    }

    /// The u→v and v→u half-edges before the collapse (`INVALID` for a border side). They
    /// name the removed faces and the corner of u and v in each. The stored half's twin entry
    /// is read back: a removed face's twins are left as they were and nothing writes them
    /// while it is removed, so this holds for any active record.
    pub fn halves(&self, t: &Topology) -> (u32, u32) {
        if self.edge == INVALID {
            (INVALID, INVALID)
        } else if self.arc & EDGE_IS_VU != 0 {
            (INVALID, self.edge)
        } else {
            (self.edge, t.twin[self.edge as usize])
        }
    }

    /// How many surviving faces u had.
    pub fn arc_len(&self) -> u16 {
        self.arc & !EDGE_IS_VU
    }

    /// How many faces the collapse touched (stack entries it keeps).
    pub fn touched_count(&self) -> u16 {
        self.touched
    }
}

/// The twins of the half-edges of the faces on `hu` and `hv` other than the edge itself:
/// x1 (a→v), y1 (u→a), x2 (b→u), y2 (v→b); `INVALID` for a border or a missing face.
pub(super) fn outer_half_edges(t: &Topology, hu: u32, hv: u32) -> [u32; 4] {
    let tw = |g: u32| if g == INVALID { INVALID } else { t.twin[g as usize] };
    let nx = |g: u32| if g == INVALID { INVALID } else { Topology::next(g) };
    let pv = |g: u32| if g == INVALID { INVALID } else { Topology::prev(g) };
    [tw(nx(hu)), tw(pv(hu)), tw(nx(hv)), tw(pv(hv))]
}

/// The faces a collapse edits, each once, in the order its stack entries are kept: the
/// removed faces (on `hu`, `hv`), the faces across the wing edges (of x1 = a→v and y2 = v→b),
/// then the arc (u's surviving faces, `arc_len` of them counter-clockwise from `arc_start`).
/// Reads the same before the collapse and after it while the record is on top: the collapse
/// leaves the removed faces' twin entries as they were, and the arc is still a fan.
pub(super) fn touched_faces(
    t: &Topology,
    hu: u32,
    hv: u32,
    arc_start: u32,
    arc_len: u16,
) -> impl Iterator<Item = u32> + '_ {
    let outer = outer_half_edges(t, hu, hv);
    let mut fixed = [INVALID; 4];
    let mut k = 0;
    for f in [hu, hv, outer[0], outer[3]].into_iter().filter(|&g| g != INVALID).map(|g| g / 3) {
        if !fixed[..k].contains(&f) {
            fixed[k] = f;
            k += 1;
        }
    }
    let arc = std::iter::successors((arc_len > 0).then_some(arc_start), |&g| Some(t.twin[Topology::prev(g) as usize]))
        .take(arc_len as usize)
        .map(|g| g / 3)
        .filter(move |f| !fixed[..k].contains(f));
    fixed.into_iter().take(k).chain(arc)
}

/// A collapse worked out but not yet performed: what it will touch and how to undo it.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The collapse.
    pub collapse: HalfEdgeCollapse,
    /// The vertex that stays.
    pub target: u32,
    pub(super) touched: Faces,
    pub(super) record: CollapseRecord,
}

impl Plan {
    /// Faces the collapse edits, without repeats, in the order its stack entries will be kept.
    pub fn touched(&self) -> &[u32] {
        self.touched.as_slice()
    }

    /// The deepest chain among the touched faces after this collapse.
    pub fn depth_after(&self, h: &Hierarchy) -> u16 {
        self.touched().iter().map(|&f| h.counter[f as usize]).max().unwrap_or(0) + 1
    }
}

/// Faces a plan touches that fit inline: a removed vertex of valence 22 (two removed faces,
/// two across the wings, the rest of its fan). Plans are made by the dozen per frame (each
/// rebalancing attempt tries every neighbour), so they do not allocate below that.
const INLINE_FACES: usize = 24;

/// A short list of faces, inline up to [`INLINE_FACES`] and on the heap past that.
#[derive(Debug, Clone)]
pub(super) enum Faces {
    Inline(u8, [u32; INLINE_FACES]),
    Heap(Vec<u32>),
}

impl Faces {
    pub(super) fn collect(faces: impl Iterator<Item = u32>) -> Self {
        let mut out = Faces::Inline(0, [INVALID; INLINE_FACES]);
        for f in faces {
            match &mut out {
                Faces::Inline(len, inline) if (*len as usize) < INLINE_FACES => {
                    inline[*len as usize] = f;
                    *len += 1;
                }
                Faces::Inline(_, inline) => {
                    let mut heap = inline.to_vec();
                    heap.push(f);
                    out = Faces::Heap(heap);
                }
                Faces::Heap(heap) => heap.push(f),
            }
        }
        out
    }

    pub(super) fn as_slice(&self) -> &[u32] {
        match self {
            Faces::Inline(len, inline) => &inline[..*len as usize],
            Faces::Heap(heap) => heap,
        }
    }
}

impl PartialEq for Faces {
    fn eq(&self, other: &Self) -> bool {
        self.as_slice() == other.as_slice()
    }
}
