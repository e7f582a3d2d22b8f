//! `dynlod simplify --method parallel`: papers/000's rounds of parallel half-edge collapses,
//! view-dependent with `--eye`, to a pixel error or a triangle target; and `--method
//! runtime`, the frame-to-frame runtime's cut for the same cameras (graded, its charges
//! carrying what each removal buried: `Runtime::cut`).

use dynlod::BuildOptions;

use super::{add_input_notes, print_input_notes, save_output, ParallelArgs};

/// What a cut did, whichever engine made it.
pub(super) struct Made {
    pub output_triangles: usize,
    /// Rounds (papers/000), or the runtime's updates over every threshold tried.
    pub iterations: usize,
    pub milliseconds: f64,
    pub stop: String,
    pub collapses: usize,
    /// Candidates that evaluated their targets (papers/000's rounds only).
    pub selections: Option<usize>,
    /// The threshold the cut ended at (pixels with an eye, else model units).
    pub threshold: f32,
}

/// `simplify --method parallel` or `runtime`: view-dependent with --eye (each --eye a
/// camera; the cut keeps what every one needs).
pub(super) fn parallel(
    input: &std::path::Path,
    output: &std::path::Path,
    a: ParallelArgs,
    lock_border: bool,
    build: BuildOptions,
    json: bool,
) -> Result<(), String> {
    if dynlod::io::WriteFormat::from_path(output).is_none() {
        return Err(format!("{}: cannot write this extension (use .obj, .ply or .glb)", output.display()));
    }
    check_args(&a)?;
    let mut mesh = dynlod::load_mesh(input, build).map_err(|e| e.to_string())?;
    if lock_border {
        dynlod::simplify::lock_border(&mut mesh);
    }
    let views = views_of(&a, mesh.bounds(), mesh.origin)?;
    let input_triangles = mesh.topology.live_face_count();
    let target = a.triangles.or(a.ratio.map(|r| (input_triangles as f64 * r).round() as usize));
    let (result, made) = cut(&mesh, &views, &a, target)?;
    let saved = save_output(output, &result.to_indexed())?;
    // A target not reached: how many of the vertices left may not move at all.
    let short = target.filter(|&n| made.output_triangles > n).map(|_| {
        let (live, fixed) =
            dynlod::mesh::constraints::count_fixed(&result, dynlod::mesh::constraints::BORDER_CORNER_DEGREES);
        (live, fixed, anchors_left(&mesh, &result, a.runtime))
    });
    let method = if a.runtime { "runtime" } else { "parallel" };
    if json {
        let mut v = serde_json::json!({
            "input": input.display().to_string(), "output": output.display().to_string(), "method": method,
            "input_triangles": input_triangles, "output_triangles": made.output_triangles,
            "iterations": made.iterations, "milliseconds": made.milliseconds, "threshold": made.threshold,
            "view_dependent": !views.is_empty(), "cameras": views.len(), "stop": made.stop,
            "schedule": a.schedule.name(), "collapses": made.collapses,
        });
        if let Some(n) = made.selections {
            v["selections"] = n.into();
        }
        if let Some(n) = target {
            v["target_triangles"] = n.into();
            v["target_met"] = (made.output_triangles <= n).into();
        }
        if let Some((live, fixed, anchors)) = short {
            v["remaining"] = serde_json::json!({ "vertices": live, "fixed": fixed, "anchors": anchors });
        }
        add_input_notes(&mut v, &mesh);
        saved.add_to(&mut v);
        println!("{v}");
    } else {
        print_input_notes(input, &mesh);
        saved.print(output);
        println!(
            "{} -> {}: {} -> {} triangles in {} rounds, {:.1} ms (u = {}{}, stopped: {})",
            input.display(),
            output.display(),
            input_triangles,
            made.output_triangles,
            made.iterations,
            made.milliseconds,
            made.threshold,
            if views.is_empty() { "" } else { " px" },
            made.stop
        );
        if let (Some(n), Some((live, fixed, anchors))) = (target, short) {
            eprintln!(
                "note: target of {n} triangles not reached: {} is the fewest any threshold gave; of the {live} \
                 vertices left, {anchors} are anchors, which always stay (papers/000 §3: one per cell of a grid, \
                 and every vertex no collapse may move), {fixed} may not move (border corners, seam \
                 junctions, where primitives meet, locked), and the others found no collapse into a vertex \
                 that stays that the papers/000 boundary planes{} and the link condition allow \
                 (--method qem or mca-qem go further)",
                made.output_triangles,
                match views.len() {
                    0 => "",
                    1 => " from this eye",
                    _ => " from these eyes",
                }
            );
        }
    }
    Ok(())
}

