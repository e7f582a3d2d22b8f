//! Anchors the grid of papers/000 §3 cannot place: the ones the mesh's structure needs so
//! that every vertex has somewhere to go. R vertices collapse only into S (§2), and on a
//! model with parts, hard edges and holes the grid leaves whole regions without a target
//! whatever the threshold. Three kinds, all added to layer L0 (they always stay):
//!
//! ```text
//!   fixed:      a vertex no collapse may move (a corner, a seam junction, where primitives
//!               meet, locked) stays anyway; in S it is also a target for its neighbours
//!   chains:     vertices that may only slide along their two constrained edges (a border,
//!               a seam) go only to S vertices on that line; a line with none (a round hole,
//!               a cylinder's rim) gets one, the best of its vertices
//!   components: a part the grid gave no anchor (a bolt beside an engine block) gets one
//! ```
//! The best vertex of a group is chosen as in a grid cell (anchors.rs): the largest
//! m(V, P) = (l − d)² · e(V), P and l the centre and longest side of the group's bounding
//! box, then the nearest to P, then the smallest id. On the glTF models the grid alone left
//! most of the mesh in such regions: the 2CylinderEngine stopped at 72,873 of 110,336
//! triangles under any threshold (docs/BENCHMARKS.md, "How far the runtime can coarsen").

use rayon::prelude::*;

use super::anchors::{best_per_cell, nested_floors, select_anchors, AnchorOptions, Scored};
use crate::mesh::{constraints, Mesh};
use crate::topology::{face_components, vflag, HalfEdges, Topology, UnionFind, INVALID};

/// How a vertex may move under the constraints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Motion {
    /// Never (see [`constraints::movable_targets`]).
    Fixed,
    /// Only along its two constrained edges, to these neighbours.
    Slides([u32; 2]),
    /// Along some unconstrained edge.
    Free,
}

/// How `u` may move; `scratch`: buffers reused from vertex to vertex.
fn motion(m: &Mesh, u: u32, corner_degrees: f64, scratch: &mut (Vec<u32>, Vec<(u32, u32)>)) -> Motion {
    let t = &m.topology;
    if t.vflags[u as usize] & vflag::LOCKED != 0 {
        return Motion::Fixed;
    }
    let (fan, targets) = scratch;
    fan.clear();
    fan.extend(t.outgoing(u));
    constraints::movable_targets(m, u, fan, corner_degrees, targets);
    if targets.is_empty() {
        return Motion::Fixed;
    }
    let mut along = fan.iter().filter(|&&g| constraints::edge_constrained(m, g)).map(|&g| t.dest(g));
    // The incoming border edge is constrained too; the fan (outgoing edges) lacks it.
    let incoming = t.is_boundary_vertex(u).then(|| t.origin(Topology::prev(fan[fan.len() - 1])));
    match (along.next(), along.next(), along.next(), incoming) {
        (Some(a), Some(b), None, None) | (Some(a), None, None, Some(b)) => Motion::Slides([a, b]),
        _ => Motion::Free,
    }
}

/// The L0 anchors to add to `grid` (the grid's anchors that always stay) on `m`: every vertex
/// that cannot move, one vertex of every sliding line with no anchor on it or at its ends, and
/// one vertex of every connected component that still has none. Ascending, none in `grid`.
/// `errors`: e(V) per vertex (anchors.rs ranks by it); `corner_degrees`: the border corner
/// angle the engine uses.
pub fn structure_anchors(m: &Mesh, errors: &[f32], grid: &[u32], corner_degrees: f64) -> Vec<u32> {
    let t = &m.topology;
    let n = t.vertex_count();
    let live = |v: u32| t.vertex_he[v as usize] != INVALID && t.vflags[v as usize] & vflag::REMOVED == 0;
    let motions: Vec<Option<Motion>> = (0..n as u32)
        .into_par_iter()
        .map_init(Default::default, |sc, v| live(v).then(|| motion(m, v, corner_degrees, sc)))
        .collect();
    let mut anchor = vec![false; n];
    for &a in grid {
        anchor[a as usize] = true;
    }
    let mut added = Vec::new();
    for (v, mo) in motions.iter().enumerate() {
        if *mo == Some(Motion::Fixed) && !anchor[v] {
            anchor[v] = true;
            added.push(v as u32);
        }
    }
    // Sliding lines: union-find over sliders joined by their constrained edges.
    let slides = |v: u32| match motions[v as usize] {
        Some(Motion::Slides(ends)) => Some(ends),
        _ => None,
    };
    let mut sets = UnionFind::new(n);
    for v in 0..n as u32 {
        for w in slides(v).into_iter().flatten() {
            // Joined only where both ends slide along this edge (a seam's edge is
            // constrained from both sides).
            if slides(w).is_some_and(|e| e.contains(&v)) {
                sets.union(v, w);
            }
        }
    }
    let mut line = vec![INVALID; n];
    let mut held = vec![false; n]; // by root: the line has S on it or at an end
    for v in 0..n as u32 {
        if let Some(ends) = slides(v) {
            let r = sets.find(v);
            line[v as usize] = r;
            held[r as usize] |= anchor[v as usize] || ends.iter().any(|&w| anchor[w as usize]);
        }
    }
    let lines_needing = best_of_groups(m, errors, &line, |r| !held[r as usize]);
    for &v in &lines_needing {
        anchor[v as usize] = true;
    }
    added.extend(lines_needing);
    // Components.
    let (face_comp, count) = face_components(t);
    let comp: Vec<u32> = (0..n as u32)
        .map(|v| if live(v) { face_comp[(t.vertex_he[v as usize] / 3) as usize] } else { INVALID })
        .collect();
    let mut anchored = vec![false; count];
    for v in 0..n {
        if anchor[v] && comp[v] != INVALID {
            anchored[comp[v] as usize] = true;
        }
    }
    added.extend(best_of_groups(m, errors, &comp, |c| !anchored[c as usize]));
    added.sort_unstable();
    added
}

