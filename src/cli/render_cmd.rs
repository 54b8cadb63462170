//! `raytree render`.

use super::args::RenderArgs;
use super::load::load;
use super::output::{ImageFormat, Inputs, Origin, OutputSet, encode_counting, image_format};
use super::render_warnings::warn_image;
use super::say::{sayln, warnln};
use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use std::time::Instant;

/// Render the scene to a PNG or EXR file and report time and rays.
pub fn run(a: &RenderArgs) -> Result<()> {
    let format = image_format(&a.output)?;
    check_spp_map(a)?;
    if !a.aov.is_empty() || !a.debug_view.is_empty() {
        if a.denoise || a.features {
            anyhow::bail!(
                "--denoise and --features do not combine with --aov or --debug-view: render them in two runs"
            );
        }
        return super::aov_cmd::run(a);
    }
    let loaded = load(a.scene.as_deref(), &a.overrides)?;
    let scene = &loaded.scene;
    super::load::refuse_splat_views(scene, a.denoise || a.features, "--denoise and --features")?;
    let mib = super::budget::mib(a.overrides.max_memory);
    super::budget::check_image(scene, mib)?;
    if a.denoise || a.features {
        super::budget::check_image_with(scene, mib, super::denoise_out::PIXEL_BYTES)?;
    }
    let inputs = Inputs::new(loaded.inputs.iter().map(|p| p.as_path()));
    let mut set = OutputSet::new(&inputs, a.force);
    let out = set.reserve(&a.output, Origin::Named)?;
    let guides = super::denoise_out::Guides::create(a, &mut set)?;
    let map_slot = match &a.spp_map {
        Some(p) => Some(set.reserve(p, Origin::Named)?),
        None => None,
    };
    let (w, h) = (scene.camera.width, scene.camera.height);
    let bar = ProgressBar::new(u64::from(h)).with_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows {elapsed_precise}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("rendering {} {w}x{h}", loaded.label));
    let start = Instant::now();
    let progress = |rows| bar.set_position(u64::from(rows));
    let (image, stats, map) = if let Some(g) = &guides {
        g.render(scene, &progress)
    } else {
        // The samples per pixel are in every render's map; the diagnostics only when asked.
        let options = if a.diagnose {
            raytree::RenderOptions::diagnosed()
        } else {
            raytree::RenderOptions::new()
        };
        raytree::render(&raytree::SceneIntegrator::new(scene), &options, &progress).into_parts()
    };
    let secs = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let (bytes, clamped) = encode_counting(&image, format)?;
    if let Some(slot) = map_slot {
        set.stage(slot, &super::spp_map::png(&map)?)?;
    }
    set.stage(out, &bytes)?;
    if let Some(g) = guides {
        g.stage(&mut set, format)?;
    }
    set.commit()?;
    let report = Report {
        a,
        scene,
        stats: &stats,
        secs,
    };
    report.say()?;
    warn_image(a, scene, &stats, clamped, format);
    Ok(())
}

/// `--spp-map` must be a PNG of its own, not the output image.
fn check_spp_map(a: &RenderArgs) -> Result<()> {
    if let Some(p) = &a.spp_map
        && image_format(p)? != ImageFormat::Png
    {
        anyhow::bail!("--spp-map: {} must be a .png", p.display());
    }
    if let Some(p) = &a.spp_map
        && std::path::absolute(p).ok() == std::path::absolute(&a.output).ok()
    {
        anyhow::bail!(
            "--spp-map {} is the output image: give the map a file of its own",
            p.display()
        );
    }
    Ok(())
}

/// What a finished render reports: the files, time and rays, then one line per feature in use.
struct Report<'a> {
    a: &'a RenderArgs,
    scene: &'a raytree::Scene,
    stats: &'a raytree::RenderStats,
    /// Wall-clock seconds of the render alone (not the encoding).
    secs: f64,
}

