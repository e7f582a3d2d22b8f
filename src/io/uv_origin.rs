//! Which way texture coordinates run. [`IndexedMesh::uvs`](crate::mesh::IndexedMesh::uvs)
//! holds them as glTF does (§3.7.2.1: the origin at the image's top-left, v down), and so do
//! the textures a GLB carries. OBJ and PLY put the origin at the bottom-left, v up (as
//! OpenGL, Blender, MeshLab and 3ds Max do), so their loaders turn v into 1 − v and their
//! writers turn it back, as Blender's glTF exporter and Cesium's obj2gltf do. Without it, a
//! texture on an OBJ converted to GLB (or the other way) comes out upside down.
//!
//! Reading rounds 1 − v to f32 once; writing gives the shortest decimal that reads back as
//! the same f32, so an OBJ written from an OBJ keeps its `vt 0.1` as `0.1`, not `0.10000002`.

/// glTF's v for `v` as a bottom-left file writes it: 1 − v, rounded to f32 once.
pub(super) fn from_bottom_left([u, v]: [f64; 2]) -> [f32; 2] {
    [u as f32, (1.0 - v) as f32]
}

/// The v a bottom-left text file writes for glTF's `v`: the decimal with the fewest digits
/// after the point that [`from_bottom_left`] reads back as `v` (1 − v itself where none does,
/// as for a NaN).
pub(super) fn to_bottom_left(v: f32) -> f64 {
    let exact = 1.0 - f64::from(v);
    (0..=17)
        .filter_map(|decimals| format!("{exact:.decimals$}").parse::<f64>().ok())
        .find(|&d| reads_back(d, v))
        .unwrap_or(exact)
}

/// The same for a file that stores v as f32 (a binary PLY): the f32 of [`to_bottom_left`]
/// where that reads back as `v`, else the f32 nearest to 1 − v (the decimal's f32 can fall
/// just outside what reads back where 1 − v is larger than v: file v = −3.3900018).
pub(super) fn to_bottom_left_f32(v: f32) -> f32 {
    let short = to_bottom_left(v) as f32;
    match reads_back(f64::from(short), v) {
        true => short,
        false => (1.0 - f64::from(v)) as f32,
    }
}

/// Whether a file's v (`file`) reads back as glTF's `v`.
pub(super) fn reads_back(file: f64, v: f32) -> bool {
    from_bottom_left([0.0, file])[1] == v
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn short_decimals_come_back_as_written() {
        for text in ["0", "1", "0.1", "0.25", "0.333333", "0.9", "0.123456", "2.5", "-3.75", "0.000001"] {
            let v: f64 = text.parse().unwrap();
            let [_, gltf] = from_bottom_left([0.0, v]);
            assert_eq!(to_bottom_left(gltf).to_string(), text, "{text}");
        }
    }

    #[test]
    fn the_image_turns_over() {
        assert_eq!(from_bottom_left([0.25, 0.0]), [0.25, 1.0]);
        assert_eq!(from_bottom_left([0.25, 1.0]), [0.25, 0.0]);
        assert_eq!(from_bottom_left([0.5, 0.2]), [0.5, 0.8]);
    }

    #[test]
    fn an_f32_the_shortest_decimal_misses_reads_back() {
        let file = f32::from_bits(0xc058_f5ca); // −3.3900018
        let [_, v] = from_bottom_left([0.0, f64::from(file)]);
        assert!(!reads_back(f64::from(to_bottom_left(v) as f32), v));
        assert_eq!(to_bottom_left_f32(v), file);
    }

    proptest! {
        /// Whatever v a text file holds, what is read from it is written so that it reads
        /// back the same, bit for bit (zero's sign aside).
        #[test]
        fn text_reads_back(file in -1e6f64..1e6) {
            let [_, v] = from_bottom_left([0.0, file]);
            prop_assert_eq!(from_bottom_left([0.0, to_bottom_left(v)])[1], v);
        }

        /// The same where the file stores v as f32.
        #[test]
        fn f32_reads_back(file in -1e6f32..1e6) {
            let [_, v] = from_bottom_left([0.0, f64::from(file)]);
            prop_assert_eq!(from_bottom_left([0.0, f64::from(to_bottom_left_f32(v))])[1], v);
        }

        /// Texture coordinates within a few tiles of the image, as f32 files hold them.
        #[test]
        fn f32_reads_back_near_the_image(file in -4f32..4.0) {
            let [_, v] = from_bottom_left([0.0, f64::from(file)]);
            prop_assert_eq!(from_bottom_left([0.0, f64::from(to_bottom_left_f32(v))])[1], v);
        }
    }
}
