//! glTF extensions: quantized attributes (`KHR_mesh_quantization`, what gltfpack writes) read
//! as the extension defines them; required extensions read, carried or refused by name;
//! material and texture extensions carried to GLB output as the source wrote them.

use base64::Engine;
use dynlod::io::{self, Format};
use dynlod::mesh::NotKeptKind;
use dynlod::{BuildOptions, IndexedMesh, LoadErrorKind, Mesh};
use serde_json::{json, Value};

fn load(doc: &Value) -> Result<IndexedMesh, LoadErrorKind> {
    io::load_bytes(doc.to_string().as_bytes(), Format::Gltf, None)
}

/// A unit quad (two triangles) as gltfpack would quantize it: positions UNSIGNED_SHORT, not
/// normalized, with the dequantising scale on the node; normals normalized BYTE; texture
/// coordinates UNSIGNED_SHORT, not normalized (a material's texture transform scales them).
/// Every element is padded to 4 bytes, as the extension requires. The last vertex's
/// position is overridden by a sparse accessor.
fn quantized() -> Value {
    let mut bin = Vec::new();
    for p in [[0u16, 0, 0], [1000, 0, 0], [0, 1000, 0], [7, 7, 7]] {
        bin.extend(p.iter().flat_map(|c| c.to_le_bytes()));
        bin.extend([0, 0]);
    }
    for n in [[0i8, 0, 127], [0, 0, 127], [0, -128, 0], [127, 0, 0]] {
        bin.extend(n.map(|c| c as u8));
        bin.push(0);
    }
    for t in [[0u16, 0], [1024, 0], [0, 1024], [1024, 1024]] {
        bin.extend(t.iter().flat_map(|c| c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 2, 1, 3] {
        bin.extend(i.to_le_bytes());
    }
    // Sparse: vertex 3 becomes (1000, 1000, 0).
    bin.extend(3u16.to_le_bytes());
    bin.extend([0, 0]);
    for c in [1000u16, 1000, 0] {
        bin.extend(c.to_le_bytes());
    }
    bin.extend([0, 0]);
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin));
    json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization", "KHR_texture_transform"],
        "extensionsRequired": ["KHR_mesh_quantization", "KHR_texture_transform"],
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "scale": [0.001, 0.001, 0.001]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
            "extensions": {"KHR_texture_transform": {"scale": [0.0009765625, 0.0009765625]}}}}}],
        "textures": [{}],
        "buffers": [{"byteLength": bin.len(), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 32, "byteStride": 8},
            {"buffer": 0, "byteOffset": 32, "byteLength": 16, "byteStride": 4},
            {"buffer": 0, "byteOffset": 48, "byteLength": 16, "byteStride": 4},
            {"buffer": 0, "byteOffset": 64, "byteLength": 12},
            {"buffer": 0, "byteOffset": 76, "byteLength": 4},
            {"buffer": 0, "byteOffset": 80, "byteLength": 8}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5123, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1000, 1000, 0],
             "sparse": {"count": 1, "indices": {"bufferView": 4, "componentType": 5123}, "values": {"bufferView": 5}}},
            {"bufferView": 1, "componentType": 5120, "normalized": true, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    })
}

