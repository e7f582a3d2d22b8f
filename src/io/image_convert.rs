//! Texture files glTF cannot hold (it holds PNG and JPEG) turned into PNG through the `image`
//! crate: the TGA, BMP and TIFF textures OBJ sets and photogrammetry exports often come with,
//! and the DDS ones of game assets (block-compressed DXT1, DXT3 and DXT5, as the `image` crate
//! decodes them; BC4–BC7 and uncompressed DDS are refused with its reason). An MTL `map_d`
//! (alpha) in a file of its own is made the colour texture's alpha channel ([`with_alpha`]).
//! The pixels are kept as they are (alpha and 16-bit channels included; floating-point
//! channels become 16-bit).

use std::io::Cursor;

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{DynamicImage, ImageFormat};

/// The image in `bytes`, of any type the `image` crate here reads (the file `name`, whose
/// extension gives the type where the bytes do not: TGA has no signature); or why not.
pub(super) fn decode(bytes: &[u8], name: &str) -> Result<DynamicImage, String> {
    let format = image::guess_format(bytes).ok().or_else(|| ImageFormat::from_path(name).ok());
    let image = match format {
        Some(format) => image::load_from_memory_with_format(bytes, format),
        None => image::load_from_memory(bytes),
    };
    image.map_err(|e| format!("not a readable image: {e}"))
}

/// The colour texture in `colour` with its alpha taken from the grey levels of `mask` (an
/// MTL `map_d` beside a `map_Kd`: cut-out leaves, fences, hair), as one RGBA PNG, which is
/// how glTF holds a base colour's alpha; or why not (either unreadable, or their sizes differ).
pub(super) fn with_alpha(colour: (&[u8], &str), mask: (&[u8], &str)) -> Result<Vec<u8>, String> {
    let (rgb, grey) = (decode(colour.0, colour.1)?, decode(mask.0, mask.1)?.to_luma8());
    if rgb.width() != grey.width() || rgb.height() != grey.height() {
        let size = |w: u32, h: u32| format!("{w}×{h}");
        let (c, m) = (size(rgb.width(), rgb.height()), size(grey.width(), grey.height()));
        return Err(format!("its size {m} is not its colour texture's {c}"));
    }
    let mut rgba = rgb.to_rgba8();
    rgba.pixels_mut().zip(grey.pixels()).for_each(|(p, g)| p.0[3] = g.0[0]);
    png(&DynamicImage::ImageRgba8(rgba))
}

/// The image in `bytes` (the file `name`, whose extension gives the type where the bytes do
/// not: TGA has no signature) as a PNG; or why it cannot be.
pub(super) fn to_png(bytes: &[u8], name: &str) -> Result<Vec<u8>, String> {
    let format = image::guess_format(bytes)
        .ok()
        .or_else(|| ImageFormat::from_path(name).ok())
        .filter(|f| matches!(f, ImageFormat::Tga | ImageFormat::Bmp | ImageFormat::Tiff | ImageFormat::Dds))
        .ok_or("not a PNG or JPEG, nor a TGA, BMP, TIFF or DDS to convert")?;
    let image = image::load_from_memory_with_format(bytes, format)
        .map_err(|e| format!("not a readable {}: {e}", format.extensions_str()[0].to_uppercase()))?;
    let image = match image {
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_) => DynamicImage::ImageRgba16(image.to_rgba16()),
        other => other,
    };
    png(&image)
}

fn png(image: &DynamicImage) -> Result<Vec<u8>, String> {
    let mut png = Vec::new();
    let encoder = PngEncoder::new_with_quality(Cursor::new(&mut png), CompressionType::Fast, FilterType::Adaptive);
    image.write_with_encoder(encoder).map_err(|e| e.to_string())?;
    Ok(png)
}
