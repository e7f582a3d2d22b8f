//! Helpers shared by the test files (each test binary includes what it uses).
#![allow(dead_code)]

use dynlod::{procedural, IndexedMesh, Mesh};
use proptest::prelude::*;

/// n · (eye − a) for face `f`: positive when the face turns its front to the eye.
pub fn facing(m: &Mesh, f: [u32; 3], eye: [f64; 3]) -> f64 {
    let [a, b, c] = f.map(|v| glam::DVec3::from(m.positions[v as usize].map(f64::from)));
    (b - a).cross(c - a).dot(glam::DVec3::from(eye) - a)
}

/// Random surfaces: tori (closed, genus 1), bumpy grids with random diagonals (open disks),
/// UV spheres with seams (closed, genus 0 after welding).
pub fn surfaces() -> impl Strategy<Value = IndexedMesh> {
    prop_oneof![
        (6usize..20, 4usize..12).prop_map(|(r, s)| procedural::torus(r, s)),
        (3usize..12, 3usize..12, any::<u64>()).prop_map(|(w, h, bits)| {
            let mut g = procedural::grid(w, h, move |i, j| bits >> ((i * 7 + j) % 64) & 1 == 1);
            for (k, p) in g.positions.iter_mut().enumerate() {
                p[2] = ((k as u64).wrapping_mul(bits | 1) % 97) as f32 / 200.0;
            }
            g
        }),
        (4usize..12, 6usize..16).prop_map(|(a, b)| procedural::uv_sphere(a, b)),
    ]
}

/// `n` proptest cases, times `DYNLOD_PROPTEST_SCALE` when set (a soak run before a release:
/// `DYNLOD_PROPTEST_SCALE=50 cargo test --release`). Cases are drawn afresh every run;
/// failures are kept in the `*.proptest-regressions` files and replayed first.
pub fn cases(n: u32) -> u32 {
    let scale = std::env::var("DYNLOD_PROPTEST_SCALE").ok().and_then(|s| s.parse::<u32>().ok());
    n.saturating_mul(scale.unwrap_or(1).max(1))
}
