//! How a `SceneRuntime`'s frame grows with the scene: k × k spheres (960 triangles each) on a
//! ground plane, seen by a camera sliding along one edge, either as k² distinct meshes (a
//! runtime each) or as one mesh drawn k² times (one runtime serving k² views, or 4 or 8
//! instance groups sharing them by distance). Warm frames at
//! 1 px and under a budget of 20,000 drawn triangles; prints median and p90 update time and
//! the triangles drawn and held.
//!
//! Run: `cargo run --release --example scene_scaling [k ...]` (default 10 and 20).

use dynlod::lod::{RuntimeOptions, SceneRuntime};
use dynlod::view::View;
use dynlod::Mesh;

fn at(x: f32, z: f32) -> [[f32; 4]; 4] {
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [x, 0.0, z, 1.0]]
}

/// Frame `f`: the camera slides along the grid's near edge, looking into it.
fn camera(f: usize) -> View {
    let x = 0.05 * f as f32;
    View::perspective([x, 2.0, 4.0], [x + 3.0, 0.0, -10.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080))
}

fn run(meshes: Vec<(Mesh, Vec<[[f32; 4]; 4]>)>, groups: usize, what: &str) {
    for budget in [None, Some(20_000)] {
        let options = RuntimeOptions::default().budget(budget);
        let mut scene = SceneRuntime::from_meshes(meshes.clone(), options).unwrap();
        scene.set_instance_groups(groups);
        for f in 0..5 {
            scene.update(&[camera(f)]);
        }
        let mut ms: Vec<f64> = (5..125)
            .map(|f| {
                let t = std::time::Instant::now();
                scene.update(&[camera(f)]);
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        ms.sort_by(f64::total_cmp);
        println!(
            "{what:<38} {:>14} {:>10.3} {:>10.3} {:>10} {:>10}",
            budget.map_or("1 px".to_string(), |b| format!("budget {b}")),
            ms[ms.len() / 2],
            ms[ms.len() * 9 / 10],
            scene.drawn_triangles(),
            scene.held_triangles()
        );
    }
}

fn main() {
    let sizes: Vec<usize> = std::env::args().skip(1).map(|s| s.parse().expect("k: a number")).collect();
    let sphere = Mesh::build(&dynlod::procedural::uv_sphere(16, 32), Default::default()).unwrap();
    let place = |n: usize, k: usize| at(4.0 * (n % k) as f32, -4.0 * (n / k) as f32);
    println!("{:<38} {:>14} {:>10} {:>10} {:>10} {:>10}", "scene", "mode", "median ms", "p90 ms", "drawn", "held");
    for k in if sizes.is_empty() { vec![10, 20] } else { sizes } {
        let distinct = (0..k * k).map(|n| (sphere.clone(), vec![place(n, k)])).collect();
        run(distinct, 1, &format!("{} distinct meshes", k * k));
        let instanced = vec![(sphere.clone(), (0..k * k).map(|n| place(n, k)).collect::<Vec<_>>())];
        for groups in [1, 4, 8] {
            run(instanced.clone(), groups, &format!("1 mesh drawn {} times, {groups} groups", k * k));
        }
    }
}
