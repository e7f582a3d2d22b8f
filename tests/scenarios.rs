//! Scenario tests on tiny hand-built meshes with exact expected outcomes.

use dynlod::mesh::{Location, RepairKind};
use dynlod::procedural;
use dynlod::topology::{vflag, HalfEdges, Topology, TopologyError, INVALID};
use dynlod::{BuildError, BuildOptions, IndexedMesh, Mesh, MeshError};

fn build(m: &IndexedMesh) -> Mesh {
    let mesh = Mesh::build(m, BuildOptions::default()).expect("builds");
    mesh.topology.validate().expect("valid");
    mesh
}

fn repair(mesh: &Mesh, kind: RepairKind) -> Option<&dynlod::Repair> {
    mesh.repairs.iter().find(|r| r.kind == kind)
}

fn tri(p: &[[f32; 3]], t: &[[u32; 3]]) -> IndexedMesh {
    IndexedMesh::from_triangles(p.to_vec(), t.to_vec())
}

#[test]
fn tetrahedron_is_closed_genus_zero() {
    let mesh = build(&procedural::tetrahedron());
    let s = mesh.topology.stats();
    assert_eq!((s.vertices, s.edges, s.faces), (4, 6, 4));
    assert_eq!((s.euler, s.genus, s.boundary_edges, s.boundary_loops), (2, Some(0), 0, 0));
    assert!(mesh.repairs.is_empty());
    for v in 0..4 {
        let mut n: Vec<u32> = mesh.topology.neighbors(v).collect();
        n.sort();
        let expected: Vec<u32> = (0..4).filter(|&u| u != v).collect();
        assert_eq!(n, expected, "one-ring of {v}");
    }
}

#[test]
fn torus_has_genus_one() {
    let s = build(&procedural::torus(12, 8)).topology.stats();
    assert_eq!((s.euler, s.genus, s.components.len()), (0, Some(1), 1));
}

#[test]
fn grid_is_a_disk_with_one_border_loop() {
    let mesh = build(&procedural::grid(4, 3, |i, j| (i + j) % 2 == 0));
    let s = mesh.topology.stats();
    assert_eq!((s.vertices, s.faces, s.boundary_edges, s.boundary_loops, s.genus), (20, 24, 14, 1, Some(0)));
    // Border vertex 0 (corner): neighbours run counter-clockwise from its outgoing border edge.
    assert!(mesh.topology.is_boundary_vertex(0));
    let h = mesh.topology.vertex_he[0];
    assert_eq!(mesh.topology.twin[h as usize], INVALID);
    // Interior vertex 6 = (1,1): six or four neighbours depending on diagonals, all distinct.
    let n: Vec<u32> = mesh.topology.neighbors(6).collect();
    let mut d = n.clone();
    d.sort();
    d.dedup();
    assert_eq!(n.len(), d.len());
    assert!(!mesh.topology.is_boundary_vertex(6));
}

#[test]
fn single_triangle_has_one_border_loop_of_three() {
    let mesh = build(&tri(&[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], &[[0, 1, 2]]));
    let s = mesh.topology.stats();
    assert_eq!((s.boundary_edges, s.boundary_loops, s.euler, s.genus), (3, 1, 1, Some(0)));
    assert!((0..3).all(|v| mesh.topology.vflags[v] & vflag::BOUNDARY != 0));
}

#[test]
fn bowtie_vertex_is_split_into_one_vertex_per_fan() {
    // Two triangles touching only at vertex 0.
    let p = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [-1., 0., 0.], [-1., -1., 0.]];
    let mesh = build(&tri(&p, &[[0, 1, 2], [0, 3, 4]]));
    assert_eq!(mesh.positions.len(), 6);
    assert_eq!(mesh.topology.stats().components.len(), 2);
    let r = repair(&mesh, RepairKind::SplitNonManifoldVertices).expect("split recorded");
    assert_eq!((r.count, r.examples.clone()), (1, vec![Location::Vertex(0)]));
    assert_eq!(mesh.defects.non_manifold_vertices, 1);
    // Both copies sit where vertex 0 was.
    assert_eq!(mesh.positions[0], mesh.positions[5]);
}

#[test]
fn pinch_made_by_welding_is_undone_without_a_repair() {
    // Same as the bowtie, but the file has two separate vertex records at the pinch.
    let p = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 0., 0.], [-1., 0., 0.], [-1., -1., 0.]];
    let mesh = build(&tri(&p, &[[0, 1, 2], [3, 4, 5]]));
    assert_eq!(mesh.positions.len(), 6);
    assert!(mesh.repairs.is_empty(), "{:?}", mesh.repairs);
}

