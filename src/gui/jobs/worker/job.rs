//! One render job as a resumable state machine: [`JobRun::step`] does one band (of the
//! progressive passes, the image, or the statistics) or the closing growth line, and says
//! whether more is to come. The native worker thread calls it in a loop; on wasm32, which has
//! no threads, the UI thread calls it between frames for a time budget ([`super::Worker::tick`]).
//! Either way the deliveries are the same pixels, statistics and lines in the same order
//! (bands may be cut at other rows: a row's pixels do not depend on its band).

use super::Job;
use crate::gui::jobs::delivery::Delivery;
use crate::gui::jobs::progressive;
use crate::gui::model::stats::{PixelStats, StatsRecorder};
use crate::integrator::{Integrator, NoopRecorder, RayCounts, SceneIntegrator};
use crate::math::Rgb;
use crate::render::{render_pixel, render_rows};
use crate::sampling::SceneSampler;
use rayon::prelude::*;
use web_time::Instant;

/// Where a job stands.
enum Phase {
    /// Progressive passes (the image).
    Progressive(Box<progressive::Run>),
    /// The image on the plain render's path, from row `y0`.
    Image(u32),
    /// The recorded statistics pass, from row `y0`.
    Stats(u32),
    /// The tree-growth line.
    Growth,
    /// Nothing left.
    Finished,
}

/// A job in progress.
pub(super) struct JobRun {
    pub(super) job: Job,
    phase: Phase,
    rays: RayCounts,
    start: Instant,
    image_rows: u32,
    band_rows: u32,
    /// On the UI thread (wasm32): bands of one row, filled a pixel at a time until the slice's
    /// time is up ([`Row`]).
    row: Option<Row>,
    /// Light tracing: the whole image's splat sums, from the light pass the first band runs
    /// (`crate::render::splat`), added to each band's camera pixels.
    splats: Option<Vec<Rgb>>,
}

/// The row under way on the UI thread: its pixels (and statistics) so far.
#[derive(Default)]
struct Row {
    pixels: Vec<Rgb>,
    stats: Vec<PixelStats>,
}

impl JobRun {
    /// Start `job`, cutting the image into bands of `image_rows` and the statistics into bands
    /// of `band_rows` (the worker thread's: [`super::IMAGE_ROWS`], [`super::BAND_ROWS`]).
    pub(super) fn new(job: Job, image_rows: u32, band_rows: u32) -> Self {
        let h = job.scene.camera.height;
        let phase = match job.progressive {
            Some(options) => Phase::Progressive(Box::new(progressive::Run::new(
                &job.scene, options, image_rows,
            ))),
            None if job.image_first => Phase::Image(0),
            None => Phase::Image(h),
        };
        Self {
            job,
            phase,
            rays: RayCounts::default(),
            start: Instant::now(),
            image_rows: image_rows.max(1),
            band_rows: band_rows.max(1),
            row: None,
            splats: None,
        }
    }

    /// Start `job` for the UI thread: one-row bands, each filled a pixel at a time so that a
    /// slice stops within a pixel of its time (progressive passes keep their bands).
    #[cfg(any(target_arch = "wasm32", test))]
    pub(super) fn by_pixels(job: Job) -> Self {
        let mut run = Self::new(job, 1, 1);
        run.row = Some(Row::default());
        run
    }

    /// The job's generation.
    #[cfg(any(target_arch = "wasm32", test))]
    pub(super) fn generation(&self) -> u64 {
        self.job.generation
    }

    /// Do the next piece; `false` once the job is finished, cancelled or its receiver is gone.
    /// `tracer` is the integrator of the job's scene; a job `JobRun::by_pixels` goes on to
    /// the next pixel while `more_time` says so.
    pub(super) fn step(
        &mut self,
        tracer: &SceneIntegrator<'_>,
        cancelled: &(dyn Fn() -> bool + Sync),
        send: &dyn Fn(Delivery) -> bool,
        more_time: &dyn Fn() -> bool,
    ) -> bool {
        if cancelled() {
            self.phase = Phase::Finished;
        }
        let next = match std::mem::replace(&mut self.phase, Phase::Finished) {
            Phase::Progressive(mut run) => {
                match run.step(tracer, self.job.generation, cancelled, send) {
                    progressive::Step::More => {
                        self.phase = Phase::Progressive(run);
                        return true;
                    }
                    progressive::Step::Finished(r) => {
                        self.rays = r;
                        self.image_done(send)
                    }
                    progressive::Step::Stopped => None,
                }
            }
            Phase::Image(y0) if self.by_pixel(tracer) && y0 < self.job.scene.camera.height => {
                self.image_pixels(y0, tracer, send, more_time)
            }
            Phase::Stats(y0) if self.row.is_some() && y0 < self.job.scene.camera.height => {
                self.stats_pixels(y0, tracer, send, more_time)
            }
            Phase::Image(y0) => self.image_band(y0, tracer, send),
            Phase::Stats(y0) => self.stats_band(y0, tracer, send),
            Phase::Growth => {
                self.growth(cancelled, send);
                None
            }
            Phase::Finished => None,
        };
        self.phase = next.unwrap_or(Phase::Finished);
        !matches!(self.phase, Phase::Finished)
    }

