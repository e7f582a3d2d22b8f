//! Quality and time of every simplification method beside meshoptimizer, at 50 % … 1 % of the
//! bunny (bundled) and the armadillo (`../shared/meshes`, when present): symmetric Hausdorff
//! max / mean / RMS as % of the bounding-box diagonal. Prints a markdown table and draws
//! `docs/quality_<mesh>.png` (RMS against triangle count; needs the DejaVu Sans font).
//!
//! Run: `cargo run --release --example quality_report`

use std::time::Instant;

use dynlod::metrics::{hausdorff, HausdorffOptions};
use dynlod::simplify::{simplify, Method, SimplifyOptions};
use dynlod::{BuildOptions, Mesh};
use plotters::prelude::*;

#[path = "../benches/support/meshopt_ref.rs"]
mod meshopt_ref;

const RATIOS: [f64; 7] = [0.5, 0.3, 0.2, 0.1, 0.05, 0.02, 0.01];
const METHODS: [&str; 6] = ["mca", "qem", "mca-qem", "qem-batch", "qem-flat", "meshopt"];

struct Row {
    method: &'static str,
    ratio: f64,
    triangles: usize,
    ms: f64,
    max: f64,
    mean: f64,
    rms: f64,
}

fn measure(name: &str, mesh: &Mesh) -> Vec<Row> {
    let original = mesh.to_indexed();
    let n = original.triangles.len();
    let mut rows = Vec::new();
    for ratio in RATIOS {
        let target = (n as f64 * ratio).round() as usize;
        for method in METHODS {
            let start = Instant::now();
            let simplified = match method {
                "meshopt" => meshopt_ref::simplify_mesh(&original, target),
                m => {
                    let method = Method::from_name(m).expect("a method of dynlod::simplify");
                    let mut work = mesh.clone();
                    simplify(&mut work, SimplifyOptions::default().method(method).target_triangles(target));
                    work.to_indexed()
                }
            };
            let ms = start.elapsed().as_secs_f64() * 1e3;
            let h = hausdorff(&original, &simplified, HausdorffOptions::default());
            rows.push(Row {
                method,
                ratio,
                triangles: simplified.triangles.len(),
                ms,
                max: h.pct(h.max),
                mean: h.pct(h.mean),
                rms: h.pct(h.rms),
            });
            eprintln!("{name} {method} {ratio}: {} tris", simplified.triangles.len());
        }
    }
    rows
}

fn print_table(name: &str, rows: &[Row]) {
    println!("\n### {name}\n");
    println!("| ratio | method | triangles | time (ms) | Hausdorff max % | mean % | RMS % | RMS ÷ meshopt |");
    println!("|---:|---|---:|---:|---:|---:|---:|---:|");
    for r in rows {
        let mo = rows.iter().find(|x| x.method == "meshopt" && x.ratio == r.ratio).unwrap();
        println!(
            "| {:.0} % | {} | {} | {:.1} | {:.4} | {:.4} | {:.4} | {:.2} |",
            r.ratio * 100.0,
            r.method,
            r.triangles,
            r.ms,
            r.max,
            r.mean,
            r.rms,
            r.rms / mo.rms
        );
    }
}

fn plot(name: &str, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    let font = std::fs::read("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")?;
    plotters::style::register_font("sans-serif", FontStyle::Normal, Box::leak(font.into_boxed_slice()))
        .map_err(|_| "bad font")?;
    let path = format!("{}/docs/quality_{name}.png", env!("CARGO_MANIFEST_DIR"));
    let root = BitMapBackend::new(&path, (900, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let (xmin, xmax) =
        rows.iter().fold((f64::MAX, 0.0f64), |(a, b), r| (a.min(r.triangles as f64), b.max(r.triangles as f64)));
    let (ymin, ymax) = rows.iter().fold((f64::MAX, 0.0f64), |(a, b), r| (a.min(r.rms), b.max(r.rms)));
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{name}: symmetric Hausdorff RMS vs triangles"), ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((xmin * 0.8..xmax * 1.2).log_scale(), (ymin * 0.8..ymax * 1.25).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("triangles")
        .y_desc("RMS, % of bbox diagonal")
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&|x| format!("{:.0}", x))
        .y_label_formatter(&|y| format!("{y:.3}"))
        .light_line_style(WHITE.mix(0.0))
        .label_style(("sans-serif", 14))
        .draw()?;
    let colors = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];
    for (k, method) in METHODS.iter().enumerate() {
        let pts: Vec<(f64, f64)> =
            rows.iter().filter(|r| r.method == *method).map(|r| (r.triangles as f64, r.rms)).collect();
        let color = colors[k];
        chart
            .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?
            .label(*method)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()?;
    root.present()?;
    eprintln!("wrote {path}");
    Ok(())
}

fn main() {
    let mut inputs =
        vec![("bunny", concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz").to_string())];
    let armadillo = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/scans/armadillo_libigl.obj");
    if std::path::Path::new(armadillo).exists() {
        inputs.push(("armadillo", armadillo.to_string()));
    }
    for (name, path) in inputs {
        let mesh = dynlod::load_mesh(&path, BuildOptions::default()).expect("load");
        let rows = measure(name, &mesh);
        print_table(name, &rows);
        if let Err(e) = plot(name, &rows) {
            eprintln!("no plot for {name}: {e}");
        }
    }
}
