//! A glTF read so that it can be written back whole with lighter meshes: the scene's nodes,
//! skins, animations, cameras, materials, extensions and extras stay as the source wrote
//! them, and each mesh definition is read once, in its own space (not baked into world space
//! per instance, as [`load`](super::load) does), to be simplified on its own.
//!
//! Each mesh carries, besides what [`load`](super::load) reads, the vertex data that no
//! simplification here interpolates (every collapse is a half-edge collapse, so each vertex
//! left keeps its own values): joints and weights (`JOINTS_n`, `WEIGHTS_n`),
//! application-specific `_NAME` attributes, and every morph target's deltas
//! (`TARGET{k}:POSITION`, ...). They are further attributes
//! ([`IndexedMesh::attributes`](crate::IndexedMesh)), so vertices that differ in them are
//! different wedges (a seam), and the simplifiers give them no weight.
//! [`GltfScene::save`] writes them back in their source's component types
//! (`write_scene`).

use std::path::Path;
use std::sync::Arc;

use glam::Mat3;

use super::gltf::{malformed, Loader};
use super::gltf_parse::parse_with_buffers;
use crate::error::{LoadError, LoadErrorKind};
use crate::mesh::{GltfMaterials, IndexedMesh};

/// A glTF scene whose triangle meshes can be replaced (see the module docs).
#[derive(Debug, Clone)]
pub struct GltfScene {
    /// The source's JSON, as written.
    pub(super) raw: serde_json::Value,
    /// The source, parsed.
    document: gltf::Document,
    /// The source's buffers.
    pub(super) buffers: Vec<Vec<u8>>,
    /// Its materials, textures, samplers and images, every image's bytes where they could be
    /// read (external files and data URIs are embedded in the output).
    pub(super) resources: Arc<GltfMaterials>,
    /// The mesh definitions that have triangles, in the source's order.
    pub meshes: Vec<SceneMesh>,
}

/// One mesh definition of a [`GltfScene`], in its own space.
#[derive(Debug, Clone)]
pub struct SceneMesh {
    /// Its index among the source's meshes.
    pub index: usize,
    /// Its name in the source (empty if none).
    pub name: String,
    /// Its triangle primitives (points and lines are written back as they were).
    pub mesh: IndexedMesh,
    /// The source's primitive index behind each of `mesh`'s primitives.
    pub primitives: Vec<usize>,
    /// Nodes of the scene [`load`](super::load) reads (the default one, or the first) that
    /// draw it: how many times a flattened load holds it.
    pub instances: usize,
    /// The largest axis scale of those nodes' world transforms (1 where none draws it): a
    /// distance d in the mesh's own units is up to about `scale` × d in the scene (exactly,
    /// for transforms without shear).
    pub scale: f32,
    /// Where it is drawn: one entry per instance, in the order the scene's nodes are walked
    /// (`instances` of them; without a scene, once where it is).
    pub placements: Vec<Placement>,
}

/// One node's drawing of a mesh: what carries a world-space camera into the mesh's own
/// space ([`View::in_model_space`](crate::view::View::in_model_space)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The node's index in the source (`None`: the file has no scene, and the mesh is read
    /// where it is).
    pub node: Option<usize>,
    /// Which of the node's `EXT_mesh_gpu_instancing` instances (`None`: the node has none,
    /// and draws its mesh once).
    pub instance: Option<usize>,
    /// The node's world transform (times the instance's, for an instance), object → world,
    /// column-major (`world[column][row]`).
    pub world: [[f32; 4]; 4],
}

impl Placement {
    /// How errors name it: "node n" (or "node n instance i", for one of a node's GPU
    /// instances), or, where no node is known, "instance k" by its position `k` in its mesh's
    /// list.
    pub fn label(&self, k: usize) -> String {
        match (self.node, self.instance) {
            (Some(n), Some(i)) => format!("node {n} instance {i}"),
            (Some(n), None) => format!("node {n}"),
            (None, _) => format!("instance {k}"),
        }
    }

