//! Benchmarks for `tessella bench`: CPU vs GPU refinement throughput, and the GMR Figure 7
//! experiment (a static fully refined vertex buffer vs the instanced pattern). Rows carry the
//! adapter's label; software adapters are marked as such, their numbers say nothing about GPUs.

use crate::render::Target;
use crate::scene::{scene_uniforms, RenderOptions};
use image::RgbaImage;
use std::time::Instant;
use tessella_core::refine::{Evaluator, Plan, Surface, SurfaceOptions};
use tessella_core::{samples, Mesh, RefineOptions, Refiner, Scheme};
use tessella_gpu::{
    gpu_refine, AdaptiveRenderer, Displacement, GpuContext, GpuError, GpuEvaluator, GpuOutput,
    PatternRenderer,
};

/// One row of [`refine_throughput`].
#[derive(Debug, Clone, PartialEq)]
pub struct RefineRow {
    pub adapter: String,
    pub faces: usize,
    pub level: u32,
    pub vertices: u64,
    pub triangles: u64,
    /// Median wall time of the CPU refinement (all threads).
    pub cpu_ms: f64,
    /// Median wall time of the GPU refinement including upload and readback.
    pub gpu_ms: f64,
}

/// Times CPU and GPU refinement of `mesh` with `scheme` at each level (median of `repeats`).
pub fn refine_throughput(
    ctx: &GpuContext,
    mesh: &Mesh,
    scheme: Scheme,
    levels: &[u32],
    repeats: u32,
) -> Result<Vec<RefineRow>, GpuError> {
    let mut rows = Vec::new();
    for &level in levels {
        let refiner = Refiner::new(mesh, &RefineOptions::new(scheme, level))?;
        let mut cpu = Vec::new();
        let mut gpu = Vec::new();
        for _ in 0..repeats.max(1) {
            let t = Instant::now();
            std::hint::black_box(refiner.refine());
            cpu.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            std::hint::black_box(gpu_refine(ctx, &refiner)?);
            gpu.push(t.elapsed().as_secs_f64() * 1e3);
        }
        rows.push(RefineRow {
            adapter: ctx.adapter_label(),
            faces: mesh.face_count(),
            level,
            vertices: refiner.layout().vertex_count,
            triangles: refiner.layout().triangle_count,
            cpu_ms: median(&mut cpu),
            gpu_ms: median(&mut gpu),
        });
    }
    Ok(rows)
}

/// Markdown table of [`refine_throughput`] rows.
pub fn refine_table(rows: &[RefineRow]) -> String {
    let mut s = String::from(
        "| adapter | faces | level | vertices | triangles | CPU ms | GPU ms | CPU Mvert/s | GPU Mvert/s |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let rate = |ms: f64| r.vertices as f64 / ms / 1e3;
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.1} | {:.1} |\n",
            r.adapter,
            r.faces,
            r.level,
            r.vertices,
            r.triangles,
            r.cpu_ms,
            r.gpu_ms,
            rate(r.cpu_ms),
            rate(r.gpu_ms)
        );
    }
    s
}

/// Settings of the Figure 7 experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure7Config {
    /// Coarse triangle counts (GMR: 10, 100, 1000).
    pub faces: Vec<usize>,
    /// Pattern levels (GMR: 64 and 128).
    pub levels: Vec<u32>,
    /// Frames timed per configuration (median).
    pub frames: u32,
    /// Render target size.
    pub size: (u32, u32),
    pub scheme: Scheme,
}

impl Default for Figure7Config {
    fn default() -> Self {
        Figure7Config {
            faces: vec![10, 100, 1000],
            levels: vec![64, 128],
            frames: 10,
            size: (512, 512),
            scheme: Scheme::Pn,
        }
    }
}

