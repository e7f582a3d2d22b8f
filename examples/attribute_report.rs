//! Attribute-weighted simplification beside meshoptimizer's `simplifyWithAttributes`: the
//! greedy quadric simplifier with and without `--attribute-weights`, and meshopt with and
//! without attributes, at 50 %, 25 % and 10 % of each mesh. For each run: the geometric RMS
//! (symmetric Hausdorff, % of the bounding-box diagonal) and the RMS error of every attribute
//! in its own units ([`dynlod::metrics::attribute_errors`]).
//!
//! Meshes: the bundled bunny with area-weighted smooth normals and a painted colour field
//! (always), and `Duck.glb` and `DamagedHelmet.glb` from `../shared/meshes` when present.
//! Weights: normal 0.5, uv 1, color 1 (meshoptimizer's suggestions).
//!
//! Run: `cargo run --release --example attribute_report`

use std::time::Instant;

use dynlod::metrics::{attribute_errors, hausdorff, HausdorffOptions};
use dynlod::simplify::{simplify, AttributeWeights, Method, SimplifyOptions};
use dynlod::{BuildOptions, IndexedMesh, Mesh};

#[path = "../benches/support/meshopt_ref.rs"]
mod meshopt_ref;
#[path = "../benches/support/painted.rs"]
mod painted;
use painted::painted_bunny;

const RATIOS: [f64; 3] = [0.5, 0.25, 0.1];

struct Row {
    ratio: f64,
    method: &'static str,
    triangles: usize,
    ms: f64,
    rms_pct: f64,
    attributes: Vec<(String, f64)>,
}

fn measure(original: &IndexedMesh, weights: &AttributeWeights) -> Vec<Row> {
    let mesh = Mesh::build(original, BuildOptions::default()).expect("build");
    let mut rows = Vec::new();
    for ratio in RATIOS {
        let target = (original.triangles.len() as f64 * ratio).round() as usize;
        for method in ["qem", "qem weighted", "qem-flat", "qem-flat weighted", "meshopt", "meshopt weighted"] {
            let start = Instant::now();
            let out = match method {
                "meshopt" => meshopt_ref::simplify_mesh_with_attributes(original, target, &AttributeWeights::default()),
                "meshopt weighted" => meshopt_ref::simplify_mesh_with_attributes(original, target, weights),
                _ => {
                    let w = if method.ends_with("weighted") { *weights } else { AttributeWeights::default() };
                    let m = if method.starts_with("qem-flat") { Method::QemFlat } else { Method::Qem };
                    let mut work = mesh.clone();
                    let opts = SimplifyOptions::default().method(m).target_triangles(target).attribute_weights(w);
                    simplify(&mut work, opts);
                    work.to_indexed()
                }
            };
            let ms = start.elapsed().as_secs_f64() * 1e3;
            let h = hausdorff(original, &out, HausdorffOptions::default());
            let attributes = attribute_errors(original, &out, HausdorffOptions::default())
                .into_iter()
                .map(|e| (e.semantic, e.rms))
                .collect();
            rows.push(Row { ratio, method, triangles: out.triangles.len(), ms, rms_pct: h.pct(h.rms), attributes });
        }
    }
    rows
}

fn print_table(name: &str, rows: &[Row]) {
    let semantics: Vec<&str> = rows[0].attributes.iter().map(|a| a.0.as_str()).collect();
    println!("\n### {name}\n");
    print!("| ratio | method | triangles | time (ms) | geometric RMS % |");
    semantics.iter().for_each(|s| print!(" {s} RMS |"));
    println!();
    print!("|---:|---|---:|---:|---:|");
    semantics.iter().for_each(|_| print!("---:|"));
    println!();
    for r in rows {
        print!("| {:.0} % | {} | {} | {:.1} | {:.4} |", r.ratio * 100.0, r.method, r.triangles, r.ms, r.rms_pct);
        r.attributes.iter().for_each(|a| print!(" {:.4} |", a.1));
        println!();
    }
}

fn main() {
    let weights = AttributeWeights { normal: 0.5, uv: 1.0, color: 1.0, tangent: 0.0 };
    let mut inputs = vec![("bunny, smooth normals and painted colours".to_string(), painted_bunny())];
    let shared = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/gltf");
    for name in ["Duck.glb", "DamagedHelmet.glb"] {
        let path = format!("{shared}/{name}");
        if std::path::Path::new(&path).exists() {
            inputs.push((name.to_string(), dynlod::io::load(&path).expect("a shared glTF")));
        }
    }
    println!("weights: {weights:?}");
    for (name, mesh) in inputs {
        print_table(&name, &measure(&mesh, &weights));
    }
}
