//! Progressive rendering in the inspector (issue 16): the image is rendered in passes of
//! growing sample counts, each pixel accumulating a running sum (the image) and a Welford
//! running mean and variance of its samples' luminance (the noise estimate), delivered after
//! every band so the window refines live, until the estimate falls below a target or the
//! samples reach a cap.
//!
//! Passes draw samples `first..first + count` of each pixel through the sampler seam
//! ([`PixelSampler::refine`] on the scene's [`SceneSampler`]): the first pass is
//! [`FIRST_PASS`] samples, every later pass doubles the total (4, 8, 16, ...). Under the Sobol
//! sampler (the path integrator's default) the sequence just continues, and the sum is added
//! sample by sample in index order as `render` adds it, so the image after `N` samples equals
//! `render` at `spp = N` bit for bit (a test checks it). Under the stratified sampler each pass
//! lies on its own complete stratified grid (as adaptive antialiasing's second pass does): the
//! first pass equals `render` at 4 spp, later totals are unbiased but not `render`'s grid.
//! Adaptive antialiasing (`settings.adaptive`) is not applied to progressive passes, and mesh
//! scenes are traced pixel by pixel (no packets; the same pixels, a little slower).
//!
//! The noise estimate: for pixel `i` with `n` samples of luminance mean `m_i` and Welford sum
//! of squared deviations `M2_i`, the variance of its mean is `M2_i / (n (n - 1))`, its relative
//! standard error `r_i = sqrt(M2_i / (n (n - 1))) / (m_i + 0.01)`, and the image's estimate the
//! RMS of `r_i` over the pixels. It assumes independent samples, so under Sobol (whose error
//! falls faster than `1/sqrt(n)`) it overstates the error: a conservative stop.

#[cfg(test)]
mod tests;

use super::delivery::Delivery;
use crate::bsdf::luminance;
use crate::gui::model::progressive::{Composition, Options, Report, Stop, composition};
use crate::integrator::{Integrator, NoopRecorder, RayCounts};
use crate::math::Rgb;
use crate::render::pixel_loop::{self, Beauty};
use crate::sampling::{PixelSampler, SceneSampler};
use rayon::prelude::*;
use web_time::Instant;

/// Samples per pixel of the first pass.
pub const FIRST_PASS: u32 = 4;
/// Added to a pixel's mean luminance before dividing, so black pixels do not dominate.
pub const OFFSET: f64 = 0.01;

/// One pixel's running sum (of radiance) and Welford state (of luminance).
#[derive(Clone, Copy, Debug, Default)]
pub struct PixelAcc {
    sum: Rgb,
    mean: f64,
    m2: f64,
}

impl PixelAcc {
    /// Add the pixel's sample number `k` (0-based: `k` samples came before).
    #[inline]
    pub fn add(&mut self, k: u32, l: Rgb) {
        self.sum += l;
        let y = luminance(l);
        let y = if y.is_finite() { y } else { 0.0 };
        let delta = y - self.mean;
        self.mean += delta / f64::from(k + 1);
        self.m2 += delta * (y - self.mean);
    }

    /// The luminance mean and the variance of that mean after `n` samples.
    #[must_use]
    pub fn mean_and_variance(&self, n: u32) -> (f64, f64) {
        let var = if n > 1 {
            self.m2 / (f64::from(n) * f64::from(n - 1))
        } else {
            f64::INFINITY
        };
        (self.mean, var)
    }
}

/// The progressive image: one [`PixelAcc`] per pixel, all with the same sample count.
#[derive(Clone, Debug)]
pub struct Accumulator {
    width: u32,
    pixels: Vec<PixelAcc>,
    samples: u32,
}

impl Accumulator {
    /// An empty accumulator for a `width x height` image.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            pixels: vec![PixelAcc::default(); (width * height) as usize],
            samples: 0,
        }
    }

    /// Samples per pixel of the finished passes.
    #[must_use]
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Pixel `i` (row-major).
    #[must_use]
    pub fn pixel(&self, i: usize) -> &PixelAcc {
        &self.pixels[i]
    }

    /// Rows `y0..y1` of the image after `n` samples (non-finite pixels black).
    #[must_use]
    pub fn rows(&self, y0: u32, y1: u32, n: u32) -> Vec<Rgb> {
        let w = self.width as usize;
        self.pixels[y0 as usize * w..y1 as usize * w]
            .iter()
            .map(|p| {
                let l = p.sum / f64::from(n.max(1));
                if l.is_finite() { l } else { Rgb::ZERO }
            })
            .collect()
    }

    /// The image's mean relative standard error: the RMS over pixels of
    /// `sqrt(var of mean) / (mean luminance + OFFSET)` (infinite below two samples).
    #[must_use]
    pub fn error(&self) -> f64 {
        if self.samples < 2 || self.pixels.is_empty() {
            return f64::INFINITY;
        }
        let sum: f64 = self.terms().iter().sum();
        (sum / self.pixels.len() as f64).sqrt()
    }

    /// Each pixel's squared relative error `var of mean / (mean luminance + OFFSET)^2`
    /// (row-major; infinite below two samples): the terms whose mean is the square of
    /// [`Self::error`].
    #[must_use]
    pub fn terms(&self) -> Vec<f64> {
        self.pixels
            .iter()
            .map(|p| {
                let (m, v) = p.mean_and_variance(self.samples);
                v / (m.abs() + OFFSET).powi(2)
            })
            .collect()
    }

    /// Which pixels carry the estimate ([`composition`]).
    #[must_use]
    pub fn composition(&self) -> Option<Composition> {
        composition(&self.terms(), self.width)
    }

    /// Trace samples `first..first + count` of rows `rows` (in parallel over rows) into the
    /// pixels; `first` must be [`Self::samples`]. Returns the rays traced. Rows stop early,
    /// between pixels, once `cancelled` says so (the accumulator is then to be dropped).
    pub fn trace<I: Integrator>(
        &mut self,
        integrator: &I,
        sampler: &SceneSampler,
        (first, count): (u32, u32),
        rows: std::ops::Range<u32>,
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> RayCounts {
        let w = self.width as usize;
        let cam = pixel_loop::Camera::new(integrator);
        let mut pass = *sampler;
        pass.refine(first, count);
        self.pixels[rows.start as usize * w..rows.end as usize * w]
            .par_chunks_mut(w)
            .enumerate()
            .map(|(i, row)| {
                let y = rows.start + i as u32;
                let mut sampler = pass;
                let mut counts = RayCounts::default();
                for (x, p) in row.iter_mut().enumerate() {
                    if cancelled() {
                        break;
                    }
                    for s in first..first + count {
                        // The render's sample: a non-finite path sample is dropped (black,
                        // counted).
                        let (l, kept) = pixel_loop::one_sample(
                            integrator,
                            cam,
                            &mut sampler,
                            (x as u32, y, s),
                            &mut Beauty(NoopRecorder),
                            &mut (),
                            &mut counts,
                        );
                        p.add(s, if kept { l } else { Rgb::ZERO });
                    }
                }
                counts
            })
            .reduce(RayCounts::default, |mut a, b| {
                a += b;
                a
            })
    }

    /// Declare a pass of `count` samples finished.
    pub fn finish_pass(&mut self, count: u32) {
        self.samples += count;
    }
}

