//! Wavefront OBJ through `tobj`: polygons triangulated (`polygon.rs`), one index per vertex (positions are
//! split where normals/UVs differ; welding joins them again), each object a primitive, and
//! vertex colours of the common `v x y z r g b` extension as `COLOR_0` (an alpha after them,
//! which tobj refuses, is read past: listed where it is below 1). Any text encoding
//! (`text.rs`); a `usemtl` without a name is read past; points, lines and faces of fewer
//! than three corners are skipped and reported at their lines; free-form curves and
//! surfaces are listed as not kept (refused where there is nothing else). `vt` has its
//! origin at the image's bottom-left, and turns over into glTF's (`uv_origin.rs`).

use std::borrow::Cow;
use std::io::BufReader;
use std::path::Path;

use super::polygon::Triangulator;
use crate::error::LoadErrorKind;
use crate::mesh::{IndexedMesh, Location, NotKept, NotKeptKind, Primitive, Repair, RepairKind, VertexAttribute};

pub(super) fn load(bytes: &[u8], base: Option<&Path>) -> Result<IndexedMesh, LoadErrorKind> {
    let text = super::text::utf8(bytes);
    let (text, skipped, survey) = passed_over(text.as_bytes());
    let bytes: &[u8] = &text;
    // Before tobj, which lets some bad references through and whose index arithmetic
    // overflows on others (see `bad_reference`).
    if let Some((line, word)) = &survey.not_a_number {
        let message = format!("`{}` is not a number (a vertex's w or colour)", super::text::shortened(word));
        return Err(LoadErrorKind::Malformed { format: "OBJ", line: Some(*line), message });
    }
    if let Some((line, e)) = bad_reference(bytes) {
        return Err(LoadErrorKind::Malformed { format: "OBJ", line: Some(line), message: e.to_string() });
    }
    // Polygons come as tobj reads them and are triangulated here (`polygon.rs`): tobj's own
    // triangulation is a fan, which folds concave faces.
    let opts = tobj::LoadOptions { triangulate: false, single_index: true, ignore_points: true, ignore_lines: true };
    let reordered = (base.is_some() && survey.late_library).then(|| libraries_first(bytes));
    let mut reader = BufReader::new(reordered.as_deref().unwrap_or(bytes));
    // Material libraries are read from beside the file (`obj_materials.rs`), where there is
    // one; those that cannot be read are listed as not kept.
    let unread = std::cell::RefCell::new(Vec::new());
    let library = |name: &Path| {
        let name = name.to_string_lossy();
        let read = base.map_or(Err(String::new()), |b| super::obj_materials::library(b, &name));
        read.and_then(|r| r.map_err(|e| e.to_string())).map_err(|why| {
            let note = if why.is_empty() { name.to_string() } else { format!("{name} ({why})") };
            unread.borrow_mut().push(note);
            tobj::LoadError::OpenFileFailed
        })
    };
    let (models, materials) = tobj::load_obj_buf(&mut reader, &opts, library).map_err(|e| {
        LoadErrorKind::Malformed { format: "OBJ", line: locate_error(bytes, e), message: e.to_string() }
    })?;
    // An attribute some objects lack is kept for the others: the objects without it hold
    // zeros and are flagged, so the writers leave it out of them as the source did.
    let has_normals = |m: &tobj::Mesh| !m.normals.is_empty() && m.normals.len() == m.positions.len();
    let has_uvs = |m: &tobj::Mesh| !m.texcoords.is_empty() && 3 * m.texcoords.len() == 2 * m.positions.len();
    let any_normals = models.iter().any(|m| has_normals(&m.mesh));
    let any_uvs = models.iter().any(|m| has_uvs(&m.mesh));
    let has_colours = |m: &tobj::Mesh| !m.vertex_color.is_empty() && m.vertex_color.len() == m.positions.len();
    let any_colours = models.iter().any(|m| has_colours(&m.mesh));
    let mut colours = VertexAttribute::new("COLOR_0", 3, Vec::new());
    let mut out = IndexedMesh::default();
    // tobj reads every number as f64 (its `use_f64`): positions far from the file's origin
    // keep their precision (`mesh/origin.rs`); the rest become f32 here.
    let mut points: Vec<[f64; 3]> = Vec::new();
    // Faces are numbered as tobj keeps them (file order: it starts a model where an object,
    // group or material changes), what `passed_over` blanked not counted; `face_lines` turns
    // those numbers into lines.
    let (mut tri, mut poly, mut face) = (Triangulator::after(skipped), Vec::new(), 0usize);
    for (pi, m) in models.iter().enumerate() {
        let base = points.len() as u32;
        let mesh = &m.mesh;
        let n = mesh.positions.len() / 3;
        points.extend(mesh.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        let (no_normals, no_uvs) = (any_normals && !has_normals(mesh), any_uvs && !has_uvs(mesh));
        if no_normals {
            out.normals.resize(out.normals.len() + n, [0.0; 3]);
        } else if any_normals {
            out.normals.extend(mesh.normals.chunks_exact(3).map(|p| [p[0] as f32, p[1] as f32, p[2] as f32]));
        }
        if no_uvs {
            out.uvs.resize(out.uvs.len() + n, [0.0; 2]);
        } else if any_uvs {
            out.uvs.extend(mesh.texcoords.chunks_exact(2).map(|p| super::uv_origin::from_bottom_left([p[0], p[1]])));
        }
        if has_colours(mesh) {
            colours.values.extend(mesh.vertex_color.iter().map(|&c| c as f32));
        } else if any_colours {
            colours.values.resize(colours.values.len() + 3 * n, 0.0);
            colours.absent.push(pi as u32);
        }
        if mesh.face_arities.is_empty() {
            // Only triangles.
            out.triangles.extend(mesh.indices.chunks_exact(3).map(|t| [t[0] + base, t[1] + base, t[2] + base]));
            face += mesh.indices.len() / 3;
        } else {
            let mut corners = mesh.indices.iter().map(|&i| i + base);
            for &k in &mesh.face_arities {
                poly.clear();
                poly.extend(corners.by_ref().take(k as usize));
                tri.face(face, &poly, |i| points[i as usize], &mut out.triangles);
                face += 1;
            }
        }
        out.triangle_primitive.resize(out.triangles.len(), pi as u32);
        out.primitives.push(Primitive {
            name: m.name.clone(),
            material: mesh.material_id,
            no_normals,
            no_uvs,
            gltf_source: None,
        });
    }
    (out.positions, out.origin) = crate::mesh::origin::relative_positions(&points);
    let free_form = survey.free_form;
    if out.triangles.is_empty() {
        if let Some((count, keywords, line)) = &free_form {
            return Err(LoadErrorKind::Unsupported {
                format: "OBJ",
                message: format!(
                    "only free-form geometry ({count} {keywords} statement{}, the first at line {line}), \
                     which dynlod does not tessellate; export it as polygons",
                    if *count == 1 { "" } else { "s" }
                ),
            });
        }
    }
    let skipped = tri.skipped();
    if out.triangles.is_empty() && skipped.count > 0 {
        let first = skipped.examples.first().map(|l| format!(", the first at {l}")).unwrap_or_default();
        return Err(LoadErrorKind::Unsupported {
            format: "OBJ",
            message: format!(
                "only points, lines or faces of fewer than 3 corners ({}{first}); no surface to simplify",
                skipped.count
            ),
        });
    }
    tri.push_repairs_into(&mut out.load_repairs);
    // An OBJ numbers its faces nowhere; a polygon's line is what finds it in the file.
    for r in out.load_repairs.iter_mut().filter(|r| r.kind == RepairKind::FannedSelfCrossingPolygons) {
        r.examples = face_lines(bytes, &r.examples);
    }
    if out.primitives.len() <= 1 {
        out.triangle_primitive.clear();
    }
    if any_colours {
        out.attributes.push(colours);
    }
    // Materials, for a GLB output; the libraries that could not be read, and what the
    // materials hold that glTF's do not carry, are listed.
    let unread = unread.into_inner();
    if !unread.is_empty() {
        out.not_kept.push(NotKept::new(NotKeptKind::Materials, unread.len(), unread.join(", ")));
    }
    if let (Some(base), Ok(materials)) = (base, &materials) {
        if !materials.is_empty() {
            let (carried, lost) = super::obj_materials::gltf_materials(materials, base);
            out.gltf_materials = Some(std::sync::Arc::new(carried));
            if !lost.is_empty() {
                out.not_kept.push(NotKept::new(NotKeptKind::MaterialMaps, lost.len(), lost.join("; ")));
            }
        }
    }
    if let Some((count, keywords, _)) = free_form {
        out.not_kept.push(NotKept::new(NotKeptKind::FreeFormGeometry, count, keywords));
    }
    if let Some((count, line)) = survey.alpha {
        let what = format!("vertex colour alpha below 1 ({count} `v x y z r g b a`, the first at line {line})");
        out.not_kept.push(NotKept::new(NotKeptKind::OtherAttributes, 1, what));
    }
    Ok(out)
}

/// The first face corner naming a position, texture coordinate or normal that does not
/// exist, with tobj's error for it. tobj refuses most, but not all: a texture or normal index
/// of 0, or a relative one reaching exactly one before the first, reads as "none" (the UV or
/// normal silently dropped), and one far out of range wraps its index arithmetic and reads
/// another entry. So every reference is checked here, as tobj resolves them: a relative index
/// against what the file defined so far, an absolute one against the whole file.
fn bad_reference(text: &[u8]) -> Option<(usize, tobj::LoadError)> {
    // One pass with absolute indices checked against what is defined so far; a file that
    // refers forward (tobj allows it) is scanned again against its totals.
    let mut forward = [0i64; 3];
    let totals = match scan_references(text, Absolute::Forward, &mut forward) {
        Ok(totals) => totals,
        Err(found) => return Some(found),
    };
    if (0..3).any(|k| forward[k] > totals[k]) {
        return scan_references(text, Absolute::Within(totals), &mut forward).err();
    }
    None
}

/// How [`scan_references`] checks an absolute (positive) index.
#[derive(Clone, Copy)]
enum Absolute {
    /// Not yet: the largest beyond what is defined so far goes to `forward`.
    Forward,
    /// Against these counts of v, vt and vn (the whole file's).
    Within([i64; 3]),
    /// Against what is defined so far.
    SoFar,
}

/// [`bad_reference`]'s pass: checks every face corner, relative indices against what is
/// defined so far and absolute ones as `absolute` says. Returns the counts of v, vt and vn,
/// or the first bad corner's line and error. Works on bytes: it reads every line of every
/// OBJ loaded, and `str` splitting and parsing made it about twice as slow.
fn scan_references(
    text: &[u8],
    absolute: Absolute,
    forward: &mut [i64; 3],
) -> Result<[i64; 3], (usize, tobj::LoadError)> {
    use tobj::LoadError as E;
    let mut so_far = [0i64; 3];
    for (i, line) in text.split(|&b| b == b'\n').enumerate() {
        let mut words = line.split(u8::is_ascii_whitespace).filter(|w| !w.is_empty());
        match words.next() {
            Some(b"v") => so_far[0] += 1,
            Some(b"vt") => so_far[1] += 1,
            Some(b"vn") => so_far[2] += 1,
            Some(b"f") => {
                for w in words {
                    for (k, part) in w.split(|&b| b == b'/').enumerate().take(3) {
                        // Unparsable parts are tobj's to refuse (FaceParseError).
                        let Some(idx) = parse_index(part) else { continue };
                        let ok = if idx > 0 {
                            forward[k] = forward[k].max(idx);
                            match absolute {
                                Absolute::Forward => true,
                                Absolute::Within(totals) => idx <= totals[k],
                                Absolute::SoFar => idx <= so_far[k],
                            }
                        } else {
                            idx.checked_neg().is_some_and(|n| n > 0 && n <= so_far[k])
                        };
                        if !ok {
                            let e = [E::FaceVertexOutOfBounds, E::FaceTexCoordOutOfBounds, E::FaceNormalOutOfBounds][k];
                            return Err((i + 1, e));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(so_far)
}

/// An OBJ index as `isize::from_str` reads it (an optional sign, then digits), or `None`.
fn parse_index(part: &[u8]) -> Option<i64> {
    let (neg, digits) = match part {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, part),
    };
    if digits.is_empty() {
        return None;
    }
    let mut n: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        n = n.checked_mul(10)?.checked_sub(i64::from(d - b'0'))?;
    }
    if neg {
        Some(n)
    } else {
        n.checked_neg()
    }
}

/// The first word of an OBJ line: its statement.
fn keyword(line: &[u8]) -> Option<&[u8]> {
    line.split(u8::is_ascii_whitespace).find(|w| !w.is_empty())
}

/// What the pass over an OBJ's lines ([`passed_over`]) finds besides the lines it changes.
#[derive(Default)]
struct Survey {
    /// Free-form curves and surfaces, which tobj reads past without a word: how many
    /// statements, which keywords (`curv, surf`), and the first one's line.
    free_form: Option<(usize, String, usize)>,
    /// Whether a `mtllib` follows the first `usemtl` ([`libraries_first`]).
    late_library: bool,
    /// The first `v` line with a word past x, y and z (w, or a colour) that is not a number,
    /// and the word: tobj reads past a colour that is not a number (the colours of the
    /// others then miss their vertices), and names no line for a w that is not.
    not_a_number: Option<(usize, String)>,
    /// Vertex colours with an alpha below 1 (`v x y z r g b a`, the alpha read past): how
    /// many, and the first one's line.
    alpha: Option<(usize, usize)>,
}

/// The lines tobj must not see, blanked (the line count kept, so errors still name lines):
/// - a `usemtl` without a name after a space, which tobj refuses and Blender 2.6 wrote for
///   faces without a material (no material is read here, so the line says nothing);
/// - points (`p`) and lines (`l`), which are not surfaces: tobj drops two-corner ones, but
///   reads a polyline of three or more as a polygon face (`l 1 2 3 4 5` became a surface);
/// - faces of fewer than three corners, which tobj drops without a word.
///
/// The last two are counted in the returned record, at their lines. A texture coordinate of
/// one component (`vt u`, a 1D texture; the OBJ spec makes v 0), which tobj refuses, gets
/// its `0` written out. The same pass takes the [`Survey`].
fn passed_over(text: &[u8]) -> (Cow<'_, [u8]>, Repair, Survey) {
    let mut skipped = Repair::new(RepairKind::SkippedNonTrianglePrimitives);
    // A `v` line's words past x, y and z, in one scan (every vertex line comes here): the
    // first that is not a number, and the alpha where there are four (x y z r g b a).
    let vertex_tail = |line: &[u8]| -> (Option<String>, Option<f64>) {
        let (mut count, mut last) = (0, 0.0);
        for word in line.split(u8::is_ascii_whitespace).filter(|w| !w.is_empty()).skip(4) {
            match std::str::from_utf8(word).ok().and_then(|w| w.parse::<f64>().ok()) {
                Some(x) => (count, last) = (count + 1, x),
                None => return (Some(String::from_utf8_lossy(word).into_owned()), None),
            }
        }
        (None, (count == 4).then_some(last))
    };
    let pass = |line: &[u8]| -> Option<Pass> {
        let line = line.trim_ascii();
        let mut words = line.split(u8::is_ascii_whitespace).filter(|w| !w.is_empty());
        match words.next()? {
            b"usemtl" => {
                line.splitn(2, |&c| c == b' ').nth(1).is_none_or(|n| n.trim_ascii().is_empty()).then_some(Pass::Blank)
            }
            b"p" | b"l" => Some(Pass::Skip),
            b"f" => (words.count() < 3).then_some(Pass::Skip),
            b"vt" => (words.count() == 1).then_some(Pass::PadTexcoord),
            b"v" => vertex_tail(line).1.map(Pass::DropAlpha),
            _ => None,
        }
    };
    let (mut survey, mut changed, mut used_material) = (Survey::default(), false, false);
    let (mut free, mut first_free, mut free_keywords) = (0, 0, Vec::new());
    for (i, line) in text.split(|&c| c == b'\n').enumerate() {
        // A `v` line is scanned here once, for the survey and the pass both.
        let key = keyword(line);
        let p = match key {
            Some(b"v") => {
                let (not_a_number, alpha) = vertex_tail(line);
                if let (None, Some(word)) = (&survey.not_a_number, not_a_number) {
                    survey.not_a_number = Some((i + 1, word));
                }
                alpha.map(Pass::DropAlpha)
            }
            _ => pass(line),
        };
        if let Some(p) = p {
            if matches!(p, Pass::DropAlpha(a) if a < 1.0) {
                let (count, first) = survey.alpha.unwrap_or((0, i + 1));
                survey.alpha = Some((count + 1, first));
            }
            changed = true;
            continue;
        }
        match key {
            Some(b"usemtl") => used_material = true,
            Some(b"mtllib") => survey.late_library |= used_material,
            Some(k @ (b"curv" | b"curv2" | b"surf")) => {
                free += 1;
                if first_free == 0 {
                    first_free = i + 1;
                }
                let k = std::str::from_utf8(k).expect("ASCII");
                if !free_keywords.contains(&k) {
                    free_keywords.push(k);
                }
            }
            _ => {}
        }
    }
    survey.free_form = (free > 0).then(|| (free, free_keywords.join(", "), first_free));
    if !changed {
        return (Cow::Borrowed(text), skipped, survey);
    }
    let mut out = Vec::with_capacity(text.len());
    for (i, line) in text.split(|&c| c == b'\n').enumerate() {
        if i > 0 {
            out.push(b'\n');
        }
        match pass(line) {
            None => out.extend_from_slice(line),
            Some(Pass::Skip) => skipped.add(Location::Line(i as u32 + 1)),
            Some(Pass::Blank) => {}
            Some(Pass::PadTexcoord) => out.extend_from_slice(&[line.trim_ascii_end(), b" 0"].concat()),
            Some(Pass::DropAlpha(_)) => {
                let line = line.trim_ascii_end();
                out.extend_from_slice(&line[..line.iter().rposition(u8::is_ascii_whitespace).unwrap_or(line.len())]);
            }
        }
    }
    (Cow::Owned(out), skipped, survey)
}

/// tobj looks a `usemtl` name up when it reads the line, so a material from a library named
/// later in the file (assimp's `cube_mtllib_after_g.obj`) would be missed. Where a `mtllib`
/// follows the first `usemtl` ([`Survey::late_library`]), tobj gets every `mtllib` line
/// first and those lines blanked where they were: a copy, for tobj alone (every line number
/// here is taken from the file).
fn libraries_first(text: &[u8]) -> Vec<u8> {
    let library = |line: &&[u8]| keyword(line) == Some(b"mtllib");
    let mut out = Vec::with_capacity(text.len() + 64);
    for line in text.split(|&c| c == b'\n').filter(library) {
        out.extend_from_slice(line);
        out.push(b'\n');
    }
    for (i, line) in text.split(|&c| c == b'\n').enumerate() {
        if i > 0 {
            out.push(b'\n');
        }
        if !library(&line) {
            out.extend_from_slice(line);
        }
    }
    out
}

/// What [`passed_over`] does with a line.
enum Pass {
    /// Blanked, as saying nothing.
    Blank,
    /// Blanked and recorded as skipped.
    Skip,
    /// A one-component `vt` given its v of 0.
    PadTexcoord,
    /// A `v x y z r g b a`'s alpha (given) read past: tobj reads three colour channels.
    DropAlpha(f64),
}

/// The lines of the faces `at` names (`Location::Face(k)`: the k-th `f` line of `text`, as
/// tobj keeps them), in one pass.
fn face_lines(text: &[u8], at: &[Location]) -> Vec<Location> {
    let mut out = at.to_vec();
    let mut face = 0u32;
    for (i, line) in text.split(|&c| c == b'\n').enumerate() {
        if keyword(line) == Some(b"f") {
            for l in out.iter_mut().filter(|l| **l == Location::Face(face)) {
                *l = Location::Line(i as u32 + 1);
            }
            face += 1;
        }
    }
    out
}

/// tobj does not say where it failed; find the first line that explains the error kind.
fn locate_error(bytes: &[u8], e: tobj::LoadError) -> Option<usize> {
    use tobj::LoadError as E;
    let text = String::from_utf8_lossy(bytes);
    if matches!(e, E::FaceVertexOutOfBounds | E::FaceTexCoordOutOfBounds | E::FaceNormalOutOfBounds) {
        // tobj resolves a model's faces when the model ends, so an absolute index may look
        // ahead within it, but not past it: the first corner beyond what is defined so far.
        let found = scan_references(bytes, Absolute::SoFar, &mut [0; 3]).err();
        return found.filter(|(_, found)| *found == e).map(|(line, _)| line);
    }
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else { continue };
        let bad_nums = |need: usize| words.clone().take(need).filter(|w| w.parse::<f64>().is_ok()).count() < need;
        let found = match key {
            "v" => match e {
                E::PositionParseError => bad_nums(3),
                // A colour of one or two channels, or more than r g b a; a w of zero.
                E::ColorParseError => matches!(words.clone().count(), 5 | 7..),
                E::ScalingByZeroError => {
                    let w: Vec<&str> = words.clone().collect();
                    w.len() == 4 && w[3].parse::<f64>().is_ok_and(|w| w == 0.0)
                }
                _ => false,
            },
            "vn" => matches!(e, E::NormalParseError) && bad_nums(3),
            "vt" => matches!(e, E::TexcoordParseError) && bad_nums(2),
            "f" => {
                matches!(e, E::FaceParseError)
                    && words.clone().any(|w| w.split('/').take(3).any(|p| !p.is_empty() && p.parse::<i64>().is_err()))
            }
            _ => false,
        };
        if found {
            return Some(i + 1);
        }
    }
    None
}
