//! The `dynlod` command line: `info`, `simplify`, `compare`, `fly` and `demo`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use dynlod::info::MeshInfo;
use dynlod::lod::coarsen::Schedule;
use dynlod::simplify::{AttributeWeights, Method, SimplifyOptions};
use dynlod::{BuildOptions, Mesh};

mod demo;
mod fly;
mod parallel;
mod scene;

#[derive(Parser)]
#[command(name = "dynlod", version, about = "View-dependent progressive meshes: inspect, simplify, fly")]
struct Cli {
    /// Worker threads (default: one per core, or RAYON_NUM_THREADS). Results are the same
    /// for any count; a frame-to-frame runtime is often fastest on 2-4 (docs/BENCHMARKS.md).
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
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
    /// Simplify a mesh offline and write the result (format from OUT's extension).
    Simplify {
        /// Input mesh.
        input: PathBuf,
        /// Output mesh (.obj, .ply or .glb), written atomically.
        output: PathBuf,
        /// qem-flat (quadric cost, passes over a flat triangle list: the fastest, and
        /// within a few % of meshoptimizer's error), mca (dihedral cost, multiple choice;
        /// papers/002: about twice the error at equal counts), qem (greedy quadric),
        /// mca-qem (quadric cost, multiple choice), qem-batch (quadric cost, passes of
        /// independent collapses on every core), parallel (papers/000 rounds; with --eye,
        /// view-dependent in pixels), runtime (the frame-to-frame runtime's cut for the same
        /// cameras: graded from the full mesh, so a farther eye never keeps more, and each
        /// removal charged with what it buried). Default: qem-flat, or runtime with --eye.
        #[arg(long)]
        method: Option<String>,
        /// Stop at this many triangles.
        #[arg(long, conflicts_with = "ratio")]
        triangles: Option<usize>,
        /// Stop at this fraction of the input triangles (0..1).
        #[arg(long)]
        ratio: Option<f64>,
        /// Never exceed this quadric error √(Q/W), in model units.
        #[arg(long)]
        error: Option<f64>,
        /// Candidates drawn per multiple-choice step.
        #[arg(long, default_value_t = 6)]
        candidates: usize,
        /// Seed of the multiple-choice draws.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Keep every border vertex where it is.
        #[arg(long)]
        lock_border: bool,
        /// qem, mca-qem, qem-batch, qem-flat: weigh attributes in the cost beside the geometry, so
        /// colours, texture coordinates and shading hold up (Hoppe 1999 attribute quadrics,
        /// as meshoptimizer's simplifyWithAttributes). W for every kind, or KIND=W,... with
        /// KIND normal, uv, color, tangent (e.g. normal=0.5,color=1). A weight of 1 prices a
        /// change of 1 in the attribute like a move across the whole mesh.
        #[arg(long, value_parser = parse_attribute_weights)]
        attribute_weights: Option<AttributeWeights>,
        /// Refuse inputs that need repair.
        #[arg(long)]
        strict: bool,
        /// Keep the input's vertex and face order. By default both are renumbered along a
        /// space-filling curve first (neighbours on the surface become neighbours in memory,
        /// which makes every pass faster); the output's order follows.
        #[arg(long)]
        keep_order: bool,
        /// glTF to GLB: bake the scene into one mesh in world space and simplify that. By
        /// default the scene is kept (nodes, skins, animations, morph targets, materials) and
        /// each mesh definition is simplified once, in its own space, to the triangles a run
        /// over the whole baked scene left it (--ratio and --triangles count the triangles
        /// drawn; --error is in the scene's units, divided by each mesh's largest node scale).
        #[arg(long)]
        flatten: bool,
        /// Print one JSON object with the run's figures.
        #[arg(long)]
        json: bool,
        /// runtime, parallel: camera position X,Y,Z (makes the cut view-dependent; with no
        /// --method, runtime's). Repeat it for several cameras: the cut keeps what every one
        /// of them needs.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        eye: Vec<[f64; 3]>,
        /// runtime, parallel: point the camera looks at, X,Y,Z (default: the mesh's centre): once for
        /// every --eye, or once per --eye in the same order.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        target: Vec<[f64; 3]>,
        /// runtime, parallel: vertical field of view in degrees.
        #[arg(long, default_value_t = 60.0, allow_hyphen_values = true)]
        fov: f32,
        /// runtime, parallel with --eye: an orthographic camera instead, with this many world units
        /// filling the viewport's height (looking from --eye towards --target).
        #[arg(long, conflicts_with = "fov", allow_hyphen_values = true)]
        ortho_height: Option<f32>,
        /// runtime, parallel: viewport height in pixels.
        #[arg(long, default_value_t = 1080, value_parser = clap::value_parser!(u32).range(1..))]
        height: u32,
        /// runtime, parallel: viewport width in pixels.
        #[arg(long, default_value_t = 1920, value_parser = clap::value_parser!(u32).range(1..))]
        width: u32,
        /// runtime, parallel with --eye: the threshold u in screen pixels.
        #[arg(long, value_parser = parse_pixel_error, allow_hyphen_values = true)]
        pixel_error: Option<f32>,
        /// parallel: which candidates act each round: local-minima (the lowest error among
        /// neighbouring candidates goes first; faster, lower error) or all (papers/000 as
        /// published: every candidate, tests 2 and 3 keep simultaneous moves safe).
        #[arg(long, default_value = "local-minima", value_parser = parse_schedule)]
        schedule: Schedule,
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
    /// Fly a camera around a mesh with the frame-to-frame runtime and print per-frame figures.
    Fly {
        /// Mesh file.
        mesh: PathBuf,
        /// Camera path: orbit (1° per frame), dolly (in and back out), zoom (field of view),
        /// cuts (jumps between shots 0.6 and 40 diagonals away, graded like first frames) or
        /// still (the orbit's first view on every frame: once nothing changes, frames are skipped).
        #[arg(long, default_value = "orbit")]
        path: dynlod::camera_path::CameraPath,
        /// Frames to fly.
        #[arg(long, default_value_t = 360)]
        frames: usize,
        /// Screen-space error in pixels above which a vertex is split back.
        #[arg(long, default_value_t = 1.0, value_parser = parse_pixel_error, allow_hyphen_values = true)]
        pixel_error: f32,
        /// Triangle budget instead of a fixed pixel error.
        #[arg(long)]
        budget: Option<usize>,
        /// Viewport width in pixels.
        #[arg(long, default_value_t = 1920, value_parser = clap::value_parser!(u32).range(1..))]
        width: u32,
        /// Viewport height in pixels.
        #[arg(long, default_value_t = 1080, value_parser = clap::value_parser!(u32).range(1..))]
        height: u32,
        /// Keep the input's vertex and face order. By default both are renumbered along a
        /// space-filling curve first (neighbours on the surface become neighbours in memory,
        /// which makes every pass faster).
        #[arg(long)]
        keep_order: bool,
        /// Orthographic cameras (a shadow map's, a CAD or map view): the path's eye and
        /// axes, framing at the mesh's centre what the perspective camera frames there.
        #[arg(long)]
        orthographic: bool,
        /// Cameras flying the path together, evenly turned about the vertical axis through the
        /// mesh's centre (2: one on each side), all served by one runtime: a split screen, or
        /// one mesh drawn several times. Each camera sees at most the pixel error.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..=256))]
        cameras: u16,
        /// A glTF scene kept as it is instead of baked into one mesh: one runtime per mesh
        /// definition, in its own space, serving every node that draws it (each instance sees
        /// at most the pixel error). Triangle counts are those the scene draws, and a
        /// --budget is the whole scene's: one threshold for every mesh, a mesh's triangles
        /// counted once per node that draws it. A node that stretches or shears its mesh draws
        /// a copy with the stretch baked in (noted on stderr).
        #[arg(long)]
        instanced: bool,
        /// With --instanced, up to this many runtimes for a mesh drawn more than once, each
        /// serving the nodes in one band of distance (the nearest first): far instances stop
        /// drawing the detail the nearest needs, for a runtime's memory per group.
        #[arg(long, default_value_t = 1, requires = "instanced", value_parser = clap::value_parser!(u16).range(1..=64))]
        groups: u16,
        /// Rebalancing attempts per frame (0: off). Under a still camera only those that
        /// get as far as a trial split count, among up to 16x as many records looked at.
        #[arg(long, default_value_t = 64)]
        rebalance: usize,
        /// Splits and collapses per frame at most: a frame that reaches it ends and the next
        /// goes on, so a camera cut spreads over frames of bounded work (deterministic). With
        /// --instanced, each mesh's (a mesh that reaches it ends the scene's frame).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        max_edits: Option<u64>,
        /// Which candidates act each collapse round: local-minima or all (as for simplify).
        #[arg(long, default_value = "local-minima", value_parser = parse_schedule)]
        schedule: Schedule,
        /// Write one CSV row per frame to this file.
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Validate the mesh and recount the hierarchy after every frame; exit 1 on a violation.
        /// The checks walk the whole mesh between updates, so frame times run higher (about
        /// 2-3x on the bunny orbit): time without it.
        #[arg(long)]
        verify: bool,
        /// Print a JSON summary instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Run the main job on the bundled Stanford bunny.
    Demo,
}

fn main() -> ExitCode {
    // Rust ignores SIGPIPE, so printing into a closed pipe (`dynlod info --json | head`)
    // would panic; a command-line tool should end quietly there, as `cat` does.
    #[cfg(unix)]
    // SAFETY: restores the default disposition before any thread starts; no handler runs.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    if let Some(n) = cli.threads {
        if let Err(e) = rayon::ThreadPoolBuilder::new().num_threads(n.into()).build_global() {
            eprintln!("dynlod: cannot start {n} threads: {e}");
            return ExitCode::from(2);
        }
    }
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
        Command::Simplify {
            input,
            output,
            method,
            triangles,
            ratio,
            error,
            candidates,
            seed,
            lock_border,
            attribute_weights,
            strict,
            keep_order,
            flatten,
            json,
            eye,
            target,
            fov,
            ortho_height,
            height,
            width,
            pixel_error,
            schedule,
        } => {
            let weights = attribute_weights.unwrap_or_default();
            if let Some(r) = ratio {
                if !(0.0..=1.0).contains(&r) {
                    return Err(format!("--ratio must be between 0 and 1, got {r}"));
                }
            }
            let keep_scene = scene::keeps_scene(&input, &output, flatten);
            let job = |engine| scene::Job {
                input: &input,
                output: &output,
                engine,
                triangles,
                ratio,
                lock_border,
                build: build_options(strict, keep_order),
                json,
            };
            if let Some(e) = error {
                if e.is_nan() || e < 0.0 {
                    return Err(format!("--error must be a non-negative number, got {e}"));
                }
            }
            // Cameras ask for a view-dependent cut: the runtime's unless another is named, and
            // never a method that would leave them out.
            let view_dependent = !eye.is_empty() || pixel_error.is_some();
            let method = method.unwrap_or_else(|| if eye.is_empty() { "qem-flat" } else { "runtime" }.into());
            if view_dependent && !matches!(method.as_str(), "parallel" | "runtime") {
                let given = if eye.is_empty() { "--pixel-error" } else { "--eye" };
                return Err(format!(
                    "{given} asks for a view-dependent cut, which --method {method} does not make (it ignores \
                     cameras): use --method runtime (the default with --eye) or parallel"
                ));
            }
            let method = match method.as_str() {
                m @ ("parallel" | "runtime") if weights.any() => return Err(weights_refused(m)),
                m @ ("parallel" | "runtime") => {
                    let p = ParallelArgs {
                        eye,
                        target,
                        fov,
                        ortho_height,
                        height,
                        width,
                        pixel_error,
                        triangles,
                        ratio,
                        error,
                        schedule,
                        runtime: m == "runtime",
                    };
                    if keep_scene {
                        return scene::simplify_scene(job(scene::Engine::Parallel(p, Vec::new())));
                    }
                    return parallel::parallel(
                        &input,
                        &output,
                        p,
                        lock_border,
                        build_options(strict, keep_order),
                        json,
                    );
                }
                other => Method::from_name(other).ok_or_else(|| {
                    let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
                    format!("unknown --method {other:?} (expected {}, parallel or runtime)", names.join(", "))
                })?,
            };
            let opts = SimplifyOptions::default().method(method).attribute_weights(weights);
            if weights.any() && !opts.weighs_attributes() {
                return Err(weights_refused(method.name()));
            }
            if triangles.is_none() && ratio.is_none() && error.is_none() {
                return Err("give a stopping rule: --triangles N, --ratio R or --error E".into());
            }
            if dynlod::io::WriteFormat::from_path(&output).is_none() {
                return Err(format!("{}: cannot write this extension (use .obj, .ply or .glb)", output.display()));
            }
            if keep_scene {
                let opts = opts.max_error(error.unwrap_or(f64::INFINITY)).candidates(candidates).seed(seed);
                return scene::simplify_scene(job(scene::Engine::Offline(opts, method)));
            }
            let start = std::time::Instant::now();
            let mut mesh = dynlod::load_mesh(&input, build_options(strict, keep_order)).map_err(|e| e.to_string())?;
            let input_triangles = mesh.topology.live_face_count();
            let target = match (triangles, ratio) {
                (Some(n), _) => n,
                (None, Some(r)) => (input_triangles as f64 * r).round() as usize,
                (None, None) => 0,
            };
            if lock_border {
                dynlod::simplify::lock_border(&mut mesh);
            }
            let opts = opts
                .target_triangles(target)
                .max_error(error.unwrap_or(f64::INFINITY))
                .candidates(candidates)
                .seed(seed)
                .progress(input_triangles > 100_000 && std::io::IsTerminal::is_terminal(&std::io::stderr()));
            let asked = triangles.is_some() || ratio.is_some();
            let stats = dynlod::simplify::simplify(&mut mesh, opts.explain_shortfall(asked));
            let saved = save_output(&output, &mesh.to_indexed())?;
            let ms = start.elapsed().as_secs_f64() * 1e3;
            // A target asked for and not reached: say what holds the remaining vertices.
            let short = stats.remaining;
            if json {
                let mut v = serde_json::json!({
                    "input": input.display().to_string(), "output": output.display().to_string(),
                    "method": method.name(),
                    "input_triangles": input_triangles, "output_triangles": stats.output_triangles,
                    "iterations": stats.collapses, "collapses": stats.collapses,
                    "milliseconds": stats.init_ms + stats.simplify_ms, "init_ms": stats.init_ms, "simplify_ms": stats.simplify_ms,
                    "total_ms_with_io": ms, "max_error": stats.max_error,
                    "stop": format!("{:?}", stats.stop),
                });
                if asked {
                    v["target_triangles"] = target.into();
                    v["target_met"] = (stats.output_triangles <= target).into();
                }
                if let Some(r) = short {
                    v["remaining"] = serde_json::json!({
                        "vertices": r.vertices, "locked": r.locked, "fixed": r.fixed,
                        "blocked": r.blocked, "over_error": r.over_error, "movable": r.movable,
                    });
                }
                if weights.any() {
                    v["weighted_attributes"] = stats.weighted_attributes.clone().into();
                }
                add_input_notes(&mut v, &mesh);
                saved.add_to(&mut v);
                println!("{v}");
            } else {
                print_input_notes(&input, &mesh);
                if weights.any() {
                    eprintln!("{}", weighted_note(&input, &stats.weighted_attributes));
                }
                saved.print(&output);
                println!(
                    "{} -> {}: {} -> {} triangles in {:.1} ms ({} collapses, max error {:.3e}, stopped: {:?})",
                    input.display(),
                    output.display(),
                    input_triangles,
                    stats.output_triangles,
                    stats.init_ms + stats.simplify_ms,
                    stats.collapses,
                    stats.max_error,
                    stats.stop
                );
                if let Some(r) = short {
                    eprintln!("{}", short_of_target(target, stats.output_triangles, &r));
                }
            }
            Ok(())
        }
        Command::Compare { original, simplified, json, density } => compare(&original, &simplified, json, density),
        Command::Fly {
            mesh,
            path,
            frames,
            pixel_error,
            budget,
            width,
            height,
            rebalance,
            max_edits,
            schedule,
            keep_order,
            orthographic,
            cameras,
            instanced,
            groups,
            csv,
            verify,
            json,
        } => {
            let baseline = dynlod::rss::resident();
            let runtime = dynlod::lod::RuntimeOptions::default()
                .pixel_error(pixel_error)
                .budget(budget)
                .rebalance_moves(rebalance)
                .max_edits(max_edits.map(|n| n as usize))
                .schedule(schedule);
            let o = dynlod::fly::FlyOptions::default()
                .path(path)
                .frames(frames)
                .viewport(width, height)
                .runtime(runtime)
                .verify(verify)
                .orthographic(orthographic)
                .cameras(cameras.into());
            let subject = if instanced {
                fly::Subject::scene(&mesh, build_options(false, keep_order), &o, groups.into())?
            } else {
                fly::Subject::Mesh(Box::new(
                    dynlod::load_mesh(&mesh, build_options(false, keep_order)).map_err(|e| e.to_string())?,
                ))
            };
            fly::run(subject, &o, csv.as_deref(), json, baseline)
        }
        Command::Demo => demo::demo(),
    }
}