/// One row of [`figure7`].
#[derive(Debug, Clone, PartialEq)]
pub struct Figure7Row {
    pub adapter: String,
    pub faces: usize,
    pub level: u32,
    /// (a) static vertex buffer of the fully refined, welded mesh.
    pub static_ms: f64,
    pub static_vertices: u64,
    pub static_bytes: u64,
    /// (b) the instanced pattern plus per-triangle nets.
    pub pattern_ms: f64,
    pub pattern_vertices: u64,
    pub pattern_bytes: u64,
    /// Fraction of pixels where the two pictures differ by more than 12 levels in a channel:
    /// both draw the same surface, so this stays near 0 (edges may round differently).
    pub pictures_differ: f64,
}

/// The first `faces` triangles of a subdivided icosphere, vertices compacted: a closed-ish
/// surface with exactly the wanted number of coarse triangles.
pub fn mesh_with_faces(faces: usize) -> Result<Mesh, GpuError> {
    let mut sub = 0;
    while 20 * 4usize.pow(sub) < faces {
        sub += 1;
    }
    Ok(samples::first_faces(&samples::icosphere(sub), faces))
}

/// GMR Figure 7 redone: frame time and GPU footprint of (a) a static refined vertex buffer
/// (written by [`GpuEvaluator`]) and (b) the instanced pattern, for each coarse triangle count
/// and level. Both pictures are compared, so a row also says that both drew the same surface.
pub fn figure7(ctx: &GpuContext, config: &Figure7Config) -> Result<Vec<Figure7Row>, GpuError> {
    let mut rows = Vec::new();
    let options = RenderOptions {
        size: config.size,
        ..Default::default()
    };
    let target = Target::new(ctx, config.size)?;
    for &faces in &config.faces {
        let mesh = mesh_with_faces(faces)?;
        for &level in &config.levels {
            let plan = Plan::new(&mesh, &RefineOptions::new(config.scheme, level))?;
            let frame = plan.frame(&mesh)?;
            let renderer =
                PatternRenderer::new(ctx, &plan, &frame, &Target::FORMATS, &Displacement::None)?;
            renderer.set_uniforms(&scene_uniforms(&mesh, &options, 0.0));
            let bg = options.background;
            // (b) pattern.
            let pattern_ms = time_frames(config.frames, || {
                target.draw(ctx, bg, |pass| renderer.draw(pass))
            })?;
            let pattern_picture = target.read(ctx)?;
            // (a) static buffer of the refined mesh, evaluated once.
            let mut gpu = GpuEvaluator::new(ctx, &plan)?;
            gpu.evaluate(&plan, &frame, GpuOutput::Own)?;
            let (indices, format) = gpu.index_buffer(&plan)?;
            let indices = indices.clone();
            let vertices = gpu
                .vertex_buffer()
                .ok_or_else(|| GpuError::Readback("no vertex buffer".into()))?;
            let count = plan.triangle_count() as u32 * 3;
            let static_ms = time_frames(config.frames, || {
                target.draw(ctx, bg, |pass| {
                    renderer.draw_refined(
                        pass,
                        vertices.slice(..),
                        indices.slice(..),
                        format,
                        count,
                    )
                })
            })?;
            let static_picture = target.read(ctx)?;
            rows.push(Figure7Row {
                adapter: ctx.adapter_label(),
                faces: mesh.face_count(),
                level,
                static_ms,
                static_vertices: plan.vertex_count() as u64,
                static_bytes: vertices.size() + indices.size(),
                pattern_ms,
                pattern_vertices: renderer.pattern_vertex_count(),
                pattern_bytes: renderer.byte_size(),
                pictures_differ: differing(&pattern_picture, &static_picture),
            });
        }
    }
    Ok(rows)
}

/// Fraction of pixels of `a` and `b` with a channel more than 12 levels apart.
fn differing(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let bad = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 12))
        .count();
    bad as f64 / (a.width() * a.height()).max(1) as f64
}

