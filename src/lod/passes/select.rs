//! Choosing a half-edge collapse for one removal candidate, papers/000 §4.4 and the second
//! result of §5. Pure: it reads the mesh state of the round and writes nothing, so every
//! candidate of a round can be evaluated in parallel.
//!
//! ```text
//!   planes = ⋃ boundaries of V_R's triangles (tests 1–3, by how many candidates each has)
//!   valid(N) = N ∈ S, the collapse V_R → N is topologically legal on its own,
//!              and the edge V_R–N crosses no plane
//!   choose the valid N with the least quadric error Q_R(N), Q_R from V_R's current faces
//! ```
//! When nothing is valid, the same check is repeated with test-1 planes only (every other
//! candidate treated as staying): if that allows a collapse, V_R is blocked by its neighbours
//! and stays a candidate (deadlock handling, §5); if not, V_R cannot be removed.

use super::boundaries::{face_normal, triangle_planes_into, Plane, Test};
use crate::mesh::{constraints, Mesh};
use crate::simplify::Quadric;
use crate::topology::{HalfEdgeCollapse, HalfEdges, Topology, INVALID};
use crate::view::Viewpoint;
use bitvec::vec::BitVec;
use glam::DVec3;

/// What a candidate decided this round.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Selection {
    /// Collapse into `target`: of the valid targets, the one with the least Q_R.
    Collapse {
        /// The collapse.
        collapse: HalfEdgeCollapse,
        /// The vertex V_R merges into.
        target: u32,
    },
    /// No valid target this round. `alone` says whether one would be valid if no neighbour
    /// were removed in parallel (the test-1-only result of §5).
    Blocked {
        /// Whether test 1 alone allows some collapse.
        alone: bool,
    },
}

/// The `candidate` set of a vertex that moves alone this round (no other vertex is a
/// candidate): a local-minima actor, since none of its neighbours acts in its round.
pub const NOBODY_ELSE: &[bool] = &[];

/// Which vertices a candidate may collapse into: S (`class[v]`), and besides, under nested
/// anchors (anchors.rs, [`AnchorOptions::nested`](super::anchors::AnchorOptions::nested)),
/// an anchor whose floor is above the candidate's own, though it leaves later itself. A far
/// view removes the finer anchors too, and with only the few that always stay for targets
/// the rounds stall (one cold frame left a distant bunny at 46,905 triangles); so each
/// anchor takes the removals finer than itself first, then goes into a coarser one, as
/// moving away frame by frame does.
#[derive(Debug, Clone, Copy)]
pub struct Stays<'a> {
    /// S.
    pub class: &'a [bool],
    /// The anchors' error floors (none: S alone).
    pub floors: Option<&'a Floors>,
}

/// The anchors' error floors (papers/000 §3) by vertex id: a sorted list, searched only for
/// the few vertices a bit per vertex marks as listed (a charge and a selection ask for every
/// vertex they look at, and most are no anchor: the searches took 4 % of a cold start).
#[derive(Debug, Clone, Default)]
pub struct Floors {
    list: Vec<(u32, f32)>,
    listed: BitVec,
}

impl Floors {
    /// The floors of `list` (ascending vertex ids, each once) on a mesh of `vertices` vertex ids.
    pub fn new(list: Vec<(u32, f32)>, vertices: usize) -> Self {
        debug_assert!(list.windows(2).all(|w| w[0].0 < w[1].0), "floors by ascending vertex id");
        let mut listed = BitVec::repeat(false, if list.is_empty() { 0 } else { vertices });
        for &(v, _) in &list {
            listed.set(v as usize, true);
        }
        Self { list, listed }
    }

    /// The floor of `v`, 0 when it has none.
    #[inline]
    pub fn get(&self, v: u32) -> f32 {
        if !self.listed.get(v as usize).is_some_and(|b| *b) {
            return 0.0;
        }
        self.list.binary_search_by_key(&v, |e| e.0).map_or(0.0, |k| self.list[k].1)
    }

    /// Whether no vertex has a floor.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.list.capacity() * 8 + self.listed.capacity() / 8
    }
}

