//! STL, ascii and binary, through `stl_io` (which merges bit-identical corners). Facet
//! normals are not kept: they are per face, and as wedges they would make every edge a seam.
//! Errors name the facet, and in ascii the line (`stl_ascii.rs`).

use std::borrow::Cow;
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
    let solid = text.trim_ascii_start().get(..5).is_some_and(|w| w.eq_ignore_ascii_case(b"solid"));
    let ascii = solid && !is_binary_stl(bytes);
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
    let mesh = match ascii {
        true => read_ascii(bytes)?,
        false => stl_io::read_stl(&mut AsBinary(Cursor::new(bytes))).map_err(|e| stl_io_error("binary", e))?,
    };
    let mut out = IndexedMesh::default();
    (out.positions, out.origin) =
        crate::mesh::origin::relative_f32_positions(mesh.vertices.iter().map(|v| v.0).collect());
    for (face, t) in mesh.faces.iter().enumerate() {
        let mut tri = [0u32; 3];
        for (corner, &i) in t.vertices.iter().enumerate() {
            tri[corner] = super::check_index(i as i64, out.positions.len(), face, corner)?;
            // An STL numbers no vertices (stl_io's are its merged ones): a NaN or infinite
            // corner is named by its facet, as the file has it.
            let p = mesh.vertices[i].0;
            if !p.iter().all(|c| c.is_finite()) {
                return Err(LoadErrorKind::Malformed {
                    format: "STL",
                    line: None,
                    message: format!("facet {face} corner {corner} has a non-finite coordinate {p:?}"),
                });
            }
        }
        out.triangles.push(tri);
    }
    Ok(out)
}

/// An ascii STL through stl_io, with the place of any error found by `stl_ascii.rs`. The
/// text is made UTF-8 first (`text.rs`: a byte-order mark, a Latin-1 solid name). stl_io
/// takes a file as ascii only where it starts with `solid ` exactly; a nameless `solid`, one
/// after a tab or after blank space would go to its binary reader, so the first line is
/// written as `solid ` where it is not (the name is not kept anyway). Keywords in capitals
/// are read in lower case.
fn read_ascii(bytes: &[u8]) -> Result<stl_io::IndexedMesh, LoadErrorKind> {
    let text = super::text::utf8(bytes);
    let body = text.trim_start();
    let skipped = text[..text.len() - body.len()].matches('\n').count();
    // Some CAD tools write the keywords in capitals (`SOLID`, `FACET NORMAL`, `VERTEX`), or
    // some of them (`solid` then `Outer Loop`), which stl_io does not know: such a file is
    // read in lower case (numbers read the same, and the solid's name is not kept). An error
    // is still reported in the file's own words.
    let after_solid = body.find('\n').map_or("", |n| &body[n..]);
    let read = match body.starts_with("solid") && !after_solid.bytes().any(|b| b.is_ascii_uppercase()) {
        true => Cow::Borrowed(body),
        false => Cow::Owned(body.to_ascii_lowercase()),
    };
    let read = match read.starts_with("solid ") {
        true => read,
        false => Cow::Owned(format!("solid \n{}", read.split_once('\n').map_or("", |(_, rest)| rest))),
    };
    stl_io::read_stl(&mut Cursor::new(read.as_bytes()))
        .map_err(|e| super::stl_ascii::locate(body, skipped).unwrap_or_else(|| stl_io_error("ascii", e)))
}

/// stl_io's error as ours, where nothing better is known.
fn stl_io_error(kind: &str, e: std::io::Error) -> LoadErrorKind {
    match e.kind() {
        std::io::ErrorKind::UnexpectedEof => {
            LoadErrorKind::Truncated { format: "STL", message: format!("{kind}: {e}") }
        }
        _ => LoadErrorKind::Malformed { format: "STL", line: None, message: format!("{kind}: {e}") },
    }
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
