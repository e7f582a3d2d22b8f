//! The renderer's view of the runtime: stable triangle index buffers over attribute wedges,
//! one part per primitive (material), each with its own slots and changed ranges.
//!
//! ```text
//!   slot:   0    1    2    3    4   ...      a face keeps its slot while it is live;
//!         [abc][def][---][ghi][jkl]          a freed slot holds a degenerate triangle and is
//!                     ^ free                 reused lowest-first by the next face that appears
//!   changed_ranges(): merged runs of slots written since the last frame → upload only those
//!
//!   compaction, when fewer than half the slots are live (and the part is not tiny):
//!         [abc][---][---][def][---][ghi]  →  [abc][ghi][def]      the tail's live faces fill
//!                                                                  the holes below, the tail is cut
//! ```
//! Faces never change primitive (a collapse removes two faces and re-points the others), so
//! each primitive's part holds only its own faces and is drawn with its own material:
//! one draw call per part, as a renderer draws a glTF mesh's primitives. A part never holds
//! more slots than its primitive had input triangles. Single-primitive meshes (every scan)
//! have one part.
//!
//! Compaction keeps a part within twice its live triangle count, so a renderer draws and
//! holds what is on screen, not the original mesh's worth of degenerate slots. It moves at
//! most as many faces as there are live triangles and happens only after at least that many
//! slots were freed since the last one, so its cost is amortised over the frees that caused
//! it. Moved faces' new slots are reported like any other write; the renderer draws
//! `triangles().len()` triangles of each part. With compaction off ([`IndexBuffer::new`]'s
//! `compact`) a face never changes slot while it is live, and no part shrinks.
//! Indices are wedge ids ([`crate::mesh::Wedges`]): one renderer vertex per (position, normal,
//! uv), so seams render correctly at every level of detail. A half-edge collapse moves no
//! vertex, so the vertex buffer ([`crate::Mesh::wedge_positions`] and the wedges' attributes)
//! is uploaded once and never changes; only these index buffers do.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::ops::Range;

use crate::mesh::Mesh;
use crate::topology::{HalfEdges, INVALID};

/// Slots closer than this are reported as one range (one upload call beats two tiny ones).
const MERGE_GAP: u32 = 4;

/// Parts of fewer slots than this are never compacted (nothing worth saving).
const MIN_COMPACT_SLOTS: usize = 1024;

/// The live triangles in stable slots, one [`IndexPart`] per primitive of the mesh, with
/// dirty tracking.
#[derive(Debug, Clone)]
pub struct IndexBuffer {
    parts: Vec<IndexPart>,
    /// Slot of each face in its primitive's part, or `INVALID` for a face that is not live.
    slot_of_face: Vec<u32>,
    compact: bool,
}

/// One primitive's triangles: its stable slots, their free list and what the last sync wrote.
#[derive(Debug, Clone, Default)]
pub struct IndexPart {
    triangles: Vec<[u32; 3]>,
    /// The face in each slot, or `INVALID` for a free one.
    face_of_slot: Vec<u32>,
    free: BinaryHeap<Reverse<u32>>,
    dirty: Vec<u32>,
    ranges: Vec<Range<u32>>,
    live: usize,
}

impl IndexBuffer {
    /// Every live face of `mesh` in face order, each primitive's from slot 0 of its part.
    /// `compact`: whether a part compacts itself when fewer than half its slots are live (see
    /// the module docs).
    pub fn new(mesh: &Mesh, compact: bool) -> Self {
        let t = &mesh.topology;
        let mut counts = vec![0usize; mesh.primitives.len().max(1)];
        for f in (0..t.face_slots()).filter(|&f| t.is_face_live(f as u32)) {
            counts[mesh.primitive_of(f) as usize] += 1;
        }
        let mut parts: Vec<IndexPart> = counts
            .iter()
            .map(|&n| IndexPart {
                triangles: Vec::with_capacity(n),
                face_of_slot: Vec::with_capacity(n),
                ..Default::default()
            })
            .collect();
        let mut slot_of_face = vec![INVALID; t.face_slots()];
        for f in 0..t.face_slots() as u32 {
            if t.is_face_live(f) {
                let part = &mut parts[mesh.primitive_of(f as usize) as usize];
                slot_of_face[f as usize] = part.triangles.len() as u32;
                part.triangles.push(wedges_of(mesh, f));
                part.face_of_slot.push(f);
            }
        }
        for part in &mut parts {
            part.live = part.triangles.len();
            if part.live > 0 {
                part.ranges.push(0..part.live as u32);
            }
        }
        Self { parts, slot_of_face, compact }
    }

    /// One part per primitive, in the order of [`Mesh::primitives`] (whose `material` says
    /// what to draw it with).
    pub fn parts(&self) -> &[IndexPart] {
        &self.parts
    }

    /// Live (non-degenerate) triangles, over every part.
    pub fn live(&self) -> usize {
        self.parts.iter().map(IndexPart::live).sum()
    }

    /// Slot of face `f` in the part of its primitive ([`Mesh::primitive_of`]), or `INVALID`
    /// when the face is not live.
    pub fn slot_of_face(&self, f: u32) -> u32 {
        self.slot_of_face[f as usize]
    }

    /// Slots written by the last sync, over every part.
    pub fn changed_triangles(&self) -> usize {
        self.parts.iter().map(IndexPart::changed_triangles).sum()
    }

