//! The `dynlod` binary: exit codes, JSON keys, one-line errors.

use base64::Engine;
use std::process::Command;

mod common;
use common::dynlod;

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn info_json_has_the_documented_keys() {
    let dir = tempfile::tempdir().unwrap();
    // A square of two triangles plus a duplicate of the first.
    let f = write(&dir, "sq.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n3 2 1 0\n");
    let (code, out, err) = dynlod(&["info", "--json", &f]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "vertices",
        "triangles",
        "input_triangles",
        "components",
        "boundary_edges",
        "non_manifold_edges",
        "repairs",
        "bbox_min",
        "bbox_max",
        "genus",
        "boundary_loops",
        "wedges",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {out}");
    }
    assert_eq!(v["triangles"], 2);
    assert_eq!(v["input_triangles"], 3);
    assert_eq!(v["boundary_edges"], 4);
    assert_eq!(v["bbox_max"], serde_json::json!([1.0, 1.0, 0.0]));
    assert_eq!(v["repairs"][0]["kind"], "dropped_duplicate_faces");
    assert_eq!(v["repairs"][0]["examples"][0], "face 2");
}

#[test]
fn bad_input_exits_2_with_one_line_naming_file_and_place() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n");
    let (code, out, err) = dynlod(&["info", &f]);
    assert_eq!(code, 2);
    assert!(out.is_empty());
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("bad.off") && err.contains("face 0 corner 2"), "{err}");
    let (code, _, err) = dynlod(&["info", &dir.path().join("nope.ply").to_string_lossy()]);
    assert_eq!(code, 2);
    assert!(err.contains("nope.ply"));
}

#[test]
fn strict_refuses_a_file_that_needs_repair() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "dup.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n");
    assert_eq!(dynlod(&["info", &f]).0, 0);
    let (code, _, err) = dynlod(&["info", "--strict", &f]);
    assert_eq!(code, 2);
    assert!(err.contains("strict") && err.contains("duplicate"), "{err}");
}

