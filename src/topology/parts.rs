//! The connectivity cut into parts, so that the collapses of a papers/000 §4 round can be made
//! on several threads at once without locks (docs/ALGORITHM.md, "Applying a round in parts").
//!
//! ```text
//!   vertex ids  [0 ........ V1)[V1 ........ V2) …      part k: vertices [V_k, V_k+1),
//!   face ids    [0 ... F1)[F1 ........... F2) …              faces [F_k, F_k+1) (and their half-edges)
//!   inner(x) = k   when x, every face around x and every corner of those faces are in part k
//!   a collapse u → v (wings a, b) belongs to part k when inner(u) = inner(v) = inner(a) = inner(b) = k
//! ```
//! Everything such a collapse reads or writes lies in its part: the fans of u, v and the wings
//! (faces, their twins, their corners), and per-vertex state of those corners. (A twin across a
//! fan's edge is an outgoing half-edge of one of its ends, so it is in a face of that fan too.)
//! So the collapses of different parts touch disjoint ids, and making each part's collapses in
//! order, all parts side by side, leaves the same mesh as making them part after part. The
//! collapses that belong to no part are made afterwards, on the whole mesh.
//!
//! A collapse in part k keeps every inner vertex inner: v gains u's faces (in part k, with
//! corners in part k), other fans only lose faces or rename u to v. A collapse that belongs to
//! no part can change a fan across the cut, so the vertices it touched are looked at again
//! ([`Parts::refresh`]). The cuts never move, and nothing here depends on the thread count.
//!
//! The cuts follow the vertex ids: faces are cut where their lowest corner crosses a vertex
//! cut, which keeps most fans inside one part when the ids run along the surface (a mesh in
//! spatial order, [`crate::BuildOptions::spatial_order`]). In any other order fewer vertices
//! are inner and more collapses wait for the whole mesh; the result is as valid either way.

use super::{HalfEdgeCollapse, HalfEdges, HalfEdgesMut, Topology, INVALID};

/// Marks a vertex that is not inside a single part.
const MIXED: u8 = u8::MAX;

/// Where the ids are cut, and which vertices lie inside one part (see the module docs).
#[derive(Debug, Clone)]
pub struct Parts {
    /// P + 1 vertex ids, from 0 to the vertex count.
    vertex_cuts: Vec<u32>,
    /// P + 1 face ids, from 0 to the face count.
    face_cuts: Vec<u32>,
    /// Per vertex: its part if it is inner, else [`MIXED`].
    inner: Vec<u8>,
}

impl Parts {
    /// Cuts `t` into `parts` ranges of about equal vertex counts (at most 254).
    pub fn new(t: &Topology, parts: usize) -> Self {
        use rayon::prelude::*;
        let parts = parts.clamp(1, MIXED as usize - 1);
        let n = t.vertex_count();
        let vertex_cuts: Vec<u32> = (0..=parts).map(|k| (k * n / parts) as u32).collect();
        // Faces before cut k: those whose lowest corner is below vertex cut k (a prefix when
        // faces are sorted by their lowest corner, as in spatial order). A removed face
        // counts in the last part.
        let low = |f: &[u32; 3]| f[0].min(f[1]).min(f[2]);
        let face_cuts: Vec<u32> = vertex_cuts
            .iter()
            .enumerate()
            .map(|(k, &cut)| match k {
                0 => 0,
                _ if k == parts => t.faces.len() as u32,
                _ => t.faces.par_iter().filter(|f| low(f) < cut).count() as u32,
            })
            .collect();
        // A vertex is inner unless it is a corner of a face with a corner in another part, or
        // a corner of a face in another part (then that face has a corner from outside its
        // part: this one). So only the faces with corners outside their part mark anything.
        let outside: Vec<[u32; 3]> = (0..parts)
            .into_par_iter()
            .flat_map_iter(|k| {
                let vertices = vertex_cuts[k]..vertex_cuts[k + 1];
                let faces = &t.faces[face_cuts[k] as usize..face_cuts[k + 1] as usize];
                faces.iter().filter(move |f| f[0] != INVALID && !f.iter().all(|x| vertices.contains(x))).copied()
            })
            .collect();
        let mut inner: Vec<u8> = vec![0; n];
        for k in 0..parts {
            inner[vertex_cuts[k] as usize..vertex_cuts[k + 1] as usize].fill(k as u8);
        }
        for x in outside.into_iter().flatten() {
            inner[x as usize] = MIXED;
        }
        for (part, &h) in inner.iter_mut().zip(&t.vertex_he) {
            if h == INVALID {
                *part = MIXED;
            }
        }
        Self { vertex_cuts, face_cuts, inner }
    }

