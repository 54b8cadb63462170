//! Loading scenes and applying command-line overrides, with errors that name the file.

use super::args::Overrides;
use anyhow::{Context, Result, anyhow, bail};
use raytree::Scene;
use serde::de::DeserializeOwned;
use std::path::Path;

/// A loaded scene and how to name it in messages.
pub struct Loaded {
    /// The scene with overrides applied.
    pub scene: Scene,
    /// The file name, or `<built-in classic>`.
    pub label: String,
}

/// Read and validate `path` (or the built-in scene), then apply `o`.
pub fn load(path: Option<&Path>, o: &Overrides) -> Result<Loaded> {
    let (mut scene, label) = match path {
        None => (Scene::default_scene(), "<built-in classic>".to_string()),
        Some(p) => {
            let label = p.display().to_string();
            let src =
                std::fs::read_to_string(p).with_context(|| format!("cannot read scene {label}"))?;
            let dir = p.parent().unwrap_or(Path::new(""));
            let scene = Scene::from_json_with(&src, &mut |file| read_obj(dir, file))
                .map_err(|e| anyhow!("{label}:{e}"))?;
            (scene, label)
        }
    };
    apply(&mut scene, o)?;
    Ok(Loaded { scene, label })
}

/// Read and parse the OBJ `file` (relative paths against the scene's directory `dir`); errors
/// name the file and, for bad contents, the line ([`raytree::mesh::parse_obj_read`]).
pub fn read_obj(dir: &Path, file: &str) -> Result<raytree::mesh::MeshData, String> {
    let path = dir.join(file);
    raytree::mesh::parse_obj_read(file, &path, std::fs::read_to_string(&path))
}

fn enum_value<T: DeserializeOwned>(flag: &str, v: &str) -> Result<T> {
    serde_json::from_value(serde_json::Value::String(v.to_string()))
        .map_err(|e| anyhow!("--{flag}: unknown value {v:?} ({e})"))
}

/// Parse `X,Y` or `WxH`-style pairs.
pub fn pair(flag: &str, v: &str, sep: char) -> Result<(u32, u32)> {
    let parse = |s: &str| s.trim().parse::<u32>().ok();
    match v.split_once(sep).map(|(a, b)| (parse(a), parse(b))) {
        Some((Some(a), Some(b))) => Ok((a, b)),
        _ => bail!("--{flag}: expected two whole numbers separated by '{sep}', got {v:?}"),
    }
}

/// Apply overrides and re-validate the settings.
pub fn apply(scene: &mut Scene, o: &Overrides) -> Result<()> {
    let s = &mut scene.settings;
    if let Some(v) = o.spp {
        s.spp = v;
    }
    if let Some(v) = o.max_depth {
        s.max_depth = v;
    }
    if let Some(v) = o.epsilon {
        s.offset.epsilon = v;
    }
    if let Some(v) = &o.offset {
        s.offset.strategy = enum_value("offset", v)?;
    }
    if let Some(v) = &o.fresnel {
        s.fresnel = enum_value("fresnel", v)?;
    }
    if let Some(v) = &o.shadows {
        s.shadows = enum_value("shadows", v)?;
    }
    if let Some(v) = o.min_weight {
        s.min_weight = v;
    }
    if let Some(v) = &o.integrator {
        s.integrator = raytree::scene::IntegratorKind::from_name(v)
            .map_err(|msg| anyhow!("--integrator: {msg}"))?;
    }
    if let Some(v) = o.seed {
        s.seed = v;
    }
    raytree::scene::check_settings(s).map_err(|(path, msg)| {
        let flag = path.rsplit('.').next().unwrap_or(&path).replace('_', "-");
        anyhow!("--{flag}: {msg}")
    })?;
    if let Some(size) = &o.size {
        let (w, h) = pair("size", size, 'x')?;
        if w == 0 || h == 0 || w > 65_536 || h > 65_536 {
            bail!("--size: width and height must be in 1..=65536, got {size}");
        }
        scene.camera = scene.camera.with_size(w, h);
    }
    Ok(())
}
