//! glTF 2.0 (`.gltf` with external or data-URI buffers, and `.glb`) through the `gltf` crate,
//! without decoding images. Every primitive of every mesh instanced by the default scene (or
//! the first scene; or, with no scene, every mesh once) is read with its node's world
//! transform applied: positions by the matrix, normals by its inverse transpose, winding
//! reversed under a mirroring transform. POSITION, NORMAL and TEXCOORD_0 are kept; each
//! (mesh, primitive) pair becomes one [`Primitive`] with its material index.
//!
//! Triangle lists, strips and fans are read; point and line primitives are skipped and the
//! skip is recorded as a repair (an error if the file has nothing else).

use std::path::Path;

use base64::Engine;
use glam::{Mat3, Mat4, Vec3};
use gltf::mesh::Mode;

use super::gltf_accessor::{read, unreadable};
use crate::error::LoadErrorKind;
use crate::mesh::{IndexedMesh, Location, NotKept, NotKeptKind, Primitive, Repair, RepairKind, MAX_EXAMPLES};

fn malformed(message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Malformed { format: "glTF", line: None, message: message.into() }
}

const MAX_NODE_DEPTH: usize = 256;

struct Loader {
    buffers: Vec<Vec<u8>>,
    out: IndexedMesh,
    /// Whether any primitive read has normals, texture coordinates.
    any_normals: bool,
    any_uvs: bool,
    prim_ids: std::collections::HashMap<(usize, usize), u32>,
    skipped: Repair,
    /// Primitives whose normals or texture coordinates could not be read as such.
    unreadable: Repair,
    first_skipped: Option<(usize, usize, Mode)>,
    /// What the mesh will not carry, counted while reading (see `not_kept`).
    seen: Seen,
}

/// Counts behind the [`NotKept`] list of a glTF input.
#[derive(Default)]
struct Seen {
    /// Nodes visited, and how many times each mesh was drawn by one.
    nodes: usize,
    instances: std::collections::BTreeMap<usize, usize>,
    /// Whether any drawn mesh had a transform other than the identity.
    transformed: bool,
    /// Primitives (each once) with morph targets.
    with_morphs: usize,
    /// Attributes besides POSITION, NORMAL and TEXCOORD_0, and the primitives having any.
    other_attributes: std::collections::BTreeSet<String>,
    with_other_attributes: usize,
}

pub(super) fn load(bytes: &[u8], base: Option<&Path>) -> Result<IndexedMesh, LoadErrorKind> {
    let (g, raw) = parse(bytes)?;
    let mut l = Loader {
        buffers: load_buffers(&g, &raw, base)?,
        out: IndexedMesh::default(),
        any_normals: false,
        any_uvs: false,
        prim_ids: Default::default(),
        skipped: Repair::new(RepairKind::SkippedNonTrianglePrimitives),
        unreadable: Repair::new(RepairKind::DroppedUnreadableAttributes),
        first_skipped: None,
        seen: Seen::default(),
    };
    match g.default_scene().or_else(|| g.scenes().next()) {
        Some(scene) => {
            for node in scene.nodes() {
                l.visit(node, Mat4::IDENTITY, 0)?;
            }
        }
        None => {
            for mesh in g.meshes() {
                l.add_mesh(&mesh, Mat4::IDENTITY)?;
            }
        }
    }
    let mut out = l.out;
    if out.triangles.is_empty() {
        if let Some((mesh, primitive, mode)) = l.first_skipped {
            return Err(LoadErrorKind::UnsupportedPrimitiveMode { mesh, primitive, mode: format!("{mode:?}") });
        }
    }
    out.not_kept = not_kept(&g, &raw, &l.seen);
    // An attribute that some primitives lack is kept for the others: the primitives without
    // it hold zeros and are flagged, so a GLB leaves it out of them as the source did.
    if !l.any_normals {
        out.normals.clear();
        out.primitives.iter_mut().for_each(|p| p.no_normals = false);
    }
    if !l.any_uvs {
        out.uvs.clear();
        out.primitives.iter_mut().for_each(|p| p.no_uvs = false);
    }
    if out.primitives.len() <= 1 {
        out.triangle_primitive.clear();
    }
    l.skipped.push_into(&mut out.load_repairs);
    l.unreadable.push_into(&mut out.load_repairs);
    if g.materials().len() > 0 {
        out.gltf_materials = Some(std::sync::Arc::new(materials(&g, &raw, &l.buffers, base)));
    }
    Ok(out)
}

