//! An output's materials: an OBJ's MTL library and texture files beside it
//! (`io/write_mtl.rs`), a PLY's one texture (`io/texture_files.rs`); read back by our own
//! loaders and compared with what was written. TGA, BMP, TIFF and DDS textures made PNGs;
//! `map_Bump` read as a normal map where its pixels are one.

use std::path::Path;
use std::sync::Arc;

use dynlod::io::{self, WriteFormat};
use dynlod::mesh::{GltfImage, GltfMaterials, Primitive};
use dynlod::{procedural, IndexedMesh};
use serde_json::json;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

/// A sphere in two primitives, with materials 0 and 1 (to be given), and the test texture's
/// bytes.
fn two_materials() -> (IndexedMesh, Vec<u8>) {
    let mut m = procedural::uv_sphere(4, 6);
    let half = m.triangles.len() / 2;
    m.triangle_primitive = (0..m.triangles.len()).map(|t| u32::from(t >= half)).collect();
    m.primitives = (0..2).map(|k| Primitive { material: Some(k), ..Primitive::default() }).collect();
    (m, std::fs::read(data("textured_quad_wood.png")).unwrap())
}

/// `stem.obj` in `dir`, two triangles of a unit square with texture coordinates, using the
/// `materials` of the library `mtl` (written as `stem.mtl`); read back.
fn two_triangles(dir: &Path, stem: &str, mtl: &str, materials: [&str; 2]) -> IndexedMesh {
    std::fs::write(dir.join(format!("{stem}.mtl")), mtl).unwrap();
    let mut obj = format!("mtllib {stem}.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n");
    obj += &format!("usemtl {}\nf 1/1 2/2 3/3\nusemtl {}\nf 2/2 4/4 3/3\n", materials[0], materials[1]);
    std::fs::write(dir.join(format!("{stem}.obj")), obj).unwrap();
    io::load(dir.join(format!("{stem}.obj"))).unwrap()
}

fn names(files: &[std::path::PathBuf]) -> Vec<String> {
    files.iter().map(|f| f.file_name().unwrap().to_string_lossy().into_owned()).collect()
}