    /// Add light tracing's splats to the camera pixels of the band from row `y0` (the light
    /// pass runs once, for the first band that needs it): the render's pixels bit for bit. A
    /// pixel that is not finite is shown black.
    fn add_splats(&mut self, tracer: &SceneIntegrator<'_>, y0: u32, pixels: &mut [Rgb]) {
        if tracer.splats() {
            if self.splats.is_none() {
                let (sums, counts) = crate::render::splat::light_pass(tracer, &|_| {});
                self.rays += counts;
                self.splats = Some(sums);
            }
            let sums = self.splats.as_deref().unwrap_or_default();
            let spp = self.job.scene.settings.spp;
            let start = y0 as usize * self.job.scene.camera.width as usize;
            for (p, s) in pixels.iter_mut().zip(&sums[start..]) {
                *p = crate::render::splat::with_splats(*p, *s, spp);
            }
        }
        for p in pixels {
            if !p.is_finite() {
                *p = Rgb::ZERO;
            }
        }
    }

    /// Pass 1, the image, on the plain render's path: rows `y0..` of one band.
    fn image_band(
        &mut self,
        y0: u32,
        tracer: &SceneIntegrator<'_>,
        send: &dyn Fn(Delivery) -> bool,
    ) -> Option<Phase> {
        let h = self.job.scene.camera.height;
        if y0 >= h {
            return self.image_done(send);
        }
        let y1 = (y0 + self.image_rows).min(h);
        let (mut pixels, counts) = render_rows(tracer, y0..y1);
        self.add_splats(tracer, y0, &mut pixels);
        self.rays += counts;
        let generation = self.job.generation;
        send(Delivery::Band {
            generation,
            y0,
            pixels,
        })
        .then_some(Phase::Image(y1))
    }

    /// The image is complete (when it came first); on to the statistics.
    fn image_done(&mut self, send: &dyn Fn(Delivery) -> bool) -> Option<Phase> {
        if self.job.image_first
            && !send(Delivery::Done {
                generation: self.job.generation,
                seconds: self.start.elapsed().as_secs_f64(),
                rays: self.rays,
            })
        {
            return None;
        }
        self.start = Instant::now();
        Some(Phase::Stats(0))
    }

    /// Pass 2, the debug statistics: every ray recorded, folded per pixel (and the image too, when
    /// it was not rendered first: the recorded pass computes the same pixels).
    fn stats_band(
        &mut self,
        y0: u32,
        tracer: &SceneIntegrator<'_>,
        send: &dyn Fn(Delivery) -> bool,
    ) -> Option<Phase> {
        let scene = &*self.job.scene;
        let (w, h) = (scene.camera.width, scene.camera.height);
        if y0 >= h {
            return self.stats_done(send);
        }
        let spp = scene.settings.spp.max(1);
        let y1 = (y0 + self.band_rows).min(h);
        let rows: Vec<(Vec<Rgb>, Vec<PixelStats>, RayCounts)> = (y0..y1)
            .into_par_iter()
            .map(|y| {
                let mut rec = StatsRecorder::default();
                let mut counts = RayCounts::default();
                // One sampler per row, as the render's pixel loop keeps one: each sample
                // restarts it at its (pixel, index), so the pixels are the same.
                let mut sampler = SceneSampler::for_settings(&tracer.scene().settings);
                let (px, st) = (0..w)
                    .map(|x| {
                        let l = render_pixel(
                            tracer,
                            &mut sampler,
                            (x, y),
                            &mut rec,
                            &mut counts,
                            |_| {},
                        )
                        .0;
                        (if l.is_finite() { l } else { Rgb::ZERO }, rec.take(spp))
                    })
                    .unzip();
                (px, st, counts)
            })
            .collect();
        let mut pixels = Vec::new();
        let mut stats = Vec::new();
        for (p, st, counts) in rows {
            pixels.extend(p);
            stats.extend(st);
            self.rays += counts;
        }
        self.add_splats(tracer, y0, &mut pixels);
        let generation = self.job.generation;
        if !self.job.image_first
            && !send(Delivery::Band {
                generation,
                y0,
                pixels,
            })
        {
            return None;
        }
        send(Delivery::Stats {
            generation,
            y0,
            stats,
        })
        .then_some(Phase::Stats(y1))
    }

