//! Further vertex attributes (texture coordinate sets past the first, colours, tangents):
//! read from glTF, PLY, OBJ and OFF, carried as wedges through welding, the simplifier and
//! the runtime, written back, and named where an output format cannot hold them.

mod common;

use std::collections::HashSet;

use base64::Engine;
use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::io::{self, Format, WriteFormat};
use dynlod::lod::{Runtime, RuntimeOptions};
use dynlod::mesh::{NotKeptKind, VertexAttribute};
use dynlod::simplify::{simplify, Method, SimplifyOptions};
use dynlod::{procedural, BuildError, BuildOptions, IndexedMesh, Mesh, MeshError};
use serde_json::{json, Value};

/// The binary part of a hand-made glTF: every array its own view and accessor.
#[derive(Default)]
struct Bin {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    fn push(&mut self, bytes: &[u8], count: usize, kind: &str, component: u32, normalized: bool) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}));
        let mut a =
            json!({"bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": kind});
        if normalized {
            a["normalized"] = json!(true);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    fn floats(&mut self, v: &[f32], kind: &str, per: usize) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.push(&bytes, v.len() / per, kind, 5126, false)
    }

    fn positions(&mut self, v: &[f32]) -> usize {
        let i = self.floats(v, "VEC3", 3);
        let axis = |k: usize| v.iter().skip(k).step_by(3).copied();
        let (lo, hi): (Vec<f32>, Vec<f32>) =
            (0..3).map(|k| (axis(k).fold(f32::MAX, f32::min), axis(k).fold(f32::MIN, f32::max))).unzip();
        self.accessors[i]["min"] = json!(lo);
        self.accessors[i]["max"] = json!(hi);
        i
    }
}

/// One mesh of two primitives, drawn twice (once mirrored and moved aside):
/// - a quad with NORMAL, TEXCOORD_0, TEXCOORD_1, COLOR_0 (normalized UNSIGNED_BYTE RGBA) and
///   TANGENT;
/// - a triangle beside it with an RGB FLOAT COLOR_0 and an application-specific `_TEMPERATURE`.
fn two_primitives() -> Value {
    let mut b = Bin::default();
    let quad = [0., 0., 0., 1., 0., 0., 0., 1., 0., 1., 1., 0.];
    let pos_a = b.positions(&quad);
    let normal = b.floats(&[0., 0., 1.].repeat(4), "VEC3", 3);
    let uv0 = b.floats(&[0., 0., 1., 0., 0., 1., 1., 1.], "VEC2", 2);
    let uv1 = b.floats(&[0.25, 0.25, 0.75, 0.25, 0.25, 0.75, 0.75, 0.75], "VEC2", 2);
    let colour = b.push(&[255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 255, 51, 51, 51, 0], 4, "VEC4", 5121, true);
    let tangent = b.floats(&[1., 0., 0., 1.].repeat(4), "VEC4", 4);
    let idx_a = b.push(&[0u8, 1, 2, 2, 1, 3], 6, "SCALAR", 5121, false);
    let pos_b = b.positions(&[1., 0., 0., 2., 0., 0., 1., 1., 0.]);
    let grey = b.floats(&[0.5; 9], "VEC3", 3);
    let temperature = b.floats(&[20., 21., 22.], "SCALAR", 1);
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&b.bin));
    json!({
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 0, "scale": [-1, 1, 1], "translation": [-5, 0, 0]}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": pos_a, "NORMAL": normal, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1,
                            "COLOR_0": colour, "TANGENT": tangent}, "indices": idx_a},
            {"attributes": {"POSITION": pos_b, "COLOR_0": grey, "_TEMPERATURE": temperature}}
        ]}],
        "buffers": [{"byteLength": b.bin.len(), "uri": uri}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    })
}

fn attribute<'m>(m: &'m IndexedMesh, semantic: &str) -> &'m VertexAttribute {
    m.attributes.iter().find(|a| a.semantic == semantic).unwrap_or_else(|| panic!("no {semantic}"))
}

