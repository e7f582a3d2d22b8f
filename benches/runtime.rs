//! The frame-to-frame runtime (papers/001 + papers/000) against rebuilding every frame.
//!
//! Per mesh: the runtime is warmed at the start of an orbit (2 bounding-box diagonals away,
//! 1 px at 1920×1080), then each timed iteration moves the camera 1° and calls `update`
//! (a warm frame). Side by side, in the same run: `meshopt::simplify` rebuilding the same
//! triangle count from the full mesh (what a renderer without a runtime pays per frame), and
//! our own cold start (`Runtime::new` + one `update`) for the same view; and the same orbit
//! through orthographic cameras (`camera_path::orthographic`) beside meshopt rebuilding
//! its triangle count; and a still camera once the mesh has settled, the frame skipped
//! (`RuntimeOptions::skip_unchanged_frames`) and run in full; two cameras on opposite sides
//! served by one runtime (`Runtime::update_views`) against one runtime each. Meshes: the bundled
//! bunny; `igea_triangles.ply` (269k) and a midpoint-subdivided igea (≈1.07M) when
//! `../shared/meshes` exists. Printed once per mesh (outside the timing): memory against
//! papers/001's 46n + 72m and Hu et al.'s 69n + 56m; the median and p99 warm frame over a
//! whole timed 360-frame orbit beside meshopt's rebuild and our cold start on sampled frames;
//! and (bunny) chain depths over a 360-frame walk with and without rebalancing. Then camera
//! cuts (`runtime_cuts/…`): the cut frame away and back, capped and not, beside meshopt. Then
//! (`runtime_scene/…`) a kept glTF scene, a runtime per mesh, against the same scene baked; and
//! a bunny drawn 36 times under one runtime, in instance groups, and as 36 distinct meshes.

use std::path::Path;

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use dynlod::camera_path::{frame_bounds, orthographic, CameraPath};
use dynlod::fly::{fly, FlyOptions};
use dynlod::lod::coarsen::Schedule;
use dynlod::lod::{Runtime, RuntimeOptions};
use dynlod::{BuildOptions, Mesh};

#[path = "support/meshopt_ref.rs"]
mod meshopt_ref;
#[path = "support/subdivide.rs"]
mod subdivide;
use subdivide::subdivide;

fn meshes() -> Vec<(String, Mesh)> {
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let mut out = vec![("bunny".to_string(), dynlod::load_mesh(bunny, BuildOptions::default()).unwrap())];
    let igea = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes/scans/igea_triangles.ply");
    if igea.exists() && std::env::var("DYNLOD_BENCH_SMALL").is_err() {
        let m = dynlod::load_mesh(&igea, BuildOptions::default()).unwrap();
        let sub = Mesh::build(&subdivide(&m.to_indexed()), BuildOptions::default()).unwrap();
        out.push(("igea".to_string(), m));
        out.push(("igea_x4".to_string(), sub));
    }
    out
}

fn report(name: &str, mesh: &Mesh) {
    let (centre, diag) = frame_bounds(&mesh.positions);
    let view = CameraPath::Orbit.view(0, 360, centre, diag, (1920, 1080));
    let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default());
    rt.update(Some(&view));
    let r = rt.memory_report();
    let (n, m) = (r.vertices as f64, r.active_vertices as f64);
    let total = r.total() as f64;
    eprintln!(
        "{name}: memory {:.1} MB for n = {} vertices, m = {} active: {:.1} B/n at this m; \
         papers/001 46n+72m = {:.1} MB, Hu et al. 69n+56m = {:.1} MB, goal 40n+48m = {:.1} MB",
        total / 1e6,
        r.vertices,
        r.active_vertices,
        total / n,
        (46.0 * n + 72.0 * m) / 1e6,
        (69.0 * n + 56.0 * m) / 1e6,
        (40.0 * n + 48.0 * m) / 1e6
    );
    let mut entries = r.entries.clone();
    entries.sort_by_key(|e| std::cmp::Reverse(e.1));
    for (k, b) in entries.iter().take(8) {
        eprintln!("  {k:<28} {:>8.2} B/n", *b as f64 / n);
    }
    percentiles(name, mesh);
    if name == "bunny" {
        for moves in [0usize, 64] {
            for path in [CameraPath::Orbit, CameraPath::Dolly] {
                let o = FlyOptions::default()
                    .path(path)
                    .frames(360)
                    .runtime(RuntimeOptions::default().rebalance_moves(moves));
                let f = fly(mesh.clone(), &o, |_| {}).unwrap();
                let max = f.frames.iter().map(|s| s.max_chain_depth).max().unwrap_or(0);
                let mean = f.frames.iter().map(|s| s.mean_chain_depth).sum::<f64>() / f.frames.len() as f64;
                let last = f.frames.last().unwrap();
                eprintln!(
                    "  {path:?} 360 frames, rebalancing {moves:>2}/frame: max chain depth {max}, mean over frames {mean:.3}, \
                     at the end max {} mean {:.3}",
                    last.max_chain_depth, last.mean_chain_depth
                );
            }
        }
    }
}

