//! Pixels: samples from a [`PixelSampler`], the parallel render, and re-tracing one pixel into
//! a tree.
//!
//! One code path: the pixel loop ([`pixel_loop`]) is generic over the integrator, the sampler
//! and a per-sample sink holding the recorder; the image uses [`NoopRecorder`], the tree
//! [`TreeRecorder`], so a recorded pixel equals the rendered one bit for bit, and the AOV
//! render and the denoiser's gather are sinks of the same loop.

use crate::geometry::Shape;
use crate::integrator::{
    DiagnosticRecorder, Integrator, NoopRecorder, RayCounts, Recorder, SceneIntegrator,
    TreeRecorder,
};
use crate::math::{Ray, Rgb};
use crate::sampling::{PixelFilter, PixelSampler, SceneSampler, StratifiedJitter};
use crate::scene::{Film, Scene};
use crate::tree::{RayTree, SampleRecord, TREE_SCHEMA, TREE_SCHEMA_SPLATS};
use glam::DVec2;
use rayon::prelude::*;

/// Film position of sample `s` of pixel (x, y) at seed 0: [`StratifiedJitter`]'s film offset
/// (the centre for one sample, otherwise jittered stratified) added to the pixel's corner.
#[must_use]
pub fn sample_position(x: u32, y: u32, s: u32, spp: u32) -> (f64, f64) {
    let mut sampler = StratifiedJitter::new(spp, 0);
    film_position(&mut sampler, x, y, s)
}

/// Start sample `s` of pixel (x, y) in `sampler` and return its film position: the pixel's
/// corner plus the sampler's first 2D value.
#[inline(always)]
fn film_position<S: PixelSampler>(sampler: &mut S, x: u32, y: u32, s: u32) -> (f64, f64) {
    sampler.start_sample((x, y), s);
    let (u, v) = sampler.next_2d();
    (f64::from(x) + u, f64::from(y) + v)
}

/// Start sample `s` of pixel (x, y) in `sampler` and return its film position and camera ray.
///
/// The film position is the pixel centre plus an offset drawn from `filter` with the sampler's
/// first 2D value (filter importance sampling, pbrt-v4 section 8.8.3, so every sample has
/// weight 1); the box filter keeps the historical `corner + u` bit for bit. A thin-lens camera
/// then draws the lens sample as the next 2D value ([`Film::lens_ray`]); a pinhole draws
/// nothing more, so aperture 0 traces the pinhole's rays and leaves the sampler's later
/// dimensions where they were. Both the pixel loop and the packet bands call this, so they
/// trace the same rays.
///
/// [`Film::lens_ray`]: crate::scene::Film::lens_ray
#[inline(always)]
pub(crate) fn camera_sample<S: PixelSampler>(
    film: &Film<'_>,
    filter: PixelFilter,
    sampler: &mut S,
    x: u32,
    y: u32,
    s: u32,
) -> ((f64, f64), Ray) {
    sampler.start_sample((x, y), s);
    let (u, v) = sampler.next_2d();
    let (fx, fy) = match filter {
        PixelFilter::Box => (f64::from(x) + u, f64::from(y) + v),
        f => {
            let o = f.sample(DVec2::new(u, v));
            (f64::from(x) + 0.5 + o.x, f64::from(y) + 0.5 + o.y)
        }
    };
    let ray = if film.has_lens() {
        let (a, b) = sampler.next_2d();
        film.lens_ray(fx, fy, DVec2::new(a, b))
    } else {
        film.ray(fx, fy)
    };
    ((fx, fy), ray)
}

/// Re-trace pixel (x, y) and record its full tree. `None` if the pixel is outside the image.
#[must_use]
pub fn trace_pixel(scene: &Scene, x: u32, y: u32) -> Option<RayTree> {
    trace_pixel_within(scene, x, y, u64::MAX).unwrap_or(None)
}

/// More light paths land in a traced pixel than its caller allowed to record
/// ([`trace_pixel_within`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TooManySplats {
    /// The light paths that splat into the pixel.
    pub paths: u64,
    /// The most the caller allowed.
    pub limit: u64,
}

