//! The dynamic vertex hierarchy of papers/001: a record per collapsed vertex, written when the
//! collapse happens and consumed by the vertex split that undoes it, with per-face counters
//! that decide when a split is legal.
//!
//! ```text
//!   collapse u → v (record R, keyed by u; R.target = consumedBy(u) = v)
//!     touched(R) = the one or two removed faces, u's surviving faces (the "arc", now v's),
//!                  and the faces across the two wing edges (their twins are relinked)
//!     for f in touched(R):  below_R[f] = top[f];  top[f] = R;  counter[f] += 1
//!
//!   split R is legal  ⇔  top[f] == R for every f in touched(R)
//!                     ⇔  counter[f] still has the value R left on it (a stack per face)
//!   split R: restore every field R changed, then top[f] = below_R[f], counter[f] -= 1
//! ```
//!
//! papers/001 keeps one counter per edge and compares it with the value the collapse left;
//! we keep it per *face*, over every face the collapse edited (corners, twins,
//! wedges), which is the same test made exact: records that touch a face form a stack (a
//! collapse pushes, a legal split pops its own top), so "R is on top of all its faces" means
//! every field R wrote still holds the value R wrote, and the split is the exact inverse of the
//! collapse — same slots, same winding, same wedges. A split that is not on top waits until
//! the records above it are split first ("their own parents first"). `counter[f]` is the
//! length of the dependency chain through f, as papers/001 notes. Records on top of all their
//! faces form the *front*, maintained incrementally so a frame visits only the front.
//!
//! Files: `record.rs` (what a collapse keeps to be undone), `restore.rs` (the undo itself),
//! `check.rs` (the recount behind [`Hierarchy::check`]).

mod check;
mod record;
mod restore;

use bitvec::vec::BitVec;

use record::{touched_faces, Faces, EDGE_IS_VU};
pub use record::{CollapseRecord, Plan, Unrecordable, Unsplittable, MAX_ARC};
use restore::{restore, u_wedges};

use super::lazy_list::LazyList;
use crate::mesh::{constraints, Mesh};
use crate::topology::{on_removed_face, HalfEdgeCollapse, HalfEdges, Topology, INVALID};

/// The records, the per-face stacks and the front.
#[derive(Debug, Clone)]
pub struct Hierarchy {
    records: Vec<CollapseRecord>,
    /// (squared object-space error, radius) per vertex: for a collapsed vertex, what its
    /// collapse was charged (saturated over the records it buries; the radius around u holds
    /// every vertex they bury); for a live vertex, what collapsing it would be charged now,
    /// kept by the runtime ([`Hierarchy::set_charge`]). One array for both: a vertex is one or
    /// the other, so the records need no fields of their own for it (8 B per n saved).
    charges: Vec<[f32; 2]>,
    /// The record below on each touched face that had one, one slab per record, in the
    /// order of [`touched_faces`]. The faces themselves are walked from the record while it
    /// is on top (the only time a split needs them), not stored; nor is the record below a
    /// face the collapse found untouched (a stack's bottom entry), since a face with
    /// counter 1 under a record on top has nothing below it.
    arena: Vec<u32>,
    /// Auditing: every record's (face, record below) for each face it touched, bottoms
    /// included, so [`Hierarchy::check`] can recount buried records' stacks, compare the
    /// arena with them, and [`Hierarchy::touched`] can name a buried record's faces.
    audit: Option<Vec<Vec<(u32, u32)>>>,
    free_slabs: Vec<Vec<u32>>,
    top: Vec<u32>,
    counter: Vec<u16>,
    blocked: Vec<u16>,
    /// Records on top of all their faces (and, until a pass clears them, some that were).
    front: LazyList,
    depth_hist: Vec<u32>,
    changed: Vec<u32>,
    changed_mark: BitVec,
    exposed: Vec<u32>,
    active: usize,
}

