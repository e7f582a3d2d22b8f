//! The indexed triangle mesh as files store it: one attribute record per vertex, triangles as
//! index triples, optionally split into primitives (glTF primitives, OBJ objects) that each
//! carry a material. This is what loaders produce and writers consume; it has no connectivity.

use crate::error::MeshError;

/// The most vertices a mesh holds: half the u32 id range (the connectivity's ids count
/// vertices and their wedges).
pub(crate) const MAX_VERTICES: usize = u32::MAX as usize / 2 - 1;

/// A primitive (sub-mesh) of an indexed mesh: a name and a material slot.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Primitive {
    /// Name from the file (glTF mesh name, OBJ object name), possibly empty.
    pub name: String,
    /// Material index in the source file, when it has one.
    pub material: Option<usize>,
    /// The source primitive had no normals while others did: its vertices hold zero normals,
    /// and a GLB written from the mesh leaves NORMAL out of this primitive (so a viewer
    /// computes flat normals, as for the source).
    pub no_normals: bool,
    /// The same for texture coordinates (TEXCOORD_0): zeros inside, left out of a GLB.
    pub no_uvs: bool,
    /// The glTF mesh and primitive it was read from (every node drawing that mesh shares
    /// it).
    pub gltf_source: Option<[usize; 2]>,
}

/// One image of a glTF source: its bytes (embedded in the output) or, when they could not be
/// read, its original URI.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfImage {
    /// The image's name, if any.
    pub name: Option<String>,
    /// MIME type (`image/png`, `image/jpeg`), when known.
    pub mime_type: Option<String>,
    /// The encoded image, or `None` when only the URI is known.
    pub bytes: Option<Vec<u8>>,
    /// The original URI (external file or data URI), when the image was not in a buffer.
    pub uri: Option<String>,
}

/// The material definitions of a glTF source, carried so that a GLB written from the mesh
/// keeps every primitive's material: `materials`, `textures` and `samplers` as the source's
/// JSON arrays (indices unchanged), images with their bytes, and the extensions they use.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GltfMaterials {
    /// The source's `materials` array.
    pub materials: serde_json::Value,
    /// The source's `textures` array.
    pub textures: serde_json::Value,
    /// The source's `samplers` array.
    pub samplers: serde_json::Value,
    /// The source's images, in order.
    pub images: Vec<GltfImage>,
    /// `extensionsUsed` of the source, less mesh-compression extensions.
    pub extensions_used: Vec<String>,
    /// `extensionsRequired` of the source, less mesh-compression extensions.
    pub extensions_required: Vec<String>,
}

/// Triangles over vertices with optional per-vertex normals, texture coordinates and further
/// attributes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IndexedMesh {
    /// Vertex positions, relative to [`IndexedMesh::origin`].
    pub positions: Vec<[f32; 3]>,
    /// Where the positions' zero lies in the file's coordinates. Zero, unless the file's
    /// coordinates lie so far from its origin (more than [`super::origin::FAR`] bounding-box
    /// diagonals) that f32 would lose their precision: then the loaders read them in f64
    /// relative to a round point at the bounds' centre, and every writer adds it back. A
    /// renderer draws the mesh translated by it (or, for precision, relative to the camera).
    pub origin: [f64; 3],
    /// Per-vertex normals: empty, or one per position.
    pub normals: Vec<[f32; 3]>,
    /// Per-vertex texture coordinates (glTF TEXCOORD_0): empty, or one per position. As glTF
    /// has them, with the origin at the image's top-left and v down: OBJ and PLY, which put
    /// it at the bottom-left, are turned over (v ↦ 1 − v) by their loaders and writers
    /// (`io/uv_origin.rs`).
    pub uvs: Vec<[f32; 2]>,
    /// Further per-vertex attributes (`TEXCOORD_1`, `COLOR_0`, `TANGENT`, ...), each with
    /// values for every vertex.
    pub attributes: Vec<super::VertexAttribute>,
    /// Triangles as indices into the vertex arrays, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Primitive of each triangle: empty when there is a single primitive.
    pub triangle_primitive: Vec<u32>,
    /// The primitives. Empty means one unnamed primitive without material.
    pub primitives: Vec<Primitive>,
    /// What the loader had to change to read the file (e.g. skipped line primitives).
    pub load_repairs: Vec<super::Repair>,
    /// Material definitions of a glTF source ([`Primitive::material`] indexes them).
    pub gltf_materials: Option<std::sync::Arc<GltfMaterials>>,
    /// What the source holds that this mesh does not carry (a glTF's node hierarchy,
    /// animations, extra attributes).
    pub not_kept: Vec<super::NotKept>,
}

impl IndexedMesh {
    /// A mesh from positions and triangles only.
    pub fn from_triangles(positions: Vec<[f32; 3]>, triangles: Vec<[u32; 3]>) -> Self {
        Self { positions, triangles, ..Self::default() }
    }

