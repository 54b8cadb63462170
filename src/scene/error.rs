//! [`SceneError`], and serde_json's messages reworded for it.

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
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let (Some(l), Some(c)) = (self.line, self.column) {
            write!(f, "{l}:{c}: ")?;
        }
        if !self.path.is_empty() {
            write!(f, "{}: ", self.path)?;
        }
        f.write_str(&self.message)
    }
}

/// Strip serde_json's " at line L column C" suffix (the position is reported separately).
pub(super) fn bare_message(e: &serde_json::Error) -> String {
    let s = e.to_string();
    match s.rfind(" at line ") {
        Some(i) => s[..i].to_string(),
        None => s,
    }
}

/// A path for an error inside `objects[i]` or `lights[i]`, which serde reports at the element
/// itself (an internally tagged enum is buffered, so the path stops there), and its position.
/// The offending member is found by elimination: the first member (not `type`) without which
/// the element no longer fails this way, deserialised again on its own. A path ending in an
/// unknown segment (`camera.?`, from a syntax error) loses that segment. Anything else is
/// returned as it came.
pub(super) fn field_of_tagged(
    src: &str,
    path: String,
    message: &str,
    at: (usize, usize),
) -> (String, (usize, usize)) {
    let path = match path.strip_suffix(".?").or(path.strip_suffix('?')) {
        Some(p) => p.to_string(),
        None => path,
    };
    let Some((list, index)) = tagged_element(&path) else {
        return (path, at);
    };
    if message.starts_with("unknown variant") || message.starts_with("missing field `type`") {
        let field = format!("{path}.type");
        let at = super::locate(src, &field).unwrap_or(at);
        return (field, at);
    }
    let Ok(doc) = serde_json::from_str::<serde_json::Value>(src) else {
        return (path, at);
    };
    let Some(serde_json::Value::Object(element)) = doc.get(list).and_then(|l| l.get(index)) else {
        return (path, at);
    };
    for key in element.keys().filter(|k| *k != "type") {
        let mut without = element.clone();
        without.remove(key);
        let result = if list == "objects" {
            serde_json::from_value::<super::desc::ObjectDesc>(without.into()).map(|_| ())
        } else {
            serde_json::from_value::<super::desc::LightDesc>(without.into()).map(|_| ())
        };
        let culprit = match result {
            Ok(()) => true,
            Err(e) => e.to_string().starts_with(&format!("missing field `{key}`")),
        };
        if culprit && !message.starts_with("missing field") {
            let field = format!("{path}.{key}");
            let at = super::locate(src, &field).unwrap_or(at);
            return (field, at);
        }
    }
    (path, at)
}

/// `("objects", i)` or `("lights", i)` when `path` is exactly such an element.
fn tagged_element(path: &str) -> Option<(&'static str, usize)> {
    for list in ["objects", "lights"] {
        if let Some(i) = path
            .strip_prefix(list)
            .and_then(|r| r.strip_prefix('['))
            .and_then(|r| r.strip_suffix(']'))
            .and_then(|r| r.parse().ok())
        {
            return Some((list, i));
        }
    }
    None
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
    if path.is_empty() {
        field.to_string()
    } else {
        format!("{path}.{field}")
    }
}
