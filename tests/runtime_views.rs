//! The runtime under several views at once (`Runtime::update_views`): a split screen, one
//! mesh drawn by several instances, the two eyes of a stereo camera. Every frame keeps the
//! runtime's invariants, no triangle turns against any eye, each view alone sees at most the
//! pixel error, and the result depends on the set of views, not their order or repeats.

mod common;

use common::runtime::{check, same_mesh, walk, FacingWatch};
use common::surfaces;
use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::lod::{FrameStats, FrameStop, Runtime, RuntimeOptions};
use dynlod::view::View;
use dynlod::{BuildOptions, Mesh};
use proptest::prelude::*;

fn bunny() -> Mesh {
    dynlod::load_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz"), BuildOptions::default())
        .unwrap()
}

/// The bunny orbit's views (2 diagonals, 1° a frame, 1920×1080) at `frames`.
fn orbit_at<const N: usize>(m: &Mesh, frames: [usize; N]) -> [View; N] {
    let (centre, diag) = frame_bounds(&m.positions);
    frames.map(|f| CameraPath::Orbit.view(f, 360, centre, diag, (1920, 1080)))
}

/// What a frame did: collapses, splits, moves, triangles, changed triangles, why it stopped.
type Edits = (usize, usize, usize, usize, usize, FrameStop);

/// What a frame did, without its timings and frame number.
fn edits(s: &FrameStats) -> Edits {
    (s.collapses, s.splits, s.rebalanced, s.triangles, s.changed_triangles, s.stop)
}

/// Flies `frames` (each a list of views) from the full mesh: the mesh at the end and each
/// frame's edits.
fn fly(m: &Mesh, frames: &[Vec<View>], options: &RuntimeOptions) -> (Mesh, Vec<Edits>) {
    let mut rt = Runtime::new(m.clone(), options.clone());
    let stats = frames.iter().map(|views| edits(&rt.update_views(views))).collect();
    (rt.into_mesh(), stats)
}

/// `k` random walks side by side, one view of each per frame; the second walk's views are
/// orthographic when `ortho` is set.
fn walks(seed: u64, k: usize, frames: usize, m: &Mesh, ortho: bool) -> Vec<Vec<View>> {
    let (centre, diag) = frame_bounds(&m.positions);
    let each: Vec<Vec<View>> =
        (0..k as u64).map(|j| walk(seed.wrapping_add(j * 0x9e37), frames, centre, diag)).collect();
    let lens = |j: usize, v: View| {
        if ortho && j == 1 {
            v.orthographic_at(glam::Vec3::from(v.eye).distance(glam::Vec3::from(centre)))
        } else {
            v
        }
    };
    (0..frames).map(|f| (0..k).map(|j| lens(j, each[j][f])).collect()).collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(24), ..ProptestConfig::default() })]

    /// Two or three cameras on random walks, one of them orthographic at times. After every
    /// frame: the runtime's invariants hold; no face that faced any eye turned away from it
    /// unless a split gave it back its original vertex; once converged, each view alone sees
    /// at most the pixel error and the runtime's screen error is the largest of the views'.
    /// Fully refined the walk gives the input. The views reversed, or the first one repeated,
    /// give the same frames; 1 and 2 threads agree.
    #[test]
    fn several_cameras_keep_the_mesh_valid_facing_every_eye_and_within_each_view(
        m in surfaces(), seed in any::<u64>(), px in 0.3f32..8.0, k in 2usize..4, ortho in any::<bool>()
    ) {
        let mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
        let s0 = mesh.topology.stats();
        let frames = walks(seed, k, 60, &mesh, ortho);
        let options = RuntimeOptions::default().audit(true).pixel_error(px);
        let mut rt = Runtime::new(mesh.clone(), options.clone());
        for views in &frames {
            let watch = FacingWatch::before(&rt, views);
            let s = rt.update_views(views);
            check(&rt, s0.euler, s0.boundary_loops);
            if let Some((f, j)) = watch.turned(&rt) {
                prop_assert!(false, "face {} turned away from eye {} without a split", f, j);
            }
            let each: Vec<f32> = views.iter().map(|v| rt.screen_error_in(v)).collect();
            prop_assert_eq!(rt.screen_error(), each.iter().copied().fold(0.0, f32::max));
            if s.stop == FrameStop::Converged {
                for (j, &e) in each.iter().enumerate() {
                    prop_assert!(e <= px * 1.0001, "view {} sees {} px, over {}", j, e, px);
                }
            }
        }
        rt.refine_fully();
        prop_assert!(same_mesh(rt.mesh(), &mesh));

        let (out, stats) = fly(&mesh, &frames, &options);
        let reversed: Vec<Vec<View>> = frames.iter().map(|v| v.iter().rev().copied().collect()).collect();
        let repeated: Vec<Vec<View>> = frames.iter().map(|v| [&v[..], &v[..1]].concat()).collect();
        for other in [reversed, repeated] {
            let (o, s) = fly(&mesh, &other, &options);
            prop_assert!(same_mesh(&o, &out));
            prop_assert_eq!(&s, &stats);
        }
        let two = common::on_threads(2, || fly(&mesh, &frames, &options));
        let one = common::on_threads(1, || fly(&mesh, &frames, &options));
        prop_assert!(one == two);
    }
}

