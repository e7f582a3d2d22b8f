//! Compressed glTF read as the decoders web engines use read it:
//! - meshoptimizer's codecs (`EXT_meshopt_compression`, `KHR_meshopt_compression`: what
//!   `gltfpack -c` writes), against meshoptimizer's WebAssembly decoder (the npm package
//!   three.js and Babylon.js load; `scripts/make-meshopt-fixtures.sh`);
//! - Draco (`KHR_draco_mesh_compression`: what gltf-pipeline `-d`, Blender and gltf-transform
//!   write), decoded here by the pure Rust `draco-core`, against Google's Draco decoder built
//!   to WebAssembly (npm `draco3dgltf`; `scripts/make-draco-fixtures.sh`).
//!
//! The references are the same files decoded by those decoders and written uncompressed
//! (tests/data/README.md).
//!
//! meshoptimizer's x86 build undoes the 8-bit octahedral filter with SSE's approximate
//! reciprocal square root (`_mm_rsqrt_ps`, vertexfilter.cpp), its WebAssembly build exactly,
//! so a normal may land a unit of its 8-bit grid apart (0.1–0.3 % of the normal values of the
//! shared GLBs compressed with `-cc`; nothing else differs). Values are therefore compared
//! within one such unit, and nearly all of them must match exactly. Draco's decoding is
//! exact: every value equal.

use dynlod::io::{self, GltfScene};
use dynlod::IndexedMesh;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");

/// One unit of a normalized 8-bit integer, the coarsest grid a filtered value lies on.
const UNIT: f64 = 1.0 / 127.0;

/// Every value of every accessor of a GLB, in the order of its accessors.
fn accessor_values(glb: &[u8]) -> Vec<Vec<f64>> {
    let g = gltf::Gltf::from_slice_without_validation(glb).unwrap();
    let bin = g.blob.as_deref().unwrap_or(&[]);
    g.accessors()
        .map(|a| {
            let view = a.view().expect("the writer gives every accessor a view");
            let size = a.data_type().size();
            let n = a.dimensions().multiplicity();
            let stride = view.stride().unwrap_or(size * n);
            let start = view.offset() + a.offset();
            let mut out = Vec::with_capacity(a.count() * n);
            for e in 0..a.count() {
                for c in 0..n {
                    let at = start + e * stride + c * size;
                    let b = &bin[at..at + size];
                    out.push(match a.data_type() {
                        gltf::accessor::DataType::I8 => f64::from(b[0] as i8),
                        gltf::accessor::DataType::U8 => f64::from(b[0]),
                        gltf::accessor::DataType::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
                        gltf::accessor::DataType::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
                        gltf::accessor::DataType::U32 => f64::from(u32::from_le_bytes(b.try_into().unwrap())),
                        gltf::accessor::DataType::F32 => f64::from(f32::from_le_bytes(b.try_into().unwrap())),
                    });
                }
            }
            out
        })
        .collect()
}

/// The values of two lists side by side: each within [`UNIT`] of the other, and at least
/// 98 % of them equal. Returns how many differ.
fn close(what: &str, a: &[f64], b: &[f64]) -> usize {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    let differ = a.iter().zip(b).filter(|(x, y)| x != y).count();
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!((x - y).abs() <= UNIT, "{what}: value {i} is {x}, {y} in the reference");
    }
    assert!(differ * 50 <= a.len(), "{what}: {differ} of {} values differ", a.len());
    differ
}

/// The mesh a flattening load gives: the same topology and texture coordinates, colours and
/// positions exactly; normals and tangents (octahedral filter) within a unit. Returns how
/// many values differ.
fn same_mesh(what: &str, ours: &IndexedMesh, reference: &IndexedMesh) -> usize {
    assert_eq!(ours.triangles, reference.triangles, "{what}: triangles");
    assert_eq!(ours.triangle_primitive, reference.triangle_primitive, "{what}");
    assert_eq!(ours.positions, reference.positions, "{what}: positions");
    assert_eq!(ours.uvs, reference.uvs, "{what}: texture coordinates");
    let flat = |v: &[[f32; 3]]| v.iter().flatten().map(|&c| f64::from(c)).collect::<Vec<_>>();
    let mut differ = close(&format!("{what}: normals"), &flat(&ours.normals), &flat(&reference.normals));
    assert_eq!(ours.attributes.len(), reference.attributes.len(), "{what}");
    for (a, b) in ours.attributes.iter().zip(&reference.attributes) {
        assert_eq!(a.semantic, b.semantic, "{what}");
        let values = |v: &dynlod::mesh::VertexAttribute| v.values.iter().map(|&c| f64::from(c)).collect::<Vec<_>>();
        differ += close(&format!("{what}: {}", a.semantic), &values(a), &values(b));
    }
    assert_eq!(format!("{:?}", ours.load_repairs), format!("{:?}", reference.load_repairs), "{what}");
    assert_eq!(format!("{:?}", ours.not_kept), format!("{:?}", reference.not_kept), "{what}");
    differ
}

