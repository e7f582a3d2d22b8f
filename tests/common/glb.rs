//! GLB files built in the tests: a JSON document and its binary chunks laid out in one buffer.

use serde_json::json;

/// Little-endian bytes of a list of values.
pub fn bytes<T: Copy, const N: usize>(values: &[T], to: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| to(v)).collect()
}

/// `doc` with `chunks` laid out in one buffer, one view each (4-byte aligned), and the buffer.
pub fn pack(mut doc: serde_json::Value, chunks: &[Vec<u8>]) -> (serde_json::Value, Vec<u8>) {
    let mut bin = Vec::new();
    let mut views = Vec::new();
    for c in chunks {
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": c.len()}));
        bin.extend_from_slice(c);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
    }
    doc["bufferViews"] = json!(views);
    doc["buffers"] = json!([{"byteLength": bin.len()}]);
    (doc, bin)
}

/// A GLB of `doc` and `chunks`.
pub fn glb((doc, chunks): (serde_json::Value, Vec<Vec<u8>>)) -> Vec<u8> {
    let (doc, bin) = pack(doc, &chunks);
    let mut text = serde_json::to_vec(&doc).unwrap();
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((12 + 8 + text.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(text);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// A bumpy n×n grid in the unit square at z = 0 (n² · 2 triangles).
pub fn bumpy_grid(n: usize) -> (Vec<[f32; 3]>, Vec<u16>) {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push([x, y, 0.02 * ((x * 9.0).sin() * (y * 7.0).cos())]);
        }
    }
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = (j * (n + 1) + i) as u16;
            let (b, c, d) = (a + 1, a + (n + 1) as u16, a + (n + 2) as u16);
            indices.extend([a, b, d, a, d, c]);
        }
    }
    (positions, indices)
}

/// A GLB whose mesh 0, a bumpy grid, is drawn by one node per entry of `nodes` (glTF node
/// objects without their "mesh"), and whose mesh 1, a smaller grid, no node draws.
pub fn two_grids(nodes: &[serde_json::Value]) -> Vec<u8> {
    let (p, idx) = bumpy_grid(40);
    let (q, qdx) = bumpy_grid(6);
    let bounds = |p: &[[f32; 3]]| dynlod::mesh::bounds(p.iter().copied());
    let ((plo, phi), (qlo, qhi)) = (bounds(&p), bounds(&q));
    let nodes: Vec<serde_json::Value> = nodes
        .iter()
        .map(|n| {
            let mut n = n.clone();
            n["mesh"] = json!(0);
            n
        })
        .collect();
    let doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": [
            {"name": "ground", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]},
            {"name": "spare", "primitives": [{"attributes": {"POSITION": 2}, "indices": 3}]},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": p.len(), "type": "VEC3", "min": plo, "max": phi},
            {"bufferView": 1, "componentType": 5123, "count": idx.len(), "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": q.len(), "type": "VEC3", "min": qlo, "max": qhi},
            {"bufferView": 3, "componentType": 5123, "count": qdx.len(), "type": "SCALAR"},
        ],
    });
    let chunks = vec![
        bytes(&p.concat(), f32::to_le_bytes),
        bytes(&idx, u16::to_le_bytes),
        bytes(&q.concat(), f32::to_le_bytes),
        bytes(&qdx, u16::to_le_bytes),
    ];
    glb((doc, chunks))
}
