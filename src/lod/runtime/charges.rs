//! The charge and class of every live vertex: e(V) of papers/000 §3 on the current mesh,
//! saturated over the records around it (module docs of `runtime`: errors are monotone along
//! chains), turned into pixels for the view and compared with τc.

use rayon::prelude::*;

use crate::lod::passes::classify::{screen_error_in, screen_error_views, vertex_error};
use crate::par::map_sized_into;
use crate::topology::{vflag, HalfEdges, Topology, INVALID};
use crate::view::Frustum;

use super::scratch::ReclassifyScratch;
use super::{is_live, list_once, unmark, Runtime, PARALLEL_MIN};

impl Runtime {
    /// Squared object error and radius that collapsing `u` would be charged: e(u) (with its
    /// anchor floor) and every record on the faces around u or across its link edges.
    pub(super) fn charge(&self, u: u32) -> (f32, f32) {
        let t = &self.mesh.topology;
        let mut c = (self.own_error(u), 0.0);
        // Neighbouring faces often share their top record (a collapse tops every face it
        // touched): each record is charged once per run of equal tops.
        let mut last = INVALID;
        let mut bury = |rec: u32| {
            if rec != last {
                self.bury(u, &mut c, rec);
                last = rec;
            }
        };
        for g in t.outgoing(u) {
            bury(self.hierarchy.top(g / 3));
            let across = t.twin[Topology::next(g) as usize];
            if across != INVALID {
                bury(self.hierarchy.top(across / 3));
            }
        }
        c
    }

    /// The charge of a planned collapse: e(u) with its floor, and the records it buries.
    pub(in crate::lod) fn plan_charge(&self, u: u32, plan: &crate::lod::hierarchy::Plan) -> (f32, f32) {
        let mut c = (self.own_error(u), 0.0);
        for rec in self.hierarchy.buried_by(plan) {
            self.bury(u, &mut c, rec);
        }
        c
    }

    /// e(u) on the current mesh (papers/000 eq. 1), raised to u's anchor floor.
    fn own_error(&self, u: u32) -> f32 {
        vertex_error(&self.mesh.topology, &self.mesh.positions, self.normals[u as usize], u).max(self.floor.get(u))
    }

    /// Raises u's charge (error, radius) to cover record `rec` (nothing for `INVALID`).
    fn bury(&self, u: u32, c: &mut (f32, f32), rec: u32) {
        if rec != INVALID {
            let [error, radius] = self.hierarchy.charge(rec);
            let d = dist(self.mesh.positions[u as usize], self.mesh.positions[rec as usize]);
            *c = (c.0.max(error), c.1.max(d + radius));
        }
    }

    /// Pixels of a (squared error, radius) charge at vertex `u` for the current views: the
    /// largest over them (a vertex is fine only where every view finds it so); model units
    /// without a view.
    pub(in crate::lod) fn pixels(&self, u: u32, e: f32, r: f32) -> f32 {
        match self.frustums.as_slice() {
            [one] => self.pixels_in(Some(one), u, e, r),
            [] => self.pixels_in(None, u, e, r),
            views => self.pixels_in_each(views, u, e, r),
        }
    }

