//! Stanford PLY (ascii, binary little and big endian) through `ply-rs-bw`. Reads `vertex`
//! (x, y, z of any numeric type; nx, ny, nz; u/v, s/t or texture_u/texture_v), `face` lists
//! (`vertex_indices` or `vertex_index`, polygons triangulated: `polygon.rs`) and `tristrips` lists
//! (strips separated by -1, alternate triangles reversed to keep one winding, as in
//! `igea_tristrips.ply`), and vertex colours (`red`, `green`, `blue`, optionally `alpha`, or
//! the `diffuse_` names) as `COLOR_0` in 0–1: 8-bit channels over 255, 16-bit over 65,535,
//! floating-point ones as they are. Other properties and elements are read past and listed in
//! `not_kept`. The header is made readable first (`ply_header.rs`: bare lines as comments).
//! Texture coordinates per face corner (`texcoord` lists) and texture numbers (`texnumber`),
//! as MeshLab writes a textured mesh, are read too (`ply_wedges.rs`), and the header's
//! `comment TextureFile` names become materials (one over per-vertex coordinates too). An
//! ascii body whose elements spread over lines, or share them, is read as words where it fails
//! one element to a line (`ply_ascii.rs`).
//! Texture coordinates have their origin at the image's bottom-left, and turn over into
//! glTF's (`uv_origin.rs`).

use std::io::{BufReader, Cursor};

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{Property, PropertyAccess, PropertyAccessResult};

use crate::error::LoadErrorKind;
use crate::mesh::{IndexedMesh, NotKept, NotKeptKind, VertexAttribute};

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v as f64,
        Property::UChar(v) => v as f64,
        Property::Short(v) => v as f64,
        Property::UShort(v) => v as f64,
        Property::Int(v) => v as f64,
        Property::UInt(v) => v as f64,
        Property::Float(v) => v as f64,
        Property::Double(v) => v,
        _ => return None,
    })
}

fn int_list(p: Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
        Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
        Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
        _ => return None,
    })
}

/// One `vertex` record: position, normal, UV and colour slots.
#[derive(Default)]
struct Vertex {
    p: [f64; 3],
    n: [f64; 3],
    uv: [f64; 2],
    rgba: [f32; 4],
}

/// The colour channel a vertex property names.
fn channel(name: &str) -> Option<usize> {
    Some(match name.strip_prefix("diffuse_").unwrap_or(name) {
        "red" => 0,
        "green" => 1,
        "blue" => 2,
        "alpha" => 3,
        _ => return None,
    })
}

/// Whether a vertex element has colours: red, green and blue channels at least.
fn has_colour(el: &ply_rs_bw::ply::ElementDef) -> bool {
    (0..3).all(|c| el.properties.keys().any(|k| channel(k) == Some(c)))
}

/// A colour channel in 0–1: integers over their type's maximum, floats as they are.
fn unit(p: &Property) -> Option<f32> {
    Some(match *p {
        Property::UChar(v) => f32::from(v) / 255.0,
        Property::UShort(v) => f32::from(v) / 65535.0,
        Property::Char(v) => f32::from(v.max(0)) / 127.0,
        Property::Short(v) => f32::from(v.max(0)) / 32767.0,
        Property::UInt(v) => (f64::from(v) / f64::from(u32::MAX)) as f32,
        Property::Int(v) => (f64::from(v.max(0)) / f64::from(i32::MAX)) as f32,
        Property::Float(v) => v,
        Property::Double(v) => v as f32,
        _ => return None,
    })
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: &str, p: Property) -> PropertyAccessResult {
        if let Some(c) = channel(name) {
            return match unit(&p) {
                Some(v) => {
                    self.rgba[c] = v;
                    PropertyAccessResult::Set
                }
                None => PropertyAccessResult::UnsupportedType,
            };
        }
        let slot = match name {
            "x" => &mut self.p[0],
            "y" => &mut self.p[1],
            "z" => &mut self.p[2],
            "nx" => &mut self.n[0],
            "ny" => &mut self.n[1],
            "nz" => &mut self.n[2],
            "u" | "s" | "texture_u" | "texture_s" => &mut self.uv[0],
            "v" | "t" | "texture_v" | "texture_t" => &mut self.uv[1],
            _ => return PropertyAccessResult::Ignored,
        };
        match scalar(&p) {
            Some(v) => {
                *slot = v;
                PropertyAccessResult::Set
            }
            None => PropertyAccessResult::UnsupportedType,
        }
    }
}

