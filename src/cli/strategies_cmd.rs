//! `raytree strategies`: Veach's figure (1997, figure 10.3) of a scene, the bidirectional
//! render split by strategy, written as a report directory.

use super::args::StrategiesArgs;
use super::canvas::Canvas;
use super::load::load;
use super::output::{Inputs, Origin, OutDir, OutputSet};
use super::say::sayln;
use anyhow::{Result, bail};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raytree::analysis::strategies::{Part, PartImage, Split, split};
use raytree::math::Rgb;
use raytree::render::Image;
use std::fmt::Write as _;
use std::time::Instant;

/// The deepest `--bounces` (a split keeps `(b + 1)(b + 4) / 2` strategies apart).
const MAX_BOUNCES: u32 = 6;

/// Bytes a pixel costs per part (weighted and unweighted sums, then their images).
const PART_PIXEL_BYTES: u64 = 4 * 24;

/// Widest contact-sheet cell; larger images are subsampled into it.
const CELL: u32 = 160;

/// Run the split and write the report directory (nothing is written unless it succeeded; in
/// an existing directory only the files it names are replaced, each atomically).
pub fn run(a: &StrategiesArgs) -> Result<()> {
    if a.bounces > MAX_BOUNCES {
        bail!("--bounces: at most {MAX_BOUNCES}, got {}", a.bounces);
    }
    let mut overrides = a.overrides.clone();
    match overrides.integrator.as_deref() {
        None | Some("bdpt") => overrides.integrator = Some("bdpt".to_string()),
        Some(other) => bail!(
            "--integrator {other:?}: strategies splits the bidirectional render (bdpt); leave --integrator out"
        ),
    }
    let loaded = load(a.scene.as_deref(), &overrides)?;
    let scene = &loaded.scene;
    let parts = u64::from((a.bounces + 1) * (a.bounces + 4) / 2 + 2);
    let mib = super::budget::mib(a.overrides.max_memory);
    super::budget::check_image_with(scene, mib, parts * PART_PIXEL_BYTES)?;
    let inputs = Inputs::new(loaded.inputs.iter().map(|p| p.as_path()));
    let h = scene.camera.height;
    let bar = ProgressBar::with_draw_target(Some(2 * u64::from(h)), ProgressDrawTarget::stderr())
        .with_style(
            ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows {elapsed_precise}")
                .expect("valid template")
                .progress_chars("=> "),
        );
    bar.set_message(format!(
        "splitting {} by strategy (camera rows, then light rows)",
        loaded.label
    ));
    let start = Instant::now();
    let s = split(scene, a.bounces, &|rows| bar.set_position(u64::from(rows)));
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    let shares = s.shares();
    let finite = |v: &[Rgb]| v.iter().all(|c| c.is_finite());
    if !s
        .parts
        .iter()
        .all(|p| finite(&p.weighted) && finite(&p.unweighted))
    {
        bail!(
            "a strategy's image is not finite (the scene's radiance overflows a 64-bit float); nothing was written"
        );
    }
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    for p in &s.parts {
        let stem = p.part.stem();
        files.push((format!("{stem}.png"), png(&s, &p.weighted)?));
        if matches!(p.part, Part::Strategy { .. }) {
            files.push((format!("{stem}-unweighted.png"), png(&s, &p.unweighted)?));
        }
    }
    files.push(("sheet.png".to_string(), sheet(&s, &shares)?));
    let md = raytree::text::guard_nonfinite(&markdown(&s, &shares, &loaded.label)).into_owned();
    files.push(("report.md".to_string(), md.into_bytes()));
    let json = serde_json::to_string_pretty(&report_json(&s, &shares, &loaded.label))?;
    files.push(("report.json".to_string(), json.into_bytes()));
    let dir = OutDir::create(&a.output)?;
    let mut set = OutputSet::new(&inputs, false);
    for (name, bytes) in &files {
        let slot = dir.reserve(&mut set, name, Origin::Named)?;
        set.stage(slot, bytes)?;
    }
    set.commit()?;
    dir.keep();
    sayln!("{}", raytree::text::guard_nonfinite(&summary(&shares)))?;
    sayln!(
        "wrote {} ({} files, {}x{} at {} spp, {secs:.2} s)",
        a.output.display(),
        files.len(),
        s.width,
        s.height,
        s.spp
    )?;
    Ok(())
}

