//! Every invariant of [`Topology`], checked from scratch. Run by the tests after every
//! operation and by `dynlod info`; later passes run it after each round in debug builds.
//!
//! Checked, in order (the first violation is reported with its ids):
//! 1. array lengths agree;
//! 2. live faces name three distinct, live, in-range vertices;
//! 3. twins are symmetric and opposite (`twin[twin[h]] == h`, `origin(twin h) == dest(h)`):
//!    consistent orientation across every edge;
//! 4. no directed edge appears twice, and no border half-edge has an unlinked opposite
//!    (manifold edges, no multi-edges);
//! 5. each vertex's fan from `vertex_he` holds all its faces, border vertices start at their
//!    border half-edge and carry the BOUNDARY flag (manifold vertices);
//! 6. per component, the Euler characteristic χ = V − E + F and the number of border loops b
//!    give a genus g = (2 − χ − b) / 2 that is a whole number ≥ 0.

use rustc_hash::FxHashMap;

use super::{vflag, HalfEdges, Topology, INVALID};

/// The first violated invariant, with the ids involved.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TopologyError {
    /// Array lengths disagree.
    #[error("array {array} has {len} entries, expected {expected}")]
    Length {
        /// Which array.
        array: &'static str,
        /// Its length.
        len: usize,
        /// The length implied by the others.
        expected: usize,
    },
    /// A face names a vertex that does not exist or was removed.
    #[error("face {face} corner {corner} names vertex {vertex}, which does not exist or was removed")]
    FaceVertexOutOfRange {
        /// Face id.
        face: u32,
        /// Corner 0..3.
        corner: u8,
        /// The vertex named.
        vertex: u32,
    },
    /// A face names the same vertex twice.
    #[error("face {face} names the same vertex twice")]
    DegenerateFace {
        /// Face id.
        face: u32,
    },
    /// `twin[twin[h]] != h`, or the twin lies in a removed face.
    #[error("half-edge {he} has twin {twin}, whose twin is not {he}")]
    TwinAsymmetric {
        /// Half-edge id.
        he: u32,
        /// Its recorded twin.
        twin: u32,
    },
    /// Twins run the same way, or do not join the same vertices.
    #[error("half-edges {he} and {other} on edge {v0}-{v1} are not opposite: inconsistent orientation")]
    InconsistentOrientation {
        /// One half-edge.
        he: u32,
        /// The other.
        other: u32,
        /// Smaller endpoint.
        v0: u32,
        /// Larger endpoint.
        v1: u32,
    },
    /// More than two faces share an edge.
    #[error("edge {v0}-{v1} is shared by {faces} faces")]
    NonManifoldEdge {
        /// Smaller endpoint.
        v0: u32,
        /// Larger endpoint.
        v1: u32,
        /// Faces on the edge.
        faces: u32,
    },
    /// Two half-edges join the same vertices without being twins.
    #[error("half-edges {he} and {other} both join vertices {v0} and {v1} but are not twins")]
    MultiEdge {
        /// One half-edge.
        he: u32,
        /// The other.
        other: u32,
        /// One endpoint.
        v0: u32,
        /// The other endpoint.
        v1: u32,
    },
    /// A vertex's fan does not hold all its faces: the vertex is pinched (a bowtie).
    #[error("vertex {vertex} is not manifold: its fan holds {fan_faces} of its {incident_faces} faces")]
    NonManifoldVertex {
        /// Vertex id.
        vertex: u32,
        /// Faces met walking around it.
        fan_faces: u32,
        /// Faces that use it.
        incident_faces: u32,
    },
    /// `vertex_he` is wrong: not outgoing, or not the border half-edge of a border vertex.
    #[error("vertex {vertex}: vertex_he {he} is not its {}outgoing half-edge", if *border { "border " } else { "" })]
    VertexHalfEdge {
        /// Vertex id.
        vertex: u32,
        /// The recorded half-edge.
        he: u32,
        /// Whether the vertex is on a border.
        border: bool,
    },
    /// The BOUNDARY flag disagrees with the half-edges.
    #[error("vertex {vertex}: BOUNDARY flag is {flag} but the vertex is {}on a border", if *flag { "not " } else { "" })]
    BoundaryFlag {
        /// Vertex id.
        vertex: u32,
        /// The flag as stored.
        flag: bool,
    },
    /// A vertex without faces that is not flagged REMOVED.
    #[error("vertex {vertex} has no faces but is not marked removed")]
    IsolatedVertex {
        /// Vertex id.
        vertex: u32,
    },
    /// The counts of a component do not describe an orientable surface.
    #[error("component {component}: χ = {euler} with {boundary_loops} border loops gives no whole genus ≥ 0")]
    Euler {
        /// Component index (see [`super::TopologyStats`]).
        component: u32,
        /// V − E + F of the component.
        euler: i64,
        /// Border loops of the component.
        boundary_loops: u32,
    },
}

