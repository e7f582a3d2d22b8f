//! `dynlod simplify --method parallel --eye ...` for several views at once: a mesh cut for
//! several cameras (`--eye` repeated), and a kept glTF scene cut for a world-space camera.
//! Each mesh definition of a scene is cut once, in its own space, for the camera as every
//! node that draws it sees it ([`View::in_model_space`]), so an instance near the eye keeps
//! the detail it needs for all of them; the nodes come out as they went in.

use dynlod::io::GltfScene;
use dynlod::lod::coarsen::{coarsen_views, CoarsenOptions};
use dynlod::view::View;
use dynlod::{BuildOptions, Mesh};
use serde_json::json;

mod common;
use common::dynlod;
use common::glb::two_grids as scene;

const EYE: [f32; 3] = [0.5, 0.5, 1.2];
const LOOK_AT: [f32; 3] = [0.5, 0.5, 0.0];

/// The camera the command line places with `--eye 0.5,0.5,1.2 --target 0.5,0.5,0 --fov 60
/// --width 1920 --height 1080`.
fn camera() -> View {
    View::perspective(EYE, LOOK_AT, [0.0, 1.0, 0.0], 60.0, (1920, 1080))
}

/// `simplify IN OUT --method parallel` from that camera at 1 px, with `--json`.
fn cut_scene(input: &str, output: &str) -> (i32, serde_json::Value, String) {
    let (code, out, err) = dynlod(&[
        "simplify",
        input,
        output,
        "--method",
        "parallel",
        "--eye",
        "0.5,0.5,1.2",
        "--target",
        "0.5,0.5,0",
        "--fov",
        "60",
        "--width",
        "1920",
        "--height",
        "1080",
        "--pixel-error",
        "1",
        "--json",
    ]);
    (code, serde_json::from_str(&out).unwrap_or(serde_json::Value::Null), err)
}

/// What the library's rounds leave of the scene's mesh 0 for `views` (in its own space).
fn library_cut(scene: &GltfScene, views: &[View]) -> usize {
    let mut mesh = Mesh::build(&scene.meshes[0].mesh, BuildOptions::default().spatial_order(true)).unwrap();
    coarsen_views(&mut mesh, views, CoarsenOptions::default().threshold(1.0));
    mesh.topology.live_face_count()
}

#[test]
fn a_kept_scene_is_cut_for_every_instance_of_each_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.glb");
    let output = dir.path().join("out.glb");
    // The grid right under the eye, and again 40 units away (shrunk by half: a far node).
    let nodes =
        [json!({"name": "near"}), json!({"name": "far", "translation": [0.0, 0.0, -40.0], "scale": [0.5, 0.5, 0.5]})];
    std::fs::write(&input, scene(&nodes)).unwrap();
    let (code, v, err) = cut_scene(input.to_str().unwrap(), output.to_str().unwrap());
    assert_eq!(code, 0, "{err}");
    assert_eq!(v["scene"], json!(true));
    let ground = &v["meshes"][0];
    assert_eq!((ground["instances"].as_u64(), ground["input_triangles"].as_u64()), (Some(2), Some(3200)));
    let left = ground["output_triangles"].as_u64().unwrap() as usize;
    // The mesh no node draws is kept as it is.
    assert_eq!(
        (v["meshes"][1]["stop"].as_str(), v["meshes"][1]["output_triangles"].as_u64()),
        (Some("NotDrawn"), Some(72))
    );

    // The same cut as the library's rounds for both instances' views, which keep more than
    // the far instance alone would.
    let source = GltfScene::load(&input).unwrap();
    let placements = &source.meshes[0].placements;
    assert_eq!(placements.iter().map(|p| p.node).collect::<Vec<_>>(), [Some(0), Some(1)]);
    let views: Vec<View> = placements.iter().map(|p| camera().in_model_space(p.world).unwrap()).collect();
    assert_eq!(left, library_cut(&source, &views));
    let (near, far) = (library_cut(&source, &views[..1]), library_cut(&source, &views[1..]));
    assert!(far < near / 2, "the far instance alone allows far fewer: {far} against {near}");
    assert!(
        left > far && left >= near * 9 / 10,
        "both instances keep what the near one needs: {left} ({near} near, {far} far)"
    );
    assert!(left < 3200, "something was cut");

    // The nodes come out as they went in, each drawing the cut mesh.
    let doc = gltf::Gltf::from_slice(&std::fs::read(&output).unwrap()).unwrap();
    let drawn: Vec<(Option<&str>, Option<usize>)> =
        doc.nodes().map(|n| (n.name(), n.mesh().map(|m| m.index()))).collect();
    assert_eq!(drawn, [(Some("near"), Some(0)), (Some("far"), Some(0))]);
    let out = GltfScene::load(&output).unwrap();
    assert_eq!(out.meshes[0].mesh.triangles.len(), left);
}

