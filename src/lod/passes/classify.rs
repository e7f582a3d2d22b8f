//! Vertex analysis and classification, papers/000 §3.
//!
//! ```text
//!        N_2   N_3              e(V) = (1/m) Σ_i (t · n_i)²            (equation 1)
//!          \   /                t = tangent plane of V (unit vertex normal through V)
//!   N_1 ---- V ---- N_4         n_i = neighbour N_i as (x, y, z, 1)
//!          /   \
//!        N_6   N_5
//! ```
//!
//! The static error e(V) is a mean squared distance (model units²). For a view it becomes an
//! error in screen pixels ([`screen_error`]): √e(V) × pixels per unit at V's distance × an
//! angle factor (1 + sin θ) / 2, θ between the vertex normal and the direction to the eye (a
//! displacement along the normal shows fully on the silhouette and half-strength face-on),
//! × `back_facing_scale` when V faces away, × `outside_frustum_scale` outside the frustum.
//! Decision (the paper names the inputs, not the formula): see docs/ALGORITHM.md.
//!
//! Classification: V goes to R (remove) when its error is ≤ the threshold u, else to S.
//! Without a view, the error is √e(V) in model units and u is in model units too.

use rayon::prelude::*;

use crate::topology::{vflag, HalfEdges, Topology, INVALID};
use crate::view::{Frustum, View};

/// Thresholds and scales of the classification.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct ClassifyOptions {
    /// The threshold u: pixels with a view, model units without. Default: 1.0.
    pub threshold: f32,
    /// Error multiplier for vertices facing away from the eye. Default: 0.25.
    pub back_facing_scale: f32,
    /// Error multiplier for vertices outside the view frustum. Default: 0.1.
    pub outside_frustum_scale: f32,
}

impl Default for ClassifyOptions {
    fn default() -> Self {
        Self { threshold: 1.0, back_facing_scale: 0.25, outside_frustum_scale: 0.1 }
    }
}

impl ClassifyOptions {
    /// Sets [`ClassifyOptions::threshold`].
    pub fn threshold(mut self, u: f32) -> Self {
        self.threshold = u;
        self
    }
}

/// Area-weighted unit vertex normals over the live faces (zero for isolated vertices). Each
/// vertex sums its own fan, so the vertices run in parallel and the result does not depend on
/// the thread count.
pub fn vertex_normals(t: &Topology, positions: &[[f32; 3]]) -> Vec<[f32; 3]> {
    (0..t.vertex_count() as u32).into_par_iter().map(|v| vertex_normal(t, positions, v)).collect()
}

/// [`vertex_normals`] and [`vertex_errors`] in one pass over the fans (each vertex's error
/// needs only its own normal, worked out just before from the same fan).
pub fn vertex_normals_and_errors(t: &Topology, positions: &[[f32; 3]]) -> (Vec<[f32; 3]>, Vec<f32>) {
    (0..t.vertex_count() as u32).into_par_iter().map(|v| normal_and_error(t, positions, v)).unzip()
}

/// Most fan faces [`normal_and_error`] takes in its one walk (their neighbours, and a border
/// vertex's last one, fit its list); a vertex with more is walked twice ([`vertex_normal`],
/// then [`vertex_error`]).
const RING: usize = 32;

/// [`vertex_normal`] and [`vertex_error`] of `v` from one walk of its fan: the neighbours are
/// noted on the way round, in [`HalfEdges::neighbors`] order, so both come out bit for bit
/// as the two functions give them.
fn normal_and_error(t: &Topology, positions: &[[f32; 3]], v: u32) -> ([f32; 3], f32) {
    if t.vertex_he[v as usize] == INVALID {
        return ([0.0; 3], 0.0);
    }
    let mut ring = [0u32; RING + 1];
    let mut len = 0;
    let mut sum = [0.0f64; 3];
    let mut last = INVALID;
    for g in t.outgoing(v) {
        if len == RING {
            let n = vertex_normal(t, positions, v);
            return (n, vertex_error(t, positions, n, v));
        }
        ring[len] = t.dest(g);
        len += 1;
        last = g;
        let cr = face_cross(t.faces[(g / 3) as usize].map(|v| positions[v as usize].map(f64::from)));
        for k in 0..3 {
            sum[k] += cr[k];
        }
    }
    if t.vflags[v as usize] & vflag::BOUNDARY != 0 {
        // `neighbors`' last: the far end of the incoming border half-edge.
        ring[len] = t.origin(Topology::prev(last));
        len += 1;
    }
    let n = unit(sum);
    (n, error_from(positions, n, v, ring[..len].iter().copied()))
}