/// papers/000 rounds on `mesh` (from every view of `views` at once; none: view-independent),
/// or with `--method runtime` the runtime's cut, down to `target` triangles or, without one,
/// to the threshold the arguments give: the result and its figures.
pub(super) fn cut(
    mesh: &dynlod::Mesh,
    views: &[dynlod::view::View],
    a: &ParallelArgs,
    target: Option<usize>,
) -> Result<(dynlod::Mesh, Made), String> {
    use dynlod::lod::coarsen::{coarsen_to_triangles, coarsen_views, CoarsenOptions};
    let view_dependent = !views.is_empty();
    let (lo, hi) = mesh.bounds();
    let diag = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f32>().sqrt();
    let threshold = if view_dependent { a.pixel_error } else { a.error.map(|e| e as f32) };
    let threshold = threshold.filter(|u| u.is_finite() && *u >= 0.0);
    if target.is_none() && threshold.is_none() {
        return Err(if view_dependent {
            "give --pixel-error PX (or --triangles N / --ratio R) with --eye".into()
        } else {
            "give --error E (model units) or --triangles N / --ratio R".into()
        });
    }
    if a.runtime {
        return runtime_cut(mesh, views, target, threshold);
    }
    let options = CoarsenOptions::default().schedule(a.schedule);
    let (m, stats, u) = match (target, threshold) {
        (Some(n), _) => {
            let (lo_u, hi_u) = if view_dependent { (1e-3, 1e4) } else { (1e-7 * diag, diag) };
            coarsen_to_triangles(mesh, views, &options, n, lo_u, hi_u)
        }
        (None, Some(u)) => {
            let mut m = mesh.clone();
            let s = coarsen_views(&mut m, views, options.clone().threshold(u));
            (m, s, u)
        }
        (None, None) => unreachable!("a target or a threshold, checked above"),
    };
    let made = Made {
        output_triangles: stats.output_triangles,
        iterations: stats.rounds.len(),
        milliseconds: stats.milliseconds,
        stop: format!("{:?}", stats.stop),
        collapses: stats.rounds.iter().map(|r| r.collapsed).sum(),
        selections: Some(stats.rounds.iter().map(|r| r.candidates - r.waiting).sum()),
        threshold: u,
    };
    Ok((m, made))
}

/// `--method runtime`: the runtime's cut (`Runtime::cut`) at the threshold, or with the
/// threshold searched for `target` triangles (`Runtime::cut_to_triangles`).
fn runtime_cut(
    mesh: &dynlod::Mesh,
    views: &[dynlod::view::View],
    target: Option<usize>,
    threshold: Option<f32>,
) -> Result<(dynlod::Mesh, Made), String> {
    use dynlod::lod::{Runtime, RuntimeOptions};
    let options = RuntimeOptions::default().pixel_error(threshold.unwrap_or(1.0));
    let cut = match target {
        Some(n) => Runtime::cut_to_triangles(mesh.clone(), views, options, n),
        None => Runtime::cut(mesh.clone(), views, options),
    }
    .map_err(|e| e.to_string())?;
    let stop = if cut.settled { format!("{:?}", cut.last.stop) } else { "FrameCap".into() };
    let made = Made {
        output_triangles: cut.mesh.topology.live_face_count(),
        iterations: cut.frames,
        milliseconds: cut.milliseconds,
        stop,
        collapses: cut.collapses - cut.splits,
        selections: None,
        threshold: cut.threshold,
    };
    Ok((cut.mesh, made))
}

