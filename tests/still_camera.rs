//! A still camera costs nothing once the mesh has settled
//! ([`RuntimeOptions::skip_unchanged_frames`]), and skipping changes nothing: frame by frame
//! the same figures, mesh and index buffer as full updates.

mod common;

use common::surfaces;
use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::lod::{FrameStats, Runtime, RuntimeOptions};
use dynlod::view::View;
use dynlod::{BuildOptions, Mesh};
use proptest::prelude::*;

fn bunny() -> Mesh {
    dynlod::load_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz"), BuildOptions::default())
        .unwrap()
}

/// What a frame did and left, times and `skipped` aside.
type Figures = (usize, usize, usize, usize, usize, usize, usize, u32, u16, u64);

fn figures(s: &FrameStats) -> Figures {
    (
        s.collapses,
        s.splits,
        s.rebalanced,
        s.rebalance_attempts,
        s.triangles,
        s.vertices,
        s.changed_triangles,
        s.pixel_error.to_bits(),
        s.max_chain_depth,
        s.mean_chain_depth.to_bits(),
    )
}

/// The renderer's view of the runtime: every part's triangles.
fn drawn(rt: &Runtime) -> Vec<Vec<[u32; 3]>> {
    rt.index_buffer().parts().iter().map(|p| p.triangles().to_vec()).collect()
}

/// Flies `views` with and without skipping; asserts the same figures after every frame and
/// the same mesh and index buffer at the end. Returns which frames were skipped.
fn skip_against_full(mesh: &Mesh, options: RuntimeOptions, views: &[View]) -> Vec<bool> {
    let mut skip = Runtime::new(mesh.clone(), options.clone().skip_unchanged_frames(true));
    let mut full = Runtime::new(mesh.clone(), options.skip_unchanged_frames(false));
    let mut skipped = Vec::new();
    for (k, v) in views.iter().enumerate() {
        let (a, b) = (skip.update(Some(v)), full.update(Some(v)));
        assert!(!b.skipped, "frame {k}: skipped with skipping off");
        assert_eq!(figures(&a), figures(&b), "frame {k}: {a:?}");
        assert_eq!((a.frame, a.stop), (b.frame, b.stop));
        skipped.push(a.skipped);
    }
    assert_eq!(drawn(&skip), drawn(&full));
    let (mut a, mut b) = (skip.into_mesh(), full.into_mesh());
    a.topology.rebuild_vertex_links();
    b.topology.rebuild_vertex_links();
    assert!(a == b, "the meshes differ");
    skipped
}

/// The bunny under a still camera, rebalancing on: the full updates settle (no edit and, since
/// a failed move is not tried again before something changes, no rebalancing attempt), and
/// from soon after the last frame that did something every update is skipped, with the same
/// figures, mesh and index buffer as the full ones.
#[test]
fn a_still_camera_is_skipped_once_nothing_changes() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let view = CameraPath::Orbit.view(30, 360, centre, diag, (1920, 1080));
    for budget in [None, Some(5_000)] {
        let mut full = Runtime::new(m.clone(), RuntimeOptions::default().budget(budget).skip_unchanged_frames(false));
        let stats: Vec<FrameStats> = (0..100).map(|_| full.update(Some(&view))).collect();
        let last_active = stats
            .iter()
            .rposition(|s| s.collapses + s.splits + s.rebalance_attempts + s.changed_triangles > 0)
            .unwrap();
        assert!(last_active < 60, "{budget:?}: still working on frame {last_active}");
        let skipped = skip_against_full(&m, RuntimeOptions::default().budget(budget), &vec![view; 100]);
        let first = skipped.iter().position(|&s| s).expect("no frame skipped");
        // A move that failed before the last change is tried again (and fails) up to 16
        // frames later; until then the frame is not known to repeat.
        assert!(first > last_active && first <= last_active + 17, "{budget:?}: {first} after {last_active}");
        assert!(skipped[first..].iter().all(|&s| s), "{budget:?}: a skipped frame was followed by a full one");
    }
}

/// Without a view (errors in model units) the same holds: repeated `update(None)` calls are
/// skipped once nothing changes, with the figures of full updates.
#[test]
fn view_independent_updates_are_skipped_too() {
    let m = bunny();
    let options = RuntimeOptions::default().pixel_error(2e-4);
    let mut skip = Runtime::new(m.clone(), options.clone());
    let mut full = Runtime::new(m, options.skip_unchanged_frames(false));
    let mut skipped = 0;
    for k in 0..300 {
        let (a, b) = (skip.update(None), full.update(None));
        assert_eq!(figures(&a), figures(&b), "frame {k}: {a:?}");
        skipped += usize::from(a.skipped);
    }
    assert!(skipped > 100, "{skipped} updates skipped");
    assert!(skip.triangles() < 30_000, "{} triangles: nothing coarsened", skip.triangles());
    assert_eq!(drawn(&skip), drawn(&full));
}

