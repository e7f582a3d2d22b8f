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

/// meshopt's `simplifyWithAttributes` on an indexed mesh, weighing normals, TEXCOORD_0 and
/// the further attributes by kind as [`dynlod::simplify::AttributeWeights`] does (meshopt
/// scales positions into the unit cube, dynlod scales attributes by the extent instead: the
/// same weights mean the same). The result keeps the input's vertices and attributes.
pub fn simplify_mesh_with_attributes(
    m: &IndexedMesh,
    target_triangles: usize,
    w: &dynlod::simplify::AttributeWeights,
) -> IndexedMesh {
    let n = m.positions.len();
    let mut columns: Vec<(Vec<f32>, usize, f32)> = Vec::new();
    if w.of("NORMAL") > 0.0 && !m.normals.is_empty() {
        columns.push((m.normals.as_flattened().to_vec(), 3, w.of("NORMAL")));
    }
    if w.of("TEXCOORD_0") > 0.0 && !m.uvs.is_empty() {
        columns.push((m.uvs.as_flattened().to_vec(), 2, w.of("TEXCOORD_0")));
    }
    for a in &m.attributes {
        let weight = w.of(&a.semantic);
        if weight > 0.0 {
            let read = a.varying_components();
            let v = (0..n).flat_map(|i| a.get(i)[..read].to_vec()).collect();
            columns.push((v, read, weight));
        }
    }
    let k: usize = columns.iter().map(|c| c.1).sum();
    let mut attributes = vec![0.0f32; n * k.max(1)];
    let mut weights = Vec::with_capacity(k);
    let mut at = 0;
    for (values, c, weight) in &columns {
        for i in 0..n {
            attributes[i * k + at..i * k + at + c].copy_from_slice(&values[i * c..(i + 1) * c]);
        }
        weights.extend(std::iter::repeat_n(*weight, *c));
        at += c;
    }
    let indices: Vec<u32> = m.triangles.iter().flatten().copied().collect();
    let bytes: &[u8] = bytemuck::cast_slice(&m.positions);
    let adapter = meshopt::VertexDataAdapter::new(bytes, 12, 0).expect("tightly packed positions");
    let locks = vec![false; n];
    let out = meshopt::simplify_with_attributes_and_locks(
        &indices,
        &adapter,
        &attributes,
        &weights,
        k.max(1) * 4,
        &locks,
        target_triangles * 3,
        1.0,
        meshopt::SimplifyOptions::None,
        None,
    );
    // Primitive ids are left out: meshopt does not keep primitives apart (use on meshes of one).
    IndexedMesh {
        triangles: out.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        triangle_primitive: Vec::new(),
        ..m.clone()
    }
}