/// (b − a) × (c − a) of a face's corners.
fn face_cross([a, b, c]: [[f64; 3]; 3]) -> [f64; 3] {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
}

/// `n` scaled to unit length in f32 (zero when `n` is).
fn unit(n: [f64; 3]) -> [f32; 3] {
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if l > 0.0 {
        n.map(|c| (c / l) as f32)
    } else {
        [0.0; 3]
    }
}

/// V's tangent plane: its (stored) normal through V, in f64. e(V) and §6's metric measure
/// distances from it.
pub(crate) struct TangentPlane {
    n: [f64; 3],
    d: f64,
}

impl TangentPlane {
    #[inline]
    pub(crate) fn new(positions: &[[f32; 3]], normal: [f32; 3], v: u32) -> Self {
        let p = positions[v as usize].map(f64::from);
        let n = normal.map(f64::from);
        Self { n, d: -(n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) }
    }

    /// Signed distance of `q` (along the normal's length).
    #[inline]
    pub(crate) fn distance(&self, q: [f32; 3]) -> f64 {
        let (n, q) = (self.n, q.map(f64::from));
        n[0] * q[0] + n[1] * q[1] + n[2] * q[2] + self.d
    }
}

/// e(V) over the given neighbours of `v`, summed in the order given.
fn error_from(positions: &[[f32; 3]], normal: [f32; 3], v: u32, ring: impl Iterator<Item = u32>) -> f32 {
    let plane = TangentPlane::new(positions, normal, v);
    let (mut sum, mut m) = (0.0f64, 0u32);
    for w in ring {
        let dist = plane.distance(positions[w as usize]);
        sum += dist * dist;
        m += 1;
    }
    if m == 0 {
        0.0
    } else {
        (sum / m as f64) as f32
    }
}

/// The unit area-weighted normal of `v`'s faces (zero for a removed vertex or a degenerate fan).
pub fn vertex_normal(t: &Topology, positions: &[[f32; 3]], v: u32) -> [f32; 3] {
    let mut n = [0.0f64; 3];
    if t.vertex_he[v as usize] != INVALID {
        for g in t.outgoing(v) {
            let cr = face_cross(t.faces[(g / 3) as usize].map(|v| positions[v as usize].map(f64::from)));
            for k in 0..3 {
                n[k] += cr[k];
            }
        }
    }
    unit(n)
}

/// e(V) of equation 1: the mean squared distance of V's neighbours from V's tangent plane.
pub fn vertex_error(t: &Topology, positions: &[[f32; 3]], normal: [f32; 3], v: u32) -> f32 {
    if t.vertex_he[v as usize] == INVALID {
        return 0.0;
    }
    error_from(positions, normal, v, t.neighbors(v))
}

/// e(V) for every vertex, in parallel.
pub fn vertex_errors(t: &Topology, positions: &[[f32; 3]], normals: &[[f32; 3]]) -> Vec<f32> {
    (0..t.vertex_count() as u32).into_par_iter().map(|v| vertex_error(t, positions, normals[v as usize], v)).collect()
}

/// The error of a vertex with static error `e` at `p` with normal `n`, in pixels for `view`
/// (see the module docs), or √e in model units without a view.
pub fn screen_error(view: Option<&View>, p: [f32; 3], n: [f32; 3], e: f32, o: &ClassifyOptions) -> f32 {
    screen_error_in(view.map(Frustum::new).as_ref(), p, n, e, o)
}

