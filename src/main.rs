//! The `raytree` command: owns files, terminals, exit codes and progress bars.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