    /// [`Runtime::pixels`] under several views, out of line: inlined, its loop made the
    /// one-view path save and restore more registers on every call (+3 % on a warm frame).
    ///
    /// A record's pixels in a view are its pixels at the sphere's nearest point, scaled where
    /// the sphere misses the frustum; the frustum test is the dearer part. So the unscaled
    /// figures come first, the largest view is tested first, and another view is tested only
    /// if its figure could still raise the largest: the same maximum, bit for bit, with one
    /// frustum test instead of two for most records under two views. From
    /// [`ORDER_FROM`](super::view_order::ORDER_FROM) views on, the views are walked nearest first and the walk
    /// stops where no view left could raise the largest (`view_order.rs`).
    #[inline(never)]
    fn pixels_in_each(&self, views: &[Frustum], u: u32, e: f32, r: f32) -> f32 {
        let p = self.mesh.positions[u as usize];
        if r <= 0.0 {
            let (n, o) = (self.normals[u as usize], &self.options.classify);
            if self.view_order.is_set() {
                // A view's error is at most g · its pixels per unit at p · both scales.
                let widest = o.back_facing_scale.max(1.0) * o.outside_frustum_scale.max(1.0);
                let each = |k: usize| screen_error_in(Some(&views[k]), p, n, e, o);
                return self.view_order.largest(e.max(0.0).sqrt(), 0.0, widest, each, |_, px| px);
            }
            return screen_error_views(views, p, n, e, o);
        }
        let g = e.max(0.0).sqrt();
        if !g.is_finite() {
            return g;
        }
        let outside = self.options.classify.outside_frustum_scale;
        let near = |f: &Frustum| nearest_pixels(f, p, r, g);
        let scaled = |f: &Frustum, px: f32| if f.touches_sphere(p, r + g) { px } else { px * outside };
        let bound = outside.max(1.0);
        if self.view_order.is_set() {
            return self.view_order.largest(g, r, bound, |k| near(&views[k]), |k, px| scaled(&views[k], px));
        }
        let (first, largest) =
            views
                .iter()
                .enumerate()
                .map(|(k, f)| (k, near(f)))
                .fold((0, f32::MIN), |a, b| if b.1 > a.1 { b } else { a });
        let mut best = scaled(&views[first], largest);
        for (k, f) in views.iter().enumerate() {
            if k != first {
                let px = near(f);
                if px * bound > best {
                    best = best.max(scaled(f, px));
                }
            }
        }
        best
    }

    /// [`Runtime::pixels`] in one view (`None`: model units).
    #[inline(always)]
    pub(super) fn pixels_in(&self, frustum: Option<&Frustum>, u: u32, e: f32, r: f32) -> f32 {
        // The position is read in each branch, not once before: read once, it was copied to
        // the stack for the call below and re-read from there with mismatched widths (a
        // stalled store-to-load forward, a third of this function's time in some builds).
        if r <= 0.0 {
            let (p, n) = (self.mesh.positions[u as usize], self.normals[u as usize]);
            return screen_error_in(frustum, p, n, e, &self.options.classify);
        }
        let p = self.mesh.positions[u as usize];
        let g = e.max(0.0).sqrt();
        let Some(frustum) = frustum else { return g };
        if !g.is_finite() {
            return g;
        }
        let mut px = nearest_pixels(frustum, p, r, g);
        if !frustum.touches_sphere(p, r + g) {
            px *= self.options.classify.outside_frustum_scale;
        }
        px
    }

    /// τc, the collapse threshold.
    pub(in crate::lod) fn collapse_threshold(&self) -> f32 {
        self.tau / self.options.hysteresis
    }

    /// Whether `v`, with charge `c`, belongs to R (removable) for the current view.
    fn in_r_for(&self, v: u32, c: [f32; 2]) -> bool {
        self.mesh.topology.vflags[v as usize] & (vflag::REMOVED | vflag::LOCKED) == 0
            && self.pixels(v, c[0], c[1]) <= self.collapse_threshold()
    }

    /// The split threshold τs at which the next live vertex would become removable (R) in
    /// the current view: the hysteresis times the smallest pixel error over τc of a live,
    /// unlocked vertex; infinite where none is finite. One pass over the live vertices.
    pub(in crate::lod) fn removal_threshold(&self) -> f32 {
        let (tc, t) = (self.collapse_threshold(), &self.mesh.topology);
        let is_live = is_live(t);
        let px = |&v: &u32| {
            let free = is_live(v) && t.vflags[v as usize] & vflag::LOCKED == 0;
            let [e, r] = self.hierarchy.charge(v);
            if free {
                self.pixels(v, e, r)
            } else {
                f32::INFINITY
            }
        };
        let least = self.live.entries().par_iter().map(px).filter(|&p| p > tc).reduce(|| f32::INFINITY, f32::min);
        self.options.hysteresis * least
    }

