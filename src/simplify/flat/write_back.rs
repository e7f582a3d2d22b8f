//! The flat passes' result written back into the mesh they started from: each face slot's
//! corners and wedges, the twins of the live faces (found through the rows), the removed
//! vertices' flags, and every vertex's outgoing half-edge. The mesh then reads as if the
//! half-edge collapses had been made on it ([`crate::topology::Topology::validate`] holds).

use rayon::prelude::*;

use super::faces::FlatFaces;
use crate::mesh::Mesh;
use crate::topology::{vflag, INVALID};

/// Fewest faces a parallel task takes.
const TASK: usize = 1024;

pub(super) fn write_back(mesh: &mut Mesh, flat: &FlatFaces) {
    let live = flat.live_faces();
    let twins: Vec<[u32; 3]> = live.par_iter().with_min_len(TASK).map(|&f| twins_of(flat, f)).collect();
    let t = &mut mesh.topology;
    for (f, face) in t.faces.iter_mut().enumerate() {
        *face = if flat.is_dead(f as u32) { [INVALID; 3] } else { flat.tri(f as u32) };
    }
    for (&f, tw) in live.iter().zip(&twins) {
        t.twin[3 * f as usize..3 * f as usize + 3].copy_from_slice(tw);
    }
    if !flat.identity_wedges() {
        for &f in &live {
            mesh.wedges.corner[3 * f as usize..3 * f as usize + 3].copy_from_slice(&flat.wedges_of(f));
        }
    }
    for v in 0..flat.vertex_count() {
        if flat.count(v as u32) == 0 && t.vertex_he[v] != INVALID {
            t.vflags[v] |= vflag::REMOVED;
        }
    }
    t.rebuild_vertex_links();
}

/// The twin of each half-edge of live face `f`: the half-edge b → a of the live face on the
/// other side of its edge a → b, or `INVALID` on a border.
fn twins_of(flat: &FlatFaces, f: u32) -> [u32; 3] {
    let tri = flat.tri(f);
    [0, 1, 2].map(|k| {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        flat.row(b)
            .filter(|&g| g != f)
            .find_map(|g| {
                let o = flat.tri(g);
                (0..3).find(|&j| o[j] == b && o[(j + 1) % 3] == a).map(|j| 3 * g + j as u32)
            })
            .unwrap_or(INVALID)
    })
}
