//! The collapse cost of papers/002 §3.2 (Jia, Tang, Pan), equations 1–3:
//!
//! ```text
//!   Cost(u, v) = ‖u − v‖ · Σ_j Σ_i (1 − e_j · f_i) · W(s_i, b_j)
//!   W(s_i, b_j) = n / (n + D(s_i, b_j))
//! ```
//! S = the n faces around u (unit normals f_i), B = the m ≤ 2 faces on edge (u, v) (unit
//! normals e_j). D(s_i, b_j) counts the faces passed going from b_j to s_i: counter-clockwise
//! from b_1 (the face holding u → v) and clockwise from b_2 (the face holding v → u), so the
//! faces next to each b_j weigh most.
//!
//! ```text
//!        s_2   s_1=b_1          fan of u in counter-clockwise order, starting at b_1:
//!     s_3    u ----> v           D(s_i, b_1) = i − 1, D(s_i, b_2) = position of b_2 − position of s_i
//!        s_4   s_5=b_2
//! ```
//! Decision (the paper is silent): for a border vertex the fan is a path, not a cycle, and
//! D is the number of steps along that path from b_1, whichever way it runs.

use crate::topology::{HalfEdges, Topology, INVALID};

/// Unit normal of face `f` (zero for a degenerate face).
pub fn unit_normal(p: &[[f32; 3]], f: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = f.map(|v| p[v as usize].map(f64::from));
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if l > 0.0 {
        n.map(|c| c / l)
    } else {
        [0.0; 3]
    }
}

/// Equation 2 for collapsing u into v. `fan` lists u's outgoing half-edges counter-clockwise
/// (as [`HalfEdges::outgoing`] gives them); `hu` is u → v (or `INVALID` on a border where only
/// v → u exists) and `hv` is v → u (or `INVALID`).
pub fn dihedral_cost(t: &Topology, p: &[[f32; 3]], fan: &[u32], u: u32, v: u32, hu: u32, hv: u32) -> f64 {
    let normals: Vec<[f64; 3]> = fan.iter().map(|&g| unit_normal(p, t.faces[(g / 3) as usize])).collect();
    dihedral_cost_with(t, p, fan, &normals, u, v, hu, hv)
}

/// [`dihedral_cost`] with the fan's unit normals already computed (one per entry of `fan`).
#[allow(clippy::too_many_arguments)]
pub fn dihedral_cost_with(
    t: &Topology,
    p: &[[f32; 3]],
    fan: &[u32],
    normals: &[[f64; 3]],
    u: u32,
    v: u32,
    hu: u32,
    hv: u32,
) -> f64 {
    let n = fan.len();
    if n == 0 {
        return f64::INFINITY;
    }
    // Positions of b_1 and b_2 in the fan: u's corner in f1 is hu itself; in f2 = (v, u, b)
    // it is next(hv) = u → b.
    let i1 = (hu != INVALID).then(|| fan.iter().position(|&g| g == hu)).flatten();
    let i2 = (hv != INVALID).then(|| fan.iter().position(|&g| g == Topology::next(hv))).flatten();
    let border = t.is_boundary_vertex(u);
    let nf = n as f64;
    let mut sum = 0.0;
    for (j, ib) in [i1, i2].into_iter().enumerate() {
        let Some(ib) = ib else { continue };
        let e = normals[ib];
        for (i, f) in normals.iter().enumerate() {
            let d = if border {
                i.abs_diff(ib)
            } else if j == 0 {
                (i + n - ib) % n // counter-clockwise from b_1
            } else {
                (ib + n - i) % n // clockwise from b_2
            };
            let cos = e[0] * f[0] + e[1] * f[1] + e[2] * f[2];
            sum += (1.0 - cos) * nf / (nf + d as f64);
        }
    }
    let (a, b) = (p[u as usize], p[v as usize]);
    let d = [(a[0] - b[0]) as f64, (a[1] - b[1]) as f64, (a[2] - b[2]) as f64];
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    len * sum
}
