//! Helpers shared by the integration tests (each `tests/*.rs` is its own crate, and none uses
//! every helper).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run the `raytree` binary with `args` in `dir`.
pub fn raytree(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raytree"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the raytree binary runs")
}

/// The path of `fixtures/NAME`, as an argument for the binary.
pub fn fixture(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
        .display()
        .to_string()
}

/// The process's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Assert exit code 2 and return stderr.
pub fn fails(o: &Output) -> String {
    assert_eq!(
        o.status.code(),
        Some(2),
        "stdout: {}\nstderr: {}",
        String::from_utf8_lossy(&o.stdout),
        stderr(o)
    );
    stderr(o)
}

/// `raytree args` in `dir` exits 2 with `text` in its error and leaves no file in `dir` besides
/// the scene `s.json`.
pub fn fails_with(dir: &Path, args: &[&str], text: &str) {
    let o = raytree(args, dir);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(text), "{args:?}: {err}");
    let written: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name() != "s.json")
        .collect();
    assert!(written.is_empty(), "{args:?} wrote {written:?}");
}

/// SplitMix64: deterministic numbers for the seeded test loops.
pub struct Rng(pub u64);

impl Rng {
    /// The next number in `[0, 1)`.
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}
