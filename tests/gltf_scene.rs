//! Scene-keeping glTF simplification (`dynlod::io::GltfScene`): a skinned, morphing mesh
//! beside a point primitive and an instanced mesh, built here, simplified by every offline
//! method, and read back with the `gltf` crate. The scene's nodes, skin, animation and points
//! come out as they went in; every vertex left keeps its joints, weights, `_ID` and morph
//! deltas bit for bit, in the source's component types.

use std::collections::HashMap;

use dynlod::io::GltfScene;
use dynlod::simplify::{simplify, simplify_scene, Method, SceneOptions, SceneTarget, SimplifyOptions};
use dynlod::{BuildOptions, IndexedMesh, Mesh};
use proptest::prelude::*;
use serde_json::json;

mod common;
use common::glb::{bytes, glb, pack};

/// The test scene: mesh 0 is an n×n grid over a bump, skinned to two joints (JOINTS_0 as
/// UNSIGNED_BYTE, WEIGHTS_0 as normalized UNSIGNED_SHORT), with a `_ID` (UNSIGNED_SHORT, the
/// vertex's own index) and one morph target, plus a point primitive; mesh 1, a smaller grid,
/// is drawn by two nodes. A skin, an animation and a camera complete it.
fn scene(n: usize) -> Vec<u8> {
    glb(scene_parts(n))
}

