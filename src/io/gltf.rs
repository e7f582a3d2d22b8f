//! glTF 2.0 (`.gltf` with external or data-URI buffers, and `.glb`) through the `gltf` crate,
//! without decoding images. Every primitive of every mesh instanced by the default scene (or
//! the first scene; the first that has nodes where that one is empty; or, with no scene,
//! every mesh once) is read with its node's world transform applied: positions by the
//! matrix, normals by its inverse transpose, winding reversed under a mirroring transform.
//! A node with `EXT_mesh_gpu_instancing` draws its mesh once per instance, each under the
//! node's transform times the instance's (`gltf_instancing`).
//! POSITION, NORMAL and TEXCOORD_0 are kept, quantized ones too (`gltf_accessor`), and so are
//! further texture coordinates, colours and tangents (`gltf_attributes`); each (mesh,
//! primitive) pair becomes one [`Primitive`] with its material index. The document is split
//! from a GLB, checked and validated in `gltf_parse`, its extensions in `gltf_extensions`;
//! buffers, images and the material definitions a GLB output carries are read in
//! `gltf_resources`.
//!
//! Triangle lists, strips and fans are read; point and line primitives, and those without
//! POSITION, are skipped and the skip is recorded as a repair (an error if the file has
//! nothing else), as are the one or two indices a triangle list's count leaves over. A POSITION accessor without the `min` and
//! `max` glTF requires is read and recorded too (`gltf_parse`, which reads the document).
//!
//! The same [`Loader`] reads one mesh definition at a time in its own space for
//! `gltf_scene`, which keeps the scene around the meshes; such a load also reads joints,
//! weights, `_NAME` attributes and morph targets, as they are.

use std::collections::BTreeSet;
use std::path::Path;

use glam::{DMat3, DMat4, DQuat, DVec3, Mat3, Mat4, Vec3};
use gltf::mesh::Mode;

use super::gltf_accessor::{read, unreadable};
use super::gltf_attributes::{append, carried, mark_absent, read_attribute, read_values, verbatim};
use super::gltf_extensions::{material_extensions, not_carried};
use super::gltf_parse::{bounded, parse_with_buffers};
use super::gltf_resources::materials;
use crate::error::LoadErrorKind;
use crate::mesh::{
    IndexedMesh, Location, NotKept, NotKeptKind, Primitive, Repair, RepairKind, VertexAttribute, MAX_EXAMPLES,
};

pub(super) fn malformed(message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Malformed { format: "glTF", line: None, message: message.into() }
}

const MAX_NODE_DEPTH: usize = 256;

pub(super) struct Loader<'a> {
    buffers: &'a [Vec<u8>],
    /// A scene-keeping load (`gltf_scene`): the document and its JSON, from which joints,
    /// weights, `_NAME` attributes and morph-target deltas are read too, as they are.
    scene: Option<(&'a gltf::Document, &'a serde_json::Value)>,
    out: IndexedMesh,
    /// Whether any primitive read has normals, texture coordinates.
    any_normals: bool,
    any_uvs: bool,
    prim_ids: std::collections::HashMap<(usize, usize), u32>,
    /// What the output loses: primitives of point or line modes or without POSITION (a
    /// flattening load only; a scene-keeping output keeps them as they are), and the one or
    /// two indices a triangle primitive's count leaves over.
    skipped: Repair,
    /// Primitives whose normals or texture coordinates could not be read as such.
    unreadable: Repair,
    /// Primitives whose POSITION accessor lacks the min and max glTF requires.
    unbounded: Repair,
    first_skipped: Option<(usize, usize, Mode)>,
    /// Vertex blocks already read, by (POSITION, readable NORMAL, readable TEXCOORD_0
    /// accessors; readable further attributes; world transform bits).
    blocks: std::collections::HashMap<BlockKey, Block>,
    /// The further attributes each primitive was read with, by primitive id.
    prim_attributes: Vec<Vec<String>>,
    /// What the mesh will not carry, counted while reading (see `not_kept`).
    seen: Seen,
    /// Once any node transform is not the identity (a flattening load only): the positions
    /// as the accessors hold them, and each block's first vertex and world transform, so a
    /// placement far from the origin keeps its precision (`mesh/origin.rs`, [`far_placed`]).
    local: Vec<[f32; 3]>,
    placed: Vec<(usize, DMat4)>,
    /// The world transform of the node being read, in f64 from the JSON's own numbers.
    world64: DMat4,
}