/// Every triangle corner as (position, normal, uv, further attributes), in bits.
fn corners(m: &IndexedMesh) -> Vec<Vec<u32>> {
    let vertex = |i: usize| {
        let mut v: Vec<u32> = m.positions[i].iter().map(|c| c.to_bits()).collect();
        v.extend(m.normals.get(i).into_iter().flatten().map(|c| c.to_bits()));
        v.extend(m.uvs.get(i).into_iter().flatten().map(|c| c.to_bits()));
        for a in &m.attributes {
            v.extend(a.get(i).iter().map(|c| c.to_bits()));
        }
        v
    };
    m.triangles.iter().flatten().map(|&i| vertex(i as usize)).collect()
}

#[test]
fn gltf_texture_sets_colours_and_tangents_are_read_per_primitive() {
    let m = io::load_bytes(two_primitives().to_string().as_bytes(), Format::Gltf, None).unwrap();
    assert!(m.load_repairs.is_empty(), "{:?}", m.load_repairs);
    assert_eq!(m.positions.len(), 14, "two instances of 4 + 3 vertices");
    let names: HashSet<&str> = m.attributes.iter().map(|a| a.semantic.as_str()).collect();
    assert_eq!(names, HashSet::from(["TEXCOORD_1", "COLOR_0", "TANGENT"]));
    // Normalized bytes over 255; the RGB primitive's colours gain an alpha of 1.
    let colour = attribute(&m, "COLOR_0");
    assert_eq!(colour.components, 4);
    assert_eq!(colour.get(0), [1., 0., 0., 1.]);
    assert_eq!(colour.get(1), [0., 1., 0., 128. / 255.]);
    assert_eq!(colour.get(3), [0.2, 0.2, 0.2, 0.]);
    assert_eq!(colour.get(4), [0.5, 0.5, 0.5, 1.]);
    assert!(colour.absent.is_empty());
    // The triangle has neither a second UV set nor tangents: zeros, and marked absent.
    for semantic in ["TEXCOORD_1", "TANGENT"] {
        let a = attribute(&m, semantic);
        assert_eq!(a.absent, [1], "{semantic}");
        assert!(a.get(5).iter().all(|&c| c == 0.0), "{semantic}");
    }
    assert_eq!(attribute(&m, "TEXCOORD_1").get(1), [0.75, 0.25]);
    // The first instance's tangents as written; the mirrored one's turned and flipped in
    // handedness (x → −x, and w = −1, so the rebuilt bitangent keeps pointing along +y).
    let tangent = attribute(&m, "TANGENT");
    assert_eq!(tangent.get(0), [1., 0., 0., 1.]);
    assert_eq!(tangent.get(7), [-1., 0., 0., -1.]);
    // What is not carried is still named.
    let other = m.not_kept.iter().find(|n| n.kind == NotKeptKind::OtherAttributes).unwrap();
    assert_eq!((other.count, other.detail.as_str()), (1, "_TEMPERATURE"));
}

#[test]
fn a_glb_written_from_the_mesh_holds_every_attribute_where_the_source_had_it() {
    let input = io::load_bytes(two_primitives().to_string().as_bytes(), Format::Gltf, None).unwrap();
    let written = Mesh::build(&input, BuildOptions::default()).unwrap().to_indexed();
    assert_eq!(corners(&written), corners(&input), "building and unwelding keeps every corner");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.glb");
    io::save(&path, &written).unwrap();
    let back = io::load(&path).unwrap();
    // A GLB groups the triangles by primitive.
    let triangles = |m: &IndexedMesh| {
        let mut t: Vec<Vec<Vec<u32>>> = corners(m).chunks(3).map(<[_]>::to_vec).collect();
        t.sort();
        t
    };
    assert_eq!(triangles(&back), triangles(&written));
    let absent =
        |m: &IndexedMesh| m.attributes.iter().map(|a| (a.semantic.clone(), a.absent.clone())).collect::<Vec<_>>();
    assert_eq!(absent(&back), absent(&written), "the primitives lacking each");
    assert!(io::not_written(&written, WriteFormat::Glb).is_empty());
}

