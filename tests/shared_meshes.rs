//! Every file in `../shared/meshes` loads to a valid connectivity or a typed error, with the
//! counts of the README there. Ignored by default (the folder is not in the repository);
//! `.ci/run` runs them with `--ignored` when it exists.

use std::path::PathBuf;

use dynlod::mesh::RepairKind;
use dynlod::topology::{Topology, TopologyStats};
use dynlod::{BuildError, BuildOptions, Error, Mesh, MeshError};

mod common;
use common::check_source_triangles;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes")
}

/// Every mesh file under scans/, gltf/ and bad/, in name order.
fn shared_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = ["scans", "gltf", "bad"]
        .iter()
        .flat_map(|sub| std::fs::read_dir(dir().join(sub)).expect("../shared/meshes exists"))
        .map(|entry| entry.unwrap().path())
        .collect();
    files.sort();
    files
}

/// The shared files that load and build, with their meshes (the sweeps below run on these).
fn shared_meshes() -> impl Iterator<Item = (PathBuf, Mesh)> {
    shared_files().into_iter().filter_map(|p| dynlod::load_mesh(&p, BuildOptions::default()).ok().map(|m| (p, m)))
}

/// `t` validates and keeps the Euler characteristic and border loops of `before`.
fn assert_same_surface(t: &Topology, before: &TopologyStats, what: &str) {
    t.validate().unwrap_or_else(|e| panic!("{what}: {e}"));
    let s = t.stats();
    assert_eq!((s.euler, s.boundary_loops), (before.euler, before.boundary_loops), "{what}");
}

/// (file, input triangles, components, boundary edges, boundary loops, non-manifold edges in
/// the input, genus) for files whose README topology is unaffected by repair: the README
/// figures, checked here against our own.
const CLEAN: &[(&str, usize, usize, u32, u32, usize, u32)] = &[
    ("scans/bun_zipper.ply", 69_451, 1, 223, 5, 0, 0),
    ("scans/stanford-bunny.obj", 69_451, 1, 223, 5, 0, 0),
    ("scans/bunny_closed_pmp.off", 69_666, 1, 0, 0, 0, 0),
    ("scans/armadillo_libigl.obj", 86_482, 1, 0, 0, 0, 0),
    ("scans/igea_triangles.ply", 268_686, 1, 0, 0, 0, 0),
    ("scans/igea_tristrips.ply", 268_686, 1, 0, 0, 0, 0),
    ("bad/libigl_3holes.off", 7_200, 1, 0, 0, 0, 3),
    ("bad/libigl_camelhead.off", 22_704, 1, 56, 1, 0, 0),
    ("bad/cgal_blobby_3cc.off", 3_417, 3, 219, 4, 0, 0),
    ("bad/draco_multiple_tetrahedrons.obj", 20, 5, 0, 0, 0, 0),
    ("bad/draco_multiple_isolated_triangles.obj", 5, 5, 15, 5, 0, 0),
    ("bad/trimesh_soup.stl", 100, 100, 300, 100, 0, 0),
    ("gltf/Duck.glb", 4_212, 1, 0, 0, 0, 0),
];

#[test]
#[ignore = "needs ../shared/meshes"]
fn clean_files_match_the_readme_counts() {
    for &(file, tris, comps, be, bl, nme, genus) in CLEAN {
        let mesh =
            dynlod::load_mesh(dir().join(file), BuildOptions::default()).unwrap_or_else(|e| panic!("{file}: {e}"));
        mesh.topology.validate().unwrap_or_else(|e| panic!("{file}: {e}"));
        let s = mesh.topology.stats();
        assert_eq!(mesh.input_triangles, tris, "{file} triangles");
        assert_eq!(s.components.len(), comps, "{file} components");
        assert_eq!((s.boundary_edges, s.boundary_loops), (be, bl), "{file} boundary");
        assert_eq!(mesh.defects.non_manifold_edges, nme, "{file} non-manifold edges");
        assert_eq!(s.genus, Some(genus), "{file} genus");
    }
}

