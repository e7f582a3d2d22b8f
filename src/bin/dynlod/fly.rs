//! `dynlod fly` and the runtime part of `dynlod demo`: formatting what [`dynlod::fly`] measures.

use std::io::Write;
use std::path::Path;

use dynlod::fly::{fly, fly_scene, FlyOptions, FlyReport};
use dynlod::io::GltfScene;
use dynlod::lod::{FrameStats, FrameStop, SceneRuntime};
use dynlod::{BuildOptions, Mesh};

/// What `fly` flies: one mesh (a glTF scene baked into it), or a glTF scene kept as it is
/// (`--instanced`).
pub enum Subject {
    /// One mesh under one runtime (boxed, as the scene runtime: either is hundreds of bytes
    /// of lists and state).
    Mesh(Box<Mesh>),
    /// A scene's meshes, each under a runtime serving its placements; the scene's world bounds.
    Scene(Box<SceneRuntime>, ([f32; 3], [f32; 3])),
}

impl Subject {
    /// Loads `path` as a kept glTF scene under a [`SceneRuntime`] (with the audit `--verify`
    /// needs) with up to `groups` runtimes per mesh.
    pub fn scene(path: &Path, build: BuildOptions, o: &FlyOptions, groups: usize) -> Result<Self, String> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("gltf" | "glb")) {
            return Err(format!("{}: --instanced needs a glTF scene (.gltf or .glb)", path.display()));
        }
        let scene = GltfScene::load(path).map_err(|e| e.to_string())?;
        let options = o.runtime.clone().audit(o.runtime.audit || o.verify);
        let mut rt = SceneRuntime::new(&scene, build, options).map_err(|e| format!("{}: {e}", path.display()))?;
        rt.set_instance_groups(groups);
        for note in rt.stretched() {
            eprintln!("note: {}: {note}", path.display());
        }
        Ok(Self::Scene(Box::new(rt), scene.world_bounds()))
    }
}

const CSV_HEADER: &str = concat!(
    "frame,triangles,vertices,collapses,splits,rebalanced,split_rounds,collapse_rounds,",
    "update_ms,classify_ms,split_ms,collapse_ms,rebalance_ms,output_ms,max_chain_depth,mean_chain_depth,",
    "pixel_error,changed_triangles,changed_ranges,stop,screen_error_px,graded_phases,attempts,",
    "rebalance_attempts,skipped"
);

fn csv_row(s: &FrameStats, screen_error: f32) -> String {
    format!(
        "{},{},{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{},{:.4},{},{},{},{:?},{},{},{},{},{}",
        s.frame,
        s.triangles,
        s.vertices,
        s.collapses,
        s.splits,
        s.rebalanced,
        s.split_rounds,
        s.collapse_rounds,
        s.total_ms,
        s.classify_ms,
        s.split_ms,
        s.collapse_ms,
        s.rebalance_ms,
        s.output_ms,
        s.max_chain_depth,
        s.mean_chain_depth,
        s.pixel_error,
        s.changed_triangles,
        s.changed_ranges,
        s.stop,
        screen_error,
        s.graded_phases,
        s.attempts,
        s.rebalance_attempts,
        u8::from(s.skipped)
    )
}

/// Writes `text` to `path` atomically (temp file in the same folder, then rename).
fn write_atomic(path: &Path, text: &str) -> Result<(), String> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut tmp = tempfile::NamedTempFile::new_in(dir).map_err(|e| format!("{}: {e}", path.display()))?;
    tmp.write_all(text.as_bytes()).map_err(|e| format!("{}: {e}", path.display()))?;
    tmp.persist(path).map_err(|e| format!("{}: {}", path.display(), e.error))?;
    Ok(())
}