/// The image of `pixels` as PNG (the render's tone mapping: linear to sRGB, clamped).
fn png(s: &Split, pixels: &[Rgb]) -> Result<Vec<u8>> {
    let image = Image {
        width: s.width,
        height: s.height,
        pixels: pixels.to_vec(),
    };
    Ok(raytree::codec::png(&image)?)
}

/// `s=1 t=2 41.3%, ...` for the strategies that carry light, largest first.
fn summary(shares: &[(Part, f64)]) -> String {
    let mut v: Vec<&(Part, f64)> = shares.iter().filter(|(_, x)| *x > 0.0).collect();
    v.sort_by(|a, b| b.1.total_cmp(&a.1));
    let list: Vec<String> = v
        .iter()
        .map(|(p, x)| format!("{} {:.1}%", p.label(), 100.0 * x))
        .collect();
    if list.is_empty() {
        "the image is black: no strategy carries light".to_string()
    } else {
        format!("share of the image's luminance: {}", list.join(", "))
    }
}

/// The mean luminance of `pixels`.
fn mean_luminance(pixels: &[Rgb]) -> f64 {
    let n = pixels.len().max(1) as f64;
    pixels
        .iter()
        .map(|&c| raytree::bsdf::luminance(c))
        .sum::<f64>()
        / n
}

fn share_of(shares: &[(Part, f64)], part: Part) -> f64 {
    shares
        .iter()
        .find(|(p, _)| *p == part)
        .map_or(0.0, |(_, x)| *x)
}

/// report.md: one row per part.
fn markdown(s: &Split, shares: &[(Part, f64)], label: &str) -> String {
    let mut out = format!(
        "# Strategies of {label}\n\nThe bidirectional render ({}x{}, {} spp) split by strategy (s light-subpath vertices, t camera-subpath vertices; Veach 1997, figure 10.3). Weighted images carry their MIS weights and add up to the render; unweighted ones are each strategy alone (MIS off), an unbiased estimate of the light its path length carries wherever the strategy can make the path. Paths with more than {} bounces are summed in `longer`.\n\n| part | bounces | share | contributions | mean luminance (weighted) | mean luminance (unweighted) |\n|---|---|---|---|---|---|\n",
        s.width, s.height, s.spp, s.max_bounces
    );
    for p in &s.parts {
        let bounces = p.part.bounces().map_or("-".to_string(), |b| b.to_string());
        let _ = writeln!(
            out,
            "| {} | {bounces} | {:.2}% | {} | {:.6} | {:.6} |",
            p.part.label(),
            100.0 * share_of(shares, p.part),
            p.contributions,
            mean_luminance(&p.weighted),
            mean_luminance(&p.unweighted),
        );
    }
    let _ = writeln!(
        out,
        "\n{}\n\nCamera samples dropped (not finite): {}.",
        summary(shares),
        s.dropped
    );
    out
}

/// report.json: the same numbers.
fn report_json(s: &Split, shares: &[(Part, f64)], label: &str) -> serde_json::Value {
    let parts: Vec<serde_json::Value> = s
        .parts
        .iter()
        .map(|p| {
            let strategy = match p.part {
                Part::Strategy { s, t } => serde_json::json!([s, t]),
                _ => serde_json::Value::Null,
            };
            serde_json::json!({
                "part": p.part.label(),
                "strategy": strategy,
                "bounces": p.part.bounces(),
                "share": share_of(shares, p.part),
                "contributions": p.contributions,
                "mean_luminance_weighted": mean_luminance(&p.weighted),
                "mean_luminance_unweighted": mean_luminance(&p.unweighted),
            })
        })
        .collect();
    serde_json::json!({
        "scene": label,
        "size": [s.width, s.height],
        "spp": s.spp,
        "max_bounces": s.max_bounces,
        "dropped_samples": s.dropped,
        "parts": parts,
    })
}