/// Files with defects: the README's input counts, and the repairs we expect to see.
#[test]
#[ignore = "needs ../shared/meshes"]
fn broken_files_are_repaired_with_the_readme_defects() {
    let cases: &[(&str, usize, usize, &[RepairKind])] = &[
        ("bad/draco_deg_faces.obj", 4, 0, &[RepairKind::DroppedDegenerateFaces]),
        ("bad/draco_non_manifold_wrap.obj", 12, 1, &[RepairKind::CutNonManifoldEdges]),
        ("bad/libigl_truck.obj", 4_770, 54, &[RepairKind::ReorientedFaces, RepairKind::CutNonManifoldEdges]),
        ("bad/trimesh_cycloidal.ply", 43_368, 242, &[RepairKind::CutNonManifoldEdges]),
        (
            "bad/trimesh_joined_tetrahedra.obj",
            8,
            3,
            &[RepairKind::DroppedDuplicateFaces, RepairKind::CutNonManifoldEdges],
        ),
        (
            "scans/bun_zipper_res2.ply",
            16_301,
            150,
            &[RepairKind::DroppedDuplicateFaces, RepairKind::DroppedUnreferencedVertices],
        ),
        (
            "scans/bun_zipper_res3.ply",
            3_851,
            141,
            &[RepairKind::DroppedDuplicateFaces, RepairKind::DroppedUnreferencedVertices],
        ),
        ("gltf/DamagedHelmet.glb", 15_452, 7, &[RepairKind::CutNonManifoldEdges]),
        ("gltf/2CylinderEngine.glb", 121_496, 0, &[RepairKind::DroppedDegenerateFaces]),
    ];
    for &(file, tris, nme, kinds) in cases {
        let mesh =
            dynlod::load_mesh(dir().join(file), BuildOptions::default()).unwrap_or_else(|e| panic!("{file}: {e}"));
        mesh.topology.validate().unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(mesh.input_triangles, tris, "{file} triangles");
        assert_eq!(mesh.defects.non_manifold_edges, nme, "{file} non-manifold edges");
        for k in kinds {
            assert!(mesh.repairs.iter().any(|r| r.kind == *k), "{file}: expected {k:?} in {:?}", mesh.repairs);
        }
        let strict = dynlod::load_mesh(dir().join(file), BuildOptions::default().strict(true));
        assert!(
            matches!(strict, Err(Error::Build { source: BuildError::RepairNeeded(_), .. })),
            "{file}: strict must refuse"
        );
    }
    let dup = |f: &str, n: usize| {
        let m = dynlod::load_mesh(dir().join(f), BuildOptions::default()).unwrap();
        assert_eq!(
            m.repairs.iter().find(|r| r.kind == RepairKind::DroppedDuplicateFaces).map(|r| r.count),
            Some(n),
            "{f}"
        );
    };
    dup("scans/bun_zipper_res2.ply", 87);
    dup("scans/bun_zipper_res3.ply", 83);
    let unref = dynlod::load_mesh(dir().join("scans/bun_zipper.ply"), BuildOptions::default()).unwrap();
    assert_eq!(unref.repairs[0].count, 1_113);
    let degtri = dynlod::load_mesh(dir().join("bad/cgal_degtri_sliding.off"), BuildOptions::default()).unwrap();
    assert_eq!(degtri.defects.zero_area_triangles, 4);
}

#[test]
#[ignore = "needs ../shared/meshes"]
fn every_shared_file_loads_valid_or_fails_typed() {
    let mut seen = 0;
    for p in shared_files() {
        seen += 1;
        match dynlod::load_mesh(&p, BuildOptions::default()) {
            Ok(mesh) => {
                mesh.topology.validate().unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                let (lo, hi) = mesh.bounds();
                assert!(lo.iter().zip(&hi).all(|(a, b)| a <= b));
            }
            Err(Error::Build { source: BuildError::Mesh(MeshError::AllDegenerate { .. }), path }) => {
                assert!(path.ends_with("draco_degenerate_mesh.obj"), "{}", path.display());
            }
            Err(e) => panic!("{}: {e}", p.display()),
        }
    }
    assert_eq!(seen, 27);
}

/// The frame-to-frame runtime on every real mesh that builds: a dolly in and out (splits and
/// collapses both), valid with the same Euler characteristic and border loops after every
/// frame, counters recounted, and fully refined it is the input exactly.
#[test]
#[ignore = "needs ../shared/meshes"]
fn the_runtime_flies_every_shared_mesh_and_restores_it() {
    use dynlod::camera_path::{frame_bounds, CameraPath};
    use dynlod::lod::{Runtime, RuntimeOptions};
    let mut flown = 0;
    for (p, mesh) in shared_meshes() {
        let s0 = mesh.topology.stats();
        let (centre, diag) = frame_bounds(&mesh.positions);
        let mut rt = Runtime::new(mesh.clone(), RuntimeOptions::default().audit(true));
        let frames = if mesh.topology.live_face_count() > 100_000 { 12 } else { 24 };
        let (mut collapses, mut splits) = (0, 0);
        for f in 0..frames {
            // Stretches of six frames alternate between perspective and orthographic views.
            let view = if f / 6 % 2 == 1 {
                dynlod::camera_path::orthographic(
                    CameraPath::Dolly.view(f * 2, 2 * frames, centre, diag, (1280, 720)),
                    centre,
                )
            } else {
                CameraPath::Dolly.view(f * 2, 2 * frames, centre, diag, (1280, 720))
            };
            let s = rt.update(Some(&view));
            collapses += s.collapses;
            splits += s.splits;
            assert_same_surface(&rt.mesh().topology, &s0, &format!("{} frame {f}", p.display()));
            rt.hierarchy().check(&rt.mesh().topology).unwrap_or_else(|e| panic!("{} frame {f}: {e}", p.display()));
        }
        if mesh.topology.live_face_count() > 1000 {
            assert!(collapses > 0 && splits > 0, "{}: {collapses} collapses, {splits} splits", p.display());
        }
        rt.refine_fully();
        let (mut a, mut b) = (rt.into_mesh(), mesh);
        a.topology.rebuild_vertex_links();
        b.topology.rebuild_vertex_links();
        assert!(a == b, "{}: not restored exactly", p.display());
        flown += 1;
    }
    assert_eq!(flown, 26);
}