    pub(super) fn classify_all(&mut self) {
        // The live list's dropped entries (collapsed vertices) are skipped, not classified.
        const DROPPED: u8 = 2;
        self.with_scratch(
            |s| &mut s.classes,
            |rt, class| {
                let live = rt.live.entries();
                let is_live = is_live(&rt.mesh.topology);
                live.par_iter()
                    .map(|&v| if is_live(v) { u8::from(rt.in_r_for(v, rt.hierarchy.charge(v))) } else { DROPPED })
                    .collect_into_vec(class);
                for (&v, &c) in live.iter().zip(class.iter()) {
                    if c != DROPPED {
                        rt.in_r[v as usize] = c == 1;
                        rt.stays[v as usize] = c == 0;
                    }
                }
            },
        );
    }

    /// After edits to `faces`: recomputes the charge and class of every vertex whose charge
    /// can depend on them (their vertices, and the far vertex of each face across their
    /// edges); puts the vertices whose class changed in `changed`.
    pub(in crate::lod) fn reclassify_faces(&mut self, faces: &[u32], changed: &mut Vec<u32>) {
        self.with_scratch(|s| &mut s.reclassify, |rt, sc| rt.reclassify_with(faces, changed, sc));
    }

    /// [`Runtime::reclassify_faces`] with its lists.
    fn reclassify_with(&mut self, faces: &[u32], changed: &mut Vec<u32>, sc: &mut ReclassifyScratch) {
        let ReclassifyScratch { vertices: vs, fresh } = sc;
        vs.clear();
        let t = &self.mesh.topology;
        let seen = &mut self.seen;
        for &f in faces.iter().filter(|&&f| t.is_face_live(f)) {
            for v in t.faces[f as usize] {
                list_once(seen, vs, v);
            }
            for h in 3 * f..3 * f + 3 {
                let o = t.twin[h as usize];
                if o != INVALID {
                    list_once(seen, vs, t.origin(Topology::prev(o)));
                }
            }
        }
        unmark(seen, vs);
        let fresh_class = |&v: &u32| {
            let c: [f32; 2] = self.charge(v).into();
            (self.in_r_for(v, c), c)
        };
        // Each vertex once, in first-seen order (the callers do not depend on the order).
        map_sized_into(vs, PARALLEL_MIN, 1, &mut (), fresh, |_: &mut (), v| fresh_class(v));
        changed.clear();
        for (&v, &(r, c)) in vs.iter().zip(fresh.iter()) {
            if self.in_r[v as usize] != r {
                changed.push(v);
            }
            self.hierarchy.set_charge(v, c);
            self.in_r[v as usize] = r;
            self.stays[v as usize] = !r;
        }
    }

    /// Checks that every live vertex's stored charge is what a fresh walk works out
    /// from the mesh and the hierarchy now, bit for bit: the frame start classifies from the
    /// stored charges, so one left stale by the incremental re-classification would decide a
    /// wrong class and nothing else would notice. Walks every live vertex (tests and
    /// `dynlod fly --verify`).
    pub fn check_charges(&self) -> Result<(), String> {
        let is_live = is_live(&self.mesh.topology);
        let stale = self.live.entries().par_iter().copied().filter(|&v| is_live(v)).find_first(|&v| {
            let fresh: [f32; 2] = self.charge(v).into();
            fresh.map(f32::to_bits) != self.hierarchy.charge(v).map(f32::to_bits)
        });
        match stale {
            None => Ok(()),
            Some(v) => Err(format!(
                "vertex {v}: stored charge {:?}, but its neighbourhood now gives {:?}",
                self.hierarchy.charge(v),
                <[f32; 2]>::from(self.charge(v))
            )),
        }
    }

    /// `u` has just collapsed.
    pub(super) fn live_remove(&mut self, u: u32) {
        self.live.remove(is_live(&self.mesh.topology));
        self.in_r[u as usize] = false;
        self.stays[u as usize] = false;
    }

    /// `u` has just been split back.
    pub(super) fn live_add(&mut self, u: u32) {
        self.live.insert(u);
    }
}

/// Pixels of an error `g` at the point of the sphere of radius `r` around `p` nearest the eye
/// of `frustum` (before the frustum test).
#[inline(always)]
fn nearest_pixels(frustum: &Frustum, p: [f32; 3], r: f32, g: f32) -> f32 {
    g * frustum.pixels_per_unit_at(dist(p, frustum.eye()) - r)
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