/// The JSON and buffer views of [`scene`].
fn scene_parts(n: usize) -> (serde_json::Value, Vec<Vec<u8>>) {
    let mut positions = Vec::new();
    let (mut normals, mut uvs, mut joints, mut weights, mut ids, mut deltas) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            let z = 0.2 * ((x * 3.1).sin() * (y * 2.3).cos());
            positions.push([x, y, z]);
            normals.push([0.0f32, 0.0, 1.0]);
            uvs.push([x, y]);
            joints.push([u8::from(x > 0.5), 1 - u8::from(x > 0.5), 0, 0]);
            let w = (y * 65535.0).round() as u16;
            weights.push([w, 65535 - w, 0, 0]);
            ids.push(positions.len() as u16 - 1);
            deltas.push([0.0f32, 0.0, x * y]);
        }
    }
    let mut indices: Vec<u16> = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = (j * (n + 1) + i) as u16;
            let (b, c, d) = (a + 1, a + (n + 1) as u16, a + (n + 2) as u16);
            indices.extend([a, b, d, a, d, c]);
        }
    }
    let small: Vec<[f32; 3]> = (0..9).map(|k| [(k % 3) as f32, (k / 3) as f32, ((k * 7) % 3) as f32 * 0.1]).collect();
    let small_idx: Vec<u16> = vec![0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7];
    let points: Vec<[f32; 3]> = vec![[2.0, 2.0, 2.0], [3.0, 2.0, 2.0]];
    let ibm: Vec<f32> = [glam::Mat4::IDENTITY, glam::Mat4::from_translation(glam::Vec3::X)]
        .iter()
        .flat_map(|m| m.to_cols_array())
        .collect();
    let times = [0.0f32, 1.0];
    let rotations =
        [[0.0f32, 0.0, 0.0, 1.0], [0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2, std::f32::consts::FRAC_1_SQRT_2]];
    let v = positions.len();
    let chunks = vec![
        bytes(&positions.concat(), f32::to_le_bytes),
        bytes(&normals.concat(), f32::to_le_bytes),
        bytes(&uvs.concat(), f32::to_le_bytes),
        joints.concat(),
        bytes(&weights.concat(), u16::to_le_bytes),
        bytes(&ids, u16::to_le_bytes),
        bytes(&deltas.concat(), f32::to_le_bytes),
        bytes(&indices, u16::to_le_bytes),
        bytes(&points.concat(), f32::to_le_bytes),
        bytes(&small.concat(), f32::to_le_bytes),
        bytes(&small_idx, u16::to_le_bytes),
        bytes(&ibm, f32::to_le_bytes),
        bytes(&times, f32::to_le_bytes),
        bytes(&rotations.concat(), f32::to_le_bytes),
    ];
    let lo_hi = |p: &[[f32; 3]]| {
        let lo: Vec<f32> = (0..3).map(|k| p.iter().map(|q| q[k]).fold(f32::INFINITY, f32::min)).collect();
        let hi: Vec<f32> = (0..3).map(|k| p.iter().map(|q| q[k]).fold(f32::NEG_INFINITY, f32::max)).collect();
        (lo, hi)
    };
    let ((plo, phi), (dlo, dhi), (xlo, xhi), (slo, shi)) =
        (lo_hi(&positions), lo_hi(&deltas), lo_hi(&points), lo_hi(&small));
    let doc = json!({
        "asset": {"version": "2.0", "generator": "dynlod test"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 3, 4]}],
        "nodes": [
            {"mesh": 0, "skin": 0, "name": "body"},
            {"name": "root", "children": [2]},
            {"name": "arm", "translation": [1.0, 0.0, 0.0]},
            {"mesh": 1, "translation": [5.0, 0.0, 0.0]},
            {"mesh": 1, "translation": [9.0, 0.0, 0.0], "scale": [2.0, 2.0, 2.0], "camera": 0},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "skins": [{"joints": [1, 2], "inverseBindMatrices": 11}],
        "animations": [{"channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}],
                        "samplers": [{"input": 12, "output": 13}]}],
        "meshes": [
            {"name": "skinned", "weights": [0.5], "primitives": [
                {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "JOINTS_0": 3, "WEIGHTS_0": 4, "_ID": 5},
                 "targets": [{"POSITION": 6}], "indices": 7},
                {"attributes": {"POSITION": 8}, "mode": 0},
            ]},
            {"name": "instanced", "primitives": [{"attributes": {"POSITION": 9}, "indices": 10}]},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": v, "type": "VEC3", "min": plo, "max": phi},
            {"bufferView": 1, "componentType": 5126, "count": v, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": v, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5121, "count": v, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5123, "normalized": true, "count": v, "type": "VEC4"},
            {"bufferView": 5, "componentType": 5123, "count": v, "type": "SCALAR"},
            {"bufferView": 6, "componentType": 5126, "count": v, "type": "VEC3", "min": dlo, "max": dhi},
            {"bufferView": 7, "componentType": 5123, "count": indices.len(), "type": "SCALAR"},
            {"bufferView": 8, "componentType": 5126, "count": 2, "type": "VEC3", "min": xlo, "max": xhi},
            {"bufferView": 9, "componentType": 5126, "count": 9, "type": "VEC3", "min": slo, "max": shi},
            {"bufferView": 10, "componentType": 5123, "count": small_idx.len(), "type": "SCALAR"},
            {"bufferView": 11, "componentType": 5126, "count": 2, "type": "MAT4"},
            {"bufferView": 12, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]},
            {"bufferView": 13, "componentType": 5126, "count": 2, "type": "VEC4"},
        ],
    });
    (doc, chunks)
}

/// Every mesh of `scene` through `method` to `ratio` of its triangles.
fn simplified(scene: &GltfScene, method: Method, ratio: f64) -> Vec<IndexedMesh> {
    scene
        .meshes
        .iter()
        .map(|sm| {
            let mut m = Mesh::build(&sm.mesh, BuildOptions::default()).unwrap();
            let target = (m.topology.live_face_count() as f64 * ratio).round() as usize;
            simplify(&mut m, SimplifyOptions::default().method(method).target_triangles(target));
            m.to_indexed()
        })
        .collect()
}