#[test]
fn formats_that_cannot_hold_an_attribute_say_so() {
    let m = io::load_bytes(two_primitives().to_string().as_bytes(), Format::Gltf, None).unwrap();
    let obj = io::not_written(&m, WriteFormat::Obj);
    assert_eq!(obj.len(), 2, "{obj:?}");
    assert!(obj[0].contains("TEXCOORD_1") && obj[0].contains("TANGENT") && !obj[0].contains("COLOR_0"), "{obj:?}");
    assert!(obj[1].contains("alpha"), "{obj:?}");
    let ply = io::not_written(&m, WriteFormat::Ply);
    assert!(ply.iter().any(|l| l.contains("2 primitives")) && !ply.iter().any(|l| l.contains("alpha")), "{ply:?}");
    // Colours on some primitives only: the others come out black, and that is said too.
    let mut part = m.clone();
    part.attributes.retain(|a| a.semantic == "COLOR_0");
    part.attributes[0].absent = vec![1];
    assert!(io::not_written(&part, WriteFormat::Obj).iter().any(|l| l.contains("missing from 1 primitive")));
    // The command line prints them, and `--json` lists them.
    let dir = tempfile::tempdir().unwrap();
    let (src, out) = (dir.path().join("in.gltf"), dir.path().join("out.obj"));
    std::fs::write(&src, two_primitives().to_string()).unwrap();
    let run = |json: bool| {
        let mut args = vec!["simplify", src.to_str().unwrap(), out.to_str().unwrap(), "--ratio", "1"];
        if json {
            args.push("--json");
        }
        std::process::Command::new(env!("CARGO_BIN_EXE_dynlod")).args(args).output().unwrap()
    };
    let text = run(false);
    assert!(text.status.success());
    let stderr = String::from_utf8_lossy(&text.stderr);
    assert!(stderr.contains("left out, the format cannot hold it: vertex attributes"), "{stderr}");
    let v: Value = serde_json::from_slice(&run(true).stdout).unwrap();
    assert_eq!(v["not_written"].as_array().unwrap().len(), 2, "{v}");
    // The OBJ holds the colours (RGB).
    let back = io::load(&out).unwrap();
    assert_eq!(back.attributes.len(), 1);
    assert_eq!((back.attributes[0].semantic.as_str(), back.attributes[0].components), ("COLOR_0", 3));
}

#[test]
fn ply_colours_are_read_written_and_read_back_to_the_same_bytes() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
               property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n\
               property float confidence\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0 255 0 0 255 1\n1 0 0 0 255 0 200 1\n0 1 0 0 0 255 17 1\n1 1 0 1 2 3 4 1\n3 0 1 2\n3 2 1 3\n";
    let m = io::load_bytes(ply.as_bytes(), Format::Ply, None).unwrap();
    let c = attribute(&m, "COLOR_0");
    assert_eq!((c.components, c.get(1)), (4, &[0., 1., 0., 200. / 255.][..]));
    let other = m.not_kept.iter().find(|n| n.kind == NotKeptKind::OtherAttributes).unwrap();
    assert_eq!(other.detail, "confidence", "colours are kept; the rest is named");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.ply");
    io::save(&path, &Mesh::build(&m, BuildOptions::default()).unwrap().to_indexed()).unwrap();
    let back = io::load(&path).unwrap();
    assert_eq!(corners(&back), corners(&m));
    // RGB under the `diffuse_` names, 16-bit; a lone channel is not a colour.
    let rgb16 = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                 property ushort diffuse_red\nproperty ushort diffuse_green\nproperty ushort diffuse_blue\n\
                 element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                 0 0 0 65535 0 0\n1 0 0 0 65535 0\n0 1 0 0 0 0\n3 0 1 2\n";
    let m = io::load_bytes(rgb16.as_bytes(), Format::Ply, None).unwrap();
    assert_eq!(attribute(&m, "COLOR_0").values[..6], [1., 0., 0., 0., 1., 0.]);
    let red = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               property uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0 9\n1 0 0 9\n0 1 0 9\n3 0 1 2\n";
    let m = io::load_bytes(red.as_bytes(), Format::Ply, None).unwrap();
    assert!(m.attributes.is_empty());
    assert_eq!(m.not_kept[0].detail, "red");
}

