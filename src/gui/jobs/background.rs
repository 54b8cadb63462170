//! Background work off the UI: natively a thread of its own; on wasm32, which has no threads,
//! a task queued on the UI thread and run between frames ([`run_pending`], one task per frame
//! after the panels are laid out, so a frame first shows that the work is under way).
//!
//! - [`spawn`]: one job (the Whitted-vs-path comparison, the denoiser).
//! - [`Lane`]: a long-lived worker that only ever needs the newest job (the diagram's
//!   rasteriser, the acne lab): natively a thread draining a channel, on wasm32 a slot.

/// Run `f` in the background (a thread named `name` with `stack` bytes of stack natively).
pub fn spawn(
    name: &str,
    stack: Option<usize>,
    f: impl FnOnce() + Send + 'static,
) -> std::io::Result<()> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        let mut b = std::thread::Builder::new().name(name.into());
        if let Some(bytes) = stack {
            b = b.stack_size(bytes);
        }
        b.spawn(f).map(drop)
    }
    #[cfg(target_arch = "wasm32")]
    {
        let _ = (name, stack);
        queue::push(Box::new(f));
        Ok(())
    }
}

/// Run the oldest queued task, if any (wasm32; natively there is none). Returns whether more
/// are waiting (then the caller asks for another frame).
#[must_use]
pub fn run_pending() -> bool {
    #[cfg(target_arch = "wasm32")]
    {
        queue::run_one()
    }
    #[cfg(not(target_arch = "wasm32"))]
    false
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

#[cfg(target_arch = "wasm32")]
struct Slot<J> {
    newest: Option<J>,
    run: Box<dyn FnMut(J) + Send>,
}

impl<J: Send + 'static> Lane<J> {
    /// Start the worker: `run` is called with each job that is the newest when the worker
    /// gets to it (older jobs queued behind it are dropped).
    pub fn new(
        name: &str,
        stack: Option<usize>,
        run: impl FnMut(J) + Send + 'static,
    ) -> std::io::Result<Self> {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let mut run = run;
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
                    run(job);
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
                    run: Box::new(run),
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
            let slot = std::sync::Arc::clone(&self.slot);
            let mut s = lock(&slot);
            let first = s.newest.replace(job).is_none();
            drop(s);
            if first {
                queue::push(Box::new(move || {
                    let mut s = lock(&slot);
                    if let Some(j) = s.newest.take() {
                        (s.run)(j);
                    }
                }));
            }
            true
        }
    }
}

#[cfg(target_arch = "wasm32")]
fn lock<T>(m: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
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
    use std::cell::RefCell;
    use std::collections::VecDeque;

    type Task = Box<dyn FnOnce()>;

    thread_local! {
        static TASKS: RefCell<VecDeque<Task>> = const { RefCell::new(VecDeque::new()) };
    }

    pub(super) fn push(task: Task) {
        TASKS.with(|t| t.borrow_mut().push_back(task));
    }

    /// Run the oldest task (outside the queue's borrow: it may queue more).
    pub(super) fn run_one() -> bool {
        let task = TASKS.with(|t| t.borrow_mut().pop_front());
        if let Some(task) = task {
            task();
        }
        TASKS.with(|t| !t.borrow().is_empty())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;

    #[test]
    fn a_lane_runs_the_newest_job_and_spawn_runs_its_task() {
        let (tx, rx) = channel();
        let lane = Lane::new("test-lane", None, move |j: u32| tx.send(j).unwrap()).unwrap();
        assert!(lane.send(7));
        assert_eq!(rx.recv().unwrap(), 7);
        drop(lane);
        let (tx, rx) = channel();
        spawn("test-spawn", Some(1 << 20), move || tx.send(3).unwrap()).unwrap();
        assert_eq!(rx.recv().unwrap(), 3);
        assert!(!run_pending(), "natively nothing is queued");
    }
}