/// The values of an accessor as u32/f32 bit patterns per element, with its component type:
/// what the `gltf` crate reads, not what dynlod does.
fn accessor(doc: &gltf::Document, blob: &[u8], index: usize) -> (u32, Vec<Vec<u32>>) {
    let a = doc.accessors().nth(index).unwrap();
    let view = a.view().unwrap();
    let size = a.size();
    let stride = view.stride().unwrap_or(size);
    let width = a.data_type().size();
    let start = view.offset() + a.offset();
    let elements = (0..a.count())
        .map(|e| {
            let at = start + e * stride;
            (0..a.dimensions().multiplicity())
                .map(|c| {
                    let b = &blob[at + c * width..at + (c + 1) * width];
                    match width {
                        1 => b[0] as u32,
                        2 => u16::from_le_bytes([b[0], b[1]]) as u32,
                        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                    }
                })
                .collect()
        })
        .collect();
    (a.data_type().as_gl_enum(), elements)
}

/// An accessor of a parsed GLB, as [`accessor`] reads it.
fn accessor_values(g: &gltf::Gltf, index: usize) -> (u32, Vec<Vec<u32>>) {
    accessor(&g.document, g.blob.as_deref().unwrap(), index)
}

/// A primitive's attribute accessors by name (targets as `T0:POSITION`).
fn attributes(prim: &serde_json::Value) -> HashMap<String, usize> {
    let mut out: HashMap<String, usize> = prim["attributes"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.clone(), v.as_u64().unwrap() as usize))
        .collect();
    for (t, target) in prim["targets"].as_array().into_iter().flatten().enumerate() {
        for (k, v) in target.as_object().unwrap() {
            out.insert(format!("T{t}:{k}"), v.as_u64().unwrap() as usize);
        }
    }
    out
}

/// Checks `out` (a GLB written from `source`) keeps the scene and, vertex by vertex, every
/// attribute the source had at the same position, bit for bit and in the same component
/// type. Returns the triangles of mesh 0's first primitive.
fn check_kept(source: &[u8], out: &[u8]) -> usize {
    let (a, b) = (gltf::Gltf::from_slice(source).unwrap(), gltf::Gltf::from_slice(out).unwrap());
    let (ja, jb) =
        (serde_json::to_value(a.document.as_json()).unwrap(), serde_json::to_value(b.document.as_json()).unwrap());
    for key in ["nodes", "skins", "animations", "cameras", "scenes"] {
        let (x, y) = (&ja[key], &jb[key]);
        if key == "skins" || key == "animations" {
            assert_eq!(x.as_array().map(Vec::len), y.as_array().map(Vec::len), "{key}");
        } else {
            assert_eq!(x, y, "{key}");
        }
    }
    assert_eq!(ja["meshes"][0]["weights"], jb["meshes"][0]["weights"]);
    let (ba, bb) = (a.blob.as_deref().unwrap(), b.blob.as_deref().unwrap());
    // Skin and animation data, read through their (renumbered) accessors.
    let same = |pa: &serde_json::Value, pb: &serde_json::Value| {
        let (x, y) = (pa.as_u64().unwrap() as usize, pb.as_u64().unwrap() as usize);
        assert_eq!(accessor(&a.document, ba, x), accessor(&b.document, bb, y));
    };
    same(&ja["skins"][0]["inverseBindMatrices"], &jb["skins"][0]["inverseBindMatrices"]);
    same(&ja["animations"][0]["samplers"][0]["input"], &jb["animations"][0]["samplers"][0]["input"]);
    same(&ja["animations"][0]["samplers"][0]["output"], &jb["animations"][0]["samplers"][0]["output"]);
    // The point primitive, as it was.
    let (pa, pb) = (&ja["meshes"][0]["primitives"][1], &jb["meshes"][0]["primitives"][1]);
    assert_eq!(pb["mode"], 0);
    same(&pa["attributes"]["POSITION"], &pb["attributes"]["POSITION"]);
    // The skinned primitive: every vertex left is a source vertex, all its attributes kept.
    let (pa, pb) = (&ja["meshes"][0]["primitives"][0], &jb["meshes"][0]["primitives"][0]);
    let (aa, ab) = (attributes(pa), attributes(pb));
    let mut names: Vec<&String> = aa.keys().collect();
    names.sort();
    let mut names_b: Vec<&String> = ab.keys().collect();
    names_b.sort();
    assert_eq!(names, names_b);
    let read = |doc, blob, map: &HashMap<String, usize>| -> HashMap<String, (u32, Vec<Vec<u32>>)> {
        map.iter().map(|(k, &i)| (k.clone(), accessor(doc, blob, i))).collect()
    };
    let (va, vb) = (read(&a.document, ba, &aa), read(&b.document, bb, &ab));
    // Positions as keys, -0.0 as +0.0 (welding makes them one).
    let key = |p: &Vec<u32>| -> Vec<u32> { p.iter().map(|&c| if c == 0x8000_0000 { 0 } else { c }).collect() };
    let by_position: HashMap<Vec<u32>, usize> = va["POSITION"].1.iter().enumerate().map(|(i, p)| (key(p), i)).collect();
    for (k, (ty, values)) in &vb {
        assert_eq!(*ty, va[k].0, "{k}: component type");
        for (i, p) in vb["POSITION"].1.iter().enumerate() {
            let Some(&s) = by_position.get(&key(p)) else {
                panic!("{k}: vertex {i} at {p:?} is at no source vertex's position");
            };
            if k == "NORMAL" || k == "POSITION" {
                continue; // normals written as unit vectors (these are); positions matched above
            }
            assert_eq!(values[i], va[k].1[s], "{k} of vertex {i} (source vertex {s})");
        }
    }
    let (_, idx) = accessor(&b.document, bb, pb["indices"].as_u64().unwrap() as usize);
    assert_eq!(
        b.document.accessors().nth(pb["indices"].as_u64().unwrap() as usize).unwrap().data_type().as_gl_enum(),
        5123
    );
    idx.len() / 3
}

