//! The half-edge collapse on the connectivity: legality rules and invariants after every step.

use dynlod::topology::{
    Gained, HalfEdgeCollapse, HalfEdges, HalfEdgesMut, Illegal, Parts, RoundTouches, Topology, INVALID,
};
use dynlod::{procedural, BuildOptions, IndexedMesh, Mesh};
use proptest::prelude::*;

mod common;

fn topo(m: &IndexedMesh) -> Topology {
    Mesh::build(m, BuildOptions::default()).unwrap().topology
}

fn all_collapses(t: &Topology) -> Vec<HalfEdgeCollapse> {
    let mut out = Vec::new();
    for h in 0..t.twin.len() as u32 {
        if t.is_face_live(h / 3) {
            out.push(HalfEdgeCollapse { he: h, remove: t.origin(h) });
            if t.twin[h as usize] == INVALID {
                out.push(HalfEdgeCollapse { he: h, remove: t.dest(h) });
            }
        }
    }
    out
}

#[test]
fn a_tetrahedron_cannot_lose_a_vertex() {
    let t = topo(&procedural::tetrahedron());
    assert!(all_collapses(&t).iter().all(|&c| t.collapse_is_legal(c) == Err(Illegal::Wing)));
}

#[test]
fn a_single_triangle_cannot_collapse() {
    let t = topo(&IndexedMesh::from_triangles(vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![[0, 1, 2]]));
    assert!(all_collapses(&t).iter().all(|&c| t.collapse_is_legal(c).is_err()));
}

#[test]
fn octahedron_collapses_to_a_bipyramid() {
    let mut t = topo(&procedural::octahedron());
    let c = HalfEdgeCollapse { he: 0, remove: t.origin(0) };
    assert_eq!(t.collapse_is_legal(c), Ok(()));
    let v = t.collapse_target(c);
    let removed = t.collapse(c);
    assert!(removed.iter().all(|&f| f != INVALID));
    t.validate().unwrap();
    let s = t.stats();
    assert_eq!((s.vertices, s.edges, s.faces, s.genus), (5, 9, 6, Some(0)));
    assert_eq!(t.valence(v), 4);
}

#[test]
fn interior_vertex_may_not_slide_onto_a_border_edge_and_border_vertex_stays_on_border() {
    let t = topo(&procedural::grid(3, 3, |_, _| false));
    for c in all_collapses(&t) {
        let on_border = t.twin[c.he as usize] == INVALID;
        if t.is_boundary_vertex(c.remove) && !on_border {
            assert_eq!(t.collapse_is_legal(c), Err(Illegal::Border));
        }
    }
}

#[test]
fn link_condition_refuses_a_collapse_that_would_pinch() {
    // A strip of three triangles (0,1,2), (1,3,2), (2,3,4) plus (0,2,4)... a fan where 0 and 3
    // share neighbours 2 only through non-wing faces: the fan around 2 is closed by 0-4.
    let p = vec![[0., 0., 0.], [1., 0., 0.], [0.5, 1., 0.], [1.5, 1., 0.], [0.5, 2., 0.], [-0.5, 1., 0.]];
    let t = [[0, 1, 2], [1, 3, 2], [2, 3, 4], [2, 4, 5], [0, 2, 5]];
    let top = topo(&IndexedMesh::from_triangles(p, t.to_vec()));
    // Collapsing border vertex 1 into 5 is not even an edge; collapsing 0 into 4 neither.
    // Collapse 1 -> 3 along the border: common neighbours of 1 and 3 are {2}: the wing. Legal.
    let h = (0..top.twin.len() as u32)
        .find(|&h| top.origin(h) == 3 && top.dest(h) == 1 || top.origin(h) == 1 && top.dest(h) == 3)
        .unwrap();
    assert_eq!(top.collapse_is_legal(HalfEdgeCollapse { he: h, remove: 1 }), Ok(()));
}

