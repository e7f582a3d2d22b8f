//! The text encodings that real exports use, made into the UTF-8 the parsers read: a UTF-8
//! byte-order mark (Notepad and many Windows tools write one) is read past, UTF-16 with its
//! mark is decoded, and text that is not UTF-8 is read as Latin-1 (ISO 8859-1: what 3ds Max
//! and older Blender wrote for names such as `usemtl Terraindæk`; numbers and keywords are
//! ASCII in every one of them, so only names and comments depend on the choice). Line
//! numbers are kept, so errors still name the line of the file.

use std::borrow::Cow;

const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// `bytes` as text: borrowed where they are UTF-8 already (past a byte-order mark), else
/// decoded as above.
pub(crate) fn utf8(bytes: &[u8]) -> Cow<'_, str> {
    let bytes = without_bom(bytes);
    let utf16 = match bytes {
        [0xFF, 0xFE, rest @ ..] => Some((rest, u16::from_le_bytes as fn([u8; 2]) -> u16)),
        [0xFE, 0xFF, rest @ ..] => Some((rest, u16::from_be_bytes as fn([u8; 2]) -> u16)),
        _ => None,
    };
    if let Some((rest, unit)) = utf16 {
        let units = rest.chunks_exact(2).map(|c| unit([c[0], c[1]]));
        return Cow::Owned(char::decode_utf16(units).map(|c| c.unwrap_or('\u{FFFD}')).collect());
    }
    match std::str::from_utf8(bytes) {
        Ok(text) => Cow::Borrowed(text),
        Err(_) => Cow::Owned(bytes.iter().map(|&b| b as char).collect()),
    }
}

/// `bytes` with the header before the line `end` (ASCII but for comments and names) made
/// UTF-8 as [`utf8`] does, and the rest, binary or not, as it is.
pub(crate) fn header_utf8<'a>(bytes: &'a [u8], end: &[u8]) -> Cow<'a, [u8]> {
    let mut at = 0;
    for line in bytes.split(|&c| c == b'\n') {
        if line.trim_ascii() == end {
            break;
        }
        at += line.len() + 1;
    }
    let header = &bytes[..at.min(bytes.len())];
    match utf8(header) {
        Cow::Borrowed(_) => Cow::Borrowed(bytes),
        Cow::Owned(header) => {
            let mut header = header.into_bytes();
            header.extend_from_slice(&bytes[at.min(bytes.len())..]);
            Cow::Owned(header)
        }
    }
}

/// At most 60 characters of `s` for an error message, marked where cut, control characters
/// escaped (a parser may read one as a word: OpenSCAD's `unparseable.stl`).
pub(crate) fn shortened(s: &str) -> String {
    let mut out: String = s.chars().take(60).flat_map(char::escape_debug).collect();
    if s.chars().nth(60).is_some() {
        out.push('…');
    }
    out
}

/// `bytes` past a UTF-8 byte-order mark, if it starts with one.
pub(crate) fn without_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_encoding_comes_out_as_the_same_utf8() {
        let text = "# Terraindæk\nv 1 2 3\n";
        let latin1: Vec<u8> = text.chars().map(|c| c as u8).collect();
        let utf16le: Vec<u8> = [0xFF, 0xFE].into_iter().chain(text.encode_utf16().flat_map(u16::to_le_bytes)).collect();
        let utf16be: Vec<u8> = [0xFE, 0xFF].into_iter().chain(text.encode_utf16().flat_map(u16::to_be_bytes)).collect();
        let bom: Vec<u8> = UTF8_BOM.iter().chain(text.as_bytes()).copied().collect();
        for (name, bytes) in
            [("utf-8", text.as_bytes()), ("bom", &bom), ("latin-1", &latin1), ("le", &utf16le), ("be", &utf16be)]
        {
            assert_eq!(&*utf8(bytes), text, "{name}");
        }
        assert!(matches!(utf8(text.as_bytes()), Cow::Borrowed(_)));
        // A header's Latin-1 comment, with a binary body after it left as it is.
        let body = [0xE9u8, 0xFF, 0x00, 0x0A];
        let file = [b"ply\ncomment Cr\xE9\xE9\nend_header\n".as_slice(), &body].concat();
        let read = header_utf8(&file, b"end_header");
        assert_eq!(&*read, [b"ply\ncomment Cr\xC3\xA9\xC3\xA9\nend_header\n".as_slice(), &body].concat());
        assert!(matches!(header_utf8(b"ply\nend_header\n\xFF", b"end_header"), Cow::Borrowed(_)));
        assert!(matches!(utf8(&bom), Cow::Borrowed(_)));
    }
}