/// [`trace_pixel`], recording at most `max_splat_paths` light paths that splat into the pixel
/// (under light tracing and BDPT): beyond that, `Err` before any is recorded, so that a caller
/// with a memory budget can refuse (`raytree trace --max-memory`).
///
/// # Errors
/// [`TooManySplats`] when more light paths than `max_splat_paths` land in the pixel.
pub fn trace_pixel_within(
    scene: &Scene,
    x: u32,
    y: u32,
    max_splat_paths: u64,
) -> Result<Option<RayTree>, TooManySplats> {
    if x >= scene.camera.width || y >= scene.camera.height {
        return Ok(None);
    }
    let mut rec = TreeRecorder::default();
    let mut samples = Vec::new();
    let mut counts = RayCounts::default();
    let integrator = SceneIntegrator::new(scene);
    let mut sampler = SceneSampler::for_settings(&scene.settings);
    let (radiance, _) = render_pixel(
        &integrator,
        &mut sampler,
        (x, y),
        &mut rec,
        &mut counts,
        |s| samples.push(s),
    );
    // Automatic antialiasing: an edge pixel took more than its first pass.
    let edge = adaptive_plan(&integrator)
        .filter(|p| p.auto)
        .map(|p| samples.len() > p.first as usize);
    // The settings as traced: the automatic cut and roulette weight are recorded as the values
    // they took (an automatic roulette that is off stays absent).
    // Light tracing: the light paths that land here, recorded after the camera samples.
    let (splats, splat_divisor, radiance) = if integrator.splats() {
        let (records, _) = splat::pixel_splats(&integrator, (x, y), &mut rec, max_splat_paths)
            .map_err(|paths| TooManySplats {
                paths,
                limit: max_splat_paths,
            })?;
        let spp = scene.settings.spp.max(1);
        let radiance = splat::with_splats(radiance, splat::splat_sum(&records), spp);
        (records, spp, radiance)
    } else {
        (Vec::new(), 0, radiance)
    };
    let roulette = crate::integrator::bound::carried::effective_roulette_below(scene);
    let settings = crate::scene::Settings {
        whitted: crate::scene::WhittedSettings {
            min_weight: Some(crate::integrator::bound::effective_min_weight(scene)),
            roulette_below: (roulette > 0.0 || scene.settings.whitted.roulette_below.is_some())
                .then_some(roulette),
            ..scene.settings.whitted
        },
        ..scene.settings
    };
    let schema = if splats.is_empty() {
        TREE_SCHEMA
    } else {
        TREE_SCHEMA_SPLATS
    };
    Ok(Some(RayTree {
        schema: schema.to_string(),
        pixel: [x, y],
        settings,
        radiance,
        samples,
        nodes: rec.nodes,
        edge,
        splats,
        splat_divisor,
    }))
}

/// How [`render`] renders a whole image: the sampler its pixels draw from and whether the
/// diagnostics run.
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions<S = SceneSampler> {
    /// The sampler every row or band copies; `None`: the scene's
    /// ([`SceneSampler::for_settings`]: its kind, `spp` and `seed`). Under automatic
    /// antialiasing ([`AdaptivePlan::auto`]) the film positions are the plan's own (the
    /// pixel's Sobol points) and it is not used.
    pub sampler: Option<S>,
    /// Run the self-hit and leak diagnostics ([`DiagnosticRecorder`]): the same image, plus
    /// the counts in [`RenderStats`] and per pixel in [`Rendered::map`]. Costs extra
    /// intersections per spawned ray.
    pub diagnose: bool,
}

impl RenderOptions {
    /// The scene's sampler, no diagnostics.
    #[must_use]
    pub fn new() -> Self {
        Self {
            sampler: None,
            diagnose: false,
        }
    }

