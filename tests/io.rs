//! Every loader on small inline files, malformed files to typed errors, writers round-trip.

use base64::Engine;
use dynlod::io::{self, Format, WriteFormat};
use dynlod::mesh::{Location, RepairKind};
use dynlod::{procedural, BuildOptions, IndexedMesh, LoadErrorKind, Mesh, MeshError};

fn load(text: &[u8], f: Format) -> Result<IndexedMesh, LoadErrorKind> {
    io::load_bytes(text, f, None)
}

#[test]
fn obj_polygons_are_fan_triangulated_and_objects_become_primitives() {
    let obj = b"# quad and triangle\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\no second\nv 2 0 0\nf -4 -3 -1\n";
    let m = load(obj, Format::Obj).unwrap();
    assert_eq!(m.triangles.len(), 3);
    assert_eq!(m.primitives.len(), 2);
    assert_eq!(m.primitives[0].name, "first");
    assert_eq!(m.triangle_primitive, vec![0, 0, 1]);
    let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
    mesh.topology.validate().unwrap();
}

#[test]
fn obj_errors_name_the_line() {
    let e = load(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n", Format::Obj).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { format: "OBJ", line: Some(5), .. }), "{e}");
    let e = load(b"v 0 0 0\nv 1 x 0\n", Format::Obj).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { line: Some(2), .. }), "{e}");
    let e = load(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 0 x\nf 1/1 2/1 3/1\n", Format::Obj).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { line: Some(5), .. }), "{e}");
}

