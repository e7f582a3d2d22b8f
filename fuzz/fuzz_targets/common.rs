//! What the targets that run the algorithms share: the input split into control bytes and
//! Obj text, loaded without the panic guard and built, small enough to keep executions short.

/// Most triangles a target runs on: the algorithms' cost is not what is fuzzed.
const MAX_FACES: usize = 3000;

/// `data`'s first `n` bytes (the target's controls; bit 0 of the first asks for spatial
/// order) and the mesh the rest builds, or `None` where there is nothing to run on.
pub fn controls_and_mesh(data: &[u8], n: usize) -> Option<(&[u8], dynlod::Mesh)> {
    if data.len() < n {
        return None;
    }
    let (ctl, text) = data.split_at(n);
    let m = dynlod::io::load_bytes_unguarded(text, dynlod::io::Format::Obj, None).ok()?;
    let mesh = dynlod::Mesh::build(&m, dynlod::BuildOptions::default().spatial_order(ctl[0] & 1 != 0)).ok()?;
    let faces = mesh.topology.live_face_count();
    (faces > 0 && faces <= MAX_FACES).then_some((ctl, mesh))
}
