//! A list of ids with O(1) insert and remove and no position per id: the runtime's live
//! vertices and the hierarchy's front (papers/001's splittable records), each of which a
//! frame walks in full while only a few of its ids change.
//!
//! A swap-remove list needs a position per id to find what it removes (4 bytes per input
//! vertex for each list). Here a removal only counts: the entry stays until the list holds
//! more than an eighth of dropped entries, then one pass keeps the members (the owner's
//! predicate says which), in order. A bit per id says whether the id has an entry, so an id
//! that comes back before that pass reuses its entry instead of listing itself twice.
//! Walks see members and dropped entries alike and skip the latter; at most an eighth of a
//! walk is dropped entries.

use bitvec::vec::BitVec;

/// Ids in insertion order, with dropped entries kept until a pass clears them.
#[derive(Debug, Clone, Default)]
pub(crate) struct LazyList {
    entries: Vec<u32>,
    listed: BitVec,
    members: usize,
}

impl LazyList {
    /// A list of `members` (distinct ids below `ids`).
    pub fn new(ids: usize, members: Vec<u32>) -> Self {
        let mut listed = BitVec::repeat(false, ids);
        for &u in &members {
            listed.set(u as usize, true);
        }
        Self { members: members.len(), entries: members, listed }
    }

    /// `u`, not a member, becomes one.
    pub fn insert(&mut self, u: u32) {
        self.members += 1;
        if !self.listed.replace(u as usize, true) {
            self.entries.push(u);
        }
    }

    /// An id that was a member no longer is. `is_member` answers for every listed id as it
    /// stands now (this id included), in case the pass runs.
    pub fn remove(&mut self, is_member: impl Fn(u32) -> bool) {
        self.members -= 1;
        if self.entries.len() > self.members + self.members / 8 + 64 {
            self.compact(is_member);
        }
    }

    /// Drops every entry whose id is no longer a member, keeping the others' order.
    pub fn compact(&mut self, is_member: impl Fn(u32) -> bool) {
        let listed = &mut self.listed;
        self.entries.retain(|&u| {
            let keep = is_member(u);
            if !keep {
                listed.set(u as usize, false);
            }
            keep
        });
        debug_assert_eq!(self.entries.len(), self.members, "the members and the predicate disagree");
    }

    /// How many members.
    pub fn len(&self) -> usize {
        self.members
    }

    /// Every member, and dropped entries not cleared yet (at most an eighth of them and 64):
    /// callers skip those.
    pub fn entries(&self) -> &[u32] {
        &self.entries
    }

    /// Whether `u` has an entry (a member, or dropped and not cleared).
    pub fn is_listed(&self, u: u32) -> bool {
        self.listed[u as usize]
    }

    /// Gives back capacity once the entries use less than half of it (a far view leaves few
    /// members). Shrinking to the entries and a quarter, and growing by doubling, a list
    /// does not shrink and grow in turn.
    pub fn shrink(&mut self) {
        let len = self.entries.len();
        if self.entries.capacity() > 2 * len + 1024 {
            self.entries.shrink_to(len + len / 4);
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.entries.capacity() * 4 + self.listed.capacity() / 8
    }
}

#[cfg(test)]
mod tests {
    use super::LazyList;
    use proptest::prelude::*;

    proptest! {
        /// Against a plain set: after any inserts and removes, the members are exactly the
        /// listed entries that are members, each listed once, in first-listed order, and
        /// dropped entries never outnumber an eighth of the members and 64.
        #[test]
        fn agrees_with_a_set(ops in prop::collection::vec((0u32..200, any::<bool>()), 0..2000)) {
            let mut member = [false; 200];
            let mut list = LazyList::new(200, vec![]);
            for (u, add) in ops {
                if add && !member[u as usize] {
                    member[u as usize] = true;
                    list.insert(u);
                } else if !add && member[u as usize] {
                    member[u as usize] = false;
                    list.remove(|v| member[v as usize]);
                }
                let members: Vec<u32> = list.entries().iter().copied().filter(|&v| member[v as usize]).collect();
                prop_assert_eq!(members.len(), list.len());
                prop_assert_eq!(member.iter().filter(|&&m| m).count(), list.len());
                let mut sorted = list.entries().to_vec();
                sorted.sort_unstable();
                sorted.dedup();
                prop_assert_eq!(sorted.len(), list.entries().len(), "an id listed twice");
                prop_assert!(list.entries().len() <= list.len() + list.len() / 8 + 64);
                for v in 0..200 {
                    prop_assert_eq!(list.is_listed(v), list.entries().contains(&v));
                }
            }
            list.compact(|v| member[v as usize]);
            prop_assert_eq!(list.entries().len(), list.len());
        }
    }
}
