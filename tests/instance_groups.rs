//! Instance groups (`SceneRuntime::set_instance_groups`): a mesh drawn many times gets up to k
//! runtimes, each serving the placements in one band of distance. Every placement is served by
//! exactly one runtime of its mesh each frame, the nearest by the first; every instance still
//! sees at most the pixel error; a field of instances draws fewer triangles than under one
//! runtime; groups follow changes of placements and of k; under a budget the scene keeps it;
//! the result is the same on 1 and 2 threads.

use dynlod::lod::{RuntimeOptions, SceneMeshRuntime, SceneRuntime};
use dynlod::view::View;
use dynlod::{procedural, BuildOptions, Mesh};
use proptest::prelude::*;

mod common;
use common::glb::two_grids;
use common::runtime::{check, walk};
use common::{dynlod, on_threads};

fn at(x: f32, z: f32) -> [[f32; 4]; 4] {
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [x, 0.0, z, 1.0]]
}

/// A placement turned by `turn` radians about the vertical axis, scaled by `s` and moved to
/// `(x, z)`.
fn placed(turn: f32, s: f32, x: f32, z: f32) -> [[f32; 4]; 4] {
    let (sin, cos) = turn.sin_cos();
    [[s * cos, 0.0, -s * sin, 0.0], [0.0, s, 0.0, 0.0], [s * sin, 0.0, s * cos, 0.0], [x, 0.0, z, 1.0]]
}

fn sphere() -> Mesh {
    Mesh::build(&procedural::uv_sphere(24, 48), BuildOptions::default()).unwrap()
}

/// A 5 × 5 field of spheres 4 apart, running away from the camera.
fn field() -> Vec<[[f32; 4]; 4]> {
    (0..25).map(|n| at(4.0 * (n % 5) as f32, -4.0 * (n / 5) as f32)).collect()
}

/// Frame `f`: the camera slides along the field's near edge, looking into it.
fn camera(f: usize) -> View {
    let x = 0.1 * f as f32;
    View::perspective([x, 1.5, 4.0], [x + 3.0, 0.0, -10.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080))
}

fn scene(worlds: Vec<[[f32; 4]; 4]>, groups: usize, options: RuntimeOptions) -> SceneRuntime {
    let mut rt = SceneRuntime::from_meshes(vec![(sphere(), worlds)], options).unwrap();
    rt.set_instance_groups(groups);
    rt
}

/// The mesh's runtimes, in order.
fn runtimes(rt: &SceneRuntime, mesh: usize) -> Vec<&SceneMeshRuntime> {
    rt.meshes().iter().filter(|m| m.mesh == mesh).collect()
}

/// Every placement of `worlds` is served by exactly one of the mesh's runtimes, as the entry
/// its `instances` names; groups are numbered in order.
fn assert_shared(rt: &SceneRuntime, mesh: usize, worlds: &[[[f32; 4]; 4]]) {
    let mut served = vec![0; worlds.len()];
    for (g, m) in runtimes(rt, mesh).into_iter().enumerate() {
        assert_eq!(m.group, g);
        assert_eq!(m.placements.len(), m.instances.len());
        for (p, &i) in m.placements.iter().zip(&m.instances) {
            assert_eq!(p.world, worlds[i]);
            served[i] += 1;
        }
    }
    assert!(served.iter().all(|&n| n == 1), "{served:?}");
}

/// Every instance's screen error through the runtime that serves it, over `cameras`.
fn worst_error(rt: &SceneRuntime, cameras: &[View]) -> f32 {
    let mut worst = 0.0f32;
    for m in rt.meshes() {
        for p in &m.placements {
            for c in cameras {
                worst = worst.max(m.runtime.screen_error_in(&c.in_model_space(p.world).unwrap()));
            }
        }
    }
    worst
}

/// Distance from the first camera's eye to a placement's origin.
fn distance(camera: &View, world: &[[f32; 4]; 4]) -> f32 {
    let e = camera.eye;
    ((world[3][0] - e[0]).powi(2) + (world[3][1] - e[1]).powi(2) + (world[3][2] - e[2]).powi(2)).sqrt()
}