    /// The scene's sampler, with the diagnostics.
    #[must_use]
    pub fn diagnosed() -> Self {
        Self {
            sampler: None,
            diagnose: true,
        }
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: PixelSampler> RenderOptions<S> {
    /// These options drawing from copies of `sampler` instead.
    #[must_use]
    pub fn with_sampler<T: PixelSampler>(self, sampler: T) -> RenderOptions<T> {
        RenderOptions {
            sampler: Some(sampler),
            diagnose: self.diagnose,
        }
    }
}

/// A finished [`render`].
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image (non-finite pixels written black).
    pub image: Image,
    /// What the render did.
    pub stats: RenderStats,
    /// The samples each pixel took ([`DiagnosticMap::samples`]), and with
    /// [`RenderOptions::diagnose`] its self-hit and leak counts (empty otherwise).
    pub map: DiagnosticMap,
}

impl Rendered {
    /// The image, the statistics and the per-pixel map, as a tuple.
    #[must_use]
    pub fn into_parts(self) -> (Image, RenderStats, DiagnosticMap) {
        (self.image, self.stats, self.map)
    }
}

/// Render the whole image by `integrator` in parallel: the one entry point of every command,
/// the inspector and the tests. Rows go over rayon's pool; for scenes with meshes, bands of 8
/// rows whose camera rays are traced as 8x8 packets, the same pixels bit for bit; under light
/// tracing and BDPT the light pass splats after the camera pass. `progress` is called with the
/// number of rows finished so far, from worker threads. Non-finite pixels are written black
/// and counted; [`RenderStats::first_nonfinite`] names the first so its tree can be
/// inspected.
pub fn render<I: Integrator, S: PixelSampler>(
    integrator: &I,
    options: &RenderOptions<S>,
    progress: &(dyn Fn(u32) + Sync),
) -> Rendered {
    let (image, stats, map) = match (&options.sampler, options.diagnose) {
        (Some(s), false) => render_recorded::<NoopRecorder, _, _>(integrator, s, progress),
        (Some(s), true) => render_recorded::<DiagnosticRecorder, _, _>(integrator, s, progress),
        (None, diagnose) => {
            let s = SceneSampler::for_settings(&integrator.scene().settings);
            if diagnose {
                render_recorded::<DiagnosticRecorder, _, _>(integrator, &s, progress)
            } else {
                render_recorded::<NoopRecorder, _, _>(integrator, &s, progress)
            }
        }
    };
    Rendered { image, stats, map }
}

/// Rows `rows` of the image without recording, in parallel over rayon's pool: linear radiance
/// (row-major, non-finite values as traced) and the rays traced. The same pixels as
/// [`render`] (for scenes with meshes, bands of 8 rows from `rows.start` traced as 8x8
/// packets; under adaptive or automatic antialiasing the first passes of the rows and of the
/// rows beside them, which the next band traces again); the inspector shows its image with it
/// before it gathers statistics.
pub fn render_rows<I: Integrator>(
    integrator: &I,
    rows: std::ops::Range<u32>,
) -> (Vec<Rgb>, RayCounts) {
    let scene = integrator.scene();
    let w = scene.camera.width;
    let sampler = SceneSampler::for_settings(&scene.settings);
    let parts: Vec<(Vec<Rgb>, RayCounts)> = if uses_packets::<NoopRecorder, I>(integrator) {
        packet_bands::<NoopRecorder, I, _>(integrator, &sampler, rows, &|_| {})
    } else if let Some(plan) = adaptive_plan(integrator) {
        // The band's first passes and those of the rows beside it once, not a pixel's
        // neighbours per pixel: the same pixels as the render.
        adaptive::band_for(integrator, &sampler, plan, rows)
    } else {
        rows.into_par_iter()
            .map(|y| {
                let mut counts = RayCounts::default();
                let mut sampler = sampler;
                let row = (0..w)
                    .map(|x| {
                        let rec = &mut NoopRecorder;
                        render_pixel(integrator, &mut sampler, (x, y), rec, &mut counts, |_| {}).0
                    })
                    .collect();
                (row, counts)
            })
            .collect()
    };
    let mut pixels = Vec::with_capacity(parts.iter().map(|p| p.0.len()).sum());
    let mut counts = RayCounts::default();
    for (p, c) in parts {
        pixels.extend(p);
        counts += c;
    }
    (pixels, counts)
}

/// Whether a render with recorder `R` traces camera rays as packets: nothing is recorded, the
/// integrator takes packets and the scene has a mesh.
pub(crate) fn uses_packets<R: Recorder, I: Integrator>(integrator: &I) -> bool {
    let scene = integrator.scene();
    !R::RECORDS
        && !R::DIAGNOSE
        && integrator.traces_packets()
        && adaptive_plan(integrator).is_none()
        && scene.camera.width > 0
        && scene
            .objects
            .iter()
            .any(|o| matches!(o.shape, Shape::Mesh(_)))
}

/// Samples every pixel of a render by `integrator` takes at least: `spp`, or the first pass of
/// its [`AdaptivePlan`] (a pixel that took more was refined).
#[must_use]
pub fn first_spp<I: Integrator>(integrator: &I) -> u32 {
    adaptive_plan(integrator).map_or(integrator.scene().settings.spp.max(1), |p| p.first)
}

// Not inlined into `render`: there LLVM compiled the pixel loop's callees (the Whitted
// recursion, the path loop) differently, 2.1-2.5% more instructions for the same source
// (callgrind; docs/architecture.md). Called once per render, so the call costs nothing.
#[inline(never)]
fn render_recorded<R: Recorder + Default, I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, DiagnosticMap) {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spp = scene.settings.spp.max(1);
    let rows: Vec<SinkRow<()>> = if uses_packets::<R, I>(integrator) {
        let done = std::sync::atomic::AtomicU32::new(0);
        let on_band = |n| progress(done.fetch_add(n, std::sync::atomic::Ordering::Relaxed) + n);
        packet_bands::<R, I, S>(integrator, sampler, 0..h, &on_band)
            .into_iter()
            .flat_map(|(band, counts)| {
                let rows: Vec<SinkRow<()>> = band
                    .chunks(w as usize)
                    .enumerate()
                    .map(|(i, row)| {
                        let counts = if i == 0 { counts } else { RayCounts::default() };
                        let row = row.iter().map(|&value| PixelOut {
                            value,
                            taken: spp,
                            diag: (0, 0),
                            out: (),
                        });
                        (row.collect(), counts)
                    })
                    .collect();
                rows
            })
            .collect()
    } else if integrator.splats() {
        // The light pass reports the progress: it is most of the work.
        let mut rows = pixel_loop::rows(integrator, sampler, || Beauty(R::default()), &|_| {});
        let (sums, counts) = splat::light_pass(integrator, progress);
        splat::add_to_rows(&mut rows, &sums, spp, counts);
        rows
    } else {
        pixel_loop::rows(integrator, sampler, || Beauty(R::default()), progress)
    };
    let first = first_spp(integrator);
    let (image, stats, map, _) = pixel_loop::assemble((w, h), first, R::DIAGNOSE, rows);
    (image, stats, map)
}