#[test]
fn inconsistent_winding_is_reoriented_by_majority() {
    // A 2x1 strip of 4 triangles, the third one wound backwards: 3 against 1.
    let p = [[0., 0., 0.], [1., 0., 0.], [2., 0., 0.], [0., 1., 0.], [1., 1., 0.], [2., 1., 0.]];
    let mesh = build(&tri(&p, &[[0, 1, 4], [0, 4, 3], [1, 5, 2], [1, 5, 4]]));
    let r = repair(&mesh, RepairKind::ReorientedFaces).expect("reoriented");
    assert_eq!(r.examples, vec![Location::Face(2)], "only face 2 is wound clockwise: {r}");
    // Every face now faces +z.
    for f in &mesh.topology.faces {
        let [a, b, c] = f.map(|v| mesh.positions[v as usize]);
        let z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert!(z > 0.0);
    }
}

#[test]
fn mobius_strip_is_cut_where_no_orientation_exists() {
    // A closed band of 8 quads whose last quad reconnects with a half twist.
    let n = 8;
    let mut p = Vec::new();
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        p.push([a.cos() * 2.0, a.sin() * 2.0, -0.5]);
        p.push([a.cos() * 2.0, a.sin() * 2.0, 0.5]);
    }
    let mut t = Vec::new();
    for i in 0..n {
        let (a, b) = (2 * i as u32, 2 * i as u32 + 1);
        let (c, d) = if i + 1 < n { (2 * (i + 1) as u32, 2 * (i + 1) as u32 + 1) } else { (1, 0) };
        t.push([a, c, d]);
        t.push([a, d, b]);
    }
    let mesh = build(&tri(&p, &t));
    assert!(repair(&mesh, RepairKind::CutNonOrientableEdges).is_some(), "{:?}", mesh.repairs);
    let s = mesh.topology.stats();
    assert_eq!(s.components.len(), 1);
    assert_eq!(s.genus, Some(0));
}

#[test]
fn fin_of_three_faces_on_one_edge_is_cut_apart() {
    // Three triangles share edge 0-1.
    let p = [[0., 0., 0.], [1., 0., 0.], [0.5, 1., 0.], [0.5, -1., 0.], [0.5, 0., 1.]];
    let mesh = build(&tri(&p, &[[0, 1, 2], [1, 0, 3], [0, 1, 4]]));
    assert_eq!(mesh.defects.non_manifold_edges, 1);
    let r = repair(&mesh, RepairKind::CutNonManifoldEdges).expect("cut recorded");
    assert_eq!(r.examples, vec![Location::Edge(0, 1)]);
    // Faces 0 and 1 pair (opposite windings); face 2 ends up on its own.
    let s = mesh.topology.stats();
    assert_eq!(s.faces, 3);
    assert_eq!(s.components.len(), 2);
}

#[test]
fn duplicate_faces_in_either_winding_are_dropped() {
    let p = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]];
    let mesh = build(&tri(&p, &[[0, 1, 2], [1, 3, 2], [2, 1, 0], [0, 1, 2]]));
    let r = repair(&mesh, RepairKind::DroppedDuplicateFaces).expect("dropped");
    assert_eq!((r.count, r.examples.clone()), (2, vec![Location::Face(2), Location::Face(3)]));
    assert_eq!(mesh.topology.live_face_count(), 2);
    assert_eq!(mesh.face_source.iter().collect::<Vec<_>>(), [0, 1]);
}

#[test]
fn degenerate_and_unreferenced_are_dropped_and_named() {
    let p = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [5., 5., 5.], [0., 0., 0.]];
    // Face 1 repeats a vertex; face 2 uses vertex 4, which welds onto vertex 0.
    let mesh = build(&tri(&p, &[[0, 1, 2], [1, 1, 2], [4, 1, 2]]));
    let d = repair(&mesh, RepairKind::DroppedDegenerateFaces).unwrap();
    assert_eq!(d.examples, vec![Location::Face(1)]);
    let dup = repair(&mesh, RepairKind::DroppedDuplicateFaces).unwrap();
    assert_eq!(dup.examples, vec![Location::Face(2)]);
    let u = repair(&mesh, RepairKind::DroppedUnreferencedVertices).unwrap();
    assert_eq!(u.examples, vec![Location::Vertex(3)]);
    assert_eq!(mesh.positions.len(), 3);
}

