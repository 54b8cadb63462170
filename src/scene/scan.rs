//! One linear pass over the scene text before serde sees it, for what serde accepts silently:
//! a key defined twice in one object (serde_json keeps the last, and a struct's derived
//! deserialiser takes the last or fails far from it), and an array where the format wants an
//! object (serde fills a struct from a sequence in field order: `"settings": [3, 7]` would be
//! max_depth 3, spp 7). Syntax errors are left to serde, which reports them well.
//!
//! Iterative (no recursion, whatever the nesting) and linear in the text: each byte is looked
//! at a bounded number of times.

use super::SceneError;
use super::path::{self, Seg};
use crate::input::quote;
use std::collections::HashMap;

enum Frame {
    /// An object: the keys seen so far and where.
    Object(HashMap<String, usize>),
    /// An array: the index of the current element.
    Array(usize),
}

/// Reject duplicate keys and arrays in place of objects, with the path and position of the
/// offending key or value.
pub(super) fn scan(src: &str) -> Result<(), SceneError> {
    let b = src.as_bytes();
    let mut pos = ws(b, 0);
    let mut path: Vec<Seg> = Vec::new();
    let mut frames: Vec<Frame> = Vec::new();
    loop {
        // A value starts at `pos`, at `path`.
        shape_check(src, &path, b.get(pos).copied(), pos)?;
        match b.get(pos) {
            Some(b'{') => {
                pos = ws(b, pos + 1);
                if b.get(pos) == Some(&b'}') {
                    pos += 1;
                } else {
                    let mut keys = HashMap::new();
                    let Some((next, seg)) = key(src, pos, &path, &mut keys)? else {
                        return Ok(());
                    };
                    frames.push(Frame::Object(keys));
                    path.push(seg);
                    pos = next;
                    continue;
                }
            }
            Some(b'[') => {
                pos = ws(b, pos + 1);
                if b.get(pos) == Some(&b']') {
                    pos += 1;
                } else {
                    frames.push(Frame::Array(0));
                    path.push(Seg::Index(0));
                    continue;
                }
            }
            Some(b'"') => match skip_string(b, pos) {
                Some(p) => pos = p,
                None => return Ok(()),
            },
            Some(_) => pos = skip_scalar(b, pos),
            None => return Ok(()),
        }
        // A value ended just before `pos`: close what it completes.
        loop {
            pos = ws(b, pos);
            let Some(frame) = frames.last_mut() else {
                return Ok(());
            };
            path.pop();
            match (frame, b.get(pos)) {
                (Frame::Object(keys), Some(b',')) => {
                    let Some((next, seg)) = key(src, ws(b, pos + 1), &path, keys)? else {
                        return Ok(());
                    };
                    path.push(seg);
                    pos = next;
                    break;
                }
                (Frame::Array(i), Some(b',')) => {
                    *i += 1;
                    path.push(Seg::Index(*i));
                    pos = ws(b, pos + 1);
                    break;
                }
                (Frame::Object(_), Some(b'}')) | (Frame::Array(_), Some(b']')) => {
                    frames.pop();
                    pos += 1;
                }
                _ => return Ok(()),
            }
        }
    }
}

/// Read the member name at `pos` of the object at `parent` and its `:`; record it in `keys`
/// (a duplicate is an error at the second). `Ok(None)` on a syntax error (serde reports it);
/// otherwise the position of the member's value and the member's segment.
fn key(
    src: &str,
    pos: usize,
    parent: &[Seg],
    keys: &mut HashMap<String, usize>,
) -> Result<Option<(usize, Seg)>, SceneError> {
    let b = src.as_bytes();
    if b.get(pos) != Some(&b'"') {
        return Ok(None);
    }
    let Some(end) = skip_string(b, pos) else {
        return Ok(None);
    };
    let raw = &src[pos + 1..end - 1];
    let name = if raw.contains('\\') {
        match serde_json::from_str::<String>(&src[pos..end]) {
            Ok(s) => s,
            Err(_) => return Ok(None),
        }
    } else {
        raw.to_string()
    };
    let colon = ws(b, end);
    if b.get(colon) != Some(&b':') {
        return Ok(None);
    }
    if let Some(&first) = keys.get(&name) {
        let (l, c) = super::locate::line_col(src, first);
        let mut p = parent.to_vec();
        p.push(Seg::Key(name.clone()));
        return Err(error(
            src,
            path::join(&p),
            pos,
            format!("duplicate key {} (first defined at {l}:{c})", quote(&name)),
        ));
    }
    keys.insert(name.clone(), pos);
    Ok(Some((ws(b, colon + 1), Seg::Key(name))))
}

fn error(src: &str, path: String, pos: usize, message: String) -> SceneError {
    let (l, c) = super::locate::line_col(src, pos);
    SceneError {
        path,
        line: Some(l),
        column: Some(c),
        message,
    }
}

fn is(seg: &Seg, name: &str) -> bool {
    matches!(seg, Seg::Key(k) if k == name)
}

