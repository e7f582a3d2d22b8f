//! Shape of a connectivity: components, border edges and loops, Euler characteristic and
//! genus per component (g = (2 − χ − b) / 2 for an orientable surface with b border loops).

use super::{HalfEdges, Topology, UnionFind, INVALID};

/// Counts for one connected component (faces connected through shared edges).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ComponentStats {
    /// Live vertices.
    pub vertices: u32,
    /// Undirected edges.
    pub edges: u32,
    /// Live faces.
    pub faces: u32,
    /// Edges with one face.
    pub boundary_edges: u32,
    /// Closed loops of border edges.
    pub boundary_loops: u32,
    /// χ = V − E + F.
    pub euler: i64,
    /// Genus, when (2 − χ − b) is even and ≥ 0 (always, for a valid topology).
    pub genus: Option<u32>,
}

/// Counts for the whole mesh.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TopologyStats {
    /// Live vertices.
    pub vertices: u32,
    /// Undirected edges.
    pub edges: u32,
    /// Live faces.
    pub faces: u32,
    /// Edges with one face.
    pub boundary_edges: u32,
    /// Closed loops of border edges.
    pub boundary_loops: u32,
    /// χ = V − E + F over all components.
    pub euler: i64,
    /// Sum of component genera, when every component has one.
    pub genus: Option<u32>,
    /// Per component, ordered by smallest face id.
    pub components: Vec<ComponentStats>,
}

/// The connected component (faces joined through shared edges) of every face slot, numbered
/// in order of each component's smallest face id (`INVALID` for a dead slot), and how many
/// there are. A vertex belongs to the component of any face of its fan (`vertex_he`'s).
pub fn face_components(t: &Topology) -> (Vec<u32>, usize) {
    let nf = t.faces.len();
    // Union-find over faces through twins.
    let mut sets = UnionFind::new(nf);
    for h in 0..t.twin.len() as u32 {
        let g = t.twin[h as usize];
        if g != INVALID && t.is_face_live(h / 3) && (g as usize) < t.twin.len() {
            sets.union(h / 3, g / 3);
        }
    }
    let mut comp_of_root = vec![INVALID; nf];
    let mut count = 0;
    let mut face_comp = vec![INVALID; nf];
    for f in 0..nf as u32 {
        if !t.is_face_live(f) {
            continue;
        }
        let r = sets.find(f) as usize;
        if comp_of_root[r] == INVALID {
            comp_of_root[r] = count as u32;
            count += 1;
        }
        face_comp[f as usize] = comp_of_root[r];
    }
    (face_comp, count)
}

pub(super) fn compute(t: &Topology) -> TopologyStats {
    let (face_comp, count) = face_components(t);
    let mut comps = vec![ComponentStats::default(); count];
    for &c in &face_comp {
        if c != INVALID {
            comps[c as usize].faces += 1;
        }
    }
    for &h in &t.vertex_he {
        if h != INVALID && (h as usize) < t.twin.len() && face_comp[(h / 3) as usize] != INVALID {
            comps[face_comp[(h / 3) as usize] as usize].vertices += 1;
        }
    }
    // Each undirected edge once: from its smaller half-edge, or its only one on a border.
    for h in 0..t.twin.len() as u32 {
        let c = face_comp[(h / 3) as usize];
        let twin = t.twin[h as usize];
        if c == INVALID || (twin != INVALID && twin < h) {
            continue;
        }
        comps[c as usize].edges += 1;
        if twin == INVALID {
            comps[c as usize].boundary_edges += 1;
        }
    }
    // Border loops: follow border half-edges a -> b, then b's outgoing border half-edge.
    let mut seen = vec![false; t.twin.len()];
    for h in 0..t.twin.len() as u32 {
        if seen[h as usize] || !t.is_face_live(h / 3) || t.twin[h as usize] != INVALID {
            continue;
        }
        comps[face_comp[(h / 3) as usize] as usize].boundary_loops += 1;
        let mut cur = h;
        while !seen[cur as usize] {
            seen[cur as usize] = true;
            let next = t.vertex_he.get(t.dest(cur) as usize).copied().unwrap_or(INVALID);
            if next == INVALID || next as usize >= t.twin.len() || t.twin[next as usize] != INVALID {
                break;
            }
            cur = next;
        }
    }
    let mut s = TopologyStats { genus: Some(0), ..Default::default() };
    for c in &mut comps {
        c.euler = c.vertices as i64 - c.edges as i64 + c.faces as i64;
        let g2 = 2 - c.euler - c.boundary_loops as i64;
        c.genus = (g2 >= 0 && g2 % 2 == 0).then_some((g2 / 2) as u32);
        s.vertices += c.vertices;
        s.edges += c.edges;
        s.faces += c.faces;
        s.boundary_edges += c.boundary_edges;
        s.boundary_loops += c.boundary_loops;
        s.euler += c.euler;
        s.genus = s.genus.zip(c.genus).map(|(a, b)| a + b);
    }
    s.components = comps;
    s
}
