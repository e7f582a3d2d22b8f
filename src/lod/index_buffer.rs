//! The renderer's view of the runtime: a stable triangle index buffer over attribute wedges.
//!
//! ```text
//!   slot:   0    1    2    3    4   ...      a face keeps its slot while it is live;
//!         [abc][def][---][ghi][jkl]          a freed slot holds a degenerate triangle and is
//!                     ^ free                 reused lowest-first by the next face that appears
//!   changed_ranges(): merged runs of slots written since the last frame → upload only those
//!
//!   compaction, when fewer than half the slots are live (and the buffer is not tiny):
//!         [abc][---][---][def][---][ghi]  →  [abc][ghi][def]      the tail's live faces fill
//!                                                                  the holes below, the tail is cut
//! ```
//! Compaction keeps the buffer within twice the live triangle count, so a renderer draws and
//! holds what is on screen, not the original mesh's worth of degenerate slots. It moves at
//! most as many faces as there are live triangles and happens only after at least that many
//! slots were freed since the last one, so its cost is amortised over the frees that caused
//! it. Moved faces' new slots are reported like any other write; the renderer draws
//! `triangles().len()` triangles. With compaction off ([`IndexBuffer::new`]'s `compact`) a
//! face never changes slot while it is live, and the buffer never shrinks.
//! Indices are wedge ids ([`crate::mesh::Wedges`]): one renderer vertex per (position, normal,
//! uv), so seams render correctly at every level of detail.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::ops::Range;

use crate::mesh::Mesh;
use crate::topology::{HalfEdges, INVALID};

/// Slots closer than this are reported as one range (one upload call beats two tiny ones).
const MERGE_GAP: u32 = 4;

/// Buffers of fewer slots than this are never compacted (nothing worth saving).
const MIN_COMPACT_SLOTS: usize = 1024;

/// A stable index buffer with dirty tracking.
#[derive(Debug, Clone)]
pub struct IndexBuffer {
    triangles: Vec<[u32; 3]>,
    slot_of_face: Vec<u32>,
    /// The face in each slot, or `INVALID` for a free one.
    face_of_slot: Vec<u32>,
    compact: bool,
    free: BinaryHeap<Reverse<u32>>,
    dirty: Vec<u32>,
    ranges: Vec<Range<u32>>,
    live: usize,
}

impl IndexBuffer {
    /// Every live face of `mesh` in face order, slots 0, 1, 2, … `compact`: whether the buffer
    /// compacts itself when fewer than half its slots are live (see the module docs).
    pub fn new(mesh: &Mesh, compact: bool) -> Self {
        let t = &mesh.topology;
        let mut slot_of_face = vec![INVALID; t.face_slots()];
        let mut triangles = Vec::with_capacity(t.live_face_count());
        let mut face_of_slot = Vec::with_capacity(t.live_face_count());
        for f in 0..t.face_slots() as u32 {
            if t.is_face_live(f) {
                slot_of_face[f as usize] = triangles.len() as u32;
                triangles.push(wedges_of(mesh, f));
                face_of_slot.push(f);
            }
        }
        let live = triangles.len();
        let mut ranges = Vec::new();
        if live > 0 {
            ranges.push(0..live as u32);
        }
        Self {
            triangles,
            slot_of_face,
            face_of_slot,
            compact,
            free: BinaryHeap::new(),
            dirty: Vec::new(),
            ranges,
            live,
        }
    }

