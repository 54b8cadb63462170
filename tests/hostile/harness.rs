//! Run the binary bounded: an address-space cap (`ulimit -v` in a shell that then execs the
//! binary, since the tests stay free of `unsafe`) and a wall-clock timeout after which the
//! process is killed and the case fails.
#![allow(dead_code)]

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What a bounded run did.
#[derive(Debug)]
pub struct Run {
    /// Exit code, `None` if killed by a signal (an abort, or our timeout).
    pub code: Option<i32>,
    /// Killed by the timeout.
    pub timed_out: bool,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// Exit 0 or 2, in time, with no panic and no abort.
    pub fn assert_clean(&self) -> &Self {
        assert!(!self.timed_out, "timed out: {self:#?}");
        assert!(
            matches!(self.code, Some(0 | 2)),
            "exit not 0 or 2: {self:#?}"
        );
        assert!(!self.stderr.contains("panicked"), "panicked: {self:#?}");
        self
    }

    /// Exit 2 with an `error:` message, in time, no panic.
    pub fn assert_refused(&self) -> &Self {
        assert!(!self.timed_out, "timed out: {self:#?}");
        assert_eq!(self.code, Some(2), "not refused: {self:#?}");
        assert!(
            self.stderr.contains("error:"),
            "no error message: {self:#?}"
        );
        assert!(!self.stderr.contains("panicked"), "panicked: {self:#?}");
        self
    }
}

/// Default cap on address space for a case (MiB): generous for rayon's thread arenas, far
/// below what the runaway cases of issue 13 allocated.
pub const MEM_MIB: u64 = 2048;
/// Default wall-clock limit for a case.
pub const TIMEOUT: Duration = Duration::from_secs(60);

/// Run `raytree args` in `dir` under `mem_mib` of address space and `timeout`, with `stdin`
/// as its standard input (empty when `None`).
pub fn run_with(args: &[&str], dir: &Path, mem_mib: u64, timeout: Duration) -> Run {
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {}; exec \"$0\" \"$@\"", mem_mib * 1024))
        .arg(env!("CARGO_BIN_EXE_raytree"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sh runs");
    let mut out = child.stdout.take().expect("piped");
    let mut err = child.stderr.take().expect("piped");
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out.read_to_end(&mut s);
        s
    });
    let ereader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let start = Instant::now();
    let mut timed_out = false;
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if start.elapsed() > timeout {
            timed_out = true;
            let _ = child.kill();
            break child.wait().expect("wait");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Run {
        code: status.code(),
        timed_out,
        stdout: String::from_utf8_lossy(&reader.join().unwrap_or_default()).into_owned(),
        stderr: String::from_utf8_lossy(&ereader.join().unwrap_or_default()).into_owned(),
    }
}

/// [`run_with`] with the default cap and timeout.
pub fn run(args: &[&str], dir: &Path) -> Run {
    run_with(args, dir, MEM_MIB, TIMEOUT)
}

/// Every file below `dir` whose name ends in `.tmp` or contains `.tmp.` (what a crashed or
/// interrupted command would leave).
pub fn temp_files(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.ends_with(".tmp") || name.contains(".tmp.") {
                found.push(e.path().display().to_string());
            }
            if e.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(e.path());
            }
        }
    }
    found
}

/// A snapshot of every file below `dir` (relative path -> bytes), to show a failing command
/// changed nothing.
pub fn snapshot(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut map = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if e.file_type().is_ok_and(|t| t.is_dir()) {
                stack.push(p);
            } else if e.file_type().is_ok_and(|t| t.is_file()) {
                let rel = p.strip_prefix(dir).unwrap_or(&p).display().to_string();
                map.insert(rel, std::fs::read(&p).unwrap_or_default());
            }
        }
    }
    map
}