    /// Ranges to upload after the last sync, over every part.
    pub fn changed_range_count(&self) -> usize {
        self.parts.iter().map(|p| p.changed_ranges().len()).sum()
    }

    /// Brings the parts up to date for the faces in `changed` (any order, no repeats needed).
    pub fn sync(&mut self, mesh: &Mesh, changed: &[u32]) {
        for part in &mut self.parts {
            part.dirty.clear();
        }
        let t = &mesh.topology;
        // Free first, so faces appearing in the same frame can reuse the slots.
        for &f in changed {
            let s = self.slot_of_face[f as usize];
            if s != INVALID && !t.is_face_live(f) {
                self.parts[mesh.primitive_of(f as usize) as usize].free_slot(s);
                self.slot_of_face[f as usize] = INVALID;
            }
        }
        for &f in changed {
            if t.is_face_live(f) {
                let part = &mut self.parts[mesh.primitive_of(f as usize) as usize];
                part.place(f, wedges_of(mesh, f), &mut self.slot_of_face[f as usize]);
            }
        }
        for part in &mut self.parts {
            if self.compact && part.triangles.len() >= MIN_COMPACT_SLOTS && 2 * part.live < part.triangles.len() {
                part.compact_now(&mut self.slot_of_face);
            }
            part.merge_ranges();
        }
    }

    /// Bytes held, per structure.
    pub fn memory(&self) -> Vec<(&'static str, usize)> {
        let sum = |f: fn(&IndexPart) -> usize| self.parts.iter().map(f).sum::<usize>();
        vec![
            ("index_buffer.triangles", sum(|p| p.triangles.capacity() * 12)),
            ("index_buffer.slot_maps", self.slot_of_face.capacity() * 4 + sum(|p| p.face_of_slot.capacity() * 4)),
            (
                "index_buffer.free_and_dirty",
                sum(|p| p.free.capacity() * 4 + p.dirty.capacity() * 4 + p.ranges.capacity() * 8),
            ),
        ]
    }
}

impl IndexPart {
    /// The part's buffer: wedge ids per triangle slot; freed slots are degenerate (`[w, w, w]`).
    /// Draw all of it (`triangles().len()` triangles).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Slots `range` in input vertex ids ([`Mesh::wedge_source`]) instead of wedge ids, for a
    /// renderer that draws its own vertex buffer: upload these for each of
    /// [`IndexPart::changed_ranges`]. Freed slots stay degenerate.
    pub fn source_triangles<'a>(
        &'a self,
        mesh: &'a Mesh,
        range: Range<u32>,
    ) -> impl ExactSizeIterator<Item = [u32; 3]> + 'a {
        self.triangles[range.start as usize..range.end as usize].iter().map(|t| t.map(|w| mesh.wedge_source(w)))
    }

    /// The face in `slot` (`None` for a free slot or one past the end): for picking, with
    /// [`Mesh::face_source`] naming the input triangle behind it.
    pub fn face_in_slot(&self, slot: u32) -> Option<u32> {
        self.face_of_slot.get(slot as usize).copied().filter(|&f| f != INVALID)
    }

    /// Live (non-degenerate) triangles in this part.
    pub fn live(&self) -> usize {
        self.live
    }

    /// Slot ranges written by the last [`IndexBuffer::sync`] (all slots after `new`), merged
    /// across gaps of a few slots.
    pub fn changed_ranges(&self) -> &[Range<u32>] {
        &self.ranges
    }

    /// Slots written by the last sync.
    pub fn changed_triangles(&self) -> usize {
        self.dirty.len()
    }

    /// Frees slot `s`: a degenerate triangle, reused lowest-first.
    fn free_slot(&mut self, s: u32) {
        let w = self.triangles[s as usize][0];
        self.triangles[s as usize] = [w, w, w];
        self.face_of_slot[s as usize] = INVALID;
        self.free.push(Reverse(s));
        self.dirty.push(s);
        self.live -= 1;
    }

    /// Writes live face `f`'s triangle `tri` into its slot `*slot`, taking the lowest free
    /// slot (or a new one) when it has none.
    fn place(&mut self, f: u32, tri: [u32; 3], slot: &mut u32) {
        let mut s = *slot;
        if s == INVALID {
            s = match self.free.pop() {
                Some(Reverse(s)) => s,
                None => {
                    self.triangles.push(tri);
                    self.face_of_slot.push(INVALID);
                    self.triangles.len() as u32 - 1
                }
            };
            *slot = s;
            self.face_of_slot[s as usize] = f;
            self.live += 1;
        } else if self.triangles[s as usize] == tri {
            return;
        }
        self.triangles[s as usize] = tri;
        self.dirty.push(s);
    }

    /// Moves the live faces at or above slot `live` into the free slots below it, in slot
    /// order, and cuts the part to `live` slots (none free after).
    fn compact_now(&mut self, slot_of_face: &mut [u32]) {
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
            slot_of_face[f as usize] = hole as u32;
            self.dirty.push(hole as u32);
        }
        self.triangles.truncate(live);
        self.face_of_slot.truncate(live);
        self.triangles.shrink_to_fit();
        self.face_of_slot.shrink_to_fit();
        self.free = BinaryHeap::new();
        self.dirty.retain(|&s| (s as usize) < live);
    }

    /// Sorts the slots written this sync and merges them into upload ranges.
    fn merge_ranges(&mut self) {
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
}

fn wedges_of(mesh: &Mesh, f: u32) -> [u32; 3] {
    [0, 1, 2].map(|k| mesh.corner_wedge(3 * f + k))
}