/// Where the format wants an object (a struct or a map): the document, `camera`, `settings`,
/// `settings.offset`, `materials` and each material, a checker, each object and light.
fn wants_object(p: &[Seg]) -> bool {
    match p {
        [] => true,
        [a] => is(a, "camera") || is(a, "settings") || is(a, "materials"),
        [a, b] => {
            (is(a, "settings") && is(b, "offset"))
                || (is(a, "materials") && matches!(b, Seg::Key(_)))
                || ((is(a, "objects") || is(a, "lights")) && matches!(b, Seg::Index(_)))
        }
        [a, Seg::Key(_), c, d] => is(a, "materials") && is(c, "diffuse") && is(d, "checker"),
        _ => false,
    }
}

/// The elements of a `diffuse` array are numbers (`[r, g, b]`); anything nested would be
/// read as a checker given by position.
fn wants_number(p: &[Seg]) -> bool {
    matches!(p, [a, Seg::Key(_), c, Seg::Index(_)] if is(a, "materials") && is(c, "diffuse"))
}

fn shape_check(src: &str, p: &[Seg], first: Option<u8>, pos: usize) -> Result<(), SceneError> {
    let got = match first {
        Some(b'[') => "an array",
        Some(b'{') => "an object",
        _ => return Ok(()),
    };
    if wants_object(p) && first == Some(b'[') {
        return Err(error(
            src,
            path::join(p),
            pos,
            "expected an object {...} with named fields, got an array".into(),
        ));
    }
    if wants_number(p) {
        return Err(error(
            src,
            path::join(p),
            pos,
            format!("expected a number, got {got}"),
        ));
    }
    Ok(())
}

fn ws(b: &[u8], mut pos: usize) -> usize {
    while pos < b.len() && matches!(b[pos], b' ' | b'\t' | b'\n' | b'\r') {
        pos += 1;
    }
    pos
}

/// Position just past the string starting at `pos`.
pub(super) fn skip_string(b: &[u8], mut pos: usize) -> Option<usize> {
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

/// Position just past a number or literal starting at `pos` (at least one byte on).
fn skip_scalar(b: &[u8], pos: usize) -> usize {
    let mut p = pos + 1;
    while p < b.len()
        && !matches!(b[p], b',' | b'}' | b']' | b'"' | b'{' | b'[' | b':')
        && !b[p].is_ascii_whitespace()
    {
        p += 1;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(src: &str) -> SceneError {
        scan(src).unwrap_err()
    }

    #[test]
    fn duplicate_keys_are_found_at_the_second_anywhere() {
        let e = err("{\"materials\": {\"m\": {}, \"m\": {\"ior\": 1}}}");
        assert_eq!(e.path, "materials.m");
        assert_eq!((e.line, e.column), (Some(1), Some(25)));
        assert!(e.message.contains("first defined at 1:16"), "{e}");
        let e = err("{\"objects\": [{}, {\"radius\": 1, \"center\": [0,0,0], \"radius\": 2}]}");
        assert_eq!(e.path, "objects[1].radius");
        // Escaped spellings of the same key are the same key.
        let e = err("{\"a.b\": 1, \"a\\u002eb\": 2}");
        assert_eq!(e.path, "[\"a.b\"]");
        assert!(
            scan("{\"a\": {\"x\": 1}, \"b\": {\"x\": 1}, \"c\": [{\"x\": 1}, {\"x\": 2}]}").is_ok()
        );
    }

    #[test]
    fn arrays_where_objects_belong_are_refused() {
        for (src, path) in [
            ("[1]", ""),
            ("{\"settings\": [3, 7]}", "settings"),
            ("{\"camera\": [[0,0,5],[0,0,0]]}", "camera"),
            (
                "{\"settings\": {\"offset\": [\"ray\", 1]}}",
                "settings.offset",
            ),
            ("{\"materials\": {\"m\": [[1,1,1]]}}", "materials.m"),
            ("{\"materials\": []}", "materials"),
            ("{\"objects\": [{}, [\"sphere\"]]}", "objects[1]"),
            ("{\"lights\": [[\"point\"]]}", "lights[0]"),
            (
                "{\"materials\": {\"m\": {\"diffuse\": {\"checker\": [[1,1,1],[0,0,0],1]}}}}",
                "materials.m.diffuse.checker",
            ),
            (
                "{\"materials\": {\"m\": {\"diffuse\": [{\"even\": [1,1,1]}]}}}",
                "materials.m.diffuse[0]",
            ),
        ] {
            assert_eq!(err(src).path, path, "{src}");
        }
        // Triples and lists stay arrays.
        assert!(scan("{\"objects\": [], \"background\": [1,2,3], \"materials\": {\"m\": {\"diffuse\": [1,2,3]}}}").is_ok());
    }

    #[test]
    fn syntax_errors_are_left_to_serde_and_deep_nesting_is_fine() {
        for src in [
            "",
            "{",
            "{\"a\" 1}",
            "{\"a\": [1,}",
            "{\"a\": \"x",
            "]",
            "{,}",
        ] {
            assert!(scan(src).is_ok(), "{src}");
        }
        let deep = format!("{{\"x\": {}{}}}", "[".repeat(100_000), "]".repeat(100_000));
        assert!(scan(&deep).is_ok());
    }
}
