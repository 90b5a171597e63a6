//! The GL measurements shared by `examples/gl.rs` and `tessella bench --gl`: PN on the
//! hardware tessellator (equal spacing, transform feedback and read-back) against the CPU
//! refinement of the same plan, both timed in the same call. On a software driver (llvmpipe)
//! only the ratios mean something ([`tessella_gl::DriverInfo::is_software`]).

use std::time::Instant;
use tessella_core::refine::{Levels, Plan, Spacing};
use tessella_core::{Mesh, NormalMode, RefineOptions, RefinedMesh, Scheme};
use tessella_gl::{GlError, GlTessellator};

/// One measurement of [`measure`]: the same plan on the GL tessellator and on the CPU.
#[derive(Debug, Clone, PartialEq)]
pub struct GlBenchRow {
    pub normals: NormalMode,
    /// The integer tessellation level (equal spacing).
    pub level: u32,
    pub triangles: usize,
    /// Vertices the GL writes: an unwelded soup, three per triangle.
    pub vertices: usize,
    /// Median seconds of the GL draw with transform feedback and read-back.
    pub gl_seconds: f64,
    /// Median seconds of the CPU refinement of the same plan (evaluation only, reused buffers).
    pub cpu_seconds: f64,
}

/// Triangles per coarse face of equal spacing at integer level `n`: `(3n² − (n mod 2)) / 2`
/// (the grid pattern at level `m` has `m²`).
pub fn equal_spacing_triangles(n: u32) -> usize {
    let n = n as usize;
    (3 * n * n - n % 2) / 2
}

/// The median of `v` (not empty).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// PN at equal spacing `level` with `normals` on `mesh`: the GL tessellator and the CPU, median
/// of `repeats` after one warm-up each.
pub fn measure(
    gl: &mut GlTessellator,
    mesh: &Mesh,
    level: u32,
    normals: NormalMode,
    repeats: usize,
) -> Result<GlBenchRow, GlError> {
    let repeats = repeats.max(1);
    let o = RefineOptions::new(Scheme::Pn, 1)
        .with_normals(normals)
        .with_spacing(Spacing::Equal)
        .with_levels(Levels::Uniform(level as f32));
    let p = gl.prepare(mesh, &o, None)?;
    let _warm = gl.run(&p)?;
    let times: Vec<f64> = (0..repeats)
        .map(|_| gl.run(&p).map(|r| r.draw_seconds))
        .collect::<Result<_, _>>()?;
    let gl_seconds = median(times);
    let triangles = p.plan.triangle_count();
    Ok(GlBenchRow {
        normals,
        level,
        triangles,
        vertices: triangles * 3,
        gl_seconds,
        cpu_seconds: cpu_seconds(mesh, &o, repeats)?.0,
    })
}

/// The CPU refinement of `options` on `mesh` (its own layout), evaluation only into reused
/// buffers: `(median seconds of repeats after one warm-up, triangles)`.
pub fn cpu_seconds(
    mesh: &Mesh,
    options: &RefineOptions,
    repeats: usize,
) -> Result<(f64, usize), GlError> {
    let plan = Plan::new(mesh, options)?;
    let frame = plan.frame(mesh)?;
    let mut out = RefinedMesh::default();
    plan.refine_into(&frame, &mut out, &|_| {})?; // warm up: allocate, fault pages in
    let times: Vec<f64> = (0..repeats.max(1))
        .map(|_| {
            let t = Instant::now();
            plan.refine_into(&frame, &mut out, &|_| {})
                .map(|_| t.elapsed().as_secs_f64())
        })
        .collect::<Result<_, _>>()?;
    Ok((median(times), plan.triangle_count()))
}
