//! The GL measurements shared by `examples/gl.rs` and `tessella bench --gl` ([`tables`]): PN on
//! the hardware tessellator (equal spacing, transform feedback and read-back) against the CPU
//! refinement of the same plan, both timed in the same call. On a software driver (llvmpipe)
//! only the ratios mean something ([`tessella_gl::DriverInfo::is_software`]).

use std::time::Instant;
use tessella_core::refine::{Levels, Plan, Spacing};
use tessella_core::{Mesh, NormalMode, RefineOptions, RefinedMesh, Scheme};
use tessella_gl::{GlContext, GlError, GlTessellator};

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

/// What `tessella bench --gl` compares the GL tessellator with besides the CPU: the instanced
/// pattern renderer (wgpu) on an adapter, or nothing, and why.
pub enum Pattern {
    #[cfg(feature = "blocking")]
    Adapter(Box<tessella_gpu::GpuContext>),
    /// Not measured: the reason.
    None(String),
}

impl Pattern {
    fn label(&self) -> String {
        match self {
            #[cfg(feature = "blocking")]
            Pattern::Adapter(ctx) => ctx.adapter_label(),
            Pattern::None(why) => format!("not measured: {why}"),
        }
    }

    /// Median seconds of a frame at grid `level` and whether the adapter is software; `None`
    /// without an adapter (the arguments are read by the `blocking` build's adapter alone).
    #[cfg_attr(not(feature = "blocking"), allow(unused_variables))]
    fn frame(&self, mesh: &Mesh, level: u32, frames: u32) -> anyhow::Result<Option<(f64, bool)>> {
        match self {
            #[cfg(feature = "blocking")]
            Pattern::Adapter(ctx) => {
                let rows = crate::gpu::scheme_frame_times(
                    ctx,
                    mesh,
                    &[Scheme::Pn],
                    level,
                    frames,
                    (512, 512),
                )?;
                Ok(Some((rows[0].frame_ms / 1e3, ctx.is_software())))
            }
            Pattern::None(_) => Ok(None),
        }
    }
}

fn kind(software: bool) -> &'static str {
    if software {
        "software"
    } else {
        "hardware"
    }
}

