//! GLB output of a [`GltfScene`] with its triangle meshes replaced: the source's JSON is
//! copied (nodes, skins, animations, cameras, materials, extensions, extras), each replaced
//! primitive gets new accessors of its own (its vertices only: positions, normals, texture
//! coordinates, colours, tangents, joints, weights, `_NAME` attributes and morph targets;
//! indices as UNSIGNED_SHORT where they fit), and everything goes into one binary chunk.
//!
//! The source's accessors and buffer views that only replaced primitives used are left out,
//! so the file shrinks with its meshes; the others (inverse bind matrices, animation
//! samplers, `EXT_mesh_gpu_instancing` transforms, point and line primitives, images) are
//! copied and renumbered. Where the source uses an extension this writer does not know, it
//! cannot tell what that extension's indices point at, so it keeps every accessor and view
//! at its index (the output is larger; a note says why). Images read from files or data URIs
//! are embedded. Geometry decoded from Draco or meshopt compression (or read from a fallback) is
//! written uncompressed.

use std::collections::{BTreeSet, HashMap};
use std::io::{self, Write};

use serde_json::{json, Value};

use super::gltf_accessor::encode;
use super::gltf_extensions::DRACO;
use super::gltf_meshopt::EXTENSIONS as MESHOPT;
use super::gltf_scene::GltfScene;
use super::write::{glb_container, unit, unit_tangent, writable};
use crate::mesh::IndexedMesh;

/// Extensions whose indices into accessors and buffer views this writer knows (instancing,
/// compression) or that have none (materials, textures, lights, ...).
fn understood(extension: &str) -> bool {
    ["KHR_materials_", "KHR_texture_", "EXT_texture_", "MSFT_texture_"].iter().any(|p| extension.starts_with(p))
        || [
            "KHR_lights_punctual",
            "KHR_mesh_quantization",
            "EXT_mesh_gpu_instancing",
            "MSFT_lod",
            "KHR_xmp_json_ld",
            "KHR_animation_pointer",
            "KHR_node_visibility",
            "EXT_lights_image_based",
        ]
        .contains(&extension)
        || extension == DRACO
        || MESHOPT.contains(&extension)
}

fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

/// The binary chunk being built, and the views and accessors added to it.
struct Bin {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    /// Appends `data` at an offset congruent to `align_as` modulo 4 (a copied view keeps its
    /// source's alignment, which its accessors' offsets assume), and returns the offset.
    fn put(&mut self, data: &[u8], align_as: usize) -> usize {
        while self.bytes.len() % 4 != align_as % 4 {
            self.bytes.push(0);
        }
        let at = self.bytes.len();
        self.bytes.extend_from_slice(data);
        at
    }

