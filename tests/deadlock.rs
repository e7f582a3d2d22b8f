//! papers/000 §5 on a hand-built deadlocked ring.
//!
//! ```text
//!   o0 ... o5   border ring, radius 3, in R but no neighbour in S: not candidates
//!   r0 ... r5   the ring, radius 2, in R: six candidates, each next to two others
//!   s0 ... s5   locked (S), radius 1, turned 15° ahead of the ring
//!   c           locked (S), the centre
//! ```
//! Each r_i's only targets are s_{i-1} and s_i. Alone (test 1) either collapse is fine, but
//! the triangle (r_{i-1}, r_i, s_{i-1}) has two candidates, and its test-2 plane through
//! s_{i-1} parallel to r_{i-1}r_i cuts r_i off from s_i; (r_i, r_{i+1}, s_i) does the same to
//! s_{i-1}. So every candidate is blocked by its neighbours' boundaries: the ring is
//! deadlocked until §5 sets all but one aside.

use dynlod::lod::coarsen::{CoarsenOptions, Coarsener, RoundStats, Schedule};
use dynlod::simplify::lock_vertices;
use dynlod::topology::{vflag, INVALID};
use dynlod::{BuildOptions, IndexedMesh, Mesh};

mod common;
use common::facing;

const K: u32 = 6;

/// The ring mesh; `bump` lifts r2 off the plane (so its error e(V) tops its neighbours').
fn ring(bump: f32) -> (Mesh, [u32; 6]) {
    let at = |radius: f32, degrees: f32, z: f32| {
        let a = degrees.to_radians();
        [radius * a.cos(), radius * a.sin(), z]
    };
    let mut p = vec![[0.0, 0.0, 0.0]];
    let (s, r, o) = (|i: u32| 1 + i % K, |i: u32| 1 + K + i % K, |i: u32| 1 + 2 * K + i % K);
    p.extend((0..K).map(|i| at(1.0, 60.0 * i as f32 + 15.0, 0.0)));
    p.extend((0..K).map(|i| at(2.0, 60.0 * i as f32, if i == 2 { bump } else { 0.0 })));
    p.extend((0..K).map(|i| at(3.0, 60.0 * i as f32 + 30.0, 0.0)));
    let mut t = Vec::new();
    for i in 0..K {
        t.push([0, s(i), s(i + 1)]);
        t.push([r(i), r(i + 1), s(i)]); // two candidates: test 2 with s_i fixed
        t.push([s(i), r(i + 1), s(i + 1)]);
        t.push([r(i), o(i), r(i + 1)]);
        t.push([o(i), o(i + 1), r(i + 1)]);
    }
    let mut mesh = Mesh::build(&IndexedMesh::from_triangles(p, t), BuildOptions::default()).unwrap();
    mesh.topology.validate().unwrap();
    assert!(mesh.repairs.is_empty(), "{:?}", mesh.repairs);
    lock_vertices(&mut mesh, (0..=K).collect::<Vec<_>>());
    (mesh, std::array::from_fn(|i| r(i as u32)))
}

fn removed(m: &Mesh, v: u32) -> bool {
    m.topology.vflags[v as usize] & vflag::REMOVED != 0
}

/// One round, then the checks every round must pass: valid, nothing turned over.
fn step(mesh: &mut Mesh, c: &mut Coarsener) -> RoundStats {
    let r = c.round(mesh);
    mesh.topology.validate().unwrap();
    for f in mesh.topology.faces.iter().filter(|f| f[0] != INVALID) {
        assert!(facing(mesh, *f, [0.0, 0.0, 10.0]) > 0.0, "face {f:?} turned over");
    }
    r
}

/// Three rounds, then more until the ring is gone (at most 20 in all).
fn resolve(mesh: &mut Mesh, c: &mut Coarsener, ring: [u32; 6]) -> (Vec<RoundStats>, Vec<bool>) {
    let mut rounds: Vec<RoundStats> = (0..3).map(|_| step(mesh, c)).collect();
    let after_three = ring.iter().map(|&v| removed(mesh, v)).collect();
    while rounds.len() < 20 && !ring.iter().all(|&v| removed(mesh, v)) {
        rounds.push(step(mesh, c));
    }
    (rounds, after_three)
}