#[test]
fn groups_serve_each_placement_once_within_the_error_and_draw_less() {
    let worlds = field();
    let mut one = scene(worlds.clone(), 1, RuntimeOptions::default());
    let mut four = scene(worlds.clone(), 4, RuntimeOptions::default());
    assert_eq!(runtimes(&four, 0).len(), 4);
    let shape = sphere().topology.stats();
    let (mut drawn_one, mut drawn_four) = (0, 0);
    for f in 0..30 {
        let cam = [camera(f)];
        one.update(&cam);
        four.update(&cam);
        assert_shared(&four, 0, &worlds);
        for m in four.meshes() {
            check(&m.runtime, shape.euler, shape.boundary_loops);
        }
        assert!(worst_error(&four, &cam) <= 1.0, "frame {f}: {}", worst_error(&four, &cam));
        // The nearest placement is the first group's; the first group's farthest is nearer
        // than the last group's nearest.
        let groups = runtimes(&four, 0);
        let near = |m: &SceneMeshRuntime| {
            m.placements.iter().map(|p| distance(&cam[0], &p.world)).fold(f32::INFINITY, f32::min)
        };
        let far = |m: &SceneMeshRuntime| m.placements.iter().map(|p| distance(&cam[0], &p.world)).fold(0.0, f32::max);
        let nearest = worlds.iter().map(|w| distance(&cam[0], w)).fold(f32::INFINITY, f32::min);
        assert_eq!(near(groups[0]), nearest, "frame {f}");
        assert!(!groups[3].placements.is_empty() && far(groups[0]) < near(groups[3]), "frame {f}");
        // A group draws no more than the one runtime serving everything (a group holds the
        // detail its own nearest needs, the one runtime the scene's nearest's).
        assert!(groups.iter().all(|m| m.runtime.triangles() <= one.meshes()[0].runtime.triangles() + 8), "frame {f}");
        drawn_one += one.drawn_triangles();
        drawn_four += four.drawn_triangles();
    }
    assert!(drawn_four * 10 < drawn_one * 8, "{drawn_four} against {drawn_one}");
}

/// k groups for a mesh drawn n times: min(k, n) runtimes, one at least; a group added starts as
/// a copy of the farthest, one dropped is the farthest; placements set between updates are
/// shared at once by the last cameras.
#[test]
fn groups_follow_the_placements_and_k() {
    let worlds = field();
    let mut rt = scene(worlds[..2].to_vec(), 3, RuntimeOptions::default());
    assert_eq!((rt.meshes().len(), rt.mesh_count(), rt.instance_groups()), (2, 1, 3));
    // Before any update: everything to the first.
    assert_eq!(runtimes(&rt, 0)[0].placements.len(), 2);
    rt.update(&[camera(0)]);
    assert_shared(&rt, 0, &worlds[..2]);
    let farthest = rt.meshes()[1].runtime.mesh().clone();
    rt.set_placements(0, &worlds).unwrap();
    assert_eq!(rt.meshes().len(), 3);
    assert!(rt.meshes()[2].runtime.mesh() == &farthest, "the new group copies the farthest");
    assert_shared(&rt, 0, &worlds);
    rt.update(&[camera(1)]);
    assert_shared(&rt, 0, &worlds);
    let first = rt.meshes()[0].runtime.mesh().clone();
    rt.set_instance_groups(1);
    assert_eq!(rt.meshes().len(), 1);
    assert!(rt.meshes()[0].runtime.mesh() == &first, "the first group stays");
    assert_shared(&rt, 0, &worlds);
    assert!(worst_error(&rt, &[camera(1)]) > 1.0, "the far instances were coarser than the near needs");
    rt.update(&[camera(1)]);
    assert!(worst_error(&rt, &[camera(1)]) <= 1.0);
    rt.set_instance_groups(0);
    assert_eq!(rt.instance_groups(), 1);
    rt.set_instance_groups(2);
    rt.set_placements(0, &[]).unwrap();
    assert_eq!(rt.meshes().len(), 1);
    assert!(rt.update(&[camera(2)])[0].skipped && rt.drawn_triangles() == 0);
}