    /// A new view over `data` (aligned to 4) and its index.
    fn view(&mut self, data: &[u8], target: Option<u32>, stride: Option<usize>) -> usize {
        let at = self.put(data, 0);
        let mut v = json!({"buffer": 0, "byteOffset": at, "byteLength": data.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        if let Some(s) = stride {
            v["byteStride"] = json!(s);
        }
        self.views.push(v);
        self.views.len() - 1
    }

    fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }
}

/// Writes `scene` with `meshes[i]` in place of `scene.meshes[i]`; returns notes on what the
/// output could not keep as it was.
pub(super) fn write_scene_glb(
    w: &mut impl Write,
    scene: &GltfScene,
    meshes: &[IndexedMesh],
) -> io::Result<Vec<String>> {
    if meshes.len() != scene.meshes.len() {
        return Err(invalid(format!("{} meshes given for a scene of {}", meshes.len(), scene.meshes.len())));
    }
    for (m, sm) in meshes.iter().zip(&scene.meshes) {
        if m.triangles.is_empty() {
            return Err(invalid(format!("{} has no triangles left; ask for more", sm.label())));
        }
        writable(m)?;
        if m.primitives.len().max(1) != sm.primitives.len() {
            return Err(invalid(format!(
                "{}: {} primitives given for {}",
                sm.label(),
                m.primitives.len(),
                sm.primitives.len()
            )));
        }
    }
    let mut notes = Vec::new();
    let mut doc = scene.raw.clone();
    // (mesh, primitive) of the source → (scene mesh, primitive id).
    let mut replaced: HashMap<(usize, usize), (usize, u32)> = HashMap::new();
    for (i, sm) in scene.meshes.iter().enumerate() {
        for (p, &pi) in sm.primitives.iter().enumerate() {
            replaced.insert((sm.index, pi), (i, p as u32));
        }
    }
    let is_replaced = |mi: usize, pi: usize| replaced.contains_key(&(mi, pi));
    let used = |key: &str| -> Vec<String> {
        let list = doc.get(key).and_then(Value::as_array);
        list.into_iter().flatten().filter_map(Value::as_str).map(str::to_string).collect()
    };
    let unknown: Vec<String> = used("extensionsUsed").into_iter().filter(|e| !understood(e)).collect();
    let n_accessors = doc["accessors"].as_array().map_or(0, Vec::len);
    let n_views = doc["bufferViews"].as_array().map_or(0, Vec::len);

    // What the output keeps of the source's accessors and views.
    let mut kept_accessors = BTreeSet::new();
    let mut kept_views = BTreeSet::new();
    if unknown.is_empty() {
        accessor_refs(&mut doc, &is_replaced, &mut |v| {
            kept_accessors.extend(v.as_u64().map(|i| i as usize).filter(|&i| i < n_accessors));
        });
        for &a in &kept_accessors {
            let acc = &doc["accessors"][a];
            for v in
                [&acc["bufferView"], &acc["sparse"]["indices"]["bufferView"], &acc["sparse"]["values"]["bufferView"]]
            {
                kept_views.extend(v.as_u64().map(|i| i as usize).filter(|&i| i < n_views));
            }
        }
        other_view_refs(&mut doc, &is_replaced, &mut |v| {
            kept_views.extend(v.as_u64().map(|i| i as usize).filter(|&i| i < n_views));
        });
    } else {
        kept_accessors.extend(0..n_accessors);
        kept_views.extend(0..n_views);
        notes.push(format!(
            "kept the source's full-resolution vertex data beside the new meshes: it uses {}, which this writer \
             does not know, so it cannot tell which of its buffer data is still needed",
            unknown.join(", ")
        ));
    }

    // Copied views first, renumbered in order, then the copied accessors.
    let mut bin = Bin { bytes: Vec::new(), views: Vec::new(), accessors: Vec::new() };
    let mut view_of = vec![None; n_views];
    for &v in &kept_views {
        let mut view = doc["bufferViews"][v].clone();
        let data =
            view_bytes(scene, &view).ok_or_else(|| invalid(format!("buffer view {v} lies outside its buffer")))?;
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let at = bin.put(data, offset);
        view["buffer"] = json!(0);
        view["byteOffset"] = json!(at);
        MESHOPT.iter().for_each(|m| drop_extension(&mut view, m));
        bin.views.push(view);
        view_of[v] = Some(bin.views.len() - 1);
    }
    let mut accessor_of = vec![None; n_accessors];
    for &a in &kept_accessors {
        let mut acc = doc["accessors"][a].clone();
        for pointer in ["/bufferView", "/sparse/indices/bufferView", "/sparse/values/bufferView"] {
            acc.pointer_mut(pointer).into_iter().for_each(|v| remap(v, &view_of));
        }
        accessor_of[a] = Some(bin.accessor(acc));
    }
    accessor_refs(&mut doc, &is_replaced, &mut |v| remap(v, &accessor_of));
    other_view_refs(&mut doc, &is_replaced, &mut |v| remap(v, &view_of));

    // Images read from files or data URIs go into the binary chunk.
    if let Some(images) = doc.get_mut("images").and_then(Value::as_array_mut) {
        for (image, source) in images.iter_mut().zip(&scene.resources.images) {
            if image.get("bufferView").is_some() {
                continue;
            }
            match &source.bytes {
                Some(bytes) => {
                    let v = bin.view(bytes, None, None);
                    image.as_object_mut().map(|o| o.remove("uri"));
                    image["bufferView"] = json!(v);
                    image["mimeType"] = json!(source.mime_type.clone().unwrap_or_else(|| "image/png".into()));
                }
                None => notes.push(format!(
                    "image {:?} could not be read, so it is referred to by its URI as the source did; copy it beside \
                     the output",
                    source.uri.as_deref().unwrap_or("")
                )),
            }
        }
    }

    // The replaced primitives; those left without triangles are dropped. Each mesh's
    // triangles are sorted out by primitive in one pass (a pass per primitive would cost
    // primitives × triangles: minutes for a CAD part of thousands of primitives).
    let n_meshes = doc["meshes"].as_array().map_or(0, Vec::len);
    let by_primitive: Vec<Vec<Vec<u32>>> = meshes
        .iter()
        .map(|m| {
            let mut lists = vec![Vec::new(); m.primitives.len().max(1)];
            for t in 0..m.triangles.len() {
                lists[m.primitive_of(t) as usize].push(t as u32);
            }
            lists
        })
        .collect();
    for mi in 0..n_meshes {
        let Some(prims) = doc["meshes"][mi]["primitives"].as_array().cloned() else { continue };
        let mut out = Vec::new();
        for (pi, mut prim) in prims.into_iter().enumerate() {
            let Some(&(i, p)) = replaced.get(&(mi, pi)) else {
                out.push(prim);
                continue;
            };
            let m = &meshes[i];
            let source_attributes = prim["attributes"].clone();
            let triangles = &by_primitive[i][p as usize];
            match primitive_data(&mut bin, m, p, triangles, &scene.raw, &source_attributes) {
                Some((attributes, indices, targets)) => {
                    prim["attributes"] = attributes;
                    prim["indices"] = json!(indices);
                    prim["mode"] = json!(4);
                    match targets {
                        Some(t) => prim["targets"] = t,
                        None => {
                            prim.as_object_mut().map(|o| o.remove("targets"));
                        }
                    }
                    drop_extension(&mut prim, DRACO);
                    out.push(prim);
                }
                None => notes
                    .push(format!("{} primitive {pi} has no triangles left and was left out", scene.meshes[i].label())),
            }
        }
        doc["meshes"][mi]["primitives"] = json!(out);
    }

    // One buffer (the BIN chunk's length must be a multiple of 4); extensions no longer used
    // are no longer declared.
    bin.put(&[], 0);
    doc["buffers"] = json!([{"byteLength": bin.bytes.len()}]);
    doc["bufferViews"] = json!(bin.views);
    doc["accessors"] = json!(bin.accessors);
    let draco_left = doc["meshes"]
        .as_array()
        .into_iter()
        .flatten()
        .any(|m| m["primitives"].as_array().into_iter().flatten().any(|p| p["extensions"].get(DRACO).is_some()));
    for key in ["extensionsUsed", "extensionsRequired"] {
        if let Some(list) = doc.get_mut(key).and_then(Value::as_array_mut) {
            list.retain(|e| !MESHOPT.iter().any(|m| e == m) && (e != DRACO || draco_left));
            if list.is_empty() {
                doc.as_object_mut().map(|o| o.remove(key));
            }
        }
    }
    if doc.get("bufferViews").and_then(Value::as_array).is_some_and(Vec::is_empty) {
        doc.as_object_mut().map(|o| o.remove("bufferViews"));
    }
    let generator = doc["asset"]["generator"].as_str().map(str::to_string);
    let ours = concat!("dynlod ", env!("CARGO_PKG_VERSION"));
    doc["asset"]["generator"] = json!(match generator {
        Some(g) => format!("{ours} (from {g})"),
        None => ours.to_string(),
    });
    glb_container(w, &doc, &bin.bytes)?;
    Ok(notes)
}

/// The bytes a source buffer view spans.
fn view_bytes<'s>(scene: &'s GltfScene, view: &Value) -> Option<&'s [u8]> {
    let buffer = scene.buffers.get(view["buffer"].as_u64()? as usize)?;
    let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
    buffer.get(offset..offset.checked_add(view["byteLength"].as_u64()? as usize)?)
}

