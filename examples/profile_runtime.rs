//! Profiling helper: flies the runtime around a mesh (default: the bundled bunny), checking
//! every frame, then refines fully and compares with the input. `perf record` this binary.
//! Arguments: [MESH] [FRAMES] [PIXEL_ERROR] [SCHEDULE: local-minima|all] [PATH: orbit|dolly|zoom]
//! `CHECK=1` audits and checks the hierarchy every frame.

use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::lod::coarsen::Schedule;
use dynlod::lod::{Runtime, RuntimeOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .map(String::as_str)
        .filter(|s| !s.is_empty())
        .unwrap_or(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz"));
    let frames: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(90);
    let px: f32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let schedule = args.get(4).and_then(|s| Schedule::from_name(s)).unwrap_or_default();
    let camera: CameraPath = args.get(5).and_then(|s| s.parse().ok()).unwrap_or(CameraPath::Orbit);
    let check = std::env::var("CHECK").is_ok();
    let before = dynlod::rss::resident();
    let base = dynlod::load_mesh(path, Default::default()).unwrap();
    let (centre, diag) = frame_bounds(&base.positions);
    let mut rt = Runtime::new(base.clone(), RuntimeOptions::default().pixel_error(px).schedule(schedule).audit(check));
    let mut times = Vec::new();
    let mut phase = [0.0f64; 5];
    let mut ops = [0usize; 4];
    for f in 0..frames {
        let view = camera.view(f, frames, centre, diag, (1920, 1080));
        let s = rt.update(Some(&view));
        if f < 3 || f % 30 == 0 {
            eprintln!("{s:?}");
        }
        if f > 0 {
            times.push(s.total_ms);
            for (k, x) in
                [s.classify_ms, s.split_ms, s.collapse_ms, s.rebalance_ms, s.output_ms].into_iter().enumerate()
            {
                phase[k] += x / (frames - 1) as f64;
            }
            for (k, x) in [s.collapses, s.splits, s.collapse_rounds, s.rebalanced].into_iter().enumerate() {
                ops[k] += x;
            }
        }
        if check {
            rt.mesh().topology.validate().unwrap();
            rt.hierarchy().check(&rt.mesh().topology).unwrap();
        }
    }
    times.sort_by(f64::total_cmp);
    if !times.is_empty() {
        eprintln!("warm median {:.3} ms, p99 {:.3} ms", times[times.len() / 2], times[times.len() * 99 / 100]);
    }
    eprintln!(
        "warm mean ms: classify {:.3} split {:.3} collapse {:.3} rebalance {:.3} output {:.3}",
        phase[0], phase[1], phase[2], phase[3], phase[4]
    );
    eprintln!("warm totals: collapses {} splits {} collapse rounds {} rebalanced {}", ops[0], ops[1], ops[2], ops[3]);
    let r = rt.memory_report();
    eprintln!("memory {} bytes, n {}, m {}", r.total(), r.vertices, r.active_vertices);
    dynlod::rss::trim_heap();
    if let (Some(a), Some(b)) = (before, dynlod::rss::resident()) {
        eprintln!("resident heap grew by {} bytes since loading began (trimmed)", b.anon.saturating_sub(a.anon));
    }
    for (k, b) in &r.entries {
        eprintln!("  {k:28} {b:>10} {:>7.1} B/n", *b as f64 / r.vertices as f64);
    }
    let n = rt.refine_fully();
    let mut a = rt.into_mesh();
    let mut b = base;
    a.topology.rebuild_vertex_links();
    b.topology.rebuild_vertex_links();
    eprintln!("refined {n}; restored exactly: {}", a == b);
}