    /// The buffer: wedge ids per triangle slot; freed slots are degenerate (`[w, w, w]`).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Slots `range` in input vertex ids ([`Mesh::wedge_source`]) instead of wedge ids, for a
    /// renderer that draws its own vertex buffer: upload these for each of
    /// [`IndexBuffer::changed_ranges`]. Freed slots stay degenerate.
    pub fn source_triangles<'a>(
        &'a self,
        mesh: &'a Mesh,
        range: Range<u32>,
    ) -> impl ExactSizeIterator<Item = [u32; 3]> + 'a {
        self.triangles[range.start as usize..range.end as usize].iter().map(|t| t.map(|w| mesh.wedge_source(w)))
    }

    /// Live (non-degenerate) triangles.
    pub fn live(&self) -> usize {
        self.live
    }

    /// Slot of face `f`, or `INVALID` when the face is not live.
    pub fn slot_of_face(&self, f: u32) -> u32 {
        self.slot_of_face[f as usize]
    }

    /// Triangle-slot ranges written by the last [`IndexBuffer::sync`] (all slots after `new`).
    pub fn changed_ranges(&self) -> &[Range<u32>] {
        &self.ranges
    }

    /// Brings the buffer up to date for the faces in `changed` (any order, no repeats needed).
    pub fn sync(&mut self, mesh: &Mesh, changed: &[u32]) {
        self.dirty.clear();
        let t = &mesh.topology;
        // Free first, so faces appearing in the same frame can reuse the slots.
        for &f in changed {
            let s = self.slot_of_face[f as usize];
            if s != INVALID && !t.is_face_live(f) {
                let w = self.triangles[s as usize][0];
                self.triangles[s as usize] = [w, w, w];
                self.slot_of_face[f as usize] = INVALID;
                self.face_of_slot[s as usize] = INVALID;
                self.free.push(Reverse(s));
                self.dirty.push(s);
                self.live -= 1;
            }
        }
        for &f in changed {
            if !t.is_face_live(f) {
                continue;
            }
            let tri = wedges_of(mesh, f);
            let mut s = self.slot_of_face[f as usize];
            if s == INVALID {
                s = match self.free.pop() {
                    Some(Reverse(s)) => s,
                    None => {
                        self.triangles.push(tri);
                        self.face_of_slot.push(INVALID);
                        self.triangles.len() as u32 - 1
                    }
                };
                self.slot_of_face[f as usize] = s;
                self.face_of_slot[s as usize] = f;
                self.live += 1;
            } else if self.triangles[s as usize] == tri {
                continue;
            }
            self.triangles[s as usize] = tri;
            self.dirty.push(s);
        }
        if self.compact && self.triangles.len() >= MIN_COMPACT_SLOTS && 2 * self.live < self.triangles.len() {
            self.compact_now();
        }
        self.dirty.sort_unstable();
        self.dirty.dedup();
        // A big frame (the first, a jump) must not pin its list's memory for the rest of the walk.
        if self.dirty.capacity() > 4 * self.dirty.len().max(MIN_COMPACT_SLOTS) {
            self.dirty.shrink_to(self.dirty.len().max(MIN_COMPACT_SLOTS));
        }
        self.ranges.clear();
        for &s in &self.dirty {
            match self.ranges.last_mut() {
                Some(r) if s <= r.end + MERGE_GAP => r.end = s + 1,
                _ => self.ranges.push(s..s + 1),
            }
        }
    }

    /// Moves the live faces at or above slot `live` into the free slots below it, in slot
    /// order, and cuts the buffer to `live` slots (none free after).
    fn compact_now(&mut self) {
        let live = self.live;
        let mut hole = 0;
        for s in live..self.triangles.len() {
            let f = self.face_of_slot[s];
            if f == INVALID {
                continue;
            }
            while self.face_of_slot[hole] != INVALID {
                hole += 1;
            }
            self.triangles[hole] = self.triangles[s];
            self.face_of_slot[hole] = f;
            self.slot_of_face[f as usize] = hole as u32;
            self.dirty.push(hole as u32);
        }
        self.triangles.truncate(live);
        self.face_of_slot.truncate(live);
        self.triangles.shrink_to_fit();
        self.face_of_slot.shrink_to_fit();
        self.free = BinaryHeap::new();
        self.dirty.retain(|&s| (s as usize) < live);
    }

    /// Slots written by the last sync.
    pub fn changed_triangles(&self) -> usize {
        self.dirty.len()
    }

    /// Bytes held, per structure.
    pub fn memory(&self) -> Vec<(&'static str, usize)> {
        vec![
            ("index_buffer.triangles", self.triangles.capacity() * 12),
            ("index_buffer.slot_maps", self.slot_of_face.capacity() * 4 + self.face_of_slot.capacity() * 4),
            ("index_buffer.free_and_dirty", self.free.capacity() * 4 + self.dirty.capacity() * 4),
        ]
    }
}

fn wedges_of(mesh: &Mesh, f: u32) -> [u32; 3] {
    [0, 1, 2].map(|k| mesh.corner_wedge(3 * f + k))
}