/// `vt u`, a 1D texture coordinate (the OBJ spec makes v 0), was refused by tobj without a
/// line; it reads as (u, 0), which is glTF's (u, 1): the mesh holds v from the image's top.
#[test]
fn obj_one_component_texture_coordinates_read_with_v_zero() {
    let m = load(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25\nvt 1\r\nvt 0.5 0.5\nf 1/1 2/2 3/3\n", Format::Obj).unwrap();
    assert_eq!(m.uvs, [[0.25, 1.0], [1.0, 1.0], [0.5, 0.5]]);
}

/// tobj reads a texture or normal index of 0, or a relative one reaching one before the
/// first, as "none" and drops the attribute without a word; far out of range, its index
/// arithmetic wraps. Each is refused with its line, as a position index is.
#[test]
fn obj_attribute_references_that_do_not_exist_are_refused() {
    let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nvn 0 0 1\n";
    for (face, what) in [
        ("f 1/0 2/1 3/1", "texcoord"),
        ("f 1/-2 2/-2 3/-2", "texcoord"),
        ("f 1/1 2/1 3/9223372036854775807", "texcoord"),
        ("f 1/1/1 2/1/1 3/1/0", "normal"),
        ("f 1//-2 2//1 3//1", "normal"),
        ("f 1/1/1 2/1/1 3/1/-9223372036854775808", "normal"),
        ("f 0 2 3", "vertex"),
    ] {
        let e = load(format!("{head}{face}\n").as_bytes(), Format::Obj).unwrap_err();
        assert!(matches!(e, LoadErrorKind::Malformed { format: "OBJ", line: Some(6), .. }), "{face}: {e}");
        assert!(e.to_string().contains(what), "{face}: {e}");
    }
    // Relative references within range, and attributes left out on purpose, still load.
    for face in ["f -3/-1/-1 -2/-1/-1 -1/-1/-1", "f 1//1 2//1 3//1", "f 1 2 3"] {
        let m = load(format!("{head}{face}\n").as_bytes(), Format::Obj).unwrap_or_else(|e| panic!("{face}: {e}"));
        assert_eq!(m.triangles.len(), 1, "{face}");
    }
    let m = load(format!("{head}f -3/-1 -2/-1 -1/-1\n").as_bytes(), Format::Obj).unwrap();
    assert_eq!(m.uvs, vec![[0.25, 0.25]; 3], "vt 0.25 0.75, v from the image's top");
    // tobj resolves an object's faces when the object ends: a face may name vertices below it.
    let m = load(format!("f 1/1 2/1 3/1\n{head}").as_bytes(), Format::Obj).unwrap();
    assert_eq!((m.triangles.len(), m.uvs.len()), (1, 3));
}

/// A textured PLY as MeshLab writes it: texture coordinates per face corner (`texcoord`) and
/// a texture number per face (`texnumber`, counting the header's `TextureFile` comments).
/// Both were read past; now a vertex whose corners agree keeps its number, one whose corners
/// disagree gets a copy (its colour too) after the file's vertices, welded back by position
/// with the seam on its wedges, and the faces fall into one primitive per texture.
#[test]
fn ply_corner_texture_coordinates_and_texture_numbers() {
    let head = |faces: &str| {
        format!(
            "ply\nformat {{}} 1.0\ncomment TextureFile a.png\ncomment TextureFile b.png\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\nproperty list uchar int vertex_indices\n{faces}end_header\n"
        )
    };
    let vertices = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
    let ascii = |faces: &str, rows: [&str; 2]| {
        let mut s = head(faces).replace("{}", "ascii");
        for (k, v) in vertices.iter().enumerate() {
            s += &format!("{} {} {} {} 0 0\n", v[0], v[1], v[2], 50 * k);
        }
        s + rows[0] + "\n" + rows[1] + "\n"
    };
    let texcoord = "property list uchar float texcoord\nproperty int texnumber\n";
    // Vertex 0 at (0, 0) in the first face and (0.5, 0.5) in the second: a seam.
    let rows = ["3 0 1 2 6 0 0 1 0 1 1 1", "3 0 2 3 6 0.5 0.5 1 1 0 1 0"];
    let m = load(ascii(texcoord, rows).as_bytes(), Format::Ply).unwrap();
    assert_eq!(m.positions, [vertices.as_slice(), &[vertices[0]]].concat());
    assert_eq!(m.uvs, [[0., 1.], [1., 1.], [1., 0.], [0., 0.], [0.5, 0.5]], "v from the image's top");
    assert_eq!(m.triangles, [[0, 1, 2], [4, 2, 3]]);
    let colour = &m.attributes.iter().find(|a| a.semantic == "COLOR_0").unwrap();
    assert_eq!(colour.get(4), colour.get(0), "the copy keeps vertex 0's colour");
    let names: Vec<&str> = m.primitives.iter().map(|p| p.name.as_str()).collect();
    assert_eq!((names, &m.triangle_primitive), (vec!["a.png", "b.png"], &vec![1, 0]));
    assert!(m.not_kept.is_empty(), "{:?}", m.not_kept);
    let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
    let info = dynlod::info::MeshInfo::new(&mesh);
    assert_eq!((mesh.positions.len(), info.seam_edges), (4, 1), "welded back, the seam kept");
    // Binary, the same.
    let mut bin = head(texcoord).replace("{}", "binary_little_endian").into_bytes();
    for (k, v) in vertices.iter().enumerate() {
        bin.extend(v.iter().flat_map(|c| c.to_le_bytes()));
        bin.extend([50 * k as u8, 0, 0]);
    }
    for row in rows {
        let w: Vec<f32> = row.split(' ').map(|w| w.parse().unwrap()).collect();
        bin.push(3);
        bin.extend(w[1..4].iter().flat_map(|&i| (i as i32).to_le_bytes()));
        bin.push(6);
        bin.extend(w[5..11].iter().flat_map(|c| c.to_le_bytes()));
        bin.extend((w[11] as i32).to_le_bytes());
    }
    let b = load(&bin, Format::Ply).unwrap();
    assert_eq!((&b.positions, &b.uvs, &b.triangles), (&m.positions, &m.uvs, &m.triangles));
    assert_eq!(b.triangle_primitive, m.triangle_primitive);
    // Read from a file, the textures beside it become the primitives' materials (for a GLB
    // output); one not there is listed.
    let dir = tempfile::tempdir().unwrap();
    let png = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/textured_quad_wood.png")).unwrap();
    std::fs::write(dir.path().join("a.png"), &png).unwrap();
    std::fs::write(dir.path().join("quad.ply"), ascii(texcoord, rows)).unwrap();
    let m = io::load(dir.path().join("quad.ply")).unwrap();
    let mats = m.gltf_materials.as_ref().expect("materials");
    assert_eq!(m.primitives.iter().map(|p| p.material).collect::<Vec<_>>(), [Some(0), Some(1)]);
    assert_eq!(mats.materials[0]["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
    assert!(mats.materials[1]["pbrMetallicRoughness"].get("baseColorTexture").is_none());
    assert_eq!((mats.images.len(), mats.images[0].bytes.as_ref()), (1, Some(&png)));
    assert_eq!(m.not_kept[0].detail, "TextureFile b.png (not found)");
    io::save(dir.path().join("quad.glb"), &m).unwrap();
    let back = io::load(dir.path().join("quad.glb")).unwrap();
    assert_eq!(back.gltf_materials.unwrap().images[0].bytes.as_ref(), Some(&png));
    // Corners that agree: no copy, one primitive. A list of the wrong length: read past, as before.
    let same = ["3 0 1 2 6 0 0 1 0 1 1 0", "3 0 2 3 6 0 0 1 1 0 1 0"];
    let m = load(ascii(texcoord, same).as_bytes(), Format::Ply).unwrap();
    assert_eq!((m.positions.len(), m.primitives.len(), m.primitives[0].name.as_str()), (4, 1, "a.png"));
    let short = ["3 0 1 2 4 0 0 1 0 0", "3 0 2 3 6 0 0 1 1 0 1 0"];
    let m = load(ascii(texcoord, short).as_bytes(), Format::Ply).unwrap();
    assert!(m.uvs.is_empty());
    assert_eq!(m.not_kept[0].detail, "face texcoord, face texnumber");
}

const PLY_ASCII: &str = "ply\nformat ascii 1.0\ncomment test\nelement vertex 4\nproperty float x\nproperty float y\nproperty double z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\nproperty uchar red\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3 255\n0 1\n";

#[test]
fn ply_ascii_reads_any_numeric_type_normals_uvs_and_skips_other_elements() {
    let m = load(PLY_ASCII.as_bytes(), Format::Ply).unwrap();
    assert_eq!(m.positions.len(), 4);
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(m.normals[2], [0.0, 0.0, 1.0]);
    assert_eq!(m.uvs[1], [1.0, 1.0], "s t = 1 0: the image's bottom right, in glTF's terms");
    assert_eq!(m.uvs[2], [1.0, 0.0]);
}

/// An ascii PLY whose elements spread over lines (a wrapped face list) or share one (two
/// vertices a line), as rply and MeshLab read them: the same mesh as the tidy file, with the
/// lines recorded as a repair (so `--strict` refuses it). Words that do not fit the header
/// keep ply-rs's error and its line.
#[test]
fn ply_ascii_elements_over_lines_read_as_words() {
    let tidy = load(PLY_ASCII.as_bytes(), Format::Ply).unwrap();
    let body = "0 0 0 0 0 1 0 0 1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0\n0 0 1 0 1\n4 0 1 2\n3 255\n0 1\n";
    let wrapped = PLY_ASCII.replace(PLY_ASCII.split_once("end_header\n").unwrap().1, body);
    let m = load(wrapped.as_bytes(), Format::Ply).unwrap();
    assert_eq!(
        (&m.positions, &m.triangles, &m.normals, &m.uvs),
        (&tidy.positions, &tidy.triangles, &tidy.normals, &tidy.uvs)
    );
    let lines: Vec<(RepairKind, usize, &[Location])> =
        m.load_repairs.iter().map(|r| (r.kind, r.count, &r.examples[..])).collect();
    let at = [Location::Line(20), Location::Line(22), Location::Line(24)];
    assert_eq!(lines, [(RepairKind::RewrappedAsciiElements, 3, &at[..])]);
    assert!(Mesh::build(&m, BuildOptions::default().strict(true)).is_err(), "strict mode");
    // One word short: ply-rs's error, at the first line that did not hold its element.
    let short = wrapped.replace("3 255\n", "3\n");
    let e = load(short.as_bytes(), Format::Ply).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { line: Some(22), .. }), "{e:?}");
    // A face naming a vertex past the last: named by its face, as in a tidy file.
    let e = load(wrapped.replace("4 0 1 2\n", "4 0 1 7\n").as_bytes(), Format::Ply).unwrap_err();
    assert!(e.to_string().contains("face 0") && e.to_string().contains('7'), "{e}");
}

/// Words ply-rs passes over without failing: past an element's properties on its line, and
/// lines past the last element. They are recorded (so `--strict` refuses the file), not
/// dropped without a word; where the body read as words fits the header exactly, it is
/// read that way, as ply-rs would otherwise misread it.
#[test]
fn ply_ascii_words_past_an_element_are_recorded() {
    let tidy = load(PLY_ASCII.as_bytes(), Format::Ply).unwrap();
    assert!(tidy.load_repairs.is_empty());
    let repairs = |m: &IndexedMesh| -> Vec<(RepairKind, usize, Vec<Location>)> {
        m.load_repairs.iter().map(|r| (r.kind, r.count, r.examples.clone())).collect()
    };
    // A ninth number on vertex 1's line (21), and a line past the edge (26).
    let extra = PLY_ASCII.replace("1 0 0 0 0 1 1 0\n", "1 0 0 0 0 1 1 0 7\n") + "9 9\n";
    let m = load(extra.as_bytes(), Format::Ply).unwrap();
    assert_eq!((&m.positions, &m.triangles, &m.uvs), (&tidy.positions, &tidy.triangles, &tidy.uvs));
    assert_eq!(repairs(&m), [(RepairKind::IgnoredExtraWords, 2, vec![Location::Line(21), Location::Line(26)])]);
    assert!(Mesh::build(&m, BuildOptions::default().strict(true)).is_err(), "strict mode");
    // Blank lines at the end are nothing.
    assert!(load(format!("{PLY_ASCII}\n \n").as_bytes(), Format::Ply).unwrap().load_repairs.is_empty());
    // Two faces, the second's length at the end of the first's line: ply-rs reads the first,
    // passes over that 3, and reads `0 2 3` as an empty face; as words, both faces are there.
    let two = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
               element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
               3 0 1 2 3\n0 2 3\n";
    let m = load(two.as_bytes(), Format::Ply).unwrap();
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(repairs(&m), [(RepairKind::RewrappedAsciiElements, 1, vec![Location::Line(14)])]);
}

#[test]
fn ply_tristrips_keep_one_winding_and_skip_joins() {
    // One strip 0 1 2 3, a restart, then 2 3 4 (the grid's second row written as a strip).
    let ply = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n0 1 0\n1 0 0\n1 1 0\n2 0 0\n2 1 0\n9 0 2 1 3 -1 2 4 3 5\n";
    let m = load(ply.as_bytes(), Format::Ply).unwrap();
    assert_eq!(m.triangles, vec![[0, 2, 1], [1, 2, 3], [2, 4, 3], [3, 4, 5]]);
    let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
    assert!(mesh.repairs.is_empty(), "strip winding must already be consistent: {:?}", mesh.repairs);
}

#[test]
fn ply_binary_big_endian_and_errors() {
    let mut b = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        for c in p {
            b.extend(c.to_be_bytes());
        }
    }
    let mut ok = b.clone();
    ok.push(3);
    for i in [0u32, 1, 2] {
        ok.extend(i.to_be_bytes());
    }
    assert_eq!(load(&ok, Format::Ply).unwrap().triangles, vec![[0, 1, 2]]);
    // Truncated in the face list.
    let e = load(&ok[..ok.len() - 2], Format::Ply).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Truncated { format: "PLY", .. }), "{e}");
    // Index out of range names the face and corner.
    let mut bad = b.clone();
    bad.push(3);
    for i in [0u32, 1, 7] {
        bad.extend(i.to_be_bytes());
    }
    let e = load(&bad, Format::Ply).unwrap_err();
    assert!(
        matches!(e, LoadErrorKind::Mesh(MeshError::IndexOutOfRange { face: 0, corner: 2, index: 7, vertex_count: 3 })),
        "{e}"
    );
}

/// A header count no file of its length can hold is refused at once, by name (found by the
/// load_ply fuzz target: an element without properties declaring 7 × 10¹⁴ entries made the
/// reader loop for ever).
#[test]
fn ply_counts_past_the_file_length_are_refused_not_read() {
    let head = "ply\nformat binary_little_endian 1.0\nelement junk 712472712472614\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
    // On a thread, so that a reader that loops fails the test instead of hanging it.
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(load(head.as_bytes(), Format::Ply).map(|_| ()));
    });
    let e = rx.recv_timeout(std::time::Duration::from_secs(20)).expect("answered at once").unwrap_err();
    assert!(e.to_string().contains("element junk declares 712472712472614 entries"), "{e}");
    let e = load(b"ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", Format::Ply).unwrap_err();
    assert!(e.to_string().contains("element vertex declares 4000000000 entries"), "{e}");
}

