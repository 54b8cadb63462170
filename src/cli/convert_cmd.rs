//! `raytree convert`: the raytree JSON of a pbrt-v4, Mitsuba 3 (or raytree) scene, so it can be
//! edited, diffed and versioned. Approximations are printed on stderr as `note: file:line: ...`.

use super::load::read_limited;
use super::load_formats as lf;
use super::output::{Inputs, Pending};
use super::say::warnln;
use anyhow::{Result, anyhow};
use clap::Args;
use raytree::input::{MAX_SCENE_BYTES, escape_controls};
use std::path::PathBuf;

/// `raytree convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    /// Scene: pbrt-v4 (.pbrt), Mitsuba 3 (.xml) or raytree JSON.
    pub scene: PathBuf,
    /// Output JSON (never one of the files the scene reads).
    #[arg(short, long, default_value = "scene.json")]
    pub output: PathBuf,
    /// Mitsuba scenes: give `$NAME` the value VALUE; repeatable.
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
}

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
        raytree::Scene::from_json_with(&src, &mut |file| super::load::read_obj(dir, file))
            .map_err(|e| anyhow!("{label}:{e}"))?;
        serde_json::from_str(raytree::input::strip_bom(&src))?
    };
    // The files the scene read may not be overwritten either.
    let all = Inputs::new(inputs.iter().map(PathBuf::as_path));
    drop(pending);
    let pending = Pending::create(&a.output, &all)?;
    let mut json = serde_json::to_string_pretty(&desc)?;
    json.push('\n');
    pending.commit(json.as_bytes())
}
