//! What instance groups save: the bundled bunny drawn k × k times on a grid, seen by a camera
//! sliding along the grid's near edge, with 1, 2, 4 and 8 groups, beside k² distinct bunnies
//! (each under its own runtime: what per-instance detail would draw). Warm frames at 1 px and
//! under a budget of 200,000 drawn triangles; prints median and p90 update time, the triangles
//! drawn and held, and the runtimes' memory.
//!
//! Run: `cargo run --release --example instance_groups [k [groups ...]]` (default 6; 1, 2, 4
//! and 8 groups).

use dynlod::lod::{RuntimeOptions, SceneRuntime};
use dynlod::view::View;
use dynlod::Mesh;

fn at(x: f32, z: f32) -> [[f32; 4]; 4] {
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [x, 0.0, z, 1.0]]
}

/// Frame `f`: the camera slides along the grid's near edge, looking into it.
fn camera(f: usize) -> View {
    let x = 0.002 * f as f32;
    View::perspective([x, 0.15, 0.3], [x + 0.2, 0.0, -1.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080))
}

fn run(meshes: Vec<(Mesh, Vec<[[f32; 4]; 4]>)>, groups: usize, what: &str) {
    for budget in [None, Some(200_000)] {
        let options = RuntimeOptions::default().budget(budget);
        let mut scene = SceneRuntime::from_meshes(meshes.clone(), options).unwrap();
        scene.set_instance_groups(groups);
        for f in 0..5 {
            scene.update(&[camera(f)]);
        }
        let mut ms: Vec<f64> = (5..65)
            .map(|f| {
                let t = std::time::Instant::now();
                scene.update(&[camera(f)]);
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        ms.sort_by(f64::total_cmp);
        println!(
            "{what:<28} {:>14} {:>9.3} {:>9.3} {:>10} {:>9} {:>8.1}",
            budget.map_or("1 px".to_string(), |b| format!("budget {b}")),
            ms[ms.len() / 2],
            ms[ms.len() * 9 / 10],
            scene.drawn_triangles(),
            scene.held_triangles(),
            scene.memory_bytes() as f64 / 1e6,
        );
    }
}

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).map(|s| s.parse().expect("numbers")).collect();
    let k = args.first().copied().unwrap_or(6);
    let groups = if args.len() > 1 { args[1..].to_vec() } else { vec![1, 2, 4, 8] };
    let data = std::fs::read("examples/data/bun_zipper.ply.gz").expect("run from the repository root");
    let indexed = dynlod::io::load_gz_bytes(&data, dynlod::io::Format::Ply).unwrap();
    let bunny = Mesh::build(&indexed, Default::default()).unwrap();
    let place = |n: usize| at(0.25 * (n % k) as f32, -0.25 * (n / k) as f32);
    println!(
        "{:<28} {:>14} {:>9} {:>9} {:>10} {:>9} {:>8}",
        "scene", "mode", "median ms", "p90 ms", "drawn", "held", "MB"
    );
    let distinct = (0..k * k).map(|n| (bunny.clone(), vec![place(n)])).collect();
    run(distinct, 1, &format!("{} distinct bunnies", k * k));
    let instanced = vec![(bunny.clone(), (0..k * k).map(place).collect::<Vec<_>>())];
    for groups in groups {
        run(instanced.clone(), groups, &format!("1 bunny × {}, {groups} groups", k * k));
    }
}
