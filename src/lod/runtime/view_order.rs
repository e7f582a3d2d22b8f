//! Many views of one mesh (a mesh drawn by hundreds of instances, each instance's camera
//! carried into the mesh's space): a record's pixels are the largest over the views, and
//! working each one out made a frame's cost grow with the views (docs/BENCHMARKS.md, "How a
//! scene's frame grows"). The views are ordered once a frame so that a record can stop early:
//! the orthographic ones first (their pixels do not fall with distance), then the perspective
//! ones by the distance from their eye to the mesh's bounding sphere, nearest first. A vertex
//! lies in that sphere, so a view whose eye is D from its centre sees a record of radius r at
//! least D − R − r away, and no view after it sees it nearer. Once the pixels that bound allows
//! (with the largest pixels-per-unit factor of the views left, and a margin for rounding)
//! cannot beat the largest so far, the rest cannot either: the same maximum, bit for bit,
//! from the few nearest views.

use crate::view::Frustum;

/// Views from this many on are ordered; fewer are all worked out (two views cost two
/// distances and, mostly, one frustum test, which the ordering would not save: walked in
/// order from 2 views on, two cameras on the bunny orbit took +21 % instructions on 100 warm
/// frames, 415.5 → 501.2 M, and +4.7 % on the first).
pub(super) const ORDER_FROM: usize = 5;

/// Relative slack on the distance bound and the pixels, above the rounding of the few
/// operations on either side (each about 6e-8).
const SLACK: f32 = 1e-5;

/// A perspective view in the order, with what the bound needs.
#[derive(Clone, Copy, Debug)]
struct NearView {
    /// Its index among the frame's frustums.
    k: u32,
    /// Distance from the eye to the mesh's sphere (negative inside it), less the slack.
    gap: f32,
    /// The largest pixels-per-unit-at-unit-distance of this view and those after it.
    kmax: f32,
}

/// The frame's views in bound order (module docs); empty under fewer than [`ORDER_FROM`].
#[derive(Debug, Clone, Default)]
pub(super) struct ViewOrder {
    ortho: Vec<u32>,
    near_first: Vec<NearView>,
}

impl ViewOrder {
    /// Orders `views` for a mesh within the sphere `(centre, radius)`.
    pub(super) fn set(&mut self, views: &[Frustum], (centre, radius): ([f32; 3], f32)) {
        self.ortho.clear();
        self.near_first.clear();
        if views.len() < ORDER_FROM {
            return;
        }
        for (k, f) in views.iter().enumerate() {
            if f.is_orthographic() {
                self.ortho.push(k as u32);
                continue;
            }
            let d = dist(f.eye(), centre);
            let gap = d - radius - SLACK * (d + radius);
            let kmax = f.pixels_per_unit_at(1.0);
            self.near_first.push(NearView { k: k as u32, gap, kmax });
        }
        // Nearest first, ties by index: a total order, so the walk is the same every run.
        self.near_first.sort_by(|a, b| a.gap.total_cmp(&b.gap).then(a.k.cmp(&b.k)));
        let mut most = 0.0f32;
        for v in self.near_first.iter_mut().rev() {
            most = most.max(v.kmax);
            v.kmax = most;
        }
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        self.ortho.capacity() * 4 + self.near_first.capacity() * std::mem::size_of::<NearView>()
    }

    /// Whether the views are ordered this frame.
    pub(super) fn is_set(&self) -> bool {
        !self.ortho.is_empty() || !self.near_first.is_empty()
    }

    /// The largest pixels over the views of a record of radius `r` (0: a vertex alone) and
    /// error length `g`: `unscaled(k)` is view `k`'s figure before its frustum test and
    /// `scaled(k, px)` the view's pixels from it. Each view's pixels must be at most
    /// `unscaled(k) · widest` and at most `g · K / (distance − r) · widest`, `K` its pixels per
    /// unit at unit distance and `widest` (at least 1) the largest factor the tests apply.
    pub(super) fn largest(
        &self,
        g: f32,
        r: f32,
        widest: f32,
        unscaled: impl Fn(usize) -> f32,
        scaled: impl Fn(usize, f32) -> f32,
    ) -> f32 {
        if g == 0.0 {
            // Nothing to see from anywhere (every view's pixels are 0 · a finite factor).
            return 0.0;
        }
        let consider = |k: u32, best: &mut f32| {
            let px = unscaled(k as usize);
            if px * widest > *best {
                *best = best.max(scaled(k as usize, px));
            }
        };
        let mut best = f32::MIN;
        for &k in &self.ortho {
            consider(k, &mut best);
        }
        for v in &self.near_first {
            let den = v.gap - r * (1.0 + SLACK);
            // Within 1e-6 of the sphere no bound holds (pixels there are clamped): work it out.
            if den > 1e-6 && g * v.kmax / den * widest * (1.0 + SLACK) < best {
                break;
            }
            consider(v.k, &mut best);
        }
        best
    }
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::lod::passes::classify::{screen_error_in, ClassifyOptions};
    use crate::view::View;

    /// A view from `eye` looking at `target`; orthographic where `ortho`, with its own field of view and
    /// viewport otherwise.
    fn view(eye: [f32; 3], target: [f32; 3], ortho: bool, fov: f32, w: u32) -> View {
        if ortho {
            View::orthographic(eye, target, [0.0, 1.0, 0.0], 2.0 + fov / 10.0, (w, 720))
        } else {
            View::perspective(eye, target, [0.0, 1.0, 0.0], fov, (w, 720))
        }
    }

