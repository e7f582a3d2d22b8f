//! Polygon faces in OBJ, PLY and OFF: concave ones are triangulated without folding, ones
//! that cross themselves are fanned and reported (`src/io/polygon.rs`); what is not a face
//! (OBJ points and lines, faces of fewer than three corners) is skipped and reported, and OBJ
//! free-form geometry is listed or refused.

use dynlod::io::{self, Format};
use dynlod::mesh::{Location, RepairKind};
use dynlod::{BuildOptions, IndexedMesh, Mesh};
use glam::Vec3;

/// An L-shaped prism of height 1 over the L of area 3. Its top cap is written from corner
/// (1, 2), from which a fan folds: one triangle turns down, another covers the L's notch.
const L: [[f32; 2]; 6] = [[1.0, 2.0], [0.0, 2.0], [0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]];

fn prism_faces() -> Vec<Vec<usize>> {
    let mut faces = vec![(0..6).rev().collect(), (6..12).collect()];
    faces.extend((0..6).map(|i| vec![i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6]));
    faces
}

fn prism_points() -> Vec<[f32; 3]> {
    (0..2).flat_map(|z| L.iter().map(move |p| [p[0], p[1], z as f32])).collect()
}

fn obj(points: &[[f32; 3]], faces: &[Vec<usize>]) -> String {
    let mut s: String = points.iter().map(|p| format!("v {} {} {}\n", p[0], p[1], p[2])).collect();
    for f in faces {
        let corners: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        s += &format!("f {}\n", corners.join(" "));
    }
    s
}

fn off(points: &[[f32; 3]], faces: &[Vec<usize>]) -> String {
    let mut s = format!("OFF\n{} {} 0\n", points.len(), faces.len());
    s.extend(points.iter().map(|p| format!("{} {} {}\n", p[0], p[1], p[2])));
    for f in faces {
        let corners: Vec<String> = f.iter().map(|i| i.to_string()).collect();
        s += &format!("{} {}\n", f.len(), corners.join(" "));
    }
    s
}

fn ply(points: &[[f32; 3]], faces: &[Vec<usize>]) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        points.len(),
        faces.len()
    );
    // The OFF body less its two header lines.
    s.extend(off(points, faces).lines().skip(2).map(|l| format!("{l}\n")));
    s
}

fn each_format(points: &[[f32; 3]], faces: &[Vec<usize>]) -> Vec<(Format, IndexedMesh)> {
    [(Format::Obj, obj(points, faces)), (Format::Off, off(points, faces)), (Format::Ply, ply(points, faces))]
        .into_iter()
        .map(|(f, text)| (f, io::load_bytes(text.as_bytes(), f, None).unwrap_or_else(|e| panic!("{f:?}: {e}"))))
        .collect()
}

fn normal(m: &IndexedMesh, t: [u32; 3]) -> Vec3 {
    let [a, b, c] = t.map(|i| Vec3::from(m.positions[i as usize]));
    (b - a).cross(c - a) / 2.0
}

#[test]
fn concave_faces_read_without_folding_in_every_polygon_format() {
    for (format, m) in each_format(&prism_points(), &prism_faces()) {
        // 4 + 4 cap triangles and 2 for each of the 6 sides; no repair needed.
        assert_eq!(m.triangles.len(), 20, "{format:?}");
        assert!(m.load_repairs.is_empty(), "{format:?}: {:?}", m.load_repairs);
        for (cap, z, up) in [("bottom", 0.0, -1.0), ("top", 1.0, 1.0)] {
            let tris: Vec<_> =
                m.triangles.iter().filter(|t| t.iter().all(|&i| m.positions[i as usize][2] == z)).collect();
            assert_eq!(tris.len(), 4, "{format:?} {cap}");
            for &&t in &tris {
                let n = normal(&m, t);
                assert!(n.z * up > 0.0, "{format:?}: {cap} triangle {t:?} turns against its face ({n})");
            }
            // Covering the L and nothing else: the triangles' areas add up to its 3.
            let area: f32 = tris.iter().map(|&&t| normal(&m, t).length()).sum();
            assert!((area - 3.0).abs() < 1e-5, "{format:?} {cap}: area {area}");
        }
        let mesh = Mesh::build(&m, BuildOptions::default().strict(true)).unwrap();
        mesh.topology.validate().unwrap();
    }
}

