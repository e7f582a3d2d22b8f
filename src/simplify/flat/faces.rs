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
//!
//! The corners, wedges, dead flags and face counts are atomic cells read and written with
//! relaxed ordering (plain loads and stores on x86 and ARM): the walk collapses in several
//! blocks of the mesh at once through a shared `&FlatFaces`, and the blocks touch disjoint
//! cells (the argument is in `walk.rs`). Between phases rayon's joins order everything.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::topology::INVALID;

/// 0, a, a + b, … : where each row starts, and the total.
fn prefix_sums(counts: impl Iterator<Item = u32>) -> Vec<u32> {
    let mut sum = 0;
    let mut first: Vec<u32> = counts
        .map(|c| {
            sum += c;
            sum - c
        })
        .collect();
    first.push(sum);
    first
}

/// The corner after and before corner k of a face, counter-clockwise.
const NEXT: [usize; 3] = [1, 2, 0];
const PREV: [usize; 3] = [2, 0, 1];

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
    tris: Vec<[AtomicU32; 3]>,
    /// Wedge per corner per face slot; empty when the mesh's wedges are its vertices.
    wedges: Vec<[AtomicU32; 3]>,
    dead: Vec<AtomicBool>,
    /// Live faces per vertex, exact at every moment.
    count: Vec<AtomicU32>,
    /// Row `v` is `corners[first[v]..first[v + 1]]`: v's corners `3f + k` (corner k of face
    /// f is v), so a walk reads each face's other corners without searching for v.
    first: Vec<u32>,
    corners: Vec<u32>,
    /// The rows before the last rebuild (their buffers, reused).
    old_first: Vec<u32>,
    old_corners: Vec<u32>,
    /// Per vertex, the vertex collapsed into it in the last pass (`INVALID` if none).
    gained: Vec<u32>,
}

/// Fewest vertices a task of the row rebuild takes.
const ROW_TASK: usize = 4096;

impl FlatFaces {
    pub fn new(mesh: &Mesh) -> Self {
        let t = &mesh.topology;
        let tris = t.faces.iter().map(|f| f.map(AtomicU32::new)).collect();
        let dead = t.faces.iter().map(|f| AtomicBool::new(f[0] == INVALID)).collect();
        let wedges = if mesh.wedges.is_identity() {
            Vec::new()
        } else {
            (0..t.faces.len() as u32).map(|f| [0, 1, 2].map(|k| AtomicU32::new(mesh.corner_wedge(3 * f + k)))).collect()
        };
        let mut count = vec![0u32; t.vertex_count()];
        for f in t.faces.iter().filter(|f| f[0] != INVALID) {
            for &v in f {
                count[v as usize] += 1;
            }
        }
        // Every live face in its corners' rows, in slot order (a counting sort).
        let first = prefix_sums(count.iter().copied());
        let mut corners = vec![INVALID; first[count.len()] as usize];
        let mut fill = first.clone();
        for (f, tri) in t.faces.iter().enumerate().filter(|(_, f)| f[0] != INVALID) {
            for (k, &v) in tri.iter().enumerate() {
                corners[fill[v as usize] as usize] = 3 * f as u32 + k as u32;
                fill[v as usize] += 1;
            }
        }
        Self {
            tris,
            wedges,
            dead,
            count: count.into_iter().map(AtomicU32::new).collect(),
            first,
            corners,
            old_first: Vec::new(),
            old_corners: Vec::new(),
            gained: vec![INVALID; t.vertex_count()],
        }
    }