#[test]
fn a_flat_deadlocked_ring_is_resolved_by_setting_all_but_one_aside() {
    let (mut mesh, ring) = ring(0.0);
    let euler = mesh.topology.stats().euler;
    let opts = CoarsenOptions::default().threshold(0.5).anchors(None).schedule(Schedule::AllCandidates);
    let mut c = Coarsener::new(&mesh, &[], opts);
    for (v, &in_r) in c.remove_set().iter().enumerate() {
        assert_eq!(in_r, v > K as usize, "vertex {v}: only the two outer rings are in R");
    }
    let (rounds, after_three) = resolve(&mut mesh, &mut c, ring);
    // Rounds 1 and 2: the six ring vertices are candidates, each blocked by its neighbours
    // though free alone; round 2 sees no neighbour gone and sets five aside. All errors are
    // zero here, so the tie goes to the largest id: r5.
    for r in &rounds[..2] {
        assert_eq!((r.candidates, r.collapsed, r.blocked, r.stuck), (6, 0, 6, 0), "{rounds:?}");
    }
    assert_eq!((rounds[0].ignored, rounds[1].ignored), (0, 5), "{rounds:?}");
    // Round 3: r5 is the only candidate; with its neighbours set aside it is free.
    assert_eq!((rounds[2].candidates, rounds[2].collapsed), (1, 1), "{rounds:?}");
    assert_eq!(after_three, [false, false, false, false, false, true]);
    // The ignore flags lift around what changed and the rest of the ring follows.
    assert!(ring.iter().all(|&v| removed(&mesh, v)), "ring not resolved in {} rounds: {rounds:?}", rounds.len());
    assert_eq!(mesh.topology.stats().euler, euler);
}

#[test]
fn in_a_deadlock_the_vertex_with_the_largest_error_goes_first() {
    let (mut mesh, ring) = ring(0.02);
    let opts = CoarsenOptions::default().threshold(0.5).anchors(None).schedule(Schedule::AllCandidates);
    let mut c = Coarsener::new(&mesh, &[], opts);
    assert!(ring.iter().all(|&v| c.remove_set()[v as usize]));
    let (rounds, after_three) = resolve(&mut mesh, &mut c, ring);
    // r2 (lifted) tops r1 and r3; r5 still wins its zero-error tie with r4 and r0 by id.
    assert_eq!((rounds[1].candidates, rounds[1].blocked, rounds[1].ignored), (6, 6, 4), "{rounds:?}");
    assert_eq!((rounds[2].candidates, rounds[2].collapsed), (2, 2), "{rounds:?}");
    assert_eq!(after_three, [false, false, true, false, false, true]);
    assert!(ring.iter().all(|&v| removed(&mesh, v)), "ring not resolved in {} rounds: {rounds:?}", rounds.len());
}

/// The same ring under [`Schedule::LocalMinima`] (the default): neighbouring candidates take
/// turns instead of blocking each other. All errors are zero, so the order among the six is
/// the scrambled id: each round only candidates with no neighbouring candidate ahead act and
/// test 1 alone applies to them. Nothing is ever blocked by a neighbour, and the ring is gone
/// within six rounds. (Once a ring vertex has gone, the outer border vertices next to it
/// become candidates too: they are corners, cannot go even alone, and cost the ring vertices
/// waiting on them a round before they are set aside.)
#[test]
fn under_local_minima_the_ring_takes_turns_and_nothing_is_blocked() {
    let (mut mesh, ring) = ring(0.0);
    let euler = mesh.topology.stats().euler;
    let mut c = Coarsener::new(&mesh, &[], CoarsenOptions::default().threshold(0.5).anchors(None));
    let mut rounds = Vec::new();
    while rounds.len() < 6 && !ring.iter().all(|&v| removed(&mesh, v)) {
        let before: Vec<bool> = ring.iter().map(|&v| removed(&mesh, v)).collect();
        let r = step(&mut mesh, &mut c);
        let after: Vec<bool> = ring.iter().map(|&v| removed(&mesh, v)).collect();
        let now: Vec<bool> = (0..6).map(|i| after[i] && !before[i]).collect();
        // What went this round is an independent set of the ring: never two neighbours.
        assert!((0..6).all(|i| !(now[i] && now[(i + 1) % 6])), "neighbours went together: {now:?}");
        assert_eq!((r.blocked, r.deferred), (0, 0), "{r:?}");
        assert!(now.iter().any(|&x| x), "no ring vertex went: {r:?}");
        rounds.push(r);
    }
    assert_eq!(rounds[0].candidates, 6, "{rounds:?}");
    assert!(rounds[0].waiting >= 3, "{rounds:?}");
    assert!(ring.iter().all(|&v| removed(&mesh, v)), "ring not gone in 6 rounds: {rounds:?}");
    assert_eq!(mesh.topology.stats().euler, euler);
}