/// `scene` written back as GLB, its meshes as they were read.
fn written(scene: &GltfScene) -> Vec<u8> {
    let meshes: Vec<IndexedMesh> = scene.meshes.iter().map(|m| m.mesh.clone()).collect();
    let mut out = Vec::new();
    scene.write_glb(&mut out, &meshes).unwrap();
    out
}

/// The scene written back as GLB (nodes, animations, lines and materials kept): every
/// accessor's values as the reference's, within a unit, and the same document otherwise.
/// Returns how many values differ.
fn same_scene_output(what: &str, ours: &GltfScene, reference: &GltfScene) -> usize {
    let (a, b) = (written(ours), written(reference));
    let (va, vb) = (accessor_values(&a), accessor_values(&b));
    assert_eq!(va.len(), vb.len(), "{what}: accessors");
    let mut differ = 0;
    for (i, (x, y)) in va.iter().zip(&vb).enumerate() {
        differ += close(&format!("{what}: output accessor {i}"), x, y);
    }
    let json = |glb: &[u8]| {
        serde_json::to_value(gltf::Gltf::from_slice_without_validation(glb).unwrap().document.into_json()).unwrap()
    };
    let (ja, jb) = (json(&a), json(&b));
    for key in ["accessors", "animations", "nodes", "meshes", "materials"] {
        assert_eq!(ja[key], jb[key], "{what}: {key}");
    }
    differ
}

/// gltfpack 1.3's `-cc` output, with every filter of both extensions between them (octahedral
/// 8- and 16-bit, quaternion, exponential, colour), the triangle and index-sequence codecs,
/// and the version 1 vertex codec (KHR), reads as the web decoder reads it.
#[test]
fn gltfpack_fixtures_read_as_the_web_decoder_reads_them() {
    for v in ["ext", "khr"] {
        let (file, reference) = (format!("{DATA}meshopt_{v}.glb"), format!("{DATA}meshopt_{v}_ref.glb"));
        let bytes = std::fs::read(&file).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        for filter in ["OCTAHEDRAL", "QUATERNION", "EXPONENTIAL", "TRIANGLES", "INDICES"] {
            assert!(text.contains(filter), "{file} uses {filter}");
        }
        let (ours, theirs) = (io::load(&file).unwrap(), io::load(&reference).unwrap());
        assert_eq!(ours.triangles.len(), 288);
        same_mesh(&file, &ours, &theirs);
        same_scene_output(&file, &GltfScene::load(&file).unwrap(), &GltfScene::load(&reference).unwrap());
    }
    assert!(String::from_utf8_lossy(&std::fs::read(format!("{DATA}meshopt_khr.glb")).unwrap()).contains("\"COLOR\""));
}

/// GLB output declares neither extension: its data is written uncompressed.
#[test]
fn output_is_uncompressed() {
    let out = written(&GltfScene::load(format!("{DATA}meshopt_khr.glb")).unwrap());
    let doc = gltf::Gltf::from_slice_without_validation(&out).unwrap();
    let used: Vec<&str> = doc.extensions_used().collect();
    assert!(!used.iter().any(|e| e.contains("meshopt")), "{used:?}");
    let json = serde_json::to_value(doc.document.as_json()).unwrap();
    assert!(json["bufferViews"].as_array().unwrap().iter().all(|v| v.get("extensions").is_none()));
    assert_eq!(doc.buffers().count(), 1);
}

/// A compressed stream that is cut short or overwritten is a typed error naming the buffer
/// view (or, where meshoptimizer decodes garbage, the indices it gives are caught as any
/// file's are): never a panic, never a silent mesh.
#[test]
fn damaged_streams_are_errors_that_name_the_view() {
    let bytes = std::fs::read(format!("{DATA}meshopt_ext.glb")).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let bin = 20 + length + 8;
    // Overwrite each stream's first byte (its header: the codec and its version).
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
    for (i, view) in doc["bufferViews"].as_array().unwrap().iter().enumerate() {
        let Some(ext) = view["extensions"].get("EXT_meshopt_compression") else { continue };
        let mut broken = bytes.clone();
        broken[bin + ext["byteOffset"].as_u64().unwrap_or(0) as usize] = 0xff;
        let e = io::load_bytes(&broken, io::Format::Gltf, None).unwrap_err().to_string();
        assert!(
            e.contains(&format!("buffer view {i} (EXT_meshopt_compression)")) && e.contains("does not decode"),
            "{e}"
        );
    }
    // Stream lengths one byte short, and one past the buffer.
    let mut short = doc.clone();
    let view = &mut short["bufferViews"][1]["extensions"]["EXT_meshopt_compression"];
    view["byteLength"] = (view["byteLength"].as_u64().unwrap() - 1).into();
    let e = io::load_bytes(&with_json(&bytes, &short), io::Format::Gltf, None).unwrap_err().to_string();
    assert!(e.contains("buffer view 1 (EXT_meshopt_compression): its ATTRIBUTES stream does not decode"), "{e}");
    let mut past = doc.clone();
    past["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteOffset"] = 1_000_000.into();
    let e = io::load_bytes(&with_json(&bytes, &past), io::Format::Gltf, None).unwrap_err().to_string();
    assert!(
        e.contains("buffer view 1 (EXT_meshopt_compression): its stream")
            && e.contains("runs past the end of buffer 0"),
        "{e}"
    );
}