#[test]
fn zero_area_faces_are_kept_unless_asked() {
    // Two triangles plus a sliver with three distinct collinear vertices.
    let p = [[0., 0., 0.], [2., 0., 0.], [1., 1., 0.], [1., 0., 0.]];
    let t = [[0, 3, 2], [3, 1, 2], [0, 1, 3]];
    let kept = build(&tri(&p, &t));
    assert_eq!(kept.defects.zero_area_triangles, 1);
    assert_eq!(kept.topology.live_face_count(), 3);
    let dropped = Mesh::build(&tri(&p, &t), BuildOptions::default().drop_zero_area(true)).unwrap();
    assert_eq!(dropped.topology.live_face_count(), 2);
    assert_eq!(repair(&dropped, RepairKind::DroppedZeroAreaFaces).unwrap().examples, vec![Location::Face(2)]);
}

#[test]
fn strict_mode_turns_the_first_repair_into_an_error() {
    let p = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]];
    let m = tri(&p, &[[0, 1, 2], [0, 1, 2]]);
    match Mesh::build(&m, BuildOptions::default().strict(true)) {
        Err(BuildError::RepairNeeded(r)) => assert_eq!(r.kind, RepairKind::DroppedDuplicateFaces),
        other => panic!("expected RepairNeeded, got {other:?}"),
    }
    assert!(Mesh::build(&procedural::tetrahedron(), BuildOptions::default().strict(true)).is_ok());
}

#[test]
fn unusable_input_gets_a_typed_error_naming_the_place() {
    let p = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]];
    let e = Mesh::build(&IndexedMesh::from_triangles(p.clone(), vec![[0, 1, 2], [0, 7, 2]]), BuildOptions::default())
        .unwrap_err();
    assert!(
        matches!(e, BuildError::Mesh(MeshError::IndexOutOfRange { face: 1, corner: 1, index: 7, vertex_count: 3 })),
        "{e}"
    );
    let mut nan = p.clone();
    nan[2][1] = f32::NAN;
    let e = Mesh::build(&IndexedMesh::from_triangles(nan, vec![[0, 1, 2]]), BuildOptions::default()).unwrap_err();
    assert!(matches!(e, BuildError::Mesh(MeshError::NonFiniteCoordinate { vertex: 2, .. })), "{e}");
    let e = Mesh::build(&IndexedMesh::from_triangles(p.clone(), vec![]), BuildOptions::default()).unwrap_err();
    assert!(matches!(e, BuildError::Mesh(MeshError::NoFaces { vertices: 3 })), "{e}");
    assert!(e.to_string().contains("3 vertices and no faces (a point cloud?)"), "{e}");
    let e = Mesh::build(&IndexedMesh::from_triangles(vec![], vec![]), BuildOptions::default()).unwrap_err();
    assert!(matches!(e, BuildError::Mesh(MeshError::Empty)));
    let e = Mesh::build(&IndexedMesh::from_triangles(p.clone(), vec![[0, 0, 1]]), BuildOptions::default()).unwrap_err();
    assert!(matches!(e, BuildError::Mesh(MeshError::AllDegenerate { dropped: 1 })));
    // A primitive id past the list (an empty list is one primitive): a GLB writer would have
    // dropped those triangles without a word.
    let mut prims = IndexedMesh::from_triangles(p, vec![[0, 1, 2], [0, 2, 1]]);
    prims.triangle_primitive = vec![0, 1];
    let e = Mesh::build(&prims, BuildOptions::default()).unwrap_err();
    assert!(
        matches!(e, BuildError::Mesh(MeshError::PrimitiveOutOfRange { face: 1, primitive: 1, primitive_count: 1 })),
        "{e}"
    );
    prims.primitives = vec![Default::default(); 2];
    assert!(Mesh::build(&prims, BuildOptions::default()).is_ok());
    prims.triangle_primitive.pop();
    let e = Mesh::build(&prims, BuildOptions::default()).unwrap_err();
    assert!(matches!(e, BuildError::Mesh(MeshError::PrimitiveListLength { len: 1, triangle_count: 2 })), "{e}");
}

#[test]
fn non_finite_normals_are_zeroed_and_recorded() {
    let mut m = procedural::tetrahedron();
    m.normals = vec![[0.0, 0.0, 1.0]; 4];
    m.normals[3] = [f32::NAN, 0.0, 0.0];
    let mesh = build(&m);
    let r = repair(&mesh, RepairKind::ZeroedNonFiniteAttributes).unwrap();
    assert_eq!(r.examples, vec![Location::Vertex(3)]);
    assert!(mesh.wedges.normals.iter().all(|n| n.iter().all(|c| c.is_finite())));
}