/// For each group g (`group[v]`, `INVALID`: none) with `wanted(g)`, its best vertex, picked
/// as a grid cell picks ([`best_per_cell`]) with the group's bounding box for the cell.
fn best_of_groups(m: &Mesh, errors: &[f32], group: &[u32], wanted: impl Fn(u32) -> bool) -> Vec<u32> {
    let p = |v: usize| m.positions[v].map(f64::from);
    let in_play = |g: u32| g != INVALID && wanted(g);
    let groups = group.iter().filter(|&&g| g != INVALID).max().map_or(0, |&g| g as usize + 1);
    let mut bounds = vec![([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]); groups];
    for (v, &g) in group.iter().enumerate().filter(|e| in_play(*e.1)) {
        let (lo, hi) = &mut bounds[g as usize];
        for k in 0..3 {
            lo[k] = lo[k].min(p(v)[k]);
            hi[k] = hi[k].max(p(v)[k]);
        }
    }
    let scored: Vec<Scored> = group
        .iter()
        .enumerate()
        .filter(|e| in_play(*e.1))
        .map(|(v, &g)| {
            let (lo, hi) = bounds[g as usize];
            let l = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
            let d = (0..3).map(|k| (p(v)[k] - 0.5 * (lo[k] + hi[k])).powi(2)).sum::<f64>().sqrt();
            ([u64::from(g), 0, 0], (l - d).powi(2) * errors[v] as f64, d, v as u32)
        })
        .collect();
    best_per_cell(scored, 0, false)
}

/// Anchors chosen for a mesh: the layers of [`select_anchors`] with [`structure_anchors`]
/// added to L0, and the error floor of each L0 anchor.
#[derive(Debug, Clone, PartialEq)]
pub struct Anchors {
    /// Vertex ids per layer, ascending.
    pub layers: Vec<Vec<u32>>,
    /// The floor of each of `layers[0]`, in its order: +∞ for an anchor that always stays,
    /// finite under [`AnchorOptions::nested`] ([`nested_floors`]).
    pub floors: Vec<f32>,
}

impl Anchors {
    /// The anchors of L0 that stay whatever the threshold.
    pub fn always(&self) -> impl Iterator<Item = u32> + '_ {
        self.layers[0].iter().zip(&self.floors).filter(|(_, f)| f.is_infinite()).map(|(&v, _)| v)
    }

    /// Every anchor with its floor (L0's own, L_i's `o.layer_errors[i − 1]`, the largest where
    /// a vertex is in several layers), by vertex id, ascending.
    pub fn floor_list(&self, o: &AnchorOptions) -> Vec<(u32, f32)> {
        let mut list: Vec<(u32, f32)> = self.layers[0].iter().copied().zip(self.floors.iter().copied()).collect();
        for (layer, vs) in self.layers.iter().enumerate().skip(1) {
            list.extend(vs.iter().map(|&v| (v, o.layer_errors[layer - 1])));
        }
        largest_per_vertex(&mut list);
        list
    }

    /// Raises `errors` to the anchors' floors ([`Anchors::floor_list`]).
    pub fn raise(&self, errors: &mut [f32], o: &AnchorOptions) {
        for (v, f) in self.floor_list(o) {
            errors[v as usize] = errors[v as usize].max(f);
        }
    }
}

/// The anchors the coarsening rounds and the runtime keep on `m`: the grid's
/// ([`select_anchors`], L0 nested per [`AnchorOptions::nested`]) and the structure's
/// ([`structure_anchors`], placed against the grid's anchors that always stay, and always
/// staying themselves).
pub fn mesh_anchors(m: &Mesh, errors: &[f32], o: &AnchorOptions) -> Anchors {
    let (t, p) = (&m.topology, &m.positions);
    let layers = select_anchors(t, p, errors, o);
    let floors = nested_floors(t, p, errors, &layers[0], o);
    let mut grid = Anchors { layers, floors };
    let always: Vec<u32> = grid.always().collect();
    let extra = structure_anchors(m, errors, &always, constraints::BORDER_CORNER_DEGREES);
    // Merge: a structure anchor that the grid held with a finite floor now always stays.
    let mut merged: Vec<(u32, f32)> = grid.layers[0].iter().copied().zip(grid.floors).collect();
    merged.extend(extra.into_iter().map(|v| (v, f32::INFINITY)));
    largest_per_vertex(&mut merged);
    (grid.layers[0], grid.floors) = merged.into_iter().unzip();
    grid
}

/// Sorts (vertex, floor) pairs by vertex and keeps each vertex's largest floor.
fn largest_per_vertex(list: &mut Vec<(u32, f32)>) {
    list.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
    list.dedup_by_key(|e| e.0);
}
