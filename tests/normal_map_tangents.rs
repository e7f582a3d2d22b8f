//! Tangents made for normal maps where the file has none (`io/normal_map_tangents.rs`):
//! MikkTSpace's frames, as the reference implementation makes them, split where a mirrored
//! UV island's handedness turns, and carried through simplification to GLB output.

mod common;

use dynlod::io::{self, Format};
use dynlod::{BuildOptions, IndexedMesh, Mesh};

/// A UV sphere as an OBJ with normals and a texture mirrored across its middle (u runs
/// 1 → 0 → 1 around it, as a symmetric character's map is laid out), its material naming a
/// normal map with `norm`.
fn mirrored_sphere(dir: &std::path::Path) -> (IndexedMesh, usize) {
    let (stacks, slices) = (12, 24);
    let mut obj = String::from("mtllib s.mtl\nusemtl skin\n");
    for i in 0..=stacks {
        let theta = std::f64::consts::PI * i as f64 / stacks as f64;
        for j in 0..=slices {
            let phi = std::f64::consts::TAU * j as f64 / slices as f64;
            let n = [theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()];
            obj += &format!("v {} {} {}\nvn {} {} {}\n", n[0], n[1], n[2], n[0], n[1], n[2]);
            let u = (2.0 * j as f64 / slices as f64 - 1.0).abs();
            obj += &format!("vt {u} {}\n", 1.0 - i as f64 / stacks as f64);
        }
    }
    let at = |i: usize, j: usize| i * (slices + 1) + j + 1;
    for i in 0..stacks {
        for j in 0..slices {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if i != 0 {
                obj += &format!("f {a}/{a}/{a} {d}/{d}/{d} {b}/{b}/{b}\n");
            }
            if i != stacks - 1 {
                obj += &format!("f {d}/{d}/{d} {c}/{c}/{c} {b}/{b}/{b}\n");
            }
        }
    }
    std::fs::write(dir.join("s.obj"), obj).unwrap();
    std::fs::write(dir.join("s.mtl"), "newmtl skin\nKd 1 1 1\nnorm skin_normal.png\n").unwrap();
    image::RgbImage::from_pixel(4, 4, image::Rgb([128, 128, 255])).save(dir.join("skin_normal.png")).unwrap();
    let vertices = (stacks + 1) * (slices + 1);
    (io::load(dir.join("s.obj")).unwrap(), vertices)
}

/// Every corner's frame is the reference MikkTSpace's (within float rounding, and its
/// handedness exactly), both handedness values occur, and the vertices on the mirror line
/// were split, since their corners on either side disagree.
#[test]
fn frames_are_the_reference_mikktspace_split_at_the_mirror() {
    let dir = tempfile::tempdir().unwrap();
    let (m, vertices) = mirrored_sphere(dir.path());
    let tangent = m.attributes.iter().find(|a| a.semantic == "TANGENT").expect("tangents made");
    assert!(tangent.absent.is_empty());
    let (compared, none, worst, handedness) = common::mikktspace::against_reference(&m, 0);
    assert_eq!((compared, none), (3 * m.triangles.len(), 0));
    assert!(worst < 0.05, "{worst}°");
    assert_eq!(handedness, 0);
    let signs: Vec<f32> = (0..m.positions.len()).map(|v| tangent.get(v)[3]).collect();
    assert!(signs.contains(&1.0) && signs.contains(&-1.0), "the mirror turns the handedness");
    assert!(m.positions.len() > vertices, "{} vertices, {vertices} in the file", m.positions.len());
}

/// Simplified, the mesh keeps the frames of the vertices that survive, and a GLB written
/// from it holds them: TANGENT on the primitive, unit vectors with a handedness of ±1.
#[test]
fn frames_ride_through_simplification_to_glb() {
    let dir = tempfile::tempdir().unwrap();
    let (m, _) = mirrored_sphere(dir.path());
    let full = m.attributes.iter().find(|a| a.semantic == "TANGENT").unwrap();
    let mut mesh = Mesh::build(&m, BuildOptions::default()).unwrap();
    let target = m.triangles.len() * 3 / 10;
    dynlod::simplify::simplify(&mut mesh, dynlod::simplify::SimplifyOptions::default().target_triangles(target));
    let out = mesh.to_indexed();
    assert!(out.triangles.len() < m.triangles.len() / 2);
    let kept = out.attributes.iter().find(|a| a.semantic == "TANGENT").expect("TANGENT kept");
    // Each surviving vertex's frame is one the full mesh had at that position.
    for v in 0..out.positions.len() {
        let had = (0..m.positions.len()).any(|w| m.positions[w] == out.positions[v] && full.get(w) == kept.get(v));
        assert!(had, "vertex {v}: {:?}", kept.get(v));
    }
    let glb = dir.path().join("lod.glb");
    io::save(&glb, &out).unwrap();
    let bytes = std::fs::read(&glb).unwrap();
    let back = io::load_bytes(&bytes, Format::Glb, None).unwrap();
    let t = back.attributes.iter().find(|a| a.semantic == "TANGENT").expect("TANGENT in the GLB");
    for v in 0..back.positions.len() {
        let f = t.get(v);
        let length = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        assert!((length - 1.0).abs() < 1e-3 && f[3].abs() == 1.0, "{f:?}");
    }
}
