//! `KHR_draco_mesh_compression`: a triangle primitive whose geometry is held only as a Draco
//! stream (its accessors declare counts and types but have no data) is decoded, by the pure
//! Rust `draco-core` decoder, into a buffer appended to the file's, and its accessors are
//! pointed at it: from there the file reads as one written uncompressed, by the flattening
//! load and the scene-keeping one alike. Blender's exporter, gltf-pipeline (`-d`) and
//! gltf-transform write it; three.js and Babylon.js read it with Google's decoder.
//!
//! ```text
//!   primitive ── KHR_draco_mesh_compression { bufferView: v, attributes: {POSITION: 1, ...} }
//!      │            └─ Draco stream (buffer view v) ──decode──▶ points, faces, attribute 1, ...
//!      └─ attributes { POSITION: accessor a (count, type; no bufferView) }
//!                                              ◀── a new view over the decoded values
//! ```
//!
//! Each attribute the extension names is written as its accessor declares it (component
//! type and count), its values converted from what the stream holds as Draco's decoder
//! converts them (by value); the faces become the indices accessor (one is added where the
//! primitive has none), a triangle list (a TRIANGLE_STRIP primitive, which the extension
//! also allows, decodes to one and becomes one). A primitive that also carries uncompressed data (a fallback) is
//! read from that, as before; points and lines are left as they are (the loader skips
//! them). A stream that does not decode, a count that differs from its accessor's, an
//! attribute id the stream lacks, an accessor two primitives would fill: an error naming
//! the mesh and primitive. The decoder's own limits refuse streams that claim more than
//! they hold; the vertex count is capped where a mesh's is.

use serde_json::{json, Value};

use super::gltf::malformed;
use super::gltf_accessor::encode;
use super::gltf_extensions::DRACO;
use crate::error::LoadErrorKind;

/// Decodes every Draco-only triangle primitive of `raw` into a buffer appended to `buffers`,
/// pointing its accessors at the decoded values (see the module docs). Returns whether any
/// was decoded (and so `raw` changed).
pub(super) fn decode(raw: &mut Value, buffers: &mut Vec<Vec<u8>>) -> Result<bool, LoadErrorKind> {
    let mut out = Decoded { bytes: Vec::new(), views: Vec::new(), filled: std::collections::BTreeSet::new() };
    let buffer = buffers.len();
    let mut patches = Vec::new();
    let meshes = raw["meshes"].as_array().map_or(0, Vec::len);
    for mi in 0..meshes {
        let primitives = raw["meshes"][mi]["primitives"].as_array().map_or(0, Vec::len);
        for pi in 0..primitives {
            let prim = &raw["meshes"][mi]["primitives"][pi];
            let Some(ext) = prim["extensions"].get(DRACO) else { continue };
            // The extension allows TRIANGLES and TRIANGLE_STRIP; either decodes to a list.
            let mode = prim["mode"].as_u64().unwrap_or(4);
            if !matches!(mode, 4 | 5) || !compressed_only(raw, prim) {
                continue;
            }
            let here = |what: String| malformed(format!("mesh {mi} primitive {pi}: {DRACO} {what}"));
            let stream = stream(raw, buffers, ext).map_err(here)?;
            patches.push((mi, pi, primitive(raw, prim, ext, stream, &mut out).map_err(here)?));
        }
    }
    if patches.is_empty() {
        return Ok(false);
    }
    let first_view = raw["bufferViews"].as_array().map_or(0, Vec::len);
    for (mi, pi, patch) in patches {
        if let Some((count, view)) = patch.new_indices {
            let index = raw["accessors"].as_array().map_or(0, Vec::len);
            let accessor =
                json!({"bufferView": first_view + view, "componentType": 5125, "count": count, "type": "SCALAR"});
            ensure_array(raw, "accessors").push(accessor);
            raw["meshes"][mi]["primitives"][pi]["indices"] = json!(index);
        }
        let prim = &mut raw["meshes"][mi]["primitives"][pi];
        prim["mode"] = json!(4);
        prim["extensions"].as_object_mut().map(|e| e.remove(DRACO));
        if prim["extensions"].as_object().is_some_and(|e| e.is_empty()) {
            prim.as_object_mut().map(|p| p.remove("extensions"));
        }
        let indices = raw["meshes"][mi]["primitives"][pi]["indices"].as_u64().map(|i| i as usize);
        for (accessor, view) in patch.filled {
            let a = &mut raw["accessors"][accessor];
            a["bufferView"] = json!(first_view + view);
            a.as_object_mut().map(|o| o.remove("byteOffset"));
            if Some(accessor) == indices {
                a["count"] = json!(patch.index_count);
            }
        }
    }
    for (offset, length) in &out.views {
        ensure_array(raw, "bufferViews").push(json!({"buffer": buffer, "byteOffset": offset, "byteLength": length}));
    }
    ensure_array(raw, "buffers").push(json!({"byteLength": out.bytes.len()}));
    buffers.push(out.bytes);
    Ok(true)
}