#[test]
fn obj_and_off_colours_are_read() {
    let obj = b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n";
    let m = io::load_bytes(obj, Format::Obj, None).unwrap();
    assert_eq!(attribute(&m, "COLOR_0").values, [1., 0., 0., 0., 1., 0., 0., 0., 1.]);
    assert!(m.not_kept.is_empty(), "{:?}", m.not_kept);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    io::save(&path, &m).unwrap();
    assert_eq!(corners(&io::load(&path).unwrap()), corners(&m));
    // RGBA (tobj refuses a fourth channel): the colours read, the alpha read past and listed
    // where it is below 1. A colour of two channels, or five, and a w of zero are refused at
    // their lines.
    let rgba = b"v 0 0 0 1 0 0 1\nv 1 0 0 0 1 0 0.5\nv 0 1 0 0 0 1 1\nf 1 2 3\n";
    let m = io::load_bytes(rgba, Format::Obj, None).unwrap();
    assert_eq!(attribute(&m, "COLOR_0").values, [1., 0., 0., 0., 1., 0., 0., 0., 1.]);
    let listed: Vec<&str> = m.not_kept.iter().map(|n| n.detail.as_str()).collect();
    assert_eq!(listed, ["vertex colour alpha below 1 (1 `v x y z r g b a`, the first at line 2)"]);
    let opaque = String::from_utf8_lossy(rgba).replace("0.5", "1");
    assert!(io::load_bytes(opaque.as_bytes(), Format::Obj, None).unwrap().not_kept.is_empty());
    // A colour or w that is not a number (tobj read past the first, and the colours of the
    // other vertices then missed theirs) is refused at its line too.
    for bad in [
        "v 1 0 0 1 1",
        "v 1 0 0 1 1 1 1 1",
        "v 1 0 0 1 1 1 x",
        "v 1 0 0 0",
        "v 1 0 0 0 x 0",
        "v 1 0 0 x",
        "v 1 0 0 a b c 1",
    ] {
        let obj = format!("v 0 0 0\n{bad}\nv 0 1 0\nf 1 2 3\n");
        let e = io::load_bytes(obj.as_bytes(), Format::Obj, None).unwrap_err();
        assert!(matches!(e, dynlod::LoadErrorKind::Malformed { line: Some(2), .. }), "{bad}: {e}");
    }
    // COFF: integers over 255 when some exceed 1, otherwise 0–1 as written.
    let off = b"COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 51 0 255\n0 1 0 0 0 255 0\n3 0 1 2\n";
    let m = io::load_bytes(off, Format::Off, None).unwrap();
    assert_eq!(attribute(&m, "COLOR_0").get(1), [0., 0.2, 0., 1.]);
    let off = b"COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 0.5 0 1\n0 1 0 0 0 1 0\n3 0 1 2 1 1 1\n";
    let m = io::load_bytes(off, Format::Off, None).unwrap();
    assert_eq!(attribute(&m, "COLOR_0").get(0), [1., 0., 0., 1.]);
    assert_eq!(m.not_kept[0].detail, "face colours");
    // RGB without alpha, as CGAL writes COFF (its `mesh_with_colors.off`, with comments
    // before the keyword and a face of five corners): opaque. Read as RGBA, the first three
    // vertices took the next ones' coordinates and the faces ran out.
    let off = b"# a comment\nCOFF\n4 2 0\n0 0 0 0.9 0 0 #red\n1 0 0 0 0 0.9\n1 1 0 255 0 0\n0 1 0 0 255 0\n3 0 1 2 0.9 0 0\n3 0 2 3\n";
    let m = io::load_bytes(off, Format::Off, None).unwrap();
    assert_eq!(m.positions, [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]]);
    assert_eq!(m.triangles.len(), 2);
    let c = attribute(&m, "COLOR_0");
    assert_eq!([c.get(0), c.get(1), c.get(2)], [[0.9, 0., 0., 1.], [0., 0., 0.9, 1.], [255., 0., 0., 1.]]);
    // The 0–255 scale where every given component is an integer and one exceeds 1.
    let m = io::load_bytes(b"COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 0 51 0\n0 1 0 0 0 255\n3 0 1 2\n", Format::Off, None)
        .unwrap();
    assert_eq!(attribute(&m, "COLOR_0").get(1), [0., 0.2, 0., 1.]);
}

