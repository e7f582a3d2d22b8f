//! Midpoint subdivision, for a million-triangle mesh from igea (`igea ×4` in
//! docs/BENCHMARKS.md). Included by `benches/runtime.rs` and `examples/still_camera.rs`.

use dynlod::IndexedMesh;

/// Splits every triangle into four at its edge midpoints (shared midpoints, so it stays
/// watertight where the input was).
pub fn subdivide(m: &IndexedMesh) -> IndexedMesh {
    let mut positions = m.positions.clone();
    let mut mid = std::collections::HashMap::new();
    let mut at = |a: u32, b: u32, positions: &mut Vec<[f32; 3]>| {
        *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let (p, q) = (positions[a as usize], positions[b as usize]);
            positions.push([0, 1, 2].map(|k| 0.5 * (p[k] + q[k])));
            positions.len() as u32 - 1
        })
    };
    let mut triangles = Vec::with_capacity(m.triangles.len() * 4);
    for &[a, b, c] in &m.triangles {
        let (ab, bc, ca) = (at(a, b, &mut positions), at(b, c, &mut positions), at(c, a, &mut positions));
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    IndexedMesh::from_triangles(positions, triangles)
}