/// `glb` with its JSON chunk replaced by `doc`.
fn with_json(glb: &[u8], doc: &serde_json::Value) -> Vec<u8> {
    let length = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let mut text = serde_json::to_vec(doc).unwrap();
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let rest = &glb[20 + length..];
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((20 + text.len() + rest.len()) as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(text);
    out.extend(rest);
    out
}

/// gltf-pipeline's Draco (Google's encoder) of the meshopt fixtures' ball: positions,
/// normals, tangents, texture coordinates and colours in one stream, at the default level
/// (EdgeBreaker, quantised) and at level 0 unquantised (sequential), beside an uncompressed
/// line primitive: read exactly as Google's decoder reads them, flattened and scene-kept.
#[test]
fn draco_fixtures_read_as_googles_decoder_reads_them() {
    for v in ["draco", "draco_sequential"] {
        let (file, reference) = (format!("{DATA}{v}.glb"), format!("{DATA}{v}_ref.glb"));
        assert!(String::from_utf8_lossy(&std::fs::read(&file).unwrap()).contains("KHR_draco_mesh_compression"));
        let (ours, theirs) = (io::load(&file).unwrap(), io::load(&reference).unwrap());
        assert_eq!(ours.triangles.len(), 288);
        assert_eq!(ours.attributes.iter().map(|a| a.semantic.as_str()).collect::<Vec<_>>(), ["TANGENT", "COLOR_0"]);
        assert_eq!(same_mesh(&file, &ours, &theirs), 0, "{file}: every value equal");
        let (a, b) = (GltfScene::load(&file).unwrap(), GltfScene::load(&reference).unwrap());
        assert_eq!(same_scene_output(&file, &a, &b), 0, "{file}: every value equal");
    }
}

/// GLB output of a Draco source is uncompressed and does not declare the extension; a line
/// primitive beside the Draco one is copied as it was.
#[test]
fn draco_output_is_uncompressed() {
    let out = written(&GltfScene::load(format!("{DATA}draco.glb")).unwrap());
    let doc = gltf::Gltf::from_slice(&out).unwrap();
    assert_eq!(doc.extensions_used().count(), 0, "{:?}", doc.extensions_used().collect::<Vec<_>>());
    let modes: Vec<_> = doc.meshes().flat_map(|m| m.primitives().map(|p| p.mode())).collect();
    assert_eq!(modes, [gltf::mesh::Mode::Triangles, gltf::mesh::Mode::Lines]);
    assert_eq!(doc.buffers().count(), 1);
}

/// A TRIANGLE_STRIP primitive (which the extension allows) decodes to the same triangle list
/// as a TRIANGLES one, whatever its indices accessor counted.
#[test]
fn a_draco_strip_reads_as_its_decoded_list() {
    let bytes = std::fs::read(format!("{DATA}draco.glb")).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
    let list = io::load(format!("{DATA}draco.glb")).unwrap();
    doc["meshes"][0]["primitives"][0]["mode"] = 5.into();
    let indices = doc["meshes"][0]["primitives"][0]["indices"].as_u64().unwrap() as usize;
    doc["accessors"][indices]["count"] = 290.into();
    let strip = io::load_bytes(&with_json(&bytes, &doc), io::Format::Gltf, None).unwrap();
    assert_eq!((strip.triangles, strip.positions), (list.triangles, list.positions));
}

/// A Draco stream cut short, overwritten or pointing past its buffer, an attribute id the
/// stream lacks, an accessor whose count is not what the stream decodes: each a typed error
/// naming the mesh and primitive, never a panic.
#[test]
fn damaged_draco_streams_are_errors_that_name_the_primitive() {
    let bytes = std::fs::read(format!("{DATA}draco.glb")).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
    let prim = "/meshes/0/primitives/0";
    let ext = doc.pointer(&format!("{prim}/extensions/KHR_draco_mesh_compression")).unwrap().clone();
    let stream = ext["bufferView"].as_u64().unwrap() as usize;
    let load = |d: &serde_json::Value, b: &[u8]| io::load_bytes(&with_json(b, d), io::Format::Gltf, None);
    let expect = |d: &serde_json::Value, b: &[u8], what: &str| {
        let e = load(d, b).unwrap_err().to_string();
        assert!(
            e.contains("mesh 0 primitive 0: KHR_draco_mesh_compression") && e.contains(what),
            "{e}\n expected: {what}"
        );
    };
    // The stream's header ("DRACO", version, kind) overwritten.
    let offset = 20 + length + 8 + doc["bufferViews"][stream]["byteOffset"].as_u64().unwrap_or(0) as usize;
    let mut broken = bytes.clone();
    broken[offset..offset + 5].copy_from_slice(b"OCARD");
    let e = io::load_bytes(&broken, io::Format::Gltf, None).unwrap_err().to_string();
    assert!(e.contains("mesh 0 primitive 0: KHR_draco_mesh_compression stream does not decode"), "{e}");
    // Cut to a half, a tenth, a byte: an error each time (where the decoder makes something
    // of what is left, the counts no longer match).
    let full = doc["bufferViews"][stream]["byteLength"].as_u64().unwrap();
    for cut in [full / 2, full / 10, 1] {
        let mut d = doc.clone();
        d["bufferViews"][stream]["byteLength"] = cut.into();
        assert!(load(&d, &bytes).is_err(), "a stream cut to {cut} of {full} bytes");
    }
    let mut d = doc.clone();
    d["bufferViews"][stream]["byteOffset"] = 1_000_000.into();
    expect(&d, &bytes, "runs past the end of buffer 0");
    let mut d = doc.clone();
    *d.pointer_mut(&format!("{prim}/extensions/KHR_draco_mesh_compression/attributes/NORMAL")).unwrap() = 9.into();
    expect(&d, &bytes, "gives NORMAL the id 9, which the stream does not have");
    let mut d = doc.clone();
    let position = d.pointer(&format!("{prim}/attributes/POSITION")).unwrap().as_u64().unwrap() as usize;
    d["accessors"][position]["count"] = 5.into();
    expect(&d, &bytes, &format!("values of POSITION, but its accessor {position} declares 5"));
    let mut d = doc.clone();
    let indices = d.pointer(&format!("{prim}/indices")).unwrap().as_u64().unwrap() as usize;
    d["accessors"][indices]["count"] = 3.into();
    expect(&d, &bytes, &format!("triangles, but the indices accessor {indices} declares 3 indices"));
}

/// For `.ci/run` (`scripts/compression-check.sh` makes the pairs): every `NAME.glb` in
/// `$DYNLOD_COMPRESSED_PAIRS` beside its reference `NAME.ref.glb`, as above. gltfpack's `-c`,
/// `-cc`, `-cc -ce khr` and `-mi -cc`, gltf-pipeline's `-d` and gltf-transform's quantize
/// then draco, of the shared GLBs and the bundled bunny; a Draco pair (`_draco`, `_qdraco`)
/// must match exactly.
#[test]
#[ignore = "needs the pairs scripts/compression-check.sh makes (node, npm)"]
fn compressed_pairs_read_as_the_web_decoder_reads_them() {
    let dir = std::env::var("DYNLOD_COMPRESSED_PAIRS").expect("DYNLOD_COMPRESSED_PAIRS names the folder of pairs");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    let mut checked = 0;
    for file in files.iter().filter(|p| !p.to_string_lossy().ends_with(".ref.glb")) {
        let reference = file.with_extension("ref.glb");
        let (ours, theirs) = (io::load(file).unwrap(), io::load(&reference).unwrap());
        let what = file.display().to_string();
        let flat = same_mesh(&what, &ours, &theirs);
        let scene = same_scene_output(&what, &GltfScene::load(file).unwrap(), &GltfScene::load(&reference).unwrap());
        let values: usize =
            [ours.positions.len() * 3, ours.normals.len() * 3, ours.uvs.len() * 2].iter().sum::<usize>()
                + ours.attributes.iter().map(|a| a.values.len()).sum::<usize>();
        println!(
            "{what}: {} triangles as the reference; {flat} of {values} vertex values and {scene} values of the scene output a unit apart",
            ours.triangles.len()
        );
        if what.ends_with("draco.glb") {
            assert_eq!((flat, scene), (0, 0), "{what}: Draco decodes exactly");
        }
        checked += 1;
    }
    assert!(checked >= 3, "{checked} pairs in {dir}");
}
