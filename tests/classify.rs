//! papers/000 §3 vertex analysis: the error, its scaling into pixels, classification, anchors.

use dynlod::lod::passes::anchors::{apply_anchors, select_anchors, AnchorOptions};
use dynlod::lod::passes::classify::{
    classify, screen_error, vertex_error, vertex_errors, vertex_normals, vertex_normals_and_errors, ClassifyOptions,
};
use dynlod::view::{Frustum, View};
use dynlod::{procedural, BuildOptions, IndexedMesh, Mesh};

fn build(m: &IndexedMesh) -> Mesh {
    Mesh::build(m, BuildOptions::default()).unwrap()
}

#[test]
fn error_is_the_mean_squared_height_of_the_neighbours_over_the_tangent_plane() {
    let mut g = procedural::grid(2, 2, |_, _| false);
    let flat = build(&g);
    let n = vertex_normals(&flat.topology, &flat.positions);
    assert!(vertex_errors(&flat.topology, &flat.positions, &n).iter().all(|&e| e == 0.0));
    // Lift the eight neighbours of the centre (vertex 4) by h: with the normal +z, e = h².
    let h = 0.3f32;
    for (i, p) in g.positions.iter_mut().enumerate() {
        if i != 4 {
            p[2] = h;
        }
    }
    let lifted = build(&g);
    let e = vertex_error(&lifted.topology, &lifted.positions, [0.0, 0.0, 1.0], 4);
    assert!((e - h * h).abs() < 1e-6, "{e}");
}

#[test]
fn one_unit_covers_the_expected_pixels() {
    let v = View::perspective([0.0, 0.0, 10.0], [0.0; 3], [0.0, 1.0, 0.0], 90.0, (1920, 1000));
    assert!((v.pixels_per_unit([0.0; 3]) - 50.0).abs() < 1e-3);
    assert!((v.pixels_per_unit([0.0, 0.0, -10.0]) - 25.0).abs() < 1e-3, "twice as far, half the pixels");
    assert!(v.in_frustum([0.0; 3], 0.0));
    assert!(!v.in_frustum([0.0, 0.0, 20.0], 0.0), "behind the eye");
    assert!(!v.in_frustum([0.0, 30.0, 0.0], 0.0), "above the 90° cone at distance 10");
    assert!(v.in_frustum([0.0, 30.0, 0.0], 15.0), "a big enough sphere reaches in");
    assert!((v.facing([0.0; 3], [0.0, 0.0, 1.0]) - 1.0).abs() < 1e-6);
    assert!((v.facing([0.0; 3], [0.0, 0.0, -1.0]) + 1.0).abs() < 1e-6);
}

/// An orthographic view: the same pixels per unit at every distance, the same facing at every
/// point, and a box for a frustum (in front of the eye's plane only).
#[test]
fn an_orthographic_unit_covers_the_same_pixels_everywhere() {
    let v = View::orthographic([0.0, 0.0, 10.0], [0.0; 3], [0.0, 1.0, 0.0], 20.0, (1920, 1000));
    for p in [[0.0; 3], [0.0, 0.0, -990.0], [9.0, -4.0, 5.0]] {
        assert_eq!(v.pixels_per_unit(p), 50.0, "{p:?}");
    }
    assert_eq!(v.pixels_per_unit_at(1e9), 50.0);
    // The box is 38.4 × 20 world units (the aspect widens it), open towards −z.
    assert!(v.in_frustum([0.0, 0.0, -1000.0], 0.0));
    assert!(v.in_frustum([19.0, 9.9, 0.0], 0.0));
    assert!(!v.in_frustum([19.0, 10.5, 0.0], 0.0), "above the box");
    assert!(v.in_frustum([19.0, 10.5, 0.0], 0.6), "a big enough sphere reaches in");
    assert!(!v.in_frustum([20.0, 0.0, 0.0], 0.0), "right of the box");
    assert!(!v.in_frustum([0.0, 0.0, 11.0], 0.5), "behind the eye's plane");
    // Facing reads the normal against −forward alone: the same off axis as on it.
    for p in [[0.0; 3], [15.0, 8.0, -3.0]] {
        assert!((v.facing(p, [0.0, 0.0, 1.0]) - 1.0).abs() < 1e-6);
        assert!((v.facing(p, [0.0, 0.0, -1.0]) + 1.0).abs() < 1e-6);
        assert!(v.facing(p, [1.0, 0.0, 0.0]).abs() < 1e-6, "edge-on wherever it is");
    }
    // A perspective view from the same eye reads the off-axis point's normal differently.
    let persp = View::perspective([0.0, 0.0, 10.0], [0.0; 3], [0.0, 1.0, 0.0], 90.0, (1920, 1000));
    assert!(persp.facing([15.0, 8.0, -3.0], [-1.0, 0.0, 0.0]) > 0.5);
    // `orthographic_at` frames at the given distance what the perspective view frames there.
    let framed = persp.orthographic_at(10.0);
    assert!((framed.pixels_per_unit([0.0; 3]) - persp.pixels_per_unit([0.0; 3])).abs() < 1e-3);
    assert_eq!(framed.orthographic_at(3.0), framed, "an orthographic view stays as it is");
}