fn parse_schedule(s: &str) -> Result<Schedule, String> {
    Schedule::from_name(s).ok_or_else(|| format!("unknown schedule {s:?} (expected local-minima or all)"))
}

/// Why `--attribute-weights` cannot go with `method`.
fn weights_refused(method: &str) -> String {
    format!("--attribute-weights needs the quadric cost: qem, mca-qem, qem-batch or qem-flat (not {method})")
}

fn parse_attribute_weights(s: &str) -> Result<AttributeWeights, String> {
    AttributeWeights::parse(s)
}

/// Which attributes `--attribute-weights` made count, or that none of the kinds weighted is
/// in the mesh (the run was then geometric only).
fn weighted_note(input: &std::path::Path, weighted: &[String]) -> String {
    if weighted.is_empty() {
        format!(
            "note: {}: carries none of the attributes --attribute-weights weighs; the cost was geometric only",
            input.display()
        )
    } else {
        format!("note: attributes weighed in the cost: {}", weighted.join(", "))
    }
}

/// A pixel error: a finite number ≥ 0 (0 keeps everything the views see).
fn parse_pixel_error(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(px) if px.is_finite() && px >= 0.0 => Ok(px),
        _ => Err(format!("expected a number of pixels, 0 or more, got {s:?}")),
    }
}

