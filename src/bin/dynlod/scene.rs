//! `dynlod simplify` from glTF to GLB: each mesh definition simplified on its own, in its own
//! space, and the scene written back around them (nodes, skins, animations, materials, morph
//! targets; [`dynlod::io::GltfScene`]). `--flatten` bakes the scene into one mesh instead.

use std::path::Path;

use dynlod::io::GltfScene;
use dynlod::simplify::{Method, SimplifyOptions};
use dynlod::BuildOptions;
use rayon::prelude::*;

use super::{lock_border_vertices, ParallelArgs};

/// The engine each mesh goes through.
pub(super) enum Engine {
    /// An offline method, its options set but for the target.
    Offline(SimplifyOptions, Method),
    /// papers/000 rounds (`--eye` is refused: it places a camera in world space).
    Parallel(ParallelArgs),
}

/// What `simplify` was asked, for a scene.
pub(super) struct Job<'a> {
    pub input: &'a Path,
    pub output: &'a Path,
    pub engine: Engine,
    pub triangles: Option<usize>,
    pub ratio: Option<f64>,
    pub lock_border: bool,
    pub build: BuildOptions,
    pub json: bool,
}

/// Whether `simplify IN OUT` keeps the scene: a glTF read and a GLB written, unless
/// `--flatten`.
pub(super) fn keeps_scene(input: &Path, output: &Path, flatten: bool) -> bool {
    let ext = |p: &Path| p.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    !flatten && matches!(ext(input).as_deref(), Some("gltf" | "glb")) && ext(output).as_deref() == Some("glb")
}

/// One mesh definition's figures.
struct Done {
    input: usize,
    output: usize,
    target: Option<usize>,
    stop: String,
    max_error: Option<f64>,
}

pub(super) fn simplify_scene(job: Job<'_>) -> Result<(), String> {
    if let Engine::Parallel(a) = &job.engine {
        if a.eye.is_some() {
            return Err("--eye places the camera in world space, where a kept scene's meshes are not: add \
                        --flatten to cut the scene baked into one mesh"
                .into());
        }
    }
    let start = std::time::Instant::now();
    let scene = GltfScene::load(job.input).map_err(|e| e.to_string())?;
    let mut meshes = Vec::new();
    let mut notes = Vec::new();
    for sm in &scene.meshes {
        let label = sm.label();
        let mut mesh =
            dynlod::Mesh::build(&sm.mesh, job.build).map_err(|e| format!("{}: {label}: {e}", job.input.display()))?;
        notes.extend(mesh.repairs.iter().map(|r| format!("{label}: repaired on load: {r}")));
        notes.extend(mesh.not_kept.iter().map(|n| format!("{label}: {n}")));
        if job.lock_border {
            lock_border_vertices(&mut mesh);
        }
        meshes.push(mesh);
    }
    let inputs: Vec<usize> = meshes.iter().map(|m| m.topology.live_face_count()).collect();
    let targets = targets(&job, &scene, &inputs)?;
    let mut outputs = Vec::new();
    let mut done = Vec::new();
    // The meshes are independent: one per task, results in the scene's order (each engine
    // gives the same result on any thread).
    let engine = &job.engine;
    let runs: Vec<Result<_, String>> = meshes
        .into_par_iter()
        .zip(targets.par_iter().zip(&scene.meshes))
        .map(|(mesh, (&target, sm))| {
            run(mesh, engine, target, sm.scale).map(|(m, output, stop, e)| (m.to_indexed(), output, stop, e))
        })
        .collect();
    for ((r, &input), &target) in runs.into_iter().zip(&inputs).zip(&targets) {
        let (result, output, stop, max_error) = r?;
        outputs.push(result);
        done.push(Done { input, output, target, stop, max_error });
    }
    let written = scene.save(job.output, &outputs).map_err(|e| format!("{}: {e}", job.output.display()))?;
    notes.extend(written);
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let drawn = |f: &dyn Fn(&Done) -> usize| -> usize {
        scene.meshes.iter().zip(&done).map(|(sm, d)| f(d) * sm.instances).sum()
    };
    let (input, output) = (drawn(&|d| d.input), drawn(&|d| d.output));
    let (file_input, file_output) = done.iter().fold((0, 0), |(i, o), d| (i + d.input, o + d.output));
    let asked = job.triangles.or(job.ratio.map(|r| (input as f64 * r).round() as usize));
    if job.json {
        let meshes: Vec<serde_json::Value> = scene
            .meshes
            .iter()
            .zip(&done)
            .map(|(sm, d)| {
                let mut v = serde_json::json!({
                    "mesh": sm.index, "name": sm.name, "instances": sm.instances,
                    "input_triangles": d.input, "output_triangles": d.output, "stop": d.stop,
                });
                if let Some(t) = d.target {
                    v["target_triangles"] = t.into();
                }
                if let Some(e) = d.max_error {
                    v["max_error"] = e.into();
                }
                v
            })
            .collect();
        let method = match &job.engine {
            Engine::Offline(_, m) => m.name(),
            Engine::Parallel(_) => "parallel",
        };
        let mut v = serde_json::json!({
            "input": job.input.display().to_string(), "output": job.output.display().to_string(),
            "method": method, "scene": true,
            "input_triangles": input, "output_triangles": output,
            "file_input_triangles": file_input, "file_output_triangles": file_output,
            "total_ms_with_io": ms, "meshes": meshes, "notes": notes,
        });
        if let Some(n) = asked {
            v["target_triangles"] = n.into();
            v["target_met"] = (output <= n).into();
        }
        println!("{v}");
    } else {
        for n in &notes {
            eprintln!("note: {}: {n}", job.input.display());
        }
        println!(
            "{} -> {}: {input} -> {output} triangles drawn ({file_input} -> {file_output} in the file's {} mesh{}) in \
             {ms:.1} ms; scene kept: nodes, skins, animations, morph targets, materials",
            job.input.display(),
            job.output.display(),
            scene.meshes.len(),
            if scene.meshes.len() == 1 { "" } else { "es" },
        );
        for (sm, d) in scene.meshes.iter().zip(&done) {
            let short =
                d.target.filter(|&t| d.output > t).map(|t| format!(", target {t} not reached")).unwrap_or_default();
            let drawn = if sm.instances == 1 { String::new() } else { format!(", drawn {}x", sm.instances) };
            println!("  {}: {} -> {} ({}{short}{drawn})", sm.label(), d.input, d.output, d.stop);
        }
        if let Some(n) = asked.filter(|&n| output > n) {
            eprintln!(
                "note: target of {n} triangles drawn not reached ({output}): the scene simplified as one mesh, \
                 which shares the triangles out, stops there (as --flatten does), or a mesh stopped short of its \
                 share (above)"
            );
        }
    }
    Ok(())
}