#[test]
fn screen_error_weighs_silhouettes_back_faces_and_the_outside() {
    let v = View::perspective([0.0, 0.0, 10.0], [0.0; 3], [0.0, 1.0, 0.0], 90.0, (1000, 1000));
    let o = ClassifyOptions::default();
    let e = 0.04; // √e = 0.2 units = 10 px at distance 10
    let front = screen_error(Some(&v), [0.0; 3], [0.0, 0.0, 1.0], e, &o);
    let edge = screen_error(Some(&v), [0.0; 3], [1.0, 0.0, 0.0], e, &o);
    let back = screen_error(Some(&v), [0.0; 3], [0.0, 0.0, -1.0], e, &o);
    assert!((front - 5.0).abs() < 1e-3, "face-on: half strength, {front}");
    assert!((edge - 10.0).abs() < 1e-3, "silhouette: full strength, {edge}");
    assert!((back - 5.0 * o.back_facing_scale).abs() < 1e-3, "{back}");
    let outside = screen_error(Some(&v), [0.0, 0.0, 30.0], [0.0, 0.0, 1.0], e, &o);
    let mirrored = screen_error(Some(&v), [0.0, 0.0, -10.0], [0.0, 0.0, 1.0], e, &o);
    assert!(outside < mirrored * 0.2, "behind the camera counts as outside: {outside} vs {mirrored}");
    assert_eq!(screen_error(None, [0.0; 3], [0.0, 0.0, 1.0], e, &o), 0.2, "without a view: √e in units");
}

/// The one-pass normals and errors (the coarsener's and the runtime's set-up) are exactly the
/// two separate passes', on a torus and on a mesh with borders and holes.
#[test]
fn normals_and_errors_in_one_pass_equal_the_two_passes() {
    for m in [procedural::torus(48, 24), procedural::grid(20, 12, |i, j| (i + 2 * j) % 7 == 0)] {
        let mesh = build(&m);
        let (t, p) = (&mesh.topology, &mesh.positions);
        let n = vertex_normals(t, p);
        let e = vertex_errors(t, p, &n);
        assert!(e.iter().any(|&x| x > 0.0) || n.iter().all(|v| v[2].abs() == 1.0));
        assert_eq!(vertex_normals_and_errors(t, p), (n, e));
    }
}