fn float_list(p: Property) -> Option<Vec<f32>> {
    Some(match p {
        Property::ListFloat(v) => v,
        Property::ListDouble(v) => v.into_iter().map(|c| c as f32).collect(),
        _ => return None,
    })
}

/// One `face` or `tristrips` record: its index list; for a face, also its corners' texture
/// coordinates and its texture number where the file has them (`ply_wedges.rs`).
#[derive(Default)]
struct IndexList(Vec<i64>, Option<Vec<f32>>, Option<i64>);

impl PropertyAccess for IndexList {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: &str, p: Property) -> PropertyAccessResult {
        let set = match name {
            "vertex_indices" | "vertex_index" => int_list(p).map(|v| self.0 = v),
            "texcoord" => float_list(p).map(|v| self.1 = Some(v)),
            "texnumber" => scalar(&p).map(|t| self.2 = Some(t as i64)),
            _ => return PropertyAccessResult::Ignored,
        };
        match set {
            Some(()) => PropertyAccessResult::Set,
            None => PropertyAccessResult::UnsupportedType,
        }
    }
}

/// Anything else: read and dropped.
pub(super) struct Ignore;

impl PropertyAccess for Ignore {
    fn new() -> Self {
        Ignore
    }
}

fn parse_err(e: ply_rs_bw::parser::ParseError) -> LoadErrorKind {
    let message = super::ply_header::message(&e);
    if e.kind() == std::io::ErrorKind::UnexpectedEof {
        LoadErrorKind::Truncated { format: "PLY", message }
    } else {
        LoadErrorKind::Malformed { format: "PLY", line: e.line(), message }
    }
}

pub(super) fn load(bytes: &[u8], base: Option<&std::path::Path>) -> Result<IndexedMesh, LoadErrorKind> {
    // The header is ASCII; a UTF-8 byte-order mark before it is read past, and a comment in
    // Latin-1 read as such (`text.rs`): ply-rs refused the file.
    let bytes = super::text::header_utf8(super::text::without_bom(bytes), b"end_header");
    let (bytes, commented) = super::ply_header::tidy(&bytes)?;
    // The header as ply-rs reads it, for the ascii checks after the read (whose own header
    // error, where there is one, is the same).
    let header = Parser::<Ignore>::new().read_header(&mut Reader::new(BufReader::new(Cursor::new(&*bytes))));
    let header = header.map_err(parse_err);
    let read = match read(&bytes, base) {
        // An ascii body whose elements do not sit one to a line (`ply_ascii.rs`).
        Err(e) => {
            let header = header?;
            match super::ply_ascii::rewrap(&bytes, &header) {
                // Its lines are not the file's: where reading it fails on a line, the first
                // error stands (a face or vertex is numbered as in the file, though).
                Some((rewrapped, repair)) => {
                    read(&rewrapped, base).map(|mesh| (mesh, Some(repair))).map_err(|later| match later {
                        LoadErrorKind::Malformed { format: "PLY", .. } | LoadErrorKind::Truncated { .. } => e,
                        later => later,
                    })
                }
                None => Err(e),
            }
        }
        // Words ply-rs passed over: the body read as words where they fit the header
        // exactly (elements sharing lines, which ply-rs can misread without failing), and
        // otherwise recorded.
        Ok(mesh) => {
            let header = header?;
            match super::ply_ascii::extra_words(&bytes, &header) {
                None => Ok((mesh, None)),
                Some(extra) => {
                    let stream = super::ply_ascii::rewrap(&bytes, &header);
                    match stream.and_then(|(rewrapped, repair)| Some((read(&rewrapped, base).ok()?, repair))) {
                        Some((read_as_words, repair)) => Ok((read_as_words, Some(repair))),
                        None => Ok((mesh, Some(extra))),
                    }
                }
            }
        }
    };
    let (mut mesh, rewrapped) = read?;
    let mut repairs = Vec::new();
    commented.push_into(&mut repairs);
    rewrapped.into_iter().for_each(|r| r.push_into(&mut repairs));
    mesh.load_repairs.splice(0..0, repairs);
    Ok(mesh)
}

