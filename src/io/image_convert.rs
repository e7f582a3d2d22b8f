//! Texture files glTF cannot hold (it holds PNG and JPEG) turned into PNG through the `image`
//! crate: the TGA, BMP and TIFF textures OBJ sets and photogrammetry exports often come with,
//! and the DDS ones of game assets (block-compressed DXT1, DXT3 and DXT5, as the `image` crate
//! decodes them; BC4–BC7 and uncompressed DDS are refused with its reason).
//! The pixels are kept as they are (alpha and 16-bit channels included; floating-point
//! channels become 16-bit).

use std::io::Cursor;

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{DynamicImage, ImageFormat};

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
    let mut png = Vec::new();
    let encoder = PngEncoder::new_with_quality(Cursor::new(&mut png), CompressionType::Fast, FilterType::Adaptive);
    image.write_with_encoder(encoder).map_err(|e| e.to_string())?;
    Ok(png)
}