#[test]
fn a_stretched_node_is_refused_with_its_index() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.glb");
    let output = dir.path().join("out.glb");
    let nodes = [json!({"name": "plain"}), json!({"name": "stretched", "scale": [1.0, 3.0, 1.0]})];
    std::fs::write(&input, scene(&nodes)).unwrap();
    let (code, _, err) = cut_scene(input.to_str().unwrap(), output.to_str().unwrap());
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("mesh 0 (ground)") && err.contains("node 1") && err.contains("--flatten"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    assert!(!output.exists(), "nothing written");
    // Baked into world space, the same scene is cut.
    let flat = dir.path().join("flat.glb");
    let (code, out, err) = dynlod(&[
        "simplify",
        input.to_str().unwrap(),
        flat.to_str().unwrap(),
        "--method",
        "parallel",
        "--eye",
        "0.5,0.5,1.2",
        "--pixel-error",
        "1",
        "--flatten",
    ]);
    assert_eq!(code, 0, "{out}{err}");
}

/// `--eye` twice: the bunny cut for a camera in front and one behind keeps what each needs
/// (each alone lets the other side go as facing away), the library's `coarsen_views` cut
/// exactly; `--target` is given once for both or once each.
#[test]
fn several_eyes_cut_for_every_camera() {
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ply");
    let cut = |extra: &[&str]| {
        let base = ["simplify", bunny, out.to_str().unwrap(), "--method", "parallel", "--pixel-error", "1", "--json"];
        let (code, stdout, err) = dynlod(&[&base[..], extra].concat());
        (code, serde_json::from_str::<serde_json::Value>(&stdout).unwrap_or_default(), err)
    };
    let count = |v: &serde_json::Value| v["output_triangles"].as_u64().unwrap() as usize;
    let (front, back) = (["--eye", "0,0.1,0.4"], ["--eye", "0,0.1,-0.4"]);
    let (c1, one, e1) = cut(&front);
    let (c2, other, e2) = cut(&back);
    let (c3, both, e3) = cut(&[&front[..], &back[..]].concat());
    assert_eq!((c1, c2, c3), (0, 0, 0), "{e1}{e2}{e3}");
    assert_eq!(both["cameras"], json!(2));
    assert!(count(&both) > count(&one).max(count(&other)) * 3 / 2, "{both} against {one} and {other}");

    let mesh = dynlod::load_mesh(bunny, BuildOptions::default().spatial_order(true)).unwrap();
    let (lo, hi) = mesh.bounds();
    let centre = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
    let view = |eye| View::perspective(eye, centre, [0.0, 1.0, 0.0], 60.0, (1920, 1080));
    let mut m = mesh.clone();
    coarsen_views(&mut m, &[view([0.0, 0.1, 0.4]), view([0.0, 0.1, -0.4])], CoarsenOptions::default().threshold(1.0));
    assert_eq!(count(&both), m.topology.live_face_count());

    let (code, paired, err) =
        cut(&[&front[..], &back[..], &["--target", "0,0.1,0", "--target", "-0.02,0.1,0"]].concat());
    assert_eq!((code, paired["cameras"].as_u64()), (0, Some(2)), "{err}");
    let (code, _, err) = cut(&[&front[..], &["--target", "0,0.1,0", "--target", "-0.02,0.1,0"]].concat());
    assert_eq!(code, 2);
    assert!(err.contains("--target") && err.contains("eyes: 1, targets: 2"), "{err}");
}
