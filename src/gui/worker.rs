//! The render worker: one background thread renders bands of rows (in parallel over rayon) and
//! sends each band through a channel, so the UI never blocks and the image appears progressively.
//! It works in two passes: the image on the plain render's path ([`render_rows`]: no recording,
//! packets for meshes), then the per-pixel debug statistics, which record every ray and cost
//! a few times more; the image is the same either way, so it is shown as soon as it exists.
//!
//! Every job carries a generation number; starting a new job bumps the shared counter, the worker
//! abandons a job as soon as it sees a newer generation, and the receiver ignores stale bands.

use super::stats::{PixelStats, StatsRecorder};
use crate::math::Rgb;
use crate::render::{render_pixel_with, render_rows};
use crate::scene::Scene;
use crate::trace::{RayCounts, SceneIntegrator};
use rayon::prelude::*;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;
use std::time::Instant;

/// Rows of statistics gathered between cancellation checks and deliveries.
pub const BAND_ROWS: u32 = 8;
/// Rows of the image rendered between cancellation checks and deliveries (four packet bands).
pub const IMAGE_ROWS: u32 = 32;

/// Called from the worker thread after each delivery (the app passes `ctx.request_repaint`).
pub type Repaint = Arc<dyn Fn() + Send + Sync>;

/// What the worker sends back.
#[derive(Debug)]
pub enum Delivery {
    /// Image rows `y0 .. y0 + pixels.len() / width` of generation `generation`.
    Band {
        /// The job this band belongs to.
        generation: u64,
        /// First row.
        y0: u32,
        /// Linear radiance, row-major (non-finite values written black).
        pixels: Vec<Rgb>,
    },
    /// The image of generation `generation` is complete.
    Done {
        /// The finished job.
        generation: u64,
        /// Wall-clock seconds of the image pass.
        seconds: f64,
        /// Rays traced.
        rays: RayCounts,
    },
    /// Debug statistics of rows `y0 .. y0 + stats.len() / width`.
    Stats {
        /// The job these rows belong to.
        generation: u64,
        /// First row.
        y0: u32,
        /// One per pixel, row-major.
        stats: Vec<PixelStats>,
    },
    /// The statistics of generation `generation` are complete.
    StatsDone {
        /// The finished job.
        generation: u64,
        /// Wall-clock seconds of the statistics pass.
        seconds: f64,
    },
    /// How the scene's ray tree grows and what the automatic cut saves (issue 18), measured
    /// after the statistics.
    Growth {
        /// The job this belongs to.
        generation: u64,
        /// One line for the statistics.
        line: String,
    },
    /// A progressive pass is complete ([`super::progressive`]).
    Pass {
        /// The job this belongs to.
        generation: u64,
        /// The samples so far, the noise estimate and whether the run stopped.
        report: super::progressive::Report,
    },
}

impl Delivery {
    /// The generation this delivery belongs to.
    #[must_use]
    pub fn generation(&self) -> u64 {
        match self {
            Delivery::Band { generation, .. }
            | Delivery::Done { generation, .. }
            | Delivery::Stats { generation, .. }
            | Delivery::StatsDone { generation, .. }
            | Delivery::Growth { generation, .. }
            | Delivery::Pass { generation, .. } => *generation,
        }
    }
}

struct Job {
    generation: u64,
    scene: Arc<Scene>,
    image_first: bool,
    progressive: Option<super::progressive::Options>,
}

/// A handle on the render thread. Dropping it cancels the current job and joins the thread.
pub struct Worker {
    jobs: Option<Sender<Job>>,
    deliveries: Receiver<Delivery>,
    generation: Arc<AtomicU64>,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// Start the thread. `repaint` is called after every delivery.
    #[must_use]
    pub fn new(repaint: Repaint) -> Self {
        let (jobs, job_rx) = channel::<Job>();
        let (tx, deliveries) = channel();
        let generation = Arc::new(AtomicU64::new(0));
        let current = Arc::clone(&generation);
        let thread = std::thread::Builder::new()
            .name("raytree-render".into())
            .stack_size(crate::trace::THREAD_STACK_BYTES)
            .spawn(move || {
                while let Ok(mut job) = job_rx.recv() {
                    // Only the newest queued job matters.
                    while let Ok(newer) = job_rx.try_recv() {
                        job = newer;
                    }
                    run_job(&job, &current, &tx, &repaint);
                }
            })
            .expect("can spawn the render thread");
        Self {
            jobs: Some(jobs),
            deliveries,
            generation,
            thread: Some(thread),
        }
    }

    /// Render `scene` as a new generation (cancelling any older one); returns the generation.
    /// With `image_first` the image is rendered on the plain path and the statistics gathered
    /// after it; without, one pass records every ray and delivers both (sooner statistics, for
    /// a debug view on screen, later image).
    pub fn start(&self, scene: Arc<Scene>, image_first: bool) -> u64 {
        self.start_job(scene, image_first, None)
    }

