//! The glTF document from a file's bytes: the GLB split (its header checked first), the
//! JSON past a byte-order mark, glTF 1.0 refused by name, attribute accessors and required
//! extensions checked before gltf-json looks at them, and gltf-json's validation, less its
//! demand for POSITION bounds (read anyway, and recorded by the loader in `gltf.rs`).

use std::path::Path;

use super::gltf::malformed;
use super::gltf_extensions::check_required;
use super::gltf_resources::load_buffers;
use crate::error::LoadErrorKind;

/// The document, its buffers and its JSON.
pub(super) fn parse_with_buffers(
    bytes: &[u8],
    base: Option<&Path>,
) -> Result<(gltf::Document, Vec<Vec<u8>>, serde_json::Value), LoadErrorKind> {
    let (g, blob, mut raw) = parse(bytes)?;
    let mut buffers = load_buffers(&g, blob, &raw, base)?;
    if super::gltf_draco::decode(&mut raw, &mut buffers)? {
        // The decoded primitives' accessors now point at a buffer of their own.
        return Ok((document(&raw, None)?, buffers, raw));
    }
    Ok((g, buffers, raw))
}

/// The document, validated; the GLB's BIN chunk; and the JSON as written (materials are
/// carried from it, every extension and extra included). gltf-json's validation looks up the
/// accessor each POSITION names before checking that it exists (an index out of bounds, found
/// by fuzzing), so attribute accessors are checked here first; so is the GLB header's length.
/// Required extensions are checked here too ([`check_required`]), not by gltf-json, which
/// knows only the few its build enables.
fn parse(bytes: &[u8]) -> Result<(gltf::Document, Option<Vec<u8>>, serde_json::Value), LoadErrorKind> {
    // gltf's GLB reader subtracts the header's size from the total length the header
    // declares before comparing them (an overflow).
    if let Some(length) = bytes.strip_prefix(b"glTF").and_then(|b| b.get(4..8)) {
        let length = u32::from_le_bytes(length.try_into().expect("4 bytes"));
        if length < 12 {
            return Err(malformed(format!("the GLB header declares {length} bytes in all, fewer than its own 12")));
        }
    }
    // The GLB split once; its BIN chunk copied once, here, and moved into the buffers.
    let (json, blob) = match bytes.starts_with(b"glTF") {
        true => {
            // Binary glTF 1.0 (KHR_binary_glTF) has version 1 in its header.
            if bytes.get(4..8) == Some(&1u32.to_le_bytes()) {
                return Err(version_1());
            }
            let glb = gltf::binary::Glb::from_slice(bytes).map_err(|e| malformed(e.to_string()))?;
            (glb.json, glb.bin.map(std::borrow::Cow::into_owned))
        }
        false => (std::borrow::Cow::Borrowed(bytes), None),
    };
    // JSON may not start with a byte-order mark, but some writers put one there, and RFC 8259
    // lets a reader pass over it (`text.rs`).
    let json = super::text::without_bom(&json);
    let raw: serde_json::Value = serde_json::from_slice(json).map_err(|e| malformed(e.to_string()))?;
    // glTF 1.0 (its objects keyed by name; `"version": 1` was also written) reads as a
    // schema error otherwise, on the first object.
    let version = &raw["asset"]["version"];
    let keyed = ["accessors", "buffers", "meshes", "nodes"].iter().any(|k| raw[k].is_object());
    if keyed || version.as_str().is_some_and(|v| v.starts_with("1.")) || version.as_f64().is_some_and(|v| v < 2.0) {
        return Err(version_1());
    }
    Ok((document(&raw, Some(json))?, blob, raw))
}

/// The document of `raw` (parsed from `json`, its text, where given), checked and validated
/// (see [`parse`]).
fn document(raw: &serde_json::Value, json: Option<&[u8]>) -> Result<gltf::Document, LoadErrorKind> {
    // A scene's `nodes` is optional in glTF 2.0 (an empty scene leaves it out, as Blender
    // writes one), but gltf-json requires it: such scenes get an empty list, to parse.
    let nodeless = |s: &serde_json::Value| s.is_object() && s.get("nodes").is_none();
    let root = match (json, raw["scenes"].as_array().is_some_and(|s| s.iter().any(nodeless))) {
        (Some(json), false) => gltf::json::Root::from_slice(json),
        (None, false) => serde_json::from_value(raw.clone()),
        (_, true) => {
            let mut patched = raw.clone();
            for scene in patched["scenes"].as_array_mut().into_iter().flatten().filter(|s| nodeless(s)) {
                scene["nodes"] = serde_json::json!([]);
            }
            serde_json::from_value(patched)
        }
    };
    let mut root = root.map_err(|e| malformed(e.to_string()))?;
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
    root.extensions_required.clear();
    let document = gltf::Document::from_json_without_validation(root);
    validate(&document)?;
    Ok(document)
}

/// gltf-json's validation, less its demands that every accessor have a buffer view (see
/// below) and that every POSITION accessor carry `min` and `max` as three numbers. glTF 2.0
/// requires the bounds, but some exporters leave them out
/// (assimp's `IncorrectVertexArrays/Cube.gltf`), and nothing here reads them: the bounds
/// come from the positions, and a GLB output writes its own. Such a primitive is read and
/// recorded ([`crate::mesh::RepairKind::RecomputedPositionBounds`]); so is a primitive without
/// POSITION, which glTF 2.0 allows (skipped); any other error refuses the file.
fn validate(g: &gltf::Document) -> Result<(), LoadErrorKind> {
    use gltf::json::validation::Validate;
    let root = g.as_json();
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        let bound = path.as_str().ends_with(r#".attributes["POSITION"].min"#)
            || path.as_str().ends_with(r#".attributes["POSITION"].max"#);
        // POSITION itself may be left out (glTF 2.0 §3.7.2.1); the loader skips the primitive.
        let no_positions =
            path.as_str().ends_with(r#".attributes["POSITION"]"#) && error == gltf::json::validation::Error::Missing;
        // An accessor without a buffer view is zeros (glTF 2.0 §3.6.2.3), and a Draco
        // primitive's accessors have none until `gltf_draco` decodes their stream; one read
        // without data gets the loader's error, which names the primitive.
        let viewless = path.as_str().starts_with("accessors[")
            && path.as_str().ends_with("].bufferView")
            && error == gltf::json::validation::Error::Missing;
        if !bound && !no_positions && !viewless {
            errors.push((path, error));
        }
    });
    match errors.is_empty() {
        true => Ok(()),
        false => Err(malformed(gltf::Error::Validation(errors).to_string())),
    }
}

/// Whether a POSITION accessor has the `min` and `max` glTF requires, as three numbers each.
pub(super) fn bounded(a: &gltf::Accessor<'_>) -> bool {
    let three = |v: Option<gltf::json::Value>| v.is_some_and(|v| serde_json::from_value::<[f32; 3]>(v).is_ok());
    three(a.min()) && three(a.max())
}

fn version_1() -> LoadErrorKind {
    LoadErrorKind::Unsupported {
        format: "glTF",
        message: "glTF 1.0; only glTF 2.0 is read (convert the file to 2.0 first)".into(),
    }
}