impl Hierarchy {
    /// An empty hierarchy for a mesh with `vertices` vertex slots and `faces` face slots.
    /// `audit`: also keep every stack entry with its face (a list per vertex), so that
    /// [`Hierarchy::check`] recounts every stack and [`Hierarchy::touched`] answers for buried
    /// records too.
    pub fn new(vertices: usize, faces: usize, audit: bool) -> Self {
        Self {
            records: vec![CollapseRecord::default(); vertices],
            charges: vec![[0.0; 2]; vertices],
            arena: Vec::new(),
            audit: audit.then(|| vec![Vec::new(); vertices]),
            free_slabs: Vec::new(),
            top: vec![INVALID; faces],
            counter: vec![0; faces],
            blocked: vec![0; vertices],
            front: LazyList::new(vertices, Vec::new()),
            depth_hist: vec![faces as u32],
            changed: Vec::new(),
            changed_mark: BitVec::repeat(false, faces),
            exposed: Vec::new(),
            active: 0,
        }
    }

    /// The record of collapsed vertex `u` (`target == INVALID` when u is not collapsed).
    pub fn record(&self, u: u32) -> &CollapseRecord {
        &self.records[u as usize]
    }

    /// (squared error, radius) of vertex `u`: its collapse's charge if it is collapsed, else
    /// the charge last set with [`Hierarchy::set_charge`].
    #[inline]
    pub fn charge(&self, u: u32) -> [f32; 2] {
        self.charges[u as usize]
    }

    /// Sets live vertex `u`'s current charge (what collapsing it would cost).
    #[inline]
    pub fn set_charge(&mut self, u: u32, c: [f32; 2]) {
        debug_assert!(!self.is_collapsed(u), "vertex {u}: a collapsed vertex keeps its record's charge");
        self.charges[u as usize] = c;
    }

    /// Whether `u` is collapsed.
    pub fn is_collapsed(&self, u: u32) -> bool {
        self.records[u as usize].target != INVALID
    }

    /// Number of collapses not yet split back.
    pub fn active(&self) -> usize {
        self.active
    }