/// Every file with normals, UVs or colours, and every one with several primitives, flown in
/// spatial order: the index buffer read in input vertex ids names, in every live slot, input
/// vertices whose position, normal and UV are the wedge's — a renderer can draw it over the
/// file's own vertex arrays — and each live face sits in its primitive's part.
#[test]
#[ignore = "needs ../shared/meshes"]
fn the_index_buffer_reads_in_the_files_vertex_ids() {
    use dynlod::camera_path::{frame_bounds, CameraPath};
    use dynlod::lod::{Runtime, RuntimeOptions};
    let (mut checked, mut parts) = (Vec::new(), Vec::new());
    for p in shared_files() {
        let Ok(input) = dynlod::io::load(&p) else { continue };
        let plain = input.normals.is_empty() && input.uvs.is_empty() && input.attributes.is_empty();
        if plain && input.primitives.len() < 2 {
            continue;
        }
        let Ok(mesh) = Mesh::build(&input, BuildOptions::default().spatial_order(true)) else { continue };
        let (centre, diag) = frame_bounds(&mesh.positions);
        let mut rt = Runtime::new(mesh, RuntimeOptions::default());
        let mut mirror = Vec::new();
        let mut seams = check_source_triangles(&rt, &input, &mut mirror);
        for f in 0..12 {
            rt.update(Some(&CameraPath::Dolly.view(f * 4, 48, centre, diag, (1280, 720))));
            seams = seams.max(check_source_triangles(&rt, &input, &mut mirror));
        }
        parts.push((p.file_name().unwrap().to_string_lossy().into_owned(), rt.index_buffer().parts().len()));
        checked.push((p.file_name().unwrap().to_string_lossy().into_owned(), seams));
    }
    // Multi-material files draw each primitive from its own part (checked every frame above).
    for (name, n) in [("2CylinderEngine.glb", 34), ("CesiumMilkTruck.glb", 4), ("trimesh_joined_tetrahedra.obj", 2)] {
        assert!(parts.contains(&(name.to_string(), n)), "{name}: {parts:?}");
    }
    // The four glTF models, the OBJ files with normals or UVs and the coloured PLY; the
    // textured ones have seams.
    assert!(checked.len() >= 6, "{checked:?}");
    assert!(checked.iter().any(|(n, _)| n == "trimesh_cycloidal.ply"), "{checked:?}");
    for name in ["Duck.glb", "DamagedHelmet.glb", "CesiumMilkTruck.glb"] {
        assert!(checked.iter().any(|(n, s)| n == name && *s > 0), "{name}: {checked:?}");
    }
}