    /// How many parts.
    pub fn count(&self) -> usize {
        self.vertex_cuts.len() - 1
    }

    /// Part `k`'s vertex ids and face ids.
    pub fn ranges(&self, k: usize) -> (std::ops::Range<u32>, std::ops::Range<u32>) {
        (self.vertex_cuts[k]..self.vertex_cuts[k + 1], self.face_cuts[k]..self.face_cuts[k + 1])
    }

    /// The share of live vertices recorded as inner: near 1 when the ids run along the
    /// surface, much lower in scan or file order.
    pub fn inner_share(&self, t: &Topology) -> f64 {
        let live = t.live_vertex_count().max(1);
        self.inner.iter().filter(|&&k| k != MIXED).count() as f64 / live as f64
    }

    /// The part `v` is recorded as inner to, if any. Every vertex recorded inner is inner on
    /// the connectivity after every application ([`Parts::refresh`]); a vertex may be inner
    /// without being recorded (its fan moved back inside), which only costs parallelism.
    pub fn inner(&self, v: u32) -> Option<usize> {
        let k = self.inner[v as usize];
        (k != MIXED).then_some(k as usize)
    }

    /// The part `v` is inner to, worked out from its fan ([`MIXED`] if none).
    fn inner_part(&self, t: &Topology, v: u32) -> u8 {
        if t.vertex_he[v as usize] == INVALID {
            return MIXED;
        }
        let k = vertex_part(&self.vertex_cuts, v);
        let (vertices, faces) = self.ranges(k);
        let inside = t.outgoing(v).all(|g| {
            let f = g / 3;
            faces.contains(&f) && t.faces[f as usize].iter().all(|x| vertices.contains(x))
        });
        if inside {
            k as u8
        } else {
            MIXED
        }
    }

    /// The part that `c` (u → v with its wings) lies inside, if any.
    #[inline]
    pub fn part_of(&self, t: &Topology, c: HalfEdgeCollapse) -> Option<usize> {
        let k = self.inner[c.remove as usize];
        let same = |x: u32| x == INVALID || self.inner[x as usize] == k;
        (k != MIXED && same(t.collapse_target(c)) && t.wings(c).into_iter().all(same)).then_some(k as usize)
    }

    /// Works out again whether each of `vertices` is inner (after collapses that belonged to
    /// no part changed their fans), on the pool when there are at least `serial_below`.
    pub fn refresh(&mut self, t: &Topology, vertices: &[u32], serial_below: usize) {
        let now = crate::par::map_sized(vertices, serial_below, 256, |_: &mut (), &v| self.inner_part(t, v));
        for (&v, k) in vertices.iter().zip(now) {
            self.inner[v as usize] = k;
        }
    }