impl Report<'_> {
    /// Every line, in the order the command has always printed them.
    fn say(&self) -> Result<()> {
        self.say_written()?;
        self.say_adaptive()?;
        self.say_roulette()?;
        if let Some(p) = &self.a.spp_map {
            sayln!(
                "wrote {} (samples per pixel, white = the most)",
                p.display()
            )?;
        }
        self.say_integrator()?;
        self.warn_dropped();
        self.say_diagnostics()
    }

    /// The image written, then the time and the rays by kind.
    fn say_written(&self) -> Result<()> {
        let (a, scene, secs) = (self.a, self.scene, self.secs);
        let (w, h) = (scene.camera.width, scene.camera.height);
        let r = &self.stats.rays;
        sayln!(
            "wrote {} ({w}x{h}, {} spp, max depth {})",
            a.output.display(),
            scene.settings.spp,
            scene.settings.max_depth
        )?;
        sayln!(
            "time {secs:.3} s, {} rays ({:.2} Mrays/s): camera {}, reflected {}, refracted {}, shadow {}",
            r.total(),
            r.total() as f64 / secs / 1e6,
            r.camera,
            r.reflected,
            r.refracted,
            r.shadow
        )?;
        Ok(())
    }

    /// Adaptive or automatic antialiasing: how many pixels took more samples.
    fn say_adaptive(&self) -> Result<()> {
        let (scene, stats) = (self.scene, self.stats);
        let integrator = raytree::integrator::SceneIntegrator::new(scene);
        let Some(plan) = raytree::render::adaptive_plan(&integrator) else {
            return Ok(());
        };
        let pixels = u64::from(scene.camera.width) * u64::from(scene.camera.height);
        let per_pixel = stats.samples as f64 / pixels.max(1) as f64;
        if plan.auto {
            sayln!(
                "antialiasing auto: {} of {pixels} pixels on an edge took {} spp, the others {} (contrast > {}), {} samples ({per_pixel:.2} per pixel; --antialiasing uniform: {} everywhere)",
                stats.refined_pixels,
                plan.total,
                plan.first,
                plan.threshold,
                stats.samples,
                plan.total
            )?;
        } else {
            sayln!(
                "adaptive: {} of {pixels} pixels refined to {} spp (contrast > {}), {} samples ({per_pixel:.2} per pixel)",
                stats.refined_pixels,
                plan.total,
                plan.threshold,
                stats.samples
            )?;
        }
        Ok(())
    }

    /// Glass hits that followed one of their two rays (dielectric roulette).
    fn say_roulette(&self) -> Result<()> {
        let (scene, r) = (self.scene, &self.stats.rays);
        if r.roulette > 0 {
            let why = match scene.settings.whitted.dielectric_roulette {
                Some(d) => format!("from depth {d}"),
                None => format!(
                    "where the throughput was below {:.2e}",
                    raytree::integrator::bound::carried::effective_roulette_below(scene)
                ),
            };
            sayln!(
                "roulette: {} glass hits {why} followed one of their two rays (exact in expectation; --roulette-below 0 splits every hit)",
                r.roulette
            )?;
        }
        Ok(())
    }

    /// The path and light integrators' own rates.
    fn say_integrator(&self) -> Result<()> {
        let (scene, stats, secs) = (self.scene, self.stats, self.secs);
        let r = &stats.rays;
        if scene.settings.integrator == raytree::scene::IntegratorKind::Path {
            // The samples taken (adaptive antialiasing's refined pixels take more than spp).
            let samples = stats.samples;
            sayln!(
                "path: {samples} samples ({:.0} samples/s), diffuse bounces {}, rr depth {}, sampler {}",
                samples as f64 / secs,
                r.diffuse,
                scene.settings.path.rr_depth,
                scene.settings.sampler_kind().name()
            )?;
        }
        if scene.settings.integrator == raytree::scene::IntegratorKind::Light {
            let paths = u64::from(scene.camera.width)
                * u64::from(scene.camera.height)
                * u64::from(scene.settings.spp.max(1));
            sayln!(
                "light: {paths} light paths ({:.0} paths/s), {} light-path rays, {} connections to the camera, rr depth {}, sampler {}",
                paths as f64 / secs,
                r.light,
                r.connection,
                scene.settings.path.rr_depth,
                scene.settings.sampler_kind().name()
            )?;
        }
        Ok(())
    }

    /// Samples that were not a number or infinite, with the first one to trace.
    fn warn_dropped(&self) {
        let r = &self.stats.rays;
        if let Some((x, y, s)) = r.first_dropped {
            warnln!(
                "warning: {} samples were not a number or infinite and were dropped (counted black); first: sample {s} of pixel {x},{y} (`raytree trace --pixel {x},{y}`, sample {s})",
                r.dropped_samples
            );
        }
    }

    /// `--diagnose`: self-hit and leaking rays.
    fn say_diagnostics(&self) -> Result<()> {
        let (scene, stats) = (self.scene, self.stats);
        let r = &stats.rays;
        if self.a.diagnose {
            sayln!(
                "diagnostics: {} self-hit rays in {} pixels, {} leaking rays in {} pixels (offset {} {:e})",
                r.self_hits,
                stats.self_hit_pixels,
                r.leaks,
                stats.leak_pixels,
                scene.settings.offset.strategy.name(),
                scene.settings.offset.epsilon
            )?;
        }
        Ok(())
    }
}