#[test]
fn a_kept_scene_keeps_its_skin_animation_points_and_every_vertex_attribute() {
    let source = scene(16);
    let s = GltfScene::from_bytes(&source, None).unwrap();
    assert_eq!(s.meshes.len(), 2);
    assert_eq!((s.meshes[0].instances, s.meshes[1].instances), (1, 2));
    assert_eq!((s.meshes[0].scale, s.meshes[1].scale), (1.0, 2.0), "the largest node scale drawing each");
    let mut semantics: Vec<&str> = s.meshes[0].mesh.attributes.iter().map(|a| a.semantic.as_str()).collect();
    semantics.sort();
    assert_eq!(semantics, ["JOINTS_0", "TARGET0:POSITION", "WEIGHTS_0", "_ID"]);
    for method in Method::ALL {
        let out = simplified(&s, method, 0.25);
        let mut bytes = Vec::new();
        let notes = s.write_glb(&mut bytes, &out).unwrap();
        assert!(notes.is_empty(), "{notes:?}");
        let triangles = check_kept(&source, &bytes);
        assert!(triangles < 2 * 16 * 16 / 2, "{method:?}: {triangles} triangles left of 512");
        // The output reads back as a scene, and flattened, as any glTF.
        let again = GltfScene::from_bytes(&bytes, None).unwrap();
        assert_eq!(again.meshes[0].mesh.triangles.len(), triangles);
        let flat = dynlod::io::load_bytes(&bytes, dynlod::io::Format::Glb, None).unwrap();
        assert_eq!(flat.triangles.len(), triangles + 2 * again.meshes[1].mesh.triangles.len());
    }
}

#[test]
fn the_writer_leaves_out_the_source_vertex_data_it_replaced() {
    let source = scene(24);
    let s = GltfScene::from_bytes(&source, None).unwrap();
    let mut small = Vec::new();
    s.write_glb(&mut small, &simplified(&s, Method::Qem, 0.1)).unwrap();
    let mut same = Vec::new();
    s.write_glb(&mut same, &simplified(&s, Method::Qem, 1.0)).unwrap();
    // Simplified to 10 %, the file is far smaller than the source; unsimplified, it is about
    // as large (float weights and no shared vertex arrays aside).
    assert!(small.len() * 3 < source.len(), "{} of {}", small.len(), source.len());
    assert!(same.len() < source.len() * 2, "{} of {}", same.len(), source.len());
}

