//! papers/000 rounds: invariants after every round, determinism across thread counts.

use dynlod::lod::coarsen::{coarsen, coarsen_views, CoarsenOptions, CoarsenStop, Coarsener, Schedule};
use dynlod::lod::passes::anchors::AnchorOptions;
use dynlod::lod::passes::classify::{screen_error_in, vertex_normals_and_errors, ClassifyOptions};
use dynlod::topology::{HalfEdges, INVALID};
use dynlod::view::{Frustum, View};
use dynlod::{procedural, BuildOptions, Mesh};
use proptest::prelude::*;

mod common;
use common::{facing, surfaces};

fn facing32(m: &Mesh, f: [u32; 3], eye: [f32; 3]) -> f64 {
    facing(m, f, eye.map(f64::from))
}

fn schedules() -> impl Strategy<Value = Schedule> {
    prop_oneof![Just(Schedule::AllCandidates), Just(Schedule::LocalMinima)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(96), ..ProptestConfig::default() })]

    /// The same mesh and view give the same result on 1 and 2 threads.
    #[test]
    fn thread_count_does_not_change_the_result(m in surfaces(), eye in prop::array::uniform3(-5.0f32..5.0), u in 0.2f32..20.0, schedule in schedules()) {
        let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
        let view = View::perspective([eye[0], eye[1], eye[2] + 7.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (800, 600));
        let run = |threads| {
            common::on_threads(threads, || {
                let mut out = mesh.clone();
                let s = coarsen(&mut out, Some(view), CoarsenOptions::default().threshold(u).schedule(schedule));
                (out, s.rounds)
            })
        };
        let (a, ra) = run(1);
        let (b, rb) = run(2);
        prop_assert_eq!(ra, rb);
        prop_assert!(a == b);
    }

    /// After every round: valid, same Euler characteristic and border loops, and no triangle
    /// that faced the eye faces away.
    #[test]
    fn every_round_keeps_the_mesh_valid_and_facing(m in surfaces(), eye in prop::array::uniform3(-5.0f32..5.0), u in 0.2f32..20.0, schedule in schedules()) {
        let mut mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
        let eye = [eye[0], eye[1], eye[2] + 7.0];
        let view = View::perspective(eye, [0.0; 3], [0.0, 1.0, 0.0], 60.0, (800, 600));
        let before = mesh.topology.stats();
        let front: Vec<bool> = mesh.topology.faces.iter().map(|&f| facing32(&mesh, f, eye) > 1e-9).collect();
        let mut c = Coarsener::new(&mesh, &[view], CoarsenOptions::default().threshold(u).schedule(schedule));
        for _ in 0..60 {
            let r = c.round(&mut mesh);
            prop_assert_eq!(mesh.topology.validate(), Ok(()));
            let s = mesh.topology.stats();
            prop_assert_eq!((s.euler, s.boundary_loops, s.components.len()), (before.euler, before.boundary_loops, before.components.len()));
            for (f, face) in mesh.topology.faces.iter().enumerate() {
                if face[0] != INVALID && front[f] {
                    prop_assert!(facing32(&mesh, *face, eye) >= 0.0, "face {} turned away from the eye: {} round {:?}", f, facing32(&mesh, *face, eye), r);
                }
            }
            if r.candidates == 0 {
                break;
            }
        }
    }
}