#[test]
fn convex_faces_keep_the_fan_from_their_first_corner() {
    let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.5, 1.0, 0.0], [0.5, 1.5, 0.0], [-0.5, 1.0, 0.0]];
    for (format, m) in each_format(&points, &[vec![0, 1, 2, 3, 4]]) {
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]], "{format:?}");
    }
}

#[test]
fn faces_that_cross_themselves_are_fanned_and_reported() {
    // A pentagram (face 1) after a triangle (face 0): no triangulation of its corners covers
    // it without folding, so it keeps the fan and the file's face number is reported.
    let mut points: Vec<[f32; 3]> = (0..5)
        .map(|i| {
            let a = std::f32::consts::TAU * (2 * i) as f32 / 5.0;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    points.extend([[3.0, 0.0, 0.0], [4.0, 0.0, 0.0], [3.0, 1.0, 0.0]]);
    let faces = [vec![5, 6, 7], vec![0, 1, 2, 3, 4]];
    for (format, m) in each_format(&points, &faces) {
        assert_eq!(m.triangles.len(), 4, "{format:?}");
        // (OBJ numbers vertices in order of first use: compared by position.)
        let fan: Vec<_> = m.triangles[1..].iter().map(|t| t.map(|i| m.positions[i as usize])).collect();
        let expected: Vec<_> = [[0, 1, 2], [0, 2, 3], [0, 3, 4]].iter().map(|t| t.map(|i| points[i])).collect();
        assert_eq!(fan, expected, "{format:?}");
        let r = m.load_repairs.iter().find(|r| r.kind == RepairKind::FannedSelfCrossingPolygons);
        let r = r.unwrap_or_else(|| panic!("{format:?}: not reported: {:?}", m.load_repairs));
        // OBJ numbers its faces nowhere: its line (8 vertices, the triangle, then it).
        let at = if format == Format::Obj { Location::Line(10) } else { Location::Face(1) };
        assert_eq!((r.count, &r.examples), (1, &vec![at]), "{format:?}");
        assert!(r.to_string().contains("cross themselves"), "{r}");
        // Strict mode refuses it.
        assert!(Mesh::build(&m, BuildOptions::default().strict(true)).is_err(), "{format:?}");
    }
    // Its line after objects, a material, a polyline and a short face (blanked before tobj)
    // and a second pentagram in another object.
    let head = obj(&points, &[]);
    let text = format!("{head}o a\nf 6 7 8\nl 1 2\nf 1 2\nusemtl m\nf 1 2 3 4 5\n# c\no b\nf 1 2 3 4 5\n");
    let m = io::load_bytes(text.as_bytes(), Format::Obj, None).unwrap();
    let r = m.load_repairs.iter().find(|r| r.kind == RepairKind::FannedSelfCrossingPolygons).unwrap();
    assert_eq!(r.examples, [Location::Line(14), Location::Line(17)]);
}

/// A ring written as one polygon, its hole reached by a bridge walked both ways (as
/// LightWave exports one: assimp's `concave_polygon.obj`, 66 corners). A fan folds it onto
/// itself; read, it is the ring: an annulus with two borders, every triangle facing up, its
/// area the ring's.
#[test]
fn a_ring_written_as_one_polygon_with_a_bridge_reads_as_the_ring() {
    let circle = |n: usize, r: f32| -> Vec<[f32; 3]> {
        (0..n)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / n as f32;
                [r * a.cos(), r * a.sin(), 0.0]
            })
            .collect()
    };
    let mut points = circle(16, 2.0);
    points.extend(circle(8, 1.0));
    // Around the outside, across the bridge, around the hole the other way, and back.
    let mut face: Vec<usize> = (0..16).chain([0, 16]).collect();
    face.extend((17..24).rev());
    face.push(16);
    let polygon: f32 = (0..face.len())
        .map(|i| {
            let (a, b) = (points[face[i]], points[face[(i + 1) % face.len()]]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f32>()
        / 2.0;
    for (format, m) in each_format(&points, &[face.clone()]) {
        assert_eq!(m.triangles.len(), face.len() - 2, "{format:?}");
        assert!(m.load_repairs.is_empty(), "{format:?}: {:?}", m.load_repairs);
        assert!(m.triangles.iter().all(|&t| normal(&m, t).z > 0.0), "{format:?}: a triangle faces down");
        let area: f32 = m.triangles.iter().map(|&t| normal(&m, t).z).sum();
        assert!((area - polygon).abs() < 1e-5 * polygon, "{format:?}: area {area}, the ring's {polygon}");
        let mesh = Mesh::build(&m, BuildOptions::default().strict(true)).unwrap();
        mesh.topology.validate().unwrap();
        let info = dynlod::info::MeshInfo::new(&mesh);
        assert_eq!((info.boundary_loops, info.euler), (2, 0), "{format:?}");
    }
}

/// An `f` line without corners (assimp's `invalid/malformed2.obj` has one before a cube's
/// five quads) is skipped and reported at its line, as PLY and OFF faces of fewer than three
/// corners are at theirs.
#[test]
fn an_obj_face_without_corners_is_skipped_and_reported() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf\nf 1 2 3 4\n";
    let m = io::load_bytes(obj.as_bytes(), Format::Obj, None).unwrap();
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    let r = &m.load_repairs[..];
    assert_eq!(r.len(), 1, "{r:?}");
    assert_eq!(
        (r[0].kind, r[0].count, &r[0].examples),
        (RepairKind::SkippedNonTrianglePrimitives, 1, &vec![Location::Line(5)])
    );
}

/// OBJ points (`p`) and lines (`l`) are not surfaces. tobj read a polyline of three or more
/// corners as a polygon face (assimp's `testline.obj`, a wireframe cube of six closed `l`
/// polylines, loaded as a solid cube) and dropped the rest without a word; every one is now
/// skipped and reported at its line, and a file of nothing else is refused by name.
#[test]
fn obj_points_and_lines_are_skipped_and_reported_not_read_as_faces() {
    let head = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\n";
    let obj = format!("{head}f 1 2 3\nl 1 2 3 4 5\np 5\nf 1 2\nl 3 4\n");
    let m = io::load_bytes(obj.as_bytes(), Format::Obj, None).unwrap();
    assert_eq!(m.triangles.len(), 1);
    // The polyline's far corner is no surface's: the mesh ends at the triangle.
    assert!(m.positions.iter().all(|p| p.iter().all(|&c| c <= 1.0)), "{:?}", m.positions);
    let r = &m.load_repairs[..];
    assert_eq!(r.len(), 1, "{r:?}");
    let lines = [7, 8, 9, 10].map(Location::Line).to_vec();
    assert_eq!((r[0].kind, r[0].count, &r[0].examples), (RepairKind::SkippedNonTrianglePrimitives, 4, &lines));
    assert!(r[0].to_string().contains("line 7"), "{}", r[0]);
    // Only lines: refused as such, naming the first.
    let wire = format!("{head}l 1 2 3 4 1\nl 1 5\n");
    let e = io::load_bytes(wire.as_bytes(), Format::Obj, None).unwrap_err();
    assert!(matches!(e, dynlod::LoadErrorKind::Unsupported { format: "OBJ", .. }), "{e}");
    assert!(e.to_string().contains("(2, the first at line 6)"), "{e}");
}

/// OBJ free-form curves and surfaces (`curv`, `surf`: NURBS from CAD tools) are not
/// tessellated; tobj reads past them without a word. Beside polygons they are listed as not
/// kept; alone they are refused by name and line, not as an empty mesh.
#[test]
fn obj_free_form_geometry_is_listed_or_refused() {
    let patch = "cstype bspline\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\nparm u 0 0 1 1\nparm v 0 0 1 1\nend\n";
    let curve = "cstype bezier\ndeg 3\ncurv 0 1 1 2 3 1\nparm u 0 1\nend\n";
    let v = "v -1 -1 0\nv 1 -1 0\nv -1 1 0\nv 1 1 0\n";
    let m = io::load_bytes(format!("{v}f 1 2 4 3\n{patch}{curve}{curve}").as_bytes(), Format::Obj, None).unwrap();
    assert_eq!(m.triangles.len(), 2);
    let n = m.not_kept.iter().find(|n| n.kind == dynlod::mesh::NotKeptKind::FreeFormGeometry).unwrap();
    assert_eq!((n.count, n.detail.as_str()), (3, "surf, curv"));
    let e = io::load_bytes(format!("{v}{patch}").as_bytes(), Format::Obj, None).unwrap_err();
    assert!(matches!(e, dynlod::LoadErrorKind::Unsupported { .. }), "{e}");
    assert!(e.to_string().contains("only free-form geometry (1 surf statement, the first at line 7)"), "{e}");
    let plain = io::load_bytes(format!("{v}f 1 2 4 3\n").as_bytes(), Format::Obj, None).unwrap();
    assert!(plain.not_kept.is_empty(), "{:?}", plain.not_kept);
}
