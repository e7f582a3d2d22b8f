//! Texture files glTF cannot hold (it holds PNG and JPEG) turned into PNG through the `image`
//! crate: the TGA, BMP and TIFF textures OBJ sets and photogrammetry exports often come with,
//! and the DDS ones of game assets (block-compressed DXT1, DXT3 and DXT5, as the `image` crate
//! decodes them; BC4–BC7 and uncompressed DDS are refused with its reason). An MTL `map_d`
//! (alpha) in a file of its own is made the colour texture's alpha channel ([`with_alpha`]).
//! The pixels are kept as they are (alpha and 16-bit channels included; floating-point
//! channels become 16-bit).

use std::io::Cursor;

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{DynamicImage, GenericImageView, ImageFormat};

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

/// At most this many pixels a side are looked at where an image's pixels are judged
/// (`bump_map.rs`, [`binary_alpha`]), on an even grid.
const SAMPLES: u32 = 256;

/// The pixel in the middle of cell `i` of `SAMPLES` (or of `size`, if fewer) over `size`.
fn sample(i: u32, size: u32) -> u32 {
    let cells = size.min(SAMPLES);
    ((2 * u64::from(i) + 1) * u64::from(size) / (2 * u64::from(cells))) as u32
}

/// The RGBA (8-bit) of at most `SAMPLES`² pixels of `image`, each the middle of its cell of
/// an even grid (so a 1-pixel image is looked at too).
pub(super) fn grid(image: &DynamicImage) -> impl Iterator<Item = [u8; 4]> + '_ {
    let (w, h) = image.dimensions();
    (0..h.min(SAMPLES))
        .flat_map(move |y| (0..w.min(SAMPLES)).map(move |x| image.get_pixel(sample(x, w), sample(y, h)).0))
}

/// Whether the image in `bytes` (the file `name`) has an alpha channel of cut-outs: at least
/// 99 % of it within 2 % of transparent or opaque, some of it transparent. Leaves, fences and
/// hair cards are so, and want glTF's MASK (drawn without sorting) rather than BLEND.
pub(super) fn binary_alpha(bytes: &[u8], name: &str) -> Result<bool, String> {
    Ok(cut_out(&decode(bytes, name)?))
}

/// [`binary_alpha`] of a decoded image.
fn cut_out(image: &DynamicImage) -> bool {
    if !image.color().has_alpha() {
        return false;
    }
    let (mut count, mut edge, mut clear) = (0usize, 0usize, false);
    for [.., a] in grid(image) {
        count += 1;
        edge += usize::from(!(6..250).contains(&a));
        clear |= a < 6;
    }
    clear && edge as f64 >= 0.99 * count as f64
}

/// The colour texture in `colour` with its alpha taken from the grey levels of `mask` (an
/// MTL `map_d` beside a `map_Kd`: cut-out leaves, fences, hair), as one RGBA PNG, which is
/// how glTF holds a base colour's alpha, and whether that alpha is cut-outs
/// ([`binary_alpha`]); or why not (either unreadable, or their sizes differ).
pub(super) fn with_alpha(colour: (&[u8], &str), mask: (&[u8], &str)) -> Result<(Vec<u8>, bool), String> {
    let (rgb, grey) = (decode(colour.0, colour.1)?, decode(mask.0, mask.1)?.to_luma8());
    if rgb.width() != grey.width() || rgb.height() != grey.height() {
        let size = |w: u32, h: u32| format!("{w}×{h}");
        let (c, m) = (size(rgb.width(), rgb.height()), size(grey.width(), grey.height()));
        return Err(format!("its size {m} is not its colour texture's {c}"));
    }
    let mut rgba = rgb.to_rgba8();
    rgba.pixels_mut().zip(grey.pixels()).for_each(|(p, g)| p.0[3] = g.0[0]);
    let image = DynamicImage::ImageRgba8(rgba);
    Ok((png(&image)?, cut_out(&image)))
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

#[cfg(test)]
mod tests {
    use super::*;

    fn png_of(image: DynamicImage) -> Vec<u8> {
        png(&image).unwrap()
    }

    #[test]
    fn the_grid_covers_the_image_without_leaving_it() {
        assert_eq!((sample(0, 1), sample(0, 2), sample(1, 2)), (0, 0, 1));
        assert_eq!((sample(0, 1024), sample(255, 1024)), (2, 1022));
        for size in [1, 2, 255, 256, 257, 4096, u32::MAX] {
            assert!(sample(size.min(SAMPLES) - 1, size) < size);
        }
        let image = DynamicImage::ImageLuma8(image::GrayImage::from_fn(600, 3, |x, _| image::Luma([(x % 256) as u8])));
        assert_eq!(grid(&image).count(), 256 * 3);
    }

    #[test]
    fn cut_outs_are_told_from_smooth_alpha() {
        let alpha = |f: fn(u32, u32) -> u8| {
            png_of(DynamicImage::ImageRgba8(image::RgbaImage::from_fn(64, 64, |x, y| image::Rgba([9, 9, 9, f(x, y)]))))
        };
        assert_eq!(binary_alpha(&alpha(|x, _| if x < 20 { 0 } else { 255 }), "a.png"), Ok(true));
        // A JPEG-like edge of a few grey levels still cuts out; a gradient blends; all opaque
        // has nothing to cut.
        assert_eq!(binary_alpha(&alpha(|x, y| if x < 20 { 3 } else { 255 - (y % 5) as u8 }), "a.png"), Ok(true));
        assert_eq!(binary_alpha(&alpha(|x, _| (x * 4) as u8), "a.png"), Ok(false));
        assert_eq!(binary_alpha(&alpha(|_, _| 255), "a.png"), Ok(false));
        let rgb = png_of(DynamicImage::ImageRgb8(image::RgbImage::new(4, 4)));
        assert_eq!(binary_alpha(&rgb, "a.png"), Ok(false));
    }
}
