//! One module per subcommand.

mod animate;
mod bench;
mod demo;
mod gpu;
mod info;
mod pattern;
mod refine;
mod render;
mod samples;
mod tags;

use crate::args::{Cli, Command};

/// Runs the chosen subcommand.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Refine(args) => refine::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Pattern(args) => pattern::run(&args),
        Command::Samples(args) => samples::run(&args),
        Command::Demo(args) => demo::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Animate(args) => animate::run(&args),
        Command::Bench(args) => bench::run(&args),
    }
}
