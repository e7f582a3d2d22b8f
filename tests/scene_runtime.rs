//! A kept glTF scene under a moving camera (`SceneRuntime`, `dynlod fly SCENE --instanced`):
//! one runtime per mesh definition, in the mesh's own space, serving every node that draws it.
//! Each mesh's runtime is exactly a runtime given the camera carried through each placement;
//! every instance sees at most the pixel error; a mesh no node draws stays as built; a
//! stretched or sheared node draws a copy with the stretch baked in, a singular one is
//! refused by name; the result is the same on 1 and 2 threads.

use dynlod::io::GltfScene;
use dynlod::lod::{FrameStats, FrameStop, Runtime, RuntimeOptions, SceneRuntime, SceneRuntimeError};
use dynlod::view::View;
use dynlod::{BuildOptions, Mesh};
use serde_json::json;

mod common;
use common::glb::two_grids;
use common::runtime::fly_scene;
use common::{dynlod, on_threads};

/// The ground grid right under the camera, and again 40 units away at half size; the spare
/// grid drawn by no node.
fn near_and_far() -> Vec<u8> {
    two_grids(&[
        json!({"name": "near"}),
        json!({"name": "far", "translation": [0.0, 0.0, -40.0], "scale": [0.5, 0.5, 0.5]}),
    ])
}

fn load(bytes: &[u8]) -> (tempfile::TempDir, std::path::PathBuf, GltfScene) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.glb");
    std::fs::write(&path, bytes).unwrap();
    let scene = GltfScene::load(&path).unwrap();
    (dir, path, scene)
}

/// A camera sliding over the ground and pulling back, frame `f` of 40.
fn camera(f: usize) -> View {
    let t = f as f32 / 40.0;
    let eye = [0.2 + 0.6 * t, 0.5, 0.4 + 3.0 * t];
    View::perspective(eye, [eye[0], 0.5, 0.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080))
}

fn edits(s: &FrameStats) -> (usize, usize, usize, usize, FrameStop, bool) {
    (s.collapses, s.splits, s.rebalanced, s.triangles, s.stop, s.skipped)
}

#[test]
fn each_mesh_serves_every_node_that_draws_it() {
    let (_dir, _, scene) = load(&near_and_far());
    let build = BuildOptions::default();
    let mut rt = SceneRuntime::new(&scene, build, RuntimeOptions::default()).unwrap();
    // The ground by hand: a runtime given the camera through each of its two nodes.
    let ground = &scene.meshes[0];
    let mut by_hand = Runtime::new(Mesh::build(&ground.mesh, build).unwrap(), RuntimeOptions::default());
    let spare = rt.meshes()[1].runtime.triangles();
    let mut fewest = usize::MAX;
    for f in 0..40 {
        let cam = camera(f);
        let stats = rt.update(&[cam]).to_vec();
        let views: Vec<View> = ground.placements.iter().map(|p| cam.in_model_space(p.world).unwrap()).collect();
        let s = by_hand.update_views(&views);
        assert_eq!(edits(&stats[0]), edits(&s), "frame {f}");
        let shared = &rt.meshes()[0].runtime;
        assert!(shared.mesh() == by_hand.mesh(), "frame {f}");
        // Each instance, seen alone, within the pixel error.
        if s.stop == FrameStop::Converged {
            for v in &views {
                assert!(shared.screen_error_in(v) <= 1.0, "frame {f}: {}", shared.screen_error_in(v));
            }
        }
        // The mesh no node draws is never updated.
        assert!(stats[1].skipped && stats[1].collapses == 0);
        assert_eq!(rt.meshes()[1].runtime.triangles(), spare);
        assert_eq!(rt.drawn_triangles(), 2 * shared.triangles());
        assert_eq!(rt.held_triangles(), shared.triangles() + spare);
        fewest = fewest.min(shared.triangles());
    }
    // The camera pulled back far enough for the ground to coarsen.
    assert!(fewest < 3200 / 2, "{fewest}");
    // Near the ground, the far instance alone would keep less than the pair does.
    let far_view = camera(0).in_model_space(ground.placements[1].world).unwrap();
    let mut far_alone =
        Runtime::new(Mesh::build(&ground.mesh, BuildOptions::default()).unwrap(), RuntimeOptions::default());
    far_alone.update(Some(&far_view));
    let mut pair = SceneRuntime::new(&scene, BuildOptions::default(), RuntimeOptions::default()).unwrap();
    pair.update(&[camera(0)]);
    assert!(pair.meshes()[0].runtime.triangles() > 2 * far_alone.triangles());
}

#[test]
fn the_meshes_update_alike_on_one_and_two_threads() {
    let (_dir, _, scene) = load(&near_and_far());
    let fly = |threads: usize| {
        on_threads(threads, || {
            let mut rt = SceneRuntime::new(&scene, BuildOptions::default(), RuntimeOptions::default()).unwrap();
            fly_scene(&mut rt, (0..40).map(camera), edits)
        })
    };
    assert!(fly(1) == fly(2));
}

