//! papers/000 §4: boundary tests 1–3 and parallel target selection.

use dynlod::lod::passes::boundaries::{face_normal, triangle_planes, Test};
use dynlod::lod::passes::select::{select, Selection};
use dynlod::simplify::Quadric;
use dynlod::topology::{HalfEdgeCollapse, HalfEdges, HalfEdgesMut, Topology, INVALID};
use dynlod::view::Viewpoint;
use dynlod::{BuildOptions, Mesh};
use proptest::prelude::*;

mod common;
use common::{facing_from, surfaces};

const EYE: Viewpoint = Viewpoint::At([0.0, 0.0, 10.0]);

fn blocked(tri: [[f64; 3]; 3], cand: [bool; 3], r: usize, to: [f64; 3], eye: Option<Viewpoint>) -> bool {
    triangle_planes(tri, cand, r, eye).0.iter().any(|p| p.crosses(tri[r], to))
}

/// How a proptest case looks at the mesh: from no eye, from an eye at `eye`, or
/// orthographically from the direction of `eye`.
fn viewpoint(eye: [f32; 3], lens: u8) -> Option<Viewpoint> {
    let e = glam::DVec3::from(eye.map(f64::from));
    match lens % 3 {
        0 => None,
        1 => Some(Viewpoint::At(e.to_array())),
        _ => Some(Viewpoint::Towards(e.normalize().to_array())),
    }
}

/// Figure 9: V3 → V1 and V4 → V2 are each valid, but together turn triangle (V3, V4, V5) over.
#[test]
fn two_collapses_fold_jointly_and_test_2_prevents_it() {
    let (v1, v2, v3, v4, v5) =
        ([0.6, -1.0, 0.0], [-0.6, -1.0, 0.0], [-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 2.0, 0.0]);
    let tri = [v3, v4, v5];
    let z = |t: [[f64; 3]; 3]| (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]);
    assert!(z(tri) > 0.0 && z([v1, v4, v5]) > 0.0 && z([v3, v2, v5]) > 0.0, "each alone keeps the triangle facing up");
    assert!(z([v1, v2, v5]) < 0.0, "both together turn it over");
    // Alone (test 1) each collapse passes this triangle's boundary.
    assert!(!blocked(tri, [true, false, false], 0, v1, Some(EYE)));
    assert!(!blocked(tri, [false, true, false], 1, v2, Some(EYE)));
    // With both candidates in the triangle (test 2), both are refused.
    let (planes, test) = triangle_planes(tri, [true, true, false], 0, Some(EYE));
    assert_eq!((planes.len(), test), (2, Test::Two));
    assert!(blocked(tri, [true, true, false], 0, v1, Some(EYE)));
    assert!(blocked(tri, [true, true, false], 1, v2, Some(EYE)));
    // Targets on each candidate's own side of the median stay allowed.
    assert!(!blocked(tri, [true, true, false], 0, [-1.0, -0.5, 0.0], Some(EYE)));
    assert!(!blocked(tri, [true, true, false], 1, [1.0, -0.5, 0.0], Some(EYE)));
}

#[test]
fn test_1_refuses_exactly_the_moves_across_the_fixed_edge() {
    // V_R at the origin, fixed edge from (1, -1) to (1, 1): crossing x = 1 turns the triangle.
    let tri = [[0.0, 0.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0]];
    let eye = Some(Viewpoint::At([0.5, 0.0, 50.0]));
    assert!(!blocked(tri, [true, false, false], 0, [0.9, 0.5, 0.0], eye));
    assert!(!blocked(tri, [true, false, false], 0, [-3.0, 2.0, 0.0], eye));
    assert!(blocked(tri, [true, false, false], 0, [1.5, 0.0, 0.0], eye));
    // An end exactly on the plane (the far edge's own vertices) is not a crossing.
    assert!(!blocked(tri, [true, false, false], 0, [1.0, 1.0, 0.0], eye));
}

#[test]
fn test_3_gives_each_candidate_the_region_behind_its_centroid_planes() {
    let tri = [[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 3.0, 0.0]];
    let (planes, test) = triangle_planes(tri, [true, true, true], 0, Some(EYE));
    assert_eq!((planes.len(), test), (2, Test::Three));
    // Planes through the centroid (1, 1) parallel to the edges at corner 0: x = 1 and y = 1.
    assert!(!blocked(tri, [true; 3], 0, [0.5, 0.5, 0.0], Some(EYE)));
    assert!(!blocked(tri, [true; 3], 0, [-2.0, 0.9, 0.0], Some(EYE)));
    assert!(blocked(tri, [true; 3], 0, [1.5, 0.5, 0.0], Some(EYE)));
    assert!(blocked(tri, [true; 3], 0, [0.5, 1.5, 0.0], Some(EYE)));
}

