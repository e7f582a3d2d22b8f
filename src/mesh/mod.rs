//! Meshes: the indexed form files hold ([`IndexedMesh`]), and the welded, repaired, manifold
//! form every algorithm works on ([`Mesh`]): positions + [`Topology`] + attribute [`Wedges`].
//!
//! [`Mesh::build`] runs weld → clean (see `clean.rs`) → connectivity → wedges, and records
//! every repair it made; [`Mesh::to_indexed`] unwelds again for writing or rendering.

mod attributes;
mod clean;
pub mod constraints;
mod id_map;
mod indexed;
mod not_kept;
pub mod origin;
mod repair;
pub(crate) mod spatial_order;
mod weld;

pub(crate) use attributes::parse_morph_target;
pub use attributes::VertexAttribute;
pub use clean::InputDefects;
pub use id_map::IdMap;
pub(crate) use indexed::MAX_VERTICES;
pub use indexed::{bounds, GltfImage, GltfMaterials, IndexedMesh, Primitive};
pub use not_kept::{NotKept, NotKeptKind};
pub use repair::{Location, Repair, RepairKind, MAX_EXAMPLES};
pub use weld::Wedges;

use crate::error::BuildError;
use crate::topology::{vflag, HalfEdges, Topology, INVALID};

/// How [`Mesh::build`] treats defects.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct BuildOptions {
    /// Turn every repair into an error ([`BuildError::RepairNeeded`]). Default: false.
    pub strict: bool,
    /// Also drop triangles of zero area with three distinct vertices. Default: false: they
    /// are topologically sound, and dropping them would open holes (see docs/ARCHITECTURE.md).
    pub drop_zero_area: bool,
    /// Renumber vertices along a Morton curve and faces after them, so that neighbours on
    /// the surface are neighbours in memory: every pass walks fans, and on the bunny the
    /// papers/000 rounds run about a sixth faster (`mesh/spatial_order.rs`). A clean input
    /// then no longer keeps its vertex ids; [`Mesh::vertex_source`] and [`Mesh::face_source`]
    /// still name the input element behind each. Default: false (ids kept); the command
    /// line turns it on.
    pub spatial_order: bool,
}

impl BuildOptions {
    /// Sets [`BuildOptions::strict`].
    pub fn strict(mut self, on: bool) -> Self {
        self.strict = on;
        self
    }

    /// Sets [`BuildOptions::drop_zero_area`].
    pub fn drop_zero_area(mut self, on: bool) -> Self {
        self.drop_zero_area = on;
        self
    }

    /// Sets [`BuildOptions::spatial_order`].
    pub fn spatial_order(mut self, on: bool) -> Self {
        self.spatial_order = on;
        self
    }
}

/// A welded, repaired, manifold triangle mesh with attribute wedges.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Position per topological vertex, relative to [`Mesh::origin`].
    pub positions: Vec<[f32; 3]>,
    /// Where the positions' zero lies in the input's coordinates (see
    /// [`IndexedMesh::origin`]): zero unless the input lay far from its own origin. A renderer
    /// draws the mesh translated by it.
    pub origin: [f64; 3],
    /// Connectivity over those vertices.
    pub topology: Topology,
    /// Per-corner attributes (normals, UVs) as wedges.
    pub wedges: Wedges,
    /// Primitive of each face; empty when every face is in primitive 0 (a single-primitive
    /// mesh, 4 bytes per face saved). Read through [`Mesh::primitive_of`].
    face_primitive: Vec<u32>,
    /// The input's primitives (at least one).
    pub primitives: Vec<Primitive>,
    /// Material definitions of a glTF input, for writing GLB.
    pub gltf_materials: Option<std::sync::Arc<GltfMaterials>>,
    /// What the input holds that this mesh does not carry, so no output written from it has
    /// it (a glTF's node hierarchy, animations, extra attributes).
    pub not_kept: Vec<NotKept>,
    /// First input vertex behind each topological vertex (not stored when it is the identity).
    pub vertex_source: IdMap,
    /// Input triangle behind each face (not stored when it is the identity).
    pub face_source: IdMap,
    /// What was repaired, in pass order.
    pub repairs: Vec<Repair>,
    /// Defects counted in the input before repair.
    pub defects: InputDefects,
    /// Vertex records in the input.
    pub input_vertices: usize,
    /// Triangles in the input (after polygon triangulation).
    pub input_triangles: usize,
}

