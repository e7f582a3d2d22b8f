//! Coordinates far from the file's origin. A scan exported in world coordinates (a survey's
//! UTM metres, a part placed in its assembly, a tile of a city model) can lie millions of its
//! own sizes from the origin, where f32 cannot tell its vertices apart: at 10⁶, f32 steps are
//! 6 cm, and a 25 cm bunny there welds into 33 vertices. Every algorithm here runs on f32
//! positions, so the loaders read coordinates as f64 and, where f32 would lose precision,
//! keep them relative to a round point at the bounds' centre: the mesh's `origin`
//! ([`crate::IndexedMesh::origin`]), which every writer adds back.
//!
//! Meshes within [`FAR`] diagonals of the origin (every mesh in `../shared/meshes`: at most
//! 1.1) are read exactly as before, bit for bit.

use std::borrow::Cow;

/// A mesh whose farthest coordinate lies more than this many bounding-box diagonals from the
/// file's origin is read relative to its centre. At 16 diagonals, f32 steps are at most
/// 2⁻¹⁹ of the diagonal (2 µm on a 1 m scan): closer meshes lose nothing worth a move.
pub const FAR: f64 = 16.0;

/// `points` as f32, and the origin they are relative to: zero unless the points lie more than
/// [`FAR`] diagonals from it, else the bounds' centre rounded to a multiple of the largest
/// power of ten no longer than the diagonal (so it reads as a round number, and positions
/// stay within a diagonal of zero). Non-finite points are converted as they are (the mesh
/// check names them).
pub fn relative_positions(points: &[[f64; 3]]) -> (Vec<[f32; 3]>, [f64; 3]) {
    let origin = far_origin(points.iter().copied()).unwrap_or([0.0; 3]);
    (relative_to(points, origin), origin)
}

/// `points` less `origin`, as f32.
pub fn relative_to(points: &[[f64; 3]], origin: [f64; 3]) -> Vec<[f32; 3]> {
    points.iter().map(|p| std::array::from_fn(|k| (p[k] - origin[k]) as f32)).collect()
}

/// [`relative_positions`] for points read as f32 (binary STL): they have lost what they lost,
/// but moving them near zero still keeps every later computation (quadrics, normals, screen
/// errors) out of the cancellation their distance from the origin would cause. Every glTF
/// and STL load comes through here: near meshes are returned as they are, with one pass over
/// them and nothing allocated.
pub fn relative_f32_positions(points: Vec<[f32; 3]>) -> (Vec<[f32; 3]>, [f64; 3]) {
    match far_origin(points.iter().map(|p| p.map(f64::from))) {
        Some(origin) => {
            let relative = points.iter().map(|p| std::array::from_fn(|k| (f64::from(p[k]) - origin[k]) as f32));
            (relative.collect(), origin)
        }
        None => (points, [0.0; 3]),
    }
}

/// The origin [`relative_positions`] picks for `points`, where they lie far from zero.
pub fn far_origin(points: impl IntoIterator<Item = [f64; 3]>) -> Option<[f64; 3]> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        if !p.iter().all(|c| c.is_finite()) {
            return None;
        }
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    let farthest = (0..3).map(|k| lo[k].abs().max(hi[k].abs())).fold(0.0, f64::max);
    // No points: infinite bounds, so not finite either.
    if !diagonal.is_finite() || diagonal == 0.0 || farthest <= FAR * diagonal {
        return None;
    }
    let exponent = diagonal.log10().floor() as i32;
    Some(std::array::from_fn(|k| round_to_power_of_ten((lo[k] + hi[k]) / 2.0, exponent)))
}

/// `x` rounded to a multiple of 10^`exponent`, as the f64 nearest that decimal (so that it
/// prints as the round number it is).
fn round_to_power_of_ten(x: f64, exponent: i32) -> f64 {
    let multiple = (x / 10f64.powi(exponent)).round();
    format!("{multiple}e{exponent}").parse().unwrap_or(x)
}

/// One coordinate in the file's coordinates, for printing: `relative` as Rust prints an f32
/// where `origin` is zero (nothing allocated: every near mesh's OBJ), else [`decimal_sum`].
#[derive(Debug, Clone, Copy)]
pub struct InFile(pub f64, pub f32);