/// Median and 99th percentile (nearest rank) of a sample, in ms.
fn median_p99(mut t: Vec<f64>) -> (f64, f64) {
    t.sort_by(f64::total_cmp);
    let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
    (at(0.5), at(0.99))
}

/// The figure beside criterion's medians: a whole 360-frame orbit (1° per frame, 1 px
/// at 1920×1080), every warm frame timed, for both schedules; in the same run meshopt
/// rebuilding each 10th frame's triangle count from the full mesh, and our cold start on each
/// 60th frame's view (so its "p99" is the largest of 6).
fn percentiles(name: &str, mesh: &Mesh) {
    let flat = mesh.to_indexed();
    let indices: Vec<u32> = flat.triangles.iter().flatten().copied().collect();
    let (centre, diag) = frame_bounds(&mesh.positions);
    for schedule in [Schedule::LocalMinima, Schedule::AllCandidates] {
        let o = FlyOptions::default().runtime(RuntimeOptions::default().schedule(schedule));
        let f = fly(mesh.clone(), &o, |_| {}).unwrap();
        let (median, p99) = f.warm_percentiles();
        let worst = f.frames.iter().skip(1).map(|s| s.total_ms).fold(0.0, f64::max);
        let (lo, hi) = f.triangle_range();
        eprintln!(
            "{name}: orbit, {schedule:?}: warm frame median {median:.3} ms, p99 {p99:.3} ms, max {worst:.3} ms \
             over {} warm frames ({lo}..{hi} triangles)",
            f.frames.len() - 1
        );
        if schedule != Schedule::LocalMinima {
            continue;
        }
        let rebuild = (1..f.frames.len())
            .step_by(10)
            .map(|i| {
                let start = std::time::Instant::now();
                std::hint::black_box(meshopt_ref::simplify_indices(&flat.positions, &indices, f.frames[i].triangles));
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect::<Vec<_>>();
        let (rm, rp) = median_p99(rebuild);
        let cold = (0..f.frames.len())
            .step_by(60)
            .map(|i| {
                let view = CameraPath::Orbit.view(i, 360, centre, diag, (1920, 1080));
                let start = std::time::Instant::now();
                let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default());
                rt.update(Some(&view));
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect::<Vec<_>>();
        let (cm, cp) = median_p99(cold);
        eprintln!(
            "{name}: same run: meshopt rebuild median {rm:.2} ms, p99 {rp:.2} ms (36 frames); \
             cold start median {cm:.1} ms, max {cp:.1} ms (6 frames); median ratio {:.0}x, p99 ratio {:.0}x",
            rm / median,
            rp / p99
        );
    }
}

fn bench(c: &mut Criterion) {
    for (name, mesh) in meshes() {
        report(&name, &mesh);
        let flat = mesh.to_indexed();
        let indices: Vec<u32> = flat.triangles.iter().flatten().copied().collect();
        let (centre, diag) = frame_bounds(&mesh.positions);
        let view = |f: usize| CameraPath::Orbit.view(f, 360, centre, diag, (1920, 1080));
        let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default());
        for f in 0..3 {
            rt.update(Some(&view(f)));
        }
        let target = rt.triangles();
        eprintln!("{name}: {} → {target} triangles at the orbit start", mesh.topology.live_face_count());
        let mut g = c.benchmark_group(format!("runtime/{name}"));
        g.sample_size(if name == "bunny" { 50 } else { 10 });
        let mut frame = 3usize;
        g.bench_function(BenchmarkId::new("warm_frame", target), |b| {
            b.iter(|| {
                frame += 1;
                rt.update(Some(&view(frame)))
            })
        });
        // The paper's schedule (every candidate every round), warmed the same way; it keeps
        // more triangles at the same pixel error (docs/ALGORITHM.md).
        let mut paper = Runtime::new(mesh.clone(), RuntimeOptions::default().schedule(Schedule::AllCandidates));
        for f in 0..3 {
            paper.update(Some(&view(f)));
        }
        let mut paper_frame = 3usize;
        g.bench_function(BenchmarkId::new("warm_frame_paper_schedule", paper.triangles()), |b| {
            b.iter(|| {
                paper_frame += 1;
                paper.update(Some(&view(paper_frame)))
            })
        });
        g.bench_function(BenchmarkId::new("meshopt_rebuild", target), |b| {
            b.iter(|| meshopt_ref::simplify_indices(&flat.positions, &indices, target))
        });
        // The same orbit through orthographic cameras framing what the perspective ones frame
        // at the centre, and meshopt rebuilding its triangle count.
        let ortho = |f: usize| orthographic(CameraPath::Orbit.view(f, 360, centre, diag, (1920, 1080)), centre);
        let mut orth = Runtime::new(mesh.clone(), RuntimeOptions::default());
        for f in 0..3 {
            orth.update(Some(&ortho(f)));
        }
        let ortho_target = orth.triangles();
        let mut ortho_frame = 3usize;
        g.bench_function(BenchmarkId::new("warm_frame_orthographic", ortho_target), |b| {
            b.iter(|| {
                ortho_frame += 1;
                orth.update(Some(&ortho(ortho_frame)))
            })
        });
        g.bench_function(BenchmarkId::new("meshopt_rebuild_orthographic", ortho_target), |b| {
            b.iter(|| meshopt_ref::simplify_indices(&flat.positions, &indices, ortho_target))
        });
        g.bench_function(BenchmarkId::new("cold_runtime", target), |b| {
            b.iter_batched(
                || mesh.clone(),
                |m| {
                    let mut cold = Runtime::new(m, RuntimeOptions::default());
                    cold.update(Some(&view(frame)));
                    cold
                },
                BatchSize::LargeInput,
            )
        });
        // A still camera once the mesh has settled: the frame skipped, and the same frame
        // run in full (classify, probe, no rebalancing left to try).
        for skip in [true, false] {
            let mut still = Runtime::new(mesh.clone(), RuntimeOptions::default().skip_unchanged_frames(skip));
            // Up to 2,000 frames: the subdivided igea's still camera settled after 1,148 while
            // rebalancing spent its 64 attempts a frame on records turned away by their
            // counters; now after a few dozen (docs/BENCHMARKS.md, "A still camera").
            let settled = (0..2000).position(|_| {
                let s = still.update(Some(&view(3)));
                s.skipped || (!skip && s.collapses + s.splits + s.rebalance_attempts == 0)
            });
            let Some(after) = settled else { panic!("{name}: the still camera did not settle in 2,000 frames") };
            eprintln!("{name}: a still camera settled after {after} frames (skipping {skip})");
            let id = if skip { "still_frame_skipped" } else { "still_frame_full" };
            g.bench_function(BenchmarkId::new(id, still.triangles()), |b| b.iter(|| still.update(Some(&view(3)))));
        }
        two_cameras(&mut g, &mesh, centre, diag);
        g.finish();
        // Each cut iteration sets a runtime up afresh: seconds a time on the subdivided igea.
        if name != "igea_x4" {
            cuts(c, &name, &mesh, &flat.positions, &indices);
        }
    }
}

/// Two cameras orbiting on opposite sides (a split screen, `fly --cameras 2`): one runtime
/// serving both (`update_views`) against one runtime per camera, each timed iteration moving
/// both cameras 1°. The ids carry the triangles kept: one mesh for both, or each camera's.
fn two_cameras(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    mesh: &Mesh,
    centre: [f32; 3],
    diag: f32,
) {
    let pair = |f: usize| {
        [0.0, std::f32::consts::PI].map(|t| CameraPath::Orbit.view_turned(f, 360, centre, diag, (1920, 1080), t))
    };
    let mut shared = Runtime::new(mesh.clone(), RuntimeOptions::default());
    let mut each = [0, 1].map(|_| Runtime::new(mesh.clone(), RuntimeOptions::default()));
    for f in 0..3 {
        shared.update_views(&pair(f));
        for (rt, v) in each.iter_mut().zip(pair(f)) {
            rt.update(Some(&v));
        }
    }
    let mut frame = 3usize;
    g.bench_function(BenchmarkId::new("two_cameras_one_runtime", shared.triangles()), |b| {
        b.iter(|| {
            frame += 1;
            shared.update_views(&pair(frame))
        })
    });
    let mut frame = 3usize;
    let kept = format!("{}+{}", each[0].triangles(), each[1].triangles());
    g.bench_function(BenchmarkId::new("two_cameras_two_runtimes", kept), |b| {
        b.iter(|| {
            frame += 1;
            let views = pair(frame);
            [each[0].update(Some(&views[0])), each[1].update(Some(&views[1]))]
        })
    });
    let bytes = |rt: &Runtime| rt.memory_report().total();
    eprintln!(
        "two cameras: one runtime {} triangles, {} bytes; two runtimes {} + {} triangles, {} bytes",
        shared.triangles(),
        bytes(&shared),
        each[0].triangles(),
        each[1].triangles(),
        bytes(&each[0]) + bytes(&each[1])
    );
}

/// Camera cuts: a runtime warmed close up (0.6 diagonals) jumps to 40 diagonals away, and one
/// warmed there jumps back; each timed iteration is the cut frame alone, on a runtime set up
/// afresh (untimed). Beside it: the same cut capped at 2,000 edits (the first of the frames
/// it spreads over), and meshopt rebuilding the far view's triangle count.
fn cuts(c: &mut Criterion, name: &str, mesh: &Mesh, positions: &[[f32; 3]], indices: &[u32]) {
    let (centre, diag) = frame_bounds(&mesh.positions);
    let at = |d: f32| {
        let eye = [centre[0], centre[1] + 0.3 * d * diag, centre[2] + d * diag];
        dynlod::view::View::perspective(eye, centre, [0.0, 1.0, 0.0], 45.0, (1920, 1080))
    };
    let (near, far) = (at(0.6), at(40.0));
    let warmed = |views: &[&dynlod::view::View], cap: Option<usize>| {
        let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default());
        for v in views {
            rt.update(Some(v));
        }
        rt.set_max_edits(cap);
        rt
    };
    let far_count = {
        let mut rt = warmed(&[&near, &near], None);
        rt.update(Some(&far));
        rt.triangles()
    };
    let mut g = c.benchmark_group(format!("runtime_cuts/{name}"));
    g.sample_size(10);
    g.bench_function(BenchmarkId::new("cut_away", far_count), |b| {
        b.iter_batched(|| warmed(&[&near, &near], None), |mut rt| rt.update(Some(&far)), BatchSize::PerIteration)
    });
    g.bench_function(BenchmarkId::new("cut_away_capped_2000", far_count), |b| {
        b.iter_batched(|| warmed(&[&near, &near], Some(2000)), |mut rt| rt.update(Some(&far)), BatchSize::PerIteration)
    });
    g.bench_function(BenchmarkId::new("jump_in", far_count), |b| {
        b.iter_batched(|| warmed(&[&near, &far, &far], None), |mut rt| rt.update(Some(&near)), BatchSize::PerIteration)
    });
    g.bench_function(BenchmarkId::new("meshopt_rebuild", far_count), |b| {
        b.iter(|| meshopt_ref::simplify_indices(positions, indices, far_count))
    });
    g.finish();
}

/// A kept glTF scene (`SceneRuntime`, `fly --instanced`) against the same scene baked into
/// one mesh under one runtime: warm orbit frames around the scene's world bounds (2
/// diagonals, 1° a frame), when `../shared/meshes/gltf/2CylinderEngine.glb` exists (29 meshes
/// drawn by 67 nodes), at 1 px and under a budget of 30,000 triangles (the kept scene's for
/// all it draws). The ids carry the triangles drawn.
fn kept_scene(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes/gltf/2CylinderEngine.glb");
    if !path.exists() {
        return;
    }
    let scene = dynlod::io::GltfScene::load(&path).unwrap();
    let (lo, hi) = scene.world_bounds();
    let (centre, diag) = dynlod::camera_path::frame_box(lo, hi);
    let view = |f: usize| CameraPath::Orbit.view(f, 360, centre, diag, (1920, 1080));
    let mut g = c.benchmark_group("runtime_scene/2CylinderEngine");
    g.sample_size(30);
    for (mode, budget) in [("", None), ("budget_", Some(30_000))] {
        let options = RuntimeOptions::default().budget(budget);
        let mut kept = dynlod::lod::SceneRuntime::new(&scene, BuildOptions::default(), options.clone()).unwrap();
        let mut baked = Runtime::new(dynlod::load_mesh(&path, BuildOptions::default()).unwrap(), options);
        for f in 0..3 {
            kept.update(&[view(f)]);
            baked.update(Some(&view(f)));
        }
        let mut frame = 3usize;
        g.bench_function(BenchmarkId::new(format!("kept_{mode}warm_frame"), kept.drawn_triangles()), |b| {
            b.iter(|| {
                frame += 1;
                kept.update(&[view(frame)]).len()
            })
        });
        let mut frame = 3usize;
        g.bench_function(BenchmarkId::new(format!("baked_{mode}warm_frame"), baked.triangles()), |b| {
            b.iter(|| {
                frame += 1;
                baked.update(Some(&view(frame)))
            })
        });
        eprintln!(
            "2CylinderEngine {mode}: kept {} bytes for {} triangles drawn ({} px), baked {} bytes for {} ({} px)",
            kept.memory_bytes(),
            kept.drawn_triangles(),
            kept.screen_error(),
            baked.memory_report().total(),
            baked.triangles(),
            baked.screen_error()
        );
    }
    g.finish();
}

/// Instance groups (`SceneRuntime::set_instance_groups`): the bundled bunny drawn 36 times on
/// a 6 × 6 grid, a camera sliding back and forth along the near edge; warm frames with 1, 4
/// and 8 groups, beside 36 distinct bunnies under a runtime each (what per-instance detail
/// draws, at 36 runtimes' memory). The ids carry the triangles drawn.
fn instance_groups(c: &mut Criterion) {
    let bunny = dynlod::load_mesh(
        concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz"),
        BuildOptions::default(),
    )
    .unwrap();
    let at = |n: usize| {
        let (x, z) = (0.25 * (n % 6) as f32, -0.25 * (n / 6) as f32);
        [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [x, 0.0, z, 1.0]]
    };
    let view = |f: usize| {
        let x = 0.002 * (f % 400).min(400 - f % 400) as f32;
        dynlod::view::View::perspective([x, 0.15, 0.3], [x + 0.2, 0.0, -1.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080))
    };
    let mut g = c.benchmark_group("runtime_scene/bunny_x36");
    g.sample_size(10);
    let instanced = || vec![(bunny.clone(), (0..36).map(at).collect::<Vec<_>>())];
    let distinct = || (0..36).map(|n| (bunny.clone(), vec![at(n)])).collect::<Vec<_>>();
    for (name, meshes, groups) in [
        ("one_runtime", instanced(), 1),
        ("groups_4", instanced(), 4),
        ("groups_8", instanced(), 8),
        ("distinct", distinct(), 1),
    ] {
        let mut scene = dynlod::lod::SceneRuntime::from_meshes(meshes, RuntimeOptions::default()).unwrap();
        scene.set_instance_groups(groups);
        for f in 0..5 {
            scene.update(&[view(f)]);
        }
        let mut frame = 5usize;
        g.bench_function(BenchmarkId::new(name, scene.drawn_triangles()), |b| {
            b.iter(|| {
                frame += 1;
                scene.update(&[view(frame)]).len()
            })
        });
        eprintln!(
            "bunny x36 {name}: {} triangles drawn, {} held, {} bytes, {} px",
            scene.drawn_triangles(),
            scene.held_triangles(),
            scene.memory_bytes(),
            scene.screen_error()
        );
    }
    g.finish();
}

criterion_group!(benches, bench, kept_scene, instance_groups);
criterion_main!(benches);