/// Replaces an index by its new number (`None`: left out, which `accessor_refs` and
/// `other_view_refs` never visit).
fn remap(v: &mut Value, new: &[Option<usize>]) {
    if let Some(n) = v.as_u64().and_then(|i| new.get(i as usize).copied().flatten()) {
        *v = json!(n);
    }
}

fn drop_extension(v: &mut Value, name: &str) {
    if let Some(ext) = v.get_mut("extensions").and_then(Value::as_object_mut) {
        ext.remove(name);
        if ext.is_empty() {
            v.as_object_mut().map(|o| o.remove("extensions"));
        }
    }
}

/// The elements of the array at `pointer` (none where there is none). Indexing a missing
/// key of a `Value` mutably would insert a `null` there, which glTF does not allow.
fn each<'v>(v: &'v mut Value, pointer: &str) -> impl Iterator<Item = &'v mut Value> {
    v.pointer_mut(pointer).and_then(Value::as_array_mut).into_iter().flatten()
}

/// The values of the object at `pointer`.
fn values<'v>(v: &'v mut Value, pointer: &str) -> impl Iterator<Item = &'v mut Value> {
    v.pointer_mut(pointer).and_then(Value::as_object_mut).into_iter().flat_map(|o| o.values_mut())
}

/// Every accessor index outside the replaced primitives: skins' inverse bind matrices,
/// animation samplers, `EXT_mesh_gpu_instancing` attributes, and the attributes, indices and
/// morph targets of primitives kept as they are.
fn accessor_refs(doc: &mut Value, replaced: &dyn Fn(usize, usize) -> bool, f: &mut dyn FnMut(&mut Value)) {
    each(doc, "/skins").filter_map(|s| s.get_mut("inverseBindMatrices")).for_each(&mut *f);
    for animation in each(doc, "/animations") {
        for sampler in each(animation, "/samplers") {
            ["input", "output"].iter().for_each(|k| sampler.get_mut(*k).into_iter().for_each(&mut *f));
        }
    }
    for node in each(doc, "/nodes") {
        values(node, "/extensions/EXT_mesh_gpu_instancing/attributes").for_each(&mut *f);
    }
    for (mi, mesh) in each(doc, "/meshes").enumerate() {
        for (pi, prim) in each(mesh, "/primitives").enumerate() {
            if replaced(mi, pi) {
                continue;
            }
            values(prim, "/attributes").for_each(&mut *f);
            prim.get_mut("indices").into_iter().for_each(&mut *f);
            for target in each(prim, "/targets") {
                values(target, "").for_each(&mut *f);
            }
        }
    }
}