/// The mesh in `bytes`, a PLY file whose header ply-rs reads.
fn read(bytes: &[u8], base: Option<&std::path::Path>) -> Result<IndexedMesh, LoadErrorKind> {
    let mut reader = Reader::new(BufReader::new(Cursor::new(bytes)));
    let header = Parser::<Ignore>::new().read_header(&mut reader).map_err(parse_err)?;
    // Every entry takes at least a byte (binary) or a line (ascii): a count past the file's
    // length is a broken header, and reading it would loop that many times (a 243-byte file
    // declaring 7 × 10¹⁴ entries of an element without properties ran for ever).
    if let Some((name, el)) = header.elements.iter().find(|(_, el)| el.count > bytes.len()) {
        return Err(LoadErrorKind::Malformed {
            format: "PLY",
            line: None,
            message: format!(
                "element {name} declares {} entries, more than the {}-byte file can hold",
                el.count,
                bytes.len()
            ),
        });
    }
    let mut out = IndexedMesh::default();
    let mut faces: Vec<IndexList> = Vec::new();
    let mut strips: Vec<IndexList> = Vec::new();
    let mut saw_vertex = false;
    for (_, el) in &header.elements {
        match el.name.as_str() {
            "vertex" => {
                for axis in ["x", "y", "z"] {
                    if !el.properties.contains_key(axis) {
                        return Err(LoadErrorKind::Malformed {
                            format: "PLY",
                            line: None,
                            message: format!("vertex element has no {axis} property"),
                        });
                    }
                }
                let has = |names: &[&str]| names.iter().any(|n| el.properties.contains_key(*n));
                let has_n = has(&["nx"]) && has(&["ny"]) && has(&["nz"]);
                let has_uv = has(&["u", "s", "texture_u", "texture_s"]) && has(&["v", "t", "texture_v", "texture_t"]);
                let verts =
                    Parser::<Vertex>::new().read_payload_for_element(&mut reader, el, &header).map_err(parse_err)?;
                let points: Vec<[f64; 3]> = verts.iter().map(|v| v.p).collect();
                (out.positions, out.origin) = crate::mesh::origin::relative_positions(&points);
                if has_n {
                    out.normals = verts.iter().map(|v| v.n.map(|c| c as f32)).collect();
                }
                if has_uv {
                    out.uvs = verts.iter().map(|v| super::uv_origin::from_bottom_left(v.uv)).collect();
                }
                if has_colour(el) {
                    let components = if el.properties.keys().any(|k| channel(k) == Some(3)) { 4 } else { 3 };
                    let values = verts.iter().flat_map(|v| v.rgba[..components].to_vec()).collect();
                    out.attributes.push(VertexAttribute::new("COLOR_0", components, values));
                }
                saw_vertex = true;
            }
            "face" => {
                faces =
                    Parser::<IndexList>::new().read_payload_for_element(&mut reader, el, &header).map_err(parse_err)?
            }
            "tristrips" => {
                strips =
                    Parser::<IndexList>::new().read_payload_for_element(&mut reader, el, &header).map_err(parse_err)?
            }
            _ => {
                Parser::<Ignore>::new().read_payload_for_element(&mut reader, el, &header).map_err(parse_err)?;
            }
        }
    }
    if !saw_vertex {
        return Err(LoadErrorKind::Malformed { format: "PLY", line: None, message: "no vertex element".into() });
    }
    // Corner texture coordinates count where every face has two per corner and the vertices
    // have none of their own; texture numbers where every face has one.
    let wedged = !faces.is_empty()
        && out.uvs.is_empty()
        && faces.iter().all(|f| f.1.as_ref().is_some_and(|t| t.len() == 2 * f.0.len()));
    let numbered = wedged && strips.is_empty() && faces.iter().all(|f| f.2.is_some());
    out.not_kept = not_kept(&header, wedged, numbered);
    let nv = out.positions.len();
    let mut wedges = wedged.then(|| super::ply_wedges::Wedges::new(&mut out));
    // Each triangle's texture number, where the faces have them.
    let mut numbers = Vec::new();
    let mut poly = Vec::new();
    let mut tri = super::polygon::Triangulator::default();
    for (fi, f) in faces.iter().enumerate() {
        poly.clear();
        for (c, &i) in f.0.iter().enumerate() {
            let v = super::check_index(i, nv, fi, c)?;
            poly.push(match (&mut wedges, &f.1) {
                (Some(w), Some(uv)) => {
                    let uv = [uv[2 * c], uv[2 * c + 1]].map(f64::from);
                    w.vertex(&mut out, v, super::uv_origin::from_bottom_left(uv))
                }
                _ => v,
            });
        }
        tri.face(fi, &poly, |i| out.positions[i as usize].map(f64::from), &mut out.triangles);
        if numbered {
            numbers.resize(out.triangles.len(), f.2.unwrap_or(0));
        }
    }
    tri.push_repairs_into(&mut out.load_repairs);
    let textures = texture_files(&header);
    if numbered {
        super::ply_wedges::primitives(&mut out, &numbers, &textures);
    } else if !out.uvs.is_empty() && textures.len() == 1 {
        // One texture, over texture coordinates per corner or per vertex.
        out.primitives = vec![crate::mesh::Primitive { name: textures[0].clone(), ..Default::default() }];
    }
    // The textures as materials, one per primitive, for a GLB output.
    if let (Some(base), true) = (base, !out.uvs.is_empty() && !out.primitives.is_empty()) {
        let names: Vec<String> = out.primitives.iter().map(|p| p.name.clone()).collect();
        let (materials, lost) = super::obj_materials::texture_materials(&names, base);
        out.primitives.iter_mut().enumerate().for_each(|(k, p)| p.material = Some(k));
        out.gltf_materials = Some(std::sync::Arc::new(materials));
        if !lost.is_empty() {
            out.not_kept.push(NotKept::new(NotKeptKind::MaterialMaps, lost.len(), lost.join("; ")));
        }
    }
    for (si, s) in strips.iter().enumerate() {
        strip_triangles(&s.0, nv, si, &mut out.triangles)?;
    }
    Ok(out)
}