#[test]
fn farther_views_remove_more_and_never_less() {
    let mesh = build(&procedural::torus(48, 24));
    let (t, p) = (&mesh.topology, &mesh.positions);
    let n = vertex_normals(t, p);
    let e = vertex_errors(t, p, &n);
    let o = ClassifyOptions::default().threshold(1.0);
    let mut last = 0;
    let mut prev: Option<(View, Vec<bool>)> = None;
    for d in [2.0f32, 4.0, 8.0, 16.0, 32.0] {
        let view = View::perspective([0.0, 0.0, d], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
        let r = classify(&[Frustum::new(&view)], t, p, &n, &e, &o);
        let count = r.iter().filter(|&&x| x).count();
        assert!(count >= last, "distance {d}: {count} < {last}");
        if let Some((pv, pr)) = &prev {
            // Twice as far halves the pixels per unit while the angle factor can at most double,
            // so a vertex front-facing and inside both views can only move from S to R.
            for v in 0..r.len() {
                let steady = |w: &View| w.in_frustum(p[v], e[v].sqrt()) && w.facing(p[v], n[v]) >= 0.0;
                if steady(pv) && steady(&view) {
                    let (a, b) =
                        (screen_error(Some(pv), p[v], n[v], e[v], &o), screen_error(Some(&view), p[v], n[v], e[v], &o));
                    assert!(
                        !pr[v] || r[v],
                        "vertex {v} went back to S moving away: {a} -> {b} px, facing {} -> {}",
                        pv.facing(p[v], n[v]),
                        view.facing(p[v], n[v])
                    );
                }
            }
        }
        last = count;
        prev = Some((view, r));
    }
    assert!(last > 0);
}

#[test]
fn classification_does_not_depend_on_the_thread_count() {
    let mesh = build(&procedural::uv_sphere(40, 60));
    let (t, p) = (&mesh.topology, &mesh.positions);
    let n = vertex_normals(t, p);
    let view = View::perspective([0.3, 0.2, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
    let run = |threads| {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| {
            let e = vertex_errors(t, p, &n);
            classify(&[Frustum::new(&view)], t, p, &n, &e, &ClassifyOptions::default().threshold(0.5))
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn layer_zero_anchors_always_stay() {
    let mesh = build(&procedural::torus(40, 20));
    let (t, p) = (&mesh.topology, &mesh.positions);
    let n = vertex_normals(t, p);
    let mut e = vertex_errors(t, p, &n);
    let o = AnchorOptions::default().cells(3).layer_errors(vec![1e-3]);
    let anchors = select_anchors(t, p, &e, &o);
    assert_eq!(anchors.len(), 2);
    assert!(!anchors[0].is_empty() && anchors[1].len() > anchors[0].len());
    // One anchor per non-empty L0 cell: at most 3³.
    assert!(anchors[0].len() <= 27);
    apply_anchors(&mut e, &anchors, &o);
    let r = classify(&[], t, p, &n, &e, &ClassifyOptions::default().threshold(f32::MAX));
    for &a in &anchors[0] {
        assert!(!r[a as usize], "L0 anchor {a} must stay whatever the threshold");
    }
    assert_eq!(r.iter().filter(|&&x| !x).count(), anchors[0].len(), "with u = MAX only L0 stays");
    for &a in &anchors[1] {
        assert!(e[a as usize] >= 1e-3);
    }
    // Deterministic.
    assert_eq!(select_anchors(t, p, &vertex_errors(t, p, &n), &o), anchors);
}

#[test]
fn the_anchor_is_the_largest_weighted_error_in_its_cell() {
    // A flat grid with one raised vertex: in its cell, m = (l − d)² · e is zero everywhere else.
    let mut g = procedural::grid(8, 8, |_, _| false);
    g.positions[3 * 9 + 2][2] = 0.5; // vertex (2, 3)
    let mesh = build(&g);
    let (t, p) = (&mesh.topology, &mesh.positions);
    let n = vertex_normals(t, p);
    let e = vertex_errors(t, p, &n);
    let anchors = select_anchors(t, p, &e, &AnchorOptions::default().cells(2));
    let raised = (0..p.len() as u32).find(|&v| p[v as usize] == [2.0, 3.0, 0.5]).unwrap();
    // The raised vertex and its neighbours have e > 0; the raised one has by far the largest.
    assert!(anchors[0].contains(&raised), "{:?}", anchors[0]);
}

/// What the grid cannot place (passes/structure_anchors.rs): vertices that can never move,
/// one vertex of every line whose vertices may only slide along it and that has no anchor,
/// one vertex of every part without one.
#[test]
fn structure_anchors_are_the_fixed_vertices_and_one_per_unanchored_line_and_part() {
    use dynlod::lod::passes::structure_anchors::structure_anchors;
    use dynlod::mesh::constraints::BORDER_CORNER_DEGREES;
    let anchors = |m: &Mesh, grid: &[u32]| {
        let n = vertex_normals(&m.topology, &m.positions);
        structure_anchors(m, &vertex_errors(&m.topology, &m.positions, &n), grid, BORDER_CORNER_DEGREES)
    };
    // A square: its four corners turn by 90° and stay; each side ends at two of them.
    let square = build(&procedural::grid(4, 4, |_, _| false));
    let corner = |x: f32, y: f32| square.positions.iter().position(|p| *p == [x, y, 0.0]).unwrap() as u32;
    let mut corners = vec![corner(0.0, 0.0), corner(4.0, 0.0), corner(4.0, 4.0), corner(0.0, 4.0)];
    corners.sort_unstable();
    assert_eq!(anchors(&square, &[]), corners);
    // A torus with an anchor: nothing fixed, no border, one part.
    let torus = build(&procedural::torus(12, 8));
    assert_eq!(anchors(&torus, &[0]), Vec::<u32>::new());
    // Without: one, for the part.
    assert_eq!(anchors(&torus, &[]).len(), 1);
    // A cylinder open at both ends, 24 around: its rims turn by 15°, no corner; one anchor on
    // each rim, none for the part (the rims' anchors are in it).
    let mut tube = IndexedMesh::default();
    for ring in 0..3 {
        for j in 0..24 {
            let (s, c) = (j as f32 / 24.0 * std::f32::consts::TAU).sin_cos();
            tube.positions.push([c, s, ring as f32]);
        }
    }
    let id = |i: usize, j: usize| (i * 24 + j % 24) as u32;
    for i in 0..2 {
        for j in 0..24 {
            tube.triangles.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            tube.triangles.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    let tube = build(&tube);
    let rims = anchors(&tube, &[]);
    assert_eq!(rims.len(), 2, "{rims:?}");
    let z: Vec<f32> = rims.iter().map(|&v| tube.positions[v as usize][2]).collect();
    assert_eq!(z, [0.0, 2.0]);
    // An anchor on one rim already: only the other gets one.
    let on_top = (0..72).find(|&v| tube.positions[v as usize][2] == 2.0).unwrap() as u32;
    let other = anchors(&tube, &[on_top]);
    assert_eq!(other.len(), 1);
    assert_eq!(tube.positions[other[0] as usize][2], 0.0);
}

/// Nested L0 (anchors.rs, `nested_floors`): on a flat 32 × 32 grid with 8 cells per axis,
/// 64 anchors; the 4-cell grid keeps 16 of them, the 2-cell grid 4. Those 4 always stay; the
/// other 12 of the 4-cell grid get (κ · 8)², the 48 left (κ · 4)².
#[test]
fn nested_anchors_get_the_floor_of_the_coarsest_grid_they_are_in() {
    use dynlod::lod::passes::anchors::nested_floors;
    let mesh = build(&procedural::grid(32, 32, |_, _| false));
    let (t, p) = (&mesh.topology, &mesh.positions);
    let e = vertex_errors(t, p, &vertex_normals(t, p));
    let o = AnchorOptions::default().cells(8).nested(Some(0.25));
    let l0 = select_anchors(t, p, &e, &o).swap_remove(0);
    assert_eq!(l0.len(), 64);
    let floors = nested_floors(t, p, &e, &l0, &o);
    let count = |f: f32| floors.iter().filter(|&&x| x == f).count();
    assert_eq!((count(f32::INFINITY), count(4.0), count(1.0)), (4, 12, 48), "{floors:?}");
    // Each coarser set is picked among the finer one: the 4 that stay are one per quadrant.
    let stay: Vec<[f32; 3]> =
        l0.iter().zip(&floors).filter(|(_, f)| f.is_infinite()).map(|(&v, _)| p[v as usize]).collect();
    for (qx, qy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let inside = |c: f32, q: i32| (c >= 16.0 * q as f32) && (c <= 16.0 * (q + 1) as f32);
        assert_eq!(stay.iter().filter(|s| inside(s[0], qx) && inside(s[1], qy)).count(), 1, "{stay:?}");
    }
    // Without nesting, every L0 anchor always stays (the paper's L0).
    assert!(nested_floors(t, p, &e, &l0, &o.clone().nested(None)).iter().all(|f| f.is_infinite()));
}