#[test]
fn uv_seam_welds_into_one_vertex_with_two_wedges() {
    let sphere = procedural::uv_sphere(6, 8);
    let mesh = build(&sphere);
    let s = mesh.topology.stats();
    assert_eq!((s.components.len(), s.boundary_edges, s.genus), (1, 0, Some(0)), "welded sphere is closed");
    // 5 interior rings of 8 + 2 poles.
    assert_eq!(mesh.positions.len(), 5 * 8 + 2);
    assert!(mesh.wedges.len() > mesh.positions.len());
    // Seams: the meridian between the poles' rings (6 - 2 = 4 edges) and, because each pole
    // triangle has its own pole UV, all 8 edges at each pole.
    assert_eq!(mesh.seam_edges(), 4 + 2 * 8);
    let seam_vertices = (0..mesh.positions.len()).filter(|&v| mesh.topology.vflags[v] & vflag::SEAM != 0).count();
    assert_eq!(seam_vertices, 5 + 2);
}

#[test]
fn validate_reports_each_broken_invariant_with_ids() {
    let good = build(&procedural::tetrahedron()).topology;
    let mut t = good.clone();
    let real = t.twin[0];
    let wrong = (3..12).find(|&g| g != real).unwrap();
    t.twin[0] = wrong;
    assert_eq!(t.validate(), Err(TopologyError::TwinAsymmetric { he: 0, twin: wrong }));

    let mut t = good.clone();
    t.faces[0].swap(1, 2); // flip one face of a closed surface
    assert!(matches!(t.validate(), Err(TopologyError::InconsistentOrientation { .. })), "{:?}", t.validate());

    let mut t = good.clone();
    t.faces[1] = [0, 0, 1];
    assert_eq!(t.validate(), Err(TopologyError::DegenerateFace { face: 1 }));

    let mut t = good.clone();
    let v = t.origin(4);
    t.vertex_he[v as usize] = 4 + 1; // an outgoing half-edge of another vertex
    assert!(matches!(t.validate(), Err(TopologyError::VertexHalfEdge { .. })));

    let mut t = good.clone();
    t.vflags[2] |= vflag::BOUNDARY;
    assert_eq!(t.validate(), Err(TopologyError::BoundaryFlag { vertex: 2, flag: true }));

    let mut t = good;
    t.vertex_he.push(INVALID);
    t.vflags.push(0);
    assert_eq!(t.validate(), Err(TopologyError::IsolatedVertex { vertex: 4 }));
}

#[test]
fn from_faces_refuses_what_is_not_a_manifold() {
    let fin = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]];
    assert_eq!(Topology::from_faces(5, fin), Err(TopologyError::NonManifoldEdge { v0: 0, v1: 1, faces: 3 }));
    let bowtie = vec![[0, 1, 2], [0, 3, 4]];
    assert!(matches!(Topology::from_faces(5, bowtie), Err(TopologyError::NonManifoldVertex { vertex: 0, .. })));
    let flipped = vec![[0, 1, 2], [0, 1, 3]];
    assert!(matches!(
        Topology::from_faces(4, flipped),
        Err(TopologyError::InconsistentOrientation { v0: 0, v1: 1, .. })
    ));
}

#[test]
fn two_tetrahedra_sharing_a_face_become_closed_and_open_parts() {
    // trimesh's joined_tetrahedra shape: tets {0,1,2,3} and {0,1,2,4} glued on face 012.
    let p = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [0., 0., -1.]];
    let t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3], [0, 1, 2], [0, 4, 1], [1, 4, 2], [2, 4, 0]];
    let mesh = build(&tri(&p, &t));
    let s = mesh.topology.stats();
    // Face 4 repeats face 0 in the other winding.
    assert_eq!(repair(&mesh, RepairKind::DroppedDuplicateFaces).unwrap().examples, vec![Location::Face(4)]);
    assert_eq!(s.faces, 7);
    assert_eq!(mesh.defects.non_manifold_edges, 3);
    assert!(repair(&mesh, RepairKind::CutNonManifoldEdges).is_some());
    // Whatever the pairing, every component is a valid orientable surface.
    assert!(s.components.iter().all(|c| c.genus == Some(0)));
}

#[test]
fn unweld_reproduces_every_corner_attribute() {
    let sphere = procedural::uv_sphere(5, 7);
    let mesh = build(&sphere);
    let out = mesh.to_indexed();
    assert_eq!(out.triangles.len(), sphere.triangles.len());
    for (f, t) in out.triangles.iter().enumerate() {
        let src = sphere.triangles[mesh.face_source.get(f) as usize];
        for c in 0..3 {
            let (o, i) = (t[c] as usize, src[c] as usize);
            assert_eq!(out.positions[o], sphere.positions[i]);
            assert_eq!(out.normals[o], sphere.normals[i]);
            assert_eq!(out.uvs[o], sphere.uvs[i]);
        }
    }
    // One output vertex per distinct (position, normal, uv): no more than the input had.
    assert!(out.positions.len() <= sphere.positions.len());
}