/// Vertex and face properties that are read past (face colours, confidence, flags, ...) and
/// elements that are skipped, as the file names them.
fn not_kept(header: &ply_rs_bw::ply::Header, wedged: bool, numbered: bool) -> Vec<NotKept> {
    const VERTEX: [&str; 14] =
        ["x", "y", "z", "nx", "ny", "nz", "u", "v", "s", "t", "texture_u", "texture_v", "texture_s", "texture_t"];
    let mut properties = Vec::new();
    let mut elements = Vec::new();
    for (name, el) in &header.elements {
        match name.as_str() {
            "vertex" => {
                let colour = has_colour(el);
                let read = |k: &str| VERTEX.contains(&k) || colour && channel(k).is_some();
                properties.extend(el.properties.keys().filter(|k| !read(k)).cloned())
            }
            "face" | "tristrips" => properties.extend(
                el.properties
                    .keys()
                    .filter(|k| k.as_str() != "vertex_indices" && k.as_str() != "vertex_index")
                    .filter(|k| !(name == "face" && (wedged && *k == "texcoord" || numbered && *k == "texnumber")))
                    .map(|k| format!("{name} {k}")),
            ),
            _ => elements.push(name.clone()),
        }
    }
    let mut out = Vec::new();
    if !properties.is_empty() {
        out.push(NotKept::new(NotKeptKind::OtherAttributes, 1, properties.join(", ")));
    }
    if !elements.is_empty() {
        out.push(NotKept::new(NotKeptKind::OtherElements, elements.len(), elements.join(", ")));
    }
    out
}

/// The texture files a header names (`comment TextureFile NAME`, as MeshLab writes them), in
/// order: what a face's `texnumber` counts.
fn texture_files(header: &ply_rs_bw::ply::Header) -> Vec<String> {
    let files = header.comments.iter().filter_map(|c| c.trim().strip_prefix("TextureFile"));
    files.map(|name| name.trim().to_string()).collect()
}

/// Expands one `tristrips` list: runs separated by -1; in each run, triangle k is
/// (a, b, c) for even k and (b, a, c) for odd k, so all keep the strip's winding.
/// Triangles repeating an index (strip joins) are left for the repair pass to drop.
fn strip_triangles(list: &[i64], nv: usize, strip: usize, out: &mut Vec<[u32; 3]>) -> Result<(), LoadErrorKind> {
    for run in list.split(|&i| i < 0) {
        let mut ids = Vec::with_capacity(run.len());
        for (c, &i) in run.iter().enumerate() {
            ids.push(super::check_index(i, nv, strip, c)?);
        }
        for k in 0..ids.len().saturating_sub(2) {
            let (a, b, c) = (ids[k], ids[k + 1], ids[k + 2]);
            if a == b || b == c || a == c {
                continue; // zero-area joins inside strips are not triangles of the surface
            }
            out.push(if k % 2 == 0 { [a, b, c] } else { [b, a, c] });
        }
    }
    Ok(())
}
