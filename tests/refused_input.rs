//! Input the level-of-detail passes cannot use (a NaN camera, an eye on its target, a field of
//! view of 0° or 180°, an empty viewport, an orthographic height of 0, a negative or NaN pixel
//! error) is refused by name and changes nothing: `Runtime::update` and `SceneRuntime::update`
//! (`FrameStop::Refused`), papers/000's rounds (`CoarsenStop::Refused`), `Runtime::cut` (`Err`),
//! and the command line (exit 2 with the reason).

mod common;

use common::runtime::walk;
use common::{dynlod, surfaces};
use dynlod::camera_path::frame_bounds;
use dynlod::lod::coarsen::{coarsen_views, CoarsenOptions, CoarsenStop};
use dynlod::lod::{FrameStats, FrameStop, InputError, Runtime, RuntimeOptions, SceneRuntime};
use dynlod::view::{View, ViewError};
use dynlod::{BuildOptions, Mesh};
use proptest::prelude::*;

const IDENTITY: [[f32; 4]; 4] =
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];

/// Views that cannot be used, each with what is wrong with it, around a mesh at `centre`.
fn bad_views(centre: [f32; 3], diag: f32) -> Vec<(View, ViewError)> {
    let up = [0.0, 1.0, 0.0];
    let eye = [centre[0], centre[1], centre[2] + 2.0 * diag];
    let nan = f32::NAN;
    vec![
        (View::perspective([nan, eye[1], eye[2]], centre, up, 60.0, (640, 480)), ViewError::Eye),
        (View::perspective(centre, centre, up, 60.0, (640, 480)), ViewError::Direction),
        (View::perspective(eye, centre, up, 0.0, (640, 480)), ViewError::FieldOfView),
        (View::perspective(eye, centre, up, 180.0, (640, 480)), ViewError::FieldOfView),
        (View::perspective(eye, centre, up, nan, (640, 480)), ViewError::FieldOfView),
        (View::perspective(eye, centre, up, 60.0, (0, 480)), ViewError::Viewport),
        (View::orthographic(eye, centre, up, 0.0, (640, 480)), ViewError::Height),
        (View::orthographic(eye, centre, up, nan, (640, 480)), ViewError::Height),
    ]
}

/// A frame's figures without its times (which no two runs share).
fn figures(s: &FrameStats) -> FrameStats {
    FrameStats {
        classify_ms: 0.0,
        split_ms: 0.0,
        collapse_ms: 0.0,
        rebalance_ms: 0.0,
        output_ms: 0.0,
        total_ms: 0.0,
        ..*s
    }
}

fn index_buffer(rt: &Runtime) -> Vec<Vec<[u32; 3]>> {
    rt.index_buffer().parts().iter().map(|p| p.triangles().to_vec()).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(24), ..ProptestConfig::default() })]

    /// Unusable views slipped in anywhere in a random walk, alone or beside the walk's own
    /// view, in pixel-error and in budget mode: each such update is refused naming the view
    /// and its fault, leaves the mesh, the index buffer and the frame count as they were and
    /// reports no changed range, and every other frame, and the end, are those of the walk
    /// without them.
    #[test]
    fn refused_updates_change_nothing(
        m in surfaces(),
        seed in any::<u64>(),
        inserts in prop::collection::vec((0usize..24, 0usize..8, any::<bool>()), 1..6),
        budget in any::<bool>(),
    ) {
        let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
        let (centre, diag) = frame_bounds(&mesh.positions);
        let views = walk(seed, 24, centre, diag);
        let bad = bad_views(centre, diag);
        let budget = budget.then_some(mesh.topology.live_face_count() / 3);
        let options = RuntimeOptions::default().budget(budget).audit(true);
        let (mut plain, mut tried) = (Runtime::new(mesh.clone(), options.clone()), Runtime::new(mesh.clone(), options));
        for (f, v) in views.iter().enumerate() {
            for &(at, which, beside) in inserts.iter().filter(|i| i.0 == f) {
                let (view, fault) = bad[which];
                let (before, ib, faces) = (tried.triangles(), index_buffer(&tried), tried.mesh().topology.faces.clone());
                let (given, index) = if beside { (vec![*v, view], 1) } else { (vec![view], 0) };
                let s = tried.update_views(&given);
                prop_assert_eq!(s.stop, FrameStop::Refused(InputError::View { index, error: fault }), "frame {}", at);
                prop_assert_eq!((s.collapses, s.splits, s.triangles, s.changed_ranges), (0, 0, before, 0));
                prop_assert_eq!(s.frame, f as u64, "a refused update is not a frame");
                prop_assert!(tried.index_buffer().parts().iter().all(|p| p.changed_ranges().is_empty()));
                prop_assert!(index_buffer(&tried) == ib && tried.mesh().topology.faces == faces);
                prop_assert!(tried.screen_error_in(&view).is_nan(), "no pixels to measure in");
            }
            let (a, b) = (plain.update(Some(v)), tried.update(Some(v)));
            prop_assert_eq!(figures(&a), figures(&b), "frame {}", f + 1);
            prop_assert!(a.stop != FrameStop::Refused(InputError::PixelError));
        }
        prop_assert!(index_buffer(&plain) == index_buffer(&tried));
        prop_assert!(plain.mesh().topology.faces == tried.mesh().topology.faces);
        tried.hierarchy().check(&tried.mesh().topology).unwrap();
    }
}

