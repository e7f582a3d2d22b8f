//! What may move where, shared by every engine that collapses edges: borders stay borders,
//! UV/normal seams stay seams, primitives stay apart, corners and seam ends stay put, and each
//! attribute wedge of the removed vertex maps onto one wedge of the kept vertex.
//!
//! ```text
//!   constrained edge = border | seam (wedges differ across it) | between two primitives
//!   u with 0 constrained edges: free       u with 2: slides along them only
//!   u with 1 (a seam's end, inside a chart): moves along its other edges
//!   u with ≥ 3: fixed (junction)           border turning > 30° (85° under QEM): fixed
//! ```
//! A seam's end moved along an unconstrained edge is as clean as any collapse: u has one wedge
//! (its fan is cut only once), the faces on the edge give it one wedge of v, and the seam edge
//! (u, x) becomes (v, x) with the same two wedges at x: the seam keeps an end, one edge over
//! (or closes, once the end reaches a border and the faces between go). meshoptimizer goes
//! further: its complex vertices (junctions) move too, mapping wedges across charts. They stay
//! here, so no face ever reads two charts.

use std::borrow::Borrow;

use glam::DVec3;

use super::Mesh;
use crate::topology::{
    on_removed_face, CollapseWrites, HalfEdgeCollapse, HalfEdges, HalfEdgesMut, Topology, INVALID, LISTED_CORNERS,
};

/// A border vertex whose border turns by more than this many degrees is a corner and stays,
/// for engines whose cost does not see borders (the dihedral cost of papers/002, and the
/// view-dependent rounds of papers/000 and the runtime, whose targets are chosen among
/// plane-safe edges).
pub const BORDER_CORNER_DEGREES: f64 = 30.0;

/// The corner angle under a quadric cost. Its border planes already charge a border vertex
/// for leaving the line of its border edges, so only real corners are fixed (a square's
/// corner, 90°, stays). 30° here fixed most vertices of the bunny's jagged holes, and the
/// budget they held cost 16 % RMS against meshoptimizer at 1 % (1.16× → 1.04×).
pub const QUADRIC_BORDER_CORNER_DEGREES: f64 = 85.0;

/// A vertex with more neighbours than this stays (its fan is not worth walking per candidate).
pub const MAX_MOVABLE_VALENCE: usize = 128;

/// Whether the mesh has one attribute wedge per vertex and a single primitive (scans without
/// normals or UVs): then no edge is a seam or between primitives and every wedge carries over,
/// so the corner reads below can be skipped. O(1); collapses keep it (they add no wedge).
pub fn plain_attributes(m: &Mesh) -> bool {
    // Every vertex has at least one wedge, and `IndexedMesh::check` keeps face primitives
    // below the primitive count.
    m.wedges.len() == m.positions.len() && m.primitives.len() == 1
}

/// Whether the edge of half-edge `g` is a border, a seam, or between two primitives.
pub fn edge_constrained(m: &Mesh, g: u32) -> bool {
    let t = &m.topology;
    let o = t.twin[g as usize];
    if o == INVALID {
        return true;
    }
    let differ = || {
        let c = |h: u32| m.corner_wedge(h);
        c(g) != c(Topology::next(o))
            || c(Topology::next(g)) != c(o)
            || m.primitive_of((g / 3) as usize) != m.primitive_of((o / 3) as usize)
    };
    if plain_attributes(m) {
        // Unit-test builds check the shortcut against the reads it skips.
        #[cfg(test)]
        assert!(!differ(), "half-edge {g}: a plain mesh with a seam");
        return false;
    }
    differ()
}

/// Fills `out` with the (half-edge, target) pairs along which `u` may move, given its
/// outgoing half-edges `fan` (counter-clockwise from `vertex_he`). Leaves `out` empty when u
/// must stay (corner, junction, or a border that turns by more than `corner_degrees`).
pub fn movable_targets(m: &Mesh, u: u32, fan: &[u32], corner_degrees: f64, out: &mut Vec<(u32, u32)>) {
    out.clear();
    let t = &m.topology;
    let Some(&last) = fan.last() else { return };
    out.extend(fan.iter().map(|&g| (g, t.dest(g))));
    let border = t.is_boundary_vertex(u);
    if border {
        let inc = Topology::prev(last);
        out.push((inc, t.origin(inc)));
    }
    if out.len() > MAX_MOVABLE_VALENCE {
        out.clear(); // a valence over this is not worth moving
        return;
    }
    if !border && plain_attributes(m) {
        // No seams or primitive edges, and every edge of an interior vertex has a twin: no
        // edge of the fan is constrained, every neighbour is a target.
        #[cfg(test)]
        assert!(fan.iter().all(|&g| !edge_constrained(m, g)), "vertex {u}: an interior fan with a border edge");
        return;
    }
    // Constrained-edge flags as bits (no allocation): the border incoming edge is always one.
    let mut flags: u128 = 0;
    for (k, &(g, _)) in out.iter().enumerate() {
        let constrained = (border && k == out.len() - 1) || edge_constrained(m, g);
        flags |= u128::from(constrained) << k;
    }
    let n_constrained = flags.count_ones();
    // A border vertex has two border edges, so one constrained edge is a seam's end.
    let end_moves = n_constrained == 1;
    if n_constrained > 2 || (border && is_border_corner(m, u, out[0].1, out[out.len() - 1].1, corner_degrees)) {
        out.clear();
        return;
    }
    if n_constrained != 0 {
        // Along the two constrained edges, or a seam end along every other edge.
        let mut k = 0;
        out.retain(|_| {
            let keep = (flags >> k & 1 == 1) != end_moves;
            k += 1;
            keep
        });
    }
}