/// Markdown table of [`figure7`] rows.
pub fn figure7_table(rows: &[Figure7Row]) -> String {
    let mut s = String::from(
        "| adapter | coarse triangles | level | static VBO ms | static VBO vertices | static VBO bytes | pattern ms | pattern vertices | pattern bytes | pixels differing |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {} | {} | {:.2} | {} | {} | {:.1}% |\n",
            r.adapter,
            r.faces,
            r.level,
            r.static_ms,
            r.static_vertices,
            r.static_bytes,
            r.pattern_ms,
            r.pattern_vertices,
            r.pattern_bytes,
            100.0 * r.pictures_differ
        );
    }
    s
}

/// One row of [`scheme_frame_times`].
#[derive(Debug, Clone, PartialEq)]
pub struct SchemeRow {
    pub adapter: String,
    pub scheme: String,
    pub faces: usize,
    pub level: u32,
    /// Basis size: control points per coarse triangle.
    pub k: usize,
    pub frame_ms: f64,
}

/// Frame time of the instanced pattern per scheme (e.g. PN vs PNG1: 10 vs 21 control points).
pub fn scheme_frame_times(
    ctx: &GpuContext,
    mesh: &Mesh,
    schemes: &[Scheme],
    level: u32,
    frames: u32,
    size: (u32, u32),
) -> Result<Vec<SchemeRow>, GpuError> {
    let options = RenderOptions {
        size,
        ..Default::default()
    };
    let target = Target::new(ctx, size)?;
    let uniforms = scene_uniforms(mesh, &options, 0.0);
    let mut rows = Vec::new();
    for &scheme in schemes {
        let plan = Plan::new(mesh, &RefineOptions::new(scheme, level))?;
        let frame = plan.frame(mesh)?;
        let renderer =
            PatternRenderer::new(ctx, &plan, &frame, &Target::FORMATS, &Displacement::None)?;
        renderer.set_uniforms(&uniforms);
        let frame_ms = time_frames(frames, || {
            target.draw(ctx, options.background, |pass| renderer.draw(pass))
        })?;
        rows.push(SchemeRow {
            adapter: ctx.adapter_label(),
            scheme: scheme.name().to_string(),
            faces: mesh.face_count(),
            level,
            k: scheme.basis().len(),
            frame_ms,
        });
    }
    Ok(rows)
}

/// Markdown table of [`scheme_frame_times`] rows.
pub fn scheme_table(rows: &[SchemeRow]) -> String {
    let mut s = String::from("| adapter | scheme | K | coarse triangles | level | frame ms |\n|---|---|---:|---:|---:|---:|\n");
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.2} |\n",
            r.adapter, r.scheme, r.k, r.faces, r.level, r.frame_ms
        );
    }
    s
}

