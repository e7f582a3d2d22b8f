//! Polygon faces (OBJ, PLY, OFF) to triangles.
//!
//! A fan from the first corner, as most tools do, wherever it covers the polygon: where every
//! fan triangle turns the way the polygon does about its Newell normal. That is every convex
//! polygon, and every concave one whose first corner sees all the others, so such files read
//! exactly as a fan. Elsewhere a fan folds — one triangle turns backwards and another covers
//! ground outside the polygon (an L-shaped face fanned from the wrong corner) — and the
//! polygon is ear-clipped instead (`earcut`, in the plane of its Newell normal). Ear clipping
//! passes over corners that lie on a straight edge; they are put back by splitting the
//! triangle on that edge, so a vertex shared with the neighbouring face stays shared.
//!
//! A polygon that no triangulation covers without folding (it crosses itself in its plane) is
//! fanned as before and reported ([`RepairKind::FannedSelfCrossingPolygons`]).
//!
//! [`RepairKind::FannedSelfCrossingPolygons`]: crate::mesh::RepairKind::FannedSelfCrossingPolygons

use std::collections::HashMap;

use earcut::Earcut;
use glam::DVec3;

use crate::mesh::{Location, Repair, RepairKind};

/// How [`Triangulator::triangulate`] turned one polygon into triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Triangulated {
    /// Fewer than three corners: nothing added.
    TooShort,
    /// A fan from the first corner (it covers the polygon, or the polygon has no area).
    Fan,
    /// Ear-clipped: a fan would have folded.
    EarClipped,
    /// Fanned although the fan folds: the polygon crosses itself, so nothing covers it.
    FannedSelfCrossing,
}

/// Reusable buffers for [`Triangulator::triangulate`], and the record of a file's faces that
/// [`Triangulator::face`] could not make into a surface.
pub(crate) struct Triangulator {
    earcut: Earcut<f64>,
    plane: Vec<[f64; 2]>,
    ears: Vec<u32>,
    tris: Vec<[u32; 3]>,
    /// Faces of fewer than three corners, skipped (after what the reader skipped itself).
    skipped: Repair,
    /// Faces that cross themselves, fanned.
    crossing: Repair,
}

impl Default for Triangulator {
    fn default() -> Self {
        Self::after(Repair::new(RepairKind::SkippedNonTrianglePrimitives))
    }
}

impl Triangulator {
    /// A triangulator whose record of skipped faces goes on from `skipped` (what the reader
    /// left out before triangulating: an OBJ's points and lines).
    pub(crate) fn after(skipped: Repair) -> Self {
        Self {
            earcut: Earcut::new(),
            plane: Vec::new(),
            ears: Vec::new(),
            tris: Vec::new(),
            skipped,
            crossing: Repair::new(RepairKind::FannedSelfCrossingPolygons),
        }
    }

    /// [`Self::triangulate`] for the file's face number `face`, recorded where it is too
    /// short to be a surface or crosses itself.
    pub(crate) fn face(
        &mut self,
        face: usize,
        poly: &[u32],
        position: impl Fn(u32) -> [f64; 3],
        out: &mut Vec<[u32; 3]>,
    ) {
        match self.triangulate(poly, position, out) {
            Triangulated::TooShort => self.skipped.add(Location::Face(face as u32)),
            Triangulated::FannedSelfCrossing => self.crossing.add(Location::Face(face as u32)),
            Triangulated::Fan | Triangulated::EarClipped => {}
        }
    }

    /// What was skipped so far.
    pub(crate) fn skipped(&self) -> &Repair {
        &self.skipped
    }

    /// The records of skipped and fanned faces, onto `list` where they hold any.
    pub(crate) fn push_repairs_into(self, list: &mut Vec<Repair>) {
        self.skipped.push_into(list);
        self.crossing.push_into(list);
    }

