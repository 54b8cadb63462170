//! The one pixel loop: for a pixel, choose its samples (the scene's `spp`, or under an
//! [`AdaptivePlan`](super::AdaptivePlan) the two passes of `src/render/adaptive.rs`), draw each camera sample
//! from the scene's sampler (`camera_sample`), trace it, apply the NaN rule
//! ([`RayCounts::keep_sample`]) and hand it to a [`SampleSink`]. The render ([`Beauty`]), a
//! pixel's tree (`render_pixel`), the AOV render (`crate::aov::render_aovs`: the
//! split by light path expression and the debug views' statistics) and the denoiser's feature
//! gather (`crate::denoise::gather`) are sinks of this loop, so they take the same samples in
//! the same order and their beauty images are the render's bit for bit, adaptive or not.
//!
//! A sink is a generic parameter like the recorder: [`Beauty`] does nothing per sample and its
//! pixel data is `()`, so the render's loop compiles to the plain loop.

use super::{Image, RenderStats, camera_sample};
use crate::integrator::{Integrator, RayCounts, Recorder};
use crate::math::{Ray, Rgb};
use crate::sampling::{PixelFilter, PixelSampler};
use crate::scene::{Film, IntegratorKind};
use crate::tree::{NodeId, SampleRecord};
use rayon::prelude::*;

/// One camera sample as the loop traced it.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// The pixel.
    pub pixel: (u32, u32),
    /// Sample index within the pixel (the second adaptive pass goes on from `spp`).
    pub index: u32,
    /// Film position in pixels.
    pub film: (f64, f64),
    /// The camera ray.
    pub ray: Ray,
    /// The sample's radiance as traced (possibly not finite).
    pub radiance: Rgb,
    /// Whether the radiance enters the pixel's sum ([`RayCounts::keep_sample`]); a dropped
    /// sample enters as black.
    pub kept: bool,
    /// The recorded root node, when the sink's recorder records.
    pub root: Option<NodeId>,
}

/// What the pixel loop hands every camera sample to.
pub trait SampleSink {
    /// The recorder the samples are traced with.
    type Rec: Recorder;
    /// Per-pixel state while its samples come in (kept between the adaptive passes).
    type Pixel: Default + Send;
    /// A finished pixel's result.
    type Out: Send;
    /// The recorder for the next sample.
    fn recorder(&mut self) -> &mut Self::Rec;
    /// Called before each sample is traced.
    #[inline(always)]
    fn start_sample(&mut self) {}
    /// Sample `s` of the pixel whose state is `px`, after tracing.
    fn sample(&mut self, px: &mut Self::Pixel, s: &Sample);
    /// The pixel took `taken` samples in all.
    fn finish(&mut self, px: Self::Pixel, taken: u32) -> Self::Out;
}

/// The render's sink: only the beauty (the loop's own sum), traced with recorder `R`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Beauty<R>(pub R);

impl<R: Recorder> SampleSink for Beauty<R> {
    type Rec = R;
    type Pixel = ();
    type Out = ();
    #[inline(always)]
    fn recorder(&mut self) -> &mut R {
        &mut self.0
    }
    #[inline(always)]
    fn sample(&mut self, (): &mut (), _: &Sample) {}
    #[inline(always)]
    fn finish(&mut self, (): (), _: u32) {}
}

/// A pixel's tree: samples recorded into `rec`, each root reported as a [`SampleRecord`].
pub(super) struct Traced<'a, R, F> {
    pub rec: &'a mut R,
    pub on_sample: F,
}

impl<R: Recorder, F: FnMut(SampleRecord)> SampleSink for Traced<'_, R, F> {
    type Rec = R;
    type Pixel = ();
    type Out = ();
    #[inline(always)]
    fn recorder(&mut self) -> &mut R {
        self.rec
    }
    #[inline(always)]
    fn sample(&mut self, (): &mut (), s: &Sample) {
        if let Some(root) = s.root {
            (self.on_sample)(SampleRecord {
                index: s.index,
                film: [s.film.0, s.film.1],
                root,
                radiance: s.radiance,
            });
        }
    }
    #[inline(always)]
    fn finish(&mut self, (): (), _: u32) {}
}

/// What is fixed for every sample of a render: film, filter, whether the NaN rule keeps all.
#[derive(Clone, Copy)]
pub(crate) struct Camera<'a> {
    film: &'a Film<'a>,
    filter: PixelFilter,
    whitted: bool,
}

impl<'a> Camera<'a> {
    #[inline(always)]
    pub(crate) fn new<I: Integrator>(integrator: &'a I) -> Self {
        Self {
            film: integrator.film(),
            filter: integrator.scene().settings.filter.filter(),
            whitted: integrator.kind() == IntegratorKind::Whitted,
        }
    }

    /// Start sample `s` of pixel (x, y) in `sampler`: its film position and camera ray, as
    /// the pixel loop draws them.
    #[inline(always)]
    pub(crate) fn sample<S: PixelSampler>(
        self,
        sampler: &mut S,
        x: u32,
        y: u32,
        s: u32,
    ) -> ((f64, f64), Ray) {
        camera_sample(self.film, self.filter, sampler, x, y, s)
    }
}

/// Sample `s` of pixel (x, y) traced into `sink`: returns its radiance and whether it is kept.
#[inline(always)]
// The integrator, camera and sampler of the sample, the sample's index, and the sink, pixel and counts it adds to.
#[allow(clippy::too_many_arguments)]
pub(crate) fn one_sample<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    cam: Camera<'_>,
    sampler: &mut S,
    (x, y, s): (u32, u32, u32),
    sink: &mut K,
    px: &mut K::Pixel,
    counts: &mut RayCounts,
) -> (Rgb, bool) {
    let (film, ray) = cam.sample(sampler, x, y, s);
    sink.start_sample();
    let (l, root) = integrator.camera_radiance(ray, sampler, sink.recorder(), counts);
    let kept = counts.keep_sample(l, cam.whitted, (x, y, s));
    let sample = Sample {
        pixel: (x, y),
        index: s,
        film,
        ray,
        radiance: l,
        kept,
        root,
    };
    sink.sample(px, &sample);
    (l, kept)
}