/// A negative or NaN pixel error is refused on every update until it is set right, and the
/// mesh is then coarsened as if the refused updates had never been asked for.
#[test]
fn a_negative_or_nan_pixel_error_is_refused() {
    let mesh = Mesh::build(&dynlod::procedural::torus(64, 32), BuildOptions::default()).unwrap();
    let view = common::view_from_diagonals(&mesh, 8.0, (640, 480));
    let full = mesh.topology.live_face_count();
    for px in [-1.0, f32::NAN, -0.0 - f32::MIN_POSITIVE] {
        let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default().pixel_error(px));
        for _ in 0..2 {
            let s = rt.update(Some(&view));
            assert_eq!(s.stop, FrameStop::Refused(InputError::PixelError), "{px}");
            assert_eq!((s.triangles, s.frame), (full, 0));
        }
        rt.set_pixel_error(1.0);
        let s = rt.update(Some(&view));
        let mut fresh = Runtime::new(mesh.clone(), RuntimeOptions::default());
        assert_eq!(figures(&s), figures(&fresh.update(Some(&view))));
        assert!(s.triangles < full / 2, "{s:?}");
    }
    // 0 keeps all the views see, and infinity takes all they allow: neither is refused.
    for px in [0.0, f32::INFINITY] {
        let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default().pixel_error(px));
        assert_eq!(rt.update(Some(&view)).stop, FrameStop::Converged, "{px}");
    }
    // A hysteresis set below 1 by hand (the builder clamps it) is refused too.
    let mut options = RuntimeOptions::default();
    options.hysteresis = 0.5;
    let mut rt = Runtime::new(mesh.clone(), options);
    assert_eq!(rt.update(Some(&view)).stop, FrameStop::Refused(InputError::Hysteresis));
    assert_eq!(rt.update(None).stop, FrameStop::Refused(InputError::Hysteresis));
}

/// papers/000's rounds and the runtime's cut refuse what the runtime refuses, before they
/// touch the mesh.
#[test]
fn the_rounds_and_the_cut_refuse_unusable_views() {
    let mesh = Mesh::build(&dynlod::procedural::torus(64, 32), BuildOptions::default()).unwrap();
    let (centre, diag) = frame_bounds(&mesh.positions);
    let good = common::view_from_diagonals(&mesh, 8.0, (640, 480));
    for (view, fault) in bad_views(centre, diag) {
        let refusal = InputError::View { index: 1, error: fault };
        let mut m = mesh.clone();
        let s = coarsen_views(&mut m, &[good, view], CoarsenOptions::default());
        assert_eq!(s.stop, CoarsenStop::Refused(refusal));
        assert!(m == mesh && s.rounds.is_empty() && s.output_triangles == s.input_triangles);
        let cut = Runtime::cut(mesh.clone(), &[good, view], RuntimeOptions::default());
        assert_eq!(cut.err(), Some(refusal));
        let cut = Runtime::cut_to_triangles(mesh.clone(), &[good, view], RuntimeOptions::default(), 100);
        assert_eq!(cut.err(), Some(refusal));
    }
    let mut m = mesh.clone();
    let s = coarsen_views(&mut m, &[], CoarsenOptions::default().threshold(-1.0));
    assert_eq!(s.stop, CoarsenStop::Refused(InputError::PixelError));
    let cut = Runtime::cut(mesh.clone(), &[good], RuntimeOptions::default().pixel_error(f32::NAN));
    assert_eq!(cut.err(), Some(InputError::PixelError));
    // The same with usable views goes ahead.
    let cut = Runtime::cut(mesh.clone(), &[good], RuntimeOptions::default()).unwrap();
    assert!(cut.mesh.topology.live_face_count() < mesh.topology.live_face_count() / 2);
}

