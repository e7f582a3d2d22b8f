//! Helpers shared by the test files (each test binary includes what it uses).
#![allow(dead_code)]

use dynlod::{procedural, IndexedMesh, Mesh};

pub mod glb;
pub mod mikktspace;
pub mod runtime;

/// Runs the `dynlod` binary: exit code, stdout, stderr.
pub fn dynlod(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dynlod")).args(args).output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}
use proptest::prelude::*;

/// n · (eye − a) for face `f`: positive when the face turns its front to the eye.
pub fn facing(m: &Mesh, f: [u32; 3], eye: [f64; 3]) -> f64 {
    facing_from(m, f, dynlod::view::Viewpoint::At(eye))
}

/// n · (the direction from corner a towards the camera) for face `f`: positive when the face
/// turns its front to a perspective eye or an orthographic view.
pub fn facing_from(m: &Mesh, f: [u32; 3], eye: dynlod::view::Viewpoint) -> f64 {
    let [a, b, c] = f.map(|v| glam::DVec3::from(m.positions[v as usize].map(f64::from)));
    (b - a).cross(c - a).dot(glam::DVec3::from(eye.seen_from(a.to_array())))
}

/// A perspective camera `d` bounding-box diagonals from `m`'s centre (negative: the other
/// side), looking at it from above and the front along (0.3, 0.4, 0.866), 60°.
pub fn view_from_diagonals(m: &Mesh, d: f32, viewport: (u32, u32)) -> dynlod::view::View {
    let (c, diag) = dynlod::camera_path::frame_bounds(&m.positions);
    let eye = glam::Vec3::from(c) + glam::Vec3::new(0.3, 0.4, 0.866).normalize() * d * diag;
    dynlod::view::View::perspective(eye.into(), c, [0.0, 1.0, 0.0], 60.0, viewport)
}

/// Random surfaces: tori (closed, genus 1), bumpy grids with random diagonals (open disks),
/// the same with a UV seam that ends inside (a seam's end), UV spheres with seams (closed,
/// genus 0 after welding).
pub fn surfaces() -> impl Strategy<Value = IndexedMesh> {
    let bumps = |g: &mut IndexedMesh, bits: u64| {
        for (k, p) in g.positions.iter_mut().enumerate() {
            p[2] = ((k as u64).wrapping_mul(bits | 1) % 97) as f32 / 200.0;
        }
    };
    prop_oneof![
        (6usize..20, 4usize..12).prop_map(|(r, s)| procedural::torus(r, s)),
        (3usize..12, 3usize..12, any::<u64>()).prop_map(move |(w, h, bits)| {
            let mut g = procedural::grid(w, h, move |i, j| bits >> ((i * 7 + j) % 64) & 1 == 1);
            bumps(&mut g, bits);
            g
        }),
        (3usize..12, 2usize..12, 1usize..11, any::<u64>()).prop_map(move |(w, h, cut, bits)| {
            let mut g = procedural::cut_grid(w, h, cut, move |i, j| bits >> ((i * 5 + j) % 64) & 1 == 1);
            // Copies of a vertex share its bump (they are one point split by the seam).
            let mut by_point = std::collections::HashMap::new();
            for (k, p) in g.positions.iter_mut().enumerate() {
                let z = *by_point
                    .entry(p.map(f32::to_bits))
                    .or_insert(((k as u64).wrapping_mul(bits | 1) % 97) as f32 / 200.0);
                p[2] = z;
            }
            g
        }),
        (4usize..12, 6usize..16).prop_map(|(a, b)| procedural::uv_sphere(a, b)),
    ]
}

/// `f` run on a rayon pool of `threads` threads (the same-result-on-1-and-N-threads checks).
pub fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

/// `n` proptest cases, times `DYNLOD_PROPTEST_SCALE` when set (a soak run before a release:
/// `DYNLOD_PROPTEST_SCALE=50 cargo test --release`). Cases are drawn afresh every run;
/// failures are kept in the `*.proptest-regressions` files and replayed first.
pub fn cases(n: u32) -> u32 {
    let scale = std::env::var("DYNLOD_PROPTEST_SCALE").ok().and_then(|s| s.parse::<u32>().ok());
    n.saturating_mul(scale.unwrap_or(1).max(1))
}

/// Every live slot of every part, read in input vertex ids, names input vertices whose
/// position, normal, UV and further attributes are the wedge's: a renderer can draw the
/// buffers over its own vertex arrays. Each live face sits in the part of its primitive, so a
/// renderer drawing part p with primitive p's material draws every face with its own. `mirrors`
/// holds what the renderer uploaded (one list per part), updated here from the changed ranges.
/// Returns how many topological vertices were drawn through more than one input vertex (seams).
pub fn check_source_triangles(
    rt: &dynlod::lod::Runtime,
    input: &IndexedMesh,
    mirrors: &mut Vec<Vec<[u32; 3]>>,
) -> usize {
    let (m, ib) = (rt.mesh(), rt.index_buffer());
    assert_eq!(ib.parts().len(), m.primitives.len(), "one part per primitive");
    mirrors.resize(ib.parts().len(), Vec::new());
    let mut seen: std::collections::HashMap<u32, u32> = Default::default();
    let mut seams = std::collections::HashSet::new();
    for (p, (part, mirror)) in ib.parts().iter().zip(mirrors.iter_mut()).enumerate() {
        mirror.resize(part.triangles().len(), [0; 3]);
        for r in part.changed_ranges() {
            for (k, t) in part.source_triangles(m, r.clone()).enumerate() {
                mirror[r.start as usize + k] = t;
            }
        }
        for (slot, (wedges, sources)) in part.triangles().iter().zip(mirror.iter()).enumerate() {
            let live = wedges[0] != wedges[1]; // a freed slot is [w, w, w]
            for (&w, &s) in wedges.iter().zip(sources) {
                assert_eq!(s, m.wedge_source(w), "part {p} slot {slot}: the uploaded ranges miss a change");
                let v = m.wedges.vertex_of(w);
                assert_eq!(input.positions[s as usize], m.positions[v as usize], "slot {slot}, wedge {w}");
                if !m.wedges.normals.is_empty() {
                    assert_eq!(input.normals[s as usize], m.wedges.normals[w as usize], "slot {slot}, wedge {w}");
                }
                if !m.wedges.uvs.is_empty() {
                    assert_eq!(input.uvs[s as usize], m.wedges.uvs[w as usize], "slot {slot}, wedge {w}");
                }
                for (a, b) in input.attributes.iter().zip(&m.wedges.attributes) {
                    assert_eq!(a.get(s as usize), b.get(w as usize), "slot {slot}, wedge {w}, {}", a.semantic);
                }
                if live && *seen.entry(v).or_insert(s) != s {
                    seams.insert(v);
                }
            }
        }
    }
    use dynlod::topology::HalfEdges;
    let t = &m.topology;
    let mut live = 0;
    for f in (0..t.face_slots() as u32).filter(|&f| t.is_face_live(f)) {
        let part = &ib.parts()[m.primitive_of(f as usize) as usize];
        let wedges = [0, 1, 2].map(|k| m.corner_wedge(3 * f + k));
        assert_eq!(part.triangles()[ib.slot_of_face(f) as usize], wedges, "face {f} is not in its primitive's part");
        live += 1;
    }
    assert_eq!(ib.parts().iter().map(|p| p.live()).sum::<usize>(), live);
    seams.len()
}
