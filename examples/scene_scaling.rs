//! How a `SceneRuntime`'s frame grows with the scene: k × k copies of a mesh on a ground
//! plane, seen by a camera sliding along one edge, either as k² distinct meshes (a runtime
//! each) or as one mesh drawn k² times (one runtime serving k² views, or instance groups
//! sharing them by distance). Warm frames at 1 px and under a budget of drawn triangles;
//! prints median and p90 update time, the triangles drawn and held, and the runtimes' memory.
//!
//! Run: `cargo run --release --example scene_scaling [k ...]` (spheres of 960 triangles 4
//! apart, budget 20,000, 1, 4 and 8 groups; default k = 10 and 20), or
//! `cargo run --release --example scene_scaling bunny [k [groups ...]]` (the bundled bunny
//! 0.25 apart, budget 200,000; default k = 6, 1, 2, 4 and 8 groups).

use dynlod::lod::{RuntimeOptions, SceneRuntime};
use dynlod::view::View;
use dynlod::Mesh;

/// The field: its mesh and spacing, the camera (its eye's height and distance in front of the
/// first row, where it looks: x ahead and z, its step a frame), the budget, the frames timed
/// and the group counts tried.
struct Field {
    mesh: Mesh,
    spacing: f32,
    eye: [f32; 2],
    look: [f32; 2],
    step: f32,
    budget: usize,
    frames: std::ops::Range<usize>,
    groups: Vec<usize>,
}

impl Field {
    fn at(&self, n: usize, k: usize) -> [[f32; 4]; 4] {
        let (x, z) = (self.spacing * (n % k) as f32, -self.spacing * (n / k) as f32);
        [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [x, 0.0, z, 1.0]]
    }

    /// Frame `f`: the camera slides along the field's near edge, looking into it.
    fn camera(&self, f: usize) -> View {
        let x = self.step * f as f32;
        let ([y, z], [ahead, far]) = (self.eye, self.look);
        View::perspective([x, y, z], [x + ahead, 0.0, far], [0.0, 1.0, 0.0], 60.0, (1920, 1080))
    }

    fn run(&self, meshes: Vec<(Mesh, Vec<[[f32; 4]; 4]>)>, groups: usize, what: &str) {
        for budget in [None, Some(self.budget)] {
            let options = RuntimeOptions::default().budget(budget);
            let mut scene = SceneRuntime::from_meshes(meshes.clone(), options).unwrap();
            scene.set_instance_groups(groups);
            for f in 0..self.frames.start {
                scene.update(&[self.camera(f)]);
            }
            let mut ms: Vec<f64> = self
                .frames
                .clone()
                .map(|f| {
                    let t = std::time::Instant::now();
                    scene.update(&[self.camera(f)]);
                    t.elapsed().as_secs_f64() * 1e3
                })
                .collect();
            ms.sort_by(f64::total_cmp);
            println!(
                "{what:<38} {:>14} {:>10.3} {:>10.3} {:>10} {:>10} {:>8.1}",
                budget.map_or("1 px".to_string(), |b| format!("budget {b}")),
                ms[ms.len() / 2],
                ms[ms.len() * 9 / 10],
                scene.drawn_triangles(),
                scene.held_triangles(),
                scene.memory_bytes() as f64 / 1e6,
            );
        }
    }
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let bunny = args.first().is_some_and(|a| a == "bunny");
    if bunny {
        args.remove(0);
    }
    let numbers: Vec<usize> = args.iter().map(|s| s.parse().expect("numbers")).collect();
    let (field, sizes) = if bunny {
        let mesh = dynlod::load_mesh("examples/data/bun_zipper.ply.gz", Default::default())
            .expect("run from the repository root");
        let groups = if numbers.len() > 1 { numbers[1..].to_vec() } else { vec![1, 2, 4, 8] };
        let (eye, look, step) = ([0.15, 0.3], [0.2, -1.0], 0.002);
        let field = Field { mesh, spacing: 0.25, eye, look, step, budget: 200_000, frames: 5..65, groups };
        (field, vec![numbers.first().copied().unwrap_or(6)])
    } else {
        let mesh = Mesh::build(&dynlod::procedural::uv_sphere(16, 32), Default::default()).unwrap();
        let (eye, look, step) = ([2.0, 4.0], [3.0, -10.0], 0.05);
        let field =
            Field { mesh, spacing: 4.0, eye, look, step, budget: 20_000, frames: 5..125, groups: vec![1, 4, 8] };
        (field, if numbers.is_empty() { vec![10, 20] } else { numbers })
    };
    println!(
        "{:<38} {:>14} {:>10} {:>10} {:>10} {:>10} {:>8}",
        "scene", "mode", "median ms", "p90 ms", "drawn", "held", "MB"
    );
    for k in sizes {
        let distinct = (0..k * k).map(|n| (field.mesh.clone(), vec![field.at(n, k)])).collect();
        field.run(distinct, 1, &format!("{} distinct meshes", k * k));
        let instanced = vec![(field.mesh.clone(), (0..k * k).map(|n| field.at(n, k)).collect::<Vec<_>>())];
        for &groups in &field.groups {
            field.run(instanced.clone(), groups, &format!("1 mesh drawn {} times, {groups} groups", k * k));
        }
    }
}
