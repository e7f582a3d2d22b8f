//! Fuzz the offline simplifier on whatever the Obj and GLB loaders and their repairs accept:
//! every method, to a target, an error bound and attribute weights chosen by the first 8
//! bytes (the rest is the file). The result must validate, keep the Euler characteristic and the border loops, keep
//! every corner's wedge on its vertex, never end above the target when it says it met it, and
//! come back as it was from a file written in the input's format (`dynlod simplify`'s
//! output).
#![no_main]

use dynlod::simplify::{simplify, AttributeWeights, Method, SimplifyOptions, StopReason};
use dynlod::topology::HalfEdges;
use libfuzzer_sys::fuzz_target;

mod common;

fuzz_target!(|data: &[u8]| {
    let Some((ctl, format, mesh)) = common::controls_and_mesh(data, 8) else { return };
    let faces = mesh.topology.live_face_count();
    let before = mesh.topology.stats();
    let method = Method::ALL[usize::from(ctl[1]) % Method::ALL.len()];
    let target = faces * usize::from(ctl[2]) / 256;
    let mut o = SimplifyOptions::default()
        .method(method)
        .target_triangles(target)
        .candidates(1 + usize::from(ctl[3] & 15))
        .seed(u64::from(ctl[4]));
    if ctl[0] & 2 != 0 {
        o = o.max_error(f64::from(ctl[5]) / 64.0);
    }
    if ctl[0] & 4 != 0 {
        // Each kind on or off by a bit of ctl[6], all at ctl[7] / 16 (0 to about 16).
        let w = |bit: u8| if ctl[6] >> bit & 1 != 0 { f32::from(ctl[7]) / 16.0 } else { 0.0 };
        o = o.attribute_weights(AttributeWeights { normal: w(0), uv: w(1), color: w(2), tangent: w(3) });
    }
    let mut out = mesh.clone();
    let s = simplify(&mut out, o);
    let t = &out.topology;
    t.validate().unwrap_or_else(|e| panic!("{method:?}: {e}"));
    let after = t.stats();
    assert_eq!(
        (after.euler, after.boundary_loops),
        (before.euler, before.boundary_loops),
        "{method:?}: topology changed"
    );
    assert_eq!(t.live_face_count(), s.output_triangles, "{method:?}: stats disagree with the mesh");
    if s.stop == StopReason::Target {
        assert!(s.output_triangles <= target, "{method:?}: {} triangles for {target}", s.output_triangles);
    }
    for f in 0..t.face_slots() as u32 {
        if t.is_face_live(f) {
            for c in 0..3 {
                let g = 3 * f + c;
                let v = t.faces[f as usize][c as usize];
                assert_eq!(out.wedges.vertex_of(out.corner_wedge(g)), v, "{method:?}: corner {g} lost its wedge");
            }
        }
    }
    common::round_trip(&out, format, &format!("{method:?}"));
});