/// Why a run ends after a pass with `error` at `spp` samples, if it does.
#[must_use]
pub fn stop_rule(options: &Options, spp: u32, error: f64) -> Option<Stop> {
    if error <= options.target {
        Some(Stop::Target)
    } else if spp >= options.cap.max(1) {
        Some(Stop::Cap)
    } else {
        None
    }
}

/// What [`Run::step`] did.
pub enum Step {
    /// A band is delivered; more are to come.
    More,
    /// The run stopped (target or cap) after its last pass: the rays traced.
    Finished(RayCounts),
    /// Cancelled, or the receiver is gone.
    Stopped,
}

/// A progressive render in progress, one band at a time, for the worker: bands of every pass
/// as [`Delivery::Band`], a [`Delivery::Pass`] after each pass.
pub struct Run {
    options: Options,
    start: Instant,
    sampler: SceneSampler,
    acc: Accumulator,
    rays: RayCounts,
    /// Samples of the pass under way.
    count: u32,
    /// Next row of that pass.
    y0: u32,
    /// Rows of a band at the first pass ([`super::worker::IMAGE_ROWS`] on the worker thread).
    max_rows: u32,
}

impl Run {
    /// The first pass of `scene` under `options`, in bands of at most `max_rows` rows.
    #[must_use]
    pub fn new(scene: &crate::scene::Scene, options: Options, max_rows: u32) -> Self {
        let (w, h) = (scene.camera.width, scene.camera.height);
        Self {
            options,
            start: Instant::now(),
            sampler: SceneSampler::for_settings(&scene.settings),
            acc: Accumulator::new(w, h),
            rays: RayCounts::default(),
            count: FIRST_PASS.min(options.cap.max(1)),
            y0: 0,
            max_rows: max_rows.max(1),
        }
    }

    /// Trace and deliver the next band of the pass under way (and, after its last band, the
    /// pass's report). `integrator` is that of the scene given to [`Run::new`].
    pub fn step<I: Integrator>(
        &mut self,
        integrator: &I,
        generation: u64,
        cancelled: &(dyn Fn() -> bool + Sync),
        send: &dyn Fn(Delivery) -> bool,
    ) -> Step {
        let h = integrator.scene().camera.height;
        if cancelled() {
            return Step::Stopped;
        }
        let (first, count, y0) = (self.acc.samples(), self.count, self.y0);
        // Bands shrink as passes grow (32 rows at 4 samples, 8 from 16 on, on the worker
        // thread), so the image still refines every few seconds.
        let max = self.max_rows;
        let rows = (max * FIRST_PASS / count.max(1)).clamp((max / 4).max(1), max);
        let y1 = (y0 + rows).min(h);
        self.rays += self
            .acc
            .trace(integrator, &self.sampler, (first, count), y0..y1, cancelled);
        let pixels = self.acc.rows(y0, y1, first + count);
        if !send(Delivery::Band {
            generation,
            y0,
            pixels,
        }) {
            return Step::Stopped;
        }
        self.y0 = y1;
        if y1 < h {
            return Step::More;
        }
        self.finish_pass(generation, send)
    }

    fn finish_pass(&mut self, generation: u64, send: &dyn Fn(Delivery) -> bool) -> Step {
        self.acc.finish_pass(self.count);
        let spp = self.acc.samples();
        let error = self.acc.error();
        let stop = stop_rule(&self.options, spp, error);
        let report = Report {
            spp,
            error,
            seconds: self.start.elapsed().as_secs_f64(),
            stop,
            composition: self.acc.composition(),
        };
        if !send(Delivery::Pass { generation, report }) {
            return Step::Stopped;
        }
        if stop.is_some() {
            return Step::Finished(self.rays);
        }
        self.count = spp.min(self.options.cap.max(1) - spp);
        self.y0 = 0;
        Step::More
    }
}
