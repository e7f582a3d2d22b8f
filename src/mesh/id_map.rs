//! [`IdMap`]: a map from a mesh's element ids to other ids, held only where it is not the
//! identity: the input element behind each vertex and face ([`super::Mesh::vertex_source`],
//! [`super::Mesh::face_source`]) and each wedge's vertex ([`super::Wedges::vertex_of`]). A
//! clean input built in file order keeps its ids, and a mesh without seams has a wedge per
//! vertex; the runtime then carries no 16 bytes per vertex of maps that say
//! `i ↦ i` (docs/BENCHMARKS.md, "Memory"). The input maps ([`IdMap::shifts`]) are also kept as
//! runs of `i ↦ i + k` where that is smaller: a file whose loader dropped a few unreferenced
//! vertices maps every vertex after each to its input id plus the count dropped before it.
//!
//! ```text
//!   ids   0 1 2 4 5 6 7 9 10 11      runs (start, shift): (0, +0) (3, +1) (7, +2)
//!   get(8) = 8 + 2 = 10              the run holding 8 starts at 7
//! ```

/// A map from `0..len` to input ids; no storage when it is the identity.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct IdMap {
    /// Empty for the identity or when `runs` holds the map.
    map: Vec<u32>,
    /// (first element, shift): from the first element on, `i ↦ i + shift` (wrapping), until
    /// the next run; empty unless the map is held this way.
    runs: Vec<[u32; 2]>,
    len: usize,
}

impl IdMap {
    /// The identity on `0..len` (nothing stored).
    pub fn identity(len: usize) -> Self {
        Self { len, ..Self::default() }
    }

    /// The map `i ↦ ids[i]`, stored only if it is not the identity. Reads are an index.
    pub fn new(ids: Vec<u32>) -> Self {
        let len = ids.len();
        let identity = ids.iter().enumerate().all(|(i, &s)| s as usize == i);
        Self { map: if identity { Vec::new() } else { ids }, runs: Vec::new(), len }
    }

    /// [`IdMap::new`], or runs of shifted ids where fewer than a sixteenth of the elements
    /// start a run (each read is then a binary search over the runs): for maps that are mostly
    /// the identity with a few gaps, such as a file's vertices after unreferenced ones were
    /// dropped. The same reads either way.
    pub fn shifts(ids: Vec<u32>) -> Self {
        let shift = |i: usize| ids[i].wrapping_sub(i as u32);
        let mut runs: Vec<[u32; 2]> = Vec::new();
        for i in 0..ids.len() {
            if runs.last().is_none_or(|r| r[1] != shift(i)) {
                if 16 * (runs.len() + 1) > ids.len() {
                    return Self::new(ids);
                }
                runs.push([i as u32, shift(i)]);
            }
        }
        if runs.len() <= 1 && runs.first().is_none_or(|r| r[1] == 0) {
            return Self::identity(ids.len());
        }
        runs.shrink_to_fit();
        Self { map: Vec::new(), runs, len: ids.len() }
    }

    /// The id element `i` maps to.
    #[inline]
    pub fn get(&self, i: usize) -> u32 {
        debug_assert!(i < self.len, "element {i} of {}", self.len);
        if !self.map.is_empty() {
            self.map[i]
        } else if self.runs.is_empty() {
            i as u32
        } else {
            let k = self.runs.partition_point(|r| r[0] as usize <= i) - 1;
            (i as u32).wrapping_add(self.runs[k][1])
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the map has no elements.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether every element keeps its input id (nothing stored).
    pub fn is_identity(&self) -> bool {
        self.map.is_empty() && self.runs.is_empty()
    }

    /// The ids in element order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = u32> + '_ {
        (0..self.len).map(|i| self.get(i))
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.map.capacity() * 4 + self.runs.capacity() * 8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_is_not_stored_and_reads_the_same() {
        let id = IdMap::new(vec![0, 1, 2, 3]);
        assert!(id.is_identity());
        assert_eq!(id.bytes(), 0);
        assert_eq!(id.iter().collect::<Vec<_>>(), [0, 1, 2, 3]);
        let p = IdMap::new(vec![2, 0, 1, 3]);
        assert!(!p.is_identity());
        assert_eq!(p.bytes(), 16);
        assert_eq!((p.len(), p.get(0), p.get(3)), (4, 2, 3));
        assert_ne!(id, p);
        assert_eq!(IdMap::new(Vec::new()), IdMap::default());
        assert_eq!(IdMap::identity(4), id);
    }

    #[test]
    fn gaps_are_kept_as_runs_and_read_the_same() {
        // 999 elements, input ids with three gaps (ids 10, 500..503 and 900 dropped).
        let ids: Vec<u32> = (0..1004u32).filter(|&s| s != 10 && !(500..503).contains(&s) && s != 900).collect();
        assert_eq!(ids.len(), 999);
        let m = IdMap::shifts(ids.clone());
        assert!(!m.is_identity());
        assert_eq!(m.bytes(), 4 * 8, "four runs");
        assert!(m.iter().eq(ids.iter().copied()));
        assert_eq!(m, IdMap::shifts(ids.clone()));
        // A permutation has a run per element: kept dense.
        let perm: Vec<u32> = (0..64u32).rev().collect();
        let p = IdMap::shifts(perm.clone());
        assert_eq!(p.bytes(), 64 * 4);
        assert!(p.iter().eq(perm.iter().copied()));
        // The identity, and a shift of everything (one run), and downward shifts.
        assert!(IdMap::shifts((0..50).collect()).is_identity());
        let up = IdMap::shifts((7..57).collect());
        assert_eq!((up.bytes(), up.get(0), up.get(49)), (8, 7, 56));
        let down: Vec<u32> = (0..40).chain(20..60).collect();
        assert!(IdMap::shifts(down.clone()).iter().eq(down.iter().copied()));
        assert_eq!(IdMap::shifts(Vec::new()), IdMap::default());
    }
}