#[test]
fn without_an_eye_the_triangle_normal_takes_its_place() {
    let tri = [[0.0, 0.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0]];
    for to in [[0.9, 0.5, 0.0], [1.5, 0.0, 0.0], [1.2, 3.0, 0.4]] {
        for cand in [[true, false, false], [true, true, false], [true, true, true]] {
            assert_eq!(
                blocked(tri, cand, 0, to, None),
                blocked(tri, cand, 0, to, Some(Viewpoint::At([0.0, 0.0, 1e6]))),
                "{to:?} {cand:?}"
            );
        }
    }
}

/// An orthographic view is a perspective eye moved to infinity: its planes decide as an eye
/// far along the same direction does.
#[test]
fn an_orthographic_view_decides_as_an_eye_at_infinity() {
    let tri = [[0.0, 0.0, 0.0], [1.0, -1.0, 0.2], [1.0, 1.0, -0.1]];
    let d = glam::DVec3::new(0.3, -0.4, 1.0).normalize();
    let (ortho, far) = (Viewpoint::Towards(d.to_array()), Viewpoint::At((d * 1e7).to_array()));
    let mut refused = 0;
    for to in [[0.9, 0.5, 0.0], [1.5, 0.0, 0.0], [1.2, 3.0, 0.4], [-2.0, 0.3, 1.0], [0.7, -0.2, 3.0], [2.0, 2.0, -1.0]]
    {
        for cand in [[true, false, false], [true, true, false], [true, true, true]] {
            let b = blocked(tri, cand, 0, to, Some(ortho));
            assert_eq!(b, blocked(tri, cand, 0, to, Some(far)), "{to:?} {cand:?}");
            refused += usize::from(b);
        }
    }
    assert!(refused > 0 && refused < 18, "the cases exercise both answers ({refused} of 18 refused)");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(512), ..ProptestConfig::default() })]

    /// Test 1 under either projection refuses exactly the moves of V_R that turn the
    /// triangle against the view: under an orthographic view, those that flip the sign of
    /// its normal against −forward; under a perspective one, against the eye. Moves that end
    /// too near edge-on for f64 to tell are left out.
    #[test]
    fn test_1_refuses_exactly_the_moves_that_turn_the_triangle(
        tri in prop::array::uniform3(prop::array::uniform3(-2.0f64..2.0)),
        to in prop::array::uniform3(-3.0f64..3.0),
        dir in prop::array::uniform3(-1.0f64..1.0),
        perspective in any::<bool>(),
    ) {
        let d = glam::DVec3::from(dir);
        prop_assume!(d.length() > 0.1);
        let eye = if perspective {
            Viewpoint::At((d.normalize() * 9.0).to_array())
        } else {
            Viewpoint::Towards(d.normalize().to_array())
        };
        // n · (the direction towards the camera from the fixed corner V1).
        let turn = |t: [[f64; 3]; 3]| face_normal(t).dot(glam::DVec3::from(eye.seen_from(t[1])));
        let (before, after) = (turn(tri), turn([to, tri[1], tri[2]]));
        let scale = face_normal(tri).length().max(1e-3) * 9.0;
        prop_assume!(before.abs() > 1e-6 * scale && after.abs() > 1e-6 * scale);
        let turned = before.signum() != after.signum();
        prop_assert_eq!(blocked(tri, [true, false, false], 0, to, Some(eye)), turned);
    }
}

