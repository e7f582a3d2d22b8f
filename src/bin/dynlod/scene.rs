//! `dynlod simplify` from glTF to GLB: each mesh definition simplified on its own, in its own
//! space, and the scene written back around them (nodes, skins, animations, materials, morph
//! targets; [`dynlod::io::GltfScene`]). `--flatten` bakes the scene into one mesh instead.

use std::path::Path;

use dynlod::io::GltfScene;
use dynlod::simplify::{Drawn, Method, SceneEngine, SceneOptions, SceneTarget, SimplifyOptions};
use dynlod::view::{ModelMatrixError, View};
use dynlod::BuildOptions;

use super::ParallelArgs;

/// The engine each mesh goes through.
pub(super) enum Engine {
    /// An offline method, its options set but for the target.
    Offline(SimplifyOptions, Method),
    /// papers/000 rounds, from the world-space cameras `--eye` places (set once the scene is
    /// read: they look at the scene's centre by default), carried into each mesh's space
    /// through every node that draws it.
    Parallel(ParallelArgs, Vec<View>),
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

/// What one mesh's run says, whichever the engine.
pub(super) struct Ran {
    stop: String,
    max_error: Option<f64>,
}

impl SceneEngine for Engine {
    /// The parallel rounds refuse to run with neither a target nor an error bound.
    type Stats = Result<Ran, String>;

    fn cut(&self, mesh: &mut dynlod::Mesh, target: Option<usize>, drawn: &Drawn<'_>) -> Self::Stats {
        match self {
            Engine::Offline(opts, _) => {
                let input = mesh.topology.live_face_count();
                let progress = input > 100_000 && std::io::IsTerminal::is_terminal(&std::io::stderr());
                let stats = opts.progress(progress).cut(mesh, target, drawn);
                Ok(Ran { stop: format!("{:?}", stats.stop), max_error: Some(stats.max_error) })
            }
            Engine::Parallel(a, cameras) => {
                // No node draws it: no camera sees it, and it is kept as it is.
                if !cameras.is_empty() && drawn.placements.is_empty() {
                    return Ok(Ran { stop: "NotDrawn".into(), max_error: None });
                }
                let views = instance_views(cameras, drawn)?;
                let a = ParallelArgs { error: a.error.map(|e| e / drawn.scale), ..a.clone() };
                let (m, made) = super::parallel::cut(mesh, &views, &a, target)?;
                *mesh = m;
                Ok(Ran { stop: made.stop, max_error: None })
            }
        }
    }
}

/// The world cameras seen from the mesh's space through each node that draws it: one view per
/// camera and instance, so that the mesh keeps what its most demanding instance shows and
/// turns no triangle against any of them. A stretched or sheared node is refused (a pixel
/// error cannot be told in the mesh's own space there; `--flatten` bakes it into world space).
fn instance_views(cameras: &[View], drawn: &Drawn<'_>) -> Result<Vec<View>, String> {
    let mut views = Vec::with_capacity(cameras.len() * drawn.placements.len());
    dynlod::view::views_through(cameras, drawn.placements, &mut views).map_err(|(k, e)| {
        let why = match e {
            ModelMatrixError::NotSimilarity { scales } => {
                format!("it scales the mesh's axes by {scales:?} or shears them, so a pixel error would depend on its direction")
            }
            other => other.to_string(),
        };
        let node = drawn.placements[k].label(k);
        format!("--eye: {node} draws it with a transform the camera cannot be carried through ({why}); add --flatten to cut the scene baked into world space")
    })?;
    Ok(views)
}

pub(super) fn simplify_scene(mut job: Job<'_>) -> Result<(), String> {
    if let Engine::Parallel(a, _) = &job.engine {
        super::parallel::check_args(a)?;
    }
    let start = std::time::Instant::now();
    let scene = GltfScene::load(job.input).map_err(|e| e.to_string())?;
    if let Engine::Parallel(a, cameras) = &mut job.engine {
        *cameras = super::parallel::views_of(a, scene.world_bounds(), [0.0; 3])?;
    }
    let target = match (job.triangles, job.ratio) {
        (Some(n), _) => SceneTarget::Triangles(n),
        (None, Some(r)) => SceneTarget::Ratio(r),
        (None, None) => SceneTarget::Bound,
    };
    let options = SceneOptions::default().target(target).build(job.build).lock_border(job.lock_border);
    let lod = dynlod::simplify::simplify_scene(&scene, &job.engine, options)
        .map_err(|e| format!("{}: {e}", job.input.display()))?;
    let runs = lod
        .reports
        .iter()
        .zip(&scene.meshes)
        .map(|(r, sm)| r.stats.as_ref().map_err(|e| format!("{}: {}: {e}", job.input.display(), sm.label())))
        .collect::<Result<Vec<&Ran>, _>>()?;
    let mut notes = lod.notes.clone();
    let written = scene.save(job.output, &lod.meshes).map_err(|e| format!("{}: {e}", job.output.display()))?;
    notes.extend(written);
    let ms = start.elapsed().as_secs_f64() * 1e3;
    let (input, output) = (lod.drawn_input_triangles(), lod.drawn_output_triangles());
    let (file_input, file_output) =
        lod.reports.iter().fold((0, 0), |(i, o), r| (i + r.input_triangles, o + r.output_triangles));
    let asked = job.triangles.or(job.ratio.map(|r| (input as f64 * r).round() as usize));
    if job.json {
        let meshes: Vec<serde_json::Value> = scene
            .meshes
            .iter()
            .zip(lod.reports.iter().zip(&runs))
            .map(|(sm, (r, ran))| {
                let mut v = serde_json::json!({
                    "mesh": sm.index, "name": sm.name, "instances": r.instances,
                    "input_triangles": r.input_triangles, "output_triangles": r.output_triangles,
                    "stop": ran.stop,
                });
                if let Some(t) = r.target {
                    v["target_triangles"] = t.into();
                }
                if let Some(e) = ran.max_error {
                    v["max_error"] = e.into();
                }
                v
            })
            .collect();
        let method = match &job.engine {
            Engine::Offline(_, m) => m.name(),
            Engine::Parallel(a, _) if a.runtime => "runtime",
            Engine::Parallel(..) => "parallel",
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
        for (sm, (r, ran)) in scene.meshes.iter().zip(lod.reports.iter().zip(&runs)) {
            let short = r
                .target
                .filter(|&t| r.output_triangles > t)
                .map(|t| format!(", target {t} not reached"))
                .unwrap_or_default();
            let drawn = if r.instances == 1 { String::new() } else { format!(", drawn {}x", r.instances) };
            println!("  {}: {} -> {} ({}{short}{drawn})", sm.label(), r.input_triangles, r.output_triangles, ran.stop);
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