impl Mesh {
    /// The wedge of corner `g` (the origin of half-edge `g`): from the corner list, or the
    /// corner's own vertex where the wedges are the vertices ([`Wedges::is_identity`]).
    #[inline]
    pub fn corner_wedge(&self, g: u32) -> u32 {
        if self.wedges.is_identity() {
            self.topology.origin(g)
        } else {
            self.wedges.corner[g as usize]
        }
    }

    /// The input vertex behind wedge `w`: an index into the vertices of the [`IndexedMesh`]
    /// this mesh was built from, whose position and attributes are the wedge's (for a loaded
    /// file, the loader's vertex order: docs/ARCHITECTURE.md, "Two meshes"). Wedges merge input
    /// vertices that share all of them, so this is one of those. A renderer that keeps its
    /// own vertex buffer — with skinning weights or anything else dynlod does not carry —
    /// draws the runtime's index buffer through this map
    /// ([`crate::lod::IndexPart::source_triangles`]).
    #[inline]
    pub fn wedge_source(&self, w: u32) -> u32 {
        if self.wedges.is_identity() {
            self.vertex_source.get(w as usize)
        } else {
            self.wedges.source[w as usize]
        }
    }

    /// The position of every wedge, in wedge order: with the wedges' own attributes
    /// ([`Wedges::normals`], [`Wedges::uvs`], [`Wedges::attributes`]), the vertex buffer that
    /// the runtime's index buffer ([`crate::lod::IndexBuffer`]) indexes. No collapse or split
    /// moves a vertex, so a renderer uploads it once.
    pub fn wedge_positions(&self) -> Vec<[f32; 3]> {
        if self.wedges.is_identity() {
            return self.positions.clone();
        }
        (0..self.wedges.len() as u32).map(|w| self.positions[self.wedges.vertex_of(w) as usize]).collect()
    }

    /// Primitive id of face slot `f` (0 when every face is in primitive 0).
    pub fn primitive_of(&self, f: usize) -> u32 {
        self.face_primitive.get(f).copied().unwrap_or(0)
    }

    /// Bytes the per-face primitive ids hold (none for a single-primitive mesh).
    pub fn primitive_bytes(&self) -> usize {
        self.face_primitive.capacity() * 4
    }

    /// Welds, repairs and builds connectivity. Errors name the offending input element;
    /// with `strict`, the first needed repair is an error.
    pub fn build(input: &IndexedMesh, options: BuildOptions) -> Result<Self, BuildError> {
        input.check()?;
        let mut repairs = input.load_repairs.clone();
        let sanitized;
        let input = if has_non_finite_attributes(input) {
            let mut m = input.clone();
            weld::sanitize_attributes(&mut m, &mut repairs);
            sanitized = m;
            &sanitized
        } else {
            input
        };
        let mut defects = InputDefects::default();
        let mut w = weld::weld(input);
        w.drop_degenerate(options.drop_zero_area, &mut repairs, &mut defects);
        let twin = w.repair_topology(&mut repairs, &mut defects);
        w.drop_unreferenced(&mut repairs);
        if w.faces.is_empty() {
            return Err(crate::error::MeshError::AllDegenerate { dropped: input.triangles.len() }.into());
        }
        if options.strict {
            if let Some(r) = repairs.first() {
                return Err(BuildError::RepairNeeded(r.clone()));
            }
        }
        let mut topology = Topology::from_twins(w.positions.len(), w.faces, twin)?;
        let mut wedges = weld::build_wedges(input, w.positions.len(), &topology.faces, &w.corner_src);
        weld::into_identity(&mut wedges, &mut w.vertex_src);
        mark_seams(&mut topology, &wedges);
        let face_primitive = if input.triangle_primitive.iter().all(|&p| p == 0) {
            Vec::new()
        } else {
            w.face_src.iter().map(|&t| input.primitive_of(t as usize)).collect()
        };
        let primitives =
            if input.primitives.is_empty() { vec![Primitive::default()] } else { input.primitives.clone() };
        let mut mesh = Self {
            positions: w.positions,
            origin: input.origin,
            topology,
            wedges,
            face_primitive,
            primitives,
            gltf_materials: input.gltf_materials.clone(),
            not_kept: input.not_kept.clone(),
            vertex_source: IdMap::shifts(w.vertex_src),
            face_source: IdMap::shifts(w.face_src),
            repairs,
            defects,
            input_vertices: input.positions.len(),
            input_triangles: input.triangles.len(),
        };
        if options.spatial_order {
            spatial_order::apply(&mut mesh);
        }
        Ok(mesh)
    }