impl Topology {
    /// Checks every invariant listed in the module docs; returns the first violation.
    pub fn validate(&self) -> Result<(), TopologyError> {
        self.check_lengths()?;
        self.check_faces()?;
        self.check_twins()?;
        self.check_vertices()?;
        self.check_vertex_fans()?;
        for (i, c) in self.stats().components.iter().enumerate() {
            let g2 = 2 - c.euler - c.boundary_loops as i64;
            if g2 < 0 || g2 % 2 != 0 {
                return Err(TopologyError::Euler {
                    component: i as u32,
                    euler: c.euler,
                    boundary_loops: c.boundary_loops,
                });
            }
        }
        Ok(())
    }

    fn check_lengths(&self) -> Result<(), TopologyError> {
        let nh = self.faces.len() * 3;
        let nv = self.vertex_he.len();
        for (array, len, expected) in [("twin", self.twin.len(), nh), ("vflags", self.vflags.len(), nv)] {
            if len != expected {
                return Err(TopologyError::Length { array, len, expected });
            }
        }
        Ok(())
    }

    fn check_faces(&self) -> Result<(), TopologyError> {
        for (f, t) in self.faces.iter().enumerate() {
            if t[0] == INVALID {
                continue;
            }
            for (c, &v) in t.iter().enumerate() {
                let bad = v as usize >= self.vertex_count() || self.vflags[v as usize] & vflag::REMOVED != 0;
                if bad {
                    return Err(TopologyError::FaceVertexOutOfRange { face: f as u32, corner: c as u8, vertex: v });
                }
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                return Err(TopologyError::DegenerateFace { face: f as u32 });
            }
        }
        Ok(())
    }

    fn check_twins(&self) -> Result<(), TopologyError> {
        let nh = self.twin.len() as u32;
        // Directed edge (origin, dest) -> half-edge, to find duplicates and unlinked opposites.
        let mut directed: FxHashMap<u64, u32> = FxHashMap::default();
        directed.reserve(nh as usize);
        for h in 0..nh {
            if !self.is_face_live(h / 3) {
                continue;
            }
            let (a, b) = (self.origin(h), self.dest(h));
            if let Some(other) = directed.insert(key(a, b), h) {
                return Err(TopologyError::InconsistentOrientation { he: other, other: h, v0: a.min(b), v1: a.max(b) });
            }
            let t = self.twin[h as usize];
            if t == INVALID {
                continue;
            }
            if t >= nh || !self.is_face_live(t / 3) || self.twin[t as usize] != h {
                return Err(TopologyError::TwinAsymmetric { he: h, twin: t });
            }
            if self.origin(t) != b || self.dest(t) != a {
                return Err(TopologyError::InconsistentOrientation { he: h, other: t, v0: a.min(b), v1: a.max(b) });
            }
        }
        for h in 0..nh {
            if !self.is_face_live(h / 3) || self.twin[h as usize] != INVALID {
                continue;
            }
            let (a, b) = (self.origin(h), self.dest(h));
            if let Some(&other) = directed.get(&key(b, a)) {
                return Err(TopologyError::MultiEdge { he: h, other, v0: a, v1: b });
            }
        }
        Ok(())
    }

    fn check_vertices(&self) -> Result<(), TopologyError> {
        let mut border = vec![false; self.vertex_count()];
        for h in 0..self.twin.len() as u32 {
            if self.is_face_live(h / 3) && self.twin[h as usize] == INVALID {
                border[self.origin(h) as usize] = true;
            }
        }
        for v in 0..self.vertex_count() as u32 {
            let h = self.vertex_he[v as usize];
            let flag = self.vflags[v as usize] & vflag::BOUNDARY != 0;
            if h == INVALID {
                continue; // isolated or removed: check_vertex_fans decides
            }
            let b = border[v as usize];
            let ok = (h as usize) < self.twin.len()
                && self.is_face_live(h / 3)
                && self.origin(h) == v
                && (!b || self.twin[h as usize] == INVALID);
            if !ok {
                return Err(TopologyError::VertexHalfEdge { vertex: v, he: h, border: b });
            }
            if flag != b {
                return Err(TopologyError::BoundaryFlag { vertex: v, flag });
            }
        }
        Ok(())
    }
}

#[inline]
fn key(a: u32, b: u32) -> u64 {
    ((a as u64) << 32) | b as u64
}