    /// Records that can be split now (on top of all their faces), in no particular order.
    pub fn front(&self) -> impl Iterator<Item = u32> + '_ {
        self.front.entries().iter().copied().filter(|&u| self.is_splittable(u))
    }

    /// How many records can be split now.
    pub fn front_len(&self) -> usize {
        self.front.len()
    }

    /// The front as kept: every record that can be split now, and maybe some that could
    /// until lately (at most an eighth of them and 64), which callers skip
    /// ([`Hierarchy::is_splittable`]). For walks that test each record anyway.
    pub(crate) fn front_entries(&self) -> &[u32] {
        self.front.entries()
    }

    /// Whether `u`'s split is legal now.
    pub fn is_splittable(&self, u: u32) -> bool {
        self.is_collapsed(u) && self.blocked[u as usize] == 0
    }

    /// papers/001's counter of face `f`: how many active collapses touched it, the length of
    /// the dependency chain through it.
    pub fn counter(&self, f: u32) -> u16 {
        self.counter[f as usize]
    }

    /// The latest active record that touched face `f`, or `INVALID`.
    pub fn top(&self, f: u32) -> u32 {
        self.top[f as usize]
    }

    /// The faces record `u` touched, in the order of its stack entries: for a record on top
    /// of all its faces (`t`: the mesh this hierarchy belongs to), and with auditing for any
    /// collapsed record. `None` when u is not collapsed, or buried without auditing.
    pub fn touched(&self, t: &Topology, u: u32) -> Option<Vec<u32>> {
        let r = &self.records[u as usize];
        if r.target == INVALID {
            None
        } else if let Some(audit) = &self.audit {
            Some(audit[u as usize].iter().map(|e| e.0).collect())
        } else {
            (self.blocked[u as usize] == 0).then(|| self.faces_on_top(t, u).collect())
        }
    }

    /// The faces of record `u`, which is on top of all of them: walked from the record (the
    /// removed faces, the two across the wing edges and the arc), which holds while nothing
    /// has edited them since the collapse.
    pub(super) fn faces_on_top<'a>(&'a self, t: &'a Topology, u: u32) -> impl Iterator<Item = u32> + 'a {
        let r = &self.records[u as usize];
        debug_assert!(r.target != INVALID && self.blocked[u as usize] == 0, "record {u} is not on top");
        let (hu, hv) = r.halves(t);
        touched_faces(t, hu, hv, r.arc_start, r.arc_len())
    }

    /// The longest dependency chain: the largest face counter.
    pub fn max_depth(&self) -> u16 {
        self.depth_hist.iter().rposition(|&c| c > 0).unwrap_or(0) as u16
    }

    /// Mean counter over faces with a non-zero counter (0 when there are none).
    pub fn mean_depth(&self) -> f64 {
        let (mut n, mut sum) = (0u64, 0u64);
        for (d, &c) in self.depth_hist.iter().enumerate().skip(1) {
            n += u64::from(c);
            sum += d as u64 * u64::from(c);
        }
        if n == 0 {
            0.0
        } else {
            sum as f64 / n as f64
        }
    }

    /// Chain depth of a front record: the largest counter among its faces (kept in the
    /// record; for a buried record, its depth when it is uncovered again).
    pub fn depth(&self, u: u32) -> u16 {
        self.records[u as usize].depth
    }

    /// Puts the faces edited since the last call, each once, in `out`, and takes `out`'s
    /// room for the next ones (a frame's lists trade buffers and allocate nothing).
    pub fn swap_changed(&mut self, out: &mut Vec<u32>) {
        for &f in &self.changed {
            self.changed_mark.set(f as usize, false);
        }
        out.clear();
        std::mem::swap(out, &mut self.changed);
    }

    /// Puts the records that reached the front through splits since the last call in `out`,
    /// and takes `out`'s room for the next ones.
    pub fn swap_exposed(&mut self, out: &mut Vec<u32>) {
        out.clear();
        std::mem::swap(out, &mut self.exposed);
    }

    /// The lists handed over by swapping ([`Hierarchy::swap_changed`],
    /// [`Hierarchy::swap_exposed`]): the runtime gives back the room a cold start or a cut
    /// grew in them with its own lists' (they trade buffers with them).
    pub(in crate::lod) fn swapped_lists(&mut self) -> [&mut Vec<u32>; 2] {
        [&mut self.changed, &mut self.exposed]
    }

    fn mark_changed(&mut self, f: u32) {
        if !self.changed_mark.replace(f as usize, true) {
            self.changed.push(f);
        }
    }

    /// Works out what collapse `c` will touch and how to undo it. The caller has checked
    /// topology ([`HalfEdges::collapse_is_legal`]), constraints and wedges.
    pub fn plan(&self, mesh: &Mesh, c: HalfEdgeCollapse) -> Result<Plan, Unrecordable> {
        let t = &mesh.topology;
        let u = c.remove;
        let v = t.collapse_target(c);
        let (hu, hv) = constraints::halves(t, c);
        // u's fan counter-clockwise starting at u→v (when that exists; a border fan already
        // starts at its border half-edge), without the faces on the edge. Walked again for
        // each question rather than listed: a plan allocates nothing (rebalancing makes dozens
        // a frame).
        let k = if hu != INVALID { t.outgoing(u).position(|g| g == hu).unwrap_or(0) } else { 0 };
        let arc = || t.outgoing(u).skip(k).chain(t.outgoing(u).take(k)).filter(|&g| !on_removed_face(g, (hu, hv)));
        let arc_len = arc().count();
        if arc_len > MAX_ARC {
            return Err(Unrecordable::Degree);
        }
        let [w1, w2] = u_wedges(mesh, hu, hv);
        let switch = arc().take_while(|&g| mesh.corner_wedge(g) == w1).count();
        if arc().skip(switch).any(|g| mesh.corner_wedge(g) != w2) {
            return Err(Unrecordable::Wedges);
        }
        let arc_start = arc().next().unwrap_or(INVALID);
        let touched = Faces::collect(touched_faces(t, hu, hv, arc_start, arc_len as u16));
        let faces = touched.as_slice();
        debug_assert!(
            faces.iter().enumerate().all(|(k, f)| !faces[..k].contains(f)),
            "record of {u}: a face listed twice"
        );
        if faces.iter().any(|&f| self.counter[f as usize] == u16::MAX) {
            return Err(Unrecordable::Depth);
        }
        let record = CollapseRecord {
            target: v,
            edge: if hu != INVALID { hu } else { hv },
            arc_start,
            arc: arc_len as u16 | if hu == INVALID { EDGE_IS_VU } else { 0 },
            wedge_switch: switch as u16,
            ..Default::default()
        };
        Ok(Plan { collapse: c, target: v, touched, record })
    }

    /// The records a collapse of `plan` would bury (the current tops of its faces).
    pub fn buried_by<'a>(&'a self, plan: &'a Plan) -> impl Iterator<Item = u32> + 'a {
        plan.touched().iter().map(|&f| self.top[f as usize]).filter(|&r| r != INVALID)
    }

    /// Performs a planned collapse on `mesh` and records it with its `error` and `radius`.
    /// Returns the removed faces.
    pub fn collapse(&mut self, mesh: &mut Mesh, plan: Plan, error: f32, radius: f32) -> [u32; 2] {
        let u = plan.collapse.remove;
        let removed = constraints::collapse_with_wedges(mesh, plan.collapse);
        let depth = plan.depth_after(self);
        let stored = plan.touched().iter().filter(|&&f| self.top[f as usize] != INVALID).count();
        let slab = self.alloc(stored);
        let mut k = slab as usize;
        if let Some(audit) = &mut self.audit {
            audit[u as usize] = plan.touched().iter().map(|&f| (f, self.top[f as usize])).collect();
        }
        for &f in plan.touched() {
            let below = self.top[f as usize];
            if below != INVALID {
                self.arena[k] = below;
                k += 1;
                self.block(below);
            }
            self.top[f as usize] = u;
            self.bump(f, 1);
            self.mark_changed(f);
        }
        self.records[u as usize] = CollapseRecord { slab, touched: plan.touched().len() as u16, depth, ..plan.record };
        self.charges[u as usize] = [error, radius];
        self.blocked[u as usize] = 0;
        self.front_add(u);
        self.active += 1;
        removed
    }

    /// Splits `u` back out of its target: the exact inverse of its collapse. Appends the faces
    /// it restored to `faces` (nothing on an error).
    pub fn split(&mut self, mesh: &mut Mesh, u: u32, faces: &mut Vec<u32>) -> Result<(), Unsplittable> {
        if !self.is_collapsed(u) {
            return Err(Unsplittable::NotCollapsed);
        }
        if self.blocked[u as usize] != 0 {
            return Err(Unsplittable::Buried);
        }
        let r = self.records[u as usize];
        // The faces are read before the restore edits them (the walk needs the collapsed state).
        let start = faces.len();
        faces.extend(self.faces_on_top(&mesh.topology, u));
        let faces = &faces[start..];
        debug_assert_eq!(faces.len(), r.touched as usize, "record {u}: faces walked and entries kept differ");
        restore(mesh, u, &r);
        let mut k = r.slab as usize;
        for &f in faces {
            // On top of f, u left its counter as it was: 1 where it found f untouched.
            let below = if self.counter[f as usize] > 1 {
                k += 1;
                self.arena[k - 1]
            } else {
                INVALID
            };
            debug_assert_eq!(self.top[f as usize], u);
            self.top[f as usize] = below;
            self.bump(f, -1);
            self.mark_changed(f);
            if below != INVALID {
                self.blocked[below as usize] -= 1;
                if self.blocked[below as usize] == 0 {
                    self.front_add(below);
                    self.exposed.push(below);
                }
            }
        }
        self.release(r.slab, k - r.slab as usize);
        if let Some(audit) = &mut self.audit {
            audit[u as usize] = Vec::new();
        }
        self.records[u as usize] = CollapseRecord::default();
        self.front_remove();
        self.active -= 1;
        Ok(())
    }
}

