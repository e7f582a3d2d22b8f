//! Split rounds over the front (papers/001): every record whose pixels exceed τs is split
//! back when it is on top of all its faces; records it uncovers join the next round.

use rayon::prelude::*;

use super::Runtime;

impl Runtime {
    /// Split rounds over the front; returns (splits, rounds, hit the cap).
    pub(super) fn split_phase(&mut self) -> (usize, usize, bool) {
        let (mut splits, mut rounds) = (0, 0);
        self.hierarchy.take_exposed();
        let mut todo: Vec<u32> = self.hierarchy.front_entries().to_vec();
        while !todo.is_empty() {
            if rounds == self.options.max_rounds {
                return (splits, rounds, true);
            }
            rounds += 1;
            let tau = self.tau;
            // One pass: the records to split, and the front's largest pixel error (the budget
            // mode lowers its threshold no further than just below it).
            let (mut want, front_max) = todo
                .par_iter()
                .fold(
                    || (Vec::new(), 0.0f32),
                    |(mut want, max), &u| {
                        if !self.hierarchy.is_splittable(u) {
                            return (want, max);
                        }
                        let [e, radius] = self.hierarchy.charge(u);
                        let px = self.pixels(u, e, radius);
                        if px > tau {
                            want.push(u);
                        }
                        (want, max.max(px))
                    },
                )
                .reduce(
                    || (Vec::new(), 0.0),
                    |(mut a, x), (b, y)| {
                        a.extend(b);
                        (a, x.max(y))
                    },
                );
            if rounds == 1 {
                self.front_max_px = front_max;
            }
            want.sort_unstable();
            let mut faces = Vec::new();
            for &u in &want {
                if !self.hierarchy.is_splittable(u) {
                    continue;
                }
                self.split_vertex(u, &mut faces).expect("front records are splittable");
                splits += 1;
            }
            self.reclassify_faces(&faces);
            todo = self.hierarchy.take_exposed();
            todo.sort_unstable();
            todo.dedup();
            if want.is_empty() {
                break;
            }
        }
        (splits, rounds, false)
    }

    /// Splits collapsed vertex `u` by hand if its split is legal now.
    pub fn split(&mut self, u: u32) -> Result<(), crate::lod::hierarchy::Unsplittable> {
        let mut faces = Vec::new();
        self.split_vertex(u, &mut faces)?;
        self.reclassify_faces(&faces);
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
        crate::par::on_pool(|| self.refine_fully_here())
    }

    /// [`Runtime::refine_fully`] on the calling thread.
    fn refine_fully_here(&mut self) -> usize {
        let mut n = 0;
        loop {
            let mut front: Vec<u32> = self.hierarchy.front().collect();
            if front.is_empty() {
                break;
            }
            front.sort_unstable();
            let mut faces = Vec::new();
            for u in front {
                self.split_vertex(u, &mut faces).expect("front records are splittable");
                n += 1;
            }
            self.reclassify_faces(&faces);
        }
        self.sync_index();
        n
    }
}
