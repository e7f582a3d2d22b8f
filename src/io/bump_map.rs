//! What an MTL `map_Bump` (or `bump`) holds, told from its pixels. The statement means a
//! height map in the MTL specification, to three.js and to Assimp; Blender writes its normal
//! maps with it and reads it back as one, and so does most of what an artist's OBJ comes from.
//! The two look nothing alike: a height map is grey, and a tangent-space normal map's pixels
//! are unit vectors `2c − 1` leaning out of the surface (blue at least half, the flat
//! (128, 128, 255) most common). So the map is a normal texture where its pixels say so, and
//! is listed as not kept otherwise (glTF has no height map; an object-space normal map, whose
//! vectors point every way, is not glTF's normal texture either).

use image::DynamicImage;

/// What a bump map's pixels are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum BumpKind {
    /// A tangent-space normal map: glTF's normal texture.
    Normal,
    /// Grey levels: a height map.
    Height,
    /// Colours that are not unit vectors out of the surface.
    Neither,
}

impl BumpKind {
    /// Why a map of this kind is not kept as a normal texture.
    pub(super) fn why_not(self) -> &'static str {
        match self {
            BumpKind::Normal => "",
            BumpKind::Height => "a height map by its pixels; glTF has none",
            BumpKind::Neither => "not a tangent-space normal map nor a height map by its pixels",
        }
    }
}

/// The kind of the bump map in `bytes` (the file `name`, whose extension gives the type
/// where the bytes do not); or why it cannot be read.
pub(super) fn kind(bytes: &[u8], name: &str) -> Result<BumpKind, String> {
    Ok(classify(&super::image_convert::decode(bytes, name)?))
}

fn classify(image: &DynamicImage) -> BumpKind {
    if !image.color().has_color() {
        return BumpKind::Height;
    }
    let (mut grey, mut unit, mut lean, mut count) = (0usize, 0usize, 0.0f64, 0usize);
    for [r, g, b, _] in super::image_convert::grid(image) {
        count += 1;
        let spread = r.max(g).max(b) - r.min(g).min(b);
        grey += usize::from(spread <= 3);
        let n = [r, g, b].map(|c| f64::from(c) / 127.5 - 1.0);
        let length2 = n.iter().map(|c| c * c).sum::<f64>();
        unit += usize::from(n[2] >= -0.05 && (length2 - 1.0).abs() <= 0.4);
        lean += n[2];
    }
    let share = |k: usize| k as f64 / count as f64;
    if share(grey) >= 0.98 {
        BumpKind::Height
    } else if share(unit) >= 0.95 && lean / count as f64 >= 0.5 {
        BumpKind::Normal
    } else {
        BumpKind::Neither
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, ImageFormat, Rgb, RgbImage};

    /// A bumpy patch: heights h(x, y), and the tangent-space normal map of the same surface.
    fn surface(w: u32, h: u32) -> (GrayImage, RgbImage) {
        let height = |x: f64, y: f64| (x * 0.3).sin() * (y * 0.2).cos();
        let grey = GrayImage::from_fn(w, h, |x, y| image::Luma([(127.0 + 100.0 * height(x as f64, y as f64)) as u8]));
        let normal = RgbImage::from_fn(w, h, |x, y| {
            let (x, y) = (x as f64, y as f64);
            let (dx, dy) = (height(x + 0.5, y) - height(x - 0.5, y), height(x, y + 0.5) - height(x, y - 0.5));
            let len = (dx * dx + dy * dy + 1.0).sqrt();
            Rgb([-dx / len, -dy / len, 1.0 / len].map(|c| ((c + 1.0) * 127.5).round() as u8))
        });
        (grey, normal)
    }

    fn png(image: DynamicImage) -> Vec<u8> {
        let mut bytes = Vec::new();
        image.write_to(&mut std::io::Cursor::new(&mut bytes), ImageFormat::Png).unwrap();
        bytes
    }

    #[test]
    fn normal_maps_height_maps_and_colours_are_told_apart() {
        let (grey, normal) = surface(300, 200);
        assert_eq!(kind(&png(normal.clone().into()), "n.png"), Ok(BumpKind::Normal));
        assert_eq!(kind(&png(grey.clone().into()), "h.png"), Ok(BumpKind::Height));
        // A height map saved in colour is still grey.
        assert_eq!(kind(&png(DynamicImage::from(grey).into_rgb8().into()), "h.png"), Ok(BumpKind::Height));
        // A flat normal map, one pixel.
        assert_eq!(kind(&png(RgbImage::from_pixel(1, 1, Rgb([128, 128, 255])).into()), "f.png"), Ok(BumpKind::Normal));
        // A colour texture (a gradient of hues), and an object-space normal map (vectors
        // pointing every way): neither.
        let colour = RgbImage::from_fn(64, 64, |x, y| Rgb([(x * 4) as u8, (y * 4) as u8, 40]));
        assert_eq!(kind(&png(colour.into()), "c.png"), Ok(BumpKind::Neither));
        let object = RgbImage::from_fn(64, 64, |x, _| {
            let a = x as f64 / 64.0 * std::f64::consts::TAU;
            Rgb([a.cos(), 0.0, a.sin()].map(|c| ((c + 1.0) * 127.5).round() as u8))
        });
        assert_eq!(kind(&png(object.into()), "o.png"), Ok(BumpKind::Neither));
        // A normal map with its blue channel dropped (some engines keep only x and y).
        let mut flat = normal.clone();
        flat.pixels_mut().for_each(|p| p.0[2] = 0);
        assert_eq!(kind(&png(flat.into()), "n.png"), Ok(BumpKind::Neither));
        assert!(kind(b"not an image", "n.png").unwrap_err().starts_with("not a readable image"));
    }

    #[test]
    fn a_jpeg_normal_map_reads_as_one_through_its_artefacts() {
        let (_, normal) = surface(256, 256);
        let mut bytes = Vec::new();
        let encoder = image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 60);
        DynamicImage::from(normal).write_with_encoder(encoder).unwrap();
        assert_eq!(kind(&bytes, "n.jpg"), Ok(BumpKind::Normal));
    }
}
