//! A mesh's materials as an MTL library for an OBJ output, their textures as image files
//! beside it: what an artist converting a textured glTF or OBJ to OBJ expects to open in
//! Blender, MeshLab or a game's importer. The mapping is the inverse of the import's
//! (`obj_materials.rs`, Blender's):
//! - `Kd` is the base colour, `map_Kd` its texture (MTL multiplies them, as glTF does; our
//!   reader, as Blender's, takes a `Kd` beside a `map_Kd` for a placeholder); `d` its alpha
//!   where the material blends or masks, and `map_d` the same texture where it has an alpha
//!   channel (which Blender reads only so);
//! - `Pr` and `Pm` (the PBR extension) are roughness and metallic, and `Ns` is
//!   1000 (1 − roughness)², which Blender reads back as the same roughness; `Ks` is glTF's
//!   reflectance at normal incidence, 0.04 for a dielectric and the base colour for a metal;
//! - `Ke` and `map_Ke` are the emissive colour and texture; the normal texture with its
//!   scale is written twice, as `norm -bm` (a normal map to three.js, tinyobjloader and
//!   Assimp) and as `map_Bump -bm` (a normal map to Blender, which does not read `norm`; a
//!   height map to the others, which draw the normal map where both are given, three.js
//!   leaving the bump map out); `map_Pr` and `map_Pm` the metallic-roughness texture, each
//!   from its channel (`-imfchan g` and `b`); `map_ao` the occlusion texture (no MTL
//!   statement is; engines, Model I/O and our reader take this one).
//!
//! What MTL cannot hold is listed ([`Library::lost`]): the occlusion's strength, an alpha
//! mask (where the texture's alpha is cut-outs, which the reader masks again at 0.5, only a
//! cutoff other than 0.5), textures on a second UV set, wrapping other than repeat or clamping
//! both ways (`-clamp on`), material and
//! texture extensions (but `KHR_texture_transform` without rotation: `-o` and `-s`), and
//! images whose bytes were never read.

use serde_json::Value;

use super::texture_files::{source, word, TextureFiles};
use crate::mesh::IndexedMesh;

/// How a library dynlod writes begins: a file that begins otherwise is someone else's, and
/// is not replaced (`write.rs`).
pub(super) const SIGNATURE: &str = "# written by dynlod";

/// The library an OBJ named `stem` gets.
pub(super) struct Library {
    /// The name `usemtl` gives each material, by its index; one more at the end (glTF's
    /// default material) where some primitive has none.
    pub names: Vec<String>,
    /// The library's file name (`stem.mtl`).
    pub file: String,
    /// The MTL text.
    pub text: String,
    /// The texture files to write beside it.
    pub textures: TextureFiles,
    /// What of the materials MTL cannot hold, as phrases.
    pub lost: Vec<String>,
}

/// A number as MTL files write them: at most six decimals, trailing zeros dropped.
fn num(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// The library for `m`'s materials, when a primitive uses one; the OBJ it is for is named
/// `stem` (the library is `stem.mtl`, textures `stem_image.png`).
pub(super) fn library(m: &IndexedMesh, stem: &str) -> Option<Library> {
    let mats = m.gltf_materials.as_ref()?;
    let materials = mats.materials.as_array().filter(|a| !a.is_empty())?;
    let used = |p: &crate::mesh::Primitive| p.material.is_some_and(|k| k < materials.len());
    if !m.primitives.iter().any(used) {
        return None;
    }
    let stem = word(stem);
    let mut lib = Library {
        names: Vec::new(),
        file: format!("{stem}.mtl"),
        text: format!("{SIGNATURE} {}\n", env!("CARGO_PKG_VERSION")),
        textures: TextureFiles::default(),
        lost: Vec::new(),
    };
    for (k, material) in materials.iter().enumerate() {
        let name = material["name"].as_str().map(word).filter(|n| !n.is_empty());
        let mut name = name.unwrap_or_else(|| format!("material_{k}"));
        if lib.names.contains(&name) {
            name = (k..).map(|j| format!("{name}_{j}")).find(|n| !lib.names.contains(n)).unwrap_or_default();
        }
        lib.text += &format!("\nnewmtl {name}\n");
        Material { lib: &mut lib, mats, stem: &stem, name: &name }.write(material);
        lib.names.push(name);
    }
    if m.primitives.iter().any(|p| !used(p)) {
        // glTF's default material: white, metallic 1, roughness 1.
        let name = (0..).map(|k| format!("default_{k}")).find(|n| !lib.names.contains(n)).unwrap_or_default();
        lib.text += &format!("\nnewmtl {name}\nKd 1 1 1\nKs 1 1 1\nNs 0\nPr 1\nPm 1\nillum 2\n");
        lib.names.push(name);
    }
    Some(lib)
}

/// One material being written into the library.
struct Material<'a> {
    lib: &'a mut Library,
    mats: &'a crate::mesh::GltfMaterials,
    stem: &'a str,
    name: &'a str,
}