/// Median milliseconds of `frames` calls, after one warm-up call.
fn time_frames(
    frames: u32,
    mut frame: impl FnMut() -> Result<(), GpuError>,
) -> Result<f64, GpuError> {
    frame()?;
    let mut times = Vec::new();
    for _ in 0..frames.max(1) {
        let t = Instant::now();
        frame()?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    Ok(median(&mut times))
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Frame times of the instanced renderer with mixed patterns against one uniform pattern of
/// about the same triangle count: `(uniform_ms, mixed_ms, uniform_triangles,
/// mixed_triangles, mixed_draws)`. The mixed plan has per-edge fractional-odd levels spread
/// over `[1, √3·level]` (one draw per distinct tile); the uniform one is the grid at `level`.
pub fn mixed_pattern_frame_times(
    ctx: &GpuContext,
    mesh: &Mesh,
    level: u32,
    frames: u32,
    size: (u32, u32),
) -> Result<(f64, f64, usize, usize, usize), GpuError> {
    use tessella_core::refine::{Levels, Spacing};
    let options = RenderOptions {
        size,
        ..Default::default()
    };
    let target = Target::new(ctx, size)?;
    let uniforms = scene_uniforms(mesh, &options, 0.0);
    let uniform = Plan::new(mesh, &RefineOptions::new(Scheme::Pn, level))?;
    let edges = uniform.topology().edges.len();
    // Levels spread evenly over [1, √3·level]: about the uniform plan's triangle count.
    let top = (level as f32 * 3f32.sqrt()).min(63.0);
    let levels: std::sync::Arc<[f32]> = (0..edges)
        .map(|e| 1.0 + (e * 37 % 101) as f32 / 100.0 * (top - 1.0))
        .collect();
    let mixed = Plan::new(
        mesh,
        &RefineOptions::new(Scheme::Pn, 1)
            .with_spacing(Spacing::FractionalOdd)
            .with_levels(Levels::PerEdge {
                edges: levels,
                faces: None,
            }),
    )?;
    let mut out = Vec::new();
    for plan in [&uniform, &mixed] {
        let frame = plan.frame(mesh)?;
        let renderer =
            PatternRenderer::new(ctx, plan, &frame, &Target::FORMATS, &Displacement::None)?;
        renderer.set_uniforms(&uniforms);
        let ms = time_frames(frames, || {
            target.draw(ctx, options.background, |pass| renderer.draw(pass))
        })?;
        out.push((ms, plan.triangle_count(), renderer.draw_count()));
    }
    Ok((out[0].0, out[1].0, out[0].1, out[1].1, out[1].2))
}

/// One row of [`changing_levels`]: per frame when the levels change every frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ChangingLevelsRow {
    pub adapter: String,
    pub spacing: String,
    pub faces: usize,
    /// Median refined triangles per frame.
    pub triangles: u64,
    /// A new plan and `PatternRenderer` per frame, then the draw: median ms, and the median
    /// bytes the new renderer uploads (its tiles' stencils and patterns, the nets).
    pub rebuild_ms: f64,
    pub rebuild_bytes: u64,
    /// Of which the new plan and renderer, before the draw.
    pub rebuild_setup_ms: f64,
    /// One `AdaptiveRenderer`: `set_levels` then the draw: median ms and bytes uploaded.
    pub adaptive_ms: f64,
    pub adaptive_bytes: u64,
    /// Of which `set_levels`.
    pub set_levels_ms: f64,
    /// The draw alone, levels fixed: `PatternRenderer` (stencil rows) and `AdaptiveRenderer`
    /// (points placed and the basis evaluated in the vertex shader).
    pub pattern_draw_ms: f64,
    pub adaptive_draw_ms: f64,
}

/// Per-edge levels in `[1, top]` that differ edge by edge and move with `frame`.
fn moving_levels(edges: usize, top: f32, frame: u32) -> Vec<f32> {
    (0..edges)
        .map(|e| 1.0 + ((e * 37 + frame as usize * 11) % 101) as f32 / 100.0 * (top - 1.0))
        .collect()
}

/// What a frame costs when the levels change every frame (a camera flying, a LOD updating):
/// rebuilding the adaptive plan and its renderer each frame against one [`AdaptiveRenderer`]
/// fed new levels; and, levels fixed, the draw of each (PN, per-edge levels up to `top`).
pub fn changing_levels(
    ctx: &GpuContext,
    mesh: &Mesh,
    top: f32,
    frames: u32,
    size: (u32, u32),
) -> Result<Vec<ChangingLevelsRow>, GpuError> {
    use tessella_core::refine::{Levels, Spacing};
    let options = RenderOptions {
        size,
        ..Default::default()
    };
    let target = Target::new(ctx, size)?;
    let uniforms = scene_uniforms(mesh, &options, 0.0);
    let surface = Surface::new(mesh, &SurfaceOptions::new(Scheme::Pn))?;
    let first = surface.frame(mesh)?;
    let edges = surface.topology().edges.len();
    let frames = frames.max(1);
    let mut rows = Vec::new();
    for spacing in [Spacing::Grid, Spacing::FractionalOdd] {
        let options_at = |k| {
            RefineOptions::new(Scheme::Pn, 1)
                .with_spacing(spacing)
                .with_levels(Levels::PerEdge {
                    edges: moving_levels(edges, top, k).into(),
                    faces: None,
                })
        };
        let draw = |r: &dyn Fn(&mut wgpu::RenderPass<'_>)| target.draw(ctx, options.background, r);
        let (mut rebuild_ms, mut rebuild_bytes, mut triangles) = (vec![], vec![], vec![]);
        let (mut rebuild_setup_ms, mut set_levels_ms) = (vec![], vec![]);
        let mut last = None;
        for k in 0..=frames {
            let t = Instant::now();
            let plan = Plan::new(mesh, &options_at(k))?;
            let frame = plan.frame(mesh)?;
            let renderer =
                PatternRenderer::new(ctx, &plan, &frame, &Target::FORMATS, &Displacement::None)?;
            renderer.set_uniforms(&uniforms);
            let setup = t.elapsed().as_secs_f64() * 1e3;
            draw(&|pass| renderer.draw(pass))?;
            // Frame 0 warms up.
            if k > 0 {
                rebuild_setup_ms.push(setup);
                rebuild_ms.push(t.elapsed().as_secs_f64() * 1e3);
                rebuild_bytes.push(renderer.byte_size() as f64);
                triangles.push(plan.triangle_count() as f64);
            }
            last = Some(renderer);
        }
        let mut adaptive = AdaptiveRenderer::new(ctx, &surface, &first, &Target::FORMATS, spacing)?;
        adaptive.set_uniforms(&uniforms);
        let (mut adaptive_ms, mut adaptive_bytes) = (vec![], vec![]);
        for k in 0..=frames {
            let t = Instant::now();
            let bytes = adaptive.set_levels(&moving_levels(edges, top, k), None)?;
            let setup = t.elapsed().as_secs_f64() * 1e3;
            draw(&|pass| adaptive.draw(pass))?;
            if k > 0 {
                set_levels_ms.push(setup);
                adaptive_ms.push(t.elapsed().as_secs_f64() * 1e3);
                adaptive_bytes.push(bytes as f64);
            }
        }
        // The last frame's levels, drawn again by both.
        let pattern = last.expect("at least one frame");
        let pattern_draw_ms = time_frames(frames, || draw(&|pass| pattern.draw(pass)))?;
        let adaptive_draw_ms = time_frames(frames, || draw(&|pass| adaptive.draw(pass)))?;
        rows.push(ChangingLevelsRow {
            adapter: ctx.adapter_label(),
            spacing: spacing.name().to_string(),
            faces: mesh.face_count(),
            triangles: median(&mut triangles) as u64,
            rebuild_ms: median(&mut rebuild_ms),
            rebuild_bytes: median(&mut rebuild_bytes) as u64,
            rebuild_setup_ms: median(&mut rebuild_setup_ms),
            adaptive_ms: median(&mut adaptive_ms),
            adaptive_bytes: median(&mut adaptive_bytes) as u64,
            set_levels_ms: median(&mut set_levels_ms),
            pattern_draw_ms,
            adaptive_draw_ms,
        });
    }
    Ok(rows)
}

/// Markdown table of [`changing_levels`] rows.
pub fn changing_levels_table(rows: &[ChangingLevelsRow]) -> String {
    let mut s = String::from(
        "| adapter | spacing | coarse triangles | triangles | rebuild: frame ms (new plan + renderer) | bytes uploaded | adaptive: frame ms (set_levels) | bytes uploaded | frame speed-up | levels speed-up | draw ms: pattern / adaptive |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {:.2} ({:.2}) | {} | {:.2} ({:.3}) | {} | {:.1}x | {:.0}x | {:.2} / {:.2} |\n",
            r.adapter,
            r.spacing,
            r.faces,
            r.triangles,
            r.rebuild_ms,
            r.rebuild_setup_ms,
            r.rebuild_bytes,
            r.adaptive_ms,
            r.set_levels_ms,
            r.adaptive_bytes,
            r.rebuild_ms / r.adaptive_ms,
            r.rebuild_setup_ms / r.set_levels_ms,
            r.pattern_draw_ms,
            r.adaptive_draw_ms
        );
    }
    s
}
