//! Split rounds over the front (papers/001): every record whose pixels exceed τs is split
//! back when it is on top of all its faces; records it uncovers join the next round.

use rayon::prelude::*;

use super::scratch::{KthScratch, SplitScratch};
use super::Runtime;
use crate::par::{filter_chunks_into, filter_map_chunks_into};
use crate::view::Frustum;

impl Runtime {
    /// Split rounds over the front; returns (splits, rounds, hit the cap).
    ///
    /// The live vertices near the splits are re-classified once, after the last round, not
    /// after each: a split round reads only the records' charges, which a collapse fixed and
    /// no split changes, so the rounds decide the same splits either way; and every vertex
    /// whose charge a split can change is listed by [`Runtime::reclassify_faces`] from the
    /// split's faces, so one pass over all of them leaves the same classes as a pass per
    /// round. Rounds splitting a neighbourhood in waves had re-classified it once per wave
    /// (the igea dolly: twice the vertices, a third of the split phase's time).
    pub(super) fn split_phase(&mut self) -> (usize, usize, bool) {
        self.with_scratch(|s| &mut s.split, Self::split_rounds)
    }

    /// [`Runtime::split_phase`] with its lists.
    fn split_rounds(&mut self, sc: &mut SplitScratch) -> (usize, usize, bool) {
        let SplitScratch { todo, want, keyed, parts, faces, changed } = sc;
        let (mut splits, mut rounds, mut capped) = (0, 0, false);
        self.hierarchy.swap_exposed(todo);
        todo.clear();
        todo.extend_from_slice(self.hierarchy.front_entries());
        faces.clear();
        while !todo.is_empty() {
            if rounds == self.options.max_rounds {
                capped = true;
                break;
            }
            rounds += 1;
            let tau = self.tau;
            // By chunks, as `fresh_candidates` does (rayon's list folder costs more here).
            let wanted = |u: &u32| self.hierarchy.is_splittable(*u) && self.front_pixels(*u) > tau;
            filter_chunks_into(todo, 2048, parts, want, wanted);
            if want.len() > self.edits_left {
                // The edit cap may bind: the largest pixel errors go first.
                keyed.clear();
                keyed.extend(want.iter().map(|&u| (self.front_pixels(u), u)));
                keyed.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
                want.clear();
                want.extend(keyed.iter().map(|&(_, u)| u));
            } else {
                want.sort_unstable();
            }
            for &u in want.iter() {
                if self.edits_left == 0 {
                    break;
                }
                if !self.hierarchy.is_splittable(u) {
                    continue;
                }
                self.split_vertex(u, faces).expect("front records are splittable");
                splits += 1;
                self.edits_left -= 1;
            }
            if self.edits_left == 0 {
                break;
            }
            self.hierarchy.swap_exposed(todo);
            todo.sort_unstable();
            todo.dedup();
            if want.is_empty() {
                break;
            }
        }
        self.reclassify_faces(faces, changed);
        (splits, rounds, capped)
    }

    /// Front record `u`'s pixel error in the current view.
    fn front_pixels(&self, u: u32) -> f32 {
        let [e, radius] = self.hierarchy.charge(u);
        self.pixels(u, e, radius)
    }

    /// The front's largest pixel error in the current view: the threshold just below which
    /// the next split happens (0 when nothing can be refined). The budget mode lowers its
    /// threshold no further; it reads this after the collapse phase, which adds records.
    pub(in crate::lod) fn front_max_pixels(&self) -> f32 {
        self.front_max(|u| self.front_pixels(u))
    }

    /// The front's largest pixel error in `frustum` alone.
    pub(super) fn front_max_pixels_in(&self, frustum: &Frustum) -> f32 {
        self.front_max(|u| {
            let [e, radius] = self.hierarchy.charge(u);
            self.pixels_in(Some(frustum), u, e, radius)
        })
    }

    /// The largest `pixels` of a splittable front record.
    fn front_max(&self, pixels: impl Fn(u32) -> f32 + Sync) -> f32 {
        let chunk_max = |chunk: &[u32]| {
            let splittable = chunk.iter().filter(|&&u| self.hierarchy.is_splittable(u));
            splittable.map(|&u| pixels(u)).fold(0.0, f32::max)
        };
        self.hierarchy.front_entries().par_chunks(2048).map(chunk_max).reduce(|| 0.0, f32::max)
    }

    /// The `k`-th largest pixel error (from 1) of any collapsed vertex in the current view,
    /// or 0 where fewer are collapsed. Charges only fall down a chain, so the records
    /// answering more than a threshold are exactly those a split phase at it splits back.
    /// `sc`: its lists, kept for reuse.
    pub(super) fn kth_record_pixels(&self, k: usize, sc: &mut KthScratch) -> f32 {
        self.collapsed_pixels_into(sc);
        let px = &mut sc.pixels;
        if k == 0 || k > px.len() {
            return 0.0;
        }
        *px.select_nth_unstable_by(k - 1, |a, b| b.total_cmp(a)).1
    }

    /// The pixel error of every collapsed vertex in the current views, into `sc.pixels` (in
    /// vertex order).
    pub(in crate::lod) fn collapsed_pixels_into(&self, sc: &mut KthScratch) {
        let h = &self.hierarchy;
        let collapsed = |u: usize| h.is_collapsed(u as u32).then(|| self.front_pixels(u as u32));
        let KthScratch { parts, pixels } = sc;
        filter_map_chunks_into(self.mesh.positions.len(), 2048, parts, pixels, collapsed);
    }

    /// Splits collapsed vertex `u` by hand if its split is legal now.
    pub fn split(&mut self, u: u32) -> Result<(), crate::lod::hierarchy::Unsplittable> {
        self.edited_by_hand();
        let mut faces = Vec::new();
        self.split_vertex(u, &mut faces)?;
        self.reclassify_faces(&faces, &mut Vec::new());
        self.sync_index();
        Ok(())
    }

    /// Splits `u` if legal, lists it live again and adds the faces it edited to `faces`
    /// (the caller re-classifies them).
    pub(in crate::lod) fn split_vertex(
        &mut self,
        u: u32,
        faces: &mut Vec<u32>,
    ) -> Result<(), crate::lod::hierarchy::Unsplittable> {
        self.hierarchy.split(&mut self.mesh, u, faces)?;
        self.live_add(u);
        Ok(())
    }

    /// Splits everything back (for tests and tools): repeatedly splits the whole front.
    pub fn refine_fully(&mut self) -> usize {
        self.edited_by_hand();
        crate::par::on_pool(|| self.refine_fully_here())
    }

    /// [`Runtime::refine_fully`] on the calling thread.
    fn refine_fully_here(&mut self) -> usize {
        let mut n = 0;
        // Re-classified once at the end, as in `split_phase`.
        let mut faces = Vec::new();
        loop {
            let mut front: Vec<u32> = self.hierarchy.front().collect();
            if front.is_empty() {
                break;
            }
            front.sort_unstable();
            for u in front {
                self.split_vertex(u, &mut faces).expect("front records are splittable");
                n += 1;
            }
        }
        self.reclassify_faces(&faces, &mut Vec::new());
        self.sync_index();
        n
    }
}
