//! How far a simplified mesh's attributes (normals, texture coordinates, colours, tangents)
//! stray from the original's, sampled like the Hausdorff distance: points spread by area over
//! one surface's faces, each compared with the nearest point of the other surface, both ways.
//! A point's attribute is what its face interpolates there (normals renormalised); the figure
//! is the Euclidean distance between the two values, in the attribute's own units (colours
//! 0–1, texture coordinates in texture space, normals as unit vectors: 2 is opposite).
//!
//! Only interior samples are used: a vertex or an edge of a seam has two values, and either
//! would be as right as the other. A sample whose nearest point lies on the other side of a
//! seam is still compared with that side, so texture coordinates near seams can show large
//! maxima; the RMS is the figure to compare methods by.

use glam::DVec3;
use rayon::prelude::*;

use super::bvh::Bvh;
use super::hausdorff::{HausdorffOptions, OneSided};
use super::sampling::sample_interior;
use crate::mesh::{IndexedMesh, Primitive, VertexAttribute};

/// One attribute's error both ways.
#[derive(Debug, Clone, PartialEq)]
pub struct AttributeError {
    /// The glTF semantic (`NORMAL`, `TEXCOORD_0`, `COLOR_0`, ...).
    pub semantic: String,
    /// From the original's samples to the simplified surface.
    pub forward: OneSided,
    /// From the simplified surface's samples to the original.
    pub backward: OneSided,
    /// max(forward.max, backward.max).
    pub max: f64,
    /// max(forward.mean, backward.mean).
    pub mean: f64,
    /// max(forward.rms, backward.rms).
    pub rms: f64,
}

/// One attribute of a mesh, as the measure reads it.
struct Values<'m> {
    mesh: &'m IndexedMesh,
    values: &'m [f32],
    /// Values per vertex.
    stride: usize,
    /// Of which the first `components` are compared.
    components: usize,
    normalise: bool,
    /// Whether triangle t's primitive has the attribute.
    present: Box<dyn Fn(usize) -> bool + Sync + 'm>,
}

impl Values<'_> {
    /// The value face `t` interpolates at barycentric `w`, or `None` where its primitive
    /// lacks the attribute.
    fn at(&self, t: usize, w: [f64; 3], out: &mut [f64; 4]) -> bool {
        if !(self.present)(t) {
            return false;
        }
        let c = self.components;
        *out = [0.0; 4];
        for (k, &v) in self.mesh.triangles[t].iter().enumerate() {
            for (i, o) in out.iter_mut().enumerate().take(c) {
                *o += w[k] * f64::from(self.values[v as usize * self.stride + i]);
            }
        }
        if self.normalise {
            let len = out.iter().map(|x| x * x).sum::<f64>().sqrt();
            if len > 0.0 {
                out.iter_mut().for_each(|x| *x /= len);
            }
        }
        true
    }
}

/// The attributes both meshes carry, by semantic.
fn common<'a>(a: &'a IndexedMesh, b: &'a IndexedMesh) -> Vec<(String, Values<'a>, Values<'a>)> {
    // Normals and TEXCOORD_0: absent from a primitive by its flag.
    fn per_vertex<'a>(
        m: &'a IndexedMesh,
        values: &'a [f32],
        stride: usize,
        normalise: bool,
        lacks: fn(&Primitive) -> bool,
    ) -> Values<'a> {
        let present = move |t: usize| !m.primitives.get(m.primitive_of(t) as usize).is_some_and(lacks);
        Values { mesh: m, values, stride, components: stride, normalise, present: Box::new(present) }
    }
    let mut out = Vec::new();
    if !a.normals.is_empty() && !b.normals.is_empty() {
        let v = |m: &'a IndexedMesh| per_vertex(m, m.normals.as_flattened(), 3, true, |p| p.no_normals);
        out.push(("NORMAL".to_string(), v(a), v(b)));
    }
    if !a.uvs.is_empty() && !b.uvs.is_empty() {
        let v = |m: &'a IndexedMesh| per_vertex(m, m.uvs.as_flattened(), 2, false, |p| p.no_uvs);
        out.push(("TEXCOORD_0".to_string(), v(a), v(b)));
    }
    // Joints, weights and morph deltas are not values a surface interpolates.
    for x in a.attributes.iter().filter(|x| !x.scene_only()) {
        let Some(y) = b.attributes.iter().find(|y| y.semantic == x.semantic && y.components == x.components) else {
            continue;
        };
        // A tangent's handedness is not a value to interpolate: its direction is compared.
        let v = |m: &'a IndexedMesh, att: &'a VertexAttribute| Values {
            mesh: m,
            values: &att.values,
            stride: att.components,
            components: att.varying_components(),
            normalise: att.semantic == "TANGENT",
            present: Box::new(move |t| att.present_in(m.primitive_of(t))),
        };
        out.push((x.semantic.clone(), v(a, x), v(b, y)));
    }
    out
}

/// Barycentric coordinates of `p` (a point on the triangle's plane) in triangle `t`.
fn barycentric(p: [f32; 3], t: &[[f32; 3]; 3]) -> [f64; 3] {
    let [a, b, c] = t.map(|x| DVec3::from(x.map(f64::from)));
    let p = DVec3::from(p.map(f64::from));
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let den = d00 * d11 - d01 * d01;
    if den <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    [1.0 - v - w, v, w]
}

