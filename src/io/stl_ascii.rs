//! Where an ascii STL goes wrong. stl_io reads the file, but its errors name no place
//! ("invalid float literal", "expected finite f32, got NaN"), so on an error the text is
//! walked again here by the same grammar, line by line: the first line that does not fit is
//! reported with its line number and facet (from 0, as the faces are numbered elsewhere).
//!
//! The grammar is stl_io 0.11's: a `solid` line, then facets of `facet normal x y z`,
//! `outer loop`, three `vertex x y z`, `endloop`, `endfacet`, each on its own line (blank
//! lines skipped), up to `endsolid`; every number a finite `f32`. Keywords are matched in
//! any case, as `stl.rs` reads them.

use super::text::shortened;
use crate::error::LoadErrorKind;

/// The first place `text` (the whole file, its first line the `solid` one; `skipped` lines
/// before it) breaks the grammar, as an error; `None` where it does not.
pub(super) fn locate(text: &str, skipped: usize) -> Option<LoadErrorKind> {
    let mut lines = text.lines().enumerate().skip(1).map(|(i, l)| (i + 1 + skipped, l));
    let mut lines = lines.by_ref().filter(|(_, l)| !l.trim().is_empty());
    let mut last = 1 + skipped;
    for facet in 0.. {
        let at = |line: usize, what: String| LoadErrorKind::Malformed {
            format: "STL",
            line: Some(line),
            message: format!("ascii, facet {facet}: {what}"),
        };
        for expected in ["facet normal", "outer loop", "vertex", "vertex", "vertex", "endloop", "endfacet"] {
            let Some((n, line)) = lines.next() else {
                let message = match (facet, expected) {
                    (_, "facet normal") => {
                        let s = if facet == 1 { "" } else { "s" };
                        format!("the file ends after {facet} facet{s}, without `endsolid`")
                    }
                    _ => format!("the file ends inside facet {facet} (line {last}), before `{expected}`"),
                };
                return Some(LoadErrorKind::Truncated { format: "STL", message });
            };
            last = n;
            let words: Vec<&str> = line.split_whitespace().collect();
            if expected == "facet normal" && words.first().is_some_and(|w| w.eq_ignore_ascii_case("endsolid")) {
                return None;
            }
            let keyword = expected.split(' ').count();
            let numbers = if matches!(expected, "facet normal" | "vertex") { 3 } else { 0 };
            let fits = words.len() == keyword + numbers && words[..keyword].join(" ").eq_ignore_ascii_case(expected);
            if !fits {
                let want = if numbers > 0 { format!("`{expected} x y z`") } else { format!("`{expected}`") };
                return Some(at(n, format!("expected {want}, found `{}`", shortened(&words.join(" ")))));
            }
            for word in &words[keyword..] {
                match word.parse::<f32>() {
                    Ok(v) if v.is_finite() => {}
                    Ok(_) => return Some(at(n, format!("`{word}` is not a finite number"))),
                    Err(_) => return Some(at(n, format!("`{}` is not a number", shortened(word)))),
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const FACET: &str = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";

    fn error(text: &str) -> (Option<usize>, String) {
        match locate(text, 0) {
            Some(LoadErrorKind::Malformed { line, message, .. }) => (line, message),
            Some(LoadErrorKind::Truncated { message, .. }) => (None, message),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_well_formed_file_has_no_place_to_name() {
        assert!(locate(&format!("solid a\n{FACET}\n  \n{FACET}endsolid a\n"), 0).is_none());
    }

    #[test]
    fn the_first_line_that_breaks_the_grammar_is_named_with_its_facet() {
        let two = format!("solid a\n{FACET}{FACET}endsolid\n");
        let cases = [
            (
                "vertex 0 1 0\nendloop\nendfacet\nendsolid",
                "vertex nan 1 0\nendloop\nendfacet\nendsolid",
                13,
                "`nan` is not a finite",
            ),
            (
                "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid",
                "vertex 1 0 0\nvertex 0 1.2.3 0\nendloop\nendfacet\nendsolid",
                13,
                "`1.2.3` is not a number",
            ),
            (
                "endloop\nendfacet\nendsolid",
                "vertex 0 0 1\nendloop\nendfacet\nendsolid",
                14,
                "expected `endloop`, found `vertex 0 0 1`",
            ),
            (
                "vertex 0 1 0\nendloop\nendfacet\nendsolid",
                "vertex 0 \u{10} 1 0\nendloop\nendfacet\nendsolid",
                13,
                "`vertex 0 \\u{10} 1 0`",
            ),
        ];
        for (from, to, line, says) in cases {
            let text = two.replacen(&format!("{from}\n"), &format!("{to}\n"), 1);
            assert_ne!(text, two, "{to}");
            let (at, message) = error(&text);
            assert_eq!(at, Some(line), "{message}");
            assert!(message.starts_with("ascii, facet 1: ") && message.contains(says), "{message}");
        }
        // Lines before `solid` count.
        assert!(matches!(
            locate("solid\nfacet normal 0 0 inf\n", 2),
            Some(LoadErrorKind::Malformed { line: Some(4), .. })
        ));
        assert!(error(&format!("solid a\n{FACET}")).1.contains("after 1 facet, without `endsolid`"));
        assert!(error(&format!("solid a\n{FACET}{}", &FACET[..43]))
            .1
            .contains("inside facet 1 (line 11), before `vertex`"));
    }
}
