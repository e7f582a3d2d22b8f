//! From a welded triangle soup to a manifold, consistently oriented face set.
//!
//! The passes, in order (each records what it changed as a [`Repair`]):
//! 1. drop index-degenerate faces (a welded vertex repeated) and, on request, zero-area ones;
//! 2. drop duplicate faces (same three vertices, either winding; the first one stays);
//! 3. orient: breadth-first over edges shared by exactly two faces, neighbours taken in
//!    face order, flipping faces so that neighbours agree; per component the majority
//!    winding wins; an edge that contradicts the tree (non-orientable) is cut;
//! 4. make manifold, repeated until nothing changes:
//!    - pair half-edges into twins: two opposite half-edges pair; on an edge with more than
//!      two faces, opposite half-edges pair greedily in face order and the rest become border;
//!    - split every vertex whose faces form several fans into one vertex per fan;
//!    - a vertex pair still joined by more than one unpaired half-edge (possible only in
//!      tangled fans) gets the later faces detached onto fresh vertices;
//! 5. drop vertices no face uses.
//!
//! Every choice depends on face order and geometry only, never on the input's vertex
//! numbering or winding. That makes repair idempotent across a write: the written file welds
//! back into the same defects, and the same faces are cut and split again.
//!
//! ```text
//!   bowtie at v:   \ /      two fans share v        \ /
//!                   v   ─────────────────────>       v    v'   (v' = copy of v)
//!                  / \                                    / \
//! ```

use rustc_hash::FxHashMap;

use super::weld::Work;
use super::{Location, Repair, RepairKind};
use crate::topology::{EdgeGroups, Topology, INVALID};

/// Counts taken from the input before repairs changed it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InputDefects {
    /// Edges shared by more than two faces (after dropping index-degenerate faces).
    pub non_manifold_edges: usize,
    /// Vertices that had to be split because their faces formed several fans.
    pub non_manifold_vertices: usize,
    /// Triangles with zero area but three distinct vertices (kept unless asked otherwise).
    pub zero_area_triangles: usize,
}

/// What one pass over the edge groups found.
struct Scan {
    non_manifold_edges: usize,
    duplicates: Option<Vec<bool>>,
    consistent: bool,
}

impl Work {
    fn retain_faces(&mut self, mut keep: impl FnMut(usize, &[u32; 3]) -> bool) {
        let mut j = 0;
        for i in 0..self.faces.len() {
            if keep(i, &self.faces[i]) {
                self.faces[j] = self.faces[i];
                self.corner_src[j] = self.corner_src[i];
                self.face_src[j] = self.face_src[i];
                j += 1;
            }
        }
        self.faces.truncate(j);
        self.corner_src.truncate(j);
        self.face_src.truncate(j);
    }

    fn face_area2(&self, f: &[u32; 3]) -> f64 {
        let p = f.map(|v| self.positions[v as usize].map(|c| c as f64));
        let u = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let w = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let c = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
        c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
    }

