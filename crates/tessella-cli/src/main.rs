//! `tessella`: refine coarse triangle meshes into smooth curved surfaces, inspect meshes, and
//! print refinement patterns. Run `tessella --help` for the commands.

mod args;
mod args_batch;
mod cli;
mod commands;
mod progress;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Vulkan loaders probe for a Wayland display and libwayland prints an error when
    // XDG_RUNTIME_DIR is unset (headless machines, CI). There is no display to find either way;
    // point it at the temporary folder so the probe fails quietly. Done first, single-threaded.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    let cli = cli::Cli::parse();
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            if error.is::<commands::batch::UsageError>() {
                return ExitCode::from(2);
            }
            for cause in error.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::FAILURE
        }
    }
}
