//! A render a piece at a time, for a caller that has no threads and must give control back
//! between pieces (the web page's UI thread, between frames): [`Steps::step`] traces pixels
//! while the caller's clock allows, [`Steps::finish`] assembles what
//! [`super::render`] (or a sink's render such as the AOV render) returns, bit for bit.
//!
//! The pieces are pixels (every sample of one), in row order: the camera pass, then under
//! light tracing and BDPT the light paths seeded by each pixel, their splats added in path
//! order as [`super::splat::light_pass`] adds them. A pixel's value depends on its own samples
//! only, so the pieces give the render's pixels whatever their size. Under an
//! [`super::AdaptivePlan`] (adaptive or automatic antialiasing) a pixel's decision depends on
//! its neighbours' first passes: each pixel traces them again, unrecorded and uncounted, as a
//! pixel's tree does ([`super::render_pixel`]), where the whole render traces each once; the
//! same pixels, counts and sink results, for up to 8 more first passes a pixel.

use super::pixel_loop::{self, Beauty, PixelOut, SampleSink, SinkRow};
use super::{DiagnosticMap, Image, RenderStats, Rendered, splat};
use crate::integrator::{DiagnosticRecorder, Integrator, NoopRecorder, RayCounts, Recorder};
use crate::math::Rgb;
use crate::sampling::{PixelSampler, SceneSampler};

/// A render under way ([`Steps::step`]); `O` is the sink's per-pixel result (`()` for the
/// plain render).
pub struct Steps<O> {
    size: (u32, u32),
    spp: u32,
    first: u32,
    diagnose: bool,
    /// Finished rows, then the row under way.
    rows: Vec<SinkRow<O>>,
    row: SinkRow<O>,
    /// The light pass (light tracing, BDPT): the next seeding pixel and the splat sums.
    light: Option<LightPass>,
    /// The camera pass is complete.
    camera_done: bool,
}

/// The light pass under way: the next seeding pixel (row-major index), the sums so far and
/// the rays traced.
struct LightPass {
    next: u64,
    sums: Vec<Rgb>,
    counts: RayCounts,
}

impl<O: Send> Steps<O> {
    /// A render by `integrator` (whose scene fixes size, spp, the plan and the light pass),
    /// recorded by sinks whose recorder diagnoses when `diagnose` (as
    /// [`super::RenderOptions::diagnose`]).
    #[must_use]
    pub fn new<I: Integrator>(integrator: &I, diagnose: bool) -> Self {
        let scene = integrator.scene();
        let size = (scene.camera.width, scene.camera.height);
        let n = size.0 as usize * size.1 as usize;
        Self {
            size,
            spp: scene.settings.spp.max(1),
            first: super::first_spp(integrator),
            diagnose,
            rows: Vec::with_capacity(size.1 as usize),
            row: (Vec::with_capacity(size.0 as usize), RayCounts::default()),
            light: integrator.splats().then(|| LightPass {
                next: 0,
                sums: vec![Rgb::ZERO; n],
                counts: RayCounts::default(),
            }),
            camera_done: size.0 == 0 || size.1 == 0,
        }
    }

    /// Trace pixels by `integrator` (the same scene as [`Steps::new`]'s) into sinks from
    /// `make`, drawing from copies of `sampler`, while `more_time` says so (at least one pixel
    /// a call). Returns whether more is to come.
    pub fn step<I, S, K, F>(
        &mut self,
        integrator: &I,
        sampler: &S,
        make: &F,
        more_time: &dyn Fn() -> bool,
    ) -> bool
    where
        I: Integrator,
        S: PixelSampler,
        K: SampleSink<Out = O>,
        F: Fn() -> K + Sync + Send,
    {
        if !self.camera_done {
            self.camera_pixels(integrator, sampler, make(), more_time);
            if !self.camera_done || !more_time() {
                return self.more();
            }
        }
        if let Some(light) = &mut self.light {
            light.paths(integrator, self.size, more_time);
        }
        self.more()
    }

