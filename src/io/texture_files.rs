//! Texture images written as files beside an OBJ or PLY output, named after it
//! (`lod1_wood.png`): for an OBJ's MTL library (`write_mtl.rs`), and the textures a PLY
//! names, as MeshLab writes them (`comment TextureFile`, read back by `ply.rs`).

use serde_json::Value;

use crate::mesh::{GltfMaterials, IndexedMesh};

/// `name` as a word an OBJ, MTL or PLY statement can hold: what is not a letter, digit, `.`,
/// `-` or `_` becomes `_`.
pub(super) fn word(name: &str) -> String {
    name.chars().map(|c| if c.is_alphanumeric() || ".-_".contains(c) { c } else { '_' }).collect()
}

/// The file name image `k` of `mats` gets beside an output named `stem` (already a
/// [`word`]): `stem_name.png` after the image's own name, `stem_texture{k}.png` without one,
/// `.jpg` for a JPEG; or why it cannot be written (its bytes were never read, or they are
/// not a PNG or JPEG).
fn image_file(stem: &str, mats: &GltfMaterials, k: usize) -> Result<String, String> {
    let Some((img, bytes)) = mats.images.get(k).and_then(|i| Some((i, i.bytes.as_deref()?))) else {
        return Err("its image was not read".into());
    };
    let ext = match super::gltf_resources::image_type(bytes) {
        Some("image/png") => "png",
        Some(_) => "jpg",
        None => return Err(format!("an image of type {}", img.mime_type.as_deref().unwrap_or("unknown"))),
    };
    let own = img.name.as_deref().map(|n| word(n.rsplit_once('.').map_or(n, |(stem, _)| stem)));
    let own = own.filter(|n| !n.is_empty()).unwrap_or_else(|| format!("texture{k}"));
    Ok(format!("{stem}_{own}.{ext}"))
}

/// The texture images written beside one output: each image once, each file name its own.
#[derive(Default)]
pub(super) struct TextureFiles(pub Vec<(String, usize)>);

impl TextureFiles {
    /// The place among the files of image `k` of `mats`, beside an output named `stem` (a
    /// [`word`]): the one it has already, else a new one under [`image_file`]'s name,
    /// numbered where another image took that name; or why it cannot be written.
    pub(super) fn add(&mut self, stem: &str, mats: &GltfMaterials, k: usize) -> Result<usize, String> {
        if let Some(place) = self.0.iter().position(|(_, i)| *i == k) {
            return Ok(place);
        }
        let mut file = image_file(stem, mats, k)?;
        if self.0.iter().any(|(f, _)| *f == file) {
            let (stem, ext) = file.rsplit_once('.').unwrap_or((&file, ""));
            file = format!("{stem}_{k}.{ext}");
        }
        self.0.push((file, k));
        Ok(self.0.len() - 1)
    }
}

/// The image a glTF textureInfo shows (through its texture's `source`).
pub(super) fn source(mats: &GltfMaterials, info: &Value) -> Option<usize> {
    let texture = &mats.textures[info["index"].as_u64()? as usize];
    texture["source"].as_u64().map(|i| i as usize)
}

/// The textures a PLY output names, as MeshLab writes them: `comment TextureFile` per
/// image; with more than one, texture coordinates per face corner and a texture number per
/// face.
pub(super) struct PlyTextures {
    /// The files, in the order the texture numbers count them, and the image each holds.
    pub files: TextureFiles,
    /// The texture number of each primitive.
    pub number: Vec<u32>,
}

/// The textures a PLY output named `stem` can name: where the mesh has texture coordinates
/// and every primitive's material shows an image as its base colour, on TEXCOORD_0, each
/// image written as [`image_file`] names it.
pub(super) fn ply_textures(m: &IndexedMesh, stem: &str) -> Option<PlyTextures> {
    let mats = m.gltf_materials.as_ref()?;
    if m.uvs.is_empty() || m.primitives.is_empty() {
        return None;
    }
    let stem = word(stem);
    let mut out = PlyTextures { files: TextureFiles::default(), number: Vec::new() };
    for p in &m.primitives {
        let info = &mats.materials[p.material?]["pbrMetallicRoughness"]["baseColorTexture"];
        let image = source(mats, info).filter(|_| info["texCoord"].as_u64().unwrap_or(0) == 0)?;
        out.number.push(out.files.add(&stem, mats, image).ok()? as u32);
    }
    Some(out)
}

/// Whether every primitive's material is its base-colour texture alone (what a PLY's
/// `TextureFile` holds): no other texture, the default colour factor, opaque, no
/// extensions. Metallic and roughness factors are taken as shading MeshLab has none of.
pub(super) fn texture_alone(m: &IndexedMesh) -> bool {
    let Some(mats) = m.gltf_materials.as_ref() else { return false };
    m.primitives.iter().filter_map(|p| p.material).all(|k| {
        let material = &mats.materials[k];
        let pbr = &material["pbrMetallicRoughness"];
        let white = pbr["baseColorFactor"].as_array().is_none_or(|c| c.iter().all(|x| x.as_f64() == Some(1.0)));
        let others = ["normalTexture", "emissiveTexture", "occlusionTexture", "extensions"];
        white
            && pbr["metallicRoughnessTexture"].is_null()
            && others.iter().all(|k| material[k].is_null())
            && material["alphaMode"].as_str().is_none_or(|a| a == "OPAQUE")
            && material["emissiveFactor"].as_array().is_none_or(|c| c.iter().all(|x| x.as_f64() == Some(0.0)))
    })
}