fn surfaces() -> impl Strategy<Value = IndexedMesh> {
    prop_oneof![
        (3usize..9, 3usize..9).prop_map(|(r, s)| procedural::torus(r, s)),
        (2usize..7, 2usize..7, any::<u64>())
            .prop_map(|(w, h, bits)| procedural::grid(w, h, move |i, j| bits >> ((i * 7 + j) % 64) & 1 == 1)),
        (3usize..8, 4usize..9).prop_map(|(a, b)| procedural::uv_sphere(a, b)),
        // Poles of valence 17-25: more corners than a `CollapseWrites` lists.
        (3usize..6, 17usize..26).prop_map(|(a, b)| procedural::uv_sphere(a, b)),
        Just(procedural::octahedron()),
    ]
}

/// u's closed neighbourhood N[u].
fn closed_ring(t: &Topology, u: u32) -> Vec<u32> {
    t.neighbors(u).chain([u]).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(200), ..ProptestConfig::default() })]

    #[test]
    fn legal_collapses_keep_every_invariant(m in surfaces(), picks in prop::collection::vec(any::<u32>(), 1..200)) {
        let mut t = topo(&m);
        let before = t.stats();
        for pick in picks {
            let legal: Vec<_> = all_collapses(&t).into_iter().filter(|&c| t.collapse_is_legal(c).is_ok()).collect();
            if legal.is_empty() {
                break;
            }
            let c = legal[pick as usize % legal.len()];
            let faces_before = t.live_face_count();
            let removed = t.collapse(c);
            prop_assert_eq!(t.validate(), Ok(()));
            let s = t.stats();
            prop_assert_eq!(s.euler, before.euler);
            prop_assert_eq!(s.genus, before.genus);
            prop_assert_eq!(s.boundary_loops, before.boundary_loops);
            prop_assert_eq!(s.components.len(), before.components.len());
            prop_assert_eq!(t.live_face_count(), faces_before - removed.iter().filter(|&&f| f != INVALID).count());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(200), ..ProptestConfig::default() })]

    /// The stores of a collapse, worked out before another collapse whose closed
    /// neighbourhood is disjoint from its own, are still its stores after it, and making them
    /// then leaves a valid mesh (what lets qem-batch work out a pass's stores in parallel).
    #[test]
    fn stores_worked_out_early_survive_a_collapse_elsewhere(
        m in surfaces(),
        picks in prop::collection::vec((any::<u32>(), any::<u32>()), 1..40),
    ) {
        let mut t = topo(&m);
        for (p1, p2) in picks {
            let legal: Vec<_> = all_collapses(&t).into_iter().filter(|&c| t.collapse_is_legal(c).is_ok()).collect();
            if legal.is_empty() {
                break;
            }
            let first = legal[p1 as usize % legal.len()];
            let ring = closed_ring(&t, first.remove);
            let apart: Vec<_> = legal
                .iter()
                .copied()
                .filter(|c| !closed_ring(&t, c.remove).iter().any(|w| ring.contains(w)))
                .collect();
            if apart.is_empty() {
                t.collapse(first);
                continue;
            }
            let second = apart[p2 as usize % apart.len()];
            let early = t.collapse_writes(second);
            let mut reference = t.clone();
            reference.collapse(first);
            reference.collapse(second);
            t.collapse(first);
            prop_assert_eq!(t.collapse_writes(second), early);
            t.write_collapse(&early);
            prop_assert_eq!(t.validate(), Ok(()));
            prop_assert_eq!(&t, &reference);
        }
    }
}