#[test]
fn quantized_attributes_are_read_as_the_extension_defines_them() {
    let m = load(&quantized()).unwrap();
    let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6);
    let expected = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]];
    for (p, e) in m.positions.iter().zip(expected) {
        assert!(close(*p, e), "{p:?} against {e:?}: the node's scale dequantises, the sparse value overrides");
    }
    // Normalized BYTE: c / 127, and -128 clamps to -1. A uniform scale keeps the direction.
    let expected = [[0., 0., 1.], [0., 0., 1.], [0., -1., 0.], [1., 0., 0.]];
    for (n, e) in m.normals.iter().zip(expected) {
        assert!(close(*n, e), "{n:?} against {e:?}");
    }
    // Not normalized: the integer's value; the material's texture transform scales it.
    assert_eq!(m.uvs, [[0., 0.], [1024., 0.], [0., 1024.], [1024., 1024.]]);
    assert!(m.load_repairs.is_empty(), "{:?}", m.load_repairs);
    assert!(m.not_kept.iter().all(|n| n.kind != NotKeptKind::Extensions), "decoded or carried: {:?}", m.not_kept);

    // Normalized UNSIGNED_SHORT texture coordinates (glTF 2.0 core) divide by 65535.
    let mut doc = quantized();
    doc["accessors"][2]["normalized"] = json!(true);
    assert_eq!(load(&doc).unwrap().uvs[1], [1024. / 65535., 0.]);
    // A SHORT normal that is not normalized has no meaning (the extension allows only
    // normalized integers): dropped with the recorded repair, never misread.
    let mut doc = quantized();
    doc["accessors"][1]["normalized"] = json!(false);
    let m = load(&doc).unwrap();
    assert!(m.normals.is_empty());
    let r = &m.load_repairs[0];
    assert_eq!((r.kind.name(), r.count), ("dropped_unreadable_attributes", 1));
}