/// `baseline`: the process's resident memory before the mesh was loaded, so the summary can
/// set the growth the operating system saw beside `memory_report`'s own count. That growth
/// is read after the last frame while the runtime is still alive, once the allocator has
/// handed back what loading and the cold start freed ([`dynlod::rss::trim_heap`]): the heap
/// pages it counts are then the ones the runtime holds, as `memory_report` counts them.
pub fn run(
    subject: Subject,
    o: &FlyOptions,
    csv: Option<&Path>,
    json: bool,
    baseline: Option<dynlod::rss::Resident>,
) -> Result<(), String> {
    let text = !json;
    if text {
        println!(
            "{:>6} {:>9} {:>9} {:>7} {:>10} {:>6}",
            "frame", "triangles", "collapses", "splits", "update ms", "depth"
        );
    }
    let every = (o.frames / 24).max(1);
    let mut at_end = None;
    // (meshes, instances, most runtimes per mesh, runtimes) of a kept scene.
    let scene = match &subject {
        Subject::Mesh(_) => None,
        Subject::Scene(rt, _) => Some((
            rt.mesh_count(),
            rt.meshes().iter().map(|m| m.placements.len()).sum::<usize>(),
            rt.instance_groups(),
            rt.meshes().len(),
        )),
    };
    let each = |s: &FrameStats| {
        if s.frame == o.frames as u64 {
            let trimmed = dynlod::rss::trim_heap();
            at_end = dynlod::rss::resident().map(|r| (r, trimmed));
        }
        if text && (s.frame == 1 || s.frame % every as u64 == 0) {
            println!(
                "{:>6} {:>9} {:>9} {:>7} {:>10.3} {:>6}",
                s.frame, s.triangles, s.collapses, s.splits, s.total_ms, s.max_chain_depth
            );
        }
    };
    let report = match subject {
        Subject::Mesh(mesh) => fly(*mesh, o, each),
        Subject::Scene(rt, bounds) => fly_scene(*rt, bounds, o, each),
    };
    let report = match report {
        Ok(r) => r,
        Err(e) => {
            eprintln!("dynlod: verify failed at {e}");
            std::process::exit(1);
        }
    };
    if let Some(path) = csv {
        let mut out = String::from(CSV_HEADER);
        out.push('\n');
        for (s, &e) in report.frames.iter().zip(&report.screen_errors) {
            out.push_str(&csv_row(s, e));
            out.push('\n');
        }
        write_atomic(path, &out)?;
    }
    let rss_growth = baseline.zip(at_end).map(|(b, (r, _))| r.anon.saturating_sub(b.anon));
    let (median, p99) = report.warm_percentiles();
    let (lo, hi) = report.triangle_range();
    let screen_error = report.warm_screen_error();
    // Triangle counts of the frames over the budget, in budget mode.
    let over: Option<(usize, Vec<usize>)> =
        o.runtime.budget.map(|b| (b, report.frames.iter().filter(|f| f.triangles > b).map(|f| f.triangles).collect()));
    if json {
        let mut v = serde_json::json!({
            "frames": report.frames.len(),
            "input_triangles": report.input_triangles,
            "vertices": report.vertices,
            "median_update_ms": median,
            "p99_update_ms": p99,
            "first_update_ms": report.frames.first().map(|f| f.total_ms),
            "min_triangles": lo,
            "max_triangles": hi,
            "collapses": report.frames.iter().map(|f| f.collapses).sum::<usize>(),
            "splits": report.frames.iter().map(|f| f.splits).sum::<usize>(),
            "max_chain_depth": report.frames.iter().map(|f| f.max_chain_depth).max(),
            "mean_screen_error_px": screen_error.0,
            "max_screen_error_px": screen_error.1,
            "memory_bytes": report.memory_bytes,
            "rss_growth_bytes": rss_growth,
            "peak_rss_bytes": at_end.map(|(r, _)| r.peak),
            "heap_trimmed": at_end.map(|(_, t)| t),
            "verified": o.verify,
            "projection": if o.orthographic { "orthographic" } else { "perspective" },
            "cameras": o.cameras,
            "instanced": scene.is_some(),
            "graded_cuts": report.frames.iter().skip(1).filter(|f| f.graded_phases > 0).count(),
            "rebalanced": report.frames.iter().map(|f| f.rebalanced).sum::<usize>(),
            "rebalance_attempts": report.frames.iter().map(|f| f.rebalance_attempts).sum::<usize>(),
            "skipped_frames": report.frames.iter().filter(|f| f.skipped).count(),
        });
        if let Some((meshes, instances, groups, runtimes)) = scene {
            v["meshes"] = meshes.into();
            v["instances"] = instances.into();
            v["instance_groups"] = groups.into();
            v["runtimes"] = runtimes.into();
        }
        if let Some(cap) = o.runtime.max_edits {
            v["max_edits"] = cap.into();
            v["frames_at_edit_cap"] = report.frames.iter().filter(|f| f.stop == FrameStop::EditCap).count().into();
        }
        if let Some((b, over)) = &over {
            v["budget"] = (*b).into();
            v["frames_over_budget"] = over.len().into();
            v["max_attempts"] = report.frames.iter().map(|f| f.attempts).max().into();
        }
        println!("{v}");
    } else {
        summary(&report, median, p99, lo, hi);
        let (mean_px, max_px) = screen_error;
        println!("screen-space error left on warm frames: mean {mean_px:.3} px, largest {max_px:.3} px");
        if let Some((b, over)) = &over {
            if let Some(fewest) = over.iter().min() {
                eprintln!(
                    "note: over the budget of {b} triangles on {} of {} frames (fewest then: {fewest}): \
                     what was left were anchors, which always stay (papers/000 §3), and vertices with no \
                     collapse into a vertex that stays that the boundary planes allow from those eyes",
                    over.len(),
                    report.frames.len()
                );
            }
        }
        if let Some(g) = rss_growth {
            println!("resident heap grew by {g} bytes from before loading to the last frame (the OS's view of the same state)");
        }
    }
    Ok(())
}

fn summary(r: &FlyReport, median: f64, p99: f64, lo: usize, hi: usize) {
    println!(
        "\n{} frames: warm update median {median:.3} ms, p99 {p99:.3} ms (first frame {:.1} ms); \
         {lo}–{hi} of {} triangles; {} bytes of runtime state",
        r.frames.len(),
        r.frames.first().map_or(0.0, |f| f.total_ms),
        r.input_triangles,
        r.memory_bytes
    );
}