    /// Unwelds: one output vertex per wedge, live faces in slot order, primitives kept.
    pub fn to_indexed(&self) -> IndexedMesh {
        let w = &self.wedges;
        let mut used = vec![INVALID; w.len()];
        let mut out = IndexedMesh {
            origin: self.origin,
            attributes: w.attributes.iter().map(|a| a.empty_like(w.len())).collect(),
            primitives: self.primitives.clone(),
            gltf_materials: self.gltf_materials.clone(),
            not_kept: self.not_kept.clone(),
            ..Default::default()
        };
        for (f, face) in self.topology.faces.iter().enumerate() {
            if face[0] == INVALID {
                continue;
            }
            let mut tri = [0u32; 3];
            for (c, t) in tri.iter_mut().enumerate() {
                let wi = self.corner_wedge((3 * f + c) as u32) as usize;
                if used[wi] == INVALID {
                    used[wi] = out.positions.len() as u32;
                    out.positions.push(self.positions[w.vertex_of(wi as u32) as usize]);
                    if !w.normals.is_empty() {
                        out.normals.push(w.normals[wi]);
                    }
                    if !w.uvs.is_empty() {
                        out.uvs.push(w.uvs[wi]);
                    }
                    for (a, from) in out.attributes.iter_mut().zip(&w.attributes) {
                        a.values.extend_from_slice(from.get(wi));
                    }
                }
                *t = used[wi];
            }
            out.triangles.push(tri);
            out.triangle_primitive.push(self.primitive_of(f));
        }
        if self.primitives.len() <= 1 {
            out.triangle_primitive.clear();
        }
        out
    }

    /// Edges across which a corner attribute changes (UV or normal seams).
    pub fn seam_edges(&self) -> usize {
        let t = &self.topology;
        if self.wedges.is_identity() {
            return 0;
        }
        let c = |g: u32| self.corner_wedge(g);
        (0..t.twin.len() as u32)
            .filter(|&h| t.is_face_live(h / 3))
            .filter(|&h| {
                let g = t.twin[h as usize];
                g != INVALID && h < g && (c(h) != c(Topology::next(g)) || c(Topology::next(h)) != c(g))
            })
            .count()
    }

    /// Axis-aligned bounds of the vertices.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        bounds(self.positions.iter().copied())
    }
}

fn has_non_finite_attributes(m: &IndexedMesh) -> bool {
    let further = m.attributes.iter().flat_map(|a| &a.values);
    m.normals.iter().flatten().chain(m.uvs.iter().flatten()).chain(further).any(|c| !c.is_finite())
}

/// Flags vertices that carry more than one wedge.
fn mark_seams(t: &mut Topology, w: &Wedges) {
    let mut first = vec![INVALID; t.vertex_count()];
    for (wi, v) in w.vertex.iter().enumerate() {
        if first[v as usize] == INVALID {
            first[v as usize] = wi as u32;
        } else {
            t.vflags[v as usize] |= vflag::SEAM;
        }
    }
}