    /// Appends a copy of vertex `v` (position, normal, texture coordinates, every attribute):
    /// its id. For a value that differs between the corners of one vertex (a PLY's texture
    /// coordinate per corner, a tangent frame per corner), which a vertex array holds once
    /// per vertex.
    pub(crate) fn push_copy(&mut self, v: u32) -> u32 {
        let (v, id) = (v as usize, self.positions.len() as u32);
        self.positions.push(self.positions[v]);
        if !self.normals.is_empty() {
            self.normals.push(self.normals[v]);
        }
        if !self.uvs.is_empty() {
            self.uvs.push(self.uvs[v]);
        }
        for a in &mut self.attributes {
            let c = a.components;
            a.values.extend_from_within(v * c..(v + 1) * c);
        }
        id
    }

    /// Primitive id of triangle `t` (0 when there is a single primitive).
    pub fn primitive_of(&self, t: usize) -> u32 {
        self.triangle_primitive.get(t).copied().unwrap_or(0)
    }

    /// Checks what cannot be repaired: emptiness, index range, finite positions, attribute
    /// lengths, primitive ids, and sizes that fit u32 ids. Reports the first defect found.
    pub fn check(&self) -> Result<(), MeshError> {
        let n = self.positions.len();
        if self.triangles.is_empty() && n > 0 {
            return Err(MeshError::NoFaces { vertices: n });
        }
        if self.triangles.is_empty() || n == 0 {
            return Err(MeshError::Empty);
        }
        if n > MAX_VERTICES {
            return Err(MeshError::TooLarge { what: "vertex", count: n });
        }
        if self.triangles.len() >= (u32::MAX / 4) as usize {
            return Err(MeshError::TooLarge { what: "triangle", count: self.triangles.len() });
        }
        for (attribute, len) in [("normal", self.normals.len()), ("uv", self.uvs.len())] {
            if len != 0 && len != n {
                return Err(MeshError::AttributeLength { attribute, len, vertex_count: n });
            }
        }
        for (k, a) in self.attributes.iter().enumerate() {
            let reason = if let Err(why) = a.check_semantic() {
                why
            } else if a.values.len() != a.components * n {
                format!(
                    "{} values, but {n} vertices of {} components need {}",
                    a.values.len(),
                    a.components,
                    a.components * n
                )
            } else if self.attributes[..k].iter().any(|other| other.semantic == a.semantic) {
                "named twice".into()
            } else if a.absent.windows(2).any(|w| w[0] >= w[1])
                || a.absent.last().is_some_and(|&p| p as usize >= self.primitives.len().max(1))
            {
                // `VertexAttribute::present_in` searches the list; writers leave the attribute
                // out of the primitives it names.
                format!(
                    "absent from {:?}: not increasing primitive ids of the mesh's {}",
                    a.absent,
                    self.primitives.len().max(1)
                )
            } else {
                continue;
            };
            return Err(MeshError::BadAttribute { semantic: a.semantic.clone(), reason });
        }
        if !self.triangle_primitive.is_empty() && self.triangle_primitive.len() != self.triangles.len() {
            return Err(MeshError::PrimitiveListLength {
                len: self.triangle_primitive.len(),
                triangle_count: self.triangles.len(),
            });
        }
        // Writers look primitives up by id (a GLB would silently lose the triangles of one
        // that does not exist).
        let primitive_count = self.primitives.len().max(1);
        if let Some((face, &primitive)) =
            self.triangle_primitive.iter().enumerate().find(|(_, &p)| p as usize >= primitive_count)
        {
            return Err(MeshError::PrimitiveOutOfRange { face, primitive, primitive_count });
        }
        if !self.origin.iter().all(|c| c.is_finite()) {
            return Err(MeshError::NonFiniteOrigin { origin: self.origin });
        }
        for (vertex, p) in self.positions.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFiniteCoordinate { vertex, x: p[0], y: p[1], z: p[2] });
            }
        }
        for (face, t) in self.triangles.iter().enumerate() {
            for (corner, &i) in t.iter().enumerate() {
                if i as usize >= n {
                    return Err(MeshError::IndexOutOfRange { face, corner, index: i as i64, vertex_count: n });
                }
            }
        }
        Ok(())
    }

    /// Axis-aligned bounds of the referenced and unreferenced positions alike.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        bounds(self.positions.iter().copied())
    }
}

/// Axis-aligned bounding box of a set of points; `([0;3],[0;3])` when empty.
pub fn bounds(points: impl Iterator<Item = [f32; 3]>) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    let mut any = false;
    for p in points {
        any = true;
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if any {
        (lo, hi)
    } else {
        ([0.0; 3], [0.0; 3])
    }
}