/// Trace every sample of pixel `(x, y)` by `integrator` into `rec`, drawing from `sampler`
/// (the sampler seam; [`SceneSampler::for_settings`] for the scene's own): sample `s` starts
/// with [`PixelSampler::start_sample`], its film position is the pixel plus the first
/// [`PixelSampler::next_2d`] through the filter (`camera_sample`: then the lens sample of a
/// thin-lens camera), and the integrator draws its further dimensions. Returns the pixel
/// radiance (the mean of its samples) and how many samples it took: `spp`, or with
/// `settings.adaptive` `max_spp` where the pixel is refined (the two passes of
/// `src/render/adaptive.rs`). The pixel loop ([`pixel_loop::pixel`]) with the sink that
/// reports each recorded sample through `on_sample`. Under light tracing and BDPT this is the
/// camera samples' part only: [`trace_pixel`] adds the splats.
pub fn render_pixel<I: Integrator, S: PixelSampler, R: Recorder>(
    integrator: &I,
    sampler: &mut S,
    (x, y): (u32, u32),
    rec: &mut R,
    counts: &mut RayCounts,
    on_sample: impl FnMut(SampleRecord),
) -> (Rgb, u32) {
    let mut sink = pixel_loop::Traced { rec, on_sample };
    let (l, n, ()) = pixel_loop::pixel(integrator, sampler, x, y, &mut sink, counts);
    (l, n)
}

mod adaptive;
mod image;
mod packets;
pub mod pixel_loop;
mod plan;
pub mod splat;
pub mod steps;
pub use image::{DiagnosticMap, Image, RenderStats};
use packets::packet_bands;
use pixel_loop::{Beauty, PixelOut, SinkRow};
pub use plan::{AUTO_FIRST_DIVISOR, AdaptivePlan, adaptive_plan, antialiasing_note};

#[cfg(test)]
mod tests;
