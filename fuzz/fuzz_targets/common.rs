//! What the targets that run the algorithms share: the input split into control bytes and a
//! file (GLB when it starts with glTF's magic, Obj text otherwise), loaded without the panic
//! guard and built, small enough to keep executions short; and the check that what the
//! algorithms leave can be written in that format and read back as it was.

use dynlod::io::{self, Format};
use dynlod::mesh::IndexedMesh;

/// Most triangles a target runs on: the algorithms' cost is not what is fuzzed.
const MAX_FACES: usize = 3000;

/// `data`'s first `n` bytes (the target's controls; bit 0 of the first asks for spatial
/// order), the format of the rest and the mesh it builds, or `None` where there is nothing to
/// run on.
pub fn controls_and_mesh(data: &[u8], n: usize) -> Option<(&[u8], Format, dynlod::Mesh)> {
    if data.len() < n {
        return None;
    }
    let (ctl, file) = data.split_at(n);
    let format = if file.starts_with(b"glTF") { Format::Glb } else { Format::Obj };
    let m = io::load_bytes_unguarded(file, format, None).ok()?;
    let mesh = dynlod::Mesh::build(&m, dynlod::BuildOptions::default().spatial_order(ctl[0] & 1 != 0)).ok()?;
    let faces = mesh.topology.live_face_count();
    (faces > 0 && faces <= MAX_FACES).then_some((ctl, format, mesh))
}

