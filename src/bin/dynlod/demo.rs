//! `dynlod demo`: the main job on the bundled bunny (offline simplification, view-dependent
//! cuts at four distances and for two cameras at once, by papers/000's rounds and by the
//! runtime, and the frame-to-frame runtime flown).

use dynlod::simplify::{Method, SimplifyOptions};
use dynlod::Mesh;

use super::{build_options, fly, print_info};

/// The bundled Stanford bunny (Stanford 3D Scanning Repository), gzipped ascii PLY.
const BUNNY_PLY_GZ: &[u8] = include_bytes!("../../../examples/data/bun_zipper.ply.gz");

pub(super) fn demo() -> Result<(), String> {
    let t0 = std::time::Instant::now();
    let indexed =
        dynlod::io::load_gz_bytes(BUNNY_PLY_GZ, dynlod::io::Format::Ply).map_err(|e| format!("bundled bunny: {e}"))?;
    let t1 = std::time::Instant::now();
    let mesh = Mesh::build(&indexed, build_options(false, false)).map_err(|e| format!("bundled bunny: {e}"))?;
    let t2 = std::time::Instant::now();
    println!("dynlod demo: the Stanford bunny (Stanford 3D Scanning Repository), bundled\n");
    print_info(&mesh, "examples/data/bun_zipper.ply.gz", false);
    println!(
        "\nloaded in {:.1} ms, welded + repaired + connectivity in {:.1} ms\n",
        (t1 - t0).as_secs_f64() * 1e3,
        (t2 - t1).as_secs_f64() * 1e3
    );
    println!("offline simplification (symmetric Hausdorff error as % of the bounding-box diagonal):\n");
    println!("{:<10} {:>9} {:>10} {:>10} {:>10}", "method", "triangles", "time (ms)", "max %", "rms %");
    let original = mesh.to_indexed();
    for method in Method::ALL {
        let name = method.name();
        for ratio in [0.1, 0.01] {
            let mut work = mesh.clone();
            let target = (mesh.topology.live_face_count() as f64 * ratio).round() as usize;
            let s = dynlod::simplify::simplify(
                &mut work,
                SimplifyOptions::default().method(method).target_triangles(target),
            );
            let h = dynlod::metrics::hausdorff(&original, &work.to_indexed(), Default::default());
            println!(
                "{name:<10} {:>9} {:>10.1} {:>10.3} {:>10.4}",
                s.output_triangles,
                s.init_ms + s.simplify_ms,
                h.pct(h.max),
                h.pct(h.rms)
            );
        }
    }
    println!("\nview-dependent cuts, 1 px at 1920x1080: papers/000 rounds of parallel half-edge collapses (`simplify --method parallel`),");
    println!("and the frame-to-frame runtime's cut for the same cameras (`--method runtime`: graded, each removal charged with what it buried):\n");
    println!(
        "{:<22} {:>9} {:>10} {:>10} {:>10} {:>9} {:>10} {:>10} {:>10}",
        "camera", "triangles", "time (ms)", "max %", "rms %", "runtime", "time (ms)", "max %", "rms %"
    );
    let (centre, diag) = dynlod::camera_path::frame_bounds(&mesh.positions);
    // The last row: two cameras at once, in front and behind (each alone lets the far side go).
    let cameras: [(&str, &[f32]); 5] = [
        ("close (0.5 diagonal)", &[0.5]),
        ("mid (2 diagonals)", &[2.0]),
        ("far (8 diagonals)", &[8.0]),
        ("farther (32 diagonals)", &[32.0]),
        ("mid, front and back", &[2.0, -2.0]),
    ];
    for (label, dists) in cameras {
        let view = |dist: f32| {
            let eye = [centre[0], centre[1], centre[2] + dist * diag];
            dynlod::view::View::perspective(eye, centre, [0.0, 1.0, 0.0], 60.0, (1920, 1080))
        };
        let views: Vec<dynlod::view::View> = dists.iter().map(|&d| view(d)).collect();
        let mut work = mesh.clone();
        let s = dynlod::lod::coarsen::coarsen_views(
            &mut work,
            &views,
            dynlod::lod::coarsen::CoarsenOptions::default().threshold(1.0),
        );
        let h = dynlod::metrics::hausdorff(&original, &work.to_indexed(), Default::default());
        let cut = dynlod::lod::Runtime::cut(mesh.clone(), &views, dynlod::lod::RuntimeOptions::default())
            .map_err(|e| e.to_string())?;
        let r = dynlod::metrics::hausdorff(&original, &cut.mesh.to_indexed(), Default::default());
        println!(
            "{label:<22} {:>9} {:>10.1} {:>10.3} {:>10.4} {:>9} {:>10.1} {:>10.3} {:>10.4}",
            s.output_triangles,
            s.milliseconds,
            h.pct(h.max),
            h.pct(h.rms),
            cut.mesh.topology.live_face_count(),
            cut.milliseconds,
            r.pct(r.max),
            r.pct(r.rms)
        );
    }
    println!("\nframe-to-frame runtime (papers/001 vertex splits + papers/000 collapses), orbit 1°/frame, 1 px:\n");
    fly::demo_table(mesh)
}