#[test]
fn off_with_comments_colours_and_counts_on_the_header_line() {
    let off = "COFF 4 2 0 # counts here\n# a comment\n0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n1 1 0 255 0 0 255\n0 1 0 255 0 0 255\n3 0 1 2 1 0 0\n3 0 2 3\n";
    let m = load(off.as_bytes(), Format::Off).unwrap();
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    let e = load(b"OFF\n3 1 0\n0 0 0\n1 0 0\n", Format::Off).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Truncated { format: "OFF", .. }), "{e}");
    let e = load(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n", Format::Off).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { line: Some(5), .. }), "{e}");
    let e = load(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", Format::Off).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Mesh(MeshError::IndexOutOfRange { face: 0, corner: 2, index: 3, .. })), "{e}");
}

fn binary_stl(tris: &[[[f32; 3]; 3]], count: u32) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend(count.to_le_bytes());
    for t in tris {
        b.extend([0u8; 12]);
        for p in t {
            for c in p {
                b.extend(c.to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

#[test]
fn stl_ascii_and_binary_weld_shared_corners() {
    let ascii = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
    let a = load(ascii.as_bytes(), Format::Stl).unwrap();
    assert_eq!((a.positions.len(), a.triangles.len()), (4, 2));
    let tris = [[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.]], [[0., 0., 0.], [1., 1., 0.], [0., 1., 0.]]];
    let b = load(&binary_stl(&tris, 2), Format::Stl).unwrap();
    assert_eq!((b.positions.len(), b.triangles.len()), (4, 2));
    assert_eq!(Format::sniff(&binary_stl(&tris, 2)), Some(Format::Stl));
    let e = load(&binary_stl(&tris, 3), Format::Stl).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Truncated { format: "STL", .. }), "{e}");
    // A NaN corner is named by its facet and corner (the file numbers no vertices).
    let mut tris = tris;
    tris[1][2][0] = f32::NAN;
    let e = load(&binary_stl(&tris, 2), Format::Stl).unwrap_err();
    assert!(e.to_string().contains("facet 1 corner 2 has a non-finite coordinate"), "{e}");
}

/// stl_io's ascii errors name no place ("invalid float literal"; OpenSCAD's test files); they
/// are reported at the file's line, with the facet, after blank lines and a tabbed `solid`.
#[test]
fn stl_ascii_errors_name_their_line_and_facet() {
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    let good = format!("\n\nsolid\tpart\n{facet}\n{facet}endsolid\n");
    assert_eq!(load(good.as_bytes(), Format::Stl).unwrap().triangles.len(), 2);
    let cases = [
        (
            "vertex 0 1 0\nendloop\nendfacet\nendsolid",
            "vertex 0 1 NaN\nendloop\nendfacet\nendsolid",
            "`NaN` is not a finite number",
        ),
        (
            "vertex 0 1 0\nendloop\nendfacet\nendsolid",
            "vertex 0 1 blah\nendloop\nendfacet\nendsolid",
            "`blah` is not a number",
        ),
        (
            "endloop\nendfacet\nendsolid",
            "vertex 0 0 10\nendloop\nendfacet\nendsolid",
            "expected `endloop`, found `vertex 0 0 10`",
        ),
    ];
    for (from, to, says) in cases {
        let text = good.replacen(from, to, 1);
        assert_ne!(text, good);
        let e = load(text.as_bytes(), Format::Stl).unwrap_err();
        assert!(matches!(e, LoadErrorKind::Malformed { line: Some(16 | 17), .. }), "{e}");
        assert!(e.to_string().contains(&format!("ascii, facet 1: {says}")), "{e}");
        // In capitals (read in lower case), the error still quotes the file.
        let upper = text.replace("vertex", "VERTEX").replace("endloop", "ENDLOOP");
        let e = load(upper.as_bytes(), Format::Stl).unwrap_err();
        let says = says.replace("vertex", "VERTEX");
        assert!(e.to_string().contains(&format!("ascii, facet 1: {says}")), "{e}");
    }
    let e = load(good.replace("endsolid\n", "").as_bytes(), Format::Stl).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Truncated { .. }) && e.to_string().contains("after 2 facets"), "{e}");
}

/// A glTF with an embedded buffer: a unit quad as a 4-vertex triangle strip, instanced by two
/// nodes (one translated, one mirrored), plus a line primitive that must be skipped.
fn gltf_doc() -> String {
    let mut bin = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]] {
        for c in p {
            bin.extend(c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0,"translation":[10,0,0]}},{{"mesh":0,"scale":[-1,1,1]}}],
        "meshes":[{{"name":"quad","primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"mode":5,"material":0}},{{"attributes":{{"POSITION":0}},"indices":1,"mode":1}}]}}],
        "materials":[{{"name":"m"}}],
        "buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{data}"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":8}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5123,"count":4,"type":"SCALAR"}}]}}"#,
        len = bin.len()
    )
}

#[test]
fn gltf_applies_node_transforms_reads_strips_and_skips_lines() {
    let m = load(gltf_doc().as_bytes(), Format::Gltf).unwrap();
    assert_eq!(m.triangles.len(), 4, "two instances of a 2-triangle strip");
    assert_eq!(m.positions[1], [11.0, 0.0, 0.0], "translation applied");
    assert_eq!(m.positions[5], [-1.0, 0.0, 0.0], "mirror applied");
    assert_eq!(m.primitives.len(), 1, "instances share their primitive");
    assert_eq!(m.primitives[0].material, Some(0));
    let skipped = m.load_repairs.iter().find(|r| r.kind == RepairKind::SkippedNonTrianglePrimitives).unwrap();
    assert_eq!(skipped.count, 2, "the line primitive, once per instance");
    // Both instances face +z: the mirrored one had its winding reversed.
    let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
    for f in &mesh.topology.faces {
        let [a, b, c] = f.map(|v| mesh.positions[v as usize]);
        assert!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0);
    }
}