/// The two tables of `tessella bench --gl` on `mesh` (called `name`): PN on the hardware
/// tessellator (equal spacing n, transform feedback + read-back) against the instanced pattern
/// (made by `pattern`, after the GL context) and the CPU at about equal triangle counts, then
/// quadratic ("fake") against real normals. Ratios are against the CPU of the same plan in the
/// same run; absolute times only for hardware drivers. Levels outside the driver's range are
/// skipped, and the text says so.
pub fn tables(
    mesh: &Mesh,
    name: &str,
    levels: &[u32],
    repeat: usize,
    pattern: impl FnOnce() -> Pattern,
) -> anyhow::Result<String> {
    let repeat = repeat.max(1);
    let ctx = GlContext::new()?;
    let info = ctx.info().clone();
    let soft = info.is_software();
    let mut gl = GlTessellator::new(&ctx)?;
    let pattern = pattern();
    let asked = levels;
    let levels: Vec<u32> = asked
        .iter()
        .copied()
        .filter(|&n| n >= 1 && n as i32 <= info.max_tess_level)
        .collect();
    let mut rows: Vec<(GlBenchRow, GlBenchRow)> = Vec::new();
    for &n in &levels {
        let q = measure(&mut gl, mesh, n, NormalMode::Quadratic, repeat)?;
        let r = measure(&mut gl, mesh, n, NormalMode::Real, repeat)?;
        rows.push((q, r));
    }
    let mut out = String::new();
    let ms = |s: f64, software: bool| {
        if software {
            "—".to_string()
        } else {
            format!("{:.3}", s * 1e3)
        }
    };
    out.push('\n');
    out += &format!(
        "Hardware tessellator (GL, equal spacing n, transform feedback + read-back) against the \
         instanced pattern (wgpu, grid m, 512x512 frame) against the CPU refinement, PN, \
         quadratic normals, {name} ({} coarse triangles); time per million triangles, ratios \
         against the CPU of the same plan in this run; median of {repeat}",
        mesh.face_count()
    );
    out.push('\n');
    out += &format!(
        "GL driver: {} ({}, {}); pattern adapter: {}",
        info.renderer,
        info.version,
        kind(soft),
        pattern.label()
    );
    push_table_head(
        &mut out,
        "| n | GL triangles | m | pattern triangles | CPU ms/M triangles (n) | GL / CPU | CPU ms/M triangles (m) | pattern / CPU | GL ms/M triangles | pattern ms/M triangles |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    );
    for (q, _) in &rows {
        let per_m = |s: f64, tris: usize| s / tris as f64 * 1e6;
        // The grid level with the nearest triangle count: m² against (3n² − (n mod 2)) / 2.
        let m = (equal_spacing_triangles(q.level) as f64)
            .sqrt()
            .round()
            .max(1.0) as u32;
        let (cpu_m, pattern_tris) = cpu_seconds(mesh, &RefineOptions::new(Scheme::Pn, m), repeat)?;
        let frame = pattern.frame(mesh, m, repeat.clamp(1, 10) as u32)?;
        let gl_pm = per_m(q.gl_seconds, q.triangles);
        let cpu_n_pm = per_m(q.cpu_seconds, q.triangles);
        let cpu_m_pm = per_m(cpu_m, pattern_tris);
        let (pattern_ratio, pattern_abs) = match frame {
            Some((s, software)) => {
                let pm = per_m(s, pattern_tris);
                (format!("{:.2}", pm / cpu_m_pm), ms(pm, software))
            }
            None => ("—".into(), "—".into()),
        };
        out += &format!(
            "| {} | {} | {m} | {pattern_tris} | {:.2} | {:.2} | {:.2} | {pattern_ratio} | {} | {pattern_abs} |",
            q.level,
            q.triangles,
            cpu_n_pm * 1e3,
            gl_pm / cpu_n_pm,
            cpu_m_pm * 1e3,
            ms(gl_pm, soft),
        );
        out.push('\n');
    }

    out.push('\n');
    out += &format!(
        "Quadratic (\"fake\") against real normals on the GL tessellator, PN, equal spacing, \
         {name}; GL driver: {} ({}); ratios against the CPU of the same plan in this run",
        info.renderer,
        kind(soft)
    );
    push_table_head(
        &mut out,
        "| n | triangles | vertices | quadratic GL / CPU | real GL / CPU | real / quadratic (GL) | real / quadratic (CPU) | quadratic GL ns/vertex | real GL ns/vertex |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    );
    for (q, r) in &rows {
        let ns = |row: &GlBenchRow| {
            if soft {
                "—".to_string()
            } else {
                format!("{:.2}", row.gl_seconds * 1e9 / row.vertices as f64)
            }
        };
        out += &format!(
            "| {} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {} | {} |",
            q.level,
            q.triangles,
            q.vertices,
            q.gl_seconds / q.cpu_seconds,
            r.gl_seconds / r.cpu_seconds,
            r.gl_seconds / q.gl_seconds,
            r.cpu_seconds / q.cpu_seconds,
            ns(q),
            ns(r)
        );
        out.push('\n');
    }
    let skipped: Vec<u32> = asked
        .iter()
        .copied()
        .filter(|n| !levels.contains(n))
        .collect();
    if !skipped.is_empty() {
        out.push('\n');
        out += &format!(
            "levels {skipped:?} skipped: outside 1..=GL_MAX_TESS_GEN_LEVEL = {}",
            info.max_tess_level
        );
        out.push('\n');
    }
    if soft {
        out.push('\n');
        out += "(software GL driver: compare ratios only)";
        out.push('\n');
    }
    Ok(out)
}

/// Ends the caption line above a Markdown table, leaves a blank line, then writes the table's
/// header and alignment rows.
fn push_table_head(out: &mut String, header: &str, align: &str) {
    *out += &format!("\n\n{header}\n{align}\n");
}
