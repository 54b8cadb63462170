//! Find the line:column of a JSON path (`objects[3].radius`) in the source text.
//!
//! serde reports positions only for syntax and type errors; validation happens after parsing,
//! so this small scanner walks the text again to point at the offending value.

/// One step of a JSON path.
#[derive(Debug, PartialEq)]
enum Seg {
    Key(String),
    Index(usize),
}

fn parse_path(path: &str) -> Option<Vec<Seg>> {
    let mut segs = Vec::new();
    for part in path.split('.').filter(|p| !p.is_empty()) {
        let (key, mut rest) = part.split_at(part.find('[').unwrap_or(part.len()));
        if !key.is_empty() {
            segs.push(Seg::Key(key.to_string()));
        }
        while let Some(stripped) = rest.strip_prefix('[') {
            let end = stripped.find(']')?;
            segs.push(Seg::Index(stripped[..end].parse().ok()?));
            rest = &stripped[end + 1..];
        }
    }
    Some(segs)
}

/// 1-based line and column of the value at `path` in `src`, if it is there.
#[must_use]
pub fn locate(src: &str, path: &str) -> Option<(usize, usize)> {
    let b = src.as_bytes();
    let mut pos = ws(b, 0);
    for seg in parse_path(path)? {
        pos = match seg {
            Seg::Key(k) => member(b, pos, &k)?,
            Seg::Index(i) => element(b, pos, i)?,
        };
    }
    Some(line_col(src, pos))
}

fn line_col(src: &str, pos: usize) -> (usize, usize) {
    let before = &src[..pos.min(src.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
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
fn member(b: &[u8], pos: usize, key: &str) -> Option<usize> {
    if b.get(pos) != Some(&b'{') {
        return None;
    }
    let mut pos = ws(b, pos + 1);
    while b.get(pos) == Some(&b'"') {
        let end = skip_string(b, pos)?;
        let name = std::str::from_utf8(&b[pos + 1..end - 1]).ok()?;
        pos = ws(b, end);
        if b.get(pos) != Some(&b':') {
            return None;
        }
        pos = ws(b, pos + 1);
        if name == key {
            return Some(pos);
        }
        pos = ws(b, skip_value(b, pos)?);
        if b.get(pos) == Some(&b',') {
            pos = ws(b, pos + 1);
        }
    }
    None
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
fn skip_value(b: &[u8], pos: usize) -> Option<usize> {
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
    fn missing_paths_are_none() {
        assert_eq!(locate(SRC, "objects[2].radius"), None);
        assert_eq!(locate(SRC, "lights"), None);
        assert_eq!(locate("[1,", "[5]"), None);
        assert_eq!(locate("", "a"), None);
    }
}
