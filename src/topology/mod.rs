//! Compact manifold connectivity for parallel edits and GPU upload.
//!
//! Half-edges are implicit: half-edge `h = 3f + c` belongs to face `f = h / 3` and runs from
//! corner `c` to corner `c + 1` of that face. Every array is a flat `Vec` of `u32` ids (or a
//! `#[repr(C)]` record of them) so a compute kernel can read it unchanged; [`INVALID`] marks
//! "none" (a border, a removed face or vertex).
//!
//! ```text
//!            v2                 faces[f]   = [v0, v1, v2]      (counter-clockwise)
//!           /  \                he 3f+0    = v0 -> v1, he 3f+1 = v1 -> v2, he 3f+2 = v2 -> v0
//!   3f+2  /  f   \ 3f+1         twin[h]    = the opposite half-edge in the neighbour, or INVALID
//!        v0 ---- v1             vertex_he[v] = an outgoing half-edge (the border one if any)
//!           3f+0
//! ```
//!
//! Around a vertex, `twin(prev(h))` turns counter-clockwise from one outgoing half-edge to
//! the next; a border vertex's `vertex_he` is the outgoing border half-edge, so a walk from it
//! meets every incident face exactly once. [`Topology::validate`] checks all of this.

mod collapse;
mod edge_groups;
mod half_edges;
mod parts;
mod round_touches;
mod stats;
mod union_find;
mod validate;

pub(crate) use collapse::MAX_LINK_VALENCE;
pub use collapse::{on_removed_face, CollapseWrites, HalfEdgeCollapse, Illegal, LISTED_CORNERS};
pub use edge_groups::EdgeGroups;
pub use half_edges::{HalfEdges, HalfEdgesMut, Outgoing};
pub use parts::{Parts, TopologyPart};
pub use round_touches::{Gained, RoundTouches, RoundTouchesPart};
pub use stats::{face_components, TopologyStats};
pub use union_find::UnionFind;
pub use validate::TopologyError;

/// The "no id" marker in every connectivity array.
pub const INVALID: u32 = u32::MAX;

/// Per-vertex flag bits stored in [`Topology::vflags`].
pub mod vflag {
    /// The vertex lies on a mesh border.
    pub const BOUNDARY: u8 = 1;
    /// The vertex is no longer part of the mesh (collapsed away).
    pub const REMOVED: u8 = 2;
    /// The user asked that the vertex never move or disappear.
    pub const LOCKED: u8 = 4;
    /// The vertex lies on an attribute seam (UV or normal discontinuity).
    pub const SEAM: u8 = 8;
}

/// Manifold, consistently oriented triangle connectivity. See the module docs for layout. The
/// walks (`outgoing`, `neighbors`, …) and the collapse are the [`HalfEdges`] and
/// [`HalfEdgesMut`] traits' methods: bring them into scope with
/// `use dynlod::topology::{HalfEdges, HalfEdgesMut}`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topology {
    /// Vertex ids per face; a removed face holds `[INVALID; 3]`.
    pub faces: Vec<[u32; 3]>,
    /// Opposite half-edge, or `INVALID` on a border. Three entries per face. A removed face's
    /// entries keep their last values (what the runtime's split reads back); only live
    /// faces' twins are meaningful.
    pub twin: Vec<u32>,
    /// One outgoing half-edge per vertex: the border one for border vertices.
    pub vertex_he: Vec<u32>,
    /// [`vflag`] bits per vertex.
    pub vflags: Vec<u8>,
}

impl Topology {
    /// Builds connectivity from faces over `vertex_count` vertices. Fails, naming the first
    /// offending element, unless the faces form an oriented 2-manifold (with border) in which
    /// every vertex is used. Use [`crate::Mesh::build`] for raw input: it repairs first.
    pub fn from_faces(vertex_count: usize, faces: Vec<[u32; 3]>) -> Result<Self, TopologyError> {
        for (f, t) in faces.iter().enumerate() {
            for (c, &v) in t.iter().enumerate() {
                if v as usize >= vertex_count {
                    return Err(TopologyError::FaceVertexOutOfRange { face: f as u32, corner: c as u8, vertex: v });
                }
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(TopologyError::DegenerateFace { face: f as u32 });
            }
        }
        let mut twin = vec![INVALID; faces.len() * 3];
        let mut failure = None;
        EdgeGroups::new(vertex_count, &faces).for_each(|lo, hi, hes| {
            if failure.is_some() {
                return;
            }
            match *hes {
                [_] => {}
                [h, g] if origin_in(&faces, h) != origin_in(&faces, g) => {
                    twin[h as usize] = g;
                    twin[g as usize] = h;
                }
                [h, g] => failure = Some(TopologyError::InconsistentOrientation { he: h, other: g, v0: lo, v1: hi }),
                _ => failure = Some(TopologyError::NonManifoldEdge { v0: lo, v1: hi, faces: hes.len() as u32 }),
            }
        });
        if let Some(e) = failure {
            return Err(e);
        }
        Self::from_twins(vertex_count, faces, twin)
    }

