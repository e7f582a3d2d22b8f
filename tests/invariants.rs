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
                    let src = m.triangles[mesh.face_source.get(f) as usize];
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
            let src = m.triangles[mesh.face_source.get(f) as usize];
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

    /// Every writer round-trips any built mesh bit for bit (positions in the writer's frame,
    /// normals, UVs, faces),
    /// but for what glTF requires of a GLB's normals: unit length, so ones off by more than
    /// 0.1 % come back scaled to it, in the same direction.
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
            if back.origin == out.origin || name != "m.obj" {
                // A small mesh far out (a 1 mm triangle at 617) comes back relative to its
                // centre (`mesh/origin.rs`): moved back to the writer's frame, the same bits.
                let positions = dynlod::mesh::origin::rebased(&back.positions, back.origin, out.origin);
                prop_assert_eq!(&positions[..], &out.positions[..], "{}", name);
            } else {
                // OBJ text holds the shortest decimal that reads back as the f32 (880.2034 for
                // 880.20339966); read far out in f64, the decimal itself comes back, within
                // half an f32 step at that distance of the f32 it was written from.
                for (b, o) in back.positions.iter().zip(&out.positions) {
                    for k in 0..3 {
                        let (read, written) = (back.origin[k] + f64::from(b[k]), f64::from(o[k]));
                        let step = f64::from(o[k].abs().max(f32::MIN_POSITIVE)) * f64::from(f32::EPSILON);
                        prop_assert!((read - written).abs() <= step, "{} read as {}", written, read);
                    }
                }
            }
            prop_assert_eq!(&back.uvs, &out.uvs, "{}", name);
            prop_assert_eq!(&back.triangles, &out.triangles, "{}", name);
            if name != "m.glb" {
                prop_assert_eq!(&back.normals, &out.normals, "{}", name);
                continue;
            }
            for (b, o) in back.normals.iter().zip(&out.normals) {
                let length = o.iter().map(|c| c * c).sum::<f32>().sqrt();
                if (length - 1.0).abs() <= 1e-3 {
                    prop_assert_eq!(b, o);
                } else {
                    prop_assert!((0..3).all(|k| (b[k] - o[k] / length).abs() <= 1e-6), "{:?} from {:?}", b, o);
                }
            }
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

/// Checks that `b` is `a` renumbered: faces matched through `face_source` (corner for corner,
/// same winding), one vertex bijection consistent with every face, and everything per
/// vertex, face, half-edge and wedge carried across it.
fn same_up_to_numbering(a: &Mesh, b: &Mesh) -> Result<(), TestCaseError> {
    let (ta, tb) = (&a.topology, &b.topology);
    prop_assert_eq!(ta.faces.len(), tb.faces.len());
    prop_assert_eq!(ta.vertex_count(), tb.vertex_count());
    let mut face_of_source = std::collections::HashMap::new();
    for (f, s) in a.face_source.iter().enumerate() {
        prop_assert!(face_of_source.insert(s, f).is_none(), "face source {} twice", s);
    }
    let mut vmap = vec![u32::MAX; ta.vertex_count()]; // b's vertex -> a's
    let mut fmap = vec![0usize; tb.faces.len()]; // b's face -> a's
    for (fb, s) in b.face_source.iter().enumerate() {
        let fa = face_of_source[&s];
        fmap[fb] = fa;
        prop_assert_eq!(a.primitive_of(fa), b.primitive_of(fb));
        for k in 0..3 {
            let (va, vb) = (ta.faces[fa][k], tb.faces[fb][k]);
            prop_assert!(vmap[vb as usize] == u32::MAX || vmap[vb as usize] == va, "vertex {} maps twice", vb);
            vmap[vb as usize] = va;
            let (ca, cb) = (a.corner_wedge((3 * fa + k) as u32) as usize, b.corner_wedge((3 * fb + k) as u32) as usize);
            prop_assert_eq!(a.wedges.normals.get(ca), b.wedges.normals.get(cb));
            prop_assert_eq!(a.wedges.uvs.get(ca), b.wedges.uvs.get(cb));
            prop_assert_eq!(a.wedges.vertex_of(ca as u32), va);
            prop_assert_eq!(b.wedges.vertex_of(cb as u32), vb);
        }
    }
    let mut seen = vec![false; ta.vertex_count()];
    for (vb, &va) in vmap.iter().enumerate() {
        prop_assert!(va != u32::MAX && !std::mem::replace(&mut seen[va as usize], true), "not a bijection");
        let va = va as usize;
        prop_assert_eq!(a.positions[va], b.positions[vb]);
        prop_assert_eq!(a.vertex_source.get(va), b.vertex_source.get(vb));
        prop_assert_eq!(ta.vflags[va], tb.vflags[vb]);
    }
    let he = |h: u32| if h == u32::MAX { h } else { 3 * fmap[(h / 3) as usize] as u32 + h % 3 };
    for (h, &t) in tb.twin.iter().enumerate() {
        prop_assert_eq!(ta.twin[he(h as u32) as usize], he(t));
    }
    for (vb, &h) in tb.vertex_he.iter().enumerate() {
        prop_assert_eq!(ta.vertex_he[vmap[vb] as usize], he(h));
    }
    prop_assert_eq!(&a.repairs, &b.repairs);
    prop_assert_eq!(a.to_indexed().triangles.len(), b.to_indexed().triangles.len());
    Ok(())
}