#[test]
fn the_written_glb_holds_the_dequantised_mesh_and_no_quantization() {
    let m = load(&quantized()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("out.glb");
    io::save(&p, &Mesh::build(&m, BuildOptions::default()).unwrap().to_indexed()).unwrap();
    let back = io::load(&p).unwrap();
    assert_eq!(back.uvs, m.uvs);
    assert_eq!(back.triangles.len(), 2);
    let mats = back.gltf_materials.as_ref().unwrap();
    // Positions are written as FLOAT, so the quantization extension is not declared; the
    // texture transform the material uses is, still required.
    assert_eq!(mats.extensions_used, ["KHR_texture_transform"]);
    assert_eq!(mats.extensions_required, ["KHR_texture_transform"]);
}

/// No elements, or more than their buffer view holds (a count near 2^61 wraps the gltf
/// crate's unchecked end computation into a valid range).
#[test]
fn accessors_with_no_elements_or_too_many_are_refused_by_name() {
    for count in [5u64, 1 << 61, u64::MAX] {
        let mut doc = quantized();
        doc["accessors"][0]["count"] = json!(count);
        let e = load(&doc).unwrap_err().to_string();
        assert!(
            e.contains(&format!("POSITION accessor 0's {count} elements run past the end of buffer view 0")),
            "{e}"
        );
    }
    let mut doc = quantized();
    doc["accessors"][0]["sparse"]["count"] = json!(3);
    let e = load(&doc).unwrap_err().to_string();
    assert!(e.contains("POSITION accessor 0's sparse values or indices run past the end of their buffer view"), "{e}");

    // Without a buffer view, an accessor is zeros under its sparse values, as many as it
    // declares: 2^30 of them from a few bytes would be a 12 GB allocation.
    let mut doc = quantized();
    doc["accessors"][0].as_object_mut().unwrap().remove("bufferView");
    doc["accessors"][0]["count"] = json!(1u64 << 30);
    let e = load(&doc).unwrap_err().to_string();
    assert!(
        e.contains("POSITION accessor 0 has no buffer view and declares 1073741824 elements, more than the 88 bytes"),
        "{e}"
    );
    doc["accessors"][0]["count"] = json!(4);
    let m = load(&doc).map_err(|e| e.to_string());
    assert!(m.as_ref().err().is_none_or(|e| !e.contains("no buffer view")), "{m:?}");

    let mut doc = quantized();
    doc["accessors"][0]["count"] = json!(0);
    let e = load(&doc).unwrap_err().to_string();
    assert!(e.contains("mesh 0 primitive 0: POSITION accessor 0 has a count of 0"), "{e}");
    let mut doc = quantized();
    doc["accessors"][0]["sparse"]["count"] = json!(0);
    let e = load(&doc).unwrap_err().to_string();
    assert!(e.contains("POSITION accessor 0 is sparse with a count of 0"), "{e}");
}

#[test]
fn required_extensions_are_read_carried_or_refused_by_name() {
    let require = |extension: &str| {
        let mut doc = quantized();
        doc["extensionsUsed"].as_array_mut().unwrap().push(json!(extension));
        doc["extensionsRequired"].as_array_mut().unwrap().push(json!(extension));
        load(&doc)
    };
    for carried in [
        "KHR_materials_emissive_strength",
        "KHR_texture_basisu",
        "EXT_texture_webp",
        "KHR_lights_punctual",
        "EXT_meshopt_compression",
        "KHR_meshopt_compression",
        "EXT_mesh_gpu_instancing",
        "KHR_draco_mesh_compression",
    ] {
        assert!(require(carried).is_ok(), "{carried}");
    }
    for (refused, why) in [
        ("KHR_materials_variants", "the file requires the extension KHR_materials_variants"),
        ("XYZ_unknown", "the file requires the extension XYZ_unknown"),
    ] {
        let e = require(refused).unwrap_err();
        assert!(matches!(&e, LoadErrorKind::Unsupported { format: "glTF", message } if message.contains(why)), "{e}");
    }
}

/// Compressed geometry that is only "used" is decoded all the same: a Draco primitive whose
/// accessors have no data is read from its stream (here not a Draco stream: an error naming
/// the primitive). A meshopt fallback buffer is filled by its
/// compressed views, which must reach as far as it says it holds, and none of its views may
/// be uncompressed (they would read nothing).
#[test]
fn compressed_geometry_that_is_not_required_is_still_named() {
    let mut doc = quantized();
    doc["extensionsRequired"] = json!([]);
    doc["accessors"][0].as_object_mut().unwrap().remove("bufferView");
    doc["accessors"][0].as_object_mut().unwrap().remove("sparse");
    doc["meshes"][0]["primitives"][0]["extensions"] =
        json!({"KHR_draco_mesh_compression": {"bufferView": 3, "attributes": {"POSITION": 0}}});
    let e = load(&doc).unwrap_err().to_string();
    assert!(e.contains("mesh 0 primitive 0: KHR_draco_mesh_compression stream does not decode"), "{e}");

    let mut doc = quantized();
    doc["extensionsRequired"] = json!([]);
    doc["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({"byteLength": 64, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}));
    assert!(load(&doc).is_ok(), "a fallback buffer no view uses holds nothing to read");
    doc["buffers"][1]["byteLength"] = json!(1u64 << 40);
    let e = load(&doc).unwrap_err().to_string();
    assert!(e.contains("fallback buffer 1 declares 1099511627776 bytes, but its compressed views end at 0"), "{e}");
    doc["buffers"][1]["byteLength"] = json!(64);
    doc["bufferViews"][0]["buffer"] = json!(1);
    let e = load(&doc).unwrap_err().to_string();
    assert!(
        e.contains("buffer view 0 lies in fallback buffer 1, which holds only decoded views, but is not compressed"),
        "{e}"
    );
    doc["bufferViews"][0]["buffer"] = json!(0);
    doc["buffers"][1]["extensions"] = json!({});
    let e = load(&doc).unwrap_err().to_string();
    assert!(e.contains("buffer 1 has no uri, and only buffer 0 can be the GLB's BIN chunk"), "{e}");
}

/// Materials, textures and samplers reach GLB output as the source wrote them: extensions the
/// gltf crate does not model (and extras) included, nothing added. The output declares the
/// extensions they use and no others.
#[test]
fn glb_output_keeps_material_extensions_as_written() {
    let mut doc = quantized();
    let material = json!({
        "name": "glow",
        "emissiveFactor": [1, 1, 1],
        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5}},
        "extras": {"studio": "kept"},
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
            "extensions": {"KHR_texture_transform": {"scale": [0.5, 0.5], "rotation": 0.25}}}}
    });
    doc["materials"] = json!([material]);
    doc["textures"] = json!([{"sampler": 0, "extensions": {"EXT_texture_webp": {"source": 0}}}]);
    doc["samplers"] = json!([{"wrapS": 33648}]);
    doc["images"] = json!([{"uri": "albedo.webp"}]);
    doc["extensionsUsed"] = json!([
        "KHR_mesh_quantization",
        "KHR_texture_transform",
        "KHR_materials_emissive_strength",
        "EXT_texture_webp",
        "KHR_lights_punctual"
    ]);
    doc["extensionsRequired"] = json!(["KHR_mesh_quantization", "EXT_texture_webp"]);
    let m = load(&doc).unwrap();
    // The lights are what the output loses, and the loader says so.
    let lost: Vec<_> = m.not_kept.iter().filter(|n| n.kind == NotKeptKind::Extensions).collect();
    assert_eq!(lost.len(), 1);
    assert_eq!((lost[0].count, lost[0].detail.as_str()), (1, "KHR_lights_punctual"));
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("out.glb");
    io::save(&p, &Mesh::build(&m, BuildOptions::default()).unwrap().to_indexed()).unwrap();
    let glb = std::fs::read(&p).unwrap();
    let length = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let out: Value = serde_json::from_slice(&glb[20..20 + length]).unwrap();
    assert_eq!(out["materials"], json!([material]), "byte for byte, nothing added");
    assert_eq!(out["textures"], doc["textures"]);
    assert_eq!(out["samplers"], doc["samplers"]);
    assert_eq!(
        out["extensionsUsed"],
        json!(["KHR_texture_transform", "KHR_materials_emissive_strength", "EXT_texture_webp"])
    );
    assert_eq!(out["extensionsRequired"], json!(["EXT_texture_webp"]));
}