/// `tests/data/textured_quad.obj` to OBJ: the library and the texture come along, named after
/// the output, and the OBJ names them; read back, each primitive has the material it had.
#[test]
fn an_obj_from_an_obj_keeps_its_materials_and_texture() {
    let m = io::load(data("textured_quad.obj")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lod 1.obj");
    let files = io::save(&out, &m).unwrap();
    assert_eq!(names(&files), ["lod_1_textured_quad_wood.png", "lod_1.mtl", "lod 1.obj"]);
    assert!(io::not_written(&m, WriteFormat::Obj).is_empty(), "{:?}", io::not_written(&m, WriteFormat::Obj));
    let png = std::fs::read(data("textured_quad_wood.png")).unwrap();
    assert_eq!(std::fs::read(&files[0]).unwrap(), png);
    let text = std::fs::read_to_string(&out).unwrap();
    let statements: Vec<&str> =
        text.lines().filter(|l| l.starts_with("mtllib") || l.starts_with("usemtl") || l.starts_with("o ")).collect();
    assert_eq!(statements, ["mtllib lod_1.mtl", "o quad", "usemtl wood", "o quad", "usemtl glass"]);
    let mtl = std::fs::read_to_string(&files[1]).unwrap();
    for line in
        ["newmtl wood", "Ns 250", "Pr 0.5", "Pm 0", "map_Kd lod_1_textured_quad_wood.png", "d 0.5", "Ke 0.1 0 0"]
    {
        assert!(mtl.lines().any(|l| l == line), "{line} in\n{mtl}");
    }
    let back = io::load(&out).unwrap();
    assert_eq!(back.primitives.iter().map(|p| p.material).collect::<Vec<_>>(), [Some(0), Some(1)]);
    let (a, b) = (&m.gltf_materials.as_ref().unwrap(), &back.gltf_materials.as_ref().unwrap());
    assert_eq!(a.materials, b.materials, "the materials read back as they were read");
    assert_eq!(b.images[0].bytes.as_ref(), Some(&png));
    assert_eq!(back.uvs, m.uvs);
}

/// A glTF material with everything MTL can hold and some it cannot: the texture files are
/// written once each, the MTL statements carry factors and maps, and what is left out is
/// listed by material; read back, the maps MTL holds are the material's again.
#[test]
fn a_gltf_material_in_mtl_and_back() {
    let png = std::fs::read(data("textured_quad_wood.png")).unwrap();
    let image = |name: Option<&str>, bytes: Option<Vec<u8>>| GltfImage {
        name: name.map(Into::into),
        mime_type: Some("image/png".into()),
        bytes,
        uri: None,
    };
    let mut m = procedural::uv_sphere(4, 6);
    let half = m.triangles.len() / 2;
    m.triangle_primitive = (0..m.triangles.len()).map(|t| u32::from(t >= half)).collect();
    m.primitives = vec![
        Primitive { name: "shell".into(), material: Some(0), ..Primitive::default() },
        Primitive { name: "plain".into(), material: None, ..Primitive::default() },
    ];
    m.gltf_materials = Some(Arc::new(GltfMaterials {
        materials: json!([{
            "name": "painted metal",
            "pbrMetallicRoughness": {
                "baseColorFactor": [0.5, 0.25, 1.0, 0.75],
                "baseColorTexture": { "index": 0 },
                "metallicFactor": 0.5,
                "roughnessFactor": 0.2,
                "metallicRoughnessTexture": { "index": 1 },
            },
            "normalTexture": { "index": 2, "scale": 0.5 },
            "emissiveTexture": { "index": 3, "texCoord": 1 },
            "occlusionTexture": { "index": 1, "strength": 0.6 },
            "alphaMode": "MASK",
            "alphaCutoff": 0.25,
            "extensions": { "KHR_materials_clearcoat": {} },
        }]),
        textures: json!([{ "source": 0, "sampler": 0 }, { "source": 1 }, { "source": 2 }, { "source": 0 }]),
        samplers: json!([{ "wrapS": 33071 }]),
        images: vec![
            image(Some("albedo.png"), Some(png.clone())),
            image(None, Some(png.clone())),
            image(Some("n"), None),
        ],
        ..GltfMaterials::default()
    }));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ball.obj");
    let files = io::save(&out, &m).unwrap();
    assert_eq!(names(&files), ["ball_albedo.png", "ball_texture1.png", "ball.mtl", "ball.obj"]);
    assert_eq!(
        io::not_written(&m, WriteFormat::Obj),
        [
            "material painted_metal: alphaMode MASK (its cutoff 0.25)",
            "material painted_metal: baseColorTexture's wrapping (MTL repeats, or clamps both ways)",
            "material painted_metal: emissiveTexture (on TEXCOORD_1; OBJ has one set)",
            "material painted_metal: normalTexture (its image was not read)",
            "material painted_metal: occlusionTexture's strength 0.6",
            "material painted_metal: KHR_materials_clearcoat",
        ]
    );
    let mtl = std::fs::read_to_string(&files[2]).unwrap();
    let block = |name: &str| {
        let start = mtl.find(&format!("newmtl {name}\n")).unwrap_or_else(|| panic!("{name} in\n{mtl}"));
        mtl[start..].lines().skip(1).take_while(|l| !l.is_empty()).collect::<Vec<_>>().join("\n")
    };
    assert_eq!(
        block("painted_metal"),
        "Kd 0.5 0.25 1\nKs 0.27 0.145 0.52\nNs 640\nPr 0.2\nPm 0.5\nd 0.75\nillum 2\nmap_Kd ball_albedo.png\n\
         map_Pr -imfchan g ball_texture1.png\nmap_Pm -imfchan b ball_texture1.png\nmap_ao -imfchan r ball_texture1.png"
    );
    assert_eq!(block("default_0"), "Kd 1 1 1\nKs 1 1 1\nNs 0\nPr 1\nPm 1\nillum 2", "glTF's default material");
    let text = std::fs::read_to_string(&out).unwrap();
    let usemtl: Vec<&str> = text.lines().filter(|l| l.starts_with("usemtl")).collect();
    assert_eq!(usemtl, ["usemtl painted_metal", "usemtl default_0"]);
    // Read back: the factors MTL holds, the texture and the packed metallic-roughness map.
    let back = io::load(&out).unwrap();
    let mats = back.gltf_materials.as_ref().unwrap();
    let pbr = &mats.materials[0]["pbrMetallicRoughness"];
    // Beside a `map_Kd`, `Kd` is read as Blender reads it, a placeholder (exporters write 0.8):
    // the tint MTL holds, and spec-following readers apply, does not come back.
    assert_eq!(pbr["baseColorFactor"], json!([1.0, 1.0, 1.0, 0.75]));
    assert_eq!((pbr["metallicFactor"].as_f64(), pbr["roughnessFactor"].as_f64()), (Some(0.5), Some(0.2)));
    let texture = |info: &serde_json::Value| mats.textures[info["index"].as_u64().unwrap() as usize]["source"].clone();
    assert_eq!((texture(&pbr["baseColorTexture"]), texture(&pbr["metallicRoughnessTexture"])), (json!(0), json!(1)));
    assert_eq!(texture(&mats.materials[0]["occlusionTexture"]), json!(1), "the occlusion, from map_ao");
    assert_eq!(mats.images.len(), 2);
    assert!(back.not_kept.iter().all(|n| n.kind != dynlod::mesh::NotKeptKind::MaterialMaps), "{:?}", back.not_kept);
}

/// The normal and emissive maps go out as `norm -bm` and `map_Ke` and come back as glTF's;
/// a material without a name, or with one already used (even one made so), gets one of its
/// own, and a material no primitive uses is written too; a mesh whose
/// primitives use no material writes no library.
#[test]
fn normal_and_emissive_maps_names_and_no_library() {
    let png = std::fs::read(data("textured_quad_wood.png")).unwrap();
    let mut m = procedural::uv_sphere(4, 6);
    let third = m.triangles.len() / 3;
    m.triangle_primitive = (0..m.triangles.len()).map(|t| (t / third).min(2) as u32).collect();
    m.primitives = (0..3).map(|k| Primitive { material: Some(k), ..Primitive::default() }).collect();
    let image = GltfImage { name: None, mime_type: None, bytes: Some(png), uri: None };
    m.gltf_materials = Some(Arc::new(GltfMaterials {
        materials: json!([
            { "name": "a", "normalTexture": { "index": 0, "scale": 0.5 }, "emissiveTexture": { "index": 0 },
              "emissiveFactor": [1.0, 0.5, 0.0] },
            { "name": "a_2" },
            { "name": "a" },
            {},
        ]),
        textures: json!([{ "source": 0 }]),
        images: vec![image],
        ..GltfMaterials::default()
    }));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.obj");
    let files = io::save(&out, &m).unwrap();
    assert_eq!(names(&files), ["m_texture0.png", "m.mtl", "m.obj"], "one file for the image both maps show");
    let mtl = std::fs::read_to_string(&files[1]).unwrap();
    let news: Vec<&str> = mtl.lines().filter(|l| l.starts_with("newmtl")).collect();
    assert_eq!(news, ["newmtl a", "newmtl a_2", "newmtl a_3", "newmtl material_3"]);
    assert!(mtl.contains("Ke 1 0.5 0\n") && mtl.contains("map_Ke m_texture0.png\n"), "{mtl}");
    assert!(mtl.contains("norm -bm 0.5 m_texture0.png\nmap_Bump -bm 0.5 m_texture0.png\n"), "{mtl}");
    let back = io::load(&out).unwrap();
    let a = &back.gltf_materials.as_ref().unwrap().materials[0];
    assert_eq!((&a["normalTexture"]["scale"], &a["emissiveFactor"]), (&json!(0.5), &json!([1.0, 0.5, 0.0])));
    assert!(a["normalTexture"]["index"].is_u64() && a["emissiveTexture"]["index"].is_u64(), "{a}");
    // No primitive with a material: no library, and the OBJ names none.
    let mut plain: IndexedMesh = m.clone();
    plain.primitives.iter_mut().for_each(|p| p.material = None);
    let files = io::save(dir.path().join("plain.obj"), &plain).unwrap();
    assert_eq!(names(&files), ["plain.obj"]);
    assert!(!std::fs::read_to_string(&files[0]).unwrap().contains("mtllib"));
}

/// A 4 × 4 DDS holding one DXT1 block: red, but for a blue second row.
fn dxt1_dds() -> Vec<u8> {
    let mut dds = b"DDS ".to_vec();
    let words = |dds: &mut Vec<u8>, words: &[u32]| dds.extend(words.iter().flat_map(|w| w.to_le_bytes()));
    // Size, flags (caps, height, width, pixel format), height, width, linear size, depth, mips.
    words(&mut dds, &[124, 0x1007, 4, 4, 8, 0, 0]);
    words(&mut dds, &[0; 11]);
    words(&mut dds, &[32, 0x4]);
    dds.extend(b"DXT1");
    words(&mut dds, &[0; 5]);
    words(&mut dds, &[0x1000, 0, 0, 0, 0]);
    assert_eq!(dds.len(), 128);
    // Colour 0 red, colour 1 blue (565); two bits per pixel, a row a byte.
    dds.extend([0x00, 0xF8, 0x1F, 0x00, 0x00, 0x55, 0x00, 0x00]);
    dds
}

/// TGA, BMP, TIFF and DDS textures (common in OBJ sets and game assets; glTF holds PNG and
/// JPEG) are made PNGs with the same pixels, alpha included, and named for it; a file that is
/// none of them, or is broken, is listed with why.
#[test]
fn tga_bmp_tiff_and_dds_textures_become_pngs() {
    let dir = tempfile::tempdir().unwrap();
    let pixels =
        image::RgbaImage::from_fn(3, 2, |x, y| image::Rgba([80 * x as u8, 120 * y as u8, 7, 255 - 60 * x as u8]));
    let rgba = image::DynamicImage::ImageRgba8(pixels.clone());
    rgba.save_with_format(dir.path().join("a.tga"), image::ImageFormat::Tga).unwrap();
    rgba.save_with_format(dir.path().join("c.tiff"), image::ImageFormat::Tiff).unwrap();
    let rgb = image::DynamicImage::ImageRgb8(image::DynamicImage::ImageRgba8(pixels.clone()).to_rgb8());
    rgb.save_with_format(dir.path().join("b.bmp"), image::ImageFormat::Bmp).unwrap();
    std::fs::write(dir.path().join("d.tga"), b"\x00\x00\x0a broken").unwrap();
    std::fs::write(dir.path().join("e.gif"), b"GIF89a").unwrap();
    std::fs::write(dir.path().join("f.dds"), dxt1_dds()).unwrap();
    let mut mtl = String::new();
    let mut obj = String::from("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n");
    for (k, file) in ["a.tga", "b.bmp", "c.tiff", "d.tga", "e.gif", "f.dds"].iter().enumerate() {
        mtl += &format!("newmtl m{k}\nmap_Kd {file}\n");
        obj += &format!("usemtl m{k}\nf 1/1 2/2 3/3\n");
    }
    std::fs::write(dir.path().join("m.mtl"), mtl).unwrap();
    std::fs::write(dir.path().join("m.obj"), obj).unwrap();
    let m = io::load(dir.path().join("m.obj")).unwrap();
    let mats = m.gltf_materials.as_ref().unwrap();
    let names: Vec<_> =
        mats.images.iter().map(|i| (i.name.as_deref().unwrap(), i.mime_type.as_deref().unwrap())).collect();
    let png = "image/png";
    assert_eq!(names, [("a.png", png), ("b.png", png), ("c.png", png), ("f.png", png)]);
    let decoded = |k: usize| {
        image::load_from_memory_with_format(mats.images[k].bytes.as_ref().unwrap(), image::ImageFormat::Png).unwrap()
    };
    assert_eq!(decoded(0).to_rgba8(), pixels, "the TGA's pixels, alpha included");
    assert_eq!(decoded(1).to_rgb8(), rgb.to_rgb8(), "the BMP's");
    assert_eq!(decoded(2).to_rgba8(), pixels, "the TIFF's");
    let dds = decoded(3).to_rgba8();
    let rows: Vec<[u8; 4]> = (0..4).map(|y| dds.get_pixel(2, y).0).collect();
    assert_eq!(rows, [[255, 0, 0, 255], [0, 0, 255, 255], [255, 0, 0, 255], [255, 0, 0, 255]], "the DDS's");
    let lost = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::MaterialMaps).unwrap();
    assert_eq!(lost.count, 2, "{lost:?}");
    assert!(lost.detail.contains("m3: map_Kd d.tga (not a readable TGA"), "{}", lost.detail);
    assert!(
        lost.detail.contains("m4: map_Kd e.gif (not a PNG or JPEG, nor a TGA, BMP, TIFF or DDS to convert)"),
        "{}",
        lost.detail
    );
}

