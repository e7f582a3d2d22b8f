//! Buffers an update reuses from frame to frame, so that a warm frame allocates nothing once
//! they have grown (DESIGN.md: "no allocation in a steady-state `update`").
//!
//! Each group belongs to one function, which takes it out of the runtime for its run and puts
//! it back ([`Runtime::with_scratch`]), so that it can call the runtime's other methods
//! meanwhile; a group is never taken twice at once, since its owner does not call itself. The groups are cleared by their owners before use, not after, and
//! [`Scratch::trim`] gives back what a cold start or a cut grew far beyond a warm frame's needs:
//! after the first frame (the cold start) and every [`TRIM_EVERY`] frames, not every frame,
//! so that a camera moving in and out (large frames between small ones) does not give back
//! and grow again the same room frame after frame.

use super::Runtime;
use crate::lod::passes::select::Selection;

impl Runtime {
    /// Runs `f` on the runtime with scratch `group` taken out of it (`std::mem::take`, which
    /// allocates nothing), so that `f` may call the runtime's other methods, then puts the
    /// group back with whatever room `f` grew in it.
    pub(in crate::lod) fn with_scratch<G: Default, R>(
        &mut self,
        group: fn(&mut Scratch) -> &mut G,
        f: impl FnOnce(&mut Self, &mut G) -> R,
    ) -> R {
        let mut g = std::mem::take(group(&mut self.scratch));
        let r = f(self, &mut g);
        *group(&mut self.scratch) = g;
        r
    }
}

/// Frames between two [`Scratch::trim`]s (the first is after frame 1).
pub(super) const TRIM_EVERY: u64 = 64;

/// Every reusable buffer of an update, by owner.
#[derive(Debug, Clone, Default)]
pub(in crate::lod) struct Scratch {
    /// `classify_all`: the class of each live list entry.
    pub(super) classes: Vec<u8>,
    /// `collapse_phase`.
    pub(super) phase: PhaseScratch,
    /// `collapse_round`.
    pub(super) round: RoundScratch,
    /// `split_phase`.
    pub(super) split: SplitScratch,
    /// `reclassify_faces`.
    pub(super) reclassify: ReclassifyScratch,
    /// `kth_record_pixels`.
    pub(super) kth: KthScratch,
    /// `rebalance::run`.
    pub(in crate::lod) rebalance: RebalanceScratch,
    /// `take_views`: the views' sort order and the distinct ones' positions.
    pub(super) views: (Vec<u32>, Vec<u32>),
    /// `sync_index`: the faces the hierarchy edited since the last sync.
    pub(super) changed_faces: Vec<u32>,
}

/// The candidate lists of a collapse phase (this round's and the next).
#[derive(Debug, Clone, Default)]
pub(super) struct PhaseScratch {
    pub cands: Vec<u32>,
    pub next: Vec<u32>,
    pub parts: Vec<Vec<u32>>,
}

/// One collapse round's lists.
#[derive(Debug, Clone, Default)]
pub(super) struct RoundScratch {
    pub results: Vec<(Option<(u32, Selection)>, bool)>,
    pub touched_faces: Vec<u32>,
    pub targets: Vec<u32>,
    pub stuck: Vec<u32>,
    pub near: Vec<u32>,
    pub ignore: Vec<u32>,
    pub mark_blocked: Vec<u32>,
    pub changed: Vec<u32>,
    pub sources: Vec<u32>,
    pub woken: Vec<u32>,
    pub flags: Vec<bool>,
}

/// A split phase's lists.
#[derive(Debug, Clone, Default)]
pub(super) struct SplitScratch {
    pub todo: Vec<u32>,
    pub want: Vec<u32>,
    pub keyed: Vec<(f32, u32)>,
    pub parts: Vec<Vec<u32>>,
    pub faces: Vec<u32>,
    pub changed: Vec<u32>,
}

/// The pixel errors of every collapsed vertex, for the budget's lowering to an exact count.
#[derive(Debug, Clone, Default)]
pub(in crate::lod) struct KthScratch {
    pub parts: Vec<Vec<f32>>,
    pub pixels: Vec<f32>,
}

/// The vertices a re-classification visits and their fresh charges and classes.
#[derive(Debug, Clone, Default)]
pub(super) struct ReclassifyScratch {
    pub vertices: Vec<u32>,
    pub fresh: Vec<(bool, [f32; 2])>,
}