type BlockKey = ([Option<usize>; 3], Vec<(String, usize)>, [u32; 16]);

/// Vertices of one or more primitives in the output: `n` from `base`, whether they carry
/// the source's normals and texture coordinates, and which further attributes.
#[derive(Clone)]
struct Block {
    base: usize,
    n: usize,
    has_normals: bool,
    has_uvs: bool,
    attributes: Vec<String>,
}

/// Counts behind the [`NotKept`] list of a glTF input.
#[derive(Default)]
struct Seen {
    /// Nodes visited, `EXT_mesh_gpu_instancing` instances drawn, and how many times each
    /// mesh was drawn by a node or an instance.
    nodes: usize,
    gpu_instances: usize,
    instances: std::collections::BTreeMap<usize, usize>,
    /// Whether any drawn mesh had a transform other than the identity.
    transformed: bool,
    /// Primitives (each once) with morph targets.
    with_morphs: usize,
    /// Attributes not carried (joints, weights, application-specific ones), and the
    /// primitives having any.
    other_attributes: std::collections::BTreeSet<String>,
    with_other_attributes: usize,
}

pub(super) fn load(bytes: &[u8], base: Option<&Path>) -> Result<IndexedMesh, LoadErrorKind> {
    let (g, buffers, raw) = parse_with_buffers(bytes, base)?;
    let materials = (g.materials().len() > 0).then(|| resources(&g, &raw, &buffers, base));
    flatten(&g, &buffers, &raw, materials)
}

/// The scene baked into one mesh in world space (see the module docs), with `materials`.
pub(super) fn flatten(
    g: &gltf::Document,
    buffers: &[Vec<u8>],
    raw: &serde_json::Value,
    materials: Option<std::sync::Arc<crate::mesh::GltfMaterials>>,
) -> Result<IndexedMesh, LoadErrorKind> {
    drawn_vertices(g, raw)?;
    let mut l = Loader::new(buffers, None);
    if !walk_nodes(g, raw, Some(buffers), &mut |node, instance, world, world64| {
        l.visit(node, instance, world, world64)
    })? {
        for mesh in g.meshes() {
            l.add_mesh(&mesh, Mat4::IDENTITY)?;
        }
    }
    let not_kept = not_kept(g, raw, &material_extensions(raw), &l.seen);
    let mut out = l.finish(materials)?;
    out.not_kept = not_kept;
    Ok(out)
}

/// What [`walk_nodes`] calls: a node, which of its `EXT_mesh_gpu_instancing` instances
/// (`None`: it has none), and the transform its mesh is drawn under, as the `gltf` crate
/// reads the nodes' (f32), and the same from the JSON's own numbers in f64 (a survey tile's
/// translation keeps its millimetres).
type NodeVisit<'f, 'd> = &'f mut dyn FnMut(gltf::Node<'d>, Option<usize>, Mat4, DMat4) -> Result<(), LoadErrorKind>;

/// Refuses, before anything is read, a scene whose flattening would draw more vertices than
/// a mesh can hold (u32 ids): nodes and instances multiply a mesh's vertices, and a small
/// file can ask for billions of copies. Each mesh's position accessors count once, however
/// many primitives share one (and one whose elements are not in its buffer not at all).
fn drawn_vertices(g: &gltf::Document, raw: &serde_json::Value) -> Result<(), LoadErrorKind> {
    let per_mesh: Vec<usize> = g
        .meshes()
        .map(|m| {
            let positions: std::collections::BTreeMap<usize, usize> = m
                .primitives()
                .filter_map(|p| p.get(&gltf::Semantic::Positions))
                // One whose elements are not there gets the reader's error, which says why.
                .filter(|a| super::gltf_accessor::layout_defect(a, "").is_none())
                .map(|a| (a.index(), a.count()))
                .collect();
            positions.values().fold(0usize, |a, &n| a.saturating_add(n))
        })
        .collect();
    // The walk stops at the node that passes the limit, and the count there is reported.
    let within = |total: usize| match total > crate::mesh::MAX_VERTICES {
        true => Err(crate::error::MeshError::TooLarge { what: "vertex", count: total }.into()),
        false => Ok(()),
    };
    let mut total = 0usize;
    let drawn = walk_nodes(g, raw, None, &mut |node, _, _, _| {
        let copies = super::gltf_instancing::declared_count(g, raw, &node);
        total = total.saturating_add(node.mesh().map_or(0, |m| per_mesh[m.index()]).saturating_mul(copies));
        within(total)
    })?;
    match drawn {
        true => Ok(()),
        false => within(per_mesh.iter().fold(0, |a, &n| a.saturating_add(n))),
    }
}

