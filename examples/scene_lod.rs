//! A level of detail of a whole glTF scene through the library, as `dynlod simplify IN.glb
//! OUT.glb --ratio R` makes it: the scene baked into one mesh is simplified first, to share
//! the triangles out across its meshes by error (`GltfScene::allot`); then each mesh
//! definition is simplified once, in its own space, to its share, and the scene is written
//! back around them (nodes, skins, animations, morph targets, materials kept).
//!
//! `cargo run --release --example scene_lod -- IN.glb OUT.glb [RATIO]` (default 0.25).

use dynlod::io::GltfScene;
use dynlod::simplify::{simplify, Method, SimplifyOptions};
use dynlod::{BuildOptions, Mesh};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(input), Some(output)) = (args.get(1), args.get(2)) else {
        return Err("usage: scene_lod IN.glb OUT.glb [RATIO]".into());
    };
    let ratio: f64 = args.get(3).map(|r| r.parse()).transpose()?.unwrap_or(0.25);
    let options = |target: usize| SimplifyOptions::default().method(Method::Qem).target_triangles(target);

    // The share of each mesh: what a simplification of the baked scene leaves it.
    let scene = GltfScene::load(input)?;
    let mut flat = Mesh::build(&scene.flattened()?, BuildOptions::default())?;
    let drawn = flat.topology.live_face_count();
    simplify(&mut flat, options((drawn as f64 * ratio).round() as usize));
    let shares = scene.allot(&flat);

    // Each mesh once, in its own space; joints, weights and morph deltas ride along.
    let mut meshes = Vec::new();
    for (sm, share) in scene.meshes.iter().zip(&shares) {
        let mut mesh = Mesh::build(&sm.mesh, BuildOptions::default())?;
        let n = mesh.topology.live_face_count();
        // A mesh the scene does not draw keeps the plain ratio.
        let target = share.unwrap_or((n as f64 * ratio).round() as usize);
        let stats = simplify(&mut mesh, options(target));
        println!("{}: {n} -> {} triangles, drawn {}x", sm.label(), stats.output_triangles, sm.instances);
        meshes.push(mesh.to_indexed());
    }
    for note in scene.save(output, &meshes)? {
        println!("note: {note}");
    }
    Ok(())
}