#[test]
fn gltf_with_only_lines_is_an_unsupported_mode_error() {
    let doc = gltf_doc().replace(r#""mode":5,"material":0"#, r#""mode":3"#);
    let e = load(doc.as_bytes(), Format::Gltf).unwrap_err();
    assert!(matches!(e, LoadErrorKind::UnsupportedPrimitiveMode { mesh: 0, primitive: 0, .. }), "{e}");
}

/// glTF 2.0 requires min and max on every POSITION accessor; exporters that leave them out
/// (assimp's `IncorrectVertexArrays/Cube.gltf`) were refused by gltf-json's validation.
/// Nothing reads them, so such a primitive is read and recorded, in a flattening load and a
/// scene-keeping one alike; any other validation error still refuses the file. A triangle
/// list whose count is no multiple of 3 (the same file) has its one or two corners left
/// over recorded, not dropped without a word.
#[test]
fn gltf_position_bounds_missing_and_indices_left_over_are_recorded() {
    let plain = load(gltf_doc().as_bytes(), Format::Gltf).unwrap();
    let with_bounds = r#""min":[0,0,0],"max":[1,1,0]"#;
    for bounds in
        [r#""min":[0,0,0]"#, r#""max":[1,1,0]"#, r#""min":[0,0],"max":[1,1,0]"#, r#""min":[0,0,0],"max":"x""#, ""]
    {
        let doc = gltf_doc()
            .replace(&format!(",{with_bounds}"), &if bounds.is_empty() { String::new() } else { format!(",{bounds}") });
        assert_ne!(doc, gltf_doc());
        let m = load(doc.as_bytes(), Format::Gltf).unwrap_or_else(|e| panic!("{bounds}: {e}"));
        assert_eq!((&m.positions, &m.triangles), (&plain.positions, &plain.triangles), "{bounds}");
        let r = m.load_repairs.iter().find(|r| r.kind == RepairKind::RecomputedPositionBounds).expect(bounds);
        assert_eq!((r.count, &r.examples), (1, &vec![Location::Primitive { mesh: 0, primitive: 0 }]), "{bounds}");
        assert!(Mesh::build(&m, BuildOptions::default().strict(true)).is_err(), "{bounds}: strict mode");
        let scene = dynlod::io::GltfScene::from_bytes(doc.as_bytes(), None).unwrap();
        let r = &scene.meshes[0].mesh.load_repairs;
        assert_eq!(
            r.iter().map(|r| (r.kind, r.count)).collect::<Vec<_>>(),
            [(RepairKind::RecomputedPositionBounds, 1)]
        );
    }
    assert!(plain.load_repairs.iter().all(|r| r.kind != RepairKind::RecomputedPositionBounds));
    // Other validation errors still refuse: a material index past the materials.
    let e = load(gltf_doc().replace(r#""material":0"#, r#""material":4"#).as_bytes(), Format::Gltf).unwrap_err();
    assert!(e.to_string().contains("material"), "{e}");
    // The strip's four indices as a triangle list: one triangle and a corner left over,
    // recorded once (the line primitive is skipped once per instance, as before).
    let doc = gltf_doc().replace(r#""mode":5,"material":0"#, r#""mode":4,"material":0"#);
    let m = load(doc.as_bytes(), Format::Gltf).unwrap();
    assert_eq!(m.triangles.len(), 2, "one triangle per instance");
    let r = m.load_repairs.iter().find(|r| r.kind == RepairKind::SkippedNonTrianglePrimitives).unwrap();
    let (left_over, line) =
        (Location::Primitive { mesh: 0, primitive: 0 }, Location::Primitive { mesh: 0, primitive: 1 });
    assert_eq!((r.count, &r.examples), (3, &vec![left_over, line, line]));
    let r = &dynlod::io::GltfScene::from_bytes(doc.as_bytes(), None).unwrap().meshes[0].mesh.load_repairs;
    assert_eq!(
        (r[0].kind, r[0].count, &r[0].examples),
        (RepairKind::SkippedNonTrianglePrimitives, 1, &vec![left_over])
    );
}

/// A scene's `nodes` is optional in glTF 2.0 (an empty scene leaves it out); gltf-json
/// requires it, and refused the whole file. An empty default scene reads the first scene that
/// draws something; with none, every mesh once, where it is.
#[test]
fn gltf_scenes_without_nodes() {
    let plain = load(gltf_doc().as_bytes(), Format::Gltf).unwrap();
    let scenes = r#""scenes":[{"nodes":[0,1]}]"#;
    for (with, triangles) in [
        (r#""scenes":[{"nodes":[0,1]},{"name":"empty"}]"#, 4),
        (r#""scenes":[{"name":"empty"},{"nodes":[0,1]}]"#, 4),
        (r#""scenes":[{"name":"empty"}]"#, 2),
        (r#""scenes":[{}]"#, 2),
    ] {
        let doc = gltf_doc().replace(scenes, with);
        assert_ne!(doc, gltf_doc());
        let m = load(doc.as_bytes(), Format::Gltf).unwrap_or_else(|e| panic!("{with}: {e}"));
        assert_eq!(m.triangles.len(), triangles, "{with}");
        if triangles == 4 {
            assert_eq!((&m.positions, &m.triangles), (&plain.positions, &plain.triangles), "{with}");
        } else {
            // The quad once, where its mesh has it: no node's translation or mirror.
            assert_eq!(m.positions, [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]], "{with}");
        }
        let scene = dynlod::io::GltfScene::from_bytes(doc.as_bytes(), None).unwrap_or_else(|e| panic!("{with}: {e}"));
        assert_eq!(scene.meshes[0].mesh.triangles.len(), 2, "{with}");
    }
    // A scene that is not an object is still a schema error.
    let e = load(gltf_doc().replace(scenes, r#""scenes":[7]"#).as_bytes(), Format::Gltf).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Malformed { .. }), "{e}");
}

/// An OBJ's materials (`tests/data/textured_quad.*`: a texture named by a Windows path, a
/// translucent glossy colour with a bump map) become glTF materials, so a GLB output keeps
/// each primitive's colour and texture; what glTF does not carry is listed. Read from memory,
/// with no folder to find the library in, the library is listed as not read.
#[test]
fn obj_materials_reach_a_glb_output() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/textured_quad.obj");
    let m = io::load(&path).unwrap();
    let names: Vec<(&str, Option<usize>)> = m.primitives.iter().map(|p| (p.name.as_str(), p.material)).collect();
    assert_eq!(names, [("quad", Some(0)), ("quad", Some(1))]);
    let mats = m.gltf_materials.as_ref().expect("materials");
    let (wood, glass) = (&mats.materials[0], &mats.materials[1]);
    assert_eq!(wood["name"], "wood");
    assert_eq!(wood["pbrMetallicRoughness"]["baseColorFactor"], serde_json::json!([1.0, 1.0, 1.0, 1.0]));
    assert_eq!(wood["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
    assert_eq!(wood["pbrMetallicRoughness"]["roughnessFactor"], 0.5, "1 - sqrt(250 / 1000)");
    assert_eq!(glass["pbrMetallicRoughness"]["baseColorFactor"], serde_json::json!([0.2, 0.4, 0.6, 0.5]));
    assert_eq!(
        (&glass["alphaMode"], &glass["emissiveFactor"]),
        (&serde_json::json!("BLEND"), &serde_json::json!([0.1, 0.0, 0.0]))
    );
    assert_eq!(glass["pbrMetallicRoughness"]["metallicFactor"], 0.0);
    let png = std::fs::read(path.with_file_name("textured_quad_wood.png")).unwrap();
    assert_eq!((mats.images.len(), mats.images[0].bytes.as_ref()), (1, Some(&png)));
    let lost = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::MaterialMaps).unwrap();
    assert_eq!((lost.count, lost.detail.as_str()), (1, "glass: map_Bump glass_bump.png (not found)"));
    // The GLB holds both materials and the texture's bytes.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("quad.glb");
    io::save(&out, &m).unwrap();
    let back = io::load(&out).unwrap();
    let carried = back.gltf_materials.as_ref().unwrap();
    assert_eq!((carried.materials.as_array().unwrap().len(), carried.images[0].bytes.as_ref()), (2, Some(&png)));
    assert_eq!(back.primitives.iter().map(|p| p.material).collect::<Vec<_>>(), [Some(0), Some(1)]);
    // A library in Latin-1 (3ds Max: `newmtl Træ`), which tobj's own reader refuses; and one
    // that is not there, listed with why.
    let obj = "mtllib lat.mtl\nmtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Tr\u{e6}\nf 1 2 3\n";
    std::fs::write(dir.path().join("lat.obj"), obj).unwrap();
    std::fs::write(dir.path().join("lat.mtl"), b"newmtl Tr\xE6\nKd 0.5 0.25 0\n").unwrap();
    let m = io::load(dir.path().join("lat.obj")).unwrap();
    let mats = &m.gltf_materials.as_ref().expect("materials").materials;
    assert_eq!((&mats[0]["name"], m.primitives[0].material), (&serde_json::json!("Træ"), Some(0)));
    assert_eq!(mats[0]["pbrMetallicRoughness"]["baseColorFactor"], serde_json::json!([0.5, 0.25, 0.0, 1.0]));
    let n = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::Materials).unwrap();
    assert_eq!((n.count, n.detail.as_str()), (1, "gone.mtl (not found)"));
    // The library named after the faces that use it (assimp's `cube_mtllib_after_g.obj`):
    // tobj looks names up as it reads `usemtl`, so it gets the `mtllib` lines first. Error
    // lines still count in the file as written.
    let late = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng q\nusemtl a\nf 1 2 3\nusemtl b\nf 2 4 3\nmtllib late.mtl\n";
    std::fs::write(dir.path().join("late.mtl"), "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 0 1\n").unwrap();
    std::fs::write(dir.path().join("late.obj"), late).unwrap();
    let m = io::load(dir.path().join("late.obj")).unwrap();
    assert_eq!(m.primitives.iter().map(|p| p.material).collect::<Vec<_>>(), [Some(0), Some(1)]);
    std::fs::write(dir.path().join("late.obj"), late.replace("f 2 4 3", "f 2 4 9")).unwrap();
    let e = io::load(dir.path().join("late.obj")).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::Malformed { line: Some(9), .. }), "{e}");
    // From memory: no folder to look in.
    let m = load(&std::fs::read(&path).unwrap(), Format::Obj).unwrap();
    assert!(m.gltf_materials.is_none());
    let n = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::Materials).unwrap();
    assert_eq!((n.count, n.detail.as_str()), (1, "textured_quad.mtl"));
}

/// glTF 2.0 lets a primitive leave POSITION out (a client skips rendering it); gltf-json
/// refused the file. Such a primitive is skipped and recorded, like a line primitive, and a
/// scene-keeping output keeps it as it was.
#[test]
fn gltf_primitives_without_positions_are_skipped() {
    let line = r#"{"attributes":{"POSITION":0},"indices":1,"mode":1}"#;
    let doc = gltf_doc().replace(line, &format!(r#"{line},{{"attributes":{{"NORMAL":0}},"indices":1}}"#));
    assert_ne!(doc, gltf_doc());
    let plain = load(gltf_doc().as_bytes(), Format::Gltf).unwrap();
    let m = load(doc.as_bytes(), Format::Gltf).unwrap();
    assert_eq!((&m.positions, &m.triangles), (&plain.positions, &plain.triangles));
    let r = m.load_repairs.iter().find(|r| r.kind == RepairKind::SkippedNonTrianglePrimitives).unwrap();
    assert_eq!(r.count, 4, "the line and the unplaced primitive, once per instance");
    assert!(r.examples.contains(&Location::Primitive { mesh: 0, primitive: 2 }));
    let scene = dynlod::io::GltfScene::from_bytes(doc.as_bytes(), None).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("kept.glb");
    scene.save(&out, &[scene.meshes[0].mesh.clone()]).unwrap();
    let glb = std::fs::read(&out).unwrap();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let written: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let prims = written["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(prims.len(), 3);
    assert!(prims[2]["attributes"].get("POSITION").is_none());
}

#[test]
fn gltf_short_buffer_is_truncated_not_a_panic() {
    let doc = gltf_doc().replace(r#""byteLength":56"#, r#""byteLength":64"#);
    let e = load(doc.as_bytes(), Format::Gltf).unwrap_err();
    assert!(matches!(e, LoadErrorKind::Truncated { .. } | LoadErrorKind::Malformed { .. }), "{e}");
}

#[test]
fn format_is_sniffed_when_the_extension_says_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("mesh.dat");
    std::fs::write(&p, PLY_ASCII).unwrap();
    assert_eq!(io::load(&p).unwrap().triangles.len(), 2);
    // After a byte-order mark, and an ascii STL in capitals.
    std::fs::write(&p, [b"\xEF\xBB\xBF".as_slice(), PLY_ASCII.as_bytes()].concat()).unwrap();
    assert_eq!(io::load(&p).unwrap().triangles.len(), 2);
    let stl = "SOLID PART\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\nVERTEX 0 1 0\nENDLOOP\nENDFACET\nENDSOLID PART\n";
    std::fs::write(&p, stl).unwrap();
    assert_eq!(io::load(&p).unwrap().triangles.len(), 1);
    std::fs::write(&p, b"this is not a mesh").unwrap();
    let e = io::load(&p).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::UnknownFormat));
    assert!(e.to_string().contains("mesh.dat"), "the error names the file: {e}");
    let e = io::load(dir.path().join("missing.obj")).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::Io(_)));
}

#[test]
fn gzipped_files_load_by_inner_extension() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("quad.ply.gz");
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut enc, PLY_ASCII.as_bytes()).unwrap();
    std::fs::write(&p, enc.finish().unwrap()).unwrap();
    assert_eq!(io::load(&p).unwrap().triangles.len(), 2);
}

fn assert_same(a: &IndexedMesh, b: &IndexedMesh) {
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.normals, b.normals);
    assert_eq!(a.uvs, b.uvs);
    assert_eq!(a.triangles, b.triangles);
}

#[test]
fn every_writer_round_trips_exactly_and_atomically() {
    let sphere = Mesh::build(&procedural::uv_sphere(6, 9), BuildOptions::default()).unwrap().to_indexed();
    let dir = tempfile::tempdir().unwrap();
    for (name, f) in [("s.obj", WriteFormat::Obj), ("s.ply", WriteFormat::Ply), ("s.glb", WriteFormat::Glb)] {
        let p = dir.path().join(name);
        io::save(&p, &sphere).unwrap();
        let back = io::load(&p).unwrap();
        assert_same(&sphere, &back);
        io::save_as(&p, &sphere, f).unwrap(); // overwrite in place
    }
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 3, "no temporary files left behind: {names:?}");
    // An unwritable destination fails cleanly and leaves nothing.
    assert!(io::save(dir.path().join("no/such/dir/x.ply"), &sphere).is_err());
    assert!(io::save(dir.path().join("x.xyz"), &sphere).is_err());
}

/// A written file gets what a newly created file gets (0666 less the umask), not the
/// temporary file's owner-only 0600; an overwritten one keeps its own permissions.
#[cfg(target_os = "linux")]
#[test]
fn written_files_get_the_permissions_of_a_created_file_or_the_replaced_one() {
    use std::os::unix::fs::PermissionsExt;
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let umask =
        status.lines().find_map(|l| l.strip_prefix("Umask:")).map(|u| u32::from_str_radix(u.trim(), 8).unwrap());
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("new.ply");
    io::save(&p, &procedural::tetrahedron()).unwrap();
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let created = {
        let q = dir.path().join("created");
        std::fs::File::create(&q).unwrap();
        mode(&q)
    };
    assert_eq!(mode(&p), created, "as File::create makes it");
    if let Some(u) = umask {
        assert_eq!(created, 0o666 & !u);
    }
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o640)).unwrap();
    io::save(&p, &procedural::tetrahedron()).unwrap();
    assert_eq!(mode(&p), 0o640, "the replaced file's permissions");
}

