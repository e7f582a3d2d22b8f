//! Text files as real exporters write them (`src/io/text.rs`): a UTF-8 byte-order mark,
//! UTF-16, Latin-1 names, a nameless `usemtl`, ascii STL headers stl_io alone would take for
//! binary and a binary header it would take for ascii; glTF 1.0 refused by name instead of
//! as a schema error; and the PLY header lines Blender 2.4x wrote bare.

use base64::Engine;
use dynlod::io::{self, Format};
use dynlod::mesh::{BuildOptions, Location, Mesh, RepairKind};
use dynlod::{IndexedMesh, LoadErrorKind};

const BOM: &[u8] = b"\xEF\xBB\xBF";

fn load(bytes: &[u8], f: Format) -> Result<IndexedMesh, LoadErrorKind> {
    io::load_bytes(bytes, f, None)
}

fn with_bom(text: &str) -> Vec<u8> {
    [BOM, text.as_bytes()].concat()
}

fn utf16(text: &str, big_endian: bool) -> Vec<u8> {
    let units = text.encode_utf16();
    let mut out = if big_endian { vec![0xFE, 0xFF] } else { vec![0xFF, 0xFE] };
    out.extend(units.flat_map(|u| if big_endian { u.to_be_bytes() } else { u.to_le_bytes() }));
    out
}

fn latin1(text: &str) -> Vec<u8> {
    text.chars().map(|c| u8::try_from(u32::from(c)).expect("a Latin-1 character")).collect()
}

/// The first vertex on the first line, where a mark read as text would hide it.
const OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\no Terraindæk\nusemtl Træ\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";

#[test]
fn obj_in_any_encoding_reads_as_in_utf8() {
    let plain = load(OBJ.as_bytes(), Format::Obj).unwrap();
    assert_eq!((plain.positions.len(), plain.triangles.len()), (4, 4));
    assert_eq!(plain.primitives[0].name, "Terraindæk");
    for (name, bytes) in [
        ("bom", with_bom(OBJ)),
        ("utf-16le", utf16(OBJ, false)),
        ("utf-16be", utf16(OBJ, true)),
        ("latin-1", latin1(OBJ)),
    ] {
        let m = load(&bytes, Format::Obj).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((&m.positions, &m.triangles), (&plain.positions, &plain.triangles), "{name}");
        assert_eq!(m.primitives[0].name, "Terraindæk", "{name}");
    }
    // An error still names the file's line.
    let e = load(&latin1("# Æble\nv 0 0 0\nv 1 x 0\n"), Format::Obj).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { line: Some(3), .. }), "{e}");
}

/// Blender 2.6 wrote `usemtl ` for faces without a material (assimp's `empty_mat.obj`);
/// tobj refuses it. No material is read, so the line is passed over.
#[test]
fn a_usemtl_without_a_name_is_passed_over() {
    for line in ["usemtl ", "usemtl", "usemtl\t  ", "  usemtl\tafter_a_tab"] {
        let obj = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\n{line}\nf 1 2 3\nv 0 0 x\n");
        // The bad number two lines on is still found on its own line.
        let e = load(obj.as_bytes(), Format::Obj).unwrap_err();
        assert!(matches!(e, LoadErrorKind::Malformed { line: Some(6), .. }), "{line:?}: {e}");
        let m = load(obj.rsplit_once("v 0 0 x").unwrap().0.as_bytes(), Format::Obj).unwrap();
        assert_eq!(m.triangles.len(), 1, "{line:?}");
    }
}