impl std::fmt::Display for InFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            0.0 => write!(f, "{}", self.1),
            origin => f.write_str(&decimal_sum(origin, self.1)),
        }
    }
}

/// `origin + relative` as the shortest decimal text that reads back as `relative` (as the
/// loaders read it: in f64, less `origin`, to f32). A coordinate read as `500.1` relative to
/// `496` comes out as `500.1`, not as the f64 sum `500.09999990463257`.
pub fn decimal_sum(origin: f64, relative: f32) -> String {
    if origin == 0.0 {
        return relative.to_string();
    }
    let sum = origin + f64::from(relative);
    (0..=17)
        .map(|decimals| format!("{sum:.decimals$}"))
        .find(|text| text.parse::<f64>().is_ok_and(|x| (x - origin) as f32 == relative))
        .unwrap_or_else(|| sum.to_string())
}

/// `positions` re-expressed relative to `to` instead of `from` (in f64, then f32); borrowed
/// as they are when the two origins are the same.
pub fn rebased<'a>(positions: &'a [[f32; 3]], from: [f64; 3], to: [f64; 3]) -> Cow<'a, [[f32; 3]]> {
    if from == to {
        return Cow::Borrowed(positions);
    }
    let shift: [f64; 3] = std::array::from_fn(|k| from[k] - to[k]);
    Cow::Owned(positions.iter().map(|p| std::array::from_fn(|k| (f64::from(p[k]) + shift[k]) as f32)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meshes_near_their_origin_are_read_as_they_are() {
        let points = [[0.1, 0.2, 0.3], [-0.5, 1.0, 2.0], [16.0, 0.0, 0.0]];
        let (p, origin) = relative_positions(&points);
        assert_eq!(origin, [0.0; 3]);
        assert_eq!(p, points.map(|q| q.map(|c| c as f32)));
    }

    #[test]
    fn far_meshes_keep_their_precision_relative_to_a_round_centre() {
        // 2 mm apart, 4,123,456 m from the origin: f32 steps there are 50 cm.
        let points = [[4_123_456.0, 512_345.0, 101.5], [4_123_456.002, 512_345.002, 101.502]];
        let (p, origin) = relative_positions(&points);
        assert_eq!(origin, [4_123_456.001, 512_345.001, 101.501], "the centre, to the millimetre (diagonal 3.5 mm)");
        let back: Vec<[f64; 3]> = p.iter().map(|q| std::array::from_fn(|k| origin[k] + f64::from(q[k]))).collect();
        for (b, a) in back.iter().zip(&points) {
            for k in 0..3 {
                assert!((b[k] - a[k]).abs() < 1e-9, "{b:?} against {a:?}");
            }
        }
        assert_ne!(p[0], p[1]);
        // Read without the origin, the two points would have one x.
        assert_eq!(points[0][0] as f32, points[1][0] as f32);
    }

    #[test]
    fn decimal_sums_give_back_the_text_that_was_read() {
        for (origin, text) in [
            (496.0, "500.1"),
            (4_123_456.0, "4123456.001"),
            (4_123_456.0, "4123456.016"),
            (4_123_456.0, "4123455.75"),
            (-100.0, "-99.5"),
            (1.5, "0"),
            (0.001, "0.0005"),
            (512_345.0, "512345.123"),
        ] {
            let relative = (text.parse::<f64>().unwrap() - origin) as f32;
            assert_eq!(decimal_sum(origin, relative), text, "relative {relative} to {origin}");
        }
        assert_eq!(decimal_sum(0.0, 0.1), "0.1", "no origin: the f32's own shortest text");
    }

    #[test]
    fn rebasing_moves_positions_between_origins() {
        let p = [[0.5f32, -0.25, 0.0]];
        assert!(matches!(rebased(&p, [1.0; 3], [1.0; 3]), Cow::Borrowed(_)));
        assert_eq!(rebased(&p, [10.0, 0.0, 0.0], [0.0, 0.0, 1.0]).into_owned(), vec![[10.5, -0.25, -1.0]]);
    }
}
