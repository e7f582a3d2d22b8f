//! Fuzz the scene-keeping glTF path without its panic guard: read, simplify each mesh that
//! builds to half its triangles (the others go back as read), write GLB, and read that
//! again. No panic anywhere; a scene that was read writes, and what it writes reads back as
//! a scene of as many meshes with triangles. Then the scene under a `SceneRuntime`, where
//! it builds one (at 1 px, or under a budget for the whole scene; one to three instance
//! groups): three frames from cameras around its world bounds, every runtime valid after
//! each, every placement served.
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

    // Under a budget for the whole scene where the input's length says so: a third of what
    // it draws at full detail.
    let full: usize = scene.meshes.iter().map(|m| m.mesh.triangles.len() * m.placements.len()).sum();
    let budget = (data.len() % 2 == 0).then_some(full / 3);
    let options = dynlod::lod::RuntimeOptions::default().audit(true).budget(budget);
    let Ok(mut rt) = dynlod::lod::SceneRuntime::new(&scene, dynlod::BuildOptions::default(), options) else { return };
    // Instance groups (1–3) by the input's length too.
    rt.set_instance_groups(1 + data.len() / 2 % 3);
    let (lo, hi) = scene.world_bounds();
    let (centre, diag) = dynlod::camera_path::frame_box(lo, hi);
    for d in [0.3f32, 2.0, 30.0] {
        let eye = [centre[0] + d * diag, centre[1] + 0.5 * d * diag, centre[2] + 2.0 * d * diag];
        let camera = dynlod::view::View::perspective(eye, centre, [0.0, 1.0, 0.0], 60.0, (640, 480));
        rt.update(&[camera]);
        // Every node once: by a runtime of its mesh, or of a stretched copy of it.
        let nodes: usize = scene.meshes.iter().map(|m| m.placements.len()).sum();
        let mut served = vec![0usize; rt.mesh_count()];
        for m in rt.meshes() {
            m.runtime.mesh().topology.validate().expect("a scene runtime's mesh validates");
            m.runtime.hierarchy().check(&m.runtime.mesh().topology).expect("its stacks recount");
            served[m.mesh] += m.instances.len();
        }
        assert_eq!(served.iter().sum::<usize>(), nodes, "every placement is served once");
    }
});