/// A writer handed a broken mesh refuses it with the typed defect, in every format, and
/// leaves the file already there as it was (and no temporary file).
#[test]
fn writers_refuse_a_broken_mesh_and_keep_the_old_file() {
    let good = procedural::tetrahedron();
    let mut bad_index = good.clone();
    bad_index.triangles[2][1] = 9;
    let mut nan = good.clone();
    nan.positions[3][2] = f32::NAN;
    let mut short_normals = good.clone();
    short_normals.normals = vec![[0.0, 0.0, 1.0]; 3];
    let mut bad_primitive = good.clone();
    bad_primitive.triangle_primitive = vec![0, 0, 0, 1];
    type Expect = fn(&MeshError) -> bool;
    let cases: [(&IndexedMesh, Expect); 5] = [
        (&bad_index, |e| matches!(e, MeshError::IndexOutOfRange { face: 2, corner: 1, index: 9, vertex_count: 4 })),
        (&nan, |e| matches!(e, MeshError::NonFiniteCoordinate { vertex: 3, .. })),
        (&short_normals, |e| matches!(e, MeshError::AttributeLength { attribute: "normal", len: 3, .. })),
        (&bad_primitive, |e| matches!(e, MeshError::PrimitiveOutOfRange { face: 3, primitive: 1, .. })),
        (&IndexedMesh::default(), |e| matches!(e, MeshError::Empty)),
    ];
    let dir = tempfile::tempdir().unwrap();
    for name in ["t.obj", "t.ply", "t.glb"] {
        let p = dir.path().join(name);
        io::save(&p, &good).unwrap();
        let before = std::fs::read(&p).unwrap();
        for (mesh, expected) in &cases {
            let err = io::save(&p, mesh).unwrap_err();
            assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput, "{name}: {err}");
            let typed = err.get_ref().and_then(|e| e.downcast_ref::<MeshError>()).expect("wraps a MeshError");
            assert!(expected(typed), "{name}: unexpected defect {typed:?}");
            assert_eq!(std::fs::read(&p).unwrap(), before, "{name}: the old file changed");
        }
    }
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 3, "no temporary files left behind: {names:?}");
    // The writers on their own refuse it too (no panic on the short normals).
    let mut sink = Vec::new();
    assert!(io::write_ply(&mut sink, &short_normals).is_err());
    assert!(io::write_obj(&mut sink, &bad_index).is_err());
    assert!(io::write_glb(&mut sink, &bad_primitive).is_err());
    assert!(sink.is_empty(), "nothing written before the check");
}

#[test]
fn glb_keeps_primitives_apart() {
    let mut m = procedural::tetrahedron();
    m.triangle_primitive = vec![0, 0, 1, 1];
    m.primitives = vec![Default::default(), Default::default()];
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("t.glb");
    io::save(&p, &m).unwrap();
    let back = io::load(&p).unwrap();
    assert_eq!(back.primitives.len(), 2);
    assert_eq!(back.triangle_primitive, vec![0, 0, 1, 1]);
    // The two glTF primitives share the writer's one vertex array; the corners land on the
    // same points.
    let corners =
        |x: &IndexedMesh| -> Vec<[f32; 3]> { x.triangles.iter().flatten().map(|&i| x.positions[i as usize]).collect() };
    assert_eq!(corners(&back), corners(&m));
    let welded = Mesh::build(&back, BuildOptions::default()).unwrap();
    assert_eq!((welded.positions.len(), welded.topology.stats().genus), (4, Some(0)));
}