/// Writes `mesh` as `format` (Obj or GLB), reads it back and checks that every triangle
/// comes back with the same corners (position, and normal, UV and further attributes where
/// its primitive has them and the format holds them, bit for bit) and, in a GLB, the same
/// material, then that the file
/// builds to a mesh of the same shape (Euler characteristic, border loops, triangles).
///
/// The shape is not compared where the built mesh has two vertices at one position: a
/// repair cut the input apart there, or two of the file's vertices (in separate glTF
/// primitives, say) welded into a pinch that building split again. The file keeps such
/// copies as separate vertices, but building it welds them by position, and once the
/// neighbourhoods have been simplified the weld can join an edge where there was a point. The
/// file itself is checked all the same.
pub fn round_trip(mesh: &dynlod::Mesh, format: Format, what: &str) {
    let out = mesh.to_indexed();
    let mut file = Vec::new();
    match format {
        Format::Glb => io::write_glb(&mut file, &out),
        _ => io::write_obj(&mut file, &out),
    }
    .unwrap_or_else(|e| panic!("{what}: the writer refused the mesh: {e}"));
    let back = io::load_bytes_unguarded(&file, format, None)
        .unwrap_or_else(|e| panic!("{what}: what the writer wrote does not load: {e}"));
    assert_eq!(back.triangles.len(), out.triangles.len(), "{what}: triangle count");
    let primitive =
        |m: &IndexedMesh, t: usize| m.primitives.get(m.primitive_of(t) as usize).cloned().unwrap_or_default();
    // A corner's normal and UV, `None` where its primitive has none (flagged, or none in the
    // mesh): a file whose only primitive left lacks normals has no normals at all.
    let corner = |m: &IndexedMesh, t: usize, c: usize| {
        let (p, i) = (primitive(m, t), m.triangles[t][c] as usize);
        let normal = m.normals.get(i).copied().filter(|_| !p.no_normals);
        // A GLB holds unit normals (see `unit`).
        let normal = if format == Format::Glb { normal.map(unit) } else { normal };
        (normal, m.uvs.get(i).copied().filter(|_| !p.no_uvs))
    };
    // Positions in the file's coordinates: bit for bit where both meshes lie relative to the
    // same origin (every mesh near its own), else within an f32 step of each side's relative
    // value (`mesh/origin.rs`: a reader picks the origin from the bounds it reads, and OBJ
    // text read in f64 far out gives the decimal back, not the f32 it was printed from).
    let positions = |t: usize, s: usize, c: usize| {
        (back.positions[back.triangles[t][c] as usize], out.positions[out.triangles[s][c] as usize])
    };
    let same_position = |t: usize, s: usize, c: usize| {
        let (p, q) = positions(t, s, c);
        if back.origin == out.origin {
            return p.map(f32::to_bits) == q.map(f32::to_bits);
        }
        (0..3).all(|k| {
            let (read, written) = (back.origin[k] + f64::from(p[k]), out.origin[k] + f64::from(q[k]));
            let steps = f64::from(p[k].abs() + q[k].abs()) * f64::from(f32::EPSILON);
            (read - written).abs() <= steps + f64::from(f32::MIN_POSITIVE)
        })
    };
    // Further attributes where the written triangle's primitive has them: all of them in a
    // GLB, the colour's RGB in an Obj (the format holds nothing else).
    let further = |t: usize, c: usize, s: usize| {
        let (i, j) = (back.triangles[t][c] as usize, out.triangles[s][c] as usize);
        for a in out.attributes.iter().filter(|a| a.present_in(out.primitive_of(s))) {
            let held = if format == Format::Glb { a.components } else { 3 };
            if format != Format::Glb && a.semantic != "COLOR_0" {
                continue;
            }
            let b = back.attributes.iter().find(|b| b.semantic == a.semantic);
            let b = b.unwrap_or_else(|| panic!("{what}: {} not written", a.semantic));
            assert!(b.present_in(back.primitive_of(t)), "{what}: triangle {t} lost {}", a.semantic);
            let bits = |v: &[f32]| v[..held].iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let mut expected = a.get(j).to_vec();
            if format == Format::Glb && a.semantic == "TANGENT" {
                // Unit, with a handedness of ±1 (see `unit`).
                let xyz = unit([expected[0], expected[1], expected[2]]);
                expected[..3].copy_from_slice(&xyz);
                expected[3] = if expected[3] < 0.0 { -1.0 } else { 1.0 };
            }
            assert_eq!(bits(b.get(i)), bits(&expected), "{what}: triangle {t} corner {c}'s {}", a.semantic);
        }
    };
    // The GLB writer groups the triangles by primitive, in order; Obj keeps their order.
    let mut written: Vec<usize> = (0..out.triangles.len()).collect();
    if format == Format::Glb {
        written.sort_by_key(|&t| out.primitive_of(t));
    }
    for (t, &s) in written.iter().enumerate() {
        if format == Format::Glb {
            assert_eq!(primitive(&back, t).material, primitive(&out, s).material, "{what}: triangle {t}'s material");
        }
        for c in 0..3 {
            assert!(
                same_position(t, s, c),
                "{what}: triangle {t} corner {c}'s position: read {:?} + {:?}, written {:?} + {:?}",
                positions(t, s, c).0,
                back.origin,
                positions(t, s, c).1,
                out.origin
            );
            assert_eq!(corner(&back, t, c), corner(&out, s, c), "{what}: triangle {t} corner {c}");
            further(t, c, s);
        }
    }
    // Building welds by position; a mesh with two vertices at one position may rebuild
    // otherwise (see above).
    let mut seen = std::collections::HashSet::new();
    let cut = mesh.positions.iter().any(|p| !seen.insert(p.map(|c| (c + 0.0).to_bits())));
    if cut {
        return;
    }
    let again = dynlod::Mesh::build(&back, dynlod::BuildOptions::default())
        .unwrap_or_else(|e| panic!("{what}: what the writer wrote does not build: {e}"));
    let (s, r) = (mesh.topology.stats(), again.topology.stats());
    assert_eq!(
        (r.euler, r.boundary_loops, again.topology.live_face_count()),
        (s.euler, s.boundary_loops, mesh.topology.live_face_count()),
        "{what}: the written file builds to another shape"
    );
}

/// What the GLB writer makes of a normal or tangent: glTF requires unit length, so one off by
/// more than 0.1 % is scaled to it; others are kept bit for bit (zero included).
fn unit(n: [f32; 3]) -> [f32; 3] {
    // In f64: the squares of a tiny f32 vector's components (1e-22) are subnormal or zero in
    // f32, and a length computed from them is not its length.
    let length = n.iter().map(|&c| f64::from(c).powi(2)).sum::<f64>().sqrt();
    if length > 0.0 && (length - 1.0).abs() > 1e-3 {
        n.map(|c| (f64::from(c) / length) as f32)
    } else {
        n
    }
}