impl Stays<'_> {
    /// The anchor floor of `v`, 0 when it has none.
    pub fn floor(&self, v: u32) -> f32 {
        self.floors.map_or(0.0, |f| f.get(v))
    }

    /// Whether `from` may collapse into its neighbour `n`: n is in S, or an anchor with a
    /// higher floor than `from`'s.
    pub fn takes(&self, from: u32, n: u32) -> bool {
        self.taken_from(from)(n)
    }

    /// [`Stays::takes`] for one removal `from` and any neighbour, its floor looked up once
    /// (and only where a neighbour is not in S).
    pub fn taken_from(&self, from: u32) -> impl Fn(u32) -> bool + '_ {
        let from_floor = std::cell::OnceCell::new();
        let anchors = self.floors.is_some_and(|f| !f.is_empty());
        move |n| self.class[n as usize] || (anchors && self.floor(n) > *from_floor.get_or_init(|| self.floor(from)))
    }
}

impl<'a> From<&'a [bool]> for Stays<'a> {
    /// S alone.
    fn from(class: &'a [bool]) -> Self {
        Stays { class, floors: None }
    }
}

impl<'a> From<&'a Vec<bool>> for Stays<'a> {
    /// S alone.
    fn from(class: &'a Vec<bool>) -> Self {
        Stays { class, floors: None }
    }
}

fn p64(p: [f32; 3]) -> [f64; 3] {
    p.map(f64::from)
}

/// Buffers one thread reuses from candidate to candidate, so a round allocates nothing per
/// selection (`rayon`'s `map_init` gives each worker its own).
#[derive(Debug, Default)]
pub struct SelectScratch {
    fan: Vec<u32>,
    allowed: Vec<(u32, u32)>,
    planes: Vec<Bound>,
    faces: Vec<(DVec3, [f64; 3])>,
    targets: Vec<(u32, u32)>,
    passing: Vec<(f64, u32, HalfEdgeCollapse)>,
    refused: Vec<(u32, HalfEdgeCollapse)>,
}

thread_local! {
    /// This thread's [`SelectScratch`] for [`with_thread_scratch`].
    static THREAD_SCRATCH: std::cell::RefCell<SelectScratch> = std::cell::RefCell::default();
}

/// Runs `f` with this thread's own [`SelectScratch`]: for a pass run again and again on the
/// same threads (the runtime's rounds, frame after frame), whose per-task scratch would be
/// allocated anew each time. `f` must not call this again (it would find the scratch taken).
pub fn with_thread_scratch<R>(f: impl FnOnce(&mut SelectScratch) -> R) -> R {
    THREAD_SCRATCH.with_borrow_mut(f)
}

/// Selects the collapse of candidate `vr` on a mesh, honouring its borders, seams, corners and
/// wedges ([`constraints`]) besides the boundaries. See [`select`] for the arguments.
pub fn select_on_mesh<'a>(
    m: &Mesh,
    vr: u32,
    candidate: &[bool],
    stays: impl Into<Stays<'a>>,
    eyes: &[Viewpoint],
) -> Selection {
    select_on_mesh_with(&mut SelectScratch::default(), m, vr, candidate, stays.into(), eyes)
}

/// [`select_on_mesh`] with caller-owned buffers.
pub fn select_on_mesh_with(
    sc: &mut SelectScratch,
    m: &Mesh,
    vr: u32,
    candidate: &[bool],
    stays: Stays<'_>,
    eyes: &[Viewpoint],
) -> Selection {
    let (mut fan, mut allowed) = (std::mem::take(&mut sc.fan), std::mem::take(&mut sc.allowed));
    fan.clear();
    fan.extend(m.topology.outgoing(vr));
    constraints::movable_targets(m, vr, &fan, constraints::BORDER_CORNER_DEGREES, &mut allowed);
    let result = if allowed.is_empty() {
        // Nothing may move here whatever the neighbours do (a corner, a junction, a locked
        // vertex): the same answer the full check would give, without building planes.
        Selection::Blocked { alone: false }
    } else {
        let ok = |c: HalfEdgeCollapse| {
            let (hu, hv) = constraints::halves(&m.topology, c);
            allowed.iter().any(|&(g, _)| g == c.he) && constraints::wedges_carry_over(m, &fan, hu, hv)
        };
        select_filtered(sc, &m.topology, &m.positions, vr, &fan, candidate, stays, eyes, &ok)
    };
    (sc.fan, sc.allowed) = (fan, allowed);
    result
}

