//! Files far from their own origin (a survey's UTM coordinates, a part placed in its
//! assembly): read relative to a round point at their centre so f32 keeps their precision,
//! written back in the file's coordinates, compared in one frame (`mesh/origin.rs`).

mod common;

use std::collections::HashSet;

use base64::Engine;
use dynlod::io::{self, Format, WriteFormat};
use dynlod::metrics::{hausdorff, HausdorffOptions};
use dynlod::{procedural, BuildOptions, IndexedMesh, Mesh};
use proptest::prelude::*;

/// UTM-like: half a million metres east, four million north.
const UTM: [f64; 3] = [512_345.0, 4_123_456.0, 100.0];

/// `m` as OBJ text, every coordinate moved by `offset` and printed to the millimetre (as a
/// survey exports it). Returns the text and the coordinates as printed.
fn far_obj(m: &IndexedMesh, offset: [f64; 3], scale: f64) -> (String, Vec<[String; 3]>) {
    let mut text = String::new();
    let mut printed = Vec::new();
    for p in &m.positions {
        let c: [String; 3] = std::array::from_fn(|k| format!("{:.3}", f64::from(p[k]) * scale + offset[k]));
        text.push_str(&format!("v {} {} {}\n", c[0], c[1], c[2]));
        printed.push(c);
    }
    for t in &m.triangles {
        text.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    (text, printed)
}

/// Absolute f64 coordinates of a mesh's positions.
fn absolute(m: &IndexedMesh) -> Vec<[f64; 3]> {
    m.positions.iter().map(|p| std::array::from_fn(|k| m.origin[k] + f64::from(p[k]))).collect()
}

#[test]
fn a_far_obj_keeps_every_vertex_and_writes_back_the_coordinates_it_read() {
    // A 26 cm torus with vertices a centimetre apart, printed to the millimetre at UTM
    // coordinates, where f32 steps are 3 cm (east) and 25 cm (north).
    let torus = procedural::torus(48, 24);
    let (text, printed) = far_obj(&torus, UTM, 0.1);
    let as_f64 = |c: &[String; 3]| c.each_ref().map(|s| s.parse::<f64>().unwrap());
    let as_f32: HashSet<[u32; 3]> = printed.iter().map(|c| as_f64(c).map(|x| (x as f32).to_bits())).collect();
    assert!(
        as_f32.len() < printed.len() / 4,
        "read as f32, the vertices would weld: {} of {}",
        as_f32.len(),
        printed.len()
    );

    let far = io::load_bytes(text.as_bytes(), Format::Obj, None).unwrap();
    assert_eq!(far.origin, [512_345.0, 4_123_456.0, 100.0], "the centre, rounded to 10 cm (diagonal 37 cm)");
    let mesh = Mesh::build(&far, BuildOptions::default()).unwrap();
    // The same file at the origin (read the same way: tobj numbers vertices by first use).
    let (near_text, _) = far_obj(&torus, [0.0; 3], 0.1);
    let near = io::load_bytes(near_text.as_bytes(), Format::Obj, None).unwrap();
    assert_eq!(near.origin, [0.0; 3]);
    let near = Mesh::build(&near, BuildOptions::default()).unwrap();
    assert_eq!(mesh.topology.faces, near.topology.faces, "nothing welded that the near torus keeps apart");
    assert_eq!(mesh.origin, far.origin);

    // Written back, every coordinate is a number the file held, digit for digit.
    let mut obj = Vec::new();
    io::write_obj(&mut obj, &mesh.to_indexed()).unwrap();
    let read: HashSet<[u64; 3]> = printed.iter().map(|c| as_f64(c).map(f64::to_bits)).collect();
    let mut lines = 0;
    for line in String::from_utf8(obj).unwrap().lines().filter(|l| l.starts_with("v ")) {
        let c: Vec<String> = line.split_whitespace().skip(1).map(str::to_string).collect();
        let c: [String; 3] = c.try_into().unwrap();
        assert!(read.contains(&as_f64(&c).map(f64::to_bits)), "{line} is not a vertex of the input");
        lines += 1;
    }
    assert_eq!(lines, near.positions.len());
}

#[test]
fn every_writer_puts_a_far_mesh_back_where_it_was() {
    let sphere = procedural::uv_sphere(8, 12);
    let (text, _) = far_obj(&sphere, UTM, 3.0);
    let far = Mesh::build(&io::load_bytes(text.as_bytes(), Format::Obj, None).unwrap(), BuildOptions::default())
        .unwrap()
        .to_indexed();
    let expected = absolute(&far);
    let dir = tempfile::tempdir().unwrap();
    for (name, format) in [("s.obj", WriteFormat::Obj), ("s.ply", WriteFormat::Ply), ("s.glb", WriteFormat::Glb)] {
        let path = dir.path().join(name);
        io::save_as(&path, &far, format).unwrap();
        let back = io::load(&path).unwrap();
        assert_ne!(back.origin, [0.0; 3], "{name}: read relative to its centre again");
        if format == WriteFormat::Glb {
            // The node's translation is the origin in full: back bit for bit.
            assert_eq!((back.origin, &back.positions), (far.origin, &far.positions));
        }
        assert_eq!(back.triangles, far.triangles, "{name}");
        for (a, b) in absolute(&back).iter().zip(&expected) {
            for k in 0..3 {
                // f32 relative to a 6 m diagonal: steps of 0.5 µm.
                assert!((a[k] - b[k]).abs() < 2e-6, "{name}: {a:?} against {b:?}");
            }
        }
    }
    let mut ply = Vec::new();
    io::write_ply(&mut ply, &far).unwrap();
    let header = String::from_utf8_lossy(&ply[..200]).to_string();
    assert!(header.contains("property double x"), "PLY positions in double: {header}");
}

#[test]
fn a_far_gltf_placement_keeps_its_precision() {
    // A 2 mm triangle placed by its node 4,123,456.789 m out: baked in f32 it would be a
    // point, and the translation read as f32 is 4,123,456.75.
    let mut bin = Vec::new();
    for p in [[0f32, 0., 0.], [0.002, 0., 0.], [0., 0.002, 0.]] {
        for c in p {
            bin.extend(c.to_le_bytes());
        }
    }
    let data = base64::engine::general_purpose::STANDARD.encode(&bin);
    let doc = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"mesh":0,"translation":[4123456.789,0,0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{data}"}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[0.002,0.002,0]}}]}}"#
    );
    let m = io::load_bytes(doc.as_bytes(), Format::Gltf, None).unwrap();
    // One translation and nothing else: it is the origin, read from the JSON in f64, and the
    // positions are the accessor's, bit for bit.
    assert_eq!(m.origin, [4_123_456.789, 0.0, 0.0]);
    assert_eq!(m.positions, vec![[0.0, 0.0, 0.0], [0.002, 0.0, 0.0], [0.0, 0.002, 0.0]]);
    let a = absolute(&m);
    assert!((a[1][0] - a[0][0] - 0.002).abs() < 1e-9, "{a:?}");
    Mesh::build(&m, BuildOptions::default().strict(true)).expect("one sound triangle, no repair");
    // Turned as well as moved: transformed in f64, relative to the centre to the millimetre.
    let turned =
        doc.replace(r#""translation":[4123456.789,0,0]"#, r#""translation":[4123456.789,0,0],"rotation":[0,0,1,0]"#);
    let m = io::load_bytes(turned.as_bytes(), Format::Gltf, None).unwrap();
    assert_eq!(m.origin, [4_123_456.788, -0.001, 0.0]);
    let a = absolute(&m);
    assert!((a[0][0] - a[1][0] - 0.002).abs() < 1e-9, "turned half a turn about z: {a:?}");
}

#[test]
fn hausdorff_measures_meshes_read_relative_to_different_origins_in_one_frame() {
    let torus = procedural::torus(24, 12);
    let (text, _) = far_obj(&torus, UTM, 1.0);
    let far = io::load_bytes(text.as_bytes(), Format::Obj, None).unwrap();
    // The same surface, relative to another origin a metre away.
    let mut moved = far.clone();
    moved.origin[0] += 1.0;
    moved.positions.iter_mut().for_each(|p| p[0] -= 1.0);
    let h = hausdorff(&far, &moved, HausdorffOptions::default());
    assert!(h.max < 1e-6, "the same surface: {h:?}");
    // Moved by 1.5 m along y, and nothing else: every sample is 1.5 m away, give or take the
    // torus' own extent along y.
    let mut shifted = far.clone();
    shifted.origin[1] += 1.5;
    let h = hausdorff(&far, &shifted, HausdorffOptions::default());
    assert!(h.max > 0.5 && h.max <= 1.5 + 1e-6, "{h:?}");
}

#[test]
fn a_mesh_near_its_origin_is_read_bit_for_bit_as_before() {
    let sphere = Mesh::build(&procedural::uv_sphere(6, 9), BuildOptions::default()).unwrap().to_indexed();
    let mut obj = Vec::new();
    io::write_obj(&mut obj, &sphere).unwrap();
    let back = io::load_bytes(&obj, Format::Obj, None).unwrap();
    assert_eq!(back.origin, [0.0; 3]);
    assert_eq!(back.positions, sphere.positions);
    // 16 diagonals out is still near: read as it is.
    let (text, _) = far_obj(&sphere, [30.0, 0.0, 0.0], 1.0);
    assert_eq!(io::load_bytes(text.as_bytes(), Format::Obj, None).unwrap().origin, [0.0; 3]);
}

#[test]
fn the_command_line_reads_eyes_in_the_file_coordinates_and_writes_them_back() {
    let dir = tempfile::tempdir().unwrap();
    let (text, _) = far_obj(&procedural::torus(32, 16), UTM, 10.0);
    let input = dir.path().join("site.obj");
    std::fs::write(&input, text).unwrap();
    let output = dir.path().join("site_lod.obj");
    let (code, out, err) = common::dynlod(&[
        "simplify",
        input.to_str().unwrap(),
        output.to_str().unwrap(),
        "--eye",
        "512345,4123456,400",
        "--pixel-error",
        "2",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let written = io::load(&output).unwrap();
    assert_eq!(v["origin"], serde_json::json!(written.origin), "read back relative to the same origin");
    assert!((0..3).all(|k| (written.origin[k] - UTM[k]).abs() <= 5.0), "{:?}: the centre, to 10 m", written.origin);
    assert!(v["output_triangles"].as_u64().unwrap() < v["input_triangles"].as_u64().unwrap());
    // An eye on the target is refused with the coordinates it was given in.
    let (code, _, err) = common::dynlod(&[
        "simplify",
        input.to_str().unwrap(),
        output.to_str().unwrap(),
        "--eye",
        "512345,4123456,100",
        "--target",
        "512345,4123456,100",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--eye 512345,4123456,100"), "{err}");
    let (code, out, _) = common::dynlod(&["info", input.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let lo = v["bbox_min"][1].as_f64().unwrap();
    assert!((lo - (4_123_456.0 - 13.0)).abs() < 0.01, "bounds in the file's coordinates: {lo}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases(32)))]

    /// However far a surface is moved, it welds into the same faces and its positions keep
    /// f32's precision relative to its own size.
    #[test]
    fn moving_a_surface_away_changes_nothing_but_its_origin(
        m in common::surfaces(),
        offset in prop::array::uniform3(-1e7f64..1e7),
    ) {
        let text = |offset: [f64; 3]| -> (String, Vec<[f64; 3]>) {
            let points: Vec<[f64; 3]> =
                m.positions.iter().map(|p| std::array::from_fn(|k| f64::from(p[k]) + offset[k])).collect();
            let faces = m.triangles.iter().map(|t| format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
            (points.iter().map(|p| format!("v {} {} {}\n", p[0], p[1], p[2])).chain(faces).collect(), points)
        };
        // Both through the same reader (tobj numbers vertices by first use).
        let near = Mesh::build(&io::load_bytes(text([0.0; 3]).0.as_bytes(), Format::Obj, None).unwrap(), BuildOptions::default()).unwrap();
        let (text, points) = text(offset);
        let far_input = io::load_bytes(text.as_bytes(), Format::Obj, None).unwrap();
        let far = Mesh::build(&far_input, BuildOptions::default()).unwrap();
        prop_assert_eq!(&far.topology.faces, &near.topology.faces);
        // The rule (`mesh/origin.rs`): moved when the farthest coordinate is more than 16
        // diagonals out.
        let lo: [f64; 3] = std::array::from_fn(|k| points.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min));
        let hi: [f64; 3] = std::array::from_fn(|k| points.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max));
        let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
        let farthest = (0..3).map(|k| lo[k].abs().max(hi[k].abs())).fold(0.0, f64::max);
        prop_assert_eq!(far.origin != [0.0; 3], farthest > 16.0 * diagonal, "{:?}", far.origin);
        for (p, q) in far.positions.iter().zip(&near.positions) {
            for k in 0..3 {
                let moved = f64::from(p[k]) + far.origin[k] - offset[k];
                prop_assert!((moved - f64::from(q[k])).abs() <= diagonal * 1e-5,
                    "{} against {}", moved, q[k]);
            }
        }
    }
}