/// A PLY holds one texture, as MeshLab writes it: `comment TextureFile` beside per-vertex
/// coordinates. Where every primitive shows one image it is written beside the PLY and named,
/// and read back as the mesh's material (a PLY with per-vertex coordinates and one
/// `TextureFile` was read without it); where the material holds more, that is listed; where
/// primitives show different images, or none, no texture is named.
#[test]
fn a_ply_names_its_one_texture() {
    let png = std::fs::read(data("textured_quad_wood.png")).unwrap();
    let mut m = procedural::uv_sphere(4, 6);
    m.primitives = vec![Primitive { material: Some(0), ..Primitive::default() }];
    let image = GltfImage { name: Some("wood.png".into()), mime_type: None, bytes: Some(png.clone()), uri: None };
    let materials = |tint: f64| {
        json!([{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 }, "metallicFactor": 0.0,
                 "baseColorFactor": [tint, 1.0, 1.0, 1.0] } }])
    };
    m.gltf_materials = Some(Arc::new(GltfMaterials {
        materials: materials(1.0),
        textures: json!([{ "source": 0 }]),
        images: vec![image],
        ..GltfMaterials::default()
    }));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scan.ply");
    let files = io::save(&out, &m).unwrap();
    assert_eq!(names(&files), ["scan_wood.png", "scan.ply"]);
    assert_eq!(std::fs::read(&files[0]).unwrap(), png);
    assert!(io::not_written(&m, WriteFormat::Ply).is_empty(), "{:?}", io::not_written(&m, WriteFormat::Ply));
    let header = String::from_utf8_lossy(&std::fs::read(&out).unwrap()[..200]).into_owned();
    assert!(header.contains("\ncomment TextureFile scan_wood.png\n"), "{header}");
    let back = io::load(&out).unwrap();
    assert_eq!((back.primitives.len(), back.primitives[0].material), (1, Some(0)));
    let mats = back.gltf_materials.as_ref().unwrap();
    assert_eq!(mats.images[0].bytes.as_ref(), Some(&png));
    assert_eq!(mats.materials[0]["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
    assert_eq!(back.uvs, m.uvs);
    // A tinted texture: the tint is listed as left out.
    let mut tinted = m.clone();
    let mut mats = (**m.gltf_materials.as_ref().unwrap()).clone();
    mats.materials = materials(0.5);
    tinted.gltf_materials = Some(Arc::new(mats));
    assert_eq!(
        io::not_written(&tinted, WriteFormat::Ply),
        ["the materials but their base-colour textures, which TextureFile names (write .glb or .obj to keep them)"]
    );
    // A primitive without the texture: none is named, and the materials are listed.
    let mut two = m.clone();
    let half = two.triangles.len() / 2;
    two.triangle_primitive = (0..two.triangles.len()).map(|t| u32::from(t >= half)).collect();
    two.primitives.push(Primitive::default());
    let files = io::save(dir.path().join("two.ply"), &two).unwrap();
    assert_eq!(names(&files), ["two.ply"]);
    let lost = io::not_written(&two, WriteFormat::Ply);
    assert!(lost.contains(&"materials (write .glb or .obj to keep them)".to_string()), "{lost:?}");
}

/// Two textures: MeshLab's form, a `TextureFile` each, texture coordinates per face corner
/// and a texture number per face; read back, a primitive per texture, each with its image,
/// and every corner at its coordinates (within f32's step near 1: the file holds 1 − v).
#[test]
fn a_ply_with_two_textures_numbers_its_faces() {
    let (mut m, png) = two_materials();
    let image =
        |name: &str| GltfImage { name: Some(name.into()), mime_type: None, bytes: Some(png.clone()), uri: None };
    let texture =
        |k: usize| json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": k }, "metallicFactor": 0.0 } });
    m.gltf_materials = Some(Arc::new(GltfMaterials {
        materials: json!([texture(0), texture(1)]),
        textures: json!([{ "source": 0 }, { "source": 1 }]),
        images: vec![image("a.png"), image("b.png")],
        ..GltfMaterials::default()
    }));
    assert!(io::not_written(&m, WriteFormat::Ply).is_empty(), "{:?}", io::not_written(&m, WriteFormat::Ply));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scan.ply");
    let files = io::save(&out, &m).unwrap();
    assert_eq!(names(&files), ["scan_a.png", "scan_b.png", "scan.ply"]);
    let bytes = std::fs::read(&out).unwrap();
    let header = String::from_utf8_lossy(&bytes[..400]).into_owned();
    for line in [
        "comment TextureFile scan_a.png",
        "comment TextureFile scan_b.png",
        "property list uchar float texcoord",
        "property int texnumber",
    ] {
        assert!(header.lines().any(|l| l == line), "{line} in {header}");
    }
    assert!(!header.contains("property float u\n"), "no coordinates per vertex: {header}");
    let back = io::load(&out).unwrap();
    let materials: Vec<_> = back.primitives.iter().map(|p| p.material).collect();
    assert_eq!(materials, [Some(0), Some(1)]);
    assert_eq!(back.triangle_primitive, m.triangle_primitive);
    let mats = back.gltf_materials.as_ref().unwrap();
    assert_eq!(
        mats.images.iter().map(|i| i.name.as_deref().unwrap()).collect::<Vec<_>>(),
        ["scan_a.png", "scan_b.png"]
    );
    for (t, (a, b)) in m.triangles.iter().zip(&back.triangles).enumerate() {
        for c in 0..3 {
            let (p, q) = (m.uvs[a[c] as usize], back.uvs[b[c] as usize]);
            assert!((p[0] - q[0]).abs() == 0.0 && (p[1] - q[1]).abs() <= 6e-8, "triangle {t} corner {c}: {p:?} {q:?}");
            assert_eq!(m.positions[a[c] as usize], back.positions[b[c] as usize]);
        }
    }
}

/// A normal map as Blender writes it, `map_Bump -bm s` (the MTL specification's bump map is a
/// height map): read as the normal texture where its pixels are a normal map's, and listed
/// where they are grey (`bump`, a height map) or where `norm` names another file. Written
/// to OBJ, the normal texture is both `norm` and `map_Bump` (for Blender, which reads only
/// the second), and read back as one texture with nothing lost.
#[test]
fn a_blender_normal_map_in_map_bump_is_kept_and_a_height_map_listed() {
    let dir = tempfile::tempdir().unwrap();
    let normal = image::RgbImage::from_fn(32, 32, |x, y| {
        let (dx, dy) = (((x as f64) * 0.4).sin() * 0.3, ((y as f64) * 0.3).cos() * 0.2);
        let len = (dx * dx + dy * dy + 1.0).sqrt();
        image::Rgb([dx / len, dy / len, 1.0 / len].map(|c| ((c + 1.0) * 127.5).round() as u8))
    });
    normal.save(dir.path().join("skin_normal.png")).unwrap();
    let height = image::GrayImage::from_fn(32, 32, |x, y| image::Luma([(x * 4 + y) as u8]));
    height.save(dir.path().join("stone_height.png")).unwrap();
    let mtl = "newmtl skin\nKd 0.8 0.8 0.8\nmap_Bump -bm 0.700000 skin_normal.png\n\
               newmtl stone\nbump stone_height.png\n\
               newmtl both\nnorm skin_normal.png\nmap_Bump stone_height.png\n";
    let m = two_triangles(dir.path(), "b", mtl, ["skin", "stone"]);
    let mats = m.gltf_materials.as_ref().unwrap();
    let skin = &mats.materials[0]["normalTexture"];
    assert_eq!(skin["scale"], json!(0.7));
    let image = mats.textures[skin["index"].as_u64().unwrap() as usize]["source"].as_u64().unwrap() as usize;
    assert_eq!(mats.images[image].bytes, Some(std::fs::read(dir.path().join("skin_normal.png")).unwrap()));
    assert!(mats.materials[1]["normalTexture"].is_null());
    assert_eq!(mats.materials[2]["normalTexture"]["index"], skin["index"], "norm's texture, read once");
    let lost = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::MaterialMaps).unwrap();
    assert_eq!(
        lost.detail,
        "stone: map_Bump stone_height.png (a height map by its pixels; glTF has none); \
         both: map_Bump stone_height.png (beside norm's normal texture)"
    );
    let out = dir.path().join("out.obj");
    let files = io::save(&out, &m).unwrap();
    let written = std::fs::read_to_string(&files[1]).unwrap();
    assert!(written.contains("norm -bm 0.7 out_skin_normal.png\nmap_Bump -bm 0.7 out_skin_normal.png\n"), "{written}");
    let back = io::load(&out).unwrap();
    assert_eq!(back.gltf_materials.as_ref().unwrap().materials[0]["normalTexture"]["scale"], json!(0.7));
    assert!(back.not_kept.iter().all(|n| n.kind != dynlod::mesh::NotKeptKind::MaterialMaps), "{:?}", back.not_kept);
}

