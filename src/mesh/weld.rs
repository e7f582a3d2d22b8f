//! Welding: vertices with bit-identical positions become one topological vertex, while every
//! corner keeps the input vertex it came from, so its normal, UVs, colours and tangent
//! survive as a *wedge*.
//!
//! ```text
//!   input (glTF splits at seams)      topology            wedges at vertex v
//!   v7 (uv a) ─┐                       v ── one vertex     wedge 0: uv a  (faces left)
//!   v9 (uv b) ─┴─ same position   =>                       wedge 1: uv b  (faces right)
//! ```
//! -0.0 and +0.0 weld together; NaN never reaches here ([`IndexedMesh::check`]).

use rustc_hash::FxHashMap;

use super::attributes::classes;
use super::{IdMap, IndexedMesh, Location, Repair, RepairKind, VertexAttribute};

/// The mesh while it is being cleaned: welded faces plus the input ids behind every element.
#[derive(Debug, Clone, Default)]
pub(crate) struct Work {
    /// Position per welded vertex.
    pub positions: Vec<[f32; 3]>,
    /// First input vertex of each welded vertex (for reporting).
    pub vertex_src: Vec<u32>,
    /// Faces over welded vertices.
    pub faces: Vec<[u32; 3]>,
    /// Input vertex behind each corner (its attributes make the wedge).
    pub corner_src: Vec<[u32; 3]>,
    /// Input triangle behind each face.
    pub face_src: Vec<u32>,
}

#[inline]
fn pos_key(p: [f32; 3]) -> [u32; 3] {
    // +0.0 for -0.0, so the two zeros weld.
    p.map(|c| (c + 0.0).to_bits())
}

/// Welds positions. Welded ids follow first use in the vertex array, so output is
/// deterministic.
pub(crate) fn weld(input: &IndexedMesh) -> Work {
    let n = input.positions.len();
    let mut map: FxHashMap<[u32; 3], u32> = FxHashMap::default();
    map.reserve(n);
    let mut remap = Vec::with_capacity(n);
    let mut positions = Vec::with_capacity(n);
    let mut vertex_src = Vec::with_capacity(n);
    for (i, &p) in input.positions.iter().enumerate() {
        let next = positions.len() as u32;
        let id = *map.entry(pos_key(p)).or_insert(next);
        if id == next {
            positions.push(p);
            vertex_src.push(i as u32);
        }
        remap.push(id);
    }
    let faces = input.triangles.iter().map(|t| t.map(|i| remap[i as usize])).collect();
    Work {
        positions,
        vertex_src,
        faces,
        corner_src: input.triangles.clone(),
        face_src: (0..input.triangles.len() as u32).collect(),
    }
}

/// Attribute wedges: distinct (vertex, normal, uv, further attributes) per corner.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Wedges {
    /// Topological vertex of each wedge; nothing stored for identity wedges, where wedge v is
    /// vertex v (4 bytes per vertex saved): a mesh without seams, whose corners at a vertex
    /// all have the same attributes ([`into_identity`]). Read through [`Wedges::vertex_of`].
    pub(crate) vertex: IdMap,
    /// Normal per wedge (empty when the input had none).
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinate per wedge (empty when the input had none).
    pub uvs: Vec<[f32; 2]>,
    /// Further attributes ([`IndexedMesh::attributes`]), values per wedge.
    pub attributes: Vec<VertexAttribute>,
    /// Wedge of each corner; corner `3f + c` is the origin of half-edge `3f + c`. Empty when
    /// the wedges are the vertices themselves (no seams: wedge v is vertex v), where
    /// a corner's wedge is its vertex ([`crate::Mesh::corner_wedge`] reads either way) and the
    /// list would repeat the faces (12 bytes per face).
    pub(crate) corner: Vec<u32>,
    /// Input vertex behind each wedge: that of the first corner that made it, whose position
    /// and attributes the wedge carries. Empty for identity wedges, where a wedge's input
    /// vertex is its vertex's ([`crate::Mesh::wedge_source`] reads either way).
    pub(crate) source: Vec<u32>,
}

impl Wedges {
    /// Whether every wedge is its own vertex (no corner list is kept).
    pub fn is_identity(&self) -> bool {
        self.corner.is_empty()
    }

    /// Bytes of the corner list (none for identity wedges).
    pub fn corner_bytes(&self) -> usize {
        self.corner.capacity() * 4
    }

    /// Bytes of the input-vertex list (none for identity wedges).
    pub fn source_bytes(&self) -> usize {
        self.source.capacity() * 4
    }

    /// The topological vertex of wedge `w`.
    #[inline]
    pub fn vertex_of(&self, w: u32) -> u32 {
        self.vertex.get(w as usize)
    }

    /// Bytes of the per-wedge attributes: normals, UVs, further attributes and the
    /// wedge-to-vertex list.
    pub fn attribute_bytes(&self) -> usize {
        let further: usize = self.attributes.iter().map(|a| a.values.capacity() * 4).sum();
        self.vertex_bytes() + self.normals.capacity() * 12 + self.uvs.capacity() * 8 + further
    }