    /// Appends the triangles of the polygon `poly` (vertex ids, in winding order) to `out`,
    /// with `position(id)` the vertices' positions; triangles keep the polygon's winding.
    fn triangulate(
        &mut self,
        poly: &[u32],
        position: impl Fn(u32) -> [f64; 3],
        out: &mut Vec<[u32; 3]>,
    ) -> Triangulated {
        if poly.len() < 3 {
            return Triangulated::TooShort;
        }
        if poly.len() == 3 {
            out.push([poly[0], poly[1], poly[2]]);
            return Triangulated::Fan;
        }
        // Relative to the first corner, so far-out files lose nothing to cancellation.
        let p0 = DVec3::from(position(poly[0]));
        let at = |i: usize| DVec3::from(position(poly[i])) - p0;
        let mut normal = DVec3::ZERO;
        for i in 0..poly.len() {
            let (a, b) = (at(i), at((i + 1) % poly.len()));
            normal += a.cross(b);
        }
        // Twice the polygon's area; a polygon without area has no plane to clip in.
        let area2 = normal.length();
        if area2.is_nan() || area2 <= 0.0 || area2.is_infinite() {
            fan(poly, out);
            return Triangulated::Fan;
        }
        let normal = normal / area2;
        // Rounding may leave a fan triangle over collinear corners a hair below zero.
        let folds = (1..poly.len() - 1).any(|i| at(i).cross(at(i + 1)).dot(normal) < -1e-9 * area2);
        if !folds {
            fan(poly, out);
            return Triangulated::Fan;
        }
        if self.ear_clip(poly.len(), &at, normal, area2) {
            out.extend(self.tris.iter().map(|t| t.map(|c| poly[c as usize])));
            Triangulated::EarClipped
        } else {
            fan(poly, out);
            Triangulated::FannedSelfCrossing
        }
    }

    /// Ear-clips the polygon of `k` corners at `at(i)` into `self.tris` (corner numbers):
    /// k − 2 triangles, every one turning with `normal`. False where it finds none such.
    fn ear_clip(&mut self, k: usize, at: &impl Fn(usize) -> DVec3, normal: DVec3, area2: f64) -> bool {
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        self.plane.clear();
        self.plane.extend((0..k).map(|i| {
            let p = at(i);
            [p.dot(u), p.dot(v)]
        }));
        self.earcut.earcut(self.plane.iter().copied(), &[] as &[u32], &mut self.ears);
        let turn = |t: [u32; 3]| {
            let [a, b, c] = t.map(|i| self.plane[i as usize]);
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        };
        // Earcut winds all its triangles one way, which may be against the polygon's.
        self.tris.clear();
        self.tris.extend(self.ears.chunks_exact(3).map(|t| [t[0], t[1], t[2]]));
        if self.tris.iter().map(|&t| turn(t)).sum::<f64>() < 0.0 {
            self.tris.iter_mut().for_each(|t| t.swap(1, 2));
        }
        put_back_skipped_corners(k, &mut self.tris);
        // Covered without folding: k − 2 triangles, none backwards, adding up to the polygon.
        let tolerance = 1e-9 * area2;
        self.tris.len() == k - 2
            && self.tris.iter().all(|&t| turn(t) >= -tolerance)
            && (self.tris.iter().map(|&t| turn(t)).sum::<f64>() - area2).abs() <= tolerance * k as f64
    }
}

fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    out.extend((1..poly.len() - 1).map(|i| [poly[0], poly[i], poly[i + 1]]));
}

