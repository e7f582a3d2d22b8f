//! Where a glTF's bytes come from: its buffers (the GLB's BIN chunk, data URIs, files
//! beside it by percent-encoded URI), and, for GLB output, its material definitions as the
//! source wrote them with every image's bytes.

use std::collections::BTreeSet;
use std::path::Path;

use base64::Engine;

use super::gltf::malformed;
use super::gltf_meshopt::{decode_views, is_fallback};
use crate::error::LoadErrorKind;

/// The source's material definitions as written (every extension and extra kept), with every
/// image's bytes (from a buffer view, a data URI, or a file beside the source) so the output
/// is self-contained. Of the source's extension lists, the output declares the extensions
/// these definitions use (`named`, from `material_extensions`).
pub(super) fn materials(
    g: &gltf::Document,
    raw: &serde_json::Value,
    named: &BTreeSet<String>,
    buffers: &[Vec<u8>],
    base: Option<&Path>,
) -> crate::mesh::GltfMaterials {
    let images = g.as_json().images.iter().map(|img| image(g, img, buffers, base)).collect();
    let array = |key: &str| raw.get(key).filter(|v| v.is_array()).cloned().unwrap_or_else(|| serde_json::json!([]));
    let (materials, textures, samplers) = (array("materials"), array("textures"), array("samplers"));
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

/// One image, read from the JSON itself: the gltf crate's `Image::source` unwraps a mimeType
/// missing beside a bufferView, and a uri missing where there is no bufferView (panics found
/// by fuzzing). A missing type is guessed from the bytes or the uri; an image with neither
/// source stays without one, as it came.
fn image(
    g: &gltf::Document,
    img: &gltf::json::Image,
    buffers: &[Vec<u8>],
    base: Option<&Path>,
) -> crate::mesh::GltfImage {
    let name = img.name.clone();
    let declared = img.mime_type.as_ref().map(|m| m.0.clone());
    if let Some(view) = img.buffer_view.and_then(|v| g.views().nth(v.value())) {
        let bytes = view
            .offset()
            .checked_add(view.length())
            .and_then(|end| buffers.get(view.buffer().index())?.get(view.offset()..end))
            .map(<[u8]>::to_vec);
        let guessed = bytes.as_deref().and_then(image_type).map(String::from);
        return crate::mesh::GltfImage { name, mime_type: declared.or(guessed), bytes, uri: None };
    }
    let Some(uri) = img.uri.as_deref() else {
        return crate::mesh::GltfImage { name, mime_type: declared, bytes: None, uri: None };
    };
    let bytes = if uri.starts_with("data:") {
        data_uri(uri).ok()
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

/// The image type of `bytes` by their signature, where it is one glTF holds (PNG, JPEG).
pub(super) fn image_type(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG") {
        Some("image/png")
    } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        Some("image/jpeg")
    } else {
        None
    }
}

/// The bytes of a base64 `data:` URI (the only kind glTF embeds), or why there are none.
fn data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let (_, payload) = uri.split_once(";base64,").ok_or("data URI is not base64")?;
    base64::engine::general_purpose::STANDARD.decode(payload).map_err(|e| format!("bad base64: {e}"))
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

/// Every buffer's bytes (`blob`, the GLB's BIN chunk, is moved in, not copied). Only buffer 0
/// can be a GLB's BIN chunk (glTF 2.0 §4.4.3.3). A meshopt fallback buffer is not read (in
/// a GLB it has no `uri`): it is filled with its compressed views, decoded
/// ([`gltf_meshopt`](super::gltf_meshopt)).
pub(super) fn load_buffers(
    g: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    raw: &serde_json::Value,
    base: Option<&Path>,
) -> Result<Vec<Vec<u8>>, LoadErrorKind> {
    let mut out = Vec::new();
    for b in g.buffers() {
        if is_fallback(raw, b.index()) {
            out.push(Vec::new());
            continue;
        }
        let data = match b.source() {
            gltf::buffer::Source::Bin if b.index() > 0 => {
                return Err(malformed(format!(
                    "buffer {} has no uri, and only buffer 0 can be the GLB's BIN chunk",
                    b.index()
                )));
            }
            gltf::buffer::Source::Bin => blob
                .take()
                .ok_or_else(|| malformed(format!("buffer {} refers to a missing GLB BIN chunk", b.index())))?,
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                data_uri(uri).map_err(|e| malformed(format!("buffer {}: {e}", b.index())))?
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
    let declared: Vec<usize> = g.buffers().map(|b| b.length()).collect();
    decode_views(raw, &declared, &mut out)?;
    Ok(out)
}