/// X,Y,Z in f64: a point in the file's coordinates, which may lie far from its origin.
fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let v: Vec<f64> =
        s.split(',').map(|x| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}"))).collect::<Result<_, _>>()?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([x, y, z]),
        _ => Err(format!("expected X,Y,Z with three finite numbers, got {s:?}")),
    }
}

/// What loading changed (repairs) and what the output cannot hold (a glTF's node hierarchy,
/// animations, ...), on stderr: a simplified file should never lose things silently.
fn print_input_notes(input: &std::path::Path, mesh: &dynlod::Mesh) {
    if mesh.origin != [0.0; 3] {
        eprintln!(
            "note: {}: read relative to {:?}: its coordinates lie too far from the file's origin for f32 (--eye and --target stay in the file's coordinates; outputs add it back)",
            input.display(),
            mesh.origin
        );
    }
    for r in &mesh.repairs {
        eprintln!("note: {}: repaired on load: {r}", input.display());
    }
    for n in &mesh.not_kept {
        eprintln!("note: {}: {n}", input.display());
    }
}

/// What [`save_output`] wrote and left out.
struct Saved {
    /// What the output's format could not hold.
    lost: Vec<String>,
    /// Every file written, the output last (an OBJ's MTL library and textures first).
    files: Vec<String>,
}

