//! Spatial order ([`crate::BuildOptions::spatial_order`]): renumbers a freshly built mesh's
//! vertices along a Morton (Z-order) curve through its bounding box, and its faces by their
//! lowest vertex in that order, so that vertices and faces near each other on the surface sit
//! near each other in memory.
//!
//! ```text
//!   code(v)   = bits of x, y, z (21 each, quantised in the bounding cube) interleaved
//!   vertices  by (code, old id)          faces by (lowest new vertex id, old id)
//!   half-edge 3f + k  ->  3 f' + k       (each face keeps its corner order and winding)
//! ```
//! Every pass walks fans: a vertex's outgoing half-edges, their twins, the neighbours'
//! positions and wedges. In file order those are scattered wherever the scanner or exporter
//! put them; along the curve a fan's faces and neighbours mostly share cache lines. On the
//! bunny this halves the papers/000 rounds' simulated L1 misses (docs/BENCHMARKS.md).
//!
//! Nothing but numbering changes: connectivity, winding, wedges, primitives and flags are
//! carried over element for element, and [`Mesh::vertex_source`] / [`Mesh::face_source`]
//! still name the input vertex and triangle behind each element (repairs name input ids, as
//! before). Both sorts have unique keys, so the order does not depend on the thread count.

use rayon::prelude::*;

use super::{IdMap, Mesh};
use crate::topology::INVALID;

/// Bits per axis of the Morton code (3 × 21 = 63 bits).
const BITS: u32 = 21;

