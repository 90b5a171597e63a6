//! The GPU benchmarks of `tessella bench --gpu` and the viewer's `bench()`: CPU vs GPU refinement
//! throughput, the GMR Figure 7 experiment (a static fully refined vertex buffer vs the
//! instanced pattern), frame time per scheme, and levels that move every frame. Rows carry the
//! adapter's label; software adapters are marked as such, their numbers say nothing about GPUs.
//!
//! The frame-timed experiments are `async` (`*_async`): in a browser nothing may block the
//! page, so each frame is awaited with [`GpuContext::work_done_async`]. Natively that call
//! waits for the device, and the blocking forms (the `blocking` feature) run the same bodies
//! with `pollster`: one implementation times both.

use image::RgbaImage;
use tessella_core::refine::{Evaluator, Frame, Plan, Surface, SurfaceOptions};
use tessella_core::{samples, Mesh, RefineOptions, Scheme};
use tessella_gpu::{
    AdaptiveRenderer, Displacement, GpuContext, GpuError, GpuEvaluator, GpuOutput, IndexWidth,
    PatternRenderer,
};
use tessella_view::{scene_uniforms, Appearance, RenderOptions, RenderUniforms, Target};
use web_time::Instant;

/// The blocking twin of an async bench function, natively with the `blocking` feature: the
/// same arguments, run to completion on this thread (the async one is the browser's form).
macro_rules! blocking {
    ($(#[$doc:meta])* $name:ident = $run:ident($($arg:ident: $ty:ty),*) -> $ret:ty) => {
        $(#[$doc])*
        #[cfg(feature = "blocking")]
        pub fn $name($($arg: $ty),*) -> $ret {
            pollster::block_on($run($($arg),*))
        }
    };
}

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
#[cfg(feature = "blocking")]
pub fn refine_throughput(
    ctx: &GpuContext,
    mesh: &Mesh,
    scheme: Scheme,
    levels: &[u32],
    repeats: u32,
) -> Result<Vec<RefineRow>, GpuError> {
    let mut rows = Vec::new();
    for &level in levels {
        let refiner = tessella_core::Refiner::new(mesh, &RefineOptions::new(scheme, level))?;
        let mut cpu = Vec::new();
        let mut gpu = Vec::new();
        for _ in 0..repeats.max(1) {
            let t = Instant::now();
            std::hint::black_box(refiner.refine());
            cpu.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            std::hint::black_box(tessella_gpu::gpu_refine(ctx, &refiner)?);
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

/// One row of [`figure7_async`].
#[derive(Debug, Clone, PartialEq)]
pub struct Figure7Row {
    pub adapter: String,
    pub faces: usize,
    pub level: u32,
    /// (a) static vertex buffer of the fully refined, welded mesh: its median frame time, or
    /// `None` when it was not drawn ([`Figure7Row::static_note`] says why: it does not fit the
    /// device, which is the paper's point at large sizes).
    pub static_ms: Option<f64>,
    pub static_vertices: u64,
    /// What the static buffer takes (vertices and indices), drawn or not.
    pub static_bytes: u64,
    pub static_note: Option<String>,
    /// (b) the instanced pattern plus per-triangle nets.
    pub pattern_ms: f64,
    pub pattern_vertices: u64,
    pub pattern_bytes: u64,
    /// Fraction of pixels where the two pictures differ by more than 12 levels in a channel:
    /// both draw the same surface, so this stays near 0 (edges may round differently).
    /// `None` when the static buffer was not drawn.
    pub pictures_differ: Option<f64>,
}

impl Figure7Row {
    /// Pattern frame time over the static buffer's (the goal is within 1.5×); `None` when the
    /// static buffer was not drawn or either time read 0 (a browser's clock is coarse).
    pub fn frame_ratio(&self) -> Option<f64> {
        self.static_ms.and_then(|s| ratio(self.pattern_ms, s))
    }

    /// Pattern footprint over the static buffer's (the goal is at most 1/`faces`).
    pub fn footprint_ratio(&self) -> f64 {
        self.pattern_bytes as f64 / self.static_bytes.max(1) as f64
    }
}

/// `a / b` where both are positive and the quotient finite; `None` otherwise (a time that read
/// 0 on a coarse clock), so no report carries an infinity or a NaN.
pub fn ratio(a: f64, b: f64) -> Option<f64> {
    (a > 0.0 && b > 0.0)
        .then(|| a / b)
        .filter(|r| r.is_finite())
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

blocking! {
    /// GMR Figure 7 redone: frame time and GPU footprint of (a) a static refined vertex buffer
    /// (written by [`GpuEvaluator`]) and (b) the instanced pattern, for each coarse triangle count
    /// and level. Both pictures are compared, so a row also says that both drew the same surface.
    figure7 = figure7_async(
        ctx: &GpuContext, config: &Figure7Config
    ) -> Result<Vec<Figure7Row>, GpuError>
}

/// [`figure7`] without blocking: the browser's form.
pub async fn figure7_async(
    ctx: &GpuContext,
    config: &Figure7Config,
) -> Result<Vec<Figure7Row>, GpuError> {
    let mut rows = Vec::new();
    let options = view_at(config.size);
    options.validate()?;
    let stage = Stage::new(ctx, options)?;
    let look = &stage.look;
    for &faces in &config.faces {
        let mesh = mesh_with_faces(faces)?;
        for &level in &config.levels {
            let plan = Plan::new(&mesh, &RefineOptions::new(config.scheme, level))?;
            let frame = plan.frame(&mesh)?;
            let uniforms = scene_uniforms(&mesh, &stage.options, 0.0);
            let renderer = stage.pattern_renderer(ctx, &plan, &frame, &uniforms)?;
            // (b) pattern.
            let pattern_ms = stage
                .time_draws(ctx, config.frames, &|pass| look.draw(pass, &renderer))
                .await?;
            let pattern_picture = stage.target.read_async(ctx).await?;
            // (a) static buffer of the refined mesh, evaluated once, where it fits.
            let mut gpu = GpuEvaluator::new(ctx, &plan)?;
            let index_bytes = IndexWidth::for_plan(&plan).buffer_bytes(&plan);
            let static_bytes = gpu.vertex_bytes() + index_bytes;
            let limit = ctx.limits.max_buffer_size;
            let (static_ms, static_note, pictures_differ) = if gpu.vertex_bytes().max(index_bytes)
                > limit
            {
                let note = format!(
                        "not drawn: its vertices ({} bytes) or indices ({index_bytes} bytes) exceed the device's {limit}-byte buffer limit",
                        gpu.vertex_bytes()
                    );
                (None, Some(note), None)
            } else {
                gpu.evaluate(&plan, &frame, GpuOutput::Own)?;
                let (indices, format) = gpu.index_buffer(&plan)?;
                let indices = indices.clone();
                let vertices = gpu
                    .vertex_buffer()
                    .ok_or_else(|| GpuError::Readback("no vertex buffer".into()))?;
                let count = u32::try_from(plan.triangle_count() * 3).map_err(|_| {
                    GpuError::BadOption(format!(
                        "{} refined triangles are more than one draw indexes",
                        plan.triangle_count()
                    ))
                })?;
                let ms = stage
                    .time_draws(ctx, config.frames, &|pass| {
                        renderer.draw_refined(
                            pass,
                            look.group(),
                            vertices.slice(..),
                            indices.slice(..),
                            format,
                            count,
                        )
                    })
                    .await?;
                let static_picture = stage.target.read_async(ctx).await?;
                (
                    Some(ms),
                    None,
                    Some(differing(&pattern_picture, &static_picture)),
                )
            };
            rows.push(Figure7Row {
                adapter: ctx.adapter_label(),
                faces: mesh.face_count(),
                level,
                static_ms,
                static_vertices: plan.vertex_count() as u64,
                static_bytes,
                static_note,
                pattern_ms,
                pattern_vertices: renderer.pattern_vertex_count(),
                pattern_bytes: renderer.byte_size(),
                pictures_differ,
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

/// Markdown table of [`figure7_async`] rows, with the two ratios the paper's claim is about.
pub fn figure7_table(rows: &[Figure7Row]) -> String {
    let mut s = String::from(
        "| adapter | coarse triangles | level | static VBO ms | static VBO vertices | static VBO bytes | pattern ms | pattern vertices | pattern bytes | frame time pattern/static | footprint pattern/static (goal ≤ 1/triangles) | pixels differing |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let or_dash = |v: Option<String>| v.unwrap_or_else(|| "—".into());
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {:.2} | {} | {} | {} | {:.5} ({:.5}) | {} |\n",
            r.adapter,
            r.faces,
            r.level,
            or_dash(r.static_ms.map(|v| format!("{v:.2}"))),
            r.static_vertices,
            r.static_bytes,
            r.pattern_ms,
            r.pattern_vertices,
            r.pattern_bytes,
            or_dash(r.frame_ratio().map(|v| format!("{v:.2}x"))),
            r.footprint_ratio(),
            1.0 / r.faces.max(1) as f64,
            or_dash(r.pictures_differ.map(|v| format!("{:.1}%", 100.0 * v)))
        );
    }
    for r in rows.iter().filter(|r| r.static_note.is_some()) {
        s += &format!(
            "\n{} triangles, level {}: static buffer {}\n",
            r.faces,
            r.level,
            r.static_note.as_deref().unwrap_or_default()
        );
    }
    s
}

/// One row of [`scheme_frame_times_async`].
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

blocking! {
    /// Frame time of the instanced pattern per scheme (e.g. PN vs PNG1: 10 vs 21 control points).
    scheme_frame_times = scheme_frame_times_async(
        ctx: &GpuContext, mesh: &Mesh, schemes: &[Scheme], level: u32, frames: u32,
        size: (u32, u32)
    ) -> Result<Vec<SchemeRow>, GpuError>
}

/// [`scheme_frame_times`] without blocking.
pub async fn scheme_frame_times_async(
    ctx: &GpuContext,
    mesh: &Mesh,
    schemes: &[Scheme],
    level: u32,
    frames: u32,
    size: (u32, u32),
) -> Result<Vec<SchemeRow>, GpuError> {
    let stage = Stage::new(ctx, view_at(size))?;
    let uniforms = scene_uniforms(mesh, &stage.options, 0.0);
    let mut rows = Vec::new();
    for &scheme in schemes {
        let plan = Plan::new(mesh, &RefineOptions::new(scheme, level))?;
        let frame = plan.frame(mesh)?;
        let renderer = stage.pattern_renderer(ctx, &plan, &frame, &uniforms)?;
        let frame_ms = stage
            .time_draws(ctx, frames, &|pass| stage.look.draw(pass, &renderer))
            .await?;
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

/// Markdown table of [`scheme_frame_times_async`] rows.
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

/// The default view at `size`: what the frame-timed experiments draw.
fn view_at(size: (u32, u32)) -> RenderOptions {
    RenderOptions {
        size,
        ..Default::default()
    }
}

/// What the frame-timed experiments draw into: their view, its offscreen target and the
/// default look.
struct Stage {
    options: RenderOptions,
    target: Target,
    look: Appearance,
}

impl Stage {
    fn new(ctx: &GpuContext, options: RenderOptions) -> Result<Stage, GpuError> {
        Ok(Stage {
            target: Target::new(ctx, options.size)?,
            look: Appearance::new(ctx, Target::FORMATS),
            options,
        })
    }

    /// The instanced pattern renderer of `plan`'s `frame`, undisplaced, with the look's
    /// uniforms set to `uniforms`.
    fn pattern_renderer(
        &self,
        ctx: &GpuContext,
        plan: &Plan,
        frame: &Frame<'_>,
        uniforms: &RenderUniforms,
    ) -> Result<PatternRenderer, GpuError> {
        let renderer =
            PatternRenderer::new(ctx, plan, frame, &self.look.shading(), &Displacement::None)?;
        self.look.set_uniforms(uniforms);
        Ok(renderer)
    }

    /// [`time_draws`] into this stage's target, on its background.
    async fn time_draws(
        &self,
        ctx: &GpuContext,
        frames: u32,
        record: &dyn Fn(&mut wgpu::RenderPass<'_>),
    ) -> Result<f64, GpuError> {
        time_draws(ctx, &self.target, self.options.background, frames, record).await
    }

    /// Draws one frame with `record`, awaited until the GPU has finished it, timed from
    /// `start`: (ms before the draw, ms of the whole frame).
    async fn frame_since(
        &self,
        ctx: &GpuContext,
        start: Instant,
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) -> Result<(f64, f64), GpuError> {
        let before = start.elapsed().as_secs_f64() * 1e3;
        self.target
            .draw_async(ctx, self.options.background, record)
            .await?;
        Ok((before, start.elapsed().as_secs_f64() * 1e3))
    }
}

/// Median milliseconds of `frames` frames drawn by `record` into `target`, each awaited until
/// the GPU has finished it, after one warm-up frame.
async fn time_draws(
    ctx: &GpuContext,
    target: &Target,
    background: [u8; 4],
    frames: u32,
    record: &dyn Fn(&mut wgpu::RenderPass<'_>),
) -> Result<f64, GpuError> {
    target.draw_async(ctx, background, record).await?;
    let mut times = Vec::new();
    for _ in 0..frames.max(1) {
        let t = Instant::now();
        target.draw_async(ctx, background, record).await?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    Ok(median(&mut times))
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

blocking! {
    /// Frame times of the instanced renderer with mixed patterns against one uniform pattern of
    /// about the same triangle count: `(uniform_ms, mixed_ms, uniform_triangles,
    /// mixed_triangles, mixed_draws)`. The mixed plan has per-edge fractional-odd levels spread
    /// over `[1, √3·level]` (one draw per distinct tile); the uniform one is the grid at `level`.
    mixed_pattern_frame_times = mixed_pattern_frame_times_async(
        ctx: &GpuContext, mesh: &Mesh, level: u32, frames: u32, size: (u32, u32)
    ) -> Result<(f64, f64, usize, usize, usize), GpuError>
}

/// [`mixed_pattern_frame_times`] without blocking.
pub async fn mixed_pattern_frame_times_async(
    ctx: &GpuContext,
    mesh: &Mesh,
    level: u32,
    frames: u32,
    size: (u32, u32),
) -> Result<(f64, f64, usize, usize, usize), GpuError> {
    use tessella_core::refine::{Levels, Spacing};
    let stage = Stage::new(ctx, view_at(size))?;
    let uniforms = scene_uniforms(mesh, &stage.options, 0.0);
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
        let renderer = stage.pattern_renderer(ctx, plan, &frame, &uniforms)?;
        let ms = stage
            .time_draws(ctx, frames, &|pass| stage.look.draw(pass, &renderer))
            .await?;
        out.push((ms, plan.triangle_count(), renderer.draw_count()));
    }
    Ok((out[0].0, out[1].0, out[0].1, out[1].1, out[1].2))
}

/// One row of [`changing_levels_async`]: per frame when the levels change every frame.
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

blocking! {
    /// What a frame costs when the levels change every frame (a camera flying, a LOD updating):
    /// rebuilding the adaptive plan and its renderer each frame against one [`AdaptiveRenderer`]
    /// fed new levels; and, levels fixed, the draw of each (PN, per-edge levels up to `top`).
    changing_levels = changing_levels_async(
        ctx: &GpuContext, mesh: &Mesh, top: f32, frames: u32, size: (u32, u32)
    ) -> Result<Vec<ChangingLevelsRow>, GpuError>
}

/// [`changing_levels`] without blocking.
pub async fn changing_levels_async(
    ctx: &GpuContext,
    mesh: &Mesh,
    top: f32,
    frames: u32,
    size: (u32, u32),
) -> Result<Vec<ChangingLevelsRow>, GpuError> {
    use tessella_core::refine::{Levels, Spacing};
    let stage = Stage::new(ctx, view_at(size))?;
    let look = &stage.look;
    let uniforms = scene_uniforms(mesh, &stage.options, 0.0);
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
        let (mut rebuild_ms, mut rebuild_bytes, mut triangles) = (vec![], vec![], vec![]);
        let (mut rebuild_setup_ms, mut set_levels_ms) = (vec![], vec![]);
        let mut last = None;
        for k in 0..=frames {
            let t = Instant::now();
            let plan = Plan::new(mesh, &options_at(k))?;
            let frame = plan.frame(mesh)?;
            let renderer = stage.pattern_renderer(ctx, &plan, &frame, &uniforms)?;
            let (setup, whole) = stage
                .frame_since(ctx, t, |pass| look.draw(pass, &renderer))
                .await?;
            // Frame 0 warms up.
            if k > 0 {
                rebuild_setup_ms.push(setup);
                rebuild_ms.push(whole);
                rebuild_bytes.push(renderer.byte_size() as f64);
                triangles.push(plan.triangle_count() as f64);
            }
            last = Some(renderer);
        }
        let mut adaptive = AdaptiveRenderer::new(ctx, &surface, &first, &look.shading(), spacing)?;
        look.set_uniforms(&uniforms);
        let (mut adaptive_ms, mut adaptive_bytes) = (vec![], vec![]);
        for k in 0..=frames {
            let t = Instant::now();
            let bytes = adaptive.set_levels(&moving_levels(edges, top, k), None)?;
            let (setup, whole) = stage
                .frame_since(ctx, t, |pass| look.draw(pass, &adaptive))
                .await?;
            if k > 0 {
                set_levels_ms.push(setup);
                adaptive_ms.push(whole);
                adaptive_bytes.push(bytes as f64);
            }
        }
        // The last frame's levels, drawn again by both.
        let pattern = last.expect("at least one frame");
        let pattern_draw_ms = stage
            .time_draws(ctx, frames, &|pass| look.draw(pass, &pattern))
            .await?;
        let adaptive_draw_ms = stage
            .time_draws(ctx, frames, &|pass| look.draw(pass, &adaptive))
            .await?;
        rows.push(ChangingLevelsRow {
            adapter: ctx.adapter_label(),
            spacing: spacing.to_string(),
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

/// Markdown table of [`changing_levels_async`] rows.
pub fn changing_levels_table(rows: &[ChangingLevelsRow]) -> String {
    let or_dash = |v: Option<String>| v.unwrap_or_else(|| "—".into());
    let mut s = String::from(
        "| adapter | spacing | coarse triangles | triangles | rebuild: frame ms (new plan + renderer) | bytes uploaded | adaptive: frame ms (set_levels) | bytes uploaded | frame speed-up | levels speed-up | draw ms: pattern / adaptive |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {:.2} ({:.2}) | {} | {:.2} ({:.3}) | {} | {} | {} | {:.2} / {:.2} |\n",
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
            or_dash(ratio(r.rebuild_ms, r.adaptive_ms).map(|v| format!("{v:.1}x"))),
            or_dash(ratio(r.rebuild_setup_ms, r.set_levels_ms).map(|v| format!("{v:.0}x"))),
            r.pattern_draw_ms,
            r.adaptive_draw_ms
        );
    }
    s
}