/// An OBJ simplified in place (`a.obj` to `a.obj`) keeps its own `a.mtl`, which our
/// translation would have replaced (maps and settings MTL-to-glTF does not carry went with
/// it): the output's library takes the next free name, and a library dynlod wrote is
/// replaced as before, so writing again reuses the same names.
#[test]
fn a_library_dynlod_did_not_write_is_never_replaced() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["textured_quad.obj", "textured_quad.mtl", "textured_quad_wood.png"] {
        std::fs::copy(data(f), dir.path().join(f)).unwrap();
    }
    let obj = dir.path().join("textured_quad.obj");
    let own = std::fs::read(dir.path().join("textured_quad.mtl")).unwrap();
    let m = io::load(&obj).unwrap();
    assert_eq!(io::library_name_for(&obj), "textured_quad.mtl");
    for _ in 0..2 {
        let files = io::save(&obj, &m).unwrap();
        assert_eq!(names(&files), ["textured_quad_textured_quad_wood.png", "textured_quad_1.mtl", "textured_quad.obj"]);
        assert_eq!(std::fs::read(dir.path().join("textured_quad.mtl")).unwrap(), own, "the user's library");
        let text = std::fs::read_to_string(&obj).unwrap();
        assert!(text.lines().any(|l| l == "mtllib textured_quad_1.mtl"), "{text}");
    }
    let back = io::load(&obj).unwrap();
    assert_eq!(back.gltf_materials.as_ref().unwrap().materials, m.gltf_materials.as_ref().unwrap().materials);
    // Our own library of the output's name is replaced.
    let files = io::save(dir.path().join("textured_quad_1.obj"), &m).unwrap();
    assert_eq!(names(&files)[1], "textured_quad_1.mtl");
}