/// Every sample of pixel (x, y) into `sink`: the pixel radiance (the mean of its samples), how
/// many samples it took (`spp`, or under an [`AdaptivePlan`](super::AdaptivePlan) its first
/// pass or its refined total) and the sink's result.
pub fn pixel<I: Integrator, S: PixelSampler, K: SampleSink>(
    integrator: &I,
    sampler: &mut S,
    x: u32,
    y: u32,
    sink: &mut K,
    counts: &mut RayCounts,
) -> (Rgb, u32, K::Out) {
    if let Some(plan) = super::adaptive_plan(integrator) {
        return super::adaptive::pixel(integrator, sampler, plan, (x, y), sink, counts);
    }
    let cam = Camera::new(integrator);
    let spp = integrator.scene().settings.spp.max(1);
    let mut px = K::Pixel::default();
    let mut sum = crate::math::PixelSum::default();
    for s in 0..spp {
        let (l, kept) = one_sample(integrator, cam, sampler, (x, y, s), sink, &mut px, counts);
        if kept {
            sum += l;
        }
    }
    (sum / f64::from(spp), spp, sink.finish(px, spp))
}

/// A finished pixel of a render through a sink.
#[derive(Clone, Debug)]
pub(crate) struct PixelOut<O> {
    /// Its radiance (not yet admitted: possibly not finite).
    pub value: Rgb,
    /// Samples it took.
    pub taken: u32,
    /// Self-hit and leaking rays (a diagnosing recorder only).
    pub diag: (u32, u32),
    /// The sink's result.
    pub out: O,
}

/// One row of pixels and its ray counts.
pub(crate) type SinkRow<O> = (Vec<PixelOut<O>>, RayCounts);

/// Self-hits and leaks between two counts.
pub(super) fn diag(before: &RayCounts, after: &RayCounts) -> (u32, u32) {
    (
        (after.self_hits - before.self_hits) as u32,
        (after.leaks - before.leaks) as u32,
    )
}

/// Every row of the image through sinks from `make` (one per rayon work split), rows in
/// parallel over copies of `sampler`; `progress` gets the number of rows finished. Under an
/// [`AdaptivePlan`](super::AdaptivePlan), every pixel's first pass and then the decisions and
/// second passes ([`super::adaptive::rows`]).
pub(crate) fn rows<I, S, K, F>(
    integrator: &I,
    sampler: &S,
    make: F,
    progress: &(dyn Fn(u32) + Sync),
) -> Vec<SinkRow<K::Out>>
where
    I: Integrator,
    S: PixelSampler,
    K: SampleSink,
    F: Fn() -> K + Sync + Send,
{
    let scene = integrator.scene();
    let done = std::sync::atomic::AtomicU32::new(0);
    let on_row = || progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
    if let Some(plan) = super::adaptive_plan(integrator) {
        return super::adaptive::rows(integrator, sampler, plan, make, &on_row);
    }
    let w = scene.camera.width;
    (0..scene.camera.height)
        .into_par_iter()
        .map_init(make, |sink, y| {
            let mut counts = RayCounts::default();
            let mut sampler = sampler.clone();
            let row = (0..w)
                .map(|x| {
                    let before = counts;
                    let (value, taken, out) =
                        pixel(integrator, &mut sampler, x, y, sink, &mut counts);
                    let diag = if K::Rec::DIAGNOSE {
                        diag(&before, &counts)
                    } else {
                        (0, 0)
                    };
                    PixelOut {
                        value,
                        taken,
                        diag,
                        out,
                    }
                })
                .collect();
            on_row();
            (row, counts)
        })
        .collect()
}

/// The image, the render's counts, the per-pixel samples (and with `diagnose` the self-hits
/// and leaks) and the sinks' results of `rows`: every pixel admitted by
/// [`RenderStats::admit_pixel`]; a pixel that took more than `first` samples counts as refined.
pub(crate) fn assemble<O>(
    (w, h): (u32, u32),
    first: u32,
    diagnose: bool,
    rows: Vec<SinkRow<O>>,
) -> (Image, RenderStats, super::DiagnosticMap, Vec<O>) {
    let n = (w * h) as usize;
    let mut stats = RenderStats::default();
    let mut pixels = Vec::with_capacity(n);
    let mut outs = Vec::with_capacity(n);
    let mut map = super::DiagnosticMap {
        width: w,
        height: h,
        samples: Vec::with_capacity(n),
        ..super::DiagnosticMap::default()
    };
    let first = first.max(1);
    for (y, (row, counts)) in rows.into_iter().enumerate() {
        stats.rays += counts;
        for (x, p) in row.into_iter().enumerate() {
            stats.samples += u64::from(p.taken);
            stats.refined_pixels += u64::from(p.taken > first);
            map.samples.push(p.taken);
            pixels.push(stats.admit_pixel(p.value, x, y));
            if diagnose {
                let (s, l) = p.diag;
                stats.self_hit_pixels += u64::from(s > 0);
                stats.leak_pixels += u64::from(l > 0);
                map.self_hits.push(s);
                map.leaks.push(l);
            }
            outs.push(p.out);
        }
    }
    let image = Image {
        width: w,
        height: h,
        pixels,
    };
    (image, stats, map, outs)
}