/// Soups split into two primitives by a random mask, so primitive borders are common.
fn soup_with_primitives() -> impl Strategy<Value = IndexedMesh> {
    (soup(), any::<u64>()).prop_map(|(mut m, bits)| {
        m.triangle_primitive = (0..m.triangles.len()).map(|t| (bits >> (t % 64) & 1) as u32).collect();
        m.primitives = vec![Default::default(), Default::default()];
        m
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: common::cases(256), ..ProptestConfig::default() })]

    /// Spatial order renumbers and nothing else, on any input that builds (repairs included).
    #[test]
    fn spatial_order_only_renumbers(m in prop_oneof![soup_with_primitives(), valid_mesh().prop_map(|(m, _)| m)]) {
        let plain = Mesh::build(&m, BuildOptions::default());
        let ordered = Mesh::build(&m, BuildOptions::default().spatial_order(true));
        match (plain, ordered) {
            (Ok(a), Ok(b)) => {
                prop_assert_eq!(b.topology.validate(), Ok(()));
                // The same counts; components listed in the order they are met.
                let (mut sa, mut sb) = (a.topology.stats(), b.topology.stats());
                for s in [&mut sa, &mut sb] {
                    s.components.sort_by_key(|c| format!("{c:?}"));
                }
                prop_assert_eq!(sa, sb);
                same_up_to_numbering(&a, &b)?;
                prop_assert_eq!(Mesh::build(&m, BuildOptions::default().spatial_order(true)).unwrap(), b);
            }
            (Err(a), Err(b)) => prop_assert_eq!(a.to_string(), b.to_string()),
            (a, b) => prop_assert!(false, "plain {:?} vs ordered {:?}", a.is_ok(), b.is_ok()),
        }
    }
}

/// On a scan in scrambled order, spatial order brings each edge's two ends close in memory:
/// the median id distance across an edge falls from about n/3 to under 1 % of n.
#[test]
fn spatial_order_makes_edges_short_in_memory() {
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/bun_zipper.ply.gz");
    let scrambled = shuffle(dynlod::io::load(bunny).unwrap(), 7);
    let median_span = |m: &Mesh| {
        let mut spans: Vec<u32> =
            m.topology.faces.iter().flat_map(|f| (0..3).map(|k| f[k].abs_diff(f[(k + 1) % 3]))).collect();
        spans.sort_unstable();
        (spans[spans.len() / 2], m.positions.len() as u32)
    };
    let (before, n) = median_span(&Mesh::build(&scrambled, BuildOptions::default()).unwrap());
    let (after, _) = median_span(&Mesh::build(&scrambled, BuildOptions::default().spatial_order(true)).unwrap());
    assert!(before > n / 5, "scrambled: median span {before} of {n}");
    assert!(after < n / 100, "ordered: median span {after} of {n}");
}
