//! `raytree render --aov NAME=LPE --debug-view VIEW`: the beauty image, one image per light
//! path expression (`OUTPUT.NAME.png`/`.exr`) and Monte Carlo debug views as false colour with
//! a legend (`OUTPUT.view-VIEW.png`), all from one pass ([`raytree::aov::render_aovs`]).

use super::args::RenderArgs;
use super::canvas::Canvas;
use super::load::load;
use super::output::{ImageFormat, Inputs, Origin, OutputSet, encode_counting, image_format};
use super::say::{sayln, warnln};
use anyhow::{Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use raytree::aov::{AovRender, McView, parse_aovs, ramp, render_aovs};
use raytree::scene::IntegratorKind;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `OUTPUT` with `.tag` before its extension: `out.png` -> `out.caustics.png`.
pub(super) fn beside(output: &Path, tag: &str, ext: &str) -> PathBuf {
    let stem = output
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    output.with_file_name(format!("{stem}.{tag}.{ext}"))
}

/// Parse `--aov` (with a caret under the bad column) and `--debug-view`.
fn parse(a: &RenderArgs) -> Result<(Vec<raytree::aov::Aov>, Vec<McView>)> {
    let aovs = parse_aovs(&a.aov).map_err(|e| {
        let (shown, caret) = raytree::input::excerpt(&e.spec, e.column);
        anyhow::anyhow!("--aov {e}\n  {shown}\n  {}^", " ".repeat(caret))
    })?;
    let names: Vec<&str> = aovs.iter().map(|x| x.name.as_str()).collect();
    let views = a
        .debug_view
        .iter()
        .map(|v| McView::parse(v, &names).map_err(|e| anyhow::anyhow!("--debug-view: {e}")))
        .collect::<Result<Vec<_>>>()?;
    if let Some(v) = (0..views.len()).find(|&i| views[..i].contains(&views[i])) {
        bail!(
            "--debug-view {} is given twice: each view is written once",
            raytree::input::quote(&a.debug_view[v])
        );
    }
    Ok((aovs, views))
}

/// Render with AOVs and debug views.
pub fn run(a: &RenderArgs) -> Result<()> {
    if a.diagnose {
        bail!(
            "--diagnose does not combine with --aov or --debug-view (they trace with different recorders): render them in two runs"
        );
    }
    let format = image_format(&a.output)?;
    let (aovs, views) = parse(a)?;
    let loaded = load(a.scene.as_deref(), &a.overrides)?;
    let scene = &loaded.scene;
    super::load::refuse_splat_views(scene, true, "--aov and --debug-view")?;
    refuse_whitted(scene, &aovs, &views)?;
    super::budget::check_aov_images(
        scene,
        aovs.len(),
        super::budget::mib(a.overrides.max_memory),
    )?;
    let names: Vec<&str> = aovs.iter().map(|x| x.name.as_str()).collect();
    let inputs = Inputs::new(loaded.inputs.iter().map(|p| p.as_path()));
    let paths = output_paths(a, &names, &views);
    let mut set = OutputSet::new(&inputs, a.force);
    let derived = 1..1 + names.len() + views.len();
    let slots = paths
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let origin = match (derived.contains(&i), i <= names.len()) {
                (false, _) => Origin::Named,
                (true, true) => Origin::Derived("--aov"),
                (true, false) => Origin::Derived("--debug-view"),
            };
            set.reserve(p, origin)
        })
        .collect::<Result<Vec<_>>>()?;
    let lpes: Vec<_> = aovs.iter().map(|x| x.lpe.clone()).collect();
    let bar = ProgressBar::new(u64::from(scene.camera.height)).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows {elapsed_precise}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("rendering {} with AOVs", loaded.label));
    let start = Instant::now();
    let integrator = raytree::SceneIntegrator::new(scene);
    let r = render_aovs(&integrator, &lpes, &|rows| {
        bar.set_position(u64::from(rows))
    })?;
    let secs = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let (files, clamped) = encode_files(a, &r, &views, &names, format)?;
    for (slot, bytes) in slots.into_iter().zip(&files) {
        set.stage(slot, bytes)?;
    }
    set.commit()?;
    report(a, &r, &paths, secs, &names)?;
    super::render_warnings::warn_image(a, scene, &r.stats, clamped, format);
    if views.contains(&McView::Noise) {
        let single = r.mc.iter().filter(|p| p.samples < 2).count();
        if single > 0 {
            warnln!(
                "note: --debug-view noise: {single} of {} pixels took one sample, whose spread cannot be estimated: they show 0 (black), not a measured zero; render with --spp 2 or more",
                r.mc.len()
            );
        }
    }
    Ok(())
}

/// Whitted reports no paths: refuse the AOVs and the views that need them.
fn refuse_whitted(
    scene: &raytree::Scene,
    aovs: &[raytree::aov::Aov],
    views: &[McView],
) -> Result<()> {
    let whitted = scene.settings.integrator == IntegratorKind::Whitted;
    if whitted && !aovs.is_empty() {
        bail!("--aov: {}", raytree::aov::AovError::Whitted);
    }
    if let Some(v) = views.iter().find(|v| whitted && v.needs_paths()) {
        bail!(
            "--debug-view {}: needs the path integrator (Whitted reports no paths): add --integrator path",
            v.file_name(&[])
        );
    }
    Ok(())
}