/// The demo's runtime table: an orbit, then a dolly, around the bunny.
pub fn demo_table(mesh: Mesh) -> Result<(), String> {
    println!(
        "{:<28} {:>7} {:>12} {:>12} {:>13} {:>7}",
        "camera", "frames", "median ms", "p99 ms", "triangles", "splits"
    );
    use dynlod::camera_path::CameraPath::{Cuts, Dolly, Orbit, Still};
    for (label, path, orthographic, max_edits, cameras) in [
        ("orbit 1°/frame, 2 diagonals", Orbit, false, None, 1),
        ("the same, orthographic", Orbit, true, None, 1),
        ("the same, 2 cameras opposite", Orbit, false, None, 2),
        ("dolly 4 → 0.3 → 4 diagonals", Dolly, false, None, 1),
        ("cuts 0.6 ↔ 40 diagonals", Cuts, false, None, 1),
        ("the same, ≤ 2,000 edits/frame", Cuts, false, Some(2000), 1),
        ("still (skipped once settled)", Still, false, None, 1),
    ] {
        let frames = 120;
        // Timed on its own: the per-frame checks walk the whole mesh between updates, which
        // leaves the next update with cold caches and a sleeping pool (about 3x the time).
        // The checked flight must see the same frames (the runtime is deterministic).
        let o = FlyOptions::default()
            .path(path)
            .frames(frames)
            .orthographic(orthographic)
            .cameras(cameras)
            .runtime(dynlod::lod::RuntimeOptions::default().max_edits(max_edits));
        let r = fly(mesh.clone(), &o, |_| {}).map_err(|e| format!("flight failed at {e}"))?;
        let checked = fly(mesh.clone(), &o.verify(true), |_| {}).map_err(|e| format!("verify failed at {e}"))?;
        let counts = |r: &FlyReport| r.frames.iter().map(|f| (f.triangles, f.splits, f.collapses)).collect::<Vec<_>>();
        if counts(&r) != counts(&checked) {
            return Err(format!("{label}: the checked flight saw other frames than the timed one"));
        }
        let (median, p99) = r.warm_percentiles();
        let (lo, hi) = r.triangle_range();
        println!(
            "{label:<28} {:>7} {:>12.3} {:>12.3} {:>13} {:>7}",
            frames,
            median,
            p99,
            format!("{lo}–{hi}"),
            r.frames.iter().map(|f| f.splits).sum::<usize>()
        );
    }
    demo_scene_row(&mesh)?;
    println!(
        "\n(timed without checks; a second flight of each path, checked after every frame, saw the same \
         frames; a cut's frame is the p99 above, spread over frames by `--max-edits`; try \
         `dynlod fly MESH --path dolly --csv frames.csv`, or `--orthographic`, `--path cuts`, or \
         `--cameras 2` for one runtime serving two cameras, a split screen; the last row is a \
         scene of three bunnies in a row under one budget for all it draws, as \
         `fly SCENE.glb --instanced --budget N` flies a glTF level)"
    );
    Ok(())
}

/// The demo's scene row: the bunny drawn three times in a row (one runtime serving the three
/// placements, `SceneRuntime`) under one budget of 20,000 triangles for all it draws, orbited
/// like the rows above; checked the same way.
fn demo_scene_row(mesh: &Mesh) -> Result<(), String> {
    const LABEL: &str = "3 bunnies, budget 20,000";
    let (lo, hi) = dynlod::mesh::bounds(mesh.positions.iter().copied());
    let step = 1.2 * (hi[0] - lo[0]);
    let placed = |x: f32| [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [x, 0.0, 0.0, 1.0]];
    let worlds: Vec<_> = [-step, 0.0, step].map(placed).to_vec();
    let bounds = ([lo[0] - step, lo[1], lo[2]], [hi[0] + step, hi[1], hi[2]]);
    let scene = |audit: bool| {
        let options = dynlod::lod::RuntimeOptions::default().budget(Some(20_000)).audit(audit);
        SceneRuntime::from_meshes(vec![(mesh.clone(), worlds.clone())], options).map_err(|e| e.to_string())
    };
    let o = FlyOptions::default().frames(120);
    let r = fly_scene(scene(false)?, bounds, &o, |_| {}).map_err(|e| format!("flight failed at {e}"))?;
    let checked =
        fly_scene(scene(true)?, bounds, &o.verify(true), |_| {}).map_err(|e| format!("verify failed at {e}"))?;
    let counts = |r: &FlyReport| r.frames.iter().map(|f| (f.triangles, f.splits, f.collapses)).collect::<Vec<_>>();
    if counts(&r) != counts(&checked) {
        return Err(format!("{LABEL}: the checked flight saw other frames than the timed one"));
    }
    let (median, p99) = r.warm_percentiles();
    let (lo, hi) = r.triangle_range();
    let splits = r.frames.iter().map(|f| f.splits).sum::<usize>();
    println!("{LABEL:<28} {:>7} {median:>12.3} {p99:>12.3} {:>13} {splits:>7}", r.frames.len(), format!("{lo}–{hi}"));
    Ok(())
}
