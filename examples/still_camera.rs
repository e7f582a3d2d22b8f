//! A still camera from the cold start: after how many frames updates are skipped, the moves
//! rebalancing made until then, the CPU the full frames took and the longest of them; then a
//! 360-frame orbit's figures beside it (docs/BENCHMARKS.md, "A still camera"). The bundled
//! bunny, and igea, the armadillo and the 2CylinderEngine from `../shared/meshes` when
//! present; `igea4` (igea split 1 → 4, about 1M triangles) when named.
//!
//! Run: `cargo run --release --example still_camera [MESH ...]` (bunny, igea, armadillo,
//! engine, igea4; default all but igea4).

use std::path::Path;

use dynlod::camera_path::{frame_bounds, CameraPath};
use dynlod::lod::{Runtime, RuntimeOptions};
use dynlod::{BuildOptions, Mesh};

#[path = "../benches/support/subdivide.rs"]
mod subdivide;
use subdivide::subdivide;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let shared = root.join("../shared/meshes");
    let mut asked: Vec<String> = std::env::args().skip(1).collect();
    if asked.is_empty() {
        asked = ["bunny", "igea", "armadillo", "engine"].map(String::from).to_vec();
    }
    for name in asked {
        let path = match name.as_str() {
            "bunny" => root.join("examples/data/bun_zipper.ply.gz"),
            "igea" | "igea4" => shared.join("scans/igea_triangles.ply"),
            "armadillo" => shared.join("scans/armadillo_libigl.obj"),
            "engine" => shared.join("gltf/2CylinderEngine.glb"),
            other => panic!("unknown mesh {other}"),
        };
        if !path.exists() {
            eprintln!("{name}: {} not found, skipped", path.display());
            continue;
        }
        let mut mesh = dynlod::load_mesh(&path, BuildOptions::default()).unwrap();
        if name == "igea4" {
            mesh = Mesh::build(&subdivide(&mesh.to_indexed()), BuildOptions::default()).unwrap();
        }
        still(&name, &mesh);
        orbit(&name, &mesh);
    }
}

fn still(name: &str, mesh: &Mesh) {
    let (centre, diag) = frame_bounds(&mesh.positions);
    let view = CameraPath::Orbit.view(0, 360, centre, diag, (1920, 1080));
    let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default());
    let (mut moves, mut full, mut longest) = (0, 0.0, 0.0f64);
    for f in 0..3000 {
        let s = rt.update(Some(&view));
        if s.skipped {
            println!(
                "{name} still: skipped from frame {f}, {moves} moves, {} triangles, chain depth {} / {:.3}, \
                 full frames after the first {full:.1} ms, the longest {longest:.3} ms",
                s.triangles, s.max_chain_depth, s.mean_chain_depth
            );
            return;
        }
        moves += s.rebalanced;
        if f > 0 {
            full += s.total_ms;
            longest = longest.max(s.total_ms);
        }
    }
    println!("{name} still: not skipped in 3,000 frames");
}

fn orbit(name: &str, mesh: &Mesh) {
    let (centre, diag) = frame_bounds(&mesh.positions);
    let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default());
    let (mut times, mut moves, mut attempts) = (Vec::new(), 0, 0);
    let mut last = None;
    for f in 0..360 {
        let s = rt.update(Some(&CameraPath::Orbit.view(f, 360, centre, diag, (1920, 1080))));
        if f > 0 {
            times.push(s.total_ms);
            (moves, attempts) = (moves + s.rebalanced, attempts + s.rebalance_attempts);
        }
        last = Some(s);
    }
    times.sort_by(f64::total_cmp);
    let s = last.unwrap();
    println!(
        "{name} orbit: median {:.3} ms, p99 {:.3} ms, {moves} moves in {attempts} attempts, chain depth {} / {:.3}, \
         {} triangles",
        times[times.len() / 2],
        times[times.len() * 99 / 100],
        s.max_chain_depth,
        s.mean_chain_depth,
        s.triangles
    );
}
