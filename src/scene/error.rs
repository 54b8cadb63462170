//! [`SceneError`], and serde_json's messages reworded for it.

use super::path::{self, Seg};
use crate::input::{escape_controls, quote};
use serde_json::Value;
use std::fmt;

/// A scene that failed to parse or validate.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct SceneError {
    /// JSON path of the offending value (`objects[3].radius`), empty for the document itself.
    pub path: String,
    /// 1-based line, where known.
    pub line: Option<usize>,
    /// 1-based column, where known.
    pub column: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for SceneError {
    /// `line:col: path: message`, on one line: control characters in the path or the message
    /// (which may quote the file's strings) are escaped.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let (Some(l), Some(c)) = (self.line, self.column) {
            write!(f, "{l}:{c}: ")?;
        }
        if !self.path.is_empty() {
            write!(f, "{}: ", escape_controls(&self.path))?;
        }
        f.write_str(&escape_controls(&self.message))
    }
}

/// serde_path_to_error's path in this crate's format ([`super::path`]): a key that is not a
/// plain name is quoted (`materials["a.b"]`); an unknown segment (after a syntax error) and
/// enum variants are left out.
pub(super) fn path_of(p: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let mut out = String::new();
    for seg in p {
        out = match seg {
            Segment::Seq { index } => path::index(&out, *index),
            Segment::Map { key } => path::key(&out, key),
            Segment::Enum { .. } | Segment::Unknown => out,
        };
    }
    out
}

/// serde's "unknown field `x`, expected ..." and "unknown variant `x`, expected ..." with the
/// user's string quoted by [`quote`] (escaped, and cut if long); other messages unchanged.
pub(super) fn reword(message: String) -> String {
    // A number too large for an integer field (seed 2^64) reaches serde as a float.
    for (int, range) in [
        ("u64", "0 to 18446744073709551615"),
        ("u32", "0 to 4294967295"),
    ] {
        if message.starts_with("invalid type: floating point")
            && message.ends_with(&format!("expected {int}"))
        {
            let got = message
                .split('`')
                .nth(1)
                .map_or(String::new(), |v| format!(", got {v}"));
            return format!("must be a whole number from {range}{got}");
        }
    }
    for what in ["unknown field `", "unknown variant `"] {
        let Some(rest) = message.strip_prefix(what) else {
            continue;
        };
        let cut = rest
            .rfind("`, expected ")
            .or_else(|| rest.rfind("`, there are no"));
        if let Some(i) = cut {
            let name = &rest[..i];
            let tail = &rest[i + 1..];
            return format!("{}{}{tail}", &what[..what.len() - 1], quote(name));
        }
    }
    message
}

/// Strip serde_json's " at line L column C" suffix (the position is reported separately).
pub(super) fn bare_message(e: &serde_json::Error) -> String {
    let s = e.to_string();
    match s.rfind(" at line ") {
        Some(i) => s[..i].to_string(),
        None => s,
    }
}

/// The members each `type` of object and light may have (besides `type`), as in
/// `desc::ObjectDesc` and `desc::LightDesc` (a test holds the two together).
const MEMBERS: [(&str, &str, &[&str]); 8] = [
    (
        "objects",
        "sphere",
        &["center", "radius", "material", "name"],
    ),
    ("objects", "plane", &["point", "normal", "material", "name"]),
    ("objects", "triangle", &["vertices", "material", "name"]),
    ("objects", "box", &["min", "max", "material", "name"]),
    (
        "objects",
        "mesh",
        &[
            "file",
            "translate",
            "rotate",
            "scale",
            "normals",
            "material",
            "name",
        ],
    ),
    ("lights", "point", &["position", "intensity", "name"]),
    (
        "lights",
        "spot",
        &[
            "position",
            "direction",
            "look_at",
            "intensity",
            "cone_angle",
            "falloff_angle",
            "profile",
            "name",
        ],
    ),
    (
        "lights",
        "directional",
        &["direction", "irradiance", "name"],
    ),
];