/// Calls `f` on every node of the scene a load reads (the default one, or else the first,
/// where it draws anything; else the first scene that does) with its world transform (once
/// per instance, under the instance's transform, where `EXT_mesh_gpu_instancing` gives it
/// instances; with `buffers` `None`, each node once, its instances not read), each node
/// before its children; false where no scene has a node (none at all, or only empty ones),
/// and every mesh is read once, where it is.
/// An error for a hierarchy deeper than [`MAX_NODE_DEPTH`] (a cycle).
pub(super) fn walk_nodes<'d>(
    g: &'d gltf::Document,
    raw: &serde_json::Value,
    buffers: Option<&[Vec<u8>]>,
    f: NodeVisit<'_, 'd>,
) -> Result<bool, LoadErrorKind> {
    struct Walk<'w, 'd> {
        g: &'d gltf::Document,
        raw: &'w serde_json::Value,
        buffers: Option<&'w [Vec<u8>]>,
    }
    fn walk<'d>(
        node: gltf::Node<'d>,
        (parent, parent64): (Mat4, DMat4),
        depth: usize,
        w: &Walk<'_, 'd>,
        f: NodeVisit<'_, 'd>,
    ) -> Result<(), LoadErrorKind> {
        if depth > MAX_NODE_DEPTH {
            return Err(malformed(format!(
                "node hierarchy deeper than {MAX_NODE_DEPTH} (a cycle?) at node {}",
                node.index()
            )));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let world64 = parent64 * local_f64(&w.raw["nodes"][node.index()]).unwrap_or_else(|| world.as_dmat4());
        let instances = w.buffers.map(|b| super::gltf_instancing::instances(w.g, w.raw, b, &node)).transpose()?;
        match instances.flatten() {
            None => f(node.clone(), None, world, world64)?,
            Some(instances) => {
                for (k, instance) in instances.iter().enumerate() {
                    f(node.clone(), Some(k), world * instance.as_mat4(), world64 * *instance)?;
                }
            }
        }
        for child in node.children() {
            walk(child, (world, world64), depth + 1, w, f)?;
        }
        Ok(())
    }
    let drawing = |s: &gltf::Scene<'_>| s.nodes().len() > 0;
    let first = g.default_scene().or_else(|| g.scenes().next()).filter(drawing);
    let Some(scene) = first.or_else(|| g.scenes().find(drawing)) else {
        return Ok(false);
    };
    let w = Walk { g, raw, buffers };
    for node in scene.nodes() {
        walk(node, (Mat4::IDENTITY, DMat4::IDENTITY), 0, &w, f)?;
    }
    Ok(true)
}

/// A node's local transform from its JSON in f64: `matrix`, or `translation`, `rotation` and
/// `scale` (each defaulting as glTF says). None where a field is not what glTF says it is.
fn local_f64(node: &serde_json::Value) -> Option<DMat4> {
    let numbers = |key: &str, default: &[f64]| -> Option<Vec<f64>> {
        match &node[key] {
            serde_json::Value::Null => Some(default.to_vec()),
            v => v.as_array().filter(|a| a.len() == default.len())?.iter().map(serde_json::Value::as_f64).collect(),
        }
    };
    if !node["matrix"].is_null() {
        return Some(DMat4::from_cols_slice(&numbers("matrix", &[0.0; 16])?));
    }
    let (t, r, s) =
        (numbers("translation", &[0.0; 3])?, numbers("rotation", &[0.0, 0.0, 0.0, 1.0])?, numbers("scale", &[1.0; 3])?);
    Some(DMat4::from_scale_rotation_translation(
        DVec3::from_slice(&s),
        DQuat::from_xyzw(r[0], r[1], r[2], r[3]),
        DVec3::from_slice(&t),
    ))
}

