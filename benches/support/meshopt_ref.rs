//! The peer every comparison runs against: meshoptimizer's simplifier on positions only,
//! `SimplifyOptions::None`, target error 1.0 so that the triangle count decides. Included by
//! the benches and `examples/quality_report.rs`, so all figures use the same call.

#![allow(dead_code)]

use dynlod::IndexedMesh;

/// meshopt on an index buffer; returns the kept indices.
pub fn simplify_indices(positions: &[[f32; 3]], indices: &[u32], target_triangles: usize) -> Vec<u32> {
    let bytes: &[u8] = bytemuck::cast_slice(positions);
    let adapter = meshopt::VertexDataAdapter::new(bytes, 12, 0).expect("tightly packed positions");
    meshopt::simplify(indices, &adapter, target_triangles * 3, 1.0, meshopt::SimplifyOptions::None, None)
}

/// meshopt on an indexed mesh; the result shares the input's vertex array.
pub fn simplify_mesh(m: &IndexedMesh, target_triangles: usize) -> IndexedMesh {
    let indices: Vec<u32> = m.triangles.iter().flatten().copied().collect();
    let out = simplify_indices(&m.positions, &indices, target_triangles);
    IndexedMesh::from_triangles(m.positions.clone(), out.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect())
}
