//! An OBJ's materials (its `mtllib` files, read by tobj) as glTF materials, so that a GLB
//! written from the mesh keeps each primitive's colour and texture. The mapping is the one
//! Blender's OBJ importer makes:
//! - `Kd` and `d` (or `1 − Tr`) are the base colour and its alpha; where `map_Kd` gives a
//!   texture, the texture is the colour (Kd is often a placeholder 0.8 beside it), and
//!   `map_d` its alpha (the texture's own where it names the same file, or made its alpha
//!   channel from another file's grey levels), which masks where it is cut-outs (nearly all
//!   of it transparent or opaque: leaves, fences; `image_convert::binary_alpha`) and blends
//!   otherwise;
//! - `Ns` (0–1000) gives the roughness, 1 − √(Ns / 1000); the PBR extension's `Pr` and `Pm`
//!   win where written; metallic is 0 otherwise (glTF's default of 1 would make every OBJ
//!   metal);
//! - `Ke` is the emissive colour, `map_Ke` its texture; an alpha below 1 blends;
//! - `map_Pr` and `map_Pm` naming one file's green and blue channels (`-imfchan g`, `b`) are
//!   glTF's packed metallic-roughness texture, as `write_mtl.rs` writes them, and `map_ao`
//!   the occlusion texture (no MTL statement is one; engines write this); `norm` (with
//!   its `-bm` scale) is the normal texture, and so is `map_Bump` (or `bump`) where its
//!   pixels are a normal map's (`bump_map.rs`: Blender writes normal maps so, where the MTL
//!   specification means a height map, which is listed as not kept).
//!
//! Files are looked for beside the OBJ: the path as written (`\` read as `/`), else its file
//! name alone (a library or texture moved along with the OBJ, written as an absolute path by
//! the exporter). A texture is embedded where it is a PNG or JPEG (what glTF holds), or made
//! one from a TGA, BMP, TIFF or DDS (`image_convert.rs`); other maps (specular, `disp`,
//! ...), other image types and files not found are listed as not kept.
//! A PLY's texture files (`comment TextureFile`, `ply_wedges.rs`) become materials the same
//! way ([`texture_materials`]).

use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::bump_map::BumpKind;
use super::gltf_resources::image_type;
use crate::mesh::{GltfImage, GltfMaterials};

/// The file `name` (as an OBJ or MTL writes it) names beside `base`, if there is one.
pub(super) fn find(base: &Path, name: &str) -> Option<PathBuf> {
    let name = name.trim().replace('\\', "/");
    let written = Path::new(&name);
    if written.is_relative() {
        let path = base.join(written);
        if path.is_file() {
            return Some(path);
        }
    }
    let path = base.join(written.file_name()?);
    path.is_file().then_some(path)
}

/// The material library `name` beside `base`, read as tobj reads one, in any text encoding
/// (`text.rs`: 3ds Max wrote Latin-1 names, which tobj's own reader refuses); or why there
/// is no file to read.
pub(super) fn library(base: &Path, name: &str) -> Result<tobj::MTLLoadResult, String> {
    let path = find(base, name).ok_or("not found")?;
    let bytes = std::fs::read(&path).map_err(|e| e.to_string())?;
    Ok(tobj::load_mtl_buf(&mut super::text::utf8(&bytes).as_bytes()))
}

/// The file name in a map statement's value, past its options (`-s 1 1 1 -bm 0.5 file.png`:
/// the last word; without options, all of it, spaces included).
fn map_file(value: &str) -> &str {
    let value = value.trim();
    match value.starts_with('-') {
        true => value.rsplit(char::is_whitespace).next().unwrap_or(value),
        false => value,
    }
}

/// glTF's textureInfo for texture `t` as the map statement `value` shows it: its `-o` and
/// `-s` options (offset and scale of the texture coordinates, in u and v) as
/// `KHR_texture_transform`, marking `transformed`. MTL offsets and scales OBJ's coordinates,
/// whose v runs up from the image's bottom, and glTF's run down from its top
/// (`uv_origin.rs`): v' = 1 − ((1 − v) s + o) = v s + (1 − s − o).
fn texture_info(t: usize, value: &str, transformed: &std::cell::Cell<bool>) -> Value {
    let words: Vec<&str> = value.split_whitespace().collect();
    let option = |flag: &str, mut out: [f64; 2]| {
        let at = words.iter().position(|w| *w == flag).map_or(words.len(), |i| i + 1);
        // At most u and v (a w is for 3D textures); the last word is the file.
        let numbers = words[at..words.len().saturating_sub(1).max(at)].iter().take(2);
        for (k, x) in numbers.map_while(|w| w.parse::<f64>().ok().filter(|x| x.is_finite())).enumerate() {
            out[k] = x;
        }
        out
    };
    let (o, s) = (option("-o", [0.0, 0.0]), option("-s", [1.0, 1.0]));
    let mut info = json!({ "index": t });
    // `-clamp on`: the texture through a clamping sampler (`Built::finish` makes it).
    if words.windows(2).any(|w| w[0] == "-clamp" && w[1].eq_ignore_ascii_case("on")) {
        info[CLAMP] = json!(true);
    }
    if o != [0.0, 0.0] || s != [1.0, 1.0] {
        let transform = json!({ "offset": [o[0], 1.0 - s[1] - o[1]], "scale": s });
        info["extensions"] = json!({ "KHR_texture_transform": transform });
        transformed.set(true);
    }
    info
}

