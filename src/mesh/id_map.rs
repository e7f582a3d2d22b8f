//! [`IdMap`]: a map from a mesh's element ids to other ids, held only where it is not the
//! identity: the input element behind each vertex and face ([`super::Mesh::vertex_source`],
//! [`super::Mesh::face_source`]) and each wedge's vertex ([`super::Wedges::vertex_of`]). A
//! clean input built in file order keeps its ids, and a mesh without seams has a wedge per
//! vertex; the runtime then carries no 16 bytes per vertex of maps that say
//! `i ↦ i` (docs/BENCHMARKS.md, "Memory").

/// A map from `0..len` to input ids; no storage when it is the identity.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct IdMap {
    /// Empty for the identity.
    map: Vec<u32>,
    len: usize,
}

impl IdMap {
    /// The identity on `0..len` (nothing stored).
    pub fn identity(len: usize) -> Self {
        Self { map: Vec::new(), len }
    }

    /// The map `i ↦ ids[i]`, stored only if it is not the identity.
    pub fn new(ids: Vec<u32>) -> Self {
        let len = ids.len();
        let identity = ids.iter().enumerate().all(|(i, &s)| s as usize == i);
        Self { map: if identity { Vec::new() } else { ids }, len }
    }

    /// The id element `i` maps to.
    #[inline]
    pub fn get(&self, i: usize) -> u32 {
        debug_assert!(i < self.len, "element {i} of {}", self.len);
        if self.map.is_empty() {
            i as u32
        } else {
            self.map[i]
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
        self.map.is_empty()
    }

    /// The ids in element order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = u32> + '_ {
        (0..self.len).map(|i| self.get(i))
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.map.capacity() * 4
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
}
