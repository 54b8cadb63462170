//! Loading scenes and applying command-line overrides, with errors that name the file.

use super::args::Overrides;
use super::load_formats as lf;
use super::read::{read_limited, read_obj};
use super::say::warnln;
use anyhow::{Result, anyhow, bail};
use raytree::Scene;
use raytree::input::{MAX_SCENE_BYTES, escape_controls};
use raytree::scene::{IntegratorKind, WhittedSettings};
use serde::de::DeserializeOwned;
use std::path::Path;

/// A loaded scene and how to name it in messages.
pub struct Loaded {
    /// The scene with overrides applied.
    pub scene: Scene,
    /// The file name, or `<built-in classic>`.
    pub label: String,
    /// The files read: the scene and the OBJ meshes it references (outputs may not overwrite
    /// them).
    pub inputs: Vec<std::path::PathBuf>,
    /// What converting a pbrt or Mitsuba scene approximated (empty for JSON).
    pub notes: Vec<raytree::formats::Note>,
    /// For a JSON scene whose settings use the old spelling: the keys so written
    /// ([`raytree::scene::desc::old_spelling`]) and the file's settings in the new spelling.
    pub old_spelling: Option<String>,
}

/// Read and validate `path` (or the built-in scene), then apply `o`.
pub fn load(path: Option<&Path>, o: &Overrides) -> Result<Loaded> {
    let mut inputs = Vec::new();
    let mut notes = Vec::new();
    let mut old_spelling = None;
    let (mut scene, label) = match path {
        None => (Scene::default_scene(), "<built-in classic>".to_string()),
        Some(p) => {
            let label = escape_controls(&p.display().to_string()).into_owned();
            let bytes = read_limited(p, MAX_SCENE_BYTES)
                .map_err(|e| anyhow!("cannot read scene {label}: {e}"))?;
            let format = raytree::formats::Format::detect(&p.to_string_lossy(), &bytes);
            if lf::is_foreign(format) {
                inputs.push(p.to_path_buf());
                let defines = lf::defines(&o.define)?;
                let f = lf::convert(p, &bytes, format, &defines, &mut inputs)?;
                for line in lf::note_lines(&f.notes) {
                    warnln!("{line}");
                }
                notes = f.notes;
                (lf::validate(&label, &f.desc)?, label)
            } else {
                let src = raytree::input::decode(bytes).map_err(|e| anyhow!("{label}:{e}"))?;
                let dir = p.parent().unwrap_or(Path::new(""));
                inputs.push(p.to_path_buf());
                let scene = Scene::from_json_with(&src, &mut |file| {
                    inputs.push(dir.join(file));
                    read_obj(dir, file)
                })
                .map_err(|e| anyhow!("{label}:{e}"))?;
                old_spelling = old_spelling_note(&src, &scene.settings);
                (scene, label)
            }
        }
    };
    apply(&mut scene, o)?;
    if let Some(note) = ignored_flags(&scene, o) {
        warnln!("{note}");
    }
    if scene.settings.integrator != IntegratorKind::Whitted {
        let over = scene.overflowing_lights();
        if !over.is_empty() {
            warnln!(
                "warning: the power of {} overflows a 64-bit float; the path integrator's light sampling chooses it as if its power were the largest finite one",
                escape_controls(&over.join(", "))
            );
        }
    }
    Ok(Loaded {
        scene,
        label,
        inputs,
        notes,
        old_spelling,
    })
}

/// The keys `src` (a JSON scene) writes in the old spelling and `settings` (its settings) in
/// the new one, or `None` when it uses the new spelling.
fn old_spelling_note(src: &str, settings: &raytree::scene::Settings) -> Option<String> {
    let keys = raytree::scene::desc::old_spelling(src);
    (!keys.is_empty()).then(|| {
        format!(
            "{}; in the new spelling: {}",
            keys.join(", "),
            raytree::scene::desc::new_spelling(settings)
        )
    })
}