#[test]
fn attributes_a_mesh_cannot_carry_are_refused_by_name() {
    let base = procedural::tetrahedron();
    let with = |semantic: &str, components: usize, per_vertex: usize| {
        let mut m = base.clone();
        let values = vec![0.5; per_vertex * m.positions.len()];
        m.attributes.push(VertexAttribute::new(semantic, components, values));
        Mesh::build(&m, BuildOptions::default())
    };
    for (semantic, components, per_vertex, why) in [
        ("COLOR_0", 2, 2, "components"),
        ("TANGENT", 3, 3, "components"),
        ("TEXCOORD_0", 2, 2, "not a semantic"),
        ("TEXCOORD_01", 2, 2, "not a semantic"),
        ("JOINTS", 4, 4, "not a semantic"),
        ("JOINTS_0", 3, 3, "components"),
        ("TARGET:POSITION", 3, 3, "not a semantic"),
        ("TARGET0:", 3, 3, "not a semantic"),
        ("COLOR_0", 4, 3, "values"),
    ] {
        match with(semantic, components, per_vertex) {
            Err(BuildError::Mesh(MeshError::BadAttribute { semantic: s, reason })) => {
                assert_eq!(s, semantic);
                assert!(reason.contains(why), "{semantic}: {reason}");
            }
            other => panic!("{semantic}/{components}: {other:?}"),
        }
    }
    assert!(with("_WETNESS", 1, 1).is_ok() && with("TEXCOORD_3", 2, 2).is_ok());
    // What a scene-keeping glTF load carries (dynlod::io::GltfScene).
    assert!(with("JOINTS_0", 4, 4).is_ok() && with("WEIGHTS_1", 4, 4).is_ok() && with("TARGET2:NORMAL", 3, 3).is_ok());
    let mut twice = base.clone();
    let a = VertexAttribute::new("COLOR_0", 3, vec![0.0; 12]);
    twice.attributes = vec![a.clone(), a];
    assert!(matches!(twice.check(), Err(MeshError::BadAttribute { .. })));
    // Non-finite values are zeroed with the recorded repair, as for normals and UVs.
    let mut nan = base.clone();
    nan.attributes.push(VertexAttribute::new("COLOR_0", 3, vec![f32::NAN; 12]));
    let built = Mesh::build(&nan, BuildOptions::default()).unwrap();
    assert!(built.wedges.attributes[0].values.iter().all(|&c| c == 0.0));
    assert_eq!(built.repairs[0].kind.name(), "zeroed_non_finite_attributes");
}

/// A UV sphere as a flat-coloured export writes it: three vertices per triangle, each
/// triangle coloured by its hemisphere and, in the north, by a palette, so that colour seams
/// run along the equator and between the northern triangles of different colours.
fn painted_sphere() -> IndexedMesh {
    let s = procedural::uv_sphere(16, 32);
    let mut m = IndexedMesh::default();
    let mut values = Vec::new();
    for (f, t) in s.triangles.iter().enumerate() {
        let north = t.iter().map(|&i| s.positions[i as usize][2]).sum::<f32>() > 0.0;
        let colour = if north { [1.0, (f / 8 % 3) as f32 / 2.0, 0.25] } else { [0.0, 0.0, 1.0] };
        for &i in t {
            m.positions.push(s.positions[i as usize]);
            m.normals.push(s.normals[i as usize]);
            m.uvs.push(s.uvs[i as usize]);
            values.extend(colour);
        }
        let n = m.positions.len() as u32;
        m.triangles.push([n - 3, n - 2, n - 1]);
    }
    m.attributes.push(VertexAttribute::new("COLOR_0", 3, values));
    m
}

#[test]
fn colour_seams_are_wedges_the_simplifier_keeps_exact() {
    let input = painted_sphere();
    let mesh = Mesh::build(&input, BuildOptions::default()).unwrap();
    let plain = Mesh::build(&procedural::uv_sphere(16, 32), BuildOptions::default()).unwrap();
    assert!(mesh.seam_edges() > plain.seam_edges(), "colours split wedges where UVs do not");
    let original: HashSet<Vec<u32>> = corners(&input).into_iter().collect();
    for method in [Method::Qem, Method::Mca] {
        let mut m = mesh.clone();
        simplify(&mut m, SimplifyOptions::default().method(method).target_triangles(200));
        m.topology.validate().unwrap();
        let out = m.to_indexed();
        assert!(out.triangles.len() <= 300, "{method:?}: {}", out.triangles.len());
        // A half-edge collapse keeps one of its vertices: every corner is an input vertex,
        // position and attributes together.
        for c in corners(&out) {
            assert!(original.contains(&c), "{method:?}: a corner the input does not have");
        }
    }
}