impl Hierarchy {
    fn block(&mut self, r: u32) {
        self.blocked[r as usize] += 1;
        if self.blocked[r as usize] == 1 {
            self.front_remove();
        }
    }

    fn bump(&mut self, f: u32, by: i32) {
        let old = self.counter[f as usize];
        let new = (i32::from(old) + by) as u16;
        self.counter[f as usize] = new;
        self.depth_hist[old as usize] -= 1;
        if self.depth_hist.len() <= new as usize {
            self.depth_hist.resize(new as usize + 1, 0);
        }
        self.depth_hist[new as usize] += 1;
    }

    /// A record that was not splittable now is (new, or uncovered).
    fn front_add(&mut self, u: u32) {
        self.front.insert(u);
    }

    /// A record that was splittable no longer is (split, or buried); its record and blocked
    /// count already say so.
    fn front_remove(&mut self) {
        // Taken out for the call, so the list's pass can ask `is_splittable` (no allocation).
        let mut front = std::mem::take(&mut self.front);
        front.remove(|u| self.is_splittable(u));
        self.front = front;
    }

    fn alloc(&mut self, len: usize) -> u32 {
        if len == 0 {
            return 0;
        }
        if let Some(s) = self.free_slabs.get_mut(len).and_then(Vec::pop) {
            return s;
        }
        let s = self.arena.len() as u32;
        grow_by_a_quarter(&mut self.arena, len);
        self.arena.resize(self.arena.len() + len, INVALID);
        s
    }

