//! Background work off the UI: natively a thread of its own; on wasm32, which has no threads,
//! a task queued on the UI thread and stepped between frames ([`run_pending`], for
//! [`SLICE_BUDGET_MS`] a frame after the panels are laid out, the tasks in turn).
//!
//! - [`Task`]: what a job does, whole (natively, on its thread, over rayon's pool) or a piece
//!   at a time (wasm32: each piece a pixel or so of a render, [`crate::render::steps`]).
//! - [`spawn`]: one job (the comparison of two integrators, the split by strategy, the
//!   denoiser).
//! - [`Lane`]: a long-lived worker that only ever needs the newest job (the diagram's
//!   rasteriser, the acne lab): natively a thread draining a channel, on wasm32 a slot whose
//!   newest job replaces the one under way.

/// Time the background tasks get per frame on wasm32, as the render worker's slice
/// ([`crate::gui::jobs::worker::SLICE_BUDGET_MS`]).
pub const SLICE_BUDGET_MS: f64 = crate::gui::jobs::worker::SLICE_BUDGET_MS;

/// A background job.
pub trait Task: Send + 'static {
    /// The whole job, on the calling thread (natively: its own).
    fn run(self: Box<Self>);
    /// A piece of the job (wasm32's way; the same outcome as [`Task::run`]): work while
    /// `more_time` says so, at least a little; `false` once the job is finished (or
    /// cancelled).
    fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool;
}

/// A job that cannot be cut: its one step is all of it.
pub struct Whole<F>(pub Option<F>);

impl<F: FnOnce() + Send + 'static> Task for Whole<F> {
    fn run(self: Box<Self>) {
        if let Some(f) = self.0 {
            f();
        }
    }

    fn step(&mut self, _: &dyn Fn() -> bool) -> bool {
        if let Some(f) = self.0.take() {
            f();
        }
        false
    }
}

/// Run `task` in the background (a thread named `name` with `stack` bytes of stack natively).
pub fn spawn(name: &str, stack: Option<usize>, task: impl Task) -> std::io::Result<()> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        let mut b = std::thread::Builder::new().name(name.into());
        if let Some(bytes) = stack {
            b = b.stack_size(bytes);
        }
        b.spawn(move || Box::new(task).run()).map(drop)
    }
    #[cfg(target_arch = "wasm32")]
    {
        let _ = (name, stack);
        queue::push(Box::new(task));
        Ok(())
    }
}

/// A job with a result, done whole or a piece at a time ([`deliver`] runs it).
pub trait Work: Send + 'static {
    /// What the job makes.
    type Out: Send + 'static;
    /// The whole job (natively, on its thread, over rayon's pool).
    fn whole(self) -> Self::Out;
    /// A piece of the job (wasm32), while `more_time` says so, at least a little: the
    /// outcome once finished (the same as [`Work::whole`]'s).
    fn piece(&mut self, more_time: &dyn Fn() -> bool) -> Option<Self::Out>;
}

/// Where a [`deliver`]ed job's outcome arrives. Dropping it cancels the job (on wasm32,
/// between two pieces; natively the thread runs to its end and its outcome is dropped).
pub struct Inbox<T> {
    rx: std::sync::mpsc::Receiver<T>,
    _wanted: std::sync::Arc<()>,
}

impl<T> Inbox<T> {
    /// The outcome, if it has arrived.
    pub fn try_recv(&self) -> Option<T> {
        self.rx.try_recv().ok()
    }
}

/// The task of a [`deliver`]ed job.
struct Delivering<W: Work> {
    work: Option<W>,
    tx: std::sync::mpsc::Sender<W::Out>,
    wanted: std::sync::Weak<()>,
    repaint: Box<dyn Fn() + Send>,
}

impl<W: Work> Delivering<W> {
    fn send(&self, out: W::Out) {
        if self.tx.send(out).is_ok() {
            (self.repaint)();
        }
    }
}

impl<W: Work> Task for Delivering<W> {
    fn run(mut self: Box<Self>) {
        if let Some(work) = self.work.take() {
            let out = work.whole();
            self.send(out);
        }
    }

    fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool {
        if self.wanted.strong_count() == 0 {
            return false;
        }
        let Some(work) = &mut self.work else {
            return false;
        };
        match work.piece(more_time) {
            Some(out) => {
                self.work = None;
                self.send(out);
                false
            }
            None => true,
        }
    }
}

/// Run `work` in the background ([`spawn`]), its outcome sent to the returned inbox and
/// `repaint` called then.
pub fn deliver<W: Work>(
    name: &str,
    stack: Option<usize>,
    work: W,
    repaint: impl Fn() + Send + 'static,
) -> std::io::Result<Inbox<W::Out>> {
    let (tx, rx) = std::sync::mpsc::channel();
    let wanted = std::sync::Arc::new(());
    let task = Delivering {
        work: Some(work),
        tx,
        wanted: std::sync::Arc::downgrade(&wanted),
        repaint: Box::new(repaint),
    };
    spawn(name, stack, task)?;
    Ok(Inbox {
        rx,
        _wanted: wanted,
    })
}