    /// Render `scene` progressively ([`super::progressive`]) as a new generation, then gather
    /// its statistics at the scene's settings; returns the generation.
    pub fn start_progressive(
        &self,
        scene: Arc<Scene>,
        options: super::progressive::Options,
    ) -> u64 {
        self.start_job(scene, true, Some(options))
    }

    fn start_job(
        &self,
        scene: Arc<Scene>,
        image_first: bool,
        progressive: Option<super::progressive::Options>,
    ) -> u64 {
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        if let Some(jobs) = &self.jobs {
            // The thread only ends when we drop the sender, so this cannot fail.
            let _ = jobs.send(Job {
                generation,
                scene,
                image_first,
                progressive,
            });
        }
        generation
    }

    /// The newest generation started.
    #[must_use]
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::SeqCst)
    }

    /// A delivery if one is waiting.
    #[must_use]
    pub fn try_recv(&self) -> Option<Delivery> {
        self.deliveries.try_recv().ok()
    }

    /// Block until the next delivery (`None` if the thread is gone).
    #[must_use]
    pub fn recv(&self) -> Option<Delivery> {
        self.deliveries.recv().ok()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.generation.fetch_add(1, Ordering::SeqCst);
        self.jobs = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn run_job(job: &Job, current: &AtomicU64, tx: &Sender<Delivery>, repaint: &Repaint) {
    let scene = &*job.scene;
    let tracer = SceneIntegrator::new(scene);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let cancelled = || current.load(Ordering::SeqCst) != job.generation;
    let send = |d: Delivery| {
        let sent = tx.send(d).is_ok();
        repaint();
        sent
    };
    // 1. The image, on the plain render's path.
    let start = Instant::now();
    let mut rays = RayCounts::default();
    if let Some(options) = &job.progressive {
        match super::progressive::run(&tracer, options, job.generation, &cancelled, &send) {
            Some(r) => rays = r,
            None => return,
        }
    }
    let mut y0 = if job.image_first && job.progressive.is_none() {
        0
    } else {
        h
    };
    while y0 < h {
        if cancelled() {
            return;
        }
        let y1 = (y0 + IMAGE_ROWS).min(h);
        let (mut pixels, counts) = render_rows(&tracer, y0..y1);
        for p in &mut pixels {
            if !p.is_finite() {
                *p = Rgb::ZERO;
            }
        }
        rays += counts;
        let generation = job.generation;
        if !send(Delivery::Band {
            generation,
            y0,
            pixels,
        }) {
            return;
        }
        y0 = y1;
    }
    if job.image_first
        && !send(Delivery::Done {
            generation: job.generation,
            seconds: start.elapsed().as_secs_f64(),
            rays,
        })
    {
        return;
    }
    // 2. The debug statistics: every ray recorded, folded per pixel (and the image too, when
    // it was not rendered first: the recorded pass computes the same pixels).
    let start = Instant::now();
    let spp = scene.settings.spp.max(1);
    let mut y0 = 0;
    while y0 < h {
        if cancelled() {
            return;
        }
        let y1 = (y0 + BAND_ROWS).min(h);
        let rows: Vec<(Vec<Rgb>, Vec<PixelStats>, RayCounts)> = (y0..y1)
            .into_par_iter()
            .map(|y| {
                let mut rec = StatsRecorder::default();
                let mut counts = RayCounts::default();
                let (px, st) = (0..w)
                    .map(|x| {
                        let l = render_pixel_with(&tracer, x, y, &mut rec, &mut counts, |_| {});
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
            rays += counts;
        }
        if !job.image_first
            && !send(Delivery::Band {
                generation: job.generation,
                y0,
                pixels,
            })
        {
            return;
        }
        if !send(Delivery::Stats {
            generation: job.generation,
            y0,
            stats,
        }) {
            return;
        }
        y0 = y1;
    }
    let seconds = start.elapsed().as_secs_f64();
    if !job.image_first
        && !send(Delivery::Done {
            generation: job.generation,
            seconds,
            rays,
        })
    {
        return;
    }
    if !send(Delivery::StatsDone {
        generation: job.generation,
        seconds,
    }) {
        return;
    }
    // 3. The tree's growth and, where it grows, the rays of the automatic cut against the
    // exhaustive tree on a 16x9 sample (cancelled between pixels like the passes above).
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
        match crate::analysis::growth::cut_savings(scene, 16, 9, &cancelled) {
            Some(c) => line += &format!("; {}", c.sentence()),
            None => return,
        }
    }
    send(Delivery::Growth {
        generation: job.generation,
        line,
    });
}

#[cfg(test)]
mod tests;
