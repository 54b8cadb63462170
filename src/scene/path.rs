//! JSON paths in error messages: `objects[3].radius`, and `materials["a.b"]` for a key that is
//! not a plain name, so that every path reads back unambiguously ([`parse`]) whatever the key
//! holds (dots, brackets, quotes, newlines, escape characters).

/// One step of a JSON path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Seg {
    /// An object member.
    Key(String),
    /// An array element.
    Index(usize),
}

/// Whether `name` prints bare after a dot: ASCII letters, digits, `_` and `-`, not starting
/// with a digit or `-`.
fn is_plain(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The path of member `name` of the object at `parent` (`""` for the document).
#[must_use]
pub(super) fn key(parent: &str, name: &str) -> String {
    if is_plain(name) {
        if parent.is_empty() {
            name.to_string()
        } else {
            format!("{parent}.{name}")
        }
    } else {
        // A JSON string literal: quotes, backslashes and control characters escaped.
        let quoted = serde_json::to_string(name).unwrap_or_default();
        format!("{parent}[{quoted}]")
    }
}

/// The path of element `i` of the array at `parent`.
#[must_use]
pub(super) fn index(parent: &str, i: usize) -> String {
    format!("{parent}[{i}]")
}

/// The path of the segments `segs` from the document.
#[must_use]
pub(super) fn join(segs: &[Seg]) -> String {
    let mut p = String::new();
    for s in segs {
        p = match s {
            Seg::Key(k) => key(&p, k),
            Seg::Index(i) => index(&p, *i),
        };
    }
    p
}

/// The segments of a path written by [`key`] and [`index`]; `None` if it is not one.
#[must_use]
pub(super) fn parse(path: &str) -> Option<Vec<Seg>> {
    let b = path.as_bytes();
    let mut segs = Vec::new();
    let mut pos = 0;
    let plain = |pos: usize| {
        let end = b[pos..]
            .iter()
            .position(|&c| c == b'.' || c == b'[')
            .map_or(b.len(), |e| pos + e);
        (end > pos).then(|| (path[pos..end].to_string(), end))
    };
    if pos < b.len() && b[pos] != b'[' {
        let (k, end) = plain(pos)?;
        segs.push(Seg::Key(k));
        pos = end;
    }
    while pos < b.len() {
        match b[pos] {
            b'.' => {
                let (k, end) = plain(pos + 1)?;
                segs.push(Seg::Key(k));
                pos = end;
            }
            b'[' if b.get(pos + 1) == Some(&b'"') => {
                // A JSON string literal up to its closing quote, then `]`.
                let mut end = pos + 2;
                while end < b.len() && b[end] != b'"' {
                    end += if b[end] == b'\\' { 2 } else { 1 };
                }
                let k: String = serde_json::from_str(path.get(pos + 1..=end)?).ok()?;
                if b.get(end + 1) != Some(&b']') {
                    return None;
                }
                segs.push(Seg::Key(k));
                pos = end + 2;
            }
            b'[' => {
                let end = pos + b[pos..].iter().position(|&c| c == b']')?;
                segs.push(Seg::Index(path[pos + 1..end].parse().ok()?));
                pos = end + 1;
            }
            _ => return None,
        }
    }
    Some(segs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_names_print_bare_and_others_quoted() {
        assert_eq!(key("", "camera"), "camera");
        assert_eq!(key("materials", "glass-ball"), "materials.glass-ball");
        assert_eq!(key("materials", "a.b"), r#"materials["a.b"]"#);
        assert_eq!(key("materials", "x[0]"), r#"materials["x[0]"]"#);
        assert_eq!(
            key("materials", "a\"]\n\u{1b}"),
            r#"materials["a\"]\n\u001b"]"#
        );
        assert_eq!(key("materials", ""), r#"materials[""]"#);
        assert_eq!(index("objects", 3), "objects[3]");
    }

    #[test]
    fn every_path_reads_back() {
        let names = [
            "a",
            "a.b",
            "[",
            "]",
            "\"",
            "\\",
            "a\"].x",
            "\n",
            "\u{1b}[31m",
            "é",
            "",
            "0",
            "-x",
        ];
        for n in names {
            let segs = vec![
                Seg::Key("materials".into()),
                Seg::Key(n.into()),
                Seg::Index(2),
                Seg::Key(n.into()),
            ];
            assert_eq!(parse(&join(&segs)), Some(segs.clone()), "{n:?}");
        }
        assert_eq!(parse(""), Some(vec![]));
        assert_eq!(parse("objects[x]"), None);
        assert_eq!(parse("a..b"), None);
    }
}