#[test]
fn the_runtime_draws_coloured_wedges_from_their_input_vertices_and_restores_them() {
    let input = painted_sphere();
    let mesh = Mesh::build(&input, BuildOptions::default().spatial_order(true)).unwrap();
    let (centre, diag) = frame_bounds(&mesh.positions);
    let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default().audit(true));
    let mut mirror = Vec::new();
    assert!(common::check_source_triangles(&rt, &input, &mut mirror) > 0, "colour seams drawn");
    let mut coarsened = false;
    for f in 0..30 {
        let stats = rt.update(Some(&CameraPath::Dolly.view(f * 3, 90, centre, diag, (1280, 720))));
        coarsened |= stats.collapses > 0;
        rt.mesh().topology.validate().unwrap();
        common::check_source_triangles(&rt, &input, &mut mirror);
    }
    assert!(coarsened);
    rt.refine_fully();
    assert_eq!(corners(&rt.mesh().to_indexed()), corners(&mesh.to_indexed()));
    let report = rt.memory_report();
    let wedges = report.entries.iter().find(|e| e.0 == "wedges.attributes").unwrap().1;
    assert!(wedges >= mesh.wedges.len() * 12, "the colours are counted: {wedges} B");
}

/// A mesh with attributes but no seams (a scan with normals and colours) keeps them on
/// identity wedges (no corner, wedge-to-vertex or input-vertex list), in spatial order too,
/// and its vertices name input vertices holding their attributes, even where the first input
/// vertex at a position is an unused copy with other ones.
#[test]
fn seamless_attributes_live_on_identity_wedges() {
    let grid = procedural::grid(9, 9, |i, j| (i + j) % 3 == 0);
    let mut input = IndexedMesh::default();
    // The decoy: vertex 0's position, another colour, used by no face.
    input.positions.push(grid.positions[0]);
    input.positions.extend(&grid.positions);
    input.normals = vec![[0.0, 0.0, 1.0]; input.positions.len()];
    input.triangles = grid.triangles.iter().map(|t| t.map(|i| i + 1)).collect();
    let mut colours: Vec<f32> = input.positions.iter().flat_map(|p| [p[0] / 9.0, p[1] / 9.0, 0.5, 1.0]).collect();
    colours[..4].copy_from_slice(&[0.9, 0.1, 0.1, 0.5]);
    input.attributes.push(VertexAttribute::new("COLOR_0", 4, colours));
    let mesh = Mesh::build(&input, BuildOptions::default().spatial_order(true)).unwrap();
    assert!(mesh.wedges.is_identity());
    assert_eq!(mesh.wedges.attributes[0].len(), mesh.positions.len());
    let sorted = |m: &IndexedMesh| {
        let mut t: Vec<Vec<Vec<u32>>> = corners(m).chunks(3).map(<[_]>::to_vec).collect();
        t.sort();
        t
    };
    assert_eq!(sorted(&mesh.to_indexed()), sorted(&input));
    let (centre, diag) = frame_bounds(&mesh.positions);
    let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default().audit(true));
    let mut mirror = Vec::new();
    common::check_source_triangles(&rt, &input, &mut mirror);
    for f in 0..20 {
        rt.update(Some(&CameraPath::Zoom.view(f, 20, centre, diag, (640, 480))));
        common::check_source_triangles(&rt, &input, &mut mirror);
    }
    let report = rt.memory_report();
    let bytes = |k: &str| report.entries.iter().find(|e| e.0 == k).unwrap().1;
    assert_eq!((bytes("wedges.corner"), bytes("wedges.source")), (0, 0));
    assert!(bytes("wedges.attributes") >= mesh.positions.len() * 28, "normals and colours counted");
}

