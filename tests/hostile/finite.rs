//! Whether a command's output is all finite: the tokens of its text, the numbers of its tree
//! JSON, its SVG's attributes and text, its EXR's pixels (the checks of `commands.rs`).

use serde_json::Value;
use std::path::Path;

/// Every token of `text` that a program would read as a non-finite number: Rust's and most
/// languages' spellings of NaN and infinity (`NaN`, `inf`, `-inf`, `infinity`), however cased.
pub fn nonfinite_tokens(text: &str) -> Vec<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || "+-._".contains(c)))
        .filter(|t| t.parse::<f64>().is_ok_and(|v| !v.is_finite()))
        .map(str::to_string)
        .take(5)
        .collect()
}

/// The first number in a JSON value that is missing: `null` inside an array (vectors and
/// colours are arrays of numbers; serde_json writes NaN and infinities as `null`).
pub fn null_in_array(v: &Value, path: &str, in_array: bool) -> Option<String> {
    match v {
        Value::Null if in_array => Some(path.to_string()),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, x)| null_in_array(x, &format!("{path}[{i}]"), true)),
        Value::Object(o) => o
            .iter()
            .find_map(|(k, x)| null_in_array(x, &format!("{path}.{k}"), false)),
        _ => None,
    }
}

/// Why the SVG is not all finite, if it is not: every attribute value and text node split into
/// tokens, none of which may read as a non-finite number, and every coordinate must parse.
pub fn svg_problem(svg: &str) -> Option<String> {
    let doc = match roxmltree::Document::parse(svg) {
        Ok(d) => d,
        Err(e) => return Some(format!("not XML: {e}")),
    };
    for n in doc.descendants() {
        if let Some(t) = n.text() {
            let bad = nonfinite_tokens(t);
            if !bad.is_empty() {
                return Some(format!("text {t:?}: {bad:?}"));
            }
        }
        for a in n.attributes() {
            let bad = nonfinite_tokens(a.value());
            if !bad.is_empty() {
                return Some(format!("{}={:?}", a.name(), a.value()));
            }
            let numeric = ["x", "y", "cx", "cy", "r", "width", "height", "font-size"];
            if numeric.contains(&a.name()) && !a.value().parse::<f64>().is_ok_and(f64::is_finite) {
                return Some(format!(
                    "{}={:?} is not a finite number",
                    a.name(),
                    a.value()
                ));
            }
            if a.name() == "points" {
                for c in a.value().split([' ', ',']).filter(|c| !c.is_empty()) {
                    if !c.parse::<f64>().is_ok_and(f64::is_finite) {
                        return Some(format!("points has {c:?}"));
                    }
                }
            }
        }
    }
    None
}

pub fn exr_problem(path: &Path) -> Option<String> {
    let img = match image::open(path) {
        Ok(i) => i.into_rgb32f(),
        Err(e) => return Some(format!("unreadable EXR: {e}")),
    };
    let bad = img
        .pixels()
        .flat_map(|p| p.0)
        .filter(|v| !v.is_finite())
        .count();
    (bad > 0).then(|| format!("{bad} non-finite channels"))
}

pub fn tree_json_problem(stdout: &str) -> Option<String> {
    let v: Value = match serde_json::from_str(stdout) {
        Ok(v) => v,
        Err(e) => return Some(format!("not JSON (a NaN or inf token?): {e}")),
    };
    if let Some(p) = null_in_array(&v, "", false) {
        return Some(format!("null where a number belongs at {p}"));
    }
    // Every number that is not optional in the schema is typed: a null there fails here.
    serde_json::from_value::<raytree::RayTree>(v)
        .err()
        .map(|e| format!("not a tree: {e}"))
}