    /// Rebuilds the rows after a pass whose collapses were `made` (u → v), in parallel:
    /// each vertex keeps the live faces of its row, and a target also takes u's (v sits where
    /// u sat, so they are the same corner ids). A vertex is the target of one collapse per
    /// pass at most (it is locked after), and its faces can only have died since.
    pub fn rebuild_rows(&mut self, made: impl IntoIterator<Item = (u32, u32)>) {
        for (u, v) in made {
            self.gained[v as usize] = u;
        }
        std::mem::swap(&mut self.first, &mut self.old_first);
        std::mem::swap(&mut self.corners, &mut self.old_corners);
        self.first.clear();
        self.first.extend(prefix_sums(self.count.iter().map(|c| c.load(Relaxed))));
        // Every slot is written below (the assertion), so the buffer from two passes ago (at
        // least as long: faces only die) is cut to length rather than filled first.
        let len = self.first[self.count.len()] as usize;
        self.corners.truncate(len);
        self.corners.resize(len, INVALID);
        // Each task fills the rows of its run of vertices, a slice of its own, and lowers
        // their `gained` marks.
        let n = self.count.len();
        let mut tasks = Vec::with_capacity(n.div_ceil(ROW_TASK));
        let mut rest = self.corners.as_mut_slice();
        for (start, marks) in (0..n).step_by(ROW_TASK).zip(self.gained.chunks_mut(ROW_TASK)) {
            let end = (start + ROW_TASK).min(n);
            let (out, tail) = rest.split_at_mut((self.first[end] - self.first[start]) as usize);
            tasks.push((start..end, out, marks));
            rest = tail;
        }
        let (old_first, old_corners, dead) = (&self.old_first, &self.old_corners, &self.dead);
        let old_row = |v: u32| &old_corners[old_first[v as usize] as usize..old_first[v as usize + 1] as usize];
        let count = &self.count;
        tasks.into_par_iter().for_each(|(vertices, out, marks)| {
            let mut k = 0;
            let mut keep_live = |row: &[u32]| {
                for &c in row {
                    // Written unconditionally, kept by moving on: no branch per corner.
                    if let Some(slot) = out.get_mut(k) {
                        *slot = c;
                    }
                    k += usize::from(!dead[(c / 3) as usize].load(Relaxed));
                }
            };
            // A vertex collapsed in the pass has no row, though its old one lists live faces
            // (its target's now).
            for (v, mark) in vertices.zip(marks.iter_mut()) {
                let gained = std::mem::replace(mark, INVALID);
                if count[v].load(Relaxed) > 0 {
                    keep_live(old_row(v as u32));
                    if gained != INVALID {
                        keep_live(old_row(gained));
                    }
                }
            }
            assert_eq!(k, out.len(), "the rows hold every live face's corners once");
        });
    }

    /// The live face slots, ascending.
    pub fn live_faces(&self) -> Vec<u32> {
        (0..self.tris.len() as u32).into_par_iter().filter(|&f| !self.is_dead(f)).collect()
    }

    /// The corners of face slot `f`.
    pub fn tri(&self, f: u32) -> [u32; 3] {
        self.tris[f as usize].each_ref().map(|c| c.load(Relaxed))
    }

    /// Whether face slot `f` has been removed (or was never live).
    pub fn is_dead(&self, f: u32) -> bool {
        self.dead[f as usize].load(Relaxed)
    }

    /// The live faces around `v` (0 once it has been collapsed away).
    pub fn count(&self, v: u32) -> u32 {
        self.count[v as usize].load(Relaxed)
    }

    /// Vertex slots.
    pub fn vertex_count(&self) -> usize {
        self.count.len()
    }

    /// Whether the mesh's wedges are its vertices (no wedge list kept).
    pub fn identity_wedges(&self) -> bool {
        self.wedges.is_empty()
    }

    /// The wedges of face slot `f`'s corners (its corners for identity wedges).
    pub fn wedges_of(&self, f: u32) -> [u32; 3] {
        match self.wedges.get(f as usize) {
            Some(w) => w.each_ref().map(|c| c.load(Relaxed)),
            None => self.tri(f),
        }
    }

    /// `v`'s row: its corners, dead faces' included.
    fn row_corners(&self, v: u32) -> &[u32] {
        &self.corners[self.first[v as usize] as usize..self.first[v as usize + 1] as usize]
    }