/// The decoded values, and the views over them (offset, length), in order.
struct Decoded {
    bytes: Vec<u8>,
    views: Vec<(usize, usize)>,
    /// Accessors already given decoded values.
    filled: std::collections::BTreeSet<usize>,
}

impl Decoded {
    /// A view over `data` (4-byte aligned), by its position among the new views.
    fn view(&mut self, data: &[u8]) -> usize {
        while self.bytes.len() % 4 != 0 {
            self.bytes.push(0);
        }
        self.views.push((self.bytes.len(), data.len()));
        self.bytes.extend_from_slice(data);
        self.views.len() - 1
    }
}

/// What one decoded primitive changes: its accessors and the new views they read (by
/// position among the new views), and an indices accessor to add where it had none (its
/// count and view).
struct Patch {
    filled: Vec<(usize, usize)>,
    new_indices: Option<(usize, usize)>,
    /// The decoded index count (a strip's accessor gets it).
    index_count: usize,
}

fn ensure_array<'v>(raw: &'v mut Value, key: &str) -> &'v mut Vec<Value> {
    if !raw[key].is_array() {
        raw[key] = json!([]);
    }
    raw[key].as_array_mut().expect("made an array")
}

/// Whether a primitive's data is only in its Draco stream: an attribute or its indices
/// without a buffer view or sparse values of their own.
fn compressed_only(raw: &Value, prim: &Value) -> bool {
    let empty = |a: &Value| {
        let accessor = a.as_u64().and_then(|i| raw["accessors"].get(i as usize));
        accessor.is_some_and(|a| a.get("bufferView").is_none() && a.get("sparse").is_none())
    };
    prim["attributes"].as_object().is_some_and(|a| a.values().any(empty)) || prim.get("indices").is_some_and(empty)
}

/// The bytes of the extension's buffer view.
fn stream<'b>(raw: &Value, buffers: &'b [Vec<u8>], ext: &Value) -> Result<&'b [u8], String> {
    let v = ext["bufferView"].as_u64().ok_or("has no bufferView")?;
    let view = raw["bufferViews"].get(v as usize).ok_or(format!("names buffer view {v}, which does not exist"))?;
    let b = view["buffer"].as_u64().unwrap_or(u64::MAX);
    let (offset, length) = (view["byteOffset"].as_u64().unwrap_or(0), view["byteLength"].as_u64().unwrap_or(0));
    let data = buffers.get(b as usize).ok_or(format!("names buffer view {v}, whose buffer {b} does not exist"))?;
    let end = offset.checked_add(length).filter(|&e| e <= data.len() as u64);
    end.map(|end| &data[offset as usize..end as usize])
        .ok_or(format!("stream (buffer view {v}, {length} bytes from {offset}) runs past the end of buffer {b}"))
}

/// Components per element of an accessor type.
fn components(kind: &Value) -> Option<usize> {
    match kind.as_str()? {
        "SCALAR" => Some(1),
        "VEC2" => Some(2),
        "VEC3" => Some(3),
        "VEC4" => Some(4),
        _ => None,
    }
}

