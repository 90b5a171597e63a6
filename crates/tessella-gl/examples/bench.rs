//! The paper's comparisons, measured: PN with quadratic ("fake") against real normals on the GL
//! tessellator (time per vertex), and the GL tessellator against the CPU refinement at equal
//! triangle counts. On a software driver (llvmpipe) only the ratios mean something.
//!
//! `cargo run --release -p tessella-gl --example bench [-- LEVEL [REPEATS]]`

use std::time::Instant;
use tessella_core::refine::{Levels, Plan, Spacing};
use tessella_core::{samples, NormalMode, RefineOptions, RefinedMesh, Scheme};
use tessella_gl::{GlContext, GlError, GlTessellator};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), GlError> {
    let mut args = std::env::args().skip(1);
    let level: f32 = args.next().and_then(|a| a.parse().ok()).unwrap_or(8.0);
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
        let o = RefineOptions::new(Scheme::Pn, 1)
            .with_normals(normals)
            .with_spacing(Spacing::Equal)
            .with_levels(Levels::Uniform(level));
        let p = gl.prepare(&mesh, &o, None)?;
        let _warm = gl.run(&p)?;
        let times: Vec<f64> = (0..repeats)
            .map(|_| gl.run(&p).map(|r| r.draw_seconds))
            .collect::<Result<_, _>>()?;
        let gl_s = median(times);
        let tris = p.plan.triangle_count();
        // The CPU refinement of the same plan (soup: the same vertex count as GL's triangles × 3
        // would be unfair; the CPU writes its own layout), evaluation only.
        let plan = Plan::new(&mesh, &o).map_err(GlError::from)?;
        let frame = plan.frame(&mesh).map_err(GlError::from)?;
        let mut out = RefinedMesh::default();
        let times: Vec<f64> = (0..repeats)
            .map(|_| {
                let t = Instant::now();
                plan.refine_into(&frame, &mut out, &|_| {})
                    .map(|_| t.elapsed().as_secs_f64())
            })
            .collect::<Result<_, _>>()
            .map_err(GlError::from)?;
        let cpu_s = median(times);
        let verts = tris * 3;
        println!(
            "PN {normals:?}: {tris} triangles; GL {:.2} ms ({:.1} ns per vertex); CPU {:.2} ms; \
             GL/CPU {:.2}",
            gl_s * 1e3,
            gl_s * 1e9 / verts as f64,
            cpu_s * 1e3,
            gl_s / cpu_s
        );
        rows.push(gl_s);
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
