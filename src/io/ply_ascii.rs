//! An ascii PLY body whose elements do not sit one to a line, read as a stream of words.
//!
//! Turk's `ply.c`, which set the format, reads an ascii element from one line, and so does
//! ply-rs; rply and VCG (MeshLab) read words, wherever the lines break. Writers that wrap a
//! long face list, or put several short elements on a line, make files that MeshLab opens
//! and ply-rs refuses (or reads short: it drops the words past an element's last). Where
//! ply-rs fails on an ascii body, and its words fit the header exactly (every element's
//! properties, list lengths included, and no word left over), the body is written again one
//! element to a line and read from that, and the lines where an element started that did
//! not hold it alone are recorded ([`RepairKind::RewrappedAsciiElements`]). Where the words
//! do not fit, ply-rs's own error stands.
//!
//! Where ply-rs succeeds, it may still have passed over words: those past an element's last
//! property on its line, and lines past the last element (Turk's `ply.c` does the same).
//! [`extra_words`] finds them, so that they are read as a stream where that fits the header
//! exactly, and otherwise recorded ([`RepairKind::IgnoredExtraWords`]) instead of dropped
//! without a word.

use ply_rs_bw::ply::{Encoding, Header, PropertyType};

use crate::mesh::{Location, Repair, RepairKind};

/// `bytes` (a whole PLY file, its header ascii and readable) with its body written one
/// element to a line, and the record of the lines that held other than one element; `None`
/// where the file is not ascii, its words do not fit the header, or each element already
/// has a line of its own.
pub(super) fn rewrap(bytes: &[u8], header: &Header) -> Option<(Vec<u8>, Repair)> {
    // An element without properties has no words to place (and a count past the file's
    // length, which `ply.rs` refuses, would only loop).
    let placeable = |e: &ply_rs_bw::ply::ElementDef| !e.properties.is_empty() && e.count <= bytes.len();
    if header.encoding != Encoding::Ascii || !header.elements.values().all(placeable) {
        return None;
    }
    let start = body_start(bytes)?;
    let lines_before = bytes[..start].iter().filter(|&&b| b == b'\n').count();
    let body = std::str::from_utf8(&bytes[start..]).ok()?;
    let mut words = body
        .lines()
        .enumerate()
        .flat_map(|(i, line)| line.split_ascii_whitespace().map(move |w| (lines_before + i + 1, w)));
    let mut out = bytes[..start].to_vec();
    let mut repair = Repair::new(RepairKind::RewrappedAsciiElements);
    let mut last_line = 0;
    for element in header.elements.values() {
        for _ in 0..element.count {
            let mut first_line = None;
            let mut took = |out: &mut Vec<u8>| -> Option<(usize, &str)> {
                let (line, word) = words.next()?;
                first_line.get_or_insert(line);
                out.extend_from_slice(word.as_bytes());
                out.push(b' ');
                Some((line, word))
            };
            let mut end = 0;
            for property in element.properties.values() {
                match &property.data_type {
                    PropertyType::Scalar(_) => end = took(&mut out)?.0,
                    PropertyType::List(..) => {
                        let (line, length) = took(&mut out)?;
                        end = line;
                        for _ in 0..length.parse::<usize>().ok()? {
                            end = took(&mut out)?.0;
                        }
                    }
                }
            }
            out.pop();
            out.push(b'\n');
            let first = first_line.unwrap_or(end);
            if first != end || first == last_line {
                repair.add(Location::Line(first as u32));
            }
            last_line = end;
        }
    }
    (words.next().is_none() && repair.count > 0).then_some((out, repair))
}

/// The lines of an ascii body whose words ply-rs reads in part, as it reads them (one
/// element to a line): a line with words past its element's properties, and the first
/// non-blank line past the last element. `None` where there is none, or the body does not
/// read line by line (ply-rs's error, or [`rewrap`], deals with those).
pub(super) fn extra_words(bytes: &[u8], header: &Header) -> Option<Repair> {
    if header.encoding != Encoding::Ascii {
        return None;
    }
    let start = body_start(bytes)?;
    let lines_before = bytes[..start].iter().filter(|&&b| b == b'\n').count();
    let mut lines = bytes[start..].split(|&b| b == b'\n').enumerate().map(|(i, l)| (lines_before + i + 1, l));
    let mut repair = Repair::new(RepairKind::IgnoredExtraWords);
    for element in header.elements.values() {
        for _ in 0..element.count {
            let (number, line) = lines.next()?;
            let mut words = std::str::from_utf8(line).ok()?.split_ascii_whitespace();
            for property in element.properties.values() {
                // A scalar is a word; a list, its length and that many words.
                let taken = match &property.data_type {
                    PropertyType::Scalar(_) => 1,
                    PropertyType::List(..) => 1 + words.clone().next()?.parse::<usize>().ok()?,
                };
                words.nth(taken - 1)?;
            }
            if words.next().is_some() {
                repair.add(Location::Line(number as u32));
            }
        }
    }
    if let Some((number, _)) = lines.find(|(_, l)| !l.trim_ascii().is_empty()) {
        repair.add(Location::Line(number as u32));
    }
    (repair.count > 0).then_some(repair)
}