/// Primitives sharing one vertex array (as our writer and many exporters write them) read it
/// once: it was read once per primitive, primitives × vertices (2,000 primitives over 500k
/// vertices took 24 GB). Instances under other transforms still get their own copy.
#[test]
fn glb_primitives_sharing_a_vertex_array_read_it_once() {
    let mut m = procedural::grid(40, 40, |_, _| false);
    let parts = 100;
    m.triangle_primitive = (0..m.triangles.len()).map(|t| (t * parts / m.triangles.len()) as u32).collect();
    m.primitives = vec![Default::default(); parts];
    let mut glb = Vec::new();
    io::write_glb(&mut glb, &m).unwrap();
    let back = load(&glb, Format::Glb).unwrap();
    assert_eq!(back.positions.len(), m.positions.len(), "one copy, not one per primitive");
    assert_eq!((&back.triangles, &back.triangle_primitive), (&m.triangles, &m.triangle_primitive));
    assert!(back.load_repairs.is_empty(), "{:?}", back.load_repairs);
}

#[test]
fn bundled_bunny_loads_with_the_known_counts() {
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let mesh = dynlod::load_mesh(p, BuildOptions::default()).unwrap();
    mesh.topology.validate().unwrap();
    let s = mesh.topology.stats();
    assert_eq!((mesh.input_vertices, mesh.input_triangles), (35_947, 69_451));
    assert_eq!((s.vertices, s.faces, s.components.len()), (34_834, 69_451, 1));
    assert_eq!((s.boundary_edges, s.boundary_loops, s.genus), (223, 5, Some(0)));
    assert_eq!(mesh.repairs.len(), 1);
    assert_eq!((mesh.repairs[0].kind, mesh.repairs[0].count), (RepairKind::DroppedUnreferencedVertices, 1_113));
}

#[test]
fn gltf_external_buffers_resolve_beside_the_file() {
    let doc = gltf_doc();
    let start = doc.find("data:application").unwrap();
    let end = start + doc[start..].find('"').unwrap();
    let payload = doc[start..end].split_once(";base64,").unwrap().1;
    let bin = base64::engine::general_purpose::STANDARD.decode(payload).unwrap();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("quad.bin"), &bin).unwrap();
    std::fs::write(dir.path().join("quad.gltf"), format!("{}quad.bin{}", &doc[..start], &doc[end..])).unwrap();
    let m = io::load(dir.path().join("quad.gltf")).unwrap();
    assert_eq!(m.triangles.len(), 4);
    std::fs::remove_file(dir.path().join("quad.bin")).unwrap();
    let e = io::load(dir.path().join("quad.gltf")).unwrap_err();
    assert!(e.to_string().contains("quad.bin"), "{e}");
    // URIs are percent-encoded: `my%20quad.bin` is the file `my quad.bin`, and so is an
    // image's; a name an exporter left unencoded is found as written.
    std::fs::write(dir.path().join("my quad.bin"), &bin).unwrap();
    std::fs::write(dir.path().join("base 100%.png"), b"\x89PNG-ish").unwrap();
    let with_image = |image: &str| {
        let doc = format!("{}my%20quad.bin{}", &doc[..start], &doc[end..]);
        doc.replace(
            r#""materials":[{"name":"m"}],"#,
            &format!(r#""materials":[{{"name":"m"}}],"textures":[{{"source":0}}],"images":[{{"uri":"{image}"}}],"#),
        )
    };
    for image in ["base%20100%25.png", "base 100%.png"] {
        std::fs::write(dir.path().join("spaced.gltf"), with_image(image)).unwrap();
        let m = io::load(dir.path().join("spaced.gltf")).unwrap();
        assert_eq!(m.triangles.len(), 4);
        let img = &m.gltf_materials.as_ref().unwrap().images[0];
        assert_eq!(img.bytes.as_deref(), Some(&b"\x89PNG-ish"[..]), "{image}");
    }
}