/// The contact sheet: a row pair per bounce count (weighted above, unweighted below), one
/// column per `s` (`t = bounces + 2 - s >= 1`), each cell labelled with its strategy and share; the background and the
/// longer paths in a last row.
fn sheet(s: &Split, shares: &[(Part, f64)]) -> Result<Vec<u8>> {
    let step = s.width.div_ceil(CELL).max(1);
    let (cw, ch) = (s.width.div_ceil(step), s.height.div_ceil(step));
    let (pad, label) = (6u32, 16u32);
    let (cols, rows) = (s.max_bounces + 2, 2 * (s.max_bounces + 1) + 1);
    let head = 90u32;
    let width = head + cols * (cw + pad) + pad;
    let height = rows * (ch + label + pad) + pad;
    let mut c = Canvas::new(width, height, [24, 24, 24])?;
    let text = [230, 230, 230];
    for b in 0..=s.max_bounces {
        for k in 0..2u32 {
            let y0 = (2 * b + k) * (ch + label + pad) + pad;
            let head_text = if k == 0 {
                format!("{b} bounce{}", if b == 1 { "" } else { "s" })
            } else {
                "unweighted".to_string()
            };
            c.text(6.0, (y0 + label + ch / 2) as f32, 12.0, &head_text, text);
            for sv in 0..=b + 1 {
                let part = Part::Strategy {
                    s: sv,
                    t: b + 2 - sv,
                };
                let x0 = head + sv * (cw + pad) + pad;
                let img = s.parts.iter().find(|p| p.part == part);
                let caption = match (img, k) {
                    (None, _) => format!("{} (none)", part.label()),
                    (Some(_), 0) => {
                        format!("{} {:.1}%", part.label(), 100.0 * share_of(shares, part))
                    }
                    (Some(_), _) => part.label(),
                };
                c.text(x0 as f32, (y0 + label - 4) as f32, 11.0, &caption, text);
                cell(&mut c, s, img, k == 1, (x0, y0 + label), step);
            }
        }
    }
    let y0 = 2 * (s.max_bounces + 1) * (ch + label + pad) + pad;
    c.text(6.0, (y0 + label + ch / 2) as f32, 12.0, "other", text);
    for (i, part) in [Part::Background, Part::Longer].into_iter().enumerate() {
        let x0 = head + i as u32 * (cw + pad) + pad;
        let img = s.parts.iter().find(|p| p.part == part);
        let caption = match img {
            None => format!("{} (none)", part.label()),
            Some(_) => format!("{} {:.1}%", part.label(), 100.0 * share_of(shares, part)),
        };
        c.text(x0 as f32, (y0 + label - 4) as f32, 11.0, &caption, text);
        cell(&mut c, s, img, false, (x0, y0 + label), step);
    }
    c.png()
}

/// One cell: the part's image subsampled by `step`, or a dark grey square where the strategy
/// made no contribution (it cannot make these paths in this scene, or raytree does not sample
/// it: `s = 1, t = 1`, as pbrt-v3).
fn cell(
    c: &mut Canvas,
    s: &Split,
    img: Option<&PartImage>,
    unweighted: bool,
    at: (u32, u32),
    step: u32,
) {
    let (cw, ch) = (s.width.div_ceil(step), s.height.div_ceil(step));
    let Some(img) = img else {
        c.rect(at.0 as f32, at.1 as f32, cw as f32, ch as f32, [48, 48, 48]);
        return;
    };
    let pixels = if unweighted {
        &img.unweighted
    } else {
        &img.weighted
    };
    for cy in 0..ch {
        for cx in 0..cw {
            let (x, y) = ((cx * step).min(s.width - 1), (cy * step).min(s.height - 1));
            let p = pixels[(y * s.width + x) as usize];
            let rgb = p.to_array().map(raytree::math::linear_to_srgb8);
            c.pixel(at.0 + cx, at.1 + cy, rgb);
        }
    }
}