/// Every file written, in order: the beauty image, one per AOV `names`, one per debug view,
/// then the `--spp-map`.
fn output_paths(a: &RenderArgs, names: &[&str], views: &[McView]) -> Vec<PathBuf> {
    let ext = a
        .output
        .extension()
        .map_or("png".into(), |e| e.to_string_lossy());
    let mut paths = vec![a.output.clone()];
    paths.extend(names.iter().map(|n| beside(&a.output, n, &ext)));
    paths.extend(
        views
            .iter()
            .map(|v| beside(&a.output, &format!("view-{}", v.file_name(names)), "png")),
    );
    paths.extend(a.spp_map.clone());
    paths
}

/// The bytes of every file, in the order of [`output_paths`], and how many of the beauty
/// image's values the EXR encoding clamped.
fn encode_files(
    a: &RenderArgs,
    r: &AovRender,
    views: &[McView],
    names: &[&str],
    format: ImageFormat,
) -> Result<(Vec<Vec<u8>>, usize)> {
    let mut files = Vec::new();
    let (bytes, clamped) = encode_counting(&r.beauty, format)?;
    files.push(bytes);
    for img in &r.aovs {
        files.push(encode_counting(img, format)?.0);
    }
    for v in views {
        files.push(false_colour(r, v, names)?);
    }
    if a.spp_map.is_some() {
        let samples = r.mc.iter().map(|p| p.samples).collect();
        let (width, height) = (r.beauty.width, r.beauty.height);
        let map = raytree::DiagnosticMap {
            width,
            height,
            samples,
            ..raytree::DiagnosticMap::default()
        };
        files.push(super::spp_map::png(&map)?);
    }
    Ok((files, clamped))
}

/// What was written, the AOVs' shares of the image, dropped samples.
fn report(
    a: &RenderArgs,
    r: &AovRender,
    paths: &[PathBuf],
    secs: f64,
    names: &[&str],
) -> Result<()> {
    let (w, h) = (r.beauty.width, r.beauty.height);
    let lum = |img: &raytree::Image| -> f64 {
        img.pixels
            .iter()
            .map(|p| raytree::bsdf::luminance(*p))
            .sum()
    };
    let total = lum(&r.beauty);
    sayln!(
        "wrote {} ({w}x{h}, {} spp) in {secs:.3} s, {} rays",
        a.output.display(),
        r.mc.iter().map(|p| p.samples).min().unwrap_or(0),
        r.stats.rays.total()
    )?;
    if r.stats.refined_pixels > 0 {
        sayln!(
            "adaptive: {} of {} pixels refined, {} samples ({:.2} per pixel)",
            r.stats.refined_pixels,
            r.mc.len(),
            r.stats.samples,
            r.stats.samples as f64 / r.mc.len().max(1) as f64
        )?;
    }
    for (k, img) in r.aovs.iter().enumerate() {
        let share = if total > 0.0 { lum(img) / total } else { 0.0 };
        sayln!(
            "aov {}: {} ({:.1}% of the image's luminance)",
            names[k],
            paths[1 + k].display(),
            100.0 * share
        )?;
    }
    let views = &paths[1 + names.len()..paths.len() - usize::from(a.spp_map.is_some())];
    for p in views {
        sayln!("debug view: {}", p.display())?;
    }
    if let Some(p) = &a.spp_map {
        sayln!(
            "wrote {} (samples per pixel, white = the most)",
            p.display()
        )?;
    }
    if let Some((x, y, s)) = r.stats.rays.first_dropped {
        warnln!(
            "warning: {} samples were not a number or infinite and were dropped (counted black); first: sample {s} of pixel {x},{y}",
            r.stats.rays.dropped_samples
        );
    }
    Ok(())
}

/// Height of the legend strip under a debug view.
const LEGEND: u32 = 40;

/// The view as false colour (the ramp of the inspector's debug views) with a legend strip: the
/// colour bar from 0 to its top value, and what it measures.
fn false_colour(r: &AovRender, view: &McView, names: &[&str]) -> Result<Vec<u8>> {
    let (w, h) = (r.beauty.width, r.beauty.height);
    let values = view.values(r);
    let (_, max) = view.range(&values);
    let mut c = Canvas::new(w.max(160), h + LEGEND, [24, 24, 24])?;
    for (i, v) in values.iter().enumerate() {
        let (x, y) = (i as u32 % w.max(1), i as u32 / w.max(1));
        c.pixel(x, y, ramp((v / max) as f32));
    }
    let bar = (w.max(160) - 16) as f32;
    for i in 0..bar as u32 {
        let t = (i as f32 + 0.5) / bar;
        c.rect(8.0 + i as f32, (h + 4) as f32, 1.0, 10.0, ramp(t));
    }
    let white = [230, 230, 230];
    let y = (h + 26) as f32;
    c.text(8.0, y, 11.0, "0", white);
    let top = format!("{}{max:.3}", if view == &McView::Noise { ">=" } else { "" });
    let tw = c.text_width(&top, 11.0);
    c.text(8.0 + bar - tw, y, 11.0, &top, white);
    c.text(8.0, y + 12.0, 10.0, &view.label(names), white);
    c.png()
}
