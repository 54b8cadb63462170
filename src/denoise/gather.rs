//! The render with feature buffers: the same samples as [`crate::render::render`] with a sampler (the
//! same pixel loop, [`crate::render::pixel_loop`], with adaptive antialiasing's passes when the
//! scene has them, so the same image bit for bit), plus per pixel the mean albedo and normal of
//! its samples' feature rays and the variance of its mean luminance. With adaptive
//! antialiasing a refined pixel's features are over all its samples; [`Features::spp`] is the
//! first pass's `spp` (the fewest a pixel takes).

use super::Features;
use super::features::first_non_delta;
use crate::bsdf::luminance;
use crate::integrator::{Integrator, NoopRecorder, Whitted};
use crate::math::Rgb;
use crate::render::pixel_loop::{self, Sample, SampleSink};
use crate::render::steps::Steps;
use crate::render::{DiagnosticMap, Image, RenderStats};
use crate::sampling::{PixelSampler, SceneSampler};
use glam::DVec3;

/// One pixel's features.
struct Px {
    albedo: Rgb,
    normal: DVec3,
    emitted: Rgb,
    emitter: f64,
    variance: f64,
    albedo_variance: f64,
}

/// The gather's sink of the pixel loop: each sample's feature ray
/// ([`first_non_delta`] of its camera ray) and luminance.
struct FeatureSink<'a>(&'a Whitted<'a>, NoopRecorder);

/// One pixel's sums while its samples come in.
#[derive(Default)]
struct Sums {
    albedo: Rgb,
    normal: DVec3,
    /// Sum of the directly seen emission, and the number of samples that see an emitter.
    emitted: Rgb,
    emitters: u32,
    /// Sum and sum of squares of the finite samples' luminance, and their number.
    m: (f64, f64, u32),
    /// Sum and sum of squares of the albedo's luminance.
    a: (f64, f64),
}

impl SampleSink for FeatureSink<'_> {
    type Rec = NoopRecorder;
    type Pixel = Sums;
    type Out = Px;

    #[inline(always)]
    fn recorder(&mut self) -> &mut NoopRecorder {
        &mut self.1
    }

    fn sample(&mut self, px: &mut Sums, s: &Sample) {
        let f = first_non_delta(self.0, s.ray);
        if s.radiance.is_finite() {
            let y = luminance(s.radiance);
            px.m.0 += y;
            px.m.1 += y * y;
            px.m.2 += 1;
        }
        px.albedo += f.albedo;
        let ya = luminance(f.albedo);
        px.a.0 += ya;
        px.a.1 += ya * ya;
        px.normal += f.normal;
        if f.emitted != Rgb::ZERO {
            px.emitted += f.emitted;
            px.emitters += 1;
        }
    }

    fn finish(&mut self, px: Sums, taken: u32) -> Px {
        let k = f64::from(taken);
        Px {
            albedo: px.albedo / k,
            normal: px.normal / k,
            emitted: px.emitted / k,
            emitter: f64::from(px.emitters) / k,
            // Variance of the mean: the unbiased sample variance over n.
            variance: variance_of_mean(px.m.0, px.m.1, px.m.2),
            albedo_variance: variance_of_mean(px.a.0, px.a.1, taken),
        }
    }
}

/// [`gather_sampled`] with the scene's default sampler, as [`crate::render::render`] by default.
pub fn gather<I: Integrator>(
    integrator: &I,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, Features) {
    let sampler = SceneSampler::for_settings(&integrator.scene().settings);
    gather_sampled(integrator, &sampler, progress)
}

/// Render every pixel as [`crate::render::render`] with a sampler does (the pixel loop, rows in
/// parallel, copies of `sampler`; with `settings.adaptive` its two passes), and gather the
/// features over each pixel's samples. `progress` is called with the rows finished so far.
pub fn gather_sampled<I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, Features) {
    let (image, stats, features, _) = gather_counted(integrator, sampler, progress);
    (image, stats, features)
}

