//! The render worker: one background thread renders bands of rows (in parallel over rayon) and
//! sends each band through a channel, so the UI never blocks and the image appears progressively.
//!
//! Every job carries a generation number; starting a new job bumps the shared counter, the worker
//! abandons a job as soon as it sees a newer generation, and the receiver ignores stale bands.

use super::stats::{PixelStats, StatsRecorder};
use crate::math::Rgb;
use crate::render::render_pixel;
use crate::scene::Scene;
use crate::trace::RayCounts;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

/// Rows rendered between cancellation checks and deliveries.
pub const BAND_ROWS: u32 = 8;

/// Called from the worker thread after each delivery (the app passes `ctx.request_repaint`).
pub type Repaint = Arc<dyn Fn() + Send + Sync>;

/// What the worker sends back.
#[derive(Debug)]
pub enum Delivery {
    /// Rows `y0 .. y0 + pixels.len() / width` of generation `generation`.
    Band {
        /// The job this band belongs to.
        generation: u64,
        /// First row.
        y0: u32,
        /// Linear radiance, row-major.
        pixels: Vec<Rgb>,
        /// Debug statistics, one per pixel.
        stats: Vec<PixelStats>,
    },
    /// Generation `generation` finished.
    Done {
        /// The finished job.
        generation: u64,
        /// Wall-clock seconds of the whole render.
        seconds: f64,
        /// Rays traced.
        rays: RayCounts,
    },
}

impl Delivery {
    /// The generation this delivery belongs to.
    #[must_use]
    pub fn generation(&self) -> u64 {
        match self {
            Delivery::Band { generation, .. } | Delivery::Done { generation, .. } => *generation,
        }
    }
}

struct Job {
    generation: u64,
    scene: Arc<Scene>,
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
    pub fn start(&self, scene: Arc<Scene>) -> u64 {
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        if let Some(jobs) = &self.jobs {
            // The thread only ends when we drop the sender, so this cannot fail.
            let _ = jobs.send(Job { generation, scene });
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
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spp = scene.settings.spp.max(1);
    let start = Instant::now();
    let total = Mutex::new(RayCounts::default());
    let mut y0 = 0;
    while y0 < h {
        if current.load(Ordering::SeqCst) != job.generation {
            return;
        }
        let y1 = (y0 + BAND_ROWS).min(h);
        let rows: Vec<(Vec<Rgb>, Vec<PixelStats>)> = (y0..y1)
            .into_par_iter()
            .map(|y| {
                let mut rec = StatsRecorder::default();
                let mut counts = RayCounts::default();
                let mut px = Vec::with_capacity(w as usize);
                let mut st = Vec::with_capacity(w as usize);
                for x in 0..w {
                    let l = render_pixel(scene, x, y, &mut rec, &mut counts, |_| {});
                    px.push(if l.is_finite() { l } else { Rgb::ZERO });
                    st.push(rec.take(spp));
                }
                *total.lock().expect("no panics while holding the lock") += counts;
                (px, st)
            })
            .collect();
        let (pixels, stats) =
            rows.into_iter()
                .fold((Vec::new(), Vec::new()), |(mut p, mut s), (rp, rs)| {
                    p.extend(rp);
                    s.extend(rs);
                    (p, s)
                });
        let band = Delivery::Band {
            generation: job.generation,
            y0,
            pixels,
            stats,
        };
        if tx.send(band).is_err() {
            return;
        }
        repaint();
        y0 = y1;
    }
    let rays = *total.lock().expect("no panics while holding the lock");
    let done = Delivery::Done {
        generation: job.generation,
        seconds: start.elapsed().as_secs_f64(),
        rays,
    };
    let _ = tx.send(done);
    repaint();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_newer_job_supersedes_an_older_one_and_matches_render() {
        let w = Worker::new(Arc::new(|| {}));
        let mut scene = Scene::default_scene();
        scene.camera = scene.camera.with_size(64, 36);
        let g1 = w.start(Arc::new(scene.clone()));
        scene.settings.max_depth = 0;
        let g2 = w.start(Arc::new(scene.clone()));
        assert!(g2 > g1);
        let mut pixels = vec![Rgb::ZERO; 64 * 36];
        loop {
            match w.recv().unwrap() {
                Delivery::Band {
                    generation,
                    y0,
                    pixels: p,
                    ..
                } if generation == g2 => {
                    let at = y0 as usize * 64;
                    pixels[at..at + p.len()].copy_from_slice(&p);
                }
                Delivery::Done { generation, .. } if generation == g2 => break,
                d => assert_eq!(d.generation(), g1),
            }
        }
        let (image, _) = crate::render(&scene, &|_| {});
        assert_eq!(pixels, image.pixels);
    }
}
