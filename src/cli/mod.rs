//! Subcommands. Every user error (bad scene, bad flag, unwritable output) exits with code 2;
//! a closed standard output (`| head`) exits quietly with 0; SIGINT, SIGTERM and SIGHUP remove
//! the temporary files and exit with 128 + the signal.

mod acne_cmd;
mod acne_figures;
mod aov_cmd;
mod args;
mod budget;
mod canvas;
mod cleanup;
mod compare_cmd;
mod compare_map;
mod converge_cmd;
mod converge_plot;
mod convert_cmd;
mod cost_cmd;
mod denoise_out;
mod diagram_cmd;
mod diff_cmd;
mod effects_cmd;
mod explain_cmd;
mod load;
mod load_formats;
mod outliers_cmd;
mod output;
mod plot;
mod read;
mod render_cmd;
mod render_warnings;
mod say;
mod spp_map;
mod strategies_cmd;
mod trace_cmd;
mod versus_cmd;
#[cfg(feature = "gui")]
mod view_cmd;

use clap::Parser;
use std::process::ExitCode;

pub use args::{Cli, Command};

/// Parse arguments, run, and map errors to exit code 2.
pub fn run() -> ExitCode {
    cleanup::install();
    // Deep recursion (max_depth up to 1024) needs more than std's 2 MiB thread stacks. Fails
    // only if a global pool already exists, which then keeps its own.
    let _ = rayon::ThreadPoolBuilder::new()
        .stack_size(raytree::integrator::THREAD_STACK_BYTES)
        .build_global();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(a) => render_cmd::run(&a),
        Command::Trace(a) => trace_cmd::run(&a),
        Command::Acne(a) => acne_cmd::run(&a),
        Command::Effects(a) => effects_cmd::run(&a),
        Command::Cost(a) => cost_cmd::run(&a),
        Command::Compare(a) => compare_cmd::run(&a),
        Command::Converge(a) => converge_cmd::run(&a),
        #[cfg(feature = "gui")]
        Command::View(a) => view_cmd::run(&a),
        #[cfg(not(feature = "gui"))]
        Command::View(_) => Err(anyhow::anyhow!(
            "this raytree was built without the inspector (cargo feature \"gui\")"
        )),
        Command::Diagram(a) => diagram_cmd::run(&a),
        Command::Explain(a) => explain_cmd::run(&a),
        Command::Diff(a) => diff_cmd::run(&a),
        Command::Versus(a) => versus_cmd::run(&a),
        Command::Convert(a) => convert_cmd::run(&a),
        Command::Outliers(a) => outliers_cmd::run(&a),
        Command::Strategies(a) => strategies_cmd::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => match e.downcast_ref::<say::StdoutError>() {
            Some(o) if o.is_broken_pipe() => ExitCode::SUCCESS,
            _ => {
                say::warnln!("error: {e:#}");
                ExitCode::from(2)
            }
        },
    }
}