/// Two cameras on opposite sides of a surface, at the distances `d` and `d * ratio`.
fn two_views(eye: [f32; 3], d: f32, ratio: f32) -> [View; 2] {
    let at = |s: f32| View::perspective(eye.map(|x| x * s), [0.0; 3], [0.0, 1.0, 0.0], 60.0, (800, 600));
    let other = |v: View| {
        let e = v.eye;
        View::perspective([-e[0], e[1], -e[2]], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (800, 600))
    };
    [at(d), other(at(d * ratio))]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(64), ..ProptestConfig::default() })]

    /// Several views at once: after every round the mesh is valid with its Euler
    /// characteristic, and no triangle that faced either eye faces away from it. Every vertex
    /// removed was fine in each view alone (its pixel error under the threshold there), so
    /// each view sees at most what it would allow; one view gives what `coarsen` gives, and
    /// neither the views' order nor a repeated view changes anything.
    #[test]
    fn several_views_keep_every_view_facing_and_within_its_error(m in surfaces(), eye in prop::array::uniform3(-1.0f32..1.0), d in 3.0f32..12.0, ratio in 1.0f32..20.0, u in 0.2f32..8.0, schedule in schedules()) {
        let base = Mesh::build(&m, BuildOptions::default()).unwrap();
        let eye = [eye[0], eye[1], eye[2] + 1.5];
        let views = two_views(eye, d, ratio);
        let options = CoarsenOptions::default().threshold(u).schedule(schedule);
        let before = base.topology.stats();
        let front: Vec<[bool; 2]> = base.topology.faces.iter().map(|&f| views.map(|v| facing32(&base, f, v.eye) > 1e-9)).collect();
        let mut mesh = base.clone();
        let mut c = Coarsener::new(&mesh, &views, options.clone());
        for _ in 0..80 {
            let r = c.round(&mut mesh);
            prop_assert_eq!(mesh.topology.validate(), Ok(()));
            let s = mesh.topology.stats();
            prop_assert_eq!((s.euler, s.boundary_loops), (before.euler, before.boundary_loops));
            for (f, face) in mesh.topology.faces.iter().enumerate() {
                for (k, v) in views.iter().enumerate() {
                    if face[0] != INVALID && front[f][k] {
                        prop_assert!(facing32(&mesh, *face, v.eye) >= 0.0, "face {} turned away from eye {}", f, k);
                    }
                }
            }
            if r.candidates == 0 {
                break;
            }
        }
        let (normals, errors) = vertex_normals_and_errors(&base.topology, &base.positions);
        let o = ClassifyOptions::default();
        for v in 0..base.positions.len() {
            if base.topology.vertex_he[v] != INVALID && mesh.topology.vertex_he[v] == INVALID {
                for (k, view) in views.iter().enumerate() {
                    let px = screen_error_in(Some(&Frustum::new(view)), base.positions[v], normals[v], errors[v], &o);
                    prop_assert!(px <= u, "vertex {} removed at {} px in view {} (threshold {})", v, px, k, u);
                }
            }
        }
        let run = |vs: &[View]| {
            let mut out = base.clone();
            coarsen_views(&mut out, vs, options.clone());
            out
        };
        let both = run(&views);
        prop_assert!(both == run(&[views[1], views[0]]), "the views' order changed the result");
        prop_assert!(both == run(&[views[0], views[1], views[0]]), "a repeated view changed the result");
        let mut one = base.clone();
        coarsen(&mut one, Some(views[0]), options.clone());
        prop_assert!(one == run(&views[..1]), "one view differs from coarsen's");
    }
}

