//! The paper's comparisons, measured: PN with quadratic ("fake") against real normals on the GL
//! tessellator (time per vertex), and the GL tessellator against the CPU refinement at equal
//! triangle counts. On a software driver (llvmpipe) only the ratios mean something. The
//! measurements are [`tessella_bench::gl::measure`], which `tessella bench --gl` prints too.
//!
//! `cargo run --release -p tessella-bench --example gl [-- LEVEL [REPEATS]]`

use tessella_bench::gl as bench;
use tessella_core::{samples, NormalMode};
use tessella_gl::{GlContext, GlError, GlTessellator};

fn main() -> Result<(), GlError> {
    let mut args = std::env::args().skip(1);
    let level: u32 = args.next().and_then(|a| a.parse().ok()).unwrap_or(8);
    let repeats: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(5);
    let ctx = GlContext::new()?;
    let info = ctx.info().clone();
    let mut gl = GlTessellator::new(&ctx)?;
    let mesh = samples::icosphere(2);
    println!(
        "driver: {} ({}); mesh: icosphere(2), {} triangles; level {level}, equal spacing",
        info.renderer,
        info.version,
        mesh.face_count()
    );
    let mut rows = Vec::new();
    for normals in [NormalMode::Quadratic, NormalMode::Real] {
        let r = bench::measure(&mut gl, &mesh, level, normals, repeats)?;
        println!(
            "PN {normals:?}: {} triangles; GL {:.2} ms ({:.1} ns per vertex); CPU {:.2} ms; \
             GL/CPU {:.2}",
            r.triangles,
            r.gl_seconds * 1e3,
            r.gl_seconds * 1e9 / r.vertices as f64,
            r.cpu_seconds * 1e3,
            r.gl_seconds / r.cpu_seconds
        );
        rows.push(r.gl_seconds);
    }
    println!(
        "real / quadratic normals on the GL tessellator: {:.2}× the time",
        rows[1] / rows[0]
    );
    if info.is_software() {
        println!("(software driver: compare ratios only)");
    }
    Ok(())
}
