//! Reading and writing mesh files.
//!
//! [`load`] picks the format from the extension (`.obj`, `.ply`, `.off`, `.stl`, `.gltf`,
//! `.glb`, each optionally `.gz`) and, when that is missing or unknown, from the first bytes.
//! Every loader returns an [`IndexedMesh`] that has passed [`IndexedMesh::check`], or a
//! [`LoadError`] naming the file and what is wrong. Parsers from crates are guarded: a panic
//! inside one becomes a `Malformed` error, never a crash.
//!
//! Writers ([`save`]) always write to a temporary file in the target folder and rename it into
//! place, so a failed write never leaves half a file.

mod bump_map;
mod gltf;
mod gltf_accessor;
pub(crate) mod gltf_attributes;
mod gltf_draco;
mod gltf_extensions;
mod gltf_instancing;
mod gltf_meshopt;
mod gltf_parse;
mod gltf_resources;
mod gltf_scene;
mod image_convert;
mod normal_map_tangents;
mod obj;
mod obj_materials;
mod off;
mod ply;
mod ply_ascii;
mod ply_header;
mod ply_wedges;
mod polygon;
mod stl;
mod stl_ascii;
mod text;
mod texture_files;
mod uv_origin;
mod write;
mod write_mtl;
mod write_scene;

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::error::{LoadError, LoadErrorKind};
use crate::mesh::IndexedMesh;

pub use gltf_scene::{GltfScene, Placement, SceneMesh};
pub use write::{library_name_for, not_written, save, save_as, write_glb, write_obj, write_ply, WriteFormat};

/// The mesh formats we read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// Stanford PLY, ascii or binary.
    Ply,
    /// Object File Format.
    Off,
    /// STL, ascii or binary.
    Stl,
    /// glTF 2.0 JSON (`.gltf`) with external or embedded buffers.
    Gltf,
    /// glTF 2.0 binary container.
    Glb,
}

impl Format {
    /// The format an extension names (case-insensitive), if any.
    pub fn from_extension(ext: &str) -> Option<Self> {
        Some(match ext.to_ascii_lowercase().as_str() {
            "obj" => Self::Obj,
            "ply" => Self::Ply,
            "off" => Self::Off,
            "stl" => Self::Stl,
            "gltf" => Self::Gltf,
            "glb" => Self::Glb,
            _ => return None,
        })
    }

    /// Guesses the format from the first bytes of a file.
    pub fn sniff(bytes: &[u8]) -> Option<Self> {
        let head = &bytes[..bytes.len().min(512)];
        let text = String::from_utf8_lossy(text::without_bom(head));
        let t = text.trim_start();
        if head.starts_with(b"glTF") {
            Some(Self::Glb)
        } else if t.starts_with("ply") {
            Some(Self::Ply)
        } else if t.starts_with("OFF") || t.starts_with("COFF") || t.starts_with("NOFF") || t.starts_with("STOFF") {
            Some(Self::Off)
        } else if t.starts_with('{') && text.contains("\"asset\"") {
            Some(Self::Gltf)
        } else if t.get(..5).is_some_and(|w| w.eq_ignore_ascii_case("solid")) || stl::is_binary_stl(bytes) {
            Some(Self::Stl)
        } else if t.lines().any(|l| l.starts_with("v ") || l.starts_with("f ") || l.starts_with("o ")) {
            Some(Self::Obj)
        } else {
            None
        }
    }

    /// Short name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Obj => "OBJ",
            Self::Ply => "PLY",
            Self::Off => "OFF",
            Self::Stl => "STL",
            Self::Gltf => "glTF",
            Self::Glb => "GLB",
        }
    }
}

/// Loads a mesh file. See the module docs for formats and guarantees.
pub fn load(path: impl AsRef<Path>) -> Result<IndexedMesh, LoadError> {
    let path = path.as_ref();
    let raw = std::fs::read(path).map_err(|e| LoadError::new(path, e))?;
    let (bytes, inner_name) = if is_gzip(path, &raw) {
        let stem = path.file_stem().map(PathBuf::from).unwrap_or_default();
        (gunzip(&raw).map_err(|k| LoadError::new(path, k))?, stem)
    } else {
        (raw, path.to_path_buf())
    };
    let ext_format = inner_name.extension().and_then(|e| e.to_str()).and_then(Format::from_extension);
    let format = ext_format
        .or_else(|| Format::sniff(&bytes))
        .ok_or_else(|| LoadError::new(path, LoadErrorKind::UnknownFormat))?;
    load_bytes(&bytes, format, path.parent()).map_err(|kind| LoadError::new(path, kind))
}

/// Parses an in-memory file of a known format. `base_dir` resolves a `.gltf` file's external
/// buffers (None: only embedded buffers are allowed).
pub fn load_bytes(bytes: &[u8], format: Format, base_dir: Option<&Path>) -> Result<IndexedMesh, LoadErrorKind> {
    guarded(format.name(), || load_bytes_unguarded(bytes, format, base_dir))
}

/// `read`, with a panic inside it (in a parser from a crate) turned into a `Malformed` error
/// of `format`.
pub(crate) fn guarded<T>(
    format: &'static str,
    read: impl FnOnce() -> Result<T, LoadErrorKind>,
) -> Result<T, LoadErrorKind> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(read)).unwrap_or_else(|p| {
        let message = p
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "parser failed".into());
        Err(LoadErrorKind::Malformed { format, line: None, message })
    })
}

/// [`load_bytes`] without the panic guard, for the fuzz targets: any panic is a bug.
#[doc(hidden)]
pub fn load_bytes_unguarded(
    bytes: &[u8],
    format: Format,
    base_dir: Option<&Path>,
) -> Result<IndexedMesh, LoadErrorKind> {
    let mut mesh = match format {
        Format::Obj => obj::load(bytes, base_dir),
        Format::Ply => ply::load(bytes, base_dir),
        Format::Off => off::load(bytes),
        Format::Stl => stl::load(bytes),
        Format::Gltf | Format::Glb => gltf::load(bytes, base_dir),
    }?;
    mesh.check()?;
    normal_map_tangents::add(&mut mesh);
    Ok(mesh)
}

/// Parses a gzip-compressed in-memory file of a known format (e.g. a bundled asset).
pub fn load_gz_bytes(gz: &[u8], format: Format) -> Result<IndexedMesh, LoadErrorKind> {
    load_bytes(&gunzip(gz)?, format, None)
}

fn gunzip(gz: &[u8]) -> Result<Vec<u8>, LoadErrorKind> {
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(gz).read_to_end(&mut out).map_err(|e| LoadErrorKind::Malformed {
        format: "gzip",
        line: None,
        message: e.to_string(),
    })?;
    Ok(out)
}

fn is_gzip(path: &Path, bytes: &[u8]) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gz")) || bytes.starts_with(&[0x1f, 0x8b])
}

/// Checks one index read from a file against the vertex count, reporting face and corner.
pub(crate) fn check_index(index: i64, vertex_count: usize, face: usize, corner: usize) -> Result<u32, LoadErrorKind> {
    if index < 0 || index as u64 >= vertex_count as u64 {
        return Err(crate::error::MeshError::IndexOutOfRange { face, corner, index, vertex_count }.into());
    }
    Ok(index as u32)
}
