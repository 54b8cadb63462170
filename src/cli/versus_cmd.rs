//! `raytree versus SCENE -o DIR`: Whitted and path tracing of the same scene side by side, the
//! difference image, and the difference broken down by light transport class
//! ([`raytree::aov::versus`]); with `--pair A,B` any two integrators, their difference tested
//! against the noise ([`raytree::aov::pair`]).

use super::args::VersusArgs;
use super::canvas::Canvas;
use super::load::{Loaded, load};
use super::output::{Inputs, Origin, OutDir, OutputSet};
use super::say::sayln;
use anyhow::{Context, Result, bail};
use raytree::aov::{CLASSES, Pair, Versus, pair, versus};
use raytree::scene::IntegratorKind;
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

/// `--pair A,B`: two distinct integrators.
fn parse_pair(s: &str) -> Result<[IntegratorKind; 2]> {
    let kinds = s
        .split(',')
        .map(|p| {
            IntegratorKind::try_from(p.trim().to_string())
                .map_err(|e| anyhow::anyhow!("--pair {s}: {e}"))
        })
        .collect::<Result<Vec<_>>>()?;
    match kinds[..] {
        [a, b] if a != b => Ok([a, b]),
        [_, _] => bail!("--pair {s}: the two integrators must differ"),
        _ => bail!("--pair {s}: expected two integrators A,B (whitted, path, light, bdpt)"),
    }
}

/// Run the command.
pub fn run(a: &VersusArgs) -> Result<()> {
    let kinds = parse_pair(&a.pair)?;
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
    if kinds != [IntegratorKind::Whitted, IntegratorKind::Path] {
        return run_pair(a, &loaded, kinds, region);
    }
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
        side_by_side([&v.whitted, &v.path.beauty], ["Whitted", "path"])?,
        difference(v.difference_rgb8(), v.whitted.width, "path-Whitted")?,
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

/// Two images side by side, with captions.
fn side_by_side(images: [&raytree::Image; 2], labels: [&str; 2]) -> Result<Vec<u8>> {
    let (w, h) = (images[0].width, images[0].height);
    let mut c = Canvas::new(2 * w + 8, h + 20, [24, 24, 24])?;
    for (k, (img, label)) in images.into_iter().zip(labels).enumerate() {
        let bytes = img.to_srgb8();
        let x0 = k as u32 * (w + 8);
        for (i, p) in bytes.chunks(3).enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            c.pixel(x0 + x, y, [p[0], p[1], p[2]]);
        }
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

/// A signed luminance difference (`(pixels, scale)` of [`raytree::aov::signed_rgb8`], `w` wide) with its
/// scale as a caption after `what`.
fn difference((pixels, scale): (Vec<[u8; 3]>, f64), w: u32, what: &str) -> Result<Vec<u8>> {
    let h = pixels.len() as u32 / w.max(1);
    let mut c = Canvas::new(w.max(200), h + 20, [24, 24, 24])?;
    for (i, col) in pixels.iter().enumerate() {
        c.pixel(i as u32 % w, i as u32 / w, *col);
    }
    let caption = format!("{what}: red +, blue -, full {scale:.2}");
    c.text(4.0, (h + 15) as f32, 11.0, &caption, [230, 230, 230]);
    c.png()
}

/// `--pair A,B` other than whitted,path: both renders, timed, and their difference against
/// the noise.
fn run_pair(
    a: &VersusArgs,
    loaded: &Loaded,
    kinds: [IntegratorKind; 2],
    region: Option<[u32; 4]>,
) -> Result<()> {
    let inputs = Inputs::new(loaded.inputs.iter().map(|p| p.as_path()));
    let dir = OutDir::create(&a.output)?;
    let (na, nb) = (kinds[0].name(), kinds[1].name());
    let names = [
        format!("{na}.png"),
        format!("{nb}.png"),
        "side-by-side.png".to_string(),
        "difference.png".to_string(),
        "breakdown.json".to_string(),
    ];
    let mut set = OutputSet::new(&inputs, false);
    let slots = names
        .iter()
        .map(|n| dir.reserve(&mut set, n, Origin::Named))
        .collect::<Result<Vec<_>>>()?;
    let mut secs = Vec::new();
    let p = pair(&loaded.scene, kinds, region, &mut |s| {
        let start = Instant::now();
        let out = raytree::render::render(
            &raytree::SceneIntegrator::new(s),
            &raytree::render::RenderOptions::new(),
            &|_| {},
        );
        secs.push(start.elapsed().as_secs_f64());
        out
    });
    let d = p.difference.as_ref();
    let numbers = [p.a.mean_luminance, p.b.mean_luminance].into_iter().chain(
        d.into_iter()
            .flat_map(|d| d.mean.into_iter().chain(d.half_width)),
    );
    if numbers.into_iter().any(|x| !x.is_finite()) {
        bail!(
            "the comparison's numbers are not finite (the scene's radiance overflows a 64-bit float when summed over the region); nothing was written"
        );
    }
    let json = serde_json::to_string_pretty(&pair_json(&p, &secs, &loaded.label))?;
    let files = [
        raytree::codec::png(&p.a.image)?,
        raytree::codec::png(&p.b.image)?,
        side_by_side([&p.a.image, &p.b.image], [na, nb])?,
        difference(p.difference_rgb8(), p.a.image.width, &format!("{nb}-{na}"))?,
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
        sayln!("{}", p.summary())?;
        let t = |k: usize| secs.get(k).copied().unwrap_or(0.0);
        sayln!(
            "{na} {:.2} s ({} rays), {nb} {:.2} s ({} rays); wrote {}",
            t(0),
            p.a.stats.rays.total(),
            t(1),
            p.b.stats.rays.total(),
            a.output.display()
        )?;
    }
    Ok(())
}

fn pair_json(p: &Pair, secs: &[f64], scene: &str) -> serde_json::Value {
    let side = |s: &raytree::aov::Side, k: usize| {
        serde_json::json!({"integrator": s.kind.name(), "mean_luminance": s.mean_luminance,
            "seconds": secs.get(k).copied().unwrap_or(0.0), "rays": s.stats.rays.total()})
    };
    let difference = p.difference.as_ref().map(|d| {
        let significant = [0, 1, 2].map(|c| d.significant(c));
        serde_json::json!({"mean": d.mean, "half_width": d.half_width, "block": d.block,
            "blocks": d.blocks, "significant": significant})
    });
    serde_json::json!({
        "scene": scene,
        "region": p.region,
        "pair": [p.a.kind.name(), p.b.kind.name()],
        "a": side(&p.a, 0),
        "b": side(&p.b, 1),
        "difference": difference,
        "within_noise": p.significant().is_empty(),
    })
}