/// Selects the collapse of candidate `vr`. `candidate[v]`: v is a removal candidate this
/// round ([`NOBODY_ELSE`], empty: no other vertex moves); `stays`: which vertices are valid
/// target). `eyes`: where the cameras see from ([`crate::view::View::viewpoint`]); a target
/// must pass every eye's planes, so that no triangle turns against any of the views (none:
/// view-independent boundaries).
pub fn select<'a>(
    t: &Topology,
    positions: &[[f32; 3]],
    vr: u32,
    candidate: &[bool],
    stays: impl Into<Stays<'a>>,
    eyes: &[Viewpoint],
) -> Selection {
    let fan: Vec<u32> = t.outgoing(vr).collect();
    select_filtered(&mut SelectScratch::default(), t, positions, vr, &fan, candidate, stays.into(), eyes, &|_| true)
}

/// [`select_with_eyes`] for any number of eyes, with no eye and one eye (every view-
/// independent or one-camera selection) on their own code paths, as fast as before several
/// eyes were possible (a loop over a slice cost the runtime's cold start 2 % more).
#[allow(clippy::too_many_arguments)]
fn select_filtered(
    sc: &mut SelectScratch,
    t: &Topology,
    positions: &[[f32; 3]],
    vr: u32,
    fan: &[u32],
    candidate: &[bool],
    stays: Stays<'_>,
    eyes: &[Viewpoint],
    allowed: &dyn Fn(HalfEdgeCollapse) -> bool,
) -> Selection {
    match eyes {
        [] => select_with_eyes(sc, t, positions, vr, fan, candidate, stays, None, allowed),
        [eye] => select_with_eyes(sc, t, positions, vr, fan, candidate, stays, Some(*eye), allowed),
        _ => select_with_eyes(sc, t, positions, vr, fan, candidate, stays, eyes, allowed),
    }
}

/// Where selection sees from: no eye, one, or several. A target must pass every eye's planes.
trait Eyes: Copy {
    /// Runs `planes` for each eye (once with `None` where there is none, for view-independent
    /// planes). Which test built them depends only on the candidates, so every eye returns
    /// the same one.
    fn each(self, planes: impl FnMut(Option<Viewpoint>) -> Test) -> Test;
}

impl Eyes for Option<Viewpoint> {
    #[inline(always)]
    fn each(self, mut planes: impl FnMut(Option<Viewpoint>) -> Test) -> Test {
        planes(self)
    }
}

impl Eyes for &[Viewpoint] {
    fn each(self, mut planes: impl FnMut(Option<Viewpoint>) -> Test) -> Test {
        self.iter().fold(Test::One, |_, &eye| planes(Some(eye)))
    }
}