/// Where the body starts: past the line that reads `end_header`.
fn body_start(bytes: &[u8]) -> Option<usize> {
    let mut at = 0;
    for line in bytes.split(|&b| b == b'\n') {
        at += line.len() + 1;
        if line.trim_ascii() == b"end_header" {
            return Some(at.min(bytes.len()));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use ply_rs_bw::parser::Parser;

    const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                          property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

    fn header(file: &str) -> Header {
        let mut reader = ply_rs_bw::parser::Reader::new(file.as_bytes());
        Parser::<super::super::ply::Ignore>::new().read_header(&mut reader).unwrap()
    }

    fn rewrapped(body: &str) -> Option<(String, Vec<Location>, usize)> {
        let file = format!("{HEADER}{body}");
        let (bytes, repair) = rewrap(file.as_bytes(), &header(&file))?;
        let text = String::from_utf8(bytes).unwrap();
        Some((text.strip_prefix(HEADER).unwrap().to_string(), repair.examples.clone(), repair.count))
    }

    #[test]
    fn elements_over_lines_or_sharing_one_are_put_one_to_a_line() {
        let tidy = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        // A face list wrapped (line 13 starts it); two vertices on one line (line 10 starts
        // the second) and one over two lines (line 11).
        let (body, at, count) = rewrapped("0 0 0\n1 0 0\n0 1 0\n3 0\n 1\t2\n").unwrap();
        assert_eq!((body.as_str(), at, count), (tidy, vec![Location::Line(13)], 1));
        let (body, at, count) = rewrapped("0 0 0 1 0 0\n0\n1 0\n3 0 1 2").unwrap();
        assert_eq!((body.as_str(), at, count), (tidy, vec![Location::Line(10), Location::Line(11)], 2));
        // One element a line already: nothing to do; too few words, or one too many: the
        // body does not fit, and ply-rs's error stands.
        assert!(rewrapped(tidy).is_none());
        assert!(rewrapped("0 0 0 1 0 0 0 1 0 3 0 1").is_none());
        assert!(rewrapped("0 0 0 1 0 0 0 1 0 3 0 1 2 9").is_none());
        assert!(rewrapped("0 0 0 1 0 0 0 1 0 three 0 1 2").is_none());
        // Elements without properties, or more than the file could hold, are left alone.
        let file = format!("{HEADER}0 0 0 1 0 0\n0 1 0\n3 0 1 2\n");
        for (from, to) in [("element face 1", "element empty 2\nelement face 1"), ("vertex 3", "vertex 99999")] {
            let file = file.replace(from, to);
            assert!(rewrap(file.as_bytes(), &header(&file)).is_none(), "{to}");
        }
    }

    fn extra(body: &str) -> Option<(Vec<Location>, usize)> {
        let file = format!("{HEADER}{body}");
        extra_words(file.as_bytes(), &header(&file)).map(|r| (r.examples.clone(), r.count))
    }

    #[test]
    fn words_past_an_element_are_found_on_their_line() {
        assert_eq!(extra("0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), None);
        assert_eq!(extra("0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n  \n"), None, "blank lines at the end");
        // A fourth coordinate (line 11); a face list with a word past it (line 13).
        assert_eq!(
            extra("0 0 0\n1 0 0 9\n0 1 0\n3 0 1 2 5\n"),
            Some((vec![Location::Line(11), Location::Line(13)], 2))
        );
        // A line past the last element (line 14): only the first is named.
        assert_eq!(extra("0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n7\n8\n"), Some((vec![Location::Line(14)], 1)));
        // Lines ply-rs cannot read are not this check's to judge.
        assert_eq!(extra("0 0 0\n1 0\n0 1 0\n3 0 1 2\n"), None);
        assert_eq!(extra("0 0 0\n1 0 0\n0 1 0\n"), None);
    }
}
