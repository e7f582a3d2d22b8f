//! `View::in_model_space`: a world camera carried into a mesh's own space gives the pixel
//! errors and frustum tests of the mesh moved into the world, under any similarity; other
//! matrices are refused by name.

mod common;

use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::lod::passes::classify::{screen_error_in, ClassifyOptions};
use dynlod::lod::{Runtime, RuntimeOptions};
use dynlod::view::{Frustum, ModelMatrixError, View};
use dynlod::{procedural, BuildOptions, Mesh};
use glam::{Mat4, Quat, Vec3};
use proptest::prelude::*;

/// A similarity: rotation about `axis` by `angle`, uniform `scale`, a mirror in x or not, then
/// `shift`.
fn similarity(axis: [f32; 3], angle: f32, scale: f32, mirror: bool, shift: [f32; 3]) -> Mat4 {
    let axis = Vec3::from(axis).try_normalize().unwrap_or(Vec3::Z);
    let flip = if mirror { Vec3::new(-1.0, 1.0, 1.0) } else { Vec3::ONE };
    Mat4::from_translation(shift.into())
        * Mat4::from_quat(Quat::from_axis_angle(axis, angle))
        * Mat4::from_scale(flip * scale)
}

fn unit() -> impl Strategy<Value = [f32; 3]> {
    [-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0].prop_filter("not tiny", |v| Vec3::from(*v).length() > 0.1)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases(256)))]

    /// Pixels per unit, facing and the frustum test agree (to rounding) between the mesh
    /// moved into the world under the world view, and the mesh in its own space under the
    /// view carried there; so does the whole screen error where the frustum test is not
    /// decided by rounding. Perspective and orthographic views.
    #[test]
    fn a_view_in_model_space_sees_what_the_world_view_sees(
        axis in unit(), angle in -3.2f32..3.2, log_scale in -4.0f32..4.0, mirror: bool,
        shift in [-50.0f32..50.0, -50.0f32..50.0, -50.0f32..50.0],
        eye in [-60.0f32..60.0, -60.0f32..60.0, -60.0f32..60.0],
        target in [-60.0f32..60.0, -60.0f32..60.0, -60.0f32..60.0],
        fov in 20.0f32..100.0,
        points in prop::collection::vec((unit(), unit(), 1e-4f32..0.5), 16),
        orthographic: bool, height in 0.5f32..200.0,
    ) {
        let scale = log_scale.exp();
        let model = similarity(axis, angle, scale, mirror, shift);
        let world = if orthographic {
            View::orthographic(eye, target, [0.0, 1.0, 0.0], height, (1280, 720))
        } else {
            View::perspective(eye, target, [0.0, 1.0, 0.0], fov, (1280, 720))
        };
        prop_assume!(Vec3::from(eye).distance(Vec3::from(target)) > 1.0);
        let local = world.in_model_space(model.to_cols_array_2d()).unwrap();
        // A usable camera stays usable in any similarity's space (the runtime would refuse it).
        prop_assert_eq!((world.check(), local.check()), (Ok(()), Ok(())));
        let (fw, fm) = (Frustum::new(&world), Frustum::new(&local));
        let o = ClassifyOptions::default();
        for (p, n, g) in points {
            let pw = model.transform_point3(p.into()).to_array();
            // Normals go by the inverse transpose: for s·Q that is Q (up to length).
            let nw = model.transform_vector3(n.into()).normalize().to_array();
            prop_assume!(Vec3::from(pw).distance(Vec3::from(eye)) > 1e-2 * scale.max(1.0));
            let (a, b) = (fw.pixels_per_unit(pw) * scale, fm.pixels_per_unit(p));
            prop_assert!((a - b).abs() <= 1e-3 * a, "pixels per unit {a} against {b}");
            let (a, b) = (fw.facing(pw, nw), fm.facing(p, n));
            prop_assert!((a - b).abs() <= 1e-3, "facing {a} against {b}");
            let settled = fw.touches_sphere(pw, g * scale * 0.99) == fw.touches_sphere(pw, g * scale * 1.01);
            if settled {
                prop_assert_eq!(fw.touches_sphere(pw, g * scale), fm.touches_sphere(p, g));
                let near_silhouette = fw.facing(pw, nw).abs() < 1e-3;
                if !near_silhouette {
                    let a = screen_error_in(Some(&fw), pw, nw, (g * scale).powi(2), &o);
                    let b = screen_error_in(Some(&fm), p, n, g * g, &o);
                    prop_assert!((a - b).abs() <= 2e-3 * a, "screen error {a} against {b}");
                }
            }
        }
    }
}