/// One round of the coarsening's application step: collapses legal on the starting state,
/// none of whose removed vertices is next to another's or is another's target, drawn densely
/// (many share a target or a wing) in a random order.
fn round_of_collapses(t: &Topology, seed: u64) -> Vec<HalfEdgeCollapse> {
    let mut x = seed | 1;
    let mut keyed: Vec<(u64, HalfEdgeCollapse)> = all_collapses(t)
        .into_iter()
        .filter(|&c| t.collapse_is_legal(c).is_ok())
        .map(|c| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x, c)
        })
        .collect();
    keyed.sort_unstable_by_key(|&(k, c)| (k, c.he, c.remove));
    let (mut removed, mut target) = (vec![false; t.vertex_count()], vec![false; t.vertex_count()]);
    let mut round = Vec::new();
    for (_, c) in keyed {
        let (u, v) = (c.remove, t.collapse_target(c));
        if removed[u as usize]
            || target[u as usize]
            || removed[v as usize]
            || t.neighbors(u).any(|w| removed[w as usize])
        {
            continue;
        }
        removed[u as usize] = true;
        target[v as usize] = true;
        round.push(c);
    }
    round
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(300), ..ProptestConfig::default() })]

    /// Applying such a round in order, `RoundTouches` says a collapse is still legal exactly
    /// when the full check does, and the mesh stays valid; after the round, what it says a
    /// vertex gained is what its neighbours show.
    #[test]
    fn round_touches_tell_which_collapses_still_hold(m in surfaces(), seeds in prop::collection::vec(any::<u64>(), 1..12)) {
        let mut t = topo(&m);
        let mut touches = RoundTouches::new(t.vertex_count());
        for seed in seeds {
            let before: Vec<Vec<u32>> = (0..t.vertex_count() as u32).map(|v| t.neighbors(v).collect()).collect();
            let mut marked = Vec::new();
            for c in round_of_collapses(&t, seed) {
                let legal = t.collapse_is_legal(c).is_ok();
                prop_assert_eq!(touches.still_legal(&t, c), legal, "collapse {:?}", c);
                if legal {
                    marked.extend(t.neighbors(c.remove));
                    touches.record(&t, c);
                    t.collapse(c);
                    prop_assert_eq!(t.validate(), Ok(()));
                }
            }
            for v in 0..t.vertex_count() as u32 {
                if t.vertex_he[v as usize] == INVALID {
                    continue;
                }
                let new: Vec<u32> = t.neighbors(v).filter(|w| !before[v as usize].contains(w)).collect();
                match touches.gained(v) {
                    Gained::Nothing => prop_assert!(new.is_empty(), "vertex {} gained {:?}", v, new),
                    Gained::One(w) => prop_assert_eq!(new, vec![w], "vertex {}", v),
                    Gained::Unknown => {}
                }
            }
            touches.clear(&marked);
        }
    }
}

#[test]
fn a_pole_of_valence_twenty_collapses_through_the_walk() {
    // 20 slices: each pole has 20 neighbours, 18 surviving corners, more than are listed.
    let mut t = topo(&procedural::uv_sphere(4, 20));
    let pole = (0..t.vertex_count() as u32).find(|&v| t.valence(v) == 20).unwrap();
    let c = HalfEdgeCollapse { he: t.vertex_he[pole as usize], remove: pole };
    assert_eq!(t.collapse_is_legal(c), Ok(()));
    let w = t.collapse_writes(c);
    assert_eq!(w.corners(), None, "18 corners are more than the list holds");
    let v = t.collapse_target(c);
    let valence_v = t.valence(v);
    let faces = t.live_face_count();
    t.write_collapse(&w);
    t.validate().unwrap();
    assert!(t.faces.iter().all(|f| !f.contains(&pole)), "a face still names the pole");
    assert_eq!(t.live_face_count(), faces - 2);
    // v keeps its neighbours but the pole and gains the pole's 19 others but the two wings.
    assert_eq!(t.valence(v), valence_v - 1 + 19 - 2);
}

fn collapse_until_stuck(m: &IndexedMesh) -> Topology {
    let mut t = topo(m);
    while let Some(c) = all_collapses(&t).into_iter().find(|&c| t.collapse_is_legal(c).is_ok()) {
        t.collapse(c);
        t.validate().unwrap();
    }
    t
}