/// A note when flags the scene's integrator does not read were given, naming them: under the
/// path integrator the Whitted integrator's own flags, under Whitted `--rr-depth`, `--mis` under
/// every integrator but bdpt; `None`
/// otherwise.
pub fn ignored_flags(scene: &Scene, o: &Overrides) -> Option<String> {
    let mis = (o.mis.is_some() && scene.settings.integrator != IntegratorKind::Bdpt).then(|| {
        "note: --mis is read by --integrator bdpt alone (the path tracer always weighs its light \
         and BSDF samples by the power heuristic)"
            .to_string()
    });
    match (ignored_integrator_flags(scene, o), mis) {
        (Some(a), Some(b)) => Some(format!("{a}\n{b}")),
        (a, b) => a.or(b),
    }
}

/// [`ignored_flags`] but `--mis`.
fn ignored_integrator_flags(scene: &Scene, o: &Overrides) -> Option<String> {
    if scene.settings.integrator == IntegratorKind::Whitted {
        return o.rr_depth.is_some().then(|| {
            "note: the Whitted integrator ignores --rr-depth: it is the path integrator's \
             (add --integrator path)"
                .to_string()
        });
    }
    let flags = whitted_flags(o);
    (!flags.is_empty()).then(|| {
        let (list, are) = (
            flags.join(", "),
            if flags.len() > 1 { "they are" } else { "it is" },
        );
        let who = match scene.settings.integrator {
            IntegratorKind::Light => "light tracing",
            _ => "the path integrator",
        };
        format!(
            "note: {who} ignores {list}: {are} the Whitted integrator's ({})",
            WhittedSettings::WHY_OTHERS_IGNORE
        )
    })
}

/// The flags given in `o` that set the Whitted integrator's own settings
/// ([`WhittedSettings`]), in its fields' order.
fn whitted_flags(o: &Overrides) -> Vec<&'static str> {
    [
        ("--fresnel", o.fresnel.is_some()),
        ("--shadows", o.shadows.is_some()),
        ("--min-weight", o.min_weight.is_some()),
        ("--tolerance", o.tolerance.is_some()),
        ("--light-samples", o.light_samples.is_some()),
        ("--glossy-samples", o.glossy_samples.is_some()),
        ("--dielectric-roulette", o.dielectric_roulette.is_some()),
        ("--roulette-below", o.roulette_below.is_some()),
    ]
    .into_iter()
    .filter_map(|(flag, given)| given.then_some(flag))
    .collect()
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
    apply_whitted(&mut s.whitted, o)?;
    if let Some(v) = o.max_rays {
        s.max_rays = v;
    }
    if let Some(v) = &o.integrator {
        s.integrator = raytree::scene::IntegratorKind::from_name(v)
            .map_err(|msg| anyhow!("--integrator: {msg}"))?;
    }
    if let Some(v) = o.seed {
        s.seed = v;
    }
    if let Some(v) = o.rr_depth {
        s.path.rr_depth = v;
    }
    if let Some(v) = &o.mis {
        s.path.mis =
            raytree::scene::MisHeuristic::from_name(v).map_err(|msg| anyhow!("--mis: {msg}"))?;
    }
    apply_film_sampling(s, o)?;
    raytree::scene::check_settings(s).map_err(|(path, msg)| settings_error(&path, &msg))?;
    apply_camera(scene, o)
}

/// The sampler, pixel filter and antialiasing flags of `o` applied to `s`.
fn apply_film_sampling(s: &mut raytree::scene::Settings, o: &Overrides) -> Result<()> {
    if let Some(v) = &o.sampler {
        s.sampler = Some(
            raytree::scene::SamplerKind::from_name(v).map_err(|msg| anyhow!("--sampler: {msg}"))?,
        );
    }
    if let Some(v) = &o.filter {
        s.filter =
            raytree::scene::FilterDesc::parse(v).map_err(|msg| anyhow!("--filter: {msg}"))?;
    }
    if let Some(v) = &o.antialiasing {
        s.antialiasing = match v.as_str() {
            "auto" => raytree::scene::Antialiasing::Auto,
            "uniform" => raytree::scene::Antialiasing::Uniform,
            _ => bail!("--antialiasing: unknown mode {v:?}, expected auto or uniform"),
        };
    }
    if let Some(t) = o.adaptive {
        s.adaptive = Some(raytree::scene::AdaptiveDesc {
            threshold: t,
            max_spp: s.adaptive.and_then(|a| a.max_spp),
        });
    }
    if let Some(m) = o.max_spp {
        let Some(a) = &mut s.adaptive else {
            bail!("--max-spp: needs adaptive antialiasing (--adaptive THRESHOLD)");
        };
        a.max_spp = Some(m);
    }
    Ok(())
}

