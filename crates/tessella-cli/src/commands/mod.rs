//! One module per subcommand.

#[cfg(feature = "gpu")]
mod animate;
pub mod batch;
mod bench;
#[cfg(feature = "gl")]
mod bench_gl;
mod demo;
mod displace;
#[cfg(feature = "gpu")]
mod gpu;
mod info;
mod options;
mod pattern;
mod pattern_svg;
mod pose;
mod refine;
mod refine_gl;
mod refine_scene;
mod refined;
#[cfg(feature = "gpu")]
mod render;
#[cfg(feature = "gpu")]
mod render_gl;
mod samples;
mod tags;
#[cfg(feature = "view")]
mod view;
#[cfg(feature = "view")]
mod view_input;

use crate::cli::{Cli, Command};

/// Runs the chosen subcommand.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Refine(args) => refine::run(&args),
        Command::Batch(args) => batch::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Pattern(args) => pattern::run(&args),
        Command::Samples(args) => samples::run(&args),
        Command::Demo(args) => demo::run(&args),
        #[cfg(feature = "gpu")]
        Command::Render(args) => render::run(&args),
        #[cfg(feature = "gpu")]
        Command::Animate(args) => animate::run(&args),
        #[cfg(not(feature = "gpu"))]
        Command::Render(_) => Err(no_gpu("render")),
        #[cfg(not(feature = "gpu"))]
        Command::Animate(_) => Err(no_gpu("animate")),
        #[cfg(feature = "view")]
        Command::View(args) => view::run(&args),
        #[cfg(not(feature = "view"))]
        Command::View(_) => Err(anyhow::anyhow!(
            "view needs the GPU and a window, and this tessella was built without them; \
             rebuild with the `view` feature (cargo build -p tessella-cli --features view)"
        )),
        Command::Bench(args) => bench::run(&args),
    }
}

/// The error of a GPU command in a build without the `gpu` feature.
#[cfg(not(feature = "gpu"))]
pub(crate) fn no_gpu(what: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{what} needs the GPU, and this tessella was built without GPU support; rebuild with \
         the `gpu` feature (cargo build -p tessella-cli --features gpu)"
    )
}