/// Buffer view indices besides accessors': images, and the Draco data of primitives kept as
/// they are.
fn other_view_refs(doc: &mut Value, replaced: &dyn Fn(usize, usize) -> bool, f: &mut dyn FnMut(&mut Value)) {
    each(doc, "/images").filter_map(|i| i.get_mut("bufferView")).for_each(&mut *f);
    for (mi, mesh) in each(doc, "/meshes").enumerate() {
        for (pi, prim) in each(mesh, "/primitives").enumerate() {
            if !replaced(mi, pi) {
                prim.pointer_mut(&format!("/extensions/{DRACO}/bufferView")).into_iter().for_each(&mut *f);
            }
        }
    }
}

/// A primitive's accessor layout in the source: (componentType, normalized).
fn source_format(raw: &Value, accessor: &Value) -> (u64, bool) {
    let a = &raw["accessors"][accessor.as_u64().unwrap_or(u64::MAX) as usize];
    (a["componentType"].as_u64().unwrap_or(5126), a["normalized"].as_bool().unwrap_or(false))
}

fn component_size(component_type: u64) -> usize {
    match component_type {
        5120 | 5121 => 1,
        5122 | 5123 => 2,
        _ => 4,
    }
}

/// A vertex attribute accessor over `values` (`components` per vertex) as `component_type`;
/// elements shorter than 4 bytes get a stride padded to 4, as glTF requires of vertex data.
fn attribute_accessor(
    bin: &mut Bin,
    values: &[f32],
    components: usize,
    component_type: u64,
    normalized: bool,
) -> usize {
    let size = components * component_size(component_type);
    let encoded = encode(values, component_type, normalized);
    let stride = size.next_multiple_of(4);
    let (data, stride) = match stride == size {
        true => (encoded, None),
        false => {
            let mut padded = Vec::with_capacity(encoded.len() / size * stride);
            for e in encoded.chunks_exact(size) {
                padded.extend_from_slice(e);
                padded.resize(padded.len() + stride - size, 0);
            }
            (padded, Some(stride))
        }
    };
    let view = bin.view(&data, Some(34962), stride);
    let kind = ["SCALAR", "VEC2", "VEC3", "VEC4"][components - 1];
    let count = values.len() / components;
    let mut a = json!({"bufferView": view, "componentType": component_type, "count": count, "type": kind});
    if normalized {
        a["normalized"] = json!(true);
    }
    bin.accessor(a)
}