/// The coloured scan (the cycloidal gear's PLY, 8-bit RGBA per vertex) keeps its colours
/// through every simplifier: each output corner is an input vertex, position and colour
/// together, and a PLY written from it reads back to the same bytes.
#[test]
#[ignore = "needs ../shared/meshes"]
fn a_coloured_scan_keeps_its_colours_through_every_simplifier() {
    use dynlod::simplify::{simplify, Method, SimplifyOptions};
    let input = dynlod::io::load(dir().join("bad/trimesh_cycloidal.ply")).unwrap();
    assert_eq!((input.attributes[0].semantic.as_str(), input.attributes[0].components), ("COLOR_0", 4));
    let key = |m: &dynlod::IndexedMesh, i: usize| {
        let mut k: Vec<u32> = m.positions[i].iter().map(|c| c.to_bits()).collect();
        k.extend(m.attributes[0].get(i).iter().map(|c| c.to_bits()));
        k
    };
    let vertices: std::collections::HashSet<Vec<u32>> = (0..input.positions.len()).map(|i| key(&input, i)).collect();
    let mesh = Mesh::build(&input, BuildOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for method in Method::ALL {
        let mut m = mesh.clone();
        simplify(&mut m, SimplifyOptions::default().method(method).target_triangles(input.triangles.len() / 10));
        let out = m.to_indexed();
        assert!(out.triangles.len() < input.triangles.len() / 5, "{method:?}");
        assert!(out.triangles.iter().flatten().all(|&i| vertices.contains(&key(&out, i as usize))), "{method:?}");
        let path = dir.path().join("out.ply");
        dynlod::io::save(&path, &out).unwrap();
        assert_eq!(dynlod::io::load(&path).unwrap().attributes, out.attributes, "{method:?}");
    }
}

/// papers/000 rounds on every real mesh that builds, under both schedules, view-independent
/// at u = 1 % of the bounding-box diagonal: the run ends on its own (not at the round cap),
/// leaves a valid mesh with the input's Euler characteristic and border loops, and removes
/// something from every mesh large enough to have something to remove. CAD models (the
/// glTF engine, the cycloidal gear) are where a schedule can stall: waking every neighbour of
/// a high-valence target after each collapse once kept the local-minima schedule going to
/// the 1,000-round cap on `2CylinderEngine.glb`.
#[test]
#[ignore = "needs ../shared/meshes"]
fn parallel_coarsening_ends_on_its_own_on_every_shared_mesh() {
    use dynlod::lod::coarsen::{coarsen, CoarsenOptions, CoarsenStop, Schedule};
    let mut runs = 0;
    for (p, mesh) in shared_meshes() {
        let s0 = mesh.topology.stats();
        let (_, diag) = dynlod::camera_path::frame_bounds(&mesh.positions);
        for schedule in [Schedule::LocalMinima, Schedule::AllCandidates] {
            let mut m = mesh.clone();
            let options = CoarsenOptions::default().threshold(1e-2 * diag).schedule(schedule);
            let s = coarsen(&mut m, None, options);
            let what = format!("{} {schedule:?}: {} rounds", p.display(), s.rounds.len());
            assert_ne!(s.stop, CoarsenStop::RoundCap, "{what}");
            assert!(s.rounds.len() <= 300, "{what}");
            assert_same_surface(&m.topology, &s0, &what);
            if s.input_triangles > 1000 {
                assert!(s.output_triangles < s.input_triangles, "{what}: nothing removed");
            }
            runs += 1;
        }
    }
    assert_eq!(runs, 52);
}

/// Every method of the offline simplifier, on every shared mesh that loads, to 1 % of its
/// triangles: it ends (the batched passes once looped on `cgal_degtri_sliding.off`, whose
/// quadric costs come out a rounding error below zero), and leaves a valid manifold with the
/// input's Euler characteristic and border loops, at the target or with nothing allowed left.
#[test]
#[ignore = "needs ../shared/meshes"]
fn every_simplifier_method_ends_on_every_shared_mesh() {
    use dynlod::simplify::{simplify, Method, SimplifyOptions, StopReason};
    let mut runs = 0;
    for (p, mesh) in shared_meshes() {
        let s0 = mesh.topology.stats();
        let target = mesh.topology.live_face_count() / 100;
        for method in Method::ALL {
            let mut m = mesh.clone();
            let s = simplify(&mut m, SimplifyOptions::default().method(method).target_triangles(target));
            let what = format!("{} {}: {} -> {}", p.display(), method.name(), s.input_triangles, s.output_triangles);
            assert_same_surface(&m.topology, &s0, &what);
            assert_eq!(s.stop == StopReason::Target, s.output_triangles <= target, "{what}");
            runs += 1;
        }
    }
    assert_eq!(runs, Method::ALL.len() * 26);
}

/// The runtime's cut (`simplify --method runtime`) on every shared mesh: from 2 and from 32
/// diagonals a valid surface with the input's Euler characteristic and borders, the farther
/// keeping no more than the nearer; to 1 % of the input by the threshold's search, at most
/// that many triangles, or where no threshold goes lower (the anchors' floor) the cut at the
/// largest.
#[test]
#[ignore = "needs ../shared/meshes"]
fn the_runtimes_cut_ends_on_every_shared_mesh() {
    use dynlod::lod::{Runtime, RuntimeOptions};
    let mut runs = 0;
    for (p, mesh) in shared_meshes() {
        let s0 = mesh.topology.stats();
        let view = |d: f32| common::view_from_diagonals(&mesh, d, (1920, 1080));
        let mut nearer = usize::MAX;
        for d in [2.0, 32.0] {
            let cut = Runtime::cut(mesh.clone(), &[view(d)], RuntimeOptions::default()).unwrap();
            let kept = cut.mesh.topology.live_face_count();
            let what = format!("{} from {d} diagonals: {kept}", p.display());
            assert_same_surface(&cut.mesh.topology, &s0, &what);
            assert!(cut.settled && kept <= nearer, "{what}, {nearer} nearer");
            nearer = kept;
        }
        let target = mesh.topology.live_face_count() / 100;
        let cut = Runtime::cut_to_triangles(mesh.clone(), &[view(2.0)], RuntimeOptions::default(), target).unwrap();
        let kept = cut.mesh.topology.live_face_count();
        let what = format!("{} to {target}: {kept} at {}", p.display(), cut.threshold);
        assert_same_surface(&cut.mesh.topology, &s0, &what);
        assert!(kept <= target || cut.threshold > 1e20, "{what}");
        runs += 1;
    }
    assert_eq!(runs, 26);
}

/// The textured duck: its 122 seam ends move in the offline simplifier, so it coarsens well
/// below the 382 triangles where they used to hold it, and at 10 % its shape stays within
/// about 1 % RMS of the diagonal (2.7 % when they held); its seams keep the texture layout
/// along them; weighing normals keeps its shading closer at the same count.
#[test]
#[ignore = "needs ../shared/meshes"]
fn the_duck_coarsens_past_its_seam_ends_and_weighs_its_normals() {
    use dynlod::metrics::{attribute_errors, hausdorff};
    use dynlod::simplify::{simplify, AttributeWeights, Method, SimplifyOptions};
    let input = dynlod::io::load(dir().join("gltf/Duck.glb")).unwrap();
    let mesh = Mesh::build(&input, BuildOptions::default()).unwrap();
    let run = |target: usize, w: AttributeWeights| {
        let mut m = mesh.clone();
        let s = simplify(
            &mut m,
            SimplifyOptions::default().method(Method::Qem).target_triangles(target).attribute_weights(w),
        );
        m.topology.validate().unwrap();
        (s.output_triangles, m.to_indexed())
    };
    let (floor, _) = run(0, AttributeWeights::default());
    assert!(floor < 300, "the duck stops at {floor} triangles");
    let (n, out) = run(421, AttributeWeights::default());
    assert!((420..=421).contains(&n), "{n} triangles");
    let h = hausdorff(&input, &out, Default::default());
    assert!(h.pct(h.rms) < 1.0, "RMS {} % of the diagonal", h.pct(h.rms));
    let normal_rms = |m: &dynlod::IndexedMesh| {
        attribute_errors(&input, m, Default::default()).into_iter().find(|e| e.semantic == "NORMAL").unwrap().rms
    };
    let (_, plain) = run(1053, AttributeWeights::default());
    // The seam planes hold the texture layout along the seams (0.050 without them).
    let uv = attribute_errors(&input, &plain, Default::default()).into_iter().find(|e| e.semantic == "TEXCOORD_0");
    assert!(uv.as_ref().unwrap().rms < 0.03, "{uv:?}");
    let (_, weighted) = run(1053, AttributeWeights { normal: 0.5, ..Default::default() });
    let (p, w) = (normal_rms(&plain), normal_rms(&weighted));
    assert!(w < 0.7 * p, "normal RMS {w} weighted against {p}");
    // The flat passes weigh them alike (0.118 → 0.062 measured).
    let flat = |w: AttributeWeights| {
        let mut m = mesh.clone();
        let opts = SimplifyOptions::default().method(Method::QemFlat).target_triangles(1053).attribute_weights(w);
        simplify(&mut m, opts);
        m.topology.validate().unwrap();
        normal_rms(&m.to_indexed())
    };
    let (p, w) = (flat(AttributeWeights::default()), flat(AttributeWeights { normal: 0.5, ..Default::default() }));
    assert!(w < 0.7 * p, "qem-flat: normal RMS {w} weighted against {p}");
}

/// Every shared glTF simplified with its scene kept (as `dynlod simplify` does by default):
/// each mesh in its own space, to the share that the scene simplified as one mesh left it.
/// Seen flattened, the result draws what `--flatten` draws, within 2 %, at the same error
/// within 10 % (2CylinderEngine's 29 meshes included: one ratio for each mesh measured
/// 3.4× the RMS there); and it keeps what flattening loses: the truck's wheel animation, the
/// engine's 82 nodes.
#[test]
#[ignore = "needs ../shared/meshes"]
fn a_kept_scene_draws_what_flattening_draws_and_keeps_its_nodes() {
    use dynlod::io::GltfScene;
    use dynlod::metrics::hausdorff;
    use dynlod::simplify::{simplify, Method, SimplifyOptions};
    let opts = |target: usize| SimplifyOptions::default().method(Method::Qem).target_triangles(target);
    for name in ["Duck", "CesiumMilkTruck", "DamagedHelmet", "2CylinderEngine"] {
        let path = dir().join(format!("gltf/{name}.glb"));
        let input = dynlod::io::load(&path).unwrap();
        let mut flat = Mesh::build(&input, BuildOptions::default()).unwrap();
        let target = flat.topology.live_face_count() / 4;
        simplify(&mut flat, opts(target));
        let scene = GltfScene::load(&path).unwrap();
        let shares = scene.allot(&flat);
        let outputs: Vec<dynlod::IndexedMesh> = scene
            .meshes
            .iter()
            .zip(&shares)
            .map(|(sm, share)| {
                let mut m = Mesh::build(&sm.mesh, BuildOptions::default()).unwrap();
                simplify(&mut m, opts(share.unwrap()));
                m.to_indexed()
            })
            .collect();
        let mut bytes = Vec::new();
        let notes = scene.write_glb(&mut bytes, &outputs).unwrap();
        assert!(notes.is_empty(), "{name}: {notes:?}");
        let kept = dynlod::io::load_bytes(&bytes, dynlod::io::Format::Glb, None).unwrap();
        let flat = flat.to_indexed();
        let (a, b) = (kept.triangles.len() as f64, flat.triangles.len() as f64);
        assert!((a / b - 1.0).abs() < 0.02, "{name}: {a} triangles drawn against {b} flattened");
        let (hk, hf) = (hausdorff(&input, &kept, Default::default()), hausdorff(&input, &flat, Default::default()));
        assert!(hk.rms <= 1.1 * hf.rms, "{name}: RMS {} against {} flattened", hk.rms, hf.rms);
        // The flattened reading of the output loses what the source's does: the same scene.
        assert_eq!(kept.not_kept, input.not_kept, "{name}");
        let (g, s) = (gltf::Gltf::from_slice(&bytes).unwrap(), gltf::Gltf::open(&path).unwrap());
        assert_eq!((g.nodes().len(), g.animations().len()), (s.nodes().len(), s.animations().len()), "{name}");
    }
}

/// `simplify IN.glb OUT.glb --method parallel --eye ...` on every shared glTF, from two
/// diagonals away: each mesh is cut once for the camera as every node drawing it sees it.
/// The command's per-mesh counts are the library's; in every instance's view, every removed
/// vertex was within the pixel error and no triangle that faced the eye turned away; a file
/// of one mesh drawn once cuts as its baked copy does.
#[test]
#[ignore = "needs ../shared/meshes"]
fn a_kept_scene_is_cut_for_every_instance_of_a_camera() {
    use dynlod::io::GltfScene;
    use dynlod::lod::coarsen::{coarsen, coarsen_views, CoarsenOptions};
    use dynlod::lod::passes::classify::{screen_error_in, vertex_normals_and_errors, ClassifyOptions};
    use dynlod::topology::INVALID;
    use dynlod::view::{Frustum, View};
    let build = BuildOptions::default().spatial_order(true);
    let dir_out = tempfile::tempdir().unwrap();
    for name in ["Duck", "CesiumMilkTruck", "DamagedHelmet", "2CylinderEngine"] {
        let path = dir().join(format!("gltf/{name}.glb"));
        let flat = Mesh::build(&dynlod::io::load(&path).unwrap(), build).unwrap();
        let (centre, diag) = dynlod::camera_path::frame_bounds(&flat.positions);
        let eye = [centre[0] + 0.6 * diag, centre[1] + 0.8 * diag, centre[2] + 1.6 * diag];
        let camera = View::perspective(eye, centre, [0.0, 1.0, 0.0], 60.0, (1920, 1080));
        let out = dir_out.path().join(format!("{name}.glb"));
        let arg = |x: [f32; 3]| format!("{},{},{}", x[0], x[1], x[2]);
        let (code, stdout, err) = common::dynlod(&[
            "simplify",
            path.to_str().unwrap(),
            out.to_str().unwrap(),
            "--method",
            "parallel",
            "--eye",
            &arg(eye),
            "--target",
            &arg(centre),
            "--fov",
            "60",
            "--pixel-error",
            "1",
            "--json",
        ]);
        assert_eq!(code, 0, "{name}: {err}");
        let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        let scene = GltfScene::load(&path).unwrap();
        let o = ClassifyOptions::default();
        for (k, sm) in scene.meshes.iter().enumerate() {
            let views: Vec<View> = sm.placements.iter().map(|p| camera.in_model_space(p.world).unwrap()).collect();
            let base = Mesh::build(&sm.mesh, build).unwrap();
            let mut cut = base.clone();
            coarsen_views(&mut cut, &views, CoarsenOptions::default().threshold(1.0));
            cut.topology.validate().unwrap();
            let what = format!("{name} {}", sm.label());
            assert_eq!(
                json["meshes"][k]["output_triangles"].as_u64(),
                Some(cut.topology.live_face_count() as u64),
                "{what}"
            );
            let (normals, errors) = vertex_normals_and_errors(&base.topology, &base.positions);
            for view in &views {
                let frustum = Frustum::new(view);
                for v in 0..base.positions.len() {
                    if base.topology.vertex_he[v] != INVALID && cut.topology.vertex_he[v] == INVALID {
                        let px = screen_error_in(Some(&frustum), base.positions[v], normals[v], errors[v], &o);
                        assert!(px <= 1.0, "{what}: vertex {v} removed at {px} px in an instance's view");
                    }
                }
                for (f, face) in cut.topology.faces.iter().enumerate() {
                    let before = common::facing_from(&base, base.topology.faces[f], view.viewpoint());
                    if face[0] != INVALID && before > 1e-9 {
                        assert!(
                            common::facing_from(&cut, *face, view.viewpoint()) >= 0.0,
                            "{what}: face {f} turned away"
                        );
                    }
                }
            }
        }
        if scene.meshes.len() == 1 && scene.meshes[0].instances == 1 {
            let mut baked = flat.clone();
            coarsen(&mut baked, Some(camera), CoarsenOptions::default().threshold(1.0));
            assert_eq!(json["output_triangles"].as_u64(), Some(baked.topology.live_face_count() as u64), "{name}");
        }
    }
}

/// Every shared glTF flown as a kept scene (`SceneRuntime`), with one runtime per mesh and
/// with up to 3 instance groups: a camera orbiting the scene's world bounds, 30° a frame, near
/// and then far. After every frame each runtime validates with its own Euler characteristic,
/// its hierarchy and charges recount, every placement is served by one runtime of its mesh,
/// and once converged each instance sees at most the pixel error; a mesh no node draws stays
/// as built.
#[test]
#[ignore = "needs ../shared/meshes"]
fn every_shared_scene_flies_with_a_runtime_per_mesh() {
    use dynlod::io::GltfScene;
    use dynlod::lod::{FrameStop, RuntimeOptions, SceneRuntime};
    use dynlod::view::View;
    for (name, groups) in ["Duck", "CesiumMilkTruck", "DamagedHelmet", "2CylinderEngine"]
        .into_iter()
        .flat_map(|name| [(name, 1), (name, 3)])
    {
        let scene = GltfScene::load(dir().join(format!("gltf/{name}.glb"))).unwrap();
        let mut rt = SceneRuntime::new(&scene, BuildOptions::default(), RuntimeOptions::default().audit(true)).unwrap();
        rt.set_instance_groups(groups);
        let shapes: Vec<TopologyStats> = rt.meshes().iter().map(|m| m.runtime.mesh().topology.stats()).collect();
        let (lo, hi) = scene.world_bounds();
        let (centre, diag) = dynlod::camera_path::frame_box(lo, hi);
        for f in 0..24 {
            let (angle, dist) = ((f as f32 * 30.0).to_radians(), if f < 12 { 0.8 } else { 6.0 } * diag);
            let eye = [centre[0] + dist * angle.sin(), centre[1] + 0.3 * dist, centre[2] + dist * angle.cos()];
            let camera = View::perspective(eye, centre, [0.0, 1.0, 0.0], 60.0, (1920, 1080));
            let stats = rt.update(&[camera]).to_vec();
            let mut served: Vec<Vec<usize>> = (0..rt.mesh_count())
                .map(|k| vec![0; rt.meshes().iter().filter(|m| m.mesh == k).map(|m| m.placements.len()).sum()])
                .collect();
            for ((m, s), shape) in rt.meshes().iter().zip(&stats).zip(&shapes) {
                let what = format!("{name} ({groups} groups) mesh {} group {} frame {f}", m.index, m.group);
                assert_same_surface(&m.runtime.mesh().topology, shape, &what);
                m.runtime.hierarchy().check(&m.runtime.mesh().topology).unwrap();
                m.runtime.check_charges().unwrap();
                for &i in &m.instances {
                    served[m.mesh][i] += 1;
                }
                if m.placements.is_empty() {
                    // A group may idle with what it held; a mesh drawn nowhere stays as built.
                    assert!(s.skipped && (m.group > 0 || m.runtime.hierarchy().front().next().is_none()), "{what}");
                    continue;
                }
                if s.stop == FrameStop::Converged {
                    for p in &m.placements {
                        let px = m.runtime.screen_error_in(&camera.in_model_space(p.world).unwrap());
                        assert!(px <= 1.0, "{what}: an instance sees {px} px");
                    }
                }
            }
            assert!(served.iter().flatten().all(|&n| n == 1), "{name} ({groups} groups) frame {f}: {served:?}");
        }
        assert!(rt.drawn_triangles() < scene.meshes.iter().map(|m| m.mesh.triangles.len() * m.placements.len()).sum());
    }
}

/// Every shared glTF kept as a scene under one budget for the whole scene, half of what it
/// draws at full detail, on the walk above, with one runtime per mesh and with up to 3
/// instance groups: every runtime stays valid after every frame, a frame that converged
/// draws within the budget, and once a still camera settles the scene (skipped whole) every
/// instance shows at most the threshold the budget allowed.
#[test]
#[ignore = "needs ../shared/meshes"]
fn every_shared_scene_holds_a_budget_for_the_whole_scene() {
    use dynlod::io::GltfScene;
    use dynlod::lod::{FrameStop, RuntimeOptions, SceneRuntime};
    use dynlod::view::View;
    for (name, groups) in ["Duck", "CesiumMilkTruck", "DamagedHelmet", "2CylinderEngine"]
        .into_iter()
        .flat_map(|name| [(name, 1), (name, 3)])
    {
        let scene = GltfScene::load(dir().join(format!("gltf/{name}.glb"))).unwrap();
        let full: usize = scene.meshes.iter().map(|m| m.mesh.triangles.len() * m.placements.len()).sum();
        let budget = full / 2;
        let options = RuntimeOptions::default().audit(true).budget(Some(budget));
        let mut rt = SceneRuntime::new(&scene, BuildOptions::default(), options).unwrap();
        rt.set_instance_groups(groups);
        let shapes: Vec<TopologyStats> = rt.meshes().iter().map(|m| m.runtime.mesh().topology.stats()).collect();
        let (lo, hi) = scene.world_bounds();
        let (centre, diag) = dynlod::camera_path::frame_box(lo, hi);
        let camera = |f: usize| {
            let (angle, dist) = ((f as f32 * 30.0).to_radians(), if f < 12 { 0.8 } else { 6.0 } * diag);
            let eye = [centre[0] + dist * angle.sin(), centre[1] + 0.3 * dist, centre[2] + dist * angle.cos()];
            View::perspective(eye, centre, [0.0, 1.0, 0.0], 60.0, (1920, 1080))
        };
        for f in 0..24 {
            let stats = rt.update(&[camera(f)]).to_vec();
            for (m, shape) in rt.meshes().iter().zip(&shapes) {
                let what = format!("{name} ({groups} groups) mesh {} frame {f}", m.index);
                assert_same_surface(&m.runtime.mesh().topology, shape, &what);
                m.runtime.hierarchy().check(&m.runtime.mesh().topology).unwrap();
                m.runtime.check_charges().unwrap();
            }
            if stats.iter().all(|s| s.stop == FrameStop::Converged) {
                assert!(
                    rt.drawn_triangles() <= budget,
                    "{name} ({groups} groups) frame {f}: {} over {budget}",
                    rt.drawn_triangles()
                );
            }
        }
        let near = camera(3);
        assert!(
            (0..100).any(|_| rt.update(&[near]).iter().all(|s| s.skipped)),
            "{name} ({groups} groups): no fixed point"
        );
        assert!(rt.drawn_triangles() <= budget, "{name} ({groups} groups): {} over {budget}", rt.drawn_triangles());
        for m in rt.meshes() {
            for p in &m.placements {
                let px = m.runtime.screen_error_in(&near.in_model_space(p.world).unwrap());
                assert!(px <= rt.threshold() * 1.0001, "{name} mesh {}: {px} px over {}", m.index, rt.threshold());
            }
        }
    }
}

/// The Stanford bunny scan at a survey's coordinates (×1000, 512,345 E 4,123,456 N, printed
/// to the tenth of a millimetre the scan holds) reads, simplifies and measures as it does at
/// its own origin (`mesh/origin.rs`): every vertex kept, and the same error within a hundredth.
#[test]
#[ignore = "needs ../shared/meshes"]
fn the_bunny_at_survey_coordinates_simplifies_as_it_does_at_home() {
    use dynlod::io::{self, Format};
    use dynlod::simplify::{simplify, SimplifyOptions};
    let scan = io::load(dir().join("scans/bun_zipper.ply")).unwrap();
    let offset = [512_345.0, 4_123_456.0, 100.0];
    let mut near_text = String::new();
    let mut far_text = String::new();
    for p in &scan.positions {
        let c = p.map(|x| f64::from(x) * 1000.0);
        near_text.push_str(&format!("v {:.4} {:.4} {:.4}\n", c[0], c[1], c[2]));
        far_text.push_str(&format!("v {:.4} {:.4} {:.4}\n", c[0] + offset[0], c[1] + offset[1], c[2] + offset[2]));
    }
    for t in &scan.triangles {
        let f = format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        near_text.push_str(&f);
        far_text.push_str(&f);
    }
    let read = |text: &str| io::load_bytes(text.as_bytes(), Format::Obj, None).unwrap();
    let (near, far) = (read(&near_text), read(&far_text));
    assert_eq!(near.origin, [0.0; 3]);
    assert_eq!(far.origin, [512_300.0, 4_123_600.0, 100.0]);
    let rms = |input: &dynlod::IndexedMesh| {
        let mut mesh = Mesh::build(input, BuildOptions::default()).unwrap();
        assert_eq!(mesh.topology.vertex_count(), 34_834, "every scanned vertex kept");
        simplify(&mut mesh, SimplifyOptions::default().target_triangles(6_945));
        let h = dynlod::metrics::hausdorff(input, &mesh.to_indexed(), Default::default());
        h.pct(h.rms)
    };
    let (at_home, far_out) = (rms(&near), rms(&far));
    assert!((far_out - at_home).abs() < 0.01 * at_home, "RMS {far_out} % far out against {at_home} % at home");
}

/// Each texture image written beside an OBJ output of `m`, named by an MTL `map_Bump` (as
/// Blender writes normal maps), reads as the normal texture exactly where `m` used it as one:
/// the real normal map (DamagedHelmet's) by its pixels, and no colour, emissive or
/// metallic-roughness image.
fn bump_maps_are_told_apart(m: &dynlod::IndexedMesh, files: &[std::path::PathBuf], name: &str) {
    let mats = m.gltf_materials.as_ref().unwrap();
    let normal_images: Vec<Vec<u8>> = mats
        .materials
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|mat| mat["normalTexture"]["index"].as_u64())
        .filter_map(|t| mats.images[mats.textures[t as usize]["source"].as_u64()? as usize].bytes.clone())
        .collect();
    let images: Vec<&std::path::PathBuf> =
        files.iter().filter(|f| f.extension().is_some_and(|e| e == "png" || e == "jpg")).collect();
    if images.is_empty() {
        return;
    }
    let dir = files[0].parent().unwrap();
    let mut mtl = String::new();
    let mut obj = String::from("mtllib probe.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n");
    for (k, image) in images.iter().enumerate() {
        mtl += &format!("newmtl m{k}\nmap_Bump -bm 1 {}\n", image.file_name().unwrap().to_string_lossy());
        obj += &format!("usemtl m{k}\nf 1/1 2/2 3/3\n");
    }
    std::fs::write(dir.join("probe.mtl"), mtl).unwrap();
    std::fs::write(dir.join("probe.obj"), obj).unwrap();
    let probe = dynlod::io::load(dir.join("probe.obj")).unwrap();
    let read = probe.gltf_materials.as_ref().unwrap();
    for (k, image) in images.iter().enumerate() {
        let bytes = std::fs::read(image).unwrap();
        let normal = !read.materials[k]["normalTexture"].is_null();
        assert_eq!(normal, normal_images.contains(&bytes), "{name}: {}", image.display());
    }
    assert_eq!(normal_images.len(), usize::from(name == "DamagedHelmet.glb"), "{name}: the one normal map checked");
}

