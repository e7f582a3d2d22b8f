//! Runtime helpers shared by the runtime test files: the checks after a frame and random
//! camera walks.

use dynlod::lod::hierarchy::CollapseRecord;
use dynlod::lod::{FrameStats, Runtime, SceneRuntime};
use dynlod::topology::INVALID;
use dynlod::view::{Projection, View, Viewpoint};
use dynlod::Mesh;

use super::facing_from;

/// Flies `rt` through `cameras` (one camera a frame): each frame's figures per mesh, through
/// `figures`, and the meshes at the end (to compare flights on 1 and N threads).
pub fn fly_scene<T>(
    rt: &mut SceneRuntime,
    cameras: impl Iterator<Item = View>,
    figures: impl Fn(&FrameStats) -> T,
) -> (Vec<Vec<T>>, Vec<Mesh>) {
    let stats = cameras.map(|c| rt.update(&[c]).iter().map(&figures).collect()).collect();
    (stats, rt.meshes().iter().map(|m| m.runtime.mesh().clone()).collect())
}

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

/// The eye of `v`, worked out here rather than with `View::viewpoint`: the facing checks must
/// not share the code they check.
pub fn eye_of(v: &View) -> Viewpoint {
    match v.projection {
        Projection::Perspective { .. } => Viewpoint::At(v.eye.map(f64::from)),
        Projection::Orthographic { .. } => Viewpoint::Towards(v.forward.map(|x| -f64::from(x))),
    }
}

/// What a frame must keep facing: taken before an update, checked after it
/// ([`FacingWatch::turned`]).
pub struct FacingWatch {
    eyes: Vec<Viewpoint>,
    /// Per eye, per face slot: whether the face was live and faced the eye.
    facing: Vec<Vec<bool>>,
    records: Vec<CollapseRecord>,
    /// Per vertex: the faces its record touched (none when not collapsed).
    touched: Vec<Vec<u32>>,
}

impl FacingWatch {
    /// The faces of `rt`'s mesh that face each of `views`' eyes, and its records, now.
    pub fn before(rt: &Runtime, views: &[View]) -> Self {
        let m = rt.mesh();
        let eyes: Vec<Viewpoint> = views.iter().map(eye_of).collect();
        let faces = &m.topology.faces;
        let facing = eyes
            .iter()
            .map(|&e| faces.iter().map(|&f| f[0] != INVALID && facing_from(m, f, e) > 0.0).collect())
            .collect();
        let records = (0..m.positions.len() as u32).map(|u| *rt.hierarchy().record(u)).collect();
        let touched =
            (0..m.positions.len() as u32).map(|u| rt.hierarchy().touched(&m.topology, u).unwrap_or_default()).collect();
        Self { eyes, facing, records, touched }
    }

    /// The first face (and eye) that faced an eye before and faces away from it now, unless a
    /// split this frame edited it (a record gone or redone): a split restores the original
    /// geometry, which may face away, and a later collapse of that face only has to keep it
    /// from turning further.
    pub fn turned(&self, rt: &Runtime) -> Option<(usize, usize)> {
        let now = rt.mesh();
        let mut split_faces = vec![false; now.topology.faces.len()];
        for (u, r) in self.records.iter().enumerate() {
            if r.target != INVALID && rt.hierarchy().record(u as u32) != r {
                for &f in &self.touched[u] {
                    split_faces[f as usize] = true;
                }
            }
        }
        self.eyes.iter().enumerate().find_map(|(j, &e)| {
            self.facing[j].iter().enumerate().find_map(|(f, &was)| {
                let tri = now.topology.faces[f];
                (was && !split_faces[f] && tri[0] != INVALID && facing_from(now, tri, e) < 0.0).then_some((f, j))
            })
        })
    }
}
