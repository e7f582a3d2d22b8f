//! The flat mesh the passes edit: a triangle list indexed by the connectivity's face slots
//! and, per vertex, the slots of its faces (compressed rows, rebuilt after every pass). No
//! twins, no per-vertex half-edge: a vertex's fan is read from its faces' corners, as
//! meshoptimizer reads its adjacency.
//!
//! Within a pass the rows go stale in one way only: a collapse's target gains faces its row
//! does not list. The target is locked for the rest of the pass (module docs of `flat`), so
//! every row a pass reads (of a vertex that is not yet locked) lists exactly its live faces,
//! once dead ones are skipped. Face corners are rewritten at the collapse, so they are
//! always current.

use crate::mesh::Mesh;
use crate::topology::INVALID;

/// One face of a vertex u's fan: `a` follows u and `b` precedes it, counter-clockwise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Corner {
    pub face: u32,
    /// Which corner of the face is u (0–2).
    pub at: u8,
    pub a: u32,
    pub b: u32,
}

/// A vertex's fan and its neighbours, read from its row.
#[derive(Debug, Default)]
pub(super) struct Fan {
    pub corners: Vec<Corner>,
    /// Every neighbour once: the `a` of each corner, then for a border vertex the one `b`
    /// that is no corner's `a` (the start of its incoming border edge).
    pub ring: Vec<u32>,
}

impl Fan {
    /// The corners whose face holds edge (u, x): the one where x follows u (u → x), the one
    /// where x precedes u (x → u); `None` for a missing side (a border).
    pub fn edge(&self, x: u32) -> (Option<Corner>, Option<Corner>) {
        let forward = self.corners.iter().find(|c| c.a == x).copied();
        let backward = self.corners.iter().find(|c| c.b == x).copied();
        (forward, backward)
    }
}

/// The triangle list with per-vertex rows.
#[derive(Debug)]
pub(super) struct FlatFaces {
    /// Corners per face slot (a dead slot keeps its last corners).
    pub tris: Vec<[u32; 3]>,
    /// Wedge per corner per face slot; empty when the mesh's wedges are its vertices.
    pub wedges: Vec<[u32; 3]>,
    pub dead: Vec<bool>,
    /// Live face slots, ascending (compacted by [`FlatFaces::rebuild_rows`]).
    pub live: Vec<u32>,
    /// Live faces per vertex, exact at every moment.
    pub count: Vec<u32>,
    /// Row `v` is `corners[first[v]..first[v + 1]]`: v's corners `3f + k` (corner k of face
    /// f is v), so a walk reads each face's other corners without searching for v.
    first: Vec<u32>,
    corners: Vec<u32>,
}

impl FlatFaces {
    pub fn new(mesh: &Mesh) -> Self {
        let t = &mesh.topology;
        let tris = t.faces.clone();
        let dead: Vec<bool> = tris.iter().map(|f| f[0] == INVALID).collect();
        let live: Vec<u32> = (0..tris.len() as u32).filter(|&f| !dead[f as usize]).collect();
        let wedges = if mesh.wedges.is_identity() {
            Vec::new()
        } else {
            (0..tris.len() as u32).map(|f| [0, 1, 2].map(|k| mesh.corner_wedge(3 * f + k))).collect()
        };
        let mut count = vec![0u32; t.vertex_count()];
        for &f in &live {
            for v in tris[f as usize] {
                count[v as usize] += 1;
            }
        }
        let mut flat = Self { tris, wedges, dead, live, count, first: Vec::new(), corners: Vec::new() };
        flat.rebuild_rows();
        flat
    }

