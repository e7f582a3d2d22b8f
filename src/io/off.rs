//! Object File Format (ASCII): `OFF`, `COFF`, `NOFF`, `STOFF` and friends, counts on the header
//! line or the next, `#` comments, polygons triangulated (`polygon.rs`), vertex colours (`COFF`) read
//! as `COLOR_0` (RGBA, or RGB and opaque where a vertex line holds three; on the 0–255 scale where every component in the file is an integer
//! and some exceed 1, otherwise 0–1 as written), face colours read past (and listed in `not_kept`).
//! Any text encoding (`text.rs`). Binary and higher-dimensional OFF are refused by name.

use std::iter::Peekable;

use crate::error::LoadErrorKind;
use crate::mesh::{IndexedMesh, NotKept, NotKeptKind, VertexAttribute};

fn malformed(line: usize, message: impl Into<String>) -> LoadErrorKind {
    LoadErrorKind::Malformed { format: "OFF", line: Some(line), message: message.into() }
}

/// Whitespace-separated tokens with their 1-based line numbers, comments stripped.
struct Tokens<'a, I: Iterator<Item = (usize, &'a str)>> {
    it: Peekable<I>,
}

impl<'a, I: Iterator<Item = (usize, &'a str)> + Clone> Tokens<'a, I> {
    fn num(&mut self, what: &str) -> Result<(usize, f64), LoadErrorKind> {
        let (line, w) = self
            .it
            .next()
            .ok_or_else(|| LoadErrorKind::Truncated { format: "OFF", message: format!("file ends before {what}") })?;
        if w.eq_ignore_ascii_case("binary") {
            return Err(LoadErrorKind::Unsupported { format: "OFF", message: "binary OFF".into() });
        }
        let v = w.parse::<f64>().map_err(|_| malformed(line, format!("expected {what}, found {w:?}")))?;
        Ok((line, v))
    }

    /// How many tokens are left on the line of the next token.
    fn left_on_line(&mut self) -> usize {
        let Some(&(line, _)) = self.it.peek() else { return 0 };
        self.it.clone().take_while(|&(l, _)| l == line).count()
    }

    /// Skips what is left of `line` (per-face colours); returns whether there was anything.
    fn skip_line(&mut self, line: usize) -> bool {
        let mut skipped = false;
        while self.it.peek().is_some_and(|&(l, _)| l == line) {
            self.it.next();
            skipped = true;
        }
        skipped
    }
}

fn count((line, v): (usize, f64), what: &str) -> Result<usize, LoadErrorKind> {
    if !(0.0..=u32::MAX as f64).contains(&v) || v.fract() != 0.0 {
        return Err(malformed(line, format!("bad {what} {v}")));
    }
    Ok(v as usize)
}

pub(super) fn load(bytes: &[u8]) -> Result<IndexedMesh, LoadErrorKind> {
    let text = super::text::utf8(bytes);
    let it = text
        .lines()
        .enumerate()
        .flat_map(|(i, l)| l.split('#').next().unwrap_or("").split_whitespace().map(move |w| (i + 1, w)))
        .peekable();
    let mut t = Tokens { it };
    let (line, magic) = t.it.next().ok_or_else(|| malformed(1, "empty file"))?;
    let keyword = magic.trim_start_matches(|c: char| c.is_ascii_digit());
    if !keyword.ends_with("OFF") {
        return Err(malformed(line, format!("expected an OFF header, found {magic:?}")));
    }
    let prefix = &keyword[..keyword.len() - 3];
    if prefix.contains('4') || prefix.contains('n') {
        return Err(LoadErrorKind::Unsupported { format: "OFF", message: format!("{magic} (higher-dimensional OFF)") });
    }
    let (has_st, has_c, has_n) = (prefix.contains("ST"), prefix.contains('C'), prefix.contains('N'));
    let nv = count(t.num("the vertex count")?, "vertex count")?;
    let nf = count(t.num("the face count")?, "face count")?;
    t.num("the edge count")?;
    let mut out = IndexedMesh::default();
    let mut points = Vec::with_capacity(nv.min(1 << 22));
    let mut colours = Vec::new();
    for _ in 0..nv {
        points.push([t.num("a coordinate")?.1, t.num("a coordinate")?.1, t.num("a coordinate")?.1]);
        if has_n {
            let n = [t.num("a normal")?.1, t.num("a normal")?.1, t.num("a normal")?.1];
            out.normals.push(n.map(|c| c as f32));
        }
        if has_c {
            // Geomview's COFF colour is RGBA; CGAL and others write RGB. Where the vertex
            // is on a line of its own, what is left of it tells which.
            let rgb = t.left_on_line() == 3 + 2 * usize::from(has_st);
            for _ in 0..3 {
                colours.push(t.num("a colour")?.1);
            }
            colours.push(if rgb { f64::NAN } else { t.num("a colour")?.1 });
        }
        if has_st {
            let uv = [t.num("a texture coordinate")?.1, t.num("a texture coordinate")?.1];
            out.uvs.push(uv.map(|c| c as f32));
        }
    }
    (out.positions, out.origin) = crate::mesh::origin::relative_positions(&points);
    out.triangles.reserve(nf.min(1 << 22));
    let mut poly = Vec::new();
    let mut tri = super::polygon::Triangulator::default();
    let mut face_colours = false;
    for face in 0..nf {
        let (line, k) = t.num("a face size")?;
        let k = count((line, k), "face size")?;
        poly.clear();
        for corner in 0..k {
            let (l, i) = t.num("a face index")?;
            if i.fract() != 0.0 {
                return Err(malformed(l, format!("face {face} index {i} is not an integer")));
            }
            poly.push(super::check_index(i as i64, nv, face, corner)?);
        }
        tri.face(face, &poly, |i| out.positions[i as usize].map(f64::from), &mut out.triangles);
        face_colours |= t.skip_line(line);
    }
    tri.push_repairs_into(&mut out.load_repairs);
    if has_c && nv > 0 {
        // An alpha the file left out (NaN here) is opaque.
        let given = || colours.iter().filter(|c| !c.is_nan());
        let bytes = given().all(|c| c.fract() == 0.0) && given().any(|&c| c > 1.0);
        let values = colours
            .iter()
            .map(|&c| match (c.is_nan(), bytes) {
                (true, _) => 1.0,
                (false, true) => (c / 255.0) as f32,
                (false, false) => c as f32,
            })
            .collect();
        out.attributes.push(VertexAttribute::new("COLOR_0", 4, values));
    }
    if face_colours {
        out.not_kept.push(NotKept::new(NotKeptKind::OtherAttributes, 1, "face colours"));
    }
    Ok(out)
}
