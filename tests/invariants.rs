//! Properties that must hold on any input (proptest).

use dynlod::topology::Topology;
use dynlod::{procedural, BuildError, BuildOptions, IndexedMesh, Mesh, MeshError};
use proptest::prelude::*;

mod common;

/// Triangle soups over a small pool of points on a 3×3×3 lattice, so that coincident
/// positions, repeated indices, duplicates, fins, bowties and flipped faces are all common.
fn soup() -> impl Strategy<Value = IndexedMesh> {
    (3usize..14).prop_flat_map(|n| {
        (
            prop::collection::vec(prop::array::uniform3(0u8..3), n),
            prop::collection::vec(prop::array::uniform3(0..n as u32), 1..48),
            prop::collection::vec(prop::array::uniform2(0u8..2), n),
        )
            .prop_map(|(pts, tris, uv)| IndexedMesh {
                positions: pts.iter().map(|p| p.map(f32::from)).collect(),
                uvs: uv.iter().map(|t| t.map(f32::from)).collect(),
                triangles: tris,
                ..Default::default()
            })
    })
}

/// Valid closed or open surfaces, shuffled: vertex ids permuted, faces reordered, each
/// face's corners rotated. Returns the mesh and its expected (components, genus, loops).
fn valid_mesh() -> impl Strategy<Value = (IndexedMesh, (usize, u32, u32))> {
    let base = prop_oneof![
        (3usize..9, 3usize..9).prop_map(|(r, s)| (procedural::torus(r, s), (1, 1, 0))),
        (1usize..7, 1usize..7, any::<u64>()).prop_map(|(w, h, bits)| (
            procedural::grid(w, h, move |i, j| bits >> ((i * 7 + j) % 64) & 1 == 1),
            (1, 0, 1)
        )),
        (2usize..8, 3usize..9).prop_map(|(a, b)| (procedural::uv_sphere(a, b), (1, 0, 0))),
        Just((procedural::tetrahedron(), (1, 0, 0))),
    ];
    (base, any::<u64>()).prop_map(|((m, expect), seed)| (shuffle(m, seed), expect))
}

fn shuffle(mut m: IndexedMesh, seed: u64) -> IndexedMesh {
    let mut s = seed | 1;
    let mut rnd = move |n: usize| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s % n as u64) as usize
    };
    let n = m.positions.len();
    let mut perm: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        perm.swap(i, rnd(i + 1));
    }
    let mut inv = vec![0u32; n];
    for (new, &old) in perm.iter().enumerate() {
        inv[old] = new as u32;
    }
    m.positions = perm.iter().map(|&o| m.positions[o]).collect();
    if !m.normals.is_empty() {
        m.normals = perm.iter().map(|&o| m.normals[o]).collect();
    }
    if !m.uvs.is_empty() {
        m.uvs = perm.iter().map(|&o| m.uvs[o]).collect();
    }
    for t in &mut m.triangles {
        *t = t.map(|v| inv[v as usize]);
        t.rotate_left(rnd(3));
    }
    let nf = m.triangles.len();
    for i in (1..nf).rev() {
        m.triangles.swap(i, rnd(i + 1));
    }
    m
}

