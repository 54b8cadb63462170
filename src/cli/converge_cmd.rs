//! `raytree converge`: relative RMSE against a reference versus samples and seconds per series,
//! written as Markdown, CSV, JSON and a log-log plot (`raytree::analysis::converge`).

use super::args::ConvergeArgs;
use super::load::load;
use super::output::{Inputs, Origin, OutDir, OutputSet, encode_rgb8_png, read_image};
use super::say::{out, sayln};
use anyhow::{Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use raytree::Image;
use raytree::analysis::converge::{Curve, Series, converge, reference};
use raytree::scene::IntegratorKind;
use std::fmt::Write;
use std::path::{Path, PathBuf};

const NAMES: [&str; 4] = [
    "converge.md",
    "converge.csv",
    "converge.json",
    "converge.png",
];

/// Run every series and write the report; nothing is written unless every input is good.
pub fn run(a: &ConvergeArgs) -> Result<()> {
    let given = a.reference.as_deref().map(read_reference).transpose()?;
    let loaded = load_sized(a, given.as_ref())?;
    let scene = &loaded.scene;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let SppLimits { max_spp, ref_spp } = spp_limits(a, scene, given.as_ref())?;
    let series = parse_series(a, scene)?;
    let spps: Vec<u32> = std::iter::successors(Some(1u32), |s| s.checked_mul(2))
        .take_while(|s| *s <= max_spp)
        .collect();
    let mut inputs: Vec<&Path> = loaded.inputs.iter().map(PathBuf::as_path).collect();
    inputs.extend(a.reference.as_deref());
    let inputs = Inputs::new(inputs);
    let dir = OutDir::create(&a.output)?;
    let mut set = OutputSet::new(&inputs, a.force);
    let slots = NAMES
        .iter()
        .map(|n| dir.reserve(&mut set, n, Origin::Named))
        .collect::<Result<Vec<_>>>()?;
    let key = reference_key(&loaded.inputs, scene, ref_spp)?;
    let (reference, cache) = match given {
        Some(r) => (r, None),
        None => cached_reference(&a.output, &key, scene, ref_spp, &dir, &mut set)?,
    };
    let bar = ProgressBar::new(0).with_style(
        ProgressStyle::with_template("converge [{bar:40}] {pos}/{len} renders {elapsed_precise}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let curves = converge(scene, &reference, &series, &spps, &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    let what = match &a.reference {
        Some(p) => format!("the reference {}", p.display()),
        None => format!("a {ref_spp}-spp reference rendered by raytree"),
    };
    let md = markdown(&curves, &loaded.label, (w, h), &what);
    let plot = super::converge_plot::plot(&curves, (w, h), 1400, 650)?;
    let bytes: [Vec<u8>; 4] = [
        raytree::text::guard_nonfinite(&md)
            .into_owned()
            .into_bytes(),
        csv(&curves).into_bytes(),
        serde_json::to_vec_pretty(&curves)?,
        encode_rgb8_png(&plot, 1400, 650)?,
    ];
    for (slot, b) in slots.into_iter().zip(bytes) {
        set.stage(slot, &b)?;
    }
    if let Some((exr, json, bytes)) = cache {
        set.stage(exr, &bytes)?;
        set.stage(json, key.as_bytes())?;
    }
    set.commit()?;
    dir.keep();
    out(&md)?;
    sayln!("wrote {}/{{{}}}", a.output.display(), NAMES.join(","))?;
    Ok(())
}

/// The scene at the size of the `given` reference, or of --size, or a small default width
/// (64 with --quick, else 160) at the camera's aspect.
fn load_sized(a: &ConvergeArgs, given: Option<&Image>) -> Result<super::load::Loaded> {
    let mut overrides = a.overrides.clone();
    if overrides.size.is_none()
        && let Some(r) = given
    {
        overrides.size = Some(format!("{}x{}", r.width, r.height));
    }
    let mut loaded = load(a.scene.as_deref(), &overrides)?;
    if overrides.size.is_none() {
        let cam = &loaded.scene.camera;
        let w: u32 = if a.quick { 64 } else { 160 };
        let h = (f64::from(w) * f64::from(cam.height) / f64::from(cam.width)).round();
        loaded.scene.camera = cam.with_size(w, (h as u32).max(1));
    }
    Ok(loaded)
}

/// The largest samples per pixel of the curves and of the reference rendered here.
struct SppLimits {
    max_spp: u32,
    ref_spp: u32,
}

/// The spp limits, checked with the memory budget and against the `given` reference.
fn spp_limits(
    a: &ConvergeArgs,
    scene: &raytree::Scene,
    given: Option<&Image>,
) -> Result<SppLimits> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let max_spp = a.max_spp.unwrap_or(if a.quick { 16 } else { 64 });
    let ref_spp = a.ref_spp.unwrap_or(if a.quick { 256 } else { 1024 });
    for (flag, v) in [("--max-spp", max_spp), ("--ref-spp", ref_spp)] {
        if !(1..=raytree::scene::MAX_SPP).contains(&v) {
            bail!(
                "{flag} {v}: must be 1 to {} (the limit of --spp)",
                raytree::scene::MAX_SPP
            );
        }
    }
    // The reference, a render and their errors at once.
    super::budget::check_image_with(
        scene,
        super::budget::mib(a.overrides.max_memory),
        3 * super::budget::PIXEL_BYTES,
    )?;
    if given.is_none() && ref_spp <= max_spp {
        bail!(
            "--ref-spp {ref_spp} must be above --max-spp {max_spp}: the reference must be better than every curve"
        );
    }
    if let Some(r) = given
        && (r.width, r.height) != (w, h)
    {
        bail!(
            "the reference {} is {}x{}, the render {w}x{h} (set --size or drop it)",
            a.reference.as_deref().unwrap_or(Path::new("")).display(),
            r.width,
            r.height
        );
    }
    Ok(SppLimits { max_spp, ref_spp })
}

/// The series of --series, or the scene's defaults; those that need the path integrator only
/// with it.
fn parse_series(a: &ConvergeArgs, scene: &raytree::Scene) -> Result<Vec<Series>> {
    let series = match &a.series {
        Some(s) => s
            .split(',')
            .map(|n| Series::parse(n.trim()).map_err(|e| anyhow::anyhow!("--series: {e}")))
            .collect::<Result<Vec<_>>>()?,
        None => Series::defaults(scene),
    };
    if scene.settings.integrator != IntegratorKind::Path
        && let Some(s) = series.iter().find(|s| s.needs_path())
    {
        bail!(
            "--series {}: needs the path integrator (--integrator path)",
            s.name()
        );
    }
    Ok(series)
}

fn read_reference(path: &Path) -> Result<Image> {
    let r = read_image(path)?;
    if let Some(i) = r.pixels.iter().position(|p| !p.is_finite()) {
        bail!(
            "the reference {} has a non-finite pixel at {},{}",
            path.display(),
            i as u32 % r.width,
            i as u32 / r.width
        );
    }
    Ok(r)
}

/// What the cached reference was rendered from: the scene's files (FNV-1a of their bytes), the
/// size, the settings and the spp.
fn reference_key(files: &[PathBuf], scene: &raytree::Scene, spp: u32) -> Result<String> {
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    for f in files {
        for b in std::fs::read(f)? {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    let key = serde_json::json!({
        "files_fnv1a": format!("{hash:016x}"),
        "size": [scene.camera.width, scene.camera.height],
        "settings": scene.settings,
        "ref_spp": spp,
        // Since automatic antialiasing: the reference takes ref_spp in every pixel (a cache
        // from before, without this field, was an auto render and no longer matches).
        "reference_antialiasing": "uniform",
        "version": env!("CARGO_PKG_VERSION"),
    });
    Ok(serde_json::to_string_pretty(&key)?)
}

type Cache = Option<(usize, usize, Vec<u8>)>;

/// Whether `json` is a cache key this command wrote (so the `reference.exr` beside it is its
/// cache too, and may be replaced).
fn is_our_key(json: &Path) -> bool {
    let text = super::read::read_text(json, 1 << 20).unwrap_or_default();
    serde_json::from_str::<serde_json::Value>(&text)
        .is_ok_and(|v| v.get("files_fnv1a").is_some() && v.get("ref_spp").is_some())
}

/// The reference from the report directory when its key matches, else rendered (and, once the
/// report is written, cached). Either way the 32-bit float values of the EXR, so a cached run
/// gives the same numbers.
fn cached_reference(
    out: &Path,
    key: &str,
    scene: &raytree::Scene,
    spp: u32,
    dir: &OutDir,
    set: &mut OutputSet,
) -> Result<(Image, Cache)> {
    let (exr, json) = (out.join("reference.exr"), out.join("reference.json"));
    if super::read::read_text(&json, 1 << 20).is_ok_and(|k| k == key)
        && let Ok(r) = read_reference(&exr)
        && (r.width, r.height) == (scene.camera.width, scene.camera.height)
    {
        sayln!("using the cached reference {}", exr.display())?;
        return Ok((r, None));
    }
    let origin = if is_our_key(&json) || !(exr.exists() || json.exists()) {
        Origin::Named
    } else {
        Origin::Derived("the reference cache; --reference uses a file as the reference")
    };
    let pending = (
        dir.reserve(set, "reference.exr", origin)?,
        dir.reserve(set, "reference.json", origin)?,
    );
    sayln!(
        "rendering the reference: {spp} spp at {}x{}",
        scene.camera.width,
        scene.camera.height
    )?;
    let r = reference(scene, spp);
    let (bytes, _) = raytree::codec::exr_clamped(&r)?;
    let f32s = Image {
        pixels: r
            .pixels
            .iter()
            .map(|p| {
                p.to_array()
                    .map(|c| f64::from(raytree::codec::finite_f32(c).0))
            })
            .map(raytree::math::Rgb::from_array)
            .collect(),
        ..r
    };
    Ok((f32s, Some((pending.0, pending.1, bytes))))
}

fn markdown(curves: &[Curve], label: &str, (w, h): (u32, u32), what: &str) -> String {
    let mut s = format!(
        "Convergence of {label} at {w}x{h} against {what}. rel-RMSE = sqrt(mean over pixels and channels of ((img - ref) / (ref + 0.01))^2); a plain Monte Carlo estimator falls as N^-1/2 (slope -0.5).\n\n| series | slope vs spp | slope vs seconds |\n| --- | ---: | ---: |\n"
    );
    let slope = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
    for c in curves {
        let _ = writeln!(
            s,
            "| {} | {} | {} |",
            c.name,
            slope(c.slope_spp),
            slope(c.slope_seconds)
        );
    }
    if let Some(t) = raytree::analysis::converge::identical_text(curves) {
        let _ = writeln!(s, "\n{t}");
    }
    s.push_str("\n| series | spp | seconds | rel-RMSE |\n| --- | ---: | ---: | ---: |\n");
    for c in curves {
        for p in &c.points {
            let _ = writeln!(
                s,
                "| {} | {} | {:.4} | {:.5} |",
                c.name, p.spp, p.seconds, p.rel_rmse
            );
        }
    }
    s
}

fn csv(curves: &[Curve]) -> String {
    let mut s = String::from("series,spp,seconds,rel_rmse,slope_spp,slope_seconds\n");
    let num = |v: f64| {
        if v.is_finite() {
            v.to_string()
        } else {
            String::new()
        }
    };
    for c in curves {
        for p in &c.points {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{}",
                c.name,
                p.spp,
                num(p.seconds),
                num(p.rel_rmse),
                c.slope_spp.map_or(String::new(), num),
                c.slope_seconds.map_or(String::new(), num)
            );
        }
    }
    s
}