/// The key a textureInfo holds while it is made where its map says `-clamp on`; `finish`
/// points it at a texture of the same image through a clamping sampler instead.
const CLAMP: &str = "dynlod:clamp";

/// Materials being made into [`GltfMaterials`]: one image, and one texture, per image file
/// (and one more through a clamping sampler for each image a map clamps).
struct Built<'a> {
    base: &'a Path,
    out: GltfMaterials,
    materials: Vec<Value>,
    /// The images' paths, in order; texture k shows image k.
    files: Vec<PathBuf>,
    /// What was not carried, with why.
    lost: Vec<String>,
    /// The bump maps looked at, by path, with what their pixels are (or why not read).
    bumps: Vec<(PathBuf, Result<BumpKind, String>)>,
    /// Textures whose alpha has been looked at, with whether it is cut-outs.
    cut_outs: Vec<(usize, bool)>,
}

impl<'a> Built<'a> {
    fn new(base: &'a Path) -> Self {
        let (materials, files, lost, bumps, cut_outs) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        Built { base, out: GltfMaterials::default(), materials, files, lost, bumps, cut_outs }
    }

    /// The texture of the image file `name` beside the source, read once however many
    /// materials use it (a TGA, BMP or TIFF made a PNG, `image_convert.rs`); or why there is
    /// none.
    fn texture(&mut self, name: &str) -> Result<usize, String> {
        let path = find(self.base, name).ok_or("not found")?;
        if let Some(k) = self.files.iter().position(|f| *f == path) {
            return Ok(k);
        }
        let bytes = std::fs::read(&path).map_err(|_| "not readable")?;
        let mut file = path.file_name().map(|f| f.to_string_lossy().into_owned());
        let (bytes, mime) = match image_type(&bytes) {
            Some(mime) => (bytes, mime),
            None => {
                let png = super::image_convert::to_png(&bytes, &path.to_string_lossy())?;
                // Named for what it holds now: `wood.tga` becomes `wood.png`.
                file = file.map(|f| format!("{}.png", f.rsplit_once('.').map_or(f.as_str(), |(stem, _)| stem)));
                (png, "image/png")
            }
        };
        self.out.images.push(GltfImage { name: file, mime_type: Some(mime.into()), bytes: Some(bytes), uri: None });
        self.files.push(path);
        Ok(self.files.len() - 1)
    }

    /// [`Built::texture`] of the map `label` (`wood: map_Kd`) naming `name`; where there is
    /// none, the map is listed as not carried, with why.
    fn map(&mut self, label: &str, name: &str) -> Option<usize> {
        self.texture(name).map_err(|why| self.lost.push(format!("{label} {name} ({why})"))).ok()
    }

    /// The texture of the colour map `colour` with the alpha map `mask` (`map_Kd`, `map_d`)
    /// as its alpha channel, made once (`image_convert.rs`); where it cannot be made, the
    /// alpha map is listed as not carried under `label`, with why.
    fn masked(&mut self, label: &str, colour: &str, mask: &str) -> Option<usize> {
        let made = (|| {
            let (c, m) = (find(self.base, colour).ok_or("not found")?, find(self.base, mask).ok_or("not found")?);
            let key = PathBuf::from(format!("{}\n{}", c.display(), m.display()));
            if let Some(k) = self.files.iter().position(|f| *f == key) {
                return Ok(k);
            }
            let read = |p: &Path| std::fs::read(p).map_err(|_| "not readable".to_string());
            let (cb, mb) = (read(&c)?, read(&m)?);
            let (png, cut_out) =
                super::image_convert::with_alpha((&cb, &c.to_string_lossy()), (&mb, &m.to_string_lossy()))?;
            let stem = |p: &Path| p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            let name = format!("{}_{}.png", stem(&c), stem(&m));
            self.out.images.push(GltfImage {
                name: Some(name),
                mime_type: Some("image/png".into()),
                bytes: Some(png),
                uri: None,
            });
            self.files.push(key);
            self.cut_outs.push((self.files.len() - 1, cut_out));
            Ok::<usize, String>(self.files.len() - 1)
        })();
        made.map_err(|why| self.lost.push(format!("{label} {mask} ({why})"))).ok()
    }

