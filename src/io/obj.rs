//! Wavefront OBJ through `tobj`: polygons triangulated, one index per vertex (positions are
//! split where normals/UVs differ; welding joins them again), each object a primitive.

use std::io::BufReader;

use crate::error::LoadErrorKind;
use crate::mesh::{IndexedMesh, NotKept, NotKeptKind, Primitive};

pub(super) fn load(bytes: &[u8]) -> Result<IndexedMesh, LoadErrorKind> {
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    let mut reader = BufReader::new(bytes);
    let (models, _materials) =
        tobj::load_obj_buf(&mut reader, &opts, |_| Err(tobj::LoadError::GenericFailure)).map_err(|e| {
            LoadErrorKind::Malformed { format: "OBJ", line: locate_error(bytes, e), message: e.to_string() }
        })?;
    // An attribute some objects lack is kept for the others: the objects without it hold
    // zeros and are flagged, so the writers leave it out of them as the source did.
    let has_normals = |m: &tobj::Mesh| !m.normals.is_empty() && m.normals.len() == m.positions.len();
    let has_uvs = |m: &tobj::Mesh| !m.texcoords.is_empty() && 3 * m.texcoords.len() == 2 * m.positions.len();
    let any_normals = models.iter().any(|m| has_normals(&m.mesh));
    let any_uvs = models.iter().any(|m| has_uvs(&m.mesh));
    let mut out = IndexedMesh::default();
    for (pi, m) in models.iter().enumerate() {
        let base = out.positions.len() as u32;
        let mesh = &m.mesh;
        let n = mesh.positions.len() / 3;
        out.positions.extend(mesh.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        let (no_normals, no_uvs) = (any_normals && !has_normals(mesh), any_uvs && !has_uvs(mesh));
        if no_normals {
            out.normals.resize(out.normals.len() + n, [0.0; 3]);
        } else if any_normals {
            out.normals.extend(mesh.normals.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        }
        if no_uvs {
            out.uvs.resize(out.uvs.len() + n, [0.0; 2]);
        } else if any_uvs {
            out.uvs.extend(mesh.texcoords.chunks_exact(2).map(|p| [p[0], p[1]]));
        }
        for t in mesh.indices.chunks_exact(3) {
            out.triangles.push([t[0] + base, t[1] + base, t[2] + base]);
            out.triangle_primitive.push(pi as u32);
        }
        out.primitives.push(Primitive { name: m.name.clone(), material: mesh.material_id, no_normals, no_uvs });
    }
    if out.primitives.len() <= 1 {
        out.triangle_primitive.clear();
    }
    let coloured = models.iter().filter(|m| !m.mesh.vertex_color.is_empty()).count();
    if coloured > 0 {
        out.not_kept.push(NotKept::new(NotKeptKind::OtherAttributes, coloured, "vertex colours"));
    }
    // Materials are not read (no file beside the source is opened for them); say so.
    let libraries = String::from_utf8_lossy(bytes).lines().filter(|l| l.trim_start().starts_with("mtllib")).count();
    if libraries > 0 {
        out.not_kept.push(NotKept::new(NotKeptKind::Materials, libraries, String::new()));
    }
    Ok(out)
}

/// tobj does not say where it failed; find the first line that explains the error kind.
fn locate_error(bytes: &[u8], e: tobj::LoadError) -> Option<usize> {
    use tobj::LoadError as E;
    let text = String::from_utf8_lossy(bytes);
    let mut counts = [0i64; 3]; // v, vt, vn seen so far
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        let nums = || words.clone().map(|w| w.parse::<f64>());
        let bad_nums = |need: usize| nums().take(need).filter(|r| r.is_ok()).count() < need;
        match key {
            "v" if matches!(e, E::PositionParseError) && bad_nums(3) => return Some(i + 1),
            "vn" if matches!(e, E::NormalParseError) && bad_nums(3) => return Some(i + 1),
            "vt" if matches!(e, E::TexcoordParseError) && bad_nums(1) => return Some(i + 1),
            "v" => counts[0] += 1,
            "vt" => counts[1] += 1,
            "vn" => counts[2] += 1,
            "f" => {
                for w in words.clone() {
                    for (k, part) in w.split('/').enumerate().take(3) {
                        if part.is_empty() {
                            continue;
                        }
                        let Ok(idx) = part.parse::<i64>() else {
                            if matches!(e, E::FaceParseError) {
                                return Some(i + 1);
                            }
                            continue;
                        };
                        let n = counts[[0, 1, 2][k]];
                        let ok = (idx > 0 && idx <= n) || (idx < 0 && -idx <= n);
                        let kind_matches = matches!(
                            (k, e),
                            (0, E::FaceVertexOutOfBounds)
                                | (1, E::FaceTexCoordOutOfBounds)
                                | (2, E::FaceNormalOutOfBounds)
                        );
                        if !ok && kind_matches {
                            return Some(i + 1);
                        }
                    }
                }
            }
            _ => {}
        }
    }
    None
}
