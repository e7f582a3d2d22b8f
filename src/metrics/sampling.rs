//! Metro-style surface sampling (Cignon, Rocchini, Scopigno 1998): every vertex, points along
//! every edge, and points inside every face, at a uniform density over the surface.
//!
//! With `density` d and F faces, the surface gets about d·F interior samples spread by area
//! (a face's share is its area / total area, rounded stochastically), and each edge gets
//! points spaced by the side of the square that one interior sample covers. Random numbers
//! come from a hash of (face, k), so the samples are the same on every run and thread count.

use glam::Vec3;
use rustc_hash::FxHashSet;

/// A deterministic uniform number in [0, 1) from a key (SplitMix64 finaliser).
pub(crate) fn unit(key: u64) -> f32 {
    let mut z = key.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

/// Area of a triangle.
pub(crate) fn area(t: &[[f32; 3]; 3]) -> f32 {
    let [a, b, c] = t.map(Vec3::from);
    0.5 * (b - a).cross(c - a).length()
}

/// Sample points on the triangles `tris` (corner positions) at `density` interior samples
/// per face on average, plus vertices and edges. `vertices` are the distinct corner positions.
pub fn sample(tris: &[[[f32; 3]; 3]], density: f32) -> Vec<[f32; 3]> {
    let (want, per_sample_area) = per_sample(tris, density);
    let spacing = per_sample_area.sqrt() as f32;
    let mut out = Vec::with_capacity(want + 3 * tris.len());
    let mut seen_v: FxHashSet<[u32; 3]> = FxHashSet::default();
    let mut seen_e: FxHashSet<([u32; 3], [u32; 3])> = FxHashSet::default();
    let key = |p: [f32; 3]| p.map(|c| (c + 0.0).to_bits());
    for (f, t) in tris.iter().enumerate() {
        for c in 0..3 {
            let (a, b) = (t[c], t[(c + 1) % 3]);
            if seen_v.insert(key(a)) {
                out.push(a);
            }
            let (ka, kb) = (key(a), key(b));
            if spacing > 0.0 && seen_e.insert(if ka < kb { (ka, kb) } else { (kb, ka) }) {
                let n = (Vec3::from(b).distance(Vec3::from(a)) / spacing) as usize;
                for k in 1..=n {
                    let s = k as f32 / (n + 1) as f32;
                    out.push([a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s, a[2] + (b[2] - a[2]) * s]);
                }
            }
        }
        if per_sample_area <= 0.0 {
            continue;
        }
        interior(f, t, per_sample_area, |[wa, wb, wc]| {
            out.push(std::array::from_fn(|i| wa * t[0][i] + wb * t[1][i] + wc * t[2][i]));
        });
    }
    out
}

/// The interior samples of [`sample`] alone, as (face, barycentric coordinates): the same
/// points, for measures that read what the face interpolates there.
pub fn sample_interior(tris: &[[[f32; 3]; 3]], density: f32) -> Vec<(u32, [f32; 3])> {
    let (want, per_sample_area) = per_sample(tris, density);
    let mut out = Vec::with_capacity(want + tris.len());
    if per_sample_area <= 0.0 {
        return out;
    }
    for (f, t) in tris.iter().enumerate() {
        interior(f, t, per_sample_area, |w| out.push((f as u32, w)));
    }
    out
}

/// How many interior samples `density` asks for on `tris` (at least 1), and the area each
/// covers (0 on a surface without area).
fn per_sample(tris: &[[[f32; 3]; 3]], density: f32) -> (usize, f64) {
    let total_area: f64 = tris.iter().map(|t| area(t) as f64).sum();
    let want = (density.max(0.0) as f64 * tris.len() as f64).max(1.0);
    (want as usize, if total_area > 0.0 { total_area / want } else { 0.0 })
}

/// Face `f`'s interior samples (barycentric), one per `per_sample_area` of its area,
/// rounded stochastically.
fn interior(f: usize, t: &[[f32; 3]; 3], per_sample_area: f64, mut emit: impl FnMut([f32; 3])) {
    let exact = area(t) as f64 / per_sample_area;
    let base = (f as u64) << 20;
    let n = exact.floor() as u64 + u64::from((unit(base) as f64) < exact.fract());
    for k in 0..n {
        // Uniform point in the triangle: r1 = sqrt(u), r2 = v.
        let r1 = unit(base + 2 * k + 1).sqrt();
        let r2 = unit(base + 2 * k + 2);
        emit([1.0 - r1, r1 * (1.0 - r2), r1 * r2]);
    }
}