/// Decodes one primitive's stream into `out`; what its accessors become.
fn primitive(raw: &Value, prim: &Value, ext: &Value, stream: &[u8], out: &mut Decoded) -> Result<Patch, String> {
    let limits = draco_core::decode_limits::DecodeLimits::default().with_max_points(crate::mesh::MAX_VERTICES as u64);
    let mut input = draco_core::decoder_buffer::DecoderBuffer::new(stream).with_limits(limits);
    let mut mesh = draco_core::mesh::Mesh::new();
    draco_core::mesh_decoder::MeshDecoder::new()
        .decode(&mut input, &mut mesh)
        .map_err(|e| format!("stream does not decode: {e}"))?;
    let (points, faces) = (mesh.num_points(), mesh.num_faces());
    let ids = ext["attributes"].as_object().ok_or("has no attributes")?;
    let mut filled = Vec::new();
    for (semantic, id) in ids {
        let accessor = prim["attributes"][semantic]
            .as_u64()
            .ok_or(format!("names attribute {semantic}, which the primitive does not have"))?
            as usize;
        let a = raw["accessors"]
            .get(accessor)
            .ok_or(format!("{semantic} names accessor {accessor}, which does not exist"))?;
        let id = id.as_u64().ok_or(format!("gives {semantic} the id {id}, not a number"))?;
        let attribute = (0..mesh.num_attributes())
            .map(|i| mesh.attribute(i))
            .find(|att| u64::from(att.unique_id()) == id)
            .ok_or(format!("gives {semantic} the id {id}, which the stream does not have"))?;
        let count = a["count"].as_u64().unwrap_or(0);
        if count != points as u64 {
            return Err(format!("decodes {points} values of {semantic}, but its accessor {accessor} declares {count}"));
        }
        let n = components(&a["type"]).ok_or(format!("{semantic}'s accessor {accessor} has no vector type"))?;
        let ty = a["componentType"].as_u64().unwrap_or(0);
        // The stream's values as they are (Draco converts by value), in a vertex attribute's type.
        if !matches!(ty, 5120..=5123 | 5126) {
            return Err(format!("{semantic}'s accessor {accessor} has component type {ty}"));
        }
        let data = encode(&attribute.read_f32s(points, n), ty, false);
        if !out.filled.insert(accessor) {
            return Err(format!("would fill accessor {accessor} ({semantic}) a second time"));
        }
        filled.push((accessor, out.view(&data)));
    }
    let mut indices = Vec::with_capacity(faces * 3);
    for f in 0..faces {
        let face = mesh.face(draco_core::geometry_indices::FaceIndex(f as u32));
        indices.extend(face.map(|p| p.0));
    }
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= points) {
        return Err(format!("stream has a face naming point {bad} of {points}"));
    }
    let mut new_indices = None;
    match prim.get("indices").and_then(Value::as_u64) {
        Some(accessor) => {
            let accessor = accessor as usize;
            let a = raw["accessors"].get(accessor).ok_or(format!("indices accessor {accessor} does not exist"))?;
            let count = a["count"].as_u64().unwrap_or(0);
            // A strip's count is its own; the decoded list replaces it (`decode`).
            let strip = prim["mode"].as_u64() == Some(5);
            if count != indices.len() as u64 && !strip {
                return Err(format!(
                    "decodes {faces} triangles, but the indices accessor {accessor} declares {count} indices"
                ));
            }
            let ty = a["componentType"].as_u64().unwrap_or(0);
            let max = match ty {
                5121 => u8::MAX.into(),
                5123 => u16::MAX.into(),
                5125 => u32::MAX,
                _ => return Err(format!("indices accessor {accessor} has component type {ty}")),
            };
            if points > 0 && points as u64 - 1 > u64::from(max) {
                return Err(format!("decodes {points} points, more than indices accessor {accessor}'s type addresses"));
            }
            let data: Vec<u8> = match ty {
                5121 => indices.iter().map(|&i| i as u8).collect(),
                5123 => indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(),
                _ => indices.iter().flat_map(|&i| i.to_le_bytes()).collect(),
            };
            if !out.filled.insert(accessor) {
                return Err(format!("would fill accessor {accessor} (indices) a second time"));
            }
            filled.push((accessor, out.view(&data)));
        }
        None => {
            let data: Vec<u8> = indices.iter().flat_map(|&i| i.to_le_bytes()).collect();
            new_indices = Some((indices.len(), out.view(&data)));
        }
    }
    Ok(Patch { filled, new_indices, index_count: indices.len() })
}