impl Saved {
    /// `not_written` and `files_written` for `--json`.
    fn add_to(self, v: &mut serde_json::Value) {
        v["not_written"] = self.lost.into();
        v["files_written"] = self.files.into();
    }

    /// The same on stderr.
    fn print(&self, output: &std::path::Path) {
        for l in &self.lost {
            eprintln!("note: {}: left out, the format cannot hold it: {l}", output.display());
        }
        if let [beside @ .., _] = self.files.as_slice() {
            if !beside.is_empty() {
                eprintln!("note: {}: written beside it (materials): {}", output.display(), beside.join(", "));
            }
            let default = dynlod::io::library_name_for(output);
            let library = beside.iter().find(|f| f.ends_with(".mtl")).and_then(|f| std::path::Path::new(f).file_name());
            if library.is_some_and(|l| *l != *default) {
                eprintln!("note: {}: {default} beside it is not dynlod's and was left as it is", output.display());
            }
        }
    }
}

/// Writes a simplified mesh, atomically, in the format its extension names (checked before
/// loading); returns what was written and what that format could not hold.
fn save_output(output: &std::path::Path, mesh: &dynlod::IndexedMesh) -> Result<Saved, String> {
    let format = dynlod::io::WriteFormat::from_path(output)
        .ok_or_else(|| format!("{}: cannot write this extension (use .obj, .ply or .glb)", output.display()))?;
    let files = dynlod::io::save_as(output, mesh, format).map_err(|e| format!("{}: {e}", output.display()))?;
    let files = files.iter().map(|f| f.display().to_string()).collect();
    Ok(Saved { lost: dynlod::io::not_written(mesh, format), files })
}