    /// Pass 1.
    pub fn drop_degenerate(&mut self, drop_zero_area: bool, repairs: &mut Vec<Repair>, defects: &mut InputDefects) {
        let mut deg = Repair::new(RepairKind::DroppedDegenerateFaces);
        let mut zero = Repair::new(RepairKind::DroppedZeroAreaFaces);
        let src = self.face_src.clone();
        let mut zero_count = 0;
        let areas: Vec<bool> = self.faces.iter().map(|f| self.face_area2(f) == 0.0).collect();
        self.retain_faces(|i, f| {
            if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
                deg.add(Location::Face(src[i]));
                return false;
            }
            if areas[i] {
                zero_count += 1;
                if drop_zero_area {
                    zero.add(Location::Face(src[i]));
                    return false;
                }
            }
            true
        });
        defects.zero_area_triangles = zero_count;
        deg.push_into(repairs);
        zero.push_into(repairs);
    }

    /// Passes 2 to 4 on one shared edge grouping (regrouped only when faces changed).
    /// Returns the twin of every half-edge, ready for [`Topology::from_twins`].
    pub fn repair_topology(&mut self, repairs: &mut Vec<Repair>, defects: &mut InputDefects) -> Vec<u32> {
        let mut groups = EdgeGroups::new(self.positions.len(), &self.faces);
        let mut scan = self.scan(&groups);
        defects.non_manifold_edges = scan.non_manifold_edges;
        if let Some(dup) = scan.duplicates.take() {
            self.drop_duplicates(&dup, repairs);
            groups = EdgeGroups::new(self.positions.len(), &self.faces);
            scan = self.scan(&groups);
        }
        if !scan.consistent && self.orient(&groups, repairs) {
            groups = EdgeGroups::new(self.positions.len(), &self.faces);
        }
        self.make_manifold(groups, repairs, defects)
    }

    /// One pass over the edge groups: non-manifold edges, duplicate faces (a duplicate shares
    /// an edge group with its original and has the same third vertex), and whether every
    /// shared edge already runs both ways.
    fn scan(&self, groups: &EdgeGroups) -> Scan {
        let mut out = Scan { non_manifold_edges: 0, duplicates: None, consistent: true };
        let third = |f: &[u32; 3], lo: u32, hi: u32| f[0] ^ f[1] ^ f[2] ^ lo ^ hi;
        groups.for_each(|lo, hi, hs| {
            if hs.len() < 2 {
                return;
            }
            out.non_manifold_edges += (hs.len() > 2) as usize;
            if hs.len() == 2 {
                out.consistent &= self.origin(hs[0]) != self.origin(hs[1]);
            }
            for i in 0..hs.len() {
                for j in i + 1..hs.len() {
                    let (f, g) = ((hs[i] / 3) as usize, (hs[j] / 3) as usize);
                    if third(&self.faces[f], lo, hi) == third(&self.faces[g], lo, hi) {
                        out.duplicates.get_or_insert_with(|| vec![false; self.faces.len()])[g.max(f)] = true;
                    }
                }
            }
        });
        out
    }

    /// Pass 2: drops the faces flagged as duplicates of an earlier one.
    fn drop_duplicates(&mut self, dup: &[bool], repairs: &mut Vec<Repair>) {
        let mut r = Repair::new(RepairKind::DroppedDuplicateFaces);
        for (i, _) in dup.iter().enumerate().filter(|(_, &d)| d) {
            r.add(Location::Face(self.face_src[i]));
        }
        self.retain_faces(|i, _| !dup[i]);
        r.push_into(repairs);
    }

    fn edge_loc(&self, h: u32) -> Location {
        let f = &self.corner_src[(h / 3) as usize];
        Location::Edge(f[(h % 3) as usize], f[((h % 3 + 1) % 3) as usize])
    }

    fn origin(&self, h: u32) -> u32 {
        self.faces[(h / 3) as usize][(h % 3) as usize]
    }

    fn flip(&mut self, f: usize) {
        self.faces[f].swap(1, 2);
        self.corner_src[f].swap(1, 2);
    }

    /// Pass 3. Returns whether any face was flipped.
    fn orient(&mut self, groups: &EdgeGroups, repairs: &mut Vec<Repair>) -> bool {
        let nf = self.faces.len();
        let mut adj = vec![INVALID; nf * 3];
        groups.for_each(|_, _, h| {
            if let [a, b] = *h {
                adj[a as usize] = b;
                adj[b as usize] = a;
            }
        });
        let mut flip = vec![u8::MAX; nf]; // MAX = unvisited, else 0/1
        let mut cut = Repair::new(RepairKind::CutNonOrientableEdges);
        let mut re = Repair::new(RepairKind::ReorientedFaces);
        let mut queue = Vec::new();
        let mut comp = Vec::new();
        for seed in 0..nf {
            if flip[seed] != u8::MAX {
                continue;
            }
            flip[seed] = 0;
            queue.clear();
            comp.clear();
            queue.push(seed as u32);
            let mut qi = 0;
            while qi < queue.len() {
                let f = queue[qi];
                qi += 1;
                comp.push(f);
                // Neighbours in face order, not corner order: a flip reorders the corners,
                // and the tree (so the cut edges) must not depend on the input's winding,
                // or a repaired mesh, written and read back, would be cut elsewhere.
                let mut hs = [3 * f, 3 * f + 1, 3 * f + 2];
                hs.sort_unstable_by_key(|&h| adj[h as usize]);
                for h in hs {
                    let g = adj[h as usize];
                    if g == INVALID {
                        continue;
                    }
                    let same_dir = (self.origin(h) == self.origin(g)) as u8;
                    let want = flip[f as usize] ^ same_dir;
                    let nb = (g / 3) as usize;
                    if flip[nb] == u8::MAX {
                        flip[nb] = want;
                        queue.push(nb as u32);
                    } else if flip[nb] != want {
                        cut.add(self.edge_loc(h));
                        adj[h as usize] = INVALID;
                        adj[g as usize] = INVALID;
                    }
                }
            }
            let flipped = comp.iter().filter(|&&f| flip[f as usize] == 1).count();
            let invert = flipped * 2 > comp.len();
            for &f in &comp {
                let fl = flip[f as usize] ^ invert as u8;
                flip[f as usize] = fl;
                if fl == 1 {
                    re.add(Location::Face(self.face_src[f as usize]));
                }
            }
        }
        for (f, &fl) in flip.iter().enumerate() {
            if fl == 1 {
                self.flip(f);
            }
        }
        let flipped = re.count > 0;
        re.push_into(repairs);
        cut.push_into(repairs);
        flipped
    }

    /// Pass 4: returns the final twins; leaves faces such that [`Topology::from_twins`]
    /// succeeds.
    fn make_manifold(
        &mut self,
        first_groups: EdgeGroups,
        repairs: &mut Vec<Repair>,
        defects: &mut InputDefects,
    ) -> Vec<u32> {
        let mut cut_nm = Repair::new(RepairKind::CutNonManifoldEdges);
        let mut split = Repair::new(RepairKind::SplitNonManifoldVertices);
        let mut detach = Repair::new(RepairKind::DetachedFaces);
        let mut groups = Some(first_groups);
        let mut split_seen: FxHashMap<u32, ()> = FxHashMap::default();
        let twin = loop {
            let first = groups.is_some();
            let g = groups.take().unwrap_or_else(|| EdgeGroups::new(self.positions.len(), &self.faces));
            let (twin, tangled) = self.pair_twins(&g, if first { Some(&mut cut_nm) } else { None });
            if self.split_fans(&twin, &mut split, &mut split_seen) {
                continue;
            }
            if tangled.is_empty() {
                break twin;
            }
            for f in tangled {
                detach.add(Location::Face(self.face_src[f as usize]));
                for c in 0..3 {
                    let v = self.faces[f as usize][c];
                    self.faces[f as usize][c] = self.positions.len() as u32;
                    self.positions.push(self.positions[v as usize]);
                    self.vertex_src.push(self.vertex_src[v as usize]);
                }
            }
        };
        defects.non_manifold_vertices = split.count;
        cut_nm.push_into(repairs);
        split.push_into(repairs);
        detach.push_into(repairs);
        twin
    }

    /// Twins per the pairing rule; also returns faces whose unpaired half-edges share their
    /// vertex pair with another half-edge (these need detaching if no split separates them).
    fn pair_twins(&self, groups: &EdgeGroups, mut cut: Option<&mut Repair>) -> (Vec<u32>, Vec<u32>) {
        let mut twin = vec![INVALID; self.faces.len() * 3];
        let mut tangled = Vec::new();
        groups.for_each(|_, _, hs| {
            match *hs {
                [_] => return,
                // The common case: a manifold edge, one half-edge each way.
                [a, b] if self.origin(a) != self.origin(b) => {
                    twin[a as usize] = b;
                    twin[b as usize] = a;
                    return;
                }
                _ => {}
            }
            if hs.len() > 2 {
                if let Some(r) = cut.as_deref_mut() {
                    r.add(self.edge_loc(hs[0]));
                }
            }
            // Pair opposite half-edges greedily in face order (the first 64 of a group).
            let n = hs.len().min(64);
            let mut paired = [false; 64];
            for i in 0..n {
                if paired[i] {
                    continue;
                }
                let oi = self.origin(hs[i]);
                if let Some(j) = (i + 1..n).find(|&j| !paired[j] && self.origin(hs[j]) != oi) {
                    paired[i] = true;
                    paired[j] = true;
                    twin[hs[i] as usize] = hs[j];
                    twin[hs[j] as usize] = hs[i];
                }
            }
            // One pair (or, with no pair, one lone half-edge) may keep the vertex pair; every
            // other face on it conflicts unless a vertex split separates them.
            let keep = match (0..n).find(|&i| paired[i]) {
                Some(i) => [hs[i], twin[hs[i] as usize]],
                None => [hs[0], INVALID],
            };
            tangled.extend(hs.iter().filter(|h| !keep.contains(h)).map(|h| h / 3));
        });
        tangled.sort_unstable();
        tangled.dedup();
        (twin, tangled)
    }

    /// Splits vertices whose corners form more than one fan. Corners are visited in face
    /// order; the first fan met at a vertex keeps it, each later fan gets a copy. Returns
    /// whether any vertex was split.
    fn split_fans(&mut self, twin: &[u32], rec: &mut Repair, seen: &mut FxHashMap<u32, ()>) -> bool {
        let nv = self.positions.len();
        let mut degree = vec![0u32; nv];
        for f in &self.faces {
            for &v in f {
                degree[v as usize] += 1;
            }
        }
        // First fan's first corner per vertex, to compare input vertices across fans.
        let mut first_fan = vec![INVALID; nv];
        let mut visited = vec![false; self.faces.len() * 3];
        let mut fan = Vec::new();
        let mut any = false;
        for h in 0..self.faces.len() as u32 * 3 {
            if visited[h as usize] {
                continue;
            }
            let v = self.origin(h) as usize;
            let bound = degree[v];
            let s = crate::topology::fan_start(twin, h, bound as usize);
            fan.clear();
            let mut cur = s;
            for _ in 0..bound {
                if visited[cur as usize] {
                    break;
                }
                visited[cur as usize] = true;
                fan.push(cur);
                let n = twin[Topology::prev(cur) as usize];
                if n == INVALID {
                    break;
                }
                cur = n;
            }
            if first_fan[v] == INVALID {
                first_fan[v] = h;
                continue;
            }
            any = true;
            let nid = self.positions.len() as u32;
            self.positions.push(self.positions[v]);
            self.vertex_src.push(self.vertex_src[v]);
            // A pinch that welding made (the fans come from different input vertices) is
            // undone silently: the file was manifold there. An input vertex shared by two
            // fans is a pinch in the file itself, and a repair.
            let src = |c: u32| self.corner_src[(c / 3) as usize][(c % 3) as usize];
            let kept = src(first_fan[v]);
            if let Some(&c) = fan.iter().find(|&&c| src(c) == kept) {
                if seen.insert(src(c), ()).is_none() {
                    rec.add(Location::Vertex(src(c)));
                }
            }
            for &c in &fan {
                self.faces[(c / 3) as usize][(c % 3) as usize] = nid;
            }
        }
        any
    }

    /// Pass 5: compacts away vertices no face uses, recording their input ids.
    pub fn drop_unreferenced(&mut self, repairs: &mut Vec<Repair>) {
        // Keep the welded (first-use-in-file) order, so a clean input keeps its vertex ids.
        let mut used = vec![INVALID; self.positions.len()];
        for f in &self.faces {
            for &v in f {
                used[v as usize] = 0;
            }
        }
        let mut next = 0u32;
        for u in used.iter_mut().filter(|u| **u == 0) {
            *u = next;
            next += 1;
        }
        let mut r = Repair::new(RepairKind::DroppedUnreferencedVertices);
        let mut positions = vec![[0.0; 3]; next as usize];
        let mut vertex_src = vec![0; next as usize];
        for (v, &u) in used.iter().enumerate() {
            if u == INVALID {
                r.add(Location::Vertex(self.vertex_src[v]));
            } else {
                positions[u as usize] = self.positions[v];
                vertex_src[u as usize] = self.vertex_src[v];
            }
        }
        for f in &mut self.faces {
            *f = f.map(|v| used[v as usize]);
        }
        self.positions = positions;
        self.vertex_src = vertex_src;
        r.push_into(repairs);
    }
}