    /// Builds connectivity from faces and a twin array already known to pair opposite
    /// half-edges (as the repair passes produce). Checks
    /// twin symmetry and vertex fans; [`Topology::validate`] checks the rest.
    pub fn from_twins(vertex_count: usize, faces: Vec<[u32; 3]>, twin: Vec<u32>) -> Result<Self, TopologyError> {
        let nh = faces.len() * 3;
        if twin.len() != nh {
            return Err(TopologyError::Length { array: "twin", len: twin.len(), expected: nh });
        }
        for h in 0..nh as u32 {
            let t = twin[h as usize];
            if t != INVALID && (t as usize >= nh || twin[t as usize] != h) {
                return Err(TopologyError::TwinAsymmetric { he: h, twin: t });
            }
        }
        let mut topo = Self { faces, twin, vertex_he: vec![INVALID; vertex_count], vflags: vec![0; vertex_count] };
        topo.rebuild_vertex_links();
        topo.check_vertex_fans()?;
        Ok(topo)
    }

    /// Recomputes `vertex_he` and the BOUNDARY flag from faces and twins: each vertex gets
    /// its outgoing border half-edge if it has one, else its smallest outgoing half-edge.
    pub fn rebuild_vertex_links(&mut self) {
        self.vertex_he.fill(INVALID);
        for f in &mut self.vflags {
            *f &= !vflag::BOUNDARY;
        }
        for h in 0..self.twin.len() as u32 {
            if !self.is_face_live(h / 3) {
                continue;
            }
            let v = self.origin(h) as usize;
            let border = self.twin[h as usize] == INVALID;
            if self.vertex_he[v] == INVALID || (border && self.vflags[v] & vflag::BOUNDARY == 0) {
                self.vertex_he[v] = h;
            }
            if border {
                self.vflags[v] |= vflag::BOUNDARY;
            }
        }
    }

    /// Every vertex's fan (the walk from `vertex_he`) must hold all its faces, and every vertex
    /// must have a face unless it is flagged REMOVED.
    fn check_vertex_fans(&self) -> Result<(), TopologyError> {
        let mut incident = vec![0u32; self.vertex_count()];
        for f in self.faces.iter().filter(|f| f[0] != INVALID) {
            for &v in f {
                incident[v as usize] += 1;
            }
        }
        for (v, &count) in incident.iter().enumerate() {
            let v = v as u32;
            if self.vertex_he[v as usize] == INVALID {
                if self.vflags[v as usize] & vflag::REMOVED == 0 {
                    return Err(TopologyError::IsolatedVertex { vertex: v });
                }
                continue;
            }
            let fan = self.outgoing(v).take(count as usize + 1).count() as u32;
            if fan != count {
                return Err(TopologyError::NonManifoldVertex { vertex: v, fan_faces: fan, incident_faces: count });
            }
        }
        Ok(())
    }

    /// Number of vertex slots (including removed vertices).
    pub fn vertex_count(&self) -> usize {
        self.vertex_he.len()
    }

    /// Number of face slots (including removed faces).
    pub fn face_slots(&self) -> usize {
        self.faces.len()
    }

    /// Number of live faces.
    pub fn live_face_count(&self) -> usize {
        self.faces.iter().filter(|f| f[0] != INVALID).count()
    }

    /// Number of live vertices.
    pub fn live_vertex_count(&self) -> usize {
        self.vertex_he.iter().filter(|&&h| h != INVALID).count()
    }

    /// Next half-edge in the same face.
    #[inline]
    pub fn next(h: u32) -> u32 {
        if h % 3 == 2 {
            h - 2
        } else {
            h + 1
        }
    }

    /// Previous half-edge in the same face.
    #[inline]
    pub fn prev(h: u32) -> u32 {
        if h % 3 == 0 {
            h + 2
        } else {
            h - 1
        }
    }

    /// A half-edge of edge (u, w), in either direction, if the edge exists (on a border only
    /// one direction exists).
    pub fn find_edge(&self, u: u32, w: u32) -> Option<u32> {
        self.outgoing(u).find(|&g| self.dest(g) == w).or_else(|| {
            let last = self.outgoing(u).last()?;
            let inc = Self::prev(last);
            (self.twin[inc as usize] == INVALID && self.origin(inc) == w).then_some(inc)
        })
    }

    /// Counts and shapes: components, borders, Euler characteristic, genus.
    pub fn stats(&self) -> TopologyStats {
        stats::compute(self)
    }
}

/// Turns clockwise around the origin of outgoing half-edge `h` (`next(twin(g))` per step)
/// until the fan's first half-edge (one whose twin is a border) or all the way round back to
/// `h`, taking at most `bound` steps. Works on any twin array, so the repair passes can use it
/// before a [`Topology`] exists.
pub fn fan_start(twin: &[u32], h: u32, bound: usize) -> u32 {
    fan_start_by(|g| twin[g as usize], h, bound)
}

/// [`fan_start`] with the twins read through `twin_of` (a whole connectivity or a part of
/// it: [`HalfEdges::fan_start_of`]).
#[inline]
pub(crate) fn fan_start_by(twin_of: impl Fn(u32) -> u32, h: u32, bound: usize) -> u32 {
    let mut s = h;
    for _ in 0..bound {
        let t = twin_of(s);
        if t == INVALID {
            break;
        }
        let n = Topology::next(t);
        if n == h {
            break;
        }
        s = n;
    }
    s
}

#[inline]
fn origin_in(faces: &[[u32; 3]], h: u32) -> u32 {
    faces[(h / 3) as usize][(h % 3) as usize]
}
