//! The Hausdorff metric against cases whose distances are known exactly, and its BVH against
//! brute force.

use dynlod::metrics::{closest_on_triangle, hausdorff, Bvh, HausdorffOptions};
use dynlod::{procedural, IndexedMesh};
use proptest::prelude::*;

fn close(a: f64, b: f64, eps: f64) -> bool {
    (a - b).abs() <= eps
}

fn translated(mut m: IndexedMesh, d: [f32; 3]) -> IndexedMesh {
    for p in &mut m.positions {
        *p = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
    }
    m
}

#[test]
fn a_mesh_is_at_distance_zero_from_itself() {
    let m = procedural::torus(16, 8);
    let h = hausdorff(&m, &m, HausdorffOptions::default());
    // Interior samples are interpolated in f32, so "zero" is a few ulps of the diagonal.
    assert!(h.pct(h.max) < 1e-5, "{h:?}");
    assert_eq!(h.forward, h.backward);
    assert!(h.forward.samples >= 10 * m.triangles.len() / 2);
}

#[test]
fn plane_against_displaced_plane_is_the_displacement_everywhere() {
    let a = procedural::grid(6, 4, |i, j| (i + j) % 2 == 0);
    let b = translated(procedural::grid(3, 2, |_, _| false), [0.0, 0.0, 0.25]);
    // b spans half the extent of a in x and y: scale it up to match.
    let b = IndexedMesh { positions: b.positions.iter().map(|p| [p[0] * 2.0, p[1] * 2.0, p[2]]).collect(), ..b };
    let h = hausdorff(&a, &b, HausdorffOptions::default());
    for s in [h.forward, h.backward] {
        assert!(close(s.max, 0.25, 1e-6) && close(s.mean, 0.25, 1e-6) && close(s.rms, 0.25, 1e-6), "{s:?}");
    }
    let diag = (36.0f64 + 16.0).sqrt();
    assert!(close(h.diagonal, diag, 1e-5));
    assert!(close(h.pct(h.max), 100.0 * 0.25 / diag, 1e-5));
}

#[test]
fn nested_cubes_give_the_offset_one_way_and_the_corner_gap_the_other() {
    let d = 0.1f32;
    let inner = procedural::cube(1.0);
    let outer = procedural::cube(1.0 + d);
    let h = hausdorff(&inner, &outer, HausdorffOptions::default());
    // Every point of the inner cube is exactly d from the outer one.
    assert!(close(h.forward.max, d as f64, 1e-6) && close(h.forward.rms, d as f64, 1e-6), "{:?}", h.forward);
    // The outer corners are d·√3 from the inner corners; faces are d away.
    assert!(close(h.backward.max, d as f64 * 3f64.sqrt(), 1e-6), "{:?}", h.backward);
    assert!(h.backward.mean > d as f64 && h.backward.mean < d as f64 * 3f64.sqrt());
    assert!(close(h.max, h.backward.max, 0.0));
}

#[test]
fn octahedron_inscribed_in_a_sphere_is_one_minus_inverse_sqrt3_away() {
    // Octahedron vertices lie on the unit sphere; its face centres are 1/√3 from the centre,
    // and the sphere points over them are 1 − 1/√3 from the octahedron.
    let sphere = procedural::uv_sphere(64, 128);
    let oct = procedural::octahedron();
    let exact = 1.0 - 1.0 / 3f64.sqrt();
    // The tessellated sphere lies inside the true one by at most its sagitta.
    let sagitta = 1.0 - (std::f64::consts::PI / 64.0).cos();
    let h = hausdorff(&sphere, &oct, HausdorffOptions::default());
    assert!(h.forward.max <= exact + 1e-5 && h.forward.max >= exact - sagitta - 1e-5, "{:?} vs {exact}", h.forward);
    // The other way, sample the octahedron densely so some sample sits next to a face centre.
    let corners = |m: &IndexedMesh| -> Vec<[[f32; 3]; 3]> {
        m.triangles.iter().map(|t| t.map(|i| m.positions[i as usize])).collect()
    };
    let bvh = Bvh::new(&corners(&sphere));
    let far = dynlod::metrics::sample(&corners(&oct), 5000.0)
        .into_iter()
        .map(|p| (bvh.nearest(p).unwrap().dist2 as f64).sqrt())
        .fold(0.0, f64::max);
    assert!(far <= exact + 1e-5 && far >= exact - sagitta - 1e-4, "{far} vs {exact}");
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let a = procedural::torus(24, 12);
    let b = procedural::torus(12, 6);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| hausdorff(&a, &b, HausdorffOptions::default()))
    };
    assert_eq!(run(1), run(2));
    assert_eq!(run(1), run(3));
}

fn brute(p: [f32; 3], tris: &[[[f32; 3]; 3]]) -> f32 {
    let q = glam::Vec3A::from(p);
    tris.iter()
        .map(|t| (closest_on_triangle(q, &t.map(glam::Vec3A::from)) - q).length_squared())
        .fold(f32::INFINITY, f32::min)
}

proptest! {
    #[test]
    fn bvh_nearest_equals_brute_force(
        tris in prop::collection::vec(prop::array::uniform3(prop::array::uniform3(-10.0f32..10.0)), 1..80),
        pts in prop::collection::vec(prop::array::uniform3(-15.0f32..15.0), 1..40),
    ) {
        let bvh = Bvh::new(&tris);
        for p in pts {
            let n = bvh.nearest(p).unwrap();
            prop_assert_eq!(n.dist2, brute(p, &tris));
            let t = tris[n.triangle as usize].map(glam::Vec3A::from);
            let q = closest_on_triangle(glam::Vec3A::from(p), &t);
            prop_assert_eq!(<[f32; 3]>::from(q), n.point);
        }
    }
}