/// How many of `result`'s live vertices are anchors that always stay in the rounds (or the
/// `runtime`) that made it from `input` (the default anchors, which `cut` uses).
fn anchors_left(input: &dynlod::Mesh, result: &dynlod::Mesh, runtime: bool) -> usize {
    use dynlod::lod::passes::{classify, structure_anchors};
    let options = if runtime {
        dynlod::lod::RuntimeOptions::default().anchors.expect("the runtime's default anchors")
    } else {
        dynlod::lod::coarsen::CoarsenOptions::default().anchors.expect("the rounds' default anchors")
    };
    let (_, errors) = classify::vertex_normals_and_errors(&input.topology, &input.positions);
    let anchors = structure_anchors::mesh_anchors(input, &errors, &options);
    anchors.always().filter(|&v| result.topology.vertex_he[v as usize] != dynlod::topology::INVALID).count()
}

/// The checks of the camera and target arguments that need no mesh.
pub(super) fn check_args(a: &ParallelArgs) -> Result<(), String> {
    if !(a.fov > 0.0 && a.fov < 180.0) {
        return Err(format!("--fov must be in (0, 180) degrees, got {}", a.fov));
    }
    if let Some(h) = a.ortho_height {
        if !(h.is_finite() && h > 0.0) {
            return Err(format!("--ortho-height must be a positive number of world units, got {h}"));
        }
        if a.eye.is_empty() {
            return Err("--ortho-height places an orthographic camera: give --eye too".into());
        }
    }
    if a.target.len() > 1 && a.target.len() != a.eye.len() {
        return Err(format!(
            "--target: give it once for every --eye, or once per --eye (eyes: {}, targets: {})",
            a.eye.len(),
            a.target.len()
        ));
    }
    if let Some(r) = a.ratio {
        if !(0.0..=1.0).contains(&r) {
            return Err(format!("--ratio must be between 0 and 1, got {r}"));
        }
    }
    Ok(())
}

/// The cameras each `--eye` places (none without one), each looking at its `--target`, the
/// one `--target`, or else the centre of `bounds` (the mesh's, or a kept scene's in world
/// space).
pub(super) fn views_of(
    a: &ParallelArgs,
    (lo, hi): ([f32; 3], [f32; 3]),
    origin: [f64; 3],
) -> Result<Vec<dynlod::view::View>, String> {
    let (centre, _) = dynlod::camera_path::frame_box(lo, hi);
    let (up, viewport) = ([0.0, 1.0, 0.0], (a.width, a.height));
    // --eye and --target are in the file's coordinates; the mesh's are relative to its origin.
    let relative = |p: [f64; 3]| -> [f32; 3] { std::array::from_fn(|k| (p[k] - origin[k]) as f32) };
    let mut views = Vec::with_capacity(a.eye.len());
    for (k, &eye) in a.eye.iter().enumerate() {
        let target = a.target.get(k).or(a.target.first()).copied();
        let (eye, target) = (relative(eye), target.map_or(centre, relative));
        let view = match a.ortho_height {
            Some(h) => dynlod::view::View::orthographic(eye, target, up, h, viewport),
            None => dynlod::view::View::perspective(eye, target, up, a.fov, viewport),
        };
        // An eye on its target (the mesh's centre when no --target is given) has no direction.
        let xyz = |p: [f32; 3]| {
            let [x, y, z] = [0, 1, 2].map(|k| dynlod::mesh::origin::InFile(origin[k], p[k]));
            format!("{x},{y},{z}")
        };
        view.check().map_err(|e| format!("camera {} (--eye {}, target {}): {e}", k + 1, xyz(eye), xyz(target)))?;
        views.push(view);
    }
    Ok(views)
}