/// [`print_input_notes`] for `--json`: `repairs` and `not_kept` arrays.
fn add_input_notes(v: &mut serde_json::Value, mesh: &dynlod::Mesh) {
    v["origin"] = serde_json::json!(mesh.origin);
    v["repairs"] = dynlod::info::repairs_json(&mesh.repairs);
    v["not_kept"] = dynlod::info::not_kept_json(&mesh.not_kept);
}

/// The note printed when a sequential method stops short of its triangle target.
fn short_of_target(target: usize, reached: usize, r: &dynlod::simplify::Remaining) -> String {
    let mut why = vec![format!("{} fixed (border corners, seam junctions, where primitives meet)", r.fixed)];
    if r.locked > 0 {
        why.push(format!("{} locked", r.locked));
    }
    why.push(format!(
        "{} whose every collapse would break the manifold, split a UV/normal wedge or fold a face",
        r.blocked
    ));
    if r.over_error > 0 {
        why.push(format!("{} with collapses over --error", r.over_error));
    }
    if r.movable > 0 {
        why.push(format!("{} still movable", r.movable));
    }
    format!(
        "note: target of {target} triangles not reached ({reached} left); of the {} vertices left: {}",
        r.vertices,
        why.join(", ")
    )
}

#[derive(Clone)]
struct ParallelArgs {
    /// In the file's coordinates ([`dynlod::Mesh::origin`] not taken off).
    eye: Vec<[f64; 3]>,
    target: Vec<[f64; 3]>,
    fov: f32,
    ortho_height: Option<f32>,
    height: u32,
    width: u32,
    pixel_error: Option<f32>,
    triangles: Option<usize>,
    ratio: Option<f64>,
    error: Option<f64>,
    schedule: Schedule,
    /// `--method runtime`: the runtime's cut instead of papers/000's rounds.
    runtime: bool,
}

