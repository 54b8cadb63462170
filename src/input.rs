//! What the scene and OBJ readers share about raw input: size limits, decoding bytes (a UTF-8
//! byte-order mark is accepted, invalid UTF-8 is reported at its line and column), and quoting
//! user-supplied strings in messages so that no control character reaches a terminal.
//!
//! The library does no I/O: the CLI and the inspector read files with these limits.

use std::borrow::Cow;

/// The largest scene file read (64 MiB; the largest fixture is under 4 KiB, and a scene of a
/// million spheres is about 100 MiB of JSON, far past what the loader is meant for).
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// The largest OBJ mesh file read (1 GiB: about 25 million triangles of text).
pub const MAX_OBJ_BYTES: u64 = 1 << 30;

/// The UTF-8 byte-order mark some editors write at the start of a file.
const BOM: char = '\u{feff}';

/// `s` without a leading byte-order mark.
#[must_use]
pub fn strip_bom(s: &str) -> &str {
    s.strip_prefix(BOM).unwrap_or(s)
}

/// Where a file stops being UTF-8.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{line}:{column}: not valid UTF-8 (byte 0x{byte:02x}); save the file as UTF-8")]
pub struct BadUtf8 {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in bytes (as JSON errors count).
    pub column: usize,
    /// The first offending byte.
    pub byte: u8,
}

/// `bytes` as text without a leading byte-order mark.
///
/// # Errors
/// The line and column of the first byte that is not UTF-8.
pub fn decode(bytes: Vec<u8>) -> Result<String, BadUtf8> {
    match String::from_utf8(bytes) {
        Ok(mut s) => {
            if s.starts_with(BOM) {
                s.drain(..BOM.len_utf8());
            }
            Ok(s)
        }
        Err(e) => {
            let bytes = e.as_bytes();
            let at = e.utf8_error().valid_up_to();
            let before = &bytes[..at];
            let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
            let start = before
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |i| i + 1);
            Err(BadUtf8 {
                line,
                column: at - start + 1,
                byte: bytes[at],
            })
        }
    }
}

/// Longest quoted string shown in a message, in characters.
const QUOTE_CHARS: usize = 60;

/// `s` quoted for a message: control characters escaped (`\n`, `\u{1b}`), and cut to 60
/// characters with the full length said.
#[must_use]
pub fn quote(s: &str) -> String {
    let n = s.chars().count();
    if n <= QUOTE_CHARS {
        format!("{s:?}")
    } else {
        let head: String = s.chars().take(QUOTE_CHARS).collect();
        format!("{head:?}... ({n} characters)")
    }
}

/// A window of at most 60 characters of `s` around the 1-based character `column`, control
/// characters escaped as in [`escape_controls`] and cut ends marked `...`, with the 0-based
/// offset of that column's character in the window (for a caret line under it).
#[must_use]
pub fn excerpt(s: &str, column: usize) -> (String, usize) {
    let chars: Vec<char> = s.chars().collect();
    let at = column.saturating_sub(1).min(chars.len());
    let start = at.saturating_sub(QUOTE_CHARS / 2);
    let end = (start + QUOTE_CHARS).min(chars.len());
    let mut out = String::new();
    if start > 0 {
        out.push_str("...");
    }
    let mut caret = out.chars().count();
    for (i, c) in chars[start..end].iter().enumerate() {
        if i + start == at {
            caret = out.chars().count();
        }
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(*c);
        }
    }
    if at >= end {
        caret = out.chars().count();
    }
    if end < chars.len() {
        out.push_str(&format!("... ({} characters)", chars.len()));
    }
    (out, caret)
}

/// `s` with every control character escaped as Rust writes it in a string literal (`\n`,
/// `\u{1b}`), so that a message is one line and cannot drive the terminal.
#[must_use]
pub fn escape_controls(s: &str) -> Cow<'_, str> {
    if !s.chars().any(char::is_control) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_excerpt_is_escaped_cut_and_keeps_its_caret_under_the_column() {
        let (e, c) = excerpt("C<RD>\u{1b}]0;x\u{7}K", 6);
        assert!(!e.chars().any(char::is_control), "{e}");
        assert_eq!(&e[c..c + 6], "\\u{1b}", "{e} {c}");
        let long = format!("{}K{}", "a".repeat(100_000), "b".repeat(100_000));
        let (e, c) = excerpt(&long, 100_001);
        assert!(e.len() < 120, "{}", e.len());
        assert!(
            e.starts_with("...") && e.ends_with("(200001 characters)"),
            "{e}"
        );
        assert_eq!(e.chars().nth(c), Some('K'));
        assert_eq!(
            excerpt("ab", 3),
            ("ab".to_string(), 2),
            "a caret past the end"
        );
    }

    #[test]
    fn bom_is_dropped_and_bad_bytes_are_placed() {
        assert_eq!(decode(b"\xef\xbb\xbfv 1 2 3".to_vec()).unwrap(), "v 1 2 3");
        assert_eq!(decode(b"ab".to_vec()).unwrap(), "ab");
        let e = decode(b"{\n  \"a\xff\": 1}".to_vec()).unwrap_err();
        assert_eq!((e.line, e.column, e.byte), (2, 5, 0xff));
        let e = decode(b"\x80".to_vec()).unwrap_err();
        assert_eq!((e.line, e.column), (1, 1));
        assert_eq!(strip_bom("\u{feff}{}"), "{}");
    }

    #[test]
    fn quoting_escapes_and_cuts() {
        assert_eq!(quote("a\nb"), r#""a\nb""#);
        assert_eq!(quote("\u{1b}[31m"), r#""\u{1b}[31m""#);
        let long = "x".repeat(1000);
        let q = quote(&long);
        assert!(q.len() < 100 && q.ends_with("(1000 characters)"), "{q}");
        assert_eq!(escape_controls("a\nerror: b\u{1b}"), "a\\nerror: b\\u{1b}");
        assert!(matches!(escape_controls("plain é"), Cow::Borrowed(_)));
    }
}