/// The source's material definitions, textures, samplers and images (read from wherever
/// they are) that a GLB output carries.
pub(super) fn resources(
    g: &gltf::Document,
    raw: &serde_json::Value,
    buffers: &[Vec<u8>],
    base: Option<&Path>,
) -> std::sync::Arc<crate::mesh::GltfMaterials> {
    std::sync::Arc::new(materials(g, raw, &material_extensions(raw), buffers, base))
}

impl<'a> Loader<'a> {
    pub(super) fn new(buffers: &'a [Vec<u8>], scene: Option<(&'a gltf::Document, &'a serde_json::Value)>) -> Self {
        Loader {
            buffers,
            scene,
            out: IndexedMesh::default(),
            any_normals: false,
            any_uvs: false,
            prim_ids: Default::default(),
            skipped: Repair::new(RepairKind::SkippedNonTrianglePrimitives),
            unreadable: Repair::new(RepairKind::DroppedUnreadableAttributes),
            unbounded: Repair::new(RepairKind::RecomputedPositionBounds),
            first_skipped: None,
            blocks: Default::default(),
            prim_attributes: Vec::new(),
            seen: Seen::default(),
            local: Vec::new(),
            placed: Vec::new(),
            world64: DMat4::IDENTITY,
        }
    }

    /// The glTF primitive index behind each primitive read so far, in primitive-id order.
    pub(super) fn primitive_sources(&self) -> Vec<usize> {
        let mut by_id: Vec<(u32, usize)> = self.prim_ids.iter().map(|(&(_, pi), &id)| (id, pi)).collect();
        by_id.sort_unstable();
        by_id.into_iter().map(|(_, pi)| pi).collect()
    }

    /// Whether any triangle was read.
    pub(super) fn has_triangles(&self) -> bool {
        !self.out.triangles.is_empty()
    }

    /// Reads one mesh definition in its own space (a scene-keeping load).
    pub(super) fn add_local_mesh(&mut self, mesh: &gltf::Mesh<'_>) -> Result<(), LoadErrorKind> {
        self.add_mesh(mesh, Mat4::IDENTITY)
    }

    /// The mesh read, with `materials`; an error where no primitive had triangles.
    pub(super) fn finish(
        self,
        materials: Option<std::sync::Arc<crate::mesh::GltfMaterials>>,
    ) -> Result<IndexedMesh, LoadErrorKind> {
        let mut out = self.out;
        if self.scene.is_none() {
            (out.positions, out.origin) = if self.placed.is_empty() {
                crate::mesh::origin::relative_f32_positions(out.positions)
            } else {
                far_placed(out.positions, &self.local, &self.placed)
            };
        }
        if out.triangles.is_empty() {
            if let Some((mesh, primitive, mode)) = self.first_skipped {
                return Err(LoadErrorKind::UnsupportedPrimitiveMode { mesh, primitive, mode: format!("{mode:?}") });
            }
        }
        // An attribute that some primitives lack is kept for the others: the primitives without
        // it hold zeros and are flagged, so a GLB leaves it out of them as the source did.
        if !self.any_normals {
            out.normals.clear();
            out.primitives.iter_mut().for_each(|p| p.no_normals = false);
        }
        if !self.any_uvs {
            out.uvs.clear();
            out.primitives.iter_mut().for_each(|p| p.no_uvs = false);
        }
        mark_absent(&mut out.attributes, &self.prim_attributes);
        if out.primitives.len() <= 1 {
            out.triangle_primitive.clear();
        }
        self.skipped.push_into(&mut out.load_repairs);
        self.unbounded.push_into(&mut out.load_repairs);
        self.unreadable.push_into(&mut out.load_repairs);
        out.gltf_materials = materials;
        Ok(out)
    }
}