/// Cut-outs as OBJ sets ship them: a colour texture and an alpha map (`map_d`). Where the
/// alpha map is another file, its grey levels become the colour texture's alpha channel in
/// one RGBA PNG (glTF holds a base colour's alpha so); where it is the same RGBA file, that
/// is the texture. Cut-outs mask, other alpha blends. An alpha map of another size, or without
/// a colour map, is listed. Written to OBJ, a blending material's texture with alpha is named
/// by `map_d` too (Blender reads the alpha only from it), one without alpha (a JPEG) is not.
#[test]
fn alpha_maps_become_the_colour_textures_alpha() {
    let dir = tempfile::tempdir().unwrap();
    let colour = image::RgbImage::from_fn(4, 4, |x, y| image::Rgb([60 * x as u8, 60 * y as u8, 200]));
    colour.save(dir.path().join("leaf.jpg")).unwrap();
    let mask = image::GrayImage::from_fn(4, 4, |x, _| image::Luma([if x < 2 { 0 } else { 255 }]));
    mask.save(dir.path().join("leaf_mask.png")).unwrap();
    image::GrayImage::new(2, 2).save(dir.path().join("small.png")).unwrap();
    let rgba = image::RgbaImage::from_fn(4, 4, |x, y| image::Rgba([10, 20, 30, (x * 60 + y) as u8]));
    rgba.save(dir.path().join("fence.png")).unwrap();
    let mtl = "newmtl leaf\nmap_Kd leaf.jpg\nmap_d leaf_mask.png\n\
               newmtl fence\nmap_Kd fence.png\nmap_d -imfchan m fence.png\n\
               newmtl odd\nmap_Kd leaf.jpg\nmap_d small.png\n\
               newmtl bare\nmap_d leaf_mask.png\n";
    let m = two_triangles(dir.path(), "c", mtl, ["leaf", "fence"]);
    let mats = m.gltf_materials.as_ref().unwrap();
    let image_of = |mats: &GltfMaterials, k: usize| {
        let info = &mats.materials[k]["pbrMetallicRoughness"]["baseColorTexture"];
        let t = &mats.textures[info["index"].as_u64().unwrap() as usize];
        mats.images[t["source"].as_u64().unwrap() as usize].clone()
    };
    let leaf = image_of(mats, 0);
    assert_eq!((leaf.name.as_deref(), leaf.mime_type.as_deref()), (Some("leaf_leaf_mask.png"), Some("image/png")));
    let made = image::load_from_memory(leaf.bytes.as_ref().unwrap()).unwrap().to_rgba8();
    let jpeg = image::open(dir.path().join("leaf.jpg")).unwrap().to_rgb8();
    for (x, y, p) in made.enumerate_pixels() {
        let c = jpeg.get_pixel(x, y).0;
        assert_eq!(p.0, [c[0], c[1], c[2], mask.get_pixel(x, y).0[0]], "({x}, {y})");
    }
    assert_eq!(image_of(mats, 1).bytes, Some(std::fs::read(dir.path().join("fence.png")).unwrap()));
    let modes: Vec<&serde_json::Value> = (0..4).map(|k| &mats.materials[k]["alphaMode"]).collect();
    // The leaf's mask is cut-outs (0 or 255): MASK; the fence's alpha is a gradient: BLEND.
    assert_eq!(modes, [&json!("MASK"), &json!("BLEND"), &serde_json::Value::Null, &serde_json::Value::Null]);
    let lost = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::MaterialMaps).unwrap();
    assert_eq!(
        lost.detail,
        "odd: map_d small.png (its size 2×2 is not its colour texture's 4×4); bare: map_d leaf_mask.png"
    );
    // To OBJ and back: `map_d` beside the PNGs with alpha, the blending kept.
    let out = dir.path().join("out.obj");
    let files = io::save(&out, &m).unwrap();
    let written = std::fs::read_to_string(files.iter().find(|f| f.extension().unwrap() == "mtl").unwrap()).unwrap();
    assert!(written.contains("map_Kd out_leaf_leaf_mask.png\nmap_d out_leaf_leaf_mask.png\n"), "{written}");
    assert!(written.contains("map_Kd out_fence.png\nmap_d out_fence.png\n"), "{written}");
    let back = io::load(&out).unwrap();
    let again = back.gltf_materials.as_ref().unwrap();
    assert_eq!((&again.materials[0]["alphaMode"], &again.materials[1]["alphaMode"]), (&json!("MASK"), &json!("BLEND")));
    assert_eq!(image_of(again, 0).bytes, leaf.bytes);
    // The mask comes back as it was (cut-outs, glTF's default cutoff): nothing is listed.
    let masks = |m: &IndexedMesh| {
        io::not_written(m, WriteFormat::Obj).into_iter().filter(|l| l.contains("MASK")).collect::<Vec<_>>()
    };
    assert!(masks(&m).is_empty(), "{:?}", masks(&m));
    // Another cutoff is lost, the mask not; a mask over smooth alpha comes back blending.
    let mut cutoff = m.clone();
    let mut mats = (**cutoff.gltf_materials.as_ref().unwrap()).clone();
    mats.materials[0]["alphaCutoff"] = json!(0.3);
    mats.materials[1]["alphaMode"] = json!("MASK");
    cutoff.gltf_materials = Some(Arc::new(mats));
    assert_eq!(
        masks(&cutoff),
        [
            "material leaf: alphaMode MASK's cutoff 0.3 (read back as 0.5)",
            "material fence: alphaMode MASK (its cutoff 0.5)"
        ]
    );
    // A blending material over a JPEG: its alpha is the factor's alone, so no `map_d`.
    let mut blend = m.clone();
    let mut mats = (**blend.gltf_materials.as_ref().unwrap()).clone();
    mats.materials[0]["alphaMode"] = json!("BLEND");
    mats.materials[0]["pbrMetallicRoughness"]["baseColorFactor"] = json!([1.0, 1.0, 1.0, 0.5]);
    mats.images[0].bytes = Some(std::fs::read(dir.path().join("leaf.jpg")).unwrap());
    blend.gltf_materials = Some(Arc::new(mats));
    let files = io::save(dir.path().join("jpeg.obj"), &blend).unwrap();
    let written = std::fs::read_to_string(files.iter().find(|f| f.extension().unwrap() == "mtl").unwrap()).unwrap();
    assert!(written.contains("d 0.5\n") && !written.contains("map_d jpeg_leaf_leaf_mask.jpg"), "{written}");
    assert!(written.contains("map_Kd jpeg_leaf_leaf_mask.jpg\n"), "{written}");
}