    /// The longest of the transform's axes: a distance d in the mesh's units is up to about
    /// this times d in the scene.
    fn largest_scale(&self) -> f32 {
        let axes = Mat3::from_mat4(glam::Mat4::from_cols_array_2d(&self.world));
        [axes.x_axis, axes.y_axis, axes.z_axis].iter().map(|a| a.length()).fold(0.0, f32::max)
    }
}

impl SceneMesh {
    /// "mesh 3" or "mesh 3 (wheels)", for messages.
    pub fn label(&self) -> String {
        match self.name.is_empty() {
            true => format!("mesh {}", self.index),
            false => format!("mesh {} ({})", self.index, self.name),
        }
    }
}

impl GltfScene {
    /// The scene's bounds in world space (min, max): every drawn mesh through each of its
    /// placements (zeros when no node draws anything).
    pub fn world_bounds(&self) -> ([f32; 3], [f32; 3]) {
        crate::mesh::bounds(self.meshes.iter().flat_map(|sm| {
            sm.placements.iter().flat_map(|p| {
                let m = glam::Mat4::from_cols_array_2d(&p.world);
                sm.mesh.positions.iter().map(move |&q| m.transform_point3(glam::Vec3::from(q)).to_array())
            })
        }))
    }

    /// Reads a `.gltf` or `.glb` file (external buffers beside it).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, LoadError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|e| LoadError::new(path, e))?;
        Self::from_bytes(&bytes, path.parent()).map_err(|kind| LoadError::new(path, kind))
    }

    /// Parses an in-memory `.gltf` or `.glb`; `base` resolves external buffers and images.
    pub fn from_bytes(bytes: &[u8], base: Option<&Path>) -> Result<Self, LoadErrorKind> {
        super::guarded("glTF", || read(bytes, base))
    }

    /// The scene baked into one mesh in world space: what [`load`](super::load) reads from
    /// the same file (every instance its own copy), from what was read here, not the file
    /// again. [`GltfScene::allot`] shares a simplification of it out.
    pub fn flattened(&self) -> Result<IndexedMesh, LoadErrorKind> {
        super::guarded("glTF", || {
            let materials = (self.document.materials().len() > 0).then(|| self.resources.clone());
            let mesh = super::gltf::flatten(&self.document, &self.buffers, &self.raw, materials)?;
            mesh.check()?;
            Ok(mesh)
        })
    }

    /// [`GltfScene::from_bytes`] without the panic guard, for the fuzz targets: any panic is
    /// a bug.
    #[doc(hidden)]
    pub fn from_bytes_unguarded(bytes: &[u8], base: Option<&Path>) -> Result<Self, LoadErrorKind> {
        read(bytes, base)
    }

    /// Each mesh's share of `flattened`: [`GltfScene::flattened`] (or the same file read by
    /// [`load`](super::load)), built and simplified. Per mesh, the triangles
    /// left of it over all its instances, divided by its instance count, at least 1; `None`
    /// for a mesh the flattened scene does not draw. Used as targets, these give each mesh
    /// what a simplification of the whole scene gave it: an allocation by error across the
    /// scene, where one ratio for every mesh would take as much from a bolt as from a flat
    /// panel.
    pub fn allot(&self, flattened: &crate::Mesh) -> Vec<Option<usize>> {
        let mut left = std::collections::HashMap::<usize, usize>::new();
        for (f, face) in flattened.topology.faces.iter().enumerate() {
            if face[0] == crate::topology::INVALID {
                continue;
            }
            let p = flattened.primitive_of(f) as usize;
            if let Some([mi, _]) = flattened.primitives.get(p).and_then(|p| p.gltf_source) {
                *left.entry(mi).or_default() += 1;
            }
        }
        self.meshes
            .iter()
            .map(|sm| {
                let n = left.get(&sm.index).copied().filter(|_| sm.instances > 0)?;
                Some(((n as f64 / sm.instances as f64).round() as usize).max(1))
            })
            .collect()
    }

    /// Writes the scene with `meshes[i]` (a simplified [`SceneMesh::mesh`], primitives in the
    /// same order) in place of mesh definition `self.meshes[i]`, as GLB, atomically (a
    /// temporary file renamed into place). Returns notes on what the output could not keep
    /// as it was.
    pub fn save(&self, path: impl AsRef<Path>, meshes: &[IndexedMesh]) -> std::io::Result<Vec<String>> {
        let mut notes = Vec::new();
        super::write::atomically(path.as_ref(), |w| {
            notes = self.write_glb(w, meshes)?;
            Ok(())
        })?;
        Ok(notes)
    }

    /// [`GltfScene::save`] into any writer (a half-written output is the caller's to discard).
    /// An error, and nothing written, where `meshes` do not match the scene's (count,
    /// primitives) or a mesh has no triangles left.
    pub fn write_glb(&self, w: &mut impl std::io::Write, meshes: &[IndexedMesh]) -> std::io::Result<Vec<String>> {
        super::write_scene::write_scene_glb(w, self, meshes)
    }
}