/// Anything but an update that changes the options or the mesh ends the skipping: the next
/// update with the same view does the work.
#[test]
fn a_changed_setting_or_a_hand_edit_is_not_skipped() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let view = CameraPath::Orbit.view(30, 360, centre, diag, (1920, 1080));
    let mut rt = Runtime::new(m, RuntimeOptions::default());
    let settle = |rt: &mut Runtime| {
        for _ in 0..100 {
            if rt.update(Some(&view)).skipped {
                return;
            }
        }
        panic!("not skipping after 100 frames");
    };
    settle(&mut rt);
    // Settings set again to the values in force change nothing (a renderer may set them
    // every frame).
    for _ in 0..5 {
        rt.set_pixel_error(1.0);
        rt.set_budget(None);
        rt.set_max_edits(None);
        rt.set_rebalance_moves(64);
        assert!(rt.update(Some(&view)).skipped);
    }
    // A finer threshold splits, under the same view.
    rt.set_pixel_error(0.5);
    let s = rt.update(Some(&view));
    assert!(!s.skipped && s.splits > 0, "{s:?}");
    settle(&mut rt);
    // A vertex split by hand comes back, collapsed by the next full update.
    let u = rt.hierarchy().front().next().unwrap();
    rt.split(u).unwrap();
    let s = rt.update(Some(&view));
    assert!(!s.skipped && s.collapses > 0, "{s:?}");
    settle(&mut rt);
    // In budget mode too: the budget in force set again keeps the controller as it was.
    let mut rt = Runtime::new(bunny(), RuntimeOptions::default().budget(Some(5_000)));
    settle(&mut rt);
    for _ in 0..5 {
        rt.set_budget(Some(5_000));
        rt.set_pixel_error(1.0);
        assert!(rt.update(Some(&view)).skipped);
    }
    rt.set_budget(Some(3_000));
    let s = rt.update(Some(&view));
    assert!(!s.skipped && s.collapses > 0 && s.triangles <= 3_000, "{s:?}");
    // Another view is never skipped, however close.
    let mut moved = view;
    moved.eye[0] = f32::from_bits(view.eye[0].to_bits() + 1);
    assert!(!rt.update(Some(&moved)).skipped);
}

/// `views`, each shown 1–4 times in a row, then the last one 40 more times.
fn repeated(views: &[View], seed: u64) -> Vec<View> {
    let mut s = seed | 1;
    let mut out = Vec::new();
    for v in views {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        out.extend(std::iter::repeat_n(*v, 1 + (s % 4) as usize));
    }
    out.extend(std::iter::repeat_n(*views.last().unwrap(), 40));
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(24), ..ProptestConfig::default() })]

    /// Random meshes on camera paths whose views repeat, pixel-error and budget modes,
    /// rebalancing on: skipping gives what full updates give, frame by frame, and the still
    /// camera at the end is skipped.
    #[test]
    fn skipping_repeated_views_changes_nothing(m in surfaces(), seed in any::<u64>(), share in prop::option::of(0.05f64..1.2)) {
        let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
        let (centre, diag) = frame_bounds(&mesh.positions);
        let path = [CameraPath::Orbit, CameraPath::Dolly, CameraPath::Zoom][(seed % 3) as usize];
        let views: Vec<View> = (0..30).map(|f| path.view(f, 30, centre, diag, (640, 480))).collect();
        let budget = share.map(|s| ((mesh.topology.live_face_count() as f64 * s) as usize).max(1));
        let options = RuntimeOptions::default().audit(true).budget(budget);
        let skipped = skip_against_full(&mesh, options, &repeated(&views, seed));
        prop_assert!(*skipped.last().unwrap(), "the still camera is not skipped");
    }
}

/// Under a still camera, rebalancing does not spend a frame's attempts on records its
/// counters turn away before any split (`lod/rebalance.rs`, idle frames): those frames look
/// at more than 64 records, moving frames at 64 at most, and the bunny's still camera from
/// its cold start settles (its updates skipped) within 35 frames, where spending the attempts
/// on such records took 51, and igea 277 (docs/BENCHMARKS.md, "A still camera").
#[test]
fn a_still_camera_settles_within_a_few_dozen_frames() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let mut rt = Runtime::new(m.clone(), RuntimeOptions::default());
    let view = CameraPath::Orbit.view(0, 360, centre, diag, (1920, 1080));
    let (mut moves, mut widest, mut settled) = (0, 0, None);
    for f in 0..100 {
        let s = rt.update(Some(&view));
        widest = widest.max(s.rebalance_attempts);
        moves += s.rebalanced;
        if s.skipped {
            settled = Some(f);
            break;
        }
    }
    let settled = settled.expect("a still camera not settled in 100 frames");
    assert!(settled <= 35 && moves > 100, "settled after {settled} frames, {moves} moves");
    assert!(widest > 64, "no still frame looked past 64 records ({widest})");
    let mut rt = Runtime::new(m, RuntimeOptions::default());
    for f in 0..60 {
        let s = rt.update(Some(&CameraPath::Orbit.view(f, 360, centre, diag, (1920, 1080))));
        assert!(s.rebalance_attempts <= 64, "moving frame {f}: {} attempts", s.rebalance_attempts);
    }
}