#[test]
fn a_mesh_left_without_triangles_or_a_wrong_mesh_count_is_an_error_and_writes_nothing() {
    let s = GltfScene::from_bytes(&scene(4), None).unwrap();
    let mut out = simplified(&s, Method::Qem, 0.5);
    let mut bytes = Vec::new();
    let e = s.write_glb(&mut bytes, &out[..1]).unwrap_err();
    assert!(e.to_string().contains("1 meshes given for a scene of 2"), "{e}");
    out[1].triangles.clear();
    let e = s.write_glb(&mut bytes, &out).unwrap_err();
    assert!(e.to_string().contains("mesh 1 (instanced) has no triangles left"), "{e}");
    assert!(bytes.is_empty());
    // A path's old content survives a failed save.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.glb");
    std::fs::write(&path, b"old").unwrap();
    assert!(s.save(&path, &out).is_err());
    assert_eq!(std::fs::read(&path).unwrap(), b"old");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases(12)))]

    /// Whatever the grid, method and ratio, every vertex left keeps its source's attributes
    /// and the scene around it stays.
    #[test]
    fn every_vertex_left_keeps_its_attributes(n in 3usize..14, method in 0usize..5, ratio in 0.05f64..1.0) {
        let source = scene(n);
        let s = GltfScene::from_bytes(&source, None).unwrap();
        let out = simplified(&s, Method::ALL[method], ratio);
        let mut bytes = Vec::new();
        s.write_glb(&mut bytes, &out).unwrap();
        check_kept(&source, &bytes);
        // The same through the one-call library path, which allots the target by error.
        let engine = SimplifyOptions::default().method(Method::ALL[method]);
        let lod = simplify_scene(&s, &engine, SceneOptions::default().target(SceneTarget::Ratio(ratio))).unwrap();
        bytes.clear();
        s.write_glb(&mut bytes, &lod.meshes).unwrap();
        check_kept(&source, &bytes);
    }
}

/// `simplify_scene` is the recipe of examples/scene_lod.rs in one call: the baked scene
/// simplified first, each mesh to the share that run left it. Same meshes, bit for bit.
#[test]
fn simplify_scene_gives_each_mesh_what_the_baked_scene_left_it() {
    let s = GltfScene::from_bytes(&scene(20), None).unwrap();
    let engine = SimplifyOptions::default().method(Method::Qem);
    let lod = simplify_scene(&s, &engine, SceneOptions::default().target(SceneTarget::Ratio(0.25))).unwrap();
    let mut flat = Mesh::build(&s.flattened().unwrap(), BuildOptions::default()).unwrap();
    let drawn = flat.topology.live_face_count();
    assert_eq!(lod.drawn_input_triangles(), drawn, "800 + 2 x 8 triangles drawn");
    simplify(&mut flat, engine.target_triangles((drawn as f64 * 0.25).round() as usize));
    let shares = s.allot(&flat);
    for ((sm, share), (r, out)) in s.meshes.iter().zip(&shares).zip(lod.reports.iter().zip(&lod.meshes)) {
        assert_eq!(r.target, *share, "{}", sm.label());
        let mut m = Mesh::build(&sm.mesh, BuildOptions::default()).unwrap();
        let stats = simplify(&mut m, engine.target_triangles(share.unwrap()));
        assert_eq!((r.stats.output_triangles, r.output_triangles), (stats.output_triangles, out.triangles.len()));
        assert_eq!(m.to_indexed(), *out, "{}", sm.label());
    }
    assert!(lod.drawn_output_triangles() <= (drawn as f64 * 0.25).round() as usize + 2);
    // The point primitive is written back, not skipped: no repair to report.
    assert!(lod.notes.is_empty(), "{:?}", lod.notes);
}

