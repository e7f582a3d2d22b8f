//! A level of detail of a whole glTF scene through the library, as `dynlod simplify IN.glb
//! OUT.glb --ratio R --method qem` makes it ([`simplify_scene`]): the scene baked into one
//! mesh is simplified first, to share the triangles out across its meshes by error; then
//! each mesh definition is simplified once, in its own space, to its share, and the scene is
//! written back around them (nodes, skins, animations, morph targets, materials kept).
//!
//! `cargo run --release --example scene_lod -- IN.glb OUT.glb [RATIO]` (default 0.25).

use dynlod::io::GltfScene;
use dynlod::simplify::{simplify_scene, Method, SceneOptions, SceneTarget, SimplifyOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(input), Some(output)) = (args.get(1), args.get(2)) else {
        return Err("usage: scene_lod IN.glb OUT.glb [RATIO]".into());
    };
    let ratio: f64 = args.get(3).map(|r| r.parse()).transpose()?.unwrap_or(0.25);

    let scene = GltfScene::load(input)?;
    let engine = SimplifyOptions::default().method(Method::Qem);
    let lod = simplify_scene(&scene, &engine, SceneOptions::default().target(SceneTarget::Ratio(ratio)))?;
    for (sm, r) in scene.meshes.iter().zip(&lod.reports) {
        println!("{}: {} -> {} triangles, drawn {}x", sm.label(), r.input_triangles, r.output_triangles, r.instances);
    }
    println!("{} -> {} triangles drawn", lod.drawn_input_triangles(), lod.drawn_output_triangles());
    for note in lod.notes.iter().chain(&scene.save(output, &lod.meshes)?) {
        println!("note: {note}");
    }
    Ok(())
}