fn corner_tuple(m: &IndexedMesh, v: u32) -> ([f32; 3], [f32; 2]) {
    (m.positions[v as usize], m.uvs.get(v as usize).copied().unwrap_or_default())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(512), ..ProptestConfig::default() })]

    #[test]
    fn any_soup_builds_to_a_valid_manifold_or_names_why_not(m in soup()) {
        match Mesh::build(&m, BuildOptions::default()) {
            Ok(mesh) => {
                prop_assert_eq!(mesh.topology.validate(), Ok(()));
                prop_assert!(mesh.topology.live_face_count() <= m.triangles.len());
                prop_assert!(mesh.topology.stats().components.iter().all(|c| c.genus.is_some()));
                // Every face is an input triangle (possibly flipped), corner for corner.
                let out = mesh.to_indexed();
                for (f, t) in out.triangles.iter().enumerate() {
                    let src = m.triangles[mesh.face_source[f] as usize];
                    let mut a: Vec<_> = t.iter().map(|&v| corner_tuple(&out, v)).collect();
                    let mut b: Vec<_> = src.iter().map(|&v| corner_tuple(&m, v)).collect();
                    a.sort_by(|x, y| x.partial_cmp(y).unwrap());
                    b.sort_by(|x, y| x.partial_cmp(y).unwrap());
                    prop_assert_eq!(a, b);
                }
                // Deterministic.
                prop_assert_eq!(Mesh::build(&m, BuildOptions::default()).unwrap(), mesh);
            }
            Err(BuildError::Mesh(MeshError::AllDegenerate { dropped })) => {
                prop_assert_eq!(dropped, m.triangles.len());
                for t in &m.triangles {
                    let p = t.map(|v| m.positions[v as usize]);
                    prop_assert!(p[0] == p[1] || p[1] == p[2] || p[0] == p[2]);
                }
            }
            Err(e) => prop_assert!(false, "unexpected error {}", e),
        }
    }

    #[test]
    fn valid_meshes_come_out_untouched((m, (components, genus, loops)) in valid_mesh()) {
        let mesh = Mesh::build(&m, BuildOptions::default().strict(true)).expect("no repair needed");
        prop_assert_eq!(mesh.topology.validate(), Ok(()));
        let s = mesh.topology.stats();
        prop_assert_eq!(s.faces as usize, m.triangles.len());
        prop_assert_eq!((s.components.len(), s.genus, s.boundary_loops), (components, Some(genus), loops));
        // Euler characteristic from the known surface.
        prop_assert_eq!(s.euler, 2 * components as i64 - 2 * genus as i64 - loops as i64);
        // Unwelding gives back every corner's position and attributes in the input's order.
        let out = mesh.to_indexed();
        for (f, t) in out.triangles.iter().enumerate() {
            let src = m.triangles[mesh.face_source[f] as usize];
            for c in 0..3 {
                let (o, i) = (t[c] as usize, src[c] as usize);
                prop_assert_eq!(out.positions[o], m.positions[i]);
                if !m.uvs.is_empty() {
                    prop_assert_eq!(out.uvs[o], m.uvs[i]);
                    prop_assert_eq!(out.normals[o], m.normals[i]);
                }
            }
        }
        // The general builder agrees with the repair path's twins.
        let again = Topology::from_faces(mesh.positions.len(), mesh.topology.faces.clone()).unwrap();
        prop_assert_eq!(&again.twin, &mesh.topology.twin);
        prop_assert_eq!(again.validate(), Ok(()));
    }

    /// Every writer round-trips any built mesh bit for bit (positions, normals, UVs, faces).
    #[test]
    fn writers_round_trip_exactly(m in soup(), scale in 1e-3f32..1e3, offset in -1e3f32..1e3) {
        let mut m = m;
        for p in &mut m.positions {
            *p = p.map(|c| c * scale + offset);
        }
        m.normals = m.positions.iter().map(|p| [p[1], -p[0], 1.0 / (1.0 + p[2].abs())]).collect();
        let Ok(mesh) = Mesh::build(&m, BuildOptions::default()) else { return Ok(()) };
        let out = mesh.to_indexed();
        let dir = tempfile::tempdir().unwrap();
        for name in ["m.obj", "m.ply", "m.glb"] {
            let path = dir.path().join(name);
            dynlod::io::save(&path, &out).unwrap();
            let back = dynlod::io::load(&path).unwrap();
            prop_assert_eq!(&back.positions, &out.positions, "{}", name);
            prop_assert_eq!(&back.normals, &out.normals, "{}", name);
            prop_assert_eq!(&back.uvs, &out.uvs, "{}", name);
            prop_assert_eq!(&back.triangles, &out.triangles, "{}", name);
        }
    }

    /// Writing a repaired mesh and reading it back re-welds the copies that repairs split
    /// off, so the repairs run again; they must land on the same surface.
    #[test]
    fn repairs_are_stable_under_a_write_and_reload(m in soup()) {
        if let Ok(mesh) = Mesh::build(&m, BuildOptions::default()) {
            let again = Mesh::build(&mesh.to_indexed(), BuildOptions::default()).unwrap();
            prop_assert_eq!(again.topology.validate(), Ok(()));
            prop_assert_eq!(again.topology.stats(), mesh.topology.stats());
        }
    }
}