/// Meshes run as parallel tasks; the file is the same on one thread and on four, and a
/// triangle count is met in drawn triangles.
#[test]
fn simplify_scene_gives_the_same_file_on_any_thread_count() {
    let s = GltfScene::from_bytes(&scene(24), None).unwrap();
    let file = |threads: usize, method: Method| {
        common::on_threads(threads, || {
            let engine = SimplifyOptions::default().method(method);
            let options = SceneOptions::default().target(SceneTarget::Triangles(300));
            let lod = simplify_scene(&s, &engine, options).unwrap();
            assert!(lod.drawn_output_triangles() <= 300, "{method:?}: {}", lod.drawn_output_triangles());
            let mut bytes = Vec::new();
            s.write_glb(&mut bytes, &lod.meshes).unwrap();
            bytes
        })
    };
    for method in Method::ALL {
        assert_eq!(file(1, method), file(4, method), "{method:?}");
    }
}

/// An error bound is in the scene's units: the skinned grid, drawn here at scale 3, gets a
/// third of it. A locked border stays whole, and a ratio outside 0..1 is refused.
#[test]
fn simplify_scene_scales_the_error_bound_locks_borders_and_refuses_bad_ratios() {
    let (mut doc, chunks) = scene_parts(20);
    doc["nodes"][0]["scale"] = json!([3.0, 3.0, 3.0]);
    let s = GltfScene::from_bytes(&glb((doc, chunks)), None).unwrap();
    assert_eq!(s.meshes[0].scale, 3.0);
    let bound = 0.003;
    let engine = SimplifyOptions::default().method(Method::Qem).max_error(bound);
    let lod = simplify_scene(&s, &engine, SceneOptions::default()).unwrap();
    let grid = &lod.reports[0];
    assert_eq!(grid.target, None);
    assert!(grid.stats.max_error <= bound / 3.0, "{} > {bound} / 3", grid.stats.max_error);
    assert!(grid.output_triangles < grid.input_triangles);
    // The grid alone, with the bound unscaled, goes further: the scale made a difference.
    let mut alone = Mesh::build(&s.meshes[0].mesh, BuildOptions::default()).unwrap();
    let loose = simplify(&mut alone, engine);
    assert!(loose.max_error > bound / 3.0, "{}", loose.max_error);
    assert!(loose.output_triangles < grid.output_triangles);

    let border = |m: &IndexedMesh| -> usize {
        let built = Mesh::build(m, BuildOptions::default()).unwrap();
        let t = &built.topology;
        (0..built.positions.len() as u32).filter(|&v| dynlod::topology::HalfEdges::is_boundary_vertex(t, v)).count()
    };
    let options = SceneOptions::default().target(SceneTarget::Ratio(0.05)).lock_border(true);
    let locked = simplify_scene(&s, &engine.max_error(f64::INFINITY), options).unwrap();
    assert_eq!(border(&locked.meshes[0]), 4 * 20, "the grid's whole border is kept");
    let free = simplify_scene(&s, &engine.max_error(f64::INFINITY), options.lock_border(false)).unwrap();
    assert!(border(&free.meshes[0]) < 4 * 20);

    for r in [-0.1, 1.5, f64::NAN] {
        let e = simplify_scene(&s, &engine, SceneOptions::default().target(SceneTarget::Ratio(r))).unwrap_err();
        assert!(matches!(e, dynlod::SceneError::Ratio(_)), "{e}");
    }
}

