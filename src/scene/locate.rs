//! Find the line:column of a JSON path (`objects[3].radius`) in the source text.
//!
//! serde reports positions only for syntax and type errors; validation happens after parsing,
//! so this small scanner walks the text again to point at the offending value.

use super::path::{Seg, parse};

/// 1-based line and column of the value at `path` in `src`, if it is there.
#[must_use]
pub fn locate(src: &str, path: &str) -> Option<(usize, usize)> {
    position(src, path).map(|pos| line_col(src, pos))
}

/// Byte offset of the value at `path` in `src`. One walk along the path, skipping siblings:
/// linear in the text.
pub(super) fn position(src: &str, path: &str) -> Option<usize> {
    let b = src.as_bytes();
    let mut pos = ws(b, 0);
    for seg in parse(path)? {
        pos = match seg {
            Seg::Key(k) => member(src, pos, &k)?,
            Seg::Index(i) => element(b, pos, i)?,
        };
    }
    Some(pos)
}

/// 1-based line and byte column of byte `pos` of `src` (as serde_json counts).
pub(super) fn line_col(src: &str, pos: usize) -> (usize, usize) {
    let before = &src.as_bytes()[..pos.min(src.len())];
    let line = before.iter().filter(|&&c| c == b'\n').count() + 1;
    let col = before
        .iter()
        .rposition(|&c| c == b'\n')
        .map_or(before.len(), |i| before.len() - i - 1)
        + 1;
    (line, col)
}

fn ws(b: &[u8], mut pos: usize) -> usize {
    while pos < b.len() && b[pos].is_ascii_whitespace() {
        pos += 1;
    }
    pos
}

/// Position of the value of member `key` of the object starting at `pos`.
fn member(src: &str, pos: usize, key: &str) -> Option<usize> {
    let mut found = None;
    members(src, pos, |name, at| {
        if name == key {
            found = Some(at);
        }
        found.is_none()
    })?;
    found
}

/// Call `f(name, value position)` for each member of the object starting at `pos`, in
/// document order, while it returns true; `None` if the text there is not an object.
pub(super) fn members(src: &str, pos: usize, mut f: impl FnMut(&str, usize) -> bool) -> Option<()> {
    let b = src.as_bytes();
    if b.get(pos) != Some(&b'{') {
        return None;
    }
    let mut pos = ws(b, pos + 1);
    while b.get(pos) == Some(&b'"') {
        let end = skip_string(b, pos)?;
        let raw = src.get(pos + 1..end - 1)?;
        let decoded;
        let name = if raw.contains('\\') {
            decoded = serde_json::from_str::<String>(&src[pos..end]).ok()?;
            decoded.as_str()
        } else {
            raw
        };
        pos = ws(b, end);
        if b.get(pos) != Some(&b':') {
            return None;
        }
        pos = ws(b, pos + 1);
        if !f(name, pos) {
            return Some(());
        }
        pos = ws(b, skip_value(b, pos)?);
        if b.get(pos) == Some(&b',') {
            pos = ws(b, pos + 1);
        }
    }
    Some(())
}

/// Position of element `index` of the array starting at `pos`.
fn element(b: &[u8], pos: usize, index: usize) -> Option<usize> {
    if b.get(pos) != Some(&b'[') {
        return None;
    }
    let mut pos = ws(b, pos + 1);
    for _ in 0..index {
        if b.get(pos) == Some(&b']') {
            return None;
        }
        pos = ws(b, skip_value(b, pos)?);
        if b.get(pos) != Some(&b',') {
            return None;
        }
        pos = ws(b, pos + 1);
    }
    (b.get(pos) != Some(&b']') && pos < b.len()).then_some(pos)
}

/// Position just past the string starting at `pos`.
fn skip_string(b: &[u8], mut pos: usize) -> Option<usize> {
    pos += 1;
    while pos < b.len() {
        match b[pos] {
            b'\\' => pos += 2,
            b'"' => return Some(pos + 1),
            _ => pos += 1,
        }
    }
    None
}

/// Position just past the value starting at `pos`.
pub(super) fn skip_value(b: &[u8], pos: usize) -> Option<usize> {
    match b.get(pos)? {
        b'"' => skip_string(b, pos),
        b'{' | b'[' => {
            let mut depth = 0usize;
            let mut p = pos;
            while p < b.len() {
                match b[p] {
                    b'"' => {
                        p = skip_string(b, p)?;
                        continue;
                    }
                    b'{' | b'[' => depth += 1,
                    b'}' | b']' => {
                        depth -= 1;
                        if depth == 0 {
                            return Some(p + 1);
                        }
                    }
                    _ => {}
                }
                p += 1;
            }
            None
        }
        _ => {
            let mut p = pos;
            while p < b.len() && !matches!(b[p], b',' | b'}' | b']') && !b[p].is_ascii_whitespace()
            {
                p += 1;
            }
            Some(p)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SRC: &str = "{\n  \"objects\": [\n    {\"type\": \"sphere\", \"radius\": 1},\n    {\"name\": \"a,]}\", \"radius\": -2}\n  ],\n  \"camera\": {\"fov_y\": 0}\n}";

    #[test]
    fn finds_nested_values() {
        assert_eq!(locate(SRC, "objects[1].radius"), Some((4, 32)));
        assert_eq!(locate(SRC, "objects[0].radius"), Some((3, 34)));
        assert_eq!(locate(SRC, "camera.fov_y"), Some((6, 23)));
        assert_eq!(locate(SRC, "objects[1]"), Some((4, 5)));
    }

    #[test]
    fn keys_with_dots_brackets_and_escapes_are_found() {
        let src = "{\"materials\": {\"a.b\": 1, \"x[0]\": 2, \"q\\\"\\n\": 3, \"e\\u001b\": 4}}";
        assert_eq!(locate(src, r#"materials["a.b"]"#), Some((1, 23)));
        assert_eq!(locate(src, r#"materials["x[0]"]"#), Some((1, 34)));
        assert_eq!(locate(src, r#"materials["q\"\n"]"#), Some((1, 46)));
        assert_eq!(locate(src, r#"materials["e\u001b"]"#), Some((1, 60)));
        assert_eq!(locate(src, "materials.a"), None);
    }

    #[test]
    fn missing_paths_are_none() {
        assert_eq!(locate(SRC, "objects[2].radius"), None);
        assert_eq!(locate(SRC, "lights"), None);
        assert_eq!(locate("[1,", "[5]"), None);
        assert_eq!(locate("", "a"), None);
    }
}
