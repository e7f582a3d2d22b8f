//! Fuzz the scene-keeping glTF path without its panic guard: read, simplify each mesh that
//! builds to half its triangles (the others go back as read), write GLB, and read that
//! again. No panic anywhere; a scene that was read writes, and what it writes reads back as
//! a scene of as many meshes with triangles.
#![no_main]

use dynlod::io::GltfScene;
use dynlod::simplify::{simplify, Method, SimplifyOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(scene) = GltfScene::from_bytes_unguarded(data, None) else { return };
    let outputs: Vec<dynlod::IndexedMesh> = scene
        .meshes
        .iter()
        .map(|sm| match dynlod::Mesh::build(&sm.mesh, dynlod::BuildOptions::default()) {
            Ok(mut m) => {
                let target = m.topology.live_face_count() / 2;
                simplify(&mut m, SimplifyOptions::default().method(Method::Qem).target_triangles(target.max(1)));
                m.to_indexed()
            }
            Err(_) => sm.mesh.clone(),
        })
        .collect();
    let mut bytes = Vec::new();
    scene.write_glb(&mut bytes, &outputs).expect("a scene that was read writes");
    let again = GltfScene::from_bytes_unguarded(&bytes, None).expect("what was written reads back");
    assert_eq!(again.meshes.len(), scene.meshes.len());
});
