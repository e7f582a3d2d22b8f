//! STL, ascii and binary, through `stl_io` (which merges bit-identical corners). Facet
//! normals are not kept: they are per face, and as wedges they would make every edge a seam.

use std::io::{Cursor, Read, Seek, SeekFrom};

use crate::error::LoadErrorKind;
use crate::mesh::IndexedMesh;

/// Whether `bytes` has the exact size a binary STL header announces.
pub(super) fn is_binary_stl(bytes: &[u8]) -> bool {
    bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        84 + 50 * n == bytes.len() as u64
    }
}

pub(super) fn load(bytes: &[u8]) -> Result<IndexedMesh, LoadErrorKind> {
    // A binary header may start with any bytes: a UTF-8 byte-order mark is read past only
    // before an ascii file's `solid`.
    let text = super::text::without_bom(bytes);
    let ascii = text.trim_ascii_start().starts_with(b"solid") && !is_binary_stl(bytes);
    // stl_io takes a file as ascii only where it starts with `solid ` exactly; a nameless
    // `solid`, one after a tab or after blank space would go to its binary reader.
    let normalised;
    let bytes = match ascii {
        true if !text.starts_with(b"solid ") => {
            let rest = text.trim_ascii_start()[5..].splitn(2, |&c| c == b'\n').nth(1).unwrap_or_default();
            normalised = [b"solid \n".as_slice(), rest].concat();
            &normalised[..]
        }
        true => text,
        false => bytes,
    };
    if !ascii && bytes.len() >= 84 && !is_binary_stl(bytes) {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        if (bytes.len() as u64) < 84 + 50 * n {
            return Err(LoadErrorKind::Truncated {
                format: "STL",
                message: format!(
                    "header announces {n} triangles ({} bytes) but the file has {} bytes",
                    84 + 50 * n,
                    bytes.len()
                ),
            });
        }
    }
    if !ascii && bytes.len() < 84 {
        return Err(LoadErrorKind::Truncated {
            format: "STL",
            message: format!("{} bytes is shorter than a binary STL header", bytes.len()),
        });
    }
    let read = match ascii {
        true => stl_io::read_stl(&mut Cursor::new(bytes)),
        false => stl_io::read_stl(&mut AsBinary(Cursor::new(bytes))),
    };
    let mesh = read.map_err(|e| {
        let kind = if ascii { "ascii" } else { "binary" };
        match e.kind() {
            std::io::ErrorKind::UnexpectedEof => {
                LoadErrorKind::Truncated { format: "STL", message: format!("{kind}: {e}") }
            }
            _ => LoadErrorKind::Malformed { format: "STL", line: None, message: format!("{kind}: {e}") },
        }
    })?;
    let mut out = IndexedMesh::default();
    (out.positions, out.origin) =
        crate::mesh::origin::relative_f32_positions(mesh.vertices.iter().map(|v| v.0).collect());
    for (face, t) in mesh.faces.iter().enumerate() {
        let mut tri = [0u32; 3];
        for (corner, &i) in t.vertices.iter().enumerate() {
            tri[corner] = super::check_index(i as i64, out.positions.len(), face, corner)?;
        }
        out.triangles.push(tri);
    }
    Ok(out)
}

/// A binary STL as stl_io reads it whatever its header says. stl_io takes any file whose
/// first line starts with `solid ` for ascii, but a binary header is free text, and OpenSCAD,
/// SolidWorks and others begin it with `solid`: where a newline byte follows in the data,
/// the ascii reader got the file and failed on it. The header's first byte reads as NUL.
struct AsBinary<'a>(Cursor<&'a [u8]>);

impl Read for AsBinary<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let at_start = self.0.position() == 0;
        let n = self.0.read(buf)?;
        if at_start && n > 0 {
            buf[0] = 0;
        }
        Ok(n)
    }
}

impl Seek for AsBinary<'_> {
    fn seek(&mut self, to: SeekFrom) -> std::io::Result<u64> {
        self.0.seek(to)
    }
}
