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