    /// Drops dead slots from the live list and lists every live face in its corners' rows,
    /// in slot order (a counting sort: the counts are known).
    pub fn rebuild_rows(&mut self) {
        let dead = &self.dead;
        self.live.retain(|&f| !dead[f as usize]);
        self.first.clear();
        self.first.reserve(self.count.len() + 1);
        let mut sum = 0u32;
        for &c in &self.count {
            self.first.push(sum);
            sum += c;
        }
        self.first.push(sum);
        self.corners.clear();
        self.corners.resize(sum as usize, INVALID);
        let mut fill: Vec<u32> = self.first[..self.count.len()].to_vec();
        for &f in &self.live {
            for (k, v) in self.tris[f as usize].into_iter().enumerate() {
                self.corners[fill[v as usize] as usize] = 3 * f + k as u32;
                fill[v as usize] += 1;
            }
        }
    }

    /// `v`'s row: its corners, dead faces' included.
    fn row_corners(&self, v: u32) -> &[u32] {
        &self.corners[self.first[v as usize] as usize..self.first[v as usize + 1] as usize]
    }

    /// The live corners of `v`'s row as (face, corner, a, b).
    fn live_corners(&self, v: u32) -> impl Iterator<Item = Corner> + '_ {
        self.row_corners(v).iter().filter(|&&c| !self.dead[(c / 3) as usize]).map(|&c| {
            let (face, at) = (c / 3, c % 3);
            let t = self.tris[face as usize];
            let (a, b) = match at {
                0 => (t[1], t[2]),
                1 => (t[2], t[0]),
                _ => (t[0], t[1]),
            };
            Corner { face, at: at as u8, a, b }
        })
    }

    /// The live faces of `u`'s row as corners, and its neighbours. Exact while u is not
    /// locked in the current pass (module docs).
    pub fn fan(&self, u: u32, border: bool, out: &mut Fan) {
        out.corners.clear();
        out.ring.clear();
        out.corners.extend(self.live_corners(u));
        out.ring.extend(out.corners.iter().map(|c| c.a));
        if border {
            let open = out.corners.iter().find(|c| !out.ring.contains(&c.b)).map(|c| c.b);
            out.ring.extend(open);
        }
    }

    /// The neighbours of `v` alone, as [`FlatFaces::fan`] lists them.
    pub fn ring(&self, v: u32, border: bool, out: &mut Vec<u32>) {
        out.clear();
        out.extend(self.live_corners(v).map(|c| c.a));
        if border {
            // The one `b` that is no face's `a`.
            let open = self.live_corners(v).map(|c| c.b).find(|b| !out.contains(b));
            out.extend(open);
        }
    }

    /// The wedge at corner `at` of face `f` (the vertex itself for identity wedges).
    pub fn wedge(&self, f: u32, at: u8) -> u32 {
        match self.wedges.get(f as usize) {
            Some(w) => w[at as usize],
            None => self.tris[f as usize][at as usize],
        }
    }

    /// Collapses u into v, given u's current fan and the wedge map u → v through the faces
    /// on the edge: those faces die, u's other faces name v (and v's wedge). Returns the
    /// number of faces removed. v's row does not list the faces it gained until
    /// [`FlatFaces::rebuild_rows`].
    pub fn collapse(&mut self, u: u32, v: u32, fan: &Fan, map: [(u32, u32); 2]) -> usize {
        let mut removed = 0;
        for c in &fan.corners {
            let f = c.face as usize;
            if c.a == v || c.b == v {
                self.dead[f] = true;
                for x in self.tris[f] {
                    self.count[x as usize] -= 1;
                }
                removed += 1;
            } else {
                self.tris[f][c.at as usize] = v;
                self.count[v as usize] += 1;
                if let Some(w) = self.wedges.get_mut(f) {
                    let old = w[c.at as usize];
                    w[c.at as usize] = map.iter().find(|&&(from, _)| from == old).map_or(old, |&(_, to)| to);
                }
            }
        }
        self.count[u as usize] = 0;
        removed
    }

    /// The live faces of `v`'s row (exact once the rows are rebuilt).
    pub fn row(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.row_corners(v).iter().map(|&c| c / 3).filter(|&f| !self.dead[f as usize])
    }
}