/// Step the queued tasks, oldest first, for about `budget_ms` (wasm32; natively there are
/// none). Returns whether more are waiting (then the caller asks for another frame).
#[must_use]
pub fn run_pending(budget_ms: f64) -> bool {
    #[cfg(target_arch = "wasm32")]
    {
        queue::run_for(budget_ms)
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = budget_ms;
        false
    }
}

/// Steps of `tasks` in turn (the front one, which then goes to the back, or is dropped once
/// finished) until `budget_ms` have passed or none is left; returns whether any is left. A
/// task steps while the budget lasts, so each frame mostly serves one and the next frame the
/// next: a long comparison does not hold back the diagram of a click. The UI thread's loop
/// (wasm32), tested natively.
#[cfg(any(target_arch = "wasm32", test))]
fn step_for(tasks: &mut std::collections::VecDeque<Box<dyn Task>>, budget_ms: f64) -> bool {
    let start = web_time::Instant::now();
    let more_time = || start.elapsed().as_secs_f64() * 1e3 < budget_ms;
    while let Some(mut task) = tasks.pop_front() {
        if task.step(&more_time) {
            tasks.push_back(task);
        }
        if !more_time() {
            break;
        }
    }
    !tasks.is_empty()
}

/// A worker for jobs of type `J` where only the newest job matters.
pub struct Lane<J: Send + 'static> {
    #[cfg(not(target_arch = "wasm32"))]
    jobs: Option<std::sync::mpsc::Sender<J>>,
    #[cfg(not(target_arch = "wasm32"))]
    thread: Option<std::thread::JoinHandle<()>>,
    #[cfg(target_arch = "wasm32")]
    slot: std::sync::Arc<std::sync::Mutex<Slot<J>>>,
}

/// A lane's starter: the task of a job.
type Start<J> = Box<dyn FnMut(J) -> Box<dyn Task> + Send>;

#[cfg(target_arch = "wasm32")]
struct Slot<J> {
    /// The newest job not yet started, and whether the lane's task is queued.
    newest: Option<J>,
    queued: bool,
    start: Start<J>,
}

impl<J: Send + 'static> Lane<J> {
    /// Start the worker: `run` is called with each job that is the newest when the worker
    /// gets to it (older jobs queued behind it are dropped), whole.
    pub fn new(
        name: &str,
        stack: Option<usize>,
        run: impl FnMut(J) + Send + 'static,
    ) -> std::io::Result<Self> {
        let run = std::sync::Arc::new(std::sync::Mutex::new(run));
        Self::stepped(name, stack, move |job| {
            let run = std::sync::Arc::clone(&run);
            Whole(Some(move || (*lock(&run))(job)))
        })
    }

    /// Start the worker: `start` makes the task of each job that is the newest when the
    /// worker gets to it (older jobs queued behind it are dropped; on wasm32 a newer job also
    /// drops the task under way, between two of its steps).
    pub fn stepped<T: Task>(
        name: &str,
        stack: Option<usize>,
        mut start: impl FnMut(J) -> T + Send + 'static,
    ) -> std::io::Result<Self> {
        let start: Start<J> = Box::new(move |job| Box::new(start(job)));
        #[cfg(not(target_arch = "wasm32"))]
        {
            let mut start = start;
            let (jobs, job_rx) = std::sync::mpsc::channel::<J>();
            let mut b = std::thread::Builder::new().name(name.into());
            if let Some(bytes) = stack {
                b = b.stack_size(bytes);
            }
            let thread = b.spawn(move || {
                while let Ok(mut job) = job_rx.recv() {
                    while let Ok(newer) = job_rx.try_recv() {
                        job = newer;
                    }
                    start(job).run();
                }
            })?;
            Ok(Self {
                jobs: Some(jobs),
                thread: Some(thread),
            })
        }
        #[cfg(target_arch = "wasm32")]
        {
            let _ = (name, stack);
            Ok(Self {
                slot: std::sync::Arc::new(std::sync::Mutex::new(Slot {
                    newest: None,
                    queued: false,
                    start,
                })),
            })
        }
    }

    /// Queue `job` (superseding any not yet started); `false` if the worker is gone.
    pub fn send(&self, job: J) -> bool {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.jobs
                .as_ref()
                .is_some_and(|jobs| jobs.send(job).is_ok())
        }
        #[cfg(target_arch = "wasm32")]
        {
            let mut s = lock(&self.slot);
            s.newest = Some(job);
            if !std::mem::replace(&mut s.queued, true) {
                queue::push(Box::new(LaneTask {
                    slot: std::sync::Arc::clone(&self.slot),
                    current: None,
                }));
            }
            true
        }
    }
}

