//! Half-edges grouped by the unordered vertex pair they join, in O(n): a counting sort by the
//! smaller endpoint, then a tiny sort inside each bucket (about three entries on average).
//!
//! ```text
//!   bucket[lo] = half-edges whose smaller endpoint is lo, ordered by (other endpoint, id)
//!   a group    = the run of one (lo, hi) pair: 1 entry = border, 2 = manifold, >2 = not
//! ```
//! This is the workhorse of both the connectivity build and the repairs: it replaces a
//! global sort or a hash map keyed by vertex pairs.

/// Half-edge ids grouped by unordered vertex pair.
pub struct EdgeGroups {
    offsets: Vec<u32>,
    entries: Vec<(u32, u32)>, // (other endpoint, half-edge)
}

impl EdgeGroups {
    /// Groups the half-edges of `faces` (half-edge `3f + c` runs from corner `c` to `c + 1`).
    /// Faces whose first vertex is `u32::MAX` are treated as removed and skipped.
    pub fn new(vertex_count: usize, faces: &[[u32; 3]]) -> Self {
        let mut offsets = vec![0u32; vertex_count + 1];
        for f in faces.iter().filter(|f| f[0] != u32::MAX) {
            for c in 0..3 {
                let (a, b) = (f[c], f[(c + 1) % 3]);
                offsets[a.min(b) as usize + 1] += 1;
            }
        }
        for i in 0..vertex_count {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut entries = vec![(0u32, 0u32); offsets[vertex_count] as usize];
        for (fi, f) in faces.iter().enumerate().filter(|(_, f)| f[0] != u32::MAX) {
            for c in 0..3 {
                let (a, b) = (f[c], f[(c + 1) % 3]);
                let slot = &mut fill[a.min(b) as usize];
                entries[*slot as usize] = (a.max(b), (3 * fi + c) as u32);
                *slot += 1;
            }
        }
        for v in 0..vertex_count {
            let s = &mut entries[offsets[v] as usize..offsets[v + 1] as usize];
            if s.len() > 1 {
                s.sort_unstable();
            }
        }
        Self { offsets, entries }
    }

    /// Calls `f(lo, hi, half_edges)` for every vertex pair, in (lo, hi) order. The half-edges
    /// of one group are in increasing id order.
    pub fn for_each(&self, mut f: impl FnMut(u32, u32, &[u32])) {
        let mut buf: Vec<u32> = Vec::with_capacity(8);
        for lo in 0..self.offsets.len() - 1 {
            let s = &self.entries[self.offsets[lo] as usize..self.offsets[lo + 1] as usize];
            let mut i = 0;
            while i < s.len() {
                let hi = s[i].0;
                let mut j = i;
                buf.clear();
                while j < s.len() && s[j].0 == hi {
                    buf.push(s[j].1);
                    j += 1;
                }
                f(lo as u32, hi, &buf);
                i = j;
            }
        }
    }
}