/// S and C for a round: R is a pseudo-random half of the vertices (drawn from `picks`), S the
/// rest, C the vertices of R with a neighbour in S.
fn classes(t: &Topology, picks: u64) -> (Vec<bool>, Vec<bool>) {
    let n = t.vertex_count();
    let in_r: Vec<bool> = (0..n).map(|v| (picks.rotate_left((v % 64) as u32) ^ v as u64) & 1 == 1).collect();
    let stays: Vec<bool> = in_r.iter().map(|r| !r).collect();
    let cand = (0..n as u32).map(|v| in_r[v as usize] && t.neighbors(v).any(|w| stays[w as usize])).collect();
    (stays, cand)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(256), ..ProptestConfig::default() })]

    /// One round as papers/000 runs it: every candidate chooses from the same state, with no
    /// communication; applying all the choices turns no triangle against the view. (Checked to
    /// fail when the selection uses test-1 planes only: Figure 9's joint fold then appears.)
    /// Application re-checks the link condition in vertex order, which is where the runtime
    /// will make the round as a whole keep the manifold (about 1 choice in 700 is dropped).
    #[test]
    fn a_round_of_independent_choices_turns_no_triangle_against_the_view(
        m in surfaces(),
        picks in any::<u64>(),
        eye in prop::array::uniform3(-6.0f32..6.0),
        lens in 0u8..3,
    ) {
        let mut mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
        let n = mesh.positions.len();
        let eye = viewpoint([eye[0], eye[1], eye[2] + 8.0], lens);
        let t = &mesh.topology;
        let (stays, cand) = classes(t, picks);
        let choices: Vec<(u32, u32)> = (0..n as u32)
            .filter(|&v| cand[v as usize])
            .filter_map(|v| match select(t, &mesh.positions, v, &cand, &stays, eye.as_slice()) {
                Selection::Collapse { target, .. } => Some((v, target)),
                Selection::Blocked { .. } => None,
            })
            .collect();
        // Reference for the view-independent case: facing against each face's own normal is
        // not defined after it moves, so only check the view-dependent ones against the view.
        let before: Vec<f64> =
            mesh.topology.faces.iter().map(|&f| eye.map_or(0.0, |e| facing_from(&mesh, f, e))).collect();
        for (v, target) in choices {
            let t = &mesh.topology;
            let Some(h) = t.find_edge(v, target) else { continue };
            let c = HalfEdgeCollapse { he: h, remove: v };
            if t.collapse_is_legal(c).is_ok() {
                mesh.topology.collapse(c);
            }
        }
        prop_assert_eq!(mesh.topology.validate(), Ok(()));
        if let Some(e) = eye {
            for (f, face) in mesh.topology.faces.iter().enumerate() {
                if face[0] == INVALID || before[f].abs() < 1e-9 {
                    continue;
                }
                let after = facing_from(&mesh, *face, e);
                prop_assert!(after * before[f] >= 0.0, "face {} turned: {} -> {}", f, before[f], after);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(128), ..ProptestConfig::default() })]

    /// §4.4: of the valid targets, the one with the least Q_R (V_R's quadric on the current
    /// faces; ties to the lower id) is chosen. Checked from outside: every target that is
    /// cheaper than the chosen one must be invalid, i.e. refused when it is the only vertex in
    /// S (planes and legality do not depend on S). (Checked to fail when the targets are not
    /// ranked.)
    #[test]
    fn the_cheapest_valid_target_is_chosen(
        m in surfaces(),
        picks in any::<u64>(),
        eye in prop::array::uniform3(-6.0f32..6.0),
        lens in 0u8..3,
    ) {
        let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
        let (t, p) = (&mesh.topology, &mesh.positions);
        let n = p.len();
        let eye = viewpoint([eye[0], eye[1], eye[2] + 8.0], lens);
        let (stays, cand) = classes(t, picks);
        let p64 = |v: u32| p[v as usize].map(f64::from);
        for v in (0..n as u32).filter(|&v| cand[v as usize]) {
            let Selection::Collapse { target, .. } = select(t, p, v, &cand, &stays, eye.as_slice()) else { continue };
            let mut q = Quadric::default();
            for g in t.outgoing(v) {
                let normal = face_normal(t.faces[(g / 3) as usize].map(p64));
                let len = normal.length();
                if len > 0.0 {
                    let (unit, corner) = ((normal / len).to_array(), p64(t.faces[(g / 3) as usize][0]));
                    let d = -(unit[0] * corner[0] + unit[1] * corner[1] + unit[2] * corner[2]);
                    q += Quadric::plane(unit, d, 0.5 * len);
                }
            }
            let key = |w: u32| (q.eval(p64(w)), w);
            for w in t.neighbors(v).filter(|&w| stays[w as usize] && key(w) < key(target)) {
                let mut only = vec![false; n];
                only[w as usize] = true;
                let alone = select(t, p, v, &cand, &only, eye.as_slice());
                prop_assert!(
                    !matches!(alone, Selection::Collapse { target: x, .. } if x == w),
                    "vertex {}: chose {} but the cheaper {} is valid", v, target, w
                );
            }
        }
    }
}

/// A target collinear with the fixed edge: exact arithmetic puts it on the test-1 plane (the
/// face would end edge-on), but f64 rounding put it 3.6e-15 inside, and the next round turned
/// the face away (facing 6.38 → 0 → −2.87; a proptest grid case). The rounding band counts as
/// on the plane.
#[test]
fn a_target_on_the_plane_by_rounding_counts_as_leaving() {
    let (v48, v49, v59, v37) = ([4.0, 4.0, 0.17], [5.0, 4.0, 0.285], [4.0, 5.0, 0.34], [4.0, 3.0, 0.0]);
    let p = |a: [f64; 3]| a.map(|c| c as f32 as f64);
    let tri = [p(v48), p(v49), p(v59)];
    let eye = Viewpoint::At([-1.908208f32, 3.5197043, -1.2093086 + 7.0].map(f64::from));
    let (planes, test) = triangle_planes(tri, [false, true, false], 1, Some(eye));
    assert_eq!((planes.len(), test), (1, Test::One));
    let plane = planes[0];
    assert!(plane.side(p(v37)).abs() < plane.tolerance(p(v37)), "the target is on the plane up to rounding");
    assert!(plane.leaves_side(tri[1], p(v37)));
    // A target clearly on the candidate's side is still allowed.
    assert!(!plane.leaves_side(tri[1], p([5.0, 3.0, 0.1])));
}