#[test]
fn ply_off_and_stl_after_a_byte_order_mark() {
    let ply = "ply\nformat ascii 1.0\ncomment Æble\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let off = "OFF\n# Æble\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
    for (format, text) in [(Format::Ply, ply), (Format::Off, off), (Format::Stl, stl)] {
        let plain = load(text.as_bytes(), format).unwrap();
        let m = load(&with_bom(text), format).unwrap_or_else(|e| panic!("{format:?}: {e}"));
        assert_eq!((&m.positions, &m.triangles), (&plain.positions, &plain.triangles), "{format:?}");
        assert_eq!(m.triangles.len(), 1, "{format:?}");
    }
    // OFF and PLY comments in Latin-1, as well; a binary PLY's body left as it is.
    assert_eq!(load(&latin1(off), Format::Off).unwrap().triangles.len(), 1);
    assert_eq!(load(&latin1(ply), Format::Ply).unwrap().triangles.len(), 1);
    let head = latin1(&ply.replace("ascii", "binary_little_endian").replace("int vertex", "uint vertex"));
    let head = &head[..head.windows(11).position(|w| w == b"end_header\n").unwrap() + 11];
    let mut binary = head.to_vec();
    // Its body is not UTF-8 either (1.0 is 00 00 80 3F) and must come through unchanged.
    binary.extend([0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|c| c.to_le_bytes()));
    binary.push(3);
    binary.extend([0u32, 1, 2].iter().flat_map(|i| i.to_le_bytes()));
    let m = load(&binary, Format::Ply).unwrap();
    assert_eq!((m.positions, m.triangles), (vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![[0, 1, 2]]));
}

/// stl_io reads a file as ascii only after `solid ` exactly; these went to its binary reader
/// and came back "truncated" (assimp's `sphereWithHole.stl` has a tab there).
#[test]
fn ascii_stl_with_a_nameless_or_tabbed_solid_line() {
    let body =
        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
    for head in ["solid\n", "solid\r\n", "solid\tsphere\n", "  solid x\n", "solid x\n", "\n\nsolid x\n"] {
        let m = load(format!("{head}{body}").as_bytes(), Format::Stl).unwrap_or_else(|e| panic!("{head:?}: {e}"));
        assert_eq!(m.triangles.len(), 1, "{head:?}");
    }
    // Keywords in capitals, as some CAD tools write them (read as a binary header before).
    let upper = format!("SOLID PART\n{}", body.to_uppercase());
    assert_eq!(load(upper.as_bytes(), Format::Stl).unwrap().triangles.len(), 1);
    let mixed = format!("Solid Part\n{}", body.replace("vertex 1 0 0", "VERTEX 1.0E+00 0 0"));
    assert_eq!(load(mixed.as_bytes(), Format::Stl).unwrap().positions.len(), 3);
    // Capitals only past a lower-case `solid` line (refused before).
    let later = format!("solid part\n{}", body.replace("outer loop", "Outer Loop").replace("endsolid", "ENDSOLID"));
    assert_eq!(load(later.as_bytes(), Format::Stl).unwrap().triangles.len(), 1);
    // A Latin-1 solid name (stl_io refused the file as not UTF-8, then as a short binary).
    let m = load(&latin1(&format!("solid Æble\n{}", body.replace("endsolid", "endsolid Æble"))), Format::Stl).unwrap();
    assert_eq!(m.triangles.len(), 1);
    // A binary file whose header starts with a line `solid ...` (OpenSCAD's
    // `import_bin_solid.stl`; SolidWorks writes those too) stays binary.
    let mut bin = b"solid by a CAD tool\n".to_vec();
    bin.resize(80, b' ');
    bin.extend(1u32.to_le_bytes());
    for v in [[0f32, 0., 1.], [0., 0., 0.], [2., 0., 0.], [0., 2., 0.]] {
        bin.extend(v.iter().flat_map(|c| c.to_le_bytes()));
    }
    bin.extend([0, 0]);
    let m = load(&bin, Format::Stl).unwrap();
    assert_eq!(m.positions.iter().map(|p| p[0] + p[1]).sum::<f32>(), 4.0);
}

fn triangle_gltf(version: &str) -> String {
    let bin: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|c| c.to_le_bytes()).collect();
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    format!(
        r#"{{"asset":{{"version":{version}}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{data}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}}"#
    )
}