impl Material<'_> {
    fn write(mut self, material: &Value) {
        let pbr = &material["pbrMetallicRoughness"];
        let factor = |v: &Value, default: f64| v.as_f64().unwrap_or(default);
        let base: Vec<f64> = (0..4).map(|c| factor(&pbr["baseColorFactor"][c], 1.0)).collect();
        let metallic = factor(&pbr["metallicFactor"], 1.0);
        let roughness = factor(&pbr["roughnessFactor"], 1.0);
        let emissive: Vec<f64> = (0..3).map(|c| factor(&material["emissiveFactor"][c], 0.0)).collect();
        let rgb = |c: &[f64]| format!("{} {} {}", num(c[0]), num(c[1]), num(c[2]));
        let specular: Vec<f64> = base[..3].iter().map(|&b| 0.04 + (b - 0.04) * metallic).collect();
        let mut text =
            format!("Kd {}\nKs {}\nNs {}\n", rgb(&base), rgb(&specular), num(1000.0 * (1.0 - roughness).powi(2)));
        text += &format!("Pr {}\nPm {}\n", num(roughness), num(metallic));
        if emissive.iter().any(|&e| e != 0.0) {
            text += &format!("Ke {}\n", rgb(&emissive));
        }
        match material["alphaMode"].as_str() {
            Some("BLEND") => text += &format!("d {}\n", num(base[3])),
            Some("MASK") => {
                text += &format!("d {}\n", num(base[3]));
                // The reader masks, at glTF's default cutoff of 0.5, where `d` is 1 and the
                // texture's alpha (written as `map_d`) is cut-outs (`obj_materials`).
                let cutoff = factor(&material["alphaCutoff"], 0.5);
                let texture = source(self.mats, &pbr["baseColorTexture"]);
                let masks_again = base[3] == 1.0 && texture.is_some_and(|k| self.cut_outs(k));
                match (masks_again, cutoff == 0.5) {
                    (true, true) => {}
                    (true, false) => self.lose(format!("alphaMode MASK's cutoff {} (read back as 0.5)", num(cutoff))),
                    (false, _) => self.lose(format!("alphaMode MASK (its cutoff {})", num(cutoff))),
                }
            }
            _ => {}
        }
        text += "illum 2\n";
        let maps = [
            ("map_Kd", "baseColorTexture", &pbr["baseColorTexture"]),
            ("map_Ke", "emissiveTexture", &material["emissiveTexture"]),
        ];
        for (statement, key, info) in maps {
            if let Some(file) = self.texture(key, info) {
                text += &format!("{statement} {file}\n");
                // Blender takes a colour texture's alpha only from `map_d`.
                let blends = matches!(material["alphaMode"].as_str(), Some("BLEND" | "MASK"));
                if statement == "map_Kd" && blends && source(self.mats, info).is_some_and(|k| self.has_alpha(k)) {
                    text += &format!("map_d {file}\n");
                }
            }
        }
        let normal = &material["normalTexture"];
        if let Some(file) = self.texture("normalTexture", normal) {
            let scale = num(factor(&normal["scale"], 1.0));
            text += &format!("norm -bm {scale} {file}\nmap_Bump -bm {scale} {file}\n");
        }
        // glTF packs roughness into the green channel and metallic into the blue.
        if let Some(file) = self.texture("metallicRoughnessTexture", &pbr["metallicRoughnessTexture"]) {
            text += &format!("map_Pr -imfchan g {file}\nmap_Pm -imfchan b {file}\n");
        }
        // MTL has no occlusion statement; `map_ao` is what engines and Model I/O read.
        let occlusion = &material["occlusionTexture"];
        if let Some(file) = self.texture("occlusionTexture", occlusion) {
            // glTF's occlusion is the red channel (packed with metallic-roughness, often).
            text += &format!("map_ao -imfchan r {file}\n");
            if let Some(strength) = occlusion["strength"].as_f64().filter(|&s| s != 1.0) {
                self.lose(format!("occlusionTexture's strength {}", num(strength)));
            }
        }
        if let Some(ext) = material["extensions"].as_object() {
            for key in ext.keys() {
                self.lose(key.clone());
            }
        }
        self.lib.text += &text;
    }

    /// Whether image `k` has an alpha channel of cut-outs, as the OBJ reader judges it
    /// ([`binary_alpha`](super::image_convert::binary_alpha)).
    fn cut_outs(&self, k: usize) -> bool {
        let image = &self.mats.images[k];
        let name = image.name.as_deref().unwrap_or("image");
        self.has_alpha(k)
            && image.bytes.as_deref().is_some_and(|b| super::image_convert::binary_alpha(b, name) == Ok(true))
    }

    /// Whether image `k` holds an alpha channel: a PNG of grey or colour with alpha, or with
    /// a transparency chunk (a JPEG has none).
    fn has_alpha(&self, k: usize) -> bool {
        let Some(png) = self.mats.images[k].bytes.as_deref().filter(|b| b.starts_with(b"\x89PNG")) else {
            return false;
        };
        // Colour type 4 or 6 in the header; a transparency chunk comes before the pixels.
        let chunks = png.windows(4).position(|w| w == b"IDAT").map_or(png, |i| &png[..i]);
        matches!(png.get(25), Some(4 | 6)) || chunks.windows(4).any(|w| w == b"tRNS")
    }

    fn lose(&mut self, what: String) {
        self.lib.lost.push(format!("material {}: {what}", self.name));
    }

    /// The file name of the texture `info` shows (a glTF textureInfo), written once however
    /// many materials use it, after the options its texture transform takes; `None`, with
    /// the reason listed, where MTL cannot show it.
    fn texture(&mut self, key: &str, info: &Value) -> Option<String> {
        let texture = &self.mats.textures[info["index"].as_u64()? as usize];
        let Some(image) = source(self.mats, info) else {
            self.lose(format!("{key} (an image only an extension names)"));
            return None;
        };
        if info["texCoord"].as_u64().unwrap_or(0) != 0 {
            self.lose(format!("{key} (on TEXCOORD_{}; OBJ has one set)", info["texCoord"]));
            return None;
        }
        let file = match self.lib.textures.add(self.stem, self.mats, image) {
            Ok(place) => self.lib.textures.0[place].0.clone(),
            Err(why) => {
                self.lose(format!("{key} ({why})"));
                return None;
            }
        };
        // An offset and scale of the coordinates are MTL's `-o` and `-s` (in OBJ's
        // coordinates, v up from the image's bottom: the inverse of `obj_materials.rs`).
        let mut options = String::new();
        for (name, e) in info["extensions"].as_object().into_iter().flatten() {
            let rotated = e["rotation"].as_f64().is_some_and(|r| r != 0.0);
            if name != "KHR_texture_transform" || rotated || e["texCoord"].as_u64().is_some_and(|c| c != 0) {
                self.lose(format!("{key}'s {name}"));
                continue;
            }
            let (o, sc) = (&e["offset"], &e["scale"]);
            let (ou, ov) = (o[0].as_f64().unwrap_or(0.0), o[1].as_f64().unwrap_or(0.0));
            let (su, sv) = (sc[0].as_f64().unwrap_or(1.0), sc[1].as_f64().unwrap_or(1.0));
            options = format!("-o {} {} 0 -s {} {} 1 ", num(ou), num(1.0 - sv - ov), num(su), num(sv));
        }
        // MTL repeats, or clamps both ways (`-clamp on`: CLAMP_TO_EDGE); nothing else.
        let sampler = texture["sampler"].as_u64().and_then(|s| self.mats.samplers.get(s as usize));
        let wrap = |axis: &str| sampler.and_then(|s| s[axis].as_u64()).unwrap_or(10497);
        match (wrap("wrapS"), wrap("wrapT")) {
            (10497, 10497) => {}
            (33071, 33071) => options = format!("-clamp on {options}"),
            _ => self.lose(format!("{key}'s wrapping (MTL repeats, or clamps both ways)")),
        }
        Some(options + &file)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_words_as_mtl_writes_them() {
        assert_eq!([num(0.8), num(1.0), num(0.04), num(-0.0), num(0.1234567)], ["0.8", "1", "0.04", "0", "0.123457"]);
        assert_eq!(word("Material #1 (wood)"), "Material__1__wood_");
    }
}