/// EXT_mesh_gpu_instancing's transforms (accessors a node's extension names) are copied and
/// renumbered; an extension this writer does not know keeps every source accessor and view
/// where it was, with a note, since it could name any of them.
#[test]
fn instancing_transforms_are_kept_and_unknown_extensions_keep_all_source_data() {
    let (mut doc, mut chunks) = scene_parts(12);
    chunks.push(bytes(&[0.0f32, 0.0, 0.0, 0.0, 3.0, 0.0], f32::to_le_bytes));
    let view = chunks.len() - 1;
    doc["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({"bufferView": view, "componentType": 5126, "count": 2, "type": "VEC3"}));
    let accessor = doc["accessors"].as_array().unwrap().len() - 1;
    doc["nodes"][3]["extensions"] = json!({"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": accessor}}});
    doc["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
    let source = glb((doc.clone(), chunks.clone()));
    let s = GltfScene::from_bytes(&source, None).unwrap();
    let mut out = Vec::new();
    assert!(s.write_glb(&mut out, &simplified(&s, Method::Qem, 0.3)).unwrap().is_empty());
    let (a, b) = (gltf::Gltf::from_slice(&source).unwrap(), gltf::Gltf::from_slice(&out).unwrap());
    let container = gltf::binary::Glb::from_slice(&out).unwrap();
    let jb: serde_json::Value = serde_json::from_slice(&container.json).unwrap();
    let index = jb["nodes"][3]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"].as_u64().unwrap();
    assert_eq!(
        accessor_values(&a, accessor),
        accessor_values(&b, index as usize),
        "the instancing transforms, through their renumbered accessor"
    );
    // An unknown extension: the source's accessors all stay, at their indices.
    doc["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing", "XYZ_unknown"]);
    let unknown = glb((doc, chunks));
    let s = GltfScene::from_bytes(&unknown, None).unwrap();
    let mut kept = Vec::new();
    let notes = s.write_glb(&mut kept, &simplified(&s, Method::Qem, 0.3)).unwrap();
    assert!(notes.len() == 1 && notes[0].contains("XYZ_unknown"), "{notes:?}");
    let k = gltf::Gltf::from_slice(&kept).unwrap();
    for i in 0..a.document.accessors().len() {
        assert_eq!(accessor_values(&a, i), accessor_values(&k, i), "accessor {i}");
    }
    assert!(kept.len() > out.len() + source.len() / 2, "{} against {}", kept.len(), out.len());
}

/// A `.gltf` whose buffer and image are files beside it: the GLB holds both.
#[test]
fn a_gltf_with_external_files_becomes_one_self_contained_glb() {
    let dir = tempfile::tempdir().unwrap();
    let (mut doc, chunks) = scene_parts(8);
    let png = b"\x89PNG\r\n\x1a\nnot really an image".to_vec();
    doc["images"] = json!([{"uri": "tex%20one.png"}]);
    doc["textures"] = json!([{"source": 0}]);
    doc["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    let (mut doc, bin) = pack(doc, &chunks);
    doc["buffers"][0]["uri"] = json!("scene.bin");
    std::fs::write(dir.path().join("scene.bin"), &bin).unwrap();
    std::fs::write(dir.path().join("tex one.png"), &png).unwrap();
    let path = dir.path().join("scene.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let s = GltfScene::load(&path).unwrap();
    let out_path = dir.path().join("out/lod.glb");
    std::fs::create_dir(dir.path().join("out")).unwrap();
    assert!(s.save(&out_path, &simplified(&s, Method::Qem, 0.5)).unwrap().is_empty());
    let g = gltf::Gltf::open(&out_path).unwrap();
    let image = g.images().next().unwrap();
    let gltf::image::Source::View { view, mime_type } = image.source() else { panic!("the image is not embedded") };
    assert_eq!(mime_type, "image/png");
    let blob = g.blob.as_deref().unwrap();
    assert_eq!(&blob[view.offset()..view.offset() + view.length()], &png[..]);
    assert!(g.buffers().all(|b| matches!(b.source(), gltf::buffer::Source::Bin)));
    assert_eq!(g.meshes().next().unwrap().primitives().next().unwrap().material().index(), Some(0));
}