#[test]
fn gltf_after_a_byte_order_mark_and_gltf_1_refused_by_name() {
    let doc = triangle_gltf(r#""2.0""#);
    assert_eq!(load(doc.as_bytes(), Format::Gltf).unwrap().triangles.len(), 1);
    assert_eq!(load(&with_bom(&doc), Format::Gltf).unwrap().triangles.len(), 1);
    // glTF 1.0: said to be 1.0 (its objects keyed by name, or its version), not a schema error.
    let keyed = r#"{"asset":{"version":"1.0"},"accessors":{"a":{}},"meshes":{"m":{}}}"#;
    for doc in [keyed.to_string(), triangle_gltf(r#""1.0""#), triangle_gltf("1")] {
        let e = load(doc.as_bytes(), Format::Gltf).unwrap_err();
        assert!(matches!(e, LoadErrorKind::Unsupported { .. }) && e.to_string().contains("glTF 1.0"), "{e}");
    }
    // Binary glTF 1.0 (KHR_binary_glTF): version 1 in the header.
    let mut glb = b"glTF".to_vec();
    glb.extend([1u32, 20, 0, 0].iter().flat_map(|w| w.to_le_bytes()));
    let e = load(&glb, Format::Glb).unwrap_err();
    assert!(e.to_string().contains("glTF 1.0"), "{e}");
}

/// Blender 2.4x wrote its credit line into the PLY header bare, with no `comment` before it
/// (assimp's `Wuson.ply`); ply-rs refuses it, and a blank header line. Both are read as
/// comments and recorded; a bare line among the elements, where it could be a misspelt
/// `property`, is refused by its line.
#[test]
fn ply_header_lines_that_are_no_keyword() {
    let clean = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let blender = clean.replace("1.0\n", "1.0\nCreated by Blender3D 247 - www.blender.org, source file: \n\n");
    let plain = load(clean.as_bytes(), Format::Ply).unwrap();
    assert!(plain.load_repairs.is_empty());
    let binary_body = |head: &str| {
        let head = head.replace("ascii", "binary_little_endian");
        let mut file = head.as_bytes()[..head.find("end_header\n").unwrap() + 11].to_vec();
        file.extend([0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|c| c.to_le_bytes()));
        file.push(3);
        file.extend([0i32, 1, 2].iter().flat_map(|i| i.to_le_bytes()));
        file
    };
    for (name, file) in [("ascii", blender.clone().into_bytes()), ("binary", binary_body(&blender))] {
        let m = load(&file, Format::Ply).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((&m.positions, &m.triangles), (&plain.positions, &plain.triangles), "{name}");
        let r = &m.load_repairs;
        assert_eq!(r.len(), 1, "{name}: {r:?}");
        assert_eq!(
            (r[0].kind, r[0].count, &r[0].examples),
            (RepairKind::CommentedHeaderLines, 2, &vec![Location::Line(3), Location::Line(4)])
        );
        assert!(Mesh::build(&m, BuildOptions::default().strict(true)).is_err(), "{name}: strict mode");
    }
    assert_eq!(load(&binary_body(clean), Format::Ply).unwrap().triangles, plain.triangles);
    // Among the elements: refused, by its line, in one line of text.
    let misspelt = clean.replace("property float y", "proprety float y");
    let e = load(misspelt.as_bytes(), Format::Ply).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { line: Some(5), .. }), "{e}");
    assert!(e.to_string().contains("`proprety float y` is not a header line"), "{e}");
    // A body line that does not fit its element: ply-rs's error, with the line it read.
    let short = clean.replace("3 0 1 2", "3 0 1");
    let e = load(short.as_bytes(), Format::Ply).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { line: Some(13), .. }), "{e}");
    assert!(!e.to_string().contains('\n') && e.to_string().contains("the line reads `3 0 1`"), "{e}");
}