/// A FLOAT VEC3 accessor with the min and max glTF requires of POSITION accessors (morph
/// targets' included).
fn position_accessor(bin: &mut Bin, values: &[f32]) -> usize {
    let (lo, hi) = crate::mesh::bounds(values.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
    let a = attribute_accessor(bin, values, 3, 5126, false);
    bin.accessors[a]["min"] = json!(lo);
    bin.accessors[a]["max"] = json!(hi);
    a
}

/// The accessors of primitive `p` of `m`, whose triangles are `triangles`: its attributes
/// object, its indices accessor and its morph targets; `None` where it has none. Its
/// vertices are those its triangles use, in first-use order.
fn primitive_data(
    bin: &mut Bin,
    m: &IndexedMesh,
    p: u32,
    triangles: &[u32],
    raw: &Value,
    source_attributes: &Value,
) -> Option<(Value, usize, Option<Value>)> {
    let mut local = HashMap::new();
    let mut order: Vec<usize> = Vec::new();
    let mut indices: Vec<u32> = Vec::new();
    for &t in triangles {
        for &v in &m.triangles[t as usize] {
            let next = order.len() as u32;
            let i = *local.entry(v).or_insert(next);
            if i == next {
                order.push(v as usize);
            }
            indices.push(i);
        }
    }
    if indices.is_empty() {
        return None;
    }
    let gather = |values: &[f32], c: usize| -> Vec<f32> {
        order.iter().flat_map(|&v| values[v * c..(v + 1) * c].iter().copied()).collect()
    };
    let source = m.primitives.get(p as usize);
    let mut attributes = serde_json::Map::new();
    let positions: Vec<f32> = gather(m.positions.as_flattened(), 3);
    attributes.insert("POSITION".into(), json!(position_accessor(bin, &positions)));
    if !m.normals.is_empty() && !source.is_some_and(|s| s.no_normals) {
        let normals: Vec<f32> = order.iter().flat_map(|&v| unit(m.normals[v])).collect();
        attributes.insert("NORMAL".into(), json!(attribute_accessor(bin, &normals, 3, 5126, false)));
    }
    if !m.uvs.is_empty() && !source.is_some_and(|s| s.no_uvs) {
        let uvs = gather(m.uvs.as_flattened(), 2);
        attributes.insert("TEXCOORD_0".into(), json!(attribute_accessor(bin, &uvs, 2, 5126, false)));
    }
    let mut targets: Vec<serde_json::Map<String, Value>> = Vec::new();
    for attr in m.attributes.iter().filter(|a| a.present_in(p)) {
        let mut values = gather(&attr.values, attr.components);
        let name = attr.semantic.as_str();
        if let Some((k, semantic)) = attr.morph_target() {
            if targets.len() <= k {
                targets.resize(k + 1, serde_json::Map::new());
            }
            let a = match semantic == "POSITION" && attr.components == 3 {
                true => position_accessor(bin, &values),
                false => attribute_accessor(bin, &values, attr.components, 5126, false),
            };
            targets[k].insert(semantic.to_string(), json!(a));
            continue;
        }
        let (component_type, normalized) = match source_attributes.get(name) {
            Some(acc) if name.starts_with("JOINTS_") || name.starts_with("WEIGHTS_") || name.starts_with('_') => {
                source_format(raw, acc)
            }
            _ => (5126, false),
        };
        if name == "TANGENT" {
            for t in values.chunks_exact_mut(4) {
                t.copy_from_slice(&unit_tangent([t[0], t[1], t[2], t[3]]));
            }
        }
        let a = attribute_accessor(bin, &values, attr.components, component_type, normalized);
        attributes.insert(name.to_string(), json!(a));
    }
    let (bytes, component_type): (Vec<u8>, u64) = match order.len() < u16::MAX as usize {
        true => (indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(), 5123),
        false => (indices.iter().flat_map(|&i| i.to_le_bytes()).collect(), 5125),
    };
    let view = bin.view(&bytes, Some(34963), None);
    let idx = bin.accessor(
        json!({"bufferView": view, "componentType": component_type, "count": indices.len(), "type": "SCALAR"}),
    );
    let targets = (!targets.is_empty()).then(|| json!(targets));
    Some((Value::Object(attributes), idx, targets))
}