/// The error of `to`'s values against `from`'s at `from`'s samples.
fn one_sided(
    samples: &[(u32, [f32; 3])],
    from_tris: &[[[f32; 3]; 3]],
    from: &Values<'_>,
    to_tris: &[[[f32; 3]; 3]],
    to: &Values<'_>,
    to_bvh: &Bvh,
) -> OneSided {
    const CHUNK: usize = 4096;
    let c = from.components;
    let parts: Vec<(f64, f64, f64, usize)> = samples
        .par_chunks(CHUNK)
        .map(|chunk| {
            let (mut mx, mut s, mut s2, mut n) = (0.0f64, 0.0, 0.0, 0);
            let (mut va, mut vb) = ([0.0; 4], [0.0; 4]);
            for &(f, w) in chunk {
                if !from.at(f as usize, w.map(f64::from), &mut va) {
                    continue;
                }
                let t = &from_tris[f as usize];
                let p = std::array::from_fn(|i| w[0] * t[0][i] + w[1] * t[1][i] + w[2] * t[2][i]);
                let Some(near) = to_bvh.nearest(p) else { continue };
                let g = near.triangle as usize;
                if !to.at(g, barycentric(near.point, &to_tris[g]), &mut vb) {
                    continue;
                }
                let d = (0..c).map(|i| (va[i] - vb[i]).powi(2)).sum::<f64>().sqrt();
                (mx, s, s2, n) = (mx.max(d), s + d, s2 + d * d, n + 1);
            }
            (mx, s, s2, n)
        })
        .collect();
    let (mx, s, s2, n) =
        parts.iter().fold((0.0f64, 0.0, 0.0, 0), |a, b| (a.0.max(b.0), a.1 + b.1, a.2 + b.2, a.3 + b.3));
    let k = n.max(1) as f64;
    OneSided { max: mx, mean: s / k, rms: (s2 / k).sqrt(), samples: n }
}

/// The error of every attribute both meshes carry (normals, texture coordinates, colours,
/// tangents' directions), both ways, at `options.density` interior samples per face.
pub fn attribute_errors(
    original: &IndexedMesh,
    simplified: &IndexedMesh,
    options: HausdorffOptions,
) -> Vec<AttributeError> {
    let pairs = common(original, simplified);
    if pairs.is_empty() {
        return Vec::new();
    }
    let (ta, tb) = (super::corners(original, original.origin), super::corners(simplified, original.origin));
    let (sa, sb) = (sample_interior(&ta, options.density), sample_interior(&tb, options.density));
    let (ba, bb) = rayon::join(|| Bvh::new(&ta), || Bvh::new(&tb));
    pairs
        .into_iter()
        .map(|(semantic, va, vb)| {
            let (forward, backward) =
                rayon::join(|| one_sided(&sa, &ta, &va, &tb, &vb, &bb), || one_sided(&sb, &tb, &vb, &ta, &va, &ba));
            AttributeError {
                semantic,
                max: forward.max.max(backward.max),
                mean: forward.mean.max(backward.mean),
                rms: forward.rms.max(backward.rms),
                forward,
                backward,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::VertexAttribute;
    use crate::procedural;

    fn ramp(m: &mut IndexedMesh, slope: f32) {
        let v = m.positions.iter().flat_map(|p| [slope * p[0], 0.5, 1.0]).collect();
        m.attributes = vec![VertexAttribute::new("COLOR_0", 3, v)];
    }

    /// Two identical grids whose red channels are ramps of slopes 0.1 and 0.3: the colours
    /// differ by 0.2·x at every point, so the RMS over the unit-spaced grid [0, 4]² is
    /// 0.2·√(mean of x²) = 0.2·√(16/3), and the maximum approaches 0.2·4.
    #[test]
    fn two_ramps_differ_by_their_slopes() {
        let mut a = procedural::grid(4, 4, |_, _| false);
        let mut b = a.clone();
        ramp(&mut a, 0.1);
        ramp(&mut b, 0.3);
        let (lo, hi) = a.bounds();
        assert_eq!((lo[0], hi[0]), (0.0, 4.0), "the grid spans [0, 4]");
        let e = attribute_errors(&a, &b, HausdorffOptions::default().density(2000.0));
        assert_eq!(e.len(), 1);
        assert_eq!(e[0].semantic, "COLOR_0");
        let want = 0.2 * (16.0f64 / 3.0).sqrt();
        assert!((e[0].rms - want).abs() < 0.01 * want, "rms {} vs {want}", e[0].rms);
        assert!(e[0].max <= 0.8 + 1e-6 && e[0].max > 0.78, "max {}", e[0].max);
        let same = attribute_errors(&a, &a, HausdorffOptions::default());
        assert!(same[0].max < 1e-6, "{:?}", same[0]);
    }

    /// Meshes with no attribute in common have nothing to compare.
    #[test]
    fn nothing_in_common_gives_nothing() {
        let mut a = procedural::grid(2, 2, |_, _| false);
        let b = a.clone();
        ramp(&mut a, 1.0);
        assert!(attribute_errors(&a, &b, HausdorffOptions::default()).is_empty());
    }
}
