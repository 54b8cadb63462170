//! The render worker: one background thread renders bands of rows (in parallel over rayon) and
//! sends each band through a channel, so the UI never blocks and the image appears progressively.
//! On wasm32, which has no threads, the same job (`JobRun`, `worker/job.rs`) runs on the UI
//! thread in slices between frames instead ([`Worker::tick`]), a pixel at a time.
//! It works in two passes: the image on the plain render's path
//! ([`crate::render::render_rows`]: no recording, packets for meshes), then the per-pixel debug
//! statistics, which record every ray and cost a few times more; the image is the same either way, so it is shown as soon as it exists.
//!
//! Every job carries a generation number; starting a new job bumps the shared counter, the worker
//! abandons a job as soon as it sees a newer generation, and the receiver ignores stale bands.

use super::delivery::Delivery;
use crate::integrator::SceneIntegrator;
use crate::scene::Scene;
use job::JobRun;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};

/// Rows of statistics gathered between cancellation checks and deliveries.
pub const BAND_ROWS: u32 = 8;
/// Rows of the image rendered between cancellation checks and deliveries (four packet bands).
pub const IMAGE_ROWS: u32 = 32;
/// Milliseconds of rendering per frame on the UI thread (wasm32), so a frame stays near 60 Hz.
pub const SLICE_BUDGET_MS: f64 = 12.0;

/// Called from the worker thread after each delivery (the app passes `ctx.request_repaint`).
pub type Repaint = Arc<dyn Fn() + Send + Sync>;

struct Job {
    generation: u64,
    scene: Arc<Scene>,
    image_first: bool,
    progressive: Option<crate::gui::model::progressive::Options>,
}

/// A handle on the render thread (native) or the job in slices (wasm32). Dropping it cancels
/// the current job (and joins the thread).
pub struct Worker {
    generation: Arc<AtomicU64>,
    deliveries: Receiver<Delivery>,
    #[cfg(not(target_arch = "wasm32"))]
    jobs: Option<Sender<Job>>,
    #[cfg(not(target_arch = "wasm32"))]
    thread: Option<std::thread::JoinHandle<()>>,
    #[cfg(target_arch = "wasm32")]
    inline: Inline,
}

impl Worker {
    /// Start the thread. `repaint` is called after every delivery.
    #[cfg(not(target_arch = "wasm32"))]
    #[must_use]
    pub fn new(repaint: Repaint) -> Self {
        let (jobs, job_rx) = channel::<Job>();
        let (tx, deliveries) = channel();
        let generation = Arc::new(AtomicU64::new(0));
        let current = Arc::clone(&generation);
        let thread = std::thread::Builder::new()
            .name("raytree-render".into())
            .stack_size(crate::integrator::THREAD_STACK_BYTES)
            .spawn(move || {
                while let Ok(mut job) = job_rx.recv() {
                    // Only the newest queued job matters.
                    while let Ok(newer) = job_rx.try_recv() {
                        job = newer;
                    }
                    run_job(job, &current, &tx, &repaint);
                }
            })
            .expect("can spawn the render thread");
        Self {
            generation,
            deliveries,
            jobs: Some(jobs),
            thread: Some(thread),
        }
    }