/// A runtime on the mesh in its own space under carried views makes the decisions of a
/// runtime on the mesh moved into the world under the world's views.
#[test]
fn a_runtime_in_model_space_flies_like_one_in_the_world() {
    let input = procedural::torus(40, 80);
    let model = similarity([0.3, 1.0, -0.2], 0.9, 7.5, false, [120.0, -4.0, 33.0]);
    let mut moved = input.clone();
    for p in &mut moved.positions {
        *p = model.transform_point3((*p).into()).to_array();
    }
    let local_mesh = Mesh::build(&input, BuildOptions::default()).unwrap();
    let world_mesh = Mesh::build(&moved, BuildOptions::default()).unwrap();
    let (centre, diag) = frame_bounds(&world_mesh.positions);
    let mut in_world = Runtime::new(world_mesh, RuntimeOptions::default());
    let mut in_model = Runtime::new(local_mesh, RuntimeOptions::default());
    let matrix = model.to_cols_array_2d();
    let (mut sum_a, mut sum_b) = (0, 0);
    for f in 0..30 {
        let view = CameraPath::Dolly.view(f * 2, 60, centre, diag, (1280, 720));
        let a = in_world.update(Some(&view)).triangles;
        let b = in_model.update(Some(&view.in_model_space(matrix).unwrap())).triangles;
        // Rounding in the moved positions may tip a decision at the threshold, no more.
        // Rounding in the moved positions tips decisions at the threshold and breaks the
        // torus's many ties otherwise, and the layered grid anchors sit on the axes of each
        // space: a few per cent a frame (a scale or a turn lost would be far more).
        assert!(a.abs_diff(b) <= a / 20, "frame {f}: {a} triangles in the world, {b} in model space");
        (sum_a, sum_b) = (sum_a + a, sum_b + b);
    }
    assert!(sum_a.abs_diff(sum_b) <= sum_a / 100, "over the walk: {sum_a} against {sum_b}");
    assert!(in_world.triangles() < 6400 / 2, "the dolly must coarsen for this to mean anything");
}

#[test]
fn matrices_that_are_not_similarities_are_refused_by_name() {
    let world = View::perspective([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0], 60.0, (800, 600));
    let stretch = Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0));
    let e = world.in_model_space(stretch.to_cols_array_2d()).unwrap_err();
    assert_eq!(e, ModelMatrixError::NotSimilarity { scales: [1.0, 2.0, 1.0] });
    assert!(e.to_string().contains("scale the mesh's positions"), "{e}");
    let mut shear = Mat4::IDENTITY.to_cols_array_2d();
    shear[1][0] = 0.5; // y leans towards x
    assert!(matches!(world.in_model_space(shear), Err(ModelMatrixError::NotSimilarity { .. })));
    let zero = Mat4::from_scale(Vec3::ZERO).to_cols_array_2d();
    assert_eq!(world.in_model_space(zero), Err(ModelMatrixError::Singular { scale: 0.0 }));
    let mut nan = Mat4::IDENTITY.to_cols_array_2d();
    nan[3][1] = f32::NAN;
    assert_eq!(world.in_model_space(nan), Err(ModelMatrixError::NonFinite { column: 3, row: 1 }));
    let projection = Mat4::perspective_rh(1.0, 1.5, 0.1, 100.0).to_cols_array_2d();
    assert!(matches!(world.in_model_space(projection), Err(ModelMatrixError::NotAffine { .. })));
    // A similarity within rounding of one passes: a rotation built in f32, scaled by 3.
    let fine = similarity([1.0, 2.0, 3.0], 2.0, 3.0, true, [1.0, 2.0, 3.0]);
    assert!(world.in_model_space(fine.to_cols_array_2d()).is_ok());
}
