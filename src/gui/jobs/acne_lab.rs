//! The acne lab's worker (issue 17): on a thread of its own, the inspector's scene scaled and
//! moved from the origin as `raytree acne` does ([`crate::analysis::acne`]), rendered with the
//! diagnostics on: first the lab's chosen strategy and epsilon (the count of affected pixels),
//! then every strategy at every epsilon of [`sweep_epsilons`] (the sweep plot). Cell by cell,
//! each sent as it is done; a newer job cancels an older one between cells. No egui here.

use super::worker::Repaint;
use crate::analysis::acne::{AcneCell, CellSteps, cell, scaled_scene};
use crate::gui::model::lab::LabParams;
use crate::scene::{OffsetStrategy, Scene};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};

/// Width of the render that counts the chosen setting's affected pixels.
pub const CURRENT_WIDTH: u32 = 160;
/// Width of each render of the sweep.
pub const SWEEP_WIDTH: u32 = 48;

/// The epsilons of the sweep plot: 0, then 1e-9 to 1e-1 by decades.
#[must_use]
pub fn sweep_epsilons() -> Vec<f64> {
    std::iter::once(0.0)
        .chain((-9..=-1).map(|e| 10f64.powi(e)))
        .collect()
}

/// Renders in a whole lab job: the count, then the sweep.
#[must_use]
pub fn job_len() -> usize {
    1 + OffsetStrategy::ALL.len() * sweep_epsilons().len()
}

/// What the lab's thread sends back.
#[derive(Debug)]
pub enum LabDelivery {
    /// The chosen strategy and epsilon at [`CURRENT_WIDTH`].
    Current(u64, AcneCell),
    /// One cell of the sweep at [`SWEEP_WIDTH`] (strategies in [`OffsetStrategy::ALL`] order,
    /// then epsilons).
    Sweep(u64, AcneCell),
    /// The job is complete.
    Done(u64),
}

impl LabDelivery {
    /// The job this belongs to.
    #[must_use]
    pub fn generation(&self) -> u64 {
        match self {
            LabDelivery::Current(g, _) | LabDelivery::Sweep(g, _) | LabDelivery::Done(g) => *g,
        }
    }
}

struct Job {
    generation: u64,
    scene: Arc<Scene>,
    params: LabParams,
}

/// The lab's worker ([`super::background::Lane`]: a thread natively). Dropping it cancels the
/// job (and joins the thread).
pub struct LabWorker {
    deliveries: Receiver<LabDelivery>,
    generation: Arc<AtomicU64>,
    jobs: Option<super::background::Lane<Job>>,
}

impl LabWorker {
    /// Start the worker (`None` if the system refuses a thread); `repaint` after each
    /// delivery.
    #[must_use]
    pub fn new(repaint: Repaint) -> Option<Self> {
        let (tx, deliveries) = channel();
        let generation = Arc::new(AtomicU64::new(0));
        let current = Arc::clone(&generation);
        let jobs =
            super::background::Lane::stepped("raytree-acne-lab", None, move |job: Job| LabRun {
                job,
                current: Arc::clone(&current),
                tx: tx.clone(),
                repaint: Arc::clone(&repaint),
                next: 0,
                scenes: None,
                cell: None,
            })
            .ok()?;
        Some(Self {
            deliveries,
            generation,
            jobs: Some(jobs),
        })
    }

    /// Start a job on `scene` (cancelling the last); returns its generation.
    pub fn start(&self, scene: Arc<Scene>, params: LabParams) -> u64 {
        let generation = self.generation.fetch_add(1, Ordering::SeqCst) + 1;
        if let Some(jobs) = &self.jobs {
            jobs.send(Job {
                generation,
                scene,
                params,
            });
        }
        generation
    }

    /// A delivery if one is waiting.
    #[must_use]
    pub fn try_recv(&self) -> Option<LabDelivery> {
        self.deliveries.try_recv().ok()
    }