    fn release(&mut self, slab: u32, len: usize) {
        if len == 0 {
            return;
        }
        if self.free_slabs.len() <= len {
            self.free_slabs.resize(len + 1, Vec::new());
        }
        self.free_slabs[len].push(slab);
    }

    /// Bytes held, per structure: (name, bytes).
    pub fn memory(&self) -> Vec<(&'static str, usize)> {
        let slabs: usize = self.free_slabs.iter().map(|s| s.capacity() * 4).sum();
        vec![
            ("hierarchy.records", self.records.capacity() * std::mem::size_of::<CollapseRecord>()),
            ("hierarchy.charges", self.charges.capacity() * 8),
            ("hierarchy.arena", self.arena.capacity() * 4 + slabs),
            (
                "hierarchy.audit",
                self.audit.as_ref().map_or(0, |a| {
                    a.capacity() * std::mem::size_of::<Vec<(u32, u32)>>()
                        + a.iter().map(|e| e.capacity() * 8).sum::<usize>()
                }),
            ),
            ("hierarchy.top", self.top.capacity() * 4),
            ("hierarchy.counter", self.counter.capacity() * 2),
            ("hierarchy.blocked", self.blocked.capacity() * 2),
            ("hierarchy.front", self.front.bytes()),
            ("hierarchy.changed", self.changed.capacity() * 4 + self.changed_mark.capacity() / 8),
        ]
    }
}

/// Makes room for `more` entries, growing the capacity by a quarter instead of doubling it:
/// the arena is one of the largest structures and grows with the hierarchy, so doubling
/// would leave up to half of it reserved and unused (on the bunny orbit 7.7 B per n of
/// 30). Amortised pushes stay O(1).
fn grow_by_a_quarter(v: &mut Vec<u32>, more: usize) {
    let need = v.len() + more;
    if need > v.capacity() {
        let target = need.max(v.capacity() + v.capacity() / 4).max(1024);
        v.reserve_exact(target - v.len());
    }
}

#[cfg(test)]
mod tests {
    use super::{Hierarchy, Unrecordable, MAX_ARC};
    use crate::lod::RuntimeOptions;
    use crate::mesh::{IndexedMesh, Mesh};
    use crate::topology::{HalfEdgeCollapse, HalfEdges};