/// Sorted world positions of `mesh` drawn at `world`, rounded to 1e-4.
fn drawn_at(mesh: &Mesh, world: [[f32; 4]; 4]) -> Vec<[i64; 3]> {
    let m = glam::Mat4::from_cols_array_2d(&world);
    let mut out: Vec<[i64; 3]> = mesh
        .positions
        .iter()
        .map(|&p| m.transform_point3(glam::Vec3::from(p)).to_array().map(|x| (x * 1e4).round() as i64))
        .collect();
    out.sort_unstable();
    out
}

/// A node that stretches its mesh, and one that shears it, are drawn by copies of the mesh
/// with the stretch baked in, placed by the rest of the node's transform: the copies draw in
/// the world where the nodes drew the mesh, each instance sees at most the pixel error, and
/// the stretches are reported (`fly` notes them). A singular node is still refused by name.
#[test]
fn a_stretched_or_sheared_node_draws_a_baked_copy() {
    let shear = [1.0, 0.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -10.0, 1.0];
    let turn = [0.0, 0.382_683_43, 0.0, 0.923_879_5];
    let nodes = [
        json!({"name": "plain"}),
        json!({"name": "stretched", "scale": [1.0, 3.0, 1.0], "rotation": turn, "translation": [0.0, 0.0, -5.0]}),
        json!({"name": "sheared", "matrix": shear}),
    ];
    let (_dir, path, scene) = load(&two_grids(&nodes));
    let mut rt = SceneRuntime::new(&scene, BuildOptions::default(), RuntimeOptions::default()).unwrap();
    assert_eq!(rt.mesh_count(), 4, "ground, spare, two stretched copies");
    assert_eq!(rt.stretched().len(), 2);
    assert!(
        rt.stretched()[0].contains("node 1") && rt.stretched()[0].contains("[1.0, 3.0, 1.0]"),
        "{:?}",
        rt.stretched()
    );
    let source = Mesh::build(&scene.meshes[0].mesh, BuildOptions::default()).unwrap();
    for (k, node) in [(2usize, 1usize), (3, 2)] {
        let m = &rt.meshes()[k];
        assert_eq!((m.index, m.mesh, m.placements.len()), (0, k, 1));
        assert!(m.stretch.is_some() && dynlod::view::check_model_matrix(m.placements[0].world).is_ok());
        let node_world = scene.meshes[0].placements[node].world;
        let same = drawn_at(m.runtime.mesh(), m.placements[0].world) == drawn_at(&source, node_world);
        assert!(same, "node {node}: the copy draws elsewhere than the node drew the mesh");
    }
    assert_eq!(rt.meshes()[0].placements.len(), 1, "the plain node keeps the source's mesh");
    for f in 0..40 {
        let cam = camera(f);
        rt.update(&[cam]);
        for m in rt.meshes() {
            for p in &m.placements {
                let px = m.runtime.screen_error_in(&cam.in_model_space(p.world).unwrap());
                assert!(px <= 1.0, "frame {f}, mesh {}: {px} px", m.mesh);
            }
        }
    }
    let (code, out, err) = dynlod(&["fly", path.to_str().unwrap(), "--instanced", "--frames", "10", "--verify"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(err.contains("note:") && err.contains("node 2 stretch or shear it"), "{err}");

    let (_dir, path, scene) =
        load(&two_grids(&[json!({"name": "plain"}), json!({"name": "flat", "scale": [1.0, 0.0, 1.0]})]));
    let err = SceneRuntime::new(&scene, BuildOptions::default(), RuntimeOptions::default()).err().unwrap();
    assert!(matches!(&err, SceneRuntimeError::Placement { node, .. } if node == "node 1"), "{err}");
    assert!(err.to_string().starts_with("mesh 0 (ground) drawn by node 1:"), "{err}");
    let (code, out, err) = dynlod(&["fly", path.to_str().unwrap(), "--instanced"]);
    assert_eq!(code, 2, "{out}");
    assert!(err.contains("scene.glb: mesh 0 (ground) drawn by node 1"), "{err}");
}

/// `fly SCENE --instanced --verify`: the summary counts what the scene draws (the ground
/// twice), the meshes and the placements; `--instanced` on a file that is not glTF is
/// refused.
#[test]
fn fly_flies_a_kept_scene() {
    let (_dir, path, _) = load(&near_and_far());
    let path = path.to_str().unwrap();
    let (code, out, err) = dynlod(&["fly", path, "--instanced", "--frames", "20", "--verify", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (v["instanced"].as_bool(), v["meshes"].as_u64(), v["instances"].as_u64()),
        (Some(true), Some(2), Some(2))
    );
    assert_eq!(v["input_triangles"].as_u64(), Some(2 * 3200));
    assert!(v["max_screen_error_px"].as_f64().unwrap() <= 1.0, "{v}");
    assert_eq!(v["max_triangles"].as_u64().unwrap() % 2, 0, "{v}");
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let (code, _, err) = dynlod(&["fly", bunny, "--instanced"]);
    assert_eq!(code, 2);
    assert!(err.contains("--instanced needs a glTF scene"), "{err}");
}

/// Placements from a scene graph of one's own (`from_meshes`) fly as the glTF's nodes do; a
/// mesh's placements set anew (an instance moved, removed, all removed) are what the next
/// update serves, exactly as a runtime given those views by hand; a stretched one is refused
/// by its position, the old ones kept; a mesh out of range is named.
#[test]
fn placements_come_from_anywhere_and_change_between_frames() {
    let (_dir, _, scene) = load(&near_and_far());
    let build = BuildOptions::default();
    let parts = scene
        .meshes
        .iter()
        .map(|sm| (Mesh::build(&sm.mesh, build).unwrap(), sm.placements.iter().map(|p| p.world).collect()))
        .collect();
    let mut mine = SceneRuntime::from_meshes(parts, RuntimeOptions::default()).unwrap();
    let mut theirs = SceneRuntime::new(&scene, build, RuntimeOptions::default()).unwrap();
    // The ground by hand: a runtime given the camera through whatever places it each frame.
    let mut by_hand = Runtime::new(Mesh::build(&scene.meshes[0].mesh, build).unwrap(), RuntimeOptions::default());
    let in_space = |f: usize, worlds: &[[[f32; 4]; 4]]| -> Vec<View> {
        worlds.iter().map(|&w| camera(f).in_model_space(w).unwrap()).collect()
    };
    let (near, far) = (scene.meshes[0].placements[0].world, scene.meshes[0].placements[1].world);
    for f in 0..10 {
        let (a, b) = (mine.update(&[camera(f)]).to_vec(), theirs.update(&[camera(f)]).to_vec());
        assert_eq!(a.iter().map(edits).collect::<Vec<_>>(), b.iter().map(edits).collect::<Vec<_>>(), "frame {f}");
        assert_eq!(edits(&by_hand.update_views(&in_space(f, &[near, far]))), edits(&a[0]), "frame {f}");
    }
    // The far instance brought close, beside the near one: from the next update the mesh
    // serves both there.
    let mut beside = near;
    beside[3][0] = 1.5;
    mine.set_placements(0, &[near, beside]).unwrap();
    for f in 10..20 {
        let s = mine.update(&[camera(f)]).to_vec();
        assert_eq!(edits(&by_hand.update_views(&in_space(f, &[near, beside]))), edits(&s[0]), "frame {f}");
        assert!(mine.meshes()[0].runtime.mesh() == by_hand.mesh(), "frame {f}");
    }
    let shared = &mine.meshes()[0].runtime;
    for v in in_space(19, &[near, beside]) {
        assert!(shared.screen_error_in(&v) <= 1.0, "{}", shared.screen_error_in(&v));
    }
    assert_eq!(mine.drawn_triangles(), 2 * shared.triangles());
    // A stretched placement is refused by its position; the two before stay.
    let mut stretched = near;
    stretched[1][1] = 3.0;
    let err = mine.set_placements(0, &[near, stretched]).unwrap_err();
    assert!(err.to_string().starts_with("mesh 0 drawn by instance 1:"), "{err}");
    assert_eq!(mine.meshes()[0].placements.len(), 2);
    assert!(matches!(mine.set_placements(5, &[near]), Err(SceneRuntimeError::NoSuchMesh { mesh: 5, meshes: 2 })));
    // No placement: the mesh is no longer updated, and stays as it was.
    let kept = mine.meshes()[0].runtime.triangles();
    mine.set_placements(0, &[]).unwrap();
    let s = mine.update(&[camera(39)]).to_vec();
    assert!(s[0].skipped && mine.meshes()[0].runtime.triangles() == kept && mine.drawn_triangles() == 0);
}

/// One pixel error for the whole scene: raised, the scene draws less and each instance sees
/// at most the new error; set again to the value in force, a still camera's frames stay
/// skipped.
#[test]
fn the_pixel_error_is_set_for_the_whole_scene() {
    let (_dir, _, scene) = load(&near_and_far());
    let mut rt = SceneRuntime::new(&scene, BuildOptions::default(), RuntimeOptions::default()).unwrap();
    let cam = camera(20);
    let settle = |rt: &mut SceneRuntime| (0..100).any(|_| rt.update(&[cam]).iter().all(|s| s.skipped));
    assert!(settle(&mut rt));
    let fine = rt.drawn_triangles();
    rt.set_pixel_error(4.0);
    assert!(!rt.update(&[cam])[0].skipped);
    assert!(settle(&mut rt));
    assert!(rt.drawn_triangles() < fine * 3 / 4, "{} of {fine}", rt.drawn_triangles());
    let m = &rt.meshes()[0];
    for p in &m.placements {
        assert!(m.runtime.screen_error_in(&cam.in_model_space(p.world).unwrap()) <= 4.0);
    }
    rt.set_pixel_error(4.0);
    assert!(rt.update(&[cam]).iter().all(|s| s.skipped));
}
