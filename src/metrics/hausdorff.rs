//! Symmetric Hausdorff distance between two surfaces, in the manner of Metro: sample each
//! surface (see `sampling.rs`), find each sample's nearest point on the other surface through
//! a BVH, and report max, mean and RMS of those distances, one-sided both ways and combined.
//!
//! The symmetric figures take the larger of the two one-sided values (as the Hausdorff
//! distance does for the max). Percentages are of the first (original) mesh's bounding-box
//! diagonal. Distances are computed in parallel; sums are taken per fixed chunk and added in
//! order, so the result is the same for any thread count.

use rayon::prelude::*;

use super::bvh::Bvh;
use super::sampling::sample;
use crate::mesh::{bounds, IndexedMesh};

/// How densely to sample.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct HausdorffOptions {
    /// Interior samples per face, on average, spread by area. Default: 10.
    pub density: f32,
}

impl Default for HausdorffOptions {
    fn default() -> Self {
        Self { density: 10.0 }
    }
}

impl HausdorffOptions {
    /// Sets [`HausdorffOptions::density`].
    pub fn density(mut self, d: f32) -> Self {
        self.density = d;
        self
    }
}

/// Distances from the samples of one surface to the other.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OneSided {
    /// Largest distance.
    pub max: f64,
    /// Mean distance.
    pub mean: f64,
    /// Root mean square distance.
    pub rms: f64,
    /// Number of samples.
    pub samples: usize,
}

/// Both directions and the symmetric figures, absolute and relative.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Hausdorff {
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
    /// Bounding-box diagonal of the original.
    pub diagonal: f64,
}

impl Hausdorff {
    /// `x` as a percentage of the original's bounding-box diagonal.
    pub fn pct(&self, x: f64) -> f64 {
        if self.diagonal > 0.0 {
            100.0 * x / self.diagonal
        } else {
            0.0
        }
    }
}

fn one_sided(samples: &[[f32; 3]], target: &Bvh) -> OneSided {
    const CHUNK: usize = 4096;
    let parts: Vec<(f64, f64, f64)> = samples
        .par_chunks(CHUNK)
        .map(|c| {
            c.iter().fold((0.0f64, 0.0f64, 0.0f64), |(mx, s, s2), &p| {
                let d = target.nearest(p).map_or(f64::INFINITY, |n| (n.dist2 as f64).sqrt());
                (mx.max(d), s + d, s2 + d * d)
            })
        })
        .collect();
    let (mx, s, s2) = parts.iter().fold((0.0f64, 0.0, 0.0), |a, b| (a.0.max(b.0), a.1 + b.1, a.2 + b.2));
    let n = samples.len().max(1) as f64;
    OneSided { max: mx, mean: s / n, rms: (s2 / n).sqrt(), samples: samples.len() }
}

/// Measures how far `simplified` lies from `original` and back.
pub fn hausdorff(original: &IndexedMesh, simplified: &IndexedMesh, options: HausdorffOptions) -> Hausdorff {
    let (ta, tb) = (super::corners(original, original.origin), super::corners(simplified, original.origin));
    let (sa, sb) = (sample(&ta, options.density), sample(&tb, options.density));
    let (ba, bb) = rayon::join(|| Bvh::new(&ta), || Bvh::new(&tb));
    let (forward, backward) = rayon::join(|| one_sided(&sa, &bb), || one_sided(&sb, &ba));
    let (lo, hi) = bounds(original.triangles.iter().flatten().map(|&i| original.positions[i as usize]));
    let diagonal = (0..3).map(|k| ((hi[k] - lo[k]) as f64).powi(2)).sum::<f64>().sqrt();
    Hausdorff {
        forward,
        backward,
        max: forward.max.max(backward.max),
        mean: forward.mean.max(backward.mean),
        rms: forward.rms.max(backward.rms),
        diagonal,
    }
}