/// The document, validated, and its JSON as written (materials are carried from it, every
/// extension and extra included). gltf-json's validation looks up the accessor each POSITION
/// names before checking that it exists (an index out of bounds, found by fuzzing), so
/// attribute accessors are checked here first; so is the GLB header's length. Required
/// extensions are checked here too ([`check_required`]), not by gltf-json, which knows only
/// the few its build enables.
fn parse(bytes: &[u8]) -> Result<(gltf::Gltf, serde_json::Value), LoadErrorKind> {
    // gltf's GLB reader subtracts the header's size from the total length the header
    // declares before comparing them (an overflow).
    if let Some(length) = bytes.strip_prefix(b"glTF").and_then(|b| b.get(4..8)) {
        let length = u32::from_le_bytes(length.try_into().expect("4 bytes"));
        if length < 12 {
            return Err(malformed(format!("the GLB header declares {length} bytes in all, fewer than its own 12")));
        }
    }
    let g = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| malformed(e.to_string()))?;
    let raw = match bytes.starts_with(b"glTF") {
        true => gltf::binary::Glb::from_slice(bytes).map(|glb| serde_json::from_slice(&glb.json)),
        false => Ok(serde_json::from_slice(bytes)),
    };
    let raw: serde_json::Value = raw.map_err(|e| malformed(e.to_string()))?.map_err(|e| malformed(e.to_string()))?;
    let mut root = g.document.into_json();
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &prim.attributes {
                if accessor.value() >= root.accessors.len() {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => s.to_string(),
                        gltf::json::validation::Checked::Invalid => "an attribute".into(),
                    };
                    return Err(malformed(format!(
                        "mesh {mi} primitive {pi}: {name} names accessor {}, but the file has {}",
                        accessor.value(),
                        root.accessors.len()
                    )));
                }
            }
        }
    }
    check_required(&root.extensions_required)?;
    if draco_only(&raw) {
        return Err(compressed(COMPRESSION_EXTENSIONS[0]));
    }
    root.extensions_required.clear();
    let document = gltf::Document::from_json(root).map_err(|e| malformed(e.to_string()))?;
    Ok((gltf::Gltf { document, blob: g.blob }, raw))
}

/// Geometry compressed by these is not decoded here: refused with a typed error, since the
/// accessors such a file keeps beside the compressed data are placeholders.
const COMPRESSION_EXTENSIONS: [&str; 2] = ["KHR_draco_mesh_compression", "EXT_meshopt_compression"];

/// Whether a primitive holds its geometry only Draco-compressed: it has the extension and an
/// attribute accessor with no data of its own (neither a buffer view nor sparse values).
fn draco_only(raw: &serde_json::Value) -> bool {
    let list = |v: &serde_json::Value, key: &str| v.get(key).and_then(|m| m.as_array()).cloned().unwrap_or_default();
    let accessors = list(raw, "accessors");
    let empty = |a: &serde_json::Value| {
        let accessor = a.as_u64().and_then(|i| accessors.get(i as usize));
        accessor.is_some_and(|a| a.get("bufferView").is_none() && a.get("sparse").is_none())
    };
    list(raw, "meshes").iter().flat_map(|m| list(m, "primitives")).any(|p| {
        let attributes = p.get("attributes").and_then(|a| a.as_object());
        p["extensions"].get(COMPRESSION_EXTENSIONS[0]).is_some() && attributes.is_some_and(|a| a.values().any(empty))
    })
}

fn compressed(extension: &str) -> LoadErrorKind {
    LoadErrorKind::Unsupported {
        format: "glTF",
        message: format!(
            "the geometry is compressed with {extension}, which dynlod does not decode; decompress the file first"
        ),
    }
}

/// A required extension is read ([`gltf_accessor`](super::gltf_accessor) decodes
/// `KHR_mesh_quantization`), carried (material, texture and light extensions: they change how
/// the surface looks, not its geometry, and materials are copied to GLB output as written),
/// or refused with a typed error that names it: compressed geometry, and anything unknown,
/// which could change what the geometry means (glTF 2.0 §3.12: a loader must not load a file
/// whose required extensions it does not support).
fn check_required(required: &[String]) -> Result<(), LoadErrorKind> {
    let carried = |e: &str| {
        e == "KHR_mesh_quantization"
            || e == "KHR_lights_punctual"
            || ["KHR_materials_", "KHR_texture_", "EXT_texture_", "MSFT_texture_"].iter().any(|p| e.starts_with(p))
                && e != "KHR_materials_variants"
    };
    match required.iter().find(|e| !carried(e)) {
        None => Ok(()),
        Some(e) if COMPRESSION_EXTENSIONS.contains(&e.as_str()) => Err(compressed(e)),
        Some(e) => Err(LoadErrorKind::Unsupported {
            format: "glTF",
            message: format!("the file requires the extension {e}, which dynlod does not support"),
        }),
    }
}