/// Earcut leaves out corners on a straight run of the boundary (and repeated points). Each
/// lies on the boundary edge between the corners kept before and after it; the triangle on
/// that edge is split there. Leaves `tris` short where that edge is not found. Linear in the
/// corners (a CAD face may have thousands on its straight edges).
fn put_back_skipped_corners(k: usize, tris: &mut Vec<[u32; 3]>) {
    let mut used = vec![false; k];
    for &c in tris.iter().flatten() {
        used[c as usize] = true;
    }
    let Some(first) = used.iter().position(|&u| u) else { return };
    if used.iter().all(|&u| u) {
        return;
    }
    // The triangle on each directed edge, and the first kept corner after each corner.
    let mut on_edge: HashMap<(u32, u32), usize> = HashMap::new();
    for (ti, t) in tris.iter().enumerate() {
        for e in 0..3 {
            on_edge.insert((t[e], t[(e + 1) % 3]), ti);
        }
    }
    let mut next_kept = vec![first; k];
    let mut kept = first;
    for step in (1..k).rev() {
        let c = (first + step) % k;
        next_kept[c] = kept;
        if used[c] {
            kept = c;
        }
    }
    // Walk the boundary from a kept corner: `prev` is the last corner on it so far, and
    // the corners skipped between `prev` and the next kept one go in one by one.
    let mut prev = first as u32;
    for step in 1..k {
        let c = ((first + step) % k) as u32;
        if !used[c as usize] {
            let next = next_kept[c as usize] as u32;
            let Some(ti) = on_edge.remove(&(prev, next)) else { return };
            let t = tris[ti];
            let apex = t[(t.iter().position(|&x| x == prev).expect("the edge's corner") + 2) % 3];
            tris[ti] = [prev, c, apex];
            on_edge.insert((prev, c), ti);
            on_edge.insert((c, apex), ti);
            tris.push([c, next, apex]);
            let new = tris.len() - 1;
            on_edge.insert((c, next), new);
            on_edge.insert((next, apex), new);
            on_edge.insert((apex, c), new);
        }
        prev = c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(points: &[[f64; 3]]) -> (Triangulated, Vec<[u32; 3]>) {
        let poly: Vec<u32> = (0..points.len() as u32).collect();
        let mut out = Vec::new();
        let how = Triangulator::default().triangulate(&poly, |i| points[i as usize], &mut out);
        (how, out)
    }

    fn area(points: &[[f64; 3]], tris: &[[u32; 3]]) -> f64 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| DVec3::from(points[i as usize]));
                (b - a).cross(c - a).z / 2.0
            })
            .sum()
    }

    /// Ear-clipped into k − 2 triangles over every corner, none backwards, covering `whole`.
    fn assert_ear_clipped(points: &[[f64; 3]], whole: f64) {
        let (how, tris) = run(points);
        assert_eq!(how, Triangulated::EarClipped);
        assert_eq!(tris.len(), points.len() - 2);
        for c in 0..points.len() as u32 {
            assert!(tris.iter().any(|t| t.contains(&c)), "corner {c} left out of {tris:?}");
        }
        for t in &tris {
            assert!(area(points, &[*t]) >= 0.0, "{t:?} turns backwards");
        }
        assert!((area(points, &tris) - whole).abs() < 1e-12);
    }

    #[test]
    fn a_convex_polygon_is_a_fan_from_its_first_corner() {
        let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(run(&square), (Triangulated::Fan, vec![[0, 1, 2], [0, 2, 3]]));
    }

    #[test]
    fn an_l_fanned_from_the_wrong_corner_is_ear_clipped_instead() {
        // The L of area 3, starting at (1, 2): the fan's last triangle turns backwards.
        let l = [[1.0, 2.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        assert_ear_clipped(&l, 3.0);
    }

    #[test]
    fn corners_on_a_straight_edge_stay_in_the_triangulation() {
        // The same L with a corner halfway along its bottom edge and one on its right edge.
        let l = [
            [1.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 0.5, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert_ear_clipped(&l, 3.0);
    }

    #[test]
    fn a_corner_ear_clipping_passes_over_is_put_back() {
        // An L whose corner (0, 0) is written twice: earcut leaves one copy out.
        let l = [
            [1.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert_ear_clipped(&l, 3.0);
    }

    #[test]
    fn runs_of_skipped_corners_go_back_in_order() {
        // A 3 × 1 rectangle with two corners on its bottom edge, triangulated without them.
        let mut tris = vec![[0, 3, 4], [0, 4, 5]];
        put_back_skipped_corners(6, &mut tris);
        assert_eq!(tris, vec![[0, 1, 4], [0, 4, 5], [1, 2, 4], [2, 3, 4]]);
        // Skipped corners on both sides of the first kept one, the last run wrapping round.
        let mut tris = vec![[1, 2, 4]];
        put_back_skipped_corners(6, &mut tris);
        assert_eq!(tris, vec![[2, 3, 1], [4, 5, 3], [5, 0, 3], [0, 1, 3]]);
        // A triangle turned against the boundary has no edge to split: left short.
        let mut tris = vec![[0, 4, 2]];
        put_back_skipped_corners(6, &mut tris);
        assert_eq!(tris, vec![[0, 4, 2]]);
    }

    #[test]
    fn a_polygon_that_crosses_itself_is_fanned_and_said_so() {
        // A pentagram: its fan folds, and no triangulation of its corners covers it.
        let star: Vec<[f64; 3]> = (0..5)
            .map(|i| {
                let a = std::f64::consts::TAU * (2 * i) as f64 / 5.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let (how, tris) = run(&star);
        assert_eq!(how, Triangulated::FannedSelfCrossing);
        assert_eq!(tris, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    }

    use proptest::prelude::*;

    /// A star-shaped polygon around the origin (simple; concave wherever a radius dips),
    /// written from corner `start`, laid in a plane turned by `tilt` and moved by `offset`.
    fn star(radii: &[f64], start: usize, tilt: [f64; 2], offset: [f64; 3]) -> (Vec<[f64; 3]>, DVec3) {
        let k = radii.len();
        let turn = glam::DQuat::from_euler(glam::EulerRot::XYZ, tilt[0], tilt[1], 0.0);
        let points = (0..k)
            .map(|j| {
                let i = (j + start) % k;
                let a = std::f64::consts::TAU * i as f64 / k as f64;
                (turn * DVec3::new(radii[i] * a.cos(), radii[i] * a.sin(), 0.0) + DVec3::from(offset)).to_array()
            })
            .collect();
        (points, turn * DVec3::Z)
    }

    proptest! {
        /// Any simple polygon, in any plane, far out or not, from any first corner: k − 2
        /// triangles over all its corners, none turning against it, adding up to its area; a
        /// fan exactly where the fan does not fold.
        #[test]
        fn simple_polygons_are_covered_without_folding(
            radii in prop::collection::vec(0.1f64..1.0, 4..40),
            start in 0usize..40,
            tilt in prop::array::uniform2(-3.2f64..3.2),
            far in prop::sample::select(vec![0.0, 1e3, 1e6]),
        ) {
            let (points, normal) = star(&radii, start % radii.len(), tilt, [far, -far, far / 3.0]);
            let (how, tris) = run(&points);
            let k = points.len();
            prop_assert_eq!(tris.len(), k - 2);
            let at = |i: u32| DVec3::from(points[i as usize]) - DVec3::from(points[0]);
            let turns: Vec<f64> = tris.iter().map(|t| (at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0])).dot(normal)).collect();
            let polygon: f64 = (0..k).map(|i| at(i as u32).cross(at(((i + 1) % k) as u32)).dot(normal)).sum();
            let tolerance = 1e-9 * polygon;
            prop_assert!(turns.iter().all(|&t| t >= -tolerance), "{:?}: {:?}", how, turns);
            prop_assert!((turns.iter().sum::<f64>() - polygon).abs() <= tolerance * k as f64);
            for c in 0..k as u32 {
                prop_assert!(tris.iter().any(|t| t.contains(&c)), "corner {} left out", c);
            }
            let fan_folds = (1..k - 1).any(|i| at(i as u32).cross(at(i as u32 + 1)).dot(normal) < -tolerance);
            prop_assert_eq!(how, if fan_folds { Triangulated::EarClipped } else { Triangulated::Fan });
        }
    }
}
