//! `raytree convert`: the raytree JSON of a pbrt-v4, Mitsuba 3 (or raytree) scene, so it can be
//! edited, diffed and versioned. Approximations are printed on stderr as `note: file:line: ...`.

use super::args::ConvertArgs;
use super::load_formats as lf;
use super::output::{Inputs, Pending};
use super::read::read_limited;
use super::say::warnln;
use anyhow::{Result, anyhow};
use raytree::input::{MAX_SCENE_BYTES, escape_controls};
use std::path::PathBuf;

/// Convert, validate, and write the JSON atomically.
pub fn run(a: &ConvertArgs) -> Result<()> {
    let p = &a.scene;
    let label = escape_controls(&p.display().to_string()).into_owned();
    let mut inputs = vec![p.clone()];
    // Refuse an output that is the scene before reading anything else.
    let pending = Pending::create(&a.output, &Inputs::new(inputs.iter().map(PathBuf::as_path)))?;
    let bytes =
        read_limited(p, MAX_SCENE_BYTES).map_err(|e| anyhow!("cannot read scene {label}: {e}"))?;
    let format = raytree::formats::Format::detect(&p.to_string_lossy(), &bytes);
    let desc = if lf::is_foreign(format) {
        let f = lf::convert(p, &bytes, format, &lf::defines(&a.define)?, &mut inputs)?;
        for line in lf::note_lines(&f.notes) {
            warnln!("{line}");
        }
        lf::validate(&label, &f.desc)?;
        f.desc
    } else {
        let src = raytree::input::decode(bytes).map_err(|e| anyhow!("{label}:{e}"))?;
        let dir = p.parent().unwrap_or(std::path::Path::new(""));
        raytree::Scene::from_json_with(&src, &mut |file| super::read::read_obj(dir, file))
            .map_err(|e| anyhow!("{label}:{e}"))?;
        serde_json::from_str(raytree::input::strip_bom(&src))?
    };
    // The files the scene read may not be overwritten either.
    let all = Inputs::new(inputs.iter().map(PathBuf::as_path));
    drop(pending);
    let pending = Pending::create(&a.output, &all)?;
    let mut json = String::new();
    write_json(&serde_json::to_value(&desc)?, 0, &mut json);
    json.push('\n');
    pending.commit(json.as_bytes())
}

/// Pretty JSON with arrays of numbers (points, colours, triangles) on one line, so a converted
/// mesh reads one vertex per line; keys sorted, but a `"type"` key first.
fn write_json(v: &serde_json::Value, indent: usize, out: &mut String) {
    use serde_json::Value;
    let pad = |n: usize| "  ".repeat(n);
    match v {
        Value::Array(a) if a.iter().all(|x| !x.is_array() && !x.is_object()) => {
            let items: Vec<String> = a.iter().map(Value::to_string).collect();
            out.push_str(&format!("[{}]", items.join(", ")));
        }
        Value::Array(a) if a.is_empty() => out.push_str("[]"),
        Value::Array(a) => {
            out.push_str("[\n");
            for (i, x) in a.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                write_json(x, indent + 1, out);
                out.push_str(if i + 1 < a.len() { ",\n" } else { "\n" });
            }
            out.push_str(&format!("{}]", pad(indent)));
        }
        Value::Object(m) if m.is_empty() => out.push_str("{}"),
        Value::Object(m) => {
            out.push_str("{\n");
            // A tagged value's "type" first, as the scene format writes it; the other keys in
            // order.
            let tag = m.get_key_value("type");
            let rest = m.iter().filter(|(k, _)| k.as_str() != "type");
            for (i, (k, x)) in tag.into_iter().chain(rest).enumerate() {
                out.push_str(&format!(
                    "{}{}: ",
                    pad(indent + 1),
                    Value::String(k.clone())
                ));
                write_json(x, indent + 1, out);
                out.push_str(if i + 1 < m.len() { ",\n" } else { "\n" });
            }
            out.push_str(&format!("{}}}", pad(indent)));
        }
        scalar => out.push_str(&scalar.to_string()),
    }
}