/// A settings check's failure (`path`, `msg`) named by the flag that set the value.
fn settings_error(path: &str, msg: &str) -> anyhow::Error {
    match path {
        "settings.adaptive" | "settings.adaptive.threshold" => {
            return anyhow!("--adaptive: {msg}");
        }
        "settings.adaptive.max_spp" => return anyhow!("--max-spp: {msg}"),
        _ => {}
    }
    let flag = path.rsplit('.').next().unwrap_or(path).replace('_', "-");
    if path.starts_with("settings.filter.") {
        return anyhow!("--filter: {flag} {msg}");
    }
    anyhow!("--{flag}: {msg}")
}

/// The lens and image-size flags of `o` applied to the camera of `scene`.
fn apply_camera(scene: &mut Scene, o: &Overrides) -> Result<()> {
    if let Some(v) = o.aperture {
        scene.camera.aperture_radius =
            raytree::scene::check_aperture(v).map_err(|msg| anyhow!("--aperture: {msg}"))?;
    }
    if let Some(v) = o.focus {
        scene.camera.focus_distance =
            raytree::scene::check_focus(v).map_err(|msg| anyhow!("--focus: {msg}"))?;
    }
    if let Some(size) = &o.size {
        let (w, h) = pair("size", size, 'x')?;
        if w == 0 || h == 0 || w > 65_536 || h > 65_536 {
            bail!("--size: width and height must be in 1..=65536, got {size}");
        }
        scene.camera = scene.camera.with_size(w, h);
    }
    Ok(())
}

/// The Whitted integrator's flags of `o` applied to `w`.
fn apply_whitted(w: &mut WhittedSettings, o: &Overrides) -> Result<()> {
    if let Some(v) = &o.fresnel {
        w.fresnel = enum_value("fresnel", v)?;
    }
    if let Some(v) = &o.shadows {
        w.shadows = enum_value("shadows", v)?;
    }
    if let Some(v) = o.min_weight {
        w.min_weight = Some(v);
    }
    if let Some(v) = o.tolerance {
        w.tolerance = v;
    }
    if let Some(v) = o.light_samples {
        w.light_samples = Some(v);
    }
    if let Some(v) = o.glossy_samples {
        w.glossy_samples = v;
    }
    if let Some(v) = o.dielectric_roulette {
        w.dielectric_roulette = Some(v);
    }
    if let Some(v) = o.roulette_below {
        w.roulette_below = Some(v);
    }
    Ok(())
}

/// Refuse `what` (flags whose images are built from camera samples alone: the denoiser's
/// features, AOVs, debug views) under an integrator whose pixels also hold light-path splats
/// (`light`, `bdpt`): their images would leave the splats out.
pub fn refuse_splat_views(scene: &Scene, given: bool, what: &str) -> Result<()> {
    let kind = scene.settings.integrator;
    if given && kind.splats() {
        anyhow::bail!(
            "{what}: not available under --integrator {} (its pixels also hold light-path splats, which these images leave out): render without them, or under --integrator path",
            kind.name()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every setting the path integrator ignores has its flag recognised: all given, the note
    /// names them all, in the shared list's order.
    #[test]
    fn the_note_names_every_flag_the_path_integrator_ignores() {
        let mut scene = Scene::default_scene();
        scene.settings.integrator = IntegratorKind::Path;
        let o = Overrides {
            fresnel: Some("schlick".into()),
            shadows: Some("translucent".into()),
            min_weight: Some(0.0),
            tolerance: Some(0.01),
            light_samples: Some(2),
            glossy_samples: Some(2),
            dielectric_roulette: Some(2),
            roulette_below: Some(0.0),
            ..Overrides::default()
        };
        let note = ignored_flags(&scene, &o).unwrap();
        let want = [
            "--fresnel",
            "--shadows",
            "--min-weight",
            "--tolerance",
            "--light-samples",
            "--glossy-samples",
            "--dielectric-roulette",
            "--roulette-below",
        ];
        assert!(
            note.contains(&format!("ignores {}: they are", want.join(", "))),
            "{note}"
        );
        assert!(ignored_flags(&scene, &Overrides::default()).is_none());
    }
}