/// What a glTF input holds that the mesh read from it does not carry.
fn not_kept(g: &gltf::Gltf, raw: &serde_json::Value, seen: &Seen) -> Vec<NotKept> {
    let mut out = Vec::new();
    let mut note = |kind, count: usize, detail: String| {
        if count > 0 {
            out.push(NotKept::new(kind, count, detail));
        }
    };
    let instances: usize = seen.instances.values().sum();
    if instances > 1 || seen.transformed {
        let mut detail = format!("{} nodes", seen.nodes);
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
    // Quantization is decoded; what the materials use is carried with them.
    let carried = material_extensions(raw);
    let used = raw.get("extensionsUsed").and_then(|v| v.as_array()).into_iter().flatten().filter_map(|e| e.as_str());
    let lost: Vec<&str> = used.filter(|e| *e != "KHR_mesh_quantization" && !carried.contains(*e)).collect();
    note(NotKeptKind::Extensions, lost.len(), lost.join(", "));
    out
}

/// The source's material definitions as written (every extension and extra kept), with every
/// image's bytes (from a buffer view, a data URI, or a file beside the source) so the output
/// is self-contained. Of the source's extension lists, the output declares the extensions
/// these definitions use.
fn materials(
    g: &gltf::Gltf,
    raw: &serde_json::Value,
    buffers: &[Vec<u8>],
    base: Option<&Path>,
) -> crate::mesh::GltfMaterials {
    let images = g.as_json().images.iter().map(|img| image(g, img, buffers, base)).collect();
    let array = |key: &str| raw.get(key).filter(|v| v.is_array()).cloned().unwrap_or_else(|| serde_json::json!([]));
    let (materials, textures, samplers) = (array("materials"), array("textures"), array("samplers"));
    let named = material_extensions(raw);
    let declared = |key: &str| -> Vec<String> {
        let list = raw.get(key).and_then(|v| v.as_array());
        let names = list.into_iter().flatten().filter_map(|e| e.as_str());
        names.filter(|e| named.contains(*e)).map(str::to_string).collect()
    };
    crate::mesh::GltfMaterials {
        materials,
        textures,
        samplers,
        images,
        extensions_used: declared("extensionsUsed"),
        extensions_required: declared("extensionsRequired"),
    }
}

/// The extensions the source's materials, textures and samplers use.
fn material_extensions(raw: &serde_json::Value) -> std::collections::BTreeSet<String> {
    let mut named = std::collections::BTreeSet::new();
    for key in ["materials", "textures", "samplers"] {
        raw.get(key).into_iter().for_each(|v| extension_names(v, &mut named));
    }
    named
}

/// The keys of every `extensions` object inside `v`.
fn extension_names(v: &serde_json::Value, out: &mut std::collections::BTreeSet<String>) {
    match v {
        serde_json::Value::Object(map) => {
            for (key, value) in map {
                if key == "extensions" {
                    out.extend(value.as_object().into_iter().flat_map(|e| e.keys().cloned()));
                }
                extension_names(value, out);
            }
        }
        serde_json::Value::Array(items) => items.iter().for_each(|i| extension_names(i, out)),
        _ => {}
    }
}

/// One image, read from the JSON itself: the gltf crate's `Image::source` unwraps a mimeType
/// missing beside a bufferView, and a uri missing where there is no bufferView (panics found
/// by fuzzing). A missing type is guessed from the bytes or the uri; an image with neither
/// source stays without one, as it came.
fn image(g: &gltf::Gltf, img: &gltf::json::Image, buffers: &[Vec<u8>], base: Option<&Path>) -> crate::mesh::GltfImage {
    let name = img.name.clone();
    let declared = img.mime_type.as_ref().map(|m| m.0.clone());
    if let Some(view) = img.buffer_view.and_then(|v| g.views().nth(v.value())) {
        let bytes = view
            .offset()
            .checked_add(view.length())
            .and_then(|end| buffers.get(view.buffer().index())?.get(view.offset()..end))
            .map(<[u8]>::to_vec);
        let guessed = bytes.as_deref().and_then(|b| {
            if b.starts_with(b"\x89PNG") {
                Some("image/png".to_string())
            } else if b.starts_with(&[0xff, 0xd8, 0xff]) {
                Some("image/jpeg".to_string())
            } else {
                None
            }
        });
        return crate::mesh::GltfImage { name, mime_type: declared.or(guessed), bytes, uri: None };
    }
    let Some(uri) = img.uri.as_deref() else {
        return crate::mesh::GltfImage { name, mime_type: declared, bytes: None, uri: None };
    };
    let bytes = if let Some(data) = uri.strip_prefix("data:") {
        data.split_once(";base64,").and_then(|(_, p)| base64::engine::general_purpose::STANDARD.decode(p).ok())
    } else {
        base.and_then(|b| beside(b, uri)).and_then(|p| std::fs::read(p).ok())
    };
    let lower = uri.to_ascii_lowercase();
    let guessed = if lower.ends_with(".png") || lower.starts_with("data:image/png") {
        Some("image/png".to_string())
    } else if lower.ends_with(".jpg") || lower.ends_with(".jpeg") || lower.starts_with("data:image/jpeg") {
        Some("image/jpeg".to_string())
    } else {
        None
    };
    let keep_uri = bytes.is_none().then(|| uri.to_string());
    crate::mesh::GltfImage { name, mime_type: declared.or(guessed), bytes, uri: keep_uri }
}

/// The file a relative URI names beside the source. URIs are percent-encoded (glTF 2.0
/// §3.3.4, RFC 3986: `Base%20Color.png` names `Base Color.png`); where the decoded name does
/// not exist but the name as written does (an exporter that did not encode), that one.
/// `None` for an absolute path or a URI with a scheme.
fn beside(base: &Path, uri: &str) -> Option<std::path::PathBuf> {
    let decoded = percent_encoding::percent_decode_str(uri).decode_utf8().ok()?;
    let relative = |name: &str| !name.contains("://") && !Path::new(name).is_absolute();
    if !relative(uri) || !relative(&decoded) {
        return None;
    }
    let (encoded, decoded) = (base.join(uri), base.join(decoded.as_ref()));
    Some(if !decoded.exists() && encoded.exists() { encoded } else { decoded })
}

/// Every buffer's bytes. Only buffer 0 can be a GLB's BIN chunk (glTF 2.0 §4.4.3.3); another
/// buffer without a `uri` is an `EXT_meshopt_compression` fallback (its data exists only
/// compressed, which is not decoded here) or an error.
fn load_buffers(g: &gltf::Gltf, raw: &serde_json::Value, base: Option<&Path>) -> Result<Vec<Vec<u8>>, LoadErrorKind> {
    let mut out = Vec::new();
    for b in g.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin if b.index() > 0 => {
                let fallback = raw["buffers"][b.index()]["extensions"].get(COMPRESSION_EXTENSIONS[1]).is_some();
                return Err(match fallback {
                    true => compressed(COMPRESSION_EXTENSIONS[1]),
                    false => malformed(format!(
                        "buffer {} has no uri, and only buffer 0 can be the GLB's BIN chunk",
                        b.index()
                    )),
                });
            }
            gltf::buffer::Source::Bin => g
                .blob
                .clone()
                .ok_or_else(|| malformed(format!("buffer {} refers to a missing GLB BIN chunk", b.index())))?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let payload = uri
                    .split_once(";base64,")
                    .map(|(_, p)| p)
                    .ok_or_else(|| malformed(format!("buffer {}: data URI is not base64", b.index())))?;
                base64::engine::general_purpose::STANDARD
                    .decode(payload)
                    .map_err(|e| malformed(format!("buffer {}: bad base64: {e}", b.index())))?
            }
            gltf::buffer::Source::Uri(uri) => {
                let base = base.ok_or_else(|| LoadErrorKind::Unsupported {
                    format: "glTF",
                    message: format!("external buffer {uri:?} without a base folder"),
                })?;
                let path = beside(base, uri).ok_or_else(|| LoadErrorKind::Unsupported {
                    format: "glTF",
                    message: format!("buffer URI {uri:?} is not a relative file"),
                })?;
                std::fs::read(&path).map_err(|e| malformed(format!("buffer {} ({uri}): {e}", b.index())))?
            }
        };
        if data.len() < b.length() {
            return Err(LoadErrorKind::Truncated {
                format: "glTF",
                message: format!("buffer {} declares {} bytes but holds {}", b.index(), b.length(), data.len()),
            });
        }
        out.push(data);
    }
    Ok(out)
}