    /// Bytes of the wedge-to-vertex list (none for identity wedges).
    pub fn vertex_bytes(&self) -> usize {
        self.vertex.bytes()
    }

    /// Number of wedges.
    pub fn len(&self) -> usize {
        self.vertex.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Replaces non-finite normals, UVs and further attributes by zero, recording which vertices
/// changed.
pub(crate) fn sanitize_attributes(mesh: &mut IndexedMesh, repairs: &mut Vec<Repair>) {
    let mut r = Repair::new(RepairKind::ZeroedNonFiniteAttributes);
    for i in 0..mesh.positions.len() {
        let mut bad = false;
        if let Some(n) = mesh.normals.get_mut(i) {
            if !n.iter().all(|c| c.is_finite()) {
                *n = [0.0; 3];
                bad = true;
            }
        }
        if let Some(t) = mesh.uvs.get_mut(i) {
            if !t.iter().all(|c| c.is_finite()) {
                *t = [0.0; 2];
                bad = true;
            }
        }
        for a in &mut mesh.attributes {
            let c = a.components;
            for x in &mut a.values[i * c..(i + 1) * c] {
                if !x.is_finite() {
                    *x = 0.0;
                    bad = true;
                }
            }
        }
        if bad {
            r.add(Location::Vertex(i as u32));
        }
    }
    r.push_into(repairs);
}

/// Makes wedges that are one per vertex (a mesh with attributes but no seams: a scan with
/// normals or colours, a smooth UV-mapped surface) identity wedges: their attributes in
/// vertex order, and no corner, wedge-to-vertex or input-vertex list (32 bytes per vertex
/// less). Each vertex's input vertex (`vertex_src`) becomes its wedge's, whose attributes
/// these are: the first input vertex at a position may be an unused copy with others.
pub(crate) fn into_identity(w: &mut Wedges, vertex_src: &mut [u32]) {
    let n = vertex_src.len();
    if w.is_identity() || w.len() != n {
        return;
    }
    let mut of_vertex = vec![u32::MAX; n];
    for wi in 0..n as u32 {
        of_vertex[w.vertex_of(wi) as usize] = wi;
    }
    if of_vertex.contains(&u32::MAX) {
        return; // some vertex has two wedges and another none: not one per vertex
    }
    if !w.normals.is_empty() {
        w.normals = of_vertex.iter().map(|&wi| w.normals[wi as usize]).collect();
    }
    if !w.uvs.is_empty() {
        w.uvs = of_vertex.iter().map(|&wi| w.uvs[wi as usize]).collect();
    }
    for a in &mut w.attributes {
        *a = a.gather(&of_vertex);
    }
    for (src, &wi) in vertex_src.iter_mut().zip(&of_vertex) {
        *src = w.source[wi as usize];
    }
    w.corner = Vec::new();
    w.source = Vec::new();
    w.vertex = IdMap::identity(n);
}

/// Builds wedges for final faces over `vertex_count` vertices, from each corner's input vertex.
pub(crate) fn build_wedges(
    input: &IndexedMesh,
    vertex_count: usize,
    faces: &[[u32; 3]],
    corner_src: &[[u32; 3]],
) -> Wedges {
    let has_n = !input.normals.is_empty();
    let has_uv = !input.uvs.is_empty();
    let mut w = Wedges::default();
    if !has_n && !has_uv && input.attributes.is_empty() {
        // One wedge per vertex: identity, no corner or vertex list.
        w.vertex = IdMap::identity(vertex_count);
        return w;
    }
    w.corner.reserve(faces.len() * 3);
    // Further attributes take part through a class per input vertex (equal values, equal
    // class), so the key stays fixed-size.
    let class = classes(&input.attributes, input.positions.len());
    let mut map: FxHashMap<(u32, [u32; 3], [u32; 2], u32), u32> = FxHashMap::default();
    map.reserve(vertex_count * 5 / 4);
    let mut vertex = Vec::new();
    for (f, src) in faces.iter().zip(corner_src) {
        for c in 0..3 {
            let s = src[c] as usize;
            let n = if has_n { input.normals[s] } else { [0.0; 3] };
            let t = if has_uv { input.uvs[s] } else { [0.0; 2] };
            let key = (f[c], n.map(f32::to_bits), t.map(f32::to_bits), class.get(s).copied().unwrap_or(0));
            let next = vertex.len() as u32;
            let id = *map.entry(key).or_insert(next);
            if id == next {
                vertex.push(f[c]);
                w.source.push(src[c]);
                if has_n {
                    w.normals.push(n);
                }
                if has_uv {
                    w.uvs.push(t);
                }
            }
            w.corner.push(id);
        }
    }
    w.attributes = input.attributes.iter().map(|a| a.gather(&w.source)).collect();
    w.vertex = IdMap::new(vertex);
    w
}