/// [`screen_error`] with the view's constants worked out once ([`Frustum::new`]), for passes
/// over many vertices. Same result.
pub fn screen_error_in(view: Option<&Frustum>, p: [f32; 3], n: [f32; 3], e: f32, o: &ClassifyOptions) -> f32 {
    let g = e.max(0.0).sqrt();
    let Some(view) = view else { return g };
    if !g.is_finite() {
        return g;
    }
    let cos = view.facing(p, n);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let mut px = g * view.pixels_per_unit(p) * 0.5 * (1.0 + sin);
    if cos < 0.0 {
        px *= o.back_facing_scale;
    }
    if !view.touches_sphere(p, g) {
        px *= o.outside_frustum_scale;
    }
    px
}

/// [`screen_error_in`] under several views at once: the largest of the views' errors, so
/// that a vertex counts as fine only where every view finds it so (one mesh drawn by several
/// cameras, or by several instances under one camera, each instance's view carried into the
/// mesh's space by [`View::in_model_space`]). No views: model units, as without a view. One
/// view: [`screen_error_in`]'s value, bit for bit.
pub fn screen_error_views(views: &[Frustum], p: [f32; 3], n: [f32; 3], e: f32, o: &ClassifyOptions) -> f32 {
    let each = views.iter().map(|f| screen_error_in(Some(f), p, n, e, o));
    each.reduce(f32::max).unwrap_or_else(|| screen_error_in(None, p, n, e, o))
}

/// R/S classification under every view of `views` at once (none: view-independent; one view
/// from [`Frustum::new`]): `true` = in R (to be removed), only if every view lets the vertex
/// go ([`screen_error_views`]). Removed and locked vertices are never in R. Pure per vertex,
/// so the result is the same for any thread count.
pub fn classify(
    views: &[Frustum],
    t: &Topology,
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    errors: &[f32],
    o: &ClassifyOptions,
) -> Vec<bool> {
    (0..t.vertex_count())
        .into_par_iter()
        .map(|v| {
            if t.vflags[v] & (vflag::REMOVED | vflag::LOCKED) != 0 || t.vertex_he[v] == INVALID {
                return false;
            }
            screen_error_views(views, positions[v], normals[v], errors[v], o) <= o.threshold
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{procedural, BuildOptions, Mesh};

    /// The one-walk set-up gives exactly what the two walks give, on borders (a bumpy grid),
    /// a closed surface, and welded UV-sphere poles of 40 neighbours (past `RING`).
    #[test]
    fn one_walk_matches_the_two_walks() {
        let mut grid = procedural::grid(9, 7, |i, j| (i + j) % 3 == 0);
        for (k, p) in grid.positions.iter_mut().enumerate() {
            p[2] = ((k * 7919) % 13) as f32 * 0.05;
        }
        let meshes = [grid, procedural::torus(12, 9), procedural::uv_sphere(6, 40)];
        let mut seen = (false, false);
        for input in &meshes {
            let m = Mesh::build(input, BuildOptions::default()).unwrap();
            let (t, p) = (&m.topology, &m.positions);
            let (normals, errors) = vertex_normals_and_errors(t, p);
            for v in 0..t.vertex_count() as u32 {
                let n = vertex_normal(t, p, v);
                let e = vertex_error(t, p, n, v);
                assert_eq!(normals[v as usize].map(f32::to_bits), n.map(f32::to_bits), "normal of {v}");
                assert_eq!(errors[v as usize].to_bits(), e.to_bits(), "e(V) of {v}");
                seen.0 |= t.is_boundary_vertex(v) && e > 0.0;
                seen.1 |= t.neighbors(v).count() > RING;
            }
        }
        assert_eq!(seen, (true, true), "a bumpy border vertex and a fan past RING were both checked");
    }
}