    /// The connectivity, one [`TopologyPart`] per part, in order.
    pub fn split<'a>(&self, t: &'a mut Topology) -> Vec<TopologyPart<'a>> {
        let faces = split_by(&mut t.faces, &self.face_cuts, 1);
        let twin = split_by(&mut t.twin, &self.face_cuts, 3);
        let vertex_he = split_by(&mut t.vertex_he, &self.vertex_cuts, 1);
        let vflags = split_by(&mut t.vflags, &self.vertex_cuts, 1);
        faces
            .into_iter()
            .zip(twin)
            .zip(vertex_he.into_iter().zip(vflags))
            .enumerate()
            .map(|(k, ((faces, twin), (vertex_he, vflags)))| TopologyPart {
                first_vertex: self.vertex_cuts[k],
                first_face: self.face_cuts[k],
                first_he: 3 * self.face_cuts[k],
                faces,
                twin,
                vertex_he,
                vflags,
            })
            .collect()
    }

    /// A per-vertex array cut at the vertex cuts, with each piece's first vertex id.
    pub fn split_vertices<'a, T>(&self, xs: &'a mut [T]) -> Vec<(u32, &'a mut [T])> {
        self.vertex_cuts.iter().copied().zip(split_by(xs, &self.vertex_cuts, 1)).collect()
    }
}

/// The part of vertex `v` (or of face `v` with face cuts).
fn vertex_part(cuts: &[u32], v: u32) -> usize {
    cuts[1..].partition_point(|&c| c <= v)
}

/// `xs` cut at `cuts` (ids, `per` entries each).
fn split_by<'a, T>(mut xs: &'a mut [T], cuts: &[u32], per: usize) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(cuts.len() - 1);
    for w in cuts.windows(2) {
        let (head, rest) = std::mem::take(&mut xs).split_at_mut((w[1] - w[0]) as usize * per);
        out.push(head);
        xs = rest;
    }
    out
}

/// One part of a [`Topology`]: its range of vertices and faces, by their global ids. Asking
/// it about an id outside its ranges panics.
#[derive(Debug)]
pub struct TopologyPart<'a> {
    first_vertex: u32,
    first_face: u32,
    first_he: u32,
    faces: &'a mut [[u32; 3]],
    twin: &'a mut [u32],
    vertex_he: &'a mut [u32],
    vflags: &'a mut [u8],
}

impl TopologyPart<'_> {
    #[inline]
    fn he(&self, h: u32) -> usize {
        h.wrapping_sub(self.first_he) as usize
    }
    #[inline]
    fn f(&self, f: u32) -> usize {
        f.wrapping_sub(self.first_face) as usize
    }
    #[inline]
    fn v(&self, v: u32) -> usize {
        v.wrapping_sub(self.first_vertex) as usize
    }
}

impl HalfEdges for TopologyPart<'_> {
    #[inline]
    fn origin(&self, h: u32) -> u32 {
        self.faces.as_flattened()[self.he(h)]
    }
    #[inline]
    fn face(&self, f: u32) -> [u32; 3] {
        self.faces[self.f(f)]
    }
    #[inline]
    fn twin_of(&self, h: u32) -> u32 {
        self.twin[self.he(h)]
    }
    #[inline]
    fn vertex_he_of(&self, v: u32) -> u32 {
        self.vertex_he[self.v(v)]
    }
    #[inline]
    fn flags_of(&self, v: u32) -> u8 {
        self.vflags[self.v(v)]
    }
    #[inline]
    fn has_half_edge(&self, h: u32) -> bool {
        self.he(h) < self.twin.len()
    }
    #[inline]
    fn half_edge_slots(&self) -> usize {
        self.twin.len()
    }
}

impl HalfEdgesMut for TopologyPart<'_> {
    #[inline]
    fn set_origin(&mut self, h: u32, v: u32) {
        let i = self.he(h);
        self.faces.as_flattened_mut()[i] = v;
    }
    #[inline]
    fn set_face(&mut self, f: u32, corners: [u32; 3]) {
        let i = self.f(f);
        self.faces[i] = corners;
    }
    #[inline]
    fn set_twin(&mut self, h: u32, t: u32) {
        let i = self.he(h);
        self.twin[i] = t;
    }
    #[inline]
    fn set_vertex_he(&mut self, v: u32, h: u32) {
        let i = self.v(v);
        self.vertex_he[i] = h;
    }
    #[inline]
    fn set_flags(&mut self, v: u32, flags: u8) {
        let i = self.v(v);
        self.vflags[i] = flags;
    }
}
