//! Subcommands. Every user error (bad scene, bad flag, unwritable output) exits with code 2.

mod acne_cmd;
mod acne_figures;
mod args;
mod budget;
mod canvas;
mod compare_cmd;
mod cost_cmd;
mod diagram_cmd;
mod effects_cmd;
mod load;
mod output;
mod plot;
mod render_cmd;
mod trace_cmd;
mod view_cmd;

use clap::Parser;
use std::process::ExitCode;

pub use args::{Cli, Command};

/// Parse arguments, run, and map errors to exit code 2.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(a) => render_cmd::run(&a),
        Command::Trace(a) => trace_cmd::run(&a),
        Command::Acne(a) => acne_cmd::run(&a),
        Command::Effects(a) => effects_cmd::run(&a),
        Command::Cost(a) => cost_cmd::run(&a),
        Command::Compare(a) => compare_cmd::run(&a),
        Command::View(a) => view_cmd::run(&a),
        Command::Diagram(a) => diagram_cmd::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