/// Rebalancing's candidates and one move's lists.
#[derive(Debug, Clone, Default)]
pub(in crate::lod) struct RebalanceScratch {
    pub cands: Vec<(u16, u32)>,
    pub faces: Vec<u32>,
    pub neighbours: Vec<u32>,
    pub fan: Vec<u32>,
    pub allowed: Vec<(u32, u32)>,
    pub changed: Vec<u32>,
}

/// Shrinks `v` to room for `keep` elements (at least 256, and at least its length) when it
/// holds more than eight times that: what a cold start or a cut needed once, a warm frame
/// does not. (A smaller slack also gave back lists that warm frames fill to a steady length,
/// to grow them again after each trim: of 300 warm bunny orbit frames, 23 allocated at twice,
/// 14 at four times, 9 at eight; the runtime held 6.14 MB at four times, 6.22 MB at eight.)
pub(super) fn trim<T>(v: &mut Vec<T>, keep: usize) {
    let keep = keep.max(256).max(v.len());
    if v.capacity() > 8 * keep {
        v.shrink_to(keep);
    }
}

/// Empties scratch list `v` (its contents are the last use's, read by nobody since) and
/// [`trim`]s it.
fn empty<T>(v: &mut Vec<T>, keep: usize) {
    v.clear();
    trim(v, keep);
}

impl Scratch {
    /// Empties every list and gives back room far beyond what a frame over `live` vertices
    /// needs: the per-entry classes keep room for the live list (`entries`), every other list
    /// for a sixteenth of the live vertices (a warm frame edits a few hundred).
    pub(super) fn trim(&mut self, entries: usize, live: usize) {
        empty(&mut self.classes, entries);
        let k = live / 16;
        let PhaseScratch { cands, next, parts } = &mut self.phase;
        for v in [cands, next].into_iter().chain(parts.iter_mut()) {
            empty(v, k);
        }
        let r = &mut self.round;
        empty(&mut r.results, k);
        empty(&mut r.flags, k);
        for v in [
            &mut r.touched_faces,
            &mut r.targets,
            &mut r.stuck,
            &mut r.near,
            &mut r.ignore,
            &mut r.mark_blocked,
            &mut r.changed,
            &mut r.sources,
            &mut r.woken,
        ] {
            empty(v, k);
        }
        let s = &mut self.split;
        empty(&mut s.keyed, k);
        for v in [&mut s.todo, &mut s.want, &mut s.faces, &mut s.changed].into_iter().chain(s.parts.iter_mut()) {
            empty(v, k);
        }
        empty(&mut self.reclassify.vertices, k);
        empty(&mut self.reclassify.fresh, k);
        empty(&mut self.kth.pixels, k);
        for v in &mut self.kth.parts {
            empty(v, k);
        }
        let m = &mut self.rebalance;
        empty(&mut m.cands, k);
        empty(&mut m.allowed, k);
        for v in [&mut m.faces, &mut m.neighbours, &mut m.fan, &mut m.changed, &mut self.changed_faces] {
            empty(v, k);
        }
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        fn b<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        let (p, r, s, c, m) = (&self.phase, &self.round, &self.split, &self.reclassify, &self.rebalance);
        let lists = |vs: &[&Vec<u32>]| vs.iter().map(|v| b(*v)).sum::<usize>();
        b(&self.classes)
            + lists(&[&self.views.0, &self.views.1])
            + lists(&[&p.cands, &p.next])
            + p.parts.iter().map(b).sum::<usize>()
            + b(&r.results)
            + b(&r.flags)
            + lists(&[
                &r.touched_faces,
                &r.targets,
                &r.stuck,
                &r.near,
                &r.ignore,
                &r.mark_blocked,
                &r.changed,
                &r.sources,
                &r.woken,
            ])
            + lists(&[&s.todo, &s.want, &s.faces, &s.changed])
            + b(&s.keyed)
            + s.parts.iter().map(b).sum::<usize>()
            + b(&c.vertices)
            + b(&c.fresh)
            + b(&self.kth.pixels)
            + self.kth.parts.iter().map(b).sum::<usize>()
            + b(&m.cands)
            + lists(&[&m.faces, &m.neighbours, &m.fan, &m.changed])
            + b(&m.allowed)
            + b(&self.changed_faces)
    }
}