/// Live vertices of `m`, and how many of them may not move at all: locked, or with no
/// target [`movable_targets`] allows (corners, where primitives meet or seams cross). For explaining why a coarsening stopped where it did.
pub fn count_fixed(m: &Mesh, corner_degrees: f64) -> (usize, usize) {
    use crate::topology::vflag;
    let t = &m.topology;
    let (mut fan, mut out) = (Vec::new(), Vec::new());
    let (mut live, mut fixed) = (0, 0);
    for v in 0..t.vertex_count() as u32 {
        let flags = t.vflags[v as usize];
        if flags & vflag::REMOVED != 0 || t.vertex_he[v as usize] == INVALID {
            continue;
        }
        live += 1;
        fan.clear();
        fan.extend(t.outgoing(v));
        movable_targets(m, v, &fan, corner_degrees, &mut out);
        fixed += usize::from(flags & vflag::LOCKED != 0 || out.is_empty());
    }
    (live, fixed)
}

/// Whether border vertex `u`, between border neighbours `next` and `prev`, is a corner.
pub(crate) fn is_border_corner(m: &Mesh, u: u32, next: u32, prev: u32, degrees: f64) -> bool {
    let p = |v: u32| m.positions[v as usize].map(f64::from);
    let (pu, pn, pp) = (p(u), p(next), p(prev));
    let a = [pu[0] - pp[0], pu[1] - pp[1], pu[2] - pp[2]];
    let b = [pn[0] - pu[0], pn[1] - pu[1], pn[2] - pu[2]];
    let (la, lb) = ((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt(), (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt());
    if la == 0.0 || lb == 0.0 {
        return true;
    }
    (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb) < degrees.to_radians().cos()
}

/// (u→v, v→u) half-edges of a collapse, `INVALID` for a missing side.
pub fn halves(t: &Topology, c: HalfEdgeCollapse) -> (u32, u32) {
    let o = t.twin[c.he as usize];
    if t.origin(c.he) == c.remove {
        (c.he, o)
    } else {
        (o, c.he)
    }
}

/// The wedge map u → v through the faces on the edge: (u's wedge, v's wedge) per side.
pub fn wedge_map(m: &Mesh, hu: u32, hv: u32) -> [(u32, u32); 2] {
    let c = |g: u32| m.corner_wedge(g);
    let side1 = if hu != INVALID { (c(hu), c(Topology::next(hu))) } else { (INVALID, INVALID) };
    let side2 = if hv != INVALID { (c(Topology::next(hv)), c(hv)) } else { (INVALID, INVALID) };
    [side1, side2]
}

/// Whether every wedge of u around its fan (u's outgoing half-edges) maps to exactly one
/// wedge of v.
pub fn wedges_carry_over(m: &Mesh, fan: impl IntoIterator<Item = impl Borrow<u32>>, hu: u32, hv: u32) -> bool {
    if plain_attributes(m) {
        return true;
    }
    let map = wedge_map(m, hu, hv);
    if map[0].0 == map[1].0 && map[0].1 != map[1].1 && map[0].0 != INVALID {
        return false; // one wedge of u would need two wedges of v
    }
    fan.into_iter().all(|g| map.iter().any(|&(from, _)| from == m.corner_wedge(*g.borrow())))
}

/// Collapses `c` on the mesh: remaps u's surviving corners to v's wedges, then edits the
/// connectivity. Returns the removed faces. The caller has checked legality and wedges.
pub fn collapse_with_wedges(m: &mut Mesh, c: HalfEdgeCollapse) -> [u32; 2] {
    if m.wedges.corner.is_empty() {
        // Identity wedges: only the connectivity's stores.
        return m.topology.collapse(c);
    }
    let w = collapse_writes(m, c);
    write_collapse(m, &w)
}

/// Every store [`collapse_with_wedges`] makes: the connectivity's
/// ([`HalfEdges::collapse_writes`]) and u's surviving corners' new wedges. Reads only what
/// the connectivity's part reads, plus those corners' wedges and the removed faces'.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshCollapseWrites {
    /// The connectivity's stores.
    pub topology: CollapseWrites,
    /// The wedge map u → v ([`wedge_map`]), for corners not listed.
    map: [(u32, u32); 2],
    /// The new wedge of each listed corner ([`CollapseWrites::corners`]).
    wedges: [u32; LISTED_CORNERS],
}

/// Works out [`collapse_with_wedges`]'s stores without making them (see
/// [`HalfEdges::collapse_writes`] for when they may be made later).
pub fn collapse_writes(m: &Mesh, c: HalfEdgeCollapse) -> MeshCollapseWrites {
    let topology = m.topology.collapse_writes(c);
    if m.wedges.corner.is_empty() {
        // Identity wedges: `write_collapse` has no corner list to write.
        return MeshCollapseWrites { topology, map: [(INVALID, INVALID); 2], wedges: [INVALID; LISTED_CORNERS] };
    }
    let (hu, hv) = halves(&m.topology, c);
    let map = wedge_map(m, hu, hv);
    let mut wedges = [INVALID; LISTED_CORNERS];
    for (w, &g) in wedges.iter_mut().zip(topology.corners().unwrap_or_default()) {
        *w = remap(map, m.corner_wedge(g));
    }
    MeshCollapseWrites { topology, map, wedges }
}

/// Makes the stores of [`collapse_writes`]. Returns the removed faces.
pub fn write_collapse(m: &mut Mesh, w: &MeshCollapseWrites) -> [u32; 2] {
    let corner = &mut m.wedges.corner;
    // The removed faces' corners are left as they were: the runtime's split reads u's wedges
    // back from them (lod/hierarchy.rs). Identity wedges have no list: u's corners take v,
    // which is what the connectivity writes into them.
    if corner.is_empty() {
        return m.topology.write_collapse(&w.topology);
    }
    match w.topology.corners() {
        Some(corners) => {
            for (&g, &wedge) in corners.iter().zip(&w.wedges) {
                corner[g as usize] = wedge;
            }
        }
        None => {
            let removed = w.topology.removed;
            for g in m.topology.outgoing(w.topology.remove).filter(|&g| !removed.contains(&(g / 3))) {
                corner[g as usize] = remap(w.map, corner[g as usize]);
            }
        }
    }
    m.topology.write_collapse(&w.topology)
}

/// Wedge `w` of u through the wedge map: v's wedge, or `w` itself if the map does not name it.
fn remap(map: [(u32, u32); 2], w: u32) -> u32 {
    map.iter().find(|&&(from, _)| from == w).map_or(w, |&(_, to)| to)
}

/// A face of u's fan that survives the collapse of u onto a target, before and after the
/// move: normals unnormalised, each with the face's first corner (a point on its plane).
#[derive(Debug, Clone, Copy)]
pub struct MovedFace {
    /// The face.
    pub face: u32,
    /// First corner before the move.
    pub corner_before: DVec3,
    /// Normal before the move.
    pub before: DVec3,
    /// First corner after the move.
    pub corner_after: DVec3,
    /// Normal after the move.
    pub after: DVec3,
}

/// The faces of `fan` (u's outgoing half-edges) that survive collapsing u onto `to`, every
/// face but those of `hu` and `hv` ([`halves`]), with their normals before and after. The
/// fold tests of every engine read these; each decides what counts as a fold.
pub fn moved_faces<'a>(
    m: &'a Mesh,
    fan: &'a [u32],
    u: u32,
    to: u32,
    (hu, hv): (u32, u32),
) -> impl Iterator<Item = MovedFace> + 'a {
    let p = move |v: u32| DVec3::from(m.positions[v as usize].map(f64::from));
    let pt = p(to);
    fan.iter().filter(move |&&g| !on_removed_face(g, (hu, hv))).map(|&g| g / 3).map(move |f| {
        let face = m.topology.faces[f as usize];
        let [a, b, c] = face.map(p);
        let [a2, b2, c2] = face.map(|x| if x == u { pt } else { p(x) });
        MovedFace {
            face: f,
            corner_before: a,
            before: (b - a).cross(c - a),
            corner_after: a2,
            after: (b2 - a2).cross(c2 - a2),
        }
    })
}
