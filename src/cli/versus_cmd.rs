//! `raytree versus SCENE -o DIR`: Whitted and path tracing of the same scene side by side, the
//! difference image, and the difference broken down by light transport class
//! ([`raytree::aov::versus`]).

use super::args::VersusArgs;
use super::canvas::Canvas;
use super::load::load;
use super::output::{Inputs, Origin, OutDir, OutputSet};
use super::say::sayln;
use anyhow::{Context, Result, bail};
use raytree::aov::{CLASSES, Versus, versus};
use std::time::Instant;

fn parse_region(s: &str) -> Result<[u32; 4]> {
    let v: Vec<u32> = s
        .split(',')
        .map(|p| p.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--region {s}: expected X0,Y0,X1,Y1 (pixels)"))?;
    let [x0, y0, x1, y1] = v[..] else {
        bail!("--region {s}: expected four numbers X0,Y0,X1,Y1");
    };
    if x0 >= x1 || y0 >= y1 {
        bail!("--region {s}: empty (X0 < X1 and Y0 < Y1 are needed)");
    }
    Ok([x0, y0, x1, y1])
}

/// Run the command.
pub fn run(a: &VersusArgs) -> Result<()> {
    let region = a.region.as_deref().map(parse_region).transpose()?;
    let loaded = load(a.scene.as_deref(), &a.overrides)?;
    let scene = &loaded.scene;
    let (w, h) = (scene.camera.width, scene.camera.height);
    if let Some([x0, y0, ..]) = region
        && (x0 >= w || y0 >= h)
    {
        bail!("--region: starts outside the {w}x{h} image");
    }
    super::budget::check_image(scene, super::budget::mib(a.overrides.max_memory))?;
    let inputs = Inputs::new(loaded.inputs.iter().map(|p| p.as_path()));
    let dir = OutDir::create(&a.output)?;
    let names = [
        "whitted.png",
        "path.png",
        "side-by-side.png",
        "difference.png",
        "breakdown.json",
    ];
    let mut set = OutputSet::new(&inputs, false);
    let slots = names
        .iter()
        .map(|n| dir.reserve(&mut set, n, Origin::Named))
        .collect::<Result<Vec<_>>>()?;
    let start = Instant::now();
    let v = versus(scene, region, &|_| {})?;
    let secs = start.elapsed().as_secs_f64();
    let numbers = [v.whitted_luminance, v.path_luminance]
        .into_iter()
        .chain(v.classes.iter().map(|c| c.luminance))
        .chain(v.breakdown().into_iter().flat_map(|(_, d, s)| [d, s]));
    if numbers.into_iter().any(|x| !x.is_finite()) {
        bail!(
            "the breakdown's luminances are not finite (the scene's radiance overflows a 64-bit float when summed over the region); nothing was written"
        );
    }
    let json = serde_json::to_string_pretty(&breakdown_json(&v, &loaded.label))?;
    let files = [
        raytree::codec::png(&v.whitted)?,
        raytree::codec::png(&v.path.beauty)?,
        side_by_side(&v)?,
        difference(&v)?,
        json.clone().into_bytes(),
    ];
    for (slot, bytes) in slots.into_iter().zip(&files) {
        set.stage(slot, bytes)?;
    }
    set.commit()?;
    dir.keep();
    if a.json {
        sayln!("{json}")?;
    } else {
        sayln!("{}", breakdown_text(&v))?;
        sayln!("wrote {} ({secs:.2} s)", a.output.display())?;
    }
    Ok(())
}

/// The breakdown in words.
fn breakdown_text(v: &Versus) -> String {
    v.summary()
}

fn breakdown_json(v: &Versus, scene: &str) -> serde_json::Value {
    let classes: Vec<serde_json::Value> = v
        .classes
        .iter()
        .zip(CLASSES)
        .map(|(c, k)| {
            serde_json::json!({"name": c.name, "lpe": c.lpe, "whitted": c.whitted,
                "luminance": c.luminance, "what": k.what})
        })
        .collect();
    let shares: serde_json::Map<String, serde_json::Value> = v
        .breakdown()
        .into_iter()
        .map(|(n, d, s)| {
            (
                n.to_owned(),
                serde_json::json!({"luminance": d, "share": s}),
            )
        })
        .collect();
    serde_json::json!({
        "scene": scene,
        "region": v.region,
        "whitted_luminance": v.whitted_luminance,
        "path_luminance": v.path_luminance,
        "classes": classes,
        "difference": shares,
    })
}

/// Whitted | path, with captions.
fn side_by_side(v: &Versus) -> Result<Vec<u8>> {
    let (w, h) = (v.whitted.width, v.whitted.height);
    let mut c = Canvas::new(2 * w + 8, h + 20, [24, 24, 24])?;
    for (k, img) in [&v.whitted, &v.path.beauty].into_iter().enumerate() {
        let bytes = img.to_srgb8();
        let x0 = k as u32 * (w + 8);
        for (i, p) in bytes.chunks(3).enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            c.pixel(x0 + x, y, [p[0], p[1], p[2]]);
        }
        let label = if k == 0 { "Whitted" } else { "path" };
        c.text(
            x0 as f32 + 4.0,
            (h + 15) as f32,
            12.0,
            label,
            [230, 230, 230],
        );
    }
    c.png()
}

/// The signed luminance difference path - Whitted ([`Versus::difference_rgb8`]) with its
/// scale as a caption.
fn difference(v: &Versus) -> Result<Vec<u8>> {
    let (w, h) = (v.whitted.width, v.whitted.height);
    let (pixels, scale) = v.difference_rgb8();
    let mut c = Canvas::new(w.max(200), h + 20, [24, 24, 24])?;
    for (i, col) in pixels.iter().enumerate() {
        c.pixel(i as u32 % w, i as u32 / w, *col);
    }
    let caption = format!("path-Whitted: red +, blue -, full {scale:.2}");
    c.text(4.0, (h + 15) as f32, 11.0, &caption, [230, 230, 230]);
    c.png()
}
