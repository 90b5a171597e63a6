//! `tessella bench --gl`: PN on the OpenGL tessellator (measured by `tessella_bench::gl`, as its
//! example does) against tessella-gpu's instanced pattern renderer and the CPU at about equal
//! triangle counts, and quadratic ("fake") against real normals. Ratios are against the CPU
//! measured in the same run; absolute times are printed only for hardware drivers.

use crate::args::BenchArgs;
use tessella_bench::gl::{self as bench, GlBenchRow};
use tessella_core::{samples, Mesh, NormalMode, RefineOptions, Scheme};
use tessella_gl::{GlContext, GlTessellator};

/// tessella-gpu's instanced pattern renderer on the wgpu adapter (when there is one).
#[cfg(feature = "gpu")]
struct Pattern(Result<tessella_gpu::GpuContext, String>);

#[cfg(feature = "gpu")]
impl Pattern {
    fn new() -> Pattern {
        Pattern(super::gpu::render_context().map_err(|e| format!("{e:#}")))
    }
    fn label(&self) -> String {
        match &self.0 {
            Ok(ctx) => ctx.adapter_label(),
            Err(e) => format!("not measured: {e}"),
        }
    }
    /// Median seconds of a frame at grid `level` and whether the adapter is software; `None`
    /// without an adapter.
    fn frame(&self, mesh: &Mesh, level: u32, frames: u32) -> anyhow::Result<Option<(f64, bool)>> {
        let Ok(ctx) = &self.0 else { return Ok(None) };
        let rows = tessella_bench::gpu::scheme_frame_times(
            ctx,
            mesh,
            &[Scheme::Pn],
            level,
            frames,
            (512, 512),
        )?;
        Ok(Some((rows[0].frame_ms / 1e3, ctx.is_software())))
    }
}

#[cfg(not(feature = "gpu"))]
struct Pattern;

#[cfg(not(feature = "gpu"))]
impl Pattern {
    fn new() -> Pattern {
        Pattern
    }
    fn label(&self) -> String {
        "not measured: built without the `gpu` feature".into()
    }
    fn frame(&self, _: &Mesh, _: u32, _: u32) -> anyhow::Result<Option<(f64, bool)>> {
        Ok(None)
    }
}

fn kind(software: bool) -> &'static str {
    if software {
        "software"
    } else {
        "hardware"
    }
}

pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let (mesh, name): (Mesh, String) = match &args.mesh {
        Some(path) => (tessella_io::read_mesh(path)?, path.display().to_string()),
        None => (samples::icosphere(2), "icosphere(2)".into()),
    };
    let repeat = args.repeat.max(1);
    let ctx = GlContext::new()?;
    let info = ctx.info().clone();
    let soft = info.is_software();
    let mut gl = GlTessellator::new(&ctx)?;
    let pattern = Pattern::new();
    let levels: Vec<u32> = args
        .levels
        .iter()
        .copied()
        .filter(|&n| n >= 1 && n as i32 <= info.max_tess_level)
        .collect();
    let mut rows: Vec<(GlBenchRow, GlBenchRow)> = Vec::new();
    for &n in &levels {
        let q = bench::measure(&mut gl, &mesh, n, NormalMode::Quadratic, repeat)?;
        let r = bench::measure(&mut gl, &mesh, n, NormalMode::Real, repeat)?;
        rows.push((q, r));
    }
    let ms = |s: f64, software: bool| {
        if software {
            "—".to_string()
        } else {
            format!("{:.3}", s * 1e3)
        }
    };

    println!();
    println!(
        "Hardware tessellator (GL, equal spacing n, transform feedback + read-back) against the \
         instanced pattern (wgpu, grid m, 512x512 frame) against the CPU refinement, PN, \
         quadratic normals, {name} ({} coarse triangles); time per million triangles, ratios \
         against the CPU of the same plan in this run; median of {repeat}",
        mesh.face_count()
    );
    println!(
        "GL driver: {} ({}, {}); pattern adapter: {}",
        info.renderer,
        info.version,
        kind(soft),
        pattern.label()
    );
    println!();
    println!("| n | GL triangles | m | pattern triangles | CPU ms/M triangles (n) | GL / CPU | CPU ms/M triangles (m) | pattern / CPU | GL ms/M triangles | pattern ms/M triangles |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (q, _) in &rows {
        let per_m = |s: f64, tris: usize| s / tris as f64 * 1e6;
        // The grid level with the nearest triangle count: m² against (3n² − (n mod 2)) / 2.
        let m = (bench::equal_spacing_triangles(q.level) as f64)
            .sqrt()
            .round()
            .max(1.0) as u32;
        let (cpu_m, pattern_tris) =
            bench::cpu_seconds(&mesh, &RefineOptions::new(Scheme::Pn, m), repeat)?;
        let frame = pattern.frame(&mesh, m, repeat.clamp(1, 10) as u32)?;
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
        println!(
            "| {} | {} | {m} | {pattern_tris} | {:.2} | {:.2} | {:.2} | {pattern_ratio} | {} | {pattern_abs} |",
            q.level,
            q.triangles,
            cpu_n_pm * 1e3,
            gl_pm / cpu_n_pm,
            cpu_m_pm * 1e3,
            ms(gl_pm, soft),
        );
    }

    println!();
    println!(
        "Quadratic (\"fake\") against real normals on the GL tessellator, PN, equal spacing, \
         {name}; GL driver: {} ({}); ratios against the CPU of the same plan in this run",
        info.renderer,
        kind(soft)
    );
    println!();
    println!("| n | triangles | vertices | quadratic GL / CPU | real GL / CPU | real / quadratic (GL) | real / quadratic (CPU) | quadratic GL ns/vertex | real GL ns/vertex |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (q, r) in &rows {
        let ns = |row: &GlBenchRow| {
            if soft {
                "—".to_string()
            } else {
                format!("{:.2}", row.gl_seconds * 1e9 / row.vertices as f64)
            }
        };
        println!(
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
    }
    let skipped: Vec<u32> = args
        .levels
        .iter()
        .copied()
        .filter(|n| !levels.contains(n))
        .collect();
    if !skipped.is_empty() {
        println!();
        println!(
            "levels {skipped:?} skipped: outside 1..=GL_MAX_TESS_GEN_LEVEL = {}",
            info.max_tess_level
        );
    }
    if soft {
        println!();
        println!("(software GL driver: compare ratios only)");
    }
    Ok(())
}