#[test]
fn collapsing_until_stuck_reaches_the_smallest_surfaces() {
    // A sphere ends as a tetrahedron, a disk as a single triangle, a torus near the minimal
    // 7-vertex torus.
    let s = collapse_until_stuck(&procedural::uv_sphere(6, 8)).stats();
    assert_eq!((s.vertices, s.faces, s.genus), (4, 4, Some(0)));
    let s = collapse_until_stuck(&procedural::grid(4, 4, |i, j| (i ^ j) & 1 == 0)).stats();
    assert_eq!((s.vertices, s.faces, s.boundary_loops), (3, 1, 1));
    let s = collapse_until_stuck(&procedural::torus(10, 8)).stats();
    assert_eq!(s.genus, Some(1));
    assert!((7..=12).contains(&s.vertices), "torus stuck at {} vertices", s.vertices);
}

/// The vertices `parts` records as inner really are: their fans' faces and those faces'
/// corners lie in their part.
fn inner_vertices_are_inside(t: &Topology, parts: &Parts) -> Result<(), TestCaseError> {
    for v in 0..t.vertex_count() as u32 {
        let Some(k) = parts.inner(v) else { continue };
        let (vertices, faces) = parts.ranges(k);
        for g in t.outgoing(v) {
            let f = g / 3;
            prop_assert!(faces.contains(&f), "vertex {} is inner to part {} but face {} is not", v, k, f);
            for x in t.faces[f as usize] {
                prop_assert!(vertices.contains(&x), "vertex {} is inner to part {} but corner {} is not", v, k, x);
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(200), ..ProptestConfig::default() })]

    /// Making a round's collapses part by part, the parts side by side on the pool, and then
    /// the rest on the whole connectivity leaves the same mesh as making them in that order
    /// one after another; the vertices recorded as inner stay inside their parts.
    #[test]
    fn parts_side_by_side_make_what_one_after_another_makes(
        m in surfaces(),
        count in 2usize..5,
        seeds in prop::collection::vec(any::<u64>(), 1..10),
    ) {
        use rayon::prelude::*;
        let mut whole = topo(&m);
        let mut split = whole.clone();
        let mut parts = Parts::new(&split, count);
        inner_vertices_are_inside(&split, &parts)?;
        for seed in seeds {
            let round: Vec<HalfEdgeCollapse> =
                round_of_collapses(&whole, seed).into_iter().filter(|&c| whole.collapse_is_legal(c).is_ok()).collect();
            let mut inner = vec![Vec::new(); parts.count()];
            let mut rest = Vec::new();
            for c in round {
                match parts.part_of(&split, c) {
                    Some(k) => inner[k].push(c),
                    None => rest.push(c),
                }
            }
            for &c in inner.iter().flatten().chain(&rest) {
                if whole.collapse_is_legal(c).is_ok() {
                    whole.collapse(c);
                }
            }
            parts.split(&mut split).into_par_iter().zip(&inner).for_each(|(mut piece, list)| {
                for &c in list {
                    if piece.collapse_is_legal(c).is_ok() {
                        piece.collapse(c);
                    }
                }
            });
            let mut seen = Vec::new();
            for &c in &rest {
                if split.collapse_is_legal(c).is_ok() {
                    seen.extend(split.neighbors(c.remove));
                    split.collapse(c);
                }
            }
            parts.refresh(&split, &seen, 0);
            prop_assert_eq!(split.validate(), Ok(()));
            prop_assert!(split == whole, "the parts left a different mesh");
            inner_vertices_are_inside(&split, &parts)?;
        }
    }
}

/// On a mesh numbered along its surface most collapses lie inside a part: a grid in row
/// order, cut in two, keeps all but the rows along the cut.
#[test]
fn most_collapses_of_a_grid_lie_inside_a_part() {
    let t = topo(&procedural::grid(40, 40, |_, _| false));
    let parts = Parts::new(&t, 2);
    let round = round_of_collapses(&t, 7);
    let inside = round.iter().filter(|&&c| parts.part_of(&t, c).is_some()).count();
    assert!(round.len() > 100, "only {} collapses", round.len());
    assert!(inside * 10 >= round.len() * 8, "{inside} of {} inside a part", round.len());
    assert!(inside < round.len(), "no collapse crosses the cut");
}