/// `mesh` through the engine, to `target` triangles or the engine's error bound: the result,
/// its triangles, why it stopped and (offline methods) its largest error. `--error` is in
/// the scene's units, as with `--flatten`: a mesh drawn `scale` times larger gets the bound
/// divided by it, so that no instance strays further than asked.
fn run(
    mut mesh: dynlod::Mesh,
    engine: &Engine,
    target: Option<usize>,
    scale: f32,
) -> Result<(dynlod::Mesh, usize, String, Option<f64>), String> {
    let scale = f64::from(scale);
    Ok(match engine {
        Engine::Offline(opts, _) => {
            let input = mesh.topology.live_face_count();
            let progress = input > 100_000 && std::io::IsTerminal::is_terminal(&std::io::stderr());
            let opts = opts.target_triangles(target.unwrap_or(0)).progress(progress).max_error(opts.max_error / scale);
            let stats = dynlod::simplify::simplify(&mut mesh, opts);
            (mesh, stats.output_triangles, format!("{:?}", stats.stop), Some(stats.max_error))
        }
        Engine::Parallel(a) => {
            let a = ParallelArgs { error: a.error.map(|e| e / scale), ..a.clone() };
            let (m, stats, _) = super::parallel::cut(&mesh, None, &a, target)?;
            (m, stats.output_triangles, format!("{:?}", stats.stop), None)
        }
    })
}

/// Each mesh's triangle target. `--ratio R` and `--triangles N` count the triangles the
/// scene draws, every node's instance, as `--flatten` does. A ratio applied to each mesh alike
/// would take as much from a bolt as from a flat panel; instead the scene is first simplified
/// as one mesh in world space (what `--flatten` writes) and each mesh gets the triangles that
/// run left it, per node that draws it: the same allocation, by error across the whole
/// scene. A mesh the scene does not draw keeps the ratio. Only `--error`: no targets.
fn targets(job: &Job<'_>, scene: &GltfScene, inputs: &[usize]) -> Result<Vec<Option<usize>>, String> {
    let drawn: usize = inputs.iter().zip(&scene.meshes).map(|(&n, sm)| n * sm.instances).sum();
    let ratio = match (job.triangles, job.ratio) {
        (Some(n), _) => n as f64 / drawn.max(1) as f64,
        (None, Some(r)) => r,
        (None, None) => return Ok(vec![None; inputs.len()]),
    };
    let plain = |n: usize| Some(((n as f64 * ratio).round() as usize).min(n));
    if scene.meshes.iter().filter(|sm| sm.instances > 0).count() <= 1 || ratio >= 1.0 {
        return Ok(inputs.iter().map(|&n| plain(n)).collect());
    }
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", job.input.display());
    let flat = scene.flattened().map_err(|e| at(&e))?;
    let mut flat = dynlod::Mesh::build(&flat, job.build).map_err(|e| at(&e))?;
    if job.lock_border {
        lock_border_vertices(&mut flat);
    }
    let target = (flat.topology.live_face_count() as f64 * ratio).round() as usize;
    let (flat, _, _, _) = run(flat, &job.engine, Some(target), 1.0)?;
    Ok(scene.allot(&flat).into_iter().zip(inputs).map(|(t, &n)| t.map(|t| t.min(n)).or(plain(n))).collect())
}