/// How the commands that run the algorithms build their mesh: spatial order unless
/// `--keep-order` (see [`BuildOptions::spatial_order`]).
fn build_options(strict: bool, keep_order: bool) -> BuildOptions {
    BuildOptions::default().strict(strict).spatial_order(!keep_order)
}

fn compare(a: &std::path::Path, b: &std::path::Path, json: bool, density: f32) -> Result<(), String> {
    if !(density.is_finite() && density > 0.0) {
        return Err(format!("--density must be a positive number, got {density}"));
    }
    let ma = dynlod::io::load(a).map_err(|e| e.to_string())?;
    let mb = dynlod::io::load(b).map_err(|e| e.to_string())?;
    let options = dynlod::metrics::HausdorffOptions::default().density(density);
    let h = dynlod::metrics::hausdorff(&ma, &mb, options);
    let attributes = dynlod::metrics::attribute_errors(&ma, &mb, options);
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
        let mut v = v;
        if !attributes.is_empty() {
            let each = attributes.iter().map(|e| {
                let side = |s: &dynlod::metrics::OneSided| serde_json::json!({"max": s.max, "mean": s.mean, "rms": s.rms, "samples": s.samples});
                (e.semantic.clone(), serde_json::json!({
                    "max": e.max, "mean": e.mean, "rms": e.rms,
                    "forward": side(&e.forward), "backward": side(&e.backward),
                }))
            });
            v["attributes"] = serde_json::Value::Object(each.collect());
        }
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
        for e in &attributes {
            let name = format!("{} error", e.semantic);
            println!("{name:<22} max {:.6e} mean {:.6e} rms {:.6e} (in the attribute's units)", e.max, e.mean, e.rms);
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
