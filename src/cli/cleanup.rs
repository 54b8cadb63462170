//! Temporary paths this process owns, removed when SIGINT, SIGTERM or SIGHUP arrives; the
//! process then exits with 128 + the signal number (130, 143, 129).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

static OWNED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn owned() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    OWNED
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Start the signal thread. Without it (it fails only if signals cannot be hooked) the
/// default actions apply.
pub fn install() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            // Hold the lock to the end: no rename or registration can interleave.
            let paths = owned();
            for p in paths.iter().rev() {
                if std::fs::remove_file(p).is_err() {
                    let _ = std::fs::remove_dir(p); // only our own directories, only if empty
                }
            }
            std::process::exit(128 + sig);
        }
    });
}

/// Register `p` before creating it.
pub fn register(p: &Path) {
    owned().push(p.to_path_buf());
}

/// Forget `p` (it was removed, or is now a finished output).
pub fn forget(p: &Path) {
    owned().retain(|q| q != p);
}

/// Run `f` (a rename that turns `p` into a finished output) and forget `p`, with no signal
/// cleanup in between.
pub fn settle<T>(p: &Path, f: impl FnOnce() -> T) -> T {
    let mut paths = owned();
    let r = f();
    paths.retain(|q| q != p);
    r
}

/// Run `f` (renames that turn every path of `ps` into a finished output) and forget them, with
/// no signal cleanup in between: a signal arriving meanwhile waits until `f` has returned.
pub fn settle_all<T>(ps: &[PathBuf], f: impl FnOnce() -> T) -> T {
    let mut paths = owned();
    let r = f();
    paths.retain(|q| !ps.contains(q));
    r
}
