//! The renderer's view of the runtime: a stable triangle index buffer over attribute wedges.
//!
//! ```text
//!   slot:   0    1    2    3    4   ...      a face keeps its slot while it is live;
//!         [abc][def][---][ghi][jkl]          a freed slot holds a degenerate triangle and is
//!                     ^ free                 reused lowest-first by the next face that appears
//!   changed_ranges(): merged runs of slots written since the last frame → upload only those
//! ```
//! Indices are wedge ids ([`crate::mesh::Wedges`]): one renderer vertex per (position, normal,
//! uv), so seams render correctly at every level of detail.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::ops::Range;

use crate::mesh::Mesh;
use crate::topology::INVALID;

/// Slots closer than this are reported as one range (one upload call beats two tiny ones).
const MERGE_GAP: u32 = 4;

/// A stable index buffer with dirty tracking.
#[derive(Debug, Clone)]
pub struct IndexBuffer {
    triangles: Vec<[u32; 3]>,
    slot_of_face: Vec<u32>,
    free: BinaryHeap<Reverse<u32>>,
    dirty: Vec<u32>,
    ranges: Vec<Range<u32>>,
    live: usize,
}

impl IndexBuffer {
    /// Every live face of `mesh` in face order, slots 0, 1, 2, …
    pub fn new(mesh: &Mesh) -> Self {
        let t = &mesh.topology;
        let mut slot_of_face = vec![INVALID; t.face_slots()];
        let mut triangles = Vec::with_capacity(t.live_face_count());
        for f in 0..t.face_slots() as u32 {
            if t.is_face_live(f) {
                slot_of_face[f as usize] = triangles.len() as u32;
                triangles.push(wedges_of(mesh, f));
            }
        }
        let live = triangles.len();
        let mut ranges = Vec::new();
        if live > 0 {
            ranges.push(0..live as u32);
        }
        Self { triangles, slot_of_face, free: BinaryHeap::new(), dirty: Vec::new(), ranges, live }
    }

    /// The buffer: wedge ids per triangle slot; freed slots are degenerate (`[w, w, w]`).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
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
                        self.triangles.len() as u32 - 1
                    }
                };
                self.slot_of_face[f as usize] = s;
                self.live += 1;
            } else if self.triangles[s as usize] == tri {
                continue;
            }
            self.triangles[s as usize] = tri;
            self.dirty.push(s);
        }
        self.dirty.sort_unstable();
        self.dirty.dedup();
        self.ranges.clear();
        for &s in &self.dirty {
            match self.ranges.last_mut() {
                Some(r) if s <= r.end + MERGE_GAP => r.end = s + 1,
                _ => self.ranges.push(s..s + 1),
            }
        }
    }

    /// Slots written by the last sync.
    pub fn changed_triangles(&self) -> usize {
        self.dirty.len()
    }

    /// Bytes held, per structure.
    pub fn memory(&self) -> Vec<(&'static str, usize)> {
        vec![
            ("index_buffer.triangles", self.triangles.capacity() * 12),
            ("index_buffer.slot_of_face", self.slot_of_face.capacity() * 4),
            ("index_buffer.free_and_dirty", self.free.capacity() * 4 + self.dirty.capacity() * 4),
        ]
    }
}

fn wedges_of(mesh: &Mesh, f: u32) -> [u32; 3] {
    let c = &mesh.wedges.corner;
    let h = 3 * f as usize;
    [c[h], c[h + 1], c[h + 2]]
}