#[test]
fn glb_output_keeps_materials_textures_and_images() {
    // The test document plus a texture whose image is a (tiny, opaque) PNG data URI.
    let png = base64::engine::general_purpose::STANDARD.encode(b"\x89PNG\r\n\x1a\nnot-really-a-png");
    let doc = gltf_doc().replace(
        r#""materials":[{"name":"m"}],"#,
        &format!(
            r#""materials":[{{"name":"m","pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],"textures":[{{"source":0,"sampler":0}}],"samplers":[{{"magFilter":9729}}],"images":[{{"uri":"data:image/png;base64,{png}"}}],"#
        ),
    );
    let m = load(doc.as_bytes(), Format::Gltf).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("out.glb");
    io::save(&p, &Mesh::build(&m, BuildOptions::default()).unwrap().to_indexed()).unwrap();
    let back = io::load(&p).unwrap();
    assert_eq!(back.primitives[0].material, Some(0));
    let mats = back.gltf_materials.as_ref().expect("materials carried");
    assert_eq!(mats.materials[0]["name"], "m");
    assert_eq!(mats.materials[0]["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
    assert_eq!(mats.textures[0]["source"], 0);
    assert_eq!(mats.samplers[0]["magFilter"], 9729);
    assert_eq!(mats.images.len(), 1);
    assert_eq!(
        mats.images[0].bytes.as_deref(),
        Some(&b"\x89PNG\r\n\x1a\nnot-really-a-png"[..]),
        "image embedded byte for byte"
    );
    assert_eq!(mats.images[0].mime_type.as_deref(), Some("image/png"));
}

/// Images the gltf crate's `Image::source` unwraps (panics found by fuzzing): one in a
/// bufferView without its mimeType, whose type is guessed from its bytes, and one with no
/// source at all, which stays without one.
#[test]
fn gltf_images_without_a_type_or_a_source_load() {
    let png = base64::engine::general_purpose::STANDARD.encode(b"\x89PNG\r\n\x1a\nnot-really-a-png");
    let with_images = |images: &str| {
        gltf_doc().replace(
            r#""materials":[{"name":"m"}],"#,
            &format!(r#""materials":[{{"name":"m"}}],"textures":[{{"source":0}}],"images":{images},"#),
        )
    };
    let doc = with_images(&format!(r#"[{{"uri":"data:image/png;base64,{png}"}}]"#));
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("out.glb");
    io::save(
        &p,
        &Mesh::build(&load(doc.as_bytes(), Format::Gltf).unwrap(), BuildOptions::default()).unwrap().to_indexed(),
    )
    .unwrap();
    // The same length in spaces keeps the chunk's declared size.
    let mut glb = std::fs::read(&p).unwrap();
    let typed = br#","mimeType":"image/png""#;
    let at = glb.windows(typed.len()).position(|w| w == typed).expect("the writer names the type");
    glb[at..at + typed.len()].fill(b' ');
    let m = load(&glb, Format::Glb).unwrap();
    let image = &m.gltf_materials.as_ref().unwrap().images[0];
    assert_eq!(image.bytes.as_deref(), Some(&b"\x89PNG\r\n\x1a\nnot-really-a-png"[..]));
    assert_eq!(image.mime_type.as_deref(), Some("image/png"), "guessed from the bytes");
    let m = load(with_images(r#"[{"name":"lost"}]"#).as_bytes(), Format::Gltf).unwrap();
    let image = &m.gltf_materials.as_ref().unwrap().images[0];
    assert_eq!((image.name.as_deref(), &image.bytes, &image.uri), (Some("lost"), &None, &None));
}

#[test]
fn faces_of_fewer_than_three_vertices_are_skipped_and_recorded() {
    let off = "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n";
    let m = load(off.as_bytes(), Format::Off).unwrap();
    assert_eq!(m.triangles.len(), 1);
    let r = &m.load_repairs[0];
    assert_eq!((r.kind, r.count), (RepairKind::SkippedNonTrianglePrimitives, 1));
    assert_eq!(r.examples, vec![dynlod::mesh::Location::Face(1)]);
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n1 2\n";
    let m = load(ply.as_bytes(), Format::Ply).unwrap();
    assert_eq!((m.triangles.len(), m.load_repairs[0].count), (1, 1));
    // Strict mode refuses such a file.
    assert!(Mesh::build(&m, BuildOptions::default().strict(true)).is_err());
}

/// The test document (less its line primitive) with everything a mesh does not carry: a
/// second scene, an animation, a skin, a camera, and a joints attribute beside the positions.
fn gltf_doc_with_extras() -> String {
    gltf_doc()
        .replace(r#",{"attributes":{"POSITION":0},"indices":1,"mode":1}"#, "")
        .replace(r#""scenes":[{"nodes":[0,1]}]"#, r#""scenes":[{"nodes":[0,1]},{"nodes":[0]}]"#)
        .replace(r#""attributes":{"POSITION":0},"indices":1,"mode":5"#, r#""attributes":{"POSITION":0,"JOINTS_0":0},"indices":1,"mode":5"#)
        .replace(
            r#""materials":"#,
            r#""animations":[{"channels":[{"sampler":0,"target":{"node":0,"path":"translation"}}],"samplers":[{"input":2,"output":0}]}],
               "skins":[{"joints":[0]}],"cameras":[{"type":"perspective","perspective":{"yfov":1.0,"znear":0.1}}],"materials":"#,
        )
        .replace(
            r#"{"bufferView":1,"componentType":5123,"count":4,"type":"SCALAR"}]"#,
            r#"{"bufferView":1,"componentType":5123,"count":4,"type":"SCALAR"},{"bufferView":0,"componentType":5126,"count":4,"type":"SCALAR","min":[0],"max":[1]}]"#,
        )
}

/// Application-specific attributes (`_BATCHID` in Cesium's tiles, `_FEATURE_ID_0` of
/// EXT_mesh_features) are valid glTF; gltf-json refused them as an invalid semantic name
/// unless its `extras` feature is on.
#[test]
fn gltf_application_specific_attributes_load_and_are_named() {
    let doc = gltf_doc_with_extras().replace(r#""JOINTS_0":0"#, r#""_BATCHID":0"#);
    let m = load(doc.as_bytes(), Format::Gltf).unwrap_or_else(|e| panic!("{e}"));
    let other = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::OtherAttributes).unwrap();
    assert_eq!((other.count, other.detail.as_str()), (1, "_BATCHID"));
}

#[test]
fn gltf_records_what_the_mesh_does_not_carry() {
    use dynlod::mesh::NotKeptKind as K;
    let m = load(gltf_doc_with_extras().as_bytes(), Format::Gltf).unwrap();
    let found: Vec<(K, usize, &str)> = m.not_kept.iter().map(|n| (n.kind, n.count, n.detail.as_str())).collect();
    assert_eq!(
        found,
        vec![
            (K::FlattenedScene, 2, "2 nodes; mesh 0 drawn 2 times"),
            (K::OtherScenes, 1, ""),
            (K::Animations, 1, ""),
            (K::Skins, 1, ""),
            (K::Cameras, 1, ""),
            (K::OtherAttributes, 1, "JOINTS_0"),
        ]
    );
    // Not defects: strict mode builds it, and the mesh (and its info) carries the list.
    let mesh = Mesh::build(&m, BuildOptions::default().strict(true)).unwrap();
    assert_eq!(mesh.not_kept, m.not_kept);
    let info = dynlod::info::MeshInfo::new(&mesh).to_json("x.gltf");
    assert_eq!(info["not_kept"][2]["kind"], "animations");
    assert!(dynlod::info::MeshInfo::new(&mesh).to_text("x.gltf").contains("animations not kept: 1"));
    // One untransformed instance of a plain mesh: nothing to report.
    let plain = gltf_doc()
        .replace(r#""scenes":[{"nodes":[0,1]}]"#, r#""scenes":[{"nodes":[0]}]"#)
        .replace(r#"{"mesh":0,"translation":[10,0,0]}"#, r#"{"mesh":0}"#);
    assert_eq!(load(plain.as_bytes(), Format::Gltf).unwrap().not_kept, vec![]);
}

/// Two meshes side by side, the first with texture coordinates and normals, the second
/// with neither (a glass pane beside a textured body, as in CesiumMilkTruck.glb).
fn gltf_doc_partly_textured() -> String {
    let mut bin = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]] {
        bin.extend(p.iter().flat_map(|c| c.to_le_bytes()));
    }
    for t in [[0f32, 0.], [0.5, 0.], [0., 0.25], [0.5, 0.25]] {
        bin.extend(t.iter().flat_map(|c| c.to_le_bytes()));
    }
    for _ in 0..4 {
        bin.extend([0f32, 0., 1.].iter().flat_map(|c| c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
        "nodes":[{{"mesh":0}},{{"mesh":1,"translation":[5,0,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1,"NORMAL":2}},"indices":3,"mode":5,"material":0}}]}},
                  {{"primitives":[{{"attributes":{{"POSITION":0}},"indices":3,"mode":5,"material":1}}]}}],
        "materials":[{{"name":"textured"}},{{"name":"glass"}}],
        "buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{data}"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":32}},
                       {{"buffer":0,"byteOffset":80,"byteLength":48}},{{"buffer":0,"byteOffset":128,"byteLength":8}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},
                     {{"bufferView":2,"componentType":5126,"count":4,"type":"VEC3"}},
                     {{"bufferView":3,"componentType":5123,"count":4,"type":"SCALAR"}}]}}"#,
        len = bin.len()
    )
}

#[test]
fn attributes_some_primitives_lack_are_kept_for_the_others() {
    let m = load(gltf_doc_partly_textured().as_bytes(), Format::Gltf).unwrap();
    assert_eq!((m.uvs.len(), m.normals.len()), (8, 8), "kept, zeros for the bare primitive");
    assert_eq!(m.uvs[..4], [[0., 0.], [0.5, 0.], [0., 0.25], [0.5, 0.25]]);
    let flags: Vec<(bool, bool)> = m.primitives.iter().map(|p| (p.no_normals, p.no_uvs)).collect();
    assert_eq!(flags, vec![(false, false), (true, true)]);
    // Through the welded mesh and a GLB: the bare primitive gets neither attribute, the other
    // keeps both, and reading the file back gives the same flags and coordinates.
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("out.glb");
    io::save(&p, &Mesh::build(&m, BuildOptions::default()).unwrap().to_indexed()).unwrap();
    let bytes = std::fs::read(&p).unwrap();
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
    let attrs = |i: usize| {
        let mut k: Vec<String> =
            doc["meshes"][0]["primitives"][i]["attributes"].as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    };
    assert_eq!(attrs(0), ["NORMAL", "POSITION", "TEXCOORD_0"]);
    assert_eq!(attrs(1), ["POSITION"]);
    let back = io::load(&p).unwrap();
    let flags: Vec<(bool, bool)> = back.primitives.iter().map(|p| (p.no_normals, p.no_uvs)).collect();
    assert_eq!(flags, vec![(false, false), (true, true)]);
    let mut uvs: Vec<[f32; 2]> = back
        .triangles
        .iter()
        .zip(&back.triangle_primitive)
        .filter(|(_, &p)| p == 0)
        .flat_map(|(t, _)| t.map(|i| back.uvs[i as usize]))
        .collect();
    uvs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    uvs.dedup();
    assert_eq!(uvs, [[0., 0.], [0., 0.25], [0.5, 0.], [0.5, 0.25]]);
}

/// Accessors that are not what their attribute needs (found by fuzzing: the gltf crate reads
/// them with the wrong element size, a panic in a debug build and garbage in a release one).
/// Unreadable normals or UVs are left out of their primitive with a recorded repair; unreadable
/// or missing positions or indices are a typed error naming the primitive and the accessor.
#[test]
fn gltf_accessors_of_the_wrong_type_are_dropped_or_refused_never_misread() {
    let doc = gltf_doc_partly_textured();
    let dropped = |doc: String| {
        let m = load(doc.as_bytes(), Format::Gltf).unwrap();
        let r = m.load_repairs.iter().find(|r| r.kind == RepairKind::DroppedUnreadableAttributes).expect("recorded");
        assert_eq!((r.count, &r.examples[..]), (1, &[Location::Primitive { mesh: 0, primitive: 0 }][..]));
        m
    };
    // NORMAL naming the index accessor (SCALAR of UNSIGNED_SHORT): the UVs stay.
    // No other primitive has normals, so the mesh has none.
    let m = dropped(doc.replace(r#""NORMAL":2"#, r#""NORMAL":3"#));
    assert!(m.normals.is_empty(), "no primitive has readable normals");
    assert_eq!(m.uvs[..4], [[0., 0.], [0.5, 0.], [0., 0.25], [0.5, 0.25]]);
    // Texture coordinates of VEC3, or fewer than the positions: the normals stay.
    let vec3_uvs = doc.replace(r#""count":4,"type":"VEC2""#, r#""count":2,"type":"VEC3""#);
    let short_uvs = doc.replace(r#""count":4,"type":"VEC2""#, r#""count":3,"type":"VEC2""#);
    for m in [dropped(vec3_uvs), dropped(short_uvs)] {
        assert!(m.uvs.is_empty());
        assert_eq!(m.normals[..4], [[0., 0., 1.]; 4]);
    }
    // Positions or indices that cannot be read as such, and a stride shorter than a position.
    let stride = doc.replace(r#""byteOffset":0,"byteLength":48"#, r#""byteOffset":0,"byteLength":48,"byteStride":8"#);
    for (doc, expected) in [
        (doc.replace(r#""type":"VEC3","min"#, r#""type":"VEC2","min"#), "POSITION accessor 0 is VEC2 of FLOAT"),
        (
            doc.replace(r#""indices":3,"mode":5,"material":0"#, r#""indices":2,"mode":5,"material":0"#),
            "indices accessor 2 is VEC3 of FLOAT",
        ),
        (stride, "POSITION accessor 0's buffer view has a stride of 8 bytes, shorter than its 12-byte elements"),
        // gltf-json's validation itself indexed this one out of bounds (a panic).
        (
            doc.replace(r#""POSITION":0,"TEXCOORD_0""#, r#""POSITION":7,"TEXCOORD_0""#),
            "POSITION names accessor 7, but the file has 4",
        ),
    ] {
        let e = load(doc.as_bytes(), Format::Gltf).unwrap_err().to_string();
        assert!(e.contains(&format!("mesh 0 primitive 0: {expected}")), "{e}");
    }
    // The readable file records nothing.
    assert!(load(doc.as_bytes(), Format::Gltf).unwrap().load_repairs.is_empty());
}

/// A GLB header whose total length is shorter than the header itself (found by fuzzing: the
/// gltf crate subtracts before it compares, an overflow).
#[test]
fn glb_header_declaring_less_than_itself_is_refused() {
    let mut glb = Vec::new();
    let sphere = Mesh::build(&procedural::uv_sphere(4, 6), BuildOptions::default()).unwrap().to_indexed();
    io::write_glb(&mut glb, &sphere).unwrap();
    assert!(load(&glb, Format::Glb).is_ok());
    glb[8..12].copy_from_slice(&2u32.to_le_bytes());
    let e = load(&glb, Format::Glb).unwrap_err().to_string();
    assert!(e.contains("the GLB header declares 2 bytes in all, fewer than its own 12"), "{e}");
}

#[test]
fn obj_objects_without_uvs_or_normals_keep_them_for_the_others() {
    let obj = "o body\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 0.5 0\nvt 0 0.5\nvt 0.5 0.5\nvn 0 0 1\n\
               f 1/1/1 2/2/1 3/3/1\nf 2/2/1 4/4/1 3/3/1\n\
               o glass\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 5 6 7\n";
    let m = load(obj.as_bytes(), Format::Obj).unwrap();
    assert_eq!((m.uvs.len(), m.normals.len()), (m.positions.len(), m.positions.len()));
    let flags: Vec<(bool, bool)> = m.primitives.iter().map(|p| (p.no_normals, p.no_uvs)).collect();
    assert_eq!(flags, vec![(false, false), (true, true)]);
    // Written back: the glass faces name positions only, and re-reading gives the same flags.
    let mut text = Vec::new();
    io::write_obj(&mut text, &Mesh::build(&m, BuildOptions::default()).unwrap().to_indexed()).unwrap();
    let text = String::from_utf8(text).unwrap();
    let glass = text.split("o glass").nth(1).expect("glass object written");
    assert!(glass.lines().filter(|l| l.starts_with("f ")).all(|l| !l.contains('/')), "{glass}");
    let body = text.split("o glass").next().unwrap();
    assert!(body.lines().filter(|l| l.starts_with("f ")).all(|l| l.matches('/').count() == 6), "{body}");
    let back = load(text.as_bytes(), Format::Obj).unwrap();
    let flags: Vec<(bool, bool)> = back.primitives.iter().map(|p| (p.no_normals, p.no_uvs)).collect();
    assert_eq!(flags, vec![(false, false), (true, true)]);
}

/// Extra properties and elements, face colours and material libraries are read past in
/// every format; each loader lists them in `not_kept` so the user is told. (A lone `red` is
/// not a colour; vertex colours are read: `tests/attributes.rs`.)
#[test]
fn every_format_lists_what_it_reads_past() {
    use dynlod::mesh::NotKeptKind as K;
    let notes = |m: &IndexedMesh| -> Vec<(K, usize, String)> {
        m.not_kept.iter().map(|n| (n.kind, n.count, n.detail.clone())).collect()
    };
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               property uchar red\nproperty float confidence\nelement face 1\nproperty list uchar int vertex_indices\n\
               property uchar flags\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
               0 0 0 255 1\n1 0 0 0 1\n0 1 0 0 1\n3 0 1 2 7\n0 1\n";
    assert_eq!(
        notes(&load(ply.as_bytes(), Format::Ply).unwrap()),
        vec![(K::OtherAttributes, 1, "red, confidence, face flags".into()), (K::OtherElements, 1, "edge".into())]
    );
    let obj = "mtllib a.mtl\nv 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nusemtl red\nf 1 2 3\n";
    assert_eq!(notes(&load(obj.as_bytes(), Format::Obj).unwrap()), vec![(K::Materials, 1, "a.mtl".to_string())]);
    let off = "COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2 0.5 0.5 0.5\n";
    assert_eq!(
        notes(&load(off.as_bytes(), Format::Off).unwrap()),
        vec![(K::OtherAttributes, 1, "face colours".into())]
    );
    // Plain files: nothing to say.
    let plain = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    assert!(load(plain.as_bytes(), Format::Obj).unwrap().not_kept.is_empty());
    let plain = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                 property float nx\nproperty float ny\nproperty float nz\nelement face 1\n\
                 property list uchar int vertex_indices\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n";
    assert!(load(plain.as_bytes(), Format::Ply).unwrap().not_kept.is_empty());
    // The test PLY above has a face colour and an edge element.
    assert_eq!(notes(&load(PLY_ASCII.as_bytes(), Format::Ply).unwrap()).len(), 2);
}

/// OBJ and PLY put the texture's origin at its bottom-left, glTF at its top-left: a GLB made
/// from an OBJ showed its texture upside down, and an OBJ from a GLB too. v now turns over
/// (v ↦ 1 − v) between them, read here from the GLB by the `gltf` crate, not by our loader;
/// and an OBJ or PLY written from its own format keeps its numbers as they were written.
#[test]
fn texture_coordinates_turn_over_between_obj_ply_and_gltf() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0.1\nvt 0.333333 0.9\nf 1/1 2/2 3/3\n";
    let m = load(obj.as_bytes(), Format::Obj).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("t.glb");
    io::save(&glb, &m).unwrap();
    let doc = gltf::Gltf::from_slice(&std::fs::read(&glb).unwrap()).unwrap();
    let blob = doc.blob.as_deref();
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    let reader = prim.reader(|_| blob);
    let uvs: Vec<[f32; 2]> = reader.read_tex_coords(0).unwrap().into_f32().collect();
    assert_eq!(uvs, [[0.0, 1.0], [1.0, 0.9], [0.333333, (1.0 - 0.9f64) as f32]]);
    // Back to OBJ from the GLB: the file's own numbers again.
    let back = io::load(&glb).unwrap();
    let out = dir.path().join("t.obj");
    io::save(&out, &back).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    let vts: Vec<&str> = text.lines().filter(|l| l.starts_with("vt ")).collect();
    assert_eq!(vts, ["vt 0 0", "vt 1 0.1", "vt 0.333333 0.9"]);
    // A PLY from the OBJ: the OBJ's decimals do not all fit f32 once turned over (0.9 would
    // come back as 0.90000004), so v is written in double, and reads back as it was.
    let ply = dir.path().join("t.ply");
    io::save(&ply, &m).unwrap();
    assert!(String::from_utf8_lossy(&std::fs::read(&ply).unwrap()).contains("property double u\nproperty double v\n"));
    assert_eq!(io::load(&ply).unwrap().uvs, m.uvs);
    // A PLY from a PLY of floats keeps floats, bit for bit.
    let floats = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0.9\n1 0 0 1 0.1\n0 1 0 0.333333 0.7654321\n3 0 1 2\n";
    let m = load(floats.as_bytes(), Format::Ply).unwrap();
    let ply = dir.path().join("f.ply");
    io::save(&ply, &m).unwrap();
    let bytes = std::fs::read(&ply).unwrap();
    assert!(String::from_utf8_lossy(&bytes).contains("property float u\nproperty float v\n"));
    let t: Vec<f32> = (0..3)
        .map(|k| f32::from_le_bytes(bytes[bytes.len() - 13 - 20 * (3 - k) + 16..][..4].try_into().unwrap()))
        .collect();
    assert_eq!(t, [0.9, 0.1, 0.7654321], "the file's floats (each vertex x y z u v; then the face, 13 bytes)");
    assert_eq!(io::load(&ply).unwrap().uvs, m.uvs);
}