/// A group that gets placements having never run a frame starts as a copy of a group that
/// has: two placements side by side share one band (the second group idle, as built); one
/// moved far away goes to the second group, which then holds the first's mesh, not the full
/// one.
#[test]
fn an_idle_group_starts_warm() {
    let mut rt = scene(vec![at(-2.0, -6.0), at(2.0, -6.0)], 2, RuntimeOptions::default());
    let cam = View::perspective([0.0, 0.0, 4.0], [0.0, 0.0, -6.0], [0.0, 1.0, 0.0], 60.0, (1920, 1080));
    for _ in 0..3 {
        rt.update(&[cam]);
    }
    let groups = runtimes(&rt, 0);
    assert_eq!((groups[0].placements.len(), groups[1].placements.len()), (2, 0));
    assert_eq!(groups[1].runtime.triangles(), sphere().topology.live_face_count(), "idle, as built");
    let idle = groups[1].generation;
    rt.set_placements(0, &[at(-2.0, -6.0), at(2.0, -60.0)]).unwrap();
    let groups = runtimes(&rt, 0);
    assert_eq!((groups[0].instances.clone(), groups[1].instances.clone()), (vec![0], vec![1]));
    assert!(groups[1].runtime.mesh() == groups[0].runtime.mesh(), "a copy of the warm group");
    assert_ne!(groups[1].generation, idle, "a new generation for the renderer");
    rt.update(&[cam]);
    assert!(worst_error(&rt, &[cam]) <= 1.0);
}

/// What a renderer keeps of one runtime's index buffer: the generation it uploaded and each
/// part's triangles.
type Mirror = std::collections::HashMap<(usize, usize), (u64, Vec<Vec<[u32; 3]>>)>;

/// Brings `mirror` up to date after an update as a renderer would: a runtime of a generation
/// it has not seen is uploaded whole, else only its changed ranges (`by_generation` false: the
/// generation ignored). Returns whether every runtime's mirror equals its index buffer.
fn upload(rt: &SceneRuntime, mirror: &mut Mirror, by_generation: bool) -> bool {
    let mut same = true;
    for m in rt.meshes() {
        let parts = m.runtime.index_buffer().parts();
        let (generation, held) = mirror.entry((m.mesh, m.group)).or_insert((u64::MAX, Vec::new()));
        if (by_generation && *generation != m.generation) || held.len() != parts.len() {
            *held = parts.iter().map(|p| p.triangles().to_vec()).collect();
            *generation = m.generation;
            continue;
        }
        for (part, held) in parts.iter().zip(held.iter_mut()) {
            held.resize(part.triangles().len(), [0; 3]);
            for r in part.changed_ranges() {
                let r = r.start as usize..r.end as usize;
                held[r.clone()].copy_from_slice(&part.triangles()[r]);
            }
            same &= held.as_slice() == part.triangles();
        }
    }
    same
}

/// A renderer's contract: uploading each runtime's changed ranges keeps its copy of every
/// index buffer exact, once it uploads whole a runtime whose generation changed (a group
/// added, an idle group started warm). Seen failing without the generation: the idle group's
/// copy, started warm from the first, is not the buffer the renderer kept.
#[test]
fn a_renderer_keeps_every_groups_index_buffer_by_ranges_and_generations() {
    let mut rt = scene(vec![at(-2.0, -6.0), at(2.0, -6.0)], 2, RuntimeOptions::default());
    let (mut kept, mut naive) = (Mirror::new(), Mirror::new());
    let mut naive_broke = false;
    let frame = |rt: &mut SceneRuntime, f: usize, kept: &mut Mirror, naive: &mut Mirror| {
        rt.update(&[camera(f)]);
        assert!(upload(rt, kept, true), "frame {f}: a kept copy went wrong");
        !upload(rt, naive, false)
    };
    for f in 0..5 {
        naive_broke |= frame(&mut rt, f, &mut kept, &mut naive);
    }
    rt.set_placements(0, &[at(-2.0, -6.0), at(2.0, -60.0)]).unwrap();
    for f in 5..15 {
        naive_broke |= frame(&mut rt, f, &mut kept, &mut naive);
    }
    rt.set_placements(0, &field()).unwrap();
    rt.set_instance_groups(4);
    for f in 15..40 {
        naive_broke |= frame(&mut rt, f, &mut kept, &mut naive);
    }
    assert!(naive_broke, "the flight never replaced a runtime a renderer held");
}

