//! Helpers shared by the integration tests (each `tests/*.rs` is its own crate).

use std::path::Path;
use std::process::{Command, Output};

/// Run the `raytree` binary with `args` in `dir`.
pub fn raytree(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raytree"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the raytree binary runs")
}
