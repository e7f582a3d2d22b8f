//! Runtime helpers shared by the runtime test files: the checks after a frame and random
//! camera walks.

use dynlod::lod::Runtime;
use dynlod::view::View;
use dynlod::Mesh;

/// Topology, wedges and flags equal, with the vertex→half-edge cache made canonical.
pub fn same_mesh(a: &Mesh, b: &Mesh) -> bool {
    let (mut a, mut b) = (a.clone(), b.clone());
    a.topology.rebuild_vertex_links();
    b.topology.rebuild_vertex_links();
    a == b
}

/// After a frame: the mesh validates, the hierarchy and the charges recount, the Euler
/// characteristic and border loops are the input's, the index buffer holds every live face.
pub fn check(rt: &Runtime, euler: i64, loops: u32) {
    let t = &rt.mesh().topology;
    t.validate().unwrap();
    rt.hierarchy().check(&rt.mesh().topology).unwrap();
    rt.check_charges().unwrap();
    let s = t.stats();
    assert_eq!(s.euler, euler);
    assert_eq!(s.boundary_loops, loops);
    assert_eq!(rt.index_buffer().live(), t.live_face_count());
}

/// A random walk: the eye wanders on a shell around the mesh, with occasional jumps.
pub fn walk(seed: u64, frames: usize, centre: [f32; 3], diag: f32) -> Vec<View> {
    let mut s = seed | 1;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f32 / (1u64 << 53) as f32
    };
    let (mut az, mut el, mut dist) = (0.0f32, 0.3f32, 2.0f32);
    (0..frames)
        .map(|_| {
            if rnd() < 0.05 {
                az = rnd() * std::f32::consts::TAU;
                dist = 0.6 + 4.0 * rnd();
            }
            az += 0.05 * (rnd() - 0.3);
            el = (el + 0.05 * (rnd() - 0.5)).clamp(-1.2, 1.2);
            dist = (dist * (1.0 + 0.1 * (rnd() - 0.5))).clamp(0.4, 6.0);
            let d = dist * diag;
            let eye =
                [centre[0] + d * el.cos() * az.sin(), centre[1] + d * el.sin(), centre[2] + d * el.cos() * az.cos()];
            View::perspective(eye, centre, [0.0, 1.0, 0.0], 45.0, (640, 480))
        })
        .collect()
}