/// A kept scene refuses an unusable camera for every mesh, in pixel-error and budget mode, and
/// goes on afterwards as if it had not been given.
#[test]
fn a_scene_refuses_an_unusable_camera() {
    let torus = Mesh::build(&dynlod::procedural::torus(24, 12), BuildOptions::default()).unwrap();
    let sphere = Mesh::build(&dynlod::procedural::uv_sphere(12, 16), BuildOptions::default()).unwrap();
    let moved = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [4.0, 0.0, 0.0, 1.0]];
    let meshes = vec![(torus.clone(), vec![IDENTITY, moved]), (sphere, vec![moved])];
    let (centre, diag) = frame_bounds(&torus.positions);
    let good = common::view_from_diagonals(&torus, 3.0, (640, 480));
    for budget in [None, Some(300)] {
        let options = RuntimeOptions::default();
        let mut plain = SceneRuntime::from_meshes(meshes.clone(), options.clone()).unwrap();
        let mut tried = SceneRuntime::from_meshes(meshes.clone(), options).unwrap();
        plain.set_budget(budget);
        tried.set_budget(budget);
        for (view, fault) in bad_views(centre, diag) {
            let stats = tried.update(&[good, view]).to_vec();
            let refusal = FrameStop::Refused(InputError::View { index: 1, error: fault });
            assert!(stats.iter().all(|s| s.stop == refusal), "{stats:?}");
            assert_eq!(tried.drawn_triangles(), plain.drawn_triangles());
            let a: Vec<FrameStats> = plain.update(&[good]).iter().map(figures).collect();
            let b: Vec<FrameStats> = tried.update(&[good]).iter().map(figures).collect();
            assert_eq!(a, b, "budget {budget:?}");
        }
    }
}

/// The command line refuses such cameras and pixel errors with exit 2 and the reason, before
/// reading the mesh.
#[test]
fn the_command_line_refuses_unusable_cameras() {
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let out = std::env::temp_dir().join(format!("dynlod-refused-{}.ply", std::process::id()));
    let out = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--eye", "0,0,0", "--target", "0,0,0", "--pixel-error", "1"], "the eye and the target coincide"),
        (&["--eye", "1,1,1", "--pixel-error", "-1"], "expected a number of pixels, 0 or more"),
        (&["--eye", "1,1,1", "--pixel-error", "nan"], "expected a number of pixels, 0 or more"),
        (&["--eye", "1,1,1", "--pixel-error", "1", "--fov", "-60"], "--fov must be in (0, 180)"),
        (&["--eye", "1,1,1", "--pixel-error", "1", "--width", "0"], "--width"),
        (&["--eye", "1,1,1", "--pixel-error", "1", "--ortho-height", "-2"], "--ortho-height must be a positive"),
        (&["--method", "parallel", "--error=-1"], "--error must be a non-negative number"),
        (&["--method", "runtime", "--error", "NaN"], "--error must be a non-negative number"),
    ];
    for (args, reason) in cases {
        let mut all = vec!["simplify", bunny, out];
        all.extend_from_slice(args);
        let (code, _, err) = dynlod(&all);
        assert_eq!(code, 2, "{all:?}: {err}");
        assert!(err.contains(reason), "{all:?}: {err}");
    }
    for args in [["--pixel-error", "-1"], ["--pixel-error", "nan"], ["--width", "0"], ["--height", "0"]] {
        let mut all = vec!["fly", bunny, "--frames", "2"];
        all.extend_from_slice(&args);
        let (code, _, err) = dynlod(&all);
        assert_eq!(code, 2, "{all:?}: {err}");
        assert!(err.contains(args[0]), "{all:?}: {err}");
    }
    assert!(!std::path::Path::new(out).exists(), "nothing written");
}