    /// Block until the next delivery (`None` if the thread is gone; on wasm32 the queued job
    /// runs here first).
    #[must_use]
    pub fn recv(&self) -> Option<LabDelivery> {
        #[cfg(target_arch = "wasm32")]
        loop {
            if let Ok(d) = self.deliveries.try_recv() {
                return Some(d);
            }
            if !super::background::run_pending(f64::INFINITY) {
                return self.deliveries.try_recv().ok();
            }
        }
        #[cfg(not(target_arch = "wasm32"))]
        self.deliveries.recv().ok()
    }
}

impl Drop for LabWorker {
    fn drop(&mut self) {
        self.generation.fetch_add(1, Ordering::SeqCst);
        // Dropping the lane ends (and joins) its thread.
        self.jobs = None;
    }
}

/// `scene` at `width` (height by the camera's aspect), scaled and moved.
fn lab_scene(scene: &Scene, width: u32, p: &LabParams) -> Scene {
    let cam = &scene.camera;
    let aspect = f64::from(cam.height.max(1)) / f64::from(cam.width.max(1));
    let height = ((f64::from(width) * aspect).round() as u32).clamp(1, 4 * width);
    let sized = Scene {
        camera: cam.with_size(width, height),
        ..scene.clone()
    };
    scaled_scene(&sized, p.scale, p.shift)
}

/// A lab job as a background task: whole natively (each cell by [`cell`]); on wasm32 a pixel
/// at a time ([`CellSteps`]: the same cells), a newer job cancelling it between two pieces.
struct LabRun {
    job: Job,
    current: Arc<AtomicU64>,
    tx: Sender<LabDelivery>,
    repaint: Repaint,
    /// The next cell: 0 the chosen setting's, then the sweep's in order.
    next: usize,
    /// The lab's scenes at [`CURRENT_WIDTH`] and [`SWEEP_WIDTH`], made at the first piece.
    scenes: Option<[Scene; 2]>,
    cell: Option<CellSteps>,
}

impl LabRun {
    /// The cell `i` of the job: the scene (0 the current, 1 the sweep's), strategy and epsilon.
    fn setting(p: &LabParams, i: usize) -> (usize, OffsetStrategy, f64) {
        if i == 0 {
            return (0, p.strategy, p.epsilon);
        }
        let epsilons = sweep_epsilons();
        let (s, e) = ((i - 1) / epsilons.len(), (i - 1) % epsilons.len());
        (1, OffsetStrategy::ALL[s], epsilons[e])
    }

    /// The lab's scenes at [`CURRENT_WIDTH`] and [`SWEEP_WIDTH`].
    fn lab_scenes(&self) -> [Scene; 2] {
        let p = &self.job.params;
        [CURRENT_WIDTH, SWEEP_WIDTH].map(|w| lab_scene(&self.job.scene, w, p))
    }

    fn cancelled(&self) -> bool {
        self.current.load(Ordering::SeqCst) != self.job.generation
    }

    /// Send cell `i` (then, after the last, that the job is done); `false` once the receiver
    /// is gone.
    fn deliver(&self, i: usize, c: AcneCell) -> bool {
        let g = self.job.generation;
        let d = if i == 0 {
            LabDelivery::Current(g, c)
        } else {
            LabDelivery::Sweep(g, c)
        };
        self.send(d) && (i + 1 < job_len() || self.send(LabDelivery::Done(g)))
    }

    fn send(&self, d: LabDelivery) -> bool {
        let ok = self.tx.send(d).is_ok();
        (self.repaint)();
        ok
    }
}

impl super::background::Task for LabRun {
    /// Every cell in order, each rendered whole ([`cell`]).
    fn run(self: Box<Self>) {
        let p = self.job.params;
        let scenes = self.lab_scenes();
        for i in 0..job_len() {
            if self.cancelled() {
                return;
            }
            let (k, strategy, epsilon) = Self::setting(&p, i);
            if !self.deliver(i, cell(&scenes[k], strategy, epsilon, p.scale)) {
                return;
            }
        }
    }

    fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool {
        let p = self.job.params;
        if self.scenes.is_none() {
            self.scenes = Some(self.lab_scenes());
        }
        loop {
            if self.cancelled() {
                return false;
            }
            let Some(scenes) = &self.scenes else {
                return false;
            };
            let (k, strategy, epsilon) = Self::setting(&p, self.next);
            let cell = self
                .cell
                .get_or_insert_with(|| CellSteps::new(&scenes[k], strategy, epsilon, p.scale));
            if cell.step(more_time) {
                return true;
            }
            let done = self.cell.take().map(CellSteps::finish);
            let i = self.next;
            self.next += 1;
            if !done.is_some_and(|c| self.deliver(i, c)) || self.next == job_len() {
                return false;
            }
            if !more_time() {
                return true;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lab_counts_what_the_sweep_counts_and_a_newer_job_wins() {
        let w = LabWorker::new(Arc::new(|| {})).unwrap();
        let scene = Arc::new(Scene::default_scene());
        let far = LabParams {
            epsilon: 1e-9,
            scale: 1e6,
            shift: 1e3,
            ..LabParams::default()
        };
        let g1 = w.start(Arc::clone(&scene), LabParams::default());
        let g2 = w.start(Arc::clone(&scene), far);
        let (mut current, mut sweep) = (None, Vec::new());
        loop {
            match w.recv().unwrap() {
                d if d.generation() != g2 => assert_eq!(d.generation(), g1),
                LabDelivery::Current(_, c) => current = Some(c),
                LabDelivery::Sweep(_, c) => sweep.push(c),
                LabDelivery::Done(_) => break,
            }
        }
        assert_eq!(sweep.len() + 1, job_len());
        let c = current.unwrap();
        assert_eq!((c.pixels, c.scale), (160 * 90, 1e6));
        // A scene a billion units out with epsilon 1e-9: acne, as `raytree acne` finds.
        assert!(c.self_hit_pixels > 0, "{c:?}");
        let want = cell(&lab_scene(&scene, 160, &far), far.strategy, 1e-9, 1e6);
        assert_eq!(c.self_hit_pixels, want.self_hit_pixels);
        assert!(
            sweep
                .iter()
                .filter(|c| c.strategy == OffsetStrategy::Robust)
                .all(AcneCell::clean)
        );
        assert!(LabParams { scale: 0.0, ..far }.check().is_err());
        assert!(
            LabParams {
                epsilon: f64::NAN,
                ..far
            }
            .check()
            .is_err()
        );
        assert!(far.check().is_ok());
    }

    /// Every delivery of a lab job, run whole or stepped with `more_time` always `answer`.
    fn deliveries(stepped: Option<bool>) -> Vec<String> {
        let (tx, rx) = channel();
        let mut scene = Scene::default_scene();
        scene.camera = scene.camera.with_size(64, 36);
        let mut run = Box::new(LabRun {
            job: Job {
                generation: 1,
                scene: Arc::new(scene),
                params: LabParams::default(),
            },
            current: Arc::new(AtomicU64::new(1)),
            tx,
            repaint: Arc::new(|| {}),
            next: 0,
            scenes: None,
            cell: None,
        });
        match stepped {
            None => super::super::background::Task::run(run),
            Some(answer) => {
                let mut n = 1;
                while super::super::background::Task::step(&mut *run, &|| answer) {
                    n += 1;
                }
                let pixels = 160 * 90 + (job_len() - 1) * 48 * 27;
                assert_eq!(n, if answer { 1 } else { pixels }, "a pixel a step");
            }
        }
        rx.try_iter().map(|d| format!("{d:?}")).collect()
    }

    #[test]
    fn a_stepped_lab_job_delivers_what_the_whole_job_does() {
        let whole = deliveries(None);
        assert_eq!(whole.len(), job_len() + 1);
        assert_eq!(deliveries(Some(false)), whole);
        assert_eq!(deliveries(Some(true)), whole);
    }
}
