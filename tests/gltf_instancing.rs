//! `EXT_mesh_gpu_instancing` (src/io/gltf_instancing.rs): a node drawing its mesh once per
//! instance reads as the same scene written with one node per instance, through a flattening
//! load and a scene-keeping one; gltfpack's `-mi` output reads as the scene it was made from;
//! a malformed extension is an error naming the node; a file asking for more vertices than a
//! mesh holds is refused before anything is read.

mod common;

use std::path::PathBuf;

use common::glb::{bytes, glb};
use dynlod::io::{self, Format, GltfScene};
use dynlod::mesh::NotKeptKind;
use dynlod::{BuildOptions, IndexedMesh, LoadErrorKind, Mesh};
use glam::{Quat, Vec3};
use serde_json::{json, Value};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

/// A tetrahedron (closed, so its signed volume shows a face turned inside out) and a
/// triangle, as a scene: node 0, under `parent`'s transform, draws the tetrahedron, and its
/// child node 1 the triangle. `instances` are (translation, rotation as normalized SHORTs,
/// scale): with `as_nodes`, written as child nodes of node 0 drawing the tetrahedron, walked
/// before node 1 (the reference); else as node 0's `EXT_mesh_gpu_instancing`, with an `_ID` attribute beside.
fn scene(instances: &[([f32; 3], [i16; 4], [f32; 3])], as_nodes: bool) -> (Value, Vec<Vec<u8>>) {
    let tetra = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let tetra_faces = [0u16, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
    let tri = [[0.0f32, 0.0, 5.0], [1.0, 0.0, 5.0], [0.0, 1.0, 5.0]];
    let bounds = |p: &[[f32; 3]]| dynlod::mesh::bounds(p.iter().copied());
    let ((tlo, thi), (rlo, rhi)) = (bounds(&tetra), bounds(&tri));
    let mut chunks = vec![
        bytes(&tetra.concat(), f32::to_le_bytes),
        bytes(&tetra_faces, u16::to_le_bytes),
        bytes(&tri.concat(), f32::to_le_bytes),
        bytes(&[0u16, 1, 2], u16::to_le_bytes),
    ];
    let mut accessors = vec![
        json!({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": tlo, "max": thi}),
        json!({"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}),
        json!({"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3", "min": rlo, "max": rhi}),
        json!({"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}),
    ];
    let parent =
        json!({"translation": [0.5, -1.0, 2.0], "rotation": [0.0, 0.38268343, 0.0, 0.9238795], "children": [1]});
    let mut nodes = vec![parent, json!({"mesh": 1, "translation": [0.0, 0.0, 1.0]})];
    if as_nodes {
        for (t, r, s) in instances {
            let q = Quat::from_array(r.map(|c| (f32::from(c) / 32767.0).max(-1.0))).normalize();
            nodes.push(json!({"mesh": 0, "translation": t, "rotation": q.to_array(), "scale": s}));
            let child = nodes.len() - 1;
            nodes[0]["children"].as_array_mut().unwrap().insert(child - 2, json!(child));
        }
    } else {
        let n = instances.len();
        let mut add = |chunk: Vec<u8>, accessor: Value| {
            chunks.push(chunk);
            let mut a = accessor;
            a["bufferView"] = json!(chunks.len() - 1);
            a["count"] = json!(n);
            accessors.push(a);
            accessors.len() - 1
        };
        let t: Vec<f32> = instances.iter().flat_map(|i| i.0).collect();
        let r: Vec<i16> = instances.iter().flat_map(|i| i.1).collect();
        let s: Vec<f32> = instances.iter().flat_map(|i| i.2).collect();
        let ids: Vec<f32> = (0..n).map(|k| k as f32).collect();
        let attributes = json!({
            "TRANSLATION": add(bytes(&t, f32::to_le_bytes), json!({"componentType": 5126, "type": "VEC3"})),
            "ROTATION": add(bytes(&r, i16::to_le_bytes), json!({"componentType": 5122, "type": "VEC4", "normalized": true})),
            "SCALE": add(bytes(&s, f32::to_le_bytes), json!({"componentType": 5126, "type": "VEC3"})),
            "_ID": add(bytes(&ids, f32::to_le_bytes), json!({"componentType": 5126, "type": "SCALAR"})),
        });
        nodes[0]["mesh"] = json!(0);
        nodes[0]["extensions"] = json!({"EXT_mesh_gpu_instancing": {"attributes": attributes}});
    }
    let mut doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": nodes,
        "meshes": [
            {"name": "tetra", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]},
            {"name": "tri", "primitives": [{"attributes": {"POSITION": 2}, "indices": 3}]},
        ],
        "accessors": accessors,
    });
    if !as_nodes {
        doc["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
        doc["extensionsRequired"] = json!(["EXT_mesh_gpu_instancing"]);
    }
    (doc, chunks)
}

/// Three instances: in place; moved, turned a quarter about z and halved; moved, turned half
/// about x and mirrored in x.
const INSTANCES: [([f32; 3], [i16; 4], [f32; 3]); 3] = [
    ([0.0, 0.0, 0.0], [0, 0, 0, 32767], [1.0, 1.0, 1.0]),
    ([2.0, 0.0, 0.0], [0, 0, 23170, 23170], [0.5, 0.5, 0.5]),
    ([0.0, 3.0, 0.0], [32767, 0, 0, 0], [-1.0, 1.0, 1.0]),
];

fn load(file: &[u8]) -> Result<IndexedMesh, LoadErrorKind> {
    io::load_bytes(file, Format::Glb, None)
}

fn signed_volume(m: &IndexedMesh) -> f64 {
    let p = |v: u32| Vec3::from(m.positions[v as usize]).as_dvec3();
    m.triangles.iter().map(|t| p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0).sum()
}

fn flattened_scene_note(m: &IndexedMesh) -> (usize, String) {
    let n = m.not_kept.iter().find(|n| n.kind == NotKeptKind::FlattenedScene).expect("a flattened-scene note");
    (n.count, n.detail.clone())
}

#[test]
fn instances_read_as_the_nodes_they_stand_for() {
    let reference = load(&glb(scene(&INSTANCES, true))).unwrap();
    let instanced = load(&glb(scene(&INSTANCES, false))).unwrap();
    assert_eq!(instanced.triangles, reference.triangles, "the same triangles, each mirrored one turned back");
    assert_eq!(instanced.positions.len(), reference.positions.len());
    for (k, (a, b)) in instanced.positions.iter().zip(&reference.positions).enumerate() {
        assert!(Vec3::from(*a).distance(Vec3::from(*b)) < 1e-5, "vertex {k}: {a:?} against {b:?}");
    }
    // Every tetrahedron faces out: 1/6 each, the halved one 1/8 of that.
    let volume = signed_volume(&instanced) - signed_volume(&load(&glb(scene(&INSTANCES[..0], true))).unwrap());
    assert!((volume - (1.0 + 0.125 + 1.0) / 6.0).abs() < 1e-5, "{volume}");
    // The triangle (node 1, the instanced node's child) is drawn once.
    assert_eq!(instanced.triangles.len(), 3 * 4 + 1);
    let (count, detail) = flattened_scene_note(&instanced);
    assert_eq!(count, 4, "{detail}");
    assert!(
        detail.contains("2 nodes; 3 EXT_mesh_gpu_instancing instances (their attributes _ID not kept)"),
        "{detail}"
    );
    assert!(instanced.not_kept.iter().all(|n| n.kind != NotKeptKind::Extensions), "{:?}", instanced.not_kept);

    // Used, not required: read all the same (it was drawn once per node before, silently
    // wrong).
    let (mut doc, chunks) = scene(&INSTANCES, false);
    doc.as_object_mut().unwrap().remove("extensionsRequired");
    assert_eq!(load(&glb((doc, chunks))).unwrap().positions, instanced.positions);
}

#[test]
fn a_scene_keeping_load_places_the_mesh_once_per_instance() {
    let file = glb(scene(&INSTANCES, false));
    let s = GltfScene::from_bytes(&file, None).unwrap();
    let tetra = &s.meshes[0];
    assert_eq!((tetra.instances, tetra.placements.len()), (3, 3));
    let labels: Vec<String> = tetra.placements.iter().enumerate().map(|(k, p)| p.label(k)).collect();
    assert_eq!(labels, ["node 0 instance 0", "node 0 instance 1", "node 0 instance 2"]);
    let reference = GltfScene::from_bytes(&glb(scene(&INSTANCES, true)), None).unwrap();
    for (p, q) in tetra.placements.iter().zip(&reference.meshes[0].placements) {
        let (a, b) = (glam::Mat4::from_cols_array_2d(&p.world), glam::Mat4::from_cols_array_2d(&q.world));
        assert!(a.abs_diff_eq(b, 1e-6), "{a} against {b}");
    }
    assert_eq!((s.meshes[1].instances, s.meshes[1].placements[0].instance), (1, None));

    // Built and written again: the instancing stays, and draws the new mesh three times.
    let meshes: Vec<IndexedMesh> =
        s.meshes.iter().map(|sm| Mesh::build(&sm.mesh, BuildOptions::default()).unwrap().to_indexed()).collect();
    let mut out = Vec::new();
    assert!(s.write_glb(&mut out, &meshes).unwrap().is_empty());
    let written = load(&out).unwrap();
    assert_eq!(written.triangles.len(), 3 * 4 + 1);
    assert!((signed_volume(&written) - signed_volume(&load(&file).unwrap())).abs() < 1e-6);
}

/// A change to a scene's JSON and binary chunks.
type Edit = dyn Fn(&mut Value, &mut Vec<Vec<u8>>);

#[test]
fn a_malformed_instancing_extension_is_an_error_naming_the_node() {
    let broken = |edit: &Edit| {
        let (mut doc, mut chunks) = scene(&INSTANCES, false);
        edit(&mut doc, &mut chunks);
        load(&glb((doc, chunks))).unwrap_err().to_string()
    };
    let attributes = "/nodes/0/extensions/EXT_mesh_gpu_instancing/attributes";
    let cases: [(&str, &Edit); 6] = [
        ("node 0: EXT_mesh_gpu_instancing has no attributes", &|d, _| *d.pointer_mut(attributes).unwrap() = json!({})),
        ("attribute SCALE names accessor 99, which does not exist", &|d, _| {
            d.pointer_mut(attributes).unwrap()["SCALE"] = json!(99)
        }),
        ("ROTATION accessor 5 is VEC3 of SHORT", &|d, _| d["accessors"][5]["type"] = json!("VEC3")),
        ("attributes have different counts: ROTATION 3, SCALE 2", &|d, _| d["accessors"][6]["count"] = json!(2)),
        ("instance 1: its ROTATION has length 0", &|_, c| c[5][8..16].fill(0)),
        ("instance 2: its TRANSLATION is not finite", &|_, c| c[4][24..28].copy_from_slice(&f32::NAN.to_le_bytes())),
    ];
    for (expected, edit) in cases {
        let e = broken(edit);
        assert!(e.contains(expected) && e.contains("node 0"), "{e}\n expected: {expected}");
    }
}

/// A million instances of a mesh of a million vertices, from a few bytes of JSON over a
/// zeroed megabyte (view-less sparse accessors): refused by count, before anything is read.
#[test]
fn a_scene_drawing_more_vertices_than_a_mesh_holds_is_refused_before_reading() {
    let (mut doc, mut chunks) = scene(&INSTANCES, false);
    chunks.push(vec![0; 1 << 20]);
    let sparse = |count: usize| {
        json!({"componentType": 5126, "type": "VEC3", "count": count, "min": [0, 0, 0], "max": [1, 1, 1],
               "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 0}}})
    };
    doc["accessors"][0] = sparse(1_000_000);
    doc["accessors"][4] = sparse(1_000_000);
    for k in [5, 6, 7] {
        doc["accessors"][k]["count"] = json!(1_000_000);
    }
    let e = load(&glb((doc, chunks))).unwrap_err();
    assert!(e.to_string().contains("vertex count 1000000000000 exceeds the u32 id range"), "{e}");
}

/// Every vertex of `a` within `tolerance` of one of `b`'s (brute force: small meshes).
fn farthest_from(a: &Mesh, b: &Mesh) -> f32 {
    let nearest =
        |p: &[f32; 3]| b.positions.iter().map(|q| Vec3::from(*p).distance(Vec3::from(*q))).fold(f32::MAX, f32::min);
    a.positions.iter().map(nearest).fold(0.0, f32::max)
}

/// gltfpack's `-mi` (and `-mi -cc`, the instance transforms compressed through meshopt's
/// filters) of a scene reads as that scene: the same triangles and vertices after welding,
/// each vertex within gltfpack's quantisation of the source's, and the same signed volume:
/// every egg turned the source's way (one is mirrored, whose winding a reader must reverse).
#[test]
fn gltfpack_instancing_reads_as_the_scene_it_was_made_from() {
    let build = |m: IndexedMesh| Mesh::build(&m, BuildOptions::default()).unwrap();
    let source_raw = io::load(data("instancing_source.gltf")).unwrap();
    let volume = signed_volume(&source_raw);
    let source = build(source_raw);
    let diagonal = {
        let (lo, hi) = dynlod::mesh::bounds(source.positions.iter().copied());
        Vec3::from(hi).distance(Vec3::from(lo))
    };
    for (file, tolerance) in [("instancing_gltfpack.glb", 1e-4), ("instancing_gltfpack_c.glb", 5e-4)] {
        let raw = io::load(data(file)).unwrap();
        let (count, detail) = flattened_scene_note(&raw);
        assert_eq!(count, 8, "{detail}");
        assert!(detail.contains("7 EXT_mesh_gpu_instancing instances"), "{file}: {detail}");
        let v = signed_volume(&raw);
        assert!((v - volume).abs() < 1e-3 * volume.abs(), "{file}: volume {v} against {volume}");
        let m = build(raw);
        assert_eq!(m.topology.live_face_count(), source.topology.live_face_count(), "{file}");
        assert_eq!(m.positions.len(), source.positions.len(), "{file}");
        let far = farthest_from(&m, &source).max(farthest_from(&source, &m));
        assert!(
            far < tolerance * diagonal,
            "{file}: a vertex {far} from the source's ({} of the diagonal)",
            far / diagonal
        );
    }
}