/// Every morph target attribute of primitive `pi` of mesh `mi`, as the JSON names it: its
/// carried name (`TARGETk:S`) and accessor index. Read from the JSON, since the `gltf` crate
/// knows only POSITION, NORMAL and TANGENT targets.
fn morph_targets(raw: &serde_json::Value, mi: usize, pi: usize) -> impl Iterator<Item = (String, &serde_json::Value)> {
    let targets = raw["meshes"][mi]["primitives"][pi]["targets"].as_array().into_iter().flatten();
    targets.enumerate().flat_map(|(k, t)| {
        t.as_object().into_iter().flatten().map(move |(s, i)| (VertexAttribute::morph_target_semantic(k, s), i))
    })
}

/// What a glTF input holds that the mesh read from it does not carry.
fn not_kept(g: &gltf::Document, raw: &serde_json::Value, carried: &BTreeSet<String>, seen: &Seen) -> Vec<NotKept> {
    let mut out = Vec::new();
    let mut note = |kind, count: usize, detail: String| {
        if count > 0 {
            out.push(NotKept::new(kind, count, detail));
        }
    };
    let instances: usize = seen.instances.values().sum();
    if instances > 1 || seen.transformed {
        let mut detail = format!("{} nodes", seen.nodes);
        if seen.gpu_instances > 0 {
            detail.push_str(&format!("; {} {} instances", seen.gpu_instances, super::gltf_instancing::EXTENSION));
            let other = super::gltf_instancing::other_attributes(raw);
            if !other.is_empty() {
                let names: Vec<&str> = other.iter().map(String::as_str).collect();
                detail.push_str(&format!(" (their attributes {} not kept)", names.join(", ")));
            }
        }
        let repeated: Vec<(&usize, &usize)> = seen.instances.iter().filter(|(_, &n)| n > 1).collect();
        for (mesh, n) in repeated.iter().take(MAX_EXAMPLES) {
            detail.push_str(&format!("; mesh {mesh} drawn {n} times"));
        }
        if repeated.len() > MAX_EXAMPLES {
            detail.push_str(&format!("; {} more meshes drawn more than once", repeated.len() - MAX_EXAMPLES));
        }
        note(NotKeptKind::FlattenedScene, instances, detail);
    }
    note(NotKeptKind::OtherScenes, g.scenes().len().saturating_sub(1), String::new());
    note(NotKeptKind::Animations, g.animations().len(), String::new());
    note(NotKeptKind::Skins, g.skins().len(), String::new());
    note(NotKeptKind::Cameras, g.cameras().len(), String::new());
    note(NotKeptKind::MorphTargets, seen.with_morphs, String::new());
    let names: Vec<&str> = seen.other_attributes.iter().map(String::as_str).collect();
    note(NotKeptKind::OtherAttributes, seen.with_other_attributes, names.join(", "));
    let lost = not_carried(raw, carried);
    note(NotKeptKind::Extensions, lost.len(), lost.join(", "));
    out
}

/// The positions of a flattening load where a node transform was not the identity:
/// `transformed` (in f32, as before) unless the scene lies far from its origin
/// (`mesh/origin.rs`). Far out, when every block has the same translation and nothing else
/// (our GLB writer's node, a survey tile's placement), the accessors' positions as they are
/// and the translation as the origin, bit for bit; else the blocks transformed in f64,
/// relative to a round point at their centre.
fn far_placed(transformed: Vec<[f32; 3]>, local: &[[f32; 3]], placed: &[(usize, DMat4)]) -> (Vec<[f32; 3]>, [f64; 3]) {
    let mut wide = Vec::with_capacity(local.len());
    for (k, &(base, world)) in placed.iter().enumerate() {
        let end = placed.get(k + 1).map_or(local.len(), |next| next.0);
        wide.extend(local[base..end].iter().map(|p| world.transform_point3(DVec3::from(p.map(f64::from))).to_array()));
    }
    let Some(origin) = crate::mesh::origin::far_origin(wide.iter().copied()) else {
        return (transformed, [0.0; 3]);
    };
    let first = placed[0].1;
    if placed.iter().all(|(_, w)| DMat3::from_mat4(*w) == DMat3::IDENTITY && w.w_axis == first.w_axis) {
        return (local.to_vec(), first.w_axis.truncate().to_array());
    }
    (crate::mesh::origin::relative_to(&wide, origin), origin)
}

