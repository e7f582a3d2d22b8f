//! The PLY header as real exporters wrote it, made into one `ply-rs-bw` reads, and its errors
//! made readable.
//!
//! Blender 2.4x's exporter wrote its credit line bare, with no `comment` before it
//! (`Created by Blender3D 247 - www.blender.org, source file: ...`, assimp's `Wuson.ply`), and
//! some tools leave blank lines in the header. ply-rs refuses both. Here a blank line anywhere
//! in the header, and a line that is no header keyword before the first `element`, are read
//! as comments and recorded ([`RepairKind::CommentedHeaderLines`], at their lines). After the
//! first `element` such a line is refused: a misspelt `property` there would shift every
//! column after it, so guessing could only give garbage.

use std::borrow::Cow;

use ply_rs_bw::parser::Parser;

use super::ply::Ignore;
use super::text::shortened;
use crate::error::LoadErrorKind;
use crate::mesh::{Location, Repair, RepairKind};

/// `bytes` with the header's bare lines made comments, and the record of which; or the first
/// header line that is refused, by line number.
pub(super) fn tidy(bytes: &[u8]) -> Result<(Cow<'_, [u8]>, Repair), LoadErrorKind> {
    let parser = Parser::<Ignore>::new();
    let mut repair = Repair::new(RepairKind::CommentedHeaderLines);
    let mut bare = Vec::new();
    let mut at = 0;
    let mut seen_element = false;
    for (index, line) in bytes.split(|&c| c == b'\n').enumerate() {
        let start = at;
        at += line.len() + 1;
        if index == 0 {
            continue; // the magic number, which ply-rs checks itself
        }
        let text = String::from_utf8_lossy(line);
        let words = text.trim();
        if words == "end_header" {
            break;
        }
        if words.is_empty() {
            bare.push(start);
            repair.add(Location::Line(index as u32 + 1));
            continue;
        }
        if parser.read_header_line(&format!("{text}\n")).is_ok() {
            seen_element |= words.split_ascii_whitespace().next() == Some("element");
            continue;
        }
        if seen_element {
            return Err(LoadErrorKind::Malformed {
                format: "PLY",
                line: Some(index + 1),
                message: format!(
                    "`{}` is not a header line (ply, format, comment, obj_info, element, property or end_header)",
                    shortened(words)
                ),
            });
        }
        bare.push(start);
        repair.add(Location::Line(index as u32 + 1));
    }
    if bare.is_empty() {
        return Ok((Cow::Borrowed(bytes), repair));
    }
    let mut out = Vec::with_capacity(bytes.len() + 8 * bare.len());
    let mut from = 0;
    for start in bare {
        out.extend_from_slice(&bytes[from..start]);
        out.extend_from_slice(b"comment ");
        from = start;
    }
    out.extend_from_slice(&bytes[from..]);
    Ok((Cow::Owned(out), repair))
}

/// ply-rs's error as one line: its message without the line number it repeats, and its
/// "String: ... Error: ..." layout turned into "what; the line reads `...`".
pub(super) fn message(e: &ply_rs_bw::parser::ParseError) -> String {
    let full = e.to_string();
    let full = match e.line() {
        Some(line) => full.strip_prefix(&format!("Line {line}: ")).unwrap_or(&full).to_string(),
        None => full,
    };
    let (mut what, mut string, mut error) = (Vec::new(), None, None);
    for part in full.split("\n\t") {
        if let Some(s) = part.strip_prefix("String: ") {
            string = Some(s.trim().trim_matches('\'').trim().to_string());
        } else if let Some(s) = part.strip_prefix("Error: ") {
            error = Some(s.trim().to_string());
        } else {
            what.push(part.trim().to_string());
        }
    }
    let what = what.join(" ");
    match (string, error) {
        // "Couldn't read element line." says less than the error under it.
        (Some(line), Some(error)) => format!("{}; the line reads `{}`", error.trim_end_matches('.'), shortened(&line)),
        (Some(line), None) => format!("{}; the line reads `{}`", what.trim_end_matches('.'), shortened(&line)),
        (None, Some(error)) => format!("{} ({error})", what.trim_end_matches('.')),
        (None, None) => what,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bare_and_blank_lines_before_the_elements_become_comments() {
        let file = b"ply\nformat ascii 1.0\nCreated by Blender3D 247\n\nelement vertex 0\nend_header\n";
        let (tidied, repair) = tidy(file).unwrap();
        assert_eq!(
            &*tidied,
            b"ply\nformat ascii 1.0\ncomment Created by Blender3D 247\ncomment \nelement vertex 0\nend_header\n"
        );
        assert_eq!(repair.count, 2);
        assert_eq!(repair.examples, [Location::Line(3), Location::Line(4)]);
        let clean = b"ply\nformat ascii 1.0\nelement vertex 0\nend_header\nbare body\n";
        assert!(matches!(tidy(clean).unwrap(), (Cow::Borrowed(_), r) if r.count == 0));
    }

    #[test]
    fn a_bare_line_among_the_elements_is_refused_by_its_line() {
        let file = b"ply\nformat ascii 1.0\nelement vertex 1\nproprety float x\nend_header\n";
        match tidy(file) {
            Err(LoadErrorKind::Malformed { line: Some(4), message, .. }) => {
                assert!(message.starts_with("`proprety float x` is not a header line"), "{message}")
            }
            other => panic!("{other:?}"),
        }
    }
}