/// Every shared glTF through OBJ and back: the texture coordinates come back bit for bit
/// (turned over twice), every image a material shows comes back byte for byte, each
/// primitive keeps its material's base-colour texture, and nothing is left out (DamagedHelmet's
/// occlusion texture goes as `map_ao`) but DamagedHelmet's tangents, made for its normal map
/// on loading, which OBJ cannot hold (its reader makes them again).
#[test]
#[ignore = "needs ../shared/meshes"]
fn every_shared_gltf_goes_through_obj_and_back_with_its_textures() {
    let tmp = tempfile::tempdir().unwrap();
    for f in shared_files().into_iter().filter(|f| f.extension().is_some_and(|e| e == "glb")) {
        let m = dynlod::io::load(&f).unwrap();
        let lost = dynlod::io::not_written(&m, dynlod::io::WriteFormat::Obj);
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let tangents = ["vertex attributes TANGENT"];
        assert_eq!(lost, if name == "DamagedHelmet.glb" { &tangents[..] } else { &[] }, "{name}");
        let out = tmp.path().join(name.replace(".glb", ".obj"));
        let files = dynlod::io::save(&out, &m).unwrap();
        let back = dynlod::io::load(&out).unwrap();
        assert_eq!(back.uvs, m.uvs, "{name}");
        bump_maps_are_told_apart(&m, &files, &name);
        let (a, b) = (m.gltf_materials.as_ref().unwrap(), back.gltf_materials.as_ref().unwrap());
        let base = |mats: &dynlod::mesh::GltfMaterials, k: usize| -> Option<Vec<u8>> {
            let info = &mats.materials[k]["pbrMetallicRoughness"]["baseColorTexture"];
            let source = mats.textures[info["index"].as_u64()? as usize]["source"].as_u64()?;
            mats.images[source as usize].bytes.clone()
        };
        for (p, q) in m.primitives.iter().zip(&back.primitives) {
            let (Some(k), Some(l)) = (p.material, q.material) else { panic!("{name}: {p:?} / {q:?}") };
            assert_eq!(base(a, k), base(b, l), "{name}: material {k}");
        }
        assert_eq!(back.primitives.len(), m.primitives.len(), "{name}");
    }
}

/// DamagedHelmet has a normal map and no tangents: the frames made for it are the reference
/// MikkTSpace's at every corner but those of its degenerate triangles (25 corners where the
/// reference makes no frame or a zero one; 1 where the fallbacks differ), and the tangents
/// reach the GLB (no longer left to the viewer).
#[test]
#[ignore = "needs ../shared/meshes"]
fn damaged_helmet_gets_the_reference_mikktspace_frames() {
    let m = dynlod::io::load(dir().join("gltf/DamagedHelmet.glb")).unwrap();
    let (compared, none, worst, handedness) = common::mikktspace::against_reference(&m, 1);
    assert_eq!((compared + none, none, handedness), (3 * m.triangles.len(), 25, 0));
    assert!(worst < 0.05, "{worst}° at the second worst corner");
    let folder = tempfile::tempdir().unwrap();
    let out = folder.path().join("helmet.glb");
    dynlod::io::save(&out, &m).unwrap();
    let doc = gltf::Gltf::open(&out).unwrap();
    let primitive = doc.meshes().next().unwrap().primitives().next().unwrap();
    assert!(primitive.get(&gltf::Semantic::Tangents).is_some());
}
