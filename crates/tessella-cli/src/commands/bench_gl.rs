//! `tessella bench --gl`: PN on the OpenGL tessellator against tessella-gpu's instanced pattern
//! renderer and the CPU at about equal triangle counts, and quadratic ("fake") against real
//! normals, measured and tabled by [`tessella_bench::gl::tables`]. Ratios are against the CPU
//! measured in the same run; absolute times are printed only for hardware drivers.

use crate::args::BenchArgs;
use tessella_bench::gl::{tables, Pattern};
use tessella_core::{samples, Mesh};

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let (mesh, name): (Mesh, String) = match &args.mesh {
        Some(path) => (tessella_io::read_mesh(path)?, path.display().to_string()),
        None => (samples::icosphere(2), "icosphere(2)".into()),
    };
    print!(
        "{}",
        tables(&mesh, &name, &args.levels, args.repeat, pattern)?
    );
    Ok(())
}

/// The wgpu adapter the instanced pattern is timed on, or why it is not.
fn pattern() -> Pattern {
    #[cfg(feature = "gpu")]
    return match super::gpu::render_context() {
        Ok(ctx) => Pattern::Adapter(Box::new(ctx)),
        Err(e) => Pattern::None(format!("{e:#}")),
    };
    #[cfg(not(feature = "gpu"))]
    Pattern::None("built without the `gpu` feature".into())
}