    /// Whether texture `t`'s alpha is cut-outs (`image_convert::binary_alpha`): known where
    /// [`Built::masked`] made it, else its image decoded once however many materials ask.
    fn cut_out(&mut self, t: usize) -> bool {
        if let Some(&(_, known)) = self.cut_outs.iter().find(|(k, _)| *k == t) {
            return known;
        }
        let image = &self.out.images[t];
        let name = image.name.as_deref().unwrap_or_default();
        let known = image.bytes.as_deref().is_some_and(|b| super::image_convert::binary_alpha(b, name) == Ok(true));
        self.cut_outs.push((t, known));
        known
    }

    /// The texture of the bump map `label` (`wood: map_Bump`) naming `name`, where its pixels
    /// are a tangent-space normal map's (`bump_map.rs`); where they are not, or there is no
    /// texture, the map is listed as not carried, with why.
    fn normal_map(&mut self, label: &str, name: &str) -> Option<usize> {
        let Some(path) = find(self.base, name) else {
            return self.map(label, name);
        };
        let kind = match self.bumps.iter().find(|(p, _)| *p == path) {
            Some((_, kind)) => kind.clone(),
            None => {
                let bytes = std::fs::read(&path).map_err(|_| "not readable".to_string());
                let kind = bytes.and_then(|b| super::bump_map::kind(&b, &path.to_string_lossy()));
                self.bumps.push((path, kind.clone()));
                kind
            }
        };
        match kind.and_then(|k| if k == BumpKind::Normal { Ok(()) } else { Err(k.why_not().into()) }) {
            Ok(()) => self.map(label, name),
            Err(why) => {
                self.lost.push(format!("{label} {name} ({why})"));
                None
            }
        }
    }

    fn finish(mut self) -> (GltfMaterials, Vec<String>) {
        let mut textures: Vec<Value> = (0..self.files.len()).map(|k| json!({ "source": k })).collect();
        // MTL's `-clamp on` is glTF's CLAMP_TO_EDGE, both ways: a texture of the image
        // through sampler 0, made once per image.
        let mut clamped: Vec<(u64, usize)> = Vec::new();
        let mut point = |info: &mut serde_json::Map<String, Value>| {
            if info.remove(CLAMP).is_none() {
                return;
            }
            let image = info["index"].as_u64().unwrap_or(0);
            let at = match clamped.iter().find(|(k, _)| *k == image) {
                Some(&(_, at)) => at,
                None => {
                    textures.push(json!({ "source": image, "sampler": 0 }));
                    clamped.push((image, textures.len() - 1));
                    textures.len() - 1
                }
            };
            info.insert("index".into(), json!(at));
        };
        for material in &mut self.materials {
            texture_infos(material, &mut point);
        }
        self.out.materials = Value::Array(self.materials);
        self.out.textures = Value::Array(textures);
        self.out.samplers = match clamped.is_empty() {
            true => Value::Array(Vec::new()),
            false => json!([{ "wrapS": 33071, "wrapT": 33071 }]),
        };
        (self.out, self.lost)
    }
}

/// Every textureInfo (an object with an `index`) inside `v`, given to `f`.
fn texture_infos(v: &mut Value, f: &mut impl FnMut(&mut serde_json::Map<String, Value>)) {
    match v {
        Value::Object(map) => {
            if map.contains_key("index") {
                f(map);
            }
            map.values_mut().for_each(|x| texture_infos(x, f));
        }
        Value::Array(items) => items.iter_mut().for_each(|x| texture_infos(x, f)),
        _ => {}
    }
}

/// One material per texture file (a PLY's `comment TextureFile`, `ply_wedges.rs`), named by
/// it, the texture its base colour; and the files not carried, with why.
pub(super) fn texture_materials(names: &[String], base: &Path) -> (GltfMaterials, Vec<String>) {
    let mut built = Built::new(base);
    for name in names {
        let mut pbr = json!({ "metallicFactor": 0.0 });
        if let Some(t) = built.map("TextureFile", name) {
            pbr["baseColorTexture"] = json!({ "index": t });
        }
        built.materials.push(json!({ "name": name, "pbrMetallicRoughness": pbr }));
    }
    built.finish()
}

