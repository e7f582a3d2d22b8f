//! Instance groups: a mesh's placements shared among its runtimes by distance (a decision
//! beyond papers/000 and papers/001, whose runtime serves one mesh under one view; see
//! `scene_runtime.rs`).
//!
//! A runtime serving several placements holds, for each vertex, the detail its nearest
//! placement needs (its pixels are the largest over the views). Drawn at every placement,
//! that detail is wasted on the far ones: triangles go as the square of the pixels a unit of
//! the mesh covers, so an instance ten times farther than the nearest draws about a hundred
//! times the triangles it needs. Grouping bounds the waste: each placement's *scale* — the
//! most pixels per unit of the mesh's own space it covers in any camera, taken at the point of
//! the mesh's bounding sphere nearest the eye — puts it in one of k bands of equal ratio
//! between the largest and the smallest scale of the frame, and band g is served by runtime g.
//! Within a band the scales differ by at most `(largest / smallest)^(1/k)`; a runtime draws at
//! its own largest.
//!
//! A group that gets placements having never run a frame (added before the first update, or
//! no placement fell in its band since) starts as a copy of the nearest group that has, so
//! it adapts from a warm state instead of coarsening the whole mesh mid-flight.
//!
//! A placement no camera sees (its sphere outside every frustum) has scale 0 and goes to the
//! last band: its views ask nothing of the runtime there. The bands follow the frame's
//! largest and smallest scales, so as the camera moves the placements near a band's edge
//! change runtime: each runtime adapts to its new views as to a camera move, and every
//! instance still sees at most the pixel error. Ties keep the placements' order, and nothing
//! depends on threads: the same cameras share the same way.

use crate::view::{Frustum, View};

use super::scene_runtime::{SceneMeshDef, SceneMeshRuntime};

/// Grouping's lists, kept between frames.
#[derive(Default)]
pub(super) struct GroupScratch {
    scales: Vec<f32>,
}

/// A placement's scale (module docs): the most pixels per unit of the mesh's space any of
/// `cameras` gives it at the point of its sphere nearest the eye (at least a sixteenth of the
/// radius from the centre's side), 0 where no camera sees the sphere.
fn scale(cameras: &[View], world: [[f32; 4]; 4], (centre, radius): ([f32; 3], f32)) -> f32 {
    let mut most = 0.0f32;
    for camera in cameras {
        // Placements are checked when set: every camera carries through them.
        let view = camera.in_model_space(world).expect("placements are checked when they are set");
        let f = Frustum::new(&view);
        if f.touches_sphere(centre, radius) {
            let d = glam::Vec3::from(f.eye()).distance(glam::Vec3::from(centre)) - radius;
            most = most.max(f.pixels_per_unit_at(d.max(radius / 16.0)));
        }
    }
    most
}

/// The band of `scale` among `k` of equal ratio from `largest` down to `smallest` (both
/// positive): 0 holds the largest, k − 1 the smallest and the unseen (scale 0).
fn band(scale: f32, largest: f32, smallest: f32, k: usize) -> usize {
    if scale <= 0.0 {
        return k - 1;
    }
    let span = (largest / smallest).ln();
    if span.is_nan() || span <= 0.0 {
        return 0;
    }
    ((k as f32 * (largest / scale).ln() / span).floor().max(0.0) as usize).min(k - 1)
}

/// Shares every mesh's placements among its runtimes (`runtimes`: by mesh, then group) by
/// `cameras` (none: all to each mesh's first). A mesh with one runtime gets all its
/// placements.
pub(super) fn share(
    defs: &[SceneMeshDef],
    runtimes: &mut [SceneMeshRuntime],
    cameras: &[View],
    sc: &mut GroupScratch,
    generations: &mut u64,
) {
    let mut rest = runtimes;
    for (at, def) in defs.iter().enumerate() {
        let count = rest.iter().take_while(|m| m.mesh == at).count();
        let (mine, after) = rest.split_at_mut(count);
        rest = after;
        for m in mine.iter_mut() {
            m.placements.clear();
            m.instances.clear();
        }
        let k = mine.len();
        sc.scales.clear();
        if k > 1 {
            sc.scales.extend(def.placements.iter().map(|p| scale(cameras, p.world, def.sphere)));
        }
        let largest = sc.scales.iter().copied().fold(0.0f32, f32::max);
        let smallest = sc.scales.iter().copied().filter(|&s| s > 0.0).fold(f32::INFINITY, f32::min);
        for (i, p) in def.placements.iter().enumerate() {
            let g = match sc.scales.get(i) {
                Some(&s) if largest > 0.0 => band(s, largest, smallest, k),
                _ => 0,
            };
            mine[g].placements.push(*p);
            mine[g].instances.push(i);
        }
        warm_up(mine, generations);
    }
}

/// Gives a group that serves placements but never ran a frame a copy of the nearest group
/// that did (a group added before the first update, or one no placement fell in since):
/// it then adapts from a warm state, as to a camera move, instead of coarsening the whole
/// mesh in the middle of a flight. Each copy takes the next of `generations`.
fn warm_up(groups: &mut [SceneMeshRuntime], generations: &mut u64) {
    for g in 0..groups.len() {
        if groups[g].placements.is_empty() || groups[g].runtime.frame > 0 {
            continue;
        }
        let warm = (0..groups.len()).filter(|&h| groups[h].runtime.frame > 0).min_by_key(|&h| (h.abs_diff(g), h));
        if let Some(h) = warm {
            groups[g].runtime = groups[h].runtime.clone();
            *generations += 1;
            groups[g].generation = *generations;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::band;

    #[test]
    fn bands_split_the_ratio_evenly() {
        // Scales from 100 down to 1 in 4 bands: edges at 100 / 10^(2g/4).
        let at = |s| band(s, 100.0, 1.0, 4);
        assert_eq!([at(100.0), at(40.0), at(20.0), at(5.0), at(2.0), at(1.0)], [0, 0, 1, 2, 3, 3]);
        assert_eq!(at(0.0), 3, "unseen: the last band");
        assert_eq!(band(3.0, 3.0, 3.0, 4), 0, "one scale: the first band");
        assert_eq!(band(0.0, 3.0, 3.0, 1), 0);
    }
}
