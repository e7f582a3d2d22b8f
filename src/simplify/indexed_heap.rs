//! A binary min-heap with one slot per vertex, whose keys can be changed or removed in place
//! (no stale entries piling up, as with `BinaryHeap` and stamps). Keys order by cost
//! (`total_cmp`), then by vertex id, so the order is total and results are deterministic.

const ABSENT: u32 = u32::MAX;

pub(crate) struct IndexedHeap {
    /// (cost, vertex), heap-ordered.
    items: Vec<(f64, u32)>,
    /// Position of each vertex in `items`, or `ABSENT`.
    pos: Vec<u32>,
}

fn less(a: (f64, u32), b: (f64, u32)) -> bool {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).is_lt()
}

impl IndexedHeap {
    /// Builds the heap from (cost, vertex) pairs in O(len); each vertex at most once.
    pub fn from_items(n: usize, items: Vec<(f64, u32)>) -> Self {
        let mut h = Self { items, pos: vec![ABSENT; n] };
        for (i, &(_, v)) in h.items.iter().enumerate() {
            h.pos[v as usize] = i as u32;
        }
        for i in (0..h.items.len() / 2).rev() {
            h.down(i);
        }
        h
    }

    /// The cheapest (cost, vertex) without removing it.
    pub fn peek(&self) -> Option<(f64, u32)> {
        self.items.first().copied()
    }

    /// Whether `v` is in the heap.
    pub fn contains(&self, v: u32) -> bool {
        self.pos[v as usize] != ABSENT
    }

    /// Sets `v`'s key, inserting it if absent.
    pub fn set(&mut self, v: u32, cost: f64) {
        let p = self.pos[v as usize];
        if p == ABSENT {
            self.items.push((cost, v));
            let i = self.items.len() - 1;
            self.pos[v as usize] = i as u32;
            self.up(i);
        } else {
            let i = p as usize;
            let old = self.items[i];
            self.items[i] = (cost, v);
            if less((cost, v), old) {
                self.up(i);
            } else {
                self.down(i);
            }
        }
    }

    /// Removes `v` if present.
    pub fn remove(&mut self, v: u32) {
        let p = self.pos[v as usize];
        if p == ABSENT {
            return;
        }
        let i = p as usize;
        self.pos[v as usize] = ABSENT;
        let last = self.items.pop().expect("present implies non-empty");
        if i < self.items.len() {
            self.items[i] = last;
            self.pos[last.1 as usize] = i as u32;
            if i > 0 && less(last, self.items[(i - 1) / 2]) {
                self.up(i);
            } else {
                self.down(i);
            }
        }
    }

    fn up(&mut self, mut i: usize) {
        let x = self.items[i];
        while i > 0 {
            let parent = (i - 1) / 2;
            if !less(x, self.items[parent]) {
                break;
            }
            self.items[i] = self.items[parent];
            self.pos[self.items[i].1 as usize] = i as u32;
            i = parent;
        }
        self.items[i] = x;
        self.pos[x.1 as usize] = i as u32;
    }

    fn down(&mut self, mut i: usize) {
        let x = self.items[i];
        let n = self.items.len();
        loop {
            let l = 2 * i + 1;
            if l >= n {
                break;
            }
            let r = l + 1;
            let c = if r < n && less(self.items[r], self.items[l]) { r } else { l };
            if !less(self.items[c], x) {
                break;
            }
            self.items[i] = self.items[c];
            self.pos[self.items[i].1 as usize] = i as u32;
            i = c;
        }
        self.items[i] = x;
        self.pos[x.1 as usize] = i as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Any sequence of sets and removes pops in the same order as a sorted reference.
        #[test]
        fn pops_in_key_order(ops in prop::collection::vec((0u32..40, -5i32..5, any::<bool>()), 0..200)) {
            let mut h = IndexedHeap::from_items(40, vec![(1.0, 3), (0.5, 7), (1.0, 1)]);
            let mut reference: std::collections::BTreeMap<u32, f64> = [(3, 1.0), (7, 0.5), (1, 1.0)].into();
            for (v, c, del) in ops {
                if del {
                    h.remove(v);
                    reference.remove(&v);
                } else {
                    h.set(v, f64::from(c));
                    reference.insert(v, f64::from(c));
                }
            }
            let mut want: Vec<(f64, u32)> = reference.iter().map(|(&v, &c)| (c, v)).collect();
            want.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let mut got = Vec::new();
            while let Some(top) = h.peek() {
                got.push(top);
                h.remove(top.1);
            }
            prop_assert_eq!(got, want);
        }
    }
}