/// What gltfpack 1.3 writes by default (tests/data/README.md): the same surface as the FLOAT
/// file it was made from, to within its position grid, with the same topology; and with
/// `-c` (`EXT_meshopt_compression`), the same vertices and triangles again: its triangle
/// codec may start a triangle at another corner, nothing more (tests/meshopt_compression.rs
/// checks the decoding itself).
#[test]
fn gltfpack_output_loads_as_the_surface_it_was_made_from() {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");
    let source = io::load(format!("{data}bunny2k.glb")).unwrap();
    let packed = io::load(format!("{data}bunny2k_gltfpack.glb")).unwrap();
    assert!(packed.load_repairs.is_empty(), "{:?}", packed.load_repairs);
    let [a, b] = [&source, &packed].map(|m| Mesh::build(m, BuildOptions::default()).unwrap().topology.stats());
    assert_eq!((b.vertices, b.faces, b.boundary_loops, b.euler), (a.vertices, a.faces, a.boundary_loops, a.euler));
    assert_eq!((a.faces, a.boundary_loops, a.euler), (2083, 5, -3));
    let h = dynlod::metrics::hausdorff(&source, &packed, dynlod::metrics::HausdorffOptions::default());
    // gltfpack's default grid has 2^14 steps along the longest side, each 0.0038 % of this
    // diagonal; measured: 0.0030 % at most.
    assert!(h.pct(h.max) < 0.005, "{h:?}");
    let compressed = io::load(format!("{data}bunny2k_gltfpack_c.glb")).unwrap();
    assert!(compressed.load_repairs.is_empty());
    assert_eq!(format!("{:?}", compressed.not_kept), format!("{:?}", packed.not_kept), "the flattening only");
    assert_eq!(compressed.positions, packed.positions);
    assert_eq!(compressed.normals, packed.normals);
    let turned = |t: &[u32; 3]| {
        let first = (0..3).min_by_key(|&k| t[k]).unwrap();
        [t[first], t[(first + 1) % 3], t[(first + 2) % 3]]
    };
    let corners = |m: &IndexedMesh| m.triangles.iter().map(turned).collect::<Vec<_>>();
    assert_eq!(corners(&compressed), corners(&packed));
    assert_ne!(compressed.triangles, packed.triangles, "the codec did turn some triangles");
}