/// A path for an error inside `objects[i]` or `lights[i]`, which serde reports at the element
/// itself (an internally tagged enum is buffered, so the path stops there), and its position.
///
/// An unknown member is the first one, in document order, that the element's `type` does not
/// have. Any other error is found by elimination among the members the type does have (at
/// most seven, unknown ones set aside): the first whose removal changes the error. Each step
/// deserialises that small object again, so the cost is linear in the element's size, however
/// many members it has. Anything else is returned as it came.
pub(super) fn field_of_tagged(
    src: &str,
    path: String,
    message: &str,
    at: (usize, usize),
) -> (String, (usize, usize)) {
    let Some(list) = tagged_element(&path) else {
        return (path, at);
    };
    let found = |field: String| {
        let at = super::locate(src, &field).unwrap_or(at);
        (field, at)
    };
    if message.starts_with("missing field `type`") {
        return found(path::key(&path, "type"));
    }
    let b = src.as_bytes();
    let Some(start) = super::locate::position(src, &path) else {
        return (path, at);
    };
    let Some(end) = super::locate::skip_value(b, start) else {
        return (path, at);
    };
    let Ok(Value::Object(element)) = serde_json::from_str::<Value>(&src[start..end]) else {
        return (path, at);
    };
    let tag = element.get("type").and_then(Value::as_str).unwrap_or("");
    let Some(&(_, _, known)) = MEMBERS.iter().find(|m| m.0 == list && m.1 == tag) else {
        // An unknown variant with an unknown tag is the tag's (a known tag's unknown variant
        // is one of its members', as a spot light's `profile`: found below).
        if message.starts_with("unknown variant") {
            return found(path::key(&path, "type"));
        }
        return (path, at);
    };
    if message.starts_with("unknown field") {
        let mut unknown = None;
        super::locate::members(src, start, |name, _| {
            if name != "type" && !known.contains(&name) {
                unknown = Some(name.to_string());
            }
            unknown.is_none()
        });
        return match unknown {
            Some(k) => found(path::key(&path, &k)),
            None => (path, at),
        };
    }
    let mut base = element;
    base.retain(|k, _| k == "type" || known.contains(&k.as_str()));
    let error_of = |v: serde_json::Map<String, Value>| {
        let v = Value::Object(v);
        let r = if list == "objects" {
            serde_json::from_value::<super::desc::ObjectDesc>(v).map(|_| ())
        } else {
            serde_json::from_value::<super::desc::LightDesc>(v).map(|_| ())
        };
        r.err().map(|e| e.to_string())
    };
    let Some(original) = error_of(base.clone()) else {
        return (path, at);
    };
    let mut order = Vec::new();
    super::locate::members(src, start, |name, _| {
        if known.contains(&name) {
            order.push(name.to_string());
        }
        true
    });
    for key in order {
        let mut without = base.clone();
        without.remove(&key);
        if error_of(without).as_ref() != Some(&original) {
            return found(path::key(&path, &key));
        }
    }
    (path, at)
}

/// An error inside a tagged integrator value (`settings.integrator` or an element of
/// `settings.other_integrators`), which its reader reports at the value with the key first in
/// the message (`glossy_samples: invalid value ...`, or `unknown field "fresnel", ...`): the
/// key's own path and position, and the message without the key. Anything else, or a key the
/// text does not write, comes back as it was.
pub(super) fn key_in_integrator(
    src: &str,
    path: String,
    message: String,
    at: (usize, usize),
) -> (String, String, (usize, usize)) {
    let integrator = match path::parse(&path).as_deref() {
        Some([Seg::Key(s), Seg::Key(i)]) => s == "settings" && i == "integrator",
        Some([Seg::Key(s), Seg::Key(o), Seg::Index(_)]) => {
            s == "settings" && o == "other_integrators"
        }
        _ => false,
    };
    if !integrator {
        return (path, message, at);
    }
    let (key, rest) = if let Some(tail) = message.strip_prefix("unknown field \"") {
        (tail.split('"').next().unwrap_or(""), message.as_str())
    } else {
        match message.split_once(": ") {
            Some((k, rest)) => (k, rest),
            None => return (path, message, at),
        }
    };
    let is_key = !key.is_empty() && key.bytes().all(|b| b.is_ascii_lowercase() || b == b'_');
    let field = path::key(&path, key);
    match super::locate(src, &field) {
        Some(pos) if is_key => (field, rest.to_string(), pos),
        _ => (path, message, at),
    }
}

/// `"objects"` or `"lights"` when `path` is exactly an element of one.
fn tagged_element(path: &str) -> Option<&'static str> {
    match path::parse(path)?.as_slice() {
        [Seg::Key(list), Seg::Index(_)] => ["objects", "lights"].into_iter().find(|l| l == list),
        _ => None,
    }
}

/// serde reports a missing field at the path of the object that lacks it (empty for the
/// document); name the field itself, so that every rejection has a path (`camera`,
/// `objects[0].radius`).
pub(super) fn with_missing_field(path: String, message: &str) -> String {
    let Some(field) = message
        .strip_prefix("missing field `")
        .and_then(|r| r.split('`').next())
    else {
        return path;
    };
    path::key(&path, field)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names in serde's "expected one of `a`, `b`" for an unknown member of `json`.
    fn expected<T: serde::de::DeserializeOwned>(json: &str) -> Vec<String> {
        let e = serde_json::from_str::<T>(json)
            .err()
            .expect("unknown member");
        let msg = e.to_string();
        let list = &msg[msg.find("expected").expect("a list")..];
        list.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect()
    }

    #[test]
    fn the_member_table_matches_the_serde_types() {
        use crate::scene::desc::{LightDesc, ObjectDesc};
        for (list, tag, known) in MEMBERS {
            let json = format!("{{\"type\": \"{tag}\", \"zz\": 0}}");
            let names = if list == "objects" {
                expected::<ObjectDesc>(&json)
            } else {
                expected::<LightDesc>(&json)
            };
            let mut names: Vec<&str> = names.iter().map(String::as_str).collect();
            let mut known = known.to_vec();
            names.sort_unstable();
            known.sort_unstable();
            assert_eq!(names, known, "{tag}");
        }
    }

    #[test]
    fn reworded_messages_quote_the_users_string() {
        let m = reword("unknown field `a\u{1b}`, expected one of `x`".into());
        assert_eq!(m, "unknown field \"a\\u{1b}\", expected one of `x`");
        let m = reword("unknown variant `co`, expected `x`ne`, expected one of `a`".into());
        assert!(
            m.starts_with("unknown variant \"co`, expected `x`ne\", expected"),
            "{m}"
        );
        assert_eq!(reword("invalid type".into()), "invalid type");
    }
}