/// The floats of the accessor that primitive `p` of a GLB's only mesh names for `semantic`.
fn glb_floats(glb: &[u8], p: usize, semantic: &str) -> Vec<f32> {
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let doc: Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let bin = &glb[20 + json_len + 8..];
    let index = |v: &Value| v.as_u64().unwrap() as usize;
    let accessor = &doc["accessors"][index(&doc["meshes"][0]["primitives"][p]["attributes"][semantic])];
    let view = &doc["bufferViews"][index(&accessor["bufferView"])];
    let start = index(&view["byteOffset"]);
    let bytes = &bin[start..start + index(&view["byteLength"])];
    bytes.chunks_exact(4).map(|b| f32::from_le_bytes(b.try_into().unwrap())).collect()
}

/// glTF requires unit normals and tangents (with a handedness of ±1) in every element of
/// their accessors. An OBJ's normals need not be unit, and the vertex arrays a GLB's
/// primitives share hold zeros where a primitive had none: both are written as unit vectors
/// (the Khronos validator refused such outputs before).
#[test]
fn glb_normals_and_tangents_are_unit_vectors_throughout() {
    let mut m = IndexedMesh::from_triangles(
        vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [5., 0., 0.], [6., 0., 0.], [5., 1., 0.]],
        vec![[0, 1, 2], [3, 4, 5]],
    );
    // A tiny normal too: its squares are subnormal in f32 (the fuzzer's find).
    m.normals = vec![[0., 0., 5.], [0., 4e-22, 1e-22], [0., 0., 1.0004], [0.; 3], [0.; 3], [0.; 3]];
    m.primitives = vec![Default::default(), dynlod::mesh::Primitive { no_normals: true, ..Default::default() }];
    m.triangle_primitive = vec![0, 1];
    let mut tangents =
        VertexAttribute::new("TANGENT", 4, [[2., 0., 0., 0.5], [1., 0., 0., -3.], [0., 1., 0., 1.]].concat());
    tangents.values.resize(24, 0.0);
    tangents.absent = vec![1];
    m.attributes.push(tangents);
    let mut glb = Vec::new();
    io::write_glb(&mut glb, &m).unwrap();
    let normals = glb_floats(&glb, 0, "NORMAL");
    assert_eq!(normals[..3], [0., 0., 1.], "scaled to unit");
    assert_eq!(normals[6..9], [0., 0., 1.0004], "kept bit for bit when close");
    let tiny = 17f32.sqrt();
    assert!((normals[4] - 4.0 / tiny).abs() < 1e-6 && (normals[5] - 1.0 / tiny).abs() < 1e-6, "{:?}", &normals[3..6]);
    let tangents = glb_floats(&glb, 0, "TANGENT");
    assert_eq!(tangents[..12], [1., 0., 0., 1., 1., 0., 0., -1., 0., 1., 0., 1.]);
    // The second primitive's vertices: placeholders no primitive reads, unit all the same.
    for v in normals[9..].chunks(3).chain(tangents[12..].chunks(4).map(|t| &t[..3])) {
        assert!((v.iter().map(|c| c * c).sum::<f32>() - 1.0).abs() < 1e-6, "{v:?}");
    }
    let back = io::load_bytes(&glb, Format::Glb, None).unwrap();
    assert_eq!((back.primitives[1].no_normals, &attribute(&back, "TANGENT").absent[..]), (true, &[1][..]));
}

/// The primitives an attribute is absent from are a sorted list of the mesh's primitives
/// (`present_in` searches it); another list is refused by name, not misread.
#[test]
fn an_absent_list_that_is_not_sorted_primitive_ids_is_refused() {
    let mut m = procedural::tetrahedron();
    m.primitives = vec![Default::default(), Default::default()];
    m.triangle_primitive = vec![0, 1, 0, 1];
    m.attributes.push(VertexAttribute::new("COLOR_0", 3, vec![0.5; 12]));
    for (absent, ok) in [(vec![], true), (vec![1], true), (vec![0, 1], true), (vec![1, 0], false), (vec![2], false)] {
        m.attributes[0].absent = absent.clone();
        match m.check() {
            Err(MeshError::BadAttribute { reason, .. }) => {
                assert!(!ok && reason.contains("absent"), "{absent:?}: {reason}")
            }
            other => assert!(ok && other.is_ok(), "{absent:?}: {other:?}"),
        }
    }
}