/// `materials` as glTF's, in the same order (so tobj's material ids index them), with their
/// base-colour textures read from beside `base`; and what was not carried: maps other than
/// `map_Kd`, and textures not found or not PNG or JPEG, as "material: what".
pub(super) fn gltf_materials(materials: &[tobj::Material], base: &Path) -> (GltfMaterials, Vec<String>) {
    let mut built = Built::new(base);
    let transformed = std::cell::Cell::new(false);
    let info = |t: usize, value: &str| texture_info(t, value, &transformed);
    for m in materials {
        let param = |k: &str| m.unknown_param.get(k).and_then(|v| v.trim().parse::<f64>().ok());
        let alpha = m.dissolve.or_else(|| param("Tr").map(|t| 1.0 - t)).unwrap_or(1.0).clamp(0.0, 1.0);
        let mut pbr = serde_json::Map::new();
        let label = |key: &str| format!("{}: {key}", m.name);
        // An alpha map (`map_d`) is the colour texture's own alpha where it names the same
        // file (an RGBA PNG), and is made its alpha channel where it names another.
        let colour_map = m.diffuse_texture.as_deref().map(map_file);
        let alpha_map = m.dissolve_texture.as_deref().map(map_file);
        let same = |a: &str, b: &str| find(base, a).is_some_and(|p| find(base, b) == Some(p));
        let (texture, alpha_map) = match (colour_map, alpha_map) {
            (Some(c), Some(d)) if same(c, d) => (built.map(&label("map_Kd"), c), true),
            (Some(c), Some(d)) => match built.masked(&label("map_d"), c, d) {
                Some(t) => (Some(t), true),
                None => (built.map(&label("map_Kd"), c), false),
            },
            (c, _) => (c.and_then(|c| built.map(&label("map_Kd"), c)), false),
        };
        let colour = match texture {
            Some(t) => {
                pbr.insert("baseColorTexture".into(), info(t, m.diffuse_texture.as_deref().unwrap_or_default()));
                [1.0; 3]
            }
            None => m.diffuse.unwrap_or([1.0; 3]),
        };
        pbr.insert("baseColorFactor".into(), json!([colour[0], colour[1], colour[2], alpha]));
        pbr.insert("metallicFactor".into(), json!(param("Pm").unwrap_or(0.0).clamp(0.0, 1.0)));
        let roughness = param("Pr").or_else(|| m.shininess.map(|ns| 1.0 - (ns.clamp(0.0, 1000.0) / 1000.0).sqrt()));
        if let Some(r) = roughness {
            pbr.insert("roughnessFactor".into(), json!(r.clamp(0.0, 1.0)));
        }
        let mut material = json!({ "name": m.name, "pbrMetallicRoughness": Value::Object(pbr) });
        // An alpha map of cut-outs (`image_convert::binary_alpha`) masks; other alpha blends.
        if alpha_map && alpha == 1.0 && texture.is_some_and(|t| built.cut_out(t)) {
            material["alphaMode"] = json!("MASK");
        } else if alpha < 1.0 || alpha_map && texture.is_some() {
            material["alphaMode"] = json!("BLEND");
        }
        // MTL multiplies `map_Ke` by `Ke` where it is given, as glTF does; without it, by 1.
        let maps = |key: &str| m.unknown_param.get(key).map(|v| map_file(v));
        let emissive_map = maps("map_Ke").and_then(|name| built.map(&label("map_Ke"), name));
        if let Some(t) = emissive_map {
            material["emissiveTexture"] = info(t, &m.unknown_param["map_Ke"]);
        }
        let ke = m.emissive.or(emissive_map.map(|_| [1.0; 3]));
        if let Some(ke) = ke.filter(|ke| ke.iter().any(|&c| c > 0.0)) {
            material["emissiveFactor"] = json!(ke.map(|c| c.clamp(0.0, 1.0)));
        }
        // Roughness and metallic from one file's green and blue channels are glTF's packed
        // texture (what `write_mtl.rs` writes).
        let channel = |key: &str, c: &str| {
            let words: Vec<&str> = m.unknown_param.get(key)?.split_whitespace().collect();
            words.windows(2).any(|w| w == ["-imfchan", c]).then(|| map_file(&m.unknown_param[key]))
        };
        // `norm` is a normal map; `map_Bump` is one where its pixels say so (Blender's), and
        // the same file as `norm`'s where both are written (as `write_mtl.rs` writes them).
        let mut kept = vec!["map_Ke", "norm"];
        let normal = |t: usize, value: &str| {
            let scale = value.split_whitespace().skip_while(|w| *w != "-bm").nth(1);
            let mut normal = info(t, value);
            normal["scale"] = json!(scale.and_then(|s| s.parse::<f64>().ok()).unwrap_or(1.0));
            normal
        };
        if let Some(t) = maps("norm").and_then(|name| built.map(&label("norm"), name)) {
            material["normalTexture"] = normal(t, &m.unknown_param["norm"]);
        }
        if let Some(value) = &m.normal_texture {
            let name = map_file(value);
            if material["normalTexture"].is_null() {
                if let Some(t) = built.normal_map(&label("map_Bump"), name) {
                    material["normalTexture"] = normal(t, value);
                }
            } else if find(base, name).is_none_or(|p| maps("norm").and_then(|n| find(base, n)) != Some(p)) {
                built.lost.push(format!("{}: map_Bump {name} (beside norm's normal texture)", m.name));
            }
        }
        // No MTL statement is an occlusion map; `map_ao` is what engines write (and we do).
        if let Some((key, name)) = ["map_ao", "map_AO", "map_Ao"].iter().find_map(|k| Some((*k, maps(k)?))) {
            kept.push(key);
            if let Some(t) = built.map(&label(key), name) {
                material["occlusionTexture"] = info(t, &m.unknown_param[key]);
            }
        }
        if let (Some(r), Some(mt)) = (channel("map_Pr", "g"), channel("map_Pm", "b")) {
            if r == mt {
                kept.extend(["map_Pr", "map_Pm"]);
                if let Some(t) = built.map(&label("map_Pr, map_Pm"), r) {
                    material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = info(t, &m.unknown_param["map_Pr"]);
                }
            }
        }
        built.materials.push(material);
        // Maps tobj does not know (`map_Pr`, `norm`, `disp`, ...), in a stable order.
        let mut unknown: Vec<(&String, &String)> = m
            .unknown_param
            .iter()
            .filter(|(k, _)| !kept.contains(&k.as_str()))
            .filter(|(k, _)| k.starts_with("map_") || ["norm", "disp", "decal", "refl"].contains(&k.as_str()))
            .collect();
        unknown.sort();
        for (key, value) in unknown {
            built.lost.push(format!("{}: {key} {}", m.name, map_file(value)));
        }
        let other = [
            ("map_Ka", &m.ambient_texture),
            ("map_Ks", &m.specular_texture),
            ("map_Ns", &m.shininess_texture),
            ("map_d", &m.dissolve_texture),
        ];
        for (key, map) in other {
            // An alpha map beside a colour map was kept or listed above.
            if let Some(map) = map.as_ref().filter(|_| !(key == "map_d" && colour_map.is_some())) {
                built.lost.push(format!("{}: {key} {}", m.name, map_file(map)));
            }
        }
    }
    if transformed.get() {
        built.out.extensions_used.push("KHR_texture_transform".into());
    }
    built.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_statements_name_their_file_past_the_options() {
        assert_eq!(map_file("wood grain.png"), "wood grain.png");
        assert_eq!(map_file(" -s 1 1 1 -bm 0.5 bump.jpg "), "bump.jpg");
    }

    #[test]
    fn offsets_and_scales_are_a_texture_transform_in_gltf_coordinates() {
        let used = std::cell::Cell::new(false);
        assert_eq!(texture_info(3, "wood.png", &used), json!({ "index": 3 }));
        assert_eq!(texture_info(3, "-s 1 1 1 -o 0 0 0 wood.png", &used), json!({ "index": 3 }));
        assert!(!used.get());
        let info = texture_info(0, "-o 0.25 0.5 0 -bm 2 -s 4 2 1 wood.png", &used);
        let transform = &info["extensions"]["KHR_texture_transform"];
        assert_eq!((&transform["offset"], &transform["scale"]), (&json!([0.25, -1.5]), &json!([4.0, 2.0])));
        assert!(used.get());
        // u alone: v keeps its default; a file named like a number is still the file.
        let info = texture_info(0, "-s 3 9.png", &used);
        assert_eq!(info["extensions"]["KHR_texture_transform"]["scale"], json!([3.0, 1.0]));
        // The same point of the image either way: OBJ (u, v) = (0.1, 0.2) maps to
        // (0.1 · 4 + 0.25, 0.2 · 2 + 0.5) from the bottom, glTF's (0.1, 0.8) to it from the top.
        let (u, v) = (0.1f64, 0.8f64);
        let glt = (u * 4.0 + 0.25, v * 2.0 - 1.5);
        assert!((glt.0 - 0.65).abs() < 1e-12 && (glt.1 - (1.0 - 0.9)).abs() < 1e-12, "{glt:?}");
    }
}