#[test]
fn demo_runs_on_the_bundled_bunny() {
    let (code, out, err) = dynlod(&["demo"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("69451"), "{out}");
    assert!(out.contains("valid                  yes"), "{out}");
    assert!(out.contains("orbit 1°/frame") && out.contains("the same, orthographic") && out.contains("dolly"), "{out}");
    assert!(out.contains("cuts 0.6 ↔ 40 diagonals") && out.contains("≤ 2,000 edits/frame"), "{out}");
    // Two cameras at once keep what each needs: more than one camera at the same distance.
    let triangles = |label: &str| -> usize {
        let line = out.lines().find(|l| l.starts_with(label)).unwrap_or_else(|| panic!("no row {label:?}: {out}"));
        line[label.len()..].split_whitespace().next().unwrap().parse().unwrap()
    };
    assert!(triangles("mid, front and back") > triangles("mid (2 diagonals)") * 3 / 2, "{out}");
    // The runtime's cut (the fifth column) keeps fewer the farther the camera, where the
    // paper's rounds stop at about the same count from 8 diagonals on.
    let runtime_cut = |label: &str| -> usize {
        let line = out.lines().find(|l| l.starts_with(label)).unwrap_or_else(|| panic!("no row {label:?}: {out}"));
        line[label.len()..].split_whitespace().nth(4).unwrap().parse().unwrap()
    };
    let cuts =
        ["close (0.5 diagonal)", "mid (2 diagonals)", "far (8 diagonals)", "farther (32 diagonals)"].map(runtime_cut);
    assert!(
        cuts.windows(2).all(|w| w[1] < w[0]) && cuts[3] * 3 < triangles("farther (32 diagonals)"),
        "{cuts:?}: {out}"
    );
    // The runtime's two opposite cameras keep more than its one camera, on every frame.
    let fewest = |label: &str| -> usize {
        let line = out.lines().find(|l| l.starts_with(label)).unwrap_or_else(|| panic!("no row {label:?}: {out}"));
        let range = line[label.len()..].split_whitespace().nth(3).unwrap();
        range.split('–').next().unwrap().parse().unwrap()
    };
    assert!(fewest("the same, 2 cameras opposite") > fewest("orbit 1°/frame"), "{out}");
    // Three bunnies under one budget for all they draw: within it on every frame.
    let most = |label: &str| -> usize {
        let line = out.lines().find(|l| l.starts_with(label)).unwrap_or_else(|| panic!("no row {label:?}: {out}"));
        let range = line[label.len()..].split_whitespace().nth(3).unwrap();
        range.split('–').nth(1).unwrap().parse().unwrap()
    };
    let scene = most("3 bunnies, budget 20,000");
    assert!((15_000..=20_000).contains(&scene), "{out}");
}

/// `fly --cameras 2`: two cameras on opposite sides of the orbit, one runtime for both,
/// verified every frame. Each camera's largest error stays within the pixel error (the
/// summary's is the largest over both), and the mesh keeps more than for one camera.
#[test]
fn fly_serves_several_cameras_with_one_runtime() {
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let summary = |cameras: &str| {
        let (code, out, err) = dynlod(&["fly", bunny, "--frames", "30", "--cameras", cameras, "--verify", "--json"]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let (one, two) = (summary("1"), summary("2"));
    assert_eq!((one["cameras"].as_u64(), two["cameras"].as_u64()), (Some(1), Some(2)));
    assert!(two["max_screen_error_px"].as_f64().unwrap() <= 1.0, "{two}");
    assert!(two["min_triangles"].as_u64() > one["max_triangles"].as_u64(), "{one}\n{two}");
    let (code, _, err) = dynlod(&["fly", bunny, "--cameras", "0"]);
    assert_eq!(code, 2);
    assert!(err.contains("--cameras"), "{err}");
}

/// `--path cuts` jumps between close and far shots, verified every frame: the CSV's
/// `graded_phases` says the first frame and each jump away were graded (10, then 7: the
/// tolerance grew about 67×), and nothing else was; the jump back in splits in one frame.
#[test]
fn fly_grades_camera_cuts() {
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("cuts.csv");
    // A verified flight of the cuts path: its JSON summary, the summary's text, the CSV's text.
    let fly_cuts = |more: &[&str]| {
        let csv = csv.to_str().unwrap();
        let args = [&["fly", bunny, "--path", "cuts", "--verify", "--json", "--csv", csv], more].concat();
        let (code, out, err) = dynlod(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        (v, out, std::fs::read_to_string(csv).unwrap())
    };
    let (v, out, text) = fly_cuts(&["--frames", "8"]);
    assert!(v["max_screen_error_px"].as_f64().unwrap() <= 1.0, "{out}");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|&h| h == name).unwrap();
    let (graded, tris, stop) = (col("graded_phases"), col("triangles"), col("stop"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let phases: Vec<&str> = rows.iter().map(|r| r[graded]).collect();
    assert_eq!(phases, ["10", "0", "7", "0", "0", "0", "7", "0"], "{text}");
    let count = |r: &Vec<&str>| r[tris].parse::<usize>().unwrap();
    assert!(count(&rows[2]) < 1000 && count(&rows[4]) > 30 * count(&rows[3]), "{text}");
    assert!(rows.iter().all(|r| r[stop] == "Converged"), "{text}");
    assert_eq!(v["graded_cuts"].as_u64(), Some(2), "{out}");
    // Capped, no frame makes more than 3,000 edits and the cuts spread over frames.
    let (v, out, text) = fly_cuts(&["--frames", "40", "--max-edits", "3000"]);
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let (collapses, splits) = (col("collapses"), col("splits"));
    let edits = |r: &Vec<&str>| r[collapses].parse::<usize>().unwrap() + r[splits].parse::<usize>().unwrap();
    assert!(rows.iter().all(|r| edits(r) <= 3000), "{text}");
    let capped = rows.iter().filter(|r| r[stop] == "EditCap").count();
    assert!(capped > 10, "{text}");
    assert_eq!((v["max_edits"].as_u64(), v["frames_at_edit_cap"].as_u64()), (Some(3000), Some(capped as u64)), "{out}");
    assert_eq!(rows.last().unwrap()[stop], "Converged", "{text}");
    let (code, _, err) = dynlod(&["fly", bunny, "--max-edits", "0"]);
    assert!(code == 2 && err.contains("--max-edits"), "{err}");
}

/// `--orthographic` flies the same path through orthographic cameras, verified every frame,
/// and says so in the summary; the dolly still closes in (the view's height shrinks).
#[test]
fn fly_flies_orthographic_cameras() {
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let (code, out, err) =
        dynlod(&["fly", bunny, "--path", "dolly", "--frames", "12", "--verify", "--json", "--orthographic"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["projection"], "orthographic");
    assert!(v["min_triangles"].as_u64().unwrap() * 2 < v["max_triangles"].as_u64().unwrap(), "{out}");
    assert!(v["splits"].as_u64().unwrap() > 0, "{out}");
    assert!(v["max_screen_error_px"].as_f64().unwrap() <= 1.0, "{out}");
}

/// `--path still`: the camera rests on the orbit's first view; once a frame changes nothing
/// (rebalancing included) the rest are skipped, as the CSV's `skipped` and the JSON's
/// `skipped_frames` say, and checked after every frame (`--verify`) the mesh stays valid.
#[test]
fn fly_skips_the_frames_of_a_still_camera() {
    let dir = tempfile::tempdir().unwrap();
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let csv = dir.path().join("still.csv");
    let csv_arg = csv.to_str().unwrap();
    let (code, out, err) =
        dynlod(&["fly", bunny, "--path", "still", "--frames", "100", "--verify", "--json", "--csv", csv_arg]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let skipped = v["skipped_frames"].as_u64().unwrap();
    assert!(skipped > 40, "{out}");
    assert!(v["rebalanced"].as_u64().unwrap() > 0 && v["rebalance_attempts"].as_u64().unwrap() > 0, "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|&c| c == name).unwrap_or_else(|| panic!("no column {name}"));
    let (skip, collapses, splits, tries) = (col("skipped"), col("collapses"), col("splits"), col("rebalance_attempts"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let first = rows.iter().position(|r| r[skip] == "1").unwrap();
    assert_eq!(rows.len() - first, skipped as usize, "skipped frames come last, all of them");
    // The frame before the first skipped one changed nothing and tried no move.
    assert_eq!([rows[first - 1][collapses], rows[first - 1][splits], rows[first - 1][tries]], ["0", "0", "0"]);
}

#[test]
fn fly_writes_csv_and_json_with_the_documented_columns() {
    let dir = tempfile::tempdir().unwrap();
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let csv = dir.path().join("frames.csv");
    let csv_s = csv.to_str().unwrap();
    let (code, out, err) =
        dynlod(&["fly", bunny, "--path", "dolly", "--frames", "12", "--verify", "--json", "--csv", csv_s]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    for key in ["frames", "median_update_ms", "p99_update_ms", "min_triangles", "max_triangles", "memory_bytes"] {
        assert!(v.get(key).is_some(), "missing {key}: {out}");
    }
    assert_eq!(v["frames"], 12);
    assert!(v["min_triangles"].as_u64().unwrap() < v["max_triangles"].as_u64().unwrap());
    // Frames that converge at 1 px leave no collapse showing more than 1 px.
    let (mean_px, max_px) = (v["mean_screen_error_px"].as_f64().unwrap(), v["max_screen_error_px"].as_f64().unwrap());
    assert!(0.1 < mean_px && mean_px <= max_px && max_px <= 1.0, "{out}");
    // The runtime's own count of its bytes agrees with what the OS saw the heap grow by:
    // read at the last frame with the runtime alive, after the allocator handed back what
    // loading and the cold start freed. One worker and one glibc arena: with an arena per
    // thread the result moves with the heap's layout (1.02-1.17 on this walk, from nothing
    // more than the length of the program's path) and each further worker adds about
    // 0.3 MB (docs/BENCHMARKS.md). So pinned it gives 1.02-1.04, and a structure of 0.6 MB
    // or more left out of the count (the records, the twins: 0.8 MB each; not the arena any
    // more, 0.44 MB since stack bottoms keep no entry) fails it. Without `malloc_trim` (not
    // glibc) what the cold start freed stays resident and only a loose check is left.
    // Without --verify: its per-frame recounts allocate mesh-sized scratch.
    let out = Command::new(env!("CARGO_BIN_EXE_dynlod"))
        .args(["fly", bunny, "--path", "dolly", "--frames", "12", "--json"])
        .env("RAYON_NUM_THREADS", "1")
        .env("MALLOC_ARENA_MAX", "1")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = String::from_utf8_lossy(&out.stdout);
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    if let (Some(grew), Some(peak)) = (v["rss_growth_bytes"].as_u64(), v["peak_rss_bytes"].as_u64()) {
        let counted = v["memory_bytes"].as_u64().unwrap() as f64;
        let ratio = grew as f64 / counted;
        let window = if v["heap_trimmed"] == true { 0.95..1.12 } else { 0.5..2.5 };
        assert!(window.contains(&ratio), "resident heap growth {grew} vs counted {counted}: {out}");
        assert!(peak >= grew, "{out}");
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "frame",
        "triangles",
        "collapses",
        "splits",
        "update_ms",
        "max_chain_depth",
        "screen_error_px",
        "attempts",
        "rebalance_attempts",
        "skipped",
    ] {
        assert!(header.contains(&col), "missing column {col}");
    }
    assert_eq!(lines.count(), 12);
    // The triangle budget holds after it settles.
    let (code, out, err) = dynlod(&["fly", bunny, "--frames", "20", "--budget", "6000", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert!(v["min_triangles"].as_u64().unwrap() <= 6000, "{out}");
    assert_eq!((v["budget"].as_u64(), v["frames_over_budget"].as_u64()), (Some(6000), Some(0)), "{out}");
    // The first frame raised its threshold from 1 px within the frame, attempt by attempt.
    assert!(v["max_attempts"].as_u64().unwrap() > 1, "{out}");
    // One the boundary planes cannot reach is said so, not silently missed.
    let (code, out, err) = dynlod(&["fly", bunny, "--frames", "4", "--budget", "100", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["frames_over_budget"].as_u64(), Some(4), "{out}");
    let (_, _, err) = dynlod(&["fly", bunny, "--frames", "4", "--budget", "100"]);
    assert!(err.contains("note: over the budget of 100 triangles on 4 of 4 frames"), "{err}");
    // A bad path name is an input error.
    let (code, _, err) = dynlod(&["fly", bunny, "--path", "spiral"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("orbit, dolly, zoom, cuts or still"), "{err}");
    // The paper's schedule flies too (verified), and keeps more triangles at the same pixel
    // error than local minima (cheapest first keeps the records' charges lower).
    let summary = |sched: &str| {
        let (code, out, err) = dynlod(&["fly", bunny, "--frames", "3", "--verify", "--json", "--schedule", sched]);
        assert_eq!(code, 0, "{sched}: {err}");
        serde_json::from_str::<serde_json::Value>(out.trim()).unwrap()
    };
    let (minima, all) = (summary("local-minima"), summary("all"));
    assert!(minima["max_triangles"].as_u64() < all["max_triangles"].as_u64(), "{minima} vs {all}");
    let (code, _, err) = dynlod(&["fly", bunny, "--schedule", "some"]);
    assert_eq!(code, 2);
    assert!(err.contains("--schedule"), "{err}");
}

#[test]
fn compare_reports_hausdorff_in_absolute_and_percent() {
    let dir = tempfile::tempdir().unwrap();
    // Two unit squares 0.5 apart in z: every distance is 0.5; the diagonal is sqrt(2).
    let a = write(&dir, "a.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    let b = write(&dir, "b.off", "OFF\n4 2 0\n0 0 0.5\n1 0 0.5\n1 1 0.5\n0 1 0.5\n3 0 1 2\n3 0 2 3\n");
    let (code, out, err) = dynlod(&["compare", &a, &b, "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let f = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("missing {k}"));
    assert!((f("hausdorff_max") - 0.5).abs() < 1e-6 && (f("rms") - 0.5).abs() < 1e-6);
    assert!((f("hausdorff_max_pct") - 50.0 / 2f64.sqrt()).abs() < 1e-4);
    assert!((f("hausdorff_mean_pct") - f("rms_pct")).abs() < 1e-4);
    let (code, _, err) = dynlod(&["compare", &a, &dir.path().join("missing.ply").to_string_lossy()]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.ply"));
}

#[test]
fn simplify_writes_the_target_and_reports_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bunny_1pct.ply");
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    for method in ["mca", "qem", "mca-qem", "qem-batch"] {
        let (code, stdout, err) =
            dynlod(&["simplify", bunny, out.to_str().unwrap(), "--method", method, "--ratio", "0.01", "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        for key in ["input_triangles", "output_triangles", "iterations", "milliseconds"] {
            assert!(v.get(key).is_some(), "{method}: missing {key}");
        }
        assert_eq!(v["input_triangles"], 69_451);
        assert_eq!(v["method"], method);
        let tris = v["output_triangles"].as_u64().unwrap();
        assert!((690..=695).contains(&tris), "{method}: {tris}");
        let written = dynlod::load_mesh(&out, Default::default()).unwrap();
        assert_eq!(written.topology.live_face_count() as u64, tris);
        written.topology.validate().unwrap();
    }
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 1, "only the output, no temporary files: {names:?}");
}

/// An OBJ output's materials are written beside it, and said: `files_written` in `--json`
/// (the output last), a note on stderr without it; for the sequential methods and for the
/// parallel one alike.
#[test]
fn simplify_to_obj_lists_the_material_files_it_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let quad = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/textured_quad.obj");
    for method in ["qem", "parallel"] {
        let out = dir.path().join(format!("{method}.obj"));
        let (code, stdout, err) =
            dynlod(&["simplify", quad, out.to_str().unwrap(), "--method", method, "--ratio", "1", "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        let beside = |f: &str| dir.path().join(f).display().to_string();
        let expected = [
            beside(&format!("{method}_textured_quad_wood.png")),
            beside(&format!("{method}.mtl")),
            beside(&format!("{method}.obj")),
        ];
        assert_eq!(v["files_written"], serde_json::json!(expected), "{method}");
        assert_eq!(v["not_written"], serde_json::json!([]), "{method}");
        for f in &expected {
            assert!(std::path::Path::new(f).is_file(), "{f}");
        }
        let (code, _, err) = dynlod(&["simplify", quad, out.to_str().unwrap(), "--method", method, "--ratio", "1"]);
        assert_eq!(code, 0, "{err}");
        let note = format!("note: {}: written beside it (materials): {}, {}", expected[2], expected[0], expected[1]);
        assert!(err.contains(&note), "{method}: {err}");
        assert!(!err.contains("not dynlod's"), "{method}: {err}");
    }
    // A library of the output's name that dynlod did not write is kept, and said so.
    std::fs::write(dir.path().join("mine.mtl"), "newmtl wood\nKd 1 0 0\n").unwrap();
    let out = dir.path().join("mine.obj");
    let (code, _, err) = dynlod(&["simplify", quad, out.to_str().unwrap(), "--ratio", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains(&format!("note: {}: mine.mtl beside it is not dynlod's and was left as it is", out.display())),
        "{err}"
    );
    assert!(err.contains("mine_1.mtl") && dir.path().join("mine_1.mtl").is_file(), "{err}");
    assert_eq!(std::fs::read_to_string(dir.path().join("mine.mtl")).unwrap(), "newmtl wood\nKd 1 0 0\n");
}

/// Without `--method`, `simplify` runs `qem-flat`: the same file as asked for by name, and
/// at 10 % of the bunny well under half the RMS error `mca` (papers/002's dihedral cost)
/// leaves (about 0.04 % against 0.096 % of the diagonal: docs/BENCHMARKS.md).
#[test]
fn simplify_defaults_to_the_flat_quadric_passes() {
    let dir = tempfile::tempdir().unwrap();
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let run = |name: &str, method: Option<&str>| {
        let out = dir.path().join(name);
        let mut args = vec!["simplify", bunny, out.to_str().unwrap(), "--ratio", "0.1", "--json"];
        args.extend(method.map(|m| ["--method", m]).into_iter().flatten());
        let (code, stdout, err) = dynlod(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        (v["method"].as_str().unwrap().to_string(), std::fs::read(&out).unwrap(), out)
    };
    let (method, bytes, default_out) = run("default.ply", None);
    assert_eq!(method, "qem-flat");
    assert_eq!(bytes, run("flat.ply", Some("qem-flat")).1, "the default is qem-flat, file for file");
    let (_, _, mca_out) = run("mca.ply", Some("mca"));
    let rms = |out: &std::path::Path| {
        let (code, stdout, err) = dynlod(&["compare", bunny, out.to_str().unwrap(), "--json"]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&stdout).unwrap()["rms_pct"].as_f64().unwrap()
    };
    let (default_rms, mca_rms) = (rms(&default_out), rms(&mca_out));
    assert!(default_rms < 0.5 * mca_rms, "default {default_rms} % against mca {mca_rms} %");
}

/// The commands renumber along a space-filling curve unless `--keep-order`: with it, a clean
/// input comes back triangle for triangle; without, the same triangles in another order.
#[test]
fn simplify_keeps_the_input_order_only_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let triangles = |m: &dynlod::IndexedMesh| -> Vec<[[u32; 3]; 3]> {
        m.triangles.iter().map(|t| t.map(|v| m.positions[v as usize].map(f32::to_bits))).collect()
    };
    let input = triangles(&dynlod::io::load(bunny).unwrap());
    let mut outputs = Vec::new();
    for extra in [&["--keep-order"][..], &[]] {
        let out = dir.path().join("same.ply");
        let mut args = vec!["simplify", bunny, out.to_str().unwrap(), "--method", "qem", "--ratio", "1"];
        args.extend(extra);
        let (code, _, err) = dynlod(&args);
        assert_eq!(code, 0, "{err}");
        outputs.push(triangles(&dynlod::io::load(&out).unwrap()));
    }
    assert!(outputs[0] == input, "--keep-order changed the order");
    assert!(outputs[1] != input, "the default kept the file's order");
    let sorted = |mut t: Vec<[[u32; 3]; 3]>| {
        t.sort_unstable();
        t
    };
    assert!(sorted(outputs.pop().unwrap()) == sorted(input), "renumbering changed the triangles");
}

/// A 6 × 6 grid of unit quads in OBJ with texture coordinates (u, v) = (x, y) / 6 and a bump.
fn textured_grid(dir: &tempfile::TempDir) -> String {
    let mut text = String::new();
    for j in 0..=6 {
        for i in 0..=6 {
            let z = if (i, j) == (3, 3) { 1.0 } else { 0.0 };
            text += &format!("v {i} {j} {z}\nvt {} {}\n", i as f32 / 6.0, j as f32 / 6.0);
        }
    }
    for j in 0..6 {
        for i in 0..6 {
            let id = |i: usize, j: usize| j * 7 + i + 1;
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            text += &format!("f {a}/{a} {b}/{b} {c}/{c}\nf {a}/{a} {c}/{c} {d}/{d}\n");
        }
    }
    write(dir, "grid.obj", &text)
}

/// `--attribute-weights` names what it weighed; `compare` measures the attributes both meshes
/// carry; a method that cannot weigh them, or a weight that is not one, is refused.
#[test]
fn simplify_weighs_attributes_and_compare_measures_them() {
    let dir = tempfile::tempdir().unwrap();
    let grid = textured_grid(&dir);
    let out = dir.path().join("o.obj");
    let o = out.to_str().unwrap();
    // The flat passes weigh them too; qem's output is the one compared below.
    for method in ["qem-flat", "qem"] {
        let (code, stdout, err) = dynlod(&[
            "simplify",
            &grid,
            o,
            "--method",
            method,
            "--ratio",
            "0.3",
            "--attribute-weights",
            "uv=1",
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(v["weighted_attributes"], serde_json::json!(["TEXCOORD_0"]));
    }
    let (code, _, err) =
        dynlod(&["simplify", &grid, o, "--method", "qem", "--ratio", "0.3", "--attribute-weights", "color=1"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("carries none of the attributes"), "{err}");
    let (code, stdout, err) = dynlod(&["compare", &grid, o, "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let uv = &v["attributes"]["TEXCOORD_0"];
    assert!(uv["rms"].as_f64().is_some_and(|r| r.is_finite() && r >= 0.0), "{stdout}");
    assert!(uv["forward"]["samples"].as_u64().unwrap() > 0, "{stdout}");
    std::fs::remove_file(&out).unwrap();
    for method in ["mca", "parallel"] {
        let (code, _, err) =
            dynlod(&["simplify", &grid, o, "--method", method, "--ratio", "0.3", "--attribute-weights", "1"]);
        assert_eq!(code, 2, "{method}: {err}");
        assert!(err.contains("--attribute-weights needs"), "{method}: {err}");
    }
    for bad in ["uv=-1", "shine=1", "uv", "nan"] {
        let (code, _, err) =
            dynlod(&["simplify", &grid, o, "--method", "qem", "--ratio", "0.3", "--attribute-weights", bad]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(err.contains(bad), "{bad}: {err}");
    }
    assert!(!out.exists(), "nothing written on refusal");
}

#[test]
fn simplify_refuses_what_it_cannot_do_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(&dir, "sq.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    let out = dir.path().join("o.ply");
    let o = out.to_str().unwrap();
    for args in [
        vec!["simplify", &f, o],                                    // no stopping rule
        vec!["simplify", &f, o, "--ratio", "1.5"],                  // bad ratio
        vec!["simplify", &f, o, "--ratio", "0.5", "--method", "x"], // unknown method
    ] {
        let (code, _, err) = dynlod(&args);
        assert_eq!(code, 2, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    assert!(!out.exists(), "nothing written on refusal");
    let (code, _, err) = dynlod(&["simplify", &f, dir.path().join("o.xyz").to_str().unwrap(), "--ratio", "0.5"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn parallel_simplify_meets_a_count_by_searching_the_threshold() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.ply");
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let (code, stdout, err) =
        dynlod(&["simplify", bunny, out.to_str().unwrap(), "--method", "parallel", "--triangles", "29014", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    for key in ["input_triangles", "output_triangles", "iterations", "milliseconds"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let tris = v["output_triangles"].as_u64().unwrap();
    assert!((28_500..=29_014).contains(&tris), "{tris}");
    assert_eq!(v["schedule"], "local-minima");
    assert_eq!(dynlod::load_mesh(&out, Default::default()).unwrap().topology.live_face_count() as u64, tris);
    // The paper's schedule: every candidate selects every round, and most selections end
    // blocked by a neighbour, so it makes far more of them for the same count.
    let args = ["simplify", bunny, out.to_str().unwrap(), "--method", "parallel", "--triangles", "29014", "--json"];
    let (code, stdout, err) = dynlod(&[&args[..], &["--schedule", "all"]].concat());
    assert_eq!(code, 0, "{err}");
    let w: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(w["schedule"], "all");
    assert!((28_500..=29_014).contains(&w["output_triangles"].as_u64().unwrap()), "{w}");
    let selections = |x: &serde_json::Value| x["selections"].as_u64().unwrap();
    assert!(selections(&w) > 2 * selections(&v), "{w} vs {v}");
    assert!(selections(&v) >= v["collapses"].as_u64().unwrap(), "{v}");
    let (code, _, err) = dynlod(&[&args[..], &["--schedule", "some"]].concat());
    assert_eq!(code, 2);
    assert!(err.contains("--schedule"), "{err}");
    // View-dependent, in pixels, from an eye at 0,0.1,0.4 (perspective unless `extra` says).
    let from_eye = |extra: &[&str]| {
        let base = ["simplify", bunny, out.to_str().unwrap(), "--method", "parallel", "--eye", "0,0.1,0.4"];
        dynlod(&[&base[..], extra, &["--pixel-error", "1", "--json"]].concat())
    };
    let (code, stdout, err) = from_eye(&[]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["view_dependent"], true);
    assert!(v["output_triangles"].as_u64().unwrap() < 69_451);
    // A view without a pixel threshold or count is refused.
    let (code, _, _) = dynlod(&["simplify", bunny, out.to_str().unwrap(), "--method", "parallel", "--eye", "0,0,1"]);
    assert_eq!(code, 2);
    // Negative coordinates are values, not flags.
    let (code, stdout, err) = from_eye(&["--target", "-0.02,0.1,0"]);
    assert_eq!(code, 0, "{err}");
    let t: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(t["view_dependent"], true);
    let (code, _, err) = dynlod(&[
        "simplify",
        bunny,
        out.to_str().unwrap(),
        "--method",
        "parallel",
        "--eye",
        "-0.4,0.1,0",
        "--ratio",
        "0.1",
    ]);
    assert_eq!(code, 0, "{err}");
    // Orthographic: 0.2 world units over 1080 px is a finer scale than the perspective
    // camera's at the bunny (0.4 away, 60°: 0.46 units), so more triangles stay.
    let (code, stdout, err) = from_eye(&["--ortho-height", "0.2"]);
    assert_eq!(code, 0, "{err}");
    let o: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert!(o["output_triangles"].as_u64().unwrap() > v["output_triangles"].as_u64().unwrap(), "{o} vs {v}");
    for (bad, says) in
        [(&["--ortho-height", "0"][..], "positive"), (&["--ortho-height", "0.2", "--fov", "30"], "--fov")]
    {
        let (code, _, err) = from_eye(bad);
        assert_eq!(code, 2, "{bad:?}");
        assert!(err.contains(says), "{bad:?}: {err}");
    }
}

#[test]
fn a_target_out_of_reach_is_reported_with_what_holds_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    // A cube with one normal per side: every edge is a normal seam and every corner meets
    // three of them, so no vertex may move.
    let mut obj = String::from("v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n");
    obj += "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n";
    for (n, [a, b, c, d]) in
        [[1, 4, 3, 2], [5, 6, 7, 8], [1, 2, 6, 5], [4, 8, 7, 3], [1, 5, 8, 4], [2, 3, 7, 6]].into_iter().enumerate()
    {
        let n = n + 1;
        obj += &format!("f {a}//{n} {b}//{n} {c}//{n}\nf {a}//{n} {c}//{n} {d}//{n}\n");
    }
    let cube = write(&dir, "cube.obj", &obj);
    let out = dir.path().join("o.ply");
    let o = out.to_str().unwrap();
    for method in ["mca", "qem", "mca-qem", "qem-batch"] {
        let (code, stdout, err) = dynlod(&["simplify", &cube, o, "--method", method, "--triangles", "2", "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!((v["output_triangles"].as_u64(), v["target_met"].as_bool()), (Some(12), Some(false)), "{v}");
        let r = &v["remaining"];
        assert_eq!((r["vertices"].as_u64(), r["fixed"].as_u64(), r["movable"].as_u64()), (Some(8), Some(8), Some(0)));
        let (code, _, err) = dynlod(&["simplify", &cube, o, "--method", method, "--triangles", "2"]);
        assert_eq!(code, 0);
        assert!(err.contains("note: target of 2 triangles not reached") && err.contains("8 fixed"), "{err}");
    }
    // Reached: no note, no "remaining".
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let (_, stdout, err) = dynlod(&["simplify", bunny, o, "--method", "qem", "--ratio", "0.5", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["target_met"], true, "{v}");
    assert!(v.get("remaining").is_none() && !err.contains("note:"), "{v} {err}");
    // The parallel engine bottoms out where nothing is left that no safety plane forbids.
    let (code, stdout, err) = dynlod(&["simplify", bunny, o, "--method", "parallel", "--triangles", "10", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!((v["target_triangles"].as_u64(), v["target_met"].as_bool()), (Some(10), Some(false)), "{v}");
    let r = &v["remaining"];
    let (live, fixed, anchors) =
        (r["vertices"].as_u64().unwrap(), r["fixed"].as_u64().unwrap(), r["anchors"].as_u64().unwrap());
    // Most of what is left are anchors: every R vertex that found a way went into them.
    assert!(live > 0 && fixed < anchors && anchors < live && anchors * 10 > live * 9, "{v}");
    let (_, _, err) = dynlod(&["simplify", bunny, o, "--method", "parallel", "--triangles", "10"]);
    assert!(
        err.contains("note: target of 10 triangles not reached") && err.contains(&format!("{anchors} are anchors")),
        "{err}"
    );
    // On the cube every vertex is fixed, for the parallel engine too.
    let (_, stdout, _) = dynlod(&["simplify", &cube, o, "--method", "parallel", "--triangles", "2", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let r = &v["remaining"];
    assert_eq!(
        (r["vertices"].as_u64(), r["fixed"].as_u64(), r["anchors"].as_u64()),
        (Some(8), Some(8), Some(8)),
        "{v}"
    );
}

/// `simplify` says what loading repaired and what the output cannot hold, on stderr (and in
/// `--json`), for every method: an output file never loses things silently.
#[test]
fn simplify_reports_repairs_and_what_the_output_leaves_out() {
    let dir = tempfile::tempdir().unwrap();
    // A duplicated face (a repair) in an OBJ: nothing else to report.
    let dup = write(&dir, "dup.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 2 3\nf 2 4 3\n");
    // A glTF with two instances of one mesh and an animation.
    let quad = base64::engine::general_purpose::STANDARD.encode(
        [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.], [0., 0., 0.]]
            .iter()
            .flatten()
            .flat_map(|c| c.to_le_bytes())
            .collect::<Vec<u8>>(),
    );
    let gltf = write(
        &dir,
        "anim.gltf",
        &format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
            "nodes":[{{"mesh":0}},{{"mesh":0,"translation":[3,0,0]}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":5}}]}}],
            "animations":[{{"channels":[{{"sampler":0,"target":{{"node":1,"path":"translation"}}}}],"samplers":[{{"input":1,"output":0}}]}}],
            "buffers":[{{"byteLength":60,"uri":"data:application/octet-stream;base64,{quad}"}}],
            "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":4}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                         {{"bufferView":1,"componentType":5126,"count":1,"type":"SCALAR","min":[0],"max":[0]}}]}}"#
        ),
    );
    let out = dir.path().join("out.glb");
    let out = out.to_str().unwrap();
    for method in ["qem", "parallel"] {
        let (code, _, err) = dynlod(&["simplify", &dup, out, "--method", method, "--ratio", "0.5"]);
        assert_eq!(code, 0, "{err}");
        assert!(err.contains("dup.obj: repaired on load: dropped duplicate faces 1"), "{method}: {err}");
        let flat = ["simplify", &gltf, out, "--method", method, "--ratio", "0.5", "--flatten"];
        let (code, _, err) = dynlod(&flat);
        assert_eq!(code, 0, "{err}");
        assert!(err.contains("anim.gltf: animations not kept: 1"), "{method}: {err}");
        assert!(err.contains("anim.gltf: node hierarchy flattened"), "{method}: {err}");
        let (code, stdout, err) = dynlod(&[&flat[..], &["--json"]].concat());
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        let kinds: Vec<&str> = v["not_kept"].as_array().unwrap().iter().map(|n| n["kind"].as_str().unwrap()).collect();
        assert_eq!(kinds, ["flattened_scene", "animations"], "{method}");
        assert_eq!(v["repairs"], serde_json::json!([]), "{method}");
        // By default a glTF to GLB keeps the scene: nothing is lost, and the output has both
        // nodes and the animation (its accessor renumbered, its data copied).
        let (code, stdout, err) = dynlod(&["simplify", &gltf, out, "--method", method, "--ratio", "0.5", "--json"]);
        assert_eq!(code, 0, "{err}");
        assert!(!err.contains("not kept"), "{method}: {err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        assert_eq!(v["scene"], true, "{method}");
        assert_eq!(v["notes"], serde_json::json!([]), "{method}");
        assert_eq!(v["meshes"][0]["instances"], 2, "{method}");
        let g = gltf::Gltf::open(out).unwrap();
        assert_eq!((g.nodes().len(), g.animations().len()), (2, 1), "{method}");
        let sampler = g.animations().next().unwrap().samplers().next().unwrap();
        assert_eq!((sampler.input().count(), sampler.output().count()), (1, 4), "{method}");
    }
}

/// `--threads` sets the pool size; the outputs do not depend on it.
#[test]
fn threads_flag_changes_nothing_but_the_pool() {
    let dir = tempfile::tempdir().unwrap();
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let run = |threads: &str, method: &str| {
        let out = dir.path().join(format!("{method}_{threads}.ply"));
        let (code, _, err) = dynlod(&[
            "--threads",
            threads,
            "simplify",
            bunny,
            out.to_str().unwrap(),
            "--method",
            method,
            "--ratio",
            "0.2",
        ]);
        assert_eq!(code, 0, "{err}");
        std::fs::read(out).unwrap()
    };
    for method in ["qem-batch", "parallel"] {
        assert_eq!(run("1", method), run("3", method), "{method}");
    }
    let fly = |threads: &str| {
        let csv = dir.path().join(format!("fly_{threads}.csv"));
        let (code, _, err) =
            dynlod(&["fly", bunny, "--frames", "8", "--threads", threads, "--csv", csv.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        // Everything but the timing columns.
        let text = std::fs::read_to_string(csv).unwrap();
        text.lines()
            .map(|l| l.split(',').filter(|c| !c.contains('.')).collect::<Vec<_>>().join(","))
            .collect::<Vec<_>>()
    };
    assert_eq!(fly("1"), fly("3"));
    let (code, _, err) = dynlod(&["--threads", "0", "info", bunny]);
    assert_eq!(code, 2, "{err}");
}

/// A kept scene's `--error` is in the scene's units, as with `--flatten`: a mesh its node
/// draws four times larger is held to a quarter of the bound in its own units.
#[test]
fn a_kept_scenes_error_bound_is_in_the_scenes_units() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("torus.glb");
    dynlod::io::save(&plain, &dynlod::procedural::torus(40, 20)).unwrap();
    // The same file with its node scaled by 4.
    let bytes = std::fs::read(&plain).unwrap();
    let glb = gltf::binary::Glb::from_slice(&bytes).unwrap();
    let mut doc: serde_json::Value = serde_json::from_slice(&glb.json).unwrap();
    doc["nodes"][0]["scale"] = serde_json::json!([4.0, 4.0, 4.0]);
    let mut json = serde_json::to_vec(&doc).unwrap();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let scaled = gltf::binary::Glb {
        header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
        json: std::borrow::Cow::Owned(json),
        bin: glb.bin.clone(),
    };
    let scaled_path = dir.path().join("scaled.glb");
    std::fs::write(&scaled_path, scaled.to_vec().unwrap()).unwrap();
    let out = dir.path().join("out.glb");
    let run = |input: &std::path::Path| {
        let (code, stdout, err) = dynlod(&[
            "simplify",
            input.to_str().unwrap(),
            out.to_str().unwrap(),
            "--method",
            "qem",
            "--error",
            "0.02",
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        (v["meshes"][0]["max_error"].as_f64().unwrap(), v["output_triangles"].as_u64().unwrap())
    };
    let (e1, n1) = run(&plain);
    let (e4, n4) = run(&scaled_path);
    assert!(e1 <= 0.02 && e1 > 0.005, "{e1}");
    assert!(e4 <= 0.005, "{e4}: the bound in the mesh's units is 0.02 / 4");
    assert!(n4 > n1, "{n4} triangles drawn four times larger against {n1}");
}

/// `dynlod fly MESH | head -3` ends quietly, as `cat` does, when the reader stops reading:
/// killed by SIGPIPE, not a panic that prints a backtrace.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_the_command_quietly() {
    use std::io::Read;
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let mut child = Command::new(env!("CARGO_BIN_EXE_dynlod"))
        .args(["fly", bunny, "--frames", "360"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 16];
    child.stdout.as_mut().unwrap().read_exact(&mut first).unwrap();
    drop(child.stdout.take());
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    let status = child.wait().unwrap();
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(status.signal(), Some(13), "SIGPIPE: {status:?}, {err}");
}