fn read(bytes: &[u8], base: Option<&Path>) -> Result<GltfScene, LoadErrorKind> {
    let (g, buffers, raw) = parse_with_buffers(bytes, base)?;
    check_ranges(&g)?;
    let resources = super::gltf::resources(&g, &raw, &buffers, base);
    let materials = (g.materials().len() > 0).then(|| resources.clone());
    // Where each mesh is drawn in the scene `load` reads (the default one, or the first): what
    // a flattened load draws; without a scene, every mesh once, where it is. Its instance
    // count and largest axis scale follow from these.
    let mut placements = vec![Vec::new(); g.meshes().len()];
    let drawn = super::gltf::walk_nodes(&g, &raw, Some(&buffers), &mut |node, instance, world, _| {
        if let Some(m) = node.mesh() {
            let node = Some(node.index());
            placements[m.index()].push(Placement { node, instance, world: world.to_cols_array_2d() });
        }
        Ok(())
    })?;
    if !drawn {
        let here = Placement { node: None, instance: None, world: glam::Mat4::IDENTITY.to_cols_array_2d() };
        placements.iter_mut().for_each(|p| *p = vec![here]);
    }
    let mut meshes = Vec::new();
    for mesh in g.meshes() {
        let mut l = Loader::new(&buffers, Some((&g, &raw)));
        l.add_local_mesh(&mesh)?;
        if !l.has_triangles() {
            continue; // points or lines only: written back as they are
        }
        let primitives = l.primitive_sources();
        let out = l.finish(materials.clone())?;
        out.check()?;
        let name = mesh.name().unwrap_or("").to_string();
        let mi = mesh.index();
        let placements = std::mem::take(&mut placements[mi]);
        let scale = placements.iter().map(Placement::largest_scale).fold(0.0, f32::max);
        let scale = if scale.is_finite() && scale > 0.0 { scale } else { 1.0 };
        let instances = placements.len();
        let mut out = out;
        super::normal_map_tangents::add(&mut out);
        meshes.push(SceneMesh { index: mi, name, mesh: out, primitives, instances, scale, placements });
    }
    if meshes.is_empty() {
        return Err(malformed("no mesh has a triangle primitive"));
    }
    Ok(GltfScene { raw, document: g, buffers, resources, meshes })
}

/// Every buffer view inside its buffer and every accessor laid out inside its view, as the
/// loader checks the mesh data it reads (`layout_defect`): the writer copies what the
/// source's skins, animations and other primitives use as it is, and what is not there
/// could only come out as garbage.
fn check_ranges(g: &gltf::Document) -> Result<(), LoadErrorKind> {
    for v in g.views() {
        // `load_buffers` checked that each buffer holds the bytes it declares.
        let held = v.buffer().length();
        if v.offset().checked_add(v.length()).is_none_or(|end| end > held) {
            return Err(malformed(format!(
                "buffer view {} ({} bytes from {}) runs past the end of buffer {} ({held} bytes)",
                v.index(),
                v.length(),
                v.offset(),
                v.buffer().index()
            )));
        }
    }
    for a in g.accessors() {
        if let Some(why) = super::gltf_accessor::layout_defect(&a, &format!("accessor {}", a.index())) {
            return Err(malformed(why));
        }
    }
    Ok(())
}