/// Under a budget the groups share the one threshold: the scene draws within the budget, and
/// draws it at a lower threshold than one runtime for all could.
#[test]
fn groups_keep_a_scene_budget_at_a_lower_threshold() {
    let options = RuntimeOptions::default().budget(Some(40_000));
    let (mut one, mut four) = (scene(field(), 1, options.clone()), scene(field(), 4, options));
    for f in 0..40 {
        one.update(&[camera(f % 10)]);
        four.update(&[camera(f % 10)]);
    }
    assert!(four.drawn_triangles() <= 40_000, "{}", four.drawn_triangles());
    assert!(four.threshold() < one.threshold(), "{} against {}", four.threshold(), one.threshold());
    assert!(worst_error(&four, &[camera(9)]) <= four.threshold());
}

/// `fly SCENE --instanced --groups K`: the summary names the groups and the runtimes (the
/// ground drawn four times gets two, the spare mesh one), every instance within the pixel
/// error under `--verify`; `--groups` without `--instanced` is refused.
#[test]
fn fly_flies_a_kept_scene_in_groups() {
    let nodes: Vec<_> =
        [0.0, -8.0, -16.0, -32.0].iter().map(|z| serde_json::json!({"translation": [0.0, 0.0, z]})).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("row.glb");
    std::fs::write(&path, two_grids(&nodes)).unwrap();
    let path = path.to_str().unwrap();
    let (code, out, err) =
        dynlod(&["fly", path, "--instanced", "--groups", "2", "--frames", "20", "--verify", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let counts = ["meshes", "instances", "instance_groups", "runtimes"].map(|k| v[k].as_u64());
    assert_eq!(counts, [Some(2), Some(4), Some(2), Some(3)], "{v}");
    assert!(v["max_screen_error_px"].as_f64().unwrap() <= 1.0, "{v}");
    let (code, _, err) = dynlod(&["fly", path, "--groups", "2"]);
    assert_eq!(code, 2);
    assert!(err.contains("--instanced"), "{err}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(12), ..ProptestConfig::default() })]

    /// A torus drawn at random turns, scales and places with 1–4 groups, on a random walk with
    /// jumps: after every frame every placement is served once, every runtime keeps the
    /// runtime's invariants, every instance sees at most the pixel error; 1 and 2 threads agree.
    #[test]
    fn random_groups_stay_valid_and_deterministic(
        k in 1usize..5, seed in any::<u64>(),
        places in proptest::collection::vec((0.0f32..6.3, 0.3f32..2.0, -6.0f32..6.0, -6.0f32..6.0), 1..8),
    ) {
        let mesh = Mesh::build(&procedural::torus(16, 8), BuildOptions::default()).unwrap();
        let shape = mesh.topology.stats();
        let worlds: Vec<_> = places.iter().map(|&(t, s, x, z)| placed(t, s, x, z)).collect();
        let views = walk(seed, 25, [0.0, 0.0, 0.0], 6.0);
        let fly = |threads: usize| {
            on_threads(threads, || {
                let mut rt = SceneRuntime::from_meshes(vec![(mesh.clone(), worlds.clone())], RuntimeOptions::default()).unwrap();
                rt.set_instance_groups(k);
                assert_eq!(rt.meshes().len(), k.min(worlds.len()));
                let mut out = Vec::new();
                for (f, v) in views.iter().enumerate() {
                    let cams = std::slice::from_ref(v);
                    let stats = rt.update(cams).to_vec();
                    assert_shared(&rt, 0, &worlds);
                    for m in rt.meshes() {
                        check(&m.runtime, shape.euler, shape.boundary_loops);
                    }
                    let worst = worst_error(&rt, cams);
                    assert!(worst <= 1.0, "frame {f}: {worst}");
                    let served: Vec<Vec<usize>> = rt.meshes().iter().map(|m| m.instances.clone()).collect();
                    out.push((served, stats.iter().map(|s| (s.collapses, s.splits, s.triangles)).collect::<Vec<_>>()));
                }
                (out, rt.meshes().iter().map(|m| m.runtime.mesh().clone()).collect::<Vec<_>>())
            })
        };
        prop_assert!(fly(1) == fly(2));
    }
}