/// A mesh seen from near and from far keeps what the near view needs: the same mesh as the
/// near view alone gives where the far one asks for nothing more, and more triangles than
/// the far view alone leaves.
#[test]
fn a_near_and_a_far_view_keep_what_the_near_one_needs() {
    let base = Mesh::build(&procedural::torus(80, 40), BuildOptions::default()).unwrap();
    let look = |z: f32| View::perspective([0.3, 0.4, z], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
    let (near, far) = (look(3.0), look(60.0));
    let options = CoarsenOptions::default().threshold(1.0);
    let count = |vs: &[View]| {
        let mut m = base.clone();
        coarsen_views(&mut m, vs, options.clone());
        m.topology.validate().unwrap();
        m.topology.live_face_count()
    };
    let (n_near, n_far, n_both) = (count(&[near]), count(&[far]), count(&[near, far]));
    assert!(n_far < n_near / 2, "the far view alone coarsens much further: {n_far} against {n_near}");
    assert!(n_both > n_far, "both views keep more than the far one alone: {n_both} against {n_far}");
    assert!(n_both >= n_near * 9 / 10, "both views keep about what the near one needs: {n_both} against {n_near}");
}

#[test]
fn one_and_two_threads_give_the_same_mesh() {
    let m = Mesh::build(&procedural::torus(60, 30), BuildOptions::default()).unwrap();
    let view = View::perspective([0.5, 0.3, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
    let run = |threads| {
        common::on_threads(threads, || {
            let mut mesh = m.clone();
            let s = coarsen(&mut mesh, Some(view), CoarsenOptions::default().threshold(2.0));
            (mesh, s.rounds)
        })
    };
    let (a, ra) = run(1);
    let (b, rb) = run(2);
    assert_eq!(ra, rb);
    assert_eq!(a, b);
    assert!(a.topology.live_face_count() < m.topology.live_face_count());
}

/// Also the deadlock scenario: on a dense flat grid, neighbouring candidates block each other
/// round after round under the paper's schedule; the ignore flag (§5) breaks the ties and R
/// still empties. Under local minima no two neighbouring candidates act in one round, so
/// nothing is ever blocked by a neighbour, and R empties too.
#[test]
fn view_independent_coarsening_runs_to_completion_and_keeps_borders() {
    let mut g = procedural::grid(16, 12, |i, j| (i + 2 * j) % 3 == 0);
    for p in &mut g.positions {
        p[2] = 0.01 * (p[0] * 0.7).sin() * (p[1] * 0.5).cos();
    }
    let base = Mesh::build(&g, BuildOptions::default()).unwrap();
    let input = base.topology.live_face_count();
    for schedule in [Schedule::AllCandidates, Schedule::LocalMinima] {
        let mut mesh = base.clone();
        let options = CoarsenOptions::default()
            .threshold(0.05)
            .anchors(Some(AnchorOptions::default().cells(2)))
            .schedule(schedule);
        let s = coarsen(&mut mesh, None, options);
        assert_eq!(s.stop, CoarsenStop::Done, "{schedule:?}");
        assert!(s.output_triangles < input / 2, "{schedule:?}: {} of {input}", s.output_triangles);
        mesh.topology.validate().unwrap();
        for v in 0..mesh.positions.len() as u32 {
            if mesh.topology.vertex_he[v as usize] != INVALID && mesh.topology.is_boundary_vertex(v) {
                let p = mesh.positions[v as usize];
                assert!(
                    p[0] == 0.0 || p[0] == 16.0 || p[1] == 0.0 || p[1] == 12.0,
                    "{schedule:?}: border vertex left the border: {p:?}"
                );
            }
        }
        match schedule {
            // Deadlock prevention had work to do: candidates blocked each other, some were
            // set aside as ignored, and the run still emptied R (stop = Done).
            Schedule::AllCandidates => {
                assert!(s.rounds.iter().any(|r| r.blocked > 0));
                assert!(s.rounds.iter().any(|r| r.ignored > 0), "{:?}", s.rounds);
                assert!(s.rounds.iter().all(|r| r.waiting == 0));
            }
            // Neighbouring candidates took turns instead.
            Schedule::LocalMinima => {
                assert!(s.rounds.iter().all(|r| r.blocked == 0), "{:?}", s.rounds);
                assert!(s.rounds.iter().any(|r| r.waiting > 0));
            }
        }
    }
}

#[test]
fn the_bunny_stays_valid_and_facing_round_by_round() {
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let base = dynlod::load_mesh(p, BuildOptions::default()).unwrap();
    let before = base.topology.stats();
    for eye in [[0.0f32, 0.1, 0.35], [0.3, 0.25, -0.2]] {
        let mut mesh = base.clone();
        let view = View::perspective(eye, [-0.017, 0.11, 0.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
        let front: Vec<bool> = mesh.topology.faces.iter().map(|&f| facing32(&mesh, f, eye) > 1e-12).collect();
        let mut c = Coarsener::new(&mesh, &[view], CoarsenOptions::default().threshold(1.0));
        let mut rounds = 0;
        loop {
            let r = c.round(&mut mesh);
            rounds += 1;
            mesh.topology.validate().unwrap();
            let s = mesh.topology.stats();
            assert_eq!((s.euler, s.boundary_loops), (before.euler, before.boundary_loops));
            for (f, face) in mesh.topology.faces.iter().enumerate() {
                if face[0] != INVALID && front[f] {
                    assert!(facing32(&mesh, *face, eye) >= 0.0, "round {rounds}: face {f} turned away");
                }
            }
            if r.candidates == 0 || rounds > 300 {
                break;
            }
        }
        assert!(mesh.topology.live_face_count() < base.topology.live_face_count() / 2);
    }
}

#[test]
fn uv_seams_survive_view_dependent_coarsening() {
    let sphere = Mesh::build(&procedural::uv_sphere(32, 48), BuildOptions::default()).unwrap();
    let seams = sphere.seam_edges();
    let mut mesh = sphere.clone();
    let view = View::perspective([0.0, 0.0, 6.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (800, 600));
    coarsen(&mut mesh, Some(view), CoarsenOptions::default().threshold(2.0));
    mesh.topology.validate().unwrap();
    assert!(mesh.topology.live_face_count() < sphere.topology.live_face_count() / 2);
    // The seam is still a seam (shorter: vertices slide along it), and every corner's wedge
    // belongs to its vertex.
    assert!(mesh.seam_edges() > 0 && mesh.seam_edges() <= seams);
    for (f, face) in mesh.topology.faces.iter().enumerate() {
        if face[0] != INVALID {
            for (c, &v) in face.iter().enumerate() {
                assert_eq!(mesh.wedges.vertex_of(mesh.corner_wedge((3 * f + c) as u32)), v);
            }
        }
    }
    // UVs on the seam meridian keep both sides: some wedge at u = 0 and some at u = 1 remain.
    assert!(mesh.wedges.uvs.iter().any(|t| t[0] == 0.0) && mesh.wedges.uvs.iter().any(|t| t[0] == 1.0));
}

/// Made in parts side by side (a mesh in spatial order), a round still keeps the mesh valid,
/// its Euler characteristic and borders, and every front face facing the eye; 1 and 2
/// threads give the same rounds and mesh; and at least three in four collapses are made inside parts.
#[test]
fn collapses_made_in_parts_keep_every_invariant_on_any_thread_count() {
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let base = dynlod::load_mesh(p, BuildOptions::default().spatial_order(true)).unwrap();
    let before = base.topology.stats();
    let eye = [0.0f32, 0.1, 0.35];
    let view = View::perspective(eye, [-0.017, 0.11, 0.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
    let front: Vec<bool> = base.topology.faces.iter().map(|&f| facing32(&base, f, eye) > 1e-12).collect();
    for parts in [2, 3] {
        let run = |threads: usize, check: bool| {
            common::on_threads(threads, || {
                let mut mesh = base.clone();
                let options = CoarsenOptions::default().threshold(1.0).apply_parts(parts);
                let mut c = Coarsener::new(&mesh, &[view], options);
                let mut rounds = Vec::new();
                while rounds.len() < 300 {
                    let r = c.round(&mut mesh);
                    rounds.push(r);
                    if check {
                        mesh.topology.validate().unwrap();
                        let s = mesh.topology.stats();
                        assert_eq!((s.euler, s.boundary_loops), (before.euler, before.boundary_loops));
                        for (f, face) in mesh.topology.faces.iter().enumerate() {
                            if face[0] != INVALID && front[f] {
                                assert!(
                                    facing32(&mesh, *face, eye) >= 0.0,
                                    "round {}: face {f} turned away",
                                    rounds.len()
                                );
                            }
                        }
                    }
                    if r.candidates == 0 {
                        break;
                    }
                }
                (mesh, rounds)
            })
        };
        let (one, rounds) = run(1, true);
        let (two, rounds_two) = run(2, false);
        assert_eq!(rounds, rounds_two, "{parts} parts");
        assert!(one == two, "{parts} parts: 1 and 2 threads differ");
        let collapsed: usize = rounds.iter().map(|r| r.collapsed).sum();
        let in_parts: usize = rounds.iter().map(|r| r.collapsed_in_parts).sum();
        assert!(collapsed > base.topology.vertex_count() / 4, "{parts} parts: only {collapsed} collapses");
        assert!(in_parts * 4 >= collapsed * 3, "{parts} parts: {in_parts} of {collapsed} collapses in parts");
    }
}

/// A flat annulus: `rings` + 1 circles of `slices` vertices from radius 1 to 2. Both borders
/// turn by 360° / `slices` at each vertex, under the 30° corner angle for `slices` > 12, so no
/// border vertex is a corner: each border is one closed line its vertices may only slide along.
fn annulus(rings: usize, slices: usize) -> dynlod::IndexedMesh {
    let mut m = dynlod::IndexedMesh::default();
    for i in 0..=rings {
        let r = 1.0 + i as f32 / rings as f32;
        for j in 0..slices {
            let (s, c) = (j as f32 / slices as f32 * std::f32::consts::TAU).sin_cos();
            m.positions.push([r * c, r * s, 0.0]);
        }
    }
    let id = |i: usize, j: usize| (i * slices + j % slices) as u32;
    for i in 0..rings {
        for j in 0..slices {
            m.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            m.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    m
}

/// Live vertices of `m`, and how many of them are on a border.
fn live_and_border(m: &Mesh) -> (usize, usize) {
    let t = &m.topology;
    let live: Vec<u32> = (0..t.vertex_count() as u32).filter(|&v| t.vertex_he[v as usize] != INVALID).collect();
    (live.len(), live.iter().filter(|&&v| t.is_boundary_vertex(v)).count())
}

/// R vertices collapse only into S, so a line a vertex may only slide along needs a vertex of
/// S on it: the annulus's round borders get one each (passes/structure_anchors.rs). Without
/// them every border vertex stayed, whatever the threshold (96 of the 96).
#[test]
fn round_borders_coarsen_along_themselves() {
    let m = Mesh::build(&annulus(6, 48), BuildOptions::default()).unwrap();
    let mut out = m.clone();
    let s = coarsen(&mut out, None, CoarsenOptions::default().threshold(1e30));
    out.topology.validate().unwrap();
    let (live, border) = live_and_border(&out);
    assert!(border <= 80, "{border} of 96 border vertices left ({live} live, stop {:?})", s.stop);
    let stats = out.topology.stats();
    assert_eq!((stats.euler, stats.boundary_loops), (0, 2));
}

/// A part the anchor grid gave no anchor has no target in S: it got one
/// (passes/structure_anchors.rs). Two tori in one anchor cell: without it only one of them
/// coarsened (the other kept its 96 vertices).
#[test]
fn every_part_coarsens_even_without_a_grid_anchor() {
    let mut two = procedural::torus(12, 8);
    let second = procedural::torus(12, 8);
    let offset = two.positions.len() as u32;
    two.positions.extend(second.positions.iter().map(|p| [p[0] + 3.0, p[1], p[2]]));
    two.triangles.extend(second.triangles.iter().map(|f| f.map(|v| v + offset)));
    let m = Mesh::build(&two, BuildOptions::default()).unwrap();
    let mut out = m.clone();
    coarsen(&mut out, None, CoarsenOptions::default().threshold(1e30).anchors(Some(AnchorOptions::default().cells(1))));
    out.topology.validate().unwrap();
    let t = &out.topology;
    for part in 0..2u32 {
        let left = (part * offset..(part + 1) * offset).filter(|&v| t.vertex_he[v as usize] != INVALID).count();
        assert!(left <= offset as usize * 5 / 6, "torus {part}: {left} of {offset} vertices left");
    }
}

/// The one-shot rounds keep the paper's L0 (anchors.rs, `AnchorOptions::nested`): they
/// classify once and do not follow a removal's error along a chain of anchors, so nested
/// anchors let a 1 px cut of the bunny from 8 diagonals end 7.3 % of the diagonal off the
/// input. By default it stays near what the view scaling allows (1.4 %).
#[test]
fn a_far_one_shot_cut_keeps_its_error() {
    let bunny = dynlod::load_mesh(
        concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz"),
        BuildOptions::default(),
    )
    .unwrap();
    let original = bunny.to_indexed();
    let (centre, diag) = dynlod::camera_path::frame_bounds(&bunny.positions);
    let view =
        View::perspective([centre[0], centre[1], centre[2] + 8.0 * diag], centre, [0.0, 1.0, 0.0], 60.0, (1920, 1080));
    let cut = |options: CoarsenOptions| {
        let mut m = bunny.clone();
        coarsen(&mut m, Some(view), options.threshold(1.0));
        let h = dynlod::metrics::hausdorff(&original, &m.to_indexed(), Default::default());
        (m.topology.live_face_count(), h.pct(h.max))
    };
    let (tris, max) = cut(CoarsenOptions::default());
    assert!(tris < 4400 && max < 2.0, "{tris} triangles, {max} % off");
    let nested = CoarsenOptions::default().anchors(Some(AnchorOptions::default()));
    let (_, nested_max) = cut(nested);
    assert!(nested_max > 2.0 * max, "nested anchors: {nested_max} % against {max} %");
}