/// One view given as a list is `update` with that view, frame for frame, and no view is
/// `update(None)`.
#[test]
fn one_view_in_a_list_is_an_update_with_that_view() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let path: Vec<View> = (0..30).map(|f| CameraPath::Dolly.view(f, 30, centre, diag, (1920, 1080))).collect();
    let (mut a, mut b) =
        (Runtime::new(m.clone(), RuntimeOptions::default()), Runtime::new(m.clone(), RuntimeOptions::default()));
    for v in &path {
        assert_eq!(edits(&a.update(Some(v))), edits(&b.update_views(std::slice::from_ref(v))));
    }
    assert!(a.mesh() == b.mesh());
    let options = RuntimeOptions::default().pixel_error(diag * 1e-3);
    let (mut a, mut b) = (Runtime::new(m.clone(), options.clone()), Runtime::new(m, options));
    assert_eq!(edits(&a.update(None)), edits(&b.update_views(&[])));
    assert!(a.mesh() == b.mesh() && a.triangles() < 25_000, "{} of 69,451 triangles", a.triangles());
}

/// Two cameras that each see what the other does not: in front of the bunny and behind it, 2
/// diagonals away; a split screen of two narrow cameras close up, on its left and right
/// halves. Together they keep what each needs (each sees at most the pixel error), more than
/// either keeps alone, where the cut for one camera shows the other over the pixel error.
#[test]
fn two_cameras_each_see_their_pixel_error() {
    let m = bunny();
    let (centre, diag) = frame_bounds(&m.positions);
    let up = [0.0, 1.0, 0.0];
    let at = |z: f32| View::perspective([centre[0], centre[1], centre[2] + z * diag], centre, up, 45.0, (1920, 1080));
    let half = |x: f32| {
        let t = [centre[0] + x * diag, centre[1], centre[2]];
        View::perspective([t[0], t[1], t[2] + 0.8 * diag], t, up, 25.0, (960, 1080))
    };
    let alone = |v: &View| {
        let mut rt = Runtime::new(m.clone(), RuntimeOptions::default());
        rt.update(Some(v));
        rt
    };
    for (a, b) in [(at(2.0), at(-2.0)), (half(-0.25), half(0.25))] {
        let (ra, rb) = (alone(&a), alone(&b));
        let mut both = Runtime::new(m.clone(), RuntimeOptions::default());
        let s = both.update_views(&[a, b]);
        let seen = [both.screen_error_in(&a), both.screen_error_in(&b), ra.screen_error_in(&b), rb.screen_error_in(&a)];
        let tris = [ra.triangles(), rb.triangles(), both.triangles()];
        assert_eq!(s.stop, FrameStop::Converged);
        assert!(seen[0] <= 1.0 && seen[1] <= 1.0, "{seen:?}");
        assert!(seen[2] > 1.0 && seen[3] > 1.0, "{seen:?}");
        assert!(tris[2] > tris[0].max(tris[1]) && tris[2] < tris[0] + tris[1], "{tris:?}");
    }
}

/// A still pair of cameras is a fixed point, and its frames are skipped once it has settled;
/// so are the same pair reversed and with a view repeated.
#[test]
fn a_still_pair_of_cameras_settles_and_is_skipped() {
    let m = bunny();
    let views = orbit_at(&m, [10, 190]);
    let mut rt = Runtime::new(m, RuntimeOptions::default());
    let first = rt.update_views(&views);
    assert!(first.collapses > 10_000, "{first:?}");
    let mut settled = None;
    for f in 0..200 {
        if rt.update_views(&views).skipped {
            settled = Some(f);
            break;
        }
    }
    assert!(settled.is_some(), "a still pair never settled");
    let reversed = [views[1], views[0]];
    assert!(rt.update_views(&reversed).skipped);
    assert!(rt.update_views(&[views[0], views[1], views[0]]).skipped);
    // One of them alone is not the pair: that frame collapses what only the other needed.
    let alone = rt.update_views(&views[..1]);
    assert!(!alone.skipped && alone.collapses > 100, "{alone:?}");
}

/// Budget mode counts the mesh once, however many views see it: two cameras settle under
/// the same budget one does, at a higher threshold.
#[test]
fn a_budget_covers_the_mesh_once_for_every_view() {
    let m = bunny();
    let views = orbit_at(&m, [0, 120, 240]);
    let budget = 3_000;
    let settle = |views: &[View]| {
        let mut rt = Runtime::new(m.clone(), RuntimeOptions::default().budget(Some(budget)));
        let mut last = rt.update_views(views);
        for _ in 0..10 {
            last = rt.update_views(views);
        }
        (last, rt)
    };
    let (one, _) = settle(&views[..1]);
    let (three, rt) = settle(&views);
    for s in [&one, &three] {
        assert!(s.triangles <= budget && s.triangles > budget * 8 / 10, "{s:?}");
    }
    assert!(three.pixel_error > one.pixel_error, "one view {} px, three {} px", one.pixel_error, three.pixel_error);
    let each: Vec<f32> = views.iter().map(|v| rt.screen_error_in(v)).collect();
    assert!(each.iter().all(|&e| e <= three.pixel_error * 1.0001), "{each:?} over {}", three.pixel_error);
}