    /// The live corners of `v`'s row as (face, corner, a, b): a follows v, b precedes it.
    fn live_corners(&self, v: u32) -> impl Iterator<Item = Corner> + '_ {
        self.row_corners(v).iter().filter(|&&c| !self.is_dead(c / 3)).map(|&c| {
            let (face, at) = (c / 3, (c % 3) as usize);
            let t = &self.tris[face as usize];
            Corner { face, at: at as u8, a: t[NEXT[at]].load(Relaxed), b: t[PREV[at]].load(Relaxed) }
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

    /// The vertex after `v` in each live face of its row (counter-clockwise): every
    /// neighbour of an interior vertex once.
    pub fn followers(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.row_corners(v)
            .iter()
            .filter(|&&c| !self.is_dead(c / 3))
            .map(|&c| self.tris[(c / 3) as usize][NEXT[(c % 3) as usize]].load(Relaxed))
    }

    /// [`FlatFaces::followers`] with the wedges at each face's corners `v` and the follower.
    pub fn follower_wedges(&self, v: u32) -> impl Iterator<Item = (u32, u32, u32)> + '_ {
        self.row_corners(v).iter().filter(|&&c| !self.is_dead(c / 3)).map(|&c| {
            let (face, at) = (c / 3, (c % 3) as usize);
            let next = NEXT[at];
            (self.tris[face as usize][next].load(Relaxed), self.wedge(face, at as u8), self.wedge(face, next as u8))
        })
    }

    /// The neighbours of `v` alone, as [`FlatFaces::fan`] lists them.
    pub fn ring(&self, v: u32, border: bool, out: &mut Vec<u32>) {
        out.clear();
        out.extend(self.followers(v));
        if border {
            // The one `b` that is no face's `a`.
            let open = self.live_corners(v).map(|c| c.b).find(|b| !out.contains(b));
            out.extend(open);
        }
    }

    /// The wedge at corner `at` of face `f` (the vertex itself for identity wedges).
    pub fn wedge(&self, f: u32, at: u8) -> u32 {
        match self.wedges.get(f as usize) {
            Some(w) => w[at as usize].load(Relaxed),
            None => self.tris[f as usize][at as usize].load(Relaxed),
        }
    }

    /// Collapses u into v, given u's current fan and the wedge map u → v through the faces
    /// on the edge: those faces die, u's other faces name v (and v's wedge). Returns the
    /// number of faces removed. v's row does not list the faces it gained until
    /// [`FlatFaces::rebuild_rows`]. Writes only the faces of u's fan and the counts of
    /// their corners.
    pub fn collapse(&self, u: u32, v: u32, fan: &Fan, map: [(u32, u32); 2]) -> usize {
        let add = |x: u32, d: i32| {
            let c = &self.count[x as usize];
            c.store(c.load(Relaxed).wrapping_add_signed(d), Relaxed);
        };
        let mut removed = 0;
        for c in &fan.corners {
            let f = c.face as usize;
            if c.a == v || c.b == v {
                self.dead[f].store(true, Relaxed);
                for x in self.tri(c.face) {
                    add(x, -1);
                }
                removed += 1;
            } else {
                self.tris[f][c.at as usize].store(v, Relaxed);
                add(v, 1);
                if let Some(w) = self.wedges.get(f) {
                    let w = &w[c.at as usize];
                    let old = w.load(Relaxed);
                    w.store(map.iter().find(|&&(from, _)| from == old).map_or(old, |&(_, to)| to), Relaxed);
                }
            }
        }
        self.count[u as usize].store(0, Relaxed);
        removed
    }

    /// The live faces of `v`'s row (exact once the rows are rebuilt).
    pub fn row(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.row_corners(v).iter().map(|&c| c / 3).filter(|&f| !self.is_dead(f))
    }
}
