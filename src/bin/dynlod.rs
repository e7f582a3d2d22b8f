//! The `dynlod` command line: `info` and `demo` (later: `simplify`, `fly`, `compare`).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use dynlod::info::MeshInfo;
use dynlod::{BuildOptions, Mesh};

/// The bundled Stanford bunny (Stanford 3D Scanning Repository), gzipped ascii PLY.
const BUNNY_PLY_GZ: &[u8] = include_bytes!("../../examples/data/bun_zipper.ply.gz");

#[derive(Parser)]
#[command(name = "dynlod", version, about = "View-dependent progressive meshes: inspect, simplify, fly")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print counts, topology, bounds and repairs of a mesh file.
    Info {
        /// Mesh file (.obj .ply .off .stl .gltf .glb, optionally .gz).
        file: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
        /// Treat every repair as an error (exit 2).
        #[arg(long)]
        strict: bool,
        /// Also drop zero-area triangles (kept by default: they are topologically sound).
        #[arg(long)]
        drop_zero_area: bool,
    },
    /// Symmetric Hausdorff distance between two meshes (Metro-style sampling).
    Compare {
        /// The reference mesh (percentages are of its bounding-box diagonal).
        original: PathBuf,
        /// The mesh to measure against it.
        simplified: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
        /// Interior samples per face, on average.
        #[arg(long, default_value_t = 10.0)]
        density: f32,
    },
    /// Run the main job on the bundled Stanford bunny.
    Demo,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("dynlod: {msg}");
            ExitCode::from(2)
        }
    }
}

fn run(cmd: Command) -> Result<(), String> {
    match cmd {
        Command::Info { file, json, strict, drop_zero_area } => {
            let options = BuildOptions::default().strict(strict).drop_zero_area(drop_zero_area);
            let mesh = dynlod::load_mesh(&file, options).map_err(|e| e.to_string())?;
            print_info(&mesh, &file.display().to_string(), json);
            Ok(())
        }
        Command::Compare { original, simplified, json, density } => compare(&original, &simplified, json, density),
        Command::Demo => demo(),
    }
}

fn compare(a: &std::path::Path, b: &std::path::Path, json: bool, density: f32) -> Result<(), String> {
    if !(density.is_finite() && density > 0.0) {
        return Err(format!("--density must be a positive number, got {density}"));
    }
    let ma = dynlod::io::load(a).map_err(|e| e.to_string())?;
    let mb = dynlod::io::load(b).map_err(|e| e.to_string())?;
    let h = dynlod::metrics::hausdorff(&ma, &mb, dynlod::metrics::HausdorffOptions::default().density(density));
    if json {
        let side = |s: &dynlod::metrics::OneSided| serde_json::json!({"max": s.max, "mean": s.mean, "rms": s.rms, "samples": s.samples});
        let v = serde_json::json!({
            "original": a.display().to_string(),
            "simplified": b.display().to_string(),
            "hausdorff_max": h.max, "hausdorff_mean": h.mean, "rms": h.rms,
            "hausdorff_max_pct": h.pct(h.max), "hausdorff_mean_pct": h.pct(h.mean), "rms_pct": h.pct(h.rms),
            "diagonal": h.diagonal,
            "forward": side(&h.forward), "backward": side(&h.backward),
            "original_triangles": ma.triangles.len(), "simplified_triangles": mb.triangles.len(),
        });
        println!("{v}");
    } else {
        println!("{:<22} {} ({} triangles)", "original", a.display(), ma.triangles.len());
        println!("{:<22} {} ({} triangles)", "simplified", b.display(), mb.triangles.len());
        println!("{:<22} {:.6}", "bbox diagonal", h.diagonal);
        for (name, x) in [("hausdorff max", h.max), ("hausdorff mean", h.mean), ("rms", h.rms)] {
            println!("{name:<22} {x:.6e} ({:.4} % of diagonal)", h.pct(x));
        }
        for (name, s) in [("original -> simplified", h.forward), ("simplified -> original", h.backward)] {
            println!("{name:<22} max {:.6e} mean {:.6e} rms {:.6e} ({} samples)", s.max, s.mean, s.rms, s.samples);
        }
    }
    Ok(())
}

fn print_info(mesh: &Mesh, label: &str, json: bool) {
    let info = MeshInfo::new(mesh);
    if json {
        println!("{}", info.to_json(label));
    } else {
        print!("{}", info.to_text(label));
    }
}

fn demo() -> Result<(), String> {
    let t0 = std::time::Instant::now();
    let indexed =
        dynlod::io::load_gz_bytes(BUNNY_PLY_GZ, dynlod::io::Format::Ply).map_err(|e| format!("bundled bunny: {e}"))?;
    let t1 = std::time::Instant::now();
    let mesh = Mesh::build(&indexed, BuildOptions::default()).map_err(|e| format!("bundled bunny: {e}"))?;
    let t2 = std::time::Instant::now();
    println!("dynlod demo: the Stanford bunny (Stanford 3D Scanning Repository), bundled\n");
    print_info(&mesh, "examples/data/bun_zipper.ply.gz", false);
    println!(
        "\nloaded in {:.1} ms, welded + repaired + connectivity in {:.1} ms",
        (t1 - t0).as_secs_f64() * 1e3,
        (t2 - t1).as_secs_f64() * 1e3
    );
    println!("(coarsening and the frame-to-frame runtime arrive with the next milestones)");
    Ok(())
}