    /// These steps without the light pass: the camera samples' part of a render by light
    /// tracing or BDPT, as the renders through a sink other than the plain render's trace it
    /// (the AOV render, the denoiser's gather).
    #[must_use]
    pub fn camera_only(mut self) -> Self {
        self.light = None;
        self
    }

    fn more(&self) -> bool {
        let n = u64::from(self.size.0) * u64::from(self.size.1);
        !self.camera_done || self.light.as_ref().is_some_and(|l| l.next < n)
    }

    /// The camera pass's pixels from where it stands, while `more_time` (at least one).
    fn camera_pixels<I, S, K>(
        &mut self,
        integrator: &I,
        sampler: &S,
        mut sink: K,
        more_time: &dyn Fn() -> bool,
    ) where
        I: Integrator,
        S: PixelSampler,
        K: SampleSink<Out = O>,
    {
        let (w, h) = self.size;
        let mut sampler = sampler.clone();
        loop {
            let (row, counts) = &mut self.row;
            let (x, y) = (row.len() as u32, self.rows.len() as u32);
            let before = *counts;
            let (value, taken, out) =
                pixel_loop::pixel(integrator, &mut sampler, x, y, &mut sink, counts);
            let diag = if K::Rec::DIAGNOSE {
                pixel_loop::diag(&before, counts)
            } else {
                (0, 0)
            };
            row.push(PixelOut {
                value,
                taken,
                diag,
                out,
            });
            if x + 1 == w {
                let next = (Vec::with_capacity(w as usize), RayCounts::default());
                self.rows.push(std::mem::replace(&mut self.row, next));
                if y + 1 == h {
                    self.camera_done = true;
                    return;
                }
            }
            if !more_time() {
                return;
            }
        }
    }

    /// The finished render: image, counts, per-pixel map (self-hits and leaks when
    /// diagnosing) and the sinks' results, as the render through a sink returns them.
    #[must_use]
    pub fn finish(mut self) -> (Image, RenderStats, DiagnosticMap, Vec<O>) {
        if let Some(light) = self.light.take() {
            splat::add_to_rows(&mut self.rows, &light.sums, self.spp, light.counts);
        }
        pixel_loop::assemble(self.size, self.first, self.diagnose, self.rows)
    }
}

impl Steps<()> {
    /// One step of a plain render ([`super::render`] with [`super::RenderOptions::new`], or
    /// [`super::RenderOptions::diagnosed`] when the steps diagnose): the scene's sampler, the
    /// render's recorder.
    pub fn step_plain<I: Integrator>(
        &mut self,
        integrator: &I,
        more_time: &dyn Fn() -> bool,
    ) -> bool {
        let sampler = SceneSampler::for_settings(&integrator.scene().settings);
        if self.diagnose {
            let make = || Beauty(DiagnosticRecorder);
            self.step(integrator, &sampler, &make, more_time)
        } else {
            let make = || Beauty(NoopRecorder);
            self.step(integrator, &sampler, &make, more_time)
        }
    }

    /// The finished plain render: the image, counts and map [`super::render`] returns.
    #[must_use]
    pub fn rendered(self) -> Rendered {
        let (image, stats, map, _) = self.finish();
        Rendered { image, stats, map }
    }
}

impl LightPass {
    /// The light paths of the seeding pixels from `next` on, while `more_time` (at least one).
    fn paths<I: Integrator>(
        &mut self,
        integrator: &I,
        (w, h): (u32, u32),
        more_time: &dyn Fn() -> bool,
    ) {
        let n = u64::from(w) * u64::from(h);
        let mut sampler = splat::light_sampler(integrator);
        while self.next < n {
            let (x, y) = (
                (self.next % u64::from(w)) as u32,
                (self.next / u64::from(w)) as u32,
            );
            let sums = &mut self.sums;
            splat::light_pixel(
                integrator,
                (x, y),
                &mut sampler,
                &mut NoopRecorder,
                &mut self.counts,
                |_, sp| {
                    let (px, py) = sp.pixel;
                    sums[py as usize * w as usize + px as usize] += sp.contribution;
                },
            );
            self.next += 1;
            if !more_time() {
                return;
            }
        }
    }
}

#[cfg(test)]
mod tests;