#[allow(clippy::too_many_arguments)]
fn select_with_eyes(
    sc: &mut SelectScratch,
    t: &Topology,
    positions: &[[f32; 3]],
    vr: u32,
    fan: &[u32],
    candidate: &[bool],
    stays: Stays<'_>,
    eyes: impl Eyes,
    allowed: &dyn Fn(HalfEdgeCollapse) -> bool,
) -> Selection {
    let a = p64(positions[vr as usize]);
    // Each plane with the other two corners of its triangle: a triangle holding the target N
    // is one of the faces the collapse removes, so its planes do not apply to that target
    // (and N itself lies on them, where rounding could read a crossing).
    let (planes, faces) = (&mut sc.planes, &mut sc.faces);
    planes.clear();
    faces.clear();
    // Whether some triangle had another candidate among its corners (a plane of test 2 or 3).
    let mut shared = false;
    for &g in fan {
        let f = t.faces[(g / 3) as usize];
        let r = (g % 3) as usize;
        let tri = f.map(|v| p64(positions[v as usize]));
        let flags = f.map(|v| v == vr || (!candidate.is_empty() && candidate[v as usize]));
        let others = [f[(r + 1) % 3], f[(r + 2) % 3]];
        let normal = face_normal(tri);
        let test = eyes.each(|eye| {
            triangle_planes_into(tri, normal, flags, r, eye, &mut |p| planes.push(Bound::new(p, a, others)))
        });
        shared |= test != Test::One;
        faces.push((normal, tri[0]));
    }
    // Targets: every outgoing edge's end, and on a border the incoming border edge's start.
    let targets = &mut sc.targets;
    targets.clear();
    targets.extend(fan.iter().map(|&g| (g, t.dest(g))));
    if let Some(&last) = fan.last() {
        let inc = Topology::prev(last);
        if t.twin[inc as usize] == INVALID {
            targets.push((inc, t.origin(inc)));
        }
    }
    // Geometry and cost first (cheap); the topological checks run lazily, cheapest target
    // first, so the result equals checking everything but costs a fraction.
    let (passing, refused) = (&mut sc.passing, &mut sc.refused);
    passing.clear();
    refused.clear();
    let takes = stays.taken_from(vr);
    for &(g, n) in targets.iter() {
        if !takes(n) {
            continue;
        }
        let c = HalfEdgeCollapse { he: g, remove: vr };
        let b = p64(positions[n as usize]);
        if crosses_any(planes, n, b) {
            refused.push((n, c));
            continue;
        }
        passing.push((0.0, n, c));
    }
    // Q_R only ranks: with one target past the planes (most selections) it is not built.
    if passing.len() > 1 {
        let quadric = face_quadric(faces);
        for x in passing.iter_mut() {
            x.0 = quadric.eval(p64(positions[x.1 as usize]));
        }
        passing.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    }
    let legal = |c: HalfEdgeCollapse| t.collapse_is_legal(c).is_ok() && allowed(c);
    let best = passing.iter().copied().find(|&(_, _, c)| legal(c));
    // "alone" only matters when nothing passed; then every target that cleared the full planes
    // was illegal, so only the targets the full planes refused can make "alone" true, checked
    // against test-1 planes built only now (most candidates never need them). Where every
    // triangle already had test 1 (no other candidate in it: always, under local minima) those
    // are the planes that refused them, and the answer is no.
    let alone = best.is_some()
        || shared && {
            planes.clear();
            for &g in fan {
                let f = t.faces[(g / 3) as usize];
                let r = (g % 3) as usize;
                let mut only = [false; 3];
                only[r] = true;
                let others = [f[(r + 1) % 3], f[(r + 2) % 3]];
                let tri = f.map(|v| p64(positions[v as usize]));
                let normal = face_normal(tri);
                eyes.each(|eye| {
                    triangle_planes_into(tri, normal, only, r, eye, &mut |p| planes.push(Bound::new(p, a, others)))
                });
            }
            refused.iter().any(|&(n, c)| !crosses_any(planes, n, p64(positions[n as usize])) && legal(c))
        };
    match best {
        Some((_, target, collapse)) => Selection::Collapse { collapse, target },
        None => Selection::Blocked { alone },
    }
}

/// Q_R: the area-weighted planes of V_R's faces, from each face's [`face_normal`] and a
/// corner.
fn face_quadric(faces: &[(DVec3, [f64; 3])]) -> Quadric {
    let mut quadric = Quadric::default();
    for &(normal, p) in faces {
        let len = normal.length();
        if len > 0.0 {
            let unit = (normal / len).to_array();
            quadric += Quadric::plane(unit, -(unit[0] * p[0] + unit[1] * p[1] + unit[2] * p[2]), 0.5 * len);
        }
    }
    quadric
}

/// A boundary plane with what every target's test against it shares: the side V_R is on, and
/// the two other corners of the triangle that built it.
#[derive(Debug, Clone, Copy)]
struct Bound {
    plane: Plane,
    /// The sign of V_R's side (`Plane::side`), 0 when V_R lies on the plane (no side to keep).
    sign: f64,
    others: [u32; 2],
}

impl Bound {
    fn new(plane: Plane, a: [f64; 3], others: [u32; 2]) -> Self {
        let sa = plane.side(a);
        Self { plane, sign: if sa != 0.0 { sa.signum() } else { 0.0 }, others }
    }

    /// [`Plane::leaves_side`] from V_R to `b`, whose |b|∞ is `b_mag`.
    fn left_by(&self, b: [f64; 3], b_mag: f64) -> bool {
        self.sign != 0.0 && self.plane.side(b) * self.sign <= self.plane.tolerance_at(b_mag)
    }
}

/// Whether the move from V_R to target `n` (at `b`) leaves V_R's side of a plane of a
/// triangle that does not hold `n` (those holding it vanish with the collapse).
fn crosses_any(planes: &[Bound], n: u32, b: [f64; 3]) -> bool {
    let b_mag = glam::DVec3::from(b).abs().max_element();
    planes.iter().any(|p| !p.others.contains(&n) && p.left_by(b, b_mag))
}