/// A lane's queued task (wasm32): starts the newest job, dropping the one under way.
#[cfg(target_arch = "wasm32")]
struct LaneTask<J> {
    slot: std::sync::Arc<std::sync::Mutex<Slot<J>>>,
    current: Option<Box<dyn Task>>,
}

#[cfg(target_arch = "wasm32")]
impl<J: Send + 'static> Task for LaneTask<J> {
    fn run(mut self: Box<Self>) {
        while self.step(&|| true) {}
    }

    fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool {
        let mut s = lock(&self.slot);
        if let Some(job) = s.newest.take() {
            // The task under way is dropped: only the newest job matters.
            self.current = Some((s.start)(job));
        }
        drop(s);
        if let Some(task) = &mut self.current
            && !task.step(more_time)
        {
            self.current = None;
        }
        let mut s = lock(&self.slot);
        s.queued = self.current.is_some() || s.newest.is_some();
        s.queued
    }
}

fn lock<T: ?Sized>(m: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl<J: Send + 'static> Drop for Lane<J> {
    fn drop(&mut self) {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.jobs = None;
            if let Some(t) = self.thread.take() {
                let _ = t.join();
            }
        }
    }
}

/// The UI thread's queue of tasks (wasm32).
#[cfg(target_arch = "wasm32")]
mod queue {
    use super::Task;
    use std::cell::RefCell;
    use std::collections::VecDeque;

    thread_local! {
        static TASKS: RefCell<VecDeque<Box<dyn Task>>> = const { RefCell::new(VecDeque::new()) };
    }

    pub(super) fn push(task: Box<dyn Task>) {
        TASKS.with(|t| t.borrow_mut().push_back(task));
    }

    /// Step the tasks for `budget_ms` (outside the queue's borrow: a step may queue more;
    /// tasks queued meanwhile go after those taken).
    pub(super) fn run_for(budget_ms: f64) -> bool {
        let mut tasks = TASKS.with(|t| std::mem::take(&mut *t.borrow_mut()));
        super::step_for(&mut tasks, budget_ms);
        TASKS.with(|t| {
            let mut t = t.borrow_mut();
            let added = std::mem::take(&mut *t);
            tasks.extend(added);
            *t = tasks;
            !t.is_empty()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::mpsc::channel;

    #[test]
    fn a_lane_runs_the_newest_job_and_spawn_runs_its_task() {
        let (tx, rx) = channel();
        let lane = Lane::new("test-lane", None, move |j: u32| tx.send(j).unwrap()).unwrap();
        assert!(lane.send(7));
        assert_eq!(rx.recv().unwrap(), 7);
        drop(lane);
        let (tx, rx) = channel();
        let task = Whole(Some(move || tx.send(3).unwrap()));
        spawn("test-spawn", Some(1 << 20), task).unwrap();
        assert_eq!(rx.recv().unwrap(), 3);
        assert!(!run_pending(1.0), "natively nothing is queued");
    }

    /// A task counting its steps to `n`.
    struct Count(Arc<AtomicUsize>, usize);

    impl Task for Count {
        fn run(self: Box<Self>) {
            self.0.store(self.1, Ordering::SeqCst);
        }
        fn step(&mut self, more_time: &dyn Fn() -> bool) -> bool {
            loop {
                let k = self.0.fetch_add(1, Ordering::SeqCst) + 1;
                if k >= self.1 {
                    return false;
                }
                if !more_time() {
                    return true;
                }
            }
        }
    }

    #[test]
    fn the_ui_threads_loop_steps_tasks_in_turn_within_its_budget() {
        let (a, b) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
        let count = || (a.load(Ordering::SeqCst), b.load(Ordering::SeqCst));
        let mut tasks: std::collections::VecDeque<Box<dyn Task>> = [
            Box::new(Count(Arc::clone(&a), 3)) as Box<dyn Task>,
            Box::new(Count(Arc::clone(&b), 2)),
        ]
        .into();
        // No time: one piece a call, the tasks in turn.
        assert!(step_for(&mut tasks, 0.0));
        assert_eq!(count(), (1, 0));
        assert!(step_for(&mut tasks, 0.0));
        assert_eq!(count(), (1, 1));
        assert!(step_for(&mut tasks, 0.0));
        assert!(step_for(&mut tasks, 0.0));
        assert_eq!((count(), tasks.len()), ((2, 2), 1), "the second is done");
        // Time enough: everything left.
        assert!(!step_for(&mut tasks, 1e9));
        assert_eq!(count(), (3, 2));
    }
}