    /// A double cone: apexes 0 (up) and `k + 1` (down) over a ring of `k` vertices, so
    /// vertex 0 has `k` faces.
    fn fan(k: usize) -> Mesh {
        let ring = (0..k).map(|i| {
            let a = i as f32 / k as f32 * std::f32::consts::TAU;
            [a.cos(), a.sin(), 0.0]
        });
        let (k, down) = (k as u32, k as u32 + 1);
        let next = |i: u32| i % k + 1;
        let input = IndexedMesh {
            positions: std::iter::once([0.0, 0.0, 1.0]).chain(ring).chain([[0.0, 0.0, -1.0]]).collect(),
            triangles: (1..=k).flat_map(|i| [[0, i, next(i)], [down, next(i), i]]).collect(),
            ..Default::default()
        };
        Mesh::build(&input, Default::default()).unwrap()
    }

    /// The record counts u's surviving faces in 15 bits: a collapse leaving more is refused
    /// (not recorded with a count cut short), and one leaving exactly that many splits back
    /// to the same mesh. (`collapse_is_legal` caps u's valence far below this; `plan` guards
    /// the record's packing whatever its caller checked.)
    #[test]
    fn a_vertex_of_too_high_degree_is_not_recorded() {
        for (k, fits) in [(MAX_ARC + 2, true), (MAX_ARC + 3, false)] {
            let mut mesh = fan(k);
            let before = mesh.clone();
            let t = &mesh.topology;
            let he = t.outgoing(0).find(|&g| t.dest(g) == 2).unwrap();
            let mut h = Hierarchy::new(t.vertex_count(), t.face_slots(), true);
            let plan = h.plan(&mesh, HalfEdgeCollapse { he, remove: 0 });
            if !fits {
                assert_eq!(plan.err(), Some(Unrecordable::Degree), "{k} faces");
                continue;
            }
            let plan = plan.unwrap();
            assert_eq!(plan.touched().len(), k + 2, "the arc, the removed faces, two across the wings");
            h.collapse(&mut mesh, plan, 0.0, 0.0);
            assert_eq!(h.record(0).arc_len() as usize, MAX_ARC);
            h.check(&mesh.topology).unwrap();
            h.split(&mut mesh, 0, &mut Vec::new()).unwrap();
            // Exact but for which outgoing half-edge each vertex stores (as everywhere).
            let mut before = before;
            before.topology.rebuild_vertex_links();
            mesh.topology.rebuild_vertex_links();
            assert!(mesh == before, "{k} faces: not restored");
        }
    }

    /// `check` catches a wrong counter, a wrong top, a wrong blocked count and a wrong record
    /// below in the arena, with the audit and without it (where buried records are checked
    /// through sums).
    #[test]
    fn check_names_a_tampered_stack_with_and_without_the_audit() {
        for audit in [false, true] {
            let rt = crate::test_bunny_runtime(RuntimeOptions::default().audit(audit), 10, (1280, 720));
            let (h, t) = (&rt.hierarchy, &rt.mesh.topology);
            h.check(t).unwrap();
            // A face two records deep (a stack with a buried entry).
            let f = (0..h.counter.len()).find(|&f| h.counter[f] >= 2).expect("a face two records deep");
            let mut bad = h.clone();
            bad.counter[f] += 1;
            assert!(bad.check(t).is_err(), "audit {audit}: counter");
            let mut bad = h.clone();
            let below = (0..h.records.len() as u32).find(|&u| h.is_collapsed(u) && !h.is_splittable(u)).unwrap();
            bad.blocked[below as usize] += 1;
            assert!(bad.check(t).is_err(), "audit {audit}: blocked");
            let mut bad = h.clone();
            let other = h.front().next().unwrap();
            let f = (0..h.top.len()).find(|&f| h.top[f] != crate::topology::INVALID && h.top[f] != other).unwrap();
            bad.top[f] = other;
            assert!(bad.check(t).is_err(), "audit {audit}: top");
            // A front record's kept record below, replaced by another front record (which
            // nothing blocks, so it cannot be below anything).
            let mut bad = h.clone();
            let u = h.front().find(|&u| h.faces_on_top(t, u).any(|f| h.counter[f as usize] > 1)).unwrap();
            let other = h.front().find(|&o| o != u).unwrap();
            bad.arena[h.records[u as usize].slab as usize] = other;
            assert!(bad.check(t).is_err(), "audit {audit}: arena");
        }
    }
}