impl Loader {
    fn visit(&mut self, node: gltf::Node<'_>, parent: Mat4, depth: usize) -> Result<(), LoadErrorKind> {
        if depth > MAX_NODE_DEPTH {
            return Err(malformed(format!(
                "node hierarchy deeper than {MAX_NODE_DEPTH} (a cycle?) at node {}",
                node.index()
            )));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        self.seen.nodes += 1;
        if let Some(mesh) = node.mesh() {
            *self.seen.instances.entry(mesh.index()).or_default() += 1;
            self.seen.transformed |= world != Mat4::IDENTITY;
            self.add_mesh(&mesh, world)?;
        }
        for child in node.children() {
            self.visit(child, world, depth + 1)?;
        }
        Ok(())
    }

    /// Counts what a primitive has that the mesh may not carry (once per primitive, however
    /// many nodes draw it).
    fn count_attributes(&mut self, prim: &gltf::Primitive<'_>) {
        let s = &mut self.seen;
        let mut other = false;
        for (semantic, _) in prim.attributes() {
            match semantic {
                gltf::Semantic::Positions | gltf::Semantic::Normals | gltf::Semantic::TexCoords(0) => {}
                name => {
                    other = true;
                    s.other_attributes.insert(name.to_string());
                }
            }
        }
        s.with_other_attributes += usize::from(other);
        s.with_morphs += usize::from(prim.morph_targets().len() > 0);
    }

    fn add_mesh(&mut self, mesh: &gltf::Mesh<'_>, world: Mat4) -> Result<(), LoadErrorKind> {
        let normal_m = Mat3::from_mat4(world).inverse().transpose();
        let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
        for prim in mesh.primitives() {
            let (mi, pi) = (mesh.index(), prim.index());
            let mode = prim.mode();
            if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
                self.skipped.add(Location::Primitive { mesh: mi as u32, primitive: pi as u32 });
                self.first_skipped.get_or_insert((mi, pi, mode));
                continue;
            }
            let first_visit = !self.prim_ids.contains_key(&(mi, pi));
            let at = |what: String| malformed(format!("mesh {mi} primitive {pi}: {what}"));
            if let Some(why) = prim.get(&gltf::Semantic::Positions).and_then(|a| unreadable(&a, "POSITION")) {
                return Err(at(why));
            }
            if let Some(why) = prim.indices().and_then(|a| unreadable(&a, "indices")) {
                return Err(at(why));
            }
            // Normals or UVs that cannot be read as such are left out, and the repair says so;
            // the gltf crate would read them with the wrong element size (a panic in a debug
            // build, garbage in a release one).
            let readable =
                |semantic: gltf::Semantic, name: &str| prim.get(&semantic).filter(|a| unreadable(a, name).is_none());
            let buffers = &self.buffers[..];
            let positions: Vec<[f32; 3]> =
                prim.get(&gltf::Semantic::Positions).and_then(|a| read(a, buffers)).ok_or_else(|| {
                    malformed(format!("mesh {mi} primitive {pi}: POSITION missing or outside its buffer"))
                })?;
            let n = positions.len();
            let base = self.out.positions.len();
            self.out.positions.extend(positions.iter().map(|&p| world.transform_point3(Vec3::from(p)).to_array()));
            let normals: Option<Vec<[f32; 3]>> =
                readable(gltf::Semantic::Normals, "NORMAL").and_then(|a| read(a, buffers));
            let has_normals = normals.as_ref().is_some_and(|ns| ns.len() == n);
            self.any_normals |= has_normals;
            match normals {
                // Untransformed normals stay bit-exact (no renormalisation).
                Some(ns) if ns.len() == n && world == Mat4::IDENTITY => self.out.normals.extend(ns),
                Some(ns) if ns.len() == n => self
                    .out
                    .normals
                    .extend(ns.iter().map(|&v| (normal_m * Vec3::from(v)).normalize_or_zero().to_array())),
                _ => self.out.normals.resize(base + n, [0.0; 3]),
            }
            let uvs: Option<Vec<[f32; 2]>> =
                readable(gltf::Semantic::TexCoords(0), "TEXCOORD_0").and_then(|a| read(a, buffers));
            let has_uvs = uvs.as_ref().is_some_and(|t| t.len() == n);
            let present = |s: gltf::Semantic| prim.get(&s).is_some();
            if first_visit
                && (present(gltf::Semantic::Normals) && !has_normals
                    || present(gltf::Semantic::TexCoords(0)) && !has_uvs)
            {
                self.unreadable.add(Location::Primitive { mesh: mi as u32, primitive: pi as u32 });
            }
            self.any_uvs |= has_uvs;
            match uvs {
                Some(t) if t.len() == n => self.out.uvs.extend(t),
                _ => self.out.uvs.resize(base + n, [0.0; 2]),
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
                });
                self.count_attributes(&prim);
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