    fn stats_done(&mut self, send: &dyn Fn(Delivery) -> bool) -> Option<Phase> {
        let seconds = self.start.elapsed().as_secs_f64();
        let generation = self.job.generation;
        if !self.job.image_first
            && !send(Delivery::Done {
                generation,
                seconds,
                rays: self.rays,
            })
        {
            return None;
        }
        send(Delivery::StatsDone {
            generation,
            seconds,
        })
        .then_some(Phase::Growth)
    }

    /// Whether the image goes a pixel at a time: on the UI thread, unless the render's path
    /// works on whole bands (mesh packets, adaptive antialiasing), which then go a row at a time.
    fn by_pixel(&self, tracer: &SceneIntegrator<'_>) -> bool {
        self.row.is_some()
            && !crate::render::uses_packets::<NoopRecorder, _>(tracer)
            && crate::render::adaptive_plan(tracer).is_none()
    }

    /// The image's row `y0`, pixel by pixel (the plain render's pixels: its per-pixel path).
    fn image_pixels(
        &mut self,
        y0: u32,
        tracer: &SceneIntegrator<'_>,
        send: &dyn Fn(Delivery) -> bool,
        more_time: &dyn Fn() -> bool,
    ) -> Option<Phase> {
        let w = self.job.scene.camera.width;
        let row = self.row.get_or_insert_with(Row::default);
        let mut sampler = SceneSampler::for_settings(&tracer.scene().settings);
        loop {
            let x = row.pixels.len() as u32;
            let l = render_pixel(
                tracer,
                &mut sampler,
                (x, y0),
                &mut NoopRecorder,
                &mut self.rays,
                |_| {},
            )
            .0;
            row.pixels.push(if l.is_finite() { l } else { Rgb::ZERO });
            if x + 1 == w {
                break;
            }
            if !more_time() {
                return Some(Phase::Image(y0));
            }
        }
        let mut pixels = std::mem::take(&mut row.pixels);
        self.add_splats(tracer, y0, &mut pixels);
        let generation = self.job.generation;
        send(Delivery::Band {
            generation,
            y0,
            pixels,
        })
        .then_some(Phase::Image(y0 + 1))
    }

    /// The statistics of row `y0`, pixel by pixel.
    fn stats_pixels(
        &mut self,
        y0: u32,
        tracer: &SceneIntegrator<'_>,
        send: &dyn Fn(Delivery) -> bool,
        more_time: &dyn Fn() -> bool,
    ) -> Option<Phase> {
        let w = self.job.scene.camera.width;
        let spp = self.job.scene.settings.spp.max(1);
        let row = self.row.get_or_insert_with(Row::default);
        let mut rec = StatsRecorder::default();
        let mut sampler = SceneSampler::for_settings(&tracer.scene().settings);
        loop {
            let x = row.stats.len() as u32;
            let l = render_pixel(
                tracer,
                &mut sampler,
                (x, y0),
                &mut rec,
                &mut self.rays,
                |_| {},
            )
            .0;
            row.pixels.push(if l.is_finite() { l } else { Rgb::ZERO });
            row.stats.push(rec.take(spp));
            if x + 1 == w {
                break;
            }
            if !more_time() {
                return Some(Phase::Stats(y0));
            }
        }
        let (mut pixels, stats) = (
            std::mem::take(&mut row.pixels),
            std::mem::take(&mut row.stats),
        );
        self.add_splats(tracer, y0, &mut pixels);
        let generation = self.job.generation;
        if !self.job.image_first
            && !send(Delivery::Band {
                generation,
                y0,
                pixels,
            })
        {
            return None;
        }
        send(Delivery::Stats {
            generation,
            y0,
            stats,
        })
        .then_some(Phase::Stats(y0 + 1))
    }

    /// Last, the tree's growth and, where it grows, the rays of the automatic cut against the
    /// exhaustive tree on a 16x9 sample (cancelled between pixels like the passes above).
    fn growth(&self, cancelled: &(dyn Fn() -> bool + Sync), send: &dyn Fn(Delivery) -> bool) {
        let scene = &*self.job.scene;
        let growth = crate::analysis::growth::tree_growth(scene);
        // Under the path integrator the tree and the cut are Whitted's: the line says so.
        let mut line = if scene.settings.integrator == crate::scene::IntegratorKind::Path {
            format!(
                "path integrator: one path per sample, no split, no cut; under Whitted the ray \
                 tree would be {}",
                growth.growth.word()
            )
        } else {
            format!("ray tree {}", growth.growth.word())
        };
        if let Some(r) = growth.reasons.first() {
            line += &format!(" ({r})");
        }
        if growth.growth != crate::analysis::growth::Growth::Bounded {
            match crate::analysis::growth::cut_savings(scene, 16, 9, cancelled) {
                Some(c) => line += &format!("; {}", c.sentence()),
                None => return,
            }
        }
        send(Delivery::Growth {
            generation: self.job.generation,
            line,
        });
    }
}