impl<'a> Loader<'a> {
    /// One node of a flattening load (or one of its instances), under its world transform.
    fn visit(
        &mut self,
        node: gltf::Node<'_>,
        instance: Option<usize>,
        world: Mat4,
        world64: DMat4,
    ) -> Result<(), LoadErrorKind> {
        self.seen.nodes += usize::from(instance.is_none_or(|k| k == 0));
        self.seen.gpu_instances += usize::from(instance.is_some());
        if let Some(mesh) = node.mesh() {
            *self.seen.instances.entry(mesh.index()).or_default() += 1;
            self.seen.transformed |= world != Mat4::IDENTITY;
            self.world64 = world64;
            self.add_mesh(&mesh, world)?;
            self.world64 = DMat4::IDENTITY;
        }
        Ok(())
    }

    /// A scene-keeping load's attributes kept as they are: joints, weights, `_NAME`
    /// attributes and every morph target's (readable ones; the others are left out, and
    /// `add_mesh` records them). None for a flattening load.
    fn kept_as_they_are<'d>(&self, prim: &gltf::Primitive<'d>, mi: usize) -> Vec<(String, gltf::Accessor<'d>)>
    where
        'a: 'd,
    {
        let Some((doc, raw)) = self.scene else {
            return Vec::new();
        };
        let mut out: Vec<(String, gltf::Accessor<'d>)> =
            prim.attributes().filter_map(|(semantic, a)| verbatim(&semantic).map(|name| (name, a))).collect();
        for (name, index) in morph_targets(raw, mi, prim.index()) {
            out.extend(index.as_u64().and_then(|i| doc.accessors().nth(i as usize)).map(|a| (name, a)));
        }
        out.retain(|(name, a)| unreadable(a, name).is_none());
        out
    }

    /// The names of the attributes a primitive has that a load carries as further
    /// attributes (those it could read, and the others).
    fn further_names(&self, prim: &gltf::Primitive<'_>, mi: usize) -> Vec<String> {
        let mut names: Vec<String> = prim.attributes().filter_map(|(s, _)| carried(&s)).collect();
        if let Some((_, raw)) = self.scene {
            names.extend(prim.attributes().filter_map(|(s, _)| verbatim(&s)));
            names.extend(morph_targets(raw, mi, prim.index()).map(|(name, _)| name));
        }
        names
    }

    /// Counts what a primitive has that the mesh may not carry (once per primitive, however
    /// many nodes draw it).
    fn count_attributes(&mut self, prim: &gltf::Primitive<'_>) {
        let s = &mut self.seen;
        let mut other = false;
        for (semantic, _) in prim.attributes() {
            match semantic {
                gltf::Semantic::Positions | gltf::Semantic::Normals | gltf::Semantic::TexCoords(0) => {}
                name if carried(&name).is_some() => {}
                name if self.scene.is_some() && verbatim(&name).is_some() => {}
                name => {
                    other = true;
                    s.other_attributes.insert(name.to_string());
                }
            }
        }
        s.with_other_attributes += usize::from(other);
        s.with_morphs += usize::from(prim.morph_targets().len() > 0 && self.scene.is_none());
    }

    /// The vertices a primitive's attributes hold, under `world`, appended to the output
    /// once however many primitives share them: exporters (and our GLB writer) give many
    /// primitives one vertex array, and reading it once per primitive cost primitives ×
    /// vertices (24 GB for 2,000 primitives over 500k vertices).
    fn vertices(&mut self, prim: &gltf::Primitive<'_>, mi: usize, world: Mat4) -> Result<Block, LoadErrorKind> {
        // Normals or UVs that cannot be read as such are left out, and the repair says so;
        // the gltf crate would read them with the wrong element size (a panic in a debug
        // build, garbage in a release one).
        let readable =
            |semantic: gltf::Semantic, name: &str| prim.get(&semantic).filter(|a| unreadable(a, name).is_none());
        let normals = readable(gltf::Semantic::Normals, "NORMAL");
        let uvs = readable(gltf::Semantic::TexCoords(0), "TEXCOORD_0");
        let further: Vec<(String, gltf::Accessor<'_>)> = prim
            .attributes()
            .filter_map(|(semantic, a)| carried(&semantic).map(|name| (name, a)))
            .filter(|(name, a)| unreadable(a, name).is_none())
            .collect();
        let kept = self.kept_as_they_are(prim, mi);
        let position = prim.get(&gltf::Semantic::Positions);
        let accessors = [&position, &normals, &uvs].map(|a| a.as_ref().map(gltf::Accessor::index));
        let further_key = further.iter().chain(&kept).map(|(name, a)| (name.clone(), a.index())).collect();
        let key = (accessors, further_key, world.to_cols_array().map(f32::to_bits));
        if let Some(block) = self.blocks.get(&key) {
            return Ok(block.clone());
        }
        let buffers = self.buffers;
        let positions: Vec<[f32; 3]> = position.and_then(|a| read(a, buffers)).ok_or_else(|| {
            malformed(format!("mesh {mi} primitive {}: POSITION missing or outside its buffer", prim.index()))
        })?;
        let (n, base) = (positions.len(), self.out.positions.len());
        self.out.positions.extend(positions.iter().map(|&p| world.transform_point3(Vec3::from(p)).to_array()));
        if self.scene.is_none() && (world != Mat4::IDENTITY || !self.placed.is_empty()) {
            if self.placed.is_empty() && base > 0 {
                // The blocks before were untransformed.
                self.local.extend_from_slice(&self.out.positions[..base]);
                self.placed.push((0, DMat4::IDENTITY));
            }
            self.local.extend_from_slice(&positions);
            self.placed.push((base, self.world64));
        }
        let normals: Option<Vec<[f32; 3]>> = normals.and_then(|a| read(a, buffers)).filter(|ns| ns.len() == n);
        let uvs: Option<Vec<[f32; 2]>> = uvs.and_then(|a| read(a, buffers)).filter(|t| t.len() == n);
        let mut further: Vec<_> =
            further.into_iter().filter_map(|(name, a)| read_attribute(&name, a, buffers, world, n)).collect();
        // Read as they are (scene-keeping loads only, whose transform is the identity). One
        // whose component count differs from the same semantic's in a primitive read before
        // is left out of this one (`unreadable` records it).
        let known = &self.out.attributes;
        let fits = |a: &VertexAttribute| known.iter().all(|k| k.semantic != a.semantic || k.components == a.components);
        further.extend(kept.into_iter().filter_map(|(name, a)| read_values(&name, a, buffers, n)).filter(fits));
        let attributes = further.iter().map(|a| a.semantic.clone()).collect();
        append(&mut self.out.attributes, further, base, n);
        let block = Block { base, n, has_normals: normals.is_some(), has_uvs: uvs.is_some(), attributes };
        let linear = Mat3::from_mat4(world);
        let normal_m = linear.inverse().transpose();
        match normals {
            // Normals no transform turns (none, or a translation only: a placement, or the
            // far origin our GLB writer puts on its node) stay bit-exact (no renormalisation).
            Some(ns) if linear == Mat3::IDENTITY => self.out.normals.extend(ns),
            Some(ns) => {
                self.out.normals.extend(ns.iter().map(|&v| (normal_m * Vec3::from(v)).normalize_or_zero().to_array()))
            }
            None => self.out.normals.resize(base + n, [0.0; 3]),
        }
        match uvs {
            Some(t) => self.out.uvs.extend(t),
            None => self.out.uvs.resize(base + n, [0.0; 2]),
        }
        self.any_normals |= block.has_normals;
        self.any_uvs |= block.has_uvs;
        self.blocks.insert(key, block.clone());
        Ok(block)
    }

    fn add_mesh(&mut self, mesh: &gltf::Mesh<'_>, world: Mat4) -> Result<(), LoadErrorKind> {
        let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
        for prim in mesh.primitives() {
            let (mi, pi) = (mesh.index(), prim.index());
            let mode = prim.mode();
            let here = Location::Primitive { mesh: mi as u32, primitive: pi as u32 };
            // Points and lines are not surfaces; glTF 2.0 lets a primitive leave POSITION out
            // ("skip its rendering"). Both are skipped; a scene-keeping output keeps them.
            let triangles = matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan);
            let position = prim.get(&gltf::Semantic::Positions);
            let (true, Some(position)) = (triangles, position) else {
                if self.scene.is_none() {
                    self.skipped.add(here);
                }
                if !triangles {
                    self.first_skipped.get_or_insert((mi, pi, mode));
                }
                continue;
            };
            let first_visit = !self.prim_ids.contains_key(&(mi, pi));
            let at = |what: String| malformed(format!("mesh {mi} primitive {pi}: {what}"));
            if let Some(why) = unreadable(&position, "POSITION") {
                return Err(at(why));
            }
            if let Some(why) = prim.indices().and_then(|a| unreadable(&a, "indices")) {
                return Err(at(why));
            }
            if first_visit && !bounded(&position) {
                self.unbounded.add(here);
            }
            let Block { base, n, has_normals, has_uvs, attributes } = self.vertices(&prim, mi, world)?;
            let buffers = self.buffers;
            let present = |s: gltf::Semantic| prim.get(&s).is_some();
            let dropped = self.further_names(&prim, mi).iter().any(|name| !attributes.contains(name));
            if first_visit
                && (present(gltf::Semantic::Normals) && !has_normals
                    || present(gltf::Semantic::TexCoords(0)) && !has_uvs
                    || dropped)
            {
                self.unreadable.add(here);
            }
            let indices: Vec<u32> = match prim.indices() {
                Some(_) => prim
                    .reader(|b| buffers.get(b.index()).map(|d| &d[..]))
                    .read_indices()
                    .ok_or_else(|| malformed(format!("mesh {mi} primitive {pi}: indices outside their buffer")))?
                    .into_u32()
                    .collect(),
                None => (0..n as u32).collect(),
            };
            let next_id = self.prim_ids.len() as u32;
            let pid = *self.prim_ids.entry((mi, pi)).or_insert(next_id);
            if pid == next_id {
                let name = mesh.name().unwrap_or("").to_string();
                self.out.primitives.push(Primitive {
                    name,
                    material: prim.material().index(),
                    no_normals: !has_normals,
                    no_uvs: !has_uvs,
                    gltf_source: Some([mi, pi]),
                });
                self.prim_attributes.push(attributes);
                self.count_attributes(&prim);
            }
            // A triangle list whose count is no multiple of 3, or a strip or fan of one or two
            // corners (assimp's `IncorrectVertexArrays/Cube.gltf`): the one or two corners
            // left over make no face.
            let leftover = match mode {
                Mode::Triangles => indices.len() % 3 != 0,
                _ => (1..3).contains(&indices.len()),
            };
            if first_visit && leftover {
                self.skipped.add(here);
            }
            let first_face = self.out.triangles.len();
            let mut push = |t: [u32; 3]| self.out.triangles.push(if mirrored { [t[0], t[2], t[1]] } else { t });
            match mode {
                Mode::Triangles => indices.chunks_exact(3).for_each(|t| push([t[0], t[1], t[2]])),
                Mode::TriangleStrip => (0..indices.len().saturating_sub(2)).for_each(|i| {
                    let (a, b, c) = (indices[i], indices[i + 1], indices[i + 2]);
                    push(if i % 2 == 0 { [a, b, c] } else { [b, a, c] })
                }),
                _ => (1..indices.len().saturating_sub(1)).for_each(|i| push([indices[i], indices[i + 1], indices[0]])),
            }
            for (k, t) in self.out.triangles[first_face..].iter_mut().enumerate() {
                for (c, i) in t.iter_mut().enumerate() {
                    *i = super::check_index(*i as i64, n, first_face + k, c)? + base as u32;
                }
            }
            self.out.triangle_primitive.resize(self.out.triangles.len(), pid);
        }
        Ok(())
    }
}
