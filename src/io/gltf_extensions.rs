//! The glTF extensions the loader meets, and what it does with each (glTF 2.0 §3.12): a
//! required one is read (`KHR_mesh_quantization`, in [`gltf_accessor`](super::gltf_accessor);
//! meshopt compression, in [`gltf_meshopt`](super::gltf_meshopt); Draco compression, in
//! [`gltf_draco`](super::gltf_draco); `EXT_mesh_gpu_instancing`, in
//! [`gltf_instancing`](super::gltf_instancing)), carried (material, texture and light
//! extensions, which the materials keep as written), or refused by name (unknown
//! extensions, material variants); one only used and neither read nor carried is listed as
//! not kept.

use std::collections::BTreeSet;

use crate::error::LoadErrorKind;

/// Draco geometry compression: decoded ([`gltf_draco`](super::gltf_draco)).
pub(super) const DRACO: &str = "KHR_draco_mesh_compression";

/// The extensions whose data the loader decodes: they shape how the bytes are read, and a
/// file read through them is as if it had been written without them.
fn decoded(extension: &str) -> bool {
    extension == "KHR_mesh_quantization"
        || extension == DRACO
        || extension == super::gltf_instancing::EXTENSION
        || super::gltf_meshopt::EXTENSIONS.contains(&extension)
}

/// A required extension is read (quantization, compression, instancing: [`decoded`]),
/// carried (material, texture and light extensions: they change how the surface looks, not
/// its geometry, and materials are copied to GLB output as written), or refused with a
/// typed error that names it: anything unknown,
/// which could change what the geometry means (glTF 2.0 §3.12: a loader must not load a file
/// whose required extensions it does not support).
pub(super) fn check_required(required: &[String]) -> Result<(), LoadErrorKind> {
    let carried = |e: &str| {
        decoded(e)
            || e == "KHR_lights_punctual"
            || ["KHR_materials_", "KHR_texture_", "EXT_texture_", "MSFT_texture_"].iter().any(|p| e.starts_with(p))
                && e != "KHR_materials_variants"
    };
    match required.iter().find(|e| !carried(e)) {
        None => Ok(()),
        Some(e) => Err(LoadErrorKind::Unsupported {
            format: "glTF",
            message: format!("the file requires the extension {e}, which dynlod does not support"),
        }),
    }
}

/// The extensions the source's materials, textures and samplers use.
pub(super) fn material_extensions(raw: &serde_json::Value) -> BTreeSet<String> {
    let mut named = BTreeSet::new();
    for key in ["materials", "textures", "samplers"] {
        raw.get(key).into_iter().for_each(|v| extension_names(v, &mut named));
    }
    named
}

/// The keys of every `extensions` object inside `v`.
fn extension_names(v: &serde_json::Value, out: &mut BTreeSet<String>) {
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

/// The extensions the source uses that the mesh neither decodes (quantization, meshopt
/// compression) nor carries in its materials (`carried`, from [`material_extensions`]).
pub(super) fn not_carried<'a>(raw: &'a serde_json::Value, carried: &BTreeSet<String>) -> Vec<&'a str> {
    let used = raw.get("extensionsUsed").and_then(|v| v.as_array()).into_iter().flatten().filter_map(|e| e.as_str());
    used.filter(|e| !decoded(e) && !carried.contains(*e)).collect()
}