    /// No thread on wasm32: jobs run in [`Worker::tick`]. `repaint` is called after every
    /// delivery.
    #[cfg(target_arch = "wasm32")]
    #[must_use]
    pub fn new(repaint: Repaint) -> Self {
        let (tx, deliveries) = channel();
        Self {
            generation: Arc::new(AtomicU64::new(0)),
            deliveries,
            inline: Inline {
                run: std::sync::Mutex::new(None),
                tx,
                repaint,
            },
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
        options: crate::gui::model::progressive::Options,
    ) -> u64 {
        self.start_job(scene, true, Some(options))
    }

    fn start_job(
        &self,
        scene: Arc<Scene>,
        image_first: bool,
        progressive: Option<crate::gui::model::progressive::Options>,
    ) -> u64 {
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        let job = Job {
            generation,
            scene,
            image_first,
            progressive,
        };
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(jobs) = &self.jobs {
            // The thread only ends when we drop the sender, so this cannot fail.
            let _ = jobs.send(job);
        }
        #[cfg(target_arch = "wasm32")]
        {
            *self.inline.lock() = Some(JobRun::by_pixels(job));
            (self.inline.repaint)();
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

    /// Block until the next delivery (`None` if the thread is gone, or on wasm32 when the
    /// job is finished); on wasm32 the job runs here until it delivers.
    #[must_use]
    pub fn recv(&self) -> Option<Delivery> {
        #[cfg(target_arch = "wasm32")]
        loop {
            if let Ok(d) = self.deliveries.try_recv() {
                return Some(d);
            }
            if !self.tick_for(f64::INFINITY, 1) {
                return self.deliveries.try_recv().ok();
            }
        }
        #[cfg(not(target_arch = "wasm32"))]
        self.deliveries.recv().ok()
    }

    /// Run the current job on this thread for about [`SLICE_BUDGET_MS`] (wasm32; natively
    /// the thread does the work and this does nothing). Returns whether work remains.
    pub fn tick(&self) -> bool {
        #[cfg(target_arch = "wasm32")]
        return self.tick_for(SLICE_BUDGET_MS, usize::MAX);
        #[cfg(not(target_arch = "wasm32"))]
        false
    }

    /// Slices of the current job until `budget_ms` have passed or `max_steps` are done.
    #[cfg(target_arch = "wasm32")]
    fn tick_for(&self, budget_ms: f64, max_steps: usize) -> bool {
        let mut slot = self.inline.lock();
        let Some(run) = slot.as_mut() else {
            return false;
        };
        let more = run_slices(run, &self.generation, &self.inline.tx, budget_ms, max_steps);
        if !more {
            *slot = None;
        }
        (self.inline.repaint)();
        more
    }
}

/// The wasm32 worker's state: the job under way and the sending end of its deliveries.
#[cfg(target_arch = "wasm32")]
struct Inline {
    run: std::sync::Mutex<Option<JobRun>>,
    tx: Sender<Delivery>,
    repaint: Repaint,
}

#[cfg(target_arch = "wasm32")]
impl Inline {
    fn lock(&self) -> std::sync::MutexGuard<'_, Option<JobRun>> {
        self.run
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.generation.fetch_add(1, Ordering::SeqCst);
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.jobs = None;
            if let Some(t) = self.thread.take() {
                let _ = t.join();
            }
        }
    }
}

/// Run `job` to its end (or until a newer generation cancels it) on this thread.
#[cfg(not(target_arch = "wasm32"))]
fn run_job(job: Job, current: &AtomicU64, tx: &Sender<Delivery>, repaint: &Repaint) {
    let scene = Arc::clone(&job.scene);
    let tracer = SceneIntegrator::new(&scene);
    let generation = job.generation;
    let cancelled = || current.load(Ordering::SeqCst) != generation;
    let send = |d: Delivery| {
        let sent = tx.send(d).is_ok();
        repaint();
        sent
    };
    let mut run = JobRun::new(job, IMAGE_ROWS, BAND_ROWS);
    while run.step(&tracer, &cancelled, &send, &|| true) {}
}

/// Steps of `run` until it ends, `budget_ms` of wall-clock time have passed or `max_steps` are
/// done; returns whether it goes on. The UI thread's path (wasm32), tested natively.
#[cfg(any(target_arch = "wasm32", test))]
fn run_slices(
    run: &mut JobRun,
    current: &AtomicU64,
    tx: &Sender<Delivery>,
    budget_ms: f64,
    max_steps: usize,
) -> bool {
    let start = web_time::Instant::now();
    let scene = Arc::clone(&run.job.scene);
    let tracer = SceneIntegrator::new(&scene);
    let generation = run.generation();
    let cancelled = || current.load(Ordering::SeqCst) != generation;
    let send = |d: Delivery| tx.send(d).is_ok();
    let more_time = || start.elapsed().as_secs_f64() * 1e3 < budget_ms;
    for _ in 0..max_steps {
        if !run.step(&tracer, &cancelled, &send, &more_time) {
            return false;
        }
        if !more_time() {
            break;
        }
    }
    true
}

mod job;
#[cfg(test)]
mod tests;