/// [`gather_sampled`] that also returns the samples each pixel took
/// ([`DiagnosticMap::samples`], as [`crate::render::Rendered::map`]'s; its self-hit and
/// leak counts stay empty).
pub fn gather_counted<I: Integrator, S: PixelSampler>(
    integrator: &I,
    sampler: &S,
    progress: &(dyn Fn(u32) + Sync),
) -> (Image, RenderStats, Features, DiagnosticMap) {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let tracer = Whitted::new(scene);
    let make = || FeatureSink(&tracer, NoopRecorder);
    let rows = pixel_loop::rows(integrator, sampler, make, progress);
    let first = crate::render::first_spp(integrator);
    let (image, stats, map, outs) = pixel_loop::assemble((w, h), first, false, rows);
    let features = features_of(integrator, outs);
    (image, stats, features, map)
}

/// The features of a render by `integrator` from its pixels' gathered sums (non-finite values
/// written 0).
fn features_of<I: Integrator>(integrator: &I, outs: Vec<Px>) -> Features {
    let scene = integrator.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let n = (w * h) as usize;
    let mut features = Features {
        width: w,
        height: h,
        albedo: Vec::with_capacity(n),
        normal: Vec::with_capacity(n),
        variance: Vec::with_capacity(n),
        albedo_variance: Vec::with_capacity(n),
        emitted: Vec::with_capacity(n),
        emitter: Vec::with_capacity(n),
        spp: scene.settings.spp.max(1),
        stochastic: !integrator.traces_packets() || integrator.film().has_lens(),
    };
    let finite = |v: Rgb| if v.is_finite() { v } else { Rgb::ZERO };
    let finite_f = |v: f64| if v.is_finite() { v } else { 0.0 };
    for p in outs {
        features.albedo.push(finite(p.albedo));
        features.normal.push(finite(p.normal));
        features.variance.push(finite_f(p.variance));
        features.albedo_variance.push(finite_f(p.albedo_variance));
        features.emitted.push(finite(p.emitted));
        features.emitter.push(finite_f(p.emitter));
    }
    features
}

/// [`gather`] a piece at a time ([`crate::render::steps`]; the web page has no threads): the
/// same image, counts and features, bit for bit.
pub struct GatherSteps(Steps<Px>);

impl GatherSteps {
    /// The gather of a render by `integrator`.
    #[must_use]
    pub fn new<I: Integrator>(integrator: &I) -> Self {
        Self(Steps::new(integrator, false).camera_only())
    }

    /// Trace pixels by `integrator` (the same scene as [`GatherSteps::new`]'s) while
    /// `more_time` says so, at least one; returns whether more is to come.
    pub fn step<I: Integrator>(&mut self, integrator: &I, more_time: &dyn Fn() -> bool) -> bool {
        let scene = integrator.scene();
        let sampler = SceneSampler::for_settings(&scene.settings);
        let tracer = Whitted::new(scene);
        self.0.step(
            integrator,
            &sampler,
            &|| FeatureSink(&tracer, NoopRecorder),
            more_time,
        )
    }

    /// The image, its counts and its features, as [`gather`] returns them (call once
    /// [`GatherSteps::step`] returned `false`; `integrator` as there).
    #[must_use]
    pub fn finish<I: Integrator>(self, integrator: &I) -> (Image, RenderStats, Features) {
        let (image, stats, _, outs) = self.0.finish();
        (image, stats, features_of(integrator, outs))
    }
}

/// The variance of the mean of `n` values from their sum `s1` and sum of squares `s2` (the
/// unbiased sample variance over `n`); 0 for fewer than two values.
fn variance_of_mean(s1: f64, s2: f64, n: u32) -> f64 {
    if n < 2 {
        return 0.0;
    }
    let nf = f64::from(n);
    let mean = s1 / nf;
    (s2 / nf - mean * mean).max(0.0) / (nf - 1.0)
}