/// Renumbers `mesh` in spatial order. Meant for a mesh straight from [`Mesh::build`]: every
/// face live, every vertex used.
pub(crate) fn apply(mesh: &mut Mesh) {
    // Keys computed once and sorted with their ids (unique, so one order).
    let mut by_code: Vec<(u64, u32)> = morton_codes(&mesh.positions).into_iter().zip(0..).collect();
    by_code.sort_unstable();
    let vertices: Vec<u32> = by_code.into_iter().map(|(_, v)| v).collect();
    let new_vertex = inverse(&vertices);

    // Faces by lowest new vertex id, ties in face order: a counting sort.
    let t = &mesh.topology;
    let lowest: Vec<u32> =
        t.faces.iter().map(|f| f.iter().map(|&v| new_vertex[v as usize]).min().unwrap_or(0)).collect();
    let mut start = vec![0u32; vertices.len() + 1];
    for &l in &lowest {
        start[l as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut faces = vec![0u32; lowest.len()];
    for (f, &l) in lowest.iter().enumerate() {
        faces[start[l as usize] as usize] = f as u32;
        start[l as usize] += 1;
    }
    let new_face = inverse(&faces);
    let half_edge = |h: u32| if h == INVALID { INVALID } else { 3 * new_face[(h / 3) as usize] + h % 3 };

    let t = &mut mesh.topology;
    t.faces = gather(&faces, &t.faces, |f| f.map(|v| new_vertex[v as usize]));
    t.twin = gather_half_edges(&faces, &t.twin, half_edge);
    t.vertex_he = gather(&vertices, &t.vertex_he, half_edge);
    t.vflags = gather(&vertices, &t.vflags, |x| x);
    mesh.positions = gather(&vertices, &mesh.positions, |x| x);
    mesh.vertex_source = IdMap::shifts(vertices.par_iter().map(|&i| mesh.vertex_source.get(i as usize)).collect());
    mesh.face_source = IdMap::shifts(faces.par_iter().map(|&i| mesh.face_source.get(i as usize)).collect());
    if !mesh.face_primitive.is_empty() {
        mesh.face_primitive = gather(&faces, &mesh.face_primitive, |x| x);
    }
    // Identity wedges follow their vertices (wedge v stays vertex v), attributes and all;
    // others keep their ids and learn their vertices' new ones.
    let w = &mut mesh.wedges;
    if !w.is_identity() {
        w.corner = gather_half_edges(&faces, &w.corner, |c| c);
        w.vertex = IdMap::new(w.vertex.iter().map(|v| new_vertex[v as usize]).collect());
    } else {
        if !w.normals.is_empty() {
            w.normals = gather(&vertices, &w.normals, |x| x);
        }
        if !w.uvs.is_empty() {
            w.uvs = gather(&vertices, &w.uvs, |x| x);
        }
        for a in &mut w.attributes {
            *a = a.gather(&vertices);
        }
    }
}

/// `old` in `order`, each entry passed through `value` (`out[i] = value(old[order[i]])`),
/// sized exactly: the runtime's memory report counts capacity.
fn gather<T: Copy + Sync, U: Send>(order: &[u32], old: &[T], value: impl Fn(T) -> U + Sync) -> Vec<U> {
    order.par_iter().map(|&i| value(old[i as usize])).collect()
}

/// [`gather`] for a per-half-edge array (three entries per face, faces in `faces` order).
fn gather_half_edges(faces: &[u32], old: &[u32], value: impl Fn(u32) -> u32 + Sync) -> Vec<u32> {
    let mut out = vec![0; old.len()];
    out.par_chunks_exact_mut(3).zip(faces).for_each(|(slot, &f)| {
        for (k, s) in slot.iter_mut().enumerate() {
            *s = value(old[3 * f as usize + k]);
        }
    });
    out
}

/// `order` read backwards: `inverse(order)[order[i]] == i`.
fn inverse(order: &[u32]) -> Vec<u32> {
    let mut inv = vec![0; order.len()];
    for (i, &x) in order.iter().enumerate() {
        inv[x as usize] = i as u32;
    }
    inv
}

/// Each position's Morton code in the bounding cube of all of them (the cube, not the box,
/// so the curve's cells are cubes whatever the mesh's proportions).
pub(crate) fn morton_codes(positions: &[[f32; 3]]) -> Vec<u64> {
    let (lo, hi) = super::bounds(positions.iter().copied());
    let extent = (0..3).map(|k| f64::from(hi[k]) - f64::from(lo[k])).fold(0.0, f64::max);
    let scale = if extent > 0.0 { f64::from((1u32 << BITS) - 1) / extent } else { 0.0 };
    let cell = |p: [f32; 3], k: usize| ((f64::from(p[k]) - f64::from(lo[k])) * scale) as u64;
    positions.par_iter().map(|&p| spread(cell(p, 0)) | spread(cell(p, 1)) << 1 | spread(cell(p, 2)) << 2).collect()
}

/// The low 21 bits of `x`, two zero bits after each.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    (x | x << 2) & 0x1249_2492_4924_9249
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_interleaves_every_bit() {
        for b in 0..BITS {
            assert_eq!(spread(1 << b), 1 << (3 * b), "bit {b}");
        }
        assert_eq!(spread(u64::MAX).count_ones(), BITS);
    }

    #[test]
    fn codes_follow_the_octants() {
        let c = morton_codes(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]]);
        assert_eq!(c[0], 0);
        assert!(c[0] < c[1] && c[1] < c[2] && c[2] < c[3] && c[3] < c[4], "{c:?}");
        assert_eq!(c[4], (1 << 63) - 1);
    }

    /// The runtime's memory report counts capacity: renumbering must not grow any array.
    #[test]
    fn arrays_keep_their_size() {
        let torus = crate::procedural::torus(40, 20);
        let mut m = Mesh::build(&torus, crate::BuildOptions::default()).unwrap();
        apply(&mut m);
        let t = &m.topology;
        let sizes = [
            (t.faces.len(), t.faces.capacity()),
            (t.twin.len(), t.twin.capacity()),
            (t.vertex_he.len(), t.vertex_he.capacity()),
            (t.vflags.len(), t.vflags.capacity()),
            (m.positions.len(), m.positions.capacity()),
            (m.wedges.corner.len(), m.wedges.corner.capacity()),
            (m.face_primitive.len(), m.face_primitive.capacity()),
        ];
        for (k, (len, cap)) in sizes.into_iter().enumerate() {
            assert_eq!(len, cap, "array {k}: {len} elements in {cap}");
        }
        // Renumbered, the source maps are no longer the identity and hold exactly their ids.
        for map in [&m.vertex_source, &m.face_source] {
            assert!(!map.is_identity());
            assert_eq!(map.bytes(), map.len() * 4);
        }
    }

    #[test]
    fn inverse_reads_back() {
        assert_eq!(inverse(&[2, 0, 3, 1]), vec![1, 3, 0, 2]);
    }
}