/// Tiling and offsets: glTF's `KHR_texture_transform` (offset and scale; v measured from the
/// image's top) is MTL's `-o` and `-s` (v from its bottom), both ways, so a tiled texture
/// stays tiled from GLB to OBJ and back; a GLB from the OBJ declares the extension. A
/// rotation, which MTL cannot hold, is listed.
#[test]
fn texture_transforms_are_mtl_offsets_and_scales() {
    let (mut m, png) = two_materials();
    let transform = |t: serde_json::Value| json!({ "index": 0, "extensions": { "KHR_texture_transform": t } });
    m.gltf_materials = Some(Arc::new(GltfMaterials {
        materials: json!([
            { "name": "tiled", "pbrMetallicRoughness": {
                "baseColorTexture": transform(json!({ "offset": [0.25, 0.5], "scale": [4.0, 2.0] })) } },
            { "name": "turned", "pbrMetallicRoughness": {
                "baseColorTexture": transform(json!({ "rotation": 0.5 })) } },
        ]),
        textures: json!([{ "source": 0 }]),
        images: vec![GltfImage { name: Some("wood".into()), mime_type: None, bytes: Some(png), uri: None }],
        extensions_used: vec!["KHR_texture_transform".into()],
        ..GltfMaterials::default()
    }));
    assert_eq!(io::not_written(&m, WriteFormat::Obj), ["material turned: baseColorTexture's KHR_texture_transform"]);
    let dir = tempfile::tempdir().unwrap();
    let files = io::save(dir.path().join("t.obj"), &m).unwrap();
    let mtl = std::fs::read_to_string(&files[1]).unwrap();
    assert!(mtl.contains("map_Kd -o 0.25 -1.5 0 -s 4 2 1 t_wood.png\n"), "{mtl}");
    let back = io::load(&files[2]).unwrap();
    let mats = back.gltf_materials.as_ref().unwrap();
    let tiled = &mats.materials[0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"];
    assert_eq!((&tiled["offset"], &tiled["scale"]), (&json!([0.25, 0.5]), &json!([4.0, 2.0])));
    assert!(mats.materials[1]["pbrMetallicRoughness"]["baseColorTexture"].get("extensions").is_none());
    assert_eq!(mats.extensions_used, ["KHR_texture_transform"]);
    let glb = dir.path().join("t.glb");
    io::save(&glb, &back).unwrap();
    let doc = gltf::Gltf::open(&glb).unwrap();
    assert_eq!(doc.extensions_used().collect::<Vec<_>>(), ["KHR_texture_transform"]);
}

/// MTL's `-clamp on` is glTF's CLAMP_TO_EDGE, both ways: a decal clamped in one map and
/// repeated in another gets two textures of one image, the clamped one through a clamping
/// sampler; written to OBJ, that sampler is `-clamp on` again. A wrapping MTL cannot show
/// (mirrored, or clamped one way only) is listed.
#[test]
fn clamp_on_is_a_clamping_sampler() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([200, 10, 10])).save(dir.path().join("decal.png")).unwrap();
    let mtl = "newmtl sign\nmap_Kd -clamp on decal.png\nmap_Ke decal.png\nKe 1 1 1\n\
               newmtl wall\nmap_Kd -s 2 2 1 -clamp on decal.png\n";
    let m = two_triangles(dir.path(), "c", mtl, ["sign", "wall"]);
    let mats = m.gltf_materials.as_ref().unwrap();
    assert_eq!(mats.textures, json!([{ "source": 0 }, { "source": 0, "sampler": 0 }]));
    assert_eq!(mats.samplers, json!([{ "wrapS": 33071, "wrapT": 33071 }]));
    let index = |k: usize, key: &str| {
        let info = &mats.materials[k]["pbrMetallicRoughness"][key];
        info.get("index").unwrap_or(&mats.materials[k][key]["index"]).clone()
    };
    assert_eq!(
        (index(0, "baseColorTexture"), index(0, "emissiveTexture"), index(1, "baseColorTexture")),
        (json!(1), json!(0), json!(1))
    );
    assert!(!serde_json::to_string(&mats.materials).unwrap().contains("clamp"), "no marker left");
    // To OBJ and back: the same textures and samplers.
    assert!(io::not_written(&m, WriteFormat::Obj).is_empty(), "{:?}", io::not_written(&m, WriteFormat::Obj));
    let files = io::save(dir.path().join("out.obj"), &m).unwrap();
    let written = std::fs::read_to_string(files.iter().find(|f| f.extension().unwrap() == "mtl").unwrap()).unwrap();
    assert!(
        written.contains("map_Kd -clamp on out_decal.png\n") && written.contains("map_Ke out_decal.png\n"),
        "{written}"
    );
    assert!(written.contains("map_Kd -clamp on -o 0 0 0 -s 2 2 1 out_decal.png\n"), "{written}");
    let back = io::load(dir.path().join("out.obj")).unwrap();
    let again = back.gltf_materials.as_ref().unwrap();
    assert_eq!((&again.textures, &again.samplers), (&mats.textures, &mats.samplers));
    // Mirrored, or clamped one way: listed.
    let mut mirrored = m.clone();
    let mut odd = (**mats).clone();
    odd.samplers = json!([{ "wrapS": 33648, "wrapT": 33648 }]);
    mirrored.gltf_materials = Some(Arc::new(odd.clone()));
    let lost = io::not_written(&mirrored, WriteFormat::Obj);
    assert_eq!(lost[0], "material sign: baseColorTexture's wrapping (MTL repeats, or clamps both ways)", "{lost:?}");
    odd.samplers = json!([{ "wrapS": 33071 }]);
    mirrored.gltf_materials = Some(Arc::new(odd));
    assert_eq!(io::not_written(&mirrored, WriteFormat::Obj).len(), 2, "sign and wall");
}