    /// Anywhere in a box 40 wide, or just outside the unit sphere (where a record's radius
    /// decides which view sees it nearest).
    fn point() -> impl Strategy<Value = [f32; 3]> {
        let close = (prop::array::uniform3(-1.0f32..1.0), 1.05f32..2.0).prop_map(|(d, at)| {
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
            d.map(|c| c / l * at)
        });
        prop_oneof![prop::array::uniform3(-20.0f32..20.0), close]
    }

    proptest! {
        /// The ordered walk's largest pixels are the largest over every view, bit for bit,
        /// for records (a sphere of radius r, or a vertex alone) anywhere in the mesh's
        /// sphere, under 5–40 views of every kind, with frustum and facing scales above and
        /// below 1.
        #[test]
        fn the_walk_finds_the_largest_of_every_view(
            eyes in prop::collection::vec((point(), point(), any::<bool>(), 20.0f32..100.0, 640u32..3840), 5..40),
            records in prop::collection::vec((prop::array::uniform3(-0.57f32..0.57), 0.0f32..0.3, 0.0f32..0.01), 1..50),
            outside in prop::sample::select(vec![0.25f32, 1.0, 2.0]),
            back in prop::sample::select(vec![0.5f32, 1.0, 3.0]),
        ) {
            let frustums: Vec<Frustum> =
                eyes.iter().map(|&(e, t, o, fov, w)| Frustum::new(&view(e, t, o && fov < 30.0, fov, w))).collect();
            let sphere = ([0.0; 3], 1.0);
            let mut order = ViewOrder::default();
            order.set(&frustums, sphere);
            prop_assert!(order.is_set());
            let o = ClassifyOptions { outside_frustum_scale: outside, back_facing_scale: back, ..Default::default() };
            for &(p, r, e) in &records {
                let g = e.sqrt();
                // A record: pixels at the sphere's nearest point, scaled off the frustum.
                let near = |f: &Frustum| g * f.pixels_per_unit_at(dist(p, f.eye()) - r);
                let scaled = |f: &Frustum, px: f32| if f.touches_sphere(p, r + g) { px } else { px * outside };
                let all = frustums.iter().map(|f| scaled(f, near(f))).fold(f32::MIN, f32::max);
                let walked = order.largest(g, r, outside.max(1.0), |k| near(&frustums[k]), |k, px| scaled(&frustums[k], px));
                prop_assert_eq!(walked.to_bits(), all.to_bits(), "record at {:?} r {}", p, r);
                // A vertex alone.
                let n = [p[0] + 0.3, p[1] - 0.2, p[2] + 1.0];
                let each = |k: usize| screen_error_in(Some(&frustums[k]), p, n, e, &o);
                let all = (0..frustums.len()).map(each).fold(f32::MIN, f32::max);
                let widest = back.max(1.0) * outside.max(1.0);
                let walked = order.largest(g, 0.0, widest, each, |_, px| px);
                prop_assert_eq!(walked.to_bits(), all.to_bits(), "vertex at {:?}", p);
            }
        }
    }

    /// Eye A is nearer the mesh's sphere than eye B, but a record near the surface on B's
    /// side is nearer B: after A, B's bound must still allow for the record's radius.
    #[test]
    fn a_records_radius_counts_in_the_bound() {
        let at = |eye: [f32; 3]| Frustum::new(&View::perspective(eye, [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080)));
        let mut frustums = vec![at([0.0, 0.0, 2.0]), at([0.6, 0.0, 2.0])];
        frustums.extend((0..3).map(|k| at([0.0, 30.0 + k as f32, 0.0])));
        let mut order = ViewOrder::default();
        order.set(&frustums, ([0.0; 3], 1.0));
        let (p, r, g) = ([0.6, 0.0, 0.75], 0.3, 0.01);
        let near = |k: usize| g * frustums[k].pixels_per_unit_at(dist(p, frustums[k].eye()) - r);
        let all = (0..frustums.len()).map(near).fold(f32::MIN, f32::max);
        assert_eq!(all, near(1), "eye B sees the record largest");
        assert_eq!(order.largest(g, r, 1.0, near, |_, px| px), all);
    }

    #[test]
    fn far_views_are_not_worked_out() {
        // One eye near the mesh, 99 far behind it: the walk stops after the near one.
        let near = Frustum::new(&View::perspective([0.0, 0.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080)));
        let far = |k: usize| {
            let z = 50.0 + k as f32;
            Frustum::new(&View::perspective([0.0, 0.0, z], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080)))
        };
        let frustums: Vec<Frustum> = std::iter::once(near).chain((0..99).map(far)).collect();
        let mut order = ViewOrder::default();
        order.set(&frustums, ([0.0; 3], 1.0));
        let worked = std::cell::Cell::new(0);
        let px = |k: usize| {
            worked.set(worked.get() + 1);
            0.01 * frustums[k].pixels_per_unit_at(dist([0.0, 0.0, 0.5], frustums[k].eye()))
        };
        order.largest(0.01, 0.0, 1.0, px, |_, px| px);
        assert_eq!(worked.get(), 1);
    }
}
